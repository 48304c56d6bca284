//! The Siconos LCP files of `tests/data/siconos` and what their README
//! says about each: the folder, and the unique solutions listed there.

/// The folder of the `.dat` files, inside the repository.
pub const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/siconos");

/// The path of one file of [`DATA`].
pub fn path(name: &str) -> String {
    format!("{DATA}/{name}")
}

/// The unique solution the README's table lists for `name` ("z = [...]"),
/// or `None` where it lists several, none or only "exists".
pub fn known_solution(name: &str) -> Option<Vec<f64>> {
    let z: &[f64] = match name {
        "lcp_CPS_2.dat" => &[0.0, 1.0, 3.0],
        "lcp_CPS_4.dat" => &[2.0, 2.0, 2.0, 92.0],
        "lcp_CPS_4bis.dat" => &[3.0, 3.0, 0.0, 83.0],
        "lcp_CPS_5.dat" => &[0.0, 1.0],
        "lcp_Pang_isolated_sol.dat" => &[1.0, 0.0, 0.0],
        "lcp_deudeu.dat" => &[4.0 / 3.0, 7.0 / 3.0],
        "lcp_exp_murty.dat" => &[0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
        "lcp_exp_murty2.dat" => &[0.0, 0.0, 0.0, 0.0, 0.0, 64.0],
        "lcp_inf_sol_perturbed.dat" => &[1.0, 0.0, 1e-4],
        "lcp_ortiz.dat" => &[2.0 / 3.0, 0.0, 1.0 / 3.0, 0.0],
        "lcp_trivial.dat" => &[
            1.0,
            0.5,
            1.0 / 3.0,
            0.25,
            0.2,
            1.0 / 6.0,
            1.0 / 7.0,
            0.125,
            1.0 / 9.0,
        ],
        _ => return None,
    };
    Some(z.to_vec())
}

/// Panics unless `z` equals `expected` to `tol` relative to
/// `max(1, ||expected||_inf)`.
pub fn assert_close(name: &str, z: &[f64], expected: &[f64], tol: f64) {
    assert_eq!(z.len(), expected.len(), "{name}: size of z");
    let scale = expected.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (i, (a, b)) in z.iter().zip(expected).enumerate() {
        assert!(
            (a - b).abs() <= tol * scale,
            "{name}: z[{i}] = {a}, expected {b}"
        );
    }
}
