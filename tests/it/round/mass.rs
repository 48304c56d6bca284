//! Mass properties of round and curved shapes: the closed forms against
//! the library's polyhedron integration (tetrahedra, `geometry::mass`) of
//! fine inscribed approximations, and Steiner's exact volume.

use constraint_stabilization::body::{Body, BodyDesc, MassSpec, Shape, ShapePart};
use constraint_stabilization::internals::geometry::{ConvexPolyhedron, MassProperties, round_mass};
use nalgebra::{Matrix3, Point3, Vector3};

/// Agreement of a closed form with a fine polyhedral approximation,
/// relative (the extrapolated approximation's own error is about 1e-5).
const APPROXIMATION_AGREEMENT: f64 = 2e-4;

fn sphere_directions(subdivisions: usize) -> Vec<Vector3<f64>> {
    ConvexPolyhedron::geodesic_sphere(1.0, subdivisions)
        .expect("a geodesic sphere")
        .vertices()
        .iter()
        .map(|v| v.coords.normalize())
        .collect()
}

/// The mass properties of a core grown by `r`, from inscribed hulls of
/// directions of geodesic spheres 3 and 4 extrapolated (Richardson: the
/// error falls fourfold per subdivision, as the squared spacing).
fn grown_mass(core: &[Point3<f64>], r: f64) -> MassProperties {
    let at = |subdivisions: usize| {
        let directions = sphere_directions(subdivisions);
        let points: Vec<Point3<f64>> = core
            .iter()
            .flat_map(|p| directions.iter().map(move |d| p + d * r))
            .collect();
        hull_mass(&points)
    };
    let (coarse, fine) = (at(3), at(4));
    MassProperties {
        volume: (4.0 * fine.volume - coarse.volume) / 3.0,
        center_of_mass: fine.center_of_mass,
        inertia_unit_density: (fine.inertia_unit_density * 4.0 - coarse.inertia_unit_density) / 3.0,
    }
}

fn hull_mass(points: &[Point3<f64>]) -> MassProperties {
    *ConvexPolyhedron::from_points(points)
        .expect("a hull")
        .mass_properties()
}

fn assert_close(label: &str, closed: &MassProperties, approximate: &MassProperties) {
    let relative = |x: f64, y: f64| (x - y).abs() / y.abs().max(f64::MIN_POSITIVE);
    assert!(
        relative(closed.volume, approximate.volume) <= APPROXIMATION_AGREEMENT,
        "{label}: volume {} vs {}",
        closed.volume,
        approximate.volume
    );
    let scale = approximate.inertia_unit_density.norm();
    let error = (closed.inertia_unit_density - approximate.inertia_unit_density).norm();
    assert!(
        error <= APPROXIMATION_AGREEMENT * scale,
        "{label}: inertia\n{}\nvs\n{}",
        closed.inertia_unit_density,
        approximate.inertia_unit_density
    );
}

#[test]
fn closed_forms_match_fine_approximations() {
    assert_close(
        "sphere",
        &round_mass::sphere(0.7),
        &grown_mass(&[Point3::origin()], 0.7),
    );
    let segment = [Point3::new(0.0, 0.0, -0.9), Point3::new(0.0, 0.0, 0.9)];
    assert_close(
        "capsule",
        &round_mass::capsule(0.9, 0.4),
        &grown_mass(&segment, 0.4),
    );
    let h = Vector3::new(0.5, 0.3, 0.8);
    let corners: Vec<Point3<f64>> = (0..8)
        .map(|i| {
            let sign = |bit: usize| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
            Point3::new(sign(0) * h.x, sign(1) * h.y, sign(2) * h.z)
        })
        .collect();
    assert_close(
        "rounded cuboid",
        &round_mass::rounded_cuboid(&h, 0.2),
        &grown_mass(&corners, 0.2),
    );
    let ring = |r: f64, z: f64, n: usize| {
        (0..n).map(move |i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            Point3::new(r * a.cos(), r * a.sin(), z)
        })
    };
    let cylinder: Vec<_> = ring(0.6, -0.4, 720).chain(ring(0.6, 0.4, 720)).collect();
    assert_close(
        "cylinder",
        &round_mass::cylinder(0.4, 0.6),
        &hull_mass(&cylinder),
    );
    let mut cone: Vec<_> = ring(0.6, -0.4, 720).collect();
    cone.push(Point3::new(0.0, 0.0, 0.4));
    let closed = round_mass::cone(0.4, 0.6);
    let approximate = hull_mass(&cone);
    let com = ConvexPolyhedron::from_points(&cone)
        .expect("a cone")
        .shape_origin_offset();
    assert!(
        (closed.center_of_mass.coords - com).norm() <= 1e-9,
        "{com:?}"
    );
    assert_close("cone", &closed, &approximate);
}

