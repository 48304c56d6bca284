//! Why the pile of 200 settles later under the bridge than under Rapier
//! alone, and why a box slides late (issue 21 is blocked on it): the pile
//! run with a bridge call after every step (or Rapier alone), and per step
//! which bodies moved by how much in Rapier's step and in the call, what
//! the call did (resting, held, written, velocities written, put to
//! sleep), and which bodies Rapier keeps awake and why.
//!
//! ```text
//! cargo run --release --features rapier,serde --example probes -- settle [--plain] [--seed S] [--perturb E] [--steps N] [--from S] [--to T] [--every K] [--ip-min-rows N] [--das-max-dofs N] [--das] [--clarabel-gap G] [--target-margin REL] [--friction-rows all|implied|generated] [--velocity-friction none|change|velocity] [--zero-held-velocities] [--trace BODY FROM TO]
//! ```
//!
//! Per printed step: bodies asleep; bodies whose own motion in Rapier's
//! step fails Rapier's sleep test (`step_fail`); bodies whose net motion
//! over the step and the call fails it (`net_fail`, with the worst three
//! as `body:metres`); bodies whose Rapier sleep timer restarted in this
//! step though their own motion in it passed the test (`woken`: a strong
//! wake from a written neighbour); the call's report. The summary: the
//! first step from which every body sleeps, the last step at which any
//! body's net motion failed the test (and the bodies that failed last),
//! and the largest horizontal drift from step 150 (the measure of
//! `examples/with_and_without.rs`) with the body that made it and the steps
//! in which it moved by more than 0.1 mm. `--ip-min-rows`, `--das-max-dofs`,
//! `--das` (the dual active-set method by the stabilizer's own rule, off
//! in the bridge's default) and `--clarabel-gap` change the solver's
//! answers within the tolerance (as
//! `WITH_AND_WITHOUT_IP_MIN_ROWS` and `WITH_AND_WITHOUT_CLARABEL_GAP`);
//! `--target-margin REL` sets the stabilizer's `target_margin_relative`,
//! `--friction-rows NAME` its `friction_rows` (the bridge's default `all`);
//! `--zero-held-velocities` sets `BridgeSettings::zero_held_velocities`;
//! `--seed` and `--perturb` build another pile (`pile_world_perturbed`);
//! `--trace BODY FROM TO` prints one body's motion and velocities after
//! Rapier's step and after the call at each step of the range.

use crate::rest_probe::{dynamic_bodies, flag_value, point_motion};
use crate::scenes;

use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge};
use constraint_stabilization::stabilizer::VelocityFriction;
use rapier3d::prelude::*;

/// The step from which `with_and_without` measures the pile's drift.
const DRIFT_FROM: usize = 150;
/// A body that moved more than this in a step is listed as moving in the
/// drifting body's story (m).
const STORY_MOTION: f64 = 1e-4;

/// The bridge of the probe: the default, with the solver options.
fn bridge(args: &[String]) -> Result<RapierBridge, Box<dyn std::error::Error>> {
    let mut settings = BridgeSettings::default();
    if let Some(rows) = flag_value(args, "--ip-min-rows") {
        settings.stabilizer.solver.auto_interior_point_min_rows = rows.parse()?;
    }
    if let Some(dofs) = flag_value(args, "--das-max-dofs") {
        settings.stabilizer.solver.auto_dual_active_set_max_dofs = dofs.parse()?;
    }
    if args.iter().any(|a| a == "--das") {
        // The stabilizer's own rule for the dual active-set method.
        let own = constraint_stabilization::Settings::default().solver;
        settings.stabilizer.solver.auto_dual_active_set_max_dofs =
            own.auto_dual_active_set_max_dofs;
        settings
            .stabilizer
            .solver
            .auto_dual_active_set_violated_max_dofs = own.auto_dual_active_set_violated_max_dofs;
    }
    if let Some(gap) = flag_value(args, "--clarabel-gap") {
        let gap: f64 = gap.parse()?;
        settings.stabilizer.solver.clarabel.tol_gap = gap;
        settings.stabilizer.solver.clarabel.tol_feas = gap;
    }
    if let Some(rel) = flag_value(args, "--target-margin") {
        settings.stabilizer.target_margin_relative = rel.parse()?;
    }
    if let Some(name) = flag_value(args, "--friction-rows") {
        settings.stabilizer.friction_rows =
            constraint_stabilization::FrictionRows::from_name(&name)
                .ok_or_else(|| format!("unknown friction rows {name}"))?;
    }
    settings.zero_held_velocities = args.iter().any(|a| a == "--zero-held-velocities");
    match flag_value(args, "--velocity-friction").as_deref() {
        None => {}
        Some("none") => settings.velocity_friction = VelocityFriction::None,
        Some("change") => settings.velocity_friction = VelocityFriction::OnChange,
        Some("velocity") => settings.velocity_friction = VelocityFriction::OnVelocity,
        Some(other) => return Err(format!("unknown velocity friction {other}").into()),
    }
    Ok(RapierBridge::with_settings(settings)?)
}

