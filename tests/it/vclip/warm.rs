//! Warm starts: a query started from any valid feature pair gives the same
//! answer as a cold one (Mirtich 1998, Theorem 2: any start converges), and
//! bad input is rejected with a typed error.

use constraint_stabilization::internals::contact::minimum_translation;
use constraint_stabilization::internals::geometry::{ConvexPolyhedron, Feature};
use constraint_stabilization::internals::vclip::{
    BodyRole, DeepestVertex, FeaturePair, Outcome, VClipError, VClipResult, vclip,
};
use dev_support::random::{random_hull_varied, random_pose};
use dev_support::sat::PARALLEL_EDGES;
use dev_support::vclip::experiments::{CoherenceRun, mirtich_shapes};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Agreement of warm and cold answers (distance, depth, witness points),
/// relative to scale: both are computed from the same features up to the
/// order of the walk, so they agree to rounding.
const AGREEMENT: f64 = 1e-9;

/// A vertex is in a body's support set along a direction when it is within
/// this (relative to scale) of the support value: it decides whether the
/// closest points are unique.
const SUPPORT_TIE: f64 = 1e-9;

/// Rounding allowance for the depth of the coincident cubes (half extents
/// 1, 2, 3; exact depth 2): coordinates of order 3, a few operations.
const COINCIDENT_DEPTH_ROUNDING: f64 = 1e-12;

/// The vertices of `poly` (at `pose`) within `SUPPORT_TIE * scale` of its
/// support value along `direction` (world frame).
fn support_set(
    poly: &ConvexPolyhedron,
    pose: &Isometry3<f64>,
    direction: &Vector3<f64>,
    scale: f64,
) -> Vec<Vector3<f64>> {
    let world: Vec<Vector3<f64>> = poly.vertices().iter().map(|p| (pose * p).coords).collect();
    let top = world
        .iter()
        .map(|v| direction.dot(v))
        .fold(f64::NEG_INFINITY, f64::max);
    world
        .into_iter()
        .filter(|v| direction.dot(v) >= top - SUPPORT_TIE * scale)
        .collect()
}

/// Whether the closest points of two separated bodies are unique: with `n`
/// the unit closest direction (A to B), the contact set is the
/// intersection of A's support set along `n` with B's along `-n` (shifted);
/// it is one point when either set is one vertex, or both are edges that
/// are not parallel.
fn closest_points_are_unique(
    a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
    n: &Vector3<f64>,
) -> bool {
    let scale = a.scale().max(b.scale());
    let (sa, sb) = (
        support_set(a, pose_a, n, scale),
        support_set(b, pose_b, &-n, scale),
    );
    match (sa.len(), sb.len()) {
        (1, _) | (_, 1) => true,
        (2, 2) => {
            let (u, v) = (sa[1] - sa[0], sb[1] - sb[0]);
            u.cross(&v).norm() > PARALLEL_EDGES.sqrt() * u.norm() * v.norm()
        }
        _ => false,
    }
}

/// Counts of [`assert_same_answer`]: answers compared, and how many had
/// unique closest points (witnesses compared).
#[derive(Debug, Default)]
struct Compared {
    separated: usize,
    unique_witnesses: usize,
    penetrating: usize,
    /// `(warm depth, cold depth)` of the penetrating answers whose exact
    /// depths (the minimum translation searched from each answer's deepest
    /// vertex) differ by more than [`AGREEMENT`] (checked last, so that
    /// every other comparison runs first).
    depth_mismatches: Vec<(f64, f64)>,
}

