//! `Settings::keep_penetrated_pairs` on the input of a Rapier loop's call
//! (`tests/data/loop/`, recorded by `examples/probes/passes_probe.rs`):
//! a box wedged between the ground and a neighbour, each of its two
//! contacts separated beyond the contact margin while the other
//! penetrates. Without the setting each pass sees one contact, pushes the
//! box into the other, and the call takes dozens of passes; with it the
//! pass after the first push solves both.

use constraint_stabilization::{Scene, Settings};

use crate::stabilize::support::stabilize_with;

/// The call's lengths, as the bridge derived them (closed contacts).
const TOLERANCE: f64 = 8.250823161483923e-7;
const CONTACT_MARGIN: f64 = 4.1671924553374396e-4;
const TARGET_MARGIN: f64 = 4.1254115807419615e-7;
const ALLOWED_PENETRATION: f64 = 1.2376234742225884e-6;

/// Passes the call may take with the setting: the first push, the pass
/// that solves both contacts, a pass of second-order clean-up each for
/// the two neighbours it then touches, and the verifying detection.
const KEPT_MAX_PASSES: usize = 6;

/// Passes the call takes without the setting at least (it took 61 in
/// the loop): the pathology the fixture holds.
const UNKEPT_MIN_PASSES: usize = 20;

fn wedged_box() -> Scene {
    use constraint_stabilization::io::scene_file::read_scene;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/loop/pile_200_wedged_box.json");
    read_scene(&path).expect("reads")
}

fn settings(keep: bool) -> Settings {
    let mut settings = Settings::default();
    settings.tolerance_absolute = Some(TOLERANCE);
    settings.contact_margin_absolute = Some(CONTACT_MARGIN);
    settings.target_margin_absolute = Some(TARGET_MARGIN);
    settings.allowed_penetration = ALLOWED_PENETRATION;
    settings.keep_penetrated_pairs = keep;
    settings
}

#[test]
fn a_wedged_box_is_solved_in_a_few_passes_with_its_pairs_kept() {
    let mut kept = wedged_box();
    let (report, residual) = stabilize_with(&mut kept, settings(true));
    assert!(report.status.is_resolved(), "{:?}", report.status);
    assert!(residual <= report.tolerance, "exact depth {residual:e}");
    assert!(
        report.passes <= KEPT_MAX_PASSES,
        "{} passes with the pairs kept",
        report.passes
    );
    let mut unkept = wedged_box();
    let (without, residual) = stabilize_with(&mut unkept, settings(false));
    assert!(residual <= without.tolerance, "exact depth {residual:e}");
    println!(
        "passes: {} with the pairs kept, {} without",
        report.passes, without.passes
    );
    assert!(
        without.passes >= UNKEPT_MIN_PASSES,
        "{} passes without: the fixture no longer holds the ping-pong",
        without.passes
    );
}
