//! Bad scene input beyond `scene_file.rs` (which has one error per field
//! kind): numbers beyond f64 anywhere, zero and far-from-unit quaternions,
//! masses and densities that are zero, negative, subnormal or overflow the
//! mass properties, degenerate hulls, empty scenes, malformed and deeply
//! nested JSON, text that is not UTF-8, duplicate names. Each is a typed
//! error naming the body and the field where there is one (or the line and
//! column where the JSON itself is wrong), never a panic; docs/reliability.md
//! lists them. Sizes (files, bodies, hull points) are in
//! `scene_file_limits.rs`.

use constraint_stabilization::body::BodyError;
use constraint_stabilization::internals::geometry::GeometryError;
use constraint_stabilization::io::scene_file::{FieldProblem, SceneFileError, parse_scene};
use constraint_stabilization::{Settings, Stabilizer, Status};

/// A scene whose body 1 ("crate") has the given fields after its name.
fn second_body(fields: &str) -> String {
    format!(
        r#"{{"bodies": [
  {{"name": "ground", "shape": {{"cuboid": [5, 0.5, 5]}}, "translation": [0, -0.5, 0], "rotation": [0, 0, 0, 1], "fixed": true}},
  {{"name": "crate", {fields}}}
]}}"#
    )
}

const SHAPE: &str = r#""shape": {"cuboid": [0.5, 0.5, 0.5]}"#;
const POSE: &str = r#""translation": [0, 0.5, 0], "rotation": [0, 0, 0, 1]"#;

/// The body error of `text`: (index, field, problem).
fn body_error(text: &str) -> (usize, String, FieldProblem) {
    match parse_scene(text) {
        Err(SceneFileError::Body {
            index,
            field,
            problem,
            ..
        }) => (index, field, problem),
        other => panic!("expected a body error, got {other:?}"),
    }
}

/// The line of the JSON error of `text`.
fn json_error_line(text: &str) -> usize {
    match parse_scene(text) {
        Err(SceneFileError::Json { line, .. }) => line,
        other => panic!("expected a JSON error, got {other:?}"),
    }
}

