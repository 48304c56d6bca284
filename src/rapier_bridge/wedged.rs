//! Bodies held still that wedge an awake one: released when an island
//! cannot be solved with them held.
//!
//! # Why
//!
//! The bridge holds still the bodies Rapier (or the bridge) put to sleep:
//! obstacles for the awake ones, never written (`super::limbo`,
//! `super::sleep`). An awake body can end a step pressed between such
//! bodies and the ground: on the pile of 200 of
//! `examples/with_and_without.rs`, once its 200 bodies were put to sleep
//! and one woke, the linearized problem of that one body against its three
//! held neighbours was infeasible (Lemke's ray, clarabel's certificate),
//! and the call ended unsolved, 0.7 mm deep.
//!
//! # The rule
//!
//! When the call does not resolve and islands are left, every held body
//! whose box, grown by the call's contact margin, overlaps the box of a
//! body of a left island is released (solved as dynamic again, written if
//! moved, which wakes it in Rapier), and the call is solved again from its
//! answer; at most [`RELEASE_ROUNDS`] times, each reaching one contact
//! further. A failure that does not involve held bodies is left as it is.

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};

use crate::broad_phase::body_aabb;
use crate::scene::Scene;
use crate::stabilizer::Report;

/// Rounds of release and solve after a call left islands unsolved.
pub(crate) const RELEASE_ROUNDS: usize = 4;

/// The held bodies (dynamic bodies held still, scene indices) whose box,
/// grown by `margin`, overlaps the box of a body of an island `report`
/// left unsolved; empty when the call resolved.
pub(crate) fn held_near_left_islands(scene: &Scene, report: &Report, margin: f64) -> Vec<usize> {
    if report.status.is_resolved() || report.islands_left.is_empty() {
        return Vec::new();
    }
    let stuck: Vec<Aabb> = report
        .islands_left
        .iter()
        .flat_map(|island| island.bodies.iter())
        .filter_map(|&i| scene.bodies().get(i))
        .map(|body| body_aabb(body).loosened(margin))
        .collect();
    (0..scene.len())
        .filter(|&i| scene.bodies()[i].is_held())
        .filter(|&i| {
            let held = body_aabb(&scene.bodies()[i]);
            stuck.iter().any(|grown| grown.intersects(&held))
        })
        .collect()
}
