//! Scene JSON: exact round trip of numbers, and one error per kind of bad
//! input, each naming the body (index and name) and the field.

use crate::support::proptest_config;
use constraint_stabilization::SettingsError;
use constraint_stabilization::body::{BodyError, MassSpec, Shape};
use constraint_stabilization::io::scene_file::{
    FieldProblem, SceneFileError, parse_scene, scene_to_string,
};
use constraint_stabilization::solver::SolverChoice;
use proptest::prelude::*;

const DESIGN_EXAMPLE: &str = r#"{
  "bodies": [
    { "name": "ground", "shape": { "cuboid": [10.0, 0.5, 10.0] },
      "translation": [0.0, -0.5, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0],
      "fixed": true },
    { "name": "rock", "shape": { "convex_hull": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]] },
      "translation": [0.2, 0.1, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0],
      "mass": 2.5 }
  ],
  "settings": { "tolerance": 1e-6 }
}"#;

#[test]
fn design_example_reads_and_round_trips() {
    let scene = parse_scene(DESIGN_EXAMPLE).unwrap();
    assert_eq!(scene.len(), 2);
    let rock = &scene.bodies()[1];
    assert_eq!(rock.name(), "rock");
    assert_eq!(rock.mass_spec(), MassSpec::Mass(2.5));
    assert!(matches!(rock.shape(), Shape::ConvexHull { points } if points.len() == 4));
    assert!(scene.bodies()[0].is_fixed());
    // The hull's points are in its shape frame: the centre of mass of the
    // unit tetrahedron is (1/4, 1/4, 1/4) there, so (0.45, 0.35, 0.25) in world.
    let com = rock.com_world();
    assert!(
        (com - nalgebra::Point3::new(0.45, 0.35, 0.25)).norm() < 1e-12,
        "{com}"
    );
    assert_eq!(
        rock.translation_user(),
        &nalgebra::Vector3::new(0.2, 0.1, 0.0)
    );
    assert_eq!(scene.settings().tolerance, Some(1e-6));
    let written = scene_to_string(&scene, None);
    let again = scene_to_string(&parse_scene(&written).unwrap(), None);
    assert_eq!(written, again);
    // Same numbers as the input, compared as JSON values.
    let input: serde_json::Value = serde_json::from_str(DESIGN_EXAMPLE).unwrap();
    let output: serde_json::Value = serde_json::from_str(&written).unwrap();
    for (k, key) in ["translation", "rotation"].iter().enumerate() {
        for b in 0..2 {
            let a: Vec<f64> = serde_json::from_value(input["bodies"][b][key].clone()).unwrap();
            let o: Vec<f64> = serde_json::from_value(output["bodies"][b][key].clone()).unwrap();
            assert_eq!(a, o, "{k} {key}");
        }
    }
}

#[test]
fn output_with_report_reads_back_as_the_same_scene() {
    let scene = parse_scene(DESIGN_EXAMPLE).unwrap();
    let report = serde_json::json!({"passes": 3, "solver": "lemke"});
    let written = scene_to_string(&scene, Some(&report));
    let value: serde_json::Value = serde_json::from_str(&written).unwrap();
    assert_eq!(value["report"], report);
    let back = parse_scene(&written).unwrap();
    assert_eq!(scene_to_string(&back, None), scene_to_string(&scene, None));
}

/// Any finite f64 (not only "nice" decimals) and a quaternion a little off
/// unit; the text is written with Rust's shortest round-trip formatting.
fn any_finite() -> impl Strategy<Value = f64> {
    prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO
}

proptest! {
    #![proptest_config(proptest_config::config(200))]

    #[test]
    fn numbers_round_trip_bit_for_bit(
        t in prop::array::uniform3(any_finite()),
        q in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, 0.2..1.0f64, -5e-4..5e-4f64),
        half in prop::array::uniform3(1e-3..1e3f64),
        mass in 1e-3..1e6f64,
    ) {
        let n = (q.0 * q.0 + q.1 * q.1 + q.2 * q.2 + q.3 * q.3).sqrt() * (1.0 + q.4);
        let rotation = [q.0 / n, q.1 / n, q.2 / n, q.3 / n];
        let text = format!(
            r#"{{"bodies": [{{"name": "b", "shape": {{"cuboid": {half:?}}}, "translation": {t:?}, "rotation": {rotation:?}, "mass": {mass:?}}}]}}"#
        );
        let scene = parse_scene(&text).unwrap();
        let body = &scene.bodies()[0];
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        prop_assert_eq!(bits(body.translation_user().as_slice()), bits(&t));
        prop_assert_eq!(bits(&body.rotation_user_xyzw()), bits(&rotation));
        let written = scene_to_string(&scene, None);
        let back = parse_scene(&written).unwrap();
        let body_back = &back.bodies()[0];
        prop_assert_eq!(bits(body_back.translation_user().as_slice()), bits(&t));
        prop_assert_eq!(bits(&body_back.rotation_user_xyzw()), bits(&rotation));
        prop_assert_eq!(body_back.mass_spec(), MassSpec::Mass(mass));
        prop_assert_eq!(body_back.shape(), body.shape());
    }
}

