//! The `joints` section of scene files: every joint type with its limits
//! and generic axes written and read back bit for bit; anchor frames from
//! axes and references; bodies by name or index; a violated pendulum read
//! from `tests/data/scenes/pendulum.json` and stabilized back onto its
//! pivot. Bad joints are in `scene_joints_bad_input.rs`.

use constraint_stabilization::body::MassSpec;
use constraint_stabilization::io::scene_file::{parse_scene, read_scene, scene_to_string};
use constraint_stabilization::joints::{Joint, JointAxes, JointKind, JointLimits};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Stabilizer, Status};
use dev_support::joints::{world_frames, worst_joint_errors};
use dev_support::scene::{IDENTITY_XYZW, cuboid};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// The pendulum of `tests/data/scenes/pendulum.json`.
pub(crate) fn pendulum_path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/pendulum.json")
}

/// Asserts equal joints, bit for bit: `{:?}` of an `f64` is its shortest
/// round-trip text, distinct for distinct bits (`-0.0` included).
pub(crate) fn assert_bit_identical(a: &[Joint], b: &[Joint]) {
    assert_eq!(a, b);
    assert_eq!(format!("{a:?}"), format!("{b:?}"));
}

fn frame(t: [f64; 3], roll: f64, pitch: f64, yaw: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(t[0], t[1], t[2]),
        UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}

/// Five free bodies (two named "twin") and a fixed ground, joined by one
/// joint of each type, limited and not.
fn every_joint_type() -> Scene {
    let mut scene = Scene::new();
    let names = ["ground", "a", "b", "twin", "twin", "c"];
    for (i, name) in names.into_iter().enumerate() {
        let mass = if i == 0 {
            MassSpec::Fixed
        } else {
            MassSpec::Mass(1.0 + i as f64 / 3.0)
        };
        let at = [3.0 * i as f64, 0.1 * i as f64, -0.0];
        let desc = cuboid(name, [0.5, 0.5, 0.5], at, IDENTITY_XYZW, mass);
        scene.add_body(desc).expect("valid body");
    }
    let generic = JointKind::Generic {
        locked: JointAxes {
            linear: [false, true, true],
            angular: [true, false, true],
        },
        limits: JointLimits {
            linear: [Some([-0.1, 1.0 / 3.0]), None, None],
            angular: [None, Some([-std::f64::consts::PI, 0.7]), None],
        },
    };
    let kinds = [
        ("weld", JointKind::Fixed),
        ("ball", JointKind::Spherical),
        ("hinge", JointKind::Revolute { limit: None }),
        (
            "limited hinge",
            JointKind::Revolute {
                limit: Some([-1.25, 0.1]),
            },
        ),
        (
            "slider",
            JointKind::Prismatic {
                limit: Some([-0.0, 2.5e-7]),
            },
        ),
        ("free slider", JointKind::Prismatic { limit: None }),
        ("generic", generic),
        (
            "generic unlimited",
            JointKind::Generic {
                locked: JointAxes::ALL,
                limits: JointLimits::NONE,
            },
        ),
    ];
    let pairs = [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 4),
        (4, 5),
        (5, 0),
        (1, 4),
        (3, 2),
    ];
    for (i, ((name, kind), (a, b))) in kinds.into_iter().zip(pairs).enumerate() {
        let x = i as f64;
        scene
            .add_joint(Joint {
                name: name.into(),
                kind,
                body_a: a,
                body_b: b,
                frame_a: frame([0.1 * x, -1e-300, 1.0 / (x + 3.0)], 0.3 * x, -0.2, 1.1),
                frame_b: frame([-0.0, 0.5, 2.0f64.sqrt()], 0.1, 0.7 * x, -2.9),
            })
            .expect("valid joint");
    }
    scene
}

#[test]
fn every_joint_type_round_trips_bit_for_bit() {
    let scene = every_joint_type();
    let text = scene_to_string(&scene, None);
    let read = parse_scene(&text).expect("written scene reads back");
    assert_bit_identical(scene.joints(), read.joints());
    assert_eq!(
        scene_to_string(&read, None),
        text,
        "written twice, same text"
    );
    let file: serde_json::Value = serde_json::from_str(&text).unwrap();
    let joints = file["joints"].as_array().unwrap();
    // Bodies by unique name, else by index (the twins are bodies 3 and 4).
    assert_eq!(joints[1]["bodies"], serde_json::json!(["a", "b"]));
    assert_eq!(joints[2]["bodies"], serde_json::json!(["b", 3]));
    assert_eq!(joints[3]["bodies"], serde_json::json!([3, 4]));
    assert_eq!(joints[0]["type"], "fixed");
    assert!(joints[2].get("limits").is_none(), "no limit: none written");
    assert_eq!(joints[3]["limits"], serde_json::json!([-1.25, 0.1]));
    assert_eq!(
        joints[6]["locked"],
        serde_json::json!(["y", "z", "angular_x", "angular_z"])
    );
    let limits = &joints[6]["axis_limits"];
    assert_eq!(limits["x"], serde_json::json!([-0.1, 1.0 / 3.0]));
    assert_eq!(
        limits["angular_y"],
        serde_json::json!([-std::f64::consts::PI, 0.7])
    );
    assert_eq!(limits.as_object().unwrap().len(), 2);
    assert!(joints[7].get("axis_limits").is_none());
}

