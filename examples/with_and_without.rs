//! The same Rapier scenes run plain and with one stabilization call after
//! every step (issue 10 and 11): what the projection does to an engine's
//! simulation, measured.
//!
//! ```text
//! cargo run --release --features rapier,serde --example with_and_without -- [--steps N] [--only NAME] [--out DIR]
//! ```
//!
//! Scenes (examples/common/rapier_scenes.rs, Rapier's defaults, 60 Hz):
//! a pile of 200 boxes and hulls dropped into a bin; a pile of 60 compound
//! bodies (two or three box colliders on one rigid body, L and T shapes)
//! dropped into a bin; a pile of 60 balls, capsules, cylinders and rounded
//! boxes dropped into a bin (issue 25); four light boxes under
//! a box 100 and 1,000 times heavier; a box thrown at 15 m/s into a stack;
//! a pyramid of 55 boxes. Runs, from the same initial world:
//! - `plain`: Rapier alone;
//! - `velocity (...)`: a [`RapierBridge`] call after every step with
//!   velocity consistency and the colliders' friction, the velocity
//!   projection with the kinematic cone on `v'` or frictionless;
//! - `closed contacts`: the same (frictionless velocity projection) with
//!   the corrected contacts left touching (`CouplingMode::ClosedContacts`);
//!   the bridge's default is marked;
//! - `allowed+friction`: Rapier's allowed penetration left, positions only;
//! - `positions`: a call after every step with the library's defaults
//!   (positions only, velocities untouched, no friction).
//!
//! Per step: the exact deepest penetration of the Rapier world after the
//! step (and the call), by brute-force separating axes over every pair of
//! colliders with a dynamic body (`dev_support::sat`, on the f32 poses as
//! Rapier holds them); Rapier's step time and the call's time; the height
//! of the tracked top body (stacks, pyramid); the largest horizontal drift
//! of a tracked body from its first pose; failed calls; the steps whose
//! exact depth exceeds the tolerance the call stated (its acceptance
//! threshold: the allowed penetration of the coupling included). Writes
//! `DIR/with_and_without.csv` (every step), `DIR/with_and_without.md` (the
//! summary table) and `DIR/with_and_without_NAME.svg` (deepest penetration
//! against time, log scale, one line per run), and prints the table.

#[path = "common/rapier_scenes.rs"]
mod scenes;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use constraint_stabilization::Settings;
use constraint_stabilization::rapier_bridge::{BridgeSettings, CouplingMode, RapierBridge};
use constraint_stabilization::stabilizer::VelocityFriction;
use plotters::prelude::*;
use rapier3d::prelude::*;

/// Steps per run (5 s at 60 Hz).
const DEFAULT_STEPS: usize = 300;
/// Floor of the log-scale plot (a depth of 0 is drawn there).
const PLOT_FLOOR: f64 = 1e-9;

/// A scene: a builder of its world at step 0 and of the bodies to track
/// (bottom to top for stacks; the last one is the "top").
struct Scene {
    name: &'static str,
    build: fn() -> (PhysicsWorld, Vec<RigidBodyHandle>),
    /// The step from which drift is measured (after a dropped pile has
    /// settled; 0 for stacks built in place).
    drift_from: usize,
}

/// Every dynamic body of a world.
fn all_dynamic(world: &PhysicsWorld) -> Vec<RigidBodyHandle> {
    world
        .bodies
        .iter()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .collect()
}

fn scenes() -> Vec<Scene> {
    vec![
        Scene {
            name: "pile_200",
            build: || {
                let world = scenes::pile_world(200, 1.0, 1);
                let tracked = all_dynamic(&world);
                (world, tracked)
            },
            drift_from: 150,
        },
        Scene {
            name: "compound_pile_60",
            build: || {
                let world = scenes::compound_pile_world(60, 0.6, 1);
                let tracked = all_dynamic(&world);
                (world, tracked)
            },
            drift_from: 150,
        },
        Scene {
            name: "mixed_pile_60",
            build: || {
                let world = scenes::mixed_pile_world(60, 0.6, 1);
                let tracked = all_dynamic(&world);
                (world, tracked)
            },
            drift_from: 150,
        },
        Scene {
            name: "stack_1to100",
            build: || scenes::aligned_heavy_stack_world(100.0),
            drift_from: 0,
        },
        Scene {
            name: "stack_1to1000",
            build: || scenes::aligned_heavy_stack_world(1000.0),
            drift_from: 0,
        },
        Scene {
            name: "thrown_box",
            build: || {
                let (world, mut tracked) = scenes::thrown_box_world(6);
                tracked.pop();
                (world, tracked)
            },
            drift_from: 0,
        },
        Scene {
            name: "pyramid_55",
            build: scenes::pyramid_world,
            drift_from: 0,
        },
    ]
}

