//! A heavy stack at rest under the bridge's default coupling: four 1 kg
//! boxes of 20 cm under a 1,000 kg one (Rapier alone crushes it) stand for
//! 300 steps at 60 Hz, no box drifting sideways by 1 mm, the exact depth
//! of the world after every call within the call's stated tolerance plus
//! the f32 write-back's bound. Before held cycles
//! (`BridgeSettings::hold_cycles`) the stack drifted 7.4 mm.

use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge};
use rapier3d::prelude::*;

use super::{f32_world_depth, stated_tolerance};

/// Steps of the run: 5 s at Rapier's 60 Hz.
const STEPS: usize = 300;

/// Issue 22's bound on the largest horizontal drift of any box (m).
const DRIFT_BOUND: f64 = 1e-3;

/// Mass of the top box over a light box's.
const RATIO: f32 = 1000.0;

/// The stack of `examples/common/rapier_scenes.rs` (`aligned_heavy_stack_world`):
/// a ground slab, five 20 cm boxes 1 mm apart, the top one `RATIO` kg.
fn heavy_stack() -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..PhysicsWorld::default()
    };
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let floor = ColliderBuilder::cuboid(2.0, 2.0, 0.5).translation(Vector::new(0.0, 0.0, -0.5));
    world.insert_collider(floor, Some(ground));
    let handles = (0..5)
        .map(|level| {
            let mass = if level == 4 { RATIO } else { 1.0 };
            let z = 0.1 + level as f32 * 0.201;
            let body = RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.0, z));
            world
                .insert(body, ColliderBuilder::cuboid(0.1, 0.1, 0.1).mass(mass))
                .0
        })
        .collect();
    (world, handles)
}

fn horizontal(world: &PhysicsWorld, body: RigidBodyHandle) -> [f64; 2] {
    let t = world.bodies[body].translation();
    [f64::from(t.x), f64::from(t.y)]
}

#[test]
fn the_1_to_1000_stack_drifts_under_1_mm_for_300_steps() {
    let (mut world, handles) = heavy_stack();
    let start: Vec<[f64; 2]> = handles.iter().map(|&h| horizontal(&world, h)).collect();
    let mut bridge =
        RapierBridge::with_settings(BridgeSettings::default()).expect("default settings are valid");
    let mut drift: f64 = 0.0;
    for step in 1..=STEPS {
        world.step();
        let report = bridge
            .stabilize_world(&mut world)
            .expect("the call succeeds");
        let depth = f32_world_depth(&world);
        let bound = stated_tolerance(&report) + 2.0 * report.round_off_bound;
        assert!(
            depth <= bound,
            "step {step}: depth {depth:e} beyond the call's {bound:e}"
        );
        for (&h, s) in handles.iter().zip(&start) {
            let p = horizontal(&world, h);
            drift = drift.max((p[0] - s[0]).hypot(p[1] - s[1]));
        }
    }
    let top = f64::from(world.bodies[handles[4]].translation().z);
    assert!(
        (top - 0.9).abs() < DRIFT_BOUND,
        "the stack stands: top at {top} m"
    );
    assert!(
        drift < DRIFT_BOUND,
        "largest horizontal drift {:.3} mm",
        drift * 1e3
    );
}
