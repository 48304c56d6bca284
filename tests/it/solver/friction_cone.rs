//! The friction cone as a second-order cone of clarabel's primal form
//! (`solver::friction_cone`), against closed forms and against its pyramid.
//!
//! The oracles are not our solvers: closed forms of a single contact, and
//! the inclusions `C(mu cos(pi / K)) ⊆ P_K(mu) ⊇ C(mu)` (the pyramid of `K`
//! facets contains the cone and lies inside the cone of coefficient
//! `mu cos(pi / K)`), which bound the pyramid's answer by two cone answers.

use constraint_stabilization::solver::clarabel_qp::ClarabelFailure;
use constraint_stabilization::solver::friction_cone::cone_violation;
use constraint_stabilization::solver::{
    BodyMetric, CrossCheckOutcome, FailureReason, FrictionCone, JacobianRow, ProjectionQp,
    SolverChoice, SolverError, SolverKind, SolverSettings, cross_check_projection,
    solve_projection,
};
use nalgebra::{DVector, Matrix3, Vector3, Vector6};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative accuracy of clarabel's interior point on a cone problem (its
/// gap tolerance is 1e-8 of the scaled problem; the answer's error is
/// about its square root at worst on degenerate cones, far less here).
const CONE_REL_TOL: f64 = 1e-6;

/// Agreement of two exact solvers (Lemke, polished clarabel) on one QP.
const SAME_PROBLEM_TOL: f64 = 1e-6;

fn block(linear: Vector3<f64>, angular: Vector3<f64>) -> Vector6<f64> {
    Vector6::new(
        linear.x, linear.y, linear.z, angular.x, angular.y, angular.z,
    )
}

/// A row of body 0 at its centre of mass along `n` (no lever).
fn central_row(n: Vector3<f64>) -> JacobianRow {
    JacobianRow {
        blocks: vec![(0, block(n, Vector3::zeros()))],
    }
}

/// One body of mass `mass` on a fixed ground (normal z, friction `mu`, a
/// resting contact at its target), pushed by a frictionless row of unit
/// normal `sin(alpha) u - cos(alpha) z` (`u = (cos beta, sin beta, 0)`)
/// penetrating by `depth`: the push drives the body into the ground and
/// sideways, and the ground's cone decides how far it may slide.
pub(super) fn pushed_into_the_ground(mu: f64, alpha: f64, beta: f64, depth: f64) -> ProjectionQp {
    let mass = 2.0;
    let u = Vector3::new(beta.cos(), beta.sin(), 0.0);
    let push = u * alpha.sin() - Vector3::z() * alpha.cos();
    ProjectionQp {
        bodies: vec![BodyMetric {
            mass,
            inertia_world: Matrix3::identity() * mass / 6.0,
        }],
        rows: vec![central_row(push)],
        phi: vec![-depth],
        target: vec![0.0],
        cones: vec![FrictionCone {
            normal: central_row(Vector3::z()),
            tangents: [central_row(Vector3::x()), central_row(Vector3::y())],
            mu,
            phi: 0.0,
            target: 0.0,
        }],
        cone_facets: 4,
        num_equalities: 0,
    }
}

/// The closed form of [`pushed_into_the_ground`] with the cone of
/// coefficient `mu`: the frictionless answer slides flat, which the cone
/// forbids; the answer is the corner of the push's half-space and the
/// cone, `z = mu t`, `sin(alpha) t - cos(alpha) z = depth`:
/// `t = depth / (sin(alpha) - mu cos(alpha))` along `u`, `z = mu t` up
/// (`tan(alpha) > mu`, else the body is wedged).
fn cone_closed_form(mu: f64, alpha: f64, beta: f64, depth: f64) -> Vector3<f64> {
    let t = depth / (alpha.sin() - mu * alpha.cos());
    Vector3::new(t * beta.cos(), t * beta.sin(), mu * t)
}

fn solve(qp: &ProjectionQp, choice: SolverChoice) -> DVector<f64> {
    let settings = SolverSettings {
        choice,
        ..SolverSettings::default()
    };
    solve_projection(qp, &settings)
        .unwrap_or_else(|e| panic!("{choice:?}: {e}"))
        .dq
}

fn translation(dq: &DVector<f64>) -> Vector3<f64> {
    dq.fixed_rows::<3>(0).into_owned()
}

