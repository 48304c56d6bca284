//! One sweep: every stored contact point visited once, in order, each
//! pushing its two bodies apart along its normal at once (Box2D v2.4,
//! `b2ContactSolver::SolvePositionConstraints`, in 3D).
//!
//! For a point with separation `s` measured at the current poses
//! ([`StoredPoint::measure`]), normal `n` from B towards A and levers
//! `r_a = p_a - x_a`, `r_b = p_b - x_b`:
//!
//! ```text
//! C      = clamp(beta (s + slop), -max_correction, 0)
//! K      = 1/m_a + (r_a x n)^T I_a^-1 (r_a x n) + 1/m_b + (r_b x n)^T I_b^-1 (r_b x n)
//! lambda = -C / K                                           (if K > 0)
//! x_a += lambda n / m_a,   R_a = exp( lambda I_a^-1 (r_a x n)) R_a
//! x_b -= lambda n / m_b,   R_b = exp(-lambda I_b^-1 (r_b x n)) R_b
//! ```
//!
//! `K` is the point's effective inverse mass along `n` (the diagonal entry
//! of `J M^-1 J^T` of its row, docs/design.md section 3): to first order the
//! push raises `s` by `lambda K = -C`, so a point below `-slop` gets the
//! fraction `beta` of its error removed, at most `max_correction`. A fixed
//! body has infinite mass (no term in `K`, no motion). Box2D's inertia is a
//! scalar in 2D; in 3D `I^-1 = R I_body^-1 R^T` is taken at the body's
//! rotation at the visit. The motion of each body is the Box2D update with
//! the impulse `P = lambda n` (`x += P/m`, `theta += I^-1 (r x P)`), the
//! rotation applied as a rotation vector, as the projection applies its
//! corrections. A point with `C = 0` moves nothing, bit for bit.

use nalgebra::{Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3};

use super::point::StoredPoint;

/// Inverse mass properties of a dynamic body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InverseMass {
    /// `1 / m`.
    pub mass: f64,
    /// `I_body^-1`, body frame.
    pub inertia_body: Matrix3<f64>,
}

/// The poses being corrected and the inverse masses (`None`: fixed).
#[derive(Debug, Clone, PartialEq)]
pub struct SweepBodies {
    /// COM pose of every body of the scene (body frame to world).
    pub poses: Vec<Isometry3<f64>>,
    /// Inverse mass of every body; `None` for a fixed body.
    pub inverse_masses: Vec<Option<InverseMass>>,
}

/// The parameters of a push: `beta` and the call's lengths.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PushParameters {
    /// Fraction of the error removed per visit.
    pub baumgarte: f64,
    /// Depth left alone.
    pub slop: f64,
    /// The cap of one push.
    pub max_correction: f64,
}

/// What a sweep did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepSummary {
    /// Points visited.
    pub visited: usize,
    /// Points that moved their bodies.
    pub pushed: usize,
    /// Smallest separation met at a visit (before its push).
    pub min_separation: f64,
}

/// One body's part in a push: its index, inverse mass, and
/// `I^-1 (r x n)` (world).
struct Response {
    body: usize,
    inverse_mass: f64,
    angular: Vector3<f64>,
    /// `(r x n) . I^-1 (r x n)`.
    k_angular: f64,
}

impl SweepBodies {
    /// Visits `points` in order, once each.
    pub fn sweep(&mut self, points: &[StoredPoint], parameters: PushParameters) -> SweepSummary {
        let mut summary = SweepSummary {
            visited: 0,
            pushed: 0,
            min_separation: f64::INFINITY,
        };
        for point in points {
            let (pushed, separation) = self.push_apart(point, parameters);
            summary.visited += 1;
            summary.pushed += usize::from(pushed);
            summary.min_separation = summary.min_separation.min(separation);
        }
        summary
    }

