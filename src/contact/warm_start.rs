//! The warm starts of V-Clip: the last feature pair of every body pair,
//! kept across passes, line-search trials and calls (temporal coherence).
//!
//! An entry belongs to the two shape objects it was recorded for, held as
//! `Weak` references. A `Weak` keeps its allocation alive, so no other shape
//! can be allocated at the same address while the entry exists: comparing
//! addresses (and that the shape is still alive) identifies the object
//! exactly. (Keyed by the bare address, a shape dropped between calls and
//! a new one allocated at its place would inherit its warm start, whose
//! features could be out of range or wrong for the new shape.) A warm
//! start is only a hint, and [`super::query`] also drops one that does not
//! fit and starts cold.
//!
//! Entries of shapes that no longer exist are removed by
//! [`WarmStartCache::forget_dropped_shapes`], called once per stabilization
//! call, so the cache does not grow with bodies removed from a scene.

use std::sync::{Arc, Weak};

use crate::broad_phase::{BodyPair, PairMap};
use crate::geometry::ConvexPolyhedron;
use crate::vclip::FeaturePair;

/// Warm starts of V-Clip per body pair.
#[derive(Debug, Clone, Default)]
pub struct WarmStartCache {
    entries: PairMap<CachedPair>,
}

#[derive(Debug, Clone)]
struct CachedPair {
    shapes: ShapeIdentity,
    features: FeaturePair,
}

/// The two shape objects a cached entry was recorded for (module docs):
/// `Weak` references, compared by address while alive.
#[derive(Debug, Clone)]
pub(crate) struct ShapeIdentity([Weak<ConvexPolyhedron>; 2]);

impl ShapeIdentity {
    /// The identity of these two shapes.
    pub(crate) fn of(shapes: [&Arc<ConvexPolyhedron>; 2]) -> Self {
        ShapeIdentity(shapes.map(Arc::downgrade))
    }

    /// Whether `shapes` are the very objects recorded.
    pub(crate) fn belongs_to(&self, shapes: [&Arc<ConvexPolyhedron>; 2]) -> bool {
        self.0.iter().zip(shapes).all(|(cached, shape)| {
            cached.strong_count() > 0 && cached.as_ptr() == Arc::as_ptr(shape)
        })
    }

    /// Whether both shapes still exist.
    pub(crate) fn alive(&self) -> bool {
        self.0.iter().all(|shape| shape.strong_count() > 0)
    }
}

impl WarmStartCache {
    /// The cached start of `pair` if it was recorded for these very shapes.
    pub fn get(&self, pair: BodyPair, shapes: [&Arc<ConvexPolyhedron>; 2]) -> Option<FeaturePair> {
        self.entries
            .get(&pair)
            .filter(|entry| entry.shapes.belongs_to(shapes))
            .map(|entry| entry.features)
    }

    /// Records the final feature pair of a query. An entry of the same
    /// shapes is updated in place: its `Weak` references stay, so a
    /// repeated query touches no reference count (every box of a scene may
    /// share one shape, whose counters both threads would otherwise write
    /// on every query).
    pub fn insert(
        &mut self,
        pair: BodyPair,
        shapes: [&Arc<ConvexPolyhedron>; 2],
        features: FeaturePair,
    ) {
        match self.entries.get_mut(&pair) {
            Some(entry) if entry.shapes.belongs_to(shapes) => entry.features = features,
            _ => {
                let shapes = ShapeIdentity::of(shapes);
                self.entries.insert(pair, CachedPair { shapes, features });
            }
        }
    }

    /// Removes the entries of shapes that have been dropped.
    pub fn forget_dropped_shapes(&mut self) {
        self.entries.retain(|_, entry| entry.shapes.alive());
    }

    /// Number of cached pairs.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is cached.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}
