use nalgebra::{Isometry3, Translation3, UnitQuaternion};

use constraint_stabilization::internals::rapier_bridge::round_off::*;
use constraint_stabilization::rapier_bridge::{pose_from_f64, pose_to_f64};

/// Rounding a pose to f32 moves its origin by at most `u |t|` and turns
/// it by at most `ROTATION_ROUND_OFF`, over a grid of 9^3 rotations and
/// translations from 1e-3 to 1e4.
#[test]
fn rounding_a_pose_stays_within_the_bound() {
    let angles = |i: usize| -3.0 + 0.7 * i as f64 + 0.013 * (i * i) as f64;
    let (mut worst_rotation, mut worst_translation) = (0.0_f64, 0.0_f64);
    for (i, j, k) in (0..9).flat_map(|i| (0..9).flat_map(move |j| (0..9).map(move |k| (i, j, k)))) {
        let rotation = UnitQuaternion::from_euler_angles(angles(i), angles(j) / 2.0, angles(k));
        let scale = 10f64.powi(i as i32 % 8 - 3);
        let t = Translation3::new(scale * 1.37, -scale * 0.71, scale * angles(k));
        let exact = Isometry3::from_parts(t, rotation);
        let written = pose_to_f64(&pose_from_f64(&exact));
        let moved = (written.translation.vector - exact.translation.vector).norm();
        let turned = written.rotation.angle_to(&exact.rotation);
        worst_translation = worst_translation.max(moved / (F32_UNIT_ROUND_OFF * t.vector.norm()));
        worst_rotation = worst_rotation.max(turned / ROTATION_ROUND_OFF);
    }
    println!(
        "worst fraction of the bound: translation {worst_translation:.3}, rotation {worst_rotation:.3}"
    );
    assert!(worst_translation <= 1.0 && worst_rotation <= 1.0);
}
