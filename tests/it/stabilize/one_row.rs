//! The minimal correction for one contact row in closed form (docs/design.md
//! section 3), derived here and not taken from the library, and the
//! comparison of a body's measured motion against it: the stabilizer tests
//! that check the mass-weighted split (`minimal`, `scenes`).
#![allow(dead_code)]

use constraint_stabilization::scene::Scene;
use nalgebra::{Isometry3, Matrix3, UnitQuaternion, Vector3};

/// World-frame inverse inertia of a solid box of `mass` and `half_extents`
/// turned by `rotation`, in closed form (`I = m/3 diag(b^2 + c^2, a^2 + c^2,
/// a^2 + b^2)` for half extents `a, b, c`), not from the library.
pub fn cuboid_inverse_inertia_world(
    mass: f64,
    half_extents: &Vector3<f64>,
    rotation: &UnitQuaternion<f64>,
) -> Matrix3<f64> {
    let [a2, b2, c2] = [0, 1, 2].map(|k| half_extents[k] * half_extents[k]);
    let inverse_body = Matrix3::from_diagonal(&Vector3::new(
        3.0 / (mass * (b2 + c2)),
        3.0 / (mass * (a2 + c2)),
        3.0 / (mass * (a2 + b2)),
    ));
    let r = rotation.to_rotation_matrix();
    r.matrix() * inverse_body * r.matrix().transpose()
}

/// A dynamic body's part in one contact row: its inverse mass, world
/// inverse inertia and centre of mass, and the side of the row it is on
/// (`+1` for the body the normal points towards, `-1` for the other).
pub struct RowMember {
    /// `1 / m`.
    pub inverse_mass: f64,
    /// World-frame `I^-1`.
    pub inverse_inertia: Matrix3<f64>,
    /// Centre of mass, world frame.
    pub centre: Vector3<f64>,
    /// `+1` or `-1`.
    pub side: f64,
}

impl RowMember {
    /// A dynamic box: mass, half extents, and its pose (centre, rotation).
    pub fn cuboid(
        mass: f64,
        half_extents: [f64; 3],
        centre: Vector3<f64>,
        rotation: &UnitQuaternion<f64>,
        side: f64,
    ) -> Self {
        let half_extents = Vector3::from(half_extents);
        RowMember {
            inverse_mass: 1.0 / mass,
            inverse_inertia: cuboid_inverse_inertia_world(mass, &half_extents, rotation),
            centre,
            side,
        }
    }
}

/// A body's correction: translation and world rotation vector.
#[derive(Debug, Clone, Copy)]
pub struct Correction {
    /// `dx`.
    pub dx: Vector3<f64>,
    /// `dtheta` (the body turns by `exp(dtheta)`).
    pub dtheta: Vector3<f64>,
}

/// The minimal correction for one contact row, derived here (docs/design.md
/// section 3): the row at world point `point` with unit normal `normal` has
/// `J_i = side_i [n^T, (r_i x n)^T]` with `r_i = point - centre_i`, and
/// `dq = M^-1 J^T lambda`, `lambda = (target - phi) / (J M^-1 J^T)`.
/// Fixed bodies have no columns: leave them out of `members`.
pub fn one_row_correction(
    members: &[RowMember],
    point: &Vector3<f64>,
    normal: &Vector3<f64>,
    phi: f64,
    target: f64,
) -> Vec<Correction> {
    let columns: Vec<(Vector3<f64>, Vector3<f64>)> = members
        .iter()
        .map(|m| {
            let r_cross_n = (point - m.centre).cross(normal);
            (
                normal * (m.side * m.inverse_mass),
                m.inverse_inertia * r_cross_n * m.side,
            )
        })
        .collect();
    let effective: f64 = members
        .iter()
        .zip(&columns)
        .map(|(m, (dx, dtheta))| {
            m.side * (normal.dot(dx) + (point - m.centre).cross(normal).dot(dtheta))
        })
        .sum();
    let lambda = (target - phi) / effective;
    columns
        .into_iter()
        .map(|(dx, dtheta)| Correction {
            dx: dx * lambda,
            dtheta: dtheta * lambda,
        })
        .collect()
}

