//! Typed errors of `ConvexPolyhedron::from_points` for inputs without a
//! solid hull, and exact answers for inputs with many coplanar and
//! collinear points.

use constraint_stabilization::geometry::{
    ConvexPolyhedron, DUPLICATE_TOLERANCE, FLAT_VERTEX_TOLERANCE, FLATNESS_TOLERANCE, GeometryError,
};
use nalgebra::Point3;

fn p(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(x, y, z)
}

fn tetrahedron() -> Vec<Point3<f64>> {
    vec![
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(0.0, 0.0, 1.0),
    ]
}

#[test]
fn empty_set_is_an_error() {
    assert_eq!(
        ConvexPolyhedron::from_points(&[]),
        Err(GeometryError::Empty)
    );
}

#[test]
fn non_finite_coordinates_name_the_point() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut points = tetrahedron();
        points.insert(3, p(0.5, bad, 0.5));
        assert_eq!(
            ConvexPolyhedron::from_points(&points),
            Err(GeometryError::NonFinite { index: 3 })
        );
    }
}

#[test]
fn all_equal_points_are_degenerate() {
    let equal = vec![p(1.0, 2.0, 3.0); 10];
    assert_eq!(
        ConvexPolyhedron::from_points(&equal),
        Err(GeometryError::Degenerate)
    );
    assert_eq!(
        ConvexPolyhedron::from_points(&equal[..1]),
        Err(GeometryError::Degenerate)
    );
}

#[test]
fn collinear_points_are_degenerate() {
    let collinear: Vec<_> = (0..10)
        .map(|i| p(i as f64, 2.0 * i as f64, -(i as f64)))
        .collect();
    assert_eq!(
        ConvexPolyhedron::from_points(&collinear),
        Err(GeometryError::Degenerate)
    );
}

#[test]
fn coplanar_points_are_degenerate() {
    let coplanar: Vec<_> = (0..30)
        .map(|i| p((i % 7) as f64, (i % 5) as f64, 1.0))
        .collect();
    assert_eq!(
        ConvexPolyhedron::from_points(&coplanar),
        Err(GeometryError::Degenerate)
    );
    let three = &tetrahedron()[..3];
    assert_eq!(
        ConvexPolyhedron::from_points(three),
        Err(GeometryError::Degenerate)
    );
}

#[test]
fn thickness_just_below_the_flatness_tolerance_is_degenerate() {
    // Extent L = diagonal of the bounding box; the apex height relative to
    // L. Below the flatness tolerance: degenerate at once; below the
    // flat-vertex tolerance: the apex is dropped, then degenerate; well
    // above it: a pyramid.
    for (relative, expect_ok) in [
        (0.5 * FLATNESS_TOLERANCE, false),
        (0.5 * FLAT_VERTEX_TOLERANCE, false),
        (100.0 * FLAT_VERTEX_TOLERANCE, true),
    ] {
        let mut points = vec![
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(1.0, 1.0, 0.0),
        ];
        let extent = 2f64.sqrt();
        points.push(p(0.3, 0.3, relative * extent));
        let result = ConvexPolyhedron::from_points(&points);
        assert_eq!(result.is_ok(), expect_ok, "{relative:e}: {result:?}");
    }
}

#[test]
fn near_duplicates_are_merged_before_the_volume_check() {
    // Five points, but the fourth and fifth are within the merge tolerance
    // of the second and first: three distinct points remain.
    let tiny = 0.1 * DUPLICATE_TOLERANCE;
    let near = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(1.0, tiny, 0.0),
        p(tiny, 0.0, tiny),
    ];
    assert_eq!(
        ConvexPolyhedron::from_points(&near),
        Err(GeometryError::Degenerate)
    );
}

#[test]
fn near_duplicate_vertices_are_kept_once() {
    let tiny = 0.1 * DUPLICATE_TOLERANCE;
    let mut points = tetrahedron();
    points.extend(
        tetrahedron()
            .iter()
            .map(|q| q + nalgebra::Vector3::new(tiny, -tiny, tiny)),
    );
    let hull = ConvexPolyhedron::from_points(&points).unwrap();
    assert_eq!((hull.vertices().len(), hull.faces().len()), (4, 4));
    // Of each pair the one with the smaller x is kept: the original.
    for v in hull.vertices() {
        let q = v + hull.shape_origin_offset();
        assert!(tetrahedron().iter().any(|t| (t - q).norm() < 1e-15));
    }
}

