//! Velocity consistency (issue 10): the approach velocities at the
//! contacts of corrected islands are removed by the mass-weighted
//! projection at the velocity level. Closed form on a single contact; a
//! stack whose heavy top body stops; bystanders untouched; friction on the
//! velocity (Anitescu and Tasora's cone): resting contacts stick.

use crate::stabilize::support::heavy_on_light;
use constraint_stabilization::body::MassSpec;
use constraint_stabilization::stabilizer::{BodyVelocity, VelocityFriction, VelocityReport};
use constraint_stabilization::{Settings, Stabilizer};
use dev_support::scene::{IDENTITY_XYZW, cuboid, ground, hull, scene_of, unit_cube_sunk};
use nalgebra::{Matrix3, Point3, Vector3, Vector6};

/// Agreement with a closed form (speeds, m/s; velocities of order 1).
const CLOSED_FORM: f64 = 1e-12;
/// Sideways speed that counts as none (m/s; the bound).
const NO_SIDEWAYS: f64 = 1e-9;
/// Approach speed left that counts as none (m/s).
const NO_APPROACH: f64 = 1e-9;
/// The engine's time step of the bridge's scenes (s).
const ENGINE_STEP: f64 = 1.0 / 60.0;

/// A tetrahedron standing on one vertex at the origin, on the ground.
fn tetrahedron_on_a_vertex() -> constraint_stabilization::scene::Scene {
    let points = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 1.0, 0.0),
        Point3::new(-1.0, 1.1, 0.5),
        Point3::new(0.2, 1.2, -1.0),
    ];
    scene_of(&[
        ground(),
        hull(
            "tetra",
            points,
            [0.0; 3],
            IDENTITY_XYZW,
            MassSpec::Mass(2.0),
        ),
    ])
}

#[test]
fn a_single_contact_loses_exactly_its_approach_velocity() {
    let scene = tetrahedron_on_a_vertex();
    let body = &scene.bodies()[1];
    let mass = body.mass().expect("dynamic");
    let pose = body.com_pose();
    let rotation = pose.rotation.to_rotation_matrix();
    let inertia: Matrix3<f64> =
        rotation.matrix() * mass.inertia_body * rotation.matrix().transpose();
    let inverse_inertia = inertia.try_inverse().expect("positive definite");
    let velocity = BodyVelocity {
        linear: Vector3::new(0.3, -1.0, 0.2),
        angular: Vector3::new(0.1, 0.0, -0.2),
    };
    // Closed form: one row J = [n; r x n] at the vertex, n = y:
    // dv = -M^-1 J^T (J v) / (J M^-1 J^T).
    let n = Vector3::y();
    let r = -pose.translation.vector;
    let jv = n.dot(&velocity.linear) + r.cross(&n).dot(&velocity.angular);
    let angular_part = inverse_inertia * r.cross(&n);
    let a = 1.0 / mass.mass + r.cross(&n).dot(&angular_part);
    let lambda = -jv / a;
    let expected_linear = velocity.linear + n * (lambda / mass.mass);
    let expected_angular = velocity.angular + angular_part * lambda;

    let mut stabilizer = Stabilizer::new(Settings::default()).expect("default settings");
    let mut velocities = vec![BodyVelocity::default(), velocity];
    let report = stabilizer
        .project_velocities(&scene, &mut velocities, &[1], None, VelocityFriction::None)
        .expect("projects");
    assert_eq!(report.contacts, 1, "{report:?}");
    assert_eq!(report.islands_solved, 1);
    let got = velocities[1];
    println!("{got:?} vs {expected_linear:?} {expected_angular:?}");
    assert!((got.linear - expected_linear).norm() <= 1e-12 * velocity.linear.norm());
    assert!((got.angular - expected_angular).norm() <= 1e-12 * velocity.angular.norm());
    let jv_after = n.dot(&got.linear) + r.cross(&n).dot(&got.angular);
    assert!(jv_after.abs() <= 1e-12, "{jv_after:e}");
    assert!((report.approach_before - 1.0 * -jv.min(0.0)).abs() <= 1e-15);
    assert!(report.approach_after <= 1e-12);

    // With friction, removing the approach adds no sliding at the contact:
    // the tangential velocity of the vertex is unchanged.
    let settings = {
        let mut settings = Settings::default();
        settings.friction = 0.5;
        settings
    };
    let mut stabilizer = Stabilizer::new(settings).expect("valid settings");
    let mut velocities = vec![BodyVelocity::default(), velocity];
    let (time_step, velocity_friction) = (None, VelocityFriction::OnChange);
    stabilizer
        .project_velocities(&scene, &mut velocities, &[1], time_step, velocity_friction)
        .expect("projects");
    let point_velocity = |v: &BodyVelocity| v.linear + v.angular.cross(&r);
    let before = point_velocity(&velocity);
    let after = point_velocity(&velocities[1]);
    assert!(after.y.abs() <= 1e-9, "normal velocity left {:e}", after.y);
    let slide = Vector3::new(after.x - before.x, 0.0, after.z - before.z).norm();
    assert!(slide <= 1e-9, "tangential velocity changed by {slide:e}");
}

