//! Mirtich's experiments (V-Clip, 1998, section 6), shared by the tests and
//! the benchmark: the coherence path (Algorithm 9) and the degeneracy trials
//! of two cubes (Algorithm 10).

use constraint_stabilization::internals::geometry::ConvexPolyhedron;
use constraint_stabilization::internals::vclip::{FeaturePair, Outcome, VClip, VClipResult};
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use rand::Rng;

use super::{brute_force_distance, parry_distance, parry_intersects, parry_shape};
use crate::random::random_rotation;

/// Mirtich's four shapes: cube (side 2), icosahedron, disk (60-gon faces,
/// radius : thickness = 10 : 1), geodesic sphere with 642 vertices; all of
/// circumradius near 1.
pub fn mirtich_shapes() -> Vec<(&'static str, ConvexPolyhedron)> {
    vec![
        (
            "cube",
            ConvexPolyhedron::cuboid(Vector3::new(1.0, 1.0, 1.0)).unwrap(),
        ),
        ("icosahedron", ConvexPolyhedron::icosahedron(1.0).unwrap()),
        ("disk", ConvexPolyhedron::disk(1.0, 0.1, 60).unwrap()),
        (
            "sphere642",
            ConvexPolyhedron::geodesic_sphere(1.0, 3).unwrap(),
        ),
    ]
}

/// One run of Algorithm 9: body 2 at `(A cos(θ + px), A cos(θ + py),
/// A cos(θ + pz))` rotated by `θ` about `axis`, `θ = ω i`.
pub struct CoherenceRun {
    phases: [f64; 3],
    axis: Unit<Vector3<f64>>,
    amplitude: f64,
    omega: f64,
}

impl CoherenceRun {
    /// Random phases and axis; the amplitude keeps the bounding spheres of
    /// two bodies of circumradius `radius` apart by 5 % at least.
    /// `|p|² = A² Σ cos²(θ + p_i) >= A² (3/2 - |Σ exp(2 i p_i)| / 2)`.
    pub fn new(rng: &mut impl Rng, radius: f64, omega_degrees: f64) -> Self {
        loop {
            let phases = [0; 3].map(|_| rng.random_range(0.0..std::f64::consts::TAU));
            let (re, im) = phases.iter().fold((0.0, 0.0), |(re, im), p| {
                (re + (2.0 * p).cos(), im + (2.0 * p).sin())
            });
            let min_sum = 1.5 - 0.5 * (re * re + im * im).sqrt();
            if min_sum > 0.1 {
                let axis = Unit::new_normalize(random_rotation(rng) * Vector3::x());
                return CoherenceRun {
                    phases,
                    axis,
                    amplitude: 2.1 * radius / min_sum.sqrt(),
                    omega: omega_degrees.to_radians(),
                };
            }
        }
    }

    /// Pose of body 2 at step `i`.
    pub fn pose(&self, i: usize) -> Isometry3<f64> {
        let theta = self.omega * i as f64;
        let t = Vector3::from(self.phases.map(|p| self.amplitude * (theta + p).cos()));
        Isometry3::from_parts(
            Translation3::from(t),
            UnitQuaternion::from_axis_angle(&self.axis, theta),
        )
    }
}

/// Counts of a degeneracy experiment.
#[derive(Debug, Default, Clone, Copy)]
pub struct DegeneracyCounts {
    pub trials: usize,
    pub queries: usize,
    /// Queries that fell back to the exhaustive search (an unresolved cycle
    /// or the iteration cap).
    pub cycles: usize,
    /// Queries whose walk revisited a state and were resolved by the
    /// closest-pair test (rounding ties).
    pub resolved_ties: usize,
    /// Queries where parry's GJK distance differs from the brute-force
    /// distance by more than `agreement * scale` (oracle noise, for the
    /// record; not counted as wrong).
    pub parry_off: usize,
    /// Wrong answers: separated while parry's intersection test says
    /// intersecting, beyond its fuzz band; separated at a distance that
    /// differs from the brute-force distance by more than
    /// `agreement * scale` (bodies disjoint for parry); penetrating while
    /// parry says disjoint beyond the fuzz band.
    pub wrong: usize,
    /// Trials whose end poses had different closest features (the binary
    /// search ran).
    pub boundary_searches: usize,
}

