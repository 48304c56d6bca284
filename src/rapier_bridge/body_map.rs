//! The map from Rapier handles to scene bodies and back, kept across steps,
//! and the plan of each call: which scene bodies to remove, which read
//! colliders to append.
//!
//! Scene bodies are the read colliders in the order they were first seen
//! (the collider set's order within one call); a dynamic body with several
//! colliders is one scene body, a compound, keyed by its first collider. A mapped collider keeps its
//! shape (built once) and its V-Clip warm starts as long as it is read
//! again unchanged: same parent, same body type, mass and mass properties, same offset `P`
//! in its body, same shape signature. A collider that is no longer read
//! (removed, disabled, now skipped) has its body removed; one that changed
//! has its body removed and a new one appended. Removal keeps the order of
//! the others ([`crate::scene::Scene::remove_bodies`]), so their indices
//! shift down and [`BodyMap::remove`] follows.

use std::collections::HashMap;

use nalgebra::Isometry3;
use rapier3d::dynamics::{RigidBodyHandle, RigidBodySet};
use rapier3d::geometry::ColliderHandle;

use super::collider_shape::{ReadCollider, ReadPart, ShapeSignature};
use super::engine_mass::EngineMass;
use crate::scene::IndexMap;

/// The Rapier collider behind one scene body (or, for a compound, the
/// dynamic body and its colliders).
#[derive(Debug, Clone, PartialEq)]
pub struct MappedCollider {
    /// The collider (a compound's first, in its body's order).
    pub collider: ColliderHandle,
    /// Its parent body, if any.
    pub body: Option<RigidBodyHandle>,
    /// The mass of its dynamic parent; `None` if the scene body is fixed
    /// (fixed or kinematic parent, or no parent).
    pub dynamic_mass: Option<f64>,
    /// `P`: the scene body's frame in the Rapier body frame: the
    /// collider's (identity without parent, and for a compound, whose
    /// frame is the Rapier body's).
    pub collider_in_body: Isometry3<f64>,
    engine_mass: Option<EngineMass>,
    signature: ShapeSignature,
    parts: Vec<ReadPart>,
}

impl MappedCollider {
    pub(crate) fn of(read: &ReadCollider) -> Self {
        MappedCollider {
            collider: read.collider,
            body: read.body,
            dynamic_mass: read.dynamic_mass,
            collider_in_body: read.collider_in_body,
            engine_mass: read.engine_mass,
            signature: read.signature,
            parts: read.parts.clone(),
        }
    }

    /// The colliders of the scene body: one, or a compound's, in its
    /// body's order.
    pub fn colliders(&self) -> Vec<ColliderHandle> {
        match self.parts.is_empty() {
            true => vec![self.collider],
            false => self.parts.iter().map(|part| part.collider).collect(),
        }
    }

    /// Whether the bridge writes this body's pose back (dynamic parent).
    pub fn is_dynamic(&self) -> bool {
        self.dynamic_mass.is_some()
    }

    fn same_as(&self, read: &ReadCollider) -> bool {
        self.body == read.body
            && self.dynamic_mass.map(f64::to_bits) == read.dynamic_mass.map(f64::to_bits)
            && self.collider_in_body == read.collider_in_body
            && self.engine_mass == read.engine_mass
            && self.signature == read.signature
            && self.parts == read.parts
    }
}

/// What one call does with the scene: remove, then append.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Plan {
    /// Scene indices of the mapped colliders that vanished or changed.
    pub remove: Vec<usize>,
    /// Indices into the read list of the colliders that are new or changed.
    pub append: Vec<usize>,
}

/// Scene index to collider and back.
#[derive(Debug, Clone, Default)]
pub struct BodyMap {
    entries: Vec<MappedCollider>,
    by_collider: HashMap<ColliderHandle, usize>,
    by_body: HashMap<RigidBodyHandle, usize>,
}

impl BodyMap {
    /// The collider behind each scene body, in scene order.
    pub fn entries(&self) -> &[MappedCollider] {
        &self.entries
    }

