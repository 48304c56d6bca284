//! Rapier scenes shared by the examples (`engine_states`,
//! `with_and_without`): worlds at their first step, built with Rapier's
//! defaults (60 Hz), z up, gravity -9.81, SI units, density 1000 kg/m^3
//! unless a mass is given, fixed seeds. Lengths of generated shapes are
//! multiples of 2^-10 m, exact in f32.

#![allow(dead_code)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rapier3d::prelude::*;

/// Quantum of every generated length (m): exact in f32.
pub const LENGTH_QUANTUM: f32 = 1.0 / 1024.0;
/// Density of generated bodies (kg/m^3).
pub const DENSITY: f32 = 1000.0;
/// Rapier's default time step (s).
pub const STEP_SECONDS: f64 = 1.0 / 60.0;

/// An empty world with gravity along -z and Rapier's default parameters.
pub fn world() -> PhysicsWorld {
    PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..PhysicsWorld::default()
    }
}

pub fn quantize(x: f32) -> f32 {
    (x / LENGTH_QUANTUM).round() * LENGTH_QUANTUM
}

/// A random Rapier (f32) rotation: four components uniform in [-1, 1),
/// normalized. Not `dev_support::random::random_rotation` (f64, uniform
/// over rotations): its draws differ, and these scenes' recorded results
/// (benchmarks/results, README) are reproduced from these draws. (This
/// file stays beside the examples: it needs rapier3d, which the
/// dev-support crate cannot depend on without building it in every
/// `cargo test`.)
fn random_rapier_rotation(rng: &mut ChaCha8Rng) -> Rotation {
    let q = Rotation::from_xyzw(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    q.normalize()
}

/// The fixed ground (top face at z = 0) and, if `half_width > 0`, four walls
/// of a square bin: colliders of one fixed body.
pub fn ground_and_bin(world: &mut PhysicsWorld, half_width: f32) {
    let fixed = world.insert_body(RigidBodyBuilder::fixed());
    let floor = ColliderBuilder::cuboid(half_width.max(1.0) + 1.0, half_width.max(1.0) + 1.0, 0.5)
        .translation(Vector::new(0.0, 0.0, -0.5));
    world.insert_collider(floor, Some(fixed));
    if half_width <= 0.0 {
        return;
    }
    let (wall_half, wall_height) = (0.05, 1.0);
    for (x, y, hx, hy) in [
        (
            half_width + wall_half,
            0.0,
            wall_half,
            half_width + 2.0 * wall_half,
        ),
        (
            -half_width - wall_half,
            0.0,
            wall_half,
            half_width + 2.0 * wall_half,
        ),
        (0.0, half_width + wall_half, half_width, wall_half),
        (0.0, -half_width - wall_half, half_width, wall_half),
    ] {
        let wall = ColliderBuilder::cuboid(hx, hy, wall_height).translation(Vector::new(
            x,
            y,
            wall_height,
        ));
        world.insert_collider(wall, Some(fixed));
    }
}

/// A random box (half extents 3-8 cm) or hull (8-12 points at radii 4-8 cm).
pub fn random_collider(rng: &mut ChaCha8Rng, hull: bool) -> ColliderBuilder {
    if !hull {
        let mut h = || quantize(rng.random_range(0.03..0.08));
        return ColliderBuilder::cuboid(h(), h(), h()).density(DENSITY);
    }
    loop {
        let count = rng.random_range(8..=12);
        let radius = rng.random_range(0.04..0.08);
        let points: Vec<Vector> = (0..count)
            .map(|_| {
                let d = Vector::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                )
                .normalize_or(Vector::X);
                let p = d * radius * rng.random_range(0.8..1.0);
                Vector::new(quantize(p.x), quantize(p.y), quantize(p.z))
            })
            .collect();
        if let Some(builder) = ColliderBuilder::convex_hull(&points) {
            return builder.density(DENSITY);
        }
    }
}

/// Where the `i`-th body of a pile is dropped from: a grid of 30 cm
/// spacing over the bin of half width `bin_half_width`, layer over layer.
fn drop_position(i: usize, bin_half_width: f32) -> Vector {
    let spacing = 0.3;
    let per_row = ((2.0 * bin_half_width - 0.1) / spacing).floor() as usize;
    let (col, row, layer) = (
        i % per_row,
        (i / per_row) % per_row,
        i / (per_row * per_row),
    );
    Vector::new(
        -bin_half_width + 0.15 + col as f32 * spacing,
        -bin_half_width + 0.15 + row as f32 * spacing,
        0.2 + layer as f32 * spacing,
    )
}

