//! The same Rapier scenes run plain and with one stabilization call after
//! every step (issue 10 and 11): what the projection does to an engine's
//! simulation, measured.
//!
//! ```text
//! cargo run --release --features rapier,serde --example with_and_without -- [--steps N] [--only NAME] [--scenes A,B,...] [--runs A,B] [--out DIR]
//! ```
//!
//! `--runs A,B` runs only the runs whose name contains `A` or `B`
//! (`plain`, `default`, `closed`, `velocity`, `allowed`, `positions`).
//! `--only NAME` runs the scenes whose name contains `NAME`; `--scenes`
//! runs the scenes listed, each entry a scene's name or the part of names
//! before an underscore (`chain20` is `chain20_1x`, `chain20_100x` and
//! `chain20_1000x`; `stack` both stacks). Without either, every scene.
//!
//! Scenes (examples/common/rapier_scenes.rs, Rapier's defaults, 60 Hz):
//! a pile of 200 boxes and hulls dropped into a bin; a pile of 60 compound
//! bodies (two or three box colliders on one rigid body, L and T shapes)
//! dropped into a bin; a pile of 60 balls, capsules, cylinders and rounded
//! boxes dropped into a bin (issue 25); four light boxes under
//! a box 100 and 1,000 times heavier; a box thrown at 15 m/s into a stack;
//! a pyramid of 55 boxes. Runs, from the same initial world:
//! - `plain`: Rapier alone;
//! - `velocity (...)`: a [`RapierBridge`] call after every step with
//!   velocity consistency and the colliders' friction, the velocity
//!   projection with the kinematic cone on `v'` or frictionless;
//! - `closed contacts`: the same (frictionless velocity projection) with
//!   the corrected contacts left touching (`CouplingMode::ClosedContacts`);
//!   the bridge's default is marked;
//! - `allowed+friction`: Rapier's allowed penetration left, positions only;
//! - `positions`: a call after every step with the library's defaults
//!   (positions only, velocities untouched, no friction).
//!
//! Per step: the exact deepest penetration of the Rapier world after the
//! step (and the call), by brute-force separating axes over every pair of
//! colliders with a dynamic body (`dev_support::sat`, on the f32 poses as
//! Rapier holds them); Rapier's step time and the call's time, with the
//! call's narrow-phase queries and time (CSV only); the height
//! of the tracked top body (stacks, pyramid); the largest horizontal drift
//! of a tracked body from its first pose; failed calls; the steps whose
//! exact depth over the pairs with an awake dynamic body exceeds the
//! tolerance the call stated (its acceptance threshold: the allowed
//! penetration of the coupling included; a pair of two sleeping bodies is
//! outside what a call reads or states, and left at Rapier's depth). Writes
//! `DIR/with_and_without.csv` (every step), `DIR/with_and_without.md` (the
//! summary table) and `DIR/with_and_without_NAME.svg` (deepest penetration
//! against time, log scale, one line per run), and prints the table.
//!
//! Joint scenes (examples/common/rapier_joint_scenes.rs, issue 23): chains
//! of 20 revolute links holding an end box 1, 100 and 1,000 times a link's
//! mass, a chain of 50 links with 100 times, a ragdoll-like figure dropped
//! on the ground, the same of capsules and a ball
//! (examples/common/rapier_round_scenes.rs, issue 25), a hinged lever
//! resting on a box; each run plain and with
//! a bridge call of `BridgeSettings::default()` after every step. Per step:
//! the largest joint separation (the distance between a joint's two anchor
//! points, in f64 from Rapier's f32 poses), the chain's stretch (summed
//! separations over the rest length), the exact deepest penetration (the
//! same oracle), the call's status and tolerance, Rapier's step time and
//! the call's time. Writes `DIR/with_and_without_joints.csv` (every step),
//! the joint table after the contact table in `DIR/with_and_without.md`,
//! and `DIR/with_and_without_NAME.svg` (largest joint separation against
//! time, log scale, with and without). `DIR/with_and_without.csv` is
//! written only when a contact scene ran.

#[path = "common/rapier_joint_scenes.rs"]
mod joint_scenes;
#[path = "common/rapier_round_scenes.rs"]
mod round_scenes;
#[path = "common/rapier_scenes.rs"]
mod scenes;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use constraint_stabilization::Settings;
use constraint_stabilization::rapier_bridge::{BridgeSettings, CouplingMode, RapierBridge};
use constraint_stabilization::stabilizer::VelocityFriction;
use joint_scenes::Chain;
use plotters::prelude::*;
use rapier3d::prelude::*;

/// Steps per run (5 s at 60 Hz).
const DEFAULT_STEPS: usize = 300;
/// Floor of the log-scale plot (a depth of 0 is drawn there).
const PLOT_FLOOR: f64 = 1e-9;

/// A scene: a builder of its world at step 0 and of the bodies to track
/// (bottom to top for stacks; the last one is the "top").
struct Scene {
    name: &'static str,
    build: fn() -> (PhysicsWorld, Vec<RigidBodyHandle>),
    /// The step from which drift is measured (after a dropped pile has
    /// settled; 0 for stacks built in place).
    drift_from: usize,
}

