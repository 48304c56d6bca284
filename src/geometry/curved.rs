//! Cylinders and cones: their true solids ([`CurvedSolid`], the default
//! narrow phase's: support function, outline, signed distance of a point)
//! and the polyhedra that bound them within a stated deviation (the narrow
//! phase's with `VClipSettings::curved_support_functions` off;
//! `docs/round-shapes.md`, "Cylinders and cones").
//!
//! The circle of radius `r` is replaced by the regular `N`-gon
//! *circumscribed* about it: its edges touch the circle and its vertices
//! lie at `r / cos(π/N)`. The polygon holds the circle, so the polyhedron
//! holds the solid (a correction that separates the polyhedra separates the
//! true shapes too), and no point of its surface is farther from the true
//! surface than `r (1/cos(π/N) - 1)`. `N` is the least number of sides for
//! which that deviation is at most [`CURVED_DEVIATION_RELATIVE`] of `r`:
//!
//! ```text
//! N = ceil( π / acos( 1 / (1 + ε) ) )      (ε = 1e-3: N = 71)
//! ```
//!
//! The flat faces (a cylinder's two caps, a cone's base) are exact, so a
//! cylinder standing on its cap rests exactly; only contacts on the curved
//! side are approximate. Mass properties are the true solid's, in closed
//! form (`round_mass`).

use std::f64::consts::PI;

use nalgebra::{Point3, Vector3};

use super::{ConvexPolyhedron, GeometryError};

/// The largest distance between the polyhedral approximation of a
/// cylinder's or cone's curved surface and the true surface, relative to
/// the radius (module docs). The narrow phase's depths on curved sides
/// exceed the true depth by at most this times the radius.
pub const CURVED_DEVIATION_RELATIVE: f64 = 1e-3;

/// Number of sides of the circumscribed polygon for relative deviation
/// `deviation` (module docs), at least 3.
pub fn sides_for(deviation: f64) -> usize {
    let half_angle = (1.0 / (1.0 + deviation)).acos();
    // The ratio is finite and positive for any deviation > 0, the count
    // small (71 at 1e-3); `as` saturates for an absurdly small deviation.
    ((PI / half_angle).ceil() as usize).max(3)
}

/// The deviation, relative to the radius, of the circumscribed polygon of
/// `sides` sides: `1/cos(π/N) - 1`.
pub fn deviation_of(sides: usize) -> f64 {
    1.0 / (PI / sides as f64).cos() - 1.0
}

fn ring(radius: f64, sides: usize, z: f64) -> impl Iterator<Item = Point3<f64>> {
    let circumradius = circumradius(radius, sides);
    (0..sides).map(move |i| {
        let angle = 2.0 * PI * i as f64 / sides as f64;
        Point3::new(circumradius * angle.cos(), circumradius * angle.sin(), z)
    })
}

fn circumradius(radius: f64, sides: usize) -> f64 {
    radius * (1.0 + deviation_of(sides))
}

/// The cylinder along `z` of half height `half_height` and radius
/// `radius`, as the prism over the circumscribed polygon.
pub fn cylinder(half_height: f64, radius: f64) -> Result<ConvexPolyhedron, GeometryError> {
    check_positive("half_height", half_height)?;
    check_positive("radius", radius)?;
    let sides = sides_for(CURVED_DEVIATION_RELATIVE);
    ConvexPolyhedron::disk(circumradius(radius, sides), 2.0 * half_height, sides)
}

/// The cone along `z` (base of radius `radius` at `z = -half_height`, apex
/// at `z = half_height`), as the pyramid over the circumscribed polygon.
pub fn cone(half_height: f64, radius: f64) -> Result<ConvexPolyhedron, GeometryError> {
    check_positive("half_height", half_height)?;
    check_positive("radius", radius)?;
    let sides = sides_for(CURVED_DEVIATION_RELATIVE);
    let mut points: Vec<Point3<f64>> = ring(radius, sides, -half_height).collect();
    points.push(Point3::new(0.0, 0.0, half_height));
    let apex = sides;
    let mut faces = vec![(0..sides).rev().collect::<Vec<_>>()];
    faces.extend((0..sides).map(|i| vec![i, (i + 1) % sides, apex]));
    ConvexPolyhedron::from_faces(points, faces)
}

fn check_positive(name: &'static str, value: f64) -> Result<(), GeometryError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(GeometryError::InvalidDimension { name, value })
    }
}

