//! Round shapes (`docs/round-shapes.md`): spheres, capsules, rounded
//! cuboids and hulls exactly, cylinders and cones within their stated
//! deviation; closed forms, the support-function oracle
//! (`dev_support::support_oracle`) and parry3d-f64's contact query.

mod closed_forms;
mod mass;
mod oracle;
mod scenes;
mod support;
mod support_closed_forms;
mod support_gradient;

use constraint_stabilization::body::Body;
use constraint_stabilization::internals::contact::{self, BodyGeometry, PairQuery};
use constraint_stabilization::internals::vclip::{VClip, VClipSettings};

/// Part `k` of `body` at its current pose, as the narrow phase sees it.
pub fn part_geometry(body: &Body, k: usize) -> BodyGeometry<'_> {
    let part = &body.parts()[k];
    BodyGeometry {
        com_world: body.com_world(),
        ..BodyGeometry::convex(part.polyhedron(), part.pose(body.com_pose()), None)
    }
    .rounded(part.rounding())
}

/// The library's answer for each part pair of two bodies (A the first).
pub fn part_queries(a: &Body, b: &Body) -> Vec<PairQuery> {
    let vclip = VClip::new(VClipSettings::default());
    let mut answers = Vec::new();
    for ka in 0..a.parts().len() {
        for kb in 0..b.parts().len() {
            let (ga, gb) = (part_geometry(a, ka), part_geometry(b, kb));
            answers.push(contact::query(&vclip, &ga, &gb, None).expect("a valid query"));
        }
    }
    answers
}

/// The least separation over the contact rows of two single-part bodies
/// (contact margin `margin`), and the pair's signed distance: the rows
/// must carry it (a row asking less than the pair's penetration lets the
/// call stall on a penetration no row sees).
pub fn shallowest_row(a: &Body, b: &Body, margin: f64) -> (f64, f64) {
    let (ga, gb) = (part_geometry(a, 0), part_geometry(b, 0));
    let vclip = VClip::new(VClipSettings::default());
    let query = contact::query(&vclip, &ga, &gb, None).expect("a valid query");
    let settings = constraint_stabilization::Settings::default();
    let points = contact::contact_points(&query, &ga, &gb, margin, &settings).points;
    let least = points
        .iter()
        .map(|p| p.separation)
        .fold(f64::INFINITY, f64::min);
    (least, query.signed_value())
}

/// The library's signed distance of two bodies (least over part pairs).
pub fn signed_distance(a: &Body, b: &Body) -> f64 {
    part_queries(a, b)
        .iter()
        .map(PairQuery::signed_value)
        .fold(f64::INFINITY, f64::min)
}

/// The Rapier pile of 60 balls, capsules, cylinders and rounded boxes
/// after 5 s of Rapier (`tests/data/engine/rp08_mixed_pile.json`).
#[cfg(feature = "serde")]
pub fn rp08_mixed_pile() -> constraint_stabilization::Scene {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/engine/rp08_mixed_pile.json"
    );
    constraint_stabilization::io::scene_file::read_scene(std::path::Path::new(path))
        .expect("valid scene")
}
