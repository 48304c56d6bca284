//! The extra cost of the exact penetration depth (issue 8, "Measured"):
//! median time per penetrating query of
//!
//! 1. V-Clip alone (`VClip::query`, warm-started), whose penetrating
//!    outcome is the deepest-vertex seed;
//! 2. `contact::query`: V-Clip plus the exact-depth search, warm-started
//!    the same way;
//! 3. the search alone (`minimum_translation` from the seed of 1);
//! 4. parry3d-f64's `query::contact` (GJK/EPA) with prediction 0,
//!
//! timed in alternation in one run: in each round a family's queries go by
//! chunks of 16, the four methods in turn on each chunk (the order rotating),
//! so that load on a shared machine falls on all methods alike; per method,
//! the sum over chunks of each chunk's median time over the rounds (a
//! preemption spoils a chunk in few rounds), divided by the number of
//! queries.
//!
//! Families (all methods see the same precomputed penetrating poses):
//! - **coherence**: Mirtich's shapes (cube, icosahedron, disk, 642-vertex
//!   sphere) on the V-Clip coherence paths (`benchmarks/vclip.rs`, 1000
//!   poses, 0.5, 5 and 25 degrees per query) with the translation shrunk
//!   (the factor in the table, the first of 0.50, 0.55, ..., 1.00 at which
//!   at most half of the path penetrates) so that the bodies interpenetrate
//!   part of the time. Only
//!   the penetrating poses are timed; each keeps the warm start it had on
//!   the path (the final pair of the previous pose, penetrating or not).
//! - **box pairs**: engine-like boxes (half extents 3-9 cm) resting on one
//!   another with random tilts (1e-4 to 3e-2 rad, log-uniform) and yaws, the
//!   upper centre above the lower box's top face, sunk past touching by
//!   1e-7 to 1e-2 (log-uniform) of the smaller box's size (circumradius);
//!   the upper box often overhangs the lower one's top edges, so that edges
//!   cross.
//! - **mj01 pile**: every penetrating pair of the settled MuJoCo bin of 160
//!   boxes (`tests/data/engine/mj01_box_bin.json`, read with
//!   `constraint_stabilization::io`, pairs from the library's broad phase
//!   with margin 0).
//!
//! For the box pairs and the pile the warm start is V-Clip's final pair at
//! the same poses (a cache hit, as in the stabilizer's repeated queries of a
//! resting pair): V-Clip is then at its fastest, so the ratio
//! contact::query / V-Clip is the pessimistic one.
//!
//! Checks on the way (not timed): the depths against a brute-force
//! separating-axis depth (1e-9 relative) for shapes of at most 200
//! vertices, against parry's EPA (1e-6 relative) for the sphere; counted,
//! not asserted.
//! Also per family: the median number of candidate axes the search
//! evaluated (`Penetration::candidates`) and the share of edge–edge answers.
//!
//! Run: `cargo bench --bench contact_depth` (writes
//! `benchmarks/results/contact_depth.md`), or
//! `cargo bench --bench contact_depth -- --quick` for a smoke run (few
//! rounds and box pairs, prints only); `-- --only PREFIX` keeps the
//! families whose name starts with `PREFIX` (prints only: for instruction
//! counts of one family under callgrind).

#[path = "common/mod.rs"]
mod common;

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use constraint_stabilization::internals::broad_phase::candidate_pairs;
use constraint_stabilization::internals::contact::{self, BodyGeometry, PenetrationFeatures};
use constraint_stabilization::internals::geometry::{ConvexPolyhedron, isometry_to_parry};
use constraint_stabilization::internals::vclip::{DeepestVertex, FeaturePair, Outcome, VClip};
use constraint_stabilization::io::scene_file::read_scene;
use dev_support::sat::separating_axis_depth;
use dev_support::vclip::experiments::{CoherenceRun, mirtich_shapes};
use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::ConvexPolyhedron as ParryPolyhedron;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Poses per coherence path (as in `benchmarks/vclip.rs`).
const PATH_LENGTH: usize = 1000;
/// Degrees per query of the coherence paths.
const OMEGAS: [f64; 3] = [0.5, 5.0, 25.0];
/// Factors on the coherence path's translation, tried in turn from
/// `SHRINK_START` by `SHRINK_STEP` up to 1: the first at which at most half
/// of the path's poses penetrate is kept (the unshrunk path keeps the
/// bounding spheres apart).
const SHRINK_START: f64 = 0.5;
const SHRINK_STEP: f64 = 0.05;
/// Shapes with at most this many vertices are checked against the
/// brute-force depth, larger ones against parry's EPA.
const BRUTE_FORCE_MAX_VERTICES: usize = 200;
/// Engine-like box pairs (full run, quick run).
const BOX_PAIRS: [usize; 2] = [2000, 200];
/// Rounds of the interleaved measurement (full run, quick run).
const ROUNDS: [usize; 2] = [31, 5];
/// Queries per chunk of the interleaved timing.
const CHUNK: usize = 16;
/// Box half extents (m).
const HALF_EXTENT: std::ops::Range<f64> = 0.03..0.09;
/// Tilt of each box (rad), log-uniform.
const TILT: (f64, f64) = (1e-4, 3e-2);
/// Sink past touching, fraction of the smaller box's circumradius,
/// log-uniform.
const SINK: (f64, f64) = (1e-7, 1e-2);
/// Agreement of the exact depth with the brute force, relative to scale.
const BRUTE_FORCE_AGREEMENT: f64 = 1e-9;
/// Agreement with parry's EPA, relative to scale.
const PARRY_AGREEMENT: f64 = 1e-6;
/// The pile.
const PILE: &str = "tests/data/engine/mj01_box_bin.json";

