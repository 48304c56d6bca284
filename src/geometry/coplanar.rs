//! From a triangulated convex hull to polygonal faces.
//!
//! Hull algorithms return triangles; a polyhedron for V-Clip wants one face
//! per supporting plane. With `L` the extent of the point set and `M` its
//! largest absolute coordinate:
//! 1. Triangles are visited by decreasing area; each unassigned triangle
//!    seeds a face with its own plane `P` (the largest triangle of a face has
//!    the best conditioned normal). The face grows across edges to adjacent
//!    unassigned triangles whose three vertices all lie within
//!    [`COPLANAR_TOLERANCE`]` * max(L, M)` of `P` (`M` the largest
//!    coordinate).
//! 2. The boundary of a face is the set of its triangles' half-edges whose
//!    twin belongs to another face. It must be one simple cycle and turn
//!    left at every vertex (within the tolerance); a face whose union is
//!    pinched, has a hole or is notched (a bump of points just above the
//!    plane, but above the tolerance, forms faces of its own that can cut
//!    into the union) is split back into its triangles.
//! 3. Vertices that lie on exactly two faces are not corners of the hull:
//!    both faces contain the vertex and its two neighbours, so the three are
//!    collinear on the faces' common line (a point in the middle of an
//!    edge). They are removed from both cycles. Points inside a merged face
//!    are on no boundary and disappear with step 2.
//!
//! Orientation is inherited: triangles are counter-clockwise seen from
//! outside, so boundary half-edges of a face are too.

use std::collections::VecDeque;

use nalgebra::{Point3, Vector3};

use super::GeometryError;
use super::index_maps::{IndexMap, IndexSet};
use super::plane::triangle_area_vector;

/// Adjacent hull triangles are one face when every vertex of one is within
/// `COPLANAR_TOLERANCE * max(L, M)` of the plane of the face's largest
/// triangle (`L` extent, `M` largest coordinate of the input). Covers the
/// rounding of points generated on a common plane (a few `ε max(L, M)`)
/// with a wide margin, while keeping the Newell normal of a merged face of
/// width `w` within about `COPLANAR_TOLERANCE * max(L, M) / w` radians of
/// its plane.
pub const COPLANAR_TOLERANCE: f64 = 1e-12;

/// Polygonal faces over a subset of the input points.
#[derive(Debug, Clone)]
pub(crate) struct HullFaces {
    /// Indices into the input points of the hull's vertices.
    pub vertices: Vec<usize>,
    /// Faces as counter-clockwise cycles of indices into `vertices`.
    pub faces: Vec<Vec<usize>>,
}

/// Merges the counter-clockwise `triangles` (indices into `points`) of a
/// closed convex hull into polygonal faces; see the module doc.
/// `tolerance` is absolute (see [`COPLANAR_TOLERANCE`]).
pub(crate) fn polygon_faces(
    points: &[Point3<f64>],
    triangles: &[[usize; 3]],
    tolerance: f64,
) -> Result<HullFaces, GeometryError> {
    let neighbours = triangle_neighbours(triangles)?;
    let groups = group_coplanar(points, triangles, &neighbours, tolerance);
    let mut cycles = Vec::new();
    let mut split = 0;
    for (group, normal) in &groups {
        let convex = |members: &[usize]| {
            boundary_cycle(triangles, members)
                .filter(|cycle| is_convex_polygon(points, cycle, normal, tolerance))
        };
        match convex(group) {
            Some(cycle) => cycles.push(cycle),
            None => {
                split += 1;
                cycles.extend(convex_pieces(triangles, group, &neighbours, convex));
            }
        }
    }
    if split > 0 {
        log::trace!("{split} coplanar groups split into convex pieces");
    }
    drop_edge_points(&mut cycles)?;
    Ok(compact(cycles))
}

/// For each triangle and each of its edges `i` (from corner `i` to
/// `i + 1`), the triangle across that edge.
fn triangle_neighbours(triangles: &[[usize; 3]]) -> Result<Vec<[usize; 3]>, GeometryError> {
    let mut owner: IndexMap<(usize, usize), usize> = IndexMap::default();
    for (t, tri) in triangles.iter().enumerate() {
        for i in 0..3 {
            if owner.insert((tri[i], tri[(i + 1) % 3]), t).is_some() {
                return Err(GeometryError::HullFailed(format!(
                    "edge {}-{} is used twice in one direction",
                    tri[i],
                    tri[(i + 1) % 3]
                )));
            }
        }
    }
    triangles
        .iter()
        .map(|tri| {
            let across = |i: usize| {
                owner
                    .get(&(tri[(i + 1) % 3], tri[i]))
                    .copied()
                    .ok_or_else(|| {
                        GeometryError::HullFailed("the triangle hull is not closed".into())
                    })
            };
            Ok([across(0)?, across(1)?, across(2)?])
        })
        .collect()
}

/// Groups of triangles (by index) that form one planar face, with the unit
/// normal of their seed.
fn group_coplanar(
    points: &[Point3<f64>],
    triangles: &[[usize; 3]],
    neighbours: &[[usize; 3]],
    tolerance: f64,
) -> Vec<(Vec<usize>, Vector3<f64>)> {
    let doubled_area = |t: &[usize; 3]| {
        (points[t[1]] - points[t[0]])
            .cross(&(points[t[2]] - points[t[0]]))
            .norm()
    };
    let mut by_area: Vec<usize> = (0..triangles.len()).collect();
    by_area.sort_by(|&a, &b| doubled_area(&triangles[b]).total_cmp(&doubled_area(&triangles[a])));
    let mut assigned = vec![false; triangles.len()];
    let mut groups = Vec::new();
    for seed in by_area {
        if assigned[seed] {
            continue;
        }
        assigned[seed] = true;
        let normal = triangle_normal(points, &triangles[seed]);
        let anchor = points[triangles[seed][0]];
        let on_plane = |t: usize| {
            triangles[t]
                .iter()
                .all(|&v| (points[v] - anchor).dot(&normal).abs() <= tolerance)
        };
        let mut group = vec![seed];
        let mut queue = VecDeque::from([seed]);
        while let Some(t) = queue.pop_front() {
            for &u in &neighbours[t] {
                if !assigned[u] && on_plane(u) {
                    assigned[u] = true;
                    group.push(u);
                    queue.push_back(u);
                }
            }
        }
        groups.push((group, normal));
    }
    groups
}