    /// The scene index of a collider (of any part of a compound).
    pub fn scene_index(&self, collider: ColliderHandle) -> Option<usize> {
        self.by_collider.get(&collider).copied()
    }

    /// The scene index of a dynamic Rapier body (one scene body, a
    /// compound if it has several colliders).
    pub fn scene_index_of_body(&self, body: RigidBodyHandle) -> Option<usize> {
        self.by_body.get(&body).copied()
    }

    /// The Rapier collider (and its parent body) behind scene body `index`.
    pub fn entry(&self, index: usize) -> Option<&MappedCollider> {
        self.entries.get(index)
    }

    /// Whether scene body `index` is a dynamic Rapier body that is awake:
    /// a body a call reads (a pair of two sleeping bodies is not read).
    pub fn is_awake_dynamic(&self, index: usize, bodies: &RigidBodySet) -> bool {
        self.entry(index).is_some_and(|entry| {
            entry.is_dynamic()
                && entry
                    .body
                    .and_then(|h| bodies.get(h))
                    .is_some_and(|b| !b.is_sleeping())
        })
    }

    /// The collider behind scene body `index`.
    pub fn collider_of(&self, index: usize) -> Option<ColliderHandle> {
        self.entry(index).map(|entry| entry.collider)
    }

    /// The parent Rapier body of scene body `index` (`None` for a collider
    /// without a parent, or an index out of range).
    pub fn body_of(&self, index: usize) -> Option<RigidBodyHandle> {
        self.entry(index).and_then(|entry| entry.body)
    }

    /// Number of scene bodies.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether no collider is mapped.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    pub(crate) fn plan(&self, read: &[ReadCollider]) -> Plan {
        // The common case, a world whose colliders did not change since
        // the last call, read in the same order: nothing to remove or
        // append, known without the index below.
        let unchanged = read.len() == self.entries.len()
            && self
                .entries
                .iter()
                .zip(read)
                .all(|(entry, r)| entry.collider == r.collider && entry.same_as(r));
        if unchanged {
            return Plan {
                remove: Vec::new(),
                append: Vec::new(),
            };
        }
        let read_index: HashMap<ColliderHandle, usize> = read
            .iter()
            .enumerate()
            .map(|(i, r)| (r.collider, i))
            .collect();
        let kept = |entry: &MappedCollider| {
            read_index
                .get(&entry.collider)
                .is_some_and(|&i| entry.same_as(&read[i]))
        };
        let removed: Vec<bool> = self.entries.iter().map(|e| !kept(e)).collect();
        let remove = (0..removed.len()).filter(|&index| removed[index]).collect();
        let append = read
            .iter()
            .enumerate()
            .filter(|(_, r)| {
                self.scene_index(r.collider)
                    .is_none_or(|index| removed[index])
            })
            .map(|(i, _)| i)
            .collect();
        Plan { remove, append }
    }

    /// Follows a removal from the scene: entries of removed bodies go, the
    /// others take their new indices (order kept).
    pub(crate) fn remove(&mut self, map: &IndexMap) {
        let entries = std::mem::take(&mut self.entries);
        self.clear();
        for (old, entry) in entries.into_iter().enumerate() {
            if map.new_index(old).is_some() {
                self.push_entry(entry);
            }
        }
    }

    /// Maps the next scene body (index `len()`) to `read`.
    pub(crate) fn push(&mut self, read: &ReadCollider) {
        self.push_entry(MappedCollider::of(read));
    }

    fn push_entry(&mut self, entry: MappedCollider) {
        let index = self.entries.len();
        for collider in entry.colliders() {
            self.by_collider.insert(collider, index);
        }
        if let (Some(body), true) = (entry.body, entry.is_dynamic()) {
            self.by_body.insert(body, index);
        }
        self.entries.push(entry);
    }

    pub(crate) fn clear(&mut self) {
        *self = BodyMap::default();
    }
}