/// `count` bodies on a grid above a bin of half width `bin_half_width`,
/// alternately boxes and hulls, about to drop.
pub fn pile_world(count: usize, bin_half_width: f32, seed: u64) -> PhysicsWorld {
    pile_world_perturbed(count, bin_half_width, seed, 0.0)
}

/// [`pile_world`] with every drop height raised by `lift` (m): the same
/// bodies, dropped from heights that differ by far less than any length of
/// the scene (a probe of how chaotic the settle is; `lift = 0` is
/// [`pile_world`] bit for bit).
pub fn pile_world_perturbed(
    count: usize,
    bin_half_width: f32,
    seed: u64,
    lift: f32,
) -> PhysicsWorld {
    pile_of(count, bin_half_width, seed, lift, |rng, i| {
        random_collider(rng, i % 2 == 1)
    })
}

/// `count` bodies dropped into a bin, raised by `lift`, each at a random
/// rotation with the collider `collider(rng, i)` (drawn after the rotation).
fn pile_of(
    count: usize,
    bin_half_width: f32,
    seed: u64,
    lift: f32,
    mut collider: impl FnMut(&mut ChaCha8Rng, usize) -> ColliderBuilder,
) -> PhysicsWorld {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut world = world();
    ground_and_bin(&mut world, bin_half_width);
    for i in 0..count {
        let translation = drop_position(i, bin_half_width) + Vector::new(0.0, 0.0, lift);
        let body = RigidBodyBuilder::dynamic().pose(Pose::from_parts(
            translation,
            random_rapier_rotation(&mut rng),
        ));
        world.insert(body, collider(&mut rng, i));
    }
    world
}

/// A pile of `count` round and curved bodies (issue 25) dropped into a
/// bin: balls, capsules, cylinders and rounded cuboids in turn, 3-8 cm.
pub fn mixed_pile_world(count: usize, bin_half_width: f32, seed: u64) -> PhysicsWorld {
    pile_of(count, bin_half_width, seed, 0.0, |rng, i| {
        let mut size = || quantize(rng.random_range(0.03..0.08));
        let collider = match i % 4 {
            0 => ColliderBuilder::ball(size()),
            1 => ColliderBuilder::capsule_y(size(), 0.5 * size()),
            2 => ColliderBuilder::cylinder(size(), size()),
            _ => ColliderBuilder::round_cuboid(size(), size(), size(), 0.2 * size()),
        };
        collider.density(DENSITY)
    })
}

/// A rigid body of two or three box colliders: an L (a bar and a leg at
/// one end, the leg turned about the bar's axis by up to 30 degrees) or a
/// T (a bar and a leg at its middle, and a cross bar); arms 4-8 cm long,
/// 1.5-2.5 cm thick.
pub fn random_compound(rng: &mut ChaCha8Rng) -> Vec<ColliderBuilder> {
    let mut length = || quantize(rng.random_range(0.04..0.08));
    let (bar, leg, cross) = (length(), length(), length());
    let mut thick = || quantize(rng.random_range(0.015..0.025));
    let (t1, t2, t3) = (thick(), thick(), thick());
    let turn = rng.random_range(-0.5..0.5);
    let bar_collider = ColliderBuilder::cuboid(bar, t1, t1).density(DENSITY);
    let leg_collider = |x: f32| {
        ColliderBuilder::cuboid(t2, t2, leg)
            .translation(Vector::new(x, 0.0, leg - t1))
            .rotation(Vector::new(turn, 0.0, 0.0))
            .density(DENSITY)
    };
    if rng.random_bool(0.5) {
        return vec![bar_collider, leg_collider(bar - t2)];
    }
    let cross_collider = ColliderBuilder::cuboid(t3, cross, t3)
        .translation(Vector::new(0.0, 0.0, 2.0 * leg - t1))
        .density(DENSITY);
    vec![bar_collider, leg_collider(0.0), cross_collider]
}

/// `count` compound bodies ([`random_compound`]) on a grid above a bin of
/// half width `bin_half_width`, about to drop.
pub fn compound_pile_world(count: usize, bin_half_width: f32, seed: u64) -> PhysicsWorld {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut world = world();
    ground_and_bin(&mut world, bin_half_width);
    for i in 0..count {
        let translation = drop_position(i, bin_half_width);
        let body = world.insert_body(RigidBodyBuilder::dynamic().pose(Pose::from_parts(
            translation,
            random_rapier_rotation(&mut rng),
        )));
        for collider in random_compound(&mut rng) {
            world.insert_collider(collider, Some(body));
        }
    }
    world
}

