//! Mass properties in closed form of the round and curved solids, at unit
//! density, about the centre of mass, in the shape frame's axes.
//!
//! All are symmetric about their centre of mass's axes, so the inertia is
//! diagonal: `I = diag(S_y + S_z, S_x + S_z, S_x + S_y)` with the second
//! moments `S_k = ∫ x_k^2 dV` about the centre of mass.
//!
//! - **Sphere** of radius `r`: `V = 4/3 π r^3`, `S_k = V r^2 / 5`.
//! - **Capsule** (segment `[-h, h]` along `z`, radius `r`): a cylinder of
//!   volume `V_c = 2 π r^2 h` and two hemispheres of total volume
//!   `V_s = 4/3 π r^3`:
//!   `I_zz = V_c r^2 / 2 + 2/5 V_s r^2`,
//!   `I_xx = V_c (r^2/4 + h^2/3) + V_s (2/5 r^2 + h^2 + 3/4 h r)` (each
//!   hemisphere's centroid is `3r/8` past its flat face at `z = ±h`).
//! - **Rounded cuboid** (half extents `h`, radius `r`): the box, six face
//!   slabs of thickness `r`, twelve quarter cylinders along the edges and
//!   eight ball octants at the corners, disjoint. A quarter disk of radius
//!   `r` has the mean `4r/(3π)` and mean square `r^2/4` of a coordinate; a
//!   ball octant `3r/8` and `r^2/5`; a piece at `h_k + u` (`u` such a
//!   coordinate) adds `V (h_k^2 + 2 h_k mean(u) + mean(u^2))` to `S_k`.
//! - **Cylinder** (axis `z`, half height `h`, radius `r`):
//!   `V = 2 π r^2 h`, `I_zz = V r^2/2`, `I_xx = V (r^2/4 + h^2/3)`.
//! - **Cone** (axis `z`, base of radius `r` at `z = -h`, apex at `z = h`):
//!   `V = 2/3 π r^2 h`, centre of mass at `z = -h/2`,
//!   `I_zz = 3/10 V r^2`, `I_xx = V (3/20 r^2 + 3/80 (2h)^2)`.
//!
//! A **rounded hull** has no such closed form in this library (its edge
//! wedges and vertex sectors depend on the dihedral and solid angles); its
//! mass properties are those of an inscribed polyhedron
//! ([`rounded_hull_points`]): the hull of the core's vertices each moved
//! by `r` along the directions of a geodesic sphere. Its volume is below
//! the exact (Steiner) volume by at most the volume of the shell between
//! the rounded hull and its inscribed approximation, `A (1 - cos θ) r`
//! with `A` the rounded hull's area and `θ` the largest angle between a
//! direction and its nearest sample (tested against the Steiner volume in
//! `tests/it/geometry/round_mass.rs`).

use std::f64::consts::PI;

use nalgebra::{Matrix3, Point3, Vector3};

use super::MassProperties;

/// Geodesic-sphere subdivisions of the directions of a rounded hull's
/// inscribed approximation ([`rounded_hull_points`]): 642 directions.
pub const ROUNDED_HULL_SUBDIVISIONS: usize = 3;

/// The bound on a rounded hull's approximation: its volume is below the
/// exact (Steiner) volume by at most this fraction of the rounding shell
/// (Steiner's volume minus the core's). The inscribed ball of 642
/// directions lacks 0.4 % of the ball's volume and a face slab at most
/// `1 - cos θ` of its thickness (θ about 0.08 rad: 0.3 %); the bound
/// leaves room for both (tested in `tests/it/round/mass.rs`).
pub const ROUNDED_HULL_SHELL_DEFICIT: f64 = 0.01;

fn diagonal(volume: f64, com: Point3<f64>, s: [f64; 3]) -> MassProperties {
    MassProperties {
        volume,
        center_of_mass: com,
        inertia_unit_density: Matrix3::from_diagonal(&Vector3::new(
            s[1] + s[2],
            s[0] + s[2],
            s[0] + s[1],
        )),
    }
}

/// A sphere of radius `radius` centred on the origin.
pub fn sphere(radius: f64) -> MassProperties {
    let volume = 4.0 / 3.0 * PI * radius.powi(3);
    let s = volume * radius * radius / 5.0;
    diagonal(volume, Point3::origin(), [s; 3])
}

/// A capsule: the segment `[-half_length, half_length]` along `z` grown by
/// `radius`.
pub fn capsule(half_length: f64, radius: f64) -> MassProperties {
    let (h, r) = (half_length, radius);
    let v_cylinder = 2.0 * PI * r * r * h;
    let v_spheres = 4.0 / 3.0 * PI * r.powi(3);
    let i_zz = v_cylinder * r * r / 2.0 + 0.4 * v_spheres * r * r;
    let i_xx =
        v_cylinder * (r * r / 4.0 + h * h / 3.0) + v_spheres * (0.4 * r * r + h * h + 0.75 * h * r);
    MassProperties {
        volume: v_cylinder + v_spheres,
        center_of_mass: Point3::origin(),
        inertia_unit_density: Matrix3::from_diagonal(&Vector3::new(i_xx, i_xx, i_zz)),
    }
}

