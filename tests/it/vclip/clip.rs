use constraint_stabilization::internals::geometry::{Feature, Plane};
use constraint_stabilization::internals::vclip::clip::*;
use nalgebra::Point3;
use nalgebra::Vector3;

fn plane_x(offset: f64) -> Plane {
    Plane::through(&Point3::new(offset, 0.0, 0.0), Vector3::x())
}

#[test]
fn clip_keeps_the_part_on_the_positive_side() {
    let (t, h) = (Point3::new(-1.0, 0.0, 0.0), Point3::new(3.0, 0.0, 0.0));
    let mut clip = Clip::new(0.0);
    assert_eq!(
        clip.against(&plane_x(0.0), Feature::Vertex(7), &t, &h),
        None
    );
    assert_eq!(clip.l_lo, 0.25);
    assert_eq!(clip.n_lo, Some(Feature::Vertex(7)));
    assert_eq!(clip.n_hi, None);
    let flipped = plane_x(2.0).flipped();
    assert_eq!(clip.against(&flipped, Feature::Vertex(8), &t, &h), None);
    assert_eq!(clip.l_hi, 0.75);
    assert_eq!(clip.n_hi, Some(Feature::Vertex(8)));
}

#[test]
fn simple_and_compound_exclusion() {
    let (t, h) = (Point3::new(-1.0, 0.0, 0.0), Point3::new(3.0, 0.0, 0.0));
    let mut clip = Clip::new(0.0);
    let far = plane_x(5.0);
    assert_eq!(
        clip.against(&far, Feature::Edge(1), &t, &h),
        Some(Exclusion::Simple(Feature::Edge(1)))
    );
    let mut clip = Clip::new(0.0);
    assert_eq!(clip.against(&plane_x(2.0), Feature::Edge(1), &t, &h), None);
    assert_eq!(
        clip.against(&plane_x(1.0).flipped(), Feature::Edge(2), &t, &h),
        Some(Exclusion::Compound)
    );
}