/// A cylinder or cone as its true solid, part frame (axis `z`, origin at
/// the centre of mass), for the support-function narrow phase
/// (`contact::round::support_pair`). The support function along a unit
/// `d = (d_xy, d_z)`, with `u = d_xy / |d_xy|` (any unit vector when
/// `d_xy = 0`):
///
/// ```text
/// cylinder:  s(d) = r u + sign(d_z) h z
/// cone:      s(d) = argmax over { apex (0, 0, h - z_c), rim r u - (h + z_c) z } of d . p
/// ```
///
/// with the cone's centre of mass `z_c = -h/2` below the middle of its
/// axis (a quarter of the height `2h` above the base).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CurvedSolid {
    /// The cylinder `|z| <= h`, `x^2 + y^2 <= r^2`.
    Cylinder {
        /// Half the height `h`.
        half_height: f64,
        /// Radius `r`.
        radius: f64,
    },
    /// The cone of base radius `r` at `z = -h` and apex at `z = h` in its
    /// shape frame (the part frame is shifted down by `h/2`).
    Cone {
        /// Half the height `h`.
        half_height: f64,
        /// Base radius `r`.
        radius: f64,
    },
}

impl CurvedSolid {
    /// The radius.
    pub fn radius(&self) -> f64 {
        match *self {
            CurvedSolid::Cylinder { radius, .. } | CurvedSolid::Cone { radius, .. } => radius,
        }
    }

    /// Height of the base and the top above the part origin: `(-h, h)`
    /// for a cylinder; the cone's base at `-h/2`, apex at `3h/2` (its
    /// centre of mass a quarter of the height above the base).
    fn base_and_top(&self) -> (f64, f64) {
        match *self {
            CurvedSolid::Cylinder { half_height, .. } => (-half_height, half_height),
            CurvedSolid::Cone { half_height, .. } => (-0.5 * half_height, 1.5 * half_height),
        }
    }

    /// Largest distance of a point of the solid from the part origin.
    pub fn reach(&self) -> f64 {
        let (base, top) = self.base_and_top();
        (base * base + self.radius().powi(2)).sqrt().max(top.abs())
    }

    /// Unit radial direction of `d` (`x` when `d` is along the axis).
    fn radial(d: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(d.x, d.y, 0.0)
            .try_normalize(0.0)
            .unwrap_or_else(Vector3::x)
    }

    /// The support point along `d` (any length), part frame (type docs).
    pub fn support(&self, d: &Vector3<f64>) -> Point3<f64> {
        let (base, top) = self.base_and_top();
        let rim = Self::radial(d) * self.radius();
        match self {
            CurvedSolid::Cylinder { .. } => {
                let z = if d.z >= 0.0 { top } else { base };
                Point3::new(rim.x, rim.y, z)
            }
            CurvedSolid::Cone { .. } => {
                let apex = Point3::new(0.0, 0.0, top);
                let on_rim = Point3::new(rim.x, rim.y, base);
                if d.dot(&apex.coords) >= d.dot(&on_rim.coords) {
                    apex
                } else {
                    on_rim
                }
            }
        }
    }

    /// The cone's apex, part frame (`None` for a cylinder).
    pub fn apex(&self) -> Option<Point3<f64>> {
        match self {
            CurvedSolid::Cylinder { .. } => None,
            CurvedSolid::Cone { .. } => Some(Point3::new(0.0, 0.0, self.base_and_top().1)),
        }
    }

    /// Points of a cap resting flat on a face: the `samples` points of
    /// each rim circle (evenly spaced, on the true circle), part frame.
    pub fn outline(&self, samples: usize) -> Vec<Point3<f64>> {
        let (base, top) = self.base_and_top();
        let circle = |z: f64| {
            (0..samples).map(move |i| {
                let angle = 2.0 * PI * i as f64 / samples as f64;
                Point3::new(angle.cos(), angle.sin(), 0.0) * self.radius() + Vector3::z() * z
            })
        };
        match self {
            CurvedSolid::Cylinder { .. } => circle(base).chain(circle(top)).collect(),
            CurvedSolid::Cone { .. } => circle(base).collect(),
        }
    }