/// A bound on the second-order remainder of a one-row linearization over
/// the correction: every second-order term of `phi(q + dq)` is a rotation
/// times the displacement of a point (the contact point of a body, or the
/// face normal turning while the points move apart), so it is at most
/// `(sum |dtheta_i|) * (sum |dx_i| + |r_i| |dtheta_i|)` with `|r_i|` the
/// lever of body `i`. Later passes remove at most this much penetration.
pub fn second_order_remainder(corrections: &[Correction], levers: &[f64]) -> f64 {
    let turn: f64 = corrections.iter().map(|c| c.dtheta.norm()).sum();
    let reach: f64 = corrections
        .iter()
        .zip(levers)
        .map(|(c, lever)| c.dx.norm() + lever * c.dtheta.norm())
        .sum();
    turn * reach
}

/// A body's motion between two poses: translation of the centre of mass
/// and the world rotation vector of `R_after R_before^-1`.
pub fn motion(before: &Isometry3<f64>, after: &Isometry3<f64>) -> Correction {
    Correction {
        dx: after.translation.vector - before.translation.vector,
        dtheta: (after.rotation * before.rotation.inverse()).scaled_axis(),
    }
}

/// World positions of a body's vertices.
pub fn world_vertices(scene: &Scene, index: usize) -> Vec<Vector3<f64>> {
    let body = &scene.bodies()[index];
    body.parts()
        .iter()
        .zip(body.part_poses())
        .flat_map(|(part, pose)| {
            part.polyhedron()
                .vertices()
                .iter()
                .map(move |v| (pose * v).coords)
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The body's vertices sorted by their height along `direction`, lowest
/// first.
pub fn vertices_by_height(
    scene: &Scene,
    index: usize,
    direction: &Vector3<f64>,
) -> Vec<Vector3<f64>> {
    let mut vertices = world_vertices(scene, index);
    vertices.sort_by(|p, q| direction.dot(p).total_cmp(&direction.dot(q)));
    vertices
}

/// How many times [`second_order_remainder`] (relative to the first-order
/// push `target - phi`) a body's motion may differ from the one-row closed
/// form, relative to that motion: later passes (or the rest of a shortened
/// line-search step) remove a leftover penetration of at most the
/// remainder, along nearly the same row, so they scale the closed form by
/// at most that fraction; twice that covers the change of the row between
/// passes (itself first order in the rotation).
pub const SECOND_ORDER_FACTOR: f64 = 2.0;

/// The relative tolerance of a comparison with the one-row closed form must
/// stay below this, or the comparison could not tell a right split from a
/// wrong one (the scene's depth is then too large for a first-order check).
pub const DISCRIMINATING_TOLERANCE: f64 = 0.02;

/// Asserts that each body moved as its one-row closed form `expected`, to
/// `relative` of each part (translation, rotation) of that motion, and
/// that `relative` is below [`DISCRIMINATING_TOLERANCE`].
pub fn assert_motions_match(
    label: &str,
    measured: &[Correction],
    expected: &[Correction],
    relative: f64,
) {
    assert!(
        relative <= DISCRIMINATING_TOLERANCE,
        "{label}: relative tolerance {relative:e} cannot discriminate"
    );
    for (k, (m, e)) in measured.iter().zip(expected).enumerate() {
        println!(
            "{label}: body {k}: dx {:?} vs {:?}, dtheta {:?} vs {:?} (relative tolerance {relative:.2e})",
            m.dx, e.dx, m.dtheta, e.dtheta
        );
        assert!(
            (m.dx - e.dx).norm() <= relative * e.dx.norm(),
            "{label}: body {k} translated by {:?}, closed form {:?}",
            m.dx,
            e.dx
        );
        assert!(
            (m.dtheta - e.dtheta).norm() <= relative * e.dtheta.norm(),
            "{label}: body {k} turned by {:?}, closed form {:?}",
            m.dtheta,
            e.dtheta
        );
    }
}

/// The relative tolerance of a one-row comparison: the second-order
/// remainder and the stabilizer's depth tolerance (the final gap may lie
/// anywhere between `-tolerance` and the target), both relative to the
/// first-order push `target - phi`.
pub fn one_row_tolerance(
    corrections: &[Correction],
    levers: &[f64],
    push: f64,
    depth_tolerance: f64,
) -> f64 {
    (SECOND_ORDER_FACTOR * second_order_remainder(corrections, levers) + depth_tolerance) / push
}
