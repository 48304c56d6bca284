use constraint_stabilization::internals::projector::friction::*;
use constraint_stabilization::internals::rows::ConstraintRow;
use constraint_stabilization::internals::rows::{RowFriction, RowKind};
use constraint_stabilization::solver::JacobianRow;
use nalgebra::{Vector3, Vector6};

/// One contact of body 0 against a fixed body: normal z, tangents x
/// and y, at the centre of mass (no lever), penetrating by `depth`.
fn row(mu: f64, depth: f64) -> ConstraintRow {
    let block = |v: Vector3<f64>| vec![(0, Vector6::new(v.x, v.y, v.z, 0.0, 0.0, 0.0))];
    ConstraintRow {
        kind: RowKind::Inequality,
        phi: -depth,
        blocks: block(Vector3::z()),
        friction: Some(RowFriction {
            mu,
            tangents: [block(Vector3::x()), block(Vector3::y())],
        }),
    }
}

/// Whether a translation `dq` of the body satisfies every facet (2).
fn allowed(rows: &[JacobianRow], phi: &[f64], dq: Vector3<f64>) -> bool {
    rows.iter().zip(phi).all(|(row, &phi)| {
        let j = row.blocks[0].1.fixed_rows::<3>(0).into_owned();
        phi + j.dot(&dq) >= -1e-15
    })
}

/// (1) with `mu` on the sliding side: a contact that opens by `s` beyond
/// its required correction may slide `s / mu` along a facet's
/// direction, not more; a larger `mu` allows less sliding, and the
/// facets' forces have tangential to normal ratio `mu` (Coulomb).
#[test]
fn more_friction_allows_less_sliding() {
    let (depth, target, opening) = (0.01, 0.001, 0.004);
    for mu in [0.25, 0.5, 2.0] {
        let (rows, phi, parents) = pyramid_rows(&[row(mu, depth)], target, 4);
        assert_eq!((rows.len(), parents), (4, vec![0; 4]));
        assert!(phi.iter().all(|&p| (p + depth + target).abs() < 1e-15));
        let dn = depth + target + opening;
        let limit = opening / mu;
        assert!(allowed(&rows, &phi, Vector3::new(0.999 * limit, 0.0, dn)));
        assert!(!allowed(&rows, &phi, Vector3::new(1.001 * limit, 0.0, dn)));
        assert!(!allowed(
            &rows,
            &phi,
            Vector3::new(0.0, 0.0, depth + target - 1e-9)
        ));
        for facet in &rows {
            let f = facet.blocks[0].1.fixed_rows::<3>(0).into_owned();
            let ratio = Vector3::new(f.x, f.y, 0.0).norm() / f.z;
            assert!((ratio - mu).abs() < 1e-12, "{ratio} for mu {mu}");
        }
    }
}
