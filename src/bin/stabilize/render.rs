//! `stabilize render SCENE.json -o SCENE.svg [--view x|y|z|iso]
//! [--highlight-penetrating]`: an SVG picture of a scene
//! (`constraint_stabilization::render`).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use constraint_stabilization::io::scene_file::read_scene;
use constraint_stabilization::testbed::render::{View, render_svg};
use constraint_stabilization::{Settings, Stabilizer};

use crate::exit;

/// Arguments of `stabilize render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene file to draw.
    input: PathBuf,
    /// Where to write the SVG.
    #[arg(short, long)]
    output: PathBuf,
    /// Where the camera looks from: x, y, z or iso.
    #[arg(long, default_value = "iso")]
    view: String,
    /// Outline the bodies of penetrating pairs in red, with their depths.
    #[arg(long)]
    highlight_penetrating: bool,
}

/// Runs the subcommand.
pub fn run(args: &RenderArgs) -> ExitCode {
    let Some(view) = View::from_name(&args.view) else {
        return exit::bad_input(&format!("unknown view `{}` (x, y, z or iso)", args.view));
    };
    let scene = match read_scene(&args.input) {
        Ok(scene) => scene,
        Err(error) => return exit::bad_input(&format!("{}: {error}", args.input.display())),
    };
    let penetrations = if args.highlight_penetrating {
        let settings = Settings::default().with_scene_settings(scene.settings());
        let found = Stabilizer::new(settings).and_then(|mut s| s.penetrations(&scene));
        match found {
            Ok(found) => found,
            Err(error) => return exit::bad_input(&error.to_string()),
        }
    } else {
        Vec::new()
    };
    let svg = render_svg(&scene, view, &penetrations);
    if let Err(error) = std::fs::write(&args.output, svg) {
        return exit::bad_input(&format!("{}: {error}", args.output.display()));
    }
    println!(
        "{}: {} bodies, {} penetrating pairs marked",
        args.output.display(),
        scene.len(),
        penetrations.len()
    );
    ExitCode::SUCCESS
}
