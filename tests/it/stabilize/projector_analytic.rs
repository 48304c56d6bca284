//! The projection loop apart from the geometry: analytic constraint
//! providers whose exact answers are known in closed form.

use approx::assert_relative_eq;
use constraint_stabilization::FrictionModel;
use constraint_stabilization::Settings;
use constraint_stabilization::internals::contact::contact_row;
use constraint_stabilization::internals::projector::{
    ProjectionStatus, ProjectionSummary, StepOutcome, StepReport, project, projection_step,
};
use constraint_stabilization::internals::rows::{
    BodyInertia, BodyState, ConstraintProvider, ConstraintRow, Measurement, RowKind,
};
use constraint_stabilization::settings::ResolvedLengths;
use nalgebra::{Matrix3, Point3, UnitQuaternion, Vector3, Vector6};

const TOLERANCE: f64 = 1e-9;

/// The projection's settings (no trust region, 20 steps, the pyramid of 4,
/// rows in contact held) and lengths (tolerance [`TOLERANCE`], the given
/// target margin).
fn settings(target_margin: f64) -> (Settings, ResolvedLengths) {
    let mut settings = Settings::default();
    settings.tolerance_absolute = Some(TOLERANCE);
    settings.target_margin_absolute = Some(target_margin);
    settings.step_max_rotation = f64::INFINITY;
    settings.step_max_translation_relative = f64::INFINITY;
    settings.max_passes = 20;
    settings.friction_directions = 4;
    settings.friction_model = FrictionModel::Pyramid;
    settings.hold_open_gaps = true;
    let lengths = settings.resolve(1.0);
    (settings, lengths)
}

/// One projection step with [`settings`] for the target margin `target`.
fn step<P: ConstraintProvider>(
    provider: &mut P,
    configuration: &mut Vec<BodyState>,
    inertias: &[BodyInertia],
    target: f64,
) -> StepReport {
    let (settings, lengths) = settings(target);
    projection_step(provider, configuration, inertias, &settings, &lengths).expect("solves")
}

/// The projection loop with [`settings`] for the target margin `target`.
fn run<P: ConstraintProvider>(
    provider: &mut P,
    configuration: &mut Vec<BodyState>,
    inertias: &[BodyInertia],
    target: f64,
) -> ProjectionSummary {
    let (settings, lengths) = settings(target);
    project(provider, configuration, inertias, &settings, &lengths).expect("solves")
}

fn state(position: Point3<f64>) -> BodyState {
    BodyState {
        position,
        rotation: UnitQuaternion::identity(),
    }
}

fn inertia(mass: f64, diagonal: Vector3<f64>) -> BodyInertia {
    BodyInertia {
        mass,
        inertia_body: Matrix3::from_diagonal(&diagonal),
    }
}

/// Points attached to the bodies must stay above the fixed plane `z = 0`;
/// spheres (radius, body) must stay apart.
struct PointsAbovePlane {
    /// (body, point in the body frame).
    points: Vec<(usize, Vector3<f64>)>,
    /// Scale factor applied to the Jacobian (1 = exact; other values model a
    /// wrong linearization that the line search must catch).
    jacobian_error: f64,
}

impl PointsAbovePlane {
    fn point_world(&self, k: usize, configuration: &[BodyState]) -> Point3<f64> {
        let (body, offset) = self.points[k];
        configuration[body].position + configuration[body].rotation * offset
    }
}

impl ConstraintProvider for PointsAbovePlane {
    fn linearize(&mut self, configuration: &[BodyState]) -> Vec<ConstraintRow> {
        (0..self.points.len())
            .map(|k| {
                let body = self.points[k].0;
                let p = self.point_world(k, configuration);
                let on_plane = Point3::new(p.x, p.y, 0.0);
                let mut row = contact_row(
                    &p,
                    &on_plane,
                    &Vector3::z(),
                    Some((body, configuration[body].position)),
                    None,
                );
                row.blocks[0].1 *= self.jacobian_error;
                row
            })
            .collect()
    }

    fn measure(&mut self, configuration: &[BodyState]) -> Measurement {
        Measurement {
            values: (0..self.points.len())
                .map(|k| self.point_world(k, configuration).z)
                .collect(),
            equalities: Vec::new(),
        }
    }
}

/// A sphere of radius `r` sunk by `d` into the ground is lifted straight up
/// by `d + target` in one step: the mass-weighted minimum is a pure lift.
#[test]
fn sphere_sunk_into_plane_is_lifted_by_its_depth() {
    let (radius, depth, target) = (0.5, 0.01, 1e-6);
    let mut provider = PointsAbovePlane {
        points: vec![(0, Vector3::new(0.0, 0.0, -radius))],
        jacobian_error: 1.0,
    };
    let mut configuration = vec![state(Point3::new(0.3, -0.2, radius - depth))];
    let inertias = [inertia(2.0, Vector3::repeat(0.2))];
    let summary = run(&mut provider, &mut configuration, &inertias, target);
    assert_eq!(summary.status, ProjectionStatus::Converged);
    assert_eq!(summary.steps.len(), 2, "one step and the final check");
    let moved = configuration[0];
    assert_relative_eq!(moved.position.z, radius + target, epsilon = 1e-12);
    assert_eq!((moved.position.x, moved.position.y), (0.3, -0.2));
    assert_relative_eq!(moved.rotation.angle(), 0.0, epsilon = 1e-15);
    let displacement = summary.steps[0].displacement;
    assert_relative_eq!(
        displacement,
        2.0f64.sqrt() * (depth + target),
        epsilon = 1e-12
    );
}