const METHODS: [&str; 4] = ["V-Clip", "contact::query", "search only", "parry contact"];

/// One penetrating query: shapes (indices into the family's lists), poses,
/// the warm start every warm method gets, and V-Clip's seed with it.
struct Case {
    a: usize,
    b: usize,
    pose_a: Isometry3<f64>,
    pose_b: Isometry3<f64>,
    parry_a: Pose,
    parry_b: Pose,
    warm: Option<FeaturePair>,
    seed: DeepestVertex,
}

struct Family {
    name: String,
    shapes: Vec<Arc<ConvexPolyhedron>>,
    parry: Vec<ParryPolyhedron>,
    cases: Vec<Case>,
    /// Queries looked at to find the penetrating ones.
    tried: usize,
    /// Compare the depths with the brute force (small shapes) or parry.
    brute_force: bool,
}

impl Family {
    fn new(name: String, shapes: Vec<Arc<ConvexPolyhedron>>, brute_force: bool) -> Self {
        let parry = shapes
            .iter()
            .map(|s| s.to_parry().expect("a valid polyhedron converts"))
            .collect();
        Family {
            name,
            shapes,
            parry,
            cases: Vec::new(),
            tried: 0,
            brute_force,
        }
    }

    /// Queries V-Clip with `warm`; keeps the pose if penetrating. Returns
    /// the final pair (the next warm start).
    #[allow(clippy::too_many_arguments)]
    fn try_pose(
        &mut self,
        vclip: &VClip,
        a: usize,
        b: usize,
        pose_a: Isometry3<f64>,
        pose_b: Isometry3<f64>,
        warm: Option<FeaturePair>,
    ) -> FeaturePair {
        self.tried += 1;
        let result = vclip
            .query(&self.shapes[a], &pose_a, &self.shapes[b], &pose_b, warm)
            .expect("V-Clip answers");
        if let Outcome::Penetrating(seed) = result.outcome {
            self.cases.push(Case {
                a,
                b,
                pose_a,
                pose_b,
                parry_a: isometry_to_parry(&pose_a),
                parry_b: isometry_to_parry(&pose_b),
                warm,
                seed,
            });
        }
        result.final_pair
    }

    /// For families without a path: the warm start of every case becomes
    /// V-Clip's final pair at the same poses, and the seed the one found
    /// from there.
    fn warm_from_same_pose(&mut self, vclip: &VClip) {
        for case in &mut self.cases {
            let (a, b) = (&self.shapes[case.a], &self.shapes[case.b]);
            let cold = vclip
                .query(a, &case.pose_a, b, &case.pose_b, case.warm)
                .unwrap();
            let warm = vclip
                .query(a, &case.pose_a, b, &case.pose_b, Some(cold.final_pair))
                .unwrap();
            case.warm = Some(cold.final_pair);
            case.seed = match warm.outcome {
                Outcome::Penetrating(seed) => seed,
                Outcome::Separated { .. } => panic!("{}: warm query separated", self.name),
            };
        }
    }

    fn geometry(&self, case: &Case) -> (BodyGeometry<'_>, BodyGeometry<'_>) {
        let body = |index: usize, pose: Isometry3<f64>| {
            BodyGeometry::convex(&self.shapes[index], pose, None)
        };
        (body(case.a, case.pose_a), body(case.b, case.pose_b))
    }

