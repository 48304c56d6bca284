//! The map from Rapier handles to scene bodies, kept across steps, and the
//! decision of each call: append the new colliders, or rebuild the scene.
//!
//! Scene bodies are the read colliders in the order they were first seen
//! (the collider set's order within one call). A mapped collider keeps its
//! scene index, hence its shape (built once) and its V-Clip warm starts,
//! as long as it is read again unchanged: same parent, same body type and
//! mass, same offset `P` in its body, same shape signature. Anything else
//! (a collider removed, skipped or changed) rebuilds the scene, since a
//! scene cannot drop or change a body.

use std::collections::HashMap;

use nalgebra::Isometry3;
use rapier3d::dynamics::RigidBodyHandle;
use rapier3d::geometry::ColliderHandle;

use super::collider_shape::{ReadCollider, ShapeSignature};

/// The Rapier collider behind one scene body.
#[derive(Debug, Clone, PartialEq)]
pub struct MappedCollider {
    /// The collider.
    pub collider: ColliderHandle,
    /// Its parent body, if any.
    pub body: Option<RigidBodyHandle>,
    /// The mass of its dynamic parent; `None` if the scene body is fixed
    /// (fixed or kinematic parent, or no parent).
    pub dynamic_mass: Option<f64>,
    /// `P`: the collider frame in the body frame (identity without parent).
    pub collider_in_body: Isometry3<f64>,
    signature: ShapeSignature,
}

impl MappedCollider {
    pub(crate) fn of(read: &ReadCollider) -> Self {
        MappedCollider {
            collider: read.collider,
            body: read.body,
            dynamic_mass: read.dynamic_mass,
            collider_in_body: read.collider_in_body,
            signature: read.signature,
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
            && self.signature == read.signature
    }
}

/// What one call does with the scene.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Plan {
    /// Every mapped collider is read unchanged: append these (indices into
    /// the read list), possibly none.
    Append(Vec<usize>),
    /// A mapped collider vanished or changed: start over.
    Rebuild,
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

    /// The scene index of a collider.
    pub fn scene_index(&self, collider: ColliderHandle) -> Option<usize> {
        self.by_collider.get(&collider).copied()
    }

    /// The scene index of a dynamic Rapier body (it has one collider).
    pub fn scene_index_of_body(&self, body: RigidBodyHandle) -> Option<usize> {
        self.by_body.get(&body).copied()
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
        let read_index: HashMap<ColliderHandle, usize> = read
            .iter()
            .enumerate()
            .map(|(i, r)| (r.collider, i))
            .collect();
        let unchanged = self.entries.iter().all(|entry| {
            read_index
                .get(&entry.collider)
                .is_some_and(|&i| entry.same_as(&read[i]))
        });
        if !unchanged {
            return Plan::Rebuild;
        }
        let new = read
            .iter()
            .enumerate()
            .filter(|(_, r)| !self.by_collider.contains_key(&r.collider))
            .map(|(i, _)| i)
            .collect();
        Plan::Append(new)
    }

    /// Maps the next scene body (index `len()`) to `read`.
    pub(crate) fn push(&mut self, read: &ReadCollider) {
        let index = self.entries.len();
        self.by_collider.insert(read.collider, index);
        if let (Some(body), Some(_)) = (read.body, read.dynamic_mass) {
            self.by_body.insert(body, index);
        }
        self.entries.push(MappedCollider::of(read));
    }

    pub(crate) fn clear(&mut self) {
        *self = BodyMap::default();
    }
}
