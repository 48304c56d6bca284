//! How far a method moved the bodies, measured from the poses before and
//! after, the same way for every method.
//!
//! - Mass-weighted displacement: `sqrt(sum_i m_i |dc_i|^2 + dtheta_i^T
//!   I_i dtheta_i)` over the dynamic bodies, `dc` the centre of mass's
//!   translation, `dtheta` the rotation vector of `R_after R_before^T`, `I`
//!   the world inertia before (`stabilizer::scene_displacement`): the norm
//!   the library minimizes (to first order), so that the excess of a
//!   method over the smallest is its cost in the library's own metric.
//! - Largest motion: the largest distance any vertex of any body moved
//!   (of each part's polyhedron; for a sphere or capsule part, the box
//!   that holds it, whose vertices move at least as far as any point of
//!   the solid).

use constraint_stabilization::scene::Scene;
use constraint_stabilization::stabilizer::scene_displacement;

/// The motion between two poses of the same scene.
#[derive(Debug, Clone, Copy, Default)]
pub struct Motion {
    /// Mass-weighted displacement (mass^1/2 length).
    pub displacement: f64,
    /// Largest vertex displacement of any body (length).
    pub largest: f64,
}

/// The motion from `before` to `after` (same bodies, same order).
pub fn motion(before: &Scene, after: &Scene) -> Motion {
    let com_before: Vec<_> = before.bodies().iter().map(|b| *b.com_pose()).collect();
    let (displacement, _) = scene_displacement(after, &com_before);
    let mut largest: f64 = 0.0;
    for (b0, b1) in before.bodies().iter().zip(after.bodies()) {
        let (p0, p1) = (b0.com_pose(), b1.com_pose());
        if p0 != p1 {
            for part in b0.parts() {
                let (q0, q1) = (part.pose(p0), part.pose(p1));
                for v in part.polyhedron().vertices() {
                    largest = largest.max(((q1 * v) - (q0 * v)).norm());
                }
            }
        }
    }
    Motion {
        displacement,
        largest,
    }
}
