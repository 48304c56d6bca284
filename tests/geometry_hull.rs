//! `ConvexPolyhedron::from_points` against oracles this project did not
//! write: parry3d-f64's own hull and mass properties, and brute force over
//! the input points (support functions, containment).

use constraint_stabilization::geometry::{
    ConvexPolyhedron, GeometryError, point_to_parry, vector_from_parry,
};
use nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use parry3d_f64::mass_properties::MassProperties;
use parry3d_f64::mass_properties::details::tetrahedron_unit_inertia_tensor_wrt_point;
use parry3d_f64::math::Vector as ParryVector;
use parry3d_f64::shape::{ConvexPolyhedron as ParryConvexPolyhedron, Shape, Tetrahedron};
use proptest::prelude::*;

/// Relative agreement demanded of mass properties with parry's.
const MASS_TOLERANCE: f64 = 1e-9;

/// Containment and support tolerance, relative to the extent of the input.
const GEOMETRY_TOLERANCE: f64 = 1e-9;

fn extent(points: &[Point3<f64>]) -> f64 {
    let (lo, hi) = points
        .iter()
        .fold((points[0].coords, points[0].coords), |(lo, hi), p| {
            (lo.inf(&p.coords), hi.sup(&p.coords))
        });
    (hi - lo).norm()
}

fn to_shape_frame(hull: &ConvexPolyhedron, p_body: &Point3<f64>) -> Point3<f64> {
    p_body + hull.shape_origin_offset()
}

/// Every property the hull of `points` must have, checked by brute force
/// and against parry.
fn check_hull(points: &[Point3<f64>], hull: &ConvexPolyhedron) -> Result<(), TestCaseError> {
    let length = extent(points);
    let tol = GEOMETRY_TOLERANCE * length;
    let (v, e, f) = (
        hull.vertices().len(),
        hull.edges().len(),
        hull.faces().len(),
    );
    prop_assert_eq!(v + f, e + 2, "Euler");
    // Vertices are input points.
    for p_body in hull.vertices() {
        let p_shape = to_shape_frame(hull, p_body);
        let nearest = points
            .iter()
            .map(|q| (q - p_shape).norm())
            .fold(f64::INFINITY, f64::min);
        prop_assert!(
            nearest <= 1e-12 * length,
            "vertex {p_shape} not an input point"
        );
    }
    // Containment: every input point on or below every face plane.
    for q in points {
        let q_body = q - hull.shape_origin_offset();
        for face in hull.faces() {
            prop_assert!(face.plane.signed_distance(&q_body) <= tol);
        }
    }
    check_faces(hull, tol)?;
    check_support(points, hull, tol)?;
    check_mass_against_parry(points, hull)
}

/// Faces: outward unit normals, vertices on the plane, convex and
/// counter-clockwise about the normal, at least three vertices.
fn check_faces(hull: &ConvexPolyhedron, tol: f64) -> Result<(), TestCaseError> {
    for face in hull.faces() {
        let n = face.plane.normal;
        prop_assert!((n.norm() - 1.0).abs() < 1e-12);
        // The centre of mass (the origin) is strictly inside.
        prop_assert!(face.plane.offset < 0.0, "normal points inwards");
        let k = face.vertices.len();
        prop_assert!(k >= 3);
        for i in 0..k {
            let a = hull.vertices()[face.vertices[i]];
            let b = hull.vertices()[face.vertices[(i + 1) % k]];
            let c = hull.vertices()[face.vertices[(i + 2) % k]];
            prop_assert!(face.plane.signed_distance(&a).abs() <= tol);
            // Left turn at b seen from outside (allowing flat within tol).
            let turn = (b - a).cross(&(c - b)).dot(&n);
            prop_assert!(
                turn >= -tol * (b - a).norm().max((c - b).norm()),
                "reflex vertex"
            );
        }
    }
    Ok(())
}

/// Support function: in many directions, the maximum over the input points
/// equals the maximum over the hull's vertices.
fn check_support(
    points: &[Point3<f64>],
    hull: &ConvexPolyhedron,
    tol: f64,
) -> Result<(), TestCaseError> {
    let sphere = ConvexPolyhedron::geodesic_sphere(1.0, 2).unwrap();
    for d in sphere.vertices().iter().map(|p| p.coords) {
        let brute = points
            .iter()
            .map(|p| p.coords.dot(&d))
            .fold(f64::NEG_INFINITY, f64::max);
        let ours = hull
            .vertices()
            .iter()
            .map(|p| to_shape_frame(hull, p).coords.dot(&d))
            .fold(f64::NEG_INFINITY, f64::max);
        prop_assert!((brute - ours).abs() <= tol, "support {brute} vs {ours}");
    }
    Ok(())
}

