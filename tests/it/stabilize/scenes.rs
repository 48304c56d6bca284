//! Regression scenes of the stabilizer: penetration residual after
//! stabilization, measured by parry3d-f64 `query::contact` (not by our
//! V-Clip), a bound on passes, bit-identical bystanders, and invariance under
//! scaling the scene by 1e-3 and 1e3.
//!
//! Every scene carries a far-away pair of boxes separated by a gap inside the
//! contact margin: it forms an island of its own that does not penetrate, so
//! the stabilizer must not touch it (bit-identical poses).
//!
//! Run with `cargo test --test it stabilize::scenes:: -- --nocapture` to see the
//! measured figures (status, passes, depth before/after, residual by parry and SAT).

use crate::stabilize::one_row::{
    RowMember, assert_motions_match, motion, one_row_correction, one_row_tolerance,
    vertices_by_height,
};
use crate::stabilize::support::{describe, penetration_residual, stabilize_default};
use constraint_stabilization::body::{Body, BodyDesc, MassSpec};
use constraint_stabilization::internals::geometry::isometry_to_parry;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Status};
use dev_support::random::random_rotation;
use dev_support::sat::sat_depth;
use dev_support::scene::{
    IDENTITY_XYZW, assert_untouched, bystander_pair, cuboid, ground, hull, pose_bits, scaled,
    scene_of, unit_cube_sunk, xyzw,
};
use nalgebra::{Point3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

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

/// A body's motion agrees with its closed form to this fraction of that
/// motion; a rotation where none is expected is held to the angle that
/// moves the body's farthest point by this fraction of its motion.
const RELATIVE_MOTION: f64 = 0.01;

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
        let size = a.polyhedron().expect("a convex body").scale();
        let dt = (b.translation_user() / s - a.translation_user()).norm();
        let angle = a.user_pose().rotation.angle_to(&b.user_pose().rotation);
        assert!(
            dt <= SCALE_AGREEMENT * size.max(1.0) && angle <= SCALE_AGREEMENT,
            "{name}: body {} differs at scale {s:e}: |dt|/s {dt:e}, angle {angle:e}",
            a.name()
        );
    }
}

/// A unit box face down on the ground, sunk by `OVERLAP`: four coplanar
/// contacts (redundant rows).
fn box_face_down() -> TestScene {
    TestScene::new(
        "box face down",
        vec![ground(), unit_cube_sunk("box", OVERLAP)],
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
        let rotation = xyzw(&random_rotation(&mut rng));
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
                .expect("a convex body")
                .to_parry()
                .expect("parry accepts our hulls"),
            pose: isometry_to_parry(body.com_pose()),
            aabb: body.world_aabb(),
            scale: body.polyhedron().expect("a convex body").scale(),
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
    assert_stack_lifts_are_minimal(&masses);
}

/// In a stack on fixed ground, box `k` (from 1 at the bottom) must rise by
/// at least `k` overlaps, and pure lifts of exactly that (plus `k` target
/// margins) are feasible, whatever the masses: every box must end lifted by
/// exactly that, not slid, not turned (poses, to `RELATIVE_MOTION` of the
/// lift).
fn assert_stack_lifts_are_minimal(masses: &[f64]) {
    let spec = stack("stack", masses, 2);
    let (scene, report) = run_and_check(&spec, 1.0);
    let target = Settings::default().target_margin_relative * report.scale;
    for k in 1..=masses.len() {
        let body = &scene.bodies()[k];
        let y0 = 0.5 - OVERLAP + (k - 1) as f64 * (1.0 - OVERLAP);
        let moved = body.translation_user() - Vector3::new(0.0, y0, 0.0);
        let lift = k as f64 * (OVERLAP + target);
        let expected = Vector3::y() * lift;
        assert!(
            (moved - expected).norm() <= RELATIVE_MOTION * lift,
            "box {k} (mass {}): moved {moved:?}, expected {expected:?}",
            masses[k - 1]
        );
        let turned = body.user_pose().rotation.angle();
        assert!(
            turned <= RELATIVE_MOTION * lift / body.polyhedron().expect("a convex body").scale(),
            "box {k}: turned by {turned:e} rad"
        );
    }
}

#[test]
fn pyramid_with_base_ten() {
    check_scene_at_all_scales(&pyramid(10), true);
}

#[test]
fn two_hundred_random_hulls() {
    check_scene_at_all_scales(&random_hulls(200, 0.1, 11), true);
}

/// Half extents of the twin boxes: the least overlap of two coincident ones
/// is along their local y axis (twice the smallest half extent).
const TWIN_HALF_EXTENTS: [f64; 3] = [0.5, 0.3, 0.4];

/// Where the twins sit, and how they are turned.
const TWIN_AT: [f64; 3] = [1.0, 2.0, 3.0];

fn twin_rotation() -> UnitQuaternion<f64> {
    UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.2, 0.5))
}

