//! Edges and adjacency from counter-clockwise face cycles, and the checks of
//! a closed genus-0 two-manifold.
//!
//! Each face lists its vertices counter-clockwise seen from outside. Every
//! directed boundary step `a -> b` of a face is a half-edge; in a closed
//! two-manifold each half-edge appears exactly once and its twin `b -> a`
//! exactly once, in another face. Each undirected edge is stored once, with
//! `tail = a`, `head = b` for the first face (in face order) that traverses
//! it `a -> b`; that face is its `left_face`, the twin's face its
//! `right_face`. Euler's formula `V - E + F = 2` then rules out handles.

use super::GeometryError;
use super::index_maps::IndexMap;

/// Edge endpoints and faces, before any geometry is attached.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct EdgeTopology {
    pub tail: usize,
    pub head: usize,
    pub left_face: usize,
    pub right_face: usize,
}

/// The result of [`build_topology`].
#[derive(Debug, Clone)]
pub(crate) struct Topology {
    pub edges: Vec<EdgeTopology>,
    /// For each face, `face_edges[f][i]` joins `faces[f][i]` and `faces[f][i + 1]`.
    pub face_edges: Vec<Vec<usize>>,
    /// Incident edges of each vertex.
    pub vertex_edges: Vec<Vec<usize>>,
}

/// Builds edges and adjacency from face cycles over `vertex_count` vertices,
/// checking manifoldness and Euler's formula.
pub(crate) fn build_topology(
    vertex_count: usize,
    faces: &[Vec<usize>],
) -> Result<Topology, GeometryError> {
    let half_edges = index_half_edges(vertex_count, faces)?;
    let mut edges = Vec::new();
    let mut edge_of_half_edge: IndexMap<(usize, usize), usize> = IndexMap::default();
    let mut face_edges = Vec::with_capacity(faces.len());
    for (f, cycle) in faces.iter().enumerate() {
        let mut cycle_edges = Vec::with_capacity(cycle.len());
        for (a, b) in cycle_steps(cycle) {
            let edge = match edge_of_half_edge.get(&(b, a)) {
                Some(&e) => e,
                None => {
                    let twin_face = *half_edges.get(&(b, a)).ok_or_else(|| {
                        GeometryError::InvalidTopology(format!(
                            "edge {a}-{b} of face {f} has only one face"
                        ))
                    })?;
                    edges.push(EdgeTopology {
                        tail: a,
                        head: b,
                        left_face: f,
                        right_face: twin_face,
                    });
                    edges.len() - 1
                }
            };
            edge_of_half_edge.insert((a, b), edge);
            cycle_edges.push(edge);
        }
        face_edges.push(cycle_edges);
    }
    let vertex_edges = incident_edges(vertex_count, &edges)?;
    check_euler(vertex_count, edges.len(), faces.len())?;
    Ok(Topology {
        edges,
        face_edges,
        vertex_edges,
    })
}

/// The directed boundary steps `(a, b)` of a cycle, closing it.
fn cycle_steps(cycle: &[usize]) -> impl Iterator<Item = (usize, usize)> + '_ {
    (0..cycle.len()).map(move |i| (cycle[i], cycle[(i + 1) % cycle.len()]))
}

/// Maps every half-edge to its face; rejects repeated half-edges, short
/// faces and out-of-range indices.
fn index_half_edges(
    vertex_count: usize,
    faces: &[Vec<usize>],
) -> Result<IndexMap<(usize, usize), usize>, GeometryError> {
    let mut half_edges = IndexMap::default();
    for (f, cycle) in faces.iter().enumerate() {
        if cycle.len() < 3 {
            return Err(GeometryError::InvalidTopology(format!(
                "face {f} has {} vertices",
                cycle.len()
            )));
        }
        for (a, b) in cycle_steps(cycle) {
            if a >= vertex_count || b >= vertex_count || a == b {
                return Err(GeometryError::InvalidTopology(format!(
                    "face {f} has an invalid step {a}-{b}"
                )));
            }
            if half_edges.insert((a, b), f).is_some() {
                return Err(GeometryError::InvalidTopology(format!(
                    "half-edge {a}-{b} appears twice"
                )));
            }
        }
    }
    Ok(half_edges)
}

/// Incident edges per vertex; every vertex must have at least three.
fn incident_edges(
    vertex_count: usize,
    edges: &[EdgeTopology],
) -> Result<Vec<Vec<usize>>, GeometryError> {
    let mut vertex_edges = vec![Vec::new(); vertex_count];
    for (e, edge) in edges.iter().enumerate() {
        vertex_edges[edge.tail].push(e);
        vertex_edges[edge.head].push(e);
    }
    if let Some(v) = vertex_edges.iter().position(|list| list.len() < 3) {
        return Err(GeometryError::InvalidTopology(format!(
            "vertex {v} has {} edges",
            vertex_edges[v].len()
        )));
    }
    Ok(vertex_edges)
}

fn check_euler(vertices: usize, edges: usize, faces: usize) -> Result<(), GeometryError> {
    if vertices + faces == edges + 2 {
        Ok(())
    } else {
        Err(GeometryError::InvalidTopology(format!(
            "V - E + F = {vertices} - {edges} + {faces} is not 2"
        )))
    }
}
