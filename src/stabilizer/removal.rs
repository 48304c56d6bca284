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

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;
    use crate::body::{BodyDesc, MassSpec, Shape};
    use crate::scene::SceneError;

    fn cube(name: &str, x: f64, z: f64, mass: MassSpec) -> BodyDesc {
        BodyDesc {
            name: name.into(),
            shape: Shape::Cuboid {
                half_extents: Vector3::new(0.5, 0.5, 0.5),
            },
            translation: Vector3::new(x, 0.0, z),
            rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
            mass,
        }
    }

    /// A row of cubes sunk into a ground slab, each 0.01 deep.
    fn row(n: usize) -> Scene {
        let mut scene = Scene::new();
        let ground = BodyDesc {
            shape: Shape::Cuboid {
                half_extents: Vector3::new(20.0, 20.0, 0.5),
            },
            ..cube("ground", 0.0, -0.5, MassSpec::Fixed)
        };
        scene.add_body(ground).expect("valid ground");
        for i in 0..n {
            let desc = cube(
                &format!("cube {i}"),
                2.0 * i as f64,
                0.49,
                MassSpec::Mass(1.0),
            );
            scene.add_body(desc).expect("valid cube");
        }
        scene
    }

    /// After a call, removing a body keeps one warm start per pair left
    /// (ground and each remaining cube) and drops the removed body's.
    #[test]
    fn warm_starts_of_the_bodies_left_follow_them_to_their_new_indices() {
        let mut scene = row(4);
        let mut stabilizer = Stabilizer::default();
        stabilizer.stabilize(&mut scene).expect("the row is solved");
        assert_eq!(stabilizer.cache.len(), 4);
        let map = stabilizer
            .remove_bodies(&mut scene, &[2])
            .expect("body 2 exists");
        assert_eq!(
            map.old_to_new(),
            &[Some(0), Some(1), None, Some(2), Some(3)]
        );
        assert_eq!(scene.len(), 4);
        assert_eq!(stabilizer.cache.len(), 3);
        for b in 1..4 {
            let pair = BodyPair::new(0, b).expect("distinct");
            let shape = |body: usize| scene.bodies()[body].parts()[0].polyhedron();
            let shapes = [shape(0), shape(b)];
            assert!(
                stabilizer.cache.get(pair, shapes).is_some(),
                "pair (0, {b})"
            );
        }
    }

    #[test]
    fn index_out_of_range_is_an_error_and_changes_nothing() {
        let mut scene = row(2);
        let mut stabilizer = Stabilizer::default();
        stabilizer.stabilize(&mut scene).expect("the row is solved");
        let cached = stabilizer.cache.len();
        let error = stabilizer.remove_bodies(&mut scene, &[1, 7]).unwrap_err();
        assert_eq!(
            error,
            Error::Scene(SceneError::NoSuchBody { index: 7, len: 3 })
        );
        assert_eq!((scene.len(), stabilizer.cache.len()), (3, cached));
    }
}
