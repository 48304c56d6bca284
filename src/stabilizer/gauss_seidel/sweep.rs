//! One sweep: every stored contact point visited once, in order, each
//! pushing its two bodies apart along its normal at once, then the
//! joints' rows (Box2D v2.4,
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
//!
//! The push is one case of the relaxation of a scalar row with gradient
//! blocks `g_a`, `g_b` (`[dx; dtheta]`, world) and error `C`
//! (`SweepBodies::relax`), which the joints' rows use too
//! ([`super::joints`]):
//!
//! ```text
//! k = g_a^T M_a^-1 g_a + g_b^T M_b^-1 g_b,  lambda = -C / k,  (dx, dtheta)_i = lambda M_i^-1 g_i
//! ```
//!
//! with `M^-1 = diag(I/m, I_world^-1)`; a point's row is `g_a = [n; r_a x
//! n]`, `g_b = [-n; -(r_b x n)]`, which gives `K` and the update above.

use nalgebra::{Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3, Vector6};

use super::joints::SweepJoint;
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
    /// Joint constraints visited (equalities and limits).
    pub joint_rows: usize,
    /// Joint constraints that moved their bodies.
    pub joint_relaxed: usize,
    /// Largest `|value|` of an equality, or violation of a limit, met at a
    /// visit (before its relaxation; length units).
    pub joint_error: f64,
}

impl SweepSummary {
    /// Whether any visit moved a body.
    pub fn moved(&self) -> bool {
        self.pushed + self.joint_relaxed > 0
    }
}

/// One scalar row between two bodies: its gradient blocks `[d/dx;
/// d/dtheta]` (world) at the current poses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Scene index of the first body.
    pub body_a: usize,
    /// Scene index of the second body.
    pub body_b: usize,
    /// Gradient with respect to the first body's correction.
    pub grad_a: Vector6<f64>,
    /// Gradient with respect to the second body's correction.
    pub grad_b: Vector6<f64>,
}

/// One body's part in a relaxation: its index, `M^-1 g` (world), and
/// `g^T M^-1 g`.
struct Response {
    body: usize,
    dx: Vector3<f64>,
    dtheta: Vector3<f64>,
    k: f64,
}

impl SweepBodies {
    /// Visits `points` in order, once each, then the constraints of
    /// `joints` (each joint's in order; [`super::joints`]).
    pub fn sweep(
        &mut self,
        points: &[StoredPoint],
        joints: &[SweepJoint],
        parameters: PushParameters,
    ) -> SweepSummary {
        let mut summary = SweepSummary {
            visited: 0,
            pushed: 0,
            min_separation: f64::INFINITY,
            joint_rows: 0,
            joint_relaxed: 0,
            joint_error: 0.0,
        };
        for point in points {
            let (pushed, separation) = self.push_apart(point, parameters);
            summary.visited += 1;
            summary.pushed += usize::from(pushed);
            summary.min_separation = summary.min_separation.min(separation);
        }
        for joint in joints {
            self.relax_joint(joint, parameters, &mut summary);
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
        let lever = |p: &Point3<f64>, body: usize| p - self.poses[body].translation.vector;
        let (r_a, r_b) = (lever(&measured.p_a_world, a), lever(&measured.p_b_world, b));
        let row = Row {
            body_a: a,
            body_b: b,
            grad_a: block(n, r_a.coords.cross(&n)),
            grad_b: block(-n, n.cross(&r_b.coords)),
        };
        (self.relax(&row, c), s)
    }

    /// Relaxes `row` whose error is `c`: `lambda = -c / k` with `k = g_a^T
    /// M_a^-1 g_a + g_b^T M_b^-1 g_b`, each body moved by `lambda M^-1 g`
    /// at once (module docs). Returns whether a body moved: not when `c`
    /// is 0 or `k` is not positive (two fixed bodies, a degenerate row).
    pub(super) fn relax(&mut self, row: &Row, c: f64) -> bool {
        if c == 0.0 || !c.is_finite() {
            return false;
        }
        let response_a = self.response(row.body_a, &row.grad_a);
        let response_b = self.response(row.body_b, &row.grad_b);
        let k: f64 = [&response_a, &response_b]
            .into_iter()
            .flatten()
            .map(|r| r.k)
            .sum();
        // Box2D's `K > 0` guard (a pair of two fixed bodies has `K = 0`).
        if !(k > 0.0 && k.is_finite()) {
            return false;
        }
        let lambda = -c / k;
        for response in [response_a, response_b].into_iter().flatten() {
            self.displace(&response, lambda);
        }
        true
    }

    /// Body `body`'s response to a row with gradient block `grad`; `None`
    /// if it is fixed.
    fn response(&self, body: usize, grad: &Vector6<f64>) -> Option<Response> {
        let inverse = self.inverse_masses[body]?;
        let rotation = self.poses[body].rotation.to_rotation_matrix();
        let inverse_inertia_world =
            rotation.matrix() * inverse.inertia_body * rotation.matrix().transpose();
        let (linear, angular) = (grad.fixed_rows::<3>(0), grad.fixed_rows::<3>(3));
        let dx = linear * inverse.mass;
        let dtheta = inverse_inertia_world * angular;
        Some(Response {
            body,
            k: linear.dot(&dx) + angular.dot(&dtheta),
            dx: dx.into_owned(),
            dtheta,
        })
    }

    /// Moves a body by `lambda M^-1 g`.
    fn displace(&mut self, response: &Response, lambda: f64) {
        let pose = &mut self.poses[response.body];
        let rotation = UnitQuaternion::from_scaled_axis(response.dtheta * lambda) * pose.rotation;
        *pose = Isometry3::from_parts(
            Translation3::from(pose.translation.vector + response.dx * lambda),
            UnitQuaternion::new_normalize(rotation.into_inner()),
        );
    }
}

/// `[linear; angular]`.
fn block(linear: Vector3<f64>, angular: Vector3<f64>) -> Vector6<f64> {
    Vector6::new(
        linear.x, linear.y, linear.z, angular.x, angular.y, angular.z,
    )
}