/// Splits a group (triangles in decreasing area) into pieces grown like the
/// groups, a neighbour joining only if the piece's boundary stays one
/// convex cycle (`convex` returns it). A piece that is a single triangle
/// is that triangle. `O(k²)` for `k` triangles; only notched groups come
/// here.
fn convex_pieces(
    triangles: &[[usize; 3]],
    group: &[usize],
    neighbours: &[[usize; 3]],
    convex: impl Fn(&[usize]) -> Option<Vec<usize>>,
) -> Vec<Vec<usize>> {
    let in_group: IndexSet<usize> = group.iter().copied().collect();
    let mut assigned: IndexSet<usize> = IndexSet::default();
    let mut pieces = Vec::new();
    for &seed in group {
        if !assigned.insert(seed) {
            continue;
        }
        let mut piece = vec![seed];
        let mut k = 0;
        while k < piece.len() {
            for &u in &neighbours[piece[k]] {
                if in_group.contains(&u) && !assigned.contains(&u) {
                    piece.push(u);
                    if convex(&piece).is_some() {
                        assigned.insert(u);
                    } else {
                        piece.pop();
                    }
                }
            }
            k += 1;
        }
        match convex(&piece) {
            Some(cycle) if piece.len() > 1 => pieces.push(cycle),
            _ => pieces.extend(piece.iter().map(|&t| triangles[t].to_vec())),
        }
    }
    pieces
}

/// Whether the cycle turns left (about `normal`) at every vertex, allowing
/// each vertex to lie up to `tolerance` on the wrong side of the segment
/// joining its neighbours.
///
/// The union of triangles near one plane need not be convex: a bump of
/// points just above a face (higher than the merge tolerance) forms its own
/// faces and can notch the merged polygon. A notched group is split back
/// into its triangles, which are each convex.
fn is_convex_polygon(
    points: &[Point3<f64>],
    cycle: &[usize],
    normal: &Vector3<f64>,
    tolerance: f64,
) -> bool {
    let n = cycle.len();
    (0..n).all(|i| {
        let [a, b, c] = [i, i + 1, i + 2].map(|k| points[cycle[k % n]]);
        let turn = (b - a).cross(&(c - b)).dot(normal);
        turn >= -tolerance * (c - a).norm()
    })
}

/// The boundary of a group of triangles as one counter-clockwise cycle, or
/// `None` when it is not a single simple cycle.
fn boundary_cycle(triangles: &[[usize; 3]], group: &[usize]) -> Option<Vec<usize>> {
    let mut inside: IndexSet<(usize, usize)> = IndexSet::default();
    for &t in group {
        for i in 0..3 {
            inside.insert((triangles[t][i], triangles[t][(i + 1) % 3]));
        }
    }
    let mut next: IndexMap<usize, usize> = IndexMap::default();
    for &(a, b) in &inside {
        if !inside.contains(&(b, a)) && next.insert(a, b).is_some() {
            return None;
        }
    }
    let start = *next.keys().min()?;
    let mut cycle = vec![start];
    let mut current = next[&start];
    while current != start {
        if cycle.len() >= next.len() {
            return None;
        }
        cycle.push(current);
        current = *next.get(&current)?;
    }
    (cycle.len() == next.len()).then_some(cycle)
}

/// Removes from every cycle the vertices that lie on exactly two faces.
fn drop_edge_points(cycles: &mut [Vec<usize>]) -> Result<(), GeometryError> {
    let mut face_count: IndexMap<usize, usize> = IndexMap::default();
    for cycle in cycles.iter() {
        for &v in cycle {
            *face_count.entry(v).or_default() += 1;
        }
    }
    for cycle in cycles.iter_mut() {
        cycle.retain(|v| face_count[v] > 2);
        if cycle.len() < 3 {
            return Err(GeometryError::HullFailed(
                "a face collapsed when points in the middle of edges were removed".into(),
            ));
        }
    }
    Ok(())
}

/// Renumbers the vertices used by `cycles` as `0..n`.
fn compact(cycles: Vec<Vec<usize>>) -> HullFaces {
    let mut vertices = Vec::new();
    let mut new_index: IndexMap<usize, usize> = IndexMap::default();
    let faces = cycles
        .into_iter()
        .map(|cycle| {
            cycle
                .into_iter()
                .map(|v| {
                    *new_index.entry(v).or_insert_with(|| {
                        vertices.push(v);
                        vertices.len() - 1
                    })
                })
                .collect()
        })
        .collect();
    HullFaces { vertices, faces }
}

/// Unit normal of a triangle (zero when the triangle is degenerate), taken
/// at its best corner ([`triangle_area_vector`]): the seed of a thin face
/// (a side of a thin slab, split along a diagonal) then has a normal
/// accurate to rounding, and its twin triangle, whose far corner is a face
/// length away, is found coplanar.
fn triangle_normal(points: &[Point3<f64>], t: &[usize; 3]) -> Vector3<f64> {
    let [a, b, c] = t.map(|i| points[i]);
    triangle_area_vector(&a, &b, &c)
        .try_normalize(0.0)
        .unwrap_or_else(Vector3::zeros)
}
