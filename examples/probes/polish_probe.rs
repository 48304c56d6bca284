//! Does clarabel's active-set polish ever decide an answer? On random
//! stacks (`dev_support::solver::random_stacks`: 10 to 2,000 rows, six
//! seeds, masses spread over 0, 3 and 6 decades), each problem is solved by
//! clarabel's primal form with the polish (`ClarabelSettings::polish_above`
//! 0) and without (infinite), five times each, interleaved. Per problem: the acceptance
//! measure of each answer (`ProjectionResiduals::acceptance`, accepted at
//! most `SolverSettings::tol_residual`, 1e-6) and the median times. The
//! summary counts the problems whose unpolished answer is accepted, those
//! that only the polished one would make accepted, and the summed median
//! times.
//!
//! ```text
//! cargo run --release --features rapier,serde --example probes -- polish
//! ```

use std::time::Instant;

use constraint_stabilization::solver::{SolverChoice, SolverSettings, solve_projection};
use dev_support::solver::{StackSpec, random_stacks};

const SIZES: [usize; 7] = [10, 50, 100, 300, 500, 1000, 2000];
const SEEDS: std::ops::Range<u64> = 100..106;
const MASS_DECADES: [f64; 3] = [0.0, 3.0, 6.0];
const REPEATS: usize = 5;

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

pub fn run() {
    let tolerance = SolverSettings::default().tol_residual;
    let (mut problems, mut raw_accepted, mut polish_needed, mut neither) = (0, 0, 0, 0);
    let (mut largest_raw, mut seconds_with, mut seconds_without) = (0.0_f64, 0.0, 0.0);
    for n in SIZES {
        for seed in SEEDS {
            for decades in MASS_DECADES {
                let mut spec = StackSpec::new(n, seed);
                spec.mass_decades = decades;
                let qp = random_stacks(&spec);
                let mut times = [Vec::new(), Vec::new()];
                let mut acceptance = [f64::NAN; 2];
                for repeat in 0..REPEATS {
                    for k in 0..2 {
                        // 0: polished, 1: not; the order alternates.
                        let variant = (k + repeat) % 2;
                        let mut settings = SolverSettings {
                            choice: SolverChoice::Clarabel,
                            fall_back: false,
                            // Every answer is returned, its measure reported.
                            tol_residual: f64::INFINITY,
                            ..SolverSettings::default()
                        };
                        settings.clarabel.polish_above =
                            if variant == 0 { 0.0 } else { f64::INFINITY };
                        let start = Instant::now();
                        let result = solve_projection(&qp, &settings);
                        times[variant].push(start.elapsed().as_secs_f64());
                        acceptance[variant] =
                            result.map_or(f64::INFINITY, |s| s.residuals.acceptance());
                    }
                }
                let (with, without) = (median(&mut times[0]), median(&mut times[1]));
                seconds_with += with;
                seconds_without += without;
                problems += 1;
                largest_raw = largest_raw.max(acceptance[1]);
                if acceptance[1] <= tolerance {
                    raw_accepted += 1;
                } else if acceptance[0] <= tolerance {
                    polish_needed += 1;
                } else {
                    neither += 1;
                }
                println!(
                    "{n:5} rows (asked), seed {seed}, {decades} decades: {} rows, acceptance polished {:.2e} unpolished {:.2e}, median {:.3} ms / {:.3} ms",
                    qp.num_rows(),
                    acceptance[0],
                    acceptance[1],
                    with * 1e3,
                    without * 1e3
                );
            }
        }
    }
    println!(
        "{problems} problems: unpolished accepted {raw_accepted} (largest measure {largest_raw:.2e}), \
         accepted only polished {polish_needed}, neither {neither}; summed medians {:.1} ms with the \
         polish, {:.1} ms without ({:.2}x)",
        seconds_with * 1e3,
        seconds_without * 1e3,
        seconds_with / seconds_without
    );
}
