//! A body's convex parts: one for a convex shape, several for a compound
//! (one rigid body made of several convex pieces, as a Rapier rigid body
//! with several colliders).
//!
//! # Frames
//!
//! Part `i` of a compound is given by its convex shape and its pose
//! `(t_i, R_i)` in the compound's shape frame. Its polyhedron has its own
//! body frame (origin at the part's centre of mass, axes of the part's
//! shape frame, [`ConvexPolyhedron`]), so the part's centre of mass in the
//! compound's shape frame is `c_i = t_i + R_i o_i` (`o_i` the part's
//! `shape_origin_offset`). The body frame of the whole body has its origin
//! at the compound's centre of mass `c` and the axes of its shape frame, so
//! the part's *offset* (part frame to body frame) is the rotation `R_i` and
//! the translation `c_i - c`, and the part's world pose is
//! `pose_body * offset_i`. A convex body has one part with no offset (the
//! identity, stored as `None` so that its world pose is the body's pose bit
//! for bit).
//!
//! # Mass properties (unit density)
//!
//! Parts add: `V = sum V_i`, `c = sum V_i c_i / V`, and about `c`, in the
//! body frame,
//!
//! ```text
//! I = sum_i ( R_i I_i R_i^T + V_i (|d_i|^2 E - d_i d_i^T) ),   d_i = c_i - c
//! ```
//!
//! (parallel axes). Overlapping parts count twice, as in Rapier, whose rigid
//! body's mass is the sum of its colliders'.

use std::sync::Arc;

use nalgebra::{Isometry3, Matrix3, Translation3, Vector3};

use super::Body;
use super::part_solid::curved_solid;
use super::{BodyError, PartSolid, Shape, check_translation, unit_rotation};
use crate::geometry::curved::CurvedSolid;
use crate::geometry::{ConvexPolyhedron, Rounding};

/// Most parts a compound may have: the narrow phase of two compounds
/// compares every pair of their parts whose boxes overlap.
pub const MAX_COMPOUND_PARTS: usize = 1024;

/// One convex piece of a compound shape, placed in the compound's shape
/// frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapePart {
    /// The piece's convex shape (a cuboid or a hull, not a compound), in
    /// its own shape frame.
    pub shape: Shape,
    /// Position of the piece's shape-frame origin in the compound's shape
    /// frame.
    pub translation: Vector3<f64>,
    /// Rotation of the piece's shape frame in the compound's, quaternion
    /// `[x, y, z, w]` (unit within
    /// [`super::UNIT_QUATERNION_TOLERANCE`]).
    pub rotation_xyzw: [f64; 4],
}

/// One convex part of a body, in the body frame.
#[derive(Debug, Clone)]
pub struct BodyPart {
    polyhedron: Arc<ConvexPolyhedron>,
    rounding: Option<Rounding>,
    offset: Option<Isometry3<f64>>,
}

impl BodyPart {
    /// The part's polyhedron, in its own frame (origin at its centre of
    /// mass).
    pub fn polyhedron(&self) -> &Arc<ConvexPolyhedron> {
        &self.polyhedron
    }

    /// The core and radius of a round part (sphere, capsule, rounded
    /// cuboid or hull); `None` for a plain polyhedron. A sphere's or
    /// capsule's [`BodyPart::polyhedron`] is only the box that holds it.
    pub fn rounding(&self) -> Option<Rounding> {
        self.rounding
    }

    /// The part's length scale: its polyhedron's, or a round part's reach
    /// (largest distance of a point of the solid from the part's origin).
    pub fn scale(&self) -> f64 {
        match &self.rounding {
            Some(rounding) => rounding.reach(&self.polyhedron),
            None => self.polyhedron.scale(),
        }
    }

    /// The part's frame in the body frame; `None` for the only part of a
    /// convex body (the identity).
    pub fn offset(&self) -> Option<&Isometry3<f64>> {
        self.offset.as_ref()
    }

    /// The part's world pose when the body's centre-of-mass pose is
    /// `body_pose` (the body's pose itself, bit for bit, without offset).
    pub fn pose(&self, body_pose: &Isometry3<f64>) -> Isometry3<f64> {
        match &self.offset {
            None => *body_pose,
            Some(offset) => body_pose * offset,
        }
    }

    /// Moves the part by `shift` in the body frame (the body frame's
    /// origin moved by `-shift`, `body::engine_mass`).
    pub(super) fn shift(&mut self, shift: &Vector3<f64>) {
        let moved = Translation3::from(*shift) * self.offset.unwrap_or_else(Isometry3::identity);
        self.offset = Some(moved);
    }

    /// Largest distance of a vertex of the part from the body's centre of
    /// mass.
    pub fn reach(&self) -> f64 {
        let shift = self.offset.map_or(0.0, |o| o.translation.vector.norm());
        shift + self.scale()
    }
}

