//! Where the heavy stacks' sideways drift comes from (issue 10): the 1:1000
//! stack run with the bridge's default settings, and per step each box's
//! horizontal displacement split into the part Rapier's step made and the
//! part the bridge's call made (the velocity write-back acts through the
//! next step: its horizontal velocity change times the time step is listed
//! apart).
//!
//! ```text
//! cargo run --release --features rapier,serde --example probes -- slide [--steps N] [--ratio R] [--levels N] [--coupling plain|velocity|closed|allowed|positions] [--velocity-friction none|change|velocity] [--allowed A] [--tolerance T] [--target-margin M] [--verbose FROM TO] [--trace] [--solver-iterations N] [--no-recycling] [--coulomb] [--no-sleep] [--drift-every N] [--calls] [--no-resting] [--no-hold] [--no-collider-friction]
//! ```
//!
//! - `--coupling`: the bridge's `CouplingMode` (its default otherwise);
//!   `plain` is Rapier alone (the bridge only reads the world).
//! - `--levels N`: only the top N boxes of the stack (the heavy one last),
//!   re-stacked on the ground; `--levels 1` is one heavy box on the ground.
//! - `--allowed`, `--tolerance`, `--target-margin`: the stabilizer's
//!   `allowed_penetration`, `tolerance_absolute`, `target_margin_absolute`
//!   (the bridge raises the last two to its round-off rule).
//! - `--verbose FROM TO`: per step of the range, the stacked pairs'
//!   corners before and after, Rapier's impulses at each pair (normal,
//!   friction as summed over the points, which counts a manifold's shared
//!   friction once per point), and each box's motion; `--trace`: one line
//!   per step of the range for the bottom box instead (displacement,
//!   velocity, tilt and angular velocity after Rapier's step and after the
//!   call).
//! - Diagnostics that change Rapier's parameters (which are the user's, so
//!   never a fix): `--solver-iterations N` (`num_solver_iterations`,
//!   default 4; the drift does not fall with 16 or 64), `--no-recycling`
//!   (`contact_recycling` off), `--coulomb` (`FrictionModel::Coulomb`),
//!   `--no-sleep` (the boxes never sleep).
//! - `--velocity-friction` sets the friction of the velocity projection
//!   (`BridgeSettings::velocity_friction`; the bridge's default otherwise).
//!
//! - `--drift-every N`: the largest drift of any box every N steps;
//!   `--calls`: one line per call (resting, bodies held, bodies written,
//!   depth before); `--no-resting`, `--no-hold`, `--no-collider-friction`
//!   turn off `BridgeSettings::resting_calls`, `hold_cycles`,
//!   `collider_friction`.
//!
//! The summary ends with the largest horizontal drift of any box over the
//! run (the figure of `examples/with_and_without.rs`) and the top's height.

use crate::scenes;

use constraint_stabilization::rapier_bridge::{BridgeSettings, CouplingMode, RapierBridge};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::stabilizer::VelocityFriction;
use nalgebra::{Isometry3, Point3};
use rapier3d::prelude::*;

/// Steps of the run (5 s at 60 Hz).
const DEFAULT_STEPS: usize = 300;

/// The user poses of the scene's bodies.
fn poses(scene: &Scene) -> Vec<Isometry3<f64>> {
    scene.bodies().iter().map(|b| b.user_pose()).collect()
}

/// For each stacked pair (lower, upper) of scene indices, the upper box's
/// four lowest corners in the lower body's frame, before and after: their
/// heights above the lower's top face, and the mean tangential slide of
/// those corners over that face (lower's frame). Prints when `print`.
fn contact_motion(
    scene: &Scene,
    before: &[Isometry3<f64>],
    after: &[Isometry3<f64>],
    stack: &[usize],
    print: bool,
) -> Vec<[f64; 2]> {
    let mut slides = Vec::new();
    for w in stack.windows(2) {
        let (lower, upper) = (w[0], w[1]);
        let top = scene.bodies()[lower]
            .polyhedron()
            .expect("a convex body")
            .vertices()
            .iter()
            .map(|v| v.z)
            .fold(f64::NEG_INFINITY, f64::max);
        let mut corners: Vec<(Point3<f64>, Point3<f64>)> = scene.bodies()[upper]
            .polyhedron()
            .expect("a convex body")
            .vertices()
            .iter()
            .map(|v| {
                (
                    before[lower].inverse() * (before[upper] * v),
                    after[lower].inverse() * (after[upper] * v),
                )
            })
            .collect();
        corners.sort_by(|a, b| a.0.z.total_cmp(&b.0.z));
        let mut mean = [0.0; 2];
        for (b, a) in &corners[..4] {
            mean[0] += (a.x - b.x) / 4.0;
            mean[1] += (a.y - b.y) / 4.0;
        }
        slides.push(mean);
        if print {
            let text: Vec<String> = corners[..4]
                .iter()
                .map(|(b, a)| {
                    format!(
                        "h {:+.2e}->{:+.2e} slide {:.2e}",
                        b.z - top,
                        a.z - top,
                        (a.xy() - b.xy()).norm()
                    )
                })
                .collect();
            println!("    pair {lower}-{upper}: {}", text.join(" | "));
        }
    }
    slides
}

