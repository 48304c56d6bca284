//! Rigid bodies: a convex shape, a pose, and mass properties (or fixed).
//!
//! # Two poses, one body
//!
//! The user places a body by the *shape frame*: the frame in which the shape
//! was given (a cuboid's centre, the frame of a hull's points). The library
//! works about the *centre of mass* (COM): the body frame of
//! [`ConvexPolyhedron`] has its origin at the COM and the axes of the shape
//! frame. With `R` the rotation, `t_user` the user translation and
//! `o = ConvexPolyhedron::shape_origin_offset()` (the COM in the shape frame):
//!
//! ```text
//! p_world = t_user + R p_shape = (t_user + R o) + R p_body,   p_shape = p_body + o
//! com pose:  translation t_com = t_user + R o,   rotation R (the same)
//! ```
//!
//! The user pose is the truth: it is stored exactly as given, and the COM
//! pose is derived from it once. [`Body::set_com_pose`] with the current COM
//! pose is a no-op, so a body that the stabilizer did not move reports its
//! user pose bit for bit as it was read. A body that did move gets
//! `t_user = t_com - R o` and the new (normalized) rotation.
//!
//! # Rotations
//!
//! Rotations are quaternions `[x, y, z, w]` (scalar last). A given
//! quaternion must have a norm within [`UNIT_QUATERNION_TOLERANCE`] of 1: it
//! is then *normalized* for all computation (the raw numbers are kept only
//! to write an untouched body back unchanged); farther from unit it is
//! *rejected* ([`BodyError::RotationNotUnit`]), since it is then more likely
//! a mistake (Euler angles, a wrong order) than rounding.
//!
//! # Mass properties
//!
//! A body is fixed, or has a mass `m > 0`, or a density `rho > 0`, with
//! `m = rho V` (`V` the volume of the solid). The body-frame inertia about
//! the COM is `I_body = rho I_unit` (`I_unit` the unit-density inertia of
//! the shape); in the world frame `I_world = R I_body R^T`.

use std::sync::Arc;

use nalgebra::{Isometry3, Matrix3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};
use thiserror::Error;

use crate::geometry::{ConvexPolyhedron, GeometryError, Rounding, curved};

mod engine_mass;
mod part_solid;
mod parts;
mod state;

use part_solid::PartSolid;
use parts::Solid;
pub use parts::{BodyPart, MAX_COMPOUND_PARTS, ShapePart};
pub use state::{BodyInertia, BodyState};

/// Largest accepted deviation `| |q| - 1 |` of a given rotation quaternion
/// from unit norm. Quaternions written with four significant digits (for
/// example `[0, 0, 0.7071, 0.7071]`, norm 0.99999) pass; the accepted
/// quaternion is normalized before use.
pub const UNIT_QUATERNION_TOLERANCE: f64 = 1e-3;

/// Departure of a quaternion's norm from 1 that counts as rounding: a
/// rotation set through [`Body::set_com_pose`] within it is stored as
/// given, beyond it renormalized (products of unit quaternions drift by a
/// few ulps each).
pub const UNIT_QUATERNION_ROUNDING: f64 = 8.0 * f64::EPSILON;

/// A convex shape in the user's representation, kept so that output files
/// repeat it unchanged.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// The box `[-h, h]` with half extents `h`, centred on the shape-frame
    /// origin.
    Cuboid {
        /// Half extents along x, y, z (length, all > 0).
        half_extents: Vector3<f64>,
    },
    /// The convex hull of points given in the shape frame.
    ConvexHull {
        /// The points (shape frame); points inside the hull are allowed.
        points: Vec<Point3<f64>>,
    },
    /// A ball of radius `radius` about the shape-frame origin (a point
    /// grown by the radius, `geometry::round`).
    Sphere {
        /// Radius (length, > 0).
        radius: f64,
    },
    /// The segment from `-half_height z` to `+half_height z` grown by
    /// `radius` (a cylinder of length `2 half_height` with hemispherical
    /// ends).
    Capsule {
        /// Half the length of the core segment (length, > 0).
        half_height: f64,
        /// Radius (length, > 0).
        radius: f64,
    },
    /// The box `[-h, h]` grown by `radius` (its edges and corners rounded,
    /// its outer half extents `h + radius`).
    RoundCuboid {
        /// Half extents of the core box (length, all > 0).
        half_extents: Vector3<f64>,
        /// Rounding radius (length, >= 0).
        radius: f64,
    },
    /// The convex hull of `points` grown by `radius`.
    RoundConvexHull {
        /// The points of the core hull (shape frame).
        points: Vec<Point3<f64>>,
        /// Rounding radius (length, >= 0).
        radius: f64,
    },
    /// A solid cylinder along `z`, centred on the shape-frame origin;
    /// queried on its true solid by support functions (or, with
    /// [`crate::vclip::VClipSettings::curved_support_functions`] off, as a
    /// polyhedron within
    /// [`crate::geometry::curved::CURVED_DEVIATION_RELATIVE`] of the radius).
    Cylinder {
        /// Half the height (length, > 0).
        half_height: f64,
        /// Radius (length, > 0).
        radius: f64,
    },
    /// A solid cone along `z`: base of radius `radius` at
    /// `z = -half_height`, apex at `z = half_height` (Rapier's convention,
    /// along `z`); queried like a cylinder.
    Cone {
        /// Half the height (length, > 0).
        half_height: f64,
        /// Radius of the base (length, > 0).
        radius: f64,
    },
    /// Several convex pieces moving as one rigid body ([`ShapePart`]; frames
    /// and mass properties in the module docs of `body::parts`).
    Compound {
        /// The pieces, each placed in the compound's shape frame (at least
        /// one, at most [`MAX_COMPOUND_PARTS`]; none a compound).
        parts: Vec<ShapePart>,
    },
}

