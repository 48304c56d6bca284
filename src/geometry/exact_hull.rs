//! Triangulated convex hull by incremental construction (beneath–beyond)
//! with exact orientation predicates.
//!
//! `orient3d(a, b, c, p)` (Shewchuk 1997, adaptive exact arithmetic, crate
//! `robust`) is negative exactly when `p` is strictly above the plane of the
//! counter-clockwise triangle `(a, b, c)`, i.e. on the side its normal
//! `(b - a) × (c - a)` points to. Every decision below is that sign on the
//! input coordinates themselves, so the result is exactly convex for the
//! given floats: every edge is locally convex (the opposite vertex of the
//! neighbouring triangle is on or below the plane) and every input point is
//! on or below every triangle plane. Nothing is rounded into a wrong
//! topology, whatever the near-degeneracies (coplanar and collinear points
//! included); near-coplanar triangles are merged afterwards with a
//! tolerance (`super::coplanar`).
//!
//! Algorithm: start from a tetrahedron of four extreme points; every other
//! point is assigned to one triangle it sees (a *conflict*). Adding a point
//! `p`: the triangles it sees form a disk (the visible region of a convex
//! polytope from an outside point); they are found by a search across edges
//! from its conflict triangle, removed, and every horizon edge `(a, b)` is
//! joined to `p` by a new triangle `(a, b, p)`. The conflicts of removed
//! triangles are reassigned to a new triangle they see, else to any
//! visible triangle, else dropped (inside). Expected `O(n log n)` for points
//! in general position, `O(n²)` worst case.

use nalgebra::Point3;
use robust::{Coord3D, orient3d};

use super::GeometryError;
use super::index_maps::IndexMap;

/// A triangle of the hull under construction.
#[derive(Debug, Clone)]
struct Triangle {
    vertices: [usize; 3],
    alive: bool,
    /// Points assigned to this triangle, which they see.
    conflicts: Vec<usize>,
}

/// Triangles seen from a point, and the horizon edges `(a, b)` as the
/// visible triangles traverse them.
type VisibleRegion = (Vec<usize>, Vec<(usize, usize)>);

/// The hull under construction. Removed triangles stay in `triangles`
/// (not alive) so that indices are stable.
struct Hull<'a> {
    points: &'a [Point3<f64>],
    triangles: Vec<Triangle>,
    /// Directed edge `(a, b)` -> the alive triangle that traverses it.
    edge_owner: IndexMap<(usize, usize), usize>,
}

/// Counter-clockwise (seen from outside) triangles of the convex hull of
/// `points`, starting from the non-degenerate tetrahedron `simplex`.
/// Points strictly inside or on the boundary without being needed as
/// vertices are not used; coplanar triangles are not merged.
pub(crate) fn hull_triangles(
    points: &[Point3<f64>],
    simplex: [usize; 4],
) -> Result<Vec<[usize; 3]>, GeometryError> {
    let mut hull = Hull::tetrahedron(points, simplex)?;
    let mut order: Vec<usize> = (0..points.len()).filter(|i| !simplex.contains(i)).collect();
    hull.assign_conflicts(&mut order, 0..4);
    let mut next = 0;
    while next < hull.triangles.len() {
        match hull.triangles[next].conflicts.pop() {
            Some(p) if hull.triangles[next].alive => hull.add_point(p, next)?,
            Some(_) => {}
            None => next += 1,
        }
    }
    Ok(hull
        .triangles
        .into_iter()
        .filter(|t| t.alive)
        .map(|t| t.vertices)
        .collect())
}

fn coord(p: &Point3<f64>) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

impl<'a> Hull<'a> {
    /// The tetrahedron on `simplex`, each face oriented so that the fourth
    /// vertex is strictly below it.
    fn tetrahedron(points: &'a [Point3<f64>], simplex: [usize; 4]) -> Result<Self, GeometryError> {
        let mut hull = Hull {
            points,
            triangles: Vec::new(),
            edge_owner: IndexMap::default(),
        };
        for skip in 0..4 {
            let others: Vec<usize> = (0..4).filter(|&i| i != skip).map(|i| simplex[i]).collect();
            let mut face = [others[0], others[1], others[2]];
            let side = hull.orient(&face, simplex[skip]);
            if side == 0.0 {
                return Err(GeometryError::Degenerate);
            }
            if side < 0.0 {
                face.swap(1, 2);
            }
            hull.push_triangle(face);
        }
        Ok(hull)
    }

