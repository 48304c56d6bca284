//! The demo scene: exact body counts, determinism, and — measured with
//! parry3d-f64's contact query, not with our own geometry — penetrations that
//! are present but shallow, and islands that are many and moderate.

use constraint_stabilization::body::Shape;
use constraint_stabilization::internals::broad_phase::{BodyPair, candidate_pairs};
use constraint_stabilization::internals::contact::islands;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::testbed::demo::{
    DEFAULT_BODY_COUNT, MAX_CLUSTER_COLUMNS, MAX_STACK_HEIGHT, OVERLAP_MAX, demo_scene,
};
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::shape::ConvexPolyhedron;

struct Stats {
    penetrating: Vec<BodyPair>,
    /// Largest depth divided by the larger AABB extent of the two bodies.
    worst_relative_depth: f64,
}

fn parry_shape_and_pose(scene: &Scene, i: usize) -> (ConvexPolyhedron, Pose) {
    let body = &scene.bodies()[i];
    let points: Vec<Vector> = body
        .polyhedron()
        .expect("a convex body")
        .vertices()
        .iter()
        .map(|v| Vector::new(v.x, v.y, v.z))
        .collect();
    let hull = ConvexPolyhedron::from_convex_hull(&points).expect("a solid hull");
    let t = body.com_pose().translation.vector;
    let q = body.com_pose().rotation;
    let pose = Pose::from_parts(
        Vector::new(t.x, t.y, t.z),
        Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    );
    (hull, pose)
}

fn extent(scene: &Scene, i: usize) -> f64 {
    let (min, max) = scene.bodies()[i].world_aabb();
    (max - min).max()
}

fn penetration_stats(scene: &Scene) -> Stats {
    let shapes: Vec<_> = (0..scene.len())
        .map(|i| parry_shape_and_pose(scene, i))
        .collect();
    let mut penetrating = vec![];
    let mut worst_relative_depth: f64 = 0.0;
    for pair in candidate_pairs(scene, 0.0).unwrap() {
        let (a, pa) = &shapes[pair.body_a];
        let (b, pb) = &shapes[pair.body_b];
        let Some(contact) = parry3d_f64::query::contact(pa, a, pb, b, 0.0).unwrap() else {
            continue;
        };
        if contact.dist < 0.0 {
            penetrating.push(pair);
            let size = extent(scene, pair.body_a).max(extent(scene, pair.body_b));
            worst_relative_depth = worst_relative_depth.max(-contact.dist / size);
        }
    }
    Stats {
        penetrating,
        worst_relative_depth,
    }
}

#[test]
fn body_counts_are_exact_and_body_zero_is_the_fixed_ground() {
    for n in [0, 1, 2, 10, 100, 1000] {
        let scene = demo_scene(n, 7);
        assert_eq!(scene.len(), n);
        if n > 0 {
            assert!(scene.bodies()[0].is_fixed() && scene.bodies()[0].name() == "ground");
            assert!(scene.bodies()[1..].iter().all(|b| !b.is_fixed()));
        }
    }
}

#[test]
fn every_generated_hull_builds() {
    // A hull that failed to build would have been replaced by a cube.
    for seed in 0..4 {
        let scene = demo_scene(500, seed);
        for body in scene
            .bodies()
            .iter()
            .filter(|b| b.name().starts_with("hull"))
        {
            assert!(
                matches!(body.shape(), Shape::ConvexHull { .. }),
                "{} (seed {seed})",
                body.name()
            );
        }
    }
}

#[test]
fn same_seed_same_scene_other_seed_other_scene() {
    let bits = |s: &Scene| -> Vec<u64> {
        s.bodies()
            .iter()
            .flat_map(|b| {
                b.translation_user()
                    .iter()
                    .copied()
                    .chain(b.rotation_user_xyzw())
                    .collect::<Vec<_>>()
            })
            .map(f64::to_bits)
            .collect()
    };
    assert_eq!(bits(&demo_scene(200, 1)), bits(&demo_scene(200, 1)));
    assert_ne!(bits(&demo_scene(200, 1)), bits(&demo_scene(200, 2)));
}

#[test]
fn demo_has_shallow_penetrations_and_many_moderate_islands() {
    for (n, seed) in [(10, 3), (100, 4), (DEFAULT_BODY_COUNT, 5), (1000, 6)] {
        let scene = demo_scene(n, seed);
        let hulls = scene
            .bodies()
            .iter()
            .filter(|b| b.name().starts_with("hull"))
            .count();
        let stats = penetration_stats(&scene);
        let found = islands(&scene.fixed_flags(), &stats.penetrating).unwrap();
        let largest = found.iter().map(|i| i.bodies.len()).max().unwrap_or(0);
        let mut histogram = vec![0usize; largest + 1];
        for island in &found {
            histogram[island.bodies.len()] += 1;
        }
        let ground_pairs = stats.penetrating.iter().filter(|p| p.body_a == 0).count();
        eprintln!(
            "demo n={n} seed={seed}: hulls {hulls}, penetrating pairs {} ({} with ground), islands {}, largest island {largest}, island sizes {:?}, worst depth {:.4} of size",
            stats.penetrating.len(),
            ground_pairs,
            found.len(),
            &histogram[1..],
            stats.worst_relative_depth
        );
        let dynamic = n - 1;
        assert!(
            stats.penetrating.len() * 2 >= dynamic,
            "too few penetrations"
        );
        assert!(stats.worst_relative_depth <= OVERLAP_MAX, "too deep");
        assert!(largest <= MAX_STACK_HEIGHT * MAX_CLUSTER_COLUMNS);
        if n >= 100 {
            assert!(
                found.len() * 12 >= dynamic,
                "too few islands: {}",
                found.len()
            );
            assert!(
                hulls * 5 >= dynamic && hulls * 5 <= 4 * dynamic,
                "hull share"
            );
        }
    }
}
