//! Bodies the bridge puts to sleep while Rapier still integrates them
//! (`rapier_bridge/limbo.rs`): Rapier 0.36 drops the contacts of a body
//! flagged asleep from its solver but integrates it until its island
//! manager commits the sleep, so the bodies fall freely through each other
//! and the ground. The bridge stops that fall at every call and wakes a
//! body that fell beyond Rapier's allowed linear error. And held cycles
//! with `BridgeSettings::zero_held_velocities`.

use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge};
use nalgebra::Isometry3;
use rapier3d::prelude::*;

use super::worlds;

/// Steps of the run: 3 s at Rapier's 60 Hz (the stack sleeps by step 40).
const STEPS: usize = 180;

/// Mass of the top box over a light box's.
const RATIO: f32 = 100.0;

/// One step of free fall from rest with Rapier's default four substeps,
/// `g dt^2 (k + 1) / (2 k)` (m): the most a body at rest falls in a step
/// with no contact solved.
const ONE_STEP_FALL: f64 = 9.81 / 3600.0 * 5.0 / 8.0;

/// The farthest a box's centre moved from its pose when put to sleep (m).
fn moved(world: &PhysicsWorld, body: RigidBodyHandle, at_sleep: &Isometry3<f64>) -> f64 {
    let t = world.bodies[body].translation();
    let now = nalgebra::Vector3::new(f64::from(t.x), f64::from(t.y), f64::from(t.z));
    (now - at_sleep.translation.vector).norm()
}

/// Every box of the 1:100 stack that the bridge put to sleep stays, while
/// it is flagged asleep, within Rapier's allowed linear error of where it
/// was put to sleep (without the stop, Rapier's free fall of a flagged
/// body accumulates: 1.7 mm in the first step, 4.4 mm in the second), and
/// the world's exact depth after every call with an awake body stays
/// within the call's stated bound.
#[test]
fn a_stack_put_to_sleep_sinks_less_than_rapiers_allowed_error() {
    let (mut world, handles) = worlds::aligned_heavy_stack(RATIO);
    let mut bridge =
        RapierBridge::with_settings(BridgeSettings::default()).expect("default settings are valid");
    let allowed = f64::from(world.integration_parameters.allowed_linear_error());
    let mut at_sleep: Option<Vec<Isometry3<f64>>> = None;
    let mut deepest_sink: f64 = 0.0;
    for step in 1..=STEPS {
        world.step();
        let report = bridge
            .stabilize_world(&mut world)
            .expect("the call succeeds");
        if report.bodies_put_to_sleep > 0 && at_sleep.is_none() {
            at_sleep = Some(
                handles
                    .iter()
                    .map(|&h| {
                        constraint_stabilization::rapier_bridge::pose_to_f64(
                            world.bodies[h].position(),
                        )
                    })
                    .collect(),
            );
            continue;
        }
        let Some(poses) = &at_sleep else { continue };
        for (&h, pose) in handles.iter().zip(poses) {
            if world.bodies[h].is_sleeping() {
                let sink = moved(&world, h, pose);
                deepest_sink = deepest_sink.max(sink);
                assert!(
                    sink <= allowed + ONE_STEP_FALL,
                    "step {step}: a box put to sleep moved {sink:e} m (allowed {allowed:e})"
                );
            }
        }
    }
    assert!(at_sleep.is_some(), "the bridge puts the stack to sleep");
    assert!(deepest_sink <= allowed);
}

/// With `BridgeSettings::zero_held_velocities`, a call that holds every
/// box of the 1:1000 stack at its anchor leaves them without velocity
/// (the held cycle a fixed point in velocity too), the stack still stands
/// within 1 mm of sideways drift, and the exact depth after every call
/// with an awake box is within the call's stated bound.
#[test]
fn held_boxes_leave_the_call_without_velocity_when_asked() {
    let (mut world, handles) = worlds::aligned_heavy_stack(1000.0);
    let start: Vec<Vector> = handles
        .iter()
        .map(|&h| world.bodies[h].translation())
        .collect();
    let mut bridge = RapierBridge::with_settings(BridgeSettings {
        zero_held_velocities: true,
        ..BridgeSettings::default()
    })
    .expect("valid settings");
    let mut held_calls = 0;
    for step in 1..=STEPS {
        world.step();
        let report = bridge
            .stabilize_world(&mut world)
            .expect("the call succeeds");
        if report.bodies_held == handles.len() {
            held_calls += 1;
            for &h in &handles {
                let body = &world.bodies[h];
                assert_eq!(body.linvel(), Vector::ZERO, "step {step}");
                assert_eq!(body.angvel(), Vector::ZERO, "step {step}");
            }
        }
        if handles.iter().any(|&h| !world.bodies[h].is_sleeping()) {
            let depth = super::f32_awake_depth(&world);
            let bound = super::stated_tolerance(&report);
            assert!(
                depth <= bound,
                "step {step}: depth {depth:e} over {bound:e}"
            );
        }
    }
    assert!(held_calls > 0, "the stack is held");
    for (&h, s) in handles.iter().zip(&start) {
        let t = world.bodies[h].translation();
        let drift = f64::from((t.x - s.x).hypot(t.y - s.y));
        assert!(drift < 1e-3, "a box drifted {drift:e} m");
    }
}
