//! Joints through the bridge: Rapier's impulse joints read and their drift
//! removed with the contacts, every call, judged from Rapier's own body
//! poses (anchor points in f64 from the f32 poses); multibody joints and
//! joints to bodies outside the scene skipped with their reason.

#[path = "../../../examples/common/rapier_joint_scenes.rs"]
mod joint_scenes;

use constraint_stabilization::rapier_bridge::{
    BridgeSettings, JointSkipReason, RapierBridge, RapierJoint,
};
use joint_scenes::{chain_stretch, chain_world, joint_separation, largest_joint_separation};
use rapier3d::prelude::*;

/// Rapier steps of a chain test (2 s at 60 Hz: the chain's first swing).
const STEPS: usize = 120;
/// Largest stretch asked of a chain (relative to its rest length).
const STRETCH: f64 = 1e-3;
/// The engine alone separates this chain's joints by more than this in
/// the same steps (measured: 18 cm over 300 steps), so the test can fail.
const RAPIER_ALONE_AT_LEAST: f64 = 0.01;

fn default_bridge() -> RapierBridge {
    RapierBridge::with_settings(BridgeSettings::default()).expect("default settings")
}

#[test]
fn a_chain_with_a_heavy_end_keeps_its_joints_after_every_call() {
    let (mut world, chain) = chain_world(10, 100.0);
    let mut bridge = default_bridge();
    let mut rapier_alone_worst: f64 = 0.0;
    let (mut alone, _) = chain_world(10, 100.0);
    for step in 0..STEPS {
        world.step();
        let report = bridge
            .stabilize_world(&mut world)
            .expect("the call succeeds");
        assert_eq!(report.joints.read, chain.joints.len());
        let stabilizer = report.stabilizer.as_ref().expect("dynamic bodies");
        assert!(
            stabilizer.status.is_resolved(),
            "step {step}: {:?}",
            stabilizer.status
        );
        // The call's tolerance and the f32 write-back (twice its bound).
        let allowed = stabilizer.tolerance + 2.0 * report.round_off_bound;
        let separation = largest_joint_separation(&world);
        assert!(
            separation <= allowed,
            "step {step}: separation {separation:e} > {allowed:e}"
        );
        assert!(chain_stretch(&world, &chain) <= STRETCH);
        alone.step();
        rapier_alone_worst = rapier_alone_worst.max(largest_joint_separation(&alone));
    }
    assert!(
        rapier_alone_worst > RAPIER_ALONE_AT_LEAST,
        "{rapier_alone_worst}"
    );
}

#[test]
fn multibody_joints_and_joints_to_bodies_outside_the_scene_are_skipped_with_their_reason() {
    let mut world = PhysicsWorld::default();
    // An anchor without a collider: not in the scene.
    let anchor = world.insert_body(RigidBodyBuilder::fixed());
    let (a, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
        ColliderBuilder::cuboid(0.1, 0.1, 0.1),
    );
    let (b, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.5, 1.0, 0.0)),
        ColliderBuilder::cuboid(0.1, 0.1, 0.1),
    );
    let (c, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(1.0, 1.0, 0.0)),
        ColliderBuilder::cuboid(0.1, 0.1, 0.1),
    );
    let to_anchor = world.insert_impulse_joint(anchor, a, SphericalJointBuilder::new());
    let between = world.insert_impulse_joint(
        a,
        b,
        SphericalJointBuilder::new()
            .local_anchor1(Vector::new(0.25, 0.0, 0.0))
            .local_anchor2(Vector::new(-0.25, 0.0, 0.0)),
    );
    let multibody = world
        .multibody_joints
        .insert(b, c, RevoluteJointBuilder::new(Vector::Z), true)
        .expect("a multibody link");
    let mut bridge = default_bridge();
    let report = bridge
        .stabilize_world(&mut world)
        .expect("the call succeeds");
    assert_eq!(report.joints.read, 1);
    assert_eq!(bridge.scene().joints().len(), 1);
    let reasons: Vec<_> = report
        .joints
        .skipped
        .iter()
        .map(|s| (s.joint, s.reason.clone()))
        .collect();
    assert!(
        reasons.contains(&(
            RapierJoint::Impulse(to_anchor),
            JointSkipReason::BodyNotInScene(anchor)
        )),
        "{reasons:?}"
    );
    assert!(
        reasons.contains(&(
            RapierJoint::Multibody(multibody),
            JointSkipReason::Multibody
        )),
        "{reasons:?}"
    );
    assert!(
        !reasons
            .iter()
            .any(|(j, _)| *j == RapierJoint::Impulse(between))
    );
}

/// What the velocity projection leaves of a joint's relative velocity
/// along its locked axes, relative to what it found: the acceptance of its
/// QP (1e-6 of the largest violation), with room for rounding.
const VELOCITY_LEFT: f64 = 1e-5;

