//! Passes per call with and without `Settings::keep_penetrated_pairs`,
//! on the same inputs: the states a Rapier loop hands the bridge (issue
//! 21: one call of the pile of 200 took 61 passes, a box pushed out of the
//! ground into its neighbour and back, each pass seeing one of the two
//! contacts).
//!
//! ```text
//! cargo run --release --features rapier,serde --example probes -- passes [--steps N] [--scenes A,B] [--dump DIR]
//! ```
//!
//! The scene runs once under the bridge's defaults with
//! `keep_penetrated_pairs` off (the trajectory the setting's absence
//! gives); before each call the world is read into a scene by a second
//! bridge, and the call's lengths (tolerance, contact and target margins,
//! allowed penetration) are taken from the call. Each recorded input is
//! then stabilized by a fresh `Stabilizer` with those lengths, with and
//! without the setting, the two in alternating order. Reported: passes per
//! call (median, 90th percentile, max), calls over 10 passes, call ms
//! (median, max), the stages' medians (`Report::times`: narrow phase,
//! solve, line search; summed over islands), and the exact depth after (`dev_support::sat`) against
//! the call's tolerance. With `--dump DIR` the input whose call took the
//! most passes without the setting is written as a scene file (with its
//! lengths) to `DIR/<scene>_most_passes.json`, its allowed penetration
//! printed.

use crate::certificates_loop::world_of;
use crate::rest_probe::flag_value;

use std::path::PathBuf;
use std::time::Instant;

use constraint_stabilization::io::scene_file::write_scene;
use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge};
use constraint_stabilization::{Scene, Settings, Stabilizer};

/// Steps per run (5 s at 60 Hz).
const DEFAULT_STEPS: usize = 300;

/// Passes above which a call counts as long.
const LONG_CALL_PASSES: usize = 10;

fn quantile(values: &[f64], q: f64) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let index = ((sorted.len() as f64 - 1.0) * q).round() as usize;
    sorted.get(index).copied().unwrap_or(f64::NAN)
}

/// One call's input: the world as read, and the stabilizer settings that
/// give the call's lengths.
struct Input {
    scene: Scene,
    settings: Settings,
}

/// Runs the scene under the bridge (setting off) and records each call's
/// input.
fn record_inputs(name: &str, steps: usize) -> Result<Vec<Input>, Box<dyn std::error::Error>> {
    let Some(mut world) = world_of(name) else {
        return Err(format!("no scene named {name}").into());
    };
    let mut settings = BridgeSettings::default();
    settings.stabilizer.keep_penetrated_pairs = false;
    let mut bridge = RapierBridge::with_settings(settings)?;
    let mut reader = RapierBridge::new(Settings::default())?;
    let mut inputs = Vec::new();
    for _ in 0..steps {
        world.step();
        reader.sync(&world.bodies, &world.colliders)?;
        let scene = reader.scene().clone();
        let report = bridge.stabilize_world(&mut world)?;
        let Some(call) = report.stabilizer else {
            continue;
        };
        let lengths = bridge.stabilizer().lengths(&scene);
        let allowed = call.allowed_penetration;
        let mut settings = Settings::default();
        settings.tolerance_absolute = Some(lengths.tolerance - allowed);
        settings.contact_margin_absolute = Some(lengths.contact_margin);
        settings.target_margin_absolute = Some(lengths.target_margin + allowed);
        settings.allowed_penetration = allowed;
        inputs.push(Input { scene, settings });
    }
    Ok(inputs)
}

/// What one variant gave over the inputs.
#[derive(Default)]
struct Outcomes {
    passes: Vec<f64>,
    ms: Vec<f64>,
    /// Stage times (ms): narrow phase, solve, line search.
    stages: [Vec<f64>; 3],
    /// Calls whose exact depth after exceeds the call's tolerance.
    over_tolerance: usize,
    failed: usize,
}

pub fn run(args: Vec<String>) -> Result<(), Box<dyn std::error::Error>> {
    let value = |flag: &str| flag_value(&args, flag);
    let steps = value("--steps").map_or(Ok(DEFAULT_STEPS), |s| s.parse())?;
    let names = value("--scenes").unwrap_or_else(|| "pile_200".into());
    let dump = value("--dump").map(PathBuf::from);
    println!(
        "| scene | inputs | variant | passes per call: median / p90 / max | calls over {LONG_CALL_PASSES} passes | call ms: median / max | narrow / solve / line search ms (medians) | exact depth after over the tolerance | failed |\n|---|---|---|---|---|---|---|---|---|"
    );
    for name in names.split(',').map(str::trim) {
        let inputs = record_inputs(name, steps)?;
        let mut outcomes = [Outcomes::default(), Outcomes::default()];
        let mut most = (0, None::<&Input>);
        for (i, input) in inputs.iter().enumerate() {
            let order = if i % 2 == 0 { [0, 1] } else { [1, 0] };
            for k in order {
                let mut settings = input.settings.clone();
                settings.keep_penetrated_pairs = k == 0;
                let mut scene = input.scene.clone();
                let mut stabilizer = Stabilizer::new(settings)?;
                let start = Instant::now();
                let result = stabilizer.stabilize(&mut scene);
                let ms = start.elapsed().as_secs_f64() * 1e3;
                let outcome = &mut outcomes[k];
                let Ok(report) = result else {
                    outcome.failed += 1;
                    continue;
                };
                outcome.passes.push(report.passes as f64);
                outcome.ms.push(ms);
                let t = &report.times;
                for (stage, seconds) in
                    outcome
                        .stages
                        .iter_mut()
                        .zip([t.narrow_phase, t.solve, t.line_search])
                {
                    stage.push(seconds * 1e3);
                }
                if dev_support::sat::sat_deepest(&scene).0 > report.tolerance {
                    outcome.over_tolerance += 1;
                }
                if k == 1 && report.passes > most.0 {
                    most = (report.passes, Some(input));
                }
            }
        }
        for (k, variant) in ["keep", "off"].iter().enumerate() {
            let o = &outcomes[k];
            let long = o
                .passes
                .iter()
                .filter(|&&p| p > LONG_CALL_PASSES as f64)
                .count();
            println!(
                "| {name} | {} | {variant} | {:.0} / {:.0} / {:.0} | {long} | {:.2} / {:.1} | {:.2} / {:.2} / {:.2} | {} | {} |",
                inputs.len(),
                quantile(&o.passes, 0.5),
                quantile(&o.passes, 0.9),
                quantile(&o.passes, 1.0),
                quantile(&o.ms, 0.5),
                quantile(&o.ms, 1.0),
                quantile(&o.stages[0], 0.5),
                quantile(&o.stages[1], 0.5),
                quantile(&o.stages[2], 0.5),
                o.over_tolerance,
                o.failed,
            );
        }
        if let (Some(dir), (passes, Some(input))) = (&dump, most) {
            std::fs::create_dir_all(dir)?;
            let path = dir.join(format!("{name}_most_passes.json"));
            write_scene(&path, &input.scene, None)?;
            let s = &input.settings;
            println!(
                "wrote {} ({passes} passes without the setting; tolerance {:e}, contact margin {:e}, target margin {:e}, allowed penetration {:e})",
                path.display(),
                s.tolerance_absolute.unwrap_or(f64::NAN),
                s.contact_margin_absolute.unwrap_or(f64::NAN),
                s.target_margin_absolute.unwrap_or(f64::NAN),
                s.allowed_penetration,
            );
        }
    }
    Ok(())
}
