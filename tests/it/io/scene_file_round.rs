//! Round and curved shapes in scene files (`src/io/round_shapes.rs`):
//! every kind reads, writes and reads back to the same shape bit for bit;
//! bad input is a typed error naming the body and the field; the picture
//! draws them.

use constraint_stabilization::body::{BodyError, Shape};
use constraint_stabilization::internals::geometry::GeometryError;
use constraint_stabilization::io::scene_file::{
    FieldProblem, SceneFileError, parse_scene, scene_to_string,
};

const POSE: &str = r#""translation": [0, 0.5, 0], "rotation": [0, 0, 0, 1]"#;

fn scene_with(shape: &str) -> String {
    format!(r#"{{"bodies": [{{"name": "round", "shape": {shape}, {POSE}, "mass": 1.5}}]}}"#)
}

/// A check of the problem found.
type ProblemCheck = fn(&FieldProblem) -> bool;

fn body_error(text: &str) -> (String, FieldProblem) {
    match parse_scene(text) {
        Err(SceneFileError::Body { field, problem, .. }) => (field, problem),
        other => panic!("expected a body error, got {other:?}"),
    }
}

#[test]
fn every_round_kind_round_trips() {
    let shapes = [
        r#"{"sphere": 0.1}"#,
        r#"{"capsule": {"half_height": 0.3, "radius": 0.1}}"#,
        r#"{"cylinder": {"half_height": 0.3, "radius": 0.2}}"#,
        r#"{"cone": {"half_height": 0.3, "radius": 0.2}}"#,
        r#"{"cuboid": [0.1, 0.2, 0.3], "radius": 0.05}"#,
        r#"{"cuboid": [0.1, 0.2, 0.3], "radius": 0}"#,
        r#"{"convex_hull": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "radius": 0.1}"#,
        r#"{"compound": [{"shape": {"sphere": 0.2}, "translation": [0.3, 0, 0], "rotation": [0, 0, 0, 1]},
                         {"shape": {"capsule": {"half_height": 0.3, "radius": 0.1}}, "translation": [0, 0, 0], "rotation": [0, 0, 0, 1]}]}"#,
    ];
    for shape in shapes {
        let scene = parse_scene(&scene_with(shape)).unwrap_or_else(|e| panic!("{shape}: {e}"));
        let written = scene_to_string(&scene, None);
        let back = parse_scene(&written).unwrap_or_else(|e| panic!("{written}: {e}"));
        assert_eq!(
            back.bodies()[0].shape(),
            scene.bodies()[0].shape(),
            "{written}"
        );
        assert_eq!(back.bodies()[0].mass(), scene.bodies()[0].mass());
    }
    let scene = parse_scene(&scene_with(
        r#"{"cuboid": [0.1, 0.2, 0.3], "radius": 0.05}"#,
    ))
    .expect("valid");
    assert!(
        matches!(scene.bodies()[0].shape(), Shape::RoundCuboid { radius, .. } if *radius == 0.05)
    );
    let written = scene_to_string(&scene, None);
    assert!(written.contains("\"radius\": 0.05"), "{written}");
}

#[test]
fn bad_round_shapes_are_typed_errors_naming_the_field() {
    let cases: [(&str, &str, ProblemCheck); 10] = [
        (r#"{"sphere": -1}"#, "shape", |p| {
            matches!(
                p,
                FieldProblem::InvalidBody(BodyError::Shape(GeometryError::InvalidDimension { .. }))
            )
        }),
        (r#"{"sphere": [1]}"#, "shape.sphere", |p| {
            matches!(p, FieldProblem::WrongType(_))
        }),
        (
            r#"{"capsule": {"half_height": 1}}"#,
            "shape.capsule.radius",
            |p| *p == FieldProblem::Missing,
        ),
        (
            r#"{"capsule": {"half_height": 1, "radius": 1, "axis": 2}}"#,
            "shape.capsule.axis",
            |p| *p == FieldProblem::Unknown,
        ),
        (
            r#"{"cylinder": {"half_height": 0, "radius": 1}}"#,
            "shape",
            |p| {
                matches!(
                    p,
                    FieldProblem::InvalidBody(BodyError::Shape(
                        GeometryError::InvalidDimension { .. }
                    ))
                )
            },
        ),
        (r#"{"cuboid": [1, 1, 1], "radius": -0.1}"#, "shape", |p| {
            matches!(
                p,
                FieldProblem::InvalidBody(BodyError::Shape(GeometryError::InvalidRadius { .. }))
            )
        }),
        (
            r#"{"cuboid": [1, 1, 1], "radius": "big"}"#,
            "shape.radius",
            |p| matches!(p, FieldProblem::WrongType(_)),
        ),
        (r#"{"sphere": 1, "radius": 1}"#, "shape.radius", |p| {
            matches!(p, FieldProblem::Conflict(_))
        }),
        (
            r#"{"sphere": 1, "cone": {"half_height": 1, "radius": 1}}"#,
            "shape",
            |p| matches!(p, FieldProblem::Conflict(_)),
        ),
        (r#"{"compound": [], "radius": 1}"#, "shape.radius", |p| {
            matches!(p, FieldProblem::Conflict(_))
        }),
    ];
    for (shape, field, check) in cases {
        let (got_field, problem) = body_error(&scene_with(shape));
        assert_eq!(got_field, field, "{shape}: {problem:?}");
        assert!(check(&problem), "{shape}: {problem:?}");
    }
}

#[cfg(feature = "testbed")]
#[test]
fn the_picture_draws_round_shapes_as_curved_surfaces() {
    use constraint_stabilization::testbed::render::{View, render_svg};
    let scene = parse_scene(&scene_with(r#"{"sphere": 0.5}"#)).expect("valid");
    let svg = render_svg(&scene, View::Iso, &[]);
    // A geodesic sphere of 320 triangles shows about half of them; the
    // bounding box would show three faces.
    let faces = svg.matches("class=\"face").count();
    assert!(faces > 100, "{faces} faces drawn");
}