impl Shape {
    /// Builds the polyhedron of a convex shape (its own frame: origin at
    /// the polyhedron's centre of mass); a compound has several
    /// ([`GeometryError::NotConvex`], see [`Body::parts`]). For a round
    /// shape it is the core (rounded cuboid or hull) or the box that holds
    /// the solid (sphere, capsule), see [`BodyPart::rounding`]; for a
    /// cylinder or cone the circumscribed approximation.
    pub fn build(&self) -> Result<ConvexPolyhedron, GeometryError> {
        match self {
            Shape::Cuboid { half_extents } => ConvexPolyhedron::cuboid(*half_extents),
            Shape::ConvexHull { points } => ConvexPolyhedron::from_points(points),
            round => {
                let solid = PartSolid::build(round)?;
                Ok(Arc::unwrap_or_clone(solid.polyhedron))
            }
        }
    }

    /// The largest distance between a cylinder's or cone's circumscribed
    /// polyhedron and its true surface (length): `r (1/cos(π/N) - 1)` for
    /// radius `r` (its circumscribed `N`-gon, [`crate::geometry::curved`];
    /// at most [`crate::geometry::curved::CURVED_DEVIATION_RELATIVE`] of
    /// `r`), the largest part's for a compound, 0 for every exact shape.
    /// It bounds the narrow phase's error when
    /// [`crate::vclip::VClipSettings::curved_support_functions`] is off; by
    /// default cylinders and cones are queried on their true solids and
    /// their error is measured instead (`docs/round-shapes.md`).
    pub fn surface_deviation(&self) -> f64 {
        let sides = curved::sides_for(curved::CURVED_DEVIATION_RELATIVE);
        match self {
            Shape::Cylinder { radius, .. } | Shape::Cone { radius, .. } => {
                radius * curved::deviation_of(sides)
            }
            Shape::Compound { parts } => parts
                .iter()
                .map(|part| part.shape.surface_deviation())
                .fold(0.0, f64::max),
            _ => 0.0,
        }
    }

    /// Volume of the solid (the sum of the parts' for a compound).
    pub fn volume(&self) -> Result<f64, BodyError> {
        Solid::build(self).map(|solid| solid.volume)
    }
}

/// How a body's mass is specified.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MassSpec {
    /// The body never moves and has no mass properties.
    Fixed,
    /// Total mass (> 0); the density follows from the volume.
    Mass(f64),
    /// Uniform density (> 0, mass per volume); the mass follows.
    Density(f64),
}

/// Mass properties of a dynamic body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyMass {
    /// Total mass (> 0).
    pub mass: f64,
    /// Uniform density (mass / volume).
    pub density: f64,
    /// Inertia tensor about the centre of mass, in the body frame (axes of
    /// the shape frame), mass·length².
    pub inertia_body: Matrix3<f64>,
    /// Its inverse (symmetric positive definite for a solid).
    pub inverse_inertia_body: Matrix3<f64>,
}

