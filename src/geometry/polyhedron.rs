//! The convex polyhedron type: vertices, edges, faces, their adjacency,
//! Voronoi planes and mass properties.
//!
//! Face normals come from Newell's method, `n ∝ Σ_i v_i × v_{i+1}`, which is
//! exact for planar polygons and robust for nearly degenerate ones.
//! Construction checks, relative to the scale `s` (largest distance of a
//! vertex from the centre of mass): every vertex of a face lies within
//! `PLANARITY_TOLERANCE * s` of its plane and every vertex lies on or below
//! every face plane within the same tolerance.

use nalgebra::{Point3, Vector3};

use super::plane::triangle_area_vector;
use super::topology::build_topology;
use super::{Feature, GeometryError, MassProperties, Plane};

/// Largest distance of a face's vertex from its plane, and largest height of
/// any vertex above a face plane, relative to the polyhedron's scale.
pub const PLANARITY_TOLERANCE: f64 = 1e-9;

/// An edge from `tail` to `head`.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    /// Vertex index at parameter 0.
    pub tail: usize,
    /// Vertex index at parameter 1.
    pub head: usize,
    /// The face whose counter-clockwise cycle goes `tail -> head`.
    pub left_face: usize,
    /// The face whose counter-clockwise cycle goes `head -> tail`.
    pub right_face: usize,
    /// Unit vector from tail to head (body frame).
    pub direction: Vector3<f64>,
    /// Distance from tail to head.
    pub length: f64,
}

/// A convex polygonal face.
#[derive(Debug, Clone, PartialEq)]
pub struct Face {
    /// Vertex indices, counter-clockwise seen from outside.
    pub vertices: Vec<usize>,
    /// `edges[i]` joins `vertices[i]` and `vertices[(i + 1) % n]`.
    pub edges: Vec<usize>,
    /// Supporting plane with the outward unit normal (body frame).
    pub plane: Plane,
}

/// A convex polyhedron in its body frame (origin at the centre of mass).
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexPolyhedron {
    vertices: Vec<Point3<f64>>,
    edges: Vec<Edge>,
    faces: Vec<Face>,
    vertex_edges: Vec<Vec<usize>>,
    mass: MassProperties,
    shape_origin_offset: Vector3<f64>,
    scale: f64,
    inradius: f64,
}

impl ConvexPolyhedron {
    /// Builds a polyhedron from vertices (in the shape frame) and faces given
    /// as counter-clockwise vertex cycles seen from outside. Checks the
    /// topology (closed two-manifold, `V - E + F = 2`), planarity and
    /// convexity. Vertices are stored relative to the centre of mass.
    pub fn from_faces(
        points: Vec<Point3<f64>>,
        faces: Vec<Vec<usize>>,
    ) -> Result<Self, GeometryError> {
        check_points(&points)?;
        let topology = build_topology(points.len(), &faces)?;
        let mass = MassProperties::of_polyhedron(&points, &faces);
        let has_volume = mass.volume > 0.0 && mass.volume.is_finite();
        if !has_volume || !mass.center_of_mass.coords.iter().all(|c| c.is_finite()) {
            return Err(GeometryError::Degenerate);
        }
        let shape_origin_offset = mass.center_of_mass.coords;
        let vertices: Vec<Point3<f64>> = points.iter().map(|p| p - shape_origin_offset).collect();
        let scale = vertices.iter().map(|v| v.coords.norm()).fold(0.0, f64::max);
        let edges = topology
            .edges
            .iter()
            .map(|t| {
                let along = vertices[t.head] - vertices[t.tail];
                Edge {
                    tail: t.tail,
                    head: t.head,
                    left_face: t.left_face,
                    right_face: t.right_face,
                    direction: along / along.norm(),
                    length: along.norm(),
                }
            })
            .collect();
        let faces = faces
            .into_iter()
            .zip(topology.face_edges)
            .map(|(cycle, edges)| {
                let plane = newell_plane(&vertices, &cycle);
                Face {
                    vertices: cycle,
                    edges,
                    plane,
                }
            })
            .collect();
        let polyhedron = ConvexPolyhedron {
            vertices,
            edges,
            faces,
            vertex_edges: topology.vertex_edges,
            mass: MassProperties {
                center_of_mass: Point3::origin(),
                ..mass
            },
            shape_origin_offset,
            scale,
            inradius: 0.0,
        };
        polyhedron.check_convex()?;
        let inradius = polyhedron
            .faces
            .iter()
            .map(|face| -face.plane.offset)
            .fold(f64::INFINITY, f64::min)
            .max(0.0);
        let polyhedron = ConvexPolyhedron {
            inradius,
            ..polyhedron
        };
        Ok(polyhedron)
    }

