//! Mirtich's experiments as a benchmark (V-Clip, 1998, section 6).
//!
//! 1. Degeneracy (Algorithm 10): `VCLIP_DEGENERACY_TRIALS` (default
//!    100,000) trials of two cubes with nearly parallel faces and edges,
//!    binary-searching for where the closest features change; every query
//!    is checked against a brute-force distance and parry's intersection
//!    test. Prints the counts of cycles (exhaustive fallbacks), resolved
//!    rounding ties and wrong answers.
//! 2. Coherence (Algorithm 9): body 1 fixed, body 2 of the same shape moving
//!    sinusoidally and rotating 0.5, 5 and 25 degrees per query, for the
//!    cube, icosahedron, disk (60-gon, 10:1) and 642-vertex sphere. Side by
//!    side: V-Clip warm (cached feature pair), V-Clip cold, parry3d-f64
//!    `distance`, parry3d-f64 `contact`. One criterion iteration is a whole
//!    path of `PATH_LENGTH` queries; the table divides by it. Accuracy of
//!    the warm queries against parry's distance is counted on the way.
//!
//! Run: `cargo bench --bench vclip`. Result files (with the command, the
//! date, the commit and the load average):
//! - `benchmarks/results/vclip_degeneracy.md`: the degeneracy counts;
//! - `benchmarks/results/vclip.md`: the coherence table of the four methods
//!   timed in alternation (`VCLIP_ROUNDS` rounds, default 31), median time
//!   per query, and the accuracy of the warm queries against parry.
//!
//! criterion's own table (separate runs, minutes apart: on a shared machine
//! its ratios are less reliable) is written to
//! `target/criterion/vclip_table.md`. `VCLIP_SKIP_CRITERION=1` skips
//! criterion; `VCLIP_DEGENERACY_TRIALS=0` skips the degeneracy experiment
//! (and leaves its result file as it is).

mod common;

use std::hint::black_box;
use std::time::Duration;

use common::{Provenance, bench_command, results_dir};
use constraint_stabilization::internals::geometry::ConvexPolyhedron;
use constraint_stabilization::internals::vclip::{FeaturePair, VClip, vclip};
use criterion::Criterion;
use dev_support::vclip::experiments::{CoherenceRun, degeneracy_experiment, mirtich_shapes};
use dev_support::vclip::{parry_distance, parry_pose, parry_shape, separated_distance};
use nalgebra::Isometry3;
use parry3d_f64::query;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Queries per coherence path (Mirtich: 1000 per run).
const PATH_LENGTH: usize = 1000;

/// Degrees per query of the coherence experiment.
const OMEGAS: [f64; 3] = [0.5, 5.0, 25.0];

/// Agreement of distances with the oracle, relative to the shape scale.
const AGREEMENT: f64 = 1e-9;

/// parry's intersection test is fuzzy within about 5e-8 of touching.
const PARRY_FUZZ: f64 = 1e-7;

const METHODS: [&str; 4] = [
    "vclip_warm",
    "vclip_cold",
    "parry_distance",
    "parry_contact",
];

/// Rounds of the interleaved measurement (`VCLIP_ROUNDS` overrides).
const ROUNDS: usize = 31;

/// Seed of the degeneracy experiment.
const DEGENERACY_SEED: u64 = 10;

/// Halvings of the binary search of a degeneracy trial.
const DEGENERACY_DEPTH: usize = 30;

/// Seed of the coherence paths.
const PATH_SEED: u64 = 11;

/// Environment variables that change what the benchmark does.
const ENV_VARS: [&str; 3] = [
    "VCLIP_DEGENERACY_TRIALS",
    "VCLIP_ROUNDS",
    "VCLIP_SKIP_CRITERION",
];

fn env_usize(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn main() {
    degeneracy();
    if std::env::var("VCLIP_SKIP_CRITERION").is_err() {
        let mut criterion = Criterion::default()
            .sample_size(20)
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_secs(2))
            .configure_from_args();
        coherence(&mut criterion);
        criterion.final_summary();
        print_table();
    }
    interleaved_table();
}

/// Queries per timed chunk of a path in the interleaved table.
const CHUNK: usize = 50;

