//! The round and curved shapes of scene files:
//!
//! ```text
//! {"sphere": 0.5}
//! {"capsule":  {"half_height": 1.0, "radius": 0.25}}     (axis z)
//! {"cylinder": {"half_height": 1.0, "radius": 0.25}}     (axis z)
//! {"cone":     {"half_height": 1.0, "radius": 0.25}}     (base at -z)
//! {"cuboid": [1, 2, 3], "radius": 0.1}                   (rounded cuboid)
//! {"convex_hull": [[0,0,0], ...], "radius": 0.1}         (rounded hull)
//! ```
//!
//! Strict like the rest: an unknown or missing key, a wrong type, a
//! `radius` beside anything but a cuboid or a hull, and every value that
//! [`crate::body::Body::new`] rejects (a negative or NaN radius) are
//! errors naming the field.

use serde::Serialize;
use serde_json::{Map, Value};

use super::scene_file::FieldProblem;
use crate::body::Shape;

/// The shape kinds this file reads, besides `cuboid`, `convex_hull` and
/// `compound`.
pub(super) const ROUND_KINDS: [&str; 4] = ["sphere", "capsule", "cylinder", "cone"];

/// The key of a rounding beside `cuboid` or `convex_hull`.
pub(super) const RADIUS: &str = "radius";

/// Where a problem was found: the field (relative to the shape) and what.
pub(super) type Problem = (String, FieldProblem);

/// The round shape under `key` (one of [`ROUND_KINDS`]).
pub(super) fn parse_round(key: &str, value: &Value) -> Result<Shape, Problem> {
    if key == "sphere" {
        let radius = value.as_f64().ok_or_else(|| {
            (
                key.to_string(),
                FieldProblem::WrongType("a number (the radius)"),
            )
        })?;
        return Ok(Shape::Sphere { radius });
    }
    let expected = "an object {\"half_height\": h, \"radius\": r}";
    let object = value
        .as_object()
        .ok_or_else(|| (key.to_string(), FieldProblem::WrongType(expected)))?;
    if let Some(unknown) = object
        .keys()
        .find(|k| !["half_height", RADIUS].contains(&k.as_str()))
    {
        return Err((format!("{key}.{unknown}"), FieldProblem::Unknown));
    }
    let number = |name: &str| -> Result<f64, Problem> {
        let at = || format!("{key}.{name}");
        let value = object
            .get(name)
            .ok_or_else(|| (at(), FieldProblem::Missing))?;
        value
            .as_f64()
            .ok_or_else(|| (at(), FieldProblem::WrongType("a number")))
    };
    let (half_height, radius) = (number("half_height")?, number(RADIUS)?);
    Ok(match key {
        "capsule" => Shape::Capsule {
            half_height,
            radius,
        },
        "cylinder" => Shape::Cylinder {
            half_height,
            radius,
        },
        _ => Shape::Cone {
            half_height,
            radius,
        },
    })
}

/// The rounding of a cuboid or hull: `shape` read without its radius, and
/// the shape object's `radius`, if any.
pub(super) fn with_radius(shape: Shape, object: &Map<String, Value>) -> Result<Shape, Problem> {
    let Some(value) = object.get(RADIUS) else {
        return Ok(shape);
    };
    let radius = value
        .as_f64()
        .ok_or_else(|| (RADIUS.to_string(), FieldProblem::WrongType("a number")))?;
    match shape {
        Shape::Cuboid { half_extents } => Ok(Shape::RoundCuboid {
            half_extents,
            radius,
        }),
        Shape::ConvexHull { points } => Ok(Shape::RoundConvexHull { points, radius }),
        _ => Err((
            RADIUS.to_string(),
            FieldProblem::Conflict("a radius is given only with `cuboid` or `convex_hull`"),
        )),
    }
}

/// An axial shape as written.
#[derive(Serialize)]
pub(super) struct AxialOut {
    half_height: f64,
    radius: f64,
}

impl AxialOut {
    pub(super) fn new(half_height: f64, radius: f64) -> Self {
        AxialOut {
            half_height,
            radius,
        }
    }
}

/// The core of a rounded cuboid or hull as written, beside its `radius`.
#[derive(Serialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum CoreOut {
    Cuboid([f64; 3]),
    ConvexHull(Vec<[f64; 3]>),
}
