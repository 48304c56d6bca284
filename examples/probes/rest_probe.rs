//! What keeps a settled scene moving under the bridge (issue 22): the
//! pyramid of 55 or the pile of 200 run with a bridge call after every
//! step, and per step the motion of every body split into the part Rapier's
//! step made and the part the call made, with Rapier's sleep test.
//!
//! ```text
//! cargo run --release --features rapier,serde --example probes -- rest [--scene pyramid|pile|compound] [--steps N] [--from S] [--coupling closed|velocity|positions|plain] [--every K] [--velocity-friction none|velocity] [--no-resting]
//! ```
//!
//! Every `K` steps from step `S` (default 60, every 20) it prints: the
//! largest per-step displacement of a body's farthest point by Rapier's
//! step and by the call (Rapier's sleep test compares the sum over a step
//! against `2 * normalized_linear_threshold * length_unit * dt`, 1.67 mm
//! at 60 Hz), the horizontal displacement summed since `S` (signed, the
//! creep) by the steps and by the calls for the body that moved most, the
//! bodies asleep, the bodies whose sleep timer is running, the bodies the
//! call wrote and held (held cycles), whether the call was a resting one,
//! the bodies whose motion in Rapier's step fails Rapier's sleep test, and
//! the exact depth Rapier's step left. `--no-resting` turns the bridge's resting calls off
//! (`BridgeSettings::resting_calls`).

use crate::scenes;

use constraint_stabilization::rapier_bridge::{BridgeSettings, CouplingMode, RapierBridge};
use constraint_stabilization::stabilizer::VelocityFriction;
use rapier3d::prelude::*;

/// Largest displacement of a point at distance `reach` from the body
/// origin between two poses: translation plus angle times reach.
pub(crate) fn point_motion(a: &Pose, b: &Pose, reach: f32) -> f64 {
    let translation = (b.translation - a.translation).length();
    let angle = a.rotation.angle_between(b.rotation);
    f64::from(translation + angle * reach)
}

/// The world's dynamic bodies and the reach of each (the largest extent
/// of its mass properties).
pub(crate) fn dynamic_bodies(world: &PhysicsWorld) -> (Vec<RigidBodyHandle>, Vec<f32>) {
    let handles: Vec<RigidBodyHandle> = world
        .bodies
        .iter()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .collect();
    let reach = handles
        .iter()
        .map(|&h| world.bodies[h].mass_properties().max_extent())
        .collect();
    (handles, reach)
}

/// The word after `flag` on the command line.
pub(crate) fn flag_value(args: &[String], flag: &str) -> Option<String> {
    args.windows(2).find(|w| w[0] == flag).map(|w| w[1].clone())
}

