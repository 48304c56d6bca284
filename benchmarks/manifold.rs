//! The contact-manifold question: one constraint row per pair (the deepest
//! vertex of the witness body under the witness face, plus near pairs), or
//! one row per penetrating vertex of that body under the face plane (a
//! small manifold), `Settings::contact_manifold = false / true`.
//!
//! Both settings run side by side, interleaved run by run, on:
//! - the demo scene at 10, 100 and 1,000 bodies, several seeds;
//! - box stacks (`common::box_stack`) of 5 and 10 boxes, several seeds;
//! - one box resting face down on a fixed ground (`common::box_on_ground`),
//!   upright (the exact correction is a pure lift: a final tilt is an
//!   artefact of the contact model) and tilted by 0.3 and 2 degrees.
//!
//! Per scene and setting: status, passes, median wall time of the call
//! (fresh stabilizer per call), final deepest penetration, mass-weighted
//! displacement, largest rotation of any body (degrees), and for the
//! resting box its final tilt. The verdict (resolved or not) is the exact
//! depth of the stabilized scene by brute-force separating axes
//! (`dev_support::sat`) against the tolerance, not the library's status, which
//! is shown beside it. The table goes to `benchmarks/results/manifold.md`
//! with the command, the date, the commit and the load average; time
//! ratios are manifold / deepest.
//!
//! Run: `cargo bench --bench manifold`. `MANIFOLD_MAX_RUNS=n` caps the runs
//! per scene and setting (defaults: 15 on demo 10 and the stacks, 7 on
//! demo 100, 3 on demo 1,000, 31 on the resting box).

mod common;

use std::fmt::Write as _;

use common::{Provenance, bench_command};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::testbed::demo::demo_scene;
use constraint_stabilization::{Report, Settings};
use dev_support::sat::{ExactDepth, exact_depth};

/// A named scene and how often to run it per setting.
struct Case {
    name: String,
    scene: Scene,
    runs: usize,
    /// Index of the body whose final tilt is reported.
    tilt_body: Option<usize>,
}

/// Environment variables that change what the benchmark does (or how it
/// was built).
const ENV_VARS: [&str; 3] = [
    "MANIFOLD_MAX_RUNS",
    "RAYON_NUM_THREADS",
    "CARGO_PROFILE_RELEASE_DEBUG",
];

/// One setting's result on one case.
struct Outcome {
    report: Report,
    /// Exact depth of the stabilized scene (last run).
    exact: ExactDepth,
    median_seconds: f64,
    /// Largest rotation of any body (radians) and that body's name.
    max_rotation: (f64, String),
    tilt: Option<f64>,
}

fn cases() -> Vec<Case> {
    let cap = common::env_cap("MANIFOLD_MAX_RUNS");
    let mut cases = Vec::new();
    for (n, seeds, runs) in [(10, 1..=8u64, 15), (100, 1..=5, 7), (1000, 1..=3, 3)] {
        for seed in seeds {
            cases.push(Case {
                name: format!("demo {n} seed {seed}"),
                scene: demo_scene(n, seed),
                runs: runs.min(cap),
                tilt_body: None,
            });
        }
    }
    for height in [5, 10] {
        for seed in 1..=3u64 {
            cases.push(Case {
                name: format!("stack {height} seed {seed}"),
                scene: common::box_stack(height, seed),
                runs: 15.min(cap),
                tilt_body: None,
            });
        }
    }
    for tilt_degrees in [0.0, 0.3, 2.0] {
        cases.push(Case {
            name: format!("box on ground, tilt {tilt_degrees} deg"),
            scene: common::box_on_ground(f64::to_radians(tilt_degrees)),
            runs: 31.min(cap),
            tilt_body: Some(1),
        });
    }
    cases
}

