//! The `stabilize` command-line tool (feature `cli`), docs/design.md section 8.
//!
//! One module per subcommand. Exit codes: 0 success; 1 the problem was
//! read but not solved; 2 bad input or usage (clap's own usage errors exit
//! with 2 as well).

mod demo;
mod exit;
mod lcp;
mod progress;
mod render;
mod scene;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Removes interpenetration between convex rigid bodies; solves LCP files.
#[derive(Debug, Parser)]
#[command(name = "stabilize", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Correct a scene file: `stabilize scene IN.json -o OUT.json`.
    Scene(scene::SceneArgs),
    /// Solve an LCP file (Siconos format) and print one JSON object.
    Lcp(lcp::LcpArgs),
    /// Stabilize the built-in demonstration scene and print the report.
    Demo(demo::DemoArgs),
    /// Draw a scene file as SVG: `stabilize render IN.json -o OUT.svg`.
    Render(render::RenderArgs),
}

fn main() -> ExitCode {
    env_logger::init();
    let cli = Cli::parse();
    match cli.command {
        Command::Scene(args) => scene::run(&args),
        Command::Lcp(args) => lcp::run(&args),
        Command::Demo(args) => demo::run(&args),
        Command::Render(args) => render::run(&args),
    }
}
