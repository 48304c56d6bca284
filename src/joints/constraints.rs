//! The scalar constraints of a joint, measured exactly from the anchor
//! frames and differentiated for the rows.
//!
//! Notation: body states `(x, R)` (centre of mass, rotation), a correction
//! `(dx, dtheta)` applied as `x += dx`, `R = exp(dtheta) R`; anchor frames
//! in the world `F_a = (R_Fa, o_a)`, `F_b = (R_Fb, o_b)`; `l_k = R_Fa e_k`
//! the axes of frame `a`, `m_k = R_Fb e_k` those of frame `b`; `d = o_b -
//! o_a`. Under the correction, `o_i` moves by `dx_i + dtheta_i x (o_i -
//! x_i)` and every axis `v` of body `i` by `dtheta_i x v`.
//!
//! **Locked linear axis `k`**: `f = l_k . d = 0`, with
//!
//! ```text
//! df = l_k . dx_b + dtheta_b . ((o_b - x_b) x l_k) - l_k . dx_a + dtheta_a . (l_k x (o_b - x_a)).
//! ```
//!
//! **Locked angular axes.** With one free angular axis `f` (a hinge) the
//! two locked axes `k` ask the free axes `u_a = l_f`, `u_b = m_f` to
//! coincide: `g_k = (u_a x u_b) . l_k = 0` (the sine of the misalignment's
//! component about `l_k`; both vanish exactly when `u_b = u_a`, whatever
//! the hinge angle), with
//!
//! ```text
//! dg_k = dtheta_a . (u_a x (u_b x l_k) + l_k x (u_a x u_b)) + dtheta_b . (u_b x (l_k x u_a)).
//! ```
//!
//! Otherwise (all three locked, or one) the locked components of the
//! relative rotation vector `phi = log(R_Fa^T R_Fb)` (frame `a`) vanish:
//! `R_Fa^T R_Fb` becomes `R_rel exp(R_Fb^T (dtheta_b - dtheta_a))`, so
//!
//! ```text
//! dphi = J_r^-1(phi) R_Fb^T (dtheta_b - dtheta_a),
//! J_r^-1(phi) = I + [phi]x / 2 + (1/t^2 - (1 + cos t) / (2 t sin t)) [phi]x^2,   t = |phi|.
//! ```
//!
//! **Limits.** On a free linear axis the travel `l_k . d`; about the single
//! free angular axis `f` the hinge angle `theta = atan2(m_g . l_h, m_g .
//! l_g)` (`g`, `h` the axes after `f` in cyclic order: the angle from `y_a`
//! to `y_b` about `x_a` for a hinge about `x`), whose derivative is
//! `(c ds - s dc) / (s^2 + c^2)` with `s = m_g . l_h`, `c = m_g . l_g`.
//! A limit gives two unilateral constraints `value - min >= 0` and
//! `max - value >= 0`.
//!
//! **Units.** Angular constraints are multiplied by the scene's length
//! scale `L` so that every row, like a contact's, is in length units and
//! one tolerance governs all: an angle is within the tolerance when it is
//! below `tolerance / L` radians.

use nalgebra::{Isometry3, Matrix3, Point3, Vector3, Vector6};

use super::model::{Joint, JointAxes};

/// The world anchor frames of a joint and the centres of mass of its
/// bodies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnchorFrames {
    /// Frame `a` in the world.
    pub frame_a_world: Isometry3<f64>,
    /// Frame `b` in the world.
    pub frame_b_world: Isometry3<f64>,
    /// Centre of mass of body `a`.
    pub com_a_world: Point3<f64>,
    /// Centre of mass of body `b`.
    pub com_b_world: Point3<f64>,
}

impl AnchorFrames {
    /// The frames at the bodies' centre-of-mass poses, with each anchor
    /// frame given in its body's user frame and `offset_*` the centre of
    /// mass in that frame.
    pub fn at(
        joint: &Joint,
        com_pose_a: &Isometry3<f64>,
        offset_a: &Vector3<f64>,
        com_pose_b: &Isometry3<f64>,
        offset_b: &Vector3<f64>,
    ) -> Self {
        let in_com = |frame: &Isometry3<f64>, offset: &Vector3<f64>| {
            let mut frame = *frame;
            frame.translation.vector -= offset;
            frame
        };
        AnchorFrames {
            frame_a_world: com_pose_a * in_com(&joint.frame_a, offset_a),
            frame_b_world: com_pose_b * in_com(&joint.frame_b, offset_b),
            com_a_world: com_pose_a.translation.vector.into(),
            com_b_world: com_pose_b.translation.vector.into(),
        }
    }

    fn axis_a(&self, k: usize) -> Vector3<f64> {
        self.frame_a_world.rotation * Vector3::ith(k, 1.0)
    }

    fn axis_b(&self, k: usize) -> Vector3<f64> {
        self.frame_b_world.rotation * Vector3::ith(k, 1.0)
    }

