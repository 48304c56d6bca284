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

/// The fixed ground: a wide box whose top face is `y = 0`.
pub fn ground() -> BodyDesc {
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

/// A unit quaternion as `[x, y, z, w]`.
pub use dev_support::scene::xyzw;

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

/// The cap set by the environment variable `name` (at least 1), or no cap
/// (`usize::MAX`) if it is unset or not a number.
pub fn env_cap(name: &str) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .map_or(usize::MAX, |n: usize| n.max(1))
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

/// The arguments after `--` that several harnesses take: `--quick` and
/// `--only TEXT` (the scenes whose name contains TEXT).
pub struct BenchArgs {
    pub quick: bool,
    pub only: Option<String>,
}

impl BenchArgs {
    /// From the process's arguments.
    pub fn parse() -> Self {
        let args: Vec<String> = std::env::args().skip(1).collect();
        BenchArgs {
            quick: args.iter().any(|a| a == "--quick"),
            only: args
                .iter()
                .position(|a| a == "--only")
                .and_then(|i| args.get(i + 1).cloned()),
        }
    }
}

/// Every `tests/data/engine/*.json` by file stem, sorted (engine states
/// of Rapier, MuJoCo and Bullet; see the notes there): the integration
/// tests' reader, shared.
#[cfg(feature = "serde")]
#[path = "../../tests/it/support/engine_states.rs"]
mod engine_state_files;
// Each benchmark includes this module; not every one reads the states.
#[cfg(feature = "serde")]
#[allow(unused_imports)]
pub use engine_state_files::engine_states;

/// `scene` with `mu` as every body's friction coefficient (`None`: cleared,
/// so that the stabilizer's frictionless default applies). The Rapier
/// states written by `examples/engine_states.rs` through the bridge carry
/// Rapier's coefficient (0.5) on their bodies: a frictionless call clears
/// it. Panics on an invalid `mu` (a benchmark's constant).
// Each benchmark includes this module; not every one calls it.
#[allow(dead_code)]
pub fn with_friction(
    mut scene: constraint_stabilization::scene::Scene,
    mu: Option<f64>,
) -> constraint_stabilization::scene::Scene {
    for body in 0..scene.bodies().len() {
        scene
            .body_mut(body)
            // The index is one of the scene's bodies.
            .expect("a body of the scene")
            .set_friction(mu)
            .expect("a finite nonnegative coefficient");
    }
    scene
}

/// The friction coefficient of a pair of default bodies in the engine of
/// the state named `stem` (`bt..`, `mj..`, `rp..`): Bullet 0.5 x 0.5 (it
/// multiplies the bodies' coefficients), MuJoCo 1.0 (its default), Rapier
/// 0.5 (its default).
// Each benchmark includes this module; not every one calls it.
#[allow(dead_code)]
pub fn engine_friction(stem: &str) -> f64 {
    match stem.get(..2) {
        Some("bt") => 0.5 * 0.5,
        Some("mj") => 1.0,
        _ => 0.5,
    }
}

/// Directory of the result files (created on demand).
pub fn results_dir() -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("benchmarks/results");
    std::fs::create_dir_all(&dir).expect("create benchmarks/results");
    dir
}

/// `/proc/loadavg` (the machine is shared), or "unknown".
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg").map_or("unknown".into(), |s| s.trim().to_string())
}

/// The current UTC date and time, `YYYY-MM-DD HH:MM:SS UTC` (from the
/// system clock; civil date from days since 1970, Howard Hinnant's
/// algorithm).
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs()) as i64;
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// The commit the benchmark was built from (`git describe --always
/// --dirty`), or "unknown".
pub fn git_commit() -> String {
    std::process::Command::new("git")
        .args(["describe", "--always", "--dirty"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map_or("unknown".into(), |o| {
            String::from_utf8_lossy(&o.stdout).trim().to_string()
        })
}

/// Provenance of a result file, taken when the run starts: the command, the
/// start date, the commit, the number of CPUs and the load average.
pub struct Provenance {
    command: String,
    started: String,
    commit: String,
    load_at_start: String,
}

impl Provenance {
    /// `command` as the user types it (environment variables included).
    pub fn start(command: impl Into<String>) -> Self {
        Provenance {
            command: command.into(),
            started: utc_now(),
            commit: git_commit(),
            load_at_start: load_average(),
        }
    }

    /// The Markdown lines to put under a result file's title: command,
    /// dates, commit, CPUs, load average at the start and at the end (now).
    pub fn markdown(&self) -> String {
        let cpus = std::thread::available_parallelism().map_or(0, |n| n.get());
        format!(
            "- command: `{}`\n- started: {}; finished: {}\n- commit: {}\n\
             - machine: {cpus} CPUs, shared with other builds; load average \
             (`/proc/loadavg`) at the start: {}; at the end: {}\n",
            self.command,
            self.started,
            utc_now(),
            self.commit,
            self.load_at_start,
            load_average(),
        )
    }
}

/// The command line that ran this benchmark: `cargo bench --bench NAME`,
/// the environment variables in `env_vars` that are set, and the
/// arguments after `--` (without the ones cargo adds, such as `--bench`).
pub fn bench_command(name: &str, env_vars: &[&str]) -> String {
    let mut command = String::new();
    for var in env_vars {
        if let Ok(value) = std::env::var(var) {
            command += &format!("{var}={value} ");
        }
    }
    command += &format!("cargo bench --bench {name}");
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    if !args.is_empty() {
        command += &format!(" -- {}", args.join(" "));
    }
    command
}

/// Writes `table` in place of the generated part of the file at `path`
/// (everything before its first `## ` section) and keeps the sections
/// after it: the readings and measurements appended to a results file
/// survive its regeneration.
pub fn write_keeping_sections(path: &std::path::Path, table: &str) {
    let kept = std::fs::read_to_string(path)
        .ok()
        .and_then(|old| old.find("\n## ").map(|at| old[at..].to_owned()))
        .unwrap_or_default();
    std::fs::write(path, format!("{}{kept}", table.trim_end_matches('\n'))).expect("write md");
}