/// A body as the user describes it, before validation. See
/// [`Body::new`] and `Scene::add_body`.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyDesc {
    /// A label, repeated in output and error messages (need not be unique).
    pub name: String,
    /// The shape, in its shape frame.
    pub shape: Shape,
    /// World position of the shape-frame origin.
    pub translation: Vector3<f64>,
    /// World rotation of the shape frame, quaternion `[x, y, z, w]`; see
    /// [`UNIT_QUATERNION_TOLERANCE`].
    pub rotation_xyzw: [f64; 4],
    /// Fixed, mass or density.
    pub mass: MassSpec,
}

/// Why a body description is invalid; [`BodyError::field`] names the field.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BodyError {
    /// The shape could not be built.
    #[error("invalid shape: {0}")]
    Shape(GeometryError),
    /// A translation component is NaN or infinite.
    #[error("component {component} is {value}: it must be finite")]
    NonFiniteTranslation {
        /// 0 = x, 1 = y, 2 = z.
        component: usize,
        /// The value given.
        value: f64,
    },
    /// A rotation component is NaN or infinite.
    #[error("component {component} is {value}: it must be finite")]
    NonFiniteRotation {
        /// 0 = x, 1 = y, 2 = z, 3 = w.
        component: usize,
        /// The value given.
        value: f64,
    },
    /// The rotation quaternion is too far from unit norm.
    #[error(
        "quaternion norm is {norm}: it must be 1 within {}",
        UNIT_QUATERNION_TOLERANCE
    )]
    RotationNotUnit {
        /// Norm of the given quaternion.
        norm: f64,
    },
    /// The mass is not a finite positive number.
    #[error("mass is {0}: it must be finite and positive")]
    InvalidMass(f64),
    /// The density is not a finite positive number.
    #[error("density is {0}: it must be finite and positive")]
    InvalidDensity(f64),
    /// The friction coefficient is negative or not finite.
    #[error("friction is {0}: it must be finite and nonnegative")]
    InvalidFriction(f64),
    /// A compound has no parts or more than [`MAX_COMPOUND_PARTS`].
    #[error("a compound has {0} parts: it must have 1 to {MAX_COMPOUND_PARTS}")]
    CompoundPartCount(usize),
    /// A part of a compound is itself a compound.
    #[error("a compound's part cannot be a compound")]
    NestedCompound,
    /// A part of a compound is invalid.
    #[error("part {index}: {error}")]
    CompoundPart {
        /// Index of the part.
        index: usize,
        /// What is wrong with it (its shape, translation or rotation).
        error: Box<BodyError>,
    },
    /// A compound's summed volume or centre of mass is not finite (parts
    /// far out of range).
    #[error("the compound's parts give no finite volume and centre of mass")]
    DegenerateCompound,
    /// The mass, density or inertia derived from the given one and the
    /// volume is zero or not finite (an extreme value or a tiny shape).
    #[error("{given:?} with volume {volume} gives no usable mass properties")]
    DegenerateMass {
        /// What was given.
        given: MassSpec,
        /// The volume of the shape.
        volume: f64,
    },
}

impl BodyError {
    /// The scene-file field the error is about (`shape`, `translation`,
    /// `rotation`, `mass`, `density`).
    pub fn field(&self) -> &'static str {
        match self {
            BodyError::Shape(_)
            | BodyError::CompoundPartCount(_)
            | BodyError::NestedCompound
            | BodyError::CompoundPart { .. }
            | BodyError::DegenerateCompound => "shape",
            BodyError::NonFiniteTranslation { .. } => "translation",
            BodyError::NonFiniteRotation { .. } | BodyError::RotationNotUnit { .. } => "rotation",
            BodyError::InvalidMass(_)
            | BodyError::DegenerateMass {
                given: MassSpec::Mass(_),
                ..
            } => "mass",
            BodyError::InvalidDensity(_) | BodyError::DegenerateMass { .. } => "density",
            BodyError::InvalidFriction(_) => "friction",
        }
    }
}

/// A validated rigid body. Fields are private so that a `Body` is always
/// valid: finite pose, unit rotation, positive mass.
#[derive(Debug, Clone)]
pub struct Body {
    name: String,
    shape: Shape,
    parts: Vec<BodyPart>,
    /// The centre of mass in the shape frame.
    origin_offset: Vector3<f64>,
    mass_spec: MassSpec,
    mass: Option<BodyMass>,
    /// The mass properties of a dynamic body held still
    /// ([`Body::hold_fixed`]); `None` otherwise.
    held_mass: Option<BodyMass>,
    translation_user: Vector3<f64>,
    rotation_user_xyzw: [f64; 4],
    com_pose: Isometry3<f64>,
    friction: Option<f64>,
}

