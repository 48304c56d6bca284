//! V-Clip's warm-start cache (`contact::warm_start`): an entry answers only
//! for the very shape objects it was recorded for, a new query of the same
//! shapes updates it, a pair whose shape was replaced by another object
//! (even an identical one) is recorded anew, and entries of dropped shapes
//! go.

use std::sync::Arc;

use constraint_stabilization::internals::broad_phase::BodyPair;
use constraint_stabilization::internals::contact::WarmStartCache;
use constraint_stabilization::internals::geometry::{ConvexPolyhedron, Feature};
use constraint_stabilization::internals::vclip::FeaturePair;
use nalgebra::Vector3;

fn cube() -> Arc<ConvexPolyhedron> {
    Arc::new(ConvexPolyhedron::cuboid(Vector3::new(0.5, 0.5, 0.5)).expect("a valid cuboid"))
}

/// Two feature pairs a query could end on.
const FIRST: FeaturePair = FeaturePair {
    a: Feature::Vertex(3),
    b: Feature::Face(1),
};
const SECOND: FeaturePair = FeaturePair {
    a: Feature::Edge(2),
    b: Feature::Vertex(5),
};

#[test]
fn a_query_of_the_same_shapes_updates_the_entry() {
    let (a, b) = (cube(), cube());
    let pair = BodyPair::new(0, 1).expect("two bodies");
    let mut cache = WarmStartCache::default();
    cache.insert(pair, [&a, &b], FIRST);
    cache.insert(pair, [&a, &b], SECOND);
    assert_eq!(cache.get(pair, [&a, &b]), Some(SECOND));
    assert_eq!(cache.len(), 1);
    // The entry holds no strong reference.
    assert_eq!((Arc::strong_count(&a), Arc::strong_count(&b)), (1, 1));
}

#[test]
fn a_replaced_shape_gets_a_new_entry() {
    let (a, b, replacement) = (cube(), cube(), cube());
    let pair = BodyPair::new(0, 1).expect("two bodies");
    let mut cache = WarmStartCache::default();
    cache.insert(pair, [&a, &b], FIRST);
    // The same geometry, another object: not the recorded shapes.
    assert_eq!(cache.get(pair, [&a, &replacement]), None);
    cache.insert(pair, [&a, &replacement], SECOND);
    assert_eq!(cache.get(pair, [&a, &replacement]), Some(SECOND));
    assert_eq!(cache.get(pair, [&a, &b]), None);
    // Another pair of the same shapes is another entry.
    let other = BodyPair::new(1, 2).expect("two bodies");
    assert_eq!(cache.get(other, [&a, &replacement]), None);
}

#[test]
fn entries_of_dropped_shapes_are_forgotten() {
    let (a, b, c) = (cube(), cube(), cube());
    let mut cache = WarmStartCache::default();
    let ab = BodyPair::new(0, 1).expect("two bodies");
    let ac = BodyPair::new(0, 2).expect("two bodies");
    cache.insert(ab, [&a, &b], FeaturePair::cold());
    cache.insert(ac, [&a, &c], FeaturePair::cold());
    drop(b);
    cache.forget_dropped_shapes();
    assert_eq!(cache.len(), 1);
    assert_eq!(cache.get(ac, [&a, &c]), Some(FeaturePair::cold()));
}