    /// The box `[-h, h]` for half extents `h`, centred on its centre of mass.
    pub fn cuboid(half_extents: Vector3<f64>) -> Result<Self, GeometryError> {
        for (axis, &value) in half_extents.iter().enumerate() {
            if !value.is_finite() || value <= 0.0 {
                return Err(GeometryError::InvalidHalfExtent { axis, value });
            }
        }
        // Vertex i has sign bit 0 for x, bit 1 for y, bit 2 for z.
        let vertices = (0..8)
            .map(|i| {
                let sign = |bit: usize| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
                Point3::new(
                    sign(0) * half_extents.x,
                    sign(1) * half_extents.y,
                    sign(2) * half_extents.z,
                )
            })
            .collect();
        let faces = vec![
            vec![1, 3, 7, 5], // +x
            vec![0, 4, 6, 2], // -x
            vec![2, 6, 7, 3], // +y
            vec![0, 1, 5, 4], // -y
            vec![4, 5, 7, 6], // +z
            vec![0, 2, 3, 1], // -z
        ];
        Self::from_faces(vertices, faces)
    }

    /// Vertex positions in the body frame.
    pub fn vertices(&self) -> &[Point3<f64>] {
        &self.vertices
    }

    /// Edges.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// Faces.
    pub fn faces(&self) -> &[Face] {
        &self.faces
    }

    /// Incident edges of vertex `v`.
    pub fn vertex_edges(&self, v: usize) -> &[usize] {
        &self.vertex_edges[v]
    }

    /// The vertex at the other end of edge `e` from vertex `v`.
    pub fn other_vertex(&self, e: usize, v: usize) -> usize {
        let edge = &self.edges[e];
        if edge.tail == v { edge.head } else { edge.tail }
    }

    /// Point of edge `e` at parameter `l` (0 = tail, 1 = head), body frame.
    pub fn edge_point(&self, e: usize, l: f64) -> Point3<f64> {
        let edge = &self.edges[e];
        self.vertices[edge.tail] + edge.direction * (edge.length * l)
    }

    /// Voronoi plane between vertex `v` and its incident edge `e`: through
    /// `v`, normal along `e` pointing away from the edge, so `VR(v)` is on
    /// the positive side.
    pub fn vertex_edge_plane(&self, e: usize, v: usize) -> Plane {
        let edge = &self.edges[e];
        let normal = if v == edge.tail {
            -edge.direction
        } else {
            edge.direction
        };
        Plane::through(&self.vertices[v], normal)
    }

    /// Voronoi plane between face `f` and its boundary edge `e`: contains the
    /// edge, normal in the face plane pointing into the face, so `VR(f)` is
    /// on the positive side.
    pub fn face_edge_plane(&self, e: usize, f: usize) -> Plane {
        let edge = &self.edges[e];
        let face_normal = self.faces[f].plane.normal;
        // Counter-clockwise seen from outside: the interior is to the left of
        // the traversal direction, `n × d`.
        let normal = if f == edge.left_face {
            face_normal.cross(&edge.direction)
        } else {
            edge.direction.cross(&face_normal)
        };
        Plane::through(&self.vertices[edge.tail], normal)
    }

    /// The features adjacent to `feature`: a vertex's edges, an edge's two
    /// vertices and two faces, a face's boundary edges.
    pub fn neighbours(&self, feature: Feature) -> Vec<Feature> {
        match feature {
            Feature::Vertex(v) => self.vertex_edges[v]
                .iter()
                .map(|&e| Feature::Edge(e))
                .collect(),
            Feature::Edge(e) => {
                let edge = &self.edges[e];
                vec![
                    Feature::Vertex(edge.tail),
                    Feature::Vertex(edge.head),
                    Feature::Face(edge.left_face),
                    Feature::Face(edge.right_face),
                ]
            }
            Feature::Face(f) => self.faces[f]
                .edges
                .iter()
                .map(|&e| Feature::Edge(e))
                .collect(),
        }
    }

    /// Mass properties at unit density; the centre of mass is the origin.
    pub fn mass_properties(&self) -> &MassProperties {
        &self.mass
    }

    /// Volume of the solid.
    pub fn volume(&self) -> f64 {
        self.mass.volume
    }

