//! Bad joints in scene files: each is a typed `SceneFileError::Joint`
//! naming the joint (index and name) and the field, never a panic.
//! Unknown, missing and mistyped fields; bodies unknown, ambiguous, the
//! same, or both fixed; degenerate axes, references and quaternions;
//! limits out of order, on types without them, on locked axes; unknown or
//! repeated axes; a generic joint locking nothing; too many joints.

use constraint_stabilization::io::scene_file::{
    FieldProblem, MAX_JOINTS, SceneFileError, parse_scene,
};
use constraint_stabilization::io::scene_joints::FrameProblem;
use constraint_stabilization::joints::JointError;

/// Bodies 0 "ground" (fixed), 1 "a", 2 "b", 3 and 4 "twin", 5 "wall"
/// (fixed); a first, valid joint; then `joint` as joint 1.
fn scene_with(joint: &str) -> String {
    let body = |name: &str, x: f64, mass: &str| {
        format!(
            r#"{{"name": "{name}", "shape": {{"cuboid": [0.5, 0.5, 0.5]}}, "translation": [{x}, 3, 0], "rotation": [0, 0, 0, 1], {mass}}}"#
        )
    };
    let bodies = [
        body("ground", 0.0, r#""fixed": true"#),
        body("a", 2.0, r#""mass": 1"#),
        body("b", 4.0, r#""mass": 1"#),
        body("twin", 6.0, r#""mass": 1"#),
        body("twin", 8.0, r#""mass": 1"#),
        body("wall", 10.0, r#""fixed": true"#),
    ];
    let good = r#"{"name": "good", "type": "spherical", "bodies": ["a", "b"], "anchor_a": [0, 0, 0], "anchor_b": [0, 0, 0]}"#;
    format!(
        r#"{{"bodies": [{}],
"joints": [{good},
{joint}]}}"#,
        bodies.join(",\n")
    )
}

/// Joint 1 with the common fields (`name` "j", type `kind`, bodies a and
/// b, anchors) replaced or extended by `extra` (`"field": value, ...`,
/// which may repeat none of the common ones).
fn joint_with(kind: &str, extra: &str) -> String {
    let sep = if extra.is_empty() { "" } else { ", " };
    scene_with(&format!(
        r#"{{"name": "j", "type": "{kind}", "bodies": ["a", "b"], "anchor_a": [0, 1, 0], "anchor_b": [0, -1, 0]{sep}{extra}}}"#
    ))
}

/// The joint error of `text`: (index, name, field, problem).
fn joint_error(text: &str) -> (usize, Option<String>, String, FieldProblem) {
    match parse_scene(text) {
        Err(SceneFileError::Joint {
            index,
            name,
            field,
            problem,
        }) => (index, name, field, problem),
        other => panic!("expected a joint error, got {other:?}"),
    }
}

/// Asserts that joint 1 ("j") of `text` is refused at `field` with
/// `problem`, and that the message names the joint and the field.
fn assert_refused(text: &str, field: &str, problem: FieldProblem) {
    let error = parse_scene(text).expect_err("refused");
    let message = error.to_string();
    assert_eq!(
        joint_error(text),
        (1, Some("j".to_string()), field.to_string(), problem),
        "{message}"
    );
    assert!(
        message.contains("joint 1") && message.contains("\"j\"") && message.contains(field),
        "{message}"
    );
}

#[test]
fn unknown_fields_are_refused() {
    for field in ["anchor_c", "axis", "limit", "Bodies"] {
        let text = joint_with("revolute", &format!(r#""{field}": 1"#));
        assert_refused(&text, field, FieldProblem::Unknown);
    }
}

#[test]
fn missing_fields_are_refused() {
    let full = [
        r#""name": "j""#,
        r#""type": "revolute""#,
        r#""bodies": ["a", "b"]"#,
        r#""anchor_a": [0, 1, 0]"#,
        r#""anchor_b": [0, -1, 0]"#,
    ];
    for (skip, field) in ["name", "type", "bodies", "anchor_a", "anchor_b"]
        .into_iter()
        .enumerate()
    {
        let fields: Vec<&str> = (0..full.len())
            .filter(|&i| i != skip)
            .map(|i| full[i])
            .collect();
        let text = scene_with(&format!("{{{}}}", fields.join(", ")));
        let (index, name, got, problem) = joint_error(&text);
        assert_eq!(
            (index, got.as_str(), problem),
            (1, field, FieldProblem::Missing)
        );
        assert_eq!(name, (field != "name").then(|| "j".to_string()));
    }
    let text = joint_with("generic", "");
    assert_refused(&text, "locked", FieldProblem::Missing);
}

#[test]
fn values_of_the_wrong_type_are_refused() {
    let cases = [
        ("revolute", r#""rotation_b": "identity""#, "rotation_b"),
        ("revolute", r#""axis_a": [0, 1]"#, "axis_a"),
        ("revolute", r#""reference_b": [0, 1, "z"]"#, "reference_b"),
        ("revolute", r#""rotation_a": [0, 0, 1]"#, "rotation_a"),
        ("revolute", r#""limits": [1]"#, "limits"),
        ("prismatic", r#""limits": {"min": 0, "max": 1}"#, "limits"),
        ("generic", r#""locked": "x""#, "locked"),
        ("generic", r#""locked": ["x", 3]"#, "locked[1]"),
        (
            "generic",
            r#""locked": ["x"], "axis_limits": [[0, 1]]"#,
            "axis_limits",
        ),
        (
            "generic",
            r#""locked": ["x"], "axis_limits": {"y": [0, 1, 2]}"#,
            "axis_limits.y",
        ),
    ];
    for (kind, extra, field) in cases {
        let (index, _, got, problem) = joint_error(&joint_with(kind, extra));
        assert_eq!((index, got.as_str()), (1, field), "{extra}");
        assert!(matches!(problem, FieldProblem::WrongType(_)), "{problem:?}");
    }
    // The common fields, replaced.
    let whole = |name: &str, kind: &str, bodies: &str| {
        scene_with(&format!(
            r#"{{"name": {name}, "type": {kind}, "bodies": {bodies}, "anchor_a": [0, 0, 0], "anchor_b": [0, 0, 0]}}"#
        ))
    };
    let cases = [
        (whole("7", r#""fixed""#, r#"["a", "b"]"#), "name"),
        (whole(r#""j""#, r#""hinge""#, r#"["a", "b"]"#), "type"),
        (whole(r#""j""#, "1", r#"["a", "b"]"#), "type"),
        (whole(r#""j""#, r#""fixed""#, r#"["a"]"#), "bodies"),
        (
            whole(r#""j""#, r#""fixed""#, r#"["a", "b", "ground"]"#),
            "bodies",
        ),
        (whole(r#""j""#, r#""fixed""#, r#""a""#), "bodies"),
        (whole(r#""j""#, r#""fixed""#, "[1, -1]"), "bodies[1]"),
        (whole(r#""j""#, r#""fixed""#, "[1.5, 2]"), "bodies[0]"),
        (whole(r#""j""#, r#""fixed""#, r#"[1, null]"#), "bodies[1]"),
        (scene_with("[1, 2]"), "(joint)"),
        (
            scene_with(
                r#"{"name": "j", "type": "fixed", "bodies": [1, 2], "anchor_a": [0, 0], "anchor_b": [0, 0, 0]}"#,
            ),
            "anchor_a",
        ),
        (
            scene_with(
                r#"{"name": "j", "type": "fixed", "bodies": [1, 2], "anchor_a": [0, 0, 0], "anchor_b": "origin"}"#,
            ),
            "anchor_b",
        ),
    ];
    for (text, field) in cases {
        let (index, _, got, problem) = joint_error(&text);
        assert_eq!((index, got.as_str()), (1, field), "{text}");
        assert!(matches!(problem, FieldProblem::WrongType(_)), "{problem:?}");
    }
    let top = parse_scene(r#"{"bodies": [], "joints": {"name": "j"}}"#).err();
    assert_eq!(
        top,
        Some(SceneFileError::TopLevel {
            field: "joints".into(),
            problem: FieldProblem::WrongType("an array"),
        })
    );
}

fn with_bodies(bodies: &str) -> String {
    scene_with(&format!(
        r#"{{"name": "j", "type": "spherical", "bodies": {bodies}, "anchor_a": [0, 0, 0], "anchor_b": [0, 0, 0]}}"#
    ))
}

#[test]
fn unknown_ambiguous_same_and_fixed_bodies_are_refused() {
    let unknown = |s: &str| FieldProblem::UnknownBody(s.into());
    assert_refused(&with_bodies(r#"["a", "c"]"#), "bodies[1]", unknown("\"c\""));
    assert_refused(&with_bodies(r#"["A", "b"]"#), "bodies[0]", unknown("\"A\""));
    assert_refused(&with_bodies("[6, 1]"), "bodies[0]", unknown("6 (of 6)"));
    let huge = "[1, 18446744073709551615]";
    assert_refused(
        &with_bodies(huge),
        "bodies[1]",
        unknown("18446744073709551615 (of 6)"),
    );
    let ambiguous = FieldProblem::AmbiguousBody {
        name: "twin".into(),
        count: 2,
    };
    assert_refused(&with_bodies(r#"["a", "twin"]"#), "bodies[1]", ambiguous);
    // By index, a twin is fine.
    assert!(parse_scene(&with_bodies(r#"["a", 4]"#)).is_ok());
    let same = FieldProblem::InvalidJoint(JointError::SameBody { body: 1 });
    assert_refused(&with_bodies(r#"["a", 1]"#), "bodies", same);
    let fixed = FieldProblem::InvalidJoint(JointError::BothFixed {
        body_a: 0,
        body_b: 5,
    });
    assert_refused(&with_bodies(r#"["ground", "wall"]"#), "bodies", fixed);
    // One fixed body is fine.
    assert!(parse_scene(&with_bodies(r#"["ground", "a"]"#)).is_ok());
}

#[test]
fn degenerate_axes_references_and_quaternions_are_refused() {
    let frame = FieldProblem::DegenerateFrame;
    let cases = [
        (
            r#""axis_a": [0, 0, 0]"#,
            "axis_a",
            FrameProblem::NotADirection,
        ),
        (
            r#""axis_b": [-0.0, 0, 0]"#,
            "axis_b",
            FrameProblem::NotADirection,
        ),
        (
            r#""axis_a": [0, 1, 0], "reference_a": [0, 0, 0]"#,
            "reference_a",
            FrameProblem::NotADirection,
        ),
        (
            r#""axis_b": [0, 1, 0], "reference_b": [0, -3, 0]"#,
            "reference_b",
            FrameProblem::ReferenceParallel,
        ),
        (
            // The default axis is x.
            r#""reference_a": [2, 1e-9, 0]"#,
            "reference_a",
            FrameProblem::ReferenceParallel,
        ),
        (
            r#""rotation_a": [0, 0, 0, 0]"#,
            "rotation_a",
            FrameProblem::RotationNotUnit { norm: 0.0 },
        ),
        (
            r#""rotation_b": [0, 0, 0, 2]"#,
            "rotation_b",
            FrameProblem::RotationNotUnit { norm: 2.0 },
        ),
        (
            r#""rotation_a": [1e300, 1e300, 0, 0]"#,
            "rotation_a",
            FrameProblem::RotationNotUnit {
                norm: f64::INFINITY,
            },
        ),
    ];
    for (extra, field, problem) in cases {
        assert_refused(&joint_with("revolute", extra), field, frame(problem));
    }
    // JSON has no non-finite numbers: they are refused where they stand.
    let text = joint_with("revolute", r#""axis_a": [1e400, 0, 0]"#);
    assert!(
        matches!(
            parse_scene(&text),
            Err(SceneFileError::Json { line: 8, .. })
        ),
        "{:?}",
        parse_scene(&text)
    );
}

#[test]
fn a_rotation_with_an_axis_or_reference_is_a_conflict() {
    for (extra, field) in [
        (
            r#""rotation_a": [0, 0, 0, 1], "axis_a": [1, 0, 0]"#,
            "rotation_a",
        ),
        (
            r#""reference_b": [0, 1, 0], "rotation_b": [0, 0, 0, 1]"#,
            "rotation_b",
        ),
    ] {
        let (index, _, got, problem) = joint_error(&joint_with("fixed", extra));
        assert_eq!((index, got.as_str()), (1, field));
        assert!(matches!(problem, FieldProblem::Conflict(_)), "{problem:?}");
    }
    // Different forms on the two sides are fine.
    let text = joint_with(
        "fixed",
        r#""rotation_a": [0, 0, 0, 1], "axis_b": [0, 1, 0]"#,
    );
    assert!(parse_scene(&text).is_ok());
}

#[test]
fn limits_out_of_order_or_on_the_wrong_type_or_axis_are_refused() {
    let invalid = |axis: &str, min: f64, max: f64| {
        FieldProblem::InvalidJoint(JointError::InvalidLimit {
            axis: axis.into(),
            min,
            max,
        })
    };
    let on_locked = |axis: &str, reason: &'static str| {
        FieldProblem::InvalidJoint(JointError::LimitOnLockedAxis {
            axis: axis.into(),
            reason,
        })
    };
    let cases = [
        (
            "revolute",
            r#""limits": [1, -1]"#,
            "limits",
            invalid("angular x", 1.0, -1.0),
        ),
        (
            "prismatic",
            r#""limits": [0.5, 0.25]"#,
            "limits",
            invalid("linear x", 0.5, 0.25),
        ),
        (
            "generic",
            r#""locked": ["x"], "axis_limits": {"y": [2, 1]}"#,
            "axis_limits.y",
            invalid("linear y", 2.0, 1.0),
        ),
        (
            "generic",
            r#""locked": ["x", "angular_x", "angular_z"], "axis_limits": {"angular_y": [0.5, -0.5]}"#,
            "axis_limits.angular_y",
            invalid("angular y", 0.5, -0.5),
        ),
        (
            "generic",
            r#""locked": ["x", "y"], "axis_limits": {"x": [0, 1]}"#,
            "axis_limits.x",
            on_locked("linear x", "locked"),
        ),
        (
            "generic",
            r#""locked": ["x", "angular_x"], "axis_limits": {"angular_y": [0, 1]}"#,
            "axis_limits.angular_y",
            on_locked("angular y", "not the single free angular axis"),
        ),
        (
            "fixed",
            r#""limits": [0, 1]"#,
            "limits",
            FieldProblem::NotForType("fixed"),
        ),
        (
            "spherical",
            r#""limits": [0, 1]"#,
            "limits",
            FieldProblem::NotForType("spherical"),
        ),
        (
            "generic",
            r#""locked": ["x"], "limits": [0, 1]"#,
            "limits",
            FieldProblem::NotForType("generic"),
        ),
        (
            "revolute",
            r#""locked": ["x"]"#,
            "locked",
            FieldProblem::NotForType("revolute"),
        ),
        (
            "prismatic",
            r#""axis_limits": {"x": [0, 1]}"#,
            "axis_limits",
            FieldProblem::NotForType("prismatic"),
        ),
    ];
    for (kind, extra, field, problem) in cases {
        assert_refused(&joint_with(kind, extra), field, problem);
    }
    // Non-finite limits cannot be written in JSON.
    let text = joint_with("revolute", r#""limits": [-1e999, 0]"#);
    assert!(matches!(
        parse_scene(&text),
        Err(SceneFileError::Json { .. })
    ));
}

#[test]
fn unknown_or_repeated_axes_and_nothing_locked_are_refused() {
    let cases = [
        (
            r#""locked": ["x", "w"]"#,
            "locked[1]",
            FieldProblem::UnknownAxis("w".into()),
        ),
        (
            r#""locked": ["linear_x"]"#,
            "locked[0]",
            FieldProblem::UnknownAxis("linear_x".into()),
        ),
        (
            r#""locked": ["x"], "axis_limits": {"angular_q": [0, 1]}"#,
            "axis_limits.angular_q",
            FieldProblem::UnknownAxis("angular_q".into()),
        ),
        (
            r#""locked": ["x", "angular_y", "x"]"#,
            "locked[2]",
            FieldProblem::Conflict("axis listed twice"),
        ),
        (
            r#""locked": []"#,
            "locked",
            FieldProblem::InvalidJoint(JointError::NothingLocked),
        ),
    ];
    for (extra, field, problem) in cases {
        assert_refused(&joint_with("generic", extra), field, problem);
    }
}

#[test]
fn errors_name_an_unnamed_joint_by_index() {
    let text = scene_with(r#"{"name": 3, "type": "fixed"}"#);
    let error = parse_scene(&text).expect_err("refused");
    assert!(matches!(
        error,
        SceneFileError::Joint {
            index: 1,
            name: None,
            ..
        }
    ));
    assert!(
        error
            .to_string()
            .contains("joint 1 (unnamed), field `name`"),
        "{error}"
    );
}

#[test]
fn more_than_max_joints_are_refused_before_anything_is_built() {
    // Every entry is empty and the body has no mass: had anything been
    // built, those would be the error.
    let entries = vec!["{}"; MAX_JOINTS + 1].join(",");
    let text = format!(
        r#"{{"bodies": [{{"name": "x", "shape": {{"cuboid": [1, 1, 1]}}, "translation": [0, 0, 0], "rotation": [0, 0, 0, 1]}}], "joints": [{entries}]}}"#
    );
    assert_eq!(
        parse_scene(&text).err(),
        Some(SceneFileError::TopLevel {
            field: "joints".into(),
            problem: FieldProblem::TooMany {
                count: MAX_JOINTS + 1,
                limit: MAX_JOINTS,
            },
        })
    );
}
