//! Islands: groups of dynamic bodies connected by contact pairs.
//!
//! An island is a connected component of the graph whose vertices are the
//! dynamic bodies and whose edges are the given pairs between two dynamic
//! bodies. Fixed bodies are not vertices: they never move, so a fixed body
//! touching two dynamic bodies does not couple their corrections (the
//! fixed body's columns are absent from `J`, and `A = J M^-1 J^T` has no
//! entry linking the two). A pair of a fixed and a dynamic body belongs to
//! the dynamic body's island; a pair of two fixed bodies to none.
//!
//! Components are found by union-find (disjoint-set forest with path
//! halving and union by size; Tarjan 1975), near-linear in the number of
//! pairs. The output does not depend on the order of the input pairs beyond
//! the pair indices it reports:
//! - islands sorted by their smallest body index,
//! - each island's `bodies` and `fixed_bodies` sorted ascending,
//! - each island's `pairs` (indices into the input) ascending.
//!
//! Only bodies that appear in at least one pair are in an island: a
//! dynamic body with no pair needs no correction.

use thiserror::Error;

use crate::broad_phase::BodyPair;

/// A group of dynamic bodies whose corrections are coupled.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Island {
    /// Dynamic bodies of the island, ascending (never empty).
    pub bodies: Vec<usize>,
    /// Fixed bodies that some pair of the island touches, ascending.
    pub fixed_bodies: Vec<usize>,
    /// Indices into the input pair list of the pairs of this island, ascending.
    pub pairs: Vec<usize>,
    /// Indices into the input joint list of the joints of this island,
    /// ascending ([`islands_with_joints`]; empty from [`islands`]).
    pub joints: Vec<usize>,
}

/// Why islands could not be formed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum IslandError {
    /// A pair names a body index outside the scene.
    #[error("pair {pair} names body {body}, but there are {body_count} bodies")]
    BodyOutOfRange {
        /// Index of the pair in the input.
        pair: usize,
        /// The offending body index.
        body: usize,
        /// Number of bodies.
        body_count: usize,
    },
    /// A pair joins a body to itself.
    #[error("pair {pair} joins body {body} to itself")]
    SelfPair {
        /// Index of the pair in the input.
        pair: usize,
        /// The body.
        body: usize,
    },
    /// An island to be solved lists a body without mass properties (a
    /// fixed body): islands are built from dynamic bodies only, so this is
    /// an internal inconsistency, reported rather than trusted.
    #[error("body {body} is in an island but has no mass")]
    MasslessBody {
        /// The body.
        body: usize,
    },
}

/// Disjoint-set forest over `0..n`.
struct UnionFind {
    parent: Vec<usize>,
    size: Vec<usize>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n).collect(),
            size: vec![1; n],
        }
    }

    /// Root of `x`, halving the path on the way.
    fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }

    fn union(&mut self, a: usize, b: usize) {
        let (root_a, root_b) = (self.find(a), self.find(b));
        if root_a == root_b {
            return;
        }
        let (big, small) = if self.size[root_a] >= self.size[root_b] {
            (root_a, root_b)
        } else {
            (root_b, root_a)
        };
        self.parent[small] = big;
        self.size[big] += self.size[small];
    }
}

/// Islands of the bodies `0..fixed.len()` (`fixed[i]`: body `i` is fixed)
/// under the contact `pairs`.
pub fn islands(fixed: &[bool], pairs: &[BodyPair]) -> Result<Vec<Island>, IslandError> {
    check_pairs(fixed.len(), pairs)?;
    let mut sets = UnionFind::new(fixed.len());
    for pair in pairs {
        if !fixed[pair.body_a] && !fixed[pair.body_b] {
            sets.union(pair.body_a, pair.body_b);
        }
    }
    let (mut result, slot_of_root) = collect_bodies(fixed, pairs, &mut sets);
    for (index, pair) in pairs.iter().enumerate() {
        let Some(dynamic_body) = [pair.body_a, pair.body_b].into_iter().find(|&b| !fixed[b]) else {
            continue; // two fixed bodies: no island
        };
        let island = &mut result[slot_of_root[sets.find(dynamic_body)]];
        island.pairs.push(index);
        let fixed_ends = [pair.body_a, pair.body_b].into_iter().filter(|&b| fixed[b]);
        island.fixed_bodies.extend(fixed_ends);
    }
    for island in &mut result {
        island.fixed_bodies.sort_unstable();
        island.fixed_bodies.dedup();
    }
    log::debug!(
        "  islands: {} bodies, {} pairs touching or penetrating, {} islands",
        fixed.len(),
        pairs.len(),
        result.len()
    );
    Ok(result)
}

/// Islands of the contact `pairs` and the bodies of `joints`: a joint
/// couples its bodies like a pair does (a joint to a fixed body joins the
/// dynamic body's island, as a pair with it). Each island's `pairs` index
/// `pairs` and its `joints` index `joints`, both ascending.
pub fn islands_with_joints(
    fixed: &[bool],
    pairs: &[BodyPair],
    joints: &[BodyPair],
) -> Result<Vec<Island>, IslandError> {
    let all: Vec<BodyPair> = pairs.iter().chain(joints).copied().collect();
    let mut result = islands(fixed, &all)?;
    for island in &mut result {
        let split = island.pairs.partition_point(|&k| k < pairs.len());
        island.joints = island.pairs.split_off(split);
        for k in &mut island.joints {
            *k -= pairs.len();
        }
    }
    Ok(result)
}

/// One empty island per component that has a dynamic body in some pair,
/// with its bodies; islands are allocated in increasing order of body
/// index, so they come out sorted by their smallest body. Also returns the
/// island slot of each root.
fn collect_bodies(
    fixed: &[bool],
    pairs: &[BodyPair],
    sets: &mut UnionFind,
) -> (Vec<Island>, Vec<usize>) {
    let mut in_pair = vec![false; fixed.len()];
    for pair in pairs {
        in_pair[pair.body_a] = true;
        in_pair[pair.body_b] = true;
    }
    let mut slot_of_root = vec![usize::MAX; fixed.len()];
    let mut result: Vec<Island> = Vec::new();
    for body in (0..fixed.len()).filter(|&b| in_pair[b] && !fixed[b]) {
        let root = sets.find(body);
        if slot_of_root[root] == usize::MAX {
            slot_of_root[root] = result.len();
            result.push(Island {
                bodies: Vec::new(),
                fixed_bodies: Vec::new(),
                pairs: Vec::new(),
                joints: Vec::new(),
            });
        }
        result[slot_of_root[root]].bodies.push(body);
    }
    (result, slot_of_root)
}

fn check_pairs(body_count: usize, pairs: &[BodyPair]) -> Result<(), IslandError> {
    for (index, pair) in pairs.iter().enumerate() {
        for body in [pair.body_a, pair.body_b] {
            if body >= body_count {
                return Err(IslandError::BodyOutOfRange {
                    pair: index,
                    body,
                    body_count,
                });
            }
        }
        if pair.body_a == pair.body_b {
            return Err(IslandError::SelfPair {
                pair: index,
                body: pair.body_a,
            });
        }
    }
    Ok(())
}