#[test]
fn rounded_cuboid_volume_is_steiners_and_radius_zero_is_the_cuboid() {
    let h = Vector3::new(0.5, 0.3, 0.8);
    let core = ConvexPolyhedron::cuboid(h).expect("a cuboid");
    for r in [0.0, 0.05, 0.3, 2.0] {
        let closed = round_mass::rounded_cuboid(&h, r).volume;
        let steiner = round_mass::steiner_volume(&core, r);
        assert!(
            (closed - steiner).abs() <= 1e-12 * steiner,
            "r {r}: {closed} vs {steiner}"
        );
    }
    let plain = core.mass_properties();
    let zero = round_mass::rounded_cuboid(&h, 0.0);
    assert!((zero.inertia_unit_density - plain.inertia_unit_density).norm() <= 1e-14);
}

#[test]
fn rounded_hull_approximation_is_within_its_stated_bound() {
    // The bound of `round_mass`: the inscribed approximation's volume is
    // below Steiner's by at most ROUNDED_HULL_SHELL_DEFICIT of the rounding
    // shell.
    let points = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.1, 0.0),
        Point3::new(0.2, 0.9, 0.1),
        Point3::new(0.1, 0.2, 0.8),
        Point3::new(0.7, 0.6, 0.5),
    ];
    let core = ConvexPolyhedron::from_points(&points).expect("a hull");
    for r in [0.05, 0.2, 0.5] {
        let body = Body::new(BodyDesc {
            name: "h".into(),
            shape: Shape::RoundConvexHull {
                points: points.clone(),
                radius: r,
            },
            translation: Vector3::zeros(),
            rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
            mass: MassSpec::Density(1.0),
        })
        .expect("a rounded hull");
        let volume = body.mass().expect("dynamic").mass;
        let steiner = round_mass::steiner_volume(&core, r);
        let shell = steiner - core.volume();
        println!("rounded hull r {r}: approximation {volume}, Steiner {steiner}");
        assert!(
            volume <= steiner && steiner - volume <= round_mass::ROUNDED_HULL_SHELL_DEFICIT * shell,
            "r {r}: {volume} vs {steiner}"
        );
    }
}

#[test]
fn a_compound_of_spheres_adds_by_parallel_axes() {
    let part = |x: f64| ShapePart {
        shape: Shape::Sphere { radius: 0.5 },
        translation: Vector3::new(x, 0.0, 0.0),
        rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
    };
    let body = Body::new(BodyDesc {
        name: "dumbbell".into(),
        shape: Shape::Compound {
            parts: vec![part(-1.0), part(1.0)],
        },
        translation: Vector3::zeros(),
        rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
        mass: MassSpec::Mass(2.0),
    })
    .expect("a compound");
    let mass = body.mass().expect("dynamic");
    // Each sphere: mass 1, 2/5 m r^2 about its centre, plus m d^2 across.
    let own = 0.4 * 0.25;
    let expected = Matrix3::from_diagonal(&Vector3::new(
        2.0 * own,
        2.0 * (own + 1.0),
        2.0 * (own + 1.0),
    ));
    assert!(
        (mass.inertia_body - expected).norm() <= 1e-12,
        "{}",
        mass.inertia_body
    );
}
