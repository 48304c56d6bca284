//! Scene files (JSON, `docs/design.md` section 6), feature `serde`.
//!
//! ```text
//! { "bodies": [ { "name": "ground", "shape": { "cuboid": [10.0, 0.5, 10.0] },
//!                 "translation": [0.0, -0.5, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0],
//!                 "fixed": true },
//!               { "name": "rock", "shape": { "convex_hull": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]] },
//!                 "translation": [0.2, 0.1, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0],
//!                 "mass": 2.5 } ],
//!   "settings": { "tolerance": 1e-6 } }
//! ```
//!
//! - A body has `name`, `shape`, `translation`, `rotation` (quaternion
//!   `[x, y, z, w]`), and either `"fixed": true` or exactly one of `mass` and
//!   `density` (`"fixed": false` may be given with them; it is not written
//!   back); optionally its own Coulomb `friction` coefficient (finite,
//!   nonnegative; see [`crate::body::Body::set_friction`]). `shape` is `{"cuboid": half_extents}`, `{"convex_hull": points}`, a
//!   round or curved shape (`sphere`, `capsule`, `cylinder`, `cone`, or a
//!   `radius` beside `cuboid` or `convex_hull`: `io::round_shapes`) or
//!   `{"compound": [{"shape": ..., "translation": [x, y, z], "rotation": [x, y, z, w]}, ...]}`:
//!   one rigid body of several convex parts, each placed in the body's
//!   shape frame (a part's shape is any but a compound; at most
//!   [`MAX_COMPOUND_PARTS`] parts).
//! - `joints` is optional: an array of joints between the bodies, each
//!   with `name`, `type`, `bodies` (by unique name or index), `anchor_a`,
//!   `anchor_b`, an orientation per side (`rotation_a` or `axis_a` /
//!   `reference_a`), and `limits` or `locked` / `axis_limits` by type; at
//!   most [`MAX_JOINTS`]. The format and its checks are in
//!   [`super::scene_joints`].
//! - `settings` is optional, and so is each of its fields: `tolerance`,
//!   `contact_margin`, `target_margin`, `max_passes`, `solver`
//!   (`auto|clarabel|lemke|pgs`), `cross_check`, `method`
//!   (`projection|gauss_seidel`: the projection, the default, or the
//!   game-engine baseline of `stabilizer::gauss_seidel` with its defaults),
//!   `friction_model` (`pyramid|cone`, [`crate::FrictionModel`];
//!   friction itself is per body), `friction_rows`
//!   (`all|implied|generated`, [`crate::FrictionRows`]).
//! - Limits: a file of at most [`MAX_SCENE_FILE_BYTES`], at most
//!   [`MAX_BODIES`] bodies, at most [`MAX_HULL_POINTS`] points per hull;
//!   beyond them, an error before anything is built.
//! - An unknown or missing field is an error naming the body (index and
//!   name) and the field; a field given twice is an error with its line; so is a value of the wrong type, and every
//!   invalid value that [`crate::body::Body::new`] rejects.
//!
//! Numbers round-trip exactly: serde_json is built with `float_roundtrip`
//! (correctly rounded parsing) and writes the shortest representation that
//! parses back to the same `f64` (Ryu). A body the stabilizer did not move
//! keeps the translation and rotation it was read with, bit for bit, so
//! reading then writing an unchanged scene reproduces every number.
//!
//! Output may carry an extra top-level `report` (any JSON value). The reader
//! accepts and ignores it, so that an output file can be fed back in.
//!
//! The file's `settings` are returned in [`Scene::settings`]; they take
//! effect through [`crate::Stabilizer::for_scene`] (the defaults
//! overridden by the file's settings), not through
//! `Stabilizer::new(Settings::default())`.

use std::path::Path;

use nalgebra::{Point3, Vector3};
use serde::Serialize;
use serde_json::{Map, Value};
use thiserror::Error;

