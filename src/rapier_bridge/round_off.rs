//! The lengths of one bridge call, chosen so that rounding the written
//! poses to f32 cannot undo the correction.
//!
//! # The bound
//!
//! A written pose is the body pose `B' = U' P^-1` rounded to f32
//! ([`super::pose_from_f64`]). With `u = 2^-24` (f32 unit round-off):
//! - each translation component moves by at most `u |t_i|`, so the origin
//!   by at most `u |t|`;
//! - each quaternion component moves by at most `u` (they are at most 1),
//!   `u` in norm, and the f32 renormalization adds at most about as much
//!   again; a quaternion error `e` perpendicular to `q` turns the rotation
//!   by `2 |e|`, so the rotation changes by at most [`ROTATION_ROUND_OFF`]
//!   `= 4 u` radians.
//!
//! (The unit test below checks both on a grid of 729 poses; the worst
//! ratios measured are in `benchmarks/results/rapier_bridge.md`. The
//! angle is that of the quaternion as read back, renormalized
//! in f64; the f32 quaternion's own norm error, at most about `u`, scales a
//! point by about `2 u r` where Rapier uses it unnormalized, which the
//! slack of the rotation term covers.)
//!
//! A collider point at lever `r` from the body origin therefore moves by
//! at most
//!
//! ```text
//! delta = u (|t| + 4 r)
//! ```
//!
//! taken as the largest over the dynamic bodies (the only ones written;
//! fixed and kinematic poses are read from f32 and never rounded again)
//! that can touch another body: whose box, grown by the contact margin,
//! overlaps another's at the start of the call, or that a joint holds
//! (a joint's anchor moves as a collider point does, its distance from
//! the body origin counted in `r`). A body farther from every
//! other is never moved into contact by its rounding (far smaller than
//! the margin), so its `delta`, large far from the origin, does not
//! change any depth (counted over every dynamic body, a box thrown 350 m
//! away would give each call `delta` of about 2e-5 and a tolerance of
//! 1.7e-4 on a stack of 20 cm boxes near the origin, and closed contacts
//! would leave that stack that deep). `r` is bounded by the shape's reach
//! from its centre of mass ([`crate::body::Body::reach`]) plus the
//! distance from the body origin to that centre. The depth of a pair of
//! two written bodies changes by at most `2 delta`.
//!
//! # The rule
//!
//! The call's tolerance is at least [`TOLERANCE_PER_ROUND_OFF`]` * delta`
//! and its target margin at least [`TARGET_PER_ROUND_OFF`]` * delta`
//! (the stabilizer's own lengths when larger):
//! - a corrected contact aims at a gap of at least `4 delta`, twice what
//!   rounding can take away, so it is left separated in f32 unless the
//!   linearization missed its target by more than `2 delta`;
//! - rounding adds at most `2 delta`, a quarter of the tolerance, to any
//!   depth: the f32 world's deepest penetration is at most the call's depth
//!   after plus `2 delta` ([`super::BridgeReport::written_depth_bound`]),
//!   so at most `1.25` times the tolerance in the worst case, and within the
//!   tolerance whenever the corrected contacts reached their target (the
//!   tests measure it on the f32 world);
//! - outside closed contacts the call is solved to its tolerance lowered
//!   by `2 delta` (`lowered_for_round_off`) and states the tolerance
//!   itself: a contact that stopped short of its target (a curved pair
//!   whose last linearization left it between the two) is then still
//!   within the stated tolerance once written in f32. Closed contacts are
//!   solved to the tolerance itself (a tighter solve of every call changed
//!   their held cycles: the settled pile of 200 of
//!   `examples/with_and_without.rs` crept 177 mm instead of 0.63 mm,
//!   `benchmarks/results/round_shapes.md`). Only when a call resolved with
//!   its exact depth after within `2 delta` of the tolerance is a copy of
//!   the scene, the bodies it moved at their poses as written (rounded to
//!   f32 and read back), measured by a copy of the stabilizer; if the
//!   rounding took a pair beyond the tolerance, the call is solved again,
//!   from its answer, to the lowered tolerance. So the f32 world is within
//!   the stated tolerance in every mode, and a call that needs no second
//!   solve leaves the trajectory as it was.
//!
//! Positions near 10 with bodies of size 1 give `delta` of about 9e-7 and
//! a tolerance of about 7e-6; the stabilizer's default (1e-6 of the
//! smallest body) is kept wherever it is larger.

