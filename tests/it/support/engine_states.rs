//! The engine states of `tests/data/engine/` (Rapier, MuJoCo and Bullet
//! states written as scene files), read in the order of their names, and
//! what the tests that call the stabilizer on them share: a call on a copy
//! of the input, and the agreement of two calls' body positions.

use std::path::PathBuf;

use constraint_stabilization::io::scene_file::read_scene;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::solver::SolverChoice;
use constraint_stabilization::{Report, Settings, Stabilizer};

/// The folder of the engine states.
fn engine_state_folder() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/engine"))
}

/// The engine state of the file `tests/data/engine/{stem}.json`.
pub fn engine_state(stem: &str) -> Scene {
    read_scene(&engine_state_folder().join(format!("{stem}.json"))).expect("a valid engine state")
}

/// Every engine state, with its file's stem, sorted by name.
pub fn engine_states() -> Vec<(String, Scene)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(engine_state_folder())
        .expect("engine states folder")
        .map(|entry| entry.expect("entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|path| {
            let stem = path
                .file_stem()
                .expect("a file")
                .to_string_lossy()
                .into_owned();
            let scene = read_scene(&path).expect("a valid scene");
            (stem, scene)
        })
        .collect()
}

/// The default settings with every island solved by `choice`.
pub fn settings(choice: SolverChoice) -> Settings {
    let mut settings = Settings::default();
    settings.solver.choice = choice;
    settings
}

/// One call of `stabilizer` on a copy of `input`: its report and output.
pub fn call(stabilizer: &mut Stabilizer, input: &Scene) -> (Report, Scene) {
    let mut scene = input.clone();
    let report = stabilizer.stabilize(&mut scene).expect("a valid scene");
    (report, scene)
}

/// The largest difference of two outputs' body positions (`a`, `b`, world
/// frame) and the largest motion of a body from `input` to `b`, the scale
/// that the difference is judged against.
pub fn pose_difference(input: &Scene, a: &Scene, b: &Scene) -> (f64, f64) {
    let mut difference: f64 = 0.0;
    let mut motion: f64 = 0.0;
    for ((x, y), z) in input.bodies().iter().zip(a.bodies()).zip(b.bodies()) {
        let p_in_world = x.com_pose().translation.vector;
        let p_a_world = y.com_pose().translation.vector;
        let p_b_world = z.com_pose().translation.vector;
        difference = difference.max((p_a_world - p_b_world).norm());
        motion = motion.max((p_b_world - p_in_world).norm());
    }
    (difference, motion)
}