/// The four methods timed in alternation, one whole path each per round,
/// `ROUNDS` rounds. On a shared, loaded machine the load then weighs on all
/// four alike, which keeps the ratios meaningful where criterion's separate
/// runs (minutes apart) do not. Each path is timed in chunks of `CHUNK`
/// queries: the time per query is the sum over chunks of the median chunk
/// time, divided by the path length. A path that takes milliseconds is
/// often preempted on a loaded machine, a path of 0.3 ms rarely: whole-path
/// medians penalize the slow methods, short chunks much less. The
/// whole-path medians (sum of a round's chunks) are given too.
fn interleaved_table() {
    let provenance = Provenance::start(bench_command("vclip", &ENV_VARS));
    let rounds = env_usize("VCLIP_ROUNDS", ROUNDS).max(1);
    let mut accuracy = String::new();
    let fixed = Isometry3::identity();
    let fixed_parry = parry_pose(&fixed);
    let mut table = String::from(
        "| shape | deg/query | V-Clip warm | V-Clip cold | parry distance | parry contact | distance / warm | contact / warm |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    let mut whole = String::from(
        "| shape | deg/query | V-Clip warm | V-Clip cold | parry distance | parry contact | distance / warm | contact / warm |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    let chunks = PATH_LENGTH.div_ceil(CHUNK);
    for (name, shape) in mirtich_shapes() {
        let parry = parry_shape(&shape);
        for omega in OMEGAS {
            let poses = path(&shape, omega, PATH_SEED);
            let parry_poses: Vec<_> = poses.iter().map(parry_pose).collect();
            accuracy += &count_disagreements(name, omega, &shape, &parry, &poses);
            accuracy.push('\n');
            // times[method][chunk][round]
            let mut times = [(); 4].map(|_| vec![Vec::with_capacity(rounds); chunks]);
            for _ in 0..rounds {
                let mut warm: Option<FeaturePair> = None;
                timed_path(&mut times[0], |i| {
                    let result = vclip(&shape, &fixed, &shape, &poses[i], warm).unwrap();
                    warm = Some(black_box(result).final_pair);
                });
                timed_path(&mut times[1], |i| {
                    black_box(vclip(&shape, &fixed, &shape, &poses[i], None).unwrap());
                });
                timed_path(&mut times[2], |i| {
                    let pose = &parry_poses[i];
                    black_box(query::distance(&fixed_parry, &parry, pose, &parry).unwrap());
                });
                timed_path(&mut times[3], |i| {
                    let pose = &parry_poses[i];
                    black_box(query::contact(&fixed_parry, &parry, pose, &parry, 0.0).unwrap());
                });
            }
            let per_query = |s: f64| s * 1e9 / PATH_LENGTH as f64;
            let chunked: Vec<f64> = times
                .iter()
                .map(|m| per_query(m.iter().map(|c| common::median(c)).sum()))
                .collect();
            let paths: Vec<f64> = times
                .iter()
                .map(|m| {
                    let sums: Vec<f64> =
                        (0..rounds).map(|r| m.iter().map(|c| c[r]).sum()).collect();
                    per_query(common::median(&sums))
                })
                .collect();
            table += &table_row(name, omega, &chunked);
            whole += &table_row(name, omega, &paths);
        }
    }
    println!(
        "\nInterleaved, median time per query ({rounds} rounds, chunks of {CHUNK}):\n\n{table}"
    );
    println!("Whole-path medians:\n\n{whole}");
    let md = format!(
        "# V-Clip coherence (Mirtich 1998, Algorithm 9)\n\n{}\n\
         Body 1 fixed at the origin, body 2 of the same shape moving \
         sinusoidally and rotating 0.5, 5 or 25 degrees per query (path seed \
         {PATH_SEED}), {PATH_LENGTH} queries per path. The four methods are \
         timed in alternation, one whole path each per round, {rounds} rounds. \
         Each path is timed in chunks of {CHUNK} queries; the table gives the \
         time per query (sum over chunks of the median chunk time, divided by \
         the path length) and the ratios. On this loaded machine a path of \
         several milliseconds is often preempted and one of 0.3 ms rarely, so \
         whole-path medians (second table) penalize the slow methods; the \
         chunked times are the ones to quote. V-Clip warm starts each query from the previous query's \
         final feature pair; cold starts from none. `parry contact` is \
         parry3d-f64 `query::contact` with prediction 0, which stops as soon \
         as it knows the bodies are apart and computes no distance.\n\n\
         {table}\n\
         Whole-path medians (median over rounds of each path's total time, \
         divided by the path length), same runs:\n\n{whole}\n\
         Accuracy of the warm V-Clip queries of the same paths against \
         parry3d-f64's distance (a disagreement is a difference above \
         {AGREEMENT:e} times the shape's scale):\n\n{accuracy}",
        provenance.markdown()
    );
    let file = results_dir().join("vclip.md");
    std::fs::write(&file, md).expect("write vclip.md");
    println!("written to {}", file.display());
}

/// Runs `query(i)` for i in 0..PATH_LENGTH in order, timing chunks of
/// `CHUNK` queries: chunk `c`'s time is pushed onto `chunk_times[c]`.
fn timed_path(chunk_times: &mut [Vec<f64>], mut query: impl FnMut(usize)) {
    for (c, times) in chunk_times.iter_mut().enumerate() {
        let clock = std::time::Instant::now();
        for i in c * CHUNK..((c + 1) * CHUNK).min(PATH_LENGTH) {
            query(i);
        }
        times.push(clock.elapsed().as_secs_f64());
    }
}

/// One row of the coherence table from the four times per query (ns).
fn table_row(name: &str, omega: f64, ns: &[f64]) -> String {
    format!(
        "| {name} | {omega} | {} | {} | {} | {} | {:.1}x | {:.1}x |\n",
        format_ns(ns[0]),
        format_ns(ns[1]),
        format_ns(ns[2]),
        format_ns(ns[3]),
        ns[2] / ns[0],
        ns[3] / ns[0],
    )
}

/// Mirtich's Algorithm 10 (see the module doc); writes
/// `benchmarks/results/vclip_degeneracy.md` unless there are no trials.
fn degeneracy() {
    let trials = env_usize("VCLIP_DEGENERACY_TRIALS", 100_000);
    if trials == 0 {
        return;
    }
    let provenance = Provenance::start(bench_command("vclip", &ENV_VARS));
    let mut rng = ChaCha8Rng::seed_from_u64(DEGENERACY_SEED);
    let start = std::time::Instant::now();
    let counts = degeneracy_experiment(
        &mut rng,
        &VClip::default(),
        trials,
        DEGENERACY_DEPTH,
        AGREEMENT,
        PARRY_FUZZ,
    );
    let seconds = start.elapsed().as_secs_f64();
    println!("degeneracy: {counts:?} in {seconds:.1} s (oracle checks included)");
    let md = format!(
        "# V-Clip degeneracy test (Mirtich 1998, Algorithm 10)\n\n{}\n\
         Two cubes (half extent 1) with nearly parallel faces and edges \
         (`dev-support/src/vclip/experiments.rs`, `degeneracy_experiment`): \
         each trial queries a touching and a separated pose of the second \
         cube and, when their closest features differ, binary-searches \
         ({DEGENERACY_DEPTH} halvings) for where they change; every query is \
         warm-started from the previous one (`VClip::default()`, RNG seed \
         {DEGENERACY_SEED}). Each query is checked against a brute-force \
         distance and parry3d-f64's intersection test (tolerance {AGREEMENT:e} \
         times the scale; parry's intersection test is trusted outside \
         {PARRY_FUZZ:e} of touching). Run time {seconds:.1} s, oracle checks \
         included.\n\n\
         | count | value |\n|---|---:|\n\
         | trials | {} |\n\
         | trials with a boundary search (end features differ) | {} |\n\
         | queries | {} |\n\
         | exhaustive fallbacks (unresolved cycle or iteration cap) | {} |\n\
         | wrong answers | {} |\n\
         | walks that revisited a state, resolved (rounding ties) | {} |\n\
         | separated queries where parry's GJK distance is off the brute-force distance by more than {AGREEMENT:e} (oracle noise, not counted as wrong) | {} |\n",
        provenance.markdown(),
        counts.trials,
        counts.boundary_searches,
        counts.queries,
        counts.cycles,
        counts.wrong,
        counts.resolved_ties,
        counts.parry_off,
    );
    let file = results_dir().join("vclip_degeneracy.md");
    std::fs::write(&file, md).expect("write vclip_degeneracy.md");
    println!("written to {}", file.display());
}

/// One coherence path: poses of body 2, body 1 at the origin.
fn path(shape: &ConvexPolyhedron, omega: f64, seed: u64) -> Vec<Isometry3<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let run = CoherenceRun::new(&mut rng, shape.scale(), omega);
    (1..=PATH_LENGTH).map(|i| run.pose(i)).collect()
}

