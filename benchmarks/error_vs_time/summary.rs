//! The figures the goals are judged by, and the CSV and Markdown files.
//!
//! - **Equal time** (goal 1): the library's default call takes `t`; a
//!   baseline's remaining penetration at time `t` is the smallest exact
//!   depth among its points that took at most `t` (the initial depth if
//!   none did). The ratio divides it by the library's exact depth, floored
//!   at the tolerance (a depth of 0 would make every ratio infinite); a
//!   scene whose initial depth is within the tolerance has none. The
//!   goal: at least [`GOAL_RATIO`] on stacks, pyramids, mass ratios and
//!   engine states.
//! - **auto against the fastest** (goal 2): the library's configuration
//!   that reaches the tolerance (by the exact depth) in the least time,
//!   over every solver and pass limit at the default tolerance (a looser
//!   tolerance that happens to end within the default one is shown beside
//!   it, not counted); `auto`'s default time divided by it, goal at most
//!   [`GOAL_AUTO`].
//! - **Scaling** (goal 3): least-squares slope of `log t` against
//!   `log bodies` per family, for `auto` at the default settings; goal at
//!   most 1 on piles.
//! - **Excess displacement**: a point's mass-weighted displacement over the
//!   smallest among the points of the scene that reached the tolerance,
//!   minus 1.

use std::fmt::Write as _;

use crate::common::Provenance;
use crate::{Measured, Point, methods, settle};

/// Goal 1: the baselines' remaining penetration over the library's.
pub const GOAL_RATIO: f64 = 100.0;
/// Goal 2: `auto`'s time over the fastest configuration's.
pub const GOAL_AUTO: f64 = 1.3;
/// The library's default configuration: line and parameter.
pub const DEFAULT_LINE: (&str, &str) = ("auto passes", "passes=all");
/// The baseline lines.
pub const BASELINES: [&str; 4] = ["gs_box2d", "gs_tuned", "gs_tuned_redetect", "settle"];
/// Families goal 1 is judged on.
const GOAL_1_FAMILIES: [&str; 4] = ["stack", "pyramid", "heavy_on_pyramid", "engine"];

/// Whether a line is one of the library's own.
pub fn is_library(line: &str) -> bool {
    line.ends_with(" passes") || line.ends_with(" tol")
}

/// The points of `line`, by time. A tolerance line includes its solver's
/// unlimited run at the default tolerance (it is the pass line's last).
pub fn line_points<'a>(m: &'a Measured, line: &str) -> Vec<&'a Point> {
    let mut points: Vec<&Point> = m.points.iter().filter(|p| p.line == line).collect();
    if let Some(solver) = line.strip_suffix(" tol") {
        let full = format!("{solver} passes");
        points.extend(
            m.points
                .iter()
                .filter(|p| p.line == full && p.parameter == DEFAULT_LINE.1),
        );
    }
    points.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
    points
}

/// The library's default call.
pub fn default_point(m: &Measured) -> Option<&Point> {
    m.points
        .iter()
        .find(|p| p.line == DEFAULT_LINE.0 && p.parameter == DEFAULT_LINE.1)
}

/// The smallest exact depth of `line` within `seconds`, and whether any
/// point of the line fit in that time.
pub fn depth_within(m: &Measured, line: &str, seconds: f64) -> (f64, bool) {
    line_points(m, line)
        .iter()
        .filter(|p| p.seconds <= seconds)
        .map(|p| p.exact)
        .fold((m.initial, false), |(d, _), e| (d.min(e), true))
}

/// The library's fastest point that reaches the tolerance: among the
/// pass lines (every solver and pass limit at the default tolerance), or
/// among every library point (`any_tolerance`).
pub fn fastest_resolving(m: &Measured, any_tolerance: bool) -> Option<&Point> {
    m.points
        .iter()
        .filter(|p| {
            let considered = if any_tolerance {
                is_library(&p.line)
            } else {
                p.line.ends_with(" passes")
            };
            considered && p.exact <= m.tolerance
        })
        .min_by(|a, b| a.seconds.total_cmp(&b.seconds))
}

