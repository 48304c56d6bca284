//! The two bodies of a query and the relative transforms between their
//! frames.
//!
//! V-Clip tests a feature of one body against a Voronoi region of the other,
//! so it needs one body's points in the other's frame. With poses `T_a`,
//! `T_b` (body to world), `T_ab = T_a⁻¹ T_b` maps B's frame into A's (parry's
//! `pos12`) and `T_ba = T_ab⁻¹` the reverse. Both are kept as a rotation
//! matrix and a translation, `x_other = R x_self + t`, so that a query
//! transforms O(1) points per visited feature and never a whole body.
//! A plane `n . x + w = 0` of the other body becomes, in this body's frame,
//! `(Rᵀ n) . x + (n . t + w) = 0`.

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};

use crate::geometry::{ConvexPolyhedron, Plane};

/// A rigid map `x -> R x + t` with `R` stored as a matrix.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RigidMap {
    rotation: Matrix3<f64>,
    translation: Vector3<f64>,
}

impl RigidMap {
    pub fn from_isometry(iso: &Isometry3<f64>) -> Self {
        RigidMap {
            rotation: iso.rotation.to_rotation_matrix().into_inner(),
            translation: iso.translation.vector,
        }
    }

    pub fn point(&self, p: &Point3<f64>) -> Point3<f64> {
        Point3::from(self.rotation * p.coords + self.translation)
    }

    /// The plane `plane` (given in the target frame of this map) expressed in
    /// its source frame.
    pub fn pull_back_plane(&self, plane: &Plane) -> Plane {
        Plane {
            normal: self.rotation.tr_mul(&plane.normal),
            offset: plane.normal.dot(&self.translation) + plane.offset,
        }
    }
}

/// Two polyhedra (index 0 = A, 1 = B) and the maps between their frames.
pub(crate) struct Pair<'a> {
    pub polys: [&'a ConvexPolyhedron; 2],
    /// `to_other[i]` maps body `i`'s frame into the other body's frame.
    pub to_other: [RigidMap; 2],
    /// Slack of every sign test of the walk (length units): 0 in the normal
    /// walk; positive in the tolerant walk after a cycle, where a plane is
    /// only violated, and a derivative only nonzero, beyond the slack.
    pub slack: f64,
}

impl<'a> Pair<'a> {
    pub fn new(
        poly_a: &'a ConvexPolyhedron,
        pose_a: &Isometry3<f64>,
        poly_b: &'a ConvexPolyhedron,
        pose_b: &Isometry3<f64>,
    ) -> Self {
        let b_in_a = pose_a.inv_mul(pose_b);
        Pair {
            polys: [poly_a, poly_b],
            to_other: [
                RigidMap::from_isometry(&b_in_a.inverse()),
                RigidMap::from_isometry(&b_in_a),
            ],
            slack: 0.0,
        }
    }

    /// Vertex `v` of body `body`, in its own frame.
    pub fn vertex(&self, body: usize, v: usize) -> Point3<f64> {
        self.polys[body].vertices()[v]
    }

    /// Vertex `v` of body `body`, in the other body's frame.
    pub fn vertex_in_other(&self, body: usize, v: usize) -> Point3<f64> {
        self.to_other[body].point(&self.polys[body].vertices()[v])
    }

    /// Tail and head of edge `e` of body `body`, in the other body's frame.
    pub fn edge_in_other(&self, body: usize, e: usize) -> (Point3<f64>, Point3<f64>) {
        let edge = &self.polys[body].edges()[e];
        (
            self.vertex_in_other(body, edge.tail),
            self.vertex_in_other(body, edge.head),
        )
    }

    /// Plane of face `f` of body `body`, in the other body's frame.
    pub fn face_plane_in_other(&self, body: usize, f: usize) -> Plane {
        let plane = self.polys[body].faces()[f].plane;
        self.to_other[1 - body].pull_back_plane(&plane)
    }
}