/// An off-centre point below the plane: the first step's correction is the
/// closed-form minimum-norm solution `dq = M^-1 J^T (d + target) / (J M^-1 J^T)`,
/// and the loop converges with the merit never rising.
#[test]
fn rod_end_below_plane_rotates_and_lifts() {
    let (length, depth, target) = (1.0, 0.05, 1e-6);
    let (mass, inertia_yy) = (3.0, 0.25);
    let mut provider = PointsAbovePlane {
        points: vec![(0, Vector3::new(length, 0.0, 0.0))],
        jacobian_error: 1.0,
    };
    let mut configuration = vec![state(Point3::new(0.0, 0.0, -depth))];
    let inertias = [inertia(mass, Vector3::new(0.01, inertia_yy, inertia_yy))];
    let first = step(&mut provider, &mut configuration.clone(), &inertias, target);
    let dq = &first.solution.as_ref().unwrap().dq;
    let effective = 1.0 / mass + length * length / inertia_yy;
    let lambda = (depth + target) / effective;
    assert_relative_eq!(dq[2], lambda / mass, epsilon = 1e-9);
    assert_relative_eq!(dq[4], -length * lambda / inertia_yy, epsilon = 1e-9);
    for k in [0, 1, 3, 5] {
        assert!(dq[k].abs() < 1e-12, "dq[{k}] = {}", dq[k]);
    }
    let summary = run(&mut provider, &mut configuration, &inertias, target);
    assert_eq!(summary.status, ProjectionStatus::Converged);
    assert!(summary.steps.len() <= 6, "{} steps", summary.steps.len());
    for pair in summary.steps.windows(2) {
        assert!(pair[1].depth_before <= pair[0].depth_before);
    }
    assert!(provider.measure(&configuration).values[0] >= -TOLERANCE);
}

/// Two dynamic bodies whose masses differ by 10^4 share the correction in
/// inverse proportion to their masses.
#[test]
fn mass_ratio_splits_the_correction() {
    struct TwoSpheres;
    impl ConstraintProvider for TwoSpheres {
        fn linearize(&mut self, c: &[BodyState]) -> Vec<ConstraintRow> {
            let normal = (c[1].position - c[0].position).normalize();
            let p_1 = c[1].position - normal; // unit radii
            let p_0 = c[0].position + normal;
            vec![contact_row(
                &p_1,
                &p_0,
                &normal,
                Some((1, c[1].position)),
                Some((0, c[0].position)),
            )]
        }
        fn measure(&mut self, c: &[BodyState]) -> Measurement {
            Measurement {
                values: vec![(c[1].position - c[0].position).norm() - 2.0],
                equalities: Vec::new(),
            }
        }
    }
    let mut configuration = vec![state(Point3::origin()), state(Point3::new(1.9, 0.0, 0.0))];
    let inertias = [
        inertia(1e4, Vector3::repeat(4e3)),
        inertia(1.0, Vector3::repeat(0.4)),
    ];
    let summary = run(&mut TwoSpheres, &mut configuration, &inertias, 0.0);
    assert_eq!(summary.status, ProjectionStatus::Converged);
    let heavy_moved = -configuration[0].position.x;
    let light_moved = configuration[1].position.x - 1.9;
    assert_relative_eq!(light_moved / heavy_moved, 1e4, max_relative = 1e-9);
    assert_relative_eq!(heavy_moved + light_moved, 0.1, max_relative = 1e-12);
}

/// A linearization that underestimates the effect of a correction
/// fivefold makes the full step overshoot through a ceiling at `z = 0.3`:
/// the line search halves the step, and nothing that was clear penetrates.
#[test]
fn line_search_stops_an_overshoot_into_a_clear_constraint() {
    struct Slab;
    impl ConstraintProvider for Slab {
        fn linearize(&mut self, c: &[BodyState]) -> Vec<ConstraintRow> {
            // True slopes are +1 and -1; the rows believe 0.2 and -0.2.
            let ceiling = 0.3 - c[0].position.z;
            let blocks = |sign: f64| vec![(0, Vector6::new(0.0, 0.0, sign * 0.2, 0.0, 0.0, 0.0))];
            vec![
                ConstraintRow {
                    kind: RowKind::Inequality,
                    phi: c[0].position.z,
                    blocks: blocks(1.0),
                    friction: None,
                },
                ConstraintRow {
                    kind: RowKind::Inequality,
                    phi: ceiling,
                    blocks: blocks(-1.0),
                    friction: None,
                },
            ]
        }
        fn measure(&mut self, c: &[BodyState]) -> Measurement {
            Measurement {
                values: vec![c[0].position.z, 0.3 - c[0].position.z],
                equalities: Vec::new(),
            }
        }
    }
    let mut configuration = vec![state(Point3::new(0.0, 0.0, -0.1))];
    let inertias = [inertia(1.0, Vector3::repeat(0.1))];
    let report = step(&mut Slab, &mut configuration, &inertias, 0.0);
    assert_eq!(report.outcome, StepOutcome::Moved);
    assert_eq!(report.alpha, Some(0.5));
    assert_eq!(report.line_search_trials, 2);
    assert_relative_eq!(configuration[0].position.z, 0.15, epsilon = 1e-12);
}