impl Body {
    /// Validates a description and builds the body's polyhedron (or a
    /// compound's polyhedra).
    pub fn new(desc: BodyDesc) -> Result<Self, BodyError> {
        let solid = Solid::build(&desc.shape)?;
        Self::with_solid(desc, solid)
    }

    /// Like [`Body::new`] for a convex shape with an already built
    /// polyhedron, which the caller guarantees is `desc.shape.build()`
    /// (lets bodies share one shape).
    pub fn with_polyhedron(
        desc: BodyDesc,
        polyhedron: Arc<ConvexPolyhedron>,
    ) -> Result<Self, BodyError> {
        match desc.shape {
            Shape::Cuboid { .. } | Shape::ConvexHull { .. } => {
                Self::with_solid(desc, Solid::convex(polyhedron))
            }
            _ => Self::new(desc),
        }
    }

    fn with_solid(desc: BodyDesc, solid: Solid) -> Result<Self, BodyError> {
        check_translation(&desc.translation)?;
        let rotation = unit_rotation(desc.rotation_xyzw)?;
        let finite = solid.volume.is_finite()
            && solid.origin_offset.iter().all(|c| c.is_finite())
            && solid.inertia_unit_density.iter().all(|c| c.is_finite());
        if !finite {
            return Err(BodyError::DegenerateCompound);
        }
        let mass = body_mass(desc.mass, &solid)?;
        let com_pose = com_pose_of(&desc.translation, rotation, &solid.origin_offset);
        Ok(Body {
            name: desc.name,
            shape: desc.shape,
            parts: solid.parts,
            origin_offset: solid.origin_offset,
            mass_spec: desc.mass,
            mass,
            translation_user: desc.translation,
            rotation_user_xyzw: desc.rotation_xyzw,
            com_pose,
            friction: None,
            held_mass: None,
        })
    }

    /// The body's own friction coefficient, if it has one (else the
    /// stabilizer's [`crate::Settings::friction`] applies). A pair's
    /// coefficient is the mean of its two bodies' (Rapier's default rule).
    pub fn friction(&self) -> Option<f64> {
        self.friction
    }

    /// Sets (or, with `None`, clears) the body's friction coefficient,
    /// which must be finite and nonnegative.
    pub fn set_friction(&mut self, mu: Option<f64>) -> Result<(), BodyError> {
        if let Some(mu) = mu.filter(|mu| !(mu.is_finite() && *mu >= 0.0)) {
            return Err(BodyError::InvalidFriction(mu));
        }
        self.friction = mu;
        Ok(())
    }

    /// The body's label.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The shape as the user gave it.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// The polyhedron of a convex body, in the body frame (origin at the
    /// COM); `None` for a compound, whose polyhedra are its
    /// [`Body::parts`].
    pub fn polyhedron(&self) -> Option<&Arc<ConvexPolyhedron>> {
        match self.parts.as_slice() {
            [only] if only.offset().is_none() => Some(only.polyhedron()),
            _ => None,
        }
    }

    /// The convex parts: one (without offset) for a convex body.
    pub fn parts(&self) -> &[BodyPart] {
        &self.parts
    }

    /// Whether the body has several convex parts (or one with an offset).
    pub fn is_compound(&self) -> bool {
        self.polyhedron().is_none()
    }

    /// The body's length scale, to which geometric tolerances are relative:
    /// its polyhedron's (largest distance of a vertex from the COM), for a
    /// compound its smallest part's.
    pub fn scale(&self) -> f64 {
        self.parts
            .iter()
            .map(BodyPart::scale)
            .fold(f64::INFINITY, f64::min)
    }

    /// Largest distance of a vertex from the centre of mass (a bound for a
    /// compound: each part's offset plus its scale).
    pub fn reach(&self) -> f64 {
        self.parts.iter().map(BodyPart::reach).fold(0.0, f64::max)
    }