    fn separation(&self) -> Vector3<f64> {
        self.frame_b_world.translation.vector - self.frame_a_world.translation.vector
    }

    /// `p = R_Fa^T (o_b - o_a)`: the relative position in frame `a`.
    pub fn relative_position(&self) -> Vector3<f64> {
        self.frame_a_world.rotation.inverse() * self.separation()
    }

    /// `log(R_Fa^T R_Fb)`: the relative rotation vector in frame `a`.
    pub fn relative_rotation(&self) -> Vector3<f64> {
        (self.frame_a_world.rotation.inverse() * self.frame_b_world.rotation).scaled_axis()
    }

    /// The angle between axis `k` of frame `a` and axis `k` of frame `b`.
    pub fn axis_misalignment(&self, k: usize) -> f64 {
        let (u_a, u_b) = (self.axis_a(k), self.axis_b(k));
        u_a.cross(&u_b).norm().atan2(u_a.dot(&u_b))
    }

    /// The angle about the free axis `f` (module docs).
    pub fn hinge_angle(&self, f: usize) -> f64 {
        let (g, h) = ((f + 1) % 3, (f + 2) % 3);
        let m_g = self.axis_b(g);
        m_g.dot(&self.axis_a(h)).atan2(m_g.dot(&self.axis_a(g)))
    }
}

/// One scalar constraint of a joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointConstraint {
    /// `l_k . d = 0`.
    Linear(usize),
    /// `(u_a x u_b) . l_k = 0` for the free angular axis `free`.
    Align {
        /// The free axis.
        free: usize,
        /// The locked axis.
        k: usize,
    },
    /// `phi_k = 0`.
    Rotation(usize),
    /// `l_k . d - min >= 0`.
    TravelMin(usize, f64),
    /// `max - l_k . d >= 0`.
    TravelMax(usize, f64),
    /// `theta_f - min >= 0`.
    AngleMin(usize, f64),
    /// `max - theta_f >= 0`.
    AngleMax(usize, f64),
}

/// A constraint's value and its gradient blocks `[d/dx; d/dtheta]` for body
/// `a` and body `b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linearized {
    /// The value (length units).
    pub value: f64,
    /// Gradient with respect to body `a`'s correction.
    pub grad_a: Vector6<f64>,
    /// Gradient with respect to body `b`'s correction.
    pub grad_b: Vector6<f64>,
}

/// Below this relative-rotation angle (radians) `J_r^-1` uses its series.
pub const SMALL_ROTATION: f64 = 1e-4;

impl JointConstraint {
    /// The constraints of a joint, in a fixed order: the locked axes
    /// (equalities), then the limits (unilateral).
    pub fn of(joint: &Joint) -> Vec<JointConstraint> {
        let locked = joint.kind.locked_axes();
        let limits = joint.kind.limits();
        let mut out: Vec<JointConstraint> = (0..3)
            .filter(|&k| locked.linear[k])
            .map(JointConstraint::Linear)
            .collect();
        out.extend(angular_equalities(&locked));
        for k in 0..3 {
            if let Some([min, max]) = limits.linear[k] {
                out.extend([
                    JointConstraint::TravelMin(k, min),
                    JointConstraint::TravelMax(k, max),
                ]);
            }
            if let Some([min, max]) = limits.angular[k] {
                out.extend([
                    JointConstraint::AngleMin(k, min),
                    JointConstraint::AngleMax(k, max),
                ]);
            }
        }
        out
    }

    /// Whether this is an equality (a locked axis) rather than a limit.
    pub fn is_equality(&self) -> bool {
        matches!(
            self,
            JointConstraint::Linear(_)
                | JointConstraint::Align { .. }
                | JointConstraint::Rotation(_)
        )
    }

    /// Whether the value is an angle (scaled by `L`).
    pub fn is_angular(&self) -> bool {
        matches!(
            self,
            JointConstraint::Align { .. }
                | JointConstraint::Rotation(_)
                | JointConstraint::AngleMin(..)
                | JointConstraint::AngleMax(..)
        )
    }

    /// The exact value at `frames` (length units; angles times `scale`).
    pub fn value(&self, frames: &AnchorFrames, scale: f64) -> f64 {
        match *self {
            JointConstraint::Linear(k) => frames.axis_a(k).dot(&frames.separation()),
            JointConstraint::Align { free, k } => {
                let (u_a, u_b) = (frames.axis_a(free), frames.axis_b(free));
                scale * u_a.cross(&u_b).dot(&frames.axis_a(k))
            }
            JointConstraint::Rotation(k) => scale * frames.relative_rotation()[k],
            JointConstraint::TravelMin(k, min) => frames.axis_a(k).dot(&frames.separation()) - min,
            JointConstraint::TravelMax(k, max) => max - frames.axis_a(k).dot(&frames.separation()),
            JointConstraint::AngleMin(f, min) => scale * (frames.hinge_angle(f) - min),
            JointConstraint::AngleMax(f, max) => scale * (max - frames.hinge_angle(f)),
        }
    }

