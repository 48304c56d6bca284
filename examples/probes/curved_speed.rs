//! Cylinders by support functions against their circumscribed 71-gon
//! polyhedra (`VClipSettings::curved_support_functions`, issue 25), on
//! the Rapier pile of 60 balls, capsules, cylinders and rounded boxes:
//! two copies of the same world stepped in lockstep, one bridge call
//! after every step in each, the two calls of a step made in alternating
//! order (interleaved, so that the machine's load falls on both alike).
//!
//! ```text
//! cargo run --release --features rapier,serde --example probes -- curved [--steps N] [--positions]
//! ```
//!
//! `--positions` uses `CouplingMode::PositionsOnly` instead of the
//! bridge's default coupling. Per variant: the calls by status, the call
//! time (median, 90th percentile, max), the steps whose exact deepest
//! penetration after the call (`dev_support::sat`: the support-function
//! oracle on the true shapes) exceeds the call's tolerance, and the worst
//! ratio of that depth to the tolerance. The two worlds drift apart after
//! the first corrections (their corrections differ), so each variant's
//! figures are of its own trajectory.

use crate::scenes;

use std::collections::BTreeMap;
use std::time::Instant;

use constraint_stabilization::Settings;
use constraint_stabilization::rapier_bridge::{BridgeSettings, CouplingMode, RapierBridge};
use rapier3d::prelude::*;

/// Steps per run (5 s at 60 Hz).
const DEFAULT_STEPS: usize = 300;

/// One variant: its world, bridge and what was measured.
struct Variant {
    name: &'static str,
    world: PhysicsWorld,
    bridge: RapierBridge,
    call_ms: Vec<f64>,
    statuses: BTreeMap<String, usize>,
    beyond: usize,
    worst_ratio: f64,
}

impl Variant {
    fn new(
        name: &'static str,
        support: bool,
        positions: bool,
    ) -> Result<Self, Box<dyn std::error::Error>> {
        let mut settings = BridgeSettings::default();
        settings.stabilizer.vclip.curved_support_functions = support;
        if positions {
            settings.coupling = CouplingMode::PositionsOnly;
            settings.collider_friction = false;
        }
        Ok(Variant {
            name,
            world: scenes::mixed_pile_world(60, 0.6, 1),
            bridge: RapierBridge::with_settings(settings)?,
            call_ms: Vec::new(),
            statuses: BTreeMap::new(),
            beyond: 0,
            worst_ratio: 0.0,
        })
    }

    /// One Rapier step and one bridge call, timed; then the oracle.
    fn step(
        &mut self,
        step: usize,
        measure: &mut RapierBridge,
    ) -> Result<(), Box<dyn std::error::Error>> {
        self.world.step();
        let start = Instant::now();
        let result = self.bridge.stabilize_world(&mut self.world);
        self.call_ms.push(start.elapsed().as_secs_f64() * 1e3);
        let (status, tolerance) = match result {
            Ok(report) => (
                report
                    .stabilizer
                    .as_ref()
                    .map_or("no_dynamic_body", |r| r.status.name()),
                report.stated_tolerance.unwrap_or(f64::INFINITY),
            ),
            Err(_) => ("error", f64::INFINITY),
        };
        *self.statuses.entry(status.to_string()).or_default() += 1;
        measure.sync(&self.world.bodies, &self.world.colliders)?;
        let (depth, pair) = dev_support::sat::sat_deepest(measure.scene());
        if depth > tolerance {
            self.beyond += 1;
            let bodies = measure.scene().bodies();
            let shapes = pair.map(|(i, j)| (bodies[i].shape().clone(), bodies[j].shape().clone()));
            println!(
                "{}: step {step}, oracle depth after {depth:.4e} > tolerance {tolerance:.4e}, pair {pair:?}: {shapes:?}",
                self.name
            );
        }
        if tolerance.is_finite() && tolerance > 0.0 {
            self.worst_ratio = self.worst_ratio.max(depth / tolerance);
        }
        Ok(())
    }

    fn summary(&self) -> String {
        let mut sorted = self.call_ms.clone();
        sorted.sort_by(f64::total_cmp);
        let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
        let statuses: Vec<String> = self
            .statuses
            .iter()
            .map(|(s, c)| format!("{s} {c}"))
            .collect();
        format!(
            "| {} | {} | {:.2} | {:.2} | {:.1} | {} | {:.3} |",
            self.name,
            statuses.join(", "),
            at(0.5),
            at(0.9),
            at(1.0),
            self.beyond,
            self.worst_ratio
        )
    }
}

pub fn run(args: Vec<String>) -> Result<(), Box<dyn std::error::Error>> {
    let steps = args
        .iter()
        .position(|a| a == "--steps")
        .and_then(|i| args.get(i + 1))
        .map_or(Ok(DEFAULT_STEPS), |s| s.parse())?;
    let positions = args.iter().any(|a| a == "--positions");
    let mut variants = [
        Variant::new("support functions", true, positions)?,
        Variant::new("71-gon polyhedra", false, positions)?,
    ];
    let mut measure = RapierBridge::new(Settings::default())?;
    for step in 0..steps {
        // Alternate which variant goes first.
        if step % 2 == 0 {
            for v in variants.iter_mut() {
                v.step(step + 1, &mut measure)?;
            }
        } else {
            for v in variants.iter_mut().rev() {
                v.step(step + 1, &mut measure)?;
            }
        }
    }
    println!(
        "mixed_pile_60, {steps} steps, coupling {}",
        if positions {
            "positions only"
        } else {
            "bridge default"
        }
    );
    println!(
        "| narrow phase for cylinders | calls by status | call ms median | 90th percentile | max | steps with oracle depth after above the tolerance | worst depth / tolerance |"
    );
    println!("|---|---|---|---|---|---|---|");
    for v in &variants {
        println!("{}", v.summary());
    }
    let median = |v: &Variant| {
        let mut sorted = v.call_ms.clone();
        sorted.sort_by(f64::total_cmp);
        sorted[sorted.len() / 2]
    };
    println!(
        "median call, support / polyhedra: {:.2}",
        median(&variants[0]) / median(&variants[1])
    );
    Ok(())
}
