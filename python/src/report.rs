//! A call's [`Report`] as plain Python objects (a `dict` of numbers,
//! strings and lists), which the Python layer wraps in its `Report`
//! dataclass.

use constraint_stabilization::Report;
use constraint_stabilization::stabilizer::PairPenetration;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// `CamelCase` as `snake_case` (a solver's name from its `Debug` text).
fn snake_case(camel: &str) -> String {
    let mut out = String::with_capacity(camel.len() + 4);
    for (i, c) in camel.chars().enumerate() {
        if c.is_ascii_uppercase() {
            if i > 0 {
                out.push('_');
            }
            out.push(c.to_ascii_lowercase());
        } else {
            out.push(c);
        }
    }
    out
}

/// Penetrating pairs as `(body_a, body_b, depth)` tuples.
fn pairs(penetrations: &[PairPenetration]) -> Vec<(usize, usize, f64)> {
    penetrations
        .iter()
        .map(|p| (p.body_a, p.body_b, p.depth))
        .collect()
}

/// The report as a `dict` (keys as the Python `Report`'s fields).
pub fn report_dict<'py>(py: Python<'py>, report: &Report) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("status", report.status.name())?;
    d.set_item("converged", report.status.is_resolved())?;
    d.set_item("passes", report.passes)?;
    d.set_item("scale", report.scale)?;
    d.set_item("tolerance", report.tolerance)?;
    d.set_item("depth_before", report.depth_before)?;
    d.set_item("depth_after", report.depth_after)?;
    d.set_item("penetrations_before", pairs(&report.penetrations_before))?;
    d.set_item("penetrations_after", pairs(&report.penetrations_after))?;
    d.set_item("displacement", report.displacement)?;
    d.set_item("bodies_moved", report.bodies_moved)?;
    d.set_item("restored_input", report.restored_input)?;
    d.set_item("pair_queries", report.pair_queries)?;
    d.set_item("certified_pairs", report.certified_pairs)?;
    d.set_item("reused_pairs", report.reused_pairs)?;
    let left = PyList::empty(py);
    for island in &report.islands_left {
        let entry = PyDict::new(py);
        entry.set_item("bodies", island.bodies.clone())?;
        entry.set_item("reason", island.outcome.reason())?;
        left.append(entry)?;
    }
    d.set_item("islands_left", left)?;
    let islands = PyList::empty(py);
    for (pass, pass_report) in report.pass_reports.iter().enumerate() {
        for island in &pass_report.solved {
            let entry = PyDict::new(py);
            entry.set_item("pass_index", pass)?;
            entry.set_item("bodies", island.bodies.clone())?;
            entry.set_item("outcome", island.outcome.reason())?;
            entry.set_item(
                "solver",
                island.solver.map(|kind| snake_case(&format!("{kind:?}"))),
            )?;
            entry.set_item("constraints", island.constraints)?;
            entry.set_item("depth_before", island.depth_before)?;
            entry.set_item("depth_after", island.depth_after)?;
            islands.append(entry)?;
        }
    }
    d.set_item("islands", islands)?;
    let times = PyDict::new(py);
    times.set_item("broad_phase", report.times.broad_phase)?;
    times.set_item("narrow_phase", report.times.narrow_phase)?;
    times.set_item("solve", report.times.solve)?;
    times.set_item("line_search", report.times.line_search)?;
    times.set_item("total", report.times.total)?;
    d.set_item("times", times)?;
    Ok(d)
}
