use constraint_stabilization::body::BodyInertia;
use constraint_stabilization::internals::projector::trust_region::*;
use nalgebra::DVector;
use nalgebra::Matrix3;

/// A unit-mass cube of half-edge `h`: inertia `2 h^2 / 3` on the diagonal.
fn cube(h: f64) -> BodyInertia {
    BodyInertia {
        mass: 1.0,
        inertia_body: Matrix3::identity() * (2.0 * h * h / 3.0),
    }
}

/// At most 0.1 rad of rotation and half a body's size of translation.
const REGION: TrustRegion = TrustRegion {
    max_rotation: 0.1,
    max_translation_relative: 0.5,
};

#[test]
fn a_cube_of_half_edge_h_has_size_h() {
    approx::assert_relative_eq!(radius_of_gyration(&cube(0.3)), 0.3, max_relative = 1e-12);
}

#[test]
fn the_most_limited_body_scales_the_whole_correction() {
    let region = REGION;
    let mut dq = DVector::zeros(12);
    dq[0] = 0.1; // body 0: 0.1 of translation, limit 0.5 * 0.4 = 0.2
    dq[9] = 0.4; // body 1: 0.4 rad of rotation, limit 0.1
    let scale = region.scale(&dq, &[cube(0.4), cube(0.4)], 0.0);
    approx::assert_relative_eq!(scale, 0.25, max_relative = 1e-12);
    let unlimited = TrustRegion::UNLIMITED.scale(&dq, &[cube(0.4), cube(0.4)], 0.0);
    assert_eq!(unlimited, 1.0);
}

#[test]
fn a_body_may_always_translate_by_the_depth() {
    let region = REGION;
    let mut dq = DVector::zeros(6);
    dq[0] = 0.8; // limit 0.5 * 0.4 = 0.2, but the depth is 0.4
    let scale = region.scale(&dq, &[cube(0.4)], 0.4);
    approx::assert_relative_eq!(scale, 0.5, max_relative = 1e-12);
}
