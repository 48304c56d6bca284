//! Why the thrown box's stack drifts more under the bridge than under
//! Rapier alone (issue 22): `thrown_box` of `examples/with_and_without.rs`
//! (a 2 kg box at 15 m/s into a stack of six 8 kg boxes) run under several
//! bridge settings; for each, the largest horizontal drift of a stack box
//! over the run. With `--trace VARIANT FROM TO`, per step of the range and
//! per stack box: its horizontal position (mm from its start) and its
//! velocity along x after Rapier's step and after the call.
//!
//! ```text
//! cargo run --release --features rapier,serde --example probes -- thrown [--steps N] [--trace VARIANT FROM TO]
//! ```

use crate::scenes;

use constraint_stabilization::rapier_bridge::{BridgeSettings, CouplingMode, RapierBridge};
use constraint_stabilization::stabilizer::VelocityFriction;
use rapier3d::prelude::*;

/// The word after `flag` on the command line.
fn flag_values(args: &[String], flag: &str, n: usize) -> Option<Vec<String>> {
    let at = args.iter().position(|a| a == flag)?;
    args.get(at + 1..at + 1 + n).map(|s| s.to_vec())
}

/// The variants: a name and the bridge settings (`None`: Rapier alone).
fn variants() -> Vec<(&'static str, Option<BridgeSettings>)> {
    let d = BridgeSettings::default;
    vec![
        ("plain", None),
        ("default", Some(d())),
        (
            "positions",
            Some(BridgeSettings {
                coupling: CouplingMode::PositionsOnly,
                ..d()
            }),
        ),
        (
            "allowed",
            Some(BridgeSettings {
                coupling: CouplingMode::RespectAllowedPenetration,
                ..d()
            }),
        ),
        (
            "velocity",
            Some(BridgeSettings {
                coupling: CouplingMode::VelocityConsistency,
                ..d()
            }),
        ),
        (
            "closed+onvelocity",
            Some(BridgeSettings {
                velocity_friction: VelocityFriction::OnVelocity,
                ..d()
            }),
        ),
        (
            "closed+onchange",
            Some(BridgeSettings {
                velocity_friction: VelocityFriction::OnChange,
                ..d()
            }),
        ),
        (
            "closed-no-collider-friction",
            Some(BridgeSettings {
                collider_friction: false,
                ..d()
            }),
        ),
        (
            "no-hold-struck",
            Some(BridgeSettings {
                hold_struck_bodies: false,
                ..d()
            }),
        ),
        (
            "hold-struck-no-cycles",
            Some(BridgeSettings {
                hold_struck_bodies: true,
                hold_cycles: false,
                ..d()
            }),
        ),
        (
            "hold-struck-frictionless",
            Some(BridgeSettings {
                hold_struck_bodies: true,
                collider_friction: false,
                ..d()
            }),
        ),
        (
            "closed-no-hold",
            Some(BridgeSettings {
                hold_cycles: false,
                ..d()
            }),
        ),
    ]
}

pub fn run(args: Vec<String>) -> Result<(), Box<dyn std::error::Error>> {
    let steps: usize = flag_values(&args, "--steps", 1).map_or(Ok(300), |s| s[0].parse())?;
    let trace = flag_values(&args, "--trace", 3);
    for (name, settings) in variants() {
        let range = match &trace {
            Some(t) if t[0] == name => Some((t[1].parse::<usize>()?, t[2].parse::<usize>()?)),
            Some(_) => continue,
            None => None,
        };
        let (mut world, mut handles) = scenes::thrown_box_world(6);
        let projectile = handles.pop();
        let mut bridge = match settings {
            Some(s) => Some(RapierBridge::with_settings(s)?),
            None => None,
        };
        let start: Vec<Vector> = handles
            .iter()
            .map(|&h| world.bodies[h].translation())
            .collect();
        let mut drift: f64 = 0.0;
        let mut drift_at = Vec::new();
        for step in 1..=steps {
            world.step();
            let after_step: Vec<(Vector, Vector)> = handles
                .iter()
                .map(|&h| (world.bodies[h].translation(), world.bodies[h].linvel()))
                .collect();
            let p_after_step =
                projectile.map(|h| (world.bodies[h].translation(), world.bodies[h].linvel()));
            let mut depth = 0.0;
            if let Some(bridge) = bridge.as_mut() {
                let report = bridge.stabilize_world(&mut world)?;
                depth = report.stabilizer.as_ref().map_or(0.0, |r| r.depth_before);
                if let Some((from, to)) = range
                    && (from..=to).contains(&step)
                    && let Some(r) = report.stabilizer.as_ref()
                {
                    println!(
                        "  call: status {:?} passes {} depth after {:.2e} tolerance {:.2e} moved {} pairs before {:?}",
                        r.status,
                        r.passes,
                        r.depth_after,
                        r.tolerance,
                        r.bodies_moved,
                        r.penetrations_before
                            .iter()
                            .map(|p| format!("{p:?}"))
                            .collect::<Vec<_>>()
                    );
                }
            }
            for (h, s) in handles.iter().zip(&start) {
                let p = world.bodies[*h].translation();
                drift = drift.max(f64::from((p.x - s.x).hypot(p.y - s.y)));
            }
            if step % 5 == 0 && step <= 30 {
                drift_at.push(format!("{step}:{:.1}", drift * 1e3));
            }
            if let Some((from, to)) = range
                && (from..=to).contains(&step)
            {
                println!("step {step}: call depth before {depth:.2e}");
                if let (Some(h), Some((p, v))) = (projectile, p_after_step) {
                    let (p2, v2) = (world.bodies[h].translation(), world.bodies[h].linvel());
                    println!(
                        "  projectile: pos ({:.4} {:.4} {:.4}) -> ({:.4} {:.4} {:.4}) v ({:+.3} {:+.3} {:+.3}) -> ({:+.3} {:+.3} {:+.3})",
                        p.x, p.y, p.z, p2.x, p2.y, p2.z, v.x, v.y, v.z, v2.x, v2.y, v2.z
                    );
                }
                for (i, (&h, s)) in handles.iter().zip(&start).enumerate() {
                    let (p1, v1) = after_step[i];
                    let (p2, v2) = (world.bodies[h].translation(), world.bodies[h].linvel());
                    println!(
                        "  box {i}: step x {:+7.2} y {:+7.2} mm vx {:+.4} vy {:+.4} | call x {:+7.2} y {:+7.2} mm z {:.4} vx {:+.4} vy {:+.4} vz {:+.4}",
                        (p1.x - s.x) * 1e3,
                        (p1.y - s.y) * 1e3,
                        v1.x,
                        v1.y,
                        (p2.x - s.x) * 1e3,
                        (p2.y - s.y) * 1e3,
                        p2.z,
                        v2.x,
                        v2.y,
                        v2.z,
                    );
                }
            }
        }
        println!(
            "{name}: max horizontal drift {:.2} mm ({})",
            drift * 1e3,
            drift_at.join(" ")
        );
    }
    Ok(())
}