fn horizontal(v: Vector) -> [f64; 2] {
    [f64::from(v.x), f64::from(v.y)]
}

fn norm(v: [f64; 2]) -> f64 {
    v[0].hypot(v[1])
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn add(a: &mut [f64; 2], b: [f64; 2]) {
    a[0] += b[0];
    a[1] += b[1];
}

pub fn run(args: Vec<String>) -> Result<(), Box<dyn std::error::Error>> {
    let value = |flag: &str, k: usize| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + k).cloned())
    };
    let steps: usize = value("--steps", 1).map_or(Ok(DEFAULT_STEPS), |s| s.parse())?;
    let ratio: f32 = value("--ratio", 1).map_or(Ok(1000.0), |s| s.parse())?;
    let verbose_from: usize = value("--verbose", 1).map_or(Ok(usize::MAX), |s| s.parse())?;
    let verbose_to: usize = value("--verbose", 2).map_or(Ok(0), |s| s.parse())?;
    // `--trace`: one line per step of the range for the bottom box.
    let trace = args.iter().any(|a| a == "--trace");
    // `--drift-every N`: the largest drift of any box every N steps.
    let drift_every: usize = value("--drift-every", 1).map_or(Ok(0), |s| s.parse())?;
    let velocity_friction = match value("--velocity-friction", 1).as_deref() {
        None => BridgeSettings::default().velocity_friction,
        Some("none") => VelocityFriction::None,
        Some("change") => VelocityFriction::OnChange,
        Some("velocity") => VelocityFriction::OnVelocity,
        Some(other) => return Err(format!("unknown velocity friction {other}").into()),
    };
    // None: Rapier alone (the bridge only reads the world, for the contact
    // measurements).
    let coupling = match value("--coupling", 1).as_deref() {
        None => Some(BridgeSettings::default().coupling),
        Some("plain") => None,
        Some("velocity") => Some(CouplingMode::VelocityConsistency),
        Some("closed") => Some(CouplingMode::ClosedContacts),
        Some("allowed") => Some(CouplingMode::RespectAllowedPenetration),
        Some("positions") => Some(CouplingMode::PositionsOnly),
        Some(other) => return Err(format!("unknown coupling {other}").into()),
    };
    // `--calls`: one line per call (resting, bodies held and written).
    let print_calls = args.iter().any(|a| a == "--calls");
    let no_resting = args.iter().any(|a| a == "--no-resting");
    let no_hold = args.iter().any(|a| a == "--no-hold");
    let (mut world, mut handles) = scenes::aligned_heavy_stack_world(ratio);
    // `--levels N`: only the top N boxes (the heavy one last) stay.
    if let Some(levels) = value("--levels", 1) {
        let levels: usize = levels.parse()?;
        let removed: Vec<RigidBodyHandle> = handles.drain(..handles.len() - levels).collect();
        for h in removed {
            world.remove_body(h);
        }
        for (level, &h) in handles.iter().enumerate() {
            let z = 0.1 + level as f32 * 0.201;
            world.bodies[h].set_translation(Vector::new(0.0, 0.0, z), false);
        }
    }
    if let Some(iterations) = value("--solver-iterations", 1) {
        world.integration_parameters.num_solver_iterations = iterations.parse()?;
    }
    // Diagnostics only (Rapier's parameters are the user's): full contact
    // updates every step, or Rapier's Coulomb friction per point.
    if args.iter().any(|a| a == "--no-recycling") {
        world.integration_parameters.contact_recycling = false;
    }
    if args.iter().any(|a| a == "--no-sleep") {
        for &h in &handles {
            *world.bodies[h].activation_mut() = RigidBodyActivation::cannot_sleep();
        }
    }
    if args.iter().any(|a| a == "--coulomb") {
        world.integration_parameters.friction_model = FrictionModel::Coulomb;
    }
    let mut stabilizer = constraint_stabilization::Settings::default();
    if let Some(t) = value("--tolerance", 1) {
        stabilizer.tolerance_absolute = Some(t.parse()?);
    }
    if let Some(a) = value("--allowed", 1) {
        stabilizer.allowed_penetration = a.parse()?;
    }
    if let Some(t) = value("--target-margin", 1) {
        stabilizer.target_margin_absolute = Some(t.parse()?);
    }
    let mut bridge = RapierBridge::with_settings(BridgeSettings {
        velocity_friction,
        coupling: coupling.unwrap_or_default(),
        resting_calls: !no_resting,
        hold_cycles: !no_hold,
        collider_friction: !args.iter().any(|a| a == "--no-collider-friction"),
        ..BridgeSettings::with_stabilizer(stabilizer)
    })?;
    let colliders = stack_colliders(&world, &handles);
    let mut max_drift: f64 = 0.0;
    let dt = f64::from(world.integration_parameters.dt);
    let n = handles.len();
    let start: Vec<[f64; 2]> = handles
        .iter()
        .map(|&h| horizontal(world.bodies[h].translation()))
        .collect();
    // Signed sums per box: Rapier's steps, the calls' positions, the
    // velocity write-back's horizontal change times dt.
    let mut by_step = vec![[0.0; 2]; n];
    let mut by_call = vec![[0.0; 2]; n];
    let mut by_velocity = vec![[0.0; 2]; n];
    // Sums of magnitudes.
    let (mut abs_step, mut abs_call, mut abs_velocity) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    // Signed sums of the contacts' slides (pairs ground-box 0, box 0-1, ...).
    let mut slide_by_step = vec![[0.0; 2]; n];
    let mut slide_by_call = vec![[0.0; 2]; n];
    // Velocity projections of islands that failed, calls not resolved.
    let (mut velocity_failures, mut unresolved) = (0, 0);
    // Resting calls, calls that held bodies, bodies held (summed).
    let (mut resting_calls, mut held_calls, mut held_bodies) = (0, 0, 0);
    for step in 1..=steps {
        let p0: Vec<[f64; 2]> = handles
            .iter()
            .map(|&h| horizontal(world.bodies[h].translation()))
            .collect();
        world.step();
        let p1: Vec<[f64; 2]> = handles
            .iter()
            .map(|&h| horizontal(world.bodies[h].translation()))
            .collect();
        let v1: Vec<[f64; 2]> = handles
            .iter()
            .map(|&h| horizontal(world.bodies[h].linvel()))
            .collect();
        let tilt1: Vec<Vector> = handles
            .iter()
            .map(|&h| world.bodies[h].rotation().to_scaled_axis())
            .collect();
        let w1: Vec<Vector> = handles.iter().map(|&h| world.bodies[h].angvel()).collect();
        let z1: Vec<f64> = handles
            .iter()
            .map(|&h| f64::from(world.bodies[h].translation().z))
            .collect();
        let corrected = poses(bridge.scene());
        bridge.sync(&world.bodies, &world.colliders)?;
        let scene_before = poses(bridge.scene());
        let verbose = !trace && (verbose_from..=verbose_to).contains(&step);
        let stack = stack_of(&bridge, &handles);
        if verbose {
            println!("  Rapier's step, contacts:");
        }
        if step > 1 {
            for (sum, slide) in slide_by_step.iter_mut().zip(contact_motion(
                bridge.scene(),
                &corrected,
                &scene_before,
                &stack,
                verbose,
            )) {
                add(sum, slide);
            }
        }
        if verbose {
            print_impulses(&world, &colliders);
        }
        let report = match coupling {
            Some(_) => Some(bridge.stabilize(
                &mut world.bodies,
                &mut world.colliders,
                &world.impulse_joints,
                &world.multibody_joints,
                &world.integration_parameters,
            )?),
            None => None,
        };
        if let Some(r) = report.as_ref().filter(|_| print_calls) {
            let depth = r.stabilizer.as_ref().map_or(0.0, |s| s.depth_before);
            println!(
                "call {step}: resting {} held {} written {} depth before {depth:.3e}",
                r.resting, r.bodies_held, r.bodies_written
            );
        }
        if let Some(r) = report.as_ref() {
            resting_calls += usize::from(r.resting);
            held_bodies += r.bodies_held;
            held_calls += usize::from(r.bodies_held > 0);
        }
        velocity_failures += report
            .as_ref()
            .and_then(|r| r.velocities.as_ref())
            .map_or(0, |v| v.islands_failed);
        unresolved += usize::from(
            report
                .as_ref()
                .and_then(|r| r.stabilizer.as_ref())
                .is_some_and(|r| !r.status.is_resolved()),
        );
        let p2: Vec<[f64; 2]> = handles
            .iter()
            .map(|&h| horizontal(world.bodies[h].translation()))
            .collect();
        let v2: Vec<[f64; 2]> = handles
            .iter()
            .map(|&h| horizontal(world.bodies[h].linvel()))
            .collect();
        let z2: Vec<f64> = handles
            .iter()
            .map(|&h| f64::from(world.bodies[h].translation().z))
            .collect();
        if trace && (verbose_from..=verbose_to).contains(&step) {
            let i = 0;
            let tilt2 = world.bodies[handles[i]].rotation().to_scaled_axis();
            let w2 = world.bodies[handles[i]].angvel();
            println!(
                "trace {step}: step dxy {:+.2e} {:+.2e} v {:+.2e} {:+.2e} | tilt after step {:+.2e} {:+.2e} w {:+.2e} {:+.2e} | call dxy {:+.2e} {:+.2e} tilt after call {:+.2e} {:+.2e} w {:+.2e} {:+.2e}",
                p1[i][0] - p0[i][0],
                p1[i][1] - p0[i][1],
                v1[i][0],
                v1[i][1],
                tilt1[i].x,
                tilt1[i].y,
                w1[i].x,
                w1[i].y,
                p2[i][0] - p1[i][0],
                p2[i][1] - p1[i][1],
                tilt2.x,
                tilt2.y,
                w2.x,
                w2.y
            );
        }
        for i in 0..n {
            max_drift = max_drift.max(norm(sub(p2[i], start[i])));
            let (s, c) = (sub(p1[i], p0[i]), sub(p2[i], p1[i]));
            let dv = sub(v2[i], v1[i]);
            let w = [dv[0] * dt, dv[1] * dt];
            add(&mut by_step[i], s);
            add(&mut by_call[i], c);
            add(&mut by_velocity[i], w);
            abs_step[i] += norm(s);
            abs_call[i] += norm(c);
            abs_velocity[i] += norm(w);
        }
        if drift_every > 0 && step % drift_every == 0 {
            let top_motion = (0..n)
                .map(|i| norm(sub(p2[i], start[i])))
                .fold(0.0, f64::max);
            println!(
                "drift at step {step}: {:.3} mm (largest so far {:.3})",
                top_motion * 1e3,
                max_drift * 1e3
            );
        }
        if verbose {
            println!("  the call, contacts:");
        }
        for (sum, slide) in slide_by_call.iter_mut().zip(contact_motion(
            bridge.scene(),
            &scene_before,
            &poses(bridge.scene()),
            &stack,
            verbose,
        )) {
            add(sum, slide);
        }
        if verbose {
            let stabilizer = report.as_ref().and_then(|r| r.stabilizer.as_ref());
            println!(
                "step {step}: passes {:?}, depth {:.3e} -> {:.3e}, tolerance {:.2e}, velocities written {}",
                stabilizer.map(|r| r.passes),
                stabilizer.map_or(0.0, |r| r.depth_before),
                stabilizer.map_or(0.0, |r| r.depth_after),
                stabilizer.map_or(0.0, |r| r.tolerance),
                report.as_ref().map_or(0, |r| r.velocities_written)
            );
            for i in 0..n {
                println!(
                    "  box {i}: step dxy {:+.3e} {:+.3e}  call dxy {:+.3e} {:+.3e} dz {:+.3e}  v after step {:+.3e} {:+.3e}  dv by call {:+.3e} {:+.3e}",
                    p1[i][0] - p0[i][0],
                    p1[i][1] - p0[i][1],
                    p2[i][0] - p1[i][0],
                    p2[i][1] - p1[i][1],
                    z2[i] - z1[i],
                    v1[i][0],
                    v1[i][1],
                    v2[i][0] - v1[i][0],
                    v2[i][1] - v1[i][1],
                );
            }
        }
    }
    println!(
        "ratio 1:{ratio}, {steps} steps, dt {dt:.5} s, velocity friction {velocity_friction:?}; horizontal motion per box (mm):"
    );
    println!(
        "box | net drift | by Rapier's steps (signed sum, |.| sum) | by the calls' positions (signed, |.|) | velocity write-back x dt (signed, |.|)"
    );
    for i in 0..n {
        let end = horizontal(world.bodies[handles[i]].translation());
        println!(
            "{i} | {:.3} | {:.3} {:.3} | {:.3} {:.3} | {:.3} {:.3}",
            norm(sub(end, start[i])) * 1e3,
            norm(by_step[i]) * 1e3,
            abs_step[i] * 1e3,
            norm(by_call[i]) * 1e3,
            abs_call[i] * 1e3,
            norm(by_velocity[i]) * 1e3,
            abs_velocity[i] * 1e3,
        );
    }
    let top = world.bodies[handles[n - 1]].translation().z;
    let sleeping = handles
        .iter()
        .filter(|&&h| world.bodies[h].is_sleeping())
        .count();
    println!("bodies asleep at the end: {sleeping} of {n}");
    println!(
        "resting calls {resting_calls}; calls that held bodies {held_calls}, bodies held {held_bodies}"
    );
    println!(
        "top box at z {top:.4} m; largest drift of any box over the run {:.3} mm; calls not resolved {unresolved}, velocity islands failed {velocity_failures}",
        max_drift * 1e3
    );
    println!(
        "pair (lower-upper) | contact slide by Rapier's steps (signed sum, mm) | by the calls (mm)"
    );
    for i in 0..n {
        println!(
            "{i} | {:.3} | {:.3}",
            norm(slide_by_step[i]) * 1e3,
            norm(slide_by_call[i]) * 1e3
        );
    }
    Ok(())
}

