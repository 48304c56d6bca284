//! Time of one `Stabilizer::stabilize` call on the demo scene
//! (`demo::demo_scene(n, seed)`) at 10, 100 and 1,000 bodies.
//!
//! - `cold`: a fresh stabilizer per call (empty V-Clip warm-start cache);
//! - `warm`: one stabilizer reused, its cache filled by an earlier call on
//!   the same scene (temporal coherence across calls: the next call starts
//!   from the same overlapping poses, with every pair's last V-Clip feature
//!   pair cached).
//!
//! The scene is cloned outside the timed part (`iter_batched`).
//!
//! Before criterion runs, the stage shares (broad phase, narrow phase,
//! solve, line search, other = total minus the four) are measured from the
//! reports, medians over runs, and written to
//! `benchmarks/results/stabilize_stages.md`. With the `parallel` feature
//! the per-island stages (solve, line search) are summed over islands
//! solved on different threads, so their shares can add up to more than
//! 100 % and "other" can be negative.
//!
//! Run: `cargo bench --bench stabilize` (add `-- --quick` for a short run).

mod common;

use std::fmt::Write as _;
use std::hint::black_box;

use constraint_stabilization::demo::demo_scene;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Stabilizer};
use criterion::{BatchSize, BenchmarkId, Criterion};

/// Body counts benchmarked.
const SIZES: [usize; 3] = [10, 100, 1000];
/// Seed of the benchmarked scenes.
const SEED: u64 = 2026;

/// Runs per size for the stage table.
fn stage_runs(n: usize) -> usize {
    if n >= 1000 { 11 } else { 31 }
}

fn main() {
    write_stage_table();
    let mut criterion = Criterion::default().configure_from_args();
    bench_stabilize(&mut criterion);
    criterion.final_summary();
}

