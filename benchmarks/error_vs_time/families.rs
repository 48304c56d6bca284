//! The scenes of the error-against-time benchmark, by family and size.
//!
//! Every synthetic scene comes from a seeded `ChaCha8Rng` (the same on
//! every run and platform), y up, ground top face `y = 0`:
//! - `stack`: [`common::box_stack`], a column of boxes each sunk 3 % of its
//!   height into the one below, tilted and shifted a little;
//! - `pyramid`: a wall of unit cubes, `base` in the bottom row and one
//!   fewer per row, each sunk [`PYRAMID_SINK`] (0.5 to 1.5 times, random)
//!   into the row below and pressed [`PYRAMID_SQUEEZE`] into its
//!   neighbour, tilted up to [`PYRAMID_TILT`];
//! - `heavy_on_pyramid`: the pyramid of base [`HEAVY_PYRAMID_BASE`] (1 kg
//!   cubes) under one cube `ratio` times heavier, sunk like the others;
//! - `pile`: [`demo_scene_with`], boxes and hulls in columns and clusters,
//!   each overlapping its neighbours by 1 % to [`PILE_OVERLAP_MAX`] of the
//!   smaller extent;
//! - `pairs`: independent pairs of random hulls (no ground) on a grid,
//!   overlapping by 1 % to 10 % of their size ([`PAIR_OVERLAP`]);
//! - `deep_pairs`: the same with an overlap of [`DEEP_OVERLAP`] (half the
//!   size);
//! - `engine`: the states of `tests/data/engine/` (Rapier, MuJoCo and
//!   Bullet after a step; z up; see their notes there).