/// How the world is stabilized after each step.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Run {
    /// Rapier alone.
    Plain,
    /// Velocity consistency with the colliders' friction, the velocity
    /// projection with this friction (one of them is the bridge's default).
    Velocity(VelocityFriction),
    /// Velocity consistency (frictionless velocity projection) with the
    /// corrected contacts left closed (`CouplingMode::ClosedContacts`).
    Closed,
    /// Rapier's allowed penetration respected, with the colliders'
    /// friction, positions only.
    Allowed,
    /// Positions only, velocities untouched, no friction.
    Positions,
}

impl Run {
    const ALL: [Run; 6] = [
        Run::Plain,
        Run::Velocity(VelocityFriction::OnVelocity),
        Run::Velocity(VelocityFriction::None),
        Run::Closed,
        Run::Allowed,
        Run::Positions,
    ];

    fn name(self) -> String {
        match self {
            Run::Plain => "plain".into(),
            Run::Velocity(friction) => {
                let defaults = BridgeSettings::default();
                let default = defaults.coupling == CouplingMode::VelocityConsistency
                    && defaults.velocity_friction == friction;
                let projection = match friction {
                    VelocityFriction::None => "frictionless",
                    VelocityFriction::OnChange => "friction on dv",
                    VelocityFriction::OnVelocity => "cone on v'",
                };
                let marker = if default { "default: " } else { "" };
                format!("{marker}velocity ({projection})+friction")
            }
            Run::Closed => {
                let default = BridgeSettings::default().coupling == CouplingMode::ClosedContacts;
                let marker = if default { "default: " } else { "" };
                format!("{marker}closed contacts+friction")
            }
            Run::Allowed => "allowed+friction".into(),
            Run::Positions => "positions (seed)".into(),
        }
    }

    fn colour(self) -> RGBColor {
        match self {
            Run::Plain => RGBColor(200, 60, 40),
            Run::Velocity(VelocityFriction::OnVelocity) => RGBColor(30, 110, 200),
            Run::Velocity(_) => RGBColor(150, 80, 190),
            Run::Closed => RGBColor(230, 150, 20),
            Run::Allowed => RGBColor(40, 160, 60),
            Run::Positions => RGBColor(120, 120, 120),
        }
    }

    fn bridge(self) -> Option<RapierBridge> {
        let settings = match self {
            Run::Plain => return None,
            Run::Velocity(velocity_friction) => BridgeSettings {
                coupling: CouplingMode::VelocityConsistency,
                collider_friction: true,
                velocity_friction,
                ..BridgeSettings::default()
            },
            Run::Closed => BridgeSettings {
                coupling: CouplingMode::ClosedContacts,
                collider_friction: true,
                velocity_friction: VelocityFriction::None,
                ..BridgeSettings::default()
            },
            Run::Allowed => BridgeSettings {
                coupling: CouplingMode::RespectAllowedPenetration,
                collider_friction: true,
                ..BridgeSettings::default()
            },
            Run::Positions => BridgeSettings {
                coupling: CouplingMode::PositionsOnly,
                collider_friction: false,
                ..BridgeSettings::default()
            },
        };
        Some(RapierBridge::with_settings(settings).expect("valid settings"))
    }
}

/// One step of one run.
struct StepRecord {
    step: usize,
    depth: f64,
    /// The tolerance the call stated (its acceptance threshold, the
    /// allowed penetration included); infinite without a call.
    call_tolerance: f64,
    rapier_ms: f64,
    call_ms: f64,
    call_failed: bool,
    top_z: f64,
    drift: f64,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let steps = value("--steps").map_or(Ok(DEFAULT_STEPS), |s| s.parse())?;
    let only = value("--only");
    let out = PathBuf::from(value("--out").unwrap_or_else(|| "benchmarks/results".into()));
    std::fs::create_dir_all(&out)?;
    let mut csv = String::from(
        "scene,run,step,deepest_m,call_tolerance_m,rapier_ms,call_ms,call_failed,top_z_m,max_drift_m\n",
    );
    let mut table = String::from(
        "| scene | run | deepest after step 1 (m) | deepest, median over steps (m) | deepest, max over the last 100 steps (m) | top: start -> end z (m) | max horizontal drift (mm) | failed calls | steps deeper than the call's tolerance | Rapier step ms (median) | call ms (median / max) |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for scene in scenes() {
        if only.as_deref().is_some_and(|o| !scene.name.contains(o)) {
            continue;
        }
        let mut runs = Vec::new();
        for run in Run::ALL {
            let records = simulate(&scene, run, steps)?;
            for r in &records {
                let _ = writeln!(
                    csv,
                    "{},{},{},{:.6e},{:.6e},{:.4},{:.4},{},{:.6},{:.6e}",
                    scene.name,
                    run.name(),
                    r.step,
                    r.depth,
                    r.call_tolerance,
                    r.rapier_ms,
                    r.call_ms,
                    r.call_failed,
                    r.top_z,
                    r.drift
                );
            }
            let row = summary(scene.name, run, &records);
            eprintln!("{row}");
            table += &row;
            runs.push((run, records));
        }
        plot(
            &out.join(format!("with_and_without_{}.svg", scene.name)),
            scene.name,
            &runs,
        )?;
    }
    std::fs::write(out.join("with_and_without.csv"), csv)?;
    std::fs::write(out.join("with_and_without.md"), &table)?;
    println!("{table}");
    Ok(())
}

