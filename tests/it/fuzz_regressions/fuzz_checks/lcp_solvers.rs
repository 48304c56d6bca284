//! LCP file reader plus every solver: any text either fails to parse with
//! a typed error or gives an LCP on which Lemke, PGS and clarabel (dual
//! QP, where M is symmetric positive semidefinite) either fail with a
//! status or return a `z` that solves the LCP, checked here by the natural
//! map `||min(z, Mz + q)||_inf` relative to the data.

use constraint_stabilization::io::lcp_file::parse_lcp;
use constraint_stabilization::solver::Lcp;
use constraint_stabilization::solver::clarabel_qp::{ClarabelSettings, dual};
use constraint_stabilization::solver::lemke::{self, LemkeSettings};
use constraint_stabilization::solver::pgs::{self, PgsSettings};
use nalgebra::DVector;

/// Larger problems are skipped (Lemke's tableau is dense).
const MAX_N: usize = 48;

/// A returned `z` must satisfy `||min(z, w)||_inf <= ACCEPT * s`, `s` the
/// size of the data at `z`: `max(1, |q|_inf, |M|_inf |z|_inf)`. The solvers
/// accept on their own scaled measures at 1e-9..1e-6; rescaling costs at
/// most the conditioning of the diagonal, which this allows for.
const ACCEPT: f64 = 1e-5;

fn check_solution(solver: &str, lcp: &Lcp, z: &DVector<f64>) {
    assert!(z.iter().all(|x| x.is_finite()), "{solver}: non-finite z");
    let w = lcp.m() * z + lcp.q();
    let natural = z.zip_map(&w, f64::min).amax();
    if std::env::var_os("FUZZ_DEBUG").is_some() {
        println!("{solver}: M {} q {} z {z} w {w}", lcp.m(), lcp.q());
    }
    let size = 1f64.max(lcp.q().amax()).max(lcp.m().amax() * z.amax());
    assert!(
        natural <= ACCEPT * size,
        "{solver}: ||min(z, w)|| = {natural:e}, data size {size:e}"
    );
}

/// The check (module docs).
pub fn check(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(lcp) = parse_lcp(text) else {
        return;
    };
    if lcp.n() > MAX_N {
        return;
    }
    if let Ok(solution) = lemke::solve(&lcp, &LemkeSettings::default()) {
        check_solution("lemke", &lcp, &solution.z);
    }
    if let Ok(solution) = pgs::solve(&lcp, &PgsSettings::default()) {
        check_solution("pgs", &lcp, &solution.z);
    }
    if let Ok(solution) = dual::solve_lcp(&lcp, &ClarabelSettings::default()) {
        check_solution("clarabel", &lcp, &solution.z);
    }
}
