//! Mirtich's shapes and experiments: the coherence path with warm and cold
//! starts, and the degeneracy test of nearly parallel cubes, all checked
//! against parry3d-f64.

use constraint_stabilization::internals::vclip::{FeaturePair, Outcome, VClip, vclip};
use dev_support::random::random_pose;
use dev_support::vclip::experiments::{CoherenceRun, degeneracy_experiment, mirtich_shapes};
use dev_support::vclip::{
    parry_depth, parry_distance, parry_intersects, parry_shape, separated_distance,
};
use nalgebra::Isometry3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const AGREEMENT: f64 = 1e-9;

/// parry's intersection test is fuzzy within about 5e-8 of touching.
const PARRY_FUZZ: f64 = 1e-7;

#[test]
fn mirtich_shapes_have_the_papers_feature_counts() {
    let counts: Vec<(usize, usize, usize)> = mirtich_shapes()
        .iter()
        .map(|(_, p)| (p.vertices().len(), p.edges().len(), p.faces().len()))
        .collect();
    assert_eq!(
        counts,
        vec![(8, 12, 6), (12, 30, 20), (120, 180, 62), (642, 1920, 1280)]
    );
}

/// Algorithm 9 at 0.5, 5 and 25 degrees per query, shortened: warm and
/// cold queries agree with each other and with parry, and never fall back.
#[test]
fn coherence_runs_agree_with_parry_warm_and_cold() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for (name, shape) in mirtich_shapes() {
        let parry = parry_shape(&shape);
        let scale = shape.scale();
        for omega in [0.5, 5.0, 25.0] {
            for _ in 0..2 {
                let run = CoherenceRun::new(&mut rng, scale, omega);
                let mut warm: Option<FeaturePair> = None;
                let fixed = Isometry3::identity();
                for i in 1..=150 {
                    let pose = run.pose(i);
                    let hot = vclip(&shape, &fixed, &shape, &pose, warm).unwrap();
                    let cold = vclip(&shape, &fixed, &shape, &pose, None).unwrap();
                    warm = Some(hot.final_pair);
                    assert!(!hot.fell_back() && !cold.fell_back(), "{name}");
                    let (Some(d_hot), Some(d_cold)) =
                        (separated_distance(&hot), separated_distance(&cold))
                    else {
                        panic!("{name}: the coherence path never penetrates");
                    };
                    let d_parry = parry_distance(&parry, &fixed, &parry, &pose);
                    assert!(
                        (d_hot - d_cold).abs() <= AGREEMENT * scale,
                        "{name}: {d_hot} {d_cold}"
                    );
                    assert!(
                        (d_hot - d_parry).abs() <= AGREEMENT * scale,
                        "{name}: {d_hot} {d_parry}"
                    );
                }
            }
        }
    }
}

/// Algorithm 10, shortened (the release benchmark runs 100,000 trials):
/// zero cycles and zero wrong answers.
#[test]
fn degeneracy_test_has_no_cycles_and_no_wrong_answers() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let counts =
        degeneracy_experiment(&mut rng, &VClip::default(), 1500, 30, AGREEMENT, PARRY_FUZZ);
    eprintln!("{counts:?}");
    assert_eq!(counts.cycles, 0, "{counts:?}");
    assert_eq!(counts.wrong, 0, "{counts:?}");
    assert!(counts.boundary_searches > 300, "{counts:?}");
}

/// Shapes that touch or interpenetrate: every Mirtich shape against every
/// other at random close poses, checked against parry.
#[test]
fn mirtich_shapes_in_contact_agree_with_parry() {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let shapes = mirtich_shapes();
    for (name_a, a) in &shapes {
        for (name_b, b) in &shapes {
            let (pa, pb) = (parry_shape(a), parry_shape(b));
            for _ in 0..100 {
                let (pose_a, pose_b) = (random_pose(&mut rng, 0.8), random_pose(&mut rng, 0.8));
                let result = vclip(a, &pose_a, b, &pose_b, None).unwrap();
                assert!(!result.fell_back());
                let d_parry = parry_distance(&pa, &pose_a, &pb, &pose_b);
                match result.outcome {
                    Outcome::Separated { distance, .. } => {
                        assert!(
                            (distance - d_parry).abs() <= AGREEMENT * 2.0,
                            "{name_a}/{name_b}"
                        );
                    }
                    Outcome::Penetrating(dv) => {
                        assert!(
                            parry_intersects(&pa, &pose_a, &pb, &pose_b) || d_parry <= AGREEMENT
                        );
                        assert!(dv.depth >= parry_depth(&pa, &pose_a, &pb, &pose_b) - AGREEMENT);
                    }
                }
            }
        }
    }
}