use constraint_stabilization::body::{BodyDesc, MassSpec, Shape};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::testbed::demo::{DemoOptions, demo_scene_with};
use nalgebra::{Point3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;

/// Sink of a pyramid cube into the row below (or the ground), fraction of
/// its height (times a random factor in 0.5..1.5).
pub const PYRAMID_SINK: f64 = 0.03;
/// Overlap of neighbouring cubes in a row, fraction of their width.
pub const PYRAMID_SQUEEZE: f64 = 0.01;
/// Largest tilt of a pyramid cube (radians, random axis).
pub const PYRAMID_TILT: f64 = 0.02;
/// Base of the pyramid under the heavy cube.
pub const HEAVY_PYRAMID_BASE: usize = 5;
/// Largest overlap in a pile, fraction of the smaller extent.
pub const PILE_OVERLAP_MAX: f64 = 0.10;
/// Overlap range of the independent pairs, fraction of the size.
pub const PAIR_OVERLAP: (f64, f64) = (0.01, 0.10);
/// Overlap of the deep pairs, fraction of the size.
pub const DEEP_OVERLAP: f64 = 0.5;
/// Spacing of the pairs' grid, in body sizes.
const PAIR_SPACING: f64 = 4.0;
/// Half extent of a pyramid cube.
const CUBE_HALF: f64 = 0.5;

/// One scene of a family.
pub struct Case {
    /// Family name (`stack`, `pyramid`, ...): one plot per family.
    pub family: &'static str,
    /// `family_size` or the engine state's file stem.
    pub name: String,
    /// The family's size parameter (bodies, base, ratio), for the scaling
    /// fit; the body count is `scene.len()`.
    pub size: f64,
    pub scene: Scene,
}

/// Every case of the full run (`quick`: a small one of each family).
pub fn cases(quick: bool) -> Vec<Case> {
    let mut cases = Vec::new();
    let stacks: &[usize] = if quick { &[5] } else { &[5, 10, 20, 50] };
    for &n in stacks {
        cases.push(case("stack", n as f64, common::box_stack(n, 1)));
    }
    let bases: &[usize] = if quick { &[5] } else { &[5, 10, 20, 30] };
    for &b in bases {
        cases.push(case("pyramid", b as f64, pyramid(b, None, 7)));
    }
    let ratios: &[f64] = if quick { &[1e4] } else { &[1e2, 1e4, 1e6] };
    for &r in ratios {
        let scene = pyramid(HEAVY_PYRAMID_BASE, Some(r), 11);
        cases.push(case("heavy_on_pyramid", r, scene));
    }
    let piles: &[usize] = if quick {
        &[10, 100]
    } else {
        &[10, 100, 500, 1000, 2000]
    };
    for &n in piles {
        cases.push(case("pile", n as f64, pile(n)));
    }
    let pair_counts: &[usize] = if quick { &[100] } else { &[1000] };
    for &n in pair_counts {
        cases.push(case("pairs", n as f64, pairs(n, PAIR_OVERLAP, 3)));
    }
    let deep_counts: &[usize] = if quick { &[10] } else { &[100] };
    for &n in deep_counts {
        let scene = pairs(n, (DEEP_OVERLAP, DEEP_OVERLAP), 5);
        cases.push(case("deep_pairs", n as f64, scene));
    }
    for (name, scene) in engine_states(quick) {
        let size = scene.len() as f64;
        cases.push(Case {
            family: "engine",
            name,
            size,
            scene,
        });
    }
    cases
}

fn case(family: &'static str, size: f64, scene: Scene) -> Case {
    Case {
        family,
        name: format!("{family}_{size}"),
        size,
        scene,
    }
}

/// The pile of `bodies` bodies (ground included).
fn pile(bodies: usize) -> Scene {
    let options = DemoOptions {
        overlap_max: PILE_OVERLAP_MAX,
        ..DemoOptions::default()
    };
    demo_scene_with(bodies, 2026, &options)
}

/// A random rotation by at most `angle` about a random axis.
fn small_rotation(rng: &mut ChaCha8Rng, angle: f64) -> UnitQuaternion<f64> {
    let axis = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
    let axis = axis.try_normalize(1e-9).unwrap_or_else(Vector3::x);
    UnitQuaternion::from_scaled_axis(axis * rng.random_range(0.0..angle))
}

/// The pyramid of `base` cubes (see the module doc), with a cube
/// `heavy_ratio` times heavier on top if given.
pub fn pyramid(base: usize, heavy_ratio: Option<f64>, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut scene = Scene::new();
    // Valid by construction (positive extents, unit quaternions, positive
    // masses): add_body cannot fail.
    scene.add_body(common::ground()).expect("valid ground");
    let side = 2.0 * CUBE_HALF;
    let pitch = side * (1.0 - PYRAMID_SQUEEZE);
    let mut centre_y = CUBE_HALF;
    let add = |scene: &mut Scene, name: String, x: f64, y: f64, mass: f64, rng: &mut _| {
        let rotation = small_rotation(rng, PYRAMID_TILT);
        scene
            .add_body(BodyDesc {
                name,
                shape: Shape::Cuboid {
                    half_extents: Vector3::repeat(CUBE_HALF),
                },
                translation: Vector3::new(x, y, 0.0),
                rotation_xyzw: common::xyzw(&rotation),
                mass: MassSpec::Mass(mass),
            })
            .expect("valid cube");
    };
    let sink = |rng: &mut ChaCha8Rng| PYRAMID_SINK * side * rng.random_range(0.5..1.5);
    for row in 0..base {
        centre_y -= sink(&mut rng);
        for i in 0..base - row {
            let x = (i as f64 + 0.5 * row as f64) * pitch;
            add(
                &mut scene,
                format!("cube_{row}_{i}"),
                x,
                centre_y,
                1.0,
                &mut rng,
            );
        }
        centre_y += side;
    }
    if let Some(ratio) = heavy_ratio {
        centre_y -= sink(&mut rng);
        let x = 0.5 * (base - 1) as f64 * pitch;
        add(&mut scene, "heavy".into(), x, centre_y, ratio, &mut rng);
    }
    scene
}

/// `count` pairs of random hulls on a square grid (no ground), each pair
/// overlapping along a random direction by a fraction in `overlap` of
/// the hulls' size.
pub fn pairs(count: usize, overlap: (f64, f64), seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut scene = Scene::new();
    let columns = (count as f64).sqrt().ceil() as usize;
    for k in 0..count {
        let cell = Vector3::new((k % columns) as f64, 0.0, (k / columns) as f64) * PAIR_SPACING;
        let direction = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let direction = direction.try_normalize(1e-9).unwrap_or_else(Vector3::x);
        let fraction = if overlap.1 > overlap.0 {
            rng.random_range(overlap.0..overlap.1)
        } else {
            overlap.0
        };
        // Two hulls of radius about 0.5 whose centres are (1 - fraction)
        // diameters apart along `direction`.
        let offset = direction * 0.5 * (1.0 - fraction);
        for (side, centre) in [("a", cell - offset), ("b", cell + offset)] {
            let points: Vec<Point3<f64>> = (0..12)
                .map(|_| {
                    let v = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
                    Point3::from(v.try_normalize(1e-9).unwrap_or_else(Vector3::y) * 0.5)
                })
                .collect();
            scene
                .add_body(BodyDesc {
                    name: format!("pair_{k}_{side}"),
                    shape: Shape::ConvexHull { points },
                    translation: centre,
                    rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
                    mass: MassSpec::Density(1.0),
                })
                // Twelve random points on a sphere span a volume with
                // probability 1; the seeds used here are checked by the run.
                .expect("valid hull");
        }
    }
    scene
}

/// The engine states (`quick`: the Rapier 1:100 stack only).
fn engine_states(quick: bool) -> Vec<(String, Scene)> {
    let mut states = common::engine_states();
    if quick {
        states.retain(|(name, _)| name.starts_with("rp03"));
    }
    states
}