/// A linearization that overestimates the effect tenfold removes a tenth
/// of the depth per step: the merit falls every step and the loop reports
/// its step limit honestly.
#[test]
fn overestimated_jacobian_converges_slowly_and_says_so() {
    let mut provider = PointsAbovePlane {
        points: vec![(0, Vector3::new(0.0, 0.0, -0.5))],
        jacobian_error: 10.0,
    };
    let mut configuration = vec![state(Point3::new(0.0, 0.0, 0.4))];
    let inertias = [inertia(1.0, Vector3::repeat(0.1))];
    let summary = run(&mut provider, &mut configuration, &inertias, 0.0);
    assert_eq!(summary.status, ProjectionStatus::StepLimit);
    for step in &summary.steps {
        assert_relative_eq!(
            step.depth_after,
            0.9 * step.depth_before,
            max_relative = 1e-9
        );
    }
}

/// Nothing to do: the configuration is bit-identical and nothing is solved.
#[test]
fn satisfied_configuration_is_untouched() {
    let mut provider = PointsAbovePlane {
        points: vec![(0, Vector3::new(0.1, 0.2, -0.5))],
        jacobian_error: 1.0,
    };
    let original = vec![BodyState {
        position: Point3::new(0.1, 0.2, 0.5 + 1e-12),
        rotation: UnitQuaternion::from_euler_angles(0.0, 0.0, 0.3),
    }];
    let mut configuration = original.clone();
    let inertias = [inertia(1.0, Vector3::repeat(0.1))];
    let report = step(&mut provider, &mut configuration, &inertias, 0.0);
    assert_eq!(report.outcome, StepOutcome::AlreadySatisfied);
    assert!(report.solution.is_none());
    assert_eq!(configuration, original);
}

/// A constraint that no correction can satisfy (its Jacobian points the
/// wrong way) stalls: the line search accepts nothing and the configuration
/// is left as it was.
#[test]
fn impossible_descent_stalls_without_moving() {
    let mut provider = PointsAbovePlane {
        points: vec![(0, Vector3::new(0.0, 0.0, -0.5))],
        jacobian_error: -1.0,
    };
    let original = vec![state(Point3::new(0.0, 0.0, 0.4))];
    let mut configuration = original.clone();
    let inertias = [inertia(1.0, Vector3::repeat(0.1))];
    let report = step(&mut provider, &mut configuration, &inertias, 0.0);
    assert_eq!(report.outcome, StepOutcome::Stalled);
    assert_eq!(configuration, original);
}

/// A point attached to a body, inside a fixed axis-aligned box `[-1, 1]^3`,
/// must leave it. The constraint is the signed distance to the box surface
/// through the nearest face (negative inside): the minimal correction
/// leaves through that face, here `+x` at depth 0.2.
#[test]
fn point_inside_a_box_leaves_through_the_nearest_face() {
    struct PointInBox;
    impl PointInBox {
        /// Signed distance through the nearest face and that face's normal.
        fn nearest_face(p: &Point3<f64>) -> (f64, Vector3<f64>) {
            (0..3)
                .flat_map(|axis| [1.0, -1.0].map(|sign| (axis, sign)))
                .map(|(axis, sign)| {
                    let mut normal = Vector3::zeros();
                    normal[axis] = sign;
                    (sign * p[axis] - 1.0, normal)
                })
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .expect("six faces")
        }
    }
    impl ConstraintProvider for PointInBox {
        fn linearize(&mut self, c: &[BodyState]) -> Vec<ConstraintRow> {
            let p = c[0].position;
            let (phi, normal) = Self::nearest_face(&p);
            let on_face = p - normal * phi;
            vec![contact_row(&p, &on_face, &normal, Some((0, p)), None)]
        }
        fn measure(&mut self, c: &[BodyState]) -> Measurement {
            Measurement {
                values: vec![Self::nearest_face(&c[0].position).0],
                equalities: Vec::new(),
            }
        }
    }
    let mut configuration = vec![state(Point3::new(0.8, 0.3, -0.5))];
    let inertias = [inertia(1.0, Vector3::repeat(0.1))];
    let summary = run(&mut PointInBox, &mut configuration, &inertias, 1e-6);
    assert_eq!(summary.status, ProjectionStatus::Converged);
    let p = configuration[0].position;
    assert_relative_eq!(p.x, 1.0 + 1e-6, epsilon = 1e-12);
    assert_eq!((p.y, p.z), (0.3, -0.5));
}
