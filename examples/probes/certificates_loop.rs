//! Separation certificates in the Rapier loop (issue 21, item 4): the
//! narrow phase's queries and time per call with and without
//! `VClipSettings::motion_certificates`, on the scenes of
//! `with_and_without` (pile of 200, pyramid of 55, compound pile of 60,
//! mixed pile of 60), bridge defaults.
//!
//! ```text
//! cargo run --release --features rapier,serde --example probes -- certificates [--steps N] [--scenes A,B]
//! ```
//!
//! Two copies of the same world are stepped in lockstep, one bridge call
//! after every step in each, the two calls of a step made in alternating
//! order (interleaved, so that the machine's load falls on both alike).
//! The certificates skip only pairs that would give no row, so the two
//! worlds stay bit-identical (checked after every step; a difference is
//! reported and the figures after it are of two trajectories). Per scene,
//! over the calls that ran the stabilizer (the bridge skips it when every
//! body sleeps or is held): medians of the queries (`Report::pair_queries`), the
//! pairs certified (`Report::certified_pairs`) and answered by an earlier
//! call's answer at the same poses (`Report::reused_pairs`), the narrow
//! phase's time
//! (`StageTimes::narrow_phase`) and the call's time, Rapier's median step
//! (over all steps, and over the steps taken with an awake dynamic body:
//! a world whose bodies all sleep steps in microseconds), and the narrow
//! phase over Rapier's median awake step.

use crate::scenes;

use std::time::Instant;

use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge, pose_to_f64};
use rapier3d::prelude::*;

/// Steps per run (5 s at 60 Hz).
const DEFAULT_STEPS: usize = 300;

/// What one variant measured per call.
#[derive(Default)]
struct Calls {
    queries: Vec<f64>,
    certified: Vec<f64>,
    reused: Vec<f64>,
    narrow_ms: Vec<f64>,
    call_ms: Vec<f64>,
}

fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The world of a scene of the Rapier loop by name (`pile_200`,
/// `pyramid_55`, `compound_pile_60`, `mixed_pile_60`).
pub(crate) fn world_of(name: &str) -> Option<PhysicsWorld> {
    Some(match name {
        "pile_200" => scenes::pile_world(200, 1.0, 1),
        "pyramid_55" => scenes::pyramid_world().0,
        "compound_pile_60" => scenes::compound_pile_world(60, 0.6, 1),
        "mixed_pile_60" => scenes::mixed_pile_world(60, 0.6, 1),
        _ => return None,
    })
}

fn poses(world: &PhysicsWorld) -> Vec<nalgebra::Isometry3<f64>> {
    world
        .bodies
        .iter()
        .map(|(_, body)| pose_to_f64(body.position()))
        .collect()
}

/// The loop probes' `--steps N` (default [`DEFAULT_STEPS`]) and `--scenes
/// A,B` (default the four scenes of [`world_of`]).
pub(crate) fn steps_and_scenes(
    args: &[String],
) -> Result<(usize, String), std::num::ParseIntError> {
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let steps = value("--steps").map_or(Ok(DEFAULT_STEPS), |s| s.parse())?;
    let names = value("--scenes")
        .unwrap_or_else(|| "pile_200,pyramid_55,compound_pile_60,mixed_pile_60".into());
    Ok((steps, names))
}

pub fn run(args: Vec<String>) -> Result<(), Box<dyn std::error::Error>> {
    let (steps, names) = steps_and_scenes(&args)?;
    println!(
        "| scene | steps | calls that ran the stabilizer: with / without | queries per call (median): with / without | certified / reused per call (median) | narrow ms (median): with / without | call ms (median): with / without | Rapier step ms (median: all / awake) | narrow / awake step: with / without | poses identical |\n|---|---|---|---|---|---|---|---|---|---|"
    );
    for name in names.split(',').map(str::trim) {
        let (Some(a), Some(b)) = (world_of(name), world_of(name)) else {
            return Err(format!("no scene named {name}").into());
        };
        let mut worlds = [a, b];
        let mut bridges = [true, false].map(|certificates| {
            let mut settings = BridgeSettings::default();
            settings.stabilizer.vclip.motion_certificates = certificates;
            RapierBridge::with_settings(settings)
        });
        let mut calls = [Calls::default(), Calls::default()];
        let (mut step_ms, mut awake_step_ms) = (Vec::new(), Vec::new());
        let mut first_difference = None;
        for step in 0..steps {
            let order = if step % 2 == 0 { [0, 1] } else { [1, 0] };
            for k in order {
                let world = &mut worlds[k];
                let awake = world
                    .bodies
                    .iter()
                    .any(|(_, b)| b.is_dynamic() && !b.is_sleeping());
                let start = Instant::now();
                world.step();
                let ms = start.elapsed().as_secs_f64() * 1e3;
                step_ms.push(ms);
                if awake {
                    awake_step_ms.push(ms);
                }
                let bridge = bridges[k].as_mut().map_err(|e| e.to_string())?;
                let start = Instant::now();
                let report = bridge.stabilize_world(world)?;
                let call_ms = start.elapsed().as_secs_f64() * 1e3;
                if let Some(report) = report.stabilizer {
                    let calls = &mut calls[k];
                    calls.queries.push(report.pair_queries as f64);
                    calls.certified.push(report.certified_pairs as f64);
                    calls.reused.push(report.reused_pairs as f64);
                    calls.narrow_ms.push(report.times.narrow_phase * 1e3);
                    calls.call_ms.push(call_ms);
                }
            }
            if first_difference.is_none() && poses(&worlds[0]) != poses(&worlds[1]) {
                first_difference = Some(step + 1);
            }
        }
        let (step, awake_step) = (median(&step_ms), median(&awake_step_ms));
        let [with, without] = &calls;
        println!(
            "| {name} | {steps} | {} / {} | {:.0} / {:.0} | {:.0} / {:.0} | {:.3} / {:.3} | {:.2} / {:.2} | {step:.3} / {awake_step:.3} | {:.2} / {:.2} | {} |",
            with.queries.len(),
            without.queries.len(),
            median(&with.queries),
            median(&without.queries),
            median(&with.certified),
            median(&with.reused),
            median(&with.narrow_ms),
            median(&without.narrow_ms),
            median(&with.call_ms),
            median(&without.call_ms),
            median(&with.narrow_ms) / awake_step,
            median(&without.narrow_ms) / awake_step,
            first_difference.map_or("yes".to_string(), |s| format!("no, from step {s}")),
        );
    }
    Ok(())
}
