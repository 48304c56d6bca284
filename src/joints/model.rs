//! What a joint is: two bodies, an anchor frame on each, and the relative
//! motions of the two frames that the joint forbids or limits.
//!
//! A joint connects body `a` and body `b` through an anchor frame on each,
//! given in the body's own frame (the frame of its user pose, like
//! Rapier's local frames). With the anchor frames in the world
//! `F_a = (R_Fa, o_a)` and `F_b = (R_Fb, o_b)`, the joint's relative pose
//! is measured in frame `a`:
//!
//! ```text
//! p = R_Fa^T (o_b - o_a)           (linear, length units)
//! R_rel = R_Fa^T R_Fb              (angular)
//! ```
//!
//! A *locked* linear axis `k` asks `p_k = 0`; locked angular axes ask the
//! frames' axes to coincide (see [`super::constraints`] for the exact
//! measures). A *limit* on a free axis asks `min <= value <= max`: the
//! travel `p_k` on a free linear axis, the angle about the free angular
//! axis when exactly one is free. Every joint type is such a set of locked
//! axes: [`JointKind::locked_axes`].

use nalgebra::Isometry3;
use thiserror::Error;

/// The six axes of a joint's relative motion: translations along and
/// rotations about the anchor frame's `x`, `y`, `z`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct JointAxes {
    /// Locked translations along `x`, `y`, `z` of frame `a`.
    pub linear: [bool; 3],
    /// Locked rotations about `x`, `y`, `z`.
    pub angular: [bool; 3],
}

impl JointAxes {
    /// Every axis locked (a fixed joint).
    pub const ALL: JointAxes = JointAxes {
        linear: [true; 3],
        angular: [true; 3],
    };

    /// The free angular axis when exactly one is free.
    pub fn single_free_angular(&self) -> Option<usize> {
        let free: Vec<usize> = (0..3).filter(|&k| !self.angular[k]).collect();
        (free.len() == 1).then(|| free[0])
    }

    /// Number of locked axes.
    pub fn count(&self) -> usize {
        self.linear
            .iter()
            .chain(&self.angular)
            .filter(|&&l| l)
            .count()
    }
}

/// `[min, max]` on one free axis: length units on a linear axis, radians
/// on an angular one.
pub type Limit = [f64; 2];

/// The limits of a joint, per axis (`None`: unlimited); only free axes may
/// have one.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointLimits {
    /// Travel along `x`, `y`, `z` of frame `a`.
    pub linear: [Option<Limit>; 3],
    /// Angle about `x`, `y`, `z` (only the single free angular axis).
    pub angular: [Option<Limit>; 3],
}

impl JointLimits {
    /// No limit on any axis.
    pub const NONE: JointLimits = JointLimits {
        linear: [None; 3],
        angular: [None; 3],
    };
}

/// The type of a joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointKind {
    /// Every relative motion locked.
    Fixed,
    /// The anchor points coincide; any rotation (a ball joint).
    Spherical,
    /// The anchor points coincide and the frames' `x` axes coincide: a
    /// hinge about `x`, with an optional limit on the angle about it (the
    /// angle from `y_a` to `y_b` about `x_a`, radians, in `(-pi, pi]`).
    Revolute {
        /// `[min, max]` of the hinge angle.
        limit: Option<Limit>,
    },
    /// The frames keep their orientation and `o_b` stays on the `x` axis of
    /// frame `a`: a slider along `x`, with an optional limit on the travel
    /// `p_x`.
    Prismatic {
        /// `[min, max]` of the travel.
        limit: Option<Limit>,
    },
    /// Any set of locked axes, with limits on free ones (Rapier's
    /// `GenericJoint`).
    Generic {
        /// The locked axes.
        locked: JointAxes,
        /// Limits on free axes.
        limits: JointLimits,
    },
}

impl JointKind {
    /// The name in files and reports: `fixed`, `spherical`, `revolute`,
    /// `prismatic`, `generic`.
    pub fn name(&self) -> &'static str {
        match self {
            JointKind::Fixed => "fixed",
            JointKind::Spherical => "spherical",
            JointKind::Revolute { .. } => "revolute",
            JointKind::Prismatic { .. } => "prismatic",
            JointKind::Generic { .. } => "generic",
        }
    }

    /// The locked axes of this type.
    pub fn locked_axes(&self) -> JointAxes {
        match self {
            JointKind::Fixed => JointAxes::ALL,
            JointKind::Spherical => JointAxes {
                linear: [true; 3],
                angular: [false; 3],
            },
            JointKind::Revolute { .. } => JointAxes {
                linear: [true; 3],
                angular: [false, true, true],
            },
            JointKind::Prismatic { .. } => JointAxes {
                linear: [false, true, true],
                angular: [true; 3],
            },
            JointKind::Generic { locked, .. } => *locked,
        }
    }

    /// The limits of this type.
    pub fn limits(&self) -> JointLimits {
        match self {
            JointKind::Revolute { limit } => JointLimits {
                angular: [*limit, None, None],
                ..JointLimits::NONE
            },
            JointKind::Prismatic { limit } => JointLimits {
                linear: [*limit, None, None],
                ..JointLimits::NONE
            },
            JointKind::Generic { limits, .. } => *limits,
            JointKind::Fixed | JointKind::Spherical => JointLimits::NONE,
        }
    }
}

