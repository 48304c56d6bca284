//! The `joints` section of scene files ([`super::scene_file`]): reading it
//! into [`Joint`]s after the bodies are built, and writing it back.
//!
//! ```text
//! "joints": [
//!   { "name": "hinge 1", "type": "revolute", "bodies": ["link 0", "link 1"],
//!     "anchor_a": [0.5, 0, 0], "anchor_b": [-0.5, 0, 0],
//!     "axis_a": [0, 0, 1], "axis_b": [0, 0, 1], "limits": [-1.0, 1.0] },
//!   { "name": "slider", "type": "generic", "bodies": [0, 2],
//!     "anchor_a": [0, 1, 0], "anchor_b": [0, 0, 0],
//!     "rotation_a": [0, 0, 0, 1], "rotation_b": [0, 0, 0, 1],
//!     "locked": ["y", "z", "angular_x", "angular_y", "angular_z"],
//!     "axis_limits": { "x": [-0.5, 0.5] } } ]
//! ```
//!
//! - `name` (a string, a label: need not be unique), `type` (`fixed`,
//!   `spherical`, `revolute`, `prismatic`, `generic`: [`JointKind::name`]),
//!   `bodies` (two bodies: a name, which must be unique among the bodies,
//!   or an index, an integer) and `anchor_a`, `anchor_b` (the anchor
//!   points, each in its body's own frame: the frame of the body's
//!   `translation` and `rotation`) are required.
//! - Each anchor frame's orientation (in its body's frame) is given by
//!   either `rotation_a` (a quaternion `[x, y, z, w]`; within
//!   [`UNIT_QUATERNION_TOLERANCE`] of unit it is normalized, farther it is
//!   an error, like a body's `rotation`), or `axis_a` (the frame's `x`
//!   axis, default `[1, 0, 0]`) with an optional `reference_a` (fixes the
//!   frame's `y` axis: the reference made perpendicular to the axis by
//!   Gram–Schmidt; default the coordinate axis least aligned with `axis_a`,
//!   made perpendicular the same way); `z = x × y`. Neither: the identity.
//!   Both forms for one side is a `Conflict`. The same for `_b`. Axes need
//!   not be unit length; a zero one is an error, and so is a reference
//!   within [`REFERENCE_PARALLEL_SINE`] of parallel to its axis.
//! - `limits: [min, max]` (radians for `revolute`, length for
//!   `prismatic`) only on those two types. `generic` requires `locked`
//!   (axis names among `x`, `y`, `z`, `angular_x`, `angular_y`,
//!   `angular_z`; at least one) and takes optional `axis_limits`
//!   (`{"x": [min, max], "angular_y": [min, max], ...}`, free axes only;
//!   an angular limit only on the single free angular axis); no other type
//!   takes them. Limits must be finite with `min <= max`.
//! - Checked as for [`Scene::add_joint`]: the two bodies differ, and not
//!   both are fixed.
//! - At most [`MAX_JOINTS`] joints, checked before any body or joint is
//!   built. Every error is [`SceneFileError::Joint`], naming the joint's
//!   index and name and the field (`bodies[1]`, `axis_limits.angular_y`,
//!   `locked[2]`, ...).
//!
//! The writer writes `anchor_*` and `rotation_*` (the quaternions as
//! stored, so reading the output gives bit-identical frames), `bodies` by
//! name when the name is unique, else by index, `limits`, `locked` and
//! `axis_limits` when there are any. The section is omitted when the scene
//! has no joints.

use std::collections::HashMap;

use nalgebra::{Isometry3, Matrix3, Quaternion, Rotation3, Translation3, UnitQuaternion, Vector3};
use serde::Serialize;
use serde_json::{Map, Value};
use thiserror::Error;

use super::object_reader::{Entry, ObjectReader};
use super::scene_file::{FieldProblem, SceneFileError, numbers_of, unknown_field};
use crate::body::{UNIT_QUATERNION_ROUNDING, UNIT_QUATERNION_TOLERANCE};
use crate::joints::{Joint, JointAxes, JointError, JointKind, JointLimits, Limit};
use crate::scene::{Scene, SceneError};

