//! The contact points and joints of one sweep: every pair of every island
//! with a penetration deeper than the tolerance or a joint error beyond it,
//! in ascending pair order, each pair's manifold points in the manifold's
//! order, stored in body frames; then the joints of those islands,
//! ascending. Islands join the bodies of a joint as those of a contact
//! (`contact::islands_with_joints`), as the projection's do.
//!
//! The pairs and their manifolds are those the projection uses (the same
//! detection, islands and [`crate::contact::contact_points`]), so both
//! methods measure the same geometry. Near pairs of such an island (within
//! the contact margin, not penetrating) are visited too: a push can bring
//! them into contact within the sweep, and their re-measured separation
//! then asks for a push of its own. Islands with no penetration and no
//! joint error beyond the tolerance are left out, so their bodies keep
//! their poses bit for bit.

use nalgebra::Isometry3;

use super::joints::SweepJoint;
use super::point::StoredPoint;
use crate::Error;
use crate::contact::{Detection, SceneGeometry, contact_points};
use crate::joints::JointErrors;
use crate::scene::Scene;
use crate::settings::{ResolvedLengths, Settings};
use crate::stabilizer::joint_state::violated_islands;

/// The contacts and joints of one sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepContacts {
    /// The points, in visiting order.
    pub points: Vec<StoredPoint>,
    /// The joints of the islands visited, ascending, visited after the
    /// points.
    pub joints: Vec<SweepJoint>,
    /// Islands formed from the detection's active pairs and the joints
    /// (all of them, as [`crate::stabilizer::PassReport::islands`] counts).
    pub islands: usize,
}

/// The stored contact points and the joints of `detection` (made at
/// `geometry`, the bodies of `scene` at `body_poses`, its joints' errors
/// there `joint_errors`). A point of two compound bodies' parts is stored
/// in the bodies' frames.
pub fn sweep_points(
    scene: &Scene,
    geometry: SceneGeometry,
    body_poses: &[Isometry3<f64>],
    detection: &Detection,
    joint_errors: &[JointErrors],
    lengths: &ResolvedLengths,
    settings: &Settings,
) -> Result<SweepContacts, Error> {
    let (islands, island_count) = violated_islands(scene, detection, joint_errors, lengths)?;
    let (mut pairs, mut joints) = (Vec::new(), Vec::new());
    for island in islands {
        pairs.extend(island.pairs);
        joints.extend(island.joints);
    }
    pairs.sort_unstable();
    joints.sort_unstable();
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
    let joints = joints
        .into_iter()
        .map(|index| SweepJoint::of(scene, index, lengths.scale))
        .collect::<Result<_, _>>()?;
    Ok(SweepContacts {
        points,
        joints,
        islands: island_count,
    })
}