#[test]
fn identical_boxes_at_the_same_pose_separate() {
    let rotation = twin_rotation();
    let descs = (0..2)
        .map(|k| {
            cuboid(
                &format!("twin{k}"),
                TWIN_HALF_EXTENTS,
                TWIN_AT,
                xyzw(&rotation),
                MassSpec::Mass(1.0),
            )
        })
        .collect();
    // Separating along +n or -n is equally minimal: which one is taken
    // depends on rounding, so only the displacement must scale.
    let spec = TestScene::new("identical boxes", descs, 2);
    check_scene_at_all_scales(&spec, false);
    // The minimal correction: the least overlap is 2 * 0.3 along the boxes'
    // local y; equal masses split it, each moving half (plus half the target
    // margin) in opposite directions along that axis, without turning.
    let (scene, report) = run_and_check(&spec, 1.0);
    let target = Settings::default().target_margin_relative * report.scale;
    let half_push = TWIN_HALF_EXTENTS[1] + target / 2.0;
    assert_separated_along_axis(&scene, &[(0, half_push), (1, half_push)], &rotation);
}

/// Each listed body `(index, distance)` moved by `distance` along `±axis`
/// (the boxes' local y turned by `rotation`) from `TWIN_AT`, the first in
/// one direction and the second, if any, in the other; none turned.
fn assert_separated_along_axis(
    scene: &Scene,
    moves: &[(usize, f64)],
    rotation: &UnitQuaternion<f64>,
) {
    let axis = rotation * Vector3::y();
    let first = scene.bodies()[moves[0].0].translation_user() - Vector3::from(TWIN_AT);
    let sign = first.dot(&axis).signum();
    for (k, &(index, distance)) in moves.iter().enumerate() {
        let body = &scene.bodies()[index];
        let moved = body.translation_user() - Vector3::from(TWIN_AT);
        let direction = if k == 0 { sign } else { -sign };
        let expected = axis * (direction * distance);
        println!("{}: moved {moved:?}, expected {expected:?}", body.name());
        assert!(
            (moved - expected).norm() <= RELATIVE_MOTION * distance,
            "{}: moved {moved:?}, expected {expected:?}",
            body.name()
        );
        let turned = body.user_pose().rotation.angle_to(rotation);
        assert!(
            turned
                <= RELATIVE_MOTION * distance / body.polyhedron().expect("a convex body").scale(),
            "{}: turned by {turned:e} rad",
            body.name()
        );
    }
}

/// Centre of the small box inside the big one (half extents 1, at the
/// origin).
const SMALL_AT: [f64; 3] = [0.3, 0.1, -0.05];

/// The same on the big box's x axis: no lever between the two centres
/// across x.
const SMALL_ON_AXIS: [f64; 3] = [0.3, 0.0, 0.0];

/// Half extent of the small cube.
const SMALL_HALF: f64 = 0.2;

/// A small box entirely inside a big one of the given mass, the small one
/// at `small_at`, turned by `small_rotation`.
fn small_inside_big(
    big_mass: MassSpec,
    small_at: [f64; 3],
    small_rotation: UnitQuaternion<f64>,
) -> Vec<BodyDesc> {
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
            [SMALL_HALF; 3],
            small_at,
            xyzw(&small_rotation),
            MassSpec::Density(1.0),
        ),
    ]
}

fn small_turned() -> UnitQuaternion<f64> {
    UnitQuaternion::from_scaled_axis(Vector3::new(0.1, 0.2, 0.0))
}

#[test]
fn small_box_inside_a_big_one_escapes() {
    let descs = small_inside_big(MassSpec::Density(1.0), SMALL_AT, small_turned());
    check_scene_at_all_scales(&TestScene::new("small inside big", descs, 2), true);
}