/// Most joints a scene file may hold: 200,000 (as many as
/// [`super::scene_file::MAX_BODIES`]: a chain has one joint per body).
/// Checked before any body or joint is built. A joint takes about 500 to
/// 700 bytes as [`super::scene_file::scene_to_string`] writes it, so a
/// file with both limits reached (about 200 MB) is beyond
/// [`super::scene_file::MAX_SCENE_FILE_BYTES`]; about 100,000 of each fit.
pub const MAX_JOINTS: usize = 200_000;

/// A `reference_*` whose angle to its axis has a sine below this is
/// parallel to it: the frame's `y` axis would be mostly rounding.
pub const REFERENCE_PARALLEL_SINE: f64 = 1e-6;

const JOINT_FIELDS: [&str; 14] = [
    "name",
    "type",
    "bodies",
    "anchor_a",
    "anchor_b",
    "axis_a",
    "axis_b",
    "reference_a",
    "reference_b",
    "rotation_a",
    "rotation_b",
    "limits",
    "locked",
    "axis_limits",
];

/// The axis names of `locked` and `axis_limits`: linear `x`, `y`, `z`,
/// then angular.
const AXES: [&str; 6] = ["x", "y", "z", "angular_x", "angular_y", "angular_z"];

const TYPES: [&str; 5] = ["fixed", "spherical", "revolute", "prismatic", "generic"];

/// Why an anchor frame's orientation cannot be built.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FrameProblem {
    /// An axis or reference is zero (or not finite, which JSON cannot
    /// express).
    #[error("not a direction (zero)")]
    NotADirection,
    /// The reference is parallel to the axis.
    #[error("parallel to the axis")]
    ReferenceParallel,
    /// The quaternion's norm is farther than
    /// [`UNIT_QUATERNION_TOLERANCE`] from 1 (zero included).
    #[error("quaternion of norm {norm}: not within 1e-3 of unit")]
    RotationNotUnit {
        /// The norm.
        norm: f64,
    },
}

/// The `joints` array of a scene file's top level (empty if absent),
/// checked for its type and [`MAX_JOINTS`] before anything is built.
pub(super) fn joints_array(top: &Map<String, Value>) -> Result<&[Value], SceneFileError> {
    let problem = match top.get("joints") {
        None => return Ok(&[]),
        Some(Value::Array(joints)) if joints.len() <= MAX_JOINTS => return Ok(joints),
        Some(Value::Array(joints)) => FieldProblem::TooMany {
            count: joints.len(),
            limit: MAX_JOINTS,
        },
        Some(_) => FieldProblem::WrongType("an array"),
    };
    Err(SceneFileError::TopLevel {
        field: "joints".into(),
        problem,
    })
}

/// Reads every joint of `items` against the scene's bodies and adds them
/// to the scene; the first bad one is the error.
pub(super) fn add_joints(scene: &mut Scene, items: &[Value]) -> Result<(), SceneFileError> {
    let bodies = BodyNames::of(scene);
    let fixed = scene.fixed_flags();
    let mut joints = Vec::with_capacity(items.len());
    for (index, item) in items.iter().enumerate() {
        let joint = parse_joint(index, item, &bodies)?;
        joint
            .validate(&fixed)
            .map_err(|source| invalid(index, &joint, source))?;
        joints.push(joint);
    }
    // Every joint was validated against these same bodies above, so this
    // does not fail; were it to, it is still reported as a joint error.
    scene.add_joints(joints).map_err(|error| match error {
        SceneError::Joint {
            index,
            name,
            source,
        } => SceneFileError::Joint {
            index,
            name: Some(name),
            field: "(joint)".into(),
            problem: FieldProblem::InvalidJoint(source),
        },
        _ => SceneFileError::TopLevel {
            field: "joints".into(),
            problem: FieldProblem::Conflict("rejected by the scene"),
        },
    })
}

/// The file error of a joint that [`Joint::validate`] rejects, at the
/// field the problem is in.
fn invalid(index: usize, joint: &Joint, source: JointError) -> SceneFileError {
    let field = match &source {
        JointError::NoSuchBody { .. }
        | JointError::SameBody { .. }
        | JointError::BothFixed { .. } => "bodies".to_string(),
        JointError::InvalidFrame { which } => format!("rotation_{which}"),
        JointError::InvalidLimit { axis, .. } | JointError::LimitOnLockedAxis { axis, .. } => {
            match joint.kind {
                JointKind::Generic { .. } => format!("axis_limits.{}", file_axis(axis)),
                _ => "limits".to_string(),
            }
        }
        JointError::NothingLocked => "locked".to_string(),
    };
    SceneFileError::Joint {
        index,
        name: Some(joint.name.clone()),
        field,
        problem: FieldProblem::InvalidJoint(source),
    }
}

