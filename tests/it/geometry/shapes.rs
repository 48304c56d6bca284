//! Mirtich's test shapes: counts against the closed forms
//! `V = 10·4^k + 2, E = 30·4^k, F = 20·4^k` (icosphere), `2n, 3n, n + 2`
//! (prism), volumes against closed forms, and argument validation.

use std::f64::consts::{PI, TAU};

use approx::assert_relative_eq;
use constraint_stabilization::internals::geometry::{
    ConvexPolyhedron, GeometryError, MAX_GEODESIC_SUBDIVISIONS,
};

fn counts(shape: &ConvexPolyhedron) -> (usize, usize, usize) {
    (
        shape.vertices().len(),
        shape.edges().len(),
        shape.faces().len(),
    )
}

#[test]
fn icosahedron_counts_volume_and_radius() {
    let circumradius = 2.5;
    let ico = ConvexPolyhedron::icosahedron(circumradius).unwrap();
    assert_eq!(counts(&ico), (12, 30, 20));
    // Edge a = R / sin(2π/5); V = 5/12 (3 + √5) a³.
    let edge = circumradius / (TAU / 5.0).sin();
    let volume = 5.0 / 12.0 * (3.0 + 5.0_f64.sqrt()) * edge.powi(3);
    assert_relative_eq!(ico.volume(), volume, max_relative = 1e-12);
    for v in ico.vertices() {
        assert_relative_eq!(v.coords.norm(), circumradius, max_relative = 1e-12);
    }
    for e in ico.edges() {
        assert_relative_eq!(e.length, edge, max_relative = 1e-12);
    }
    // Solid regular icosahedron: isotropic inertia I = φ²/10 m a².
    let phi = 0.5 * (1.0 + 5.0_f64.sqrt());
    let inertia = ico.mass_properties().inertia_unit_density;
    let mean = inertia.trace() / 3.0;
    assert_relative_eq!(
        mean,
        phi * phi / 10.0 * volume * edge * edge,
        max_relative = 1e-12
    );
    for i in 0..3 {
        for j in 0..3 {
            let expected = if i == j { mean } else { 0.0 };
            assert!((inertia[(i, j)] - expected).abs() <= 1e-12 * mean);
        }
    }
}

#[test]
fn mirtich_disk_counts_and_volume() {
    let (radius, thickness, sides) = (1.0, 0.1, 60);
    let disk = ConvexPolyhedron::disk(radius, thickness, sides).unwrap();
    assert_eq!(counts(&disk), (120, 180, 62));
    let area = 0.5 * sides as f64 * radius * radius * (TAU / sides as f64).sin();
    assert_relative_eq!(disk.volume(), area * thickness, max_relative = 1e-12);
    // Prism about its axis: I_zz = m r² (2 + cos(2π/n)) / 6 for a regular
    // n-gon of circumradius r (polar moment of the polygon).
    let izz = disk.volume() * radius * radius * (2.0 + (TAU / sides as f64).cos()) / 6.0;
    let inertia = disk.mass_properties().inertia_unit_density;
    assert_relative_eq!(inertia[(2, 2)], izz, max_relative = 1e-10);
    let sides_normals_horizontal = disk
        .faces()
        .iter()
        .filter(|f| f.plane.normal.z.abs() < 1e-12)
        .count();
    assert_eq!(sides_normals_horizontal, sides);
}

#[test]
fn triangular_disk_is_the_smallest() {
    let disk = ConvexPolyhedron::disk(1.0, 1.0, 3).unwrap();
    assert_eq!(counts(&disk), (6, 9, 5));
}

#[test]
fn geodesic_sphere_counts_match_closed_form() {
    for k in 0..=4 {
        let sphere = ConvexPolyhedron::geodesic_sphere(1.0, k).unwrap();
        let p = 4usize.pow(k as u32);
        assert_eq!(counts(&sphere), (10 * p + 2, 30 * p, 20 * p), "k = {k}");
    }
    let mirtich = ConvexPolyhedron::geodesic_sphere(1.0, 3).unwrap();
    assert_eq!(counts(&mirtich), (642, 1920, 1280));
}

#[test]
fn geodesic_sphere_volume_is_between_inscribed_and_circumscribed() {
    let radius = 3.0;
    let sphere = ConvexPolyhedron::geodesic_sphere(radius, 3).unwrap();
    let ball = 4.0 / 3.0 * PI * radius.powi(3);
    // Every vertex on the sphere, so the hull is inside the ball; the
    // nearest face plane bounds the inscribed ball.
    let inradius = sphere
        .faces()
        .iter()
        .map(|f| -f.plane.offset)
        .fold(f64::INFINITY, f64::min);
    assert!(sphere.volume() < ball);
    assert!(sphere.volume() > 4.0 / 3.0 * PI * inradius.powi(3));
    // Brute-force volume: sum of cone volumes over faces from the centre.
    let cones: f64 = sphere
        .faces()
        .iter()
        .map(|f| {
            let v = |i: usize| sphere.vertices()[f.vertices[i]].coords;
            v(0).dot(&v(1).cross(&v(2))) / 6.0
        })
        .sum();
    assert_relative_eq!(sphere.volume(), cones, max_relative = 1e-12);
    assert!((sphere.volume() - ball).abs() < 0.02 * ball);
    for v in sphere.vertices() {
        assert_relative_eq!(v.coords.norm(), radius, max_relative = 1e-12);
    }
}

#[test]
fn invalid_shape_arguments_are_typed_errors() {
    assert!(matches!(
        ConvexPolyhedron::icosahedron(0.0),
        Err(GeometryError::InvalidDimension {
            name: "circumradius",
            ..
        })
    ));
    assert!(matches!(
        ConvexPolyhedron::icosahedron(f64::NAN),
        Err(GeometryError::InvalidDimension { .. })
    ));
    assert!(matches!(
        ConvexPolyhedron::disk(-1.0, 0.1, 60),
        Err(GeometryError::InvalidDimension { name: "radius", .. })
    ));
    assert!(matches!(
        ConvexPolyhedron::disk(1.0, f64::INFINITY, 60),
        Err(GeometryError::InvalidDimension {
            name: "thickness",
            ..
        })
    ));
    assert!(matches!(
        ConvexPolyhedron::disk(1.0, 0.1, 2),
        Err(GeometryError::InvalidCount {
            name: "sides",
            value: 2,
            ..
        })
    ));
    assert!(matches!(
        ConvexPolyhedron::geodesic_sphere(1.0, MAX_GEODESIC_SUBDIVISIONS + 1),
        Err(GeometryError::InvalidCount {
            name: "subdivisions",
            ..
        })
    ));
    assert!(matches!(
        ConvexPolyhedron::geodesic_sphere(0.0, 1),
        Err(GeometryError::InvalidDimension { name: "radius", .. })
    ));
}
