//! Absurdly large scene input: a file beyond `MAX_SCENE_FILE_BYTES` is
//! refused before it is read; a million bodies and a million hull points
//! are refused (`MAX_BODIES`, `MAX_HULL_POINTS`) before anything is built;
//! the largest hull accepted, every point extreme (the hull's worst case),
//! builds. Each is a typed error or a bounded run, never memory exhaustion.
//! The inputs are generated here; the figures that chose the limits are in
//! benchmarks/results/reliability.md.

use constraint_stabilization::io::scene_file::{
    FieldProblem, MAX_BODIES, MAX_HULL_POINTS, MAX_SCENE_FILE_BYTES, SceneFileError, parse_scene,
    read_scene,
};

/// A million, as in the issue.
const MILLION: usize = 1_000_000;

#[test]
fn a_file_beyond_the_limit_is_refused_before_it_is_read() {
    // Sparse: no disk space is used, and nothing is read.
    let path = std::env::temp_dir().join(format!("cs-huge-{}.json", std::process::id()));
    let file = std::fs::File::create(&path).expect("temp file");
    file.set_len(MAX_SCENE_FILE_BYTES + 1).expect("sparse file");
    let result = read_scene(&path);
    let _ = std::fs::remove_file(&path);
    match result {
        Err(SceneFileError::TooLarge { bytes, limit, .. }) => {
            assert_eq!(
                (bytes, limit),
                (MAX_SCENE_FILE_BYTES + 1, MAX_SCENE_FILE_BYTES)
            )
        }
        other => panic!("expected TooLarge, got {other:?}"),
    }
}

/// `{"bodies": [E, E, ...]}` with `count` copies of `entry`.
fn many_bodies(count: usize, entry: &str) -> String {
    format!(r#"{{"bodies": [{}]}}"#, vec![entry; count].join(","))
}

#[test]
fn a_million_bodies_are_refused_before_any_is_built() {
    // Empty objects: were any body built, the error would be a missing
    // field of body 0, not the count.
    for count in [MAX_BODIES + 1, MILLION] {
        match parse_scene(&many_bodies(count, "{}")) {
            Err(SceneFileError::TopLevel {
                field,
                problem: FieldProblem::TooMany { count: got, limit },
            }) => assert_eq!((field.as_str(), got, limit), ("bodies", count, MAX_BODIES)),
            other => panic!("{count} bodies: {other:?}"),
        }
    }
    // At the limit, the count passes and body 0 is read.
    let at_limit = parse_scene(&many_bodies(MAX_BODIES, "{}"));
    assert!(matches!(
        at_limit,
        Err(SceneFileError::Body { index: 0, .. })
    ));
}

/// A scene of one body whose hull has the given points.
fn hull_scene(points: &[[f64; 3]]) -> String {
    let points: Vec<String> = points
        .iter()
        .map(|p| format!("[{},{},{}]", p[0], p[1], p[2]))
        .collect();
    format!(
        r#"{{"bodies": [{{"name": "rock", "shape": {{"convex_hull": [{}]}},
            "translation": [0, 0, 0], "rotation": [0, 0, 0, 1], "mass": 1}}]}}"#,
        points.join(",")
    )
}

/// `count` points on the unit sphere (a golden-angle spiral): every point
/// is a vertex of the hull.
fn sphere_points(count: usize) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..count)
        .map(|k| {
            let y = 1.0 - 2.0 * (k as f64 + 0.5) / count as f64;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * k as f64;
            [r * phi.cos(), y, r * phi.sin()]
        })
        .collect()
}

#[test]
fn a_million_hull_points_are_refused_before_the_hull_is_built() {
    let points = sphere_points(MILLION);
    match parse_scene(&hull_scene(&points)) {
        Err(SceneFileError::Body {
            index,
            field,
            problem: FieldProblem::TooMany { count, limit },
            ..
        }) => assert_eq!(
            (index, field.as_str(), count, limit),
            (0, "shape.convex_hull", MILLION, MAX_HULL_POINTS)
        ),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_largest_hull_accepted_builds_with_every_point_a_vertex() {
    let scene = parse_scene(&hull_scene(&sphere_points(MAX_HULL_POINTS))).expect("accepted");
    let vertices = scene.bodies()[0]
        .polyhedron()
        .expect("a convex body")
        .vertices()
        .len();
    assert_eq!(vertices, MAX_HULL_POINTS);
}