/// A pose of a cube (half extent 1) near cube 1 (at the origin), drawn to
/// favour nearly parallel faces and edges: one of the 24 rotations of the
/// cube, perturbed by a rotation of angle 0 or 10^-k (k = 1..12), placed
/// across a face of cube 1 at gap `gap` with the lateral offsets often near
/// the edge-aligned values 0 and ±2.
pub fn near_parallel_cube_pose(rng: &mut impl Rng, gap: f64) -> Isometry3<f64> {
    let quarter = std::f64::consts::FRAC_PI_2;
    let turn = |axis: Vector3<f64>, k: usize| {
        UnitQuaternion::from_axis_angle(&Unit::new_normalize(axis), quarter * k as f64)
    };
    let symmetric = turn(Vector3::x(), rng.random_range(0..4))
        * turn(Vector3::y(), rng.random_range(0..4))
        * turn(Vector3::z(), rng.random_range(0..2));
    let angle = if rng.random_bool(0.2) {
        0.0
    } else {
        10f64.powi(-rng.random_range(1..=12))
    };
    let tilt_axis = Unit::new_normalize(random_rotation(rng) * Vector3::x());
    let rotation = UnitQuaternion::from_axis_angle(&tilt_axis, angle) * symmetric;
    let axis = rng.random_range(0..3);
    let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let mut t = Vector3::zeros();
    for k in 0..3 {
        t[k] = if k == axis {
            sign * (2.0 + gap)
        } else if rng.random_bool(0.5) {
            [-2.0, 0.0, 2.0][rng.random_range(0..3)] + rng.random_range(-1e-6..1e-6)
        } else {
            rng.random_range(-2.2..2.2)
        };
    }
    Isometry3::from_parts(Translation3::from(t), rotation)
}

/// Mirtich's Algorithm 10: `trials` trials, each between a touching (gap 0)
/// and a separated pose of the second cube, binary-searching (`depth`
/// halvings) for where the closest features change. Every query is warm
/// started from the previous one and checked against parry.
pub fn degeneracy_experiment(
    rng: &mut impl Rng,
    engine: &VClip,
    trials: usize,
    depth: usize,
    agreement: f64,
    parry_fuzz: f64,
) -> DegeneracyCounts {
    let cube = ConvexPolyhedron::cuboid(Vector3::new(1.0, 1.0, 1.0)).unwrap();
    let parry_cube = parry_shape(&cube);
    let origin = Isometry3::identity();
    let scale = cube.scale();
    let mut counts = DegeneracyCounts::default();
    let mut warm: Option<FeaturePair> = None;
    let mut query = |pose: &Isometry3<f64>, counts: &mut DegeneracyCounts| -> VClipResult {
        let result = engine.query(&cube, &origin, &cube, pose, warm).unwrap();
        warm = Some(result.final_pair);
        counts.queries += 1;
        counts.cycles += result.fell_back() as usize;
        counts.resolved_ties += result.resolved_cycle as usize;
        let parry_d = parry_distance(&parry_cube, &origin, &parry_cube, pose);
        let intersects = parry_intersects(&parry_cube, &origin, &parry_cube, pose);
        let wrong = match result.outcome {
            Outcome::Separated { distance, .. } if intersects => distance > parry_fuzz * scale,
            Outcome::Separated { distance, .. } => {
                let exact = brute_force_distance(&cube, &origin, &cube, pose);
                counts.parry_off += ((parry_d - exact).abs() > agreement * scale) as usize;
                (distance - exact).abs() > agreement * scale
            }
            Outcome::Penetrating(_) => !intersects && parry_d > parry_fuzz * scale,
        };
        counts.wrong += wrong as usize;
        result
    };
    for _ in 0..trials {
        counts.trials += 1;
        let touching = near_parallel_cube_pose(rng, 0.0);
        let gap = rng.random_range(1e-9..0.5);
        let separated = near_parallel_cube_pose(rng, gap);
        let at = |s: f64| interpolate(&touching, &separated, s);
        let (mut lo, mut hi) = (0.0, 1.0);
        let lo_pair = query(&at(lo), &mut counts).final_pair;
        let hi_pair = query(&at(hi), &mut counts).final_pair;
        if lo_pair == hi_pair {
            continue;
        }
        counts.boundary_searches += 1;
        for _ in 0..depth {
            let mid = 0.5 * (lo + hi);
            if query(&at(mid), &mut counts).final_pair == lo_pair {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    }
    counts
}

/// `(1 - s) a + s b` for translations, slerp for rotations (renormalized).
pub fn interpolate(a: &Isometry3<f64>, b: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    let pose = a.lerp_slerp(b, s);
    // slerp drifts off unit norm by about 1e-9; the oracles need a rigid pose.
    let rotation = UnitQuaternion::new_normalize(pose.rotation.into_inner());
    Isometry3::from_parts(pose.translation, rotation)
}
