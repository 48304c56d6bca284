//! Separation certificates: a pair whose last exact answer left it farther
//! apart than the contact margin by more than its two parts can have moved
//! since is not queried again.
//!
//! **The motion bound.** A part's pose maps its frame to the world,
//! `x_world = R x + t`. Between a recorded pose `(R0, t0)` and the current
//! pose `(R1, t1)` a point `x` of the part (part frame) moves by
//!
//! `d(x) = (R1 - R0) x + (t1 - t0)`, and
//! `|(R1 - R0) x| = |(R1 R0^T - I) R0 x| = 2 sin(theta / 2) |(R0 x)_perp|
//! <= 2 sin(theta / 2) |x|`,
//!
//! where `theta` is the angle of the relative rotation `R1 R0^T` and
//! `_perp` the component perpendicular to its axis. With the unit
//! quaternion `q = q1 q0^*` of that rotation, `sin(theta / 2) = |imag(q)|`
//! (the same for `q` and `-q`). Every point of the solid lies within its
//! *reach* `r` of the part-frame origin (the centre of mass of a convex
//! body): the largest norm of a vertex of the part's polyhedron, plus the
//! radius of a round part (every point of the solid is within the radius of
//! its core, and the core lies in the polyhedron's hull: the polyhedron is
//! the core itself, or a box around a point or segment core; a cylinder's
//! or cone's true solid lies inside its circumscribed polyhedron). So every
//! point of the solid moved by at most
//!
//! `delta = |t1 - t0| + 2 |imag(q1 q0^*)| r`.
//!
//! Poses hold unit quaternions to rounding (a body renormalizes one that
//! drifted). A quaternion `q = s q_hat` off unit norm rotates a vector `v`
//! (by the unit formula) to `R_hat v + (s^2 - 1)(R_hat v - v)`, at most
//! `2 |s^2 - 1| |v|` from the rotation by `q_hat`; the bound adds that for
//! both poses, and divides `|imag|` by the relative quaternion's norm when
//! below 1, so that it holds for quaternions off unit norm too.
//!
//! **The certificate.** A rigid motion maps the solid at the recorded pose
//! one to one onto the solid now. For any two points `a1`, `b1` of the
//! solids now, with `a0`, `b0` their points at the recorded poses,
//! `|a1 - b1| >= |a0 - b0| - |a1 - a0| - |b1 - b0| >= s - delta_a - delta_b`,
//! where `s` is the recorded distance. So the distance now is at least
//! `s - delta_a - delta_b`. If that exceeds the current call's contact
//! margin by the slack ([`CERTIFICATE_SLACK_RELATIVE`], for the rounding of
//! the recorded and the would-be answer), the pair is separated beyond the
//! margin: a query would classify it as neither active nor penetrating and
//! give it no row, so it is skipped. Only that class is certified by a
//! bound: touching and penetrating pairs need their exact features and
//! values. With no motion at all (both part poses bit-identical to the
//! recorded ones, the same solids) the recorded answer itself is reused,
//! as the call's memo does within a call ([`super::QueryMemo`]): the
//! narrow phase is a function of the solids and the poses.
//!
//! **What an entry belongs to.** A certificate is recorded per part pair
//! with the two shape objects (`Weak` references, as the V-Clip warm
//! starts, `ShapeIdentity`) and the parts' roundings and curved
//! solids, and is used only when all of them are the very ones of the
//! pair now: bodies added, removed, reordered or replaced, and shapes
//! changed miss, unless the very same shape objects (shared by several
//! bodies) end up under the pair's indices. Then the certificate still
//! holds: it is geometric (two solids and two poses), whatever body holds
//! a shape now, and the motion is measured from the recorded poses. The
//! margin is the current call's, never the recorded one's. The narrow
//! phase's settings decide which solid a curved part is (true solid or
//! circumscribed polyhedron), so the store is cleared when they change
//! ([`SeparationCertificates::use_settings`]).
//!
//! **Size.** Entries not used (looked up or recorded) during a call, and
//! those of dropped shapes, are removed when the next call begins.

use nalgebra::Isometry3;

use super::island_contacts::shape_pair;
use super::scene_parts::SceneParts;
use super::{PairQuery, ShapeIdentity};
use crate::broad_phase::{BodyPair, PairMap};
use crate::geometry::curved::CurvedSolid;
use crate::geometry::{ConvexPolyhedron, Rounding};
use crate::vclip::VClipSettings;

/// Slack of a certificate, relative to the pair's size (the sum of the two
/// reaches plus the recorded distance): the certified lower bound must
/// exceed the margin by this much. It covers the error of the recorded
/// distance and of the answer a query would give now (about 1e-16 of the
/// coordinates for V-Clip on polyhedra, within 2e-8 of the pair's size for
/// the support-function narrow phase of curved solids, `docs/round-shapes.md`).
pub const CERTIFICATE_SLACK_RELATIVE: f64 = 1e-6;

/// The solid of one part, as far as a certificate depends on it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PartSolid {
    rounding: Option<Rounding>,
    curved: Option<CurvedSolid>,
}

#[derive(Debug, Clone)]
struct Certificate {
    shapes: ShapeIdentity,
    solids: [PartSolid; 2],
    /// The parts' reaches (module docs).
    reach: [f64; 2],
    /// Part poses `[a, b]` of the recorded answer.
    poses: [Isometry3<f64>; 2],
    /// The recorded signed value (distance when separated).
    value: f64,
    /// The recorded answer, reused at bit-identical poses.
    query: PairQuery,
    /// Looked up or recorded during the current call.
    used: bool,
}

