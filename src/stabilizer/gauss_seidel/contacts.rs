//! The contact points of one sweep: every pair of every island with a
//! penetration deeper than the tolerance, in ascending pair order, each
//! pair's manifold points in the manifold's order, stored in body frames.
//!
//! The pairs and their manifolds are those the projection uses (the same
//! detection, islands and [`crate::contact::contact_points`]), so both
//! methods measure the same geometry. Near pairs of such an island (within
//! the contact margin, not penetrating) are visited too: a push can bring
//! them into contact within the sweep, and their re-measured separation
//! then asks for a push of its own. Islands with no penetration beyond the
//! tolerance are left out, so their bodies keep their poses bit for bit.

use nalgebra::Isometry3;

use super::point::StoredPoint;
use crate::Error;
use crate::contact::islands;
use crate::contact::{Detection, SceneGeometry, contact_points};
use crate::settings::{ResolvedLengths, Settings};

/// The contacts of one sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepContacts {
    /// The points, in visiting order.
    pub points: Vec<StoredPoint>,
    /// Islands formed from the detection's active pairs (all of them, as
    /// [`crate::stabilizer::PassReport::islands`] counts).
    pub islands: usize,
}

/// The stored contact points of `detection` (made at `geometry`, the
/// bodies at `body_poses`), for the bodies flagged in `fixed`. A point of
/// two compound bodies' parts is stored in the bodies' frames.
pub fn sweep_points(
    geometry: SceneGeometry,
    body_poses: &[Isometry3<f64>],
    fixed: &[bool],
    detection: &Detection,
    lengths: &ResolvedLengths,
    settings: &Settings,
) -> Result<SweepContacts, Error> {
    let all_islands = islands(fixed, &detection.active_bodies)?;
    let island_count = all_islands.len();
    let mut pairs: Vec<usize> = all_islands
        .into_iter()
        .filter(|island| detection.island_penetrates(island, lengths.tolerance))
        .flat_map(|island| island.pairs)
        .collect();
    pairs.sort_unstable();
    let mut points = Vec::new();
    for k in pairs {
        let pair = detection.active_pairs[k];
        let bodies = detection.active_bodies[k];
        let (a, b) = (geometry.held(pair.body_a), geometry.held(pair.body_b));
        let contact = contact_points(
            &detection.active_queries[k],
            &a,
            &b,
            lengths.contact_margin,
            settings,
        );
        let (pose_a, pose_b) = (&body_poses[bodies.body_a], &body_poses[bodies.body_b]);
        points.extend(contact.points.iter().map(|point| {
            StoredPoint::new(
                (bodies.body_a, bodies.body_b),
                point,
                contact.normal_body,
                pose_a,
                pose_b,
            )
        }));
    }
    Ok(SweepContacts {
        points,
        islands: island_count,
    })
}
