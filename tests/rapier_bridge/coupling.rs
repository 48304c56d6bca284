//! Coupling modes: with `RespectAllowedPenetration` the bridge leaves
//! Rapier's allowed linear error (5 mm by default) to the engine; with
//! `VelocityConsistency` (the default) it also removes the approach
//! velocities of the contacts it corrected.

use constraint_stabilization::Settings;
use constraint_stabilization::Status;
use constraint_stabilization::rapier_bridge::{BridgeSettings, CouplingMode, RapierBridge};
use rapier3d::prelude::*;

use super::{f32_world_depth, run, world_with_box_at};

fn respecting_bridge() -> RapierBridge {
    RapierBridge::with_settings(BridgeSettings {
        coupling: CouplingMode::RespectAllowedPenetration,
        collider_friction: false,
        ..BridgeSettings::with_stabilizer(Settings::default())
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

/// The default bridge (velocity consistency, colliders' friction) on a box
/// sunk into the ground and falling: the position is corrected and the
/// box no longer approaches the ground (its downward velocity is removed;
/// the sideways and angular velocities, which do not approach the ground,
/// are changed only through the contact's coupling); a positions-only
/// bridge leaves the velocity as it was.
#[test]
fn velocity_consistency_removes_the_approach_velocity() {
    let (mut world, body) = world_with_box_at(0.45);
    let before = world.bodies[body].linvel();
    assert!(before.y < -1.0, "falling: {before:?}");

    let mut bridge = RapierBridge::new(Settings::default()).expect("default settings");
    assert_eq!(
        bridge.settings().coupling,
        CouplingMode::VelocityConsistency
    );
    let report = run(&mut bridge, &mut world);
    assert_eq!(report.bodies_written, 1);
    assert_eq!(report.velocities_written, 1);
    let velocities = report.velocities.clone().expect("velocity projection ran");
    assert!(velocities.approach_before > 1.0, "{velocities:?}");
    assert!(velocities.approach_after <= 1e-6, "{velocities:?}");
    let rigid = &world.bodies[body];
    // Every bottom corner's velocity along the ground normal is no longer
    // an approach: at most the speculative closing, in one step, of the gap
    // the correction left (about the target margin, 1e-6: 6e-5 m/s at
    // 60 Hz), against 2 m/s before.
    let closing = 1e-4;
    let (v, w) = (rigid.linvel(), rigid.angvel());
    let centre = rigid.center_of_mass();
    for (x, z) in [(-0.5f32, -0.5f32), (-0.5, 0.5), (0.5, -0.5), (0.5, 0.5)] {
        let corner = rigid.position() * Vector::new(x, -0.5, z);
        let point_velocity = v + w.cross(corner - centre);
        assert!(
            f64::from(point_velocity.y) >= -closing,
            "corner ({x}, {z}): {point_velocity:?}"
        );
    }
    assert!(f32_world_depth(&world) <= stated_tolerance_of(&report));

    let (mut world, body) = world_with_box_at(0.45);
    let report = run(&mut super::bridge(), &mut world);
    assert_eq!(
        (report.velocities_written, report.velocities.is_none()),
        (0, true)
    );
    assert_eq!(world.bodies[body].linvel(), before);
}

fn stated_tolerance_of(report: &constraint_stabilization::rapier_bridge::BridgeReport) -> f64 {
    report
        .stabilizer
        .as_ref()
        .expect("dynamic bodies")
        .tolerance
}