/// The smallest displacement among the points that reach the tolerance.
pub fn smallest_displacement(m: &Measured) -> Option<f64> {
    m.points
        .iter()
        .filter(|p| p.exact <= m.tolerance)
        .map(|p| p.motion.displacement)
        .min_by(f64::total_cmp)
}

/// `displacement / smallest - 1` with `smallest` from
/// [`smallest_displacement`], or NaN without one.
pub fn excess(p: &Point, smallest: Option<f64>) -> f64 {
    match smallest {
        Some(d) if d > 0.0 => p.motion.displacement / d - 1.0,
        _ => f64::NAN,
    }
}

/// Goal 1's ratio for `baseline` on a scene (NaN without a default point).
pub fn equal_time_ratio(m: &Measured, baseline: &str) -> f64 {
    let Some(library) = default_point(m) else {
        return f64::NAN;
    };
    // A scene with nothing to remove has no ratio (0 / tolerance).
    if m.initial <= m.tolerance || !m.points.iter().any(|p| p.line == baseline) {
        return f64::NAN;
    }
    let (depth, _) = depth_within(m, baseline, library.seconds);
    depth / library.exact.max(m.tolerance)
}

/// Goal 2's ratio on a scene, with the fastest point.
pub fn auto_over_fastest(m: &Measured) -> Option<(f64, &Point)> {
    let auto = default_point(m)?;
    let fastest = fastest_resolving(m, false)?;
    Some((auto.seconds / fastest.seconds, fastest))
}

/// Least-squares slope of `ln y` against `ln x` (NaN with fewer than two
/// distinct `x`).
pub fn fitted_exponent(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = logs.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    if sxx > 0.0 { sxy / sxx } else { f64::NAN }
}

/// The point of `line` / `parameter` on each of a family's scenes.
fn family_points<'a>(
    measured: &'a [Measured],
    family: &'a str,
    line: &'a str,
    parameter: &'a str,
) -> impl Iterator<Item = (&'a Measured, &'a Point)> {
    measured
        .iter()
        .filter(move |m| m.family == family)
        .filter_map(move |m| {
            let point = m
                .points
                .iter()
                .find(|p| p.line == line && p.parameter == parameter);
            point.map(|p| (m, p))
        })
}

/// (bodies, seconds) of `line` / `parameter` over a family's scenes.
pub fn family_times(
    measured: &[Measured],
    family: &str,
    line: &str,
    parameter: &str,
) -> Vec<(f64, f64)> {
    family_points(measured, family, line, parameter)
        .map(|(m, p)| (m.bodies as f64, p.seconds))
        .collect()
}

/// `(rows solved, seconds)` of `auto` at the default settings on the
/// scenes of `family` that solved any row.
fn family_rows(measured: &[Measured], family: &str) -> Vec<(f64, f64)> {
    family_points(measured, family, DEFAULT_LINE.0, DEFAULT_LINE.1)
        .filter(|(_, p)| p.rows_solved > 0)
        .map(|(_, p)| (p.rows_solved as f64, p.seconds))
        .collect()
}

