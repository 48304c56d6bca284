//! A progress indicator for long runs: a spinner on standard error that
//! shows the passes of a stabilization call (pass, penetrating pairs,
//! deepest penetration, elapsed time). indicatif draws nothing when
//! standard error is not a terminal, so redirected output stays clean.

use std::time::Duration;

use constraint_stabilization::stabilizer::PassReport;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Refresh interval of the spinner.
const TICK: Duration = Duration::from_millis(120);

/// A spinner for the passes of one call, labelled `what`.
pub struct PassProgress {
    bar: ProgressBar,
    passes: usize,
}

impl PassProgress {
    /// A started spinner (hidden when standard error is not a terminal).
    pub fn start(what: &str) -> Self {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        let style = ProgressStyle::with_template("{spinner} {prefix} [{elapsed}] {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner());
        bar.set_style(style);
        bar.set_prefix(what.to_owned());
        bar.set_message("pass 1: detection");
        bar.enable_steady_tick(TICK);
        PassProgress { bar, passes: 0 }
    }

    /// Records a finished pass.
    pub fn pass(&mut self, pass: &PassReport) {
        self.passes += 1;
        self.bar.set_message(format!(
            "pass {} done: {} penetrating pairs, deepest {:.3e}; pass {}",
            self.passes,
            pass.penetrating_pairs,
            pass.deepest,
            self.passes + 1
        ));
    }

    /// Removes the spinner.
    pub fn finish(self) {
        self.bar.finish_and_clear();
    }
}
