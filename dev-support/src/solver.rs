//! Random contact-like projection QPs ([`random_stacks`]), shared by the
//! solver tests and `benchmarks/solvers.rs`. (The oracles the tests judge
//! answers by, and the Siconos files, are in `tests/it/support`.)
//!
//! A grid of stacks of boxes on a fixed ground: every box rests face-down on
//! the box below (or the ground) through its four bottom corners, so four
//! coplanar rows constrain three degrees of freedom of the pair (the LCP
//! matrix `A = J M^-1 J^T` is singular: `lambda` is not unique). Neighbouring
//! stacks touch sideways through two corner rows. Depths are random; some
//! rows are near contacts (`phi > target`), some exactly at the target.
//! Masses are log-uniform over four decades around `mass_scale`; all lengths
//! (sizes, positions, `phi`, `target`) are multiplied by `length_scale`.

use constraint_stabilization::solver::{BodyMetric, JacobianRow, ProjectionQp};
use nalgebra::{Matrix3, Rotation3, Vector3, Vector6};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Shape of a random problem.
#[derive(Debug, Clone, Copy)]
pub struct StackSpec {
    /// Approximate number of rows wanted.
    pub rows: usize,
    /// Multiplies every length.
    pub length_scale: f64,
    /// Centre of the mass range.
    pub mass_scale: f64,
    /// Decades of mass spread (masses in `mass_scale * 10^[-spread/2, spread/2]`).
    pub mass_decades: f64,
    /// Seed.
    pub seed: u64,
}

impl StackSpec {
    /// Unit scales, two decades of masses.
    pub fn new(rows: usize, seed: u64) -> Self {
        Self {
            rows,
            length_scale: 1.0,
            mass_scale: 1.0,
            mass_decades: 2.0,
            seed,
        }
    }
}

struct Box3 {
    centre: Vector3<f64>,
    half: Vector3<f64>,
}

fn contact_row(
    p: Vector3<f64>,
    n: Vector3<f64>,
    a: Option<(usize, &Box3)>,
    b: Option<(usize, &Box3)>,
) -> JacobianRow {
    let mut blocks = Vec::new();
    if let Some((k, body)) = a {
        let r = p - body.centre;
        let ang = r.cross(&n);
        blocks.push((k, Vector6::new(n.x, n.y, n.z, ang.x, ang.y, ang.z)));
    }
    if let Some((k, body)) = b {
        let r = p - body.centre;
        let ang = -r.cross(&n);
        blocks.push((k, Vector6::new(-n.x, -n.y, -n.z, ang.x, ang.y, ang.z)));
    }
    JacobianRow { blocks }
}

fn body_metric(rng: &mut ChaCha8Rng, spec: &StackSpec, half: &Vector3<f64>) -> BodyMetric {
    let exponent = rng.random_range(-0.5..=0.5) * spec.mass_decades;
    let mass = spec.mass_scale * 10f64.powf(exponent);
    let (x, y, z) = (2.0 * half.x, 2.0 * half.y, 2.0 * half.z);
    let diag = Vector3::new(y * y + z * z, x * x + z * z, x * x + y * y) * (mass / 12.0);
    let axis = Vector3::new(rng.random(), rng.random(), rng.random::<f64>()) - Vector3::repeat(0.5);
    let rot = Rotation3::new(axis * rng.random_range(0.0..0.3));
    let inertia_world: Matrix3<f64> =
        rot.matrix() * Matrix3::from_diagonal(&diag) * rot.matrix().transpose();
    BodyMetric {
        mass,
        inertia_world: (inertia_world + inertia_world.transpose()) * 0.5,
    }
}

fn gap(rng: &mut ChaCha8Rng, scale: f64, target: f64) -> f64 {
    match rng.random_range(0..10) {
        0 => target,
        1 | 2 => rng.random_range(0.0..0.02) * scale,
        _ => -rng.random_range(0.0..0.05) * scale,
    }
}

/// A random stack problem with exactly `spec.rows` rows (at least one):
/// generated with a few more, shuffled, then truncated.
pub fn random_stacks(spec: &StackSpec) -> ProjectionQp {
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
    let l = spec.length_scale;
    let target_margin = 1e-3 * l;
    let boxes_wanted = spec.rows.div_ceil(4).max(1);
    let height = ((boxes_wanted as f64).sqrt().ceil() as usize).clamp(1, 8);
    let stacks = boxes_wanted.div_ceil(height);
    let mut qp = ProjectionQp::default();
    let mut boxes: Vec<Box3> = Vec::new();
    let mut grid: Vec<Vec<usize>> = Vec::new();
    for s in 0..stacks {
        let mut column = Vec::new();
        let mut bottom = 0.0;
        for _ in 0..height {
            if boxes.len() == boxes_wanted {
                break;
            }
            let half = Vector3::new(
                rng.random_range(0.4..0.5),
                rng.random_range(0.2..0.5),
                rng.random_range(0.4..0.5),
            ) * l;
            let centre = Vector3::new(s as f64 * l, bottom + half.y, 0.0);
            bottom += 2.0 * half.y;
            qp.bodies.push(body_metric(&mut rng, spec, &half));
            column.push(boxes.len());
            boxes.push(Box3 { centre, half });
        }
        grid.push(column);
    }
    let up = Vector3::y();
    for column in &grid {
        for (level, &k) in column.iter().enumerate() {
            let body = &boxes[k];
            for (sx, sz) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p =
                    body.centre + Vector3::new(sx * body.half.x, -body.half.y, sz * body.half.z);
                let below = (level > 0).then(|| (column[level - 1], &boxes[column[level - 1]]));
                qp.rows.push(contact_row(p, up, Some((k, body)), below));
                qp.phi.push(gap(&mut rng, l, target_margin));
                qp.target.push(target_margin);
            }
        }
    }
    for pair in grid.windows(2) {
        for (&left, &right) in pair[0].iter().zip(&pair[1]) {
            let (a, b) = (&boxes[right], &boxes[left]);
            for sz in [-1.0, 1.0] {
                let p = a.centre + Vector3::new(-a.half.x, 0.0, sz * a.half.z);
                qp.rows.push(contact_row(
                    p,
                    Vector3::x(),
                    Some((right, a)),
                    Some((left, b)),
                ));
                qp.phi.push(gap(&mut rng, l, target_margin));
                qp.target.push(target_margin);
            }
        }
    }
    let mut order: Vec<usize> = (0..qp.rows.len()).collect();
    order.shuffle(&mut rng);
    order.truncate(spec.rows.max(1));
    ProjectionQp {
        rows: order.iter().map(|&i| qp.rows[i].clone()).collect(),
        phi: order.iter().map(|&i| qp.phi[i]).collect(),
        target: order.iter().map(|&i| qp.target[i]).collect(),
        bodies: qp.bodies,
        ..Default::default()
    }
}
