//! Convex polyhedra: hulls from points and from faces, their typed
//! errors, Mirtich's shapes, and the bridge to parry3d-f64.

mod cuboid_polyhedron;
mod from_faces;
mod hull;
mod hull_errors;
mod parry_bridge;
mod shapes;
