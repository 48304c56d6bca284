//! An independent measure of the penetration left in a scene, by
//! parry3d-f64's `query::contact` (GJK/EPA), which this project did not
//! write: what the demo prints and what tests assert, so that our own V-Clip
//! is never the judge of its own answers.

use crate::Error;
use crate::broad_phase::candidate_pairs;
use crate::contact::SceneParts;
use crate::geometry::{RoundCore, isometry_to_parry};
use crate::scene::Scene;
use parry3d_f64::shape::{Ball, Capsule, RoundShape, Shape};

/// Penetration statistics of a scene by parry.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ParryPenetration {
    /// Pairs that parry finds penetrating deeper than the threshold.
    pub penetrating_pairs: usize,
    /// Deepest penetration depth parry reports (0 if none).
    pub deepest: f64,
}

/// Penetrations deeper than `threshold`, over the part pairs of the
/// broad-phase pairs (each pair of two compounds' parts counts apart).
pub fn parry_penetration(scene: &Scene, threshold: f64) -> Result<ParryPenetration, Error> {
    let parts = SceneParts::of(scene);
    let shapes = (0..parts.len())
        .map(|part| parry_shape(&parts, part))
        .collect::<Result<Vec<_>, _>>()?;
    let body_poses: Vec<_> = scene.bodies().iter().map(|b| *b.com_pose()).collect();
    let part_poses = parts.poses(&body_poses);
    let poses: Vec<_> = part_poses.iter().map(isometry_to_parry).collect();
    let mut result = ParryPenetration::default();
    for pair in parts.part_pairs(&candidate_pairs(scene, 0.0)?, &part_poses, 0.0) {
        let (a, b) = (pair.body_a, pair.body_b);
        let contact =
            parry3d_f64::query::contact(&poses[a], &*shapes[a], &poses[b], &*shapes[b], 0.0);
        if let Ok(Some(contact)) = contact {
            let depth = -contact.dist;
            result.deepest = result.deepest.max(depth);
            if depth > threshold {
                result.penetrating_pairs += 1;
            }
        }
    }
    Ok(result)
}

/// parry's shape of part `part`: a ball, a capsule or a rounded polyhedron
/// for a round part (its core and radius), else the polyhedron.
fn parry_shape(parts: &SceneParts, part: usize) -> Result<Box<dyn Shape>, Error> {
    let polyhedron = parts.shapes()[part].to_parry()?;
    Ok(match parts.rounding(part) {
        None => Box::new(polyhedron),
        Some(rounding) => match rounding.core {
            RoundCore::Point => Box::new(Ball::new(rounding.radius)),
            RoundCore::Segment { half_length } => {
                Box::new(Capsule::new_z(half_length, rounding.radius))
            }
            RoundCore::Polyhedron => Box::new(RoundShape {
                inner_shape: polyhedron,
                border_radius: rounding.radius,
            }),
        },
    })
}