    /// Seconds for the family's queries `cases` by method `method`.
    fn time(&self, vclip: &VClip, method: usize, cases: std::ops::Range<usize>) -> f64 {
        let clock = Instant::now();
        for case in black_box(&self.cases[cases]) {
            let (a, b) = (&self.shapes[case.a], &self.shapes[case.b]);
            match method {
                0 => {
                    black_box(
                        vclip
                            .query(a, &case.pose_a, b, &case.pose_b, case.warm)
                            .unwrap(),
                    );
                }
                1 => {
                    let (ga, gb) = self.geometry(case);
                    black_box(contact::query(vclip, &ga, &gb, case.warm).unwrap());
                }
                2 => {
                    black_box(contact::minimum_translation(
                        a,
                        &case.pose_a,
                        b,
                        &case.pose_b,
                        &case.seed,
                    ));
                }
                _ => {
                    black_box(
                        query::contact(
                            &case.parry_a,
                            &self.parry[case.a],
                            &case.parry_b,
                            &self.parry[case.b],
                            0.0,
                        )
                        .unwrap(),
                    );
                }
            }
        }
        clock.elapsed().as_secs_f64()
    }
}

/// What the search found on a family (untimed).
#[derive(Default)]
struct Stats {
    median_candidates: f64,
    edge_edge: usize,
    checked_against: &'static str,
    disagreements: usize,
    largest_relative_error: f64,
}

fn stats(family: &Family, vclip: &VClip) -> Stats {
    let mut candidates = Vec::with_capacity(family.cases.len());
    let mut stats = Stats {
        checked_against: if family.brute_force {
            "brute force"
        } else {
            "parry EPA"
        },
        ..Stats::default()
    };
    for case in &family.cases {
        let (ga, gb) = family.geometry(case);
        let result = contact::query(vclip, &ga, &gb, case.warm).unwrap();
        let penetration = result.penetration.expect("penetrating");
        candidates.push(penetration.candidates as f64);
        stats.edge_edge +=
            matches!(penetration.features(), PenetrationFeatures::EdgeEdge { .. }) as usize;
        let (a, b) = (&family.shapes[case.a], &family.shapes[case.b]);
        let scale = a.scale().min(b.scale());
        let (reference, tolerance) = if family.brute_force {
            let depths = separating_axis_depth(a, &case.pose_a, b, &case.pose_b);
            (depths.all, BRUTE_FORCE_AGREEMENT)
        } else {
            let depth = query::contact(
                &case.parry_a,
                &family.parry[case.a],
                &case.parry_b,
                &family.parry[case.b],
                0.0,
            )
            .unwrap()
            .map_or(0.0, |c| (-c.dist).max(0.0));
            (depth, PARRY_AGREEMENT)
        };
        let error = (penetration.depth() - reference).abs() / scale;
        stats.largest_relative_error = stats.largest_relative_error.max(error);
        stats.disagreements += (error > tolerance) as usize;
    }
    stats.median_candidates = common::median(&candidates);
    stats
}

fn coherence_families(vclip: &VClip) -> Vec<Family> {
    let mut families = Vec::new();
    for (name, shape) in mirtich_shapes() {
        let shape = Arc::new(shape);
        let brute_force = shape.vertices().len() <= BRUTE_FORCE_MAX_VERTICES;
        for omega in OMEGAS {
            let mut rng = ChaCha8Rng::seed_from_u64(11);
            let run = CoherenceRun::new(&mut rng, shape.scale(), omega);
            let path = |shrink: f64| {
                let mut family = Family::new(
                    format!("{name} {omega} deg (x{shrink:.2})"),
                    vec![shape.clone()],
                    brute_force,
                );
                let mut warm = None;
                for i in 1..=PATH_LENGTH {
                    let mut pose = run.pose(i);
                    pose.translation.vector *= shrink;
                    warm = Some(family.try_pose(vclip, 0, 0, Isometry3::identity(), pose, warm));
                }
                family
            };
            let family = (0..)
                .map(|k| SHRINK_START + SHRINK_STEP * k as f64)
                .take_while(|shrink| *shrink <= 1.0 + 1e-9)
                .map(path)
                .find(|family| 2 * family.cases.len() <= family.tried)
                .unwrap_or_else(|| path(1.0));
            families.push(family);
        }
    }
    families
}

fn log_uniform(rng: &mut impl Rng, (lo, hi): (f64, f64)) -> f64 {
    (rng.random_range(lo.ln()..hi.ln())).exp()
}