    /// World poses of the parts at the body's current pose.
    pub fn part_poses(&self) -> impl Iterator<Item = Isometry3<f64>> + '_ {
        self.parts.iter().map(|p| p.pose(&self.com_pose))
    }

    /// Fixed, mass or density, as given.
    pub fn mass_spec(&self) -> MassSpec {
        self.mass_spec
    }

    /// Whether the body never moves.
    pub fn is_fixed(&self) -> bool {
        self.mass.is_none()
    }

    /// Mass properties; `None` for a fixed body.
    pub fn mass(&self) -> Option<&BodyMass> {
        self.mass.as_ref()
    }

    /// World-frame inertia about the COM, `R I_body R^T`; `None` if fixed.
    pub fn inertia_world(&self) -> Option<Matrix3<f64>> {
        let rotation = self.com_pose.rotation.to_rotation_matrix();
        self.mass
            .map(|m| rotation.matrix() * m.inertia_body * rotation.matrix().transpose())
    }

    /// World-frame inverse inertia `R I_body^-1 R^T`; `None` if fixed.
    pub fn inverse_inertia_world(&self) -> Option<Matrix3<f64>> {
        let rotation = self.com_pose.rotation.to_rotation_matrix();
        self.mass
            .map(|m| rotation.matrix() * m.inverse_inertia_body * rotation.matrix().transpose())
    }

    /// World position of the shape-frame origin, exactly as given or as
    /// derived from the last moved COM pose.
    pub fn translation_user(&self) -> &Vector3<f64> {
        &self.translation_user
    }

    /// World rotation `[x, y, z, w]` of the shape frame, exactly as given
    /// (not normalized) or as set by the last move (normalized).
    pub fn rotation_user_xyzw(&self) -> [f64; 4] {
        self.rotation_user_xyzw
    }

    /// The user pose (shape frame in world) with the normalized rotation.
    pub fn user_pose(&self) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::from(self.translation_user),
            self.com_pose.rotation,
        )
    }

    /// The centre of mass in the body's user (shape) frame.
    pub fn com_offset(&self) -> &Vector3<f64> {
        &self.origin_offset
    }

    /// The COM pose: maps body-frame points to world, `p_world = R p_body + t_com`.
    pub fn com_pose(&self) -> &Isometry3<f64> {
        &self.com_pose
    }

    /// World position of the centre of mass.
    pub fn com_world(&self) -> Point3<f64> {
        Point3::from(self.com_pose.translation.vector)
    }

    /// Moves the body to a new COM pose (rotation renormalized). Setting the
    /// current COM pose is a no-op, so the user pose stays bit-identical.
    pub fn set_com_pose(&mut self, com_pose: Isometry3<f64>) -> Result<(), BodyError> {
        if com_pose == self.com_pose {
            return Ok(());
        }
        check_translation(&com_pose.translation.vector)?;
        let rotation = unit_rotation(xyzw_of(&com_pose.rotation))?;
        // A rotation that is unit to rounding is kept bit for bit, so that
        // the pose stored is the pose the stabilizer measured (its narrow-
        // phase answers stay valid); one that drifted is renormalized.
        let drift = (com_pose.rotation.quaternion().norm() - 1.0).abs();
        let rotation = if drift <= UNIT_QUATERNION_ROUNDING {
            com_pose.rotation
        } else {
            rotation
        };
        let offset_world = rotation * self.origin_offset;
        self.translation_user = com_pose.translation.vector - offset_world;
        self.rotation_user_xyzw = xyzw_of(&rotation);
        self.com_pose = Isometry3::from_parts(com_pose.translation, rotation);
        Ok(())
    }

    /// Moves the body to a new user pose (validated as in [`Body::new`]).
    pub fn set_user_pose(
        &mut self,
        translation: Vector3<f64>,
        rotation_xyzw: [f64; 4],
    ) -> Result<(), BodyError> {
        check_translation(&translation)?;
        let rotation = unit_rotation(rotation_xyzw)?;
        self.com_pose = com_pose_of(&translation, rotation, &self.origin_offset);
        self.translation_user = translation;
        self.rotation_user_xyzw = rotation_xyzw;
        Ok(())
    }

    /// The COM pose displaced by a correction `(dx, dtheta)` (world frame):
    /// `t_com + dx`, `exp(dtheta) R` with `dtheta` a rotation vector.
    pub fn displaced_com_pose(&self, dx: &Vector3<f64>, dtheta: &Vector3<f64>) -> Isometry3<f64> {
        let state = BodyState {
            position: self.com_world(),
            rotation: self.com_pose.rotation,
        };
        state.moved(dx, dtheta, 1.0).isometry()
    }

    /// The world-frame axis-aligned bounding box `(min, max)` of the body,
    /// from its vertices (of every part).
    pub fn world_aabb(&self) -> (Point3<f64>, Point3<f64>) {
        let mut min = Point3::from(Vector3::repeat(f64::INFINITY));
        let mut max = Point3::from(Vector3::repeat(f64::NEG_INFINITY));
        for part in &self.parts {
            let (part_min, part_max) = rounded_aabb(
                part.polyhedron(),
                part.rounding().as_ref(),
                &part.pose(&self.com_pose),
            );
            min = min.inf(&part_min);
            max = max.sup(&part_max);
        }
        (min, max)
    }
}