/// Every dynamic body of a world.
fn all_dynamic(world: &PhysicsWorld) -> Vec<RigidBodyHandle> {
    world
        .bodies
        .iter()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .collect()
}

fn scenes() -> Vec<Scene> {
    vec![
        Scene {
            name: "pile_200",
            build: || {
                let world = scenes::pile_world(200, 1.0, 1);
                let tracked = all_dynamic(&world);
                (world, tracked)
            },
            drift_from: 150,
        },
        Scene {
            name: "compound_pile_60",
            build: || {
                let world = scenes::compound_pile_world(60, 0.6, 1);
                let tracked = all_dynamic(&world);
                (world, tracked)
            },
            drift_from: 150,
        },
        Scene {
            name: "mixed_pile_60",
            build: || {
                let world = scenes::mixed_pile_world(60, 0.6, 1);
                let tracked = all_dynamic(&world);
                (world, tracked)
            },
            drift_from: 150,
        },
        Scene {
            name: "stack_1to100",
            build: || scenes::aligned_heavy_stack_world(100.0),
            drift_from: 0,
        },
        Scene {
            name: "stack_1to1000",
            build: || scenes::aligned_heavy_stack_world(1000.0),
            drift_from: 0,
        },
        Scene {
            name: "thrown_box",
            build: || {
                let (world, mut tracked) = scenes::thrown_box_world(6);
                tracked.pop();
                (world, tracked)
            },
            drift_from: 0,
        },
        Scene {
            name: "pyramid_55",
            build: scenes::pyramid_world,
            drift_from: 0,
        },
    ]
}

/// A scene with joints: a builder of its world at step 0 and, for a chain,
/// its joints and rest length.
struct JointScene {
    name: &'static str,
    build: JointBuild,
}

/// A joint scene's builder: its world and, for a chain, the chain.
type JointBuild = fn() -> (PhysicsWorld, Option<Chain>);

fn joint_scenes() -> Vec<JointScene> {
    /// A chain of `LINKS` links, its end box `RATIO` times a link's mass.
    fn chain<const LINKS: usize, const RATIO: u16>() -> (PhysicsWorld, Option<Chain>) {
        let (world, chain) = joint_scenes::chain_world(LINKS, f32::from(RATIO));
        (world, Some(chain))
    }
    let scenes: [(&'static str, JointBuild); 7] = [
        ("chain20_1x", chain::<20, 1>),
        ("chain20_100x", chain::<20, 100>),
        ("chain20_1000x", chain::<20, 1000>),
        ("chain50_100x", chain::<50, 100>),
        ("ragdoll", || (joint_scenes::ragdoll_world(), None)),
        ("capsule_ragdoll", || {
            (round_scenes::capsule_ragdoll_world(), None)
        }),
        ("lever", || (joint_scenes::lever_world(), None)),
    ];
    scenes
        .into_iter()
        .map(|(name, build)| JointScene { name, build })
        .collect()
}

/// Which scenes to run: `--only` (a part of the name) and `--scenes` (a
/// comma-separated list of names or name prefixes before an underscore).
struct Selection {
    only: Option<String>,
    scenes: Option<Vec<String>>,
}

impl Selection {
    fn wants(&self, name: &str) -> bool {
        let only = self.only.as_deref().is_none_or(|o| name.contains(o));
        let listed = self
            .scenes
            .as_ref()
            .is_none_or(|list| list.iter().any(|entry| Self::names(entry, name)));
        only && listed
    }

    /// Whether a `--scenes` entry names this scene.
    fn names(entry: &str, name: &str) -> bool {
        name == entry
            || name
                .strip_prefix(entry)
                .is_some_and(|rest| rest.starts_with('_'))
    }

    /// The `--scenes` entries that name no scene.
    fn unknown(&self, names: &[&str]) -> Vec<String> {
        self.scenes
            .iter()
            .flatten()
            .filter(|entry| !names.iter().any(|name| Self::names(entry, name)))
            .cloned()
            .collect()
    }
}

/// How the world is stabilized after each step.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Run {
    /// Rapier alone.
    Plain,
    /// Velocity consistency with the colliders' friction, the velocity
    /// projection with this friction (one of them is the bridge's default).
    Velocity(VelocityFriction),
    /// Velocity consistency (frictionless velocity projection) with the
    /// corrected contacts left closed (`CouplingMode::ClosedContacts`).
    Closed,
    /// The same without resting calls (`BridgeSettings::resting_calls`
    /// off): every call closes the contacts.
    ClosedEveryCall,
    /// Rapier's allowed penetration respected, with the colliders'
    /// friction, positions only.
    Allowed,
    /// Positions only, velocities untouched, no friction.
    Positions,
    /// The bridge's defaults, `BridgeSettings::default()` (the joint
    /// scenes' run).
    Default,
}

impl Run {
    const ALL: [Run; 7] = [
        Run::Plain,
        Run::Velocity(VelocityFriction::OnVelocity),
        Run::Velocity(VelocityFriction::None),
        Run::Closed,
        Run::ClosedEveryCall,
        Run::Allowed,
        Run::Positions,
    ];