/// `linear x` → `x`, `angular x` → `angular_x` (the axis names of
/// [`JointError`] in the file's spelling).
fn file_axis(axis: &str) -> String {
    match axis.strip_prefix("linear ") {
        Some(linear) => linear.to_string(),
        None => axis.replace(' ', "_"),
    }
}

/// The bodies by name: the index of each name given once, and the names
/// given more than once (with their count).
struct BodyNames<'a> {
    unique: HashMap<&'a str, usize>,
    repeated: HashMap<&'a str, usize>,
    len: usize,
}

impl<'a> BodyNames<'a> {
    fn of(scene: &'a Scene) -> Self {
        let mut counts: HashMap<&str, (usize, usize)> = HashMap::new();
        for (index, body) in scene.bodies().iter().enumerate() {
            counts.entry(body.name()).or_insert((index, 0)).1 += 1;
        }
        let (mut unique, mut repeated) = (HashMap::new(), HashMap::new());
        for (name, (index, count)) in counts {
            match count {
                1 => unique.insert(name, index),
                _ => repeated.insert(name, count),
            };
        }
        BodyNames {
            unique,
            repeated,
            len: scene.len(),
        }
    }

    /// The index `value` (a name or an index) refers to.
    fn resolve(&self, value: &Value) -> Result<usize, FieldProblem> {
        if let Some(name) = value.as_str() {
            if let Some(&count) = self.repeated.get(name) {
                return Err(FieldProblem::AmbiguousBody {
                    name: name.into(),
                    count,
                });
            }
            return self
                .unique
                .get(name)
                .copied()
                .ok_or_else(|| FieldProblem::UnknownBody(format!("{name:?}")));
        }
        let index = value
            .as_u64()
            .ok_or(FieldProblem::WrongType("a body name or index"))?;
        usize::try_from(index)
            .ok()
            .filter(|&i| i < self.len)
            .ok_or_else(|| FieldProblem::UnknownBody(format!("{index} (of {})", self.len)))
    }
}

/// A joint's fields, read one by one so that errors name the field.
type JointReader<'a> = ObjectReader<'a>;

impl JointReader<'_> {
    /// `field` as `N` numbers, if present.
    fn numbers_if_given<const N: usize>(
        &self,
        field: &str,
        expected: &'static str,
    ) -> Result<Option<[f64; N]>, SceneFileError> {
        self.object
            .get(field)
            .map(|value| {
                numbers_of::<N>(value)
                    .ok_or_else(|| self.error(field, FieldProblem::WrongType(expected)))
            })
            .transpose()
    }

    /// A `[min, max]` at `field` of `value`.
    fn limit(&self, field: &str, value: &Value) -> Result<Limit, SceneFileError> {
        numbers_of::<2>(value)
            .ok_or_else(|| self.error(field, FieldProblem::WrongType("an array [min, max]")))
    }

    /// An error if `field` is given on a joint of type `kind`, which has
    /// no such field.
    fn not_for(&self, field: &str, kind: &'static str) -> Result<(), SceneFileError> {
        match self.object.contains_key(field) {
            true => Err(self.error(field, FieldProblem::NotForType(kind))),
            false => Ok(()),
        }
    }
}

fn parse_joint(index: usize, value: &Value, bodies: &BodyNames) -> Result<Joint, SceneFileError> {
    let reader = ObjectReader::new(Entry::Joint, index, value)?;
    if let Some(field) = unknown_field(reader.object, &JOINT_FIELDS) {
        return Err(reader.error(field, FieldProblem::Unknown));
    }
    let name = reader.name()?;
    let type_name = reader.required("type")?.as_str();
    let Some(type_name) = type_name.and_then(|t| TYPES.into_iter().find(|&k| k == t)) else {
        let expected = "one of \"fixed\", \"spherical\", \"revolute\", \"prismatic\", \"generic\"";
        return Err(reader.error("type", FieldProblem::WrongType(expected)));
    };
    let [body_a, body_b] = parse_bodies(&reader, bodies)?;
    let kind = parse_kind(&reader, type_name)?;
    Ok(Joint {
        name,
        kind,
        body_a,
        body_b,
        frame_a: parse_frame(&reader, "a")?,
        frame_b: parse_frame(&reader, "b")?,
    })
}