fn coherence(criterion: &mut Criterion) {
    let fixed = Isometry3::identity();
    let fixed_parry = parry_pose(&fixed);
    for (name, shape) in mirtich_shapes() {
        let parry = parry_shape(&shape);
        for omega in OMEGAS {
            let poses = path(&shape, omega, PATH_SEED);
            let parry_poses: Vec<_> = poses.iter().map(parry_pose).collect();
            let mut group = criterion.benchmark_group(format!("vclip_{name}_{omega}deg"));
            group.bench_function(METHODS[0], |b| {
                b.iter(|| {
                    let mut warm: Option<FeaturePair> = None;
                    for pose in &poses {
                        let result = vclip(&shape, &fixed, &shape, pose, warm).unwrap();
                        warm = Some(black_box(result).final_pair);
                    }
                })
            });
            group.bench_function(METHODS[1], |b| {
                b.iter(|| {
                    for pose in &poses {
                        black_box(vclip(&shape, &fixed, &shape, pose, None).unwrap());
                    }
                })
            });
            group.bench_function(METHODS[2], |b| {
                b.iter(|| {
                    for pose in &parry_poses {
                        black_box(query::distance(&fixed_parry, &parry, pose, &parry).unwrap());
                    }
                })
            });
            group.bench_function(METHODS[3], |b| {
                b.iter(|| {
                    for pose in &parry_poses {
                        black_box(query::contact(&fixed_parry, &parry, pose, &parry, 0.0).unwrap());
                    }
                })
            });
            group.finish();
        }
    }
}