pub fn run(args: Vec<String>) -> Result<(), Box<dyn std::error::Error>> {
    let value = |flag: &str| flag_value(&args, flag);
    let steps: usize = value("--steps").map_or(Ok(300), |s| s.parse())?;
    let from: usize = value("--from").map_or(Ok(60), |s| s.parse())?;
    let every: usize = value("--every").map_or(Ok(20), |s| s.parse())?;
    let mut world = match value("--scene").as_deref() {
        None | Some("pyramid") => scenes::pyramid_world().0,
        Some("pile") => scenes::pile_world(200, 1.0, 1),
        Some("compound") => scenes::compound_pile_world(60, 0.6, 1),
        Some(other) => return Err(format!("unknown scene {other}").into()),
    };
    let coupling = match value("--coupling").as_deref() {
        None | Some("closed") => Some(CouplingMode::ClosedContacts),
        Some("velocity") => Some(CouplingMode::VelocityConsistency),
        Some("positions") => Some(CouplingMode::PositionsOnly),
        Some("plain") => None,
        Some(other) => return Err(format!("unknown coupling {other}").into()),
    };
    let velocity_friction = match value("--velocity-friction").as_deref() {
        None => BridgeSettings::default().velocity_friction,
        Some("none") => VelocityFriction::None,
        Some("velocity") => VelocityFriction::OnVelocity,
        Some(other) => return Err(format!("unknown velocity friction {other}").into()),
    };
    let mut bridge = RapierBridge::with_settings(BridgeSettings {
        coupling: coupling.unwrap_or_default(),
        velocity_friction,
        resting_calls: !args.iter().any(|a| a == "--no-resting"),
        ..BridgeSettings::default()
    })?;
    let mut measure = RapierBridge::with_settings(BridgeSettings::default())?;
    let (handles, reach) = dynamic_bodies(&world);
    let n = handles.len();
    let mut creep_step = vec![[0.0f64; 2]; n];
    let mut creep_call = vec![[0.0f64; 2]; n];
    let dt = world.integration_parameters.dt;
    let threshold = 2.0 * 0.05 * world.integration_parameters.length_unit * dt;
    println!("sleep test: a body's point motion per step below {threshold:.2e} m for 0.5 s");
    for step in 1..=steps {
        let p0: Vec<Pose> = handles
            .iter()
            .map(|&h| *world.bodies[h].position())
            .collect();
        world.step();
        let p1: Vec<Pose> = handles
            .iter()
            .map(|&h| *world.bodies[h].position())
            .collect();
        measure.sync(&world.bodies, &world.colliders)?;
        let depth_after_step = dev_support::sat::sat_deepest(measure.scene()).0;
        let (written, resting, held) = match coupling {
            Some(_) => {
                let report = bridge.stabilize_world(&mut world)?;
                (report.bodies_written, report.resting, report.bodies_held)
            }
            None => (0, false, 0),
        };
        let p2: Vec<Pose> = handles
            .iter()
            .map(|&h| *world.bodies[h].position())
            .collect();
        let (mut by_step, mut by_call, mut net) = (0.0f64, 0.0f64, 0.0f64);
        let mut step_fails = 0;
        for i in 0..n {
            if point_motion(&p0[i], &p1[i], reach[i]) >= f64::from(threshold) {
                step_fails += 1;
            }
            net = net.max(point_motion(&p0[i], &p2[i], reach[i]));
            by_step = by_step.max(point_motion(&p0[i], &p1[i], reach[i]));
            by_call = by_call.max(point_motion(&p1[i], &p2[i], reach[i]));
            if step > from {
                let s = p1[i].translation - p0[i].translation;
                let c = p2[i].translation - p1[i].translation;
                creep_step[i][0] += f64::from(s.x);
                creep_step[i][1] += f64::from(s.y);
                creep_call[i][0] += f64::from(c.x);
                creep_call[i][1] += f64::from(c.y);
            }
        }
        if step >= from && (step - from).is_multiple_of(every) {
            let asleep = handles
                .iter()
                .filter(|&&h| world.bodies[h].is_sleeping())
                .count();
            let timer = handles
                .iter()
                .map(|&h| world.bodies[h].activation().time_since_can_sleep)
                .fold(f32::INFINITY, f32::min);
            let spin = handles
                .iter()
                .map(|&h| world.bodies[h].angvel().length())
                .fold(0.0f32, f32::max);
            let timing = handles
                .iter()
                .filter(|&&h| world.bodies[h].activation().is_eligible_for_sleep())
                .count();
            let total = |i: usize| {
                let x = creep_step[i][0] + creep_call[i][0];
                let y = creep_step[i][1] + creep_call[i][1];
                x.hypot(y)
            };
            let worst = (0..n)
                .max_by(|&a, &b| total(a).total_cmp(&total(b)))
                .unwrap_or(0);
            println!(
                "step {step}: per-step point motion, step {by_step:.2e} call {by_call:.2e} net {net:.2e} | shortest sleep timer {timer:.3} s, fastest spin {spin:.2e} rad/s | creep of body {worst} since {from}: {:.2e} m (steps {:+.2e} {:+.2e}, calls {:+.2e} {:+.2e}) | asleep {asleep}/{n}, eligible for sleep {timing} | written {written}, held {held}, resting call {resting}, bodies failing the sleep test in Rapier's step {step_fails} | depth after Rapier's step {depth_after_step:.2e}",
                total(worst),
                creep_step[worst][0],
                creep_step[worst][1],
                creep_call[worst][0],
                creep_call[worst][1],
            );
        }
    }
    Ok(())
}
