//! A heavy stack at rest under the bridge's default coupling: four 1 kg
//! boxes of 20 cm under a 1,000 kg one (Rapier alone crushes it) stand for
//! 300 steps at 60 Hz, no box drifting sideways by 1 mm, the exact depth
//! of the world after every call within the call's stated tolerance plus
//! the f32 write-back's bound, and the stack falls asleep. Before held
//! cycles (`BridgeSettings::hold_cycles`) the stack drifted 7.4 mm; before
//! held groups were put to sleep (`BridgeSettings::sleep_held_groups`) it
//! never slept.

use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge};
use rapier3d::prelude::*;

use super::{f32_awake_depth, f32_world_depth, stated_tolerance, worlds};

/// Steps of the run: 5 s at Rapier's 60 Hz.
const STEPS: usize = 300;

/// Issue 22's bound on the largest horizontal drift of any box (m).
const DRIFT_BOUND: f64 = 1e-3;

/// Issue 22's bound on when a scene falls asleep under the bridge, over
/// the step at which it does under Rapier alone.
const SLEEP_STEP_RATIO: f64 = 1.2;

/// Mass of the top box over a light box's.
const RATIO: f32 = 1000.0;

fn horizontal(world: &PhysicsWorld, body: RigidBodyHandle) -> [f64; 2] {
    let t = world.bodies[body].translation();
    [f64::from(t.x), f64::from(t.y)]
}

/// The first step at which every box of the stack is asleep under Rapier
/// alone (it crushes the light boxes first).
fn sleeps_alone() -> usize {
    let (mut world, handles) = worlds::aligned_heavy_stack(RATIO);
    (1..=STEPS)
        .find(|_| {
            world.step();
            handles.iter().all(|&h| world.bodies[h].is_sleeping())
        })
        .expect("Rapier alone puts the crushed stack to sleep")
}

/// The stack stands, drifts under 1 mm, and falls asleep (held groups put
/// to sleep, `BridgeSettings::sleep_held_groups`) no later than 20 % after
/// Rapier alone puts its crushed stack to sleep, and stays asleep. Every
/// call's exact depth is within its stated tolerance; once the stack
/// sleeps no call writes it, and its depth is Rapier's, within Rapier's
/// allowed linear error. Before held cycles the stack drifted 7.4 mm;
/// before held groups were put to sleep it never slept.
#[test]
fn the_1_to_1000_stack_drifts_under_1_mm_and_sleeps() {
    let (mut world, handles) = worlds::aligned_heavy_stack(RATIO);
    let start: Vec<[f64; 2]> = handles.iter().map(|&h| horizontal(&world, h)).collect();
    let mut bridge =
        RapierBridge::with_settings(BridgeSettings::default()).expect("default settings are valid");
    let allowed = f64::from(world.integration_parameters.allowed_linear_error());
    let mut drift: f64 = 0.0;
    let mut asleep_from = None;
    for step in 1..=STEPS {
        world.step();
        let report = bridge
            .stabilize_world(&mut world)
            .expect("the call succeeds");
        let depth = f32_world_depth(&world);
        let all_asleep = handles.iter().all(|&h| world.bodies[h].is_sleeping());
        if report.bodies_put_to_sleep > 0 {
            assert_eq!(
                report.bodies_written, 0,
                "step {step}: a sleeper was written"
            );
        }
        match report.stabilizer {
            Some(_) => {
                let bound = stated_tolerance(&report);
                assert!(
                    depth <= bound,
                    "step {step}: depth {depth:e} beyond the call's {bound:e}"
                );
            }
            None => {
                assert!(all_asleep, "step {step}: no call on an awake stack");
                assert_eq!(report.bodies_written, 0);
                assert!(
                    depth <= allowed,
                    "step {step}: asleep {depth:e} deep, Rapier allows {allowed:e}"
                );
            }
        }
        match (all_asleep, asleep_from) {
            (true, None) => asleep_from = Some(step),
            (false, Some(from)) => panic!("asleep from step {from}, awake at step {step}"),
            _ => {}
        }
        for (&h, s) in handles.iter().zip(&start) {
            let p = horizontal(&world, h);
            drift = drift.max((p[0] - s[0]).hypot(p[1] - s[1]));
        }
    }
    // Asleep, its five contacts are left at Rapier's depth, each within
    // Rapier's allowed linear error (crushed, the top ends at 0.1 m).
    let top = f64::from(world.bodies[handles[4]].translation().z);
    assert!(
        (top - 0.9).abs() <= handles.len() as f64 * allowed,
        "the stack stands: top at {top} m"
    );
    assert!(
        drift < DRIFT_BOUND,
        "largest horizontal drift {:.3} mm",
        drift * 1e3
    );
    let alone = sleeps_alone();
    let asleep_from = asleep_from.expect("the stack falls asleep under the bridge");
    assert!(
        asleep_from as f64 <= SLEEP_STEP_RATIO * alone as f64,
        "asleep from step {asleep_from} under the bridge, {alone} under Rapier alone"
    );
}

/// A stack the bridge put to sleep is woken by Rapier where a newcomer
/// lands in it, and the call corrects what is awake: the exact depth of
/// every pair with an awake body within the call's tolerance. (Rapier
/// wakes the top box only: the boxes under it stay asleep, obstacles for
/// the call, their contacts at Rapier's depth; Rapier alone wakes its
/// whole sleeping 1:1 or 1:100 stack.)
#[test]
fn a_stack_put_to_sleep_is_woken_and_corrected_by_a_newcomer() {
    let (mut world, handles) = worlds::aligned_heavy_stack(RATIO);
    let mut bridge =
        RapierBridge::with_settings(BridgeSettings::default()).expect("default settings are valid");
    let asleep = (1..=STEPS).find(|_| {
        world.step();
        bridge
            .stabilize_world(&mut world)
            .expect("the call succeeds");
        handles.iter().all(|&h| world.bodies[h].is_sleeping())
    });
    assert!(asleep.is_some(), "the stack falls asleep");
    // A 1 kg box 2 cm into the top box.
    let top = world.bodies[handles[4]].translation();
    worlds::box_at(&mut world, top + Vector::new(0.05, 0.0, 0.18), 0.1, 1.0);
    world.step();
    assert!(
        !world.bodies[handles[4]].is_sleeping(),
        "Rapier wakes the top box"
    );
    let report = bridge
        .stabilize_world(&mut world)
        .expect("the call succeeds");
    assert!(report.bodies_written >= 1);
    let depth = f32_awake_depth(&world);
    let bound = stated_tolerance(&report);
    assert!(
        depth <= bound,
        "depth {depth:e} beyond the call's {bound:e}"
    );
}
