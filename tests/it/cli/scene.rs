//! The `stabilize scene` and `stabilize demo` commands: exit codes, output
//! files, and that a corrected scene fed back in is a no-op. Needs the
//! `stabilize` binary (feature `cli`).

use std::path::PathBuf;
use std::process::Command;

fn binary() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stabilize"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cs-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

const DESIGN_EXAMPLE: &str = r#"{
  "bodies": [
    { "name": "ground", "shape": { "cuboid": [10.0, 0.5, 10.0] },
      "translation": [0.0, -0.5, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0],
      "fixed": true },
    { "name": "rock", "shape": { "convex_hull": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]] },
      "translation": [0.2, -0.1, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0],
      "mass": 2.5 }
  ],
  "settings": { "tolerance": 1e-6 }
}"#;

fn read_json(path: &PathBuf) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("output")).expect("json")
}

#[test]
fn scene_is_corrected_and_output_fed_back_is_a_no_op() {
    let input = scratch("design.json");
    let output = scratch("design-out.json");
    let again = scratch("design-again.json");
    std::fs::write(&input, DESIGN_EXAMPLE).unwrap();
    let status = binary()
        .args(["scene"])
        .arg(&input)
        .arg("-o")
        .arg(&output)
        .status()
        .unwrap();
    assert_eq!(status.code(), Some(0));
    let first = read_json(&output);
    assert_eq!(first["report"]["status"], "converged");
    // The rock's lowest point (the shape-frame origin) was 0.1 below the
    // ground's top face; it is lifted to the surface.
    let rock_y = first["bodies"][1]["translation"][1].as_f64().unwrap();
    assert!((0.0..1e-5).contains(&rock_y), "rock at y = {rock_y}");
    assert_eq!(
        first["bodies"][0],
        serde_json::from_str::<serde_json::Value>(DESIGN_EXAMPLE).unwrap()["bodies"][0]
    );
    let status = binary()
        .args(["scene"])
        .arg(&output)
        .arg("-o")
        .arg(&again)
        .status()
        .unwrap();
    assert_eq!(status.code(), Some(0));
    let second = read_json(&again);
    assert_eq!(second["report"]["status"], "nothing_to_do");
    assert_eq!(first["bodies"], second["bodies"], "bit-identical poses");
}

#[test]
fn bad_scene_exits_2_and_writes_nothing() {
    let no_mass = DESIGN_EXAMPLE.replace("\"mass\": 2.5", "\"mas\": 2.5");
    let (code, message, output) = run_scene("bad", &no_mass);
    assert_eq!(code, Some(2));
    assert!(!output.exists());
    assert!(
        message.contains("rock") && message.contains("mas"),
        "{message}"
    );
}

#[test]
fn demo_converges_and_says_so() {
    let result = binary()
        .args(["demo", "--bodies", "40", "--seed", "3"])
        .output()
        .unwrap();
    assert_eq!(result.status.code(), Some(0));
    let text = String::from_utf8_lossy(&result.stdout);
    assert!(text.contains("converged"), "{text}");
    assert!(text.contains("after:  0 pairs penetrating"), "{text}");
}

#[test]
fn demo_rejects_an_unknown_solver() {
    let result = binary()
        .args(["demo", "--solver", "magic"])
        .output()
        .unwrap();
    assert_eq!(result.status.code(), Some(2));
}

/// 1% of the wedged cube's lift (0.05).
const WEDGE_LIFT_AGREEMENT: f64 = 5e-4;

/// A unit cube sunk 0.05 into a fixed floor under a fixed ceiling 0.02
/// above its top face (more than the contact margin, 0.0087): the first
/// pass lifts the cube into the ceiling, and the second has no solution
/// (the room, 0.97, is lower than the cube).
fn wedged_cube(settings: &str) -> String {
    format!(
        r#"{{
  "bodies": [
    {{ "name": "floor", "shape": {{ "cuboid": [10.0, 0.5, 10.0] }},
      "translation": [0.0, -0.5, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0],
      "fixed": true }},
    {{ "name": "ceiling", "shape": {{ "cuboid": [10.0, 0.5, 10.0] }},
      "translation": [0.0, 1.47, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0],
      "fixed": true }},
    {{ "name": "cube", "shape": {{ "cuboid": [0.5, 0.5, 0.5] }},
      "translation": [0.0, 0.45, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0],
      "mass": 1.0 }}
  ]{settings}
}}"#
    )
}

/// Runs `stabilize scene` on `text`; returns the exit code, stderr, and
/// the output path (removed beforehand, so that its existence afterwards
/// means this run wrote it).
fn run_scene(name: &str, text: &str) -> (Option<i32>, String, PathBuf) {
    let input = scratch(&format!("{name}.json"));
    std::fs::write(&input, text).unwrap();
    run_scene_file(name, &input)
}

/// Runs `stabilize scene` on the file `input` (see [`run_scene`]).
fn run_scene_file(name: &str, input: &PathBuf) -> (Option<i32>, String, PathBuf) {
    let output = scratch(&format!("{name}-out.json"));
    let _ = std::fs::remove_file(&output);
    let result = binary()
        .args(["scene"])
        .arg(input)
        .arg("-o")
        .arg(&output)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr).into_owned();
    (result.status.code(), stderr, output)
}