pub fn run(args: Vec<String>) -> Result<(), Box<dyn std::error::Error>> {
    let _ = env_logger::try_init();
    let value = |flag: &str| flag_value(&args, flag);
    let steps: usize = value("--steps").map_or(Ok(240), |s| s.parse())?;
    let from: usize = value("--from").map_or(Ok(100), |s| s.parse())?;
    let to: usize = value("--to").map_or(Ok(steps), |s| s.parse())?;
    let every: usize = value("--every").map_or(Ok(5), |s| s.parse())?;
    let seed: u64 = value("--seed").map_or(Ok(1), |s| s.parse())?;
    let perturb: f32 = value("--perturb").map_or(Ok(0.0), |s| s.parse())?;
    let plain = args.iter().any(|a| a == "--plain");
    let trace: Option<(usize, usize, usize)> = match args.iter().position(|a| a == "--trace") {
        Some(k) if k + 3 < args.len() => Some((
            args[k + 1].parse()?,
            args[k + 2].parse()?,
            args[k + 3].parse()?,
        )),
        _ => None,
    };
    let mut world = scenes::pile_world_perturbed(200, 1.0, seed, perturb);
    let mut bridge = (!plain).then(|| bridge(&args)).transpose()?;
    let (handles, reach) = dynamic_bodies(&world);
    let n = handles.len();
    let dt = world.integration_parameters.dt;
    let threshold = f64::from(2.0 * 0.05 * world.integration_parameters.length_unit * dt);
    let mut last_fail = vec![0usize; n];
    let mut all_asleep_from: Option<usize> = None;
    let mut start: Vec<Vector> = Vec::new();
    let mut moves: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    let mut drift = vec![0.0f64; n];
    for step in 1..=steps {
        let pose = |world: &PhysicsWorld| -> Vec<Pose> {
            handles
                .iter()
                .map(|&h| *world.bodies[h].position())
                .collect()
        };
        let p0 = pose(&world);
        world.step();
        let p1 = pose(&world);
        let timers_after_step: Vec<f32> = handles
            .iter()
            .map(|&h| world.bodies[h].activation().time_since_can_sleep)
            .collect();
        let velocities_after_step: Vec<(Vector, Vector)> = handles
            .iter()
            .map(|&h| (world.bodies[h].linvel(), world.bodies[h].angvel()))
            .collect();
        let report = match bridge.as_mut() {
            Some(b) => Some(b.stabilize_world(&mut world)?),
            None => None,
        };
        let p2 = pose(&world);
        let mut step_fail = 0;
        let mut woken = 0;
        let mut net_fails: Vec<(usize, f64)> = Vec::new();
        for i in 0..n {
            let by_step = point_motion(&p0[i], &p1[i], reach[i]);
            let net = point_motion(&p0[i], &p2[i], reach[i]);
            if by_step >= threshold {
                step_fail += 1;
            } else if timers_after_step[i] < 1.5 * dt && !world.bodies[handles[i]].is_sleeping() {
                woken += 1;
            }
            if net >= threshold {
                net_fails.push((i, net));
                last_fail[i] = step;
            }
            if step > DRIFT_FROM {
                let moved = f64::from((p2[i].translation - p0[i].translation).length());
                if moved > STORY_MOTION {
                    moves[i].push((step, moved));
                }
                let d = p2[i].translation - start[i];
                drift[i] = drift[i].max(f64::from(d.x.hypot(d.y)));
            }
        }
        if let Some((body, first, last)) = trace
            && (first..=last).contains(&step)
        {
            let b = &world.bodies[handles[body]];
            let (v1, w1) = velocities_after_step[body];
            println!(
                "trace {body} step {step}: by step {:.2e} by call {:.2e} net {:.2e} | after step v {:.2e} {:.2e} {:.2e} w {:.2e} {:.2e} {:.2e} | after call v {:.2e} {:.2e} {:.2e} w {:.2e} {:.2e} {:.2e} | Rapier timer {:.3} sleeping {}",
                point_motion(&p0[body], &p1[body], reach[body]),
                point_motion(&p1[body], &p2[body], reach[body]),
                point_motion(&p0[body], &p2[body], reach[body]),
                v1.x,
                v1.y,
                v1.z,
                w1.x,
                w1.y,
                w1.z,
                b.linvel().x,
                b.linvel().y,
                b.linvel().z,
                b.angvel().x,
                b.angvel().y,
                b.angvel().z,
                b.activation().time_since_can_sleep,
                b.is_sleeping(),
            );
        }
        if step == DRIFT_FROM {
            start = p2.iter().map(|p| p.translation).collect();
        }
        let asleep = handles
            .iter()
            .filter(|&&h| world.bodies[h].is_sleeping())
            .count();
        match (asleep == n, all_asleep_from) {
            (true, None) => all_asleep_from = Some(step),
            (false, Some(_)) => all_asleep_from = None,
            _ => {}
        }
        if step < from || step > to || !(step - from).is_multiple_of(every) {
            continue;
        }
        net_fails.sort_by(|a, b| b.1.total_cmp(&a.1));
        let worst: Vec<String> = net_fails
            .iter()
            .take(3)
            .map(|(i, m)| format!("{i}:{m:.1e}"))
            .collect();
        let call = report.map_or_else(String::new, |r| {
            let (passes, depth, island) = r.stabilizer.as_ref().map_or((0, 0.0, 0), |s| {
                let island = s
                    .pass_reports
                    .iter()
                    .flat_map(|p| &p.solved)
                    .map(|i| i.bodies.len())
                    .max()
                    .unwrap_or(0);
                (s.pass_reports.len(), s.depth_before, island)
            });
            format!(
                " | call: resting {} woken falling {} written {} held {} v-written {} zeroed {} slept {} passes {passes} depth {depth:.1e} largest island {island}",
                r.resting,
                r.bodies_woken_falling,
                r.bodies_written,
                r.bodies_held,
                r.velocities_written,
                r.velocities_zeroed,
                r.bodies_put_to_sleep,
            )
        });
        println!(
            "step {step}: asleep {asleep} step_fail {step_fail} net_fail {} [{}] woken {woken}{call}",
            net_fails.len(),
            worst.join(" ")
        );
    }
    let last = last_fail.iter().copied().max().unwrap_or(0);
    let last_bodies: Vec<usize> = (0..n).filter(|&i| last_fail[i] + 10 >= last).collect();
    let worst = (0..n)
        .max_by(|&a, &b| drift[a].total_cmp(&drift[b]))
        .unwrap_or(0);
    let story: Vec<String> = moves[worst]
        .iter()
        .take(12)
        .map(|(s, m)| format!("{s}:{m:.1e}"))
        .collect();
    println!(
        "summary: all asleep from {:?}; last net failure at step {last} (bodies failing within 10 steps of it: {last_bodies:?}); drift from step {DRIFT_FROM} {:.2} mm by body {worst}, its moves {}",
        all_asleep_from,
        drift[worst] * 1e3,
        story.join(" ")
    );
    Ok(())
}