fn bench_stabilize(c: &mut Criterion) {
    let mut group = c.benchmark_group("stabilize");
    for n in SIZES {
        if n >= 1000 {
            group.sample_size(10);
        }
        let scene = demo_scene(n, SEED);
        group.bench_with_input(BenchmarkId::new("cold", n), &scene, |b, scene| {
            b.iter_batched(
                || scene.clone(),
                |mut work| {
                    let mut stabilizer = Stabilizer::new(Settings::default()).expect("settings");
                    black_box(stabilizer.stabilize(&mut work).expect("stabilize"))
                },
                BatchSize::LargeInput,
            )
        });
        let mut stabilizer = Stabilizer::new(Settings::default()).expect("settings");
        stabilizer.stabilize(&mut scene.clone()).expect("stabilize");
        group.bench_with_input(BenchmarkId::new("warm", n), &scene, |b, scene| {
            b.iter_batched(
                || scene.clone(),
                |mut work| black_box(stabilizer.stabilize(&mut work).expect("stabilize")),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

/// Per-run stage times and counters.
struct StageSample {
    broad: f64,
    narrow: f64,
    solve: f64,
    line_search: f64,
    total: f64,
}

impl StageSample {
    fn from(report: &Report) -> Self {
        let t = report.times;
        StageSample {
            broad: t.broad_phase,
            narrow: t.narrow_phase,
            solve: t.solve,
            line_search: t.line_search,
            total: t.total,
        }
    }

    fn other(&self) -> f64 {
        self.total - self.broad - self.narrow - self.solve - self.line_search
    }
}

fn write_stage_table() {
    let mut md = String::new();
    let threads = rayon_threads();
    let _ = writeln!(
        md,
        "# Stage shares of `stabilize` on the demo scene (seed {SEED})\n\n\
         Medians over runs of each stage's time from `Report::times`; share = median stage time / \
         median total. cold = fresh `Stabilizer`, warm = reused after a call on the same scene; cold and warm runs \
         interleaved. \
         {threads} rayon thread(s): solve and line search are summed over islands, so with more \
         than one thread shares may exceed 100 % and 'other' may be negative. Machine shared and \
         noisy: compare within the table.\n"
    );
    let _ = writeln!(
        md,
        "| bodies | mode | runs | total ms | broad % | narrow % | solve % | line search % | other % | \
         passes | islands solved | rows (sum) | line-search trials | status | depth before | depth after |"
    );
    let _ = writeln!(
        md,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let mut ratios = Vec::new();
    for n in SIZES {
        let scene = demo_scene(n, SEED);
        let [(cold, cold_last), (warm, warm_last)] = stage_samples(&scene, stage_runs(n));
        let _ = writeln!(md, "{}", stage_row(n, false, &cold, &cold_last));
        let _ = writeln!(md, "{}", stage_row(n, true, &warm, &warm_last));
        let total =
            |s: &[StageSample]| common::median(&s.iter().map(|x| x.total).collect::<Vec<_>>());
        ratios.push((n, total(&warm) / total(&cold)));
    }
    let _ = writeln!(md, "\nwarm / cold median total time (runs interleaved):");
    for (n, ratio) in ratios {
        let _ = writeln!(md, "- {n} bodies: {ratio:.3}");
    }
    let _ = writeln!(md, "\nLoad average at the end: {}", load_average());
    let path = common::results_dir().join("stabilize_stages.md");
    std::fs::write(&path, &md).expect("write stabilize_stages.md");
    println!("{md}\nwritten to {}", path.display());
}

/// Cold and warm runs, interleaved run by run so that the machine's load
/// drifts over both alike: `(cold samples, cold report, warm samples, warm
/// report)`, the reports of the last runs.
fn stage_samples(scene: &Scene, runs: usize) -> [(Vec<StageSample>, Report); 2] {
    let mut warm = Stabilizer::new(Settings::default()).expect("settings");
    warm.stabilize(&mut scene.clone()).expect("stabilize");
    let mut samples = [Vec::with_capacity(runs), Vec::with_capacity(runs)];
    let mut last = [None, None];
    for _ in 0..runs {
        let mut cold = Stabilizer::new(Settings::default()).expect("settings");
        for (k, stabilizer) in [&mut cold, &mut warm].into_iter().enumerate() {
            let report = stabilizer.stabilize(&mut scene.clone()).expect("stabilize");
            samples[k].push(StageSample::from(&report));
            last[k] = Some(report);
        }
    }
    let [cold_samples, warm_samples] = samples;
    let [cold_last, warm_last] = last.map(|r| r.expect("at least one run"));
    [(cold_samples, cold_last), (warm_samples, warm_last)]
}

fn stage_row(n: usize, warm: bool, samples: &[StageSample], report: &Report) -> String {
    let med =
        |f: fn(&StageSample) -> f64| common::median(&samples.iter().map(f).collect::<Vec<_>>());
    let total = med(|s| s.total);
    let pct = |v: f64| 100.0 * v / total;
    let rows: usize = report
        .pass_reports
        .iter()
        .flat_map(|p| &p.solved)
        .map(|i| i.constraints)
        .sum();
    format!(
        "| {n} | {} | {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {} | {} | {} | {} | {} | {:.3e} | {:.3e} |",
        if warm { "warm" } else { "cold" },
        samples.len(),
        total * 1e3,
        pct(med(|s| s.broad)),
        pct(med(|s| s.narrow)),
        pct(med(|s| s.solve)),
        pct(med(|s| s.line_search)),
        pct(med(StageSample::other)),
        report.passes,
        report.islands_solved(),
        rows,
        report.line_search_trials(),
        report.status.name(),
        report.depth_before,
        report.depth_after,
    )
}

/// `/proc/loadavg` (the machine is shared), or "unknown".
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg").map_or("unknown".into(), |s| s.trim().to_string())
}

/// Threads the islands are solved on: `RAYON_NUM_THREADS` if set, else the
/// available parallelism (rayon's default).
fn rayon_threads() -> usize {
    std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|&n: &usize| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}
