//! A part's core as a support function, world frame: what the
//! support-function narrow phase (`support_pair`) needs of any shape kind.
//!
//! Every part is a core grown by a radius `r >= 0` (`geometry::round`);
//! cylinders and cones are their true solids with `r = 0`
//! (`geometry::curved::CurvedSolid`). For a unit world direction `d` the
//! core's support point is `s(d) = T s_local(R^T d)` and its support
//! function `h(d) = d . s(d)`:
//!
//! | core | `s_local(d)` |
//! |---|---|
//! | polyhedron | the vertex of largest `d . v` |
//! | point | the origin |
//! | segment `[-l z, l z]` | the end of larger `d . p` |
//! | cylinder, cone | `CurvedSolid::support` |
//!
//! The support function needs one rotation: with `d_local = R^T d`,
//! `h(d) = d_local . s_local(d_local) + d . t`. The rotation is kept as a
//! matrix (`rotation`), cheaper to apply than the pose's quaternion in the
//! hundreds of evaluations of a pattern search.
//!
//! The outline (`outline`) is the finite set of surface points a flat
//! contact may rest on, for a contact along `d`: a polyhedron's vertices, a
//! segment's ends, a curved solid's rim samples when the rim is flat to
//! the contact (a cap resting on a face), a cone's apex, and the ends of
//! its side line facing `d` (which realize a cylinder lying on its side
//! exactly).

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use parry3d_f64::math::Vector as ParryVector;
use parry3d_f64::shape::SupportMap;

use super::super::BodyGeometry;
use crate::geometry::ConvexPolyhedron;
use crate::geometry::curved::CurvedSolid;
use crate::geometry::round::RoundCore;

/// Points sampled on each rim circle of a cylinder or cone for its outline
/// (a cap resting on a face gets rows at up to four of them, chosen by
/// `support_manifold`).
pub const RIM_SAMPLES: usize = 16;

/// The kind of a core.
#[derive(Debug, Clone, Copy)]
pub enum CoreShape<'a> {
    /// A polyhedron (plain, or a rounded cuboid's or hull's core).
    Polyhedron(&'a ConvexPolyhedron),
    /// The part's origin (a sphere's core).
    Point,
    /// The segment `[-half_length z, half_length z]` (a capsule's core).
    Segment {
        /// Half its length.
        half_length: f64,
    },
    /// A cylinder's or cone's true solid.
    Curved(CurvedSolid),
}

/// A core at its world pose, with the radius that grows it.
#[derive(Debug, Clone, Copy)]
pub struct PosedCore<'a> {
    /// The core.
    pub core: CoreShape<'a>,
    /// Part frame to world.
    pub pose: Isometry3<f64>,
    /// The pose's rotation as a matrix (`R`, part frame to world).
    pub rotation: Matrix3<f64>,
    /// The radius grown around the core (0 for a cylinder or cone).
    pub radius: f64,
}

impl<'a> PosedCore<'a> {
    /// The core of a part as the narrow phase sees it.
    pub fn of(geometry: &BodyGeometry<'a>) -> Self {
        let (core, radius) = match (geometry.curved, geometry.rounding) {
            (Some(curved), _) => (CoreShape::Curved(curved), 0.0),
            (None, Some(rounding)) => (
                match rounding.core {
                    RoundCore::Point => CoreShape::Point,
                    RoundCore::Segment { half_length } => CoreShape::Segment { half_length },
                    RoundCore::Polyhedron => CoreShape::Polyhedron(geometry.shape),
                },
                rounding.radius,
            ),
            (None, None) => (CoreShape::Polyhedron(geometry.shape), 0.0),
        };
        PosedCore {
            core,
            pose: geometry.pose,
            rotation: geometry.pose.rotation.to_rotation_matrix().into_inner(),
            radius,
        }
    }

    /// Largest distance of a point of the core from the part origin.
    pub fn reach(&self) -> f64 {
        match &self.core {
            CoreShape::Polyhedron(polyhedron) => polyhedron.scale(),
            CoreShape::Point => 0.0,
            CoreShape::Segment { half_length } => *half_length,
            CoreShape::Curved(curved) => curved.reach(),
        }
    }

    /// The axis of a cylinder, cone or segment, world frame: the support
    /// point jumps where `n` crosses the great circle perpendicular to it
    /// (a side's straight lines, a segment's two ends), a ridge of the
    /// overlap.
    pub fn ridge_axis(&self) -> Option<Vector3<f64>> {
        match self.core {
            CoreShape::Curved(_) | CoreShape::Segment { .. } => {
                Some(self.pose.rotation * Vector3::z())
            }
            _ => None,
        }
    }

    fn support_local(&self, d: &Vector3<f64>) -> Point3<f64> {
        match &self.core {
            CoreShape::Polyhedron(polyhedron) => {
                let mut best = Point3::origin();
                let mut best_value = f64::NEG_INFINITY;
                for v in polyhedron.vertices() {
                    let value = d.dot(&v.coords);
                    if value > best_value {
                        best_value = value;
                        best = *v;
                    }
                }
                best
            }
            CoreShape::Point => Point3::origin(),
            CoreShape::Segment { half_length } => Point3::new(0.0, 0.0, half_length.copysign(d.z)),
            CoreShape::Curved(curved) => curved.support(d),
        }
    }

    /// The core's support point along world direction `d` (any length).
    pub fn support(&self, d: &Vector3<f64>) -> Point3<f64> {
        let local = self.support_local(&self.rotation.tr_mul(d));
        Point3::from(self.rotation * local.coords + self.pose.translation.vector)
    }

    /// The core's support function `h(d) = d . s(d)`, with one rotation
    /// (module docs).
    pub fn support_value(&self, d: &Vector3<f64>) -> f64 {
        let d_local = self.rotation.tr_mul(d);
        d_local.dot(&self.support_local(&d_local).coords) + d.dot(&self.pose.translation.vector)
    }

    /// Surface points of the core a flat contact along unit world
    /// direction `d` may rest on, world frame (module docs); a rim's
    /// samples only when the whole rim lies within `flat` of the plane
    /// perpendicular to `d` (its height range `2 r sin` of its tilt).
    pub fn outline(&self, d: &Vector3<f64>, flat: f64) -> Vec<Point3<f64>> {
        let local: Vec<Point3<f64>> = match &self.core {
            CoreShape::Polyhedron(polyhedron) => polyhedron.vertices().to_vec(),
            CoreShape::Point => vec![Point3::origin()],
            CoreShape::Segment { half_length } => vec![
                Point3::new(0.0, 0.0, -half_length),
                Point3::new(0.0, 0.0, *half_length),
            ],
            CoreShape::Curved(curved) => {
                let d_local = self.pose.rotation.inverse_transform_vector(d);
                let tilt_sine = (1.0 - d_local.z * d_local.z).max(0.0).sqrt();
                let mut points = curved.outline(RIM_SAMPLES);
                if 2.0 * curved.radius() * tilt_sine > flat {
                    points.clear();
                }
                points.extend(curved.apex());
                points.extend(curved.side_line(&d_local));
                points
            }
        };
        local.into_iter().map(|p| self.pose * p).collect()
    }
}

impl SupportMap for PosedCore<'_> {
    /// The world support point: the pair is given to parry with both
    /// shapes in the world frame (identity relative pose).
    fn local_support_point(&self, dir: ParryVector) -> ParryVector {
        let p = self.support(&Vector3::new(dir.x, dir.y, dir.z));
        ParryVector::new(p.x, p.y, p.z)
    }
}