/// Sliding per unit of opening, `|dt| / dn`, of a translation.
fn slide_per_lift(dx: &Vector3<f64>) -> f64 {
    dx.x.hypot(dx.y) / dx.z
}

/// The cone's answer is its closed form in every direction; the pyramid
/// of four facets agrees along a facet normal (`beta = 0`) and slides
/// `sqrt 2 = 1 / cos(pi / 4)` times as far per unit of opening in its
/// corner (`beta = 45 deg`), where its effective coefficient is
/// `mu / sqrt 2`: its answer is then the cone's closed form for that `mu`.
#[test]
fn a_box_pushed_sideways_into_the_ground_slides_as_the_closed_form() {
    let (mu, alpha, depth) = (0.5, 1.2_f64, 1e-3);
    assert!(alpha.tan() > mu, "not wedged");
    let corner = std::f64::consts::FRAC_PI_4;
    for beta in [0.0, corner, 0.3, 2.0] {
        let qp = pushed_into_the_ground(mu, alpha, beta, depth);
        let cone = translation(&solve(&qp, SolverChoice::Clarabel));
        let expected = cone_closed_form(mu, alpha, beta, depth);
        assert!(
            (cone - expected).norm() <= CONE_REL_TOL * expected.norm(),
            "beta {beta}: {cone:?} vs {expected:?}"
        );
        assert!((slide_per_lift(&cone) - 1.0 / mu).abs() <= CONE_REL_TOL / mu);
    }
    for (beta, excess) in [(0.0, 1.0), (corner, std::f64::consts::SQRT_2)] {
        let (pyramid_qp, _) = pushed_into_the_ground(mu, alpha, beta, depth).pyramid();
        for choice in [SolverChoice::Clarabel, SolverChoice::Lemke] {
            let pyramid = translation(&solve(&pyramid_qp, choice));
            let expected = cone_closed_form(mu / excess, alpha, beta, depth);
            assert!(
                (pyramid - expected).norm() <= SAME_PROBLEM_TOL * expected.norm(),
                "{choice:?} beta {beta}: {pyramid:?} vs {expected:?}"
            );
            let ratio = slide_per_lift(&pyramid) * mu;
            assert!(
                (ratio - excess).abs() <= SAME_PROBLEM_TOL,
                "{choice:?} beta {beta}: pyramid slides {ratio} times the cone per lift"
            );
        }
    }
}

/// `sqrt(dq^T M dq)` of problem `qp`'s metric.
fn displacement(qp: &ProjectionQp, dq: &DVector<f64>) -> f64 {
    qp.bodies
        .iter()
        .enumerate()
        .map(|(k, body)| {
            let lin = dq.fixed_rows::<3>(6 * k).norm_squared() * body.mass;
            let ang = dq.fixed_rows::<3>(6 * k + 3);
            lin + ang.dot(&(body.inertia_world * ang))
        })
        .sum::<f64>()
        .sqrt()
}

/// `qp` with every cone's coefficient multiplied by `factor`.
fn with_mu_times(qp: &ProjectionQp, factor: f64) -> ProjectionQp {
    let mut out = qp.clone();
    out.cones.iter_mut().for_each(|cone| cone.mu *= factor);
    out
}