    fn name(self) -> String {
        match self {
            Run::Plain => "plain".into(),
            Run::Velocity(friction) => {
                let defaults = BridgeSettings::default();
                let default = defaults.coupling == CouplingMode::VelocityConsistency
                    && defaults.velocity_friction == friction;
                let projection = match friction {
                    VelocityFriction::None => "frictionless",
                    VelocityFriction::OnChange => "friction on dv",
                    VelocityFriction::OnVelocity => "cone on v'",
                };
                let marker = if default { "default: " } else { "" };
                format!("{marker}velocity ({projection})+friction")
            }
            Run::Closed => {
                let default = BridgeSettings::default().coupling == CouplingMode::ClosedContacts;
                let marker = if default { "default: " } else { "" };
                format!("{marker}closed contacts+friction")
            }
            Run::ClosedEveryCall => "closed contacts, no resting calls".into(),
            Run::Allowed => "allowed+friction".into(),
            Run::Positions => "positions (seed)".into(),
            Run::Default => "bridge default".into(),
        }
    }

    fn colour(self) -> RGBColor {
        match self {
            Run::Plain => RGBColor(200, 60, 40),
            Run::Velocity(VelocityFriction::OnVelocity) => RGBColor(30, 110, 200),
            Run::Velocity(_) => RGBColor(150, 80, 190),
            Run::Closed => RGBColor(230, 150, 20),
            Run::ClosedEveryCall => RGBColor(120, 60, 0),
            Run::Allowed => RGBColor(40, 160, 60),
            Run::Positions => RGBColor(120, 120, 120),
            Run::Default => RGBColor(30, 110, 200),
        }
    }

    fn bridge(self) -> Option<RapierBridge> {
        let settings = match self {
            Run::Plain => return None,
            Run::Velocity(velocity_friction) => BridgeSettings {
                coupling: CouplingMode::VelocityConsistency,
                collider_friction: true,
                velocity_friction,
                ..BridgeSettings::default()
            },
            Run::Closed => BridgeSettings {
                coupling: CouplingMode::ClosedContacts,
                collider_friction: true,
                velocity_friction: VelocityFriction::None,
                ..BridgeSettings::default()
            },
            Run::ClosedEveryCall => BridgeSettings {
                coupling: CouplingMode::ClosedContacts,
                collider_friction: true,
                velocity_friction: VelocityFriction::None,
                resting_calls: false,
                ..BridgeSettings::default()
            },
            Run::Allowed => BridgeSettings {
                coupling: CouplingMode::RespectAllowedPenetration,
                collider_friction: true,
                ..BridgeSettings::default()
            },
            Run::Positions => BridgeSettings {
                coupling: CouplingMode::PositionsOnly,
                collider_friction: false,
                ..BridgeSettings::default()
            },
            Run::Default => BridgeSettings::default(),
        };
        let mut settings = settings;
        // `WITH_AND_WITHOUT_AL_MIN_ROWS=N`: `Auto` solves islands from N
        // rows with the augmented Lagrangian (measurements of issue 21).
        if let Some(rows) = std::env::var("WITH_AND_WITHOUT_AL_MIN_ROWS")
            .ok()
            .and_then(|v| v.parse().ok())
        {
            settings
                .stabilizer
                .solver
                .auto_augmented_lagrangian_min_rows = rows;
        }
        // `WITH_AND_WITHOUT_IP_MIN_ROWS=N`: `Auto` solves islands from N
        // rows with the interior point on the body-space matrix.
        if let Some(rows) = std::env::var("WITH_AND_WITHOUT_IP_MIN_ROWS")
            .ok()
            .and_then(|v| v.parse().ok())
        {
            settings.stabilizer.solver.auto_interior_point_min_rows = rows;
        }
        // `WITH_AND_WITHOUT_CLARABEL_GAP=G`: clarabel's gap and feasibility
        // tolerances (another valid answer of the same problems).
        if let Some(gap) = std::env::var("WITH_AND_WITHOUT_CLARABEL_GAP")
            .ok()
            .and_then(|v| v.parse().ok())
        {
            settings.stabilizer.solver.clarabel.tol_gap = gap;
            settings.stabilizer.solver.clarabel.tol_feas = gap;
        }
        // `WITH_AND_WITHOUT_TARGET_MARGIN=REL`: the stabilizer's
        // `target_margin_relative` (the bridge's default is
        // `BRIDGE_TARGET_MARGIN_RELATIVE`; measurements of issue 21).
        if let Some(rel) = std::env::var("WITH_AND_WITHOUT_TARGET_MARGIN")
            .ok()
            .and_then(|v| v.parse().ok())
        {
            settings.stabilizer.target_margin_relative = rel;
        }
        // `WITH_AND_WITHOUT_KEEP_PAIRS=1` (or `0`):
        // `Settings::keep_penetrated_pairs` on (off; measurements of issue 21).
        if let Ok(keep) = std::env::var("WITH_AND_WITHOUT_KEEP_PAIRS") {
            settings.stabilizer.keep_penetrated_pairs = keep != "0";
        }
        // `WITH_AND_WITHOUT_DAS=MAX,VIOLATED_MAX`: `Auto` takes the dual
        // active-set method up to these entries of `dq` (the bridge's
        // default keeps it off; measurements of issue 21).
        if let Some((max, violated)) = std::env::var("WITH_AND_WITHOUT_DAS")
            .ok()
            .and_then(|v| v.split_once(',').map(|(a, b)| (a.parse(), b.parse())))
            .and_then(|(a, b)| Some((a.ok()?, b.ok()?)))
        {
            settings.stabilizer.solver.auto_dual_active_set_max_dofs = max;
            settings
                .stabilizer
                .solver
                .auto_dual_active_set_violated_max_dofs = violated;
        }
        // `WITH_AND_WITHOUT_ZERO_HELD_VELOCITIES=1`: the bodies a held
        // cycle puts back get their velocities zeroed too.
        if std::env::var("WITH_AND_WITHOUT_ZERO_HELD_VELOCITIES").as_deref() == Ok("1") {
            settings.zero_held_velocities = true;
        }
        Some(RapierBridge::with_settings(settings).expect("valid settings"))
    }
}