fn main() {
    let provenance = Provenance::start(bench_command("manifold", &ENV_VARS));
    let mut md = String::new();
    let _ = writeln!(
        md,
        "D = deepest vertex per pair (`false`), M = manifold (`true`). Fresh stabilizer per call, \
         both settings interleaved run by run; time = median wall time of the call. \
         depth = final deepest penetration (tolerance 1e-6 L). disp = mass-weighted displacement. \
         rot = largest rotation of any body (deg, and that body). tilt = final tilt of the resting box (deg; initial tilt in the scene name). \
         ratio = M time / D time. \
         status and depth = the library's report. exact = deepest penetration over all pairs with \
         a dynamic body by brute-force separating axes (`benchmarks/common/sat.rs`), before the \
         call and after the last run of each setting; D / M verdict: `resolved` if exact after <= \
         the tolerance, else `UNRESOLVED`.\n"
    );
    let _ = writeln!(
        md,
        "| scene | runs | exact before | D verdict | M verdict | D exact | M exact | D status | M status | \
         D passes | M passes | D ms | M ms | ratio | \
         D depth | M depth | D disp | M disp | D rot | M rot | D tilt | M tilt |"
    );
    let _ = writeln!(
        md,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let mut ratios = Vec::new();
    let mut passes = [0usize; 2];
    let mut unresolved = [0usize; 2];
    // Library status and exact verdict disagree.
    let mut disagree = [0usize; 2];
    for case in cases() {
        let [deepest, manifold] = measure(&case);
        ratios.push(manifold.median_seconds / deepest.median_seconds);
        for (k, o) in [&deepest, &manifold].iter().enumerate() {
            passes[k] += o.report.passes;
            unresolved[k] += usize::from(!o.exact.resolved());
            disagree[k] += usize::from(o.exact.resolved() != o.report.status.is_resolved());
        }
        let before = exact_depth(&case.scene, deepest.report.tolerance);
        let line = row(&case, &before, &deepest, &manifold);
        println!("{line}");
        let _ = writeln!(md, "{line}");
    }
    let geo_mean = (ratios.iter().map(|r| r.ln()).sum::<f64>() / ratios.len() as f64).exp();
    let _ = writeln!(
        md,
        "\nSummary over {} scenes: passes D {} / M {}; unresolved (exact depth) D {} / M {}; \
         library status disagreeing with the exact verdict D {} / M {}; \
         time ratio M/D geometric mean {:.3}, median {:.3}.",
        ratios.len(),
        passes[0],
        passes[1],
        unresolved[0],
        unresolved[1],
        disagree[0],
        disagree[1],
        geo_mean,
        common::median(&ratios)
    );
    let md = format!(
        "# Contact manifold vs deepest vertex (`Settings::contact_manifold`)\n\n{}\n{md}",
        provenance.markdown()
    );
    let path = common::results_dir().join("manifold.md");
    std::fs::write(&path, &md).expect("write manifold.md");
    println!("{md}\nwritten to {}", path.display());
}

/// Runs both settings, interleaved, `case.runs` times each.
fn measure(case: &Case) -> [Outcome; 2] {
    let settings = [false, true].map(|manifold| {
        let mut settings = Settings::default();
        settings.contact_manifold = manifold;
        settings
    });
    let mut times: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    let mut last: [Option<(Report, Scene)>; 2] = [None, None];
    for _ in 0..case.runs {
        for k in 0..2 {
            let (report, seconds, scene) = common::run_cold(&case.scene, &settings[k]);
            times[k].push(seconds);
            last[k] = Some((report, scene));
        }
    }
    [0, 1].map(|k| {
        let (report, scene) = last[k].take().expect("runs >= 1");
        Outcome {
            exact: exact_depth(&scene, report.tolerance),
            report,
            median_seconds: common::median(&times[k]),
            max_rotation: max_rotation(&case.scene, &scene),
            tilt: case.tilt_body.map(|i| common::tilt(&scene, i)),
        }
    })
}

/// Largest rotation angle (radians) of any body between two scenes, and
/// that body's name.
fn max_rotation(before: &Scene, after: &Scene) -> (f64, String) {
    before
        .bodies()
        .iter()
        .zip(after.bodies())
        .map(|(b, a)| {
            let angle = a
                .user_pose()
                .rotation
                .rotation_to(&b.user_pose().rotation)
                .angle();
            (angle, a.name().to_string())
        })
        .fold((0.0, "-".to_string()), |best, next| {
            if next.0 > best.0 { next } else { best }
        })
}

fn row(case: &Case, before: &ExactDepth, d: &Outcome, m: &Outcome) -> String {
    let deg = f64::to_degrees;
    let tilt = |o: &Outcome| {
        o.tilt
            .map_or("-".to_string(), |t| format!("{:.2e}", deg(t)))
    };
    let rotation = |o: &Outcome| format!("{:.2} ({})", deg(o.max_rotation.0), o.max_rotation.1);
    format!(
        "| {} | {} | {:.2e} | {} | {} | {:.2e} | {:.2e} | {} | {} | {} | {} | {:.3} | {:.3} | {:.2} | {:.2e} | {:.2e} | {:.4} | {:.4} | {} | {} | {} | {} |",
        case.name,
        case.runs,
        before.deepest,
        verdict(&d.exact),
        verdict(&m.exact),
        d.exact.deepest,
        m.exact.deepest,
        d.report.status.name(),
        m.report.status.name(),
        d.report.passes,
        m.report.passes,
        d.median_seconds * 1e3,
        m.median_seconds * 1e3,
        m.median_seconds / d.median_seconds,
        d.report.depth_after,
        m.report.depth_after,
        d.report.displacement,
        m.report.displacement,
        rotation(d),
        rotation(m),
        tilt(d),
        tilt(m),
    )
}

/// `resolved`, or `UNRESOLVED` in capitals so that it stands out.
fn verdict(exact: &ExactDepth) -> &'static str {
    if exact.resolved() {
        "resolved"
    } else {
        "UNRESOLVED"
    }
}