/// Runs `steps` steps of a fresh copy of the scene's world.
fn simulate(
    scene: &Scene,
    run: Run,
    steps: usize,
) -> Result<Vec<StepRecord>, Box<dyn std::error::Error>> {
    let (mut world, tracked) = (scene.build)();
    let mut bridge = run.bridge();
    let mut measure = RapierBridge::new(Settings::default())?;
    let mut start: Vec<Vector> = tracked
        .iter()
        .map(|&h| world.bodies[h].translation())
        .collect();
    let mut drift: f64 = 0.0;
    let mut records = Vec::with_capacity(steps);
    for step in 1..=steps {
        let t = Instant::now();
        world.step();
        let rapier_ms = t.elapsed().as_secs_f64() * 1e3;
        let (mut call_ms, mut call_failed) = (0.0, false);
        let mut call_tolerance = f64::INFINITY;
        if let Some(bridge) = bridge.as_mut() {
            let t = Instant::now();
            let result = bridge.stabilize(
                &mut world.bodies,
                &world.colliders,
                &world.integration_parameters,
            );
            call_failed = match result {
                Ok(report) => {
                    if let Some(r) = &report.stabilizer {
                        call_tolerance = r.tolerance;
                    }
                    report.stabilizer.is_some_and(|r| !r.status.is_resolved())
                }
                Err(_) => true,
            };
            call_ms = t.elapsed().as_secs_f64() * 1e3;
        }
        measure.sync(&world.bodies, &world.colliders)?;
        let depth = dev_support::sat::sat_deepest(measure.scene()).0;
        if step == scene.drift_from {
            start = tracked
                .iter()
                .map(|&h| world.bodies[h].translation())
                .collect();
        }
        for (h, s) in tracked
            .iter()
            .zip(&start)
            .filter(|_| step > scene.drift_from)
        {
            let p = world.bodies[*h].translation();
            drift = drift.max(f64::from(
                ((p.x - s.x).powi(2) + (p.y - s.y).powi(2)).sqrt(),
            ));
        }
        let top_z = tracked
            .last()
            .map_or(0.0, |&h| f64::from(world.bodies[h].translation().z));
        records.push(StepRecord {
            step,
            depth,
            call_tolerance,
            rapier_ms,
            call_ms,
            call_failed,
            top_z,
            drift,
        });
    }
    Ok(records)
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(0.0)
}

/// One row of the summary table.
fn summary(scene: &str, run: Run, records: &[StepRecord]) -> String {
    let depths: Vec<f64> = records.iter().map(|r| r.depth).collect();
    let tail = depths
        .iter()
        .rev()
        .take(100)
        .fold(0.0, |m: f64, &d| m.max(d));
    let first = records.first().map_or(0.0, |r| r.depth);
    let (start_z, end_z) = (
        records.first().map_or(0.0, |r| r.top_z),
        records.last().map_or(0.0, |r| r.top_z),
    );
    let calls: Vec<f64> = records.iter().map(|r| r.call_ms).collect();
    let max_call = calls.iter().fold(0.0, |m: f64, &c| m.max(c));
    let failed = records.iter().filter(|r| r.call_failed).count();
    let beyond = records
        .iter()
        .filter(|r| r.depth > r.call_tolerance)
        .count();
    let drift = records.last().map_or(0.0, |r| r.drift);
    format!(
        "| {scene} | {} | {first:.2e} | {:.2e} | {tail:.2e} | {start_z:.4} -> {end_z:.4} | {:.2} | {failed} | {beyond} | {:.3} | {:.2} / {max_call:.1} |\n",
        run.name(),
        median(depths),
        drift * 1e3,
        median(records.iter().map(|r| r.rapier_ms).collect()),
        median(calls),
    )
}

/// Deepest penetration against time, log scale, one line per run.
fn plot(
    path: &std::path::Path,
    scene: &str,
    runs: &[(Run, Vec<StepRecord>)],
) -> Result<(), Box<dyn std::error::Error>> {
    let steps = runs.iter().map(|(_, r)| r.len()).max().unwrap_or(1);
    let seconds = steps as f64 * scenes::STEP_SECONDS;
    let top = runs
        .iter()
        .flat_map(|(_, r)| r.iter().map(|s| s.depth))
        .fold(PLOT_FLOOR * 10.0, f64::max)
        * 2.0;
    let root = SVGBackend::new(path, (800, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{scene}: deepest penetration after each step"),
            ("sans-serif", 20),
        )
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..seconds, (PLOT_FLOOR..top).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("deepest penetration (m)")
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()?;
    for (run, records) in runs {
        let colour = run.colour();
        chart
            .draw_series(LineSeries::new(
                records.iter().map(|r| {
                    (
                        r.step as f64 * scenes::STEP_SECONDS,
                        r.depth.max(PLOT_FLOOR),
                    )
                }),
                colour.stroke_width(2),
            ))?
            .label(run.name())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