/// One step of one run.
struct StepRecord {
    step: usize,
    depth: f64,
    /// The exact deepest penetration over the pairs with an awake dynamic
    /// body: what the call's tolerance covers.
    awake_depth: f64,
    /// The tolerance the call stated (its acceptance threshold, the
    /// allowed penetration included); infinite without a call.
    call_tolerance: f64,
    rapier_ms: f64,
    call_ms: f64,
    call_failed: bool,
    top_z: f64,
    drift: f64,
    /// Dynamic bodies asleep after the step and the call, of `dynamic`.
    asleep: usize,
    dynamic: usize,
    /// Bodies the call wrote (0 without a call).
    written: usize,
    /// The call's narrow-phase queries (`Report::pair_queries`; 0 without
    /// a stabilizer call).
    queries: usize,
    /// The call's narrow-phase time (`StageTimes::narrow_phase`), ms.
    narrow_ms: f64,
}

/// One bridge call after a step, timed.
struct Call {
    ms: f64,
    /// The stabilizer's status name (`error` when the call returned an
    /// error, `no_dynamic_body` when the stabilizer was not called).
    status: &'static str,
    /// Whether no penetration or joint error beyond the tolerance remains.
    resolved: bool,
    /// The tolerance the call stated; infinite without a stabilizer report.
    tolerance: f64,
    /// The call's bound on the f32 rounding of a written pose (0 on error).
    round_off_bound: f64,
    /// Bodies whose pose the call wrote.
    written: usize,
    /// Narrow-phase queries and time (ms) of the stabilizer's call.
    queries: usize,
    narrow_ms: f64,
}

/// `field` as one CSV field (RFC 4180): in double quotes, its own quotes
/// doubled, when it holds a comma, a quote or a line break (a run name
/// such as "closed contacts, no resting calls"); else as it is.
fn csv_field(field: &str) -> String {
    if field.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_string()
    }
}

/// One call of `bridge` on the world after its step, timed.
fn call(bridge: &mut RapierBridge, world: &mut PhysicsWorld) -> Call {
    let t = Instant::now();
    let result = bridge.stabilize_world(world);
    let ms = t.elapsed().as_secs_f64() * 1e3;
    match result {
        Ok(report) => {
            let (status, resolved) = report
                .stabilizer
                .as_ref()
                .map_or(("no_dynamic_body", true), |r| {
                    (r.status.name(), r.status.is_resolved())
                });
            let tolerance = report.stated_tolerance.unwrap_or(f64::INFINITY);
            let (queries, narrow_ms) = report
                .stabilizer
                .as_ref()
                .map_or((0, 0.0), |r| (r.pair_queries, r.times.narrow_phase * 1e3));
            Call {
                ms,
                status,
                resolved,
                tolerance,
                round_off_bound: report.round_off_bound,
                written: report.bodies_written,
                queries,
                narrow_ms,
            }
        }
        Err(_) => Call {
            ms,
            status: "error",
            resolved: false,
            tolerance: f64::INFINITY,
            round_off_bound: 0.0,
            written: 0,
            queries: 0,
            narrow_ms: 0.0,
        },
    }
}

/// Dynamic bodies asleep, and dynamic bodies.
fn sleeping(world: &PhysicsWorld) -> (usize, usize) {
    let dynamic = world.bodies.iter().filter(|(_, b)| b.is_dynamic());
    let (asleep, all) = dynamic.fold((0, 0), |(a, n), (_, b)| {
        (a + usize::from(b.is_sleeping()), n + 1)
    });
    (asleep, all)
}

/// One Rapier step, its time in ms.
fn timed_step(world: &mut PhysicsWorld) -> f64 {
    let t = Instant::now();
    world.step();
    t.elapsed().as_secs_f64() * 1e3
}

