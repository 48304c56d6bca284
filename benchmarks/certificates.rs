//! Separation certificates on the engine states (issue 21, item 4): the
//! narrow phase's queries and time per call with and without
//! `VClipSettings::motion_certificates`, against one Rapier step of the
//! same scene.
//!
//! For each engine state in `tests/data/engine/*.json`, each repeat runs,
//! for both variants in alternating order (interleaved):
//! - `cold`: one call with a fresh stabilizer on a copy of the state (the
//!   certificates can only act across the call's passes);
//! - `next`: a kept stabilizer called on the state (not timed), then on its
//!   answer with every dynamic body lowered along z by 1, 2 or 3 mm (by
//!   index), as the next engine step would: the certificates of the first
//!   call act across calls.
//!
//! `of which trials`: the queries of the line search's trials (the rest
//! are the detections', `PassReport::queried_pairs`).
//!
//! The step is a Rapier step of the same scene
//! (`rapier_bridge::world_from_scene`, bodies at rest, 10 steps per
//! repeat, median of all). Medians over the repeats; `same` says whether
//! the two variants' poses were bit-identical in every call.
//!
//! Run: `cargo bench --features rapier,serde --bench certificates`
//! (`-- --quick`: 5 repeats, else 25; `-- --only STEM`: the states whose name
//! contains STEM). Prints a markdown table.

mod common;

use std::time::Instant;

use constraint_stabilization::rapier_bridge::{GRAVITY_Z_UP, world_from_scene};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Stabilizer};
use nalgebra::{Translation3, Vector3};

/// Rapier steps timed per repeat.
const STEPS: usize = 10;
/// Lowering of the `next` call's input, times 1, 2 or 3 (m).
const PRESS: f64 = 1e-3;

/// The default settings with the certificates on or off.
fn settings(certificates: bool) -> Settings {
    let mut settings = Settings::default();
    settings.vclip.motion_certificates = certificates;
    settings
}

/// One timed call on a copy of `input`.
fn call(stabilizer: &mut Stabilizer, input: &Scene) -> (Report, f64, Scene) {
    let mut scene = input.clone();
    let start = Instant::now();
    let report = stabilizer.stabilize(&mut scene).expect("a valid state");
    (report, start.elapsed().as_secs_f64(), scene)
}

/// Every dynamic body lowered along z by `PRESS` times 1, 2 or 3.
fn pressed(scene: &Scene) -> Scene {
    let mut scene = scene.clone();
    for index in 0..scene.len() {
        if scene.bodies()[index].is_fixed() {
            continue;
        }
        let drop = PRESS * (1 + index % 3) as f64;
        let pose =
            Translation3::from(Vector3::new(0.0, 0.0, -drop)) * scene.bodies()[index].com_pose();
        scene.set_com_pose(index, pose).expect("a finite pose");
    }
    scene
}

/// Per variant and kind of call: queries, certified pairs, narrow-phase
/// ms, call ms, and the output poses of the last repeat.
#[derive(Default)]
struct Measured {
    queries: Vec<f64>,
    /// Of the queries, the line-search trials' (the rest are detections').
    trial_queries: Vec<f64>,
    certified: Vec<f64>,
    narrow_ms: Vec<f64>,
    call_ms: Vec<f64>,
}

impl Measured {
    fn push(&mut self, report: &Report, seconds: f64) {
        self.queries.push(report.pair_queries as f64);
        let detections: usize = report.pass_reports.iter().map(|p| p.queried_pairs).sum();
        self.trial_queries
            .push(report.pair_queries.saturating_sub(detections) as f64);
        self.certified.push(report.certified_pairs as f64);
        self.narrow_ms.push(report.times.narrow_phase * 1e3);
        self.call_ms.push(seconds * 1e3);
    }
}

fn bits(scene: &Scene) -> Vec<[u64; 7]> {
    scene
        .bodies()
        .iter()
        .map(|b| {
            let (t, q) = (b.translation_user(), b.rotation_user_xyzw());
            [t.x, t.y, t.z, q[0], q[1], q[2], q[3]].map(f64::to_bits)
        })
        .collect()
}

fn main() {
    let common::BenchArgs { quick, only } = common::BenchArgs::parse();
    let provenance = common::Provenance::start(common::bench_command(
        "certificates --features rapier,serde",
        &[],
    ));
    let repeats = if quick { 5 } else { 25 };
    let mut table = String::from(
        "| state | call | queries: with / without | of which trials: with / without | certified | narrow ms: with / without (ratio) | call ms: with / without | step ms | narrow / step: with / without | same |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (name, state) in common::engine_states() {
        if only
            .as_ref()
            .is_some_and(|stem| !name.contains(stem.as_str()))
        {
            continue;
        }
        // [variant][cold, next]; variant 0 with certificates.
        let mut measured: [[Measured; 2]; 2] = Default::default();
        let mut same = true;
        let mut step_ms = Vec::new();
        for r in 0..repeats {
            let order = if r % 2 == 0 { [0, 1] } else { [1, 0] };
            let mut outputs: [Vec<Vec<[u64; 7]>>; 2] = Default::default();
            for v in order {
                let certificates = v == 0;
                let mut fresh = Stabilizer::new(settings(certificates)).expect("settings");
                let (report, seconds, cold) = call(&mut fresh, &state);
                measured[v][0].push(&report, seconds);
                let mut kept = Stabilizer::new(settings(certificates)).expect("settings");
                let (_, _, first) = call(&mut kept, &state);
                let (report, seconds, next) = call(&mut kept, &pressed(&first));
                measured[v][1].push(&report, seconds);
                outputs[v] = vec![bits(&cold), bits(&next)];
            }
            same &= outputs[0] == outputs[1];
            let mut built = world_from_scene(&state, GRAVITY_Z_UP).expect("a Rapier world");
            for _ in 0..STEPS {
                let start = Instant::now();
                built.world.step();
                step_ms.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        let step = common::median(&step_ms);
        for (kind, label) in ["cold", "next"].iter().enumerate() {
            let [with, without] = [&measured[0][kind], &measured[1][kind]];
            let m = |values: &[f64]| common::median(values);
            let (narrow_with, narrow_without) = (m(&with.narrow_ms), m(&without.narrow_ms));
            table += &format!(
                "| {name} | {label} | {:.0} / {:.0} | {:.0} / {:.0} | {:.0} | {narrow_with:.3} / {narrow_without:.3} ({:.2}) | {:.2} / {:.2} | {step:.3} | {:.2} / {:.2} | {} |\n",
                m(&with.queries),
                m(&without.queries),
                m(&with.trial_queries),
                m(&without.trial_queries),
                m(&with.certified),
                narrow_with / narrow_without,
                m(&with.call_ms),
                m(&without.call_ms),
                narrow_with / step,
                narrow_without / step,
                if same { "yes" } else { "no" },
            );
        }
        eprintln!("{name} done");
    }
    println!("{}\n{table}", provenance.markdown());
}
