//! Only the work a scene needs (issue 9): the narrow phase runs once per
//! pair per configuration, a pass queries again only the pairs with a body
//! that moved, and a pass solves the bodies that still penetrate (grown
//! while the answer pushes the others), not the whole resting island.
//!
//! Counts come from the report (`pair_queries`, `queried_pairs`,
//! `region_bodies`); depths from the brute-force separating-axis oracle.

use crate::stabilize::support::stabilize_with;
use constraint_stabilization::body::MassSpec;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Status};
use dev_support::sat::sat_deepest;
use dev_support::scene::{
    IDENTITY_XYZW, assert_untouched, cuboid, ground, pose_bits, scene_of, unit_cube_sunk,
};

/// Every query of a call is either a detection's (of a pair whose bodies
/// moved since its last answer) or one line-search trial of an island's
/// pairs: nothing is queried twice at one configuration.
fn assert_queries_accounted(report: &Report) {
    let detections: usize = report.pass_reports.iter().map(|p| p.queried_pairs).sum();
    let trials: usize = report
        .pass_reports
        .iter()
        .flat_map(|p| &p.solved)
        .map(|island| island.line_search_trials * island.pairs)
        .sum();
    assert_eq!(report.pair_queries, detections + trials, "{report:#?}");
}

#[test]
fn a_sunk_box_is_queried_once_per_configuration() {
    let mut scene = scene_of(&[ground(), unit_cube_sunk("box", 0.1)]);
    let (report, _) = stabilize_with(&mut scene, Settings::default());
    assert_eq!(report.status, Status::Converged);
    assert_eq!(report.passes, 1);
    let island = &report.pass_reports[0].solved[0];
    assert_eq!(island.line_search_trials, 1, "{report:#?}");
    // Detection, one trial at the accepted configuration; the second
    // detection reuses the trial's answer. (Before: detection, measure,
    // linearize, trial, detection: five queries.)
    assert_eq!(report.pair_queries, 2);
    assert_eq!(report.pass_reports[1].queried_pairs, 0);
    assert_queries_accounted(&report);
}