/// A body's solid: its parts and their summed unit-density mass
/// properties.
#[derive(Debug, Clone)]
pub(crate) struct Solid {
    /// The parts, in the order given.
    pub parts: Vec<BodyPart>,
    /// Summed volume.
    pub volume: f64,
    /// Centre of mass in the shape frame (`p_shape = p_body + origin_offset`).
    pub origin_offset: Vector3<f64>,
    /// Inertia about the centre of mass at unit density, body frame.
    pub inertia_unit_density: Matrix3<f64>,
}

impl Solid {
    /// The solid of one convex polyhedron.
    pub fn convex(polyhedron: Arc<ConvexPolyhedron>) -> Self {
        let mass = polyhedron.mass_properties();
        Solid {
            volume: mass.volume,
            origin_offset: polyhedron.shape_origin_offset(),
            inertia_unit_density: mass.inertia_unit_density,
            parts: vec![BodyPart {
                polyhedron,
                rounding: None,
                offset: None,
            }],
        }
    }

    /// Builds the solid of a shape: its polyhedron, or a compound's parts.
    pub fn build(shape: &Shape) -> Result<Self, BodyError> {
        match shape {
            Shape::Compound { parts } => Self::compound(parts),
            convex => {
                let solid = PartSolid::build(convex).map_err(BodyError::Shape)?;
                let frame = solid.frame_from_com();
                // The part frame is the body frame unless the rounding
                // moved the centre of mass (a rounded hull).
                let offset = (frame != Vector3::zeros())
                    .then(|| Isometry3::from_parts(Translation3::from(frame), Default::default()));
                Ok(Solid {
                    volume: solid.volume,
                    origin_offset: solid.com_shape,
                    inertia_unit_density: solid.inertia_unit_density,
                    parts: vec![BodyPart {
                        polyhedron: solid.polyhedron,
                        rounding: solid.rounding,
                        offset,
                    }],
                })
            }
        }
    }

    fn compound(parts: &[ShapePart]) -> Result<Self, BodyError> {
        if parts.is_empty() || parts.len() > MAX_COMPOUND_PARTS {
            return Err(BodyError::CompoundPartCount(parts.len()));
        }
        let mut placed = Vec::with_capacity(parts.len());
        for (index, part) in parts.iter().enumerate() {
            let in_part = |error: BodyError| BodyError::CompoundPart {
                index,
                error: Box::new(error),
            };
            if let Shape::Compound { .. } = part.shape {
                return Err(in_part(BodyError::NestedCompound));
            }
            check_translation(&part.translation).map_err(in_part)?;
            let rotation = unit_rotation(part.rotation_xyzw).map_err(in_part)?;
            let solid = PartSolid::build(&part.shape).map_err(|e| in_part(BodyError::Shape(e)))?;
            let com_shape = part.translation + rotation * solid.com_shape;
            placed.push((solid, rotation, com_shape));
        }
        let volume: f64 = placed.iter().map(|(p, _, _)| p.volume).sum();
        let com = placed
            .iter()
            .map(|(p, _, c)| c * p.volume)
            .sum::<Vector3<f64>>()
            / volume;
        let mut inertia = Matrix3::zeros();
        for (solid, rotation, com_shape) in &placed {
            let r = rotation.to_rotation_matrix();
            let own = r.matrix() * solid.inertia_unit_density * r.matrix().transpose();
            let d = com_shape - com;
            let shift = (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * solid.volume;
            inertia += own + shift;
        }
        let parts = placed
            .into_iter()
            .map(|(solid, rotation, com_shape)| {
                // The part frame (the polyhedron's) sits at the part's
                // centre of mass plus the rounding's shift.
                let frame = com_shape + rotation * solid.frame_from_com();
                BodyPart {
                    polyhedron: solid.polyhedron,
                    rounding: solid.rounding,
                    offset: Some(Isometry3::from_parts(
                        Translation3::from(frame - com),
                        rotation,
                    )),
                }
            })
            .collect();
        Ok(Solid {
            parts,
            volume,
            origin_offset: com,
            inertia_unit_density: inertia,
        })
    }
}

impl Body {
    /// The shape of part `k` (a compound's `k`-th part's, or the body's
    /// own for its only part).
    pub fn part_shape(&self, k: usize) -> Option<&Shape> {
        match &self.shape {
            Shape::Compound { parts } => parts.get(k).map(|part| &part.shape),
            shape => (k == 0).then_some(shape),
        }
    }

    /// Part `k`'s true solid when it is a cylinder or cone (the
    /// support-function narrow phase's; [`BodyPart::polyhedron`] is its
    /// circumscribed approximation), read off its shape; `None` for every
    /// other shape.
    pub fn part_curved(&self, k: usize) -> Option<CurvedSolid> {
        self.part_shape(k).and_then(curved_solid)
    }
}