/// The ground's collider and each box's, bottom to top.
fn stack_colliders(world: &PhysicsWorld, handles: &[RigidBodyHandle]) -> Vec<ColliderHandle> {
    let ground = world
        .colliders
        .iter()
        .find(|(_, c)| c.parent().is_some_and(|p| world.bodies[p].is_fixed()))
        .map(|(h, _)| h)
        .expect("the scene has a ground");
    let mut colliders = vec![ground];
    colliders.extend(handles.iter().map(|&h| world.bodies[h].colliders()[0]));
    colliders
}

/// Rapier's impulses of the step just taken at each stacked pair (lower,
/// upper): the normal impulse summed over the solver's contact points, the
/// friction impulse (the world-space warm-start vectors summed), its ratio
/// to `mu N`, and the pair's solver contacts (count, gap range).
fn print_impulses(world: &PhysicsWorld, colliders: &[ColliderHandle]) {
    for (k, w) in colliders.windows(2).enumerate() {
        let Some(pair) = world.narrow_phase.contact_pair(w[0], w[1]) else {
            println!("    impulses pair {k}: no contact pair");
            continue;
        };
        let (mut normal, mut tangent) = (0.0f32, Vector::ZERO);
        let mut points = 0;
        let mut friction = 0.0;
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for m in pair.solver_manifolds() {
            friction = m.data.friction;
            for p in &m.points {
                normal += p.data.impulse;
                tangent += p.data.warmstart_tangent_world;
                points += 1;
            }
            for c in &m.data.solver_contacts {
                lo = lo.min(c.dist);
                hi = hi.max(c.dist);
            }
        }
        println!(
            "    impulses pair {k}: N {normal:.4e}  T ({:+.3e} {:+.3e} {:+.3e}) |T|/(mu N) {:.3}  points {points} dist {lo:+.2e}..{hi:+.2e}",
            tangent.x,
            tangent.y,
            tangent.z,
            tangent.length() / (friction * normal).max(f32::MIN_POSITIVE)
        );
    }
}

/// Scene indices of the ground and the boxes, bottom to top.
fn stack_of(bridge: &RapierBridge, handles: &[RigidBodyHandle]) -> Vec<usize> {
    let mut stack = vec![0];
    stack.extend(
        handles
            .iter()
            .filter_map(|&h| bridge.body_map().scene_index_of_body(h)),
    );
    stack
}
