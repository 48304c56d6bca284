//! `stabilize lcp`: JSON output and exit codes on the Siconos files. Every
//! printed `z` is checked against the file's `M` and `q` here
//! (`crate::support::solver_oracle`) and against the README's solution where it is
//! unique (`crate::support::siconos`).

use std::process::Command;

use crate::support::siconos::{DATA, assert_close, known_solution};
use crate::support::solver_oracle::{LCP_TOL, assert_lcp_solved};
use constraint_stabilization::io::read_lcp_file;
use nalgebra::DVector;
use serde_json::Value;

/// Distance of an iterative solver's `z` (PGS, clarabel: stopped at a
/// natural-map residual of `LCP_TOL`) from the exact solution, relative to
/// its size: the residual amplified by the conditioning of the positive
/// definite `M` of the files used (deudeu, trivial, mmc). Measured worst:
/// 1.2e-10 (clarabel on deudeu).
const ITERATIVE_Z_TOL: f64 = 1e-8;

fn run(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_stabilize"))
        .args(args)
        .output()
        .unwrap();
    let code = out.status.code().unwrap_or(-1);
    (
        code,
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn vector(v: &Value) -> DVector<f64> {
    DVector::from_iterator(
        v.as_array().unwrap().len(),
        v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()),
    )
}

#[test]
fn lemke_on_every_file() {
    let mut names: Vec<String> = std::fs::read_dir(DATA)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
        .filter(|n| n.ends_with(".dat"))
        .collect();
    names.sort();
    assert_eq!(names.len(), 17);
    for name in names {
        let path = format!("{DATA}/{name}");
        let (code, stdout, stderr) = run(&["lcp", &path, "--solver", "lemke"]);
        let json: Value = serde_json::from_str(&stdout)
            .unwrap_or_else(|e| panic!("{name}: {e}: {stdout} {stderr}"));
        assert_eq!(json["solver"], "lemke");
        assert!(json["pivots"].as_u64().is_some(), "{name}");
        assert!(json["time_s"].as_f64().unwrap() >= 0.0, "{name}");
        let unsolvable = ["lcp_Pang_isolated_sol_perturbed.dat", "lcp_CPS_3.dat"];
        if unsolvable.contains(&name.as_str()) {
            assert_eq!(code, 1, "{name}");
            assert_eq!(json["status"], "ray_termination", "{name}");
            assert!(json["z"].is_null());
            continue;
        }
        assert_eq!(code, 0, "{name}: {stdout}");
        assert_eq!(json["status"], "solved");
        // The printed z, checked against the file's data here.
        let lcp = read_lcp_file(&path).unwrap();
        let z = vector(&json["z"]);
        assert_lcp_solved(lcp.m(), lcp.q(), &z, LCP_TOL, &name);
        if let Some(expected) = known_solution(&name) {
            assert_close(&name, z.as_slice(), &expected, LCP_TOL);
        }
        let w = lcp.m() * &z + lcp.q();
        assert!(
            (vector(&json["w"]) - w).amax() <= LCP_TOL * lcp.q().amax().max(1.0),
            "{name}"
        );
        assert!(json["residual"].as_f64().unwrap() <= LCP_TOL);
    }
}

/// Runs `stabilize lcp FILE --solver SOLVER`, expects success, and returns
/// the printed `z` after checking it solves the file's LCP.
fn solved_z(name: &str, solver: &str) -> DVector<f64> {
    let path = format!("{DATA}/{name}");
    let (code, stdout, stderr) = run(&["lcp", &path, "--solver", solver]);
    assert_eq!(code, 0, "{name} {solver}: {stdout} {stderr}");
    let json: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(json["solver"], solver, "{name}");
    assert_eq!(json["status"], "solved", "{name} {solver}");
    assert!(json["iterations"].as_u64().unwrap() > 0, "{name} {solver}");
    let z = vector(&json["z"]);
    let lcp = read_lcp_file(&path).unwrap();
    assert_lcp_solved(lcp.m(), lcp.q(), &z, LCP_TOL, &format!("{name} {solver}"));
    z
}

/// clarabel and PGS on the positive definite files: each printed `z`
/// solves the file's LCP, equals the README's solution where listed, and
/// on mmc (unique solution, not listed) equals Lemke's.
#[test]
fn clarabel_and_pgs_where_they_apply() {
    for solver in ["clarabel", "pgs"] {
        for name in ["lcp_deudeu.dat", "lcp_trivial.dat"] {
            let z = solved_z(name, solver);
            let expected = known_solution(name).expect("listed in the README");
            assert_close(name, z.as_slice(), &expected, ITERATIVE_Z_TOL);
        }
        let z = solved_z("lcp_mmc.dat", solver);
        let lemke = solved_lemke_z("lcp_mmc.dat");
        assert_close("mmc", z.as_slice(), lemke.as_slice(), ITERATIVE_Z_TOL);
    }
    // mmc needs more than one PGS sweep.
    let (_, stdout, _) = run(&["lcp", &format!("{DATA}/lcp_mmc.dat"), "--solver", "pgs"]);
    let json: Value = serde_json::from_str(&stdout).unwrap();
    assert!(json["iterations"].as_u64().unwrap() > 1);
}

/// Lemke's printed `z` (it reports pivots, not iterations).
fn solved_lemke_z(name: &str) -> DVector<f64> {
    let (code, stdout, _) = run(&["lcp", &format!("{DATA}/{name}"), "--solver", "lemke"]);
    assert_eq!(code, 0, "{name}");
    vector(&serde_json::from_str::<Value>(&stdout).unwrap()["z"])
}

#[test]
fn clarabel_refuses_a_nonsymmetric_matrix() {
    let (code, stdout, stderr) = run(&[
        "lcp",
        &format!("{DATA}/lcp_CPS_2.dat"),
        "--solver",
        "clarabel",
    ]);
    assert_eq!(code, 2);
    assert!(stdout.is_empty());
    assert!(
        stderr.contains("symmetric positive semidefinite"),
        "{stderr}"
    );
}

#[test]
fn bad_input_exits_with_2() {
    let dir = std::env::temp_dir().join(format!("stabilize-lcp-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        ("truncated.dat", "2\n0\n2\n2\n2 2\n1 0 0 1\n-1\n"),
        ("nan.dat", "1 0 1 1 1 1 NaN -1\n"),
        ("text.dat", "hello\n"),
    ];
    for (file, text) in cases {
        let path = dir.join(file);
        std::fs::write(&path, text).unwrap();
        let (code, stdout, stderr) = run(&["lcp", path.to_str().unwrap()]);
        assert_eq!(code, 2, "{file}: {stdout} {stderr}");
        assert!(stdout.is_empty(), "{file}");
        assert!(!stderr.is_empty(), "{file}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(run(&["lcp", "/nonexistent/file.dat"]).0, 2);
    assert_eq!(run(&["lcp"]).0, 2);
    assert_eq!(
        run(&[
            "lcp",
            &format!("{DATA}/lcp_CPS_1.dat"),
            "--solver",
            "simplex"
        ])
        .0,
        2
    );
}
