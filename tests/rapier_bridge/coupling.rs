//! Coupling modes: with `RespectAllowedPenetration` the bridge leaves
//! Rapier's allowed linear error (5 mm by default) to the engine.

use constraint_stabilization::Settings;
use constraint_stabilization::Status;
use constraint_stabilization::rapier_bridge::{BridgeSettings, CouplingMode, RapierBridge};
use rapier3d::prelude::*;

use super::{f32_world_depth, run, world_with_box_at};

fn respecting_bridge() -> RapierBridge {
    RapierBridge::with_settings(BridgeSettings {
        stabilizer: Settings::default(),
        coupling: CouplingMode::RespectAllowedPenetration,
    })
    .expect("valid settings")
}

/// Rapier's allowed linear error (world length).
fn allowed_error(parameters: &IntegrationParameters) -> f64 {
    f64::from(parameters.allowed_linear_error())
}

#[test]
fn box_sunk_less_than_the_allowed_error_is_not_touched() {
    let allowed = allowed_error(&IntegrationParameters::default());
    let (mut world, body) = world_with_box_at(0.5 - 0.5 * allowed as f32);
    let before = *world.bodies[body].position();
    let depth_before = f32_world_depth(&world);
    assert!(depth_before > 0.4 * allowed, "sunk by {depth_before:e}");

    let report = run(&mut respecting_bridge(), &mut world);
    let stabilizer = report.stabilizer.expect("a dynamic body");
    assert_eq!(stabilizer.status, Status::NothingToDo);
    assert_eq!(stabilizer.allowed_penetration, allowed);
    assert_eq!(report.bodies_written, 0);
    assert_eq!(*world.bodies[body].position(), before);

    let report = run(&mut super::bridge(), &mut world);
    assert_eq!(report.bodies_written, 1, "positions only removes it");
}

/// Sunk by 50 times the allowed error, the box is brought back to about
/// the allowed error: within it (plus the tolerance), and not at zero
/// (deeper than the allowed error less twice the call's target margin
/// and tolerance, the linearized target and what may be left of it).
#[test]
fn box_sunk_deeper_ends_within_the_allowed_error_not_at_zero() {
    let allowed = allowed_error(&IntegrationParameters::default());
    let (mut world, body) = world_with_box_at(0.5 - 50.0 * allowed as f32);
    let velocity_before = world.bodies[body].linvel();

    let report = run(&mut respecting_bridge(), &mut world);
    let stabilizer = report.stabilizer.expect("a dynamic body");
    assert_eq!(stabilizer.status, Status::Converged);
    let depth = f32_world_depth(&world);
    let plain_tolerance = stabilizer.tolerance - allowed;
    assert!(depth <= stabilizer.tolerance, "depth {depth:e}");
    assert!(
        depth >= allowed - 3.0 * plain_tolerance,
        "depth {depth:e}, allowed {allowed:e}"
    );
    assert_eq!(world.bodies[body].linvel(), velocity_before);
}