/// Warm and cold answers agree: same outcome kind; when separated, the
/// same distance and closest vector `witness_b - witness_a` (unique for
/// convex bodies), and the same witness points where the closest points
/// are unique; when penetrating, the same exact depth (the library's
/// answer: `contact::minimum_translation` from each deepest vertex), and
/// each deepest vertex minimizes the height over its face's plane (brute
/// force). The deepest vertex itself, and its face, may differ: the face
/// refinement is a local search from the face where the walk detected the
/// penetration, which depends on the start (measured by this test before
/// the exact search existed: 52 of 1060 arbitrary starts gave another
/// face); it is only the seed of the exact search.
fn assert_same_answer(
    warm: &VClipResult,
    cold: &VClipResult,
    a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
    compared: &mut Compared,
) {
    let scale = a.scale().max(b.scale());
    match (&warm.outcome, &cold.outcome) {
        (
            Outcome::Separated {
                distance: dw,
                witness_a_world: aw,
                witness_b_world: bw,
            },
            Outcome::Separated {
                distance: dc,
                witness_a_world: ac,
                witness_b_world: bc,
            },
        ) => {
            assert!((dw - dc).abs() <= AGREEMENT * scale, "warm {dw} cold {dc}");
            let (vw, vc) = (bw - aw, bc - ac);
            assert!((vw - vc).norm() <= AGREEMENT * scale, "warm {vw} cold {vc}");
            compared.separated += 1;
            if *dc > AGREEMENT * scale
                && closest_points_are_unique(a, pose_a, b, pose_b, &(vc / *dc))
            {
                assert!(
                    (aw - ac).norm() <= AGREEMENT * scale,
                    "A: warm {aw} cold {ac}"
                );
                assert!(
                    (bw - bc).norm() <= AGREEMENT * scale,
                    "B: warm {bw} cold {bc}"
                );
                compared.unique_witnesses += 1;
            }
        }
        (Outcome::Penetrating(w), Outcome::Penetrating(c)) => {
            let exact = |dv: &DeepestVertex| minimum_translation(a, pose_a, b, pose_b, dv).depth();
            let (exact_warm, exact_cold) = (exact(w), exact(c));
            if (exact_warm - exact_cold).abs() > AGREEMENT * scale {
                compared.depth_mismatches.push((exact_warm, exact_cold));
            }
            for dv in [w, c] {
                let (poly, pose, face_poly, face_pose) = match dv.vertex_body {
                    BodyRole::A => (a, pose_a, b, pose_b),
                    BodyRole::B => (b, pose_b, a, pose_a),
                };
                let face = &face_poly.faces()[dv.face];
                let corner = face_pose * face_poly.vertices()[face.vertices[0]];
                let lowest = poly
                    .vertices()
                    .iter()
                    .map(|p| dv.normal_world.dot(&(pose * p - corner)))
                    .fold(f64::INFINITY, f64::min);
                assert!((dv.depth + lowest).abs() <= AGREEMENT * scale);
            }
            compared.penetrating += 1;
        }
        (w, c) => panic!("warm {w:?} cold {c:?}"),
    }
}

/// Coherence paths that pass through contact (amplitude shrunk so that the
/// bodies interpenetrate part of the time): warm starts from the previous
/// query agree with cold queries.
#[test]
fn warm_starts_along_paths_through_contact_agree_with_cold() {
    let mut rng = ChaCha8Rng::seed_from_u64(20);
    let mut compared = Compared::default();
    for (name, shape) in mirtich_shapes() {
        let (mut penetrating, mut queries) = (0, 0);
        for omega in [0.5, 5.0, 25.0] {
            let run = CoherenceRun::new(&mut rng, shape.scale() * 0.6, omega);
            let fixed = Isometry3::identity();
            let mut warm = None;
            for i in 1..=(360.0 / omega).max(100.0) as usize {
                let pose = run.pose(i);
                let hot = vclip(&shape, &fixed, &shape, &pose, warm).unwrap();
                let cold = vclip(&shape, &fixed, &shape, &pose, None).unwrap();
                assert!(!hot.fell_back() && !cold.fell_back(), "{name}");
                assert_same_answer(&hot, &cold, &shape, &fixed, &shape, &pose, &mut compared);
                penetrating += matches!(hot.outcome, Outcome::Penetrating(_)) as usize;
                warm = Some(hot.final_pair);
                queries += 1;
            }
        }
        assert!(
            penetrating > queries / 20 && penetrating < queries * 19 / 20,
            "{name}: {penetrating}/{queries}"
        );
    }
    assert_compared_enough(&compared);
}

/// Each kind of comparison ran often enough to mean something, and every
/// warm-started exact depth equals the cold one (a warm start may change
/// the cost, never the answer: `src/vclip/query.rs`).
fn assert_compared_enough(compared: &Compared) {
    assert!(
        compared.separated > 500
            && compared.penetrating > 500
            && compared.unique_witnesses * 2 > compared.separated,
        "{:?}",
        (
            compared.separated,
            compared.unique_witnesses,
            compared.penetrating
        )
    );
    let worst = compared.depth_mismatches.iter().max_by(|x, y| {
        (x.0 / x.1)
            .max(x.1 / x.0)
            .total_cmp(&(y.0 / y.1).max(y.1 / y.0))
    });
    let warm_deeper = compared
        .depth_mismatches
        .iter()
        .filter(|(w, c)| w > c)
        .count();
    assert!(
        compared.depth_mismatches.is_empty(),
        "warm-started depth differs from the cold depth on {} of {} penetrating pairs; \
         warm deeper on {warm_deeper}; worst (warm, cold) {worst:?}",
        compared.depth_mismatches.len(),
        compared.penetrating
    );
}