use super::body_map::BodyMap;
use crate::broad_phase::{candidate_pairs, grown_boxes, has_candidate_pair};
use crate::scene::Scene;
use crate::settings::{ResolvedLengths, Settings};
use crate::stabilizer::scene_scale;

/// f32 unit round-off `2^-24`: the largest relative error of rounding an
/// f64 to the nearest f32.
pub const F32_UNIT_ROUND_OFF: f64 = f32::EPSILON as f64 / 2.0;

/// Largest rotation angle (radians) by which rounding a unit quaternion to
/// f32 and renormalizing it in f32 turns it: `4 u` (see the module docs).
pub const ROTATION_ROUND_OFF: f64 = 4.0 * F32_UNIT_ROUND_OFF;

/// The call's tolerance is at least this many `delta`: rounding adds at
/// most `2 delta`, a quarter of it.
pub const TOLERANCE_PER_ROUND_OFF: f64 = 8.0;

/// The call's target margin is at least this many `delta`: twice the
/// `2 delta` that rounding can take from a gap.
pub const TARGET_PER_ROUND_OFF: f64 = 4.0;

/// The most rounding the written poses can add to the depth of a pair, in
/// units of the round-off bound `delta`: each of the two bodies' points
/// moves by at most `delta`.
pub const ROUNDING_DEPTH_FACTOR: f64 = 2.0;