/// Counts warm queries whose distance differs from parry's by more than
/// `AGREEMENT * scale`, fallbacks and resolved ties: one Markdown list item.
fn count_disagreements(
    name: &str,
    omega: f64,
    shape: &ConvexPolyhedron,
    parry: &parry3d_f64::shape::ConvexPolyhedron,
    poses: &[Isometry3<f64>],
) -> String {
    let fixed = Isometry3::identity();
    let (mut warm, mut off, mut fell_back, mut ties, mut iterations) = (None, 0, 0, 0, 0);
    for pose in poses {
        let result = vclip(shape, &fixed, shape, pose, warm).unwrap();
        warm = Some(result.final_pair);
        let d_parry = parry_distance(parry, &fixed, parry, pose);
        let d = separated_distance(&result).unwrap_or(0.0);
        off += ((d - d_parry).abs() > AGREEMENT * shape.scale()) as usize;
        fell_back += result.fell_back() as usize;
        ties += result.resolved_cycle as usize;
        iterations += result.iterations;
    }
    let line = format!(
        "- {name} {omega} deg/query: {} queries, {off} off parry by > {AGREEMENT:e}, \
         {fell_back} fallbacks, {ties} resolved ties, {:.2} iterations per warm query",
        poses.len(),
        iterations as f64 / poses.len() as f64
    );
    println!("coherence {line}");
    line
}

/// Reads criterion's median estimates and prints the Markdown table.
fn print_table() {
    let mut table = String::from(
        "| shape | deg/query | V-Clip warm | V-Clip cold | parry distance | parry contact | distance / warm | contact / warm |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    for (name, _) in mirtich_shapes() {
        for omega in OMEGAS {
            let medians: Vec<Option<f64>> = METHODS
                .iter()
                .map(|m| median_ns(&format!("vclip_{name}_{omega}deg"), m))
                .collect();
            let per_query = |m: Option<f64>| m.map(|ns| ns / PATH_LENGTH as f64);
            let cell = |m: Option<f64>| per_query(m).map_or("-".into(), format_ns);
            let ratio = |m: Option<f64>| match (per_query(m), per_query(medians[0])) {
                (Some(x), Some(w)) => format!("{:.1}x", x / w),
                _ => "-".into(),
            };
            table += &format!(
                "| {name} | {omega} | {} | {} | {} | {} | {} | {} |\n",
                cell(medians[0]),
                cell(medians[1]),
                cell(medians[2]),
                cell(medians[3]),
                ratio(medians[2]),
                ratio(medians[3]),
            );
        }
    }
    println!("\nMedian time per query:\n\n{table}");
    let _ = std::fs::write("target/criterion/vclip_table.md", &table);
}

fn format_ns(ns: f64) -> String {
    if ns >= 1000.0 {
        format!("{:.2} µs", ns / 1000.0)
    } else {
        format!("{ns:.0} ns")
    }
}

/// Median of a benchmark in ns, from criterion's `estimates.json`.
fn median_ns(group: &str, function: &str) -> Option<f64> {
    let path = format!("target/criterion/{group}/{function}/new/estimates.json");
    let text = std::fs::read_to_string(path).ok()?;
    let start = text.find("\"median\"")?;
    let rest = &text[start..];
    let key = "\"point_estimate\":";
    let at = rest.find(key)? + key.len();
    let end = rest[at..].find([',', '}'])? + at;
    rest[at..end].trim().parse().ok()
}