/// Volume, centre of mass and inertia of the same hull (its faces fanned
/// into triangles) against parry: `MassProperties::from_convex_polyhedron`
/// for volume, centre of mass and principal inertias, and parry's inertia
/// formula (`tetrahedron_unit_inertia_tensor_wrt_point`, summed about
/// parry's centre of mass) for the full tensor.
///
/// Not `Shape::mass_properties` of `to_parry()`: parry's
/// `ConvexPolyhedron` merges faces whose normals are within about `1.7e-4`
/// rad and then loses volume on thin hulls (half of it on a slab of
/// relative thickness `3e-5`).
///
/// The full tensor is not read back from `MassProperties`: in parry3d-f64
/// 0.31.1 / glamx 0.3.1 `reconstruct_inertia_matrix()` returns wrong
/// off-diagonal terms (the symmetric eigenvectors are wrong, the
/// eigenvalues right), e.g. for the right-corner tetrahedron
/// `(0,0,0), (0,0,-0.127), (0,0.156,0), (0.397,0,0)`. Parry's principal
/// inertias (eigenvalues) are compared instead.
///
/// parry's own hull of the raw points is no oracle for the geometry: it
/// treats sets thinner than about `3e-4` of their size as flat and drops
/// points, so it is only required not to be larger than ours (its vertices
/// are input points, so its hull is inside the true hull).
fn check_mass_against_parry(
    points: &[Point3<f64>],
    hull: &ConvexPolyhedron,
) -> Result<(), TestCaseError> {
    let triangles: Vec<[u32; 3]> = hull
        .faces()
        .iter()
        .flat_map(|f| {
            (1..f.vertices.len() - 1)
                .map(move |i| [f.vertices[0], f.vertices[i], f.vertices[i + 1]].map(|v| v as u32))
        })
        .collect();
    let vertices: Vec<ParryVector> = hull.vertices().iter().map(point_to_parry).collect();
    let mass = MassProperties::from_convex_polyhedron(1.0, &vertices, &triangles);
    let volume = hull.volume();
    prop_assert!(
        (mass.mass() - volume).abs() <= MASS_TOLERANCE * volume,
        "volume {} vs {}",
        mass.mass(),
        volume
    );
    prop_assert!(vector_from_parry(mass.local_com).norm() <= MASS_TOLERANCE * hull.scale());
    let ours = hull.mass_properties().inertia_unit_density;
    let theirs = parry_inertia(&vertices, &triangles, mass.local_com);
    prop_assert!(
        (theirs - ours).norm() <= MASS_TOLERANCE * ours.norm(),
        "inertia\n{theirs}\nvs\n{ours}"
    );
    let mut principal: Vec<f64> = ours.symmetric_eigen().eigenvalues.iter().copied().collect();
    principal.sort_by(f64::total_cmp);
    let mut parry_principal = vector_from_parry(mass.principal_inertia());
    parry_principal.as_mut_slice().sort_by(f64::total_cmp);
    for (a, b) in principal.iter().zip(parry_principal.iter()) {
        prop_assert!(
            (a - b).abs() <= MASS_TOLERANCE * ours.norm(),
            "principal {a} vs {b}"
        );
    }
    let raw: Vec<ParryVector> = points.iter().map(point_to_parry).collect();
    if let Some(parry_raw_hull) = ParryConvexPolyhedron::from_convex_hull(&raw) {
        let parry_volume = parry_raw_hull.mass_properties(1.0).mass();
        prop_assert!(
            parry_volume <= volume * (1.0 + MASS_TOLERANCE),
            "parry's hull {parry_volume} > ours {volume}"
        );
    }
    Ok(())
}

/// Unit-density inertia tensor about `com` by parry's tetrahedron formula.
fn parry_inertia(
    vertices: &[ParryVector],
    triangles: &[[u32; 3]],
    com: ParryVector,
) -> Matrix3<f64> {
    let mut total = Matrix3::zeros();
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        let volume = Tetrahedron::new(com, a, b, c).signed_volume();
        let unit = tetrahedron_unit_inertia_tensor_wrt_point(com, com, a, b, c);
        total += Matrix3::from_fn(|i, j| unit.col(j)[i]) * volume;
    }
    total
}

fn transformed(points: Vec<Point3<f64>>, pose: &Isometry3<f64>, scale: f64) -> Vec<Point3<f64>> {
    points
        .into_iter()
        .map(|p| pose * Point3::from(p.coords * scale))
        .collect()
}

fn pose_strategy() -> impl Strategy<Value = (Isometry3<f64>, f64)> {
    (
        prop::array::uniform3(-3.0..3.0f64),
        prop::array::uniform3(-1e3..1e3f64),
        -3.0..3.0f64,
    )
        .prop_map(|(axis_angle, t, log_scale)| {
            (
                Isometry3::new(Vector3::from(t), Vector3::from(axis_angle)),
                10f64.powf(log_scale),
            )
        })
}

