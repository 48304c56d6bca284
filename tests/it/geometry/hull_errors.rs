//! Typed errors of `ConvexPolyhedron::from_points` for inputs without a
//! solid hull, and exact answers for inputs with many coplanar and
//! collinear points.

use constraint_stabilization::internals::geometry::{
    ConvexPolyhedron, DUPLICATE_TOLERANCE, FLAT_VERTEX_TOLERANCE, FLATNESS_TOLERANCE, GeometryError,
};
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion};

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

/// The flat-vertex tolerance is below the flatness tolerance, or the apex
/// of a pyramid accepted as a solid would be dropped.
const _: () = assert!(FLAT_VERTEX_TOLERANCE < FLATNESS_TOLERANCE);

#[test]
fn thickness_just_below_the_flatness_tolerance_is_degenerate() {
    // Extent L = diagonal of the bounding box; the apex height relative to
    // L. Below the flatness tolerance: degenerate at once; below the
    // flat-vertex tolerance: the apex is dropped, then degenerate; just
    // above the flatness tolerance (so above the flat-vertex tolerance,
    // which is smaller) and well above it: a pyramid that keeps its apex.
    for (relative, expect_ok) in [
        (0.5 * FLATNESS_TOLERANCE, false),
        (0.5 * FLAT_VERTEX_TOLERANCE, false),
        (2.0 * FLATNESS_TOLERANCE, true),
        (100.0 * FLATNESS_TOLERANCE, true),
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
        if let Ok(pyramid) = result {
            assert_eq!(pyramid.vertices().len(), 5, "{relative:e}: apex dropped");
        }
    }
}

/// The corners of the slab `[-1, 1]² × [-t, t]` and its centre.
fn slab(t: f64) -> Vec<Point3<f64>> {
    let mut points: Vec<_> = (0..8)
        .map(|i| {
            let s = |bit: usize| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
            p(s(0), s(1), s(2) * t)
        })
        .collect();
    points.push(p(0.0, 0.0, 0.0));
    points
}

/// Relative accuracy demanded of the volume and inertia of an
/// axis-aligned slab: its coordinates are exact, so only the rounding of
/// the tetrahedron sums, about `ε T / t` for `T = 12` triangles and
/// relative thickness `t >= 1e-8`, enters.
const SLAB_MASS_TOLERANCE: f64 = 1e-6;

/// Regression (`tests/it/geometry/hull.proptest-regressions`): the slab
/// `[-1, 1]² × [-t, t]` with `t = 7.28e-7` and its centre came back as a
/// tetrahedron. Its sides, `2t = 1.46e-6` wide, were below the old
/// thin-face tolerance `1e-6 max(L, M) = 2.83e-6`, so each lost two
/// corners, though the slab is 50 times thicker than the flatness
/// tolerance `FLATNESS_TOLERANCE * L = 2.83e-8`. Every slab above the
/// flatness tolerance (down to twice it) is its box, with the closed-form
/// volume `8 t` and inertia `m (b² + c²) / 3` (half extents `a, b, c`,
/// `m = 8 a b c`); below it (a quarter), it is flat.
#[test]
fn thin_slab_keeps_its_eight_corners() {
    let extent = 2.0 * 2f64.sqrt();
    for t in [
        1e-1,
        1e-5,
        7.282523544542664e-7,
        1e-7,
        FLATNESS_TOLERANCE * extent,
    ] {
        let points = slab(t);
        let hull = ConvexPolyhedron::from_points(&points).unwrap();
        let counts = (
            hull.vertices().len(),
            hull.edges().len(),
            hull.faces().len(),
        );
        assert_eq!(counts, (8, 12, 6), "t = {t:e}");
        for v in hull.vertices() {
            let corner = v + hull.shape_origin_offset();
            assert!(points[..8].contains(&corner), "t = {t:e}: {corner}");
        }
        let mass = 8.0 * t;
        let relative = |ours: f64, exact: f64| (ours - exact).abs() / exact;
        assert!(relative(hull.volume(), mass) <= SLAB_MASS_TOLERANCE);
        let inertia = hull.mass_properties().inertia_unit_density;
        let exact = [
            mass * (1.0 + t * t) / 3.0,
            mass * (1.0 + t * t) / 3.0,
            mass * 2.0 / 3.0,
        ];
        for (axis, exact) in exact.into_iter().enumerate() {
            let ours = inertia[(axis, axis)];
            assert!(
                relative(ours, exact) <= SLAB_MASS_TOLERANCE,
                "t = {t:e}, axis {axis}: {ours:e} vs {exact:e}"
            );
        }
    }
    let flat = ConvexPolyhedron::from_points(&slab(0.25 * FLATNESS_TOLERANCE * extent));
    assert_eq!(flat, Err(GeometryError::Degenerate));
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

/// Regression: the same slab rotated and moved (coordinates rounded at
/// `ε M`, `M ≈ 8`) came back with one side split into two triangles
/// (8 vertices, 13 edges, 7 faces): the normal of the seed triangle of that
/// side, taken from its two long sides, was tilted by about `1e-11` rad
/// (`ε l / w` for length `l = 2`, width `w = 1.46e-6`), which put the twin
/// triangle's far corner farther from its plane than the coplanar
/// tolerance `1e-12 max(L, M) ≈ 8e-12`. Taken at the right-angle corner,
/// the normal is accurate to rounding and the side is one face.
#[test]
fn rotated_thin_slab_has_six_faces() {
    let t = 7.282523544542664e-7;
    let rotation = UnitQuaternion::new_unchecked(Quaternion::new(
        0.4308014492319006,
        0.7162965032679525,
        0.0,
        0.5489348146599908,
    ));
    let pose = Isometry3::from_parts(Translation3::new(0.0, -6.7276812043874665, 0.0), rotation);
    let points: Vec<_> = slab(t).iter().map(|q| pose * q).collect();
    let hull = ConvexPolyhedron::from_points(&points).unwrap();
    let counts = (
        hull.vertices().len(),
        hull.edges().len(),
        hull.faces().len(),
    );
    assert_eq!(counts, (8, 12, 6));
}
