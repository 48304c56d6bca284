//! A scene file read, stabilized with the settings it carries, and written
//! back with the report: what `stabilize scene` does, in a few lines of
//! library code.
//!
//! ```text
//! cargo run --example scene_file -- examples/scenes_log_story.json /tmp/corrected.json
//! ```

use std::path::PathBuf;

use constraint_stabilization::Stabilizer;
use constraint_stabilization::io::scene_file::{read_scene, write_scene};
use constraint_stabilization::stabilizer::report_json::report_to_json;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1).map(PathBuf::from);
    let (Some(input), Some(output)) = (args.next(), args.next()) else {
        return Err("usage: scene_file IN.json OUT.json".into());
    };
    let mut scene = read_scene(&input)?;
    // The file's `settings` (tolerance, margins, passes, solver) applied
    // over the library's defaults.
    let mut stabilizer = Stabilizer::for_scene(&scene)?;
    let report = stabilizer.stabilize(&mut scene)?;
    write_scene(&output, &scene, Some(&report_to_json(&report, &scene)))?;
    println!(
        "{}: {} after {} passes, deepest penetration {:.3e} -> {:.3e} (tolerance {:.1e}); written to {}",
        input.display(),
        report.status.name(),
        report.passes,
        report.depth_before,
        report.depth_after,
        report.tolerance,
        output.display()
    );
    Ok(())
}