    /// `orient3d` of a triangle and a point: negative when `p` is strictly
    /// above (outside).
    fn orient(&self, face: &[usize; 3], p: usize) -> f64 {
        let [a, b, c] = face.map(|i| coord(&self.points[i]));
        orient3d(a, b, c, coord(&self.points[p]))
    }

    fn sees(&self, t: usize, p: usize) -> bool {
        self.orient(&self.triangles[t].vertices, p) < 0.0
    }

    fn push_triangle(&mut self, vertices: [usize; 3]) -> usize {
        let t = self.triangles.len();
        for i in 0..3 {
            self.edge_owner
                .insert((vertices[i], vertices[(i + 1) % 3]), t);
        }
        self.triangles.push(Triangle {
            vertices,
            alive: true,
            conflicts: Vec::new(),
        });
        t
    }

    /// Gives each point in `candidates` to the first triangle in `among`
    /// that it sees; points that see none are inside and dropped.
    ///
    /// Called with the triangles just created for the conflicts of the
    /// triangles just removed, this drops no outside point (Barber, Dobkin
    /// and Huhdanpaa 1996, Quickhull): if `q` saw a removed triangle `f`
    /// and is outside the new hull, the segment from `q` to `f` enters the
    /// new hull above the plane of `f`, hence outside the old hull, hence
    /// through a new triangle, which `q` therefore sees.
    fn assign_conflicts(&mut self, candidates: &mut Vec<usize>, among: std::ops::Range<usize>) {
        for p in candidates.drain(..) {
            let seen = among.clone().find(|&t| self.sees(t, p));
            if let Some(t) = seen {
                self.triangles[t].conflicts.push(p);
            }
        }
    }

    /// Adds `p`, which sees triangle `start`.
    fn add_point(&mut self, p: usize, start: usize) -> Result<(), GeometryError> {
        let (visible, horizon) = self.visible_region(p, start)?;
        let mut orphans = Vec::new();
        for &t in &visible {
            let triangle = &mut self.triangles[t];
            triangle.alive = false;
            orphans.append(&mut triangle.conflicts);
            for i in 0..3 {
                let edge = (triangle.vertices[i], triangle.vertices[(i + 1) % 3]);
                if self.edge_owner.get(&edge) == Some(&t) {
                    self.edge_owner.remove(&edge);
                }
            }
        }
        let first_new = self.triangles.len();
        for (a, b) in horizon {
            self.push_triangle([a, b, p]);
        }
        self.assign_conflicts(&mut orphans, first_new..self.triangles.len());
        Ok(())
    }

    /// The triangles `p` sees (search across edges from `start`) and the
    /// horizon: edges of visible triangles whose neighbour is not visible,
    /// in the direction the visible triangle traverses them.
    fn visible_region(&self, p: usize, start: usize) -> Result<VisibleRegion, GeometryError> {
        let mut visible = vec![start];
        let mut is_visible: IndexMap<usize, bool> = IndexMap::from_iter([(start, true)]);
        let mut horizon = Vec::new();
        let mut k = 0;
        while k < visible.len() {
            let t = visible[k];
            k += 1;
            let vertices = self.triangles[t].vertices;
            for i in 0..3 {
                let (a, b) = (vertices[i], vertices[(i + 1) % 3]);
                let neighbour = *self.edge_owner.get(&(b, a)).ok_or_else(|| {
                    GeometryError::HullFailed(format!("edge {a}-{b} has no twin"))
                })?;
                let seen = match is_visible.get(&neighbour) {
                    Some(&seen) => seen,
                    None => {
                        let seen = self.sees(neighbour, p);
                        is_visible.insert(neighbour, seen);
                        if seen {
                            visible.push(neighbour);
                        }
                        seen
                    }
                };
                if !seen {
                    horizon.push((a, b));
                }
            }
        }
        Ok((visible, horizon))
    }
}
