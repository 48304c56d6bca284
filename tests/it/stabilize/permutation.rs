//! The answer of a call does not depend on the order of the scene's
//! bodies: every engine state, stabilized as written and with its bodies
//! shuffled, ends at the same poses within the call's tolerance.
//!
//! Each linearized problem has a unique minimizer in `dq`, so a difference
//! can only come from choices that follow the bodies' indices (which body
//! of a pair is A, tie-breaks, the order of rows). The poses are compared
//! by the largest distance a point of a body moves between the two
//! answers, bounded by the difference of its centre of mass plus the angle
//! between its two orientations times its reach.

use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Settings, Stabilizer};

use crate::support::engine_states::engine_states;

/// A fixed shuffle of `0..n` (Fisher–Yates driven by a linear
/// congruential sequence, Knuth's MMIX constants).
fn shuffle(n: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    for i in (1..n).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        order.swap(i, (state >> 33) as usize % (i + 1));
    }
    order
}

/// `scene`'s bodies in `order` (the new scene's body `k` is `scene`'s body
/// `order[k]`), with its settings.
fn permuted(scene: &Scene, order: &[usize]) -> Scene {
    let mut out = Scene::new();
    for &i in order {
        out.push_body(scene.bodies()[i].clone());
    }
    out.set_settings(scene.settings().clone())
        .expect("the settings of a valid scene");
    out
}

#[test]
fn every_engine_state_ends_at_the_same_poses_whatever_the_order_of_its_bodies() {
    for (name, scene) in engine_states() {
        let order = shuffle(scene.len());
        let mut as_written = scene.clone();
        let mut shuffled = permuted(&scene, &order);
        let stabilize = |scene: &mut Scene| {
            Stabilizer::new(Settings::default())
                .expect("default settings")
                .stabilize(scene)
                .expect("an engine state is stabilized")
        };
        let report = stabilize(&mut as_written);
        let shuffled_report = stabilize(&mut shuffled);
        assert_eq!(report.status, shuffled_report.status, "{name}");
        let mut largest: f64 = 0.0;
        for (k, &i) in order.iter().enumerate() {
            let body = &as_written.bodies()[i];
            let (pose, other) = (body.com_pose(), shuffled.bodies()[k].com_pose());
            let moved = (pose.translation.vector - other.translation.vector).norm()
                + pose.rotation.angle_to(&other.rotation) * body.reach();
            largest = largest.max(moved);
        }
        println!(
            "{name}: {} passes, largest difference {largest:.3e} (tolerance {:.3e})",
            report.passes, report.tolerance
        );
        assert!(
            largest <= report.tolerance,
            "{name}: the shuffled scene ends {largest:e} away (tolerance {:e})",
            report.tolerance
        );
    }
}
