//! Mirtich's test shapes (Mirtich 1998, "V-Clip", section 6): icosahedron,
//! thin disk (a prism over a regular polygon) and geodesic sphere.
//!
//! - Icosahedron: the 12 vertices `(0, ±1, ±φ)` and their cyclic
//!   permutations, `φ = (1 + √5) / 2`, scaled to the circumradius `R`
//!   (`|v| = √(1 + φ²)` before scaling). Faces are the 20 vertex triples at
//!   mutual distance 2 (the edge length before scaling), oriented so that
//!   the normal points away from the centre.
//! - Disk: a right prism along `z` over the regular `n`-gon of circumradius
//!   `r`, thickness `t`: vertex `i` of the bottom (`z = -t/2`) and top
//!   (`z = t/2`) rings at angle `2πi/n`. Volume `n/2 r² sin(2π/n) t`.
//!   Mirtich uses `n = 60`, `r : t = 10 : 1`.
//! - Geodesic sphere: the icosahedron with each triangle split into four at
//!   its edge midpoints, `k` times, every new vertex projected onto the
//!   sphere of radius `R`: `V = 10·4^k + 2`, `E = 30·4^k`, `F = 20·4^k`.
//!
//! All shapes are centred on the origin, which is also their centre of mass.

use std::f64::consts::TAU;

use nalgebra::{Point3, Vector3};

use super::index_maps::IndexMap;
use super::{ConvexPolyhedron, GeometryError};

/// Largest accepted `subdivisions` of [`ConvexPolyhedron::geodesic_sphere`]
/// (6 gives 40 962 vertices).
pub const MAX_GEODESIC_SUBDIVISIONS: usize = 6;

/// Smallest number of sides of [`ConvexPolyhedron::disk`].
const MIN_DISK_SIDES: usize = 3;

/// Largest number of sides of [`ConvexPolyhedron::disk`].
const MAX_DISK_SIDES: usize = 100_000;

impl ConvexPolyhedron {
    /// Regular icosahedron with the given circumradius, centred on the
    /// origin.
    pub fn icosahedron(circumradius: f64) -> Result<Self, GeometryError> {
        check_dimension("circumradius", circumradius)?;
        let (vertices, faces) = icosahedron_mesh(circumradius);
        Self::from_faces(vertices, faces)
    }

    /// Right prism along `z` over a regular polygon with `sides` sides and
    /// circumradius `radius`, of height `thickness`, centred on the origin.
    pub fn disk(radius: f64, thickness: f64, sides: usize) -> Result<Self, GeometryError> {
        check_dimension("radius", radius)?;
        check_dimension("thickness", thickness)?;
        check_count("sides", sides, MIN_DISK_SIDES, MAX_DISK_SIDES)?;
        let ring = |z: f64| {
            (0..sides).map(move |i| {
                let angle = TAU * i as f64 / sides as f64;
                Point3::new(radius * angle.cos(), radius * angle.sin(), z)
            })
        };
        let vertices: Vec<Point3<f64>> = ring(-0.5 * thickness)
            .chain(ring(0.5 * thickness))
            .collect();
        let bottom = |i: usize| i % sides;
        let top = |i: usize| sides + i % sides;
        let mut faces = vec![
            (0..sides).rev().map(bottom).collect::<Vec<_>>(),
            (0..sides).map(top).collect(),
        ];
        faces.extend((0..sides).map(|i| vec![bottom(i), bottom(i + 1), top(i + 1), top(i)]));
        Self::from_faces(vertices, faces)
    }

    /// Icosphere of the given radius: the icosahedron subdivided
    /// `subdivisions` times (at most [`MAX_GEODESIC_SUBDIVISIONS`]), all
    /// vertices on the sphere.
    pub fn geodesic_sphere(radius: f64, subdivisions: usize) -> Result<Self, GeometryError> {
        check_dimension("radius", radius)?;
        check_count("subdivisions", subdivisions, 0, MAX_GEODESIC_SUBDIVISIONS)?;
        let (mut vertices, mut faces) = icosahedron_mesh(radius);
        for _ in 0..subdivisions {
            faces = subdivide(&mut vertices, &faces, radius);
        }
        Self::from_faces(vertices, faces)
    }
}

fn check_dimension(name: &'static str, value: f64) -> Result<(), GeometryError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(GeometryError::InvalidDimension { name, value })
    }
}

fn check_count(
    name: &'static str,
    value: usize,
    min: usize,
    max: usize,
) -> Result<(), GeometryError> {
    if (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(GeometryError::InvalidCount {
            name,
            value,
            min,
            max,
        })
    }
}

/// Vertices and counter-clockwise triangles of the icosahedron of
/// circumradius `radius`.
fn icosahedron_mesh(radius: f64) -> (Vec<Point3<f64>>, Vec<Vec<usize>>) {
    let phi = 0.5 * (1.0 + 5.0_f64.sqrt());
    let mut unit = Vec::with_capacity(12);
    for (a, b) in [(1.0, phi), (1.0, -phi), (-1.0, phi), (-1.0, -phi)] {
        unit.push(Vector3::new(0.0, a, b));
        unit.push(Vector3::new(a, b, 0.0));
        unit.push(Vector3::new(b, 0.0, a));
    }
    // Edges have length 2 and the next shortest distance is 2φ: 3 is a
    // safe threshold between them.
    let adjacent = |i: usize, j: usize| (unit[i] - unit[j]).norm() < 3.0;
    let mut faces = Vec::with_capacity(20);
    for i in 0..12 {
        for j in i + 1..12 {
            for k in j + 1..12 {
                if adjacent(i, j) && adjacent(j, k) && adjacent(i, k) {
                    let normal = (unit[j] - unit[i]).cross(&(unit[k] - unit[i]));
                    let outward = normal.dot(&(unit[i] + unit[j] + unit[k])) > 0.0;
                    faces.push(if outward {
                        vec![i, j, k]
                    } else {
                        vec![i, k, j]
                    });
                }
            }
        }
    }
    let scale = radius / (1.0 + phi * phi).sqrt();
    let vertices = unit.into_iter().map(|v| Point3::from(v * scale)).collect();
    (vertices, faces)
}

/// Splits every triangle into four at its edge midpoints, projected onto
/// the sphere of radius `radius`; new vertices are appended to `vertices`.
fn subdivide(
    vertices: &mut Vec<Point3<f64>>,
    faces: &[Vec<usize>],
    radius: f64,
) -> Vec<Vec<usize>> {
    let mut midpoints: IndexMap<(usize, usize), usize> = IndexMap::default();
    let mut midpoint = |a: usize, b: usize, vertices: &mut Vec<Point3<f64>>| {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let middle = (vertices[a].coords + vertices[b].coords) * 0.5;
            vertices.push(Point3::from(middle.normalize() * radius));
            vertices.len() - 1
        })
    };
    let mut refined = Vec::with_capacity(4 * faces.len());
    for face in faces {
        let [a, b, c] = [face[0], face[1], face[2]];
        let ab = midpoint(a, b, vertices);
        let bc = midpoint(b, c, vertices);
        let ca = midpoint(c, a, vertices);
        refined.extend([
            vec![a, ab, ca],
            vec![ab, b, bc],
            vec![ca, bc, c],
            vec![ab, bc, ca],
        ]);
    }
    refined
}