#[test]
fn the_velocity_coupling_removes_relative_velocity_along_locked_axes() {
    let (mut world, _) = chain_world(5, 100.0);
    let mut bridge = default_bridge();
    let mut projected = 0;
    for step in 0..30 {
        world.step();
        let report = bridge
            .stabilize_world(&mut world)
            .expect("the call succeeds");
        let Some(velocities) = report.velocities else {
            continue;
        };
        if velocities.joint_rate_before > 0.0 {
            projected += 1;
            assert!(
                velocities.joint_rate_after <= VELOCITY_LEFT * velocities.joint_rate_before,
                "step {step}: {:e} -> {:e}",
                velocities.joint_rate_before,
                velocities.joint_rate_after
            );
        }
    }
    assert!(projected > 0, "no call projected a joint's velocity");
}

/// A figure that falls asleep: once the bridge holds its sleeping bodies
/// still, its joints join two fixed bodies and are skipped for that
/// reason (never as invalid), and read again while the figure is awake.
#[test]
fn joints_between_bodies_held_asleep_are_skipped_as_both_fixed() {
    let mut world = joint_scenes::ragdoll_world();
    let joints = world.impulse_joints.len();
    let mut bridge = default_bridge();
    let mut skipped_as_fixed = 0;
    for step in 0..STEPS_TO_SLEEP {
        world.step();
        let report = bridge
            .stabilize_world(&mut world)
            .expect("the call succeeds");
        assert!(
            !report
                .joints
                .skipped
                .iter()
                .any(|s| matches!(s.reason, JointSkipReason::Invalid(_))),
            "step {step}: {:?}",
            report.joints.skipped
        );
        assert_eq!(
            report.joints.read + report.joints.skipped.len(),
            joints,
            "step {step}"
        );
        if report.stabilizer.is_some() {
            // Some body is awake: every joint is read.
            assert_eq!(report.joints.read, joints, "step {step}");
        } else if report.joints.read == 0 {
            assert!(
                report
                    .joints
                    .skipped
                    .iter()
                    .all(|s| s.reason == JointSkipReason::BothBodiesFixed),
                "step {step}: {:?}",
                report.joints.skipped
            );
            skipped_as_fixed += 1;
        }
    }
    assert!(skipped_as_fixed > 0, "the figure never slept");
}

/// A figure held asleep, then one of its parts woken and pulled off its
/// joint: the call that releases the part reads the part's joints (the
/// holds of that call, not the last call's, decide which joints join two
/// fixed bodies) and takes the separation away.
#[test]
fn a_part_woken_from_a_held_figure_keeps_its_joints_in_the_call_that_wakes_it() {
    let mut world = joint_scenes::ragdoll_world();
    let mut bridge = default_bridge();
    let asleep = (0..STEPS_TO_SLEEP).any(|_| {
        world.step();
        let report = bridge
            .stabilize_world(&mut world)
            .expect("the call succeeds");
        report.joints.read == 0 && !report.joints.skipped.is_empty()
    });
    assert!(asleep, "the figure never slept");
    let part = world
        .impulse_joints
        .iter()
        .next()
        .map(|(_, joint)| joint.body2())
        .expect("the ragdoll has joints");
    let body = &mut world.bodies[part];
    let mut pose = *body.position();
    pose.translation.x += PULL;
    body.set_position(pose, true);
    body.wake_up(true);
    // The pulled part's own joints (the others, between parts still
    // asleep, keep Rapier's separation: skipped as joining two fixed
    // bodies).
    let of_part = |world: &PhysicsWorld| {
        world
            .impulse_joints
            .iter()
            .filter(|(_, joint)| joint.body1() == part || joint.body2() == part)
            .map(|(_, joint)| joint_separation(world, joint))
            .fold(0.0, f64::max)
    };
    let before = of_part(&world);
    assert!(before >= 0.5 * f64::from(PULL), "pulled by {before}");
    let report = bridge
        .stabilize_world(&mut world)
        .expect("the call succeeds");
    assert!(report.joints.read > 0, "{:?}", report.joints.skipped);
    let after = of_part(&world);
    assert!(after <= WOKEN_JOINT_TOL, "separation {before} -> {after}");
}

/// How far the woken part is pulled off its joint (m; the ragdoll's parts
/// are 0.1-0.25 m long).
const PULL: f32 = 0.02;

/// A joint the call read ends at most this far apart (m): the stabilizer's
/// joint tolerance is far below it, and the poses written back in f32
/// round at about 1e-7 m; unread, the joint stays about [`PULL`] apart.
const WOKEN_JOINT_TOL: f64 = 1e-4;

/// Steps within which the ragdoll of `joint_scenes` falls asleep under the
/// bridge (it sleeps from about step 60 in the loop of `with_and_without`).
const STEPS_TO_SLEEP: usize = 300;