fn parse_bodies(
    reader: &JointReader<'_>,
    bodies: &BodyNames,
) -> Result<[usize; 2], SceneFileError> {
    let expected = "an array of 2 body names or indices";
    let pair = reader
        .required("bodies")?
        .as_array()
        .filter(|a| a.len() == 2);
    let Some(pair) = pair else {
        return Err(reader.error("bodies", FieldProblem::WrongType(expected)));
    };
    let mut out = [0; 2];
    for (k, (slot, value)) in out.iter_mut().zip(pair).enumerate() {
        *slot = bodies
            .resolve(value)
            .map_err(|problem| reader.error(&format!("bodies[{k}]"), problem))?;
    }
    Ok(out)
}

fn parse_kind(
    reader: &JointReader<'_>,
    type_name: &'static str,
) -> Result<JointKind, SceneFileError> {
    if type_name != "generic" {
        reader.not_for("locked", type_name)?;
        reader.not_for("axis_limits", type_name)?;
    }
    let limit = || {
        reader
            .object
            .get("limits")
            .map(|value| reader.limit("limits", value))
            .transpose()
    };
    match type_name {
        "revolute" => Ok(JointKind::Revolute { limit: limit()? }),
        "prismatic" => Ok(JointKind::Prismatic { limit: limit()? }),
        "generic" => {
            reader.not_for("limits", type_name)?;
            Ok(JointKind::Generic {
                locked: parse_locked(reader)?,
                limits: parse_axis_limits(reader)?,
            })
        }
        "fixed" => reader
            .not_for("limits", type_name)
            .map(|()| JointKind::Fixed),
        _ => reader
            .not_for("limits", type_name)
            .map(|()| JointKind::Spherical),
    }
}

/// The slot of axis `k` (of [`AXES`]) in linear/angular arrays.
fn axis_slot<'a, T>(linear: &'a mut [T; 3], angular: &'a mut [T; 3], k: usize) -> &'a mut T {
    match k {
        0..3 => &mut linear[k],
        _ => &mut angular[k - 3],
    }
}

fn parse_locked(reader: &JointReader<'_>) -> Result<JointAxes, SceneFileError> {
    let Some(names) = reader.required("locked")?.as_array() else {
        return Err(reader.error("locked", FieldProblem::WrongType("an array of axis names")));
    };
    let mut locked = JointAxes::default();
    for (i, value) in names.iter().enumerate() {
        let field = format!("locked[{i}]");
        let Some(name) = value.as_str() else {
            return Err(reader.error(&field, FieldProblem::WrongType("an axis name")));
        };
        let Some(k) = AXES.iter().position(|&a| a == name) else {
            return Err(reader.error(&field, FieldProblem::UnknownAxis(name.into())));
        };
        let slot = axis_slot(&mut locked.linear, &mut locked.angular, k);
        if *slot {
            return Err(reader.error(&field, FieldProblem::Conflict("axis listed twice")));
        }
        *slot = true;
    }
    if locked.count() == 0 {
        let problem = FieldProblem::InvalidJoint(JointError::NothingLocked);
        return Err(reader.error("locked", problem));
    }
    Ok(locked)
}

fn parse_axis_limits(reader: &JointReader<'_>) -> Result<JointLimits, SceneFileError> {
    let mut limits = JointLimits::NONE;
    let Some(value) = reader.object.get("axis_limits") else {
        return Ok(limits);
    };
    let Some(object) = value.as_object() else {
        let expected = "an object {\"axis\": [min, max], ...}";
        return Err(reader.error("axis_limits", FieldProblem::WrongType(expected)));
    };
    for (name, value) in object {
        let field = format!("axis_limits.{name}");
        let Some(k) = AXES.iter().position(|a| a == name) else {
            return Err(reader.error(&field, FieldProblem::UnknownAxis(name.clone())));
        };
        *axis_slot(&mut limits.linear, &mut limits.angular, k) = Some(reader.limit(&field, value)?);
    }
    Ok(limits)
}

