//! Rapier scenes with joints, shared by the examples (`with_and_without`)
//! and the bridge's tests: a chain of revolute links hanging from a fixed
//! anchor with a heavy end, a ragdoll-like figure of boxes dropped on the
//! ground, a hinged lever resting on a box. Rapier's defaults (60 Hz,
//! contacts between jointed bodies enabled), z up, gravity -9.81, SI
//! units, density 1000 kg/m^3 unless a mass is given.

#![allow(dead_code)]

use rapier3d::prelude::*;

/// Spacing of a chain's hinges (m): a link's rest length.
pub const LINK_LENGTH: f32 = 0.2;
/// Half extents of a link: a bar shorter than the spacing, so that
/// neighbours do not touch until they fold by about 90 degrees.
pub const LINK_HALF: [f32; 3] = [0.08, 0.02, 0.02];
/// Density of every part without a given mass (kg/m^3).
pub const DENSITY: f32 = 1000.0;
/// Height of a chain's anchor (m).
pub const ANCHOR_HEIGHT: f32 = 12.0;

/// An empty world with gravity along -z and Rapier's default parameters.
pub fn joint_world() -> PhysicsWorld {
    PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..PhysicsWorld::default()
    }
}

/// The fixed ground, top face at z = 0.
pub fn ground(world: &mut PhysicsWorld) -> RigidBodyHandle {
    let fixed = world.insert_body(RigidBodyBuilder::fixed());
    let floor = ColliderBuilder::cuboid(20.0, 20.0, 0.5).translation(Vector::new(0.0, 0.0, -0.5));
    world.insert_collider(floor, Some(fixed));
    fixed
}

/// A chain: its joints in order (anchor first) and its rest length.
pub struct Chain {
    /// The joints, from the anchor to the end box.
    pub joints: Vec<ImpulseJointHandle>,
    /// Sum of the hinge spacings (m).
    pub rest_length: f64,
}

/// `links` bars on revolute joints about y, released horizontally along +x
/// from a fixed anchor (a small block with a collider), the last carrying
/// a box of `end_mass_ratio` times a link's mass on a fixed joint.
pub fn chain_world(links: usize, end_mass_ratio: f32) -> (PhysicsWorld, Chain) {
    let mut world = joint_world();
    let anchor = world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(
        0.0,
        0.0,
        ANCHOR_HEIGHT,
    )));
    world.insert_collider(ColliderBuilder::cuboid(0.005, 0.005, 0.005), Some(anchor));
    let [hx, hy, hz] = LINK_HALF;
    let link_mass = 8.0 * hx * hy * hz * DENSITY;
    let mut joints = Vec::new();
    let mut previous = anchor;
    let mut previous_anchor = Vector::ZERO;
    for i in 0..links {
        let x = LINK_LENGTH * i as f32 + 0.5 * LINK_LENGTH;
        let link = world.insert_body(RigidBodyBuilder::dynamic().translation(Vector::new(
            x,
            0.0,
            ANCHOR_HEIGHT,
        )));
        world.insert_collider(
            ColliderBuilder::cuboid(hx, hy, hz).density(DENSITY),
            Some(link),
        );
        let hinge = RevoluteJointBuilder::new(Vector::Y)
            .local_anchor1(previous_anchor)
            .local_anchor2(Vector::new(-0.5 * LINK_LENGTH, 0.0, 0.0));
        joints.push(world.insert_impulse_joint(previous, link, hinge));
        previous = link;
        previous_anchor = Vector::new(0.5 * LINK_LENGTH, 0.0, 0.0);
    }
    let half = 0.03;
    let end_x = LINK_LENGTH * links as f32 + half + 0.01;
    let end = world.insert_body(RigidBodyBuilder::dynamic().translation(Vector::new(
        end_x,
        0.0,
        ANCHOR_HEIGHT,
    )));
    world.insert_collider(
        ColliderBuilder::cuboid(half, half, half).mass(end_mass_ratio * link_mass),
        Some(end),
    );
    let weld = FixedJointBuilder::new()
        .local_anchor1(previous_anchor)
        .local_anchor2(Vector::new(-half - 0.01, 0.0, 0.0));
    joints.push(world.insert_impulse_joint(previous, end, weld));
    let rest_length = f64::from(LINK_LENGTH) * links as f64;
    (
        world,
        Chain {
            joints,
            rest_length,
        },
    )
}

/// A box body of half extents `half` at `at` (density 1000).
fn part(world: &mut PhysicsWorld, half: [f32; 3], at: Vector) -> RigidBodyHandle {
    let body = world.insert_body(RigidBodyBuilder::dynamic().translation(at));
    world.insert_collider(
        ColliderBuilder::cuboid(half[0], half[1], half[2]).density(DENSITY),
        Some(body),
    );
    body
}

