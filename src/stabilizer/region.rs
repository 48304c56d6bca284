//! The region of an island that a pass solves: the bodies that still
//! penetrate, grown only as far as the correction pushes.
//!
//! After the first pass of a resting island, a few pairs still penetrate
//! while hundreds rest; re-solving the whole island for them costs the
//! whole island's QP every pass. A pass therefore starts from the dynamic
//! bodies of the pairs penetrating deeper than the tolerance and their
//! neighbours (one hop through the island's pairs); every other body of
//! the island holds still (its contacts with the region stay rows
//! of the problem, as a fixed body's do, so the step cannot push into it).
//!
//! Holding a body still is exact when the answer does not push it. The
//! region's answer `dq = M^-1 J^T lambda` has a multiplier `lambda_k >= 0`
//! on every row; a row between a region body and a held body `j` pushes
//! `j` with force `-lambda_k n_k` (the region body's linear block is `n_k`,
//! equal and opposite). Were `j` free, the first-order answer would move it
//! by `|sum_k lambda_k n_k| / m_j`. If that is within the tolerance for
//! every held body, the KKT conditions of the whole island hold to within
//! the tolerance and the region's answer is taken; otherwise the pushed
//! bodies join the region with their neighbours (one hop, then two, four,
//! ...) and the region is solved again. A region whose problem the first
//! solver cannot solve (held bodies leave no room; no fallback is tried
//! there) grows the same way. A region grown past half the island becomes
//! the whole island, so that the rounds cost at most about twice the whole
//! island's problem. The last round is the whole island, with every
//! fallback.

use nalgebra::Vector3;

use crate::broad_phase::BodyPair;
use crate::solver::JacobianRow;

/// The growth of a region inside its island.
#[derive(Debug, Clone)]
pub struct Region {
    /// Dynamic bodies of the island, ascending.
    island_bodies: Vec<usize>,
    /// Neighbours of each island body through the island's pairs (dynamic
    /// bodies only), by position in `island_bodies`.
    neighbours: Vec<Vec<usize>>,
    /// Whether each island body is in the region.
    inside: Vec<bool>,
    /// Hops by which the next growth extends the pushed bodies.
    hops: usize,
}

impl Region {
    /// The region of the bodies of `penetrating` pairs, inside the island
    /// of `bodies` (ascending) and `pairs`.
    pub fn new(bodies: &[usize], pairs: &[BodyPair], penetrating: &[BodyPair]) -> Self {
        let position = |body: usize| bodies.binary_search(&body).ok();
        let mut neighbours = vec![Vec::new(); bodies.len()];
        for pair in pairs {
            if let (Some(a), Some(b)) = (position(pair.body_a), position(pair.body_b)) {
                neighbours[a].push(b);
                neighbours[b].push(a);
            }
        }
        let mut region = Region {
            island_bodies: bodies.to_vec(),
            neighbours,
            inside: vec![false; bodies.len()],
            hops: 1,
        };
        let seeds: Vec<usize> = penetrating
            .iter()
            .flat_map(|pair| [pair.body_a, pair.body_b])
            .collect();
        region.grow(&seeds);
        region
    }

    /// The whole island.
    pub fn whole(bodies: &[usize]) -> Self {
        Region {
            island_bodies: bodies.to_vec(),
            neighbours: vec![Vec::new(); bodies.len()],
            inside: vec![true; bodies.len()],
            hops: 1,
        }
    }

    /// The region's bodies, ascending.
    pub fn bodies(&self) -> Vec<usize> {
        self.island_bodies
            .iter()
            .zip(&self.inside)
            .filter(|(_, inside)| **inside)
            .map(|(&body, _)| body)
            .collect()
    }

    /// Whether the region is the whole island.
    pub fn is_whole(&self) -> bool {
        self.inside.iter().all(|&inside| inside)
    }

    /// Whether `body` is a dynamic body of the island outside the region.
    pub fn holds_still(&self, body: usize) -> bool {
        self.island_bodies
            .binary_search(&body)
            .is_ok_and(|i| !self.inside[i])
    }

    /// Adds `pushed` (scene indices) and their neighbours within the
    /// current number of hops, then doubles the hops. With nothing pushed,
    /// grows the whole region's border instead (its problem could not be
    /// solved).
    pub fn grow(&mut self, pushed: &[usize]) {
        let mut frontier: Vec<usize> = if pushed.is_empty() {
            (0..self.inside.len()).filter(|&i| self.inside[i]).collect()
        } else {
            pushed
                .iter()
                .filter_map(|&body| self.island_bodies.binary_search(&body).ok())
                .collect()
        };
        for &i in &frontier {
            self.inside[i] = true;
        }
        for _ in 0..self.hops {
            let mut next = Vec::new();
            for &i in &frontier {
                for &j in &self.neighbours[i] {
                    if !self.inside[j] {
                        self.inside[j] = true;
                        next.push(j);
                    }
                }
            }
            frontier = next;
        }
        self.hops *= 2;
        if 2 * self.inside.iter().filter(|&&inside| inside).count() > self.inside.len() {
            self.inside.fill(true);
        }
    }
}

/// The held bodies that the region's answer pushes by more than
/// `tolerance`, ascending: `|sum_k lambda_k n_k| / m_j` over the rows of
/// pairs between the region and held body `j` (module docs; for a row of
/// the friction pyramid, `n_k` is the linear part of its facet, so
/// tangential forces count too). `row_pairs`
/// gives each row's pair, `mass` a held body's mass.
pub fn pushed_bodies(
    region: &Region,
    pairs: &[BodyPair],
    rows: &[JacobianRow],
    row_pairs: &[usize],
    lambda: &[f64],
    mass: impl Fn(usize) -> f64,
    tolerance: f64,
) -> Vec<usize> {
    let mut force: Vec<(usize, Vector3<f64>)> = Vec::new();
    for ((row, &k), &lambda) in rows.iter().zip(row_pairs).zip(lambda) {
        let pair = pairs[k];
        let held = [pair.body_a, pair.body_b]
            .into_iter()
            .find(|&body| region.holds_still(body));
        let (Some(held), Some((_, block))) = (held, row.blocks.first()) else {
            continue;
        };
        let push = -lambda * block.fixed_rows::<3>(0).into_owned();
        match force.iter_mut().find(|(body, _)| *body == held) {
            Some((_, total)) => *total += push,
            None => force.push((held, push)),
        }
    }
    let mut pushed: Vec<usize> = force
        .into_iter()
        .filter(|(body, total)| total.norm() / mass(*body) > tolerance)
        .map(|(body, _)| body)
        .collect();
    pushed.sort_unstable();
    pushed
}