/// The anchor frame of side `side` (`"a"` or `"b"`) in its body's frame.
fn parse_frame(reader: &JointReader<'_>, side: &str) -> Result<Isometry3<f64>, SceneFileError> {
    let field = |name: &str| format!("{name}_{side}");
    let anchor = reader.required(&field("anchor"))?;
    let anchor = numbers_of::<3>(anchor).ok_or_else(|| {
        reader.error(
            &field("anchor"),
            FieldProblem::WrongType("an array of 3 numbers"),
        )
    })?;
    let vector = "an array of 3 numbers";
    let rotation =
        reader.numbers_if_given::<4>(&field("rotation"), "an array of 4 numbers [x, y, z, w]")?;
    let axis = reader.numbers_if_given::<3>(&field("axis"), vector)?;
    let reference = reader.numbers_if_given::<3>(&field("reference"), vector)?;
    let frame_error =
        |name: &str, problem| reader.error(&field(name), FieldProblem::DegenerateFrame(problem));
    let rotation = match (rotation, axis.is_some() || reference.is_some()) {
        (Some(_), true) => {
            let problem =
                FieldProblem::Conflict("give a rotation or an axis and reference, not both");
            return Err(reader.error(&field("rotation"), problem));
        }
        (Some(xyzw), false) => unit_quaternion(xyzw).map_err(|p| frame_error("rotation", p))?,
        (None, _) => {
            let x =
                direction(axis.unwrap_or([1.0, 0.0, 0.0])).map_err(|p| frame_error("axis", p))?;
            let reference = match reference {
                Some(r) => direction(r).map_err(|p| frame_error("reference", p))?,
                None => least_aligned_axis(&x),
            };
            axes_rotation(&x, &reference).map_err(|p| frame_error("reference", p))?
        }
    };
    Ok(Isometry3::from_parts(Translation3::from(anchor), rotation))
}

/// The quaternion `[x, y, z, w]`: kept bit for bit when its norm is 1 up
/// to rounding (so written frames read back unchanged), normalized within
/// [`UNIT_QUATERNION_TOLERANCE`], an error farther.
fn unit_quaternion([x, y, z, w]: [f64; 4]) -> Result<UnitQuaternion<f64>, FrameProblem> {
    let quaternion = Quaternion::new(w, x, y, z);
    let norm = quaternion.norm();
    let drift = (norm - 1.0).abs();
    if drift <= UNIT_QUATERNION_ROUNDING {
        Ok(UnitQuaternion::new_unchecked(quaternion))
    } else if drift <= UNIT_QUATERNION_TOLERANCE {
        Ok(UnitQuaternion::new_normalize(quaternion))
    } else {
        Err(FrameProblem::RotationNotUnit { norm })
    }
}

/// `v` as a unit vector (scaled by its largest component first, so that
/// neither huge nor tiny components overflow or vanish).
fn direction(v: [f64; 3]) -> Result<Vector3<f64>, FrameProblem> {
    let v = Vector3::from(v);
    let scale = v.amax();
    // The strict JSON reader yields finite numbers only; the test also
    // turns a non-finite vector into an error rather than a NaN frame.
    if !(scale.is_finite() && scale > 0.0) {
        return Err(FrameProblem::NotADirection);
    }
    Ok((v / scale).normalize())
}

/// The coordinate axis least aligned with `x` (the first of equals).
fn least_aligned_axis(x: &Vector3<f64>) -> Vector3<f64> {
    let k = (1..3).fold(
        0,
        |best, k| if x[k].abs() < x[best].abs() { k } else { best },
    );
    Vector3::ith(k, 1.0)
}

/// The rotation whose `x` axis is `x` and whose `y` axis is `reference`
/// made perpendicular to `x` (both unit).
fn axes_rotation(
    x: &Vector3<f64>,
    reference: &Vector3<f64>,
) -> Result<UnitQuaternion<f64>, FrameProblem> {
    let y = reference - x * x.dot(reference);
    let sine = y.norm();
    if sine < REFERENCE_PARALLEL_SINE {
        return Err(FrameProblem::ReferenceParallel);
    }
    let y = y / sine;
    let z = x.cross(&y);
    let matrix = Matrix3::from_columns(&[*x, y, z]);
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(matrix));
    // Renormalized so that the written quaternion reads back bit for bit
    // (its norm is then 1 up to rounding); scalar part made nonnegative
    // (the same rotation), so the file shows the shorter form.
    let q = rotation.into_inner();
    let q = if q.w < 0.0 { -q } else { q };
    Ok(UnitQuaternion::new_normalize(q))
}

