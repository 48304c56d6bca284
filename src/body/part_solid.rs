//! One convex shape's solid: the polyhedron the narrow phase works on, its
//! rounding (round shapes, `geometry::round`) and its mass properties at
//! unit density.
//!
//! The part's frame is its polyhedron's body frame (origin at the
//! polyhedron's centre of mass, axes of the shape frame). The solid's
//! centre of mass is that origin for every shape but a rounded hull, whose
//! rounding moves it (its mass properties are those of an inscribed
//! approximation, `geometry::round_mass`); the body then holds the part
//! with an offset.
//!
//! | shape | polyhedron | rounding | mass properties |
//! |---|---|---|---|
//! | cuboid, hull | the shape | none | the polyhedron's |
//! | sphere, capsule | the box that holds the solid (never queried) | point / segment core | closed form |
//! | rounded cuboid | the cuboid (the core) | polyhedron core | closed form |
//! | rounded hull | the hull (the core) | polyhedron core | inscribed approximation |
//! | cylinder, cone | circumscribed approximation (`geometry::curved`) | none | closed form of the true solid |
//!
//! A cylinder's or cone's true solid (the support-function narrow
//! phase's) is not stored: [`curved_solid`] reads it off the shape.

use std::sync::Arc;

use nalgebra::{Matrix3, Point3, Vector3};

use super::Shape;
use crate::geometry::{
    ConvexPolyhedron, GeometryError, MassProperties, RoundCore, Rounding, curved,
    curved::CurvedSolid, round, round_mass,
};

/// A convex shape's solid (module docs).
#[derive(Debug, Clone)]
pub(crate) struct PartSolid {
    pub polyhedron: Arc<ConvexPolyhedron>,
    pub rounding: Option<Rounding>,
    /// Volume.
    pub volume: f64,
    /// Centre of mass in the shape frame.
    pub com_shape: Vector3<f64>,
    /// Inertia about the centre of mass at unit density, shape axes.
    pub inertia_unit_density: Matrix3<f64>,
}

impl PartSolid {
    /// A plain polyhedron's solid.
    pub fn polyhedral(polyhedron: Arc<ConvexPolyhedron>) -> Self {
        let mass = *polyhedron.mass_properties();
        PartSolid {
            volume: mass.volume,
            com_shape: polyhedron.shape_origin_offset(),
            inertia_unit_density: mass.inertia_unit_density,
            polyhedron,
            rounding: None,
        }
    }

    /// The polyhedron's origin (the part frame) relative to the solid's
    /// centre of mass, shape axes: zero but for a rounded hull.
    pub fn frame_from_com(&self) -> Vector3<f64> {
        self.polyhedron.shape_origin_offset() - self.com_shape
    }

    /// The solid of a convex shape ([`GeometryError::NotConvex`] for a
    /// compound).
    pub fn build(shape: &Shape) -> Result<Self, GeometryError> {
        let at_frame = |polyhedron: ConvexPolyhedron, rounding, mass: MassProperties| {
            let polyhedron = Arc::new(polyhedron);
            PartSolid {
                volume: mass.volume,
                com_shape: polyhedron.shape_origin_offset(),
                inertia_unit_density: mass.inertia_unit_density,
                polyhedron,
                rounding,
            }
        };
        let rounded = |core: RoundCore, radius: f64| Some(Rounding { core, radius });
        Ok(match shape {
            Shape::Cuboid { .. } | Shape::ConvexHull { .. } => {
                Self::polyhedral(Arc::new(shape.build()?))
            }
            Shape::Sphere { radius } => {
                check_positive("radius", *radius)?;
                at_frame(
                    round::bounding_box(0.0, *radius)?,
                    rounded(RoundCore::Point, *radius),
                    round_mass::sphere(*radius),
                )
            }
            Shape::Capsule {
                half_height,
                radius,
            } => {
                check_positive("half_height", *half_height)?;
                check_positive("radius", *radius)?;
                at_frame(
                    round::bounding_box(*half_height, *radius)?,
                    rounded(
                        RoundCore::Segment {
                            half_length: *half_height,
                        },
                        *radius,
                    ),
                    round_mass::capsule(*half_height, *radius),
                )
            }
            Shape::RoundCuboid {
                half_extents,
                radius,
            } => {
                round::check_radius(*radius)?;
                at_frame(
                    ConvexPolyhedron::cuboid(*half_extents)?,
                    rounded(RoundCore::Polyhedron, *radius),
                    round_mass::rounded_cuboid(half_extents, *radius),
                )
            }
            Shape::RoundConvexHull { points, radius } => {
                round::check_radius(*radius)?;
                Self::rounded_hull(ConvexPolyhedron::from_points(points)?, *radius)?
            }
            Shape::Cylinder {
                half_height,
                radius,
            } => at_frame(
                curved::cylinder(*half_height, *radius)?,
                None,
                round_mass::cylinder(*half_height, *radius),
            ),
            Shape::Cone {
                half_height,
                radius,
            } => at_frame(
                curved::cone(*half_height, *radius)?,
                None,
                round_mass::cone(*half_height, *radius),
            ),
            Shape::Compound { .. } => {
                return Err(GeometryError::NotConvex(
                    "a compound has one polyhedron per part".into(),
                ));
            }
        })
    }

    /// A hull grown by `radius`: mass properties of the inscribed
    /// approximation (`geometry::round_mass`), centre of mass in the shape
    /// frame.
    fn rounded_hull(core: ConvexPolyhedron, radius: f64) -> Result<Self, GeometryError> {
        let core = Arc::new(core);
        let rounding = Some(Rounding {
            core: RoundCore::Polyhedron,
            radius,
        });
        if radius == 0.0 {
            return Ok(PartSolid {
                rounding,
                ..Self::polyhedral(core)
            });
        }
        let directions: Vec<Vector3<f64>> =
            ConvexPolyhedron::geodesic_sphere(1.0, round_mass::ROUNDED_HULL_SUBDIVISIONS)?
                .vertices()
                .iter()
                .map(|v| v.coords.normalize())
                .collect();
        // Vertices in the core's frame: the approximation's centre of mass
        // comes out in that frame, shifted to the shape frame below.
        let points = round_mass::rounded_hull_points(&core, radius, &directions);
        let approximation = ConvexPolyhedron::from_points(&points)?;
        let mass = approximation.mass_properties();
        let com_core: Point3<f64> = Point3::from(approximation.shape_origin_offset());
        Ok(PartSolid {
            volume: mass.volume,
            com_shape: core.shape_origin_offset() + com_core.coords,
            inertia_unit_density: mass.inertia_unit_density,
            polyhedron: core,
            rounding,
        })
    }
}

fn check_positive(name: &'static str, value: f64) -> Result<(), GeometryError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(GeometryError::InvalidDimension { name, value })
    }
}

/// A cylinder's or cone's true solid, read off its shape (part frame:
/// the shape's `z` axis, origin at the centre of mass); `None` for every
/// other shape.
pub fn curved_solid(shape: &Shape) -> Option<CurvedSolid> {
    match *shape {
        Shape::Cylinder {
            half_height,
            radius,
        } => Some(CurvedSolid::Cylinder {
            half_height,
            radius,
        }),
        Shape::Cone {
            half_height,
            radius,
        } => Some(CurvedSolid::Cone {
            half_height,
            radius,
        }),
        _ => None,
    }
}