/// A column of `boxes` unit boxes on a fixed ground, each resting on the
/// one below through its four bottom corners (each with a friction cone of
/// a random `mu`, some penetrating, some open within a margin), and each
/// pushed by a frictionless row of random tilted normal at a random point
/// of its side, penetrating: every box tends to slide and turn.
pub(super) fn pushed_column(boxes: usize, seed: u64) -> ProjectionQp {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut qp = ProjectionQp {
        cone_facets: 4,
        ..ProjectionQp::default()
    };
    let half = 0.5;
    for k in 0..boxes {
        let mass = 10f64.powf(rng.random_range(-1.0..1.0));
        qp.bodies.push(BodyMetric {
            mass,
            inertia_world: Matrix3::identity() * mass / 6.0,
        });
        let centre = Vector3::new(0.0, 0.0, half + k as f64);
        let contact = |p: Vector3<f64>, n: Vector3<f64>| -> JacobianRow {
            let mut blocks = vec![(k, block(n, (p - centre).cross(&n)))];
            if k > 0 {
                let below = centre - Vector3::z();
                blocks.push((k - 1, block(-n, -(p - below).cross(&n))));
            }
            JacobianRow { blocks }
        };
        for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let p = centre + Vector3::new(sx * half, sy * half, -half);
            qp.cones.push(FrictionCone {
                normal: contact(p, Vector3::z()),
                tangents: [contact(p, Vector3::x()), contact(p, Vector3::y())],
                mu: rng.random_range(0.1..0.7),
                phi: rng.random_range(-2e-3..1e-3),
                target: 1e-5,
            });
        }
        let azimuth = rng.random_range(0.0..std::f64::consts::TAU);
        let tilt = rng.random_range(0.9..1.3_f64);
        let n = Vector3::new(
            tilt.sin() * azimuth.cos(),
            tilt.sin() * azimuth.sin(),
            -tilt.cos(),
        );
        let p = centre + Vector3::new(0.0, 0.0, rng.random_range(-0.3..0.3));
        let row = contact(p, n);
        qp.rows.push(JacobianRow {
            blocks: row.blocks[..1].to_vec(),
        });
        qp.phi.push(-rng.random_range(1e-3..5e-3));
        qp.target.push(1e-5);
    }
    qp
}

/// On random pushed columns: clarabel's cone answer satisfies every cone
/// (`mu |dt| <= dn - r`) to the acceptance tolerance, its multipliers obey
/// Coulomb (`|f_t| <= mu f_n`); the pyramid's displacement lies between
/// those of the cones of coefficients `mu cos(pi / K)` and `mu` (the
/// inclusions of the module docs), and its distance from the cone's answer
/// obeys `|dq_C - dq_P|_M^2 <= |dq_C|_M^2 - |dq_C'|_M^2` (the cone's answer
/// is feasible for the pyramid, whose answer is the M-projection of 0 onto
/// a convex set; `C'` the cone of `mu cos(pi / K)`), so `K = 64` converges.
#[test]
fn the_pyramid_is_bounded_by_two_cones_and_converges() {
    for seed in 0..6 {
        let qp = pushed_column(3, seed);
        let solution = solve_projection(
            &qp,
            &SolverSettings {
                choice: SolverChoice::Clarabel,
                ..SolverSettings::default()
            },
        )
        .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        assert!(
            !solution.pyramid_of_cones,
            "seed {seed}: {:?}",
            solution.fallbacks
        );
        let cone_dq = solution.dq.clone();
        let depth = qp.phi.iter().fold(0.0_f64, |m, p| m.max(-p));
        for (c, cone) in qp.cones.iter().enumerate() {
            let w = cone.value(&cone_dq);
            assert!(
                cone_violation(&w) <= SAME_PROBLEM_TOL * depth,
                "seed {seed} cone {c}: {w:?}"
            );
            let z = solution.lambda.fixed_rows::<3>(qp.num_rows() + 3 * c);
            assert!(
                z.y.hypot(z.z) <= z.x * (1.0 + CONE_REL_TOL) + 1e-12,
                "seed {seed} cone {c}: multiplier {z:?} outside Coulomb's cone"
            );
        }
        let d_cone = displacement(&qp, &cone_dq);
        for facets in [4, 8, 64] {
            let shrink = (std::f64::consts::PI / facets as f64).cos();
            let mut pyramid_of = qp.clone();
            pyramid_of.cone_facets = facets;
            let pyramid_dq = solve(&pyramid_of.pyramid().0, SolverChoice::Lemke);
            let inner = solve(&with_mu_times(&qp, shrink), SolverChoice::Clarabel);
            let (d_pyramid, d_inner) = (displacement(&qp, &pyramid_dq), displacement(&qp, &inner));
            println!(
                "seed {seed} K {facets}: cone {d_cone:.6e}, pyramid {d_pyramid:.6e}, \
                 cone of mu cos(pi/K) {d_inner:.6e}"
            );
            assert!(
                d_pyramid <= d_cone * (1.0 + CONE_REL_TOL),
                "seed {seed} K {facets}"
            );
            assert!(
                d_pyramid >= d_inner * (1.0 - CONE_REL_TOL),
                "seed {seed} K {facets}"
            );
            let distance = displacement(&qp, &(&cone_dq - &pyramid_dq));
            let bound = (d_cone * d_cone - d_inner * d_inner).max(0.0).sqrt();
            assert!(
                distance <= bound + CONE_REL_TOL.sqrt() * d_cone,
                "seed {seed} K {facets}: {distance:e} beyond {bound:e}"
            );
            if facets == 64 {
                assert!(distance <= 0.05 * d_cone, "seed {seed}: {distance:e}");
            }
        }
    }
}