/// A scene that no correction can solve: exit 1, the output written with
/// the progress made (the first pass lifted the cube out of the floor),
/// and a report and a message that say which island is left and why.
#[test]
fn unsolvable_scene_exits_1_writes_the_progress_and_says_why() {
    let (code, stderr, output) = run_scene("wedged", &wedged_cube(""));
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("unsolved") && stderr.contains("no solver succeeded"),
        "{stderr}"
    );
    let written = read_json(&output);
    assert_eq!(written["report"]["status"], "unsolved");
    let left = &written["report"]["islands_left"];
    assert_eq!(left.as_array().map(Vec::len), Some(1), "{left}");
    assert_eq!(left[0]["bodies"][0]["name"], "cube");
    let reason = left[0]["reason"].as_str().unwrap_or_default();
    assert!(reason.contains("no solver succeeded"), "{reason}");
    let cube_y = written["bodies"][2]["translation"][1].as_f64().unwrap();
    assert!(
        (cube_y - 0.5).abs() <= WEDGE_LIFT_AGREEMENT,
        "cube at y = {cube_y}"
    );
}

/// The pass limit reached with a penetration left: exit 1, the output
/// file written with the progress made and a report that says
/// `pass_limit`, and the same on stderr.
#[test]
fn pass_limit_exits_1_and_writes_the_partial_result() {
    let text = wedged_cube(r#", "settings": { "max_passes": 1 }"#);
    let (code, stderr, output) = run_scene("wedged-limit", &text);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("pass_limit"), "{stderr}");
    let written = read_json(&output);
    assert_eq!(written["report"]["status"], "pass_limit");
    assert_eq!(written["report"]["passes"], 1);
    // The one pass lifted the cube out of the floor (by the depth, 0.05).
    let cube_y = written["bodies"][2]["translation"][1].as_f64().unwrap();
    assert!(
        (cube_y - 0.5).abs() <= WEDGE_LIFT_AGREEMENT,
        "cube at y = {cube_y}"
    );
}

/// Bad inputs on the command line: exit 2, one line on stderr naming the
/// body (index and name) and the field, or the line of a JSON error, and no
/// output file.
#[test]
fn bad_inputs_exit_2_with_one_line_naming_body_and_field() {
    let rock = |from: &str, to: &str| DESIGN_EXAMPLE.replace(from, to);
    let cases = [
        (
            rock("\"mass\": 2.5", "\"mass\": 0"),
            ["body 1", "rock", "`mass`"],
        ),
        (
            rock("\"mass\": 2.5", "\"mass\": 2.5, \"density\": 1"),
            ["body 1", "rock", "`density`"],
        ),
        (
            rock("\"mass\": 2.5", "\"density\": -1"),
            ["body 1", "rock", "`density`"],
        ),
        (
            rock(
                "[0.2, -0.1, 0.0], \"rotation\": [0.0, 0.0, 0.0, 1.0]",
                "[0.2, -0.1, 0.0], \"rotation\": [0.0, 0.0, 0.0, 0.0]",
            ),
            ["body 1", "rock", "`rotation`"],
        ),
        (
            rock(
                "[[0,0,0],[1,0,0],[0,1,0],[0,0,1]]",
                "[[0,0,0],[1,0,0],[2,0,0],[3,0,0]]",
            ),
            ["body 1", "rock", "`shape`"],
        ),
        (
            rock("\"mass\": 2.5", "\"mass\": \"heavy\""),
            ["body 1", "rock", "`mass`"],
        ),
        (
            rock("\"mass\": 2.5", "\"mass\": 2.5, \"colour\": 1"),
            ["body 1", "rock", "`colour`"],
        ),
        (
            rock("[0.2, -0.1, 0.0]", "[0.2, -1e400, 0.0]"),
            ["invalid JSON", "line 7", "column"],
        ),
        (
            rock("\"tolerance\": 1e-6", "\"tolerance\": -1"),
            ["settings", "`tolerance`", "positive"],
        ),
        (
            rock(
                "[[0,0,0],[1,0,0],[0,1,0],[0,0,1]]",
                "[[0,0,0],[1,0,0],[0,1,0],[0,0,1]], \"radius\": -0.5",
            ),
            ["body 1", "`shape`", "radius"],
        ),
        (
            rock(
                "\"convex_hull\": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]]",
                "\"capsule\": {\"half_height\": 1, \"radius\": 1, \"axis\": 0}",
            ),
            ["body 1", "rock", "`shape.capsule.axis`"],
        ),
    ];
    for (k, (text, words)) in cases.iter().enumerate() {
        let (code, stderr, output) = run_scene(&format!("bad-{k}"), text);
        assert_eq!(code, Some(2), "{stderr}");
        assert!(!output.exists(), "case {k} wrote an output file");
        assert_eq!(stderr.lines().count(), 1, "case {k}: {stderr}");
        for word in words {
            assert!(stderr.contains(word), "case {k}: {word:?} not in {stderr}");
        }
    }
}

/// A file beyond the size limit is refused before it is read: exit 2, one
/// line, no output. The file is sparse (no disk space used).
#[test]
fn a_file_beyond_the_size_limit_exits_2() {
    use constraint_stabilization::io::scene_file::MAX_SCENE_FILE_BYTES;
    let input = scratch("huge.json");
    let file = std::fs::File::create(&input).unwrap();
    file.set_len(MAX_SCENE_FILE_BYTES + 1).unwrap();
    let (code, stderr, output) = run_scene_file("huge", &input);
    let _ = std::fs::remove_file(&input);
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("limited to"), "{stderr}");
    assert!(!output.exists());
}