/// A ragdoll-like figure of boxes (torso, head, arms and legs of two parts
/// each) on spherical joints at the shoulders, hips and neck and limited
/// hinges at the elbows and knees, lying 0.6 m above the ground, to be
/// dropped. Parts are 2 cm apart at their joints.
pub fn ragdoll_world() -> PhysicsWorld {
    let mut world = joint_world();
    ground(&mut world);
    let z = 0.6;
    let at = |x: f32, y: f32| Vector::new(x, y, z);
    let torso = part(&mut world, [0.25, 0.12, 0.08], at(0.0, 0.0));
    let head = part(&mut world, [0.1, 0.09, 0.09], at(0.38, 0.0));
    let ball = |world: &mut PhysicsWorld, a, b, anchor_a: Vector, anchor_b: Vector| {
        let joint = SphericalJointBuilder::new()
            .local_anchor1(anchor_a)
            .local_anchor2(anchor_b);
        world.insert_impulse_joint(a, b, joint);
    };
    let hinge = |world: &mut PhysicsWorld, a, b, anchor_a: Vector, anchor_b: Vector| {
        let joint = RevoluteJointBuilder::new(Vector::Y)
            .local_anchor1(anchor_a)
            .local_anchor2(anchor_b)
            .limits([-0.05, 2.3]);
        world.insert_impulse_joint(a, b, joint);
    };
    ball(
        &mut world,
        torso,
        head,
        Vector::new(0.26, 0.0, 0.0),
        Vector::new(-0.12, 0.0, 0.0),
    );
    for side in [-1.0_f32, 1.0] {
        // Arm: upper arm and forearm along -x from the shoulder, beside the torso.
        let upper = part(&mut world, [0.12, 0.04, 0.04], at(0.1, side * 0.19));
        let fore = part(&mut world, [0.11, 0.035, 0.035], at(-0.16, side * 0.19));
        ball(
            &mut world,
            torso,
            upper,
            Vector::new(0.23, side * 0.13, 0.0),
            Vector::new(0.13, side * -0.06, 0.0),
        );
        hinge(
            &mut world,
            upper,
            fore,
            Vector::new(-0.13, 0.0, 0.0),
            Vector::new(0.13, 0.0, 0.0),
        );
        // Leg: thigh and shin along -x from the hip.
        let thigh = part(&mut world, [0.17, 0.055, 0.055], at(-0.45, side * 0.07));
        let shin = part(&mut world, [0.17, 0.045, 0.045], at(-0.81, side * 0.07));
        ball(
            &mut world,
            torso,
            thigh,
            Vector::new(-0.26, side * 0.07, 0.0),
            Vector::new(0.19, 0.0, 0.0),
        );
        hinge(
            &mut world,
            thigh,
            shin,
            Vector::new(-0.18, 0.0, 0.0),
            Vector::new(0.18, 0.0, 0.0),
        );
    }
    world
}

/// A lever: a plank hinged about y at one end to a fixed post, its other
/// end resting on a box on the ground; the plank 20 times the box's mass.
pub fn lever_world() -> PhysicsWorld {
    let mut world = joint_world();
    let ground = ground(&mut world);
    let post_top = 0.5;
    world.insert_collider(
        ColliderBuilder::cuboid(0.05, 0.05, 0.5 * post_top).translation(Vector::new(
            0.0,
            0.0,
            0.5 * post_top,
        )),
        Some(ground),
    );
    let box_half = 0.2;
    part(&mut world, [box_half; 3], Vector::new(1.6, 0.0, box_half));
    // The plank hangs from a hinge 6 cm above the post's top, 5 cm beyond
    // its near end, inclined down towards the box so that its far bottom
    // edge is 1 mm above the box's top face; it settles on the box under
    // gravity. Rotated by `angle` about y, the far bottom edge (plank
    // coordinates (reach, -half_z)) is at height
    // `hinge_z - reach sin(angle) - half_z cos(angle)`.
    let plank_half: [f32; 3] = [0.8, 0.1, 0.02];
    let hinge_offset = plank_half[0] + 0.05;
    let hinge_z = post_top + 0.06;
    let drop = hinge_z - (2.0 * box_half + 0.001);
    let reach = hinge_offset + plank_half[0];
    let radius = reach.hypot(plank_half[2]);
    let angle = (drop / radius).asin() - plank_half[2].atan2(reach);
    let center = Vector::new(
        hinge_offset * angle.cos(),
        0.0,
        hinge_z - hinge_offset * angle.sin(),
    );
    let plank = world.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(center)
            .rotation(Vector::new(0.0, angle, 0.0)),
    );
    world.insert_collider(
        ColliderBuilder::cuboid(plank_half[0], plank_half[1], plank_half[2])
            .mass(20.0 * 8.0 * box_half * box_half * box_half * DENSITY),
        Some(plank),
    );
    let hinge = RevoluteJointBuilder::new(Vector::Y)
        .local_anchor1(Vector::new(0.0, 0.0, hinge_z))
        .local_anchor2(Vector::new(-hinge_offset, 0.0, 0.0));
    world.insert_impulse_joint(ground, plank, hinge);
    world
}

/// The largest distance between a joint's two anchor points, over the
/// world's impulse joints (f64, from the bodies' poses).
pub fn largest_joint_separation(world: &PhysicsWorld) -> f64 {
    world
        .impulse_joints
        .iter()
        .map(|(_, joint)| joint_separation(world, joint))
        .fold(0.0, f64::max)
}

/// Distance between the world anchor points of one joint.
pub fn joint_separation(world: &PhysicsWorld, joint: &ImpulseJoint) -> f64 {
    let point = |body: RigidBodyHandle, frame: &Pose| {
        let p = world.bodies[body].position() * frame.translation;
        [f64::from(p.x), f64::from(p.y), f64::from(p.z)]
    };
    let a = point(joint.body1(), &joint.data.local_frame1);
    let b = point(joint.body2(), &joint.data.local_frame2);
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// A chain's stretch: the sum of its joints' anchor separations over its
/// rest length.
pub fn chain_stretch(world: &PhysicsWorld, chain: &Chain) -> f64 {
    let total: f64 = chain
        .joints
        .iter()
        .filter_map(|&h| world.impulse_joints.get(h))
        .map(|joint| joint_separation(world, joint))
        .sum();
    total / chain.rest_length
}