use super::object_reader::{Entry, ObjectReader};
use super::round_shapes::{self, AxialOut, CoreOut};
pub use super::scene_joints::MAX_JOINTS;
use super::scene_joints::{self, FrameProblem, JointOut};
use crate::body::{Body, BodyDesc, BodyError, MAX_COMPOUND_PARTS, MassSpec, Shape, ShapePart};
use crate::joints::JointError;
use crate::scene::Scene;
use crate::settings::{FrictionModel, FrictionRows};
use crate::settings::{Method, SceneSettings, SettingsError};
use crate::solver::SolverChoice;

const BODY_FIELDS: [&str; 8] = [
    "name",
    "shape",
    "translation",
    "rotation",
    "fixed",
    "mass",
    "density",
    "friction",
];
const TOP_FIELDS: [&str; 4] = ["bodies", "joints", "settings", "report"];
const SETTINGS_FIELDS: [&str; 9] = [
    "tolerance",
    "contact_margin",
    "target_margin",
    "max_passes",
    "solver",
    "cross_check",
    "method",
    "friction_model",
    "friction_rows",
];

/// What is wrong with one field.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FieldProblem {
    /// A required field is absent.
    #[error("missing")]
    Missing,
    /// The field is not part of the format.
    #[error("unknown field")]
    Unknown,
    /// The value has the wrong JSON type or length.
    #[error("expected {0}")]
    WrongType(&'static str),
    /// The field contradicts another one, or a choice is missing.
    #[error("{0}")]
    Conflict(&'static str),
    /// The value is of the right type but invalid.
    #[error("{0}")]
    InvalidBody(BodyError),
    /// A settings value is invalid.
    #[error("{0}")]
    InvalidSetting(SettingsError),
    /// A joint's value is of the right type but invalid.
    #[error("{0}")]
    InvalidJoint(JointError),
    /// A joint's anchor frame orientation cannot be built.
    #[error("{0}")]
    DegenerateFrame(FrameProblem),
    /// A joint names a body that does not exist (a name, or an index out of
    /// range).
    #[error("no body {0}")]
    UnknownBody(String),
    /// A joint names a body by a name that several bodies have.
    #[error("{count} bodies are named {name:?}: give the index")]
    AmbiguousBody {
        /// The name.
        name: String,
        /// How many bodies have it.
        count: usize,
    },
    /// A joint's `locked` or `axis_limits` names no axis.
    #[error("unknown axis {0:?} (x, y, z, angular_x, angular_y, angular_z)")]
    UnknownAxis(String),
    /// The field belongs to other joint types.
    #[error("not a field of a {0} joint")]
    NotForType(&'static str),
    /// An array has more entries than the format allows.
    #[error("{count} entries: at most {limit} are read")]
    TooMany {
        /// Entries given.
        count: usize,
        /// The limit ([`MAX_BODIES`], [`MAX_HULL_POINTS`], [`MAX_JOINTS`]).
        limit: usize,
    },
}

/// Why a scene file could not be read or written.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SceneFileError {
    /// The file could not be read.
    #[error("cannot read {path}: {message}")]
    Read {
        /// The path.
        path: String,
        /// The system's message.
        message: String,
    },
    /// The file is larger than [`MAX_SCENE_FILE_BYTES`]: refused before it
    /// is read (parsed JSON takes several times the file's size in memory).
    #[error("{path} is {bytes} bytes: scene files are limited to {limit} bytes")]
    TooLarge {
        /// The path.
        path: String,
        /// Its size (at least this many bytes).
        bytes: u64,
        /// [`MAX_SCENE_FILE_BYTES`].
        limit: u64,
    },
    /// The file could not be written.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The path.
        path: String,
        /// The system's message.
        message: String,
    },
    /// The text is not JSON, or an object repeats a key.
    #[error("invalid JSON at line {line}, column {column}: {message}")]
    Json {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// serde_json's message.
        message: String,
    },
    /// A top-level field (`bodies`, `settings`) is wrong.
    #[error("field `{field}`: {problem}")]
    TopLevel {
        /// The field (`(root)` for the document itself).
        field: String,
        /// What is wrong.
        problem: FieldProblem,
    },
    /// A field of a body is wrong.
    #[error(
        "body {index} ({}), field `{field}`: {problem}",
        .name.as_deref().map_or("unnamed".to_string(), |n| format!("{n:?}"))
    )]
    Body {
        /// Position of the body in `bodies`.
        index: usize,
        /// The body's name, if it has a string `name`.
        name: Option<String>,
        /// The field, e.g. `rotation` or `shape.cuboid`.
        field: String,
        /// What is wrong.
        problem: FieldProblem,
    },
    /// A field of a joint is wrong.
    #[error(
        "joint {index} ({}), field `{field}`: {problem}",
        .name.as_deref().map_or("unnamed".to_string(), |n| format!("{n:?}"))
    )]
    Joint {
        /// Position of the joint in `joints`.
        index: usize,
        /// The joint's name, if it has a string `name`.
        name: Option<String>,
        /// The field, e.g. `bodies[1]` or `axis_limits.angular_y`.
        field: String,
        /// What is wrong.
        problem: FieldProblem,
    },
    /// A field of `settings` is wrong.
    #[error("settings, field `{field}`: {problem}")]
    Settings {
        /// The field.
        field: String,
        /// What is wrong.
        problem: FieldProblem,
    },
}

