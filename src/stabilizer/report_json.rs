//! The stabilization [`Report`] as JSON (the `report` object of an output
//! scene file, docs/design.md section 6). Bodies are named by index and name.

use serde_json::{Value, json};

use crate::joints::JointErrors;
use crate::scene::Scene;
use crate::stabilizer::{IslandReport, JointReport, PairPenetration, PassReport, Report};

/// The report as a JSON object.
pub fn report_to_json(report: &Report, scene: &Scene) -> Value {
    json!({
        "status": report.status.name(),
        "passes": report.passes,
        "scale": report.scale,
        "tolerance": report.tolerance,
        "penetration_before": report.depth_before,
        "penetration_after": report.depth_after,
        "penetrations_before": report.penetrations_before.iter()
            .map(|p| penetration_to_json(p, scene)).collect::<Vec<_>>(),
        "penetrations_after": report.penetrations_after.iter()
            .map(|p| penetration_to_json(p, scene)).collect::<Vec<_>>(),
        "joint_error_before": report.joint_error_before,
        "joint_error_after": report.joint_error_after,
        "joints": report.joints.iter()
            .map(|j| joint_to_json(j, scene)).collect::<Vec<_>>(),
        "displacement": report.displacement,
        "bodies_moved": report.bodies_moved,
        "islands_solved": report.islands_solved(),
        "line_search_trials": report.line_search_trials(),
        "islands_left": report.islands_left.iter()
            .map(|left| json!({
                "bodies": body_names(&left.bodies, scene),
                "reason": left.outcome.reason(),
            }))
            .collect::<Vec<_>>(),
        "restored_input": report.restored_input,
        "times_s": {
            "broad_phase": report.times.broad_phase,
            "narrow_phase": report.times.narrow_phase,
            "solve": report.times.solve,
            "line_search": report.times.line_search,
            "total": report.times.total,
        },
        "pass_reports": report.pass_reports.iter().map(pass_to_json).collect::<Vec<_>>(),
    })
}

fn penetration_to_json(penetration: &PairPenetration, scene: &Scene) -> Value {
    json!({
        "bodies": body_names(&[penetration.body_a, penetration.body_b], scene),
        "features": penetration.features.kind(),
        "depth": penetration.depth,
    })
}

fn pass_to_json(pass: &PassReport) -> Value {
    json!({
        "candidate_pairs": pass.candidate_pairs,
        "active_pairs": pass.active_pairs,
        "penetrating_pairs": pass.penetrating_pairs,
        "islands": pass.islands,
        "deepest": pass.deepest,
        "joint_error": pass.joint_error,
        "solved": pass.solved.iter().map(island_to_json).collect::<Vec<_>>(),
    })
}

fn island_to_json(island: &IslandReport) -> Value {
    json!({
        "bodies": island.bodies,
        "joints": island.joints,
        "constraints": island.constraints,
        "solver": island.solver.map(|s| format!("{s:?}")),
        "fallbacks": island.fallbacks.iter().map(|f| format!("{f:?}")).collect::<Vec<_>>(),
        "solver_iterations": island.solver_iterations,
        "factorizations": island.factorizations,
        "warm_started": island.warm_started,
        "cross_check": island.cross_check.as_ref().map(|c| format!("{c:?}")),
        "outcome": island.outcome.reason(),
        "trust_scale": island.trust_scale,
        "alpha": island.alpha,
        "line_search_trials": island.line_search_trials,
        "depth_before": island.depth_before,
        "depth_after": island.depth_after,
        "joint_error_before": island.joint_error_before,
        "joint_error_after": island.joint_error_after,
        "displacement": island.displacement,
    })
}

fn joint_to_json(joint: &JointReport, scene: &Scene) -> Value {
    let errors = |e: &JointErrors| {
        json!({
            "linear": e.linear,
            "angular_rad": e.angular,
            "travel_limit": e.travel_limit,
            "angle_limit_rad": e.angle_limit,
        })
    };
    json!({
        "index": joint.index,
        "name": joint.name,
        "type": joint.kind,
        "bodies": body_names(&[joint.body_a, joint.body_b], scene),
        "before": errors(&joint.before),
        "after": errors(&joint.after),
    })
}

fn body_names(bodies: &[usize], scene: &Scene) -> Vec<Value> {
    bodies
        .iter()
        .map(|&i| json!({"index": i, "name": scene.bodies().get(i).map(|b| b.name())}))
        .collect()
}
