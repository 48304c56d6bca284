//! How far one stabilization call moves each body, against the summed
//! exact depth of the penetrating pairs of its island (issue 9's goal: no
//! body moves more than twice that sum).
//!
//! ```text
//! cargo run --release --features serde --example engine_motion -- \
//!     [--rotation RAD] [--translation REL] tests/data/engine/*.json
//! ```
//!
//! `--rotation` and `--translation` override the trust region's
//! `step_max_rotation` and `step_max_translation_relative` (`inf`: off).
//!
//! For every file, one call with the default settings, then one line:
//! status, passes, islands left, and for the body with the worst ratio its
//! largest vertex motion `max_v |R' v + x' - (R v + x)|` (translation and
//! rotation together), its centre-of-mass translation, its rotation angle,
//! the summed depth `D` of its island, and `motion / D`.
//!
//! A body's island is the first island of the report (`pass_reports`, in
//! pass order) that holds it: for a body that penetrated at the start, its
//! island of the first pass; `D` sums the depths of `penetrations_before`
//! with a body in that island (fixed bodies join no island).

use std::path::Path;

use constraint_stabilization::io::scene_file::read_scene;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Stabilizer};
use nalgebra::Isometry3;

/// The motion of one body in one call.
struct Motion {
    body: usize,
    vertex: f64,
    translation: f64,
    angle_degrees: f64,
    island_depth: f64,
}

impl Motion {
    fn ratio(&self) -> f64 {
        self.vertex / self.island_depth
    }
}

fn main() {
    println!(
        "{:<34} {:>9} {:>6} {:>5} {:>6} {:>10} {:>10} {:>8} {:>10} {:>8} {:>8}",
        "file",
        "status",
        "passes",
        "left",
        "body",
        "motion",
        "transl",
        "angle",
        "D",
        "ratio",
        "t/D"
    );
    let mut settings = Settings::default();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = || -> f64 {
            let text = args.next().expect("a value after the option");
            text.parse().expect("a number")
        };
        match arg.as_str() {
            "--rotation" => settings.step_max_rotation = value(),
            "--translation" => settings.step_max_translation_relative = value(),
            path => measure(Path::new(path), &settings),
        }
    }
}

fn measure(path: &Path, settings: &Settings) {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
    let name = name.unwrap_or_default();
    let mut scene = match read_scene(path) {
        Ok(scene) => scene,
        Err(error) => return println!("{name:<34} unreadable: {error}"),
    };
    let settings = settings.clone().with_scene_settings(scene.settings());
    let poses_before: Vec<Isometry3<f64>> = scene.bodies().iter().map(|b| *b.com_pose()).collect();
    let mut stabilizer = Stabilizer::new(settings).expect("default settings");
    let report = match stabilizer.stabilize(&mut scene) {
        Ok(report) => report,
        Err(error) => return println!("{name:<34} error: {error}"),
    };
    let worst = motions(&scene, &poses_before, &report)
        .into_iter()
        .max_by(|a, b| a.ratio().total_cmp(&b.ratio()));
    let left = islands_left(&report);
    match worst {
        Some(m) => println!(
            "{name:<34} {:>9} {:>6} {:>5} {:>6} {:>10.3e} {:>10.3e} {:>8.3} {:>10.3e} {:>8.3} {:>8.3}",
            report.status.name(),
            report.passes,
            left,
            m.body,
            m.vertex,
            m.translation,
            m.angle_degrees,
            m.island_depth,
            m.ratio(),
            m.translation / m.island_depth
        ),
        None => println!(
            "{name:<34} {:>9} {:>6} {:>5}   (no body moved)",
            report.status.name(),
            report.passes,
            left
        ),
    }
}

/// Number of islands the report names as left (stalled or failed).
fn islands_left(report: &Report) -> usize {
    report.islands_left.len()
}

fn motions(scene: &Scene, poses_before: &[Isometry3<f64>], report: &Report) -> Vec<Motion> {
    let mut motions = Vec::new();
    for (body, (after, before)) in scene.bodies().iter().zip(poses_before).enumerate() {
        if after.com_pose() == before {
            continue;
        }
        let vertex = after
            .polyhedron()
            .expect("a convex body")
            .vertices()
            .iter()
            .map(|v_body| (after.com_pose() * v_body - before * v_body).norm())
            .fold(0.0, f64::max);
        let translation = (after.com_pose().translation.vector - before.translation.vector).norm();
        let angle = (after.com_pose().rotation * before.rotation.inverse()).angle();
        motions.push(Motion {
            body,
            vertex,
            translation,
            angle_degrees: angle.to_degrees(),
            island_depth: island_depth(report, body),
        });
    }
    motions
}

/// Summed exact depth of the penetrating pairs (before the call) of the
/// first island of the report holding `body`.
fn island_depth(report: &Report, body: usize) -> f64 {
    let island = report
        .pass_reports
        .iter()
        .flat_map(|pass| &pass.solved)
        .find(|island| island.bodies.binary_search(&body).is_ok());
    let Some(island) = island else {
        return 0.0;
    };
    report
        .penetrations_before
        .iter()
        .filter(|p| {
            island.bodies.binary_search(&p.body_a).is_ok()
                || island.bodies.binary_search(&p.body_b).is_ok()
        })
        .map(|p| p.depth)
        .sum()
}
