//! Engine states from Rapier: simulates scenes with Rapier's default
//! integration parameters (60 Hz) and writes the state of chosen steps as
//! scene files (docs/design.md section 6), read through the Rapier bridge.
//!
//! ```text
//! cargo run --features rapier --example engine_states -- DIR [--large PATH [--large-step N]]
//! ```
//!
//! writes the small states to `DIR/rp*.json` with `DIR/engine-notes-rapier.tsv`
//! (step, time, bodies, Rapier's own deepest contact depth and number of
//! contact points from its narrow phase, and parry's deepest penetration
//! and penetrating pairs on the state as written), and with `--large` the
//! settled pile of 1,000 to `PATH` (after [`LARGE_PILE_STEPS`] steps, or
//! `--large-step N`: an earlier step dumps it mid-settle). `rp08_mixed_pile` is a pile of 60
//! balls, capsules, cylinders and rounded boxes (issue 25) after 5 s.
//!
//! Z up, gravity -9.81, SI units, density 1000 kg/m^3 unless a mass is
//! given; fixed seeds. Lengths are multiples of 2^-10 m, exact in f32 and
//! short in the files.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use constraint_stabilization::Settings;
use constraint_stabilization::io::scene_file::write_scene;
use constraint_stabilization::rapier_bridge::RapierBridge;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::testbed::verify::{ParryPenetration, parry_penetration};
use rapier3d::prelude::*;

#[path = "common/rapier_scenes.rs"]
mod scenes;
use scenes::STEP_SECONDS;

/// A written state: the scene and what Rapier said about it.
struct State {
    stem: String,
    /// Deepest penetration and penetrating pairs by parry3d-f64 on the
    /// scene as written (the independent measure of `verify`).
    parry: ParryPenetration,
    scene: Scene,
    step: usize,
    rapier_deepest: f64,
    rapier_contacts: usize,
}

/// Steps of the pile of 1,000 before it is written (8 s: settled).
const LARGE_PILE_STEPS: usize = 480;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(dir) = args.first().map(PathBuf::from) else {
        return Err("usage: engine_states DIR [--large PATH [--large-step N]]".into());
    };
    let (mut large, mut large_step) = (None, LARGE_PILE_STEPS);
    let mut rest = args[1..].iter();
    while let Some(flag) = rest.next() {
        match flag.as_str() {
            "--large" => large = Some(PathBuf::from(rest.next().ok_or("--large needs a path")?)),
            "--large-step" => {
                large_step = rest
                    .next()
                    .and_then(|n| n.parse().ok())
                    .ok_or("--large-step needs a number of steps")?
            }
            other => return Err(format!("unknown argument {other}").into()),
        }
    }
    std::fs::create_dir_all(&dir)?;
    let states = vec![
        settled_pile("rp01_pile_200", 200, 1.0, 300, 1)?,
        heavy_on_stack("rp03_heavy_on_stack_100x", 100.0, 3)?,
        heavy_on_stack("rp04_heavy_on_stack_1000x", 1000.0, 4)?,
        pyramid("rp05_pyramid")?,
        thrown_box("rp06_thrown_box", 6)?,
        jumble("rp07_jumble_midfall", 7)?,
        settled("rp08_mixed_pile", scenes::mixed_pile_world(60, 0.6, 8), 300)?,
    ];
    let mut notes = String::from(
        "file\tstep\ttime_s\tbodies\trapier_deepest\trapier_contacts\tparry_deepest\tparry_pairs\n",
    );
    for state in &states {
        write(&dir.join(format!("{}.json", state.stem)), state, &mut notes)?;
    }
    std::fs::write(dir.join("engine-notes-rapier.tsv"), notes)?;
    if let Some(path) = large {
        let state = settled_pile("rp_pile_1000", 1000, 2.0, large_step, 2)?;
        write(&path, &state, &mut String::new())?;
    }
    Ok(())
}

fn write(path: &Path, state: &State, notes: &mut String) -> Result<(), Box<dyn std::error::Error>> {
    write_scene(path, &state.scene, None)?;
    writeln!(
        notes,
        "{}.json\t{}\t{:.4}\t{}\t{:.6e}\t{}\t{:.6e}\t{}",
        state.stem,
        state.step,
        state.step as f64 * STEP_SECONDS,
        state.scene.len(),
        state.rapier_deepest,
        state.rapier_contacts,
        state.parry.deepest,
        state.parry.penetrating_pairs
    )?;
    println!(
        "{}: step {}, {} bodies, Rapier deepest {:.3e} over {} contacts, parry deepest {:.3e} in {} pairs",
        path.display(),
        state.step,
        state.scene.len(),
        state.rapier_deepest,
        state.rapier_contacts,
        state.parry.deepest,
        state.parry.penetrating_pairs
    );
    Ok(())
}

