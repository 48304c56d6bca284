//! Regression scenes of the stabilizer: penetration residual after
//! stabilization, measured by parry3d-f64 `query::contact` (not by our
//! V-Clip), a bound on passes, bit-identical bystanders, and invariance under
//! scaling the scene by 1e-3 and 1e3.
//!
//! Every scene carries a far-away pair of boxes separated by a gap inside the
//! contact margin: it forms an island of its own that does not penetrate, so
//! the stabilizer must not touch it (bit-identical poses).
//!
//! Run with `cargo test --test stabilize_scenes -- --nocapture` to see the
//! measured figures (status, passes, depth before/after, residual by parry and SAT).

mod stabilize_support;

use constraint_stabilization::body::{Body, BodyDesc, MassSpec};
use constraint_stabilization::geometry::isometry_to_parry;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Status};
use nalgebra::{Point3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use stabilize_support::*;

/// Overlap of the boxes of the stacks and the pyramid, as a fraction of a
/// box's height (the "1%").
const OVERLAP: f64 = 0.01;

/// Gap between the two bodies of the bystander pair, a fifth of the default
/// contact margin (1e-2 of the smallest circumradius, here >= 0.1 * 0.87):
/// close enough to be a near contact, clear of any penetration.
const BYSTANDER_GAP: f64 = 2e-4;

/// Where the bystander pair sits: far from every scene below.
const BYSTANDER_AT: [f64; 3] = [0.0, 0.0, 1000.0];

/// Largest relative difference between a scaled scene's result divided by
/// the scale and the unscaled result: the stabilizer works in units of the
/// scene's scale, so only rounding separates them.
const SCALE_AGREEMENT: f64 = 1e-6;

/// A test scene: descriptions, the indices that must stay bit-identical,
/// and the most passes it may take.
struct TestScene {
    name: &'static str,
    descs: Vec<BodyDesc>,
    untouched: Vec<usize>,
    max_passes: usize,
}

impl TestScene {
    fn new(name: &'static str, mut descs: Vec<BodyDesc>, max_passes: usize) -> Self {
        let mut untouched: Vec<usize> = descs
            .iter()
            .enumerate()
            .filter(|(_, d)| d.mass == MassSpec::Fixed)
            .map(|(i, _)| i)
            .collect();
        untouched.extend([descs.len(), descs.len() + 1]);
        descs.extend(bystander_pair(BYSTANDER_AT, BYSTANDER_GAP));
        TestScene {
            name,
            descs,
            untouched,
            max_passes,
        }
    }

    fn scaled(&self, s: f64) -> Vec<BodyDesc> {
        self.descs.iter().map(|d| scaled(d, s)).collect()
    }
}

/// Stabilizes, then asserts: converged, residual (parry, SAT) within the
/// tolerance, passes bounded, bystanders and fixed bodies bit-identical.
fn run_and_check(scene_spec: &TestScene, s: f64) -> (Scene, Report) {
    let mut scene = scene_of(&scene_spec.scaled(s));
    let (depth_before, _) = penetration_residual(&scene);
    let before = pose_bits(&scene);
    let (report, residual) = stabilize_default(&mut scene);
    let label = format!("{} (scale {s:e})", scene_spec.name);
    println!(
        "{}, depth before (max of parry, SAT) {depth_before:.3e}",
        describe(&label, &report, residual)
    );
    assert!(
        depth_before > report.tolerance,
        "the scene must penetrate to test anything"
    );
    assert_eq!(report.status, Status::Converged, "{}", scene_spec.name);
    assert!(
        residual <= report.tolerance,
        "{}: residual {residual:e} above tolerance {:e}",
        scene_spec.name,
        report.tolerance
    );
    assert!(
        report.passes <= scene_spec.max_passes,
        "{}: {} passes, at most {} expected",
        scene_spec.name,
        report.passes,
        scene_spec.max_passes
    );
    assert_untouched(&scene, &before, &scene_spec.untouched);
    (scene, report)
}

/// Runs the scene at scales 1, 1e-3 and 1e3: each passes [`run_and_check`],
/// the passes are the same, the mass-weighted displacement scales by
/// `s^(5/2)` (masses scale by `s^3`, lengths by `s`) and, when the minimal
/// correction is unique, the poses scale by `s`.
fn check_scene_at_all_scales(spec: &TestScene, unique: bool) {
    let (reference, report_reference) = run_and_check(spec, 1.0);
    for s in [1e-3, 1e3] {
        let (scene, report) = run_and_check(spec, s);
        assert_eq!(
            report.passes, report_reference.passes,
            "{}: passes differ at scale {s:e}",
            spec.name
        );
        let expected = report_reference.displacement * s.powf(2.5);
        assert!(
            (report.displacement - expected).abs() <= SCALE_AGREEMENT * expected,
            "{}: displacement {:e} at scale {s:e}, expected {expected:e}",
            spec.name,
            report.displacement
        );
        if unique {
            assert_poses_scale(spec.name, &reference, &scene, s);
        }
    }
}

fn assert_poses_scale(name: &str, reference: &Scene, scaled_scene: &Scene, s: f64) {
    for (a, b) in reference.bodies().iter().zip(scaled_scene.bodies()) {
        let size = a.polyhedron().scale();
        let dt = (b.translation_user() / s - a.translation_user()).norm();
        let angle = a.user_pose().rotation.angle_to(&b.user_pose().rotation);
        assert!(
            dt <= SCALE_AGREEMENT * size.max(1.0) && angle <= SCALE_AGREEMENT,
            "{name}: body {} differs at scale {s:e}: |dt|/s {dt:e}, angle {angle:e}",
            a.name()
        );
    }
}

fn ground() -> BodyDesc {
    cuboid(
        "ground",
        [20.0, 0.5, 20.0],
        [0.0, -0.5, 0.0],
        IDENTITY_XYZW,
        MassSpec::Fixed,
    )
}

/// A unit box face down on the ground, sunk by `OVERLAP`: four coplanar
/// contacts (redundant rows).
fn box_face_down() -> TestScene {
    TestScene::new(
        "box face down",
        vec![
            ground(),
            cuboid(
                "box",
                [0.5, 0.5, 0.5],
                [0.0, 0.5 - OVERLAP, 0.0],
                IDENTITY_XYZW,
                MassSpec::Mass(1.0),
            ),
        ],
        2,
    )
}

/// `n` unit boxes stacked on the ground, each sunk by `OVERLAP` into the one
/// below (the lowest into the ground), with the given masses.
fn stack(name: &'static str, masses: &[f64], max_passes: usize) -> TestScene {
    let mut descs = vec![ground()];
    for (k, &m) in masses.iter().enumerate() {
        let y = 0.5 - OVERLAP + k as f64 * (1.0 - OVERLAP);
        descs.push(cuboid(
            &format!("box{k}"),
            [0.5, 0.5, 0.5],
            [0.0, y, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(m),
        ));
    }
    TestScene::new(name, descs, max_passes)
}

/// A 2D pyramid of unit boxes with `base` boxes in the bottom row; boxes of a
/// row are `ROW_GAP` apart, each box rests on two of the row below, sunk by
/// `OVERLAP` (the bottom row into the ground).
fn pyramid(base: usize) -> TestScene {
    const ROW_GAP: f64 = 0.05;
    let mut descs = vec![ground()];
    for row in 0..base {
        for i in 0..base - row {
            let x = (i as f64 + row as f64 / 2.0) * (1.0 + ROW_GAP);
            let y = 0.5 - OVERLAP + row as f64 * (1.0 - OVERLAP);
            descs.push(cuboid(
                &format!("r{row}b{i}"),
                [0.5, 0.5, 0.5],
                [x, y, 0.0],
                IDENTITY_XYZW,
                MassSpec::Density(1.0),
            ));
        }
    }
    TestScene::new("pyramid base 10", descs, 2)
}

/// A random unit-ish convex hull: a jittered tetrahedron (so it has volume)
/// and 12 points on an ellipsoid of radii `size * (0.7..1.3)`.
fn random_hull_points(rng: &mut ChaCha8Rng, size: f64) -> Vec<Point3<f64>> {
    let radii = Vector3::from_fn(|_, _| size * rng.random_range(0.7..1.3));
    let mut points: Vec<Point3<f64>> = [
        [1.0, 1.0, 1.0],
        [1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
    ]
    .iter()
    .map(|c| Point3::from(Vector3::from(*c).component_mul(&radii) * 0.5))
    .collect();
    for _ in 0..12 {
        let direction = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        if direction.norm() < 1e-3 {
            continue;
        }
        points.push(Point3::from(direction.normalize().component_mul(&radii)));
    }
    points
}

fn random_rotation(rng: &mut ChaCha8Rng) -> [f64; 4] {
    let axis_angle =
        Vector3::from_fn(|_, _| rng.random_range(-std::f64::consts::PI..std::f64::consts::PI));
    xyzw(&UnitQuaternion::from_scaled_axis(axis_angle))
}

/// `count` random convex hulls, dynamic, no ground, placed by rejection
/// sampling in a cube so that every pair overlaps by at most `max_overlap`
/// of the smaller body's circumradius (parry's depth).
fn random_hulls(count: usize, max_overlap: f64, seed: u64) -> TestScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let side = 4.6;
    let mut descs: Vec<BodyDesc> = Vec::new();
    let mut placed: Vec<PlacedHull> = Vec::new();
    while descs.len() < count {
        let size = rng.random_range(0.3..0.6);
        let points = random_hull_points(&mut rng, size);
        let rotation = random_rotation(&mut rng);
        loop {
            let translation = [(); 3].map(|_| rng.random_range(0.0..side));
            let desc = hull(
                &format!("hull{}", descs.len()),
                points.clone(),
                translation,
                rotation,
                MassSpec::Density(1.0),
            );
            let candidate = PlacedHull::new(&desc);
            let acceptable = placed.iter().all(|other| {
                candidate.depth(other) <= max_overlap * candidate.scale.min(other.scale)
            });
            if acceptable {
                descs.push(desc);
                placed.push(candidate);
                break;
            }
        }
    }
    TestScene::new("200 random hulls", descs, 8)
}

/// A hull being placed: parry shape and pose, AABB, circumradius.
struct PlacedHull {
    shape: parry3d_f64::shape::ConvexPolyhedron,
    pose: parry3d_f64::math::Pose,
    aabb: (Point3<f64>, Point3<f64>),
    scale: f64,
}

impl PlacedHull {
    fn new(desc: &BodyDesc) -> Self {
        let body = Body::new(desc.clone()).expect("valid hull");
        PlacedHull {
            shape: body
                .polyhedron()
                .to_parry()
                .expect("parry accepts our hulls"),
            pose: isometry_to_parry(body.com_pose()),
            aabb: body.world_aabb(),
            scale: body.polyhedron().scale(),
        }
    }

    /// parry's penetration depth of the two (0 if separated).
    fn depth(&self, other: &PlacedHull) -> f64 {
        let ((min_a, max_a), (min_b, max_b)) = (self.aabb, other.aabb);
        if (0..3).any(|k| min_a[k] > max_b[k] || min_b[k] > max_a[k]) {
            return 0.0;
        }
        parry3d_f64::query::contact(&self.pose, &self.shape, &other.pose, &other.shape, 0.0)
            .expect("parry supports convex polyhedra")
            .map_or(0.0, |c| (-c.dist).max(0.0))
    }
}

#[test]
fn box_face_down_is_lifted_flat() {
    let spec = box_face_down();
    check_scene_at_all_scales(&spec, true);
    let (scene, _) = run_and_check(&spec, 1.0);
    let body = &scene.bodies()[1];
    let t = body.translation_user();
    let angle = body
        .user_pose()
        .rotation
        .angle_to(&UnitQuaternion::identity());
    println!("box face down: translation {t:?}, tilt {angle:e}");
    assert!(angle <= 1e-9, "the box was tilted by {angle:e} rad");
    assert!(
        t.x.abs() <= 1e-9 && t.z.abs() <= 1e-9,
        "the box slid: {t:?}"
    );
    assert!(t.y >= 0.5 - 1e-6 && t.y <= 0.5 + 1e-5, "lifted to {}", t.y);
}

#[test]
fn stack_of_ten_boxes() {
    let masses = [1.0; 10];
    check_scene_at_all_scales(&stack("stack of 10", &masses, 2), true);
    assert_stack_lift_is_minimal(&masses);
}

/// In a stack on fixed ground, box `k` (from 1 at the bottom) must rise by
/// at least `k` overlaps, and pure lifts of exactly that are feasible: the
/// minimal displacement is `sqrt(sum_k m_k (k OVERLAP)^2)` (plus the target
/// margins, far below 1%).
fn assert_stack_lift_is_minimal(masses: &[f64]) {
    let spec = stack("stack", masses, 2);
    let (_, report) = run_and_check(&spec, 1.0);
    let minimal = masses
        .iter()
        .enumerate()
        .map(|(k, m)| m * ((k + 1) as f64 * OVERLAP).powi(2))
        .sum::<f64>()
        .sqrt();
    println!(
        "stack displacement {:.6e}, minimal {minimal:.6e}",
        report.displacement
    );
    assert!((report.displacement - minimal).abs() <= 0.01 * minimal);
}

#[test]
fn pyramid_with_base_ten() {
    check_scene_at_all_scales(&pyramid(10), true);
}

#[test]
fn two_hundred_random_hulls() {
    check_scene_at_all_scales(&random_hulls(200, 0.1, 11), true);
}

#[test]
fn identical_boxes_at_the_same_pose_separate() {
    let rotation = xyzw(&UnitQuaternion::from_scaled_axis(Vector3::new(
        0.3, -0.2, 0.5,
    )));
    let descs = (0..2)
        .map(|k| {
            cuboid(
                &format!("twin{k}"),
                [0.5, 0.3, 0.4],
                [1.0, 2.0, 3.0],
                rotation,
                MassSpec::Mass(1.0),
            )
        })
        .collect();
    // Separating along +n or -n is equally minimal: which one is taken
    // depends on rounding, so only the displacement must scale.
    check_scene_at_all_scales(&TestScene::new("identical boxes", descs, 2), false);
}

/// A small box entirely inside a big one of the given mass.
fn small_inside_big(big_mass: MassSpec) -> Vec<BodyDesc> {
    vec![
        cuboid(
            "big",
            [1.0, 1.0, 1.0],
            [0.0, 0.0, 0.0],
            IDENTITY_XYZW,
            big_mass,
        ),
        cuboid(
            "small",
            [0.2, 0.2, 0.2],
            [0.3, 0.1, -0.05],
            xyzw(&UnitQuaternion::from_scaled_axis(Vector3::new(
                0.1, 0.2, 0.0,
            ))),
            MassSpec::Density(1.0),
        ),
    ]
}

#[test]
fn small_box_inside_a_big_one_escapes() {
    let descs = small_inside_big(MassSpec::Density(1.0));
    check_scene_at_all_scales(&TestScene::new("small inside big", descs, 2), true);
}

#[test]
fn stack_with_mass_ratio_ten_thousand() {
    let masses = [1.0, 1e4, 1.0, 1e4, 1.0, 1e4];
    check_scene_at_all_scales(&stack("mass ratio 1e4 stack", &masses, 2), true);
    assert_stack_lift_is_minimal(&masses);
}

#[test]
fn small_box_inside_a_fixed_big_one_escapes() {
    let descs = small_inside_big(MassSpec::Fixed);
    check_scene_at_all_scales(&TestScene::new("small inside fixed big", descs, 2), true);
}

#[test]
fn box_at_the_pose_of_a_fixed_one_separates() {
    let rotation = xyzw(&UnitQuaternion::from_scaled_axis(Vector3::new(
        -0.2, 0.4, 0.1,
    )));
    let descs = vec![
        cuboid(
            "fixed",
            [0.5, 0.3, 0.4],
            [1.0, 2.0, 3.0],
            rotation,
            MassSpec::Fixed,
        ),
        cuboid(
            "free",
            [0.5, 0.3, 0.4],
            [1.0, 2.0, 3.0],
            rotation,
            MassSpec::Mass(1.0),
        ),
    ];
    check_scene_at_all_scales(
        &TestScene::new("box at a fixed box's pose", descs, 2),
        false,
    );
}