/// The exact deepest penetration of the world as Rapier holds it (f32
/// poses), by brute-force separating axes over every pair with a dynamic
/// body.
fn deepest(
    measure: &mut RapierBridge,
    world: &PhysicsWorld,
) -> Result<f64, Box<dyn std::error::Error>> {
    measure.sync(&world.bodies, &world.colliders)?;
    Ok(dev_support::sat::sat_deepest(measure.scene()).0)
}

/// The exact deepest penetration of the world, over every pair with a
/// dynamic body and over the pairs with an awake dynamic body.
fn deepest_and_awake(
    measure: &mut RapierBridge,
    world: &PhysicsWorld,
) -> Result<(f64, f64), Box<dyn std::error::Error>> {
    measure.sync(&world.bodies, &world.colliders)?;
    let scene = measure.scene();
    let map = measure.body_map();
    let awake = |i: usize| map.is_awake_dynamic(i, &world.bodies);
    let depths =
        dev_support::sat::pair_depths(scene, |a, b| dev_support::sat::sat_depth(scene, a, b));
    let all = depths.iter().fold(0.0, |m: f64, (_, d)| m.max(*d));
    let with_awake = depths
        .iter()
        .filter(|((a, b), _)| awake(*a) || awake(*b))
        .fold(0.0, |m: f64, (_, d)| m.max(*d));
    Ok((all, with_awake))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // RUST_LOG=constraint_stabilization=info: one line per call.
    let _ = env_logger::try_init();
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!(
            "with_and_without [--steps N] [--only NAME] [--scenes A,B,...] [--out DIR]\n\
             --steps N       steps per run (default {DEFAULT_STEPS})\n\
             --only NAME     the scenes whose name contains NAME\n\
             --scenes A,B    the scenes named, or named by the part before an underscore\n\
             --out DIR       where the md, csv and svg files go (default benchmarks/results)\n\
             --runs A,B      only the runs whose name contains one of A, B (default all)\n\
             scenes: {}",
            scenes()
                .iter()
                .map(|s| s.name)
                .chain(joint_scenes().iter().map(|s| s.name))
                .collect::<Vec<_>>()
                .join(", ")
        );
        return Ok(());
    }
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let steps = value("--steps").map_or(Ok(DEFAULT_STEPS), |s| s.parse())?;
    let selection = Selection {
        only: value("--only"),
        scenes: value("--scenes").map(|list| {
            list.split(',')
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .map(String::from)
                .collect()
        }),
    };
    let (contact_scenes, joint_scenes) = (scenes(), joint_scenes());
    let names: Vec<&str> = contact_scenes
        .iter()
        .map(|s| s.name)
        .chain(joint_scenes.iter().map(|s| s.name))
        .collect();
    let unknown = selection.unknown(&names);
    if !unknown.is_empty() {
        return Err(format!(
            "no scene named {}; the scenes: {}",
            unknown.join(", "),
            names.join(", ")
        )
        .into());
    }
    let out = PathBuf::from(value("--out").unwrap_or_else(|| "benchmarks/results".into()));
    std::fs::create_dir_all(&out)?;
    let mut csv = String::from(
        "scene,run,step,deepest_m,call_tolerance_m,rapier_ms,call_ms,call_failed,top_z_m,max_drift_m,queries,narrow_ms\n",
    );
    let mut table = String::new();
    for scene in contact_scenes.iter().filter(|s| selection.wants(s.name)) {
        if table.is_empty() {
            table += "| scene | run | deepest after step 1 (m) | deepest, median over steps (m) | deepest, max over the last 100 steps (m) | top: start -> end z (m) | max horizontal drift (mm) | failed calls | steps deeper than the call's tolerance | Rapier step ms (median) | call ms (median / max) | all asleep: first step / stays from | asleep at the end | bodies written while all asleep | call ms while all asleep / Rapier step ms while awake (medians) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        }
        let mut runs = Vec::new();
        let wanted_runs = value("--runs");
        let runs_wanted = Run::ALL.into_iter().filter(|run| {
            wanted_runs
                .as_deref()
                .is_none_or(|list| list.split(',').any(|part| run.name().contains(part)))
        });
        for run in runs_wanted {
            let records = simulate(scene, run, steps)?;
            for r in &records {
                let _ = writeln!(
                    csv,
                    "{},{},{},{:.6e},{:.6e},{:.4},{:.4},{},{:.6},{:.6e},{},{:.4}",
                    csv_field(scene.name),
                    csv_field(&run.name()),
                    r.step,
                    r.depth,
                    r.call_tolerance,
                    r.rapier_ms,
                    r.call_ms,
                    r.call_failed,
                    r.top_z,
                    r.drift,
                    r.queries,
                    r.narrow_ms
                );
            }
            let row = summary(scene.name, run, &records);
            eprintln!("{row}");
            table += &row;
            runs.push((run, records));
        }
        let series: Vec<Series> = runs
            .iter()
            .map(|(run, records)| Series::of(*run, records, |r| r.depth))
            .collect();
        plot(&out, scene.name, "deepest penetration", &series)?;
    }
    if !table.is_empty() {
        std::fs::write(out.join("with_and_without.csv"), csv)?;
    }
    let mut joint_csv = String::from(
        "scene,run,step,largest_joint_separation_m,chain_stretch,deepest_m,status,resolved,call_tolerance_m,round_off_bound_m,rapier_ms,call_ms\n",
    );
    let mut joint_table = String::new();
    for scene in joint_scenes.iter().filter(|s| selection.wants(s.name)) {
        if joint_table.is_empty() {
            joint_table += JOINT_TABLE_HEADER;
        }
        let mut series = Vec::new();
        for run in [Run::Plain, Run::Default] {
            let records = simulate_joints(scene, run, steps)?;
            for r in &records {
                let stretch = r.stretch.map_or(String::new(), |s| format!("{s:.6e}"));
                let (status, resolved, tolerance, round_off, call_ms) =
                    r.call
                        .as_ref()
                        .map_or(("", "", f64::INFINITY, 0.0, 0.0), |c| {
                            (
                                c.status,
                                if c.resolved { "true" } else { "false" },
                                c.tolerance,
                                c.round_off_bound,
                                c.ms,
                            )
                        });
                let _ = writeln!(
                    joint_csv,
                    "{},{},{},{:.6e},{stretch},{:.6e},{status},{resolved},{tolerance:.6e},{round_off:.6e},{:.4},{call_ms:.4}",
                    csv_field(scene.name),
                    csv_field(&run.name()),
                    r.step,
                    r.separation,
                    r.depth,
                    r.rapier_ms,
                );
            }
            let row = joint_summary(scene.name, run, &records);
            eprintln!("{row}");
            joint_table += &row;
            series.push(Series::of(run, &records, |r| r.separation));
        }
        plot(&out, scene.name, "largest joint separation", &series)?;
    }
    if !joint_table.is_empty() {
        std::fs::write(out.join("with_and_without_joints.csv"), joint_csv)?;
        if !table.is_empty() {
            table.push('\n');
        }
        table += &joint_table;
    }
    std::fs::write(out.join("with_and_without.md"), &table)?;
    println!("{table}");
    Ok(())
}

