use approx::assert_relative_eq;
use constraint_stabilization::internals::geometry::GeometryError;
use constraint_stabilization::internals::geometry::polyhedron::*;
use nalgebra::{Point3, Vector3};

#[test]
fn cuboid_topology_and_mass() {
    let half = Vector3::new(1.0, 2.0, 3.0);
    let cube = ConvexPolyhedron::cuboid(half).unwrap();
    assert_eq!(
        (
            cube.vertices().len(),
            cube.edges().len(),
            cube.faces().len()
        ),
        (8, 12, 6)
    );
    assert_relative_eq!(cube.volume(), 48.0, epsilon = 1e-12);
    // Solid box: I_xx = m (b^2 + c^2) / 3 with half extents b, c; m = volume.
    let inertia = cube.mass_properties().inertia_unit_density;
    assert_relative_eq!(inertia[(0, 0)], 48.0 * (4.0 + 9.0) / 3.0, epsilon = 1e-9);
    assert_relative_eq!(inertia[(1, 1)], 48.0 * (1.0 + 9.0) / 3.0, epsilon = 1e-9);
    assert_relative_eq!(inertia[(0, 1)], 0.0, epsilon = 1e-9);
    for face in cube.faces() {
        assert_relative_eq!(face.plane.normal.norm(), 1.0, epsilon = 1e-12);
    }
}

#[test]
fn voronoi_planes_point_into_their_feature() {
    let cube = ConvexPolyhedron::cuboid(Vector3::new(1.0, 1.0, 1.0)).unwrap();
    for (e, edge) in cube.edges().iter().enumerate() {
        let middle = cube.edge_point(e, 0.5);
        for f in [edge.left_face, edge.right_face] {
            let centre = cube.faces()[f]
                .vertices
                .iter()
                .fold(Vector3::zeros(), |acc, &v| acc + cube.vertices()[v].coords)
                / 4.0;
            assert!(
                cube.face_edge_plane(e, f)
                    .signed_distance(&Point3::from(centre))
                    > 0.5
            );
        }
        assert!(
            cube.vertex_edge_plane(e, edge.tail)
                .signed_distance(&middle)
                < 0.0
        );
        let beyond_head = cube.edge_point(e, 1.5);
        assert!(
            cube.vertex_edge_plane(e, edge.head)
                .signed_distance(&beyond_head)
                > 0.0
        );
    }
}

#[test]
fn invalid_half_extent_is_an_error() {
    let err = ConvexPolyhedron::cuboid(Vector3::new(1.0, f64::NAN, 1.0)).unwrap_err();
    assert!(matches!(
        err,
        GeometryError::InvalidHalfExtent { axis: 1, .. }
    ));
}
