//! Scenes with no penetration-free configuration within reach: a unit box
//! between two fixed slabs 0.8 apart (and 2,000 long: there is no room for
//! it anywhere near), and a ring of four boxes of side 1.1 squeezed in a
//! closed fixed box of inner size 2 x 2 x 1 (their volume exceeds the
//! room). The call must end with a status that says so (not resolved),
//! name the island left (`Report::islands_left`) with its bodies, never
//! return the scene deeper or with a higher merit than it came (judged by
//! the brute-force separating-axis depth), leave no NaN, and end: the pass
//! limit bounds the passes (`max_passes` is lowered to keep the test
//! short; the property does not depend on it).
//!
//! `cargo test --test it stabilize::infeasible:: -- --nocapture` prints each run.

use crate::stabilize::extreme::{Run, run};
use constraint_stabilization::Settings;
use constraint_stabilization::body::{BodyDesc, MassSpec};
use dev_support::scene::{IDENTITY_XYZW, cuboid};

/// Passes allowed; the status must say what stopped the call.
const MAX_PASSES: usize = 30;

fn settings() -> Settings {
    {
        let mut settings = Settings::default();
        settings.max_passes = MAX_PASSES;
        settings
    }
}

fn fixed(name: &str, half: [f64; 3], at: [f64; 3]) -> BodyDesc {
    cuboid(name, half, at, IDENTITY_XYZW, MassSpec::Fixed)
}

/// Asserts the status is not resolved and that the dynamic bodies
/// `bodies` are named as left, either as an island that stalled or
/// failed, or (at the pass limit, where the last pass still moved) among
/// the pairs still penetrating.
fn assert_left_with_bodies(label: &str, run: &Run, bodies: &[usize]) {
    let report = &run.report;
    assert!(
        !report.status.is_resolved(),
        "{label}: {}",
        report.status.name()
    );
    assert!(
        run.depth_after > report.tolerance,
        "{label}: the oracle finds it resolved"
    );
    let named: Vec<usize> = report
        .islands_left
        .iter()
        .flat_map(|left| left.bodies.iter().copied())
        .chain(
            report
                .penetrations_after
                .iter()
                .flat_map(|p| [p.body_a, p.body_b]),
        )
        .collect();
    for body in bodies {
        assert!(
            named.contains(body),
            "{label}: body {body} not named: {named:?}"
        );
    }
    for left in &report.islands_left {
        println!(
            "{label}: island {:?} left: {}",
            left.bodies,
            left.outcome.reason()
        );
    }
}

#[test]
fn box_between_two_fixed_slabs_with_no_room() {
    let descs = [
        fixed("left", [1.0, 1000.0, 1000.0], [-1.4, 0.0, 0.0]),
        fixed("right", [1.0, 1000.0, 1000.0], [1.4, 0.0, 0.0]),
        cuboid(
            "box",
            [0.5; 3],
            [0.05, 0.0, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
    ];
    let run = run("box between slabs", &descs, settings());
    assert_left_with_bodies("box between slabs", &run, &[2]);
}

#[test]
fn ring_of_boxes_squeezed_in_a_closed_fixed_box() {
    let (side, room) = (0.55, [1.0, 1.0, 0.5]);
    let mut descs = vec![
        fixed("floor", [2.0, 0.5, 2.0], [0.0, -room[1] - 0.5, 0.0]),
        fixed("ceiling", [2.0, 0.5, 2.0], [0.0, room[1] + 0.5, 0.0]),
        fixed("west", [0.5, 2.0, 2.0], [-room[0] - 0.5, 0.0, 0.0]),
        fixed("east", [0.5, 2.0, 2.0], [room[0] + 0.5, 0.0, 0.0]),
        fixed("north", [2.0, 2.0, 0.5], [0.0, 0.0, -room[2] - 0.5]),
        fixed("south", [2.0, 2.0, 0.5], [0.0, 0.0, room[2] + 0.5]),
    ];
    for (k, [x, y]) in [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]]
        .iter()
        .enumerate()
    {
        descs.push(cuboid(
            &format!("ring{k}"),
            [side; 3],
            [*x, *y, 0.0],
            IDENTITY_XYZW,
            MassSpec::Density(1.0),
        ));
    }
    let run = run("squeezed ring", &descs, settings());
    assert_left_with_bodies("squeezed ring", &run, &[6, 7, 8, 9]);
}
