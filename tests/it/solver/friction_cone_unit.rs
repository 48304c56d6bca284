use constraint_stabilization::solver::friction_cone::*;
use nalgebra::Vector3;

/// The projection is idempotent, lands in `K`, and its residual is
/// orthogonal to it (Moreau: `v = P_K(v) - P_K(-v)`, the two parts
/// orthogonal).
#[test]
fn projection_onto_the_cone_is_moreaus() {
    for v in [
        Vector3::new(1.0, 0.3, -0.2),
        Vector3::new(-1.0, 0.3, -0.2),
        Vector3::new(0.1, 2.0, -1.0),
        Vector3::new(-0.5, 2.0, 1.0),
    ] {
        let p = project_onto_cone(&v);
        let q = project_onto_cone(&-v);
        assert!((p - q - v).norm() < 1e-15, "{v:?}");
        assert!(p.dot(&q).abs() < 1e-15, "{v:?}");
        assert_eq!(cone_violation(&p), 0.0);
        assert!((project_onto_cone(&p) - p).norm() < 1e-15);
    }
}

/// Facet multipliers make a cone multiplier inside `K`, with the force
/// of the facets: `z_0 = sum beta_k`, tangential part at most that.
#[test]
fn facet_multipliers_are_cone_multipliers() {
    let z = cone_multipliers_of_facets(&[0.5, 0.0, 0.25, 1.0]);
    assert!((z - Vector3::new(1.75, -0.25, 1.0)).norm() < 1e-15);
    assert_eq!(cone_violation(&z), 0.0);
}