/// The last exact answer of every part pair that can certify it later
/// (module docs).
#[derive(Debug, Clone, Default)]
pub struct SeparationCertificates {
    entries: PairMap<Certificate>,
    /// The narrow phase's settings the entries were recorded under.
    settings: Option<VClipSettings>,
}

/// Largest distance from the part-frame origin of a point of the solid of
/// `shape` grown by `rounding` (module docs: the reach).
pub fn reach(shape: &ConvexPolyhedron, rounding: Option<&Rounding>) -> f64 {
    let hull = shape
        .vertices()
        .iter()
        .map(|v| v.coords.norm())
        .fold(0.0, f64::max);
    hull + rounding.map_or(0.0, |r| r.radius)
}

/// Bound on how far any point of a part of reach `reach` moved from pose
/// `from` to pose `to`: `|t1 - t0| + 2 |imag(q1 q0^*)| reach` (module
/// docs), plus what a quaternion off unit norm adds (module docs).
pub fn motion_bound(from: &Isometry3<f64>, to: &Isometry3<f64>, reach: f64) -> f64 {
    let translation = (to.translation.vector - from.translation.vector).norm();
    let relative = to.rotation * from.rotation.inverse();
    let off_unit = |pose: &Isometry3<f64>| (pose.rotation.quaternion().norm_squared() - 1.0).abs();
    let chord = relative.imag().norm() / (relative.quaternion().norm().min(1.0));
    translation + (2.0 * chord + 2.0 * (off_unit(from) + off_unit(to))) * reach
}

impl SeparationCertificates {
    /// Prepares the store for a call under the narrow-phase settings
    /// `settings`: clears it if they changed, drops the entries of dropped
    /// shapes and those the last call did not use.
    pub fn begin_call(&mut self, settings: &VClipSettings) {
        self.use_settings(settings);
        self.entries
            .retain(|_, entry| entry.used && entry.shapes.alive());
        self.entries
            .values_mut()
            .for_each(|entry| entry.used = false);
    }

    /// Clears the store if its entries were recorded under other
    /// narrow-phase settings than `settings` (which decide the solid of a
    /// curved part), and records these.
    pub fn use_settings(&mut self, settings: &VClipSettings) {
        if self.settings.as_ref() != Some(settings) {
            self.entries.clear();
            self.settings = Some(*settings);
        }
    }

    /// Whether the last answer of `pair` certifies that at the part poses
    /// `poses` it is separated by more than `margin` (module docs).
    pub fn certifies(
        &mut self,
        pair: BodyPair,
        parts: &SceneParts,
        poses: [&Isometry3<f64>; 2],
        margin: f64,
    ) -> bool {
        let Some(entry) = self.entries.get_mut(&pair) else {
            return false;
        };
        if !entry.belongs_to(parts, pair) {
            return false;
        }
        entry.used = true;
        let moved_a = motion_bound(&entry.poses[0], poses[0], entry.reach[0]);
        let moved_b = motion_bound(&entry.poses[1], poses[1], entry.reach[1]);
        let slack =
            CERTIFICATE_SLACK_RELATIVE * (entry.reach[0] + entry.reach[1] + entry.value.abs());
        let lower = entry.value - moved_a - moved_b;
        // A non-finite bound (a pose far out of range) certifies nothing.
        lower.is_finite() && lower - slack > margin
    }

    /// The recorded answer of `pair` if it was computed for these very
    /// solids at exactly the part poses `poses` (no motion at all: the
    /// answer itself is certified, whatever the pair's class).
    pub fn answer_at(
        &mut self,
        pair: BodyPair,
        parts: &SceneParts,
        poses: [&Isometry3<f64>; 2],
    ) -> Option<PairQuery> {
        let entry = self.entries.get_mut(&pair)?;
        let unmoved = entry.poses[0] == *poses[0] && entry.poses[1] == *poses[1];
        if !unmoved || !entry.belongs_to(parts, pair) {
            return None;
        }
        entry.used = true;
        Some(entry.query.clone())
    }

    /// Records the exact answer `query` of `pair` at the part poses
    /// `poses`.
    pub fn record(
        &mut self,
        pair: BodyPair,
        parts: &SceneParts,
        poses: [Isometry3<f64>; 2],
        query: &PairQuery,
    ) {
        let value = query.signed_value();
        if let Some(entry) = self.entries.get_mut(&pair)
            && entry.belongs_to(parts, pair)
        {
            // The same solids: only the answer and its poses change.
            entry.poses = poses;
            entry.value = value;
            entry.query = query.clone();
            entry.used = true;
            return;
        }
        let entry = Certificate {
            shapes: ShapeIdentity::of(shape_pair(parts.shapes(), pair)),
            solids: solids(parts, pair),
            reach: [pair.body_a, pair.body_b]
                .map(|part| reach(&parts.shapes()[part], parts.rounding(part).as_ref())),
            poses,
            value,
            query: query.clone(),
            used: true,
        };
        self.entries.insert(pair, entry);
    }

    /// Forgets every entry.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Number of pairs recorded.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is recorded.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

impl Certificate {
    /// Whether the entry was recorded for the very solids of `pair` now.
    fn belongs_to(&self, parts: &SceneParts, pair: BodyPair) -> bool {
        self.shapes.belongs_to(shape_pair(parts.shapes(), pair))
            && self.solids == solids(parts, pair)
    }
}

fn solids(parts: &SceneParts, pair: BodyPair) -> [PartSolid; 2] {
    [pair.body_a, pair.body_b].map(|part| PartSolid {
        rounding: parts.rounding(part),
        curved: parts.curved(part),
    })
}