/// Boxes in a row on the ground, `gap` apart along x (within the contact
/// margin, so one island), the first sunk by `depth`.
fn row_of_boxes(count: usize, gap: f64, depth: f64) -> Scene {
    let mut descs = vec![ground()];
    for i in 0..count {
        let sink = if i == 0 { depth } else { 0.0 };
        descs.push(cuboid(
            &format!("box{i}"),
            [0.5, 0.5, 0.5],
            [i as f64 * (1.0 + gap), 0.5 - sink, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ));
    }
    scene_of(&descs)
}

#[test]
fn resting_boxes_away_from_the_penetration_hold_still() {
    let (count, gap, depth) = (12, 1e-3, 0.05);
    let mut scene = row_of_boxes(count, gap, depth);
    let before = pose_bits(&scene);
    let (report, _) = stabilize_with(&mut scene, Settings::default());
    assert!(report.status.is_resolved(), "{report:#?}");
    let (deepest, pair) = sat_deepest(&scene);
    assert!(deepest <= report.tolerance, "{deepest:e} at {pair:?}");
    let solved = &report.pass_reports[0].solved;
    assert_eq!(solved.len(), 1);
    assert_eq!(solved[0].bodies.len(), count, "one island of the whole row");
    assert_eq!(solved[0].region_bodies, 2, "the sunk box and its neighbour");
    // Bodies 3.. (boxes 2..) are beyond the region: bit-identical.
    assert_untouched(&scene, &before, &(3..=count).collect::<Vec<_>>());
    assert_queries_accounted(&report);

    // The whole island gives the same sunk box: the region's answer did not
    // push the held boxes, so it is the island's to within the tolerance.
    let mut whole = row_of_boxes(count, gap, depth);
    let settings = {
        let mut settings = Settings::default();
        settings.solve_whole_islands = true;
        settings
    };
    let (whole_report, _) = stabilize_with(&mut whole, settings);
    assert!(whole_report.status.is_resolved());
    assert_eq!(whole_report.pass_reports[0].solved[0].region_bodies, count);
    let lift = |scene: &Scene| scene.bodies()[1].translation_user().y;
    assert!(
        (lift(&scene) - lift(&whole)).abs() <= 2.0 * report.tolerance,
        "region {} whole {}",
        lift(&scene),
        lift(&whole)
    );
    let target = Settings::default().target_margin_relative * report.scale;
    assert!((lift(&scene) - 0.5 - target).abs() <= 2.0 * report.tolerance);
}

/// A column of boxes on the ground with the bottom one sunk: lifting it
/// pushes every box above, so the region grows (by the pushed box and
/// doubling hops) to the whole column, and the answer is the closed form:
/// every box rises by the depth, and each contact of the column (touching
/// at zero distance) opens to the target margin.
#[test]
fn a_column_region_grows_until_nothing_held_is_pushed() {
    let (count, depth) = (16, 0.02);
    let mut descs = vec![ground()];
    for i in 0..count {
        let y = 0.5 + i as f64 - depth;
        descs.push(cuboid(
            &format!("box{i}"),
            [0.5, 0.5, 0.5],
            [0.0, y, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ));
    }
    let mut scene = scene_of(&descs);
    let (report, _) = stabilize_with(&mut scene, Settings::default());
    assert!(report.status.is_resolved(), "{report:#?}");
    let island = &report.pass_reports[0].solved[0];
    assert!(island.region_rounds > 1, "{island:#?}");
    assert_eq!(island.region_bodies, count);
    let target = Settings::default().target_margin_relative * report.scale;
    for (i, body) in scene.bodies().iter().enumerate().skip(1) {
        let expected = 0.5 + (i - 1) as f64 + i as f64 * target;
        let y = body.translation_user().y;
        assert!(
            (y - expected).abs() <= 1e-2 * target,
            "box {i}: {y} vs {expected}"
        );
    }
    let (deepest, _) = sat_deepest(&scene);
    assert!(deepest <= report.tolerance);
    assert_queries_accounted(&report);
}

#[cfg(feature = "serde")]
mod engine_states {
    use super::*;
    use constraint_stabilization::io::scene_file::read_scene;

    fn engine_state(name: &str) -> Scene {
        let path = format!(
            "{}/tests/data/engine/{name}.json",
            env!("CARGO_MANIFEST_DIR")
        );
        read_scene(std::path::Path::new(&path)).expect("engine state")
    }

    /// On a settled Rapier pile of 200 boxes and hulls, later passes solve
    /// only part of their islands, and the result is as good as solving
    /// whole islands: exact depth within the tolerance, a mass-weighted
    /// displacement within 10 % of it, no more passes.
    #[test]
    fn a_settled_pile_solves_regions_and_matches_whole_islands() {
        let mut region = engine_state("rp01_pile_200");
        let (report, _) = stabilize_with(&mut region, Settings::default());
        let mut whole = engine_state("rp01_pile_200");
        let settings = {
            let mut settings = Settings::default();
            settings.solve_whole_islands = true;
            settings
        };
        let (whole_report, _) = stabilize_with(&mut whole, settings);
        for (label, scene, report) in [
            ("region", &region, &report),
            ("whole", &whole, &whole_report),
        ] {
            assert_eq!(report.status, Status::Converged, "{label}");
            let (deepest, pair) = sat_deepest(scene);
            assert!(
                deepest <= report.tolerance,
                "{label}: {deepest:e} at {pair:?}"
            );
            assert_queries_accounted(report);
        }
        let partial = report
            .pass_reports
            .iter()
            .flat_map(|p| &p.solved)
            .filter(|island| island.region_bodies < island.bodies.len())
            .count();
        assert!(partial > 0, "no pass solved part of an island");
        assert!(report.passes <= whole_report.passes);
        let ratio = report.displacement / whole_report.displacement;
        assert!((0.9..=1.1).contains(&ratio), "displacement ratio {ratio}");
        println!(
            "pile 200: region {} passes, {} queries, displacement {:.6e}; whole {} passes, {} queries, displacement {:.6e}",
            report.passes,
            report.pair_queries,
            report.displacement,
            whole_report.passes,
            whole_report.pair_queries,
            whole_report.displacement
        );
    }
}