    /// The signed distance of `p` (part frame) to the solid's surface
    /// (negative inside), the nearest surface point and the outward unit
    /// normal there (module `contact::round::point_distance`). The solid
    /// is turned about its axis, so this is the distance in the half plane
    /// `(rho, z)` through the axis and `p` to the profile: the rectangle
    /// `[0, r] x [base, top]` (cylinder) or the triangle
    /// `(0, base), (r, base), (0, top)` (cone), whose edge on the axis is
    /// no surface. `None` when the normal is undefined (a point exactly on
    /// the rim or apex is handled; only non-finite input fails).
    pub fn signed_distance(&self, p: &Point3<f64>) -> Option<SurfaceDistance> {
        let (base, top) = self.base_and_top();
        let r = self.radius();
        let u = Self::radial(&p.coords);
        let rho = (p.x * p.x + p.y * p.y).sqrt();
        let lift = |rho: f64, z: f64| Point3::from(u * rho + Vector3::z() * z);
        let turn = |d_rho: f64, d_z: f64| u * d_rho + Vector3::z() * d_z;
        // The profile's surface edges, from the axis round to the axis:
        // (start, end) in (rho, z), with the outward unit normal.
        let slant = {
            let height = top - base;
            let norm = (height * height + r * r).sqrt();
            (height / norm, r / norm)
        };
        let edges: &[ProfileEdge] = match self {
            CurvedSolid::Cylinder { .. } => &[
                ((0.0, base), (r, base), (0.0, -1.0)),
                ((r, base), (r, top), (1.0, 0.0)),
                ((r, top), (0.0, top), (0.0, 1.0)),
            ],
            CurvedSolid::Cone { .. } => &[
                ((0.0, base), (r, base), (0.0, -1.0)),
                ((r, base), (0.0, top), slant),
            ],
        };
        // Inside: the largest edge-line value (each edge's nearest point
        // from inside lies on the edge, the profile being convex).
        let (inside_value, inside_normal) = edges
            .iter()
            .map(|&((s_rho, s_z), _, (n_rho, n_z))| {
                (n_rho * (rho - s_rho) + n_z * (p.z - s_z), (n_rho, n_z))
            })
            .max_by(|x, y| x.0.total_cmp(&y.0))?;
        if !inside_value.is_finite() {
            return None;
        }
        if inside_value <= 0.0 {
            let normal = turn(inside_normal.0, inside_normal.1);
            return Some(SurfaceDistance {
                signed: inside_value,
                closest: p - normal * inside_value,
                normal,
                flat: inside_normal.0 == 0.0,
            });
        }
        // Outside: the nearest point of the edges.
        let (distance, (c_rho, c_z), on_cap) = edges
            .iter()
            .map(|&((s_rho, s_z), (e_rho, e_z), (n_rho, _))| {
                let (d_rho, d_z) = (e_rho - s_rho, e_z - s_z);
                let length_squared = d_rho * d_rho + d_z * d_z;
                let t = ((rho - s_rho) * d_rho + (p.z - s_z) * d_z) / length_squared;
                let t = if t.is_finite() {
                    t.clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let (c_rho, c_z) = (s_rho + t * d_rho, s_z + t * d_z);
                let on_cap = n_rho == 0.0 && c_rho < r;
                ((rho - c_rho).hypot(p.z - c_z), (c_rho, c_z), on_cap)
            })
            .min_by(|x, y| x.0.total_cmp(&y.0))?;
        let closest = lift(c_rho, c_z);
        let normal = (p - closest).try_normalize(0.0)?;
        Some(SurfaceDistance {
            signed: distance,
            closest,
            normal,
            flat: on_cap,
        })
    }
}

/// A point or a direction in the half plane `(rho, z)` through the axis.
type InPlane = (f64, f64);

/// An edge of a profile in the half plane through the axis: its start,
/// its end and its outward unit normal.
type ProfileEdge = (InPlane, InPlane, InPlane);

/// The signed distance of a point to a solid's surface (negative inside),
/// the nearest surface point, the outward unit normal there, and whether
/// that point lies on a flat piece of the surface (a face or a cap, not an
/// edge, a rim or a curved side), frame of the solid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceDistance {
    /// Distance (negative inside).
    pub signed: f64,
    /// The nearest surface point.
    pub closest: Point3<f64>,
    /// Unit outward normal at `closest` (towards the point outside).
    pub normal: Vector3<f64>,
    /// Whether `closest` lies inside a flat face or cap.
    pub flat: bool,
}

impl CurvedSolid {
    /// The side line facing `d` (part frame), from the base rim to the top
    /// rim (cylinder) or the apex (cone): where a solid lying on its side
    /// touches a plane of normal `-d`.
    pub fn side_line(&self, d: &Vector3<f64>) -> [Point3<f64>; 2] {
        let (base, top) = self.base_and_top();
        let rim = Self::radial(d) * self.radius();
        let top_point = match self {
            CurvedSolid::Cylinder { .. } => Point3::new(rim.x, rim.y, top),
            CurvedSolid::Cone { .. } => Point3::new(0.0, 0.0, top),
        };
        [Point3::new(rim.x, rim.y, base), top_point]
    }
}