    /// The value and its gradients at `frames` (module docs).
    pub fn linearize(&self, frames: &AnchorFrames, scale: f64) -> Linearized {
        let value = self.value(frames, scale);
        let (grad_a, grad_b) = match *self {
            JointConstraint::Linear(k) | JointConstraint::TravelMin(k, _) => {
                travel_gradients(frames, k)
            }
            JointConstraint::TravelMax(k, _) => {
                let (a, b) = travel_gradients(frames, k);
                (-a, -b)
            }
            JointConstraint::Align { free, k } => {
                let (u_a, u_b, l) = (frames.axis_a(free), frames.axis_b(free), frames.axis_a(k));
                let da = u_a.cross(&u_b.cross(&l)) + l.cross(&u_a.cross(&u_b));
                let db = u_b.cross(&l.cross(&u_a));
                (angular_block(da * scale), angular_block(db * scale))
            }
            JointConstraint::Rotation(k) => {
                let phi = frames.relative_rotation();
                let row = right_jacobian_inverse(&phi)
                    .transpose()
                    .column(k)
                    .into_owned();
                let db = frames.frame_b_world.rotation * row * scale;
                (angular_block(-db), angular_block(db))
            }
            JointConstraint::AngleMin(f, _) => angle_gradients(frames, f, scale),
            JointConstraint::AngleMax(f, _) => {
                let (a, b) = angle_gradients(frames, f, scale);
                (-a, -b)
            }
        };
        Linearized {
            value,
            grad_a,
            grad_b,
        }
    }
}

/// The equalities of the locked angular axes (module docs).
fn angular_equalities(locked: &JointAxes) -> Vec<JointConstraint> {
    let locked_k: Vec<usize> = (0..3).filter(|&k| locked.angular[k]).collect();
    match locked.single_free_angular() {
        Some(free) => locked_k
            .into_iter()
            .map(|k| JointConstraint::Align { free, k })
            .collect(),
        None => locked_k
            .into_iter()
            .map(JointConstraint::Rotation)
            .collect(),
    }
}

fn angular_block(v: Vector3<f64>) -> Vector6<f64> {
    Vector6::new(0.0, 0.0, 0.0, v.x, v.y, v.z)
}

fn block(linear: Vector3<f64>, angular: Vector3<f64>) -> Vector6<f64> {
    Vector6::new(
        linear.x, linear.y, linear.z, angular.x, angular.y, angular.z,
    )
}

/// Gradients of `l_k . d` (module docs).
fn travel_gradients(frames: &AnchorFrames, k: usize) -> (Vector6<f64>, Vector6<f64>) {
    let l = frames.axis_a(k);
    let o_b = frames.frame_b_world.translation.vector;
    let lever_b = o_b - frames.com_b_world.coords;
    let from_a = o_b - frames.com_a_world.coords;
    (block(-l, l.cross(&from_a)), block(l, lever_b.cross(&l)))
}

/// Gradients of the hinge angle about `f`, times `scale` (module docs).
fn angle_gradients(frames: &AnchorFrames, f: usize, scale: f64) -> (Vector6<f64>, Vector6<f64>) {
    let (g, h) = ((f + 1) % 3, (f + 2) % 3);
    let (l_g, l_h, m_g) = (frames.axis_a(g), frames.axis_a(h), frames.axis_b(g));
    let (s, c) = (m_g.dot(&l_h), m_g.dot(&l_g));
    // ds = dtheta_b . (m_g x l_h) + dtheta_a . (l_h x m_g), likewise dc.
    let (ds_a, ds_b) = (l_h.cross(&m_g), m_g.cross(&l_h));
    let (dc_a, dc_b) = (l_g.cross(&m_g), m_g.cross(&l_g));
    let r2 = (s * s + c * c).max(f64::MIN_POSITIVE);
    let da = (ds_a * c - dc_a * s) / r2 * scale;
    let db = (ds_b * c - dc_b * s) / r2 * scale;
    (angular_block(da), angular_block(db))
}

/// `J_r^-1(phi)` of SO(3) (module docs).
pub fn right_jacobian_inverse(phi: &Vector3<f64>) -> Matrix3<f64> {
    let t = phi.norm();
    let hat = phi.cross_matrix();
    let coefficient = if t < SMALL_ROTATION {
        // Series of 1/t^2 - (1 + cos t) / (2 t sin t): 1/12 + t^2/720.
        1.0 / 12.0 + t * t / 720.0
    } else {
        // (1 + cos t) / sin t = cot(t/2): finite up to t = pi.
        let half = 0.5 * t;
        1.0 / (t * t) - half.cos() / (2.0 * t * half.sin())
    };
    Matrix3::identity() + hat * 0.5 + hat * hat * coefficient
}