/// The axis-aligned small cube at `small_at` inside the big one: of the
/// six faces of the big box, the nearest to the small cube's far side is
/// +x (the small cube's -x face at 0.1 must pass x = 1: 0.9; the next
/// needs at least 1.1). Turning the small cube alone only widens its
/// extent along x (its four corners on that face are symmetric about its
/// centre). A dynamic big box could gain by turning with the small one
/// about their common centre of mass when the centres are offset across x
/// (a lever); at `SMALL_ON_AXIS` there is none. So the minimal correction
/// is a translation along x of `0.9` plus the target margin, split in
/// inverse mass ratio (the big box moves `-x`), with no rotation.
fn assert_small_cube_escapes_through_plus_x(big_mass: MassSpec, small_at: [f64; 3]) {
    let descs = small_inside_big(big_mass, small_at, UnitQuaternion::identity());
    let spec = TestScene::new("axis-aligned small inside big", descs, 2);
    check_scene_at_all_scales(&spec, true);
    let (scene, report) = run_and_check(&spec, 1.0);
    let target = Settings::default().target_margin_relative * report.scale;
    let push = 1.0 - (small_at[0] - SMALL_HALF) + target;
    let small_mass = (2.0 * SMALL_HALF).powi(3);
    let (small_share, big_share) = match big_mass {
        MassSpec::Fixed => (1.0, 0.0),
        MassSpec::Density(rho) => {
            let big = 8.0 * rho;
            (big / (big + small_mass), small_mass / (big + small_mass))
        }
        MassSpec::Mass(big) => (big / (big + small_mass), small_mass / (big + small_mass)),
    };
    let expected = [
        (0, [0.0; 3], -big_share * push),
        (1, small_at, small_share * push),
    ];
    for (index, start, along_x) in expected {
        let body = &scene.bodies()[index];
        let moved = body.translation_user() - Vector3::from(start);
        let wanted = Vector3::x() * along_x;
        println!("{}: moved {moved:?}, expected {wanted:?}", body.name());
        assert!(
            (moved - wanted).norm() <= RELATIVE_MOTION * along_x.abs(),
            "{}: moved {moved:?}, expected {wanted:?}",
            body.name()
        );
        let turned = body.user_pose().rotation.angle();
        assert!(
            turned
                <= RELATIVE_MOTION * along_x.abs()
                    / body.polyhedron().expect("a convex body").scale(),
            "{}: turned by {turned:e} rad",
            body.name()
        );
    }
}

#[test]
fn axis_aligned_small_box_inside_a_big_one_escapes_minimally() {
    assert_small_cube_escapes_through_plus_x(MassSpec::Density(1.0), SMALL_ON_AXIS);
}

#[test]
fn axis_aligned_small_box_inside_a_fixed_big_one_escapes_minimally() {
    // Fixed, the big box cannot turn: the offset centre changes nothing.
    assert_small_cube_escapes_through_plus_x(MassSpec::Fixed, SMALL_AT);
}

#[test]
fn stack_with_mass_ratio_ten_thousand() {
    let masses = [1.0, 1e4, 1.0, 1e4, 1.0, 1e4];
    check_scene_at_all_scales(&stack("mass ratio 1e4 stack", &masses, 2), true);
    assert_stack_lifts_are_minimal(&masses);
}

#[test]
fn small_box_inside_a_fixed_big_one_escapes() {
    let descs = small_inside_big(MassSpec::Fixed, SMALL_AT, small_turned());
    check_scene_at_all_scales(&TestScene::new("small inside fixed big", descs, 2), true);
}

#[test]
fn box_at_the_pose_of_a_fixed_one_separates() {
    let rotation = twin_rotation();
    let descs = vec![
        cuboid(
            "fixed",
            TWIN_HALF_EXTENTS,
            TWIN_AT,
            xyzw(&rotation),
            MassSpec::Fixed,
        ),
        cuboid(
            "free",
            TWIN_HALF_EXTENTS,
            TWIN_AT,
            xyzw(&rotation),
            MassSpec::Mass(1.0),
        ),
    ];
    let spec = TestScene::new("box at a fixed box's pose", descs, 2);
    check_scene_at_all_scales(&spec, false);
    // The free box alone moves the least overlap (2 * 0.3, plus the target
    // margin) along the local y axis, without turning.
    let (scene, report) = run_and_check(&spec, 1.0);
    let target = Settings::default().target_margin_relative * report.scale;
    let push = 2.0 * TWIN_HALF_EXTENTS[1] + target;
    assert_separated_along_axis(&scene, &[(1, push)], &rotation);
}

