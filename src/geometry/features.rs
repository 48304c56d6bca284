//! Features of a polyhedron: the closed sets that V-Clip walks over.

/// A vertex, an edge or a face of one polyhedron, by index.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Feature {
    /// Index into [`crate::geometry::ConvexPolyhedron::vertices`].
    Vertex(usize),
    /// Index into [`crate::geometry::ConvexPolyhedron::edges`].
    Edge(usize),
    /// Index into [`crate::geometry::ConvexPolyhedron::faces`].
    Face(usize),
}

impl Feature {
    /// Dimension of the feature: 0 for a vertex, 1 for an edge, 2 for a face.
    pub fn dimension(self) -> usize {
        match self {
            Feature::Vertex(_) => 0,
            Feature::Edge(_) => 1,
            Feature::Face(_) => 2,
        }
    }
}
