//! The diagnostic probes, one example with a subcommand per probe (one
//! binary for `cargo test` to build and link instead of six):
//!
//! ```text
//! cargo run --release --features rapier,serde --example probes -- PROBE [ARGS...]
//! ```
//!
//! - `slide`: where the heavy stacks' sideways drift comes from (issue 10),
//!   [`slide_probe`];
//! - `rest`: what keeps a settled pile or pyramid moving under the bridge
//!   (issue 22), [`rest_probe`];
//! - `settle`: why the pile of 200 settles later under the bridge than
//!   under Rapier alone and which box slides late (issue 21),
//!   [`settle_probe`];
//! - `thrown`: why the thrown box's stack drifts under the bridge (issue
//!   22), [`thrown_probe`];
//! - `polish`: whether clarabel's polish decides any answer, and its time,
//!   on random stacks (`benchmarks/results/polish.md`), [`polish_probe`];
//! - `friction`: one call on an engine state with friction on every body,
//!   logged (issue 21), [`friction_probe`];
//! - `curved`: cylinders by support functions against their 71-gon
//!   polyhedra on the Rapier mixed pile, interleaved (issue 25),
//!   [`curved_speed`];
//! - `certificates`: the narrow phase's queries and time per call with and
//!   without separation certificates in the Rapier loop, interleaved
//!   (issue 21), [`certificates_loop`];
//! - `passes`: passes per call in the Rapier loop with and without
//!   `Settings::keep_penetrated_pairs`, and the input of the longest call
//!   (issue 21), [`passes_probe`];
//! - `warm`: the solver's warm starts against cold solves on the states of
//!   a Rapier run, interleaved (issue 21), [`warm_loop`].
//!
//! Each probe reads the arguments after its name as it documents them.

#[path = "../common/rapier_scenes.rs"]
mod scenes;

mod certificates_loop;
mod curved_speed;
mod friction_probe;
mod passes_probe;
mod polish_probe;
mod rest_probe;
mod settle_probe;
mod slide_probe;
mod thrown_probe;
mod warm_loop;

/// The probes' names, as the first argument.
const PROBES: &str =
    "slide | rest | settle | thrown | polish | friction | curved | certificates | passes | warm";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let probe = args.next();
    let args: Vec<String> = args.collect();
    match probe.as_deref() {
        Some("slide") => slide_probe::run(args),
        Some("rest") => rest_probe::run(args),
        Some("settle") => settle_probe::run(args),
        Some("thrown") => thrown_probe::run(args),
        Some("polish") => {
            polish_probe::run();
            Ok(())
        }
        Some("friction") => friction_probe::run(args),
        Some("curved") => curved_speed::run(args),
        Some("certificates") => certificates_loop::run(args),
        Some("passes") => passes_probe::run(args),
        Some("warm") => warm_loop::run(args),
        other => Err(format!("usage: probes <{PROBES}> [ARGS...] (got {other:?})").into()),
    }
}