/// The cross-check of a problem with cones compares clarabel and Lemke on
/// its pyramid: one problem for both, on which they agree; Lemke asked for
/// directly answers the pyramid and says so.
#[test]
fn clarabel_and_lemke_agree_on_the_pyramid_of_the_cones() {
    for seed in 0..4 {
        let qp = pushed_column(4, seed);
        let (solution, check) = cross_check_projection(&qp, &SolverSettings::default())
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        assert_eq!(solution.solver, SolverKind::Clarabel);
        assert!(!solution.pyramid_of_cones);
        assert!(check.on_pyramid);
        assert_eq!(check.reference, SolverKind::Lemke);
        let CrossCheckOutcome::Compared { differences, .. } = check.outcome else {
            panic!("seed {seed}: {:?}", check.outcome);
        };
        assert!(
            differences.worst() <= SAME_PROBLEM_TOL,
            "seed {seed}: {differences:?}"
        );
        let lemke = solve_projection(
            &qp,
            &SolverSettings {
                choice: SolverChoice::Lemke,
                ..SolverSettings::default()
            },
        )
        .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        assert!(lemke.pyramid_of_cones);
        assert_eq!(lemke.lambda.len(), qp.num_multipliers());
        let pyramid = solve(&qp.pyramid().0, SolverChoice::Clarabel);
        let d = displacement(&qp, &(&lemke.dq - &pyramid));
        assert!(
            d <= SAME_PROBLEM_TOL * displacement(&qp, &pyramid),
            "seed {seed}: {d:e}"
        );
    }
}

/// Under `Auto`, a problem with cones goes to clarabel whatever its size;
/// with nothing violated, nothing is solved.
#[test]
fn auto_sends_cones_to_clarabel() {
    let qp = pushed_into_the_ground(0.5, 1.2, 0.3, 1e-3);
    let solution = solve_projection(&qp, &SolverSettings::default()).expect("solvable");
    assert_eq!(solution.solver, SolverKind::Clarabel);
    let mut resting = qp.clone();
    resting.phi[0] = 0.0;
    let solution = solve_projection(&resting, &SolverSettings::default()).expect("solvable");
    assert_eq!(solution.solver, SolverKind::Trivial);
    assert_eq!(solution.lambda.len(), qp.num_multipliers());
}

/// A body wedged by the push (`tan(alpha) < mu`: the push's half-space
/// misses the cone) has no answer: clarabel certifies it, and the caller
/// (the stabilizer) can then solve without friction.
#[test]
fn a_wedged_body_is_certified_infeasible() {
    let qp = pushed_into_the_ground(2.0, 1.0, 0.3, 1e-3);
    let settings = SolverSettings {
        stop_on_infeasible: true,
        ..SolverSettings::default()
    };
    let error = solve_projection(&qp, &settings).expect_err("wedged");
    let SolverError::AllSolversFailed(fallbacks) = error else {
        panic!("{error}");
    };
    assert_eq!(fallbacks.len(), 1, "{fallbacks:?}");
    assert_eq!(
        fallbacks[0].reason,
        FailureReason::Clarabel(ClarabelFailure::PrimalInfeasible)
    );
}

/// Invalid cones are rejected before any solver runs.
#[test]
fn invalid_cones_are_rejected() {
    let qp = pushed_into_the_ground(0.5, 1.2, 0.3, 1e-3);
    let mut negative = qp.clone();
    negative.cones[0].mu = -0.1;
    let mut nan = qp.clone();
    nan.cones[0].phi = f64::NAN;
    let mut other_bodies = qp.clone();
    other_bodies.cones[0].tangents[0].blocks.clear();
    let mut few_facets = qp.clone();
    few_facets.cone_facets = 2;
    for bad in [negative, nan, other_bodies, few_facets] {
        assert!(solve_projection(&bad, &SolverSettings::default()).is_err());
    }
}