fn body_error(text: &str) -> (usize, Option<String>, String, FieldProblem, String) {
    match parse_scene(text) {
        Err(e @ SceneFileError::Body { .. }) => {
            let message = e.to_string();
            let SceneFileError::Body {
                index,
                name,
                field,
                problem,
            } = e
            else {
                unreachable!()
            };
            (index, name, field, problem, message)
        }
        other => panic!("expected a body error, got {other:?}"),
    }
}

/// A scene whose second body (index 1, "crate") has the given fields.
fn with_second_body(fields: &str) -> String {
    format!(
        r#"{{"bodies": [
            {{"name": "ground", "shape": {{"cuboid": [5, 1, 5]}}, "translation": [0, -1, 0], "rotation": [0, 0, 0, 1], "fixed": true}},
            {{"name": "crate", {fields}}}
        ]}}"#
    )
}

/// Fields of the bad body, the field the error must name, and a check of
/// the problem.
type ProblemCheck = fn(&FieldProblem) -> bool;

const SHAPE: &str = r#""shape": {"cuboid": [1, 1, 1]}"#;
const POSE: &str = r#""translation": [0, 1, 0], "rotation": [0, 0, 0, 1]"#;

#[test]
fn body_field_errors_name_index_name_and_field() {
    let cases: Vec<(String, &str, ProblemCheck)> = vec![
        (
            format!(r#"{SHAPE}, {POSE}, "mass": 1, "colour": "red""#),
            "colour",
            |p| *p == FieldProblem::Unknown,
        ),
        (format!(r#"{POSE}, "mass": 1"#), "shape", |p| {
            *p == FieldProblem::Missing
        }),
        (
            format!(r#"{SHAPE}, "rotation": [0, 0, 0, 1], "mass": 1"#),
            "translation",
            |p| *p == FieldProblem::Missing,
        ),
        (
            format!(r#"{SHAPE}, "translation": [0, 1, 0], "mass": 1"#),
            "rotation",
            |p| *p == FieldProblem::Missing,
        ),
        (
            format!(r#"{SHAPE}, "translation": [0, 1], "rotation": [0, 0, 0, 1], "mass": 1"#),
            "translation",
            |p| matches!(p, FieldProblem::WrongType(_)),
        ),
        (
            format!(r#"{SHAPE}, "translation": [0, 1, "x"], "rotation": [0, 0, 0, 1], "mass": 1"#),
            "translation",
            |p| matches!(p, FieldProblem::WrongType(_)),
        ),
        (
            format!(r#"{SHAPE}, "translation": [0, 1, 0], "rotation": [0, 0, 0, 3], "mass": 1"#),
            "rotation",
            |p| {
                matches!(
                    p,
                    FieldProblem::InvalidBody(BodyError::RotationNotUnit { .. })
                )
            },
        ),
        (format!(r#"{SHAPE}, {POSE}"#), "mass", |p| {
            matches!(p, FieldProblem::Conflict(_))
        }),
        (
            format!(r#"{SHAPE}, {POSE}, "mass": 1, "density": 2"#),
            "density",
            |p| matches!(p, FieldProblem::Conflict(_)),
        ),
        (
            format!(r#"{SHAPE}, {POSE}, "fixed": true, "mass": 1"#),
            "mass",
            |p| matches!(p, FieldProblem::Conflict(_)),
        ),
        (
            format!(r#"{SHAPE}, {POSE}, "fixed": "yes""#),
            "fixed",
            |p| matches!(p, FieldProblem::WrongType(_)),
        ),
        (format!(r#"{SHAPE}, {POSE}, "mass": -1"#), "mass", |p| {
            matches!(p, FieldProblem::InvalidBody(BodyError::InvalidMass(_)))
        }),
        (
            format!(r#"{SHAPE}, {POSE}, "density": 0"#),
            "density",
            |p| matches!(p, FieldProblem::InvalidBody(BodyError::InvalidDensity(_))),
        ),
        (
            format!(r#"{SHAPE}, {POSE}, "mass": "heavy""#),
            "mass",
            |p| matches!(p, FieldProblem::WrongType(_)),
        ),
        (
            format!(r#""shape": {{"torus": 1}}, {POSE}, "mass": 1"#),
            "shape.torus",
            |p| *p == FieldProblem::Unknown,
        ),
        (
            format!(r#""shape": {{}}, {POSE}, "mass": 1"#),
            "shape",
            |p| matches!(p, FieldProblem::Conflict(_)),
        ),
        (
            format!(
                r#""shape": {{"cuboid": [1, 1, 1], "convex_hull": [[0, 0, 0]]}}, {POSE}, "mass": 1"#
            ),
            "shape",
            |p| matches!(p, FieldProblem::Conflict(_)),
        ),
        (
            format!(r#""shape": {{"cuboid": [1, -1, 1]}}, {POSE}, "mass": 1"#),
            "shape",
            |p| matches!(p, FieldProblem::InvalidBody(BodyError::Shape(_))),
        ),
        (
            format!(
                r#""shape": {{"convex_hull": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]}}, {POSE}, "mass": 1"#
            ),
            "shape",
            |p| matches!(p, FieldProblem::InvalidBody(BodyError::Shape(_))),
        ),
        (
            format!(r#""shape": {{"convex_hull": [[0, 0], [1, 0, 0]]}}, {POSE}, "mass": 1"#),
            "shape.convex_hull",
            |p| matches!(p, FieldProblem::WrongType(_)),
        ),
        (
            format!(r#""shape": [1, 1, 1], {POSE}, "mass": 1"#),
            "shape",
            |p| matches!(p, FieldProblem::WrongType(_)),
        ),
    ];
    for (fields, expected_field, check) in cases {
        let (index, name, field, problem, message) = body_error(&with_second_body(&fields));
        assert_eq!(
            (index, name.as_deref(), field.as_str()),
            (1, Some("crate"), expected_field),
            "{fields}"
        );
        assert!(check(&problem), "{fields}: {problem:?}");
        assert!(
            message.contains("body 1")
                && message.contains("\"crate\"")
                && message.contains(expected_field),
            "{message}"
        );
    }
}

#[test]
fn body_without_a_string_name_is_named_by_index() {
    let (index, name, field, problem, message) = body_error(
        &with_second_body(&format!("{SHAPE}, {POSE}, \"mass\": 1"))
            .replace("\"name\": \"crate\",", ""),
    );
    assert_eq!(
        (index, name, field.as_str(), problem),
        (1, None, "name", FieldProblem::Missing)
    );
    assert!(message.contains("body 1 (unnamed)"), "{message}");
    let (_, name, field, _, _) = body_error(
        &with_second_body(&format!("{SHAPE}, {POSE}, \"mass\": 1")).replace("\"crate\"", "7"),
    );
    assert_eq!((name, field.as_str()), (None, "name"));
    let (index, _, field, _, _) = body_error(r#"{"bodies": [3]}"#);
    assert_eq!((index, field.as_str()), (0, "(body)"));
}

fn top_or_settings(text: &str) -> SceneFileError {
    parse_scene(text).unwrap_err()
}

#[test]
fn document_and_settings_errors_name_the_field() {
    assert!(matches!(
        top_or_settings("{\"bodies\": [}"),
        SceneFileError::Json { line: 1, .. }
    ));
    let duplicate = with_second_body(&format!("{SHAPE}, {POSE}, \"mass\": 1, \"mass\": 2"));
    match top_or_settings(&duplicate) {
        SceneFileError::Json {
            line: 3, message, ..
        } => {
            assert!(message.contains("duplicate field `mass`"), "{message}")
        }
        other => panic!("expected a duplicate-field error, got {other:?}"),
    }
    assert!(matches!(
        top_or_settings("[]"),
        SceneFileError::TopLevel {
            problem: FieldProblem::WrongType(_),
            ..
        }
    ));
    assert_eq!(
        top_or_settings("{}"),
        SceneFileError::TopLevel {
            field: "bodies".into(),
            problem: FieldProblem::Missing
        }
    );
    assert!(matches!(
        top_or_settings(r#"{"bodies": {}}"#),
        SceneFileError::TopLevel {
            problem: FieldProblem::WrongType(_),
            ..
        }
    ));
    assert_eq!(
        top_or_settings(r#"{"bodies": [], "gravity": 9.81}"#),
        SceneFileError::TopLevel {
            field: "gravity".into(),
            problem: FieldProblem::Unknown
        }
    );
    let settings = |s: &str| top_or_settings(&format!(r#"{{"bodies": [], "settings": {s}}}"#));
    let field_of = |e: SceneFileError| match e {
        SceneFileError::Settings { field, problem } => (field, problem),
        other => panic!("expected a settings error, got {other:?}"),
    };
    assert_eq!(
        field_of(settings(r#"{"tolerence": 1e-6}"#)),
        ("tolerence".into(), FieldProblem::Unknown)
    );
    assert!(
        matches!(field_of(settings(r#"{"tolerance": "small"}"#)), (f, FieldProblem::WrongType(_)) if f == "tolerance")
    );
    assert!(matches!(
        field_of(settings(r#"{"tolerance": -1}"#)),
        (f, FieldProblem::InvalidSetting(SettingsError::OutOfRange { .. })) if f == "tolerance"
    ));
    assert!(
        matches!(field_of(settings(r#"{"contact_margin": -0.1}"#)), (f, _) if f == "contact_margin")
    );
    assert!(
        matches!(field_of(settings(r#"{"target_margin": -0.1}"#)), (f, _) if f == "target_margin")
    );
    assert!(
        matches!(field_of(settings(r#"{"max_passes": 0}"#)), (f, FieldProblem::InvalidSetting(SettingsError::TooFew { least: 1, .. })) if f == "max_passes")
    );
    assert!(
        matches!(field_of(settings(r#"{"max_passes": 2.5}"#)), (f, FieldProblem::WrongType(_)) if f == "max_passes")
    );
    assert!(
        matches!(field_of(settings(r#"{"solver": "simplex"}"#)), (f, FieldProblem::WrongType(_)) if f == "solver")
    );
    assert!(
        matches!(field_of(settings(r#"{"cross_check": 1}"#)), (f, FieldProblem::WrongType(_)) if f == "cross_check")
    );
    assert!(
        matches!(top_or_settings(r#"{"bodies": [], "settings": 5}"#), SceneFileError::TopLevel { field, .. } if field == "settings")
    );
}

#[test]
fn every_settings_field_reads_and_round_trips() {
    let text = r#"{"bodies": [], "settings": {"tolerance": 1e-7, "contact_margin": 0.01, "target_margin": 0.001,
        "max_passes": 12, "solver": "pgs", "cross_check": true}}"#;
    let scene = parse_scene(text).unwrap();
    let s = scene.settings();
    assert_eq!(
        (
            s.tolerance,
            s.contact_margin,
            s.target_margin,
            s.max_passes,
            s.solver,
            s.cross_check
        ),
        (
            Some(1e-7),
            Some(0.01),
            Some(0.001),
            Some(12),
            Some(SolverChoice::Pgs),
            Some(true)
        )
    );
    assert_eq!(
        parse_scene(&scene_to_string(&scene, None))
            .unwrap()
            .settings(),
        s
    );
    for choice in SolverChoice::ALL {
        assert_eq!(SolverChoice::from_name(choice.name()), Some(choice));
    }
    // No settings in, none out.
    let empty = parse_scene(r#"{"bodies": []}"#).unwrap();
    assert!(!scene_to_string(&empty, None).contains("settings"));
}

/// A body's own friction coefficient reads, round-trips, and a bad one is
/// an error naming the body and the field.
#[test]
fn body_friction_reads_round_trips_and_is_checked() {
    let text = with_second_body(&format!(r#"{SHAPE}, {POSE}, "mass": 2, "friction": 0.75"#));
    let scene = parse_scene(&text).expect("valid scene");
    assert_eq!(scene.bodies()[1].friction(), Some(0.75));
    assert_eq!(scene.bodies()[0].friction(), None);
    let back = parse_scene(&scene_to_string(&scene, None)).expect("reads back");
    assert_eq!(back.bodies()[1].friction(), Some(0.75));
    for bad in ["-0.5", "\"rough\""] {
        let text = with_second_body(&format!(r#"{SHAPE}, {POSE}, "mass": 2, "friction": {bad}"#));
        let (index, name, field, _, message) = body_error(&text);
        assert_eq!(
            (index, name.as_deref(), field.as_str()),
            (1, Some("crate"), "friction"),
            "{message}"
        );
    }
}