/// Four 1 kg boxes of 20 cm (yaws within 5 degrees) in a column, under a
/// box `ratio` times heavier: handles of the bodies, bottom to top.
pub fn heavy_stack_world(ratio: f32, seed: u64) -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut world = world();
    ground_and_bin(&mut world, 0.0);
    let mut handles = Vec::new();
    for level in 0..5 {
        let yaw = rng.random_range(-5.0f32..5.0).to_radians();
        let mass = if level == 4 { ratio } else { 1.0 };
        let body = RigidBodyBuilder::dynamic().pose(Pose::from_parts(
            Vector::new(0.0, 0.0, 0.1 + level as f32 * 0.2005),
            Rotation::from_rotation_z(yaw),
        ));
        let (handle, _) = world.insert(body, ColliderBuilder::cuboid(0.1, 0.1, 0.1).mass(mass));
        handles.push(handle);
    }
    (world, handles)
}

/// Four 1 kg boxes of 20 cm in an aligned column (1 mm apart), under a box
/// `ratio` times heavier: handles of the bodies, bottom to top.
pub fn aligned_heavy_stack_world(ratio: f32) -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut world = world();
    ground_and_bin(&mut world, 0.0);
    let mut handles = Vec::new();
    for level in 0..5 {
        let mass = if level == 4 { ratio } else { 1.0 };
        let body = RigidBodyBuilder::dynamic().translation(Vector::new(
            0.0,
            0.0,
            0.1 + level as f32 * 0.201,
        ));
        let (handle, _) = world.insert(body, ColliderBuilder::cuboid(0.1, 0.1, 0.1).mass(mass));
        handles.push(handle);
    }
    (world, handles)
}

/// 55 boxes of 20 cm in a plane, base of 10: handles, bottom row first.
pub fn pyramid_world() -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut world = world();
    ground_and_bin(&mut world, 0.0);
    let mut handles = Vec::new();
    for row in 0..10 {
        let count = 10 - row;
        for i in 0..count {
            let x = (i as f32 - (count - 1) as f32 / 2.0) * 0.201;
            let z = 0.1 + row as f32 * 0.2005;
            let body = RigidBodyBuilder::dynamic().translation(Vector::new(x, 0.0, z));
            let (handle, _) = world.insert(
                body,
                ColliderBuilder::cuboid(0.1, 0.1, 0.1).density(DENSITY),
            );
            handles.push(handle);
        }
    }
    (world, handles)
}

/// A 2 kg box thrown at 15 m/s, spinning, at a stack of six 8 kg boxes:
/// handles of the stack, bottom to top, then the projectile's.
pub fn thrown_box_world(seed: u64) -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut world = world();
    ground_and_bin(&mut world, 0.0);
    let mut handles = Vec::new();
    for level in 0..6 {
        let yaw = rng.random_range(-3.0f32..3.0).to_radians();
        let body = RigidBodyBuilder::dynamic().pose(Pose::from_parts(
            Vector::new(0.0, 0.0, 0.1 + level as f32 * 0.2005),
            Rotation::from_rotation_z(yaw),
        ));
        let (handle, _) = world.insert(
            body,
            ColliderBuilder::cuboid(0.1, 0.1, 0.1).density(DENSITY),
        );
        handles.push(handle);
    }
    let projectile = RigidBodyBuilder::dynamic()
        .translation(Vector::new(-1.5, 0.0, 0.75))
        .linvel(Vector::new(15.0, 0.0, 0.0))
        .angvel(Vector::new(3.0, 8.0, 5.0));
    let (handle, _) = world.insert(
        projectile,
        ColliderBuilder::cuboid(0.06, 0.06, 0.06).mass(2.0),
    );
    handles.push(handle);
    (world, handles)
}

/// 50 boxes and 30 hulls in a column above the ground, about to fall.
pub fn jumble_world(seed: u64) -> PhysicsWorld {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut world = world();
    ground_and_bin(&mut world, 0.0);
    for i in 0..80 {
        let translation = Vector::new(
            rng.random_range(-0.02..0.02) + (i % 2) as f32 * 0.3,
            rng.random_range(-0.02..0.02) + ((i / 2) % 2) as f32 * 0.3,
            0.3 + (i / 4) as f32 * 0.3,
        );
        let body = RigidBodyBuilder::dynamic().pose(Pose::from_parts(
            translation,
            random_rapier_rotation(&mut rng),
        ));
        world.insert(body, random_collider(&mut rng, i % 8 >= 5));
    }
    world
}