/// A box's orientation: a yaw about the vertical, then a tilt about a
/// random horizontal axis.
fn tilted(rng: &mut impl Rng) -> UnitQuaternion<f64> {
    let yaw = UnitQuaternion::from_axis_angle(
        &Vector3::z_axis(),
        rng.random_range(0.0..std::f64::consts::TAU),
    );
    let heading = rng.random_range(0.0..std::f64::consts::TAU);
    let axis = Unit::new_normalize(Vector3::new(heading.cos(), heading.sin(), 0.0));
    UnitQuaternion::from_axis_angle(&axis, log_uniform(rng, TILT)) * yaw
}

fn box_pairs(vclip: &VClip, count: usize) -> Family {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let mut family = Family::new("box pairs".into(), Vec::new(), true);
    while family.cases.len() < count {
        let mut half = || Vector3::from_fn(|_, _| rng.random_range(HALF_EXTENT));
        let (half_upper, half_lower) = (half(), half());
        let cuboid = |half| Arc::new(ConvexPolyhedron::cuboid(half).expect("a valid box"));
        let (upper, lower) = (cuboid(half_upper), cuboid(half_lower));
        let pose_b = Isometry3::from_parts(
            Translation3::from(Vector3::from_fn(|_, _| rng.random_range(-0.5..0.5))),
            tilted(&mut rng),
        );
        let rotation_a = tilted(&mut rng);
        // The upper centre above the lower box's top face (body frame).
        let offset = Vector3::new(
            rng.random_range(-0.9..0.9) * half_lower.x,
            rng.random_range(-0.9..0.9) * half_lower.y,
            0.0,
        );
        let up = pose_b.rotation * Vector3::z();
        let at = |height: f64| {
            Isometry3::from_parts(
                Translation3::from((pose_b * Point3::from(offset)).coords + up * height),
                rotation_a,
            )
        };
        let penetrates = |height: f64| {
            matches!(
                vclip
                    .query(&upper, &at(height), &lower, &pose_b, None)
                    .unwrap()
                    .outcome,
                Outcome::Penetrating(_)
            )
        };
        // Touching height by bisection: centre inside (penetrating) to
        // clear of the lower box (separated).
        let (mut lo, mut hi) = (0.0, half_lower.z + upper.scale() * 1.01);
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if penetrates(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let size = upper.scale().min(lower.scale());
        let height = hi - log_uniform(&mut rng, SINK) * size;
        let index = family.shapes.len();
        family.shapes.push(upper);
        family.shapes.push(lower);
        family
            .parry
            .extend(family.shapes[index..].iter().map(|s| s.to_parry().unwrap()));
        family.try_pose(vclip, index, index + 1, at(height), pose_b, None);
    }
    family.warm_from_same_pose(vclip);
    family
}

fn pile(vclip: &VClip) -> Family {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(PILE);
    let scene = read_scene(&path).expect("the pile reads");
    let shapes: Vec<Arc<ConvexPolyhedron>> = scene
        .bodies()
        .iter()
        .map(|body| body.polyhedron().expect("a convex body").clone())
        .collect();
    let mut family = Family::new("mj01 pile".into(), shapes, true);
    for pair in candidate_pairs(&scene, 0.0).expect("broad phase") {
        let pose = |index: usize| *scene.bodies()[index].com_pose();
        family.try_pose(
            vclip,
            pair.body_a,
            pair.body_b,
            pose(pair.body_a),
            pose(pair.body_b),
            None,
        );
    }
    family.warm_from_same_pose(vclip);
    family
}

fn format_ns(ns: f64) -> String {
    if ns >= 10_000.0 {
        format!("{:.1} µs", ns / 1000.0)
    } else if ns >= 1000.0 {
        format!("{:.2} µs", ns / 1000.0)
    } else {
        format!("{ns:.0} ns")
    }
}

fn shell(command: &str, args: &[&str]) -> String {
    std::process::Command::new(command)
        .args(args)
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map_or_else(|| "?".into(), |s| s.trim().to_string())
}

fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg").map_or_else(|_| "?".into(), |s| s.trim().into())
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let which = quick as usize;
    let rounds = ROUNDS[which];
    let date = shell("date", &["-u", "+%Y-%m-%d %H:%M:%S UTC"]);
    let load_before = loadavg();
    let start = Instant::now();
    let vclip = VClip::default();

    let args: Vec<String> = std::env::args().collect();
    let only = args
        .windows(2)
        .find(|w| w[0] == "--only")
        .map(|w| w[1].clone());
    let mut families = coherence_families(&vclip);
    families.push(box_pairs(&vclip, BOX_PAIRS[which]));
    families.push(pile(&vclip));
    if let Some(prefix) = &only {
        families.retain(|family| family.name.starts_with(prefix.as_str()));
    }
    let setup_seconds = start.elapsed().as_secs_f64();

    // One warm-up round, then `rounds` rounds. In each round a family's
    // queries go by chunks of `CHUNK`, the four methods in turn on each
    // chunk (the order rotating from chunk to chunk and round to round).
    // A chunk takes microseconds: a preemption by the machine's other jobs
    // (milliseconds) spoils it in few rounds, and the median over rounds of
    // each chunk's time drops it. A method's time is the sum over chunks of
    // those medians.
    let mut times: Vec<[Vec<Vec<f64>>; 4]> = families
        .iter()
        .map(|family| {
            let chunks = family.cases.len().div_ceil(CHUNK);
            [(); 4].map(|_| vec![Vec::with_capacity(rounds); chunks])
        })
        .collect();
    for round in 0..=rounds {
        for (family, family_times) in families.iter().zip(&mut times) {
            let n = family.cases.len();
            for (c, begin) in (0..n).step_by(CHUNK).enumerate() {
                let chunk = begin..(begin + CHUNK).min(n);
                for k in 0..4 {
                    let method = (round + c + k) % 4;
                    let seconds = family.time(&vclip, method, chunk.clone());
                    if round > 0 {
                        family_times[method][c].push(seconds);
                    }
                }
            }
        }
    }
    let timing_seconds = start.elapsed().as_secs_f64() - setup_seconds;

    let mut table = String::from(
        "| shape / family | penetrating queries | V-Clip | contact::query | search only | parry contact \
         | contact::query / V-Clip | contact::query / parry | median candidates | edge-edge | depth check |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (family, family_times) in families.iter().zip(&times) {
        let n = family.cases.len().max(1) as f64;
        let ns: Vec<f64> = family_times
            .iter()
            .map(|chunks| chunks.iter().map(|t| common::median(t)).sum::<f64>() * 1e9 / n)
            .collect();
        let stats = stats(family, &vclip);
        table += &format!(
            "| {} | {} of {} | {} | {} | {} | {} | {:.2}x | {:.2}x | {} | {} | {} off {} (max {:.1e}) |\n",
            family.name,
            family.cases.len(),
            family.tried,
            format_ns(ns[0]),
            format_ns(ns[1]),
            format_ns(ns[2]),
            format_ns(ns[3]),
            ns[1] / ns[0],
            ns[1] / ns[3],
            stats.median_candidates,
            stats.edge_edge,
            stats.disagreements,
            stats.checked_against,
            stats.largest_relative_error,
        );
    }
    let load_after = loadavg();
    let command = if quick {
        "cargo bench --bench contact_depth -- --quick"
    } else {
        "cargo bench --bench contact_depth"
    };
    let host = format!(
        "{} ({} cores visible)",
        shell("uname", &["-m"]),
        std::thread::available_parallelism().map_or(0, |n| n.get())
    );
    let report = format!(
        "# Extra cost of the exact penetration depth\n\n\
         Produced by `benchmarks/contact_depth.rs` (see its module doc for the families \
         and the warm starts).\n\n\
         - Command: `{command}`\n\
         - Date: {date}\n\
         - Machine: {host}, shared\n\
         - /proc/loadavg before: `{load_before}`, after: `{load_after}`\n\
         - Rounds: {rounds} (after one warm-up round); in each round a family's queries go \
         by chunks of {CHUNK}, the four methods in turn on each chunk (order rotating); \
         per method, the sum over chunks of the chunk's median time over rounds, / queries\n\
         - Setup {setup_seconds:.1} s, timing {timing_seconds:.1} s\n\
         - Methods: {methods}\n\n\
         Median ns per penetrating query:\n\n{table}\n\
         Columns: *penetrating queries* `n of m`: the poses timed among those generated; \
         *search only* = `minimum_translation` from V-Clip's seed; *median candidates* = \
         `Penetration::candidates` (axes evaluated); *edge-edge* = answers whose features are \
         an edge pair; *depth check*: `contact::query`'s depth against the brute-force \
         separating-axis depth (tolerance {BRUTE_FORCE_AGREEMENT:e} of the scale) or \
         parry's EPA depth ({PARRY_AGREEMENT:e}), the count beyond tolerance and the largest \
         difference relative to the scale.\n",
        methods = METHODS.join(", "),
    );
    println!("{report}");
    if !quick && only.is_none() {
        let path = common::results_dir().join("contact_depth.md");
        std::fs::write(&path, &report).expect("write the result file");
        println!("written to {}", path.display());
    }
}