/// How far the cube's lowest corner is pushed into the free rod.
const ROD_PAIR_DEPTH: f64 = 1e-3;

/// Rounding of a vertex placed at a given height (unit-sized bodies).
const PLACEMENT_ROUNDING: f64 = 1e-12;

/// A free pair, no ground, where the split depends on the inertia: a long
/// rod (half extents 1 x 0.1 x 0.1, its inertia about its own axis 50 times
/// smaller than about the others) and a turned cube whose lowest corner is
/// `ROD_PAIR_DEPTH` into the rod's top face, off the rod's centre along and
/// across it. One row; the rod lifts, dips and rolls, the cube lifts and
/// turns, each as `dq = M^-1 J^T lambda`, `lambda = (target - phi) / (J
/// M^-1 J^T)` (inertias in closed form), to first order (the second-order
/// remainder bounds the difference), and the exact depth (SAT) after the
/// call is within the tolerance.
#[test]
fn free_rod_and_cube_split_by_mass_and_inertia() {
    let up = Vector3::y();
    let (rod_half, rod_mass): ([f64; 3], f64) = ([1.0, 0.1, 0.1], 3.0);
    let (cube_half, cube_mass): ([f64; 3], f64) = ([0.2; 3], 1.0);
    let cube_rotation: UnitQuaternion<f64> =
        UnitQuaternion::from_scaled_axis(Vector3::new(0.6, 0.2, 0.9));
    let corner_world = Vector3::new(0.7, rod_half[1] - ROD_PAIR_DEPTH, 0.03);
    // The cube's lowest corner, relative to its centre: along each local
    // axis, the side whose turned axis points down.
    let rotation_matrix = cube_rotation.to_rotation_matrix();
    let lowest_corner =
        rotation_matrix * Vector3::from_fn(|k, _| -rotation_matrix[(1, k)].signum() * cube_half[k]);
    let cube_centre = corner_world - lowest_corner;
    let mut scene = scene_of(&[
        cuboid(
            "rod",
            rod_half,
            [0.0; 3],
            IDENTITY_XYZW,
            MassSpec::Mass(rod_mass),
        ),
        cuboid(
            "cube",
            cube_half,
            cube_centre.into(),
            xyzw(&cube_rotation),
            MassSpec::Mass(cube_mass),
        ),
    ]);
    let before: Vec<_> = scene.bodies().iter().map(|b| *b.com_pose()).collect();
    let margin = Settings::default().contact_margin_relative
        * scene.bodies()[1]
            .polyhedron()
            .expect("a convex body")
            .scale();
    let heights = vertices_by_height(&scene, 1, &up);
    assert!(
        (heights[0] - corner_world).norm() <= PLACEMENT_ROUNDING
            && up.dot(&heights[1]) - rod_half[1] > 2.0 * margin,
        "one corner must be sunk, the others clear of the margin: {heights:?}"
    );
    let (report, residual) = stabilize_default(&mut scene);
    println!("{}", describe("free rod and cube", &report, residual));
    assert_eq!(report.status, Status::Converged);
    assert!(residual <= report.tolerance, "residual {residual:e}");
    assert!(sat_depth(&scene, 0, 1) <= report.tolerance, "SAT depth");
    let target = Settings::default().target_margin_relative * report.scale;
    let identity = UnitQuaternion::identity();
    // The normal points from the rod (the face's body) to the cube (the
    // vertex's body).
    let members = [
        RowMember::cuboid(rod_mass, rod_half, Vector3::zeros(), &identity, -1.0),
        RowMember::cuboid(cube_mass, cube_half, cube_centre, &cube_rotation, 1.0),
    ];
    let expected = one_row_correction(&members, &corner_world, &up, -ROD_PAIR_DEPTH, target);
    let levers = [corner_world.norm(), lowest_corner.norm()];
    let relative = one_row_tolerance(
        &expected,
        &levers,
        ROD_PAIR_DEPTH + target,
        report.tolerance + target,
    );
    let measured: Vec<_> = before
        .iter()
        .zip(scene.bodies())
        .map(|(b, body)| motion(b, body.com_pose()))
        .collect();
    assert_motions_match("free rod and cube", &measured, &expected, relative);
}
