//! `stabilize scene IN.json -o OUT.json`: correct a scene file (docs/design.md
//! section 6). The output is the input scene (same bodies, order, names and
//! shapes) with corrected poses and a `report` object; fed back in, it is a
//! no-op. Exit 0 when no penetration deeper than the tolerance remains, 1
//! when one does (pass limit, stall, or an island no solver could solve:
//! the output is written with the progress made, and the report and stderr
//! name the islands left and why), 2 on bad input; on bad input no output
//! file is written.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use constraint_stabilization::Stabilizer;
use constraint_stabilization::io::scene_file::{read_scene, write_scene};
use constraint_stabilization::stabilizer::report_json::report_to_json;

use crate::exit;
use crate::progress::PassProgress;

/// Arguments of `stabilize scene`.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// The scene file to correct.
    input: PathBuf,
    /// Where to write the corrected scene.
    #[arg(short, long)]
    output: PathBuf,
}

/// Runs the subcommand.
pub fn run(args: &SceneArgs) -> ExitCode {
    let mut scene = match read_scene(&args.input) {
        Ok(scene) => scene,
        Err(error) => return exit::bad_input(&error),
    };
    let mut stabilizer = match Stabilizer::for_scene(&scene) {
        Ok(stabilizer) => stabilizer,
        Err(error) => return exit::bad_input(&error),
    };
    let mut progress = PassProgress::start("stabilizing");
    let result = stabilizer.stabilize_observed(&mut scene, &mut |pass| progress.pass(pass));
    progress.finish();
    let report = match result {
        Ok(report) => report,
        Err(error) => return exit::bad_input(&error),
    };
    let json = report_to_json(&report, &scene);
    if let Err(error) = write_scene(&args.output, &scene, Some(&json)) {
        return exit::bad_input(&error);
    }
    eprintln!(
        "stabilize: {} after {} passes, penetration {:.3e} -> {:.3e} (tolerance {:.1e}), {} bodies moved",
        report.status.name(),
        report.passes,
        report.depth_before,
        report.depth_after,
        report.tolerance,
        report.bodies_moved
    );
    for left in &report.islands_left {
        eprintln!(
            "stabilize: island of bodies {:?} left: {}",
            left.bodies,
            left.outcome.reason()
        );
    }
    if report.restored_input {
        eprintln!("stabilize: the result was worse than the input: input poses written");
    }
    if report.status.is_resolved() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(exit::NOT_SOLVED)
    }
}