#[test]
fn numbers_beyond_f64_anywhere_are_json_errors_at_their_line() {
    // JSON has no NaN or infinity; a number beyond f64 (1e400) is the only
    // way to write one, and the parser refuses it where it stands (line 3:
    // the bad body's line).
    let places = [
        format!(r#""shape": {{"cuboid": [0.5, 1e400, 0.5]}}, {POSE}, "mass": 1"#),
        format!(
            r#""shape": {{"convex_hull": [[0,0,0],[1,0,0],[0,1,0],[0,0,-1e400]]}}, {POSE}, "mass": 1"#
        ),
        format!(r#"{SHAPE}, "translation": [0, -1e400, 0], "rotation": [0, 0, 0, 1], "mass": 1"#),
        format!(r#"{SHAPE}, "translation": [0, 0, 0], "rotation": [0, 0, 0, 1e999], "mass": 1"#),
        format!(r#"{SHAPE}, {POSE}, "mass": 1e400"#),
        format!(r#"{SHAPE}, {POSE}, "density": 1e400"#),
    ];
    for fields in places {
        assert_eq!(json_error_line(&second_body(&fields)), 3, "{fields}");
    }
    for literal in ["NaN", "Infinity", "-Infinity", "nan"] {
        let fields = format!(r#"{SHAPE}, {POSE}, "mass": {literal}"#);
        assert_eq!(json_error_line(&second_body(&fields)), 3, "{literal}");
    }
    let settings = r#"{"bodies": [], "settings": {"tolerance": 1e400}}"#;
    assert_eq!(json_error_line(settings), 1);
}

#[test]
fn zero_and_far_from_unit_quaternions_are_rotation_errors() {
    for (rotation, norm) in [
        ("[0, 0, 0, 0]", 0.0),
        ("[0, 0, 0, 2]", 2.0),
        ("[0, 0, 0, 1e-300]", 1e-300),
        // The squared norm overflows: reported as infinite, still rejected.
        ("[1e300, 1e300, 0, 0]", f64::INFINITY),
    ] {
        let fields =
            format!(r#"{SHAPE}, "translation": [0, 0.5, 0], "rotation": {rotation}, "mass": 1"#);
        let (index, field, problem) = body_error(&second_body(&fields));
        assert_eq!((index, field.as_str()), (1, "rotation"), "{rotation}");
        match problem {
            FieldProblem::InvalidBody(BodyError::RotationNotUnit { norm: given }) => {
                let close = given == norm || (given - norm).abs() <= 1e-12 * norm.max(1.0);
                assert!(close, "{rotation}: norm {given:e}")
            }
            other => panic!("{rotation}: {other:?}"),
        }
    }
    // Within the tolerance, a quaternion is normalized, not rejected.
    let fields =
        format!(r#"{SHAPE}, "translation": [0, 0.5, 0], "rotation": [0, 0, 0, 1.0009], "mass": 1"#);
    let scene = parse_scene(&second_body(&fields)).expect("near unit is accepted");
    let rotation = scene.bodies()[1].com_pose().rotation;
    assert!((rotation.quaternion().norm() - 1.0).abs() <= f64::EPSILON * 4.0);
}

#[test]
fn masses_and_densities_that_give_no_mass_properties_name_their_field() {
    let cases = [
        (r#""mass": 0"#, "mass"),
        (r#""mass": -0.0"#, "mass"),
        (r#""mass": -1e-300"#, "mass"),
        (r#""density": -1"#, "density"),
        (r#""density": 0"#, "density"),
        // Subnormal mass: the inertia's inverse overflows.
        (r#""mass": 5e-324"#, "mass"),
        // Density of 1e308 over a volume of 1: finite, but the inertia
        // (mass times length squared) is not.
        (r#""density": 1e308"#, "density"),
    ];
    for (mass, expected) in cases {
        let fields = format!(r#"{SHAPE}, {POSE}, {mass}"#);
        let (index, field, problem) = body_error(&second_body(&fields));
        assert_eq!((index, field.as_str()), (1, expected), "{mass}");
        assert!(
            matches!(problem, FieldProblem::InvalidBody(_)),
            "{mass}: {problem:?}"
        );
    }
}

/// Whether a geometry error is the one expected.
type ExpectedError = fn(&GeometryError) -> bool;

#[test]
fn degenerate_hulls_are_shape_errors() {
    let cases: [(&str, ExpectedError); 6] = [
        ("[]", |e| matches!(e, GeometryError::Empty)),
        ("[[0, 0, 0]]", |e| matches!(e, GeometryError::Degenerate)),
        (
            "[[1, 1, 1], [1, 1, 1], [1, 1, 1], [1, 1, 1], [1, 1, 1]]",
            |e| matches!(e, GeometryError::Degenerate),
        ),
        ("[[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]", |e| {
            matches!(e, GeometryError::Degenerate)
        }),
        (
            "[[0, 0, 0], [1e-60, 0, 0], [0, 1e-60, 0], [0, 0, 1e-60]]",
            |e| matches!(e, GeometryError::CoordinatesOutOfRange { .. }),
        ),
        (
            "[[0, 0, 0], [1e60, 0, 0], [0, 1e60, 0], [0, 0, 1e60]]",
            |e| matches!(e, GeometryError::CoordinatesOutOfRange { .. }),
        ),
    ];
    for (points, expected) in cases {
        let fields = format!(r#""shape": {{"convex_hull": {points}}}, {POSE}, "mass": 1"#);
        let (index, field, problem) = body_error(&second_body(&fields));
        assert_eq!((index, field.as_str()), (1, "shape"), "{points}");
        match problem {
            FieldProblem::InvalidBody(BodyError::Shape(error)) => {
                assert!(expected(&error), "{points}: {error:?}")
            }
            other => panic!("{points}: {other:?}"),
        }
    }
}

#[test]
fn an_empty_scene_reads_and_has_nothing_to_do() {
    let mut scene = parse_scene(r#"{"bodies": []}"#).expect("empty scene");
    let report = Stabilizer::new(Settings::default())
        .expect("valid settings")
        .stabilize(&mut scene)
        .expect("no error");
    assert_eq!((report.status, report.passes), (Status::NothingToDo, 0));
    for (text, field) in [
        ("{}", "bodies"),
        ("[]", "(root)"),
        ("null", "(root)"),
        ("3", "(root)"),
    ] {
        match parse_scene(text) {
            Err(SceneFileError::TopLevel { field: got, .. }) => assert_eq!(got, field, "{text}"),
            other => panic!("{text}: {other:?}"),
        }
    }
}

#[test]
fn malformed_json_is_an_error_with_its_line() {
    let good = second_body(&format!("{SHAPE}, {POSE}, \"mass\": 1"));
    let cases = [
        String::new(),
        "   \n  ".to_string(),
        good[..good.len() / 2].to_string(),
        good.replace("\"mass\": 1", "\"mass\": 1,"),
        format!("{good} x"),
        format!("{good}{good}"),
        good.replace("\"crate\"", "'crate'"),
        good.replace("\"crate\"", "\"cr\u{1}ate\""),
        format!("// a comment\n{good}"),
        good.replace("\"mass\"", "mass"),
    ];
    for text in cases {
        assert!(
            matches!(parse_scene(&text), Err(SceneFileError::Json { .. })),
            "{text:?}"
        );
    }
}

#[test]
fn deeply_nested_json_is_an_error_not_a_stack_overflow() {
    // The ignored `report` field and a settings value, each 100,000 deep:
    // serde_json's recursion limit (128) refuses them.
    let deep = format!("{}1{}", "[".repeat(100_000), "]".repeat(100_000));
    for text in [
        format!(r#"{{"bodies": [], "report": {deep}}}"#),
        format!(r#"{{"bodies": [], "settings": {{"tolerance": {deep}}}}}"#),
        format!(r#"{{"bodies": [{deep}]}}"#),
    ] {
        assert!(matches!(
            parse_scene(&text),
            Err(SceneFileError::Json { .. })
        ));
    }
}

#[test]
fn text_that_is_not_utf8_is_a_read_error() {
    let path = std::env::temp_dir().join(format!("cs-not-utf8-{}.json", std::process::id()));
    std::fs::write(&path, b"{\"bodies\": [\xff\xfe]}").expect("temp file");
    let result = constraint_stabilization::io::scene_file::read_scene(&path);
    let _ = std::fs::remove_file(&path);
    assert!(
        matches!(&result, Err(SceneFileError::Read { message, .. }) if message.contains("UTF-8")),
        "{result:?}"
    );
}

#[test]
fn duplicate_names_are_labels_and_errors_give_the_index() {
    // Names need not be unique (src/scene.rs): two bodies called "crate"
    // read, and an error in the second names it by index.
    let body = format!(r#"{{"name": "crate", {SHAPE}, {POSE}, "mass": 1}}"#);
    let text = format!(r#"{{"bodies": [{body}, {body}]}}"#);
    assert_eq!(parse_scene(&text).expect("duplicate names read").len(), 2);
    let bad = format!(r#"{{"name": "crate", {SHAPE}, {POSE}, "mass": -1}}"#);
    let (index, field, _) = body_error(&format!(r#"{{"bodies": [{body}, {bad}]}}"#));
    assert_eq!((index, field.as_str()), (1, "mass"));
}