    /// Pushes the two bodies of `point` apart; returns whether they moved
    /// and the separation met.
    fn push_apart(&mut self, point: &StoredPoint, parameters: PushParameters) -> (bool, f64) {
        let (a, b) = (point.body_a, point.body_b);
        let measured = point.measure(&self.poses[a], &self.poses[b]);
        let s = measured.separation;
        let c =
            (parameters.baumgarte * (s + parameters.slop)).clamp(-parameters.max_correction, 0.0);
        if c >= 0.0 {
            return (false, s);
        }
        let n = measured.n_world;
        let response_a = self.response(a, &measured.p_a_world, &n);
        let response_b = self.response(b, &measured.p_b_world, &n);
        let k: f64 = [&response_a, &response_b]
            .into_iter()
            .flatten()
            .map(|r| r.inverse_mass + r.k_angular)
            .sum();
        // Box2D's `K > 0` guard (a pair of two fixed bodies has `K = 0`).
        if k.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return (false, s);
        }
        let lambda = -c / k;
        if let Some(response) = response_a {
            self.displace(&response, lambda, &n);
        }
        if let Some(response) = response_b {
            self.displace(&response, -lambda, &n);
        }
        (true, s)
    }

    /// Body `body`'s response to a push at `p_world` along `n`; `None` if
    /// it is fixed.
    fn response(&self, body: usize, p_world: &Point3<f64>, n: &Vector3<f64>) -> Option<Response> {
        let inverse = self.inverse_masses[body]?;
        let pose = &self.poses[body];
        let r_world = p_world - pose.translation.vector;
        let rn_world = r_world.coords.cross(n);
        let rotation = pose.rotation.to_rotation_matrix();
        let inverse_inertia_world =
            rotation.matrix() * inverse.inertia_body * rotation.matrix().transpose();
        let angular = inverse_inertia_world * rn_world;
        Some(Response {
            body,
            inverse_mass: inverse.mass,
            angular,
            k_angular: rn_world.dot(&angular),
        })
    }

    /// Moves a body by the impulse `lambda n` (signed for its side).
    fn displace(&mut self, response: &Response, lambda: f64, n: &Vector3<f64>) {
        let pose = &mut self.poses[response.body];
        let dx_world = n * (lambda * response.inverse_mass);
        let dtheta_world = response.angular * lambda;
        let rotation = UnitQuaternion::from_scaled_axis(dtheta_world) * pose.rotation;
        *pose = Isometry3::from_parts(
            Translation3::from(pose.translation.vector + dx_world),
            UnitQuaternion::new_normalize(rotation.into_inner()),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::NormalBody;

    /// Rounding of one push on lengths of order 1.
    const ROUNDING: f64 = 1e-15;

    /// A unit-mass body with unit inertia above a fixed body, touching at
    /// `lever` (body frame of the dynamic body) with separation `s`.
    fn pair(lever: Vector3<f64>, s: f64) -> (SweepBodies, StoredPoint) {
        let bodies = SweepBodies {
            poses: vec![Isometry3::identity(), Isometry3::identity()],
            inverse_masses: vec![
                None,
                Some(InverseMass {
                    mass: 1.0,
                    inertia_body: Matrix3::identity(),
                }),
            ],
        };
        let point = StoredPoint {
            body_a: 1,
            body_b: 0,
            p_a_body: Point3::from(lever),
            p_b_body: Point3::from(lever - Vector3::y() * s),
            normal_body: NormalBody::B,
            n_ref: Vector3::y(),
        };
        (bodies, point)
    }

    fn parameters(baumgarte: f64, slop: f64, max_correction: f64) -> PushParameters {
        PushParameters {
            baumgarte,
            slop,
            max_correction,
        }
    }

    #[test]
    fn central_push_removes_the_baumgarte_fraction() {
        let (mut bodies, point) = pair(Vector3::new(0.0, -1.0, 0.0), -0.1);
        bodies.sweep(&[point], parameters(0.2, 0.0, f64::INFINITY));
        let after = point.measure(&bodies.poses[1], &bodies.poses[0]).separation;
        assert!((after - (-0.08)).abs() < ROUNDING, "{after}");
        assert_eq!(bodies.poses[0], Isometry3::identity());
    }

    #[test]
    fn push_is_capped_and_respects_the_slop() {
        let (mut capped, point) = pair(Vector3::new(0.0, -1.0, 0.0), -0.1);
        capped.sweep(&[point], parameters(1.0, 0.0, 0.03));
        let lift = capped.poses[1].translation.vector.y;
        assert!((lift - 0.03).abs() < ROUNDING, "{lift}");
        let (mut within_slop, point) = pair(Vector3::new(0.0, -1.0, 0.0), -0.004);
        let summary = within_slop.sweep(&[point], parameters(0.2, 0.005, 0.2));
        assert_eq!(summary.pushed, 0);
        assert_eq!(within_slop.poses[1], Isometry3::identity());
    }

    #[test]
    fn offset_push_uses_the_effective_mass() {
        // Lever (1, -1, 0), n = y: r x n = (0, 0, 1), K = 1 + 1 = 2, so the
        // body rises by lambda = 0.1 / 2 and turns by 0.05 about z, which
        // lifts the point by another 0.05 to first order.
        let (mut bodies, point) = pair(Vector3::new(1.0, -1.0, 0.0), -0.1);
        bodies.sweep(&[point], parameters(1.0, 0.0, f64::INFINITY));
        let pose = &bodies.poses[1];
        assert!((pose.translation.vector.y - 0.05).abs() < ROUNDING);
        let angle = pose.rotation.scaled_axis();
        assert!((angle - Vector3::new(0.0, 0.0, 0.05)).norm() < ROUNDING);
    }
}
