use constraint_stabilization::internals::vclip::closest::*;
use nalgebra::Point3;

#[test]
fn crossing_segments_meet_inside() {
    let pair = segment_segment(
        &Point3::new(-1.0, 0.0, 1.0),
        &Point3::new(1.0, 0.0, 1.0),
        &Point3::new(0.0, -1.0, 0.0),
        &Point3::new(0.0, 3.0, 0.0),
    );
    assert!((pair.s - 0.5).abs() < 1e-15 && (pair.t - 0.25).abs() < 1e-15);
    assert!((pair.distance_squared - 1.0).abs() < 1e-15);
}

/// Nearly parallel crossing edges (angle 1e-7): the distance must be the
/// gap between them, not an endpoint distance.
#[test]
fn nearly_parallel_segments_keep_their_interior_minimum() {
    let angle: f64 = 1e-7;
    let gap = 3e-7;
    let pair = segment_segment(
        &Point3::new(-1.0, 0.0, 0.0),
        &Point3::new(1.0, 0.0, 0.0),
        &Point3::new(-1.0, -angle, gap),
        &Point3::new(1.0, angle, gap),
    );
    assert!(
        (pair.distance_squared.sqrt() - gap).abs() < 1e-15,
        "{pair:?}"
    );
}

#[test]
fn parallel_segments_use_an_endpoint() {
    let pair = segment_segment(
        &Point3::new(0.0, 0.0, 0.0),
        &Point3::new(2.0, 0.0, 0.0),
        &Point3::new(1.0, 1.0, 0.0),
        &Point3::new(5.0, 1.0, 0.0),
    );
    assert!((pair.distance_squared - 1.0).abs() < 1e-15);
}