/// Runs `steps` steps of a fresh copy of the scene's world.
fn simulate(
    scene: &Scene,
    run: Run,
    steps: usize,
) -> Result<Vec<StepRecord>, Box<dyn std::error::Error>> {
    let (mut world, tracked) = (scene.build)();
    let mut bridge = run.bridge();
    let mut measure = RapierBridge::new(Settings::default())?;
    let mut start: Vec<Vector> = tracked
        .iter()
        .map(|&h| world.bodies[h].translation())
        .collect();
    let mut drift: f64 = 0.0;
    let mut records = Vec::with_capacity(steps);
    for step in 1..=steps {
        let rapier_ms = timed_step(&mut world);
        let (mut call_ms, mut call_failed) = (0.0, false);
        let (mut call_tolerance, mut written) = (f64::INFINITY, 0);
        let (mut queries, mut narrow_ms) = (0, 0.0);
        if let Some(bridge) = bridge.as_mut() {
            let call = call(bridge, &mut world);
            call_ms = call.ms;
            call_failed = !call.resolved;
            call_tolerance = call.tolerance;
            written = call.written;
            queries = call.queries;
            narrow_ms = call.narrow_ms;
        }
        let (asleep, dynamic) = sleeping(&world);
        let (depth, awake_depth) = deepest_and_awake(&mut measure, &world)?;
        if step == scene.drift_from {
            start = tracked
                .iter()
                .map(|&h| world.bodies[h].translation())
                .collect();
        }
        for (h, s) in tracked
            .iter()
            .zip(&start)
            .filter(|_| step > scene.drift_from)
        {
            let p = world.bodies[*h].translation();
            drift = drift.max(f64::from(
                ((p.x - s.x).powi(2) + (p.y - s.y).powi(2)).sqrt(),
            ));
        }
        let top_z = tracked
            .last()
            .map_or(0.0, |&h| f64::from(world.bodies[h].translation().z));
        records.push(StepRecord {
            step,
            depth,
            awake_depth,
            call_tolerance,
            rapier_ms,
            call_ms,
            call_failed,
            top_z,
            drift,
            asleep,
            dynamic,
            written,
            queries,
            narrow_ms,
        });
    }
    Ok(records)
}

/// One step of one run of a joint scene.
struct JointStepRecord {
    step: usize,
    /// The largest distance between a joint's two anchor points (m).
    separation: f64,
    /// A chain's summed anchor separations over its rest length.
    stretch: Option<f64>,
    /// The exact deepest penetration after the step and the call (m).
    depth: f64,
    rapier_ms: f64,
    /// The bridge call after the step (`None` for Rapier alone).
    call: Option<Call>,
}