#[test]
fn a_scene_without_joints_writes_no_joints_section() {
    let mut scene = every_joint_type();
    let all: Vec<usize> = (0..scene.joints().len()).collect();
    scene.remove_joints(&all).unwrap();
    let text = scene_to_string(&scene, None);
    assert!(!text.contains("\"joints\""), "{text}");
    let empty = text.replacen('{', "{\"joints\": [],", 1);
    assert!(parse_scene(&empty).unwrap().joints().is_empty());
}

const TWO_BODIES: &str = r#""bodies": [
  {"name": "ground", "shape": {"cuboid": [5, 0.5, 5]}, "translation": [0, -0.5, 0], "rotation": [0, 0, 0, 1], "fixed": true},
  {"name": "box", "shape": {"cuboid": [0.5, 0.5, 0.5]}, "translation": [0, 2, 0], "rotation": [0, 0, 0, 1], "mass": 1}
]"#;

fn one_joint(joint: &str) -> Joint {
    let text = format!(r#"{{{TWO_BODIES}, "joints": [{joint}]}}"#);
    let scene = parse_scene(&text).unwrap_or_else(|e| panic!("{e}"));
    scene.joints()[0].clone()
}

fn assert_close(a: Vector3<f64>, b: Vector3<f64>) {
    assert!((a - b).norm() < 1e-15, "{a:?} vs {b:?}");
}

#[test]
fn anchor_frames_come_from_axes_references_or_quaternions() {
    let base = r#""name": "j", "type": "spherical", "bodies": ["ground", "box"], "anchor_a": [1, 2, 3], "anchor_b": [0, -0.5, 0]"#;
    // No orientation: the identity.
    let plain = one_joint(&format!("{{{base}}}"));
    assert_eq!(plain.frame_a, Isometry3::translation(1.0, 2.0, 3.0));
    assert_eq!(plain.frame_b.rotation, UnitQuaternion::identity());
    // An axis (any length) is the frame's x; a reference, made
    // perpendicular to it, its y.
    let j = one_joint(&format!(
        r#"{{{base}, "axis_a": [0, 0, 2], "reference_a": [1, 0, 1], "axis_b": [0, 1e-200, 0]}}"#
    ));
    let r = j.frame_a.rotation;
    assert_close(r * Vector3::x(), Vector3::z());
    assert_close(r * Vector3::y(), Vector3::x());
    assert_close(r * Vector3::z(), Vector3::y());
    // Without a reference: the coordinate axis least aligned with the
    // axis (x for an axis along y), made perpendicular.
    let r = j.frame_b.rotation;
    assert_close(r * Vector3::x(), Vector3::y());
    assert_close(r * Vector3::y(), Vector3::x());
    // Huge components are scaled, not overflowed.
    let huge = one_joint(&format!(r#"{{{base}, "axis_a": [1e308, 1e308, 0]}}"#));
    let diagonal = Vector3::new(1.0, 1.0, 0.0).normalize();
    assert_close(huge.frame_a.rotation * Vector3::x(), diagonal);
    // A quaternion within 1e-3 of unit is normalized; an exact one kept.
    let q = one_joint(&format!(
        r#"{{{base}, "rotation_a": [0, 0, 0.7071, 0.7071], "rotation_b": [0, 0, 0, 1]}}"#
    ));
    let expected = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2);
    assert!(q.frame_a.rotation.angle_to(&expected) < 1e-12);
    assert!((q.frame_a.rotation.quaternion().norm() - 1.0).abs() < 1e-15);
    assert_eq!(q.frame_b.rotation, UnitQuaternion::identity());
}

#[test]
fn bodies_by_name_and_by_index_are_the_same_joint() {
    let joint = |bodies: &str| {
        one_joint(&format!(
            r#"{{"name": "j", "type": "prismatic", "bodies": {bodies}, "anchor_a": [0, 0, 0], "anchor_b": [0, 0, 0], "limits": [0, 1]}}"#
        ))
    };
    let by_name = joint(r#"["box", "ground"]"#);
    assert_eq!((by_name.body_a, by_name.body_b), (1, 0));
    assert_eq!(by_name, joint("[1, 0]"));
    assert_eq!(by_name, joint(r#"["box", 0]"#));
    assert_eq!(
        by_name.kind,
        JointKind::Prismatic {
            limit: Some([0.0, 1.0])
        }
    );
}

#[test]
fn a_pendulum_off_its_pivot_read_from_a_file_is_brought_back() {
    let mut scene = read_scene(&pendulum_path()).expect("pendulum.json reads");
    assert_eq!(scene.joints().len(), 1);
    let (before, _) = worst_joint_errors(&scene);
    assert!(before > 0.29, "the file's rod is 0.3 off its pivot");
    let mut stabilizer = Stabilizer::for_scene(&scene).expect("valid settings");
    let report = stabilizer.stabilize(&mut scene).expect("valid scene");
    assert_eq!(
        report.status,
        Status::Converged,
        "{:?}",
        report.islands_left
    );
    let (linear, angular) = worst_joint_errors(&scene);
    assert!(linear <= report.tolerance, "anchor separation {linear:e}");
    assert!(
        angular <= report.tolerance / report.scale,
        "hinge {angular:e}"
    );
    let (fa, fb) = world_frames(&scene, &scene.joints()[0]);
    assert!((fa.translation.vector - fb.translation.vector).norm() <= report.tolerance);
    // Written and read back, the stabilized scene keeps its joint exactly.
    let read = parse_scene(&scene_to_string(&scene, None)).unwrap();
    assert_bit_identical(scene.joints(), read.joints());
}