/// A joint as written.
#[derive(Serialize)]
pub(super) struct JointOut<'a> {
    name: &'a str,
    #[serde(rename = "type")]
    kind: &'static str,
    bodies: [BodyRef<'a>; 2],
    anchor_a: [f64; 3],
    anchor_b: [f64; 3],
    rotation_a: [f64; 4],
    rotation_b: [f64; 4],
    #[serde(skip_serializing_if = "Option::is_none")]
    limits: Option<Limit>,
    #[serde(skip_serializing_if = "Option::is_none")]
    locked: Option<Vec<&'static str>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    axis_limits: Option<AxisLimitsOut>,
}

/// A body by name (when unique) or index.
#[derive(Serialize)]
#[serde(untagged)]
enum BodyRef<'a> {
    Name(&'a str),
    Index(usize),
}

#[derive(Serialize)]
struct AxisLimitsOut {
    #[serde(skip_serializing_if = "Option::is_none")]
    x: Option<Limit>,
    #[serde(skip_serializing_if = "Option::is_none")]
    y: Option<Limit>,
    #[serde(skip_serializing_if = "Option::is_none")]
    z: Option<Limit>,
    #[serde(skip_serializing_if = "Option::is_none")]
    angular_x: Option<Limit>,
    #[serde(skip_serializing_if = "Option::is_none")]
    angular_y: Option<Limit>,
    #[serde(skip_serializing_if = "Option::is_none")]
    angular_z: Option<Limit>,
}

/// The scene's joints as written (empty: the section is omitted).
pub(super) fn joints_out(scene: &Scene) -> Vec<JointOut<'_>> {
    if scene.joints().is_empty() {
        return Vec::new();
    }
    let names = BodyNames::of(scene);
    let body = |index: usize| {
        let name = scene.bodies().get(index).map(|b| b.name());
        match name.filter(|n| names.unique.contains_key(n)) {
            Some(name) => BodyRef::Name(name),
            None => BodyRef::Index(index),
        }
    };
    let xyzw = |frame: &Isometry3<f64>| {
        let q = frame.rotation.quaternion();
        [q.i, q.j, q.k, q.w]
    };
    scene
        .joints()
        .iter()
        .map(|joint| {
            let (limits, locked, axis_limits) = kind_out(&joint.kind);
            JointOut {
                name: &joint.name,
                kind: joint.kind.name(),
                bodies: [body(joint.body_a), body(joint.body_b)],
                anchor_a: joint.frame_a.translation.vector.into(),
                anchor_b: joint.frame_b.translation.vector.into(),
                rotation_a: xyzw(&joint.frame_a),
                rotation_b: xyzw(&joint.frame_b),
                limits,
                locked,
                axis_limits,
            }
        })
        .collect()
}

type KindOut = (
    Option<Limit>,
    Option<Vec<&'static str>>,
    Option<AxisLimitsOut>,
);

/// `limits`, `locked` and `axis_limits` of a joint type.
fn kind_out(kind: &JointKind) -> KindOut {
    match kind {
        JointKind::Revolute { limit } | JointKind::Prismatic { limit } => (*limit, None, None),
        JointKind::Fixed | JointKind::Spherical => (None, None, None),
        JointKind::Generic { locked, limits } => {
            let flags = locked.linear.iter().chain(&locked.angular);
            let names = AXES.iter().zip(flags).filter(|(_, l)| **l);
            let [x, y, z] = limits.linear;
            let [angular_x, angular_y, angular_z] = limits.angular;
            let any = limits
                .linear
                .iter()
                .chain(&limits.angular)
                .any(Option::is_some);
            let axis_limits = any.then_some(AxisLimitsOut {
                x,
                y,
                z,
                angular_x,
                angular_y,
                angular_z,
            });
            (None, Some(names.map(|(n, _)| *n).collect()), axis_limits)
        }
    }
}
