//! The coupling modes of the Rapier bridge on issue 10's stacks: four light
//! cubes (edge 0.2, mass 1) under a cube `R` times heavier, 300 steps at
//! 60 Hz, with Rapier alone and with a bridge call after every step in
//! each coupling mode.
//!
//! ```text
//! cargo run --release --features rapier --example rapier_coupling -- [RATIO...]
//! ```
//!
//! One line per ratio (default 100 and 1000) and mode: how far the top
//! cube ended from where it started (fraction of the stack height, 1.0),
//! the largest horizontal slide of any cube over the run, the deepest
//! penetration of the world after any step (Rapier alone) or call (as
//! written, f32; measured by parry on the world read back, not by the
//! library's own report), the calls that did not resolve, and the median
//! call time.

use constraint_stabilization::Settings;
use constraint_stabilization::rapier_bridge::{
    BridgeSettings, CouplingMode, RapierBridge, pose_to_f64,
};
use constraint_stabilization::verify::parry_penetration;
use rapier3d::prelude::*;

/// Steps of the run: 5 s at Rapier's default 60 Hz.
const STEPS: usize = 300;

/// Half edge of every cube; the stack is five cubes, height 1.0.
const HALF: f32 = 0.1;

/// The stack: a fixed ground slab (top face `z = 0`), four unit-mass cubes
/// and the heavy one on top, touching, at rest, z up.
fn stack(ratio: f32) -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..PhysicsWorld::default()
    };
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let slab = ColliderBuilder::cuboid(5.0, 5.0, 0.5).translation(Vector::new(0.0, 0.0, -0.5));
    world.insert_collider(slab, Some(ground));
    let cubes = (0..5)
        .map(|i| {
            let mass = if i == 4 { ratio } else { 1.0 };
            let body = RigidBodyBuilder::dynamic().translation(Vector::new(
                0.0,
                0.0,
                HALF * (2 * i + 1) as f32,
            ));
            let collider = ColliderBuilder::cuboid(HALF, HALF, HALF).mass(mass);
            world.insert(body, collider).0
        })
        .collect();
    (world, cubes)
}

/// What one run measured.
#[derive(Default)]
struct Run {
    top_drift: f64,
    largest_slide: f64,
    deepest: f64,
    unresolved: usize,
    call_ms: Vec<f64>,
}

/// The deepest penetration of the world as it is (f32 poses), by parry.
fn world_depth(world: &PhysicsWorld) -> f64 {
    let mut reader = RapierBridge::new(Settings::default()).expect("default settings");
    reader
        .sync(&world.bodies, &world.colliders)
        .expect("the world is read");
    parry_penetration(reader.scene(), 0.0)
        .expect("parry measures the scene")
        .deepest
}

fn run(ratio: f32, coupling: Option<CouplingMode>) -> Run {
    let (mut world, cubes) = stack(ratio);
    let start: Vec<_> = cubes
        .iter()
        .map(|&h| pose_to_f64(world.bodies[h].position()).translation.vector)
        .collect();
    let mut bridge = coupling.map(|coupling| {
        RapierBridge::with_settings(BridgeSettings {
            stabilizer: Settings::default(),
            coupling,
        })
        .expect("valid settings")
    });
    let mut out = Run::default();
    for _ in 0..STEPS {
        world.step();
        if let Some(bridge) = bridge.as_mut() {
            let clock = std::time::Instant::now();
            let report = bridge.stabilize(
                &mut world.bodies,
                &world.colliders,
                &world.integration_parameters,
            );
            out.call_ms.push(clock.elapsed().as_secs_f64() * 1e3);
            let resolved = report
                .ok()
                .and_then(|r| r.stabilizer)
                .is_some_and(|r| r.status.is_resolved());
            out.unresolved += usize::from(!resolved);
        }
        out.deepest = out.deepest.max(world_depth(&world));
        for (&h, p0) in cubes.iter().zip(&start) {
            let p = pose_to_f64(world.bodies[h].position()).translation.vector;
            out.largest_slide = out.largest_slide.max((p - p0).xy().norm());
        }
    }
    let top = cubes[4];
    let end = pose_to_f64(world.bodies[top].position()).translation.vector;
    out.top_drift = (end - start[4]).norm() / f64::from(10.0 * HALF);
    out.call_ms.sort_by(f64::total_cmp);
    out
}

fn main() {
    let ratios: Vec<f32> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let ratios = if ratios.is_empty() {
        vec![100.0, 1000.0]
    } else {
        ratios
    };
    let modes = [
        ("rapier alone", None),
        ("positions only", Some(CouplingMode::PositionsOnly)),
        (
            "respect allowed penetration",
            Some(CouplingMode::RespectAllowedPenetration),
        ),
    ];
    for ratio in ratios {
        for (label, coupling) in modes {
            let r = run(ratio, coupling);
            let median = r.call_ms.get(r.call_ms.len() / 2).copied().unwrap_or(0.0);
            println!(
                "1:{ratio} {label:>28}: top drift {:.4} of height, largest slide {:.2e}, \
                 deepest after any step/call {:.2e}, unresolved calls {}, median call {:.2} ms",
                r.top_drift, r.largest_slide, r.deepest, r.unresolved, median
            );
        }
    }
}
