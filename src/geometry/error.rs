//! Errors when building a polyhedron from user data.

use thiserror::Error;

/// Why a convex polyhedron could not be built.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GeometryError {
    /// No points were given.
    #[error("the point set is empty")]
    Empty,
    /// A coordinate is NaN or infinite.
    #[error("point {index} has a non-finite coordinate")]
    NonFinite {
        /// Index of the offending point in the input.
        index: usize,
    },
    /// The points do not span a solid: fewer than four non-coplanar points
    /// remain after nearly duplicate points are merged.
    #[error("fewer than four non-coplanar points: the hull has no volume")]
    Degenerate,
    /// Coordinates beyond `geometry::MAX_COORDINATE`, or distinct points
    /// spanning less than `geometry::MIN_EXTENT`: mass properties or the
    /// hull's exact predicates would overflow or underflow.
    #[error("coordinates up to {largest:e} spanning {extent:e} are out of the supported range")]
    CoordinatesOutOfRange {
        /// The largest absolute coordinate given.
        largest: f64,
        /// The extent (bounding-box diagonal) of the points.
        extent: f64,
    },
    /// The hull algorithm failed numerically (a typed error instead of a
    /// panic or a wrong hull; see `geometry::hull`).
    #[error("convex hull failed: {0}")]
    HullFailed(String),
    /// A shape parameter (radius, thickness, ...) is not a finite positive
    /// number.
    #[error("{name} is {value}: it must be finite and positive")]
    InvalidDimension {
        /// Name of the parameter.
        name: &'static str,
        /// The value that was given.
        value: f64,
    },
    /// A count parameter (polygon sides, subdivisions) is out of range.
    #[error("{name} is {value}: it must be in {min}..={max}")]
    InvalidCount {
        /// Name of the parameter.
        name: &'static str,
        /// The value that was given.
        value: usize,
        /// Smallest accepted value.
        min: usize,
        /// Largest accepted value.
        max: usize,
    },
    /// A cuboid half extent is not a finite positive number.
    #[error("half extent {axis} is {value}: it must be finite and positive")]
    InvalidHalfExtent {
        /// Axis index (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// The value that was given.
        value: f64,
    },
    /// A rounding radius is negative or not finite.
    #[error("radius is {value}: it must be finite and nonnegative")]
    InvalidRadius {
        /// The value that was given.
        value: f64,
    },
    /// The face cycles do not describe a closed two-manifold of genus 0.
    #[error("invalid topology: {0}")]
    InvalidTopology(String),
    /// A vertex lies outside a face plane, or a face is not planar.
    #[error("not convex: {0}")]
    NotConvex(String),
}
