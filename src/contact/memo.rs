//! The narrow-phase answers of one stabilization call, so that V-Clip runs
//! once per pair per configuration.
//!
//! An answer is kept with the two poses it was computed at. Detection asks
//! the memo before querying a pair: if neither body moved since (both poses
//! bit-identical), the answer is reused. The island contacts seed their
//! first measurement and their linearization from the detection's answers,
//! and hand back the answers of the configuration their line search
//! accepted, so that after a pass only the pairs with a moved body are
//! queried again.
//!
//! The memo lives for one call: body indices name the same bodies, with the
//! same shapes, only within a call.

use nalgebra::Isometry3;

use super::PairQuery;
use crate::broad_phase::{BodyPair, PairMap};

/// A pair's answer and the poses of its two bodies when it was computed.
#[derive(Debug, Clone, PartialEq)]
pub struct PosedQuery {
    /// Centre-of-mass poses of the pair's bodies `[a, b]`.
    pub poses: [Isometry3<f64>; 2],
    /// The narrow phase's answer at those poses.
    pub query: PairQuery,
}

/// The answers of one call, by body pair.
#[derive(Debug, Clone, Default)]
pub struct QueryMemo {
    entries: PairMap<PosedQuery>,
}

impl QueryMemo {
    /// The answer of `pair` if it was computed at exactly `poses`.
    pub fn get(&self, pair: BodyPair, poses: [&Isometry3<f64>; 2]) -> Option<&PairQuery> {
        self.entries
            .get(&pair)
            .filter(|entry| entry.poses[0] == *poses[0] && entry.poses[1] == *poses[1])
            .map(|entry| &entry.query)
    }

    /// Makes room for `additional` more pairs at once (detection knows how
    /// many it will record), so that the map is not grown and rehashed
    /// step by step.
    pub fn reserve(&mut self, additional: usize) {
        self.entries.reserve(additional);
    }

    /// Records an answer (replacing the pair's earlier one).
    pub fn insert(&mut self, pair: BodyPair, answer: PosedQuery) {
        self.entries.insert(pair, answer);
    }

    /// Number of pairs recorded.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is recorded.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}
