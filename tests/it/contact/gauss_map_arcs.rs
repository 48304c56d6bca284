use approx::assert_relative_eq;
use constraint_stabilization::internals::contact::gauss_map::*;
use nalgebra::Vector3;

fn quarter_arc() -> GreatArc {
    GreatArc {
        from: Vector3::x(),
        to: Vector3::y(),
    }
}

#[test]
fn contains_only_the_minor_arc() {
    let arc = quarter_arc();
    let diagonal = Vector3::new(1.0, 1.0, 0.0).normalize();
    assert!(arc.contains(&diagonal));
    assert!(arc.contains(&Vector3::x()) && arc.contains(&Vector3::y()));
    assert!(!arc.contains(&-diagonal));
    assert!(!arc.contains(&Vector3::new(1.0, -0.1, 0.0).normalize()));
}

#[test]
fn min_dot_at_an_end_or_inside() {
    let arc = quarter_arc();
    // Least at the interior point (1, 1)/sqrt 2 for t = -(1, 1, 5).
    let t = Vector3::new(-1.0, -1.0, -5.0);
    assert_relative_eq!(arc.min_dot(&t), -(2.0_f64).sqrt(), epsilon = 1e-15);
    // Least at the end y for t = (1, -3, 0).
    assert_relative_eq!(arc.min_dot(&Vector3::new(1.0, -3.0, 0.0)), -3.0);
    // Perpendicular to the circle: constant 0.
    assert_eq!(arc.min_dot(&Vector3::z()), 0.0);
}