/// One line per scene for the progress output.
pub fn one_line(m: &Measured) -> String {
    let default = default_point(m);
    format!(
        "{}: {} bodies, initial {:.2e}; auto {:.3} ms exact {:.2e}; ratios {}",
        m.name,
        m.bodies,
        m.initial,
        default.map_or(f64::NAN, |p| p.seconds * 1e3),
        default.map_or(f64::NAN, |p| p.exact),
        BASELINES
            .iter()
            .map(|b| format!("{b} {:.1e}", equal_time_ratio(m, b)))
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// Every point as CSV.
pub fn csv(measured: &[Measured]) -> String {
    let mut out = String::from(
        "family,scene,bodies,line,parameter,iterations,status,time_ms,repeats,exact,\
         tolerance,initial,displacement,excess,largest_motion,velocities_changed,rows_solved\n",
    );
    for m in measured {
        let smallest = smallest_displacement(m);
        for p in &m.points {
            let _ = writeln!(
                out,
                "{},{},{},{},{},{},{},{:.6},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{},{}",
                m.family,
                m.name,
                m.bodies,
                p.line,
                p.parameter,
                p.iterations,
                p.status,
                p.seconds * 1e3,
                p.repeats,
                p.exact,
                m.tolerance,
                m.initial,
                p.motion.displacement,
                excess(p, smallest),
                p.motion.largest,
                p.velocities_changed,
                p.rows_solved
            );
        }
    }
    out
}

fn ratio_cell(r: f64) -> String {
    if r.is_nan() {
        "-".into()
    } else if r >= GOAL_RATIO {
        format!("{r:.1e}")
    } else {
        format!("**{r:.1e}**")
    }
}

/// The Markdown report.
pub fn markdown(measured: &[Measured], provenance: &Provenance, quick: bool) -> String {
    let mut md = String::from(
        "# Remaining penetration against run time: the library and what is used instead\n\n",
    );
    md.push_str(&provenance.markdown());
    if quick {
        md.push_str("\n**Quick run** (`--quick`): one small scene per family, one repeat, few points; the harness's smoke test, not a measurement.\n");
    }
    md.push_str(&parameters());
    md.push_str(&goals(measured));
    md.push_str(&per_scene(measured));
    md
}

fn parameters() -> String {
    let presets: Vec<String> = methods::GAUSS_SEIDEL_PRESETS
        .iter()
        .map(|p| {
            format!(
                "`{}`: Baumgarte fraction {}, slop {} L, largest correction per visit {} L, {}",
                p.name,
                p.baumgarte,
                p.slop_relative,
                p.max_correction_relative,
                if p.detect_every_sweep {
                    "contacts detected before every sweep"
                } else {
                    "contacts detected once and their points re-measured at every visit \
                     (again when a sweep pushes nothing), as Box2D"
                }
            )
        })
        .collect();
    format!(
        "\n## Methods and parameters\n\n\
         `L` is the scene scale (the circumradius of the smallest dynamic body); the \
         tolerance is the library's default, `1e-6 L`, for every method. Times are wall \
         times of the whole call (median of the repeats; every configuration of a scene \
         interleaved per repeat, each repeat's round starting at another configuration; \
         a configuration whose first run took more than {slow} s \
         is not repeated). Depths are exact: brute-force separating axes over every pair \
         (`dev_support::sat`).\n\n\
         - **Library** (`Stabilizer::stabilize`, fresh stabilizer, default settings but \
         for the solver, the pass limit and the tolerance; the target margin stays at \
         its default `{margin:e} L`, so that a looser tolerance stops earlier): per solver (`auto`, `clarabel`, `lemke`, `pgs`), a \
         *passes* line (pass limits {passes:?}, then unlimited), and for `auto` a *tol* \
         line (tolerances {tols:?} L, unlimited passes; for the other solvers it would \
         double a run that already takes most of an hour). Forced Lemke is left out where \
         `auto`'s largest island exceeds 4 times the rows up to which `auto` picks Lemke \
         (the scene's errors column says so): there one call took minutes. A solver \
         whose call takes over {slow} s gets that one point. Never changes velocities.\n\
         - **Nonlinear Gauss–Seidel position correction** (`Method::GaussSeidel`, \
         `src/gauss_seidel/`; Box2D v2.4's position solver in 3D): sweeps {sweeps:?}; \
         {presets}. Never changes velocities.\n\
         - **Settling by simulation** (`settle`): Rapier 3D (f32) from the overlapping \
         state, gravity off, velocities zeroed after every step, poses after {steps:?} \
         steps of one run; the time is the steps' and the zeroing's. Changes velocities \
         (they are zeroed). Rapier's default integration parameters: `{rapier}`.\n",
        slow = crate::SLOW_RUN_SECONDS,
        margin = constraint_stabilization::settings::DEFAULT_TARGET_MARGIN_RELATIVE,
        passes = methods::PASS_LIMITS,
        tols = methods::TOLERANCES,
        sweeps = methods::ITERATIONS,
        presets = presets.join("; "),
        steps = methods::STEPS,
        rapier = settle::parameters(),
    )
}

fn goals(measured: &[Measured]) -> String {
    let mut md = format!(
        "\n## Goals\n\n### 1. At equal run time, at least {GOAL_RATIO}× less penetration than the baselines\n\n\
         At the time of the library's default call: the baseline's remaining exact \
         penetration over the library's (floored at the tolerance). Bold: below {GOAL_RATIO}.\n\n\
         | family | scenes | {} |\n|---|---|{}\n",
        BASELINES
            .iter()
            .map(|b| format!("{b}: met / worst"))
            .collect::<Vec<_>>()
            .join(" | "),
        "---|".repeat(BASELINES.len())
    );
    let mut families: Vec<&str> = Vec::new();
    for m in measured {
        if !families.contains(&m.family) {
            families.push(m.family);
        }
    }
    for family in &families {
        let scenes: Vec<&Measured> = measured.iter().filter(|m| m.family == *family).collect();
        let cells: Vec<String> = BASELINES
            .iter()
            .map(|b| {
                let ratios: Vec<f64> = scenes
                    .iter()
                    .map(|m| equal_time_ratio(m, b))
                    .filter(|r| !r.is_nan())
                    .collect();
                if ratios.is_empty() {
                    return "-".into();
                }
                let met = ratios.iter().filter(|&&r| r >= GOAL_RATIO).count();
                let worst = ratios.iter().copied().fold(f64::INFINITY, f64::min);
                format!("{met}/{} / {}", ratios.len(), ratio_cell(worst))
            })
            .collect();
        let judged = if GOAL_1_FAMILIES.contains(family) {
            ""
        } else {
            " (not in the goal)"
        };
        let _ = writeln!(
            md,
            "| {family}{judged} | {} | {} |",
            scenes.len(),
            cells.join(" | ")
        );
    }
    let _ = write!(
        md,
        "\n### 2. `auto` within {GOAL_AUTO}× of the library's fastest configuration that reaches the tolerance\n\n\
         Fastest over every solver and pass limit at the default tolerance; the last \
         column is the fastest over every tolerance too (a looser tolerance can end \
         within the default one by luck).\n\n\
         | scene | auto ms | fastest | fastest ms | ratio | fastest at any tolerance |\n|---|---|---|---|---|---|\n"
    );
    let mut misses = 0;
    for m in measured {
        let Some((ratio, fastest)) = auto_over_fastest(m) else {
            let _ = writeln!(
                md,
                "| {} | - | none reaches the tolerance | - | - | - |",
                m.name
            );
            continue;
        };
        let auto = default_point(m).map_or(f64::NAN, |p| p.seconds * 1e3);
        let mark = if ratio > GOAL_AUTO {
            misses += 1;
            format!("**{ratio:.2}**")
        } else {
            format!("{ratio:.2}")
        };
        let any = fastest_resolving(m, true).map_or("-".into(), |p| {
            format!("{} {}: {:.3} ms", p.line, p.parameter, p.seconds * 1e3)
        });
        let _ = writeln!(
            md,
            "| {} | {auto:.3} | {} {} | {:.3} | {mark} | {any} |",
            m.name,
            fastest.line,
            fastest.parameter,
            fastest.seconds * 1e3
        );
    }
    let _ = writeln!(
        md,
        "\nScenes where `auto` is more than {GOAL_AUTO}× the fastest: {misses} of {}.",
        measured.len()
    );
    let _ = write!(
        md,
        "\n### 3. Time against body count (fitted exponent of `t ~ n^k`, `auto` at the default settings; goal k <= 1 on piles)\n\n\
         The work of a call is its rows: `rows solved` sums the rows of every island solved in every pass, \
         and `k (auto, rows)` fits `t ~ rows^k`: a scene whose bodies touch more neighbours as it grows \
         costs more per body, not more per row.\n\n\
         | family | sizes | k (auto) | rows solved (auto) | k (auto, rows) | µs per row (auto) | k (gs_tuned_redetect, 1 sweep) | k (settle, 1 step) |\n|---|---|---|---|---|---|---|---|\n"
    );
    for family in ["stack", "pyramid", "pile"] {
        let auto = family_times(measured, family, DEFAULT_LINE.0, DEFAULT_LINE.1);
        if auto.len() < 2 {
            continue;
        }
        let sweep = family_times(measured, family, "gs_tuned_redetect", "sweeps=1");
        let step = family_times(measured, family, "settle", "steps=1");
        let rows = family_rows(measured, family);
        let list = |values: Vec<String>| values.join(", ");
        let _ = writeln!(
            md,
            "| {family} | {} | {:.2} | {} | {:.2} | {} | {:.2} | {:.2} |",
            list(auto.iter().map(|(n, _)| format!("{n}")).collect()),
            fitted_exponent(&auto),
            list(rows.iter().map(|(r, _)| format!("{r}")).collect()),
            fitted_exponent(&rows),
            list(
                rows.iter()
                    .map(|(r, t)| format!("{:.1}", t / r * 1e6))
                    .collect()
            ),
            fitted_exponent(&sweep),
            fitted_exponent(&step)
        );
    }
    md
}

fn per_scene(measured: &[Measured]) -> String {
    let header: Vec<String> = BASELINES
        .iter()
        .map(|b| format!("{b} at auto's time"))
        .chain(BASELINES.iter().map(|b| format!("{b} best")))
        .collect();
    let mut md = format!(
        "\n## Per scene\n\n\
         `auto`: the default call (time, passes, exact depth after). `at auto's time`: \
         each baseline's smallest exact depth among its points that took at most that \
         time (the initial depth if none did). `best`: the smallest exact depth the \
         line reached, when and with which parameter (`within tol` if it reached the \
         tolerance). `excess`: mass-weighted displacement over the smallest among the \
         points within the tolerance, minus 1.\n\n\
         | scene | bodies | tolerance | initial | auto ms | passes | exact | excess | {} | errors |\n\
         |{}\n",
        header.join(" | "),
        "---|".repeat(9 + header.len())
    );
    for m in measured {
        let auto = default_point(m);
        let at = |line: &str| match auto {
            Some(a) if m.points.iter().any(|p| p.line == line) => {
                let (d, fit) = depth_within(m, line, a.seconds);
                if fit {
                    format!("{d:.1e}")
                } else {
                    format!("{d:.1e} (no point)")
                }
            }
            _ => "-".into(),
        };
        let best = |line: &str| {
            line_points(m, line)
                .into_iter()
                .min_by(|a, b| a.exact.total_cmp(&b.exact))
                .map_or("-".into(), |p| {
                    let within = if p.exact <= m.tolerance {
                        ", within tol"
                    } else {
                        ""
                    };
                    format!(
                        "{:.1e} ({:.1} ms, {}{within})",
                        p.exact,
                        p.seconds * 1e3,
                        p.parameter
                    )
                })
        };
        let cells: Vec<String> = BASELINES
            .iter()
            .map(|b| at(b))
            .chain(BASELINES.iter().map(|b| best(b)))
            .collect();
        let _ = writeln!(
            md,
            "| {} | {} | {:.1e} | {:.1e} | {} | {} | {} | {} | {} | {} |",
            m.name,
            m.bodies,
            m.tolerance,
            m.initial,
            auto.map_or("-".into(), |p| format!("{:.3}", p.seconds * 1e3)),
            auto.map_or("-".into(), |p| p.iterations.to_string()),
            auto.map_or("-".into(), |p| format!("{:.1e}", p.exact)),
            auto.map_or("-".into(), |p| format!(
                "{:.2}",
                excess(p, smallest_displacement(m))
            )),
            cells.join(" | "),
            m.errors
                .iter()
                .map(|(c, e)| format!("{c}: {e}"))
                .collect::<Vec<_>>()
                .join("; ")
        );
    }
    md
}