/// Largest scene file [`read_scene`] reads: 128 MiB, room for
/// [`MAX_BODIES`] bodies as [`scene_to_string`] writes them (about 400
/// bytes each), so that an output file reads back. The parsed JSON takes
/// several times the text in memory. [`parse_scene`] on text already in
/// memory has no size limit (its counts are limited below).
pub const MAX_SCENE_FILE_BYTES: u64 = 128 * 1024 * 1024;

/// Most bodies a scene file may hold: 200,000. Checked before any body is
/// built. Reading takes about 5 KB of memory per body, so 200,000 take
/// about 1 GB (measured: `benchmarks/results/reliability.md`, "The limits
/// of scene files").
pub const MAX_BODIES: usize = 200_000;

/// Most points a `convex_hull` in a scene file may have: 10,000. Checked
/// before the hull is built. The hull's cost grows with the square of its
/// vertex count when every point is extreme (points on a sphere); points
/// mostly inside their hull cost far less, but no rigid body needs that
/// many (measured: `benchmarks/results/reliability.md`, "The limits of
/// scene files").
pub const MAX_HULL_POINTS: usize = 10_000;

/// Reads a scene file of at most [`MAX_SCENE_FILE_BYTES`]. Its settings are
/// in [`Scene::settings`]; build the stabilizer with
/// [`crate::Stabilizer::for_scene`] to apply them.
pub fn read_scene(path: &Path) -> Result<Scene, SceneFileError> {
    let read_error = |e: std::io::Error| SceneFileError::Read {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let file = std::fs::File::open(path).map_err(read_error)?;
    let too_large = |bytes| SceneFileError::TooLarge {
        path: path.display().to_string(),
        bytes,
        limit: MAX_SCENE_FILE_BYTES,
    };
    let announced = file.metadata().map_err(read_error)?.len();
    if announced > MAX_SCENE_FILE_BYTES {
        return Err(too_large(announced));
    }
    // The size may change while reading (or not be known, for a pipe):
    // read at most one byte past the limit.
    let mut text = String::new();
    std::io::Read::read_to_string(
        &mut std::io::Read::take(file, MAX_SCENE_FILE_BYTES + 1),
        &mut text,
    )
    .map_err(read_error)?;
    if text.len() as u64 > MAX_SCENE_FILE_BYTES {
        return Err(too_large(text.len() as u64));
    }
    parse_scene(&text)
}

/// Parses a scene from JSON text. A top-level `report` (as written by
/// [`scene_to_string`]) is accepted and ignored.
pub fn parse_scene(text: &str) -> Result<Scene, SceneFileError> {
    let document = super::strict_json::parse(text).map_err(|e| SceneFileError::Json {
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    let top = document.as_object().ok_or(SceneFileError::TopLevel {
        field: "(root)".into(),
        problem: FieldProblem::WrongType("an object"),
    })?;
    if let Some(field) = unknown_field(top, &TOP_FIELDS) {
        return Err(top_level(field, FieldProblem::Unknown));
    }
    let settings = match top.get("settings") {
        Some(value) => parse_settings(value)?,
        None => SceneSettings::default(),
    };
    let bodies = match top.get("bodies") {
        Some(Value::Array(bodies)) if bodies.len() > MAX_BODIES => {
            let problem = FieldProblem::TooMany {
                count: bodies.len(),
                limit: MAX_BODIES,
            };
            return Err(top_level("bodies", problem));
        }
        Some(Value::Array(bodies)) => bodies,
        Some(_) => return Err(top_level("bodies", FieldProblem::WrongType("an array"))),
        None => return Err(top_level("bodies", FieldProblem::Missing)),
    };
    let joints = scene_joints::joints_array(top)?;
    settings
        .validate()
        .map_err(|source| settings_error(source.field(), FieldProblem::InvalidSetting(source)))?;
    let mut scene = Scene::new();
    for (index, value) in bodies.iter().enumerate() {
        let (desc, friction) = parse_body(index, value)?;
        let name = Some(desc.name.clone());
        let invalid = |source: BodyError| SceneFileError::Body {
            index,
            name: name.clone(),
            field: source.field().into(),
            problem: FieldProblem::InvalidBody(source),
        };
        let mut body = Body::new(desc).map_err(invalid)?;
        body.set_friction(friction).map_err(invalid)?;
        scene.push_body(body);
    }
    scene_joints::add_joints(&mut scene, joints)?;
    // The settings were validated above, so this cannot fail.
    let _ = scene.set_settings(settings);
    Ok(scene)
}

/// Writes a scene file (see [`scene_to_string`]).
pub fn write_scene(
    path: &Path,
    scene: &Scene,
    report: Option<&Value>,
) -> Result<(), SceneFileError> {
    std::fs::write(path, scene_to_string(scene, report)).map_err(|e| SceneFileError::Write {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// The scene as pretty-printed JSON: the bodies in order with their names,
/// shapes and mass specifications as given and their current user poses,
/// the joints (if any), the settings that are set, and `report` if given.
pub fn scene_to_string(scene: &Scene, report: Option<&Value>) -> String {
    let file = SceneOut {
        bodies: scene.bodies().iter().map(BodyOut::of).collect(),
        joints: scene_joints::joints_out(scene),
        settings: (!scene.settings().is_empty()).then(|| SettingsOut::of(scene.settings())),
        report,
    };
    // Serializing plain structs of f64 (finite by the Body invariant),
    // strings and a `Value` into a String cannot fail.
    serde_json::to_string_pretty(&file).unwrap_or_default()
}

fn top_level(field: &str, problem: FieldProblem) -> SceneFileError {
    SceneFileError::TopLevel {
        field: field.into(),
        problem,
    }
}

pub(super) fn unknown_field<'a>(
    object: &'a Map<String, Value>,
    allowed: &[&str],
) -> Option<&'a str> {
    object
        .keys()
        .map(String::as_str)
        .find(|key| !allowed.contains(key))
}

/// A body's fields, read one by one so that errors name the field.
type BodyReader<'a> = ObjectReader<'a>;

impl BodyReader<'_> {
    fn number(&self, field: &str) -> Result<Option<f64>, SceneFileError> {
        match self.object.get(field) {
            None => Ok(None),
            Some(value) => value
                .as_f64()
                .map(Some)
                .ok_or_else(|| self.error(field, FieldProblem::WrongType("a number"))),
        }
    }

    fn numbers<const N: usize>(
        &self,
        field: &str,
        value: &Value,
        expected: &'static str,
    ) -> Result<[f64; N], SceneFileError> {
        numbers_of::<N>(value).ok_or_else(|| self.error(field, FieldProblem::WrongType(expected)))
    }
}

pub(super) fn numbers_of<const N: usize>(value: &Value) -> Option<[f64; N]> {
    let array = value.as_array().filter(|a| a.len() == N)?;
    let mut out = [0.0; N];
    for (slot, item) in out.iter_mut().zip(array) {
        *slot = item.as_f64()?;
    }
    Some(out)
}

/// A body's description and its own friction coefficient, if given.
fn parse_body(index: usize, value: &Value) -> Result<(BodyDesc, Option<f64>), SceneFileError> {
    let reader = ObjectReader::new(Entry::Body, index, value)?;
    if let Some(field) = unknown_field(reader.object, &BODY_FIELDS) {
        return Err(reader.error(field, FieldProblem::Unknown));
    }
    let name = reader.name()?;
    let shape = parse_shape(&reader)?;
    let translation = reader.numbers::<3>(
        "translation",
        reader.required("translation")?,
        "an array of 3 numbers",
    )?;
    let rotation_xyzw = reader.numbers::<4>(
        "rotation",
        reader.required("rotation")?,
        "an array of 4 numbers [x, y, z, w]",
    )?;
    let mass = parse_mass_spec(&reader)?;
    let friction = reader.number("friction")?;
    let desc = BodyDesc {
        name,
        shape,
        translation: Vector3::from(translation),
        rotation_xyzw,
        mass,
    };
    Ok((desc, friction))
}

fn parse_shape(reader: &BodyReader<'_>) -> Result<Shape, SceneFileError> {
    parse_shape_at(reader, "shape", reader.required("shape")?, true)
}

/// The shape in `value`, at `field` (for errors); a compound's parts may
/// not be compounds (`compound_allowed` false).
fn parse_shape_at(
    reader: &BodyReader<'_>,
    field: &str,
    value: &Value,
    compound_allowed: bool,
) -> Result<Shape, SceneFileError> {
    let kinds: &[&str] = match compound_allowed {
        true => &["cuboid", "convex_hull", "compound"],
        false => &["cuboid", "convex_hull"],
    };
    let Some(object) = value.as_object() else {
        return Err(reader.error(
            field,
            FieldProblem::WrongType(
                "an object {\"cuboid\": ...}, {\"convex_hull\": ...}, {\"sphere\": ...}, ... or {\"compound\": ...}",
            ),
        ));
    };
    let known = |key: &&str| kinds.contains(key) || round_shapes::ROUND_KINDS.contains(key);
    if let Some(key) = object
        .keys()
        .map(String::as_str)
        .find(|key| !known(key) && *key != round_shapes::RADIUS)
    {
        return Err(reader.error(&format!("{field}.{key}"), FieldProblem::Unknown));
    }
    if object.keys().filter(|key| known(&key.as_str())).count() != 1 {
        return Err(reader.error(
            field,
            FieldProblem::Conflict(
                "give exactly one of `cuboid`, `convex_hull`, `sphere`, `capsule`, `cylinder`, `cone` and `compound`",
            ),
        ));
    }
    let field_of = |key: &str| format!("{field}.{key}");
    let at_field = |(at, problem): round_shapes::Problem| reader.error(&field_of(&at), problem);
    if let Some((key, value)) = object
        .iter()
        .find(|(key, _)| round_shapes::ROUND_KINDS.contains(&key.as_str()))
    {
        if object.contains_key(round_shapes::RADIUS) {
            let problem =
                FieldProblem::Conflict("a radius is given only with `cuboid` or `convex_hull`");
            return Err(reader.error(&field_of(round_shapes::RADIUS), problem));
        }
        return round_shapes::parse_round(key, value).map_err(at_field);
    }
    let shape = parse_polyhedral(reader, field, object)?;
    round_shapes::with_radius(shape, object).map_err(at_field)
}

/// A cuboid, a hull or a compound (the one such key of `object`).
fn parse_polyhedral(
    reader: &BodyReader<'_>,
    field: &str,
    object: &Map<String, Value>,
) -> Result<Shape, SceneFileError> {
    let field_of = |key: &str| format!("{field}.{key}");
    if let Some(half_extents) = object.get("cuboid") {
        let h = reader.numbers::<3>(
            &field_of("cuboid"),
            half_extents,
            "an array of 3 half extents",
        )?;
        return Ok(Shape::Cuboid {
            half_extents: Vector3::from(h),
        });
    }
    if let Some(parts) = object.get("compound") {
        if object.contains_key(round_shapes::RADIUS) {
            let problem =
                FieldProblem::Conflict("a radius is given only with `cuboid` or `convex_hull`");
            return Err(reader.error(&field_of(round_shapes::RADIUS), problem));
        }
        return parse_compound(reader, &field_of("compound"), parts);
    }
    // The one key is known and neither of the above: a hull.
    let points = &object["convex_hull"];
    let field = field_of("convex_hull");
    let count = points.as_array().map_or(0, Vec::len);
    if count > MAX_HULL_POINTS {
        let problem = FieldProblem::TooMany {
            count,
            limit: MAX_HULL_POINTS,
        };
        return Err(reader.error(&field, problem));
    }
    let expected = "an array of points [x, y, z]";
    let points = points
        .as_array()
        .and_then(|a| a.iter().map(numbers_of::<3>).collect::<Option<Vec<_>>>())
        .ok_or_else(|| reader.error(&field, FieldProblem::WrongType(expected)))?;
    Ok(Shape::ConvexHull {
        points: points.into_iter().map(Point3::from).collect(),
    })
}

/// A compound's parts: an array of `{"shape", "translation", "rotation"}`.
fn parse_compound(
    reader: &BodyReader<'_>,
    field: &str,
    value: &Value,
) -> Result<Shape, SceneFileError> {
    let expected = "an array of parts {\"shape\", \"translation\", \"rotation\"}";
    let Some(items) = value.as_array() else {
        return Err(reader.error(field, FieldProblem::WrongType(expected)));
    };
    if items.len() > MAX_COMPOUND_PARTS {
        let problem = FieldProblem::TooMany {
            count: items.len(),
            limit: MAX_COMPOUND_PARTS,
        };
        return Err(reader.error(field, problem));
    }
    let mut parts = Vec::with_capacity(items.len());
    for (index, item) in items.iter().enumerate() {
        let at = format!("{field}[{index}]");
        let Some(object) = item.as_object() else {
            return Err(reader.error(&at, FieldProblem::WrongType(expected)));
        };
        if let Some(key) = unknown_field(object, &["shape", "translation", "rotation"]) {
            return Err(reader.error(&format!("{at}.{key}"), FieldProblem::Unknown));
        }
        let get = |key: &str| {
            object
                .get(key)
                .ok_or_else(|| reader.error(&format!("{at}.{key}"), FieldProblem::Missing))
        };
        let shape = parse_shape_at(reader, &format!("{at}.shape"), get("shape")?, false)?;
        let translation = reader.numbers::<3>(
            &format!("{at}.translation"),
            get("translation")?,
            "an array of 3 numbers",
        )?;
        let rotation_xyzw = reader.numbers::<4>(
            &format!("{at}.rotation"),
            get("rotation")?,
            "an array of 4 numbers [x, y, z, w]",
        )?;
        parts.push(ShapePart {
            shape,
            translation: Vector3::from(translation),
            rotation_xyzw,
        });
    }
    Ok(Shape::Compound { parts })
}

fn parse_mass_spec(reader: &BodyReader<'_>) -> Result<MassSpec, SceneFileError> {
    let fixed = match reader.object.get("fixed") {
        None => false,
        Some(value) => value
            .as_bool()
            .ok_or_else(|| reader.error("fixed", FieldProblem::WrongType("true or false")))?,
    };
    let mass = reader.number("mass")?;
    let density = reader.number("density")?;
    match (fixed, mass, density) {
        (true, None, None) => Ok(MassSpec::Fixed),
        (true, Some(_), _) => Err(reader.error(
            "mass",
            FieldProblem::Conflict("a fixed body takes no `mass`"),
        )),
        (true, None, Some(_)) => Err(reader.error(
            "density",
            FieldProblem::Conflict("a fixed body takes no `density`"),
        )),
        (false, Some(m), None) => Ok(MassSpec::Mass(m)),
        (false, None, Some(rho)) => Ok(MassSpec::Density(rho)),
        (false, Some(_), Some(_)) => Err(reader.error(
            "density",
            FieldProblem::Conflict("give only one of `mass` and `density`"),
        )),
        (false, None, None) => Err(reader.error(
            "mass",
            FieldProblem::Conflict("missing: give `\"fixed\": true`, `mass` or `density`"),
        )),
    }
}

fn parse_settings(value: &Value) -> Result<SceneSettings, SceneFileError> {
    let Some(object) = value.as_object() else {
        return Err(top_level("settings", FieldProblem::WrongType("an object")));
    };
    if let Some(field) = unknown_field(object, &SETTINGS_FIELDS) {
        return Err(settings_error(field, FieldProblem::Unknown));
    }
    let number = |field: &str| -> Result<Option<f64>, SceneFileError> {
        object
            .get(field)
            .map(|v| {
                v.as_f64()
                    .ok_or_else(|| settings_error(field, FieldProblem::WrongType("a number")))
            })
            .transpose()
    };
    let max_passes = object
        .get("max_passes")
        .map(|v| {
            v.as_u64()
                .and_then(|n| u32::try_from(n).ok())
                .ok_or_else(|| {
                    settings_error("max_passes", FieldProblem::WrongType("an integer >= 1"))
                })
        })
        .transpose()?;
    let solver = named_setting(
        object,
        "solver",
        "one of \"auto\", \"clarabel\", \"lemke\", \"pgs\"",
        SolverChoice::from_name,
    )?;
    let cross_check = object
        .get("cross_check")
        .map(|v| {
            v.as_bool().ok_or_else(|| {
                settings_error("cross_check", FieldProblem::WrongType("true or false"))
            })
        })
        .transpose()?;
    let method = named_setting(
        object,
        "method",
        "one of \"projection\", \"gauss_seidel\"",
        Method::from_name,
    )?;
    let friction_model = named_setting(
        object,
        "friction_model",
        "one of \"pyramid\", \"cone\"",
        FrictionModel::from_name,
    )?;
    let friction_rows = named_setting(
        object,
        "friction_rows",
        "one of \"all\", \"implied\", \"generated\"",
        FrictionRows::from_name,
    )?;
    Ok(SceneSettings {
        tolerance: number("tolerance")?,
        contact_margin: number("contact_margin")?,
        target_margin: number("target_margin")?,
        max_passes,
        solver,
        cross_check,
        method,
        friction_model,
        friction_rows,
    })
}

/// The setting `field` given by name: the library's value of that name,
/// `None` when absent, else an error saying which names are `expected`.
fn named_setting<T>(
    object: &Map<String, Value>,
    field: &str,
    expected: &'static str,
    from_name: fn(&str) -> Option<T>,
) -> Result<Option<T>, SceneFileError> {
    object
        .get(field)
        .map(|v| {
            v.as_str()
                .and_then(from_name)
                .ok_or_else(|| settings_error(field, FieldProblem::WrongType(expected)))
        })
        .transpose()
}

fn settings_error(field: &str, problem: FieldProblem) -> SceneFileError {
    SceneFileError::Settings {
        field: field.into(),
        problem,
    }
}

#[derive(Serialize)]
struct SceneOut<'a> {
    bodies: Vec<BodyOut<'a>>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    joints: Vec<JointOut<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    settings: Option<SettingsOut>,
    #[serde(skip_serializing_if = "Option::is_none")]
    report: Option<&'a Value>,
}

#[derive(Serialize)]
#[serde(rename_all = "snake_case")]
enum ShapeOut {
    Cuboid([f64; 3]),
    ConvexHull(Vec<[f64; 3]>),
    Compound(Vec<PartOut>),
    Sphere(f64),
    Capsule(AxialOut),
    Cylinder(AxialOut),
    Cone(AxialOut),
    /// A rounded cuboid or hull: `{"cuboid": ..., "radius": r}`.
    #[serde(untagged)]
    Rounded {
        #[serde(flatten)]
        core: CoreOut,
        radius: f64,
    },
}

#[derive(Serialize)]
struct PartOut {
    shape: ShapeOut,
    translation: [f64; 3],
    rotation: [f64; 4],
}

impl ShapeOut {
    fn of(shape: &Shape) -> Self {
        match shape {
            Shape::Cuboid { half_extents } => ShapeOut::Cuboid((*half_extents).into()),
            Shape::ConvexHull { points } => {
                ShapeOut::ConvexHull(points.iter().map(|p| p.coords.into()).collect())
            }
            Shape::Sphere { radius } => ShapeOut::Sphere(*radius),
            Shape::Capsule {
                half_height,
                radius,
            } => ShapeOut::Capsule(AxialOut::new(*half_height, *radius)),
            Shape::Cylinder {
                half_height,
                radius,
            } => ShapeOut::Cylinder(AxialOut::new(*half_height, *radius)),
            Shape::Cone {
                half_height,
                radius,
            } => ShapeOut::Cone(AxialOut::new(*half_height, *radius)),
            Shape::RoundCuboid {
                half_extents,
                radius,
            } => ShapeOut::Rounded {
                core: CoreOut::Cuboid((*half_extents).into()),
                radius: *radius,
            },
            Shape::RoundConvexHull { points, radius } => ShapeOut::Rounded {
                core: CoreOut::ConvexHull(points.iter().map(|p| p.coords.into()).collect()),
                radius: *radius,
            },
            Shape::Compound { parts } => ShapeOut::Compound(
                parts
                    .iter()
                    .map(|part| PartOut {
                        shape: ShapeOut::of(&part.shape),
                        translation: part.translation.into(),
                        rotation: part.rotation_xyzw,
                    })
                    .collect(),
            ),
        }
    }
}

#[derive(Serialize)]
struct BodyOut<'a> {
    name: &'a str,
    shape: ShapeOut,
    translation: [f64; 3],
    rotation: [f64; 4],
    #[serde(skip_serializing_if = "Option::is_none")]
    fixed: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    mass: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    density: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    friction: Option<f64>,
}

impl<'a> BodyOut<'a> {
    fn of(body: &'a Body) -> Self {
        let shape = ShapeOut::of(body.shape());
        let (fixed, mass, density) = match body.mass_spec() {
            MassSpec::Fixed => (Some(true), None, None),
            MassSpec::Mass(m) => (None, Some(m), None),
            MassSpec::Density(rho) => (None, None, Some(rho)),
        };
        BodyOut {
            name: body.name(),
            shape,
            translation: (*body.translation_user()).into(),
            rotation: body.rotation_user_xyzw(),
            fixed,
            mass,
            density,
            friction: body.friction(),
        }
    }
}

#[derive(Serialize)]
struct SettingsOut {
    #[serde(skip_serializing_if = "Option::is_none")]
    tolerance: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    contact_margin: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    target_margin: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_passes: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    solver: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cross_check: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    method: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    friction_model: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    friction_rows: Option<&'static str>,
}

impl SettingsOut {
    fn of(settings: &SceneSettings) -> Self {
        SettingsOut {
            tolerance: settings.tolerance,
            contact_margin: settings.contact_margin,
            target_margin: settings.target_margin,
            max_passes: settings.max_passes,
            solver: settings.solver.map(SolverChoice::name),
            cross_check: settings.cross_check,
            method: settings.method.map(Method::name),
            friction_model: settings.friction_model.map(FrictionModel::name),
            friction_rows: settings.friction_rows.map(FrictionRows::name),
        }
    }
}