    /// Position of the centre of mass (the body-frame origin) in the frame in
    /// which the shape was given: `p_shape = p_body + shape_origin_offset`.
    pub fn shape_origin_offset(&self) -> Vector3<f64> {
        self.shape_origin_offset
    }

    /// Largest distance of a vertex from the centre of mass: the length scale
    /// to which geometric tolerances are relative.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// Radius of the largest ball about the centre of mass inside the solid:
    /// the smallest distance from the centre of mass to a face plane. Every
    /// support value satisfies `h(n) >= inradius` for unit `n`, the lower
    /// bound that confines the exact penetration search
    /// ([`crate::contact::penetration`]).
    pub fn inradius(&self) -> f64 {
        self.inradius
    }

    /// Number of vertices, edges and faces together.
    pub fn feature_count(&self) -> usize {
        self.vertices.len() + self.edges.len() + self.faces.len()
    }

    /// A face must be a convex polygon: at every corner `b` (between `a`
    /// and `c`) the cycle turns left about the outward normal, `b` lying at
    /// most `tolerance` on the wrong side of the segment `ac`. Vertex heights
    /// alone accept a planar non-convex face whose missing wedge is covered
    /// by coplanar neighbours.
    fn check_face_turns_left(&self, f: usize, tolerance: f64) -> Result<(), GeometryError> {
        let face = &self.faces[f];
        let n = face.vertices.len();
        for i in 0..n {
            let [a, b, c] = [i, i + 1, i + 2].map(|k| self.vertices[face.vertices[k % n]]);
            let turn = (b - a).cross(&(c - b)).dot(&face.plane.normal);
            if turn < -tolerance * (c - a).norm() {
                return Err(GeometryError::NotConvex(format!(
                    "face {f} turns clockwise at vertex {}",
                    face.vertices[(i + 1) % n]
                )));
            }
        }
        Ok(())
    }

    fn check_convex(&self) -> Result<(), GeometryError> {
        let tolerance = PLANARITY_TOLERANCE * self.scale;
        for (f, face) in self.faces.iter().enumerate() {
            if !face.plane.normal.iter().all(|c| c.is_finite()) {
                return Err(GeometryError::NotConvex(format!("face {f} has no normal")));
            }
            self.check_face_turns_left(f, tolerance)?;
            for (v, vertex) in self.vertices.iter().enumerate() {
                let height = face.plane.signed_distance(vertex);
                let on_face = face.vertices.contains(&v);
                if height > tolerance || (on_face && height < -tolerance) {
                    return Err(GeometryError::NotConvex(format!(
                        "vertex {v} is {height:e} from the plane of face {f}"
                    )));
                }
            }
        }
        Ok(())
    }
}

fn check_points(points: &[Point3<f64>]) -> Result<(), GeometryError> {
    if points.is_empty() {
        return Err(GeometryError::Empty);
    }
    match points
        .iter()
        .position(|p| !p.coords.iter().all(|c| c.is_finite()))
    {
        Some(index) => Err(GeometryError::NonFinite { index }),
        None => Ok(()),
    }
}

/// Plane of a polygon through its vertex centroid, with the normal of its
/// area vector summed over the fan `(v_0, v_i, v_{i+1})`.
///
/// Each fan triangle's area vector is taken at its best corner
/// ([`triangle_area_vector`]), not as Newell's `Σ v_i × v_{i+1}`: that sum
/// rounds every term at the size of the body (`ε s²`), which tilts the
/// normal of a face of width `w` and length `l` by about `ε s² / (w l)`.
/// A side of a slab of relative thickness `1e-8` (as thin as a solid may
/// be, [`crate::geometry::FLATNESS_TOLERANCE`]) would tilt by `1e-8` and
/// its far corners leave the plane by more than [`PLANARITY_TOLERANCE`].
/// Split at the corners between its long and short sides, it keeps a
/// normal accurate to about `ε`.
fn newell_plane(vertices: &[Point3<f64>], cycle: &[usize]) -> Plane {
    let sum = cycle
        .iter()
        .fold(Vector3::zeros(), |acc, &a| acc + vertices[a].coords);
    let centroid = Point3::from(sum / cycle.len() as f64);
    let corner = |i: usize| &vertices[cycle[i]];
    let normal = (1..cycle.len() - 1).fold(Vector3::zeros(), |acc, i| {
        acc + triangle_area_vector(corner(0), corner(i), corner(i + 1))
    });
    Plane::through(&centroid, normal.normalize())
}