fn random_feature(rng: &mut impl Rng, poly: &ConvexPolyhedron) -> Feature {
    match rng.random_range(0..3) {
        0 => Feature::Vertex(rng.random_range(0..poly.vertices().len())),
        1 => Feature::Edge(rng.random_range(0..poly.edges().len())),
        _ => Feature::Face(rng.random_range(0..poly.faces().len())),
    }
}

/// Any valid feature pair, face–face included, is a valid start.
#[test]
fn arbitrary_starting_pairs_give_the_cold_answer() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut compared = Compared::default();
    for _ in 0..1000 {
        let (n, m) = (rng.random_range(4..=80), rng.random_range(4..=80));
        let a = random_hull_varied(&mut rng, n, 1.0);
        let b = random_hull_varied(&mut rng, m, 1.0);
        let (pose_a, pose_b) = (random_pose(&mut rng, 1.2), random_pose(&mut rng, 1.2));
        let cold = vclip(&a, &pose_a, &b, &pose_b, None).unwrap();
        for _ in 0..5 {
            let start = FeaturePair {
                a: random_feature(&mut rng, &a),
                b: random_feature(&mut rng, &b),
            };
            let warm = vclip(&a, &pose_a, &b, &pose_b, Some(start)).unwrap();
            assert!(!warm.fell_back());
            assert_same_answer(&warm, &cold, &a, &pose_a, &b, &pose_b, &mut compared);
        }
    }
    assert_compared_enough(&compared);
}

#[test]
fn bad_input_is_a_typed_error() {
    let cube = ConvexPolyhedron::cuboid(Vector3::new(1.0, 1.0, 1.0)).unwrap();
    let ok = Isometry3::identity();
    let nan = Isometry3::from_parts(
        Translation3::new(f64::NAN, 0.0, 0.0),
        UnitQuaternion::identity(),
    );
    assert_eq!(
        vclip(&cube, &nan, &cube, &ok, None).unwrap_err(),
        VClipError::NonFinitePose { body: BodyRole::A }
    );
    let stretched = Isometry3::from_parts(
        Translation3::new(3.0, 0.0, 0.0),
        UnitQuaternion::new_unchecked(Quaternion::new(2.0, 0.0, 0.0, 0.0)),
    );
    assert!(matches!(
        vclip(&cube, &ok, &cube, &stretched, None),
        Err(VClipError::NonUnitRotation {
            body: BodyRole::B,
            ..
        })
    ));
    let stale = FeaturePair {
        a: Feature::Vertex(0),
        b: Feature::Face(6),
    };
    assert_eq!(
        vclip(&cube, &ok, &cube, &ok, Some(stale)).unwrap_err(),
        VClipError::InvalidWarmStart {
            body: BodyRole::B,
            feature: Feature::Face(6)
        }
    );
}

/// Coincident bodies (the same cube at the same pose) are penetrating, with
/// depth the full width along a face normal.
#[test]
fn coincident_cubes_penetrate_by_their_width() {
    let cube = ConvexPolyhedron::cuboid(Vector3::new(1.0, 2.0, 3.0)).unwrap();
    let pose = Isometry3::identity();
    let result = vclip(&cube, &pose, &cube, &pose, None).unwrap();
    let Outcome::Penetrating(dv) = result.outcome else {
        panic!("{:?}", result.outcome)
    };
    // The exact depth is the smallest width, 2 along x: both separating
    // directions along x give it; y (4) and z (6) are deeper.
    assert!(
        (dv.depth - 2.0).abs() <= COINCIDENT_DEPTH_ROUNDING,
        "depth {}",
        dv.depth
    );
    assert!(
        (dv.normal_world.x.abs() - 1.0).abs() <= COINCIDENT_DEPTH_ROUNDING,
        "normal {}",
        dv.normal_world
    );
}
