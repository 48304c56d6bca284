//! The engine states of `tests/data/engine/` (Rapier, MuJoCo and Bullet
//! states written as scene files), read in the order of their names.

use std::path::PathBuf;

use constraint_stabilization::io::scene_file::read_scene;
use constraint_stabilization::scene::Scene;

/// The folder of the engine states.
fn engine_state_folder() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/engine"))
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
