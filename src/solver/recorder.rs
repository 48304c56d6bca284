//! A recorder of the projection QPs [`super::solve_projection_warm`] is
//! given, for the benchmarks that time solvers on the problems of real
//! calls (`benchmarks/engine_qps.rs`). Off by default: one relaxed atomic
//! load per solve. Not part of the stable API.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::DVector;

use super::outcome::SolverKind;
use super::projection::ProjectionQp;

/// One recorded problem: the QP, the warm start it was given, and what
/// its solve cost in the recorded call.
#[derive(Debug, Clone)]
pub struct RecordedQp {
    /// The problem.
    pub qp: ProjectionQp,
    /// The multipliers it was warm-started from, if any.
    pub warm: Option<DVector<f64>>,
    /// Wall time of its `solve_projection_warm` call (s), validation and
    /// every solver of the fallback chain included.
    pub seconds: f64,
    /// The solver that answered (`None`: every solver failed).
    pub solver: Option<SolverKind>,
}

static ON: AtomicBool = AtomicBool::new(false);
static RECORDED: Mutex<Vec<RecordedQp>> = Mutex::new(Vec::new());

/// Starts recording (and clears what was recorded).
pub fn start() {
    if let Ok(mut recorded) = RECORDED.lock() {
        recorded.clear();
    }
    ON.store(true, Ordering::Relaxed);
}

/// Stops recording and returns the problems recorded since [`start`].
pub fn stop() -> Vec<RecordedQp> {
    ON.store(false, Ordering::Relaxed);
    RECORDED
        .lock()
        .map(|mut recorded| std::mem::take(&mut *recorded))
        .unwrap_or_default()
}

/// Whether recording is on (the caller then times the solve).
pub(crate) fn is_on() -> bool {
    ON.load(Ordering::Relaxed)
}

/// Records `qp`, solved in `seconds` by `solver`, when recording is on.
pub(crate) fn record(
    qp: &ProjectionQp,
    warm: Option<&DVector<f64>>,
    seconds: f64,
    solver: Option<SolverKind>,
) {
    if !is_on() {
        return;
    }
    if let Ok(mut recorded) = RECORDED.lock() {
        recorded.push(RecordedQp {
            qp: qp.clone(),
            warm: warm.cloned(),
            seconds,
            solver,
        });
    }
}