#[test]
fn huge_coordinates_are_an_error() {
    let huge = [
        p(-1e308, 0.0, 0.0),
        p(1e308, 0.0, 0.0),
        p(0.0, 1e308, 0.0),
        p(0.0, 0.0, 1e308),
    ];
    assert!(matches!(
        ConvexPolyhedron::from_points(&huge),
        Err(GeometryError::CoordinatesOutOfRange { .. })
    ));
}

#[test]
fn lattice_cube_has_eight_vertices_and_six_quads() {
    let mut points = Vec::new();
    for i in 0..5 {
        for j in 0..5 {
            for k in 0..5 {
                points.push(p(i as f64, j as f64, k as f64) * 0.5);
            }
        }
    }
    let hull = ConvexPolyhedron::from_points(&points).unwrap();
    assert_eq!(
        (
            hull.vertices().len(),
            hull.edges().len(),
            hull.faces().len()
        ),
        (8, 12, 6)
    );
    assert!((hull.volume() - 8.0).abs() < 1e-12);
    for face in hull.faces() {
        assert_eq!(face.vertices.len(), 4);
    }
}

#[test]
fn octahedron_with_points_inside_and_on_faces() {
    let mut points = vec![
        p(1.0, 0.0, 0.0),
        p(-1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(0.0, -1.0, 0.0),
        p(0.0, 0.0, 1.0),
        p(0.0, 0.0, -1.0),
    ];
    points.push(p(0.1, 0.2, -0.1));
    points.push(p(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0)); // centre of a face
    points.push(p(0.5, 0.5, 0.0)); // middle of an edge
    let hull = ConvexPolyhedron::from_points(&points).unwrap();
    assert_eq!(
        (
            hull.vertices().len(),
            hull.edges().len(),
            hull.faces().len()
        ),
        (6, 12, 8)
    );
    assert!((hull.volume() - 4.0 / 3.0).abs() < 1e-12);
}

#[test]
fn tiny_extent_is_an_error() {
    let tiny: Vec<_> = tetrahedron().iter().map(|q| q * 1e-60).collect();
    assert!(matches!(
        ConvexPolyhedron::from_points(&tiny),
        Err(GeometryError::CoordinatesOutOfRange { .. })
    ));
}

#[test]
fn extreme_but_supported_scales_build() {
    for scale in [1e-45, 1e-20, 1e20, 1e45] {
        let points: Vec<_> = tetrahedron().iter().map(|q| q * scale).collect();
        let hull = ConvexPolyhedron::from_points(&points).unwrap();
        let volume = scale.powi(3) / 6.0;
        assert!(
            (hull.volume() - volume).abs() <= 1e-12 * volume,
            "{scale:e}"
        );
        let inertia = hull.mass_properties().inertia_unit_density;
        assert!(inertia.iter().all(|c| c.is_finite()) && inertia[(0, 0)] > 0.0);
    }
}

/// A point outside one face of a cube and next to its edge makes a sliver
/// triangle with that edge, as wide as the point's distance to the edge.
/// Below the thin-face tolerance the point is dropped (the sliver's plane
/// would be unreliable); well above it, it is kept as a vertex.
#[test]
fn point_just_outside_an_edge_is_dropped_and_far_outside_kept() {
    let cube = |offset: f64| {
        let mut points: Vec<_> = (0..8)
            .map(|i| {
                let s = |bit: usize| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
                p(s(0), s(1), s(2))
            })
            .collect();
        points.push(p(0.3, 1.0 + offset, 1.0 - offset));
        points
    };
    let thin = ConvexPolyhedron::from_points(&cube(1e-9)).unwrap();
    assert_eq!((thin.vertices().len(), thin.faces().len()), (8, 6));
    let kept = ConvexPolyhedron::from_points(&cube(1e-3)).unwrap();
    assert_eq!(kept.vertices().len(), 9);
}