fn sphere_points() -> impl Strategy<Value = Vec<Point3<f64>>> {
    prop::collection::vec((0.0..std::f64::consts::TAU, -1.0..1.0f64), 4..200).prop_map(|v| {
        v.into_iter()
            .map(|(phi, z)| {
                let r = (1.0 - z * z).sqrt();
                Point3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect()
    })
}

fn cube_points() -> impl Strategy<Value = Vec<Point3<f64>>> {
    prop::collection::vec(prop::array::uniform3(-1.0..1.0f64), 4..200)
        .prop_map(|v| v.into_iter().map(Point3::from).collect())
}

/// Points in a slab of relative thickness `10^e`, `e` in [-7, -1].
fn slab_points() -> impl Strategy<Value = Vec<Point3<f64>>> {
    (
        prop::collection::vec(prop::array::uniform3(-1.0..1.0f64), 4..200),
        -7.0..-1.0f64,
    )
        .prop_map(|(v, e)| {
            let thickness = 10f64.powf(e);
            v.into_iter()
                .map(|c| Point3::new(c[0], c[1], c[2] * thickness))
                .collect()
        })
}

fn build_or_typed_error(points: &[Point3<f64>]) -> Option<ConvexPolyhedron> {
    match ConvexPolyhedron::from_points(points) {
        Ok(hull) => Some(hull),
        Err(GeometryError::Degenerate) => None,
        Err(other) => panic!("unexpected error {other:?}"),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn hull_of_points_on_a_sphere(points in sphere_points(), (pose, scale) in pose_strategy()) {
        let points = transformed(points, &pose, scale);
        if let Some(hull) = build_or_typed_error(&points) {
            check_hull(&points, &hull)?;
        }
    }

    #[test]
    fn hull_of_points_in_a_cube(points in cube_points(), (pose, scale) in pose_strategy()) {
        let points = transformed(points, &pose, scale);
        if let Some(hull) = build_or_typed_error(&points) {
            check_hull(&points, &hull)?;
        }
    }

    #[test]
    fn hull_of_nearly_coplanar_points(points in slab_points(), (pose, scale) in pose_strategy()) {
        let points = transformed(points, &pose, scale);
        if let Some(hull) = build_or_typed_error(&points) {
            check_hull(&points, &hull)?;
        }
    }
}

#[test]
fn error_cases() {
    let p = |x: f64, y: f64, z: f64| Point3::new(x, y, z);
    assert_eq!(
        ConvexPolyhedron::from_points(&[]),
        Err(GeometryError::Empty)
    );
    let mut nan = vec![
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(0.0, 0.0, f64::NAN),
        p(0.0, 0.0, 1.0),
    ];
    assert_eq!(
        ConvexPolyhedron::from_points(&nan),
        Err(GeometryError::NonFinite { index: 3 })
    );
    nan[3].z = f64::INFINITY;
    assert_eq!(
        ConvexPolyhedron::from_points(&nan),
        Err(GeometryError::NonFinite { index: 3 })
    );
    let equal = vec![p(1.0, 2.0, 3.0); 10];
    assert_eq!(
        ConvexPolyhedron::from_points(&equal),
        Err(GeometryError::Degenerate)
    );
    let collinear: Vec<_> = (0..10)
        .map(|i| p(i as f64, 2.0 * i as f64, -(i as f64)))
        .collect();
    assert_eq!(
        ConvexPolyhedron::from_points(&collinear),
        Err(GeometryError::Degenerate)
    );
    let coplanar: Vec<_> = (0..30)
        .map(|i| p((i % 7) as f64, (i % 5) as f64, 1.0))
        .collect();
    assert_eq!(
        ConvexPolyhedron::from_points(&coplanar),
        Err(GeometryError::Degenerate)
    );
    let three = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    assert_eq!(
        ConvexPolyhedron::from_points(&three),
        Err(GeometryError::Degenerate)
    );
    // Four points, two of them duplicates within the merge tolerance.
    let near = [
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(1.0, 1e-13, 0.0),
        p(1e-14, 0.0, 1e-14),
    ];
    assert_eq!(
        ConvexPolyhedron::from_points(&near),
        Err(GeometryError::Degenerate)
    );
    let huge = [
        p(-1e308, 0.0, 0.0),
        p(1e308, 0.0, 0.0),
        p(0.0, 1e308, 0.0),
        p(0.0, 0.0, 1e308),
    ];
    assert_eq!(
        ConvexPolyhedron::from_points(&huge),
        Err(GeometryError::ExtentTooLarge)
    );
}

#[test]
fn cube_corners_with_points_on_faces_and_edges_give_six_quads() {
    let mut points = Vec::new();
    for i in 0..5 {
        for j in 0..5 {
            for k in 0..5 {
                points.push(Point3::new(i as f64, j as f64, k as f64) * 0.5);
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
    check_hull(&points, &hull).unwrap();
}
