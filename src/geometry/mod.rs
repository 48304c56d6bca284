//! Convex polyhedra with the full feature topology that V-Clip needs.
//!
//! A [`ConvexPolyhedron`] has vertices, edges and faces (features, see
//! [`Feature`]). Every edge runs from its `tail` to its `head` and has two
//! faces: its `left_face` traverses it tail → head in its counter-clockwise
//! cycle (seen from outside), its `right_face` head → tail. Face planes have
//! outward unit normals.
//!
//! Voronoi planes (Mirtich 1998, section 3), each oriented so that the
//! region of its *lower-dimensional or named* feature is on the positive side:
//! - [`ConvexPolyhedron::vertex_edge_plane`]`(e, v)`: through `v`, normal along
//!   the edge pointing from the edge's interior towards `v`; `VR(v)` is on
//!   the positive side. As a wall of `VR(e)` it is used negated.
//! - [`ConvexPolyhedron::face_edge_plane`]`(e, f)`: contains the edge, normal in
//!   the plane of `f`, perpendicular to the edge, pointing into `f`; `VR(f)`
//!   is on the positive side. As a wall of `VR(e)` it is used negated.
//!
//! Construction: [`ConvexPolyhedron::from_faces`] (validated face cycles),
//! [`ConvexPolyhedron::cuboid`], [`ConvexPolyhedron::from_points`] (convex
//! hull with exact predicates, coplanar triangles merged; `hull`,
//! `exact_hull`, `coplanar`, `thin_faces`), and Mirtich's test shapes
//! [`ConvexPolyhedron::icosahedron`], [`ConvexPolyhedron::disk`],
//! [`ConvexPolyhedron::geodesic_sphere`] (`shapes`). [`ConvexPolyhedron::to_parry`]
//! and the `*_to_parry` / `*_from_parry` functions convert to parry3d-f64
//! (`parry_bridge`).
//!
//! All coordinates are in the *body frame*: the origin is the centre of mass
//! of the solid at uniform density, axes those of the frame in which the
//! shape was given. [`ConvexPolyhedron::shape_origin_offset`] maps back.

mod coplanar;
pub mod curved;
mod error;
mod exact_hull;
mod features;
mod flat_vertices;
mod hull;
mod index_maps;
mod mass;
mod parry_bridge;
mod plane;
pub mod polyhedron;
pub mod round;
pub mod round_mass;
mod shapes;
mod thin_faces;
mod topology;

pub use coplanar::COPLANAR_TOLERANCE;
pub use error::GeometryError;
pub use features::Feature;
pub use flat_vertices::{FLAT_VERTEX_MAX_ANGLE, FLAT_VERTEX_TOLERANCE};
pub use hull::{
    CONTAINMENT_TOLERANCE, DUPLICATE_TOLERANCE, FLATNESS_TOLERANCE, MAX_COORDINATE,
    MAX_SIMPLIFICATION_ROUNDS, MIN_EXTENT,
};
pub use mass::MassProperties;
pub use parry_bridge::{
    isometry_from_parry, isometry_to_parry, point_from_parry, point_to_parry, vector_from_parry,
    vector_to_parry,
};
pub use plane::Plane;
pub use polyhedron::{ConvexPolyhedron, Edge, Face, PLANARITY_TOLERANCE};
pub use round::{RoundCore, Rounding};
pub use shapes::MAX_GEODESIC_SUBDIVISIONS;
pub use thin_faces::THIN_FACE_TOLERANCE;