/// Runs `steps` steps of a fresh copy of a joint scene's world.
fn simulate_joints(
    scene: &JointScene,
    run: Run,
    steps: usize,
) -> Result<Vec<JointStepRecord>, Box<dyn std::error::Error>> {
    let (mut world, chain) = (scene.build)();
    let mut bridge = run.bridge();
    let mut measure = RapierBridge::new(Settings::default())?;
    if run == Run::Plain {
        // The world as built: it must start without penetration.
        let masses: Vec<String> = world
            .bodies
            .iter()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(_, b)| format!("{:.3}", b.mass()))
            .collect();
        eprintln!(
            "{}: at step 0, deepest {:.3e} m, joint separation {:.3e} m, dynamic masses (kg) {}",
            scene.name,
            deepest(&mut measure, &world)?,
            joint_scenes::largest_joint_separation(&world),
            masses.join(" ")
        );
    }
    let mut records = Vec::with_capacity(steps);
    for step in 1..=steps {
        let rapier_ms = timed_step(&mut world);
        let call = bridge.as_mut().map(|bridge| call(bridge, &mut world));
        records.push(JointStepRecord {
            step,
            separation: joint_scenes::largest_joint_separation(&world),
            stretch: chain
                .as_ref()
                .map(|chain| joint_scenes::chain_stretch(&world, chain)),
            depth: deepest(&mut measure, &world)?,
            rapier_ms,
            call,
        });
    }
    Ok(records)
}

/// The joint table's header.
const JOINT_TABLE_HEADER: &str = "| scene | run | worst joint separation (m) | joint separation, last step (m) | worst chain stretch | worst depth (m) | unresolved calls (statuses) | steps with separation above the call's tolerance + 2 round-off | Rapier step ms (median) | call ms (median / max) | call in Rapier steps (median / worst) |\n|---|---|---|---|---|---|---|---|---|---|---|\n";

/// One row of the joint table.
fn joint_summary(scene: &str, run: Run, records: &[JointStepRecord]) -> String {
    let worst = |value: fn(&JointStepRecord) -> f64| records.iter().map(value).fold(0.0, f64::max);
    let separation = worst(|r| r.separation);
    let last = records.last().map_or(0.0, |r| r.separation);
    let stretch = if records.iter().any(|r| r.stretch.is_some()) {
        format!("{:.2e}", worst(|r| r.stretch.unwrap_or(0.0)))
    } else {
        "-".into()
    };
    let depth = worst(|r| r.depth);
    let calls: Vec<(&JointStepRecord, &Call)> = records
        .iter()
        .filter_map(|r| r.call.as_ref().map(|c| (r, c)))
        .collect();
    let rapier_ms = median(records.iter().map(|r| r.rapier_ms).collect());
    if calls.is_empty() {
        return format!(
            "| {scene} | {} | {separation:.2e} | {last:.2e} | {stretch} | {depth:.2e} | - | - | {rapier_ms:.3} | - | - |\n",
            run.name()
        );
    }
    let mut statuses: Vec<(&str, usize)> = Vec::new();
    for (_, c) in calls.iter().filter(|(_, c)| !c.resolved) {
        match statuses.iter_mut().find(|(s, _)| *s == c.status) {
            Some((_, n)) => *n += 1,
            None => statuses.push((c.status, 1)),
        }
    }
    let unresolved: usize = statuses.iter().map(|(_, n)| n).sum();
    let statuses = if statuses.is_empty() {
        String::new()
    } else {
        let list: Vec<String> = statuses.iter().map(|(s, n)| format!("{s} {n}")).collect();
        format!(" ({})", list.join(", "))
    };
    let beyond = calls
        .iter()
        .filter(|(r, c)| r.separation > c.tolerance + 2.0 * c.round_off_bound)
        .count();
    let call_ms: Vec<f64> = calls.iter().map(|(_, c)| c.ms).collect();
    let max_call = call_ms.iter().fold(0.0, |m: f64, &c| m.max(c));
    let ratios: Vec<f64> = calls
        .iter()
        .map(|(r, c)| c.ms / r.rapier_ms.max(f64::MIN_POSITIVE))
        .collect();
    let worst_ratio = ratios.iter().fold(0.0, |m: f64, &c| m.max(c));
    format!(
        "| {scene} | {} | {separation:.2e} | {last:.2e} | {stretch} | {depth:.2e} | {unresolved}{statuses} | {beyond} | {rapier_ms:.3} | {:.2} / {max_call:.1} | {:.1} / {worst_ratio:.0} |\n",
        run.name(),
        median(call_ms),
        median(ratios),
    )
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(0.0)
}

