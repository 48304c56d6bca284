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
//! `benchmarks/results/stabilize_stages.md` with the command, the date, the
//! commit and the load average. With the `parallel` feature the per-island
//! stages (solve, line search) are summed over islands solved on different
//! threads, so their shares can add up to more than 100 % and "other" can
//! be negative. The verdict of each row ("resolved" or not) is the exact
//! depth of the stabilized scene, measured by brute-force separating axes
//! (`dev_support::sat`), not the library's report.
//!
//! Run: `cargo bench --bench stabilize` (add `-- --quick` for a short
//! criterion run). `STABILIZE_SKIP_CRITERION=1` writes the stage table only
//! (criterion's separate runs, minutes apart, are less comparable on a
//! shared machine; its summary goes to `target/criterion`, not to the
//! results). `STABILIZE_RUNS=n` sets the runs per size of the stage table
//! (default 31, and 11 at 1,000 bodies).

mod common;

use std::fmt::Write as _;
use std::hint::black_box;

use common::{Provenance, bench_command};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::testbed::demo::demo_scene;
use constraint_stabilization::{Report, Settings, Stabilizer};
use criterion::{BatchSize, BenchmarkId, Criterion};
use dev_support::sat::{ExactDepth, exact_depth};

/// Body counts benchmarked.
const SIZES: [usize; 3] = [10, 100, 1000];
/// Seed of the benchmarked scenes.
const SEED: u64 = 2026;

/// Environment variables that change what the benchmark does (or how it
/// was built).
const ENV_VARS: [&str; 4] = [
    "STABILIZE_RUNS",
    "STABILIZE_SKIP_CRITERION",
    "RAYON_NUM_THREADS",
    "CARGO_PROFILE_RELEASE_DEBUG",
];

/// Runs per size for the stage table.
fn stage_runs(n: usize) -> usize {
    let default = if n >= 1000 { 11 } else { 31 };
    std::env::var("STABILIZE_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|&r: &usize| r > 0)
        .unwrap_or(default)
}

fn main() {
    write_stage_table();
    if std::env::var("STABILIZE_SKIP_CRITERION").is_err() {
        let mut criterion = Criterion::default().configure_from_args();
        bench_stabilize(&mut criterion);
        criterion.final_summary();
    }
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
    let provenance = Provenance::start(bench_command("stabilize", &ENV_VARS));
    let mut body = String::new();
    let threads = rayon_threads();
    let _ = writeln!(
        body,
        "Medians over runs of each stage's time from `Report::times`; share = median stage time / \
         median total. cold = fresh `Stabilizer`, warm = reused after a call on the same scene; cold and warm runs \
         interleaved. \
         {threads} rayon thread(s): solve and line search are summed over islands, so with more \
         than one thread shares may exceed 100 % and 'other' may be negative. Machine shared and \
         noisy: compare within the table. status and depth after (library) are the \
         library's report; exact before / after are the deepest penetration over all pairs with a \
         dynamic body by brute-force separating axes (`benchmarks/common/sat.rs`) on the scene \
         before and after the last run, and the verdict is `resolved` if exact after <= the \
         tolerance (`Report::tolerance`, given in the last column).\n"
    );
    let _ = writeln!(
        body,
        "| bodies | mode | runs | total ms | broad % | narrow % | solve % | line search % | other % | \
         passes | islands solved | rows (sum) | line-search trials | status | depth after (library) | \
         exact before | exact after | verdict (exact) | tolerance |"
    );
    let _ = writeln!(
        body,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let mut ratios = Vec::new();
    for n in SIZES {
        let scene = demo_scene(n, SEED);
        let [cold, warm] = stage_samples(&scene, stage_runs(n));
        for (run, is_warm) in [(&cold, false), (&warm, true)] {
            let before = exact_depth(&scene, run.report.tolerance);
            let after = exact_depth(&run.scene, run.report.tolerance);
            let _ = writeln!(body, "{}", stage_row(n, is_warm, run, &before, &after));
        }
        let (cold, warm) = (&cold.samples, &warm.samples);
        let total =
            |s: &[StageSample]| common::median(&s.iter().map(|x| x.total).collect::<Vec<_>>());
        ratios.push((n, total(warm) / total(cold)));
    }
    let _ = writeln!(body, "\nwarm / cold median total time (runs interleaved):");
    for (n, ratio) in ratios {
        let _ = writeln!(body, "- {n} bodies: {ratio:.3}");
    }
    let md = format!(
        "# Stage shares of `stabilize` on the demo scene (seed {SEED})\n\n{}\n{body}",
        provenance.markdown()
    );
    let path = common::results_dir().join("stabilize_stages.md");
    std::fs::write(&path, &md).expect("write stabilize_stages.md");
    println!("{md}\nwritten to {}", path.display());
}

/// One mode's runs: the samples, and the report and stabilized scene of
/// the last run.
struct ModeRuns {
    samples: Vec<StageSample>,
    report: Report,
    scene: Scene,
}

/// Cold and warm runs, interleaved run by run so that the machine's load
/// drifts over both alike: `[cold, warm]`.
fn stage_samples(scene: &Scene, runs: usize) -> [ModeRuns; 2] {
    let mut warm = Stabilizer::new(Settings::default()).expect("settings");
    warm.stabilize(&mut scene.clone()).expect("stabilize");
    let mut samples = [Vec::with_capacity(runs), Vec::with_capacity(runs)];
    let mut last = [None, None];
    for _ in 0..runs {
        let mut cold = Stabilizer::new(Settings::default()).expect("settings");
        for (k, stabilizer) in [&mut cold, &mut warm].into_iter().enumerate() {
            let mut work = scene.clone();
            let report = stabilizer.stabilize(&mut work).expect("stabilize");
            samples[k].push(StageSample::from(&report));
            last[k] = Some((report, work));
        }
    }
    let [cold, warm] = samples;
    let [cold_last, warm_last] = last.map(|r| r.expect("at least one run"));
    [(cold, cold_last), (warm, warm_last)].map(|(samples, (report, scene))| ModeRuns {
        samples,
        report,
        scene,
    })
}

fn stage_row(
    n: usize,
    warm: bool,
    run: &ModeRuns,
    before: &ExactDepth,
    after: &ExactDepth,
) -> String {
    let (samples, report) = (&run.samples, &run.report);
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
        "| {n} | {} | {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {} | {} | {} | {} | {} | {:.3e} | {:.3e} | {:.3e} | {} | {:.1e} |",
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
        report.depth_after,
        before.deepest,
        after.deepest,
        after.verdict(),
        report.tolerance,
    )
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
