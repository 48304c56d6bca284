//! [`Stabilizer::remove_bodies`]: bodies removed from a scene between
//! calls, with the V-Clip warm starts of the bodies left carried over to
//! their new indices.
//!
//! The warm-start cache is keyed by body pair (scene indices) and checks
//! the identity of the pair's two shapes ([`crate::contact::WarmStartCache`]).
//! Removing a body shifts every later index down, so without a remap an
//! entry would sit under the pair that now has its old indices: the shape
//! check rejects it (a different body has a different shape object, the
//! entry is never used) and the survivors lose their warm starts, as a
//! rebuilt scene would.
//!
//! The remap goes through the cache's own lookups: for every candidate
//! pair of the scene before the removal (broad phase with the contact
//! margin, the pairs the last detection at these poses queried, hence the
//! entries worth keeping) whose two bodies stay, the entry found under the
//! old pair for the same two shapes is recorded under the new pair. Every
//! other entry is dropped. Removal keeps the order of the bodies left, so a
//! pair `a < b` stays ordered and the features are those of the same two
//! bodies in the same roles. A warm start is only a hint in any case:
//! [`crate::contact::query`] drops one that does not fit and starts cold.

use super::Stabilizer;
use crate::Error;
use crate::broad_phase::{BodyPair, candidate_pairs};
use crate::contact::SceneParts;
use crate::contact::WarmStartCache;
use crate::scene::{IndexMap, Scene};

impl Stabilizer {
    /// Removes the bodies at `indices` from `scene` ([`Scene::remove_bodies`]:
    /// order kept, old-to-new map returned) and keeps the warm starts of the
    /// pairs of bodies left, under their new indices. An index out of range
    /// is an error and changes nothing.
    pub fn remove_bodies(
        &mut self,
        scene: &mut Scene,
        indices: &[usize],
    ) -> Result<IndexMap, Error> {
        let margin = self.lengths(scene).contact_margin;
        // A broad phase that fails (it cannot for valid bodies) only costs
        // the warm starts: they are dropped rather than the call failed.
        let pairs = candidate_pairs(scene, margin).unwrap_or_default();
        let old_parts = SceneParts::of(scene);
        let map = scene.remove_bodies(indices)?;
        let new_parts = SceneParts::of(scene);
        self.cache = remapped(&self.cache, [&old_parts, &new_parts], &pairs, &map);
        // Part indices shift: the solver's warm starts are dropped rather
        // than remapped (they cost a cold solve, never an answer).
        self.solver_warm.clear();
        // Certificates are keyed by part pair: dropped likewise (a pair's
        // next detection queries it once and records it again).
        self.certificates.clear();
        // The kept sparse analyses belong to the islands of the bodies
        // before the removal: freed with them.
        self.kept_analyses.clear();
        Ok(map)
    }
}

/// The entries of `old` for the part pairs of the body pairs `pairs` (old
/// indices) whose bodies are both left (new indices, after the removal),
/// under their new part pairs. `parts` are the scene's parts before and
/// after; a body's parts keep their order.
fn remapped(
    old: &WarmStartCache,
    [old_parts, new_parts]: [&SceneParts; 2],
    pairs: &[BodyPair],
    map: &IndexMap,
) -> WarmStartCache {
    let mut cache = WarmStartCache::default();
    for &pair in pairs {
        let (Some(a), Some(b)) = (map.new_index(pair.body_a), map.new_index(pair.body_b)) else {
            continue;
        };
        let old_ranges = (
            old_parts.parts_of(pair.body_a),
            old_parts.parts_of(pair.body_b),
        );
        let new_ranges = (new_parts.parts_of(a), new_parts.parts_of(b));
        for (p_old, p_new) in old_ranges.0.zip(new_ranges.0) {
            for (q_old, q_new) in old_ranges.1.clone().zip(new_ranges.1.clone()) {
                let (Some(old_pair), Some(new_pair)) =
                    (BodyPair::new(p_old, q_old), BodyPair::new(p_new, q_new))
                else {
                    continue;
                };
                let shapes = [&new_parts.shapes()[p_new], &new_parts.shapes()[q_new]];
                if let Some(features) = old.get(old_pair, shapes) {
                    cache.insert(new_pair, shapes, features);
                }
            }
        }
    }
    cache
}