#[test]
fn a_heavy_box_falling_on_light_ones_stops_and_bystanders_keep_their_velocity() {
    let mut descs = vec![ground()];
    for (i, x) in [-1.0, 1.0].iter().enumerate() {
        descs.push(cuboid(
            &format!("light{i}"),
            [0.5, 0.5, 0.5],
            [*x, 0.5, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ));
    }
    descs.push(cuboid(
        "heavy",
        [1.5, 0.5, 0.5],
        [0.0, 1.5, 0.0],
        IDENTITY_XYZW,
        MassSpec::Mass(1000.0),
    ));
    descs.push(cuboid(
        "bystander",
        [0.5, 0.5, 0.5],
        [10.0, 0.5, 0.0],
        IDENTITY_XYZW,
        MassSpec::Mass(1.0),
    ));
    let scene = scene_of(&descs);
    let falling = BodyVelocity {
        linear: Vector3::new(0.0, -0.5, 0.0),
        angular: Vector3::zeros(),
    };
    let sinking = BodyVelocity {
        linear: Vector3::new(0.1, -0.2, 0.0),
        angular: Vector3::new(0.0, 0.3, 0.0),
    };
    let mut velocities = vec![
        BodyVelocity::default(),
        BodyVelocity::default(),
        BodyVelocity::default(),
        falling,
        sinking,
    ];
    let mut stabilizer = Stabilizer::new(Settings::default()).expect("default settings");
    let report = stabilizer
        .project_velocities(&scene, &mut velocities, &[3], None, VelocityFriction::None)
        .expect("projects");
    println!("{report:?}: {velocities:?}");
    assert_eq!(report.islands_solved, 1);
    let v: Vector6<f64> = Vector6::new(
        velocities[3].linear.x,
        velocities[3].linear.y,
        velocities[3].linear.z,
        velocities[3].angular.x,
        velocities[3].angular.y,
        velocities[3].angular.z,
    );
    assert!(v.norm() <= 1e-9, "heavy box still moves: {v:?}");
    for light in &velocities[1..3] {
        assert!(
            light.linear.norm() + light.angular.norm() <= 1e-9,
            "{light:?}"
        );
    }
    // The bystander's island was not asked for: bit for bit.
    assert_eq!(velocities[4], sinking);
    assert!(report.approach_after <= 1e-9);
}

#[test]
fn bad_velocities_are_typed_errors() {
    let scene = tetrahedron_on_a_vertex();
    let mut stabilizer = Stabilizer::new(Settings::default()).expect("default settings");
    let mut short = vec![BodyVelocity::default()];
    assert!(
        stabilizer
            .project_velocities(&scene, &mut short, &[1], None, VelocityFriction::None)
            .is_err()
    );
    let mut nan = vec![BodyVelocity::default(); 2];
    nan[1].angular.x = f64::NAN;
    let before = nan.clone();
    assert!(
        stabilizer
            .project_velocities(&scene, &mut nan, &[1], None, VelocityFriction::None)
            .is_err()
    );
    assert!(nan[1].angular.x.is_nan() && nan[0] == before[0]);
}

/// With the engine's time step, a body falling onto the ground from a gap
/// within the contact margin is slowed to close the gap in one step, not
/// stopped in the air: `v' = -gap / h`.
#[test]
fn a_speculative_contact_lets_the_gap_close_in_one_step() {
    let gap = 5e-3;
    let h = 1.0 / 60.0;
    let scene = scene_of(&[
        ground(),
        cuboid(
            "box",
            [0.5, 0.5, 0.5],
            [0.0, 0.5 + gap, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
    ]);
    let falling = BodyVelocity {
        linear: Vector3::new(0.0, -1.0, 0.0),
        angular: Vector3::zeros(),
    };
    let (time_step, velocity_friction) = (Some(h), VelocityFriction::None);
    let mut stabilizer = Stabilizer::new(Settings::default()).expect("default settings");
    let mut velocities = vec![BodyVelocity::default(), falling];
    let report = stabilizer
        .project_velocities(&scene, &mut velocities, &[1], time_step, velocity_friction)
        .expect("projects");
    assert_eq!(report.islands_solved, 1, "{report:?}");
    let v = velocities[1];
    assert!((v.linear.y + gap / h).abs() <= 1e-9, "{v:?}");
    assert!(
        v.linear.x.abs() + v.linear.z.abs() + v.angular.norm() <= 1e-9,
        "{v:?}"
    );
    // Without the time step the box is not in contact: untouched.
    let mut velocities = vec![BodyVelocity::default(), falling];
    let report = stabilizer
        .project_velocities(&scene, &mut velocities, &[1], None, VelocityFriction::None)
        .expect("projects");
    assert_eq!((report.contacts, velocities[1]), (0, falling));
    let (bad_step, no_friction) = (Some(0.0), VelocityFriction::None);
    assert!(
        stabilizer
            .project_velocities(&scene, &mut velocities, &[1], bad_step, no_friction)
            .is_err()
    );
}

/// A unit cube resting face down on the ground (`phi = 0` at its four
/// bottom corners), sliding along x at `v_t` and approaching at `v_n`.
fn sliding_cube() -> (constraint_stabilization::scene::Scene, BodyVelocity) {
    let scene = scene_of(&[ground(), unit_cube_sunk("box", 0.0)]);
    let velocity = BodyVelocity {
        linear: Vector3::new(0.3, -1.0, 0.0),
        angular: Vector3::zeros(),
    };
    (scene, velocity)
}

/// The resting cube's velocity after the projection of `velocity` with
/// friction `friction` and coefficient `mu`, and the report.
fn project_resting_cube(
    velocity: BodyVelocity,
    friction: VelocityFriction,
    mu: f64,
) -> (BodyVelocity, VelocityReport) {
    let (scene, _) = sliding_cube();
    let settings = {
        let mut settings = Settings::default();
        settings.friction = mu;
        settings
    };
    let mut stabilizer = Stabilizer::new(settings).expect("valid settings");
    let mut velocities = vec![BodyVelocity::default(), velocity];
    let (time_step, velocity_friction) = (None, friction);
    let report = stabilizer
        .project_velocities(&scene, &mut velocities, &[1], time_step, velocity_friction)
        .expect("projects");
    println!("{friction:?}, mu {mu}: {:?} ({report:?})", velocities[1]);
    (velocities[1], report)
}

/// [`project_resting_cube`] of the sliding cube's velocity: four contact
/// rows, one island projected.
fn project_sliding_cube(friction: VelocityFriction, mu: f64) -> BodyVelocity {
    let (_, velocity) = sliding_cube();
    let (after, report) = project_resting_cube(velocity, friction, mu);
    assert_eq!(
        (report.contacts, report.islands_solved),
        (4, 1),
        "{report:?}"
    );
    after
}

/// Closed form of friction on the velocity: a box resting on a fixed plane
/// (`phi = 0`) with velocity `(v_t, -v_n)`. With `mu` large enough
/// (`mu / sqrt 2 >= v_t / v_n`, the pyramid's inradius for `K = 4`, and
/// `v_t <= v_n`, so that the impulse passes within the box's base) the
/// answer is `v' = 0`: the approach and the slide are both removed, the
/// impulse `M v` inside the pyramid. With `mu = 0` only the approach goes:
/// `v' = (v_t, 0)`. Friction on the change keeps the slide too (removing
/// an approach adds no sliding, and takes none away).
#[test]
fn a_resting_box_sliding_on_a_plane_sticks_with_friction_on_the_velocity() {
    let (_, velocity) = sliding_cube();
    let still = project_sliding_cube(VelocityFriction::OnVelocity, 1.0);
    assert!(still.linear.norm() <= CLOSED_FORM, "{still:?}");
    assert!(still.angular.norm() <= CLOSED_FORM, "{still:?}");

    for (friction, mu) in [
        (VelocityFriction::OnVelocity, 0.0),
        (VelocityFriction::OnChange, 1.0),
    ] {
        let sliding = project_sliding_cube(friction, mu);
        let expected = Vector3::new(velocity.linear.x, 0.0, 0.0);
        assert!(
            (sliding.linear - expected).norm() <= CLOSED_FORM,
            "{friction:?}, mu {mu}: {sliding:?}"
        );
        assert!(sliding.angular.norm() <= CLOSED_FORM, "{sliding:?}");
    }
}

/// With friction on the velocity, a contact outside its cone starts no
/// projection by itself: the resting box sliding without approach keeps
/// its velocity bit for bit, and the report says how far outside it is.
#[test]
fn a_slide_without_approach_is_not_projected() {
    let gliding = BodyVelocity {
        linear: Vector3::new(0.3, 0.0, 0.0),
        angular: Vector3::zeros(),
    };
    let (after, report) = project_resting_cube(gliding, VelocityFriction::OnVelocity, 1.0);
    assert_eq!((report.islands_solved, after), (0, gliding));
    assert!(
        report.cone_before > 0.0 && report.approach_before <= 0.0,
        "{report:?}"
    );
}

/// Issue 10's drift through the velocity write-back: a box 1,000 times
/// heavier falling onto a light one through contact normals tilted by
/// 1e-4 rad. Without friction the projection stops the heavy box with an
/// impulse along the tilted normals and the light box, free on its
/// frictionless ground, takes the sideways part; with friction on the
/// velocity (`mu = 0.5`, the bridge's colliders' default) the resting
/// contacts stick and the light box gets no sideways velocity.
#[test]
fn a_heavy_box_on_a_tilted_light_one_gives_it_no_sideways_velocity() {
    let scene = heavy_on_light(1000.0, 1e-4, 0.0);
    let falling = BodyVelocity {
        linear: Vector3::new(0.0, -0.5, 0.0),
        angular: Vector3::zeros(),
    };
    let sideways = |friction: VelocityFriction| {
        let settings = {
            let mut settings = Settings::default();
            settings.friction = 0.5;
            settings
        };
        let mut stabilizer = Stabilizer::new(settings).expect("valid settings");
        let mut velocities = vec![BodyVelocity::default(), BodyVelocity::default(), falling];
        let (time_step, velocity_friction) = (Some(ENGINE_STEP), friction);
        let report = stabilizer
            .project_velocities(&scene, &mut velocities, &[2], time_step, velocity_friction)
            .expect("projects");
        println!("{friction:?}: {velocities:?} ({report:?})");
        assert_eq!(report.islands_solved, 1, "{report:?}");
        assert!(report.approach_after <= NO_APPROACH, "{report:?}");
        let light = velocities[1].linear;
        light.x.hypot(light.z)
    };
    let free = sideways(VelocityFriction::None);
    assert!(
        free > 1e3 * NO_SIDEWAYS,
        "the contrast: without friction the light box is pushed sideways ({free:e})"
    );
    let stuck = sideways(VelocityFriction::OnVelocity);
    assert!(
        stuck <= NO_SIDEWAYS,
        "light box pushed sideways at {stuck:e}"
    );
}

/// Islands are projected independently (on several threads with the
/// `parallel` feature) and merged in island order: projecting six
/// separate boxes sunk into the ground at once gives, bit for bit, the
/// velocities of projecting each alone, and the report merges theirs.
#[test]
fn islands_projected_together_equal_each_projected_alone() {
    let mut descs = vec![ground()];
    for i in 0..6 {
        descs.push(cuboid(
            &format!("box{i}"),
            [0.5, 0.5, 0.5],
            [3.0 * i as f64, 0.5 - 0.01 * i as f64, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0 + i as f64),
        ));
    }
    let scene = scene_of(&descs);
    let velocities: Vec<BodyVelocity> = (0..scene.len())
        .map(|i| BodyVelocity {
            linear: Vector3::new(0.1 * i as f64, -0.5 - 0.1 * i as f64, 0.05),
            angular: Vector3::new(0.02 * i as f64, 0.3, -0.1),
        })
        .collect();
    let everyone: Vec<usize> = (1..scene.len()).collect();
    let mut together = velocities.clone();
    let mut stabilizer = Stabilizer::new(Settings::default()).expect("default settings");
    let report = stabilizer
        .project_velocities(
            &scene,
            &mut together,
            &everyone,
            None,
            VelocityFriction::None,
        )
        .expect("projects");
    assert_eq!(report.islands_solved, 6, "{report:?}");
    let mut merged = VelocityReport::default();
    for &body in &everyone {
        let mut alone = velocities.clone();
        let single = Stabilizer::new(Settings::default())
            .expect("default settings")
            .project_velocities(&scene, &mut alone, &[body], None, VelocityFriction::None)
            .expect("projects");
        assert_eq!(single.islands_solved, 1);
        assert_eq!(together[body], alone[body], "body {body}");
        assert_ne!(
            alone[body], velocities[body],
            "body {body} was not projected"
        );
        merged.contacts += single.contacts;
        merged.approach_before = merged.approach_before.max(single.approach_before);
        merged.approach_after = merged.approach_after.max(single.approach_after);
    }
    assert_eq!(report.contacts, merged.contacts);
    assert_eq!(report.approach_before, merged.approach_before);
    assert_eq!(report.approach_after, merged.approach_after);
    assert!(report.approach_after <= NO_APPROACH, "{report:?}");
}
