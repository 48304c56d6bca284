//! Clipping an edge against the planes of a Voronoi region (Mirtich 1998,
//! section 4.2, `clipEdge`).
//!
//! The edge is `e(l) = (1 - l) t + l h`, `l ∈ [0, 1]`, given in the frame of
//! the region's polyhedron. Each plane `P` bounds the region (its positive
//! side) and has behind it the neighbour feature `N` of the region's
//! feature. With `dt = D_P(t)`, `dh = D_P(h)`:
//! - both negative: the edge is *simply excluded* by `P`; `N_lo = N_hi = N`;
//! - `dt < 0 <= dh`: the edge enters at `l = dt / (dt - dh)`, which raises
//!   `l_lo` (neighbour `N_lo`);
//! - `dh < 0 <= dt`: it leaves at the same formula, which lowers `l_hi`.
//!
//! If `l_lo > l_hi` the edge is *compoundly excluded*: no single plane cuts
//! it off, but no point of it lies in the region. These divisions are the
//! only ones of the algorithm, and `dt - dh` is never zero in them because
//! `dt` and `dh` have strictly different signs.

use nalgebra::Point3;

use crate::geometry::{Feature, Plane};

/// Why an edge was excluded from a region.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exclusion {
    /// One plane has both ends of the edge on its negative side; the
    /// neighbour behind it.
    Simple(Feature),
    /// No single plane excludes it, but the clipped interval is empty.
    Compound,
}

/// The state of a clip: the surviving interval and the neighbours whose
/// planes cut it. A clip can be continued with more planes (V-Clip does that
/// for edge regions: vertex-edge planes first, then face-edge planes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clip {
    /// A point is on the negative side of a plane only below `-slack`.
    pub slack: f64,
    pub l_lo: f64,
    pub l_hi: f64,
    pub n_lo: Option<Feature>,
    pub n_hi: Option<Feature>,
}

impl Clip {
    /// The whole edge, no neighbour yet.
    pub fn new(slack: f64) -> Self {
        Clip {
            slack,
            l_lo: 0.0,
            l_hi: 1.0,
            n_lo: None,
            n_hi: None,
        }
    }

    /// Clips the edge `tail -> head` against `plane` (neighbour `neighbour`).
    pub fn against(
        &mut self,
        plane: &Plane,
        neighbour: Feature,
        tail: &Point3<f64>,
        head: &Point3<f64>,
    ) -> Option<Exclusion> {
        let dt = plane.signed_distance(tail);
        let dh = plane.signed_distance(head);
        let outside = -self.slack;
        if dt < outside && dh < outside {
            self.n_lo = Some(neighbour);
            self.n_hi = Some(neighbour);
            return Some(Exclusion::Simple(neighbour));
        }
        if dt < outside {
            let l = dt / (dt - dh);
            if l > self.l_lo {
                self.l_lo = l;
                self.n_lo = Some(neighbour);
            }
        } else if dh < outside {
            let l = dt / (dt - dh);
            if l < self.l_hi {
                self.l_hi = l;
                self.n_hi = Some(neighbour);
            }
        } else {
            return None;
        }
        (self.l_lo > self.l_hi).then_some(Exclusion::Compound)
    }

    /// Clips against every `(plane, neighbour)`, stopping at the first
    /// exclusion.
    pub fn against_all(
        &mut self,
        planes: impl IntoIterator<Item = (Plane, Feature)>,
        tail: &Point3<f64>,
        head: &Point3<f64>,
    ) -> Option<Exclusion> {
        planes
            .into_iter()
            .find_map(|(plane, neighbour)| self.against(&plane, neighbour, tail, head))
    }
}

/// The point at parameter `l` of the edge `tail -> head`.
pub(crate) fn lerp(tail: &Point3<f64>, head: &Point3<f64>, l: f64) -> Point3<f64> {
    tail + (head - tail) * l
}