/// The world AABB `(min, max)` of a polyhedron at `pose`, from its vertices.
pub fn part_aabb(
    polyhedron: &ConvexPolyhedron,
    pose: &Isometry3<f64>,
) -> (Point3<f64>, Point3<f64>) {
    let mut min = Point3::from(Vector3::repeat(f64::INFINITY));
    let mut max = Point3::from(Vector3::repeat(f64::NEG_INFINITY));
    for v_body in polyhedron.vertices() {
        let v_world = pose * v_body;
        min = min.inf(&v_world);
        max = max.sup(&v_world);
    }
    (min, max)
}

/// The world AABB `(min, max)` of a part at `pose`: its polyhedron's, or
/// for a round part its core's grown by the radius.
pub fn rounded_aabb(
    polyhedron: &ConvexPolyhedron,
    rounding: Option<&Rounding>,
    pose: &Isometry3<f64>,
) -> (Point3<f64>, Point3<f64>) {
    let Some(rounding) = rounding else {
        return part_aabb(polyhedron, pose);
    };
    let (min, max) = match rounding.segment() {
        Some([p, q]) => {
            let (p_world, q_world) = (pose * p, pose * q);
            (p_world.inf(&q_world), p_world.sup(&q_world))
        }
        None => part_aabb(polyhedron, pose),
    };
    let grow = Vector3::repeat(rounding.radius);
    (min - grow, max + grow)
}

pub(crate) fn check_translation(translation: &Vector3<f64>) -> Result<(), BodyError> {
    match translation.iter().position(|c| !c.is_finite()) {
        Some(component) => Err(BodyError::NonFiniteTranslation {
            component,
            value: translation[component],
        }),
        None => Ok(()),
    }
}

/// Validates a quaternion `[x, y, z, w]` and normalizes it.
pub(crate) fn unit_rotation(xyzw: [f64; 4]) -> Result<UnitQuaternion<f64>, BodyError> {
    if let Some(component) = xyzw.iter().position(|c| !c.is_finite()) {
        return Err(BodyError::NonFiniteRotation {
            component,
            value: xyzw[component],
        });
    }
    let [x, y, z, w] = xyzw;
    let quaternion = Quaternion::new(w, x, y, z);
    let norm = quaternion.norm();
    if (norm - 1.0).abs() > UNIT_QUATERNION_TOLERANCE {
        return Err(BodyError::RotationNotUnit { norm });
    }
    Ok(UnitQuaternion::from_quaternion(quaternion))
}

fn xyzw_of(rotation: &UnitQuaternion<f64>) -> [f64; 4] {
    let q = rotation.quaternion();
    [q.i, q.j, q.k, q.w]
}

fn com_pose_of(
    translation_user: &Vector3<f64>,
    rotation: UnitQuaternion<f64>,
    origin_offset: &Vector3<f64>,
) -> Isometry3<f64> {
    let t_com = translation_user + rotation * origin_offset;
    Isometry3::from_parts(Translation3::from(t_com), rotation)
}

fn body_mass(spec: MassSpec, solid: &Solid) -> Result<Option<BodyMass>, BodyError> {
    let volume = solid.volume;
    let (mass, density) = match spec {
        MassSpec::Fixed => return Ok(None),
        MassSpec::Mass(m) if m.is_finite() && m > 0.0 => (m, m / volume),
        MassSpec::Mass(m) => return Err(BodyError::InvalidMass(m)),
        MassSpec::Density(rho) if rho.is_finite() && rho > 0.0 => (rho * volume, rho),
        MassSpec::Density(rho) => return Err(BodyError::InvalidDensity(rho)),
    };
    let inertia_body = solid.inertia_unit_density * density;
    let inverse_inertia_body = inertia_body
        .try_inverse()
        .unwrap_or(Matrix3::from_element(f64::NAN));
    let all_finite = |m: &Matrix3<f64>| m.iter().all(|c| c.is_finite());
    let usable = mass.is_finite()
        && mass > 0.0
        && density.is_finite()
        && density > 0.0
        && all_finite(&inertia_body)
        && all_finite(&inverse_inertia_body);
    if !usable {
        return Err(BodyError::DegenerateMass {
            given: spec,
            volume,
        });
    }
    Ok(Some(BodyMass {
        mass,
        density,
        inertia_body,
        inverse_inertia_body,
    }))
}