/// A joint between two bodies of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// A label for reports (need not be unique).
    pub name: String,
    /// The type.
    pub kind: JointKind,
    /// Index of body `a` in the scene.
    pub body_a: usize,
    /// Index of body `b` in the scene.
    pub body_b: usize,
    /// Anchor frame on body `a`, in body `a`'s frame (its user frame).
    pub frame_a: Isometry3<f64>,
    /// Anchor frame on body `b`, in body `b`'s frame.
    pub frame_b: Isometry3<f64>,
}

/// Why a joint is invalid.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum JointError {
    /// A body index is out of range.
    #[error("no body {body}: the scene has {len} bodies")]
    NoSuchBody {
        /// The index given.
        body: usize,
        /// Number of bodies.
        len: usize,
    },
    /// Both ends are the same body.
    #[error("joins body {body} to itself")]
    SameBody {
        /// The body.
        body: usize,
    },
    /// Both bodies are fixed: nothing could move to satisfy the joint.
    #[error("joins two fixed bodies ({body_a} and {body_b})")]
    BothFixed {
        /// Body `a`.
        body_a: usize,
        /// Body `b`.
        body_b: usize,
    },
    /// An anchor frame has a non-finite entry or a rotation that is not a
    /// unit quaternion.
    #[error("anchor frame {which} is not a finite rigid transform")]
    InvalidFrame {
        /// `"a"` or `"b"`.
        which: &'static str,
    },
    /// A limit is not finite, or its minimum exceeds its maximum.
    #[error("limit on the {axis} axis is invalid: [{min}, {max}]")]
    InvalidLimit {
        /// The axis, like `linear x` or `angular x`.
        axis: String,
        /// Minimum given.
        min: f64,
        /// Maximum given.
        max: f64,
    },
    /// A limit on a locked axis, or an angular limit where not exactly one
    /// angular axis is free.
    #[error("limit on the {axis} axis, which is {reason}")]
    LimitOnLockedAxis {
        /// The axis.
        axis: String,
        /// Why no limit applies.
        reason: &'static str,
    },
    /// A generic joint that locks nothing.
    #[error("locks no axis")]
    NothingLocked,
}

/// Tolerance on the norm of an anchor frame's quaternion.
pub const UNIT_QUATERNION_TOLERANCE: f64 = 1e-9;

const AXIS_NAMES: [&str; 3] = ["x", "y", "z"];

impl Joint {
    /// Checks the joint against a scene's bodies (`fixed[i]`: whether body
    /// `i` is fixed).
    pub fn validate(&self, fixed: &[bool]) -> Result<(), JointError> {
        for body in [self.body_a, self.body_b] {
            if body >= fixed.len() {
                return Err(JointError::NoSuchBody {
                    body,
                    len: fixed.len(),
                });
            }
        }
        if self.body_a == self.body_b {
            return Err(JointError::SameBody { body: self.body_a });
        }
        if fixed[self.body_a] && fixed[self.body_b] {
            return Err(JointError::BothFixed {
                body_a: self.body_a,
                body_b: self.body_b,
            });
        }
        check_frame(&self.frame_a, "a")?;
        check_frame(&self.frame_b, "b")?;
        let locked = self.kind.locked_axes();
        if locked.count() == 0 {
            return Err(JointError::NothingLocked);
        }
        check_limits(&locked, &self.kind.limits())
    }
}

fn check_frame(frame: &Isometry3<f64>, which: &'static str) -> Result<(), JointError> {
    let q = frame.rotation.quaternion();
    let finite = frame.translation.vector.iter().all(|x| x.is_finite())
        && q.coords.iter().all(|x| x.is_finite());
    if !finite || (q.norm() - 1.0).abs() > UNIT_QUATERNION_TOLERANCE {
        return Err(JointError::InvalidFrame { which });
    }
    Ok(())
}

fn check_limits(locked: &JointAxes, limits: &JointLimits) -> Result<(), JointError> {
    let single_free = locked.single_free_angular();
    for (k, axis_name) in AXIS_NAMES.iter().enumerate() {
        for (kind, limit, is_locked, usable) in [
            ("linear", limits.linear[k], locked.linear[k], true),
            (
                "angular",
                limits.angular[k],
                locked.angular[k],
                single_free == Some(k),
            ),
        ] {
            let Some([min, max]) = limit else { continue };
            let axis = format!("{kind} {axis_name}");
            if !(min.is_finite() && max.is_finite() && min <= max) {
                return Err(JointError::InvalidLimit { axis, min, max });
            }
            if is_locked {
                return Err(JointError::LimitOnLockedAxis {
                    axis,
                    reason: "locked",
                });
            }
            if !usable {
                return Err(JointError::LimitOnLockedAxis {
                    axis,
                    reason: "not the single free angular axis",
                });
            }
        }
    }
    Ok(())
}