/// `delta`: the most a collider point of a written body can move when its
/// pose is rounded to f32, over the dynamic bodies that can touch another
/// body (module docs: a body farther than the contact margin from every
/// other cannot be moved into contact by a rounding); 0 without them.
/// The restriction is computed only when the bound over all dynamic
/// bodies would raise the lengths of `settings` (otherwise that bound is
/// returned), and then by scanning the bodies in decreasing `delta`: the
/// first that can touch another (a candidate pair of the broad phase's
/// test, one body's boxes scanned, or a joint) gives the maximum. In a
/// scene where the bodies touch, that is the first or one of the first,
/// `O(n)` against a broad phase's hierarchy; after
/// [`ROUND_OFF_SCAN_LIMIT`] bodies that touch nothing the broad phase
/// answers for the rest. `own` are the stabilizer's own lengths on the
/// scene ([`own_lengths`]).
pub(crate) fn write_back_round_off_bound(
    scene: &Scene,
    map: &BodyMap,
    own: &ResolvedLengths,
) -> f64 {
    // The farthest joint anchor of each body from its origin (0 without
    // joints): rounding moves an anchor as it moves a collider point.
    let mut anchor_reach = vec![0.0_f64; scene.len()];
    for joint in scene.joints() {
        for (body, frame) in [
            (joint.body_a, &joint.frame_a),
            (joint.body_b, &joint.frame_b),
        ] {
            if let (Some(entry), Some(reach)) = (map.entry(body), anchor_reach.get_mut(body)) {
                let in_body = entry.collider_in_body * frame.translation.vector;
                *reach = reach.max(in_body.norm());
            }
        }
    }
    let deltas: Vec<(usize, f64)> = map
        .entries()
        .iter()
        .zip(scene.bodies())
        .zip(&anchor_reach)
        .enumerate()
        .filter(|(_, ((entry, _), _))| entry.is_dynamic())
        .map(|(index, ((entry, body), &anchor))| {
            let body_pose = body.user_pose() * entry.collider_in_body.inverse();
            let origin = body_pose.translation.vector;
            let lever = (body.reach() + (body.com_world().coords - origin).norm()).max(anchor);
            (
                index,
                F32_UNIT_ROUND_OFF * origin.norm() + ROTATION_ROUND_OFF * lever,
            )
        })
        .collect();
    let largest = deltas.iter().map(|&(_, d)| d).fold(0.0, f64::max);
    let raises_lengths = TOLERANCE_PER_ROUND_OFF * largest > own.tolerance
        || TARGET_PER_ROUND_OFF * largest > own.target_margin;
    if !raises_lengths {
        return largest;
    }
    let mut joined = vec![false; scene.len()];
    for joint in scene.joints() {
        for body in [joint.body_a, joint.body_b] {
            if let Some(flag) = joined.get_mut(body) {
                *flag = true;
            }
        }
    }
    // Boxes that fail the broad phase's checks (they cannot for valid
    // bodies) keep the bound over every dynamic body.
    let Ok(boxes) = grown_boxes(scene, own.contact_margin) else {
        return largest;
    };
    let fixed = scene.fixed_flags();
    let mut by_delta = deltas.clone();
    by_delta.sort_by(|(_, x), (_, y)| y.total_cmp(x));
    for &(index, delta) in by_delta.iter().take(ROUND_OFF_SCAN_LIMIT) {
        if joined[index] || has_candidate_pair(&boxes, &fixed, index) {
            return delta;
        }
    }
    if by_delta.len() <= ROUND_OFF_SCAN_LIMIT {
        return 0.0;
    }
    // Many bodies alone: the broad phase for the rest.
    let Ok(pairs) = candidate_pairs(scene, own.contact_margin) else {
        return largest;
    };
    let mut touching = joined;
    for pair in &pairs {
        touching[pair.body_a] = true;
        touching[pair.body_b] = true;
    }
    deltas
        .iter()
        .filter(|&&(index, _)| touching[index])
        .map(|&(_, d)| d)
        .fold(0.0, f64::max)
}

/// Bodies scanned one by one, in decreasing `delta`, for one that can
/// touch another, before the broad phase answers for the rest (the
/// bridge's bound of the write-back's rounding, module docs).
pub const ROUND_OFF_SCAN_LIMIT: usize = 8;

/// The stabilizer's own lengths on `scene` (its settings without an
/// allowed penetration), which the rule raises.
pub(crate) fn own_lengths(settings: &Settings, scene: &Scene) -> ResolvedLengths {
    Settings {
        allowed_penetration: 0.0,
        ..settings.clone()
    }
    .resolve(scene_scale(scene))
}

/// The lengths of one call: `own` (from [`own_lengths`]) with the
/// tolerance and target margin raised to the rule's for `round_off_bound`,
/// before any allowed penetration.
pub(crate) fn raised_lengths(own: &ResolvedLengths, round_off_bound: f64) -> ResolvedLengths {
    ResolvedLengths {
        tolerance: own.tolerance.max(TOLERANCE_PER_ROUND_OFF * round_off_bound),
        target_margin: own
            .target_margin
            .max(TARGET_PER_ROUND_OFF * round_off_bound),
        ..*own
    }
}

/// The lengths a call outside closed contacts is solved to: `stated` with
/// its tolerance lowered by the `2 delta` that rounding the written poses
/// to f32 can add to a depth (module docs), so that the f32 world meets
/// the tolerance `stated` names. The target margin is kept: it is at
/// least `4 delta` above the tolerance's floor, so the contacts still aim
/// at a gap.
pub(crate) fn lowered_for_round_off(
    stated: ResolvedLengths,
    round_off_bound: f64,
) -> ResolvedLengths {
    ResolvedLengths {
        tolerance: stated.tolerance - ROUNDING_DEPTH_FACTOR * round_off_bound,
        ..stated
    }
}
