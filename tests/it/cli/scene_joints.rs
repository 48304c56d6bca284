//! `stabilize scene` on jointed scenes: the pendulum of
//! `tests/data/scenes/pendulum.json` is brought back to its pivot and its
//! joint written bit for bit (output fed back in reads the same joints);
//! bad joints exit 2, name the joint and field, and write no output.

use std::path::{Path, PathBuf};
use std::process::Command;

use constraint_stabilization::io::scene_file::read_scene;

use crate::io::scene_joints::{assert_bit_identical, pendulum_path};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cs-cli-joints-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// Runs `stabilize scene input -o output` (output removed first): exit
/// code and standard error.
fn run(input: &Path, output: &Path) -> (Option<i32>, String) {
    let _ = std::fs::remove_file(output);
    let result = Command::new(env!("CARGO_BIN_EXE_stabilize"))
        .arg("scene")
        .arg(input)
        .arg("-o")
        .arg(output)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&result.stderr).into_owned();
    (result.status.code(), stderr)
}

#[test]
fn the_pendulum_is_corrected_and_its_joint_round_trips_through_the_output() {
    let output = scratch("pendulum-out.json");
    let again = scratch("pendulum-again.json");
    let (code, stderr) = run(&pendulum_path(), &output);
    assert_eq!(code, Some(0), "{stderr}");
    let input = read_scene(&pendulum_path()).unwrap();
    let first = read_scene(&output).expect("output reads back");
    assert_bit_identical(input.joints(), first.joints());
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&output).unwrap()).unwrap();
    assert_eq!(json["report"]["status"], "converged");
    // The report names the joint, with its errors before and after.
    let joint = &json["report"]["joints"][0];
    assert_eq!(joint["type"], "revolute");
    let tolerance = json["report"]["tolerance"].as_f64().unwrap();
    assert!(joint["before"]["linear"].as_f64().unwrap() > 0.1);
    assert!(joint["after"]["linear"].as_f64().unwrap() <= tolerance);
    assert!(json["report"]["joint_error_after"].as_f64().unwrap() <= tolerance);
    assert_eq!(
        json["joints"][0]["bodies"],
        serde_json::json!(["pivot", "rod"])
    );
    // The rod hangs under its pivot again: its anchor (0.5 above its
    // centre) at the pivot's (the world origin).
    let rod = &first.bodies()[1];
    let anchor = rod.user_pose() * nalgebra::Point3::new(0.0, 0.5, 0.0);
    assert!(anchor.coords.norm() < 1e-6, "{anchor}");
    let (code, stderr) = run(&output, &again);
    assert_eq!(code, Some(0), "{stderr}");
    let second = read_scene(&again).unwrap();
    assert_bit_identical(first.joints(), second.joints());
    assert_eq!(
        std::fs::read_to_string(&again)
            .unwrap()
            .split("\"report\"")
            .next(),
        std::fs::read_to_string(&output)
            .unwrap()
            .split("\"report\"")
            .next(),
        "a corrected scene fed back in is written unchanged"
    );
}

#[test]
fn bad_joints_exit_2_name_the_joint_and_field_and_write_nothing() {
    let pendulum = std::fs::read_to_string(pendulum_path()).unwrap();
    let cases = [
        (
            "unknown-body",
            r#""bodies": ["pivot", "rod"]"#,
            r#""bodies": ["pivot", "bob"]"#,
            "bodies[1]",
        ),
        (
            "same-body",
            r#""bodies": ["pivot", "rod"]"#,
            r#""bodies": ["rod", 1]"#,
            "bodies",
        ),
        (
            "index-out-of-range",
            r#""bodies": ["pivot", "rod"]"#,
            r#""bodies": ["pivot", 2]"#,
            "bodies[1]",
        ),
        (
            "zero-axis",
            r#""axis_a": [0.0, 0.0, 1.0]"#,
            r#""axis_a": [0.0, 0.0, 0.0]"#,
            "axis_a",
        ),
        (
            "limits-order",
            r#""limits": [-0.5, 0.5]"#,
            r#""limits": [0.5, -0.5]"#,
            "limits",
        ),
        ("unknown-field", r#""limits""#, r#""limit""#, "limit"),
        ("locked-on-revolute", r#""limits""#, r#""locked""#, "locked"),
    ];
    for (name, from, to, field) in cases {
        let text = pendulum.replace(from, to);
        assert_ne!(text, pendulum, "{name}");
        let input = scratch(&format!("{name}.json"));
        let output = scratch(&format!("{name}-out.json"));
        std::fs::write(&input, text).unwrap();
        let (code, stderr) = run(&input, &output);
        assert_eq!(code, Some(2), "{name}: {stderr}");
        assert!(!output.exists(), "{name}: no output on bad input");
        assert!(
            stderr.contains("joint 0 (\"hinge\")") && stderr.contains(&format!("`{field}`")),
            "{name}: {stderr}"
        );
    }
}