/// One row of the summary table.
fn summary(scene: &str, run: Run, records: &[StepRecord]) -> String {
    let depths: Vec<f64> = records.iter().map(|r| r.depth).collect();
    let tail = depths
        .iter()
        .rev()
        .take(100)
        .fold(0.0, |m: f64, &d| m.max(d));
    let first = records.first().map_or(0.0, |r| r.depth);
    let (start_z, end_z) = (
        records.first().map_or(0.0, |r| r.top_z),
        records.last().map_or(0.0, |r| r.top_z),
    );
    let calls: Vec<f64> = records.iter().map(|r| r.call_ms).collect();
    let max_call = calls.iter().fold(0.0, |m: f64, &c| m.max(c));
    let failed = records.iter().filter(|r| r.call_failed).count();
    let beyond = records
        .iter()
        .filter(|r| r.awake_depth > r.call_tolerance)
        .inspect(|r| {
            eprintln!(
                "{scene}, {}: step {}: exact depth {:.4e} over the call's tolerance {:.4e}",
                run.name(),
                r.step,
                r.awake_depth,
                r.call_tolerance
            )
        })
        .count();
    let drift = records.last().map_or(0.0, |r| r.drift);
    let sleep = Sleep::of(records);
    format!(
        "| {scene} | {} | {first:.2e} | {:.2e} | {tail:.2e} | {start_z:.4} -> {end_z:.4} | {:.2} | {failed} | {beyond} | {:.3} | {:.2} / {max_call:.1} | {} |\n",
        run.name(),
        median(depths),
        drift * 1e3,
        median(records.iter().map(|r| r.rapier_ms).collect()),
        median(calls),
        sleep.cells(),
    )
}

/// How a run falls asleep: the first step at which every dynamic body is
/// asleep, the step from which they all stay asleep, the bodies asleep at
/// the end, the bodies written from that step on, and the median call on
/// the sleeping scene against Rapier's median step while awake.
struct Sleep {
    first: Option<usize>,
    stays_from: Option<usize>,
    asleep_at_end: (usize, usize),
    written_asleep: usize,
    call_asleep_ms: Option<f64>,
    rapier_awake_ms: Option<f64>,
}

impl Sleep {
    fn of(records: &[StepRecord]) -> Sleep {
        let all_asleep = |r: &StepRecord| r.dynamic > 0 && r.asleep == r.dynamic;
        let first = records.iter().find(|r| all_asleep(r)).map(|r| r.step);
        let awake_tail = records.iter().rposition(|r| !all_asleep(r));
        let stays_from = match awake_tail {
            None => records.first().map(|r| r.step),
            Some(i) => records.get(i + 1).map(|r| r.step),
        };
        let asleep: Vec<&StepRecord> = records.iter().filter(|r| all_asleep(r)).collect();
        let awake: Vec<f64> = records
            .iter()
            .filter(|r| !all_asleep(r))
            .map(|r| r.rapier_ms)
            .collect();
        Sleep {
            first,
            stays_from,
            asleep_at_end: records.last().map_or((0, 0), |r| (r.asleep, r.dynamic)),
            written_asleep: asleep.iter().map(|r| r.written).sum(),
            call_asleep_ms: (!asleep.is_empty())
                .then(|| median(asleep.iter().map(|r| r.call_ms).collect())),
            rapier_awake_ms: (!awake.is_empty()).then(|| median(awake)),
        }
    }

    /// The table's cells: all asleep first / from; asleep at the end;
    /// written while asleep; call while asleep (ms) / Rapier awake (ms).
    fn cells(&self) -> String {
        let step = |s: Option<usize>| s.map_or("-".to_string(), |s| s.to_string());
        let ms = |m: Option<f64>| m.map_or("-".to_string(), |m| format!("{m:.4}"));
        format!(
            "{} / {} | {}/{} | {} | {} / {}",
            step(self.first),
            step(self.stays_from),
            self.asleep_at_end.0,
            self.asleep_at_end.1,
            self.written_asleep,
            ms(self.call_asleep_ms),
            ms(self.rapier_awake_ms),
        )
    }
}

/// One line of a plot: a value per step, from step 1.
struct Series {
    label: String,
    colour: RGBColor,
    values: Vec<f64>,
}

impl Series {
    /// A run's line: `value` of each of its records.
    fn of<R>(run: Run, records: &[R], value: impl Fn(&R) -> f64) -> Series {
        Series {
            label: run.name(),
            colour: run.colour(),
            values: records.iter().map(value).collect(),
        }
    }
}

/// A length (m) against time, log scale, one line per run (a value below
/// the floor drawn at the floor), as `DIR/with_and_without_SCENE.svg`.
fn plot(
    out: &std::path::Path,
    scene: &str,
    what: &str,
    series: &[Series],
) -> Result<(), Box<dyn std::error::Error>> {
    let path = out.join(format!("with_and_without_{scene}.svg"));
    let steps = series.iter().map(|s| s.values.len()).max().unwrap_or(1);
    let seconds = steps as f64 * scenes::STEP_SECONDS;
    let top = series
        .iter()
        .flat_map(|s| s.values.iter().copied())
        .fold(PLOT_FLOOR * 10.0, f64::max)
        * 2.0;
    let root = SVGBackend::new(&path, (800, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{scene}: {what} after each step"),
            ("sans-serif", 20),
        )
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..seconds, (PLOT_FLOOR..top).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc(format!("{what} (m)"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()?;
    for line in series {
        let colour = line.colour;
        chart
            .draw_series(LineSeries::new(
                line.values
                    .iter()
                    .enumerate()
                    .map(|(i, &v)| ((i + 1) as f64 * scenes::STEP_SECONDS, v.max(PLOT_FLOOR))),
                colour.stroke_width(2),
            ))?
            .label(line.label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
