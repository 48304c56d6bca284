//! The projection QPs of the slowest calls of a Rapier loop, for
//! `engine_qps --rapier SCENE`: the scene of `with_and_without` is stepped
//! `steps` times with one call of `RapierBridge::with_settings(
//! BridgeSettings::default())` after every step, the QPs each call hands to
//! the solver are recorded (`solver::recorder`), and the `worst` slowest
//! calls are kept with their stage times (the profile of issue 21's worst
//! calls: the solver against the rest of a call).

use std::time::Instant;

use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge};
use constraint_stabilization::solver::recorder::{self, RecordedQp};
use rapier3d::prelude::*;

#[path = "../examples/common/rapier_scenes.rs"]
mod rapier_scenes;

/// One recorded call of the loop.
pub struct LoopCall {
    /// The step after which it ran (1-based).
    pub step: usize,
    /// The call's time (ms), the bridge's work included.
    pub call_ms: f64,
    /// The stabilizer's stage times (ms): narrow phase, solve (the
    /// linearization and the solvers), line search, total.
    pub narrow_ms: f64,
    pub solve_ms: f64,
    pub line_search_ms: f64,
    pub stabilizer_ms: f64,
    /// Passes of the call.
    pub passes: usize,
    /// The QPs the call solved, in order.
    pub qps: Vec<RecordedQp>,
}

/// The world of a `with_and_without` scene by name.
fn scene_world(name: &str) -> Option<PhysicsWorld> {
    Some(match name {
        "pile_200" => rapier_scenes::pile_world(200, 1.0, 1),
        "compound_pile_60" => rapier_scenes::compound_pile_world(60, 0.6, 1),
        "mixed_pile_60" => rapier_scenes::mixed_pile_world(60, 0.6, 1),
        "stack_1to100" => rapier_scenes::aligned_heavy_stack_world(100.0).0,
        "stack_1to1000" => rapier_scenes::aligned_heavy_stack_world(1000.0).0,
        "thrown_box" => rapier_scenes::thrown_box_world(6).0,
        "pyramid_55" => rapier_scenes::pyramid_world().0,
        _ => return None,
    })
}

/// The `worst` slowest calls of `steps` steps of scene `name`, slowest
/// first; `settings` adjusts the bridge's default settings (the solver
/// under study).
pub fn worst_calls(
    name: &str,
    steps: usize,
    worst: usize,
    settings: impl Fn(&mut BridgeSettings),
) -> Vec<LoopCall> {
    let Some(mut world) = scene_world(name) else {
        panic!("no Rapier scene named {name}");
    };
    let mut bridge_settings = BridgeSettings::default();
    settings(&mut bridge_settings);
    let mut bridge = RapierBridge::with_settings(bridge_settings).expect("valid settings");
    let mut calls: Vec<LoopCall> = Vec::new();
    for step in 1..=steps {
        world.step();
        recorder::start();
        let t = Instant::now();
        let report = bridge.stabilize_world(&mut world);
        let call_ms = t.elapsed().as_secs_f64() * 1e3;
        let qps = recorder::stop();
        let stabilizer = report.ok().and_then(|r| r.stabilizer);
        let times = stabilizer.as_ref().map(|r| r.times);
        let times = times.unwrap_or_default();
        calls.push(LoopCall {
            step,
            call_ms,
            narrow_ms: 1e3 * times.narrow_phase,
            solve_ms: 1e3 * times.solve,
            line_search_ms: 1e3 * times.line_search,
            stabilizer_ms: 1e3 * times.total,
            passes: stabilizer.map_or(0, |r| r.passes),
            qps,
        });
    }
    calls.sort_by(|a, b| b.call_ms.total_cmp(&a.call_ms));
    // `ENGINE_QPS_AROUND_MEDIAN=1`: the calls around the median call
    // instead of the slowest.
    if std::env::var("ENGINE_QPS_AROUND_MEDIAN").as_deref() == Ok("1") {
        let first = (calls.len() / 2).saturating_sub(worst / 2);
        calls.drain(..first);
    }
    calls.truncate(worst);
    calls
}