/// Bodies dropped from a grid above a bin, alternately boxes and hulls,
/// simulated for `steps` steps.
fn settled_pile(
    stem: &str,
    count: usize,
    bin_half_width: f32,
    steps: usize,
    seed: u64,
) -> Result<State, Box<dyn std::error::Error>> {
    settled(stem, scenes::pile_world(count, bin_half_width, seed), steps)
}

/// `world` simulated for `steps` steps (a pile dropped into a bin: of
/// boxes and hulls, or of balls, capsules, cylinders and rounded boxes,
/// `scenes::mixed_pile_world`).
fn settled(
    stem: &str,
    mut world: PhysicsWorld,
    steps: usize,
) -> Result<State, Box<dyn std::error::Error>> {
    for _ in 0..steps {
        world.step();
    }
    state(stem, &world, steps)
}

/// Four 1 kg boxes under a box `ratio` times heavier; the state at the
/// deepest penetration in the first 0.5 s.
fn heavy_on_stack(stem: &str, ratio: f32, seed: u64) -> Result<State, Box<dyn std::error::Error>> {
    deepest_within(stem, scenes::heavy_stack_world(ratio, seed).0, 30)
}

/// 55 boxes of 20 cm in a plane, base of 10, settled for 2 s.
fn pyramid(stem: &str) -> Result<State, Box<dyn std::error::Error>> {
    let mut world = scenes::pyramid_world().0;
    for _ in 0..120 {
        world.step();
    }
    state(stem, &world, 120)
}

/// A 2 kg box thrown at 15 m/s, spinning, into a stack of six 8 kg boxes;
/// the state at the deepest penetration in the first second (the
/// projectile's impact).
fn thrown_box(stem: &str, seed: u64) -> Result<State, Box<dyn std::error::Error>> {
    deepest_within(stem, scenes::thrown_box_world(seed).0, 60)
}

/// 50 boxes and 30 hulls in a column falling onto the ground; the step of
/// the first 3 s with the most penetrating pairs.
fn jumble(stem: &str, seed: u64) -> Result<State, Box<dyn std::error::Error>> {
    let mut world = scenes::jumble_world(seed);
    let mut best: Option<State> = None;
    for step in 1..=180 {
        world.step();
        let state = state(stem, &world, step)?;
        let most = |s: &State| s.parry.penetrating_pairs;
        if best.as_ref().is_none_or(|b| most(&state) > most(b)) {
            best = Some(state);
        }
    }
    Ok(best.ok_or("no step simulated")?)
}

/// Steps `steps` times and keeps the state with the deepest penetration
/// (by parry on the state as written: Rapier's narrow phase describes the
/// poses at the start of its step, one step stale).
fn deepest_within(
    stem: &str,
    mut world: PhysicsWorld,
    steps: usize,
) -> Result<State, Box<dyn std::error::Error>> {
    let mut best: Option<State> = None;
    for step in 1..=steps {
        world.step();
        let state = state(stem, &world, step)?;
        if best
            .as_ref()
            .is_none_or(|b| state.parry.deepest > b.parry.deepest)
        {
            best = Some(state);
        }
    }
    Ok(best.ok_or("no step simulated")?)
}

/// Deepest penetration (positive) and number of contact points of a pair,
/// as Rapier's narrow phase reports them (computed at the start of the
/// step, before the solver moved the bodies).
fn rapier_depth(pair: &ContactPair) -> (f64, usize) {
    let PairContacts::Rigid(contacts) = &pair.contacts else {
        return (0.0, 0);
    };
    let points = contacts.manifolds.iter().flat_map(|m| &m.points);
    points.fold((0.0, 0), |(deepest, count), p| {
        (deepest.max(-f64::from(p.dist)), count + 1)
    })
}

/// The world read through the bridge, with Rapier's own depth and contacts.
fn state(
    stem: &str,
    world: &PhysicsWorld,
    step: usize,
) -> Result<State, Box<dyn std::error::Error>> {
    let mut bridge = RapierBridge::new(Settings::default())?;
    let sync = bridge.sync(&world.bodies, &world.colliders)?;
    if !sync.skipped.is_empty() {
        return Err(format!("{stem}: {} colliders skipped", sync.skipped.len()).into());
    }
    let (rapier_deepest, rapier_contacts) = world
        .contact_pairs()
        .map(rapier_depth)
        .fold((0.0, 0), |(d, c), (pd, pc)| (f64::max(d, pd), c + pc));
    Ok(State {
        stem: stem.to_owned(),
        parry: parry_penetration(bridge.scene(), 0.0)?,
        scene: bridge.scene().clone(),
        step,
        rapier_deepest,
        rapier_contacts,
    })
}
