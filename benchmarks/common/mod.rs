//! Scenes and statistics shared by the benchmarks.
//!
//! Scenes besides `demo::demo_scene`:
//! - [`box_stack`]: a fixed ground (top face `y = 0`) and a column of
//!   `height` unit-ish boxes, each sunk into the one below (or the ground) by
//!   [`STACK_OVERLAP`] of its height, with a small random tilt, yaw and
//!   sideways offset (seeded `ChaCha8Rng`), as a stack after a bad step;
//! - [`box_on_ground`]: one box resting face down on the fixed ground,
//!   sunk by [`RESTING_SINK`] of its height, upright or slightly tilted.
//!   Upright, the exact answer moves it straight up: any final tilt is an
//!   artefact of the contact model (one deepest vertex rather than the
//!   face's manifold).
//!
//! Tilt of a body: the angle between its body `y` axis in world frame
//! (`R e_y`) and the world `y` axis, `acos(clamp((R e_y).y))`.

#![allow(dead_code)]

use std::time::Instant;

use constraint_stabilization::body::{BodyDesc, MassSpec, Shape};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Stabilizer};
use nalgebra::{UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Overlap of a stacked box into the one below, fraction of its height.
pub const STACK_OVERLAP: f64 = 0.03;
/// Largest tilt of a stacked box (radians).
pub const STACK_MAX_TILT: f64 = 0.05;
/// Largest yaw of a stacked box (radians).
pub const STACK_MAX_YAW: f64 = 0.3;
/// Largest sideways offset of a stacked box, fraction of its half width.
pub const STACK_JITTER: f64 = 0.1;
/// Sink of the resting box into the ground, fraction of its height.
pub const RESTING_SINK: f64 = 0.01;
/// Half extent of the ground box in x and z.
const GROUND_HALF_WIDTH: f64 = 50.0;
/// Half height of the ground box.
const GROUND_HALF_HEIGHT: f64 = 0.5;

fn ground() -> BodyDesc {
    BodyDesc {
        name: "ground".into(),
        shape: Shape::Cuboid {
            half_extents: Vector3::new(GROUND_HALF_WIDTH, GROUND_HALF_HEIGHT, GROUND_HALF_WIDTH),
        },
        translation: Vector3::new(0.0, -GROUND_HALF_HEIGHT, 0.0),
        rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
        mass: MassSpec::Fixed,
    }
}

fn xyzw(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.i, q.j, q.k, q.w]
}

/// Ground plus a column of `height` boxes (see the module doc).
pub fn box_stack(height: usize, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut scene = Scene::new();
    // The descriptions are valid by construction (positive extents, unit
    // quaternions, positive masses): add_body cannot fail.
    scene.add_body(ground()).expect("valid ground");
    let mut top = 0.0;
    for k in 0..height {
        let half = Vector3::new(
            rng.random_range(0.4..0.6),
            rng.random_range(0.2..0.3),
            rng.random_range(0.4..0.6),
        );
        let yaw = UnitQuaternion::from_axis_angle(
            &Vector3::y_axis(),
            rng.random_range(-STACK_MAX_YAW..STACK_MAX_YAW),
        );
        let tilt = UnitQuaternion::from_axis_angle(
            &Vector3::x_axis(),
            rng.random_range(-STACK_MAX_TILT..STACK_MAX_TILT),
        );
        let rotation = tilt * yaw;
        let height_k = 2.0 * half.y;
        let centre_y = top + half.y - STACK_OVERLAP * height_k;
        let offset = STACK_JITTER * half.x;
        let translation = Vector3::new(
            rng.random_range(-offset..offset),
            centre_y,
            rng.random_range(-offset..offset),
        );
        top = centre_y + half.y;
        scene
            .add_body(BodyDesc {
                name: format!("box{k}"),
                shape: Shape::Cuboid { half_extents: half },
                translation,
                rotation_xyzw: xyzw(&rotation),
                mass: MassSpec::Mass(1.0),
            })
            .expect("valid box");
    }
    scene
}

/// Ground plus one box sunk by [`RESTING_SINK`] of its height (at its
/// centre), tilted by `tilt` radians about the world `x` axis.
pub fn box_on_ground(tilt: f64) -> Scene {
    let half = Vector3::new(0.5, 0.25, 0.4);
    let mut scene = Scene::new();
    scene.add_body(ground()).expect("valid ground");
    scene
        .add_body(BodyDesc {
            name: "box".into(),
            shape: Shape::Cuboid { half_extents: half },
            translation: Vector3::new(0.0, half.y - RESTING_SINK * 2.0 * half.y, 0.0),
            rotation_xyzw: xyzw(&UnitQuaternion::from_axis_angle(&Vector3::x_axis(), tilt)),
            mass: MassSpec::Mass(1.0),
        })
        .expect("valid box");
    scene
}

/// Tilt of body `index` from upright (radians; see the module doc).
pub fn tilt(scene: &Scene, index: usize) -> f64 {
    let up = scene.bodies()[index].user_pose().rotation * Vector3::y();
    up.y.clamp(-1.0, 1.0).acos()
}

/// Median (of a copy); NaN for an empty slice.
pub fn median(values: &[f64]) -> f64 {
    let mut sorted: Vec<f64> = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    match sorted.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => sorted[n / 2],
        n => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
    }
}

/// One cold call (fresh stabilizer) on a clone of `scene`: the report,
/// the wall time measured outside the call, and the stabilized scene.
pub fn run_cold(scene: &Scene, settings: &Settings) -> (Report, f64, Scene) {
    let mut work = scene.clone();
    let mut stabilizer = Stabilizer::new(settings.clone()).expect("valid settings");
    let start = Instant::now();
    let report = stabilizer.stabilize(&mut work).expect("stabilize");
    (report, start.elapsed().as_secs_f64(), work)
}

/// Directory of the result files (created on demand).
pub fn results_dir() -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("benchmarks/results");
    std::fs::create_dir_all(&dir).expect("create benchmarks/results");
    dir
}