/// The cuboid of half extents `half_extents` grown by `radius`, centred on
/// the origin.
pub fn rounded_cuboid(half_extents: &Vector3<f64>, radius: f64) -> MassProperties {
    let h = half_extents;
    let r = radius;
    let mut volume = 0.0;
    let mut s = [0.0; 3];
    // A piece of volume `v` whose coordinate k is `h_k + u` with `u` of mean
    // `mean[k]` and mean square `square[k]`.
    let mut add = |v: f64, shift: [f64; 3], mean: [f64; 3], square: [f64; 3]| {
        volume += v;
        for k in 0..3 {
            s[k] += v * (shift[k] * shift[k] + 2.0 * shift[k] * mean[k] + square[k]);
        }
    };
    let box_square = |k: usize| h[k] * h[k] / 3.0;
    // The box.
    let v_box = 8.0 * h.x * h.y * h.z;
    add(
        v_box,
        [0.0; 3],
        [0.0; 3],
        [box_square(0), box_square(1), box_square(2)],
    );
    for j in 0..3 {
        let (p, q) = ((j + 1) % 3, (j + 2) % 3);
        // Two face slabs normal to j: u in [0, r] past h_j.
        let v_slab = r * 4.0 * h[p] * h[q];
        let mut shift = [0.0; 3];
        let mut mean = [0.0; 3];
        let mut square = [0.0; 3];
        shift[j] = h[j];
        mean[j] = r / 2.0;
        square[j] = r * r / 3.0;
        square[p] = box_square(p);
        square[q] = box_square(q);
        add(2.0 * v_slab, shift, mean, square);
        // Four quarter cylinders along j, at (±h_p, ±h_q).
        let v_edge = PI * r * r / 4.0 * 2.0 * h[j];
        let mut shift = [0.0; 3];
        let mut mean = [0.0; 3];
        let mut square = [0.0; 3];
        square[j] = box_square(j);
        for k in [p, q] {
            shift[k] = h[k];
            mean[k] = 4.0 * r / (3.0 * PI);
            square[k] = r * r / 4.0;
        }
        add(4.0 * v_edge, shift, mean, square);
    }
    // Eight ball octants at the corners.
    let v_octant = PI * r.powi(3) / 6.0;
    add(
        8.0 * v_octant,
        [h.x, h.y, h.z],
        [3.0 * r / 8.0; 3],
        [r * r / 5.0; 3],
    );
    diagonal(volume, Point3::origin(), s)
}

/// A solid cylinder along `z`, centred on the origin.
pub fn cylinder(half_height: f64, radius: f64) -> MassProperties {
    let (h, r) = (half_height, radius);
    let volume = 2.0 * PI * r * r * h;
    let s_xy = volume * r * r / 4.0;
    diagonal(volume, Point3::origin(), [s_xy, s_xy, volume * h * h / 3.0])
}

/// A solid cone along `z`: base of radius `radius` at `z = -half_height`,
/// apex at `z = half_height`.
pub fn cone(half_height: f64, radius: f64) -> MassProperties {
    let (h, r) = (half_height, radius);
    let height = 2.0 * h;
    let volume = PI * r * r * height / 3.0;
    // About the centre of mass: S_x = S_y = 3/20 V r^2 / ... split so that
    // I_zz = 3/10 V r^2 and I_xx = V (3/20 r^2 + 3/80 H^2).
    let s_xy = 3.0 / 20.0 * volume * r * r;
    let s_z = 3.0 / 80.0 * volume * height * height;
    diagonal(volume, Point3::new(0.0, 0.0, -h / 2.0), [s_xy, s_xy, s_z])
}

/// Steiner's volume of a convex polyhedron grown by `radius`:
/// `V + A r + M r^2 + 4/3 π r^3`, with `A` the area and
/// `M = 1/2 Σ_edges length · (π - dihedral angle)` the integral of mean
/// curvature. Exact; the reference for [`rounded_hull_points`].
pub fn steiner_volume(core: &super::ConvexPolyhedron, radius: f64) -> f64 {
    let vertices = core.vertices();
    let area: f64 = core
        .faces()
        .iter()
        .map(|face| {
            let v0 = vertices[face.vertices[0]];
            let doubled: Vector3<f64> = face
                .vertices
                .windows(2)
                .skip(1)
                .map(|w| (vertices[w[0]] - v0).cross(&(vertices[w[1]] - v0)))
                .sum();
            0.5 * doubled.norm()
        })
        .sum();
    let mean_curvature: f64 = core
        .edges()
        .iter()
        .map(|edge| {
            let n_left = core.faces()[edge.left_face].plane.normal;
            let n_right = core.faces()[edge.right_face].plane.normal;
            // The exterior angle between the faces is the angle between
            // their normals.
            let exterior = n_left.dot(&n_right).clamp(-1.0, 1.0).acos();
            0.5 * edge.length * exterior
        })
        .sum();
    core.volume()
        + area * radius
        + mean_curvature * radius * radius
        + 4.0 / 3.0 * PI * radius.powi(3)
}

/// Points whose hull is inscribed in the polyhedron `core` grown by
/// `radius`: every vertex moved by `radius` along each direction of
/// `directions` (unit vectors).
pub fn rounded_hull_points(
    core: &super::ConvexPolyhedron,
    radius: f64,
    directions: &[Vector3<f64>],
) -> Vec<Point3<f64>> {
    core.vertices()
        .iter()
        .flat_map(|v| directions.iter().map(move |d| v + d * radius))
        .collect()
}
