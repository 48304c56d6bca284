//! The stabilizer: the loop of DESIGN.md section 1.
//!
//! Each pass:
//! 1. detection over the whole scene ([`detection`]): broad phase on AABBs
//!    enlarged by the contact margin, V-Clip on every candidate pair,
//!    warm-started from the pair's last query (kept across passes and
//!    calls); if no penetration is deeper than the tolerance, stop;
//! 2. islands: union-find over the pairs that penetrate or are within the
//!    contact margin (fixed bodies never join islands);
//! 3. for every island with a penetration deeper than the tolerance, one
//!    projection step ([`crate::projector::projection_step`]) with the
//!    island's contacts as constraint provider: linearize, solve the
//!    mass-weighted projection QP, backtracking line search on the true
//!    geometry, apply. Islands are independent: they are solved in parallel
//!    (feature `parallel`) and merged in island order, so the result is
//!    bit-identical whatever the number of threads.
//!
//! Guarantees: a scene with no penetration deeper than the tolerance is not
//! touched (every pose bit-identical); bodies outside solved islands are not
//! touched; the merit of each island never rises; on an error every pose is
//! as it was before the call.

mod detection;
mod island_provider;
mod parallel;
mod report;
mod settings;
mod solve_island;

use std::time::Instant;

use nalgebra::{Isometry3, Vector3};

pub use report::{IslandReport, PairPenetration, PassReport, Report, StageTimes, Status};
pub use settings::{ResolvedLengths, Settings, SettingsError};

use crate::Error;
use crate::contact::WarmStartCache;
use crate::island::islands;
use crate::projector::{ProjectionSettings, StepOutcome};
use crate::scene::Scene;
use crate::vclip::VClip;
use detection::{Detection, detect};
use island_provider::SceneGeometry;
use solve_island::{IslandSolution, solve_island};

/// The error type of a stabilization call.
pub type StabilizeError = Error;

/// Removes interpenetration from scenes; owns its settings and the V-Clip
/// warm starts of earlier queries (temporal coherence across calls).
#[derive(Debug, Clone, Default)]
pub struct Stabilizer {
    settings: Settings,
    cache: WarmStartCache,
}

impl Stabilizer {
    /// A stabilizer with validated settings.
    pub fn new(settings: Settings) -> Result<Self, Error> {
        settings.validate()?;
        Ok(Stabilizer {
            settings,
            cache: WarmStartCache::default(),
        })
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Moves the dynamic bodies of `scene` by the smallest mass-weighted
    /// correction that removes their interpenetration. On error the poses
    /// are as they were.
    pub fn stabilize(&mut self, scene: &mut Scene) -> Result<Report, Error> {
        let start = Instant::now();
        let before: Vec<([f64; 3], [f64; 4])> = scene
            .bodies()
            .iter()
            .map(|b| ((*b.translation_user()).into(), b.rotation_user_xyzw()))
            .collect();
        let com_before: Vec<Isometry3<f64>> =
            scene.bodies().iter().map(|b| *b.com_pose()).collect();
        let result = self.run(scene, start);
        if result.is_err() {
            restore(scene, &before);
        }
        let mut report = result?;
        let (displacement, moved) = scene_displacement(scene, &com_before);
        report.displacement = displacement;
        report.bodies_moved = moved;
        report.times.total = start.elapsed().as_secs_f64();
        log::info!(
            "stabilize: {} bodies, {} ({} passes, {} islands solved), depth {:.3e} -> {:.3e} (tol {:.1e}), {} moved, {:.3} ms",
            scene.len(),
            report.status.name(),
            report.passes,
            report.islands_solved(),
            report.depth_before,
            report.depth_after,
            report.tolerance,
            report.bodies_moved,
            report.times.total * 1e3
        );
        Ok(report)
    }

    fn run(&mut self, scene: &mut Scene, start: Instant) -> Result<Report, Error> {
        let lengths = self.settings.resolve(scene_scale(scene));
        let vclip = VClip::new(self.settings.vclip);
        let projection = ProjectionSettings {
            tolerance: lengths.tolerance,
            target_margin: lengths.target_margin,
            line_search: self.settings.line_search,
            solver: self.settings.solver.clone(),
            max_steps: 1,
        };
        let shapes: Vec<_> = scene
            .bodies()
            .iter()
            .map(|b| b.polyhedron().clone())
            .collect();
        let mut report = Report::new(&lengths);
        self.cache.forget_dropped_shapes();
        loop {
            let poses: Vec<Isometry3<f64>> = scene.bodies().iter().map(|b| *b.com_pose()).collect();
            let geometry = SceneGeometry {
                shapes: &shapes,
                poses: &poses,
            };
            let detection = detect(scene, geometry, &mut self.cache, &vclip, &lengths)?;
            report.record_detection(&detection);
            let mut pass = pass_report(&detection, lengths.tolerance);
            let finished = if detection.deepest <= lengths.tolerance {
                Some(if report.passes == 0 {
                    Status::NothingToDo
                } else {
                    Status::Converged
                })
            } else if report.passes == self.settings.max_passes {
                Some(Status::PassLimit)
            } else {
                None
            };
            if let Some(status) = finished {
                report.pass_reports.push(pass);
                report.status = status;
                return Ok(report);
            }
            let solutions = self.solve_pass(
                scene,
                geometry,
                &detection,
                &lengths,
                &projection,
                &mut pass,
            )?;
            report.passes += 1;
            let all_stalled = self.apply(scene, solutions, &mut report, &mut pass)?;
            log_pass(report.passes, &pass, &report.stalled_islands, start);
            report.pass_reports.push(pass);
            if all_stalled {
                report.status = Status::Stalled;
                return Ok(report);
            }
        }
    }

    /// Applies the islands' corrections in island order and records them;
    /// returns whether every island stalled.
    fn apply(
        &mut self,
        scene: &mut Scene,
        solutions: Vec<IslandSolution>,
        report: &mut Report,
        pass: &mut PassReport,
    ) -> Result<bool, Error> {
        report.stalled_islands = solutions
            .iter()
            .filter(|s| s.report.outcome == StepOutcome::Stalled)
            .map(|s| s.report.bodies.clone())
            .collect();
        let all_stalled = report.stalled_islands.len() == solutions.len();
        for solution in solutions {
            report.times.solve += solution.solve_seconds;
            report.times.line_search += solution.line_search_seconds;
            solution.apply(scene, &mut self.cache)?;
            pass.solved.push(solution.report);
        }
        Ok(all_stalled)
    }

    /// Forms islands from the detection and solves those that penetrate.
    fn solve_pass(
        &self,
        scene: &Scene,
        geometry: SceneGeometry,
        detection: &Detection,
        lengths: &ResolvedLengths,
        projection: &ProjectionSettings,
        pass: &mut PassReport,
    ) -> Result<Vec<IslandSolution>, Error> {
        let all_islands = islands(&scene.fixed_flags(), &detection.active_pairs)?;
        pass.islands = all_islands.len();
        let penetrating: Vec<_> = all_islands
            .into_iter()
            .filter(|island| {
                island
                    .pairs
                    .iter()
                    .any(|&k| -detection.active_values[k] > lengths.tolerance)
            })
            .collect();
        let results = parallel::map(&penetrating, |island| {
            solve_island(
                scene,
                geometry,
                island,
                &detection.active_pairs,
                &self.cache,
                &self.settings,
                lengths,
                projection,
            )
        });
        results.into_iter().collect()
    }
}

/// The debug line of a pass.
fn log_pass(number: usize, pass: &PassReport, stalled: &[Vec<usize>], start: Instant) {
    log::debug!(
        "pass {number}: {} candidates, {} active, {} penetrating, {} islands, \
         {} solved ({} stalled), deepest {:.3e}, {:.3} ms so far",
        pass.candidate_pairs,
        pass.active_pairs,
        pass.penetrating_pairs,
        pass.islands,
        pass.solved.len(),
        stalled.len(),
        pass.deepest,
        start.elapsed().as_secs_f64() * 1e3
    );
}

fn pass_report(detection: &Detection, tolerance: f64) -> PassReport {
    PassReport {
        candidate_pairs: detection.candidates,
        penetrating_pairs: detection.penetrating(tolerance),
        active_pairs: detection.active_pairs.len(),
        islands: 0,
        deepest: detection.deepest,
        solved: Vec::new(),
    }
}

/// The scene's length scale: the circumradius of its smallest dynamic body
/// (of its smallest body if all are fixed; 1 for an empty scene).
pub fn scene_scale(scene: &Scene) -> f64 {
    let smallest = |dynamic_only: bool| {
        scene
            .bodies()
            .iter()
            .filter(|b| !dynamic_only || !b.is_fixed())
            .map(|b| b.polyhedron().scale())
            .reduce(f64::min)
    };
    smallest(true).or_else(|| smallest(false)).unwrap_or(1.0)
}

/// Puts back the user poses recorded before the call.
fn restore(scene: &mut Scene, before: &[([f64; 3], [f64; 4])]) {
    for (body, (translation, rotation)) in scene.bodies_mut().iter_mut().zip(before) {
        // The recorded poses were accepted by the same bodies before the
        // call, so they are valid: this cannot fail.
        let restored = body.set_user_pose(Vector3::from(*translation), *rotation);
        debug_assert!(restored.is_ok());
    }
}

/// Mass-weighted displacement between `com_before` and the scene's poses,
/// and the number of bodies whose pose changed.
fn scene_displacement(scene: &Scene, com_before: &[Isometry3<f64>]) -> (f64, usize) {
    let mut squared = 0.0;
    let mut moved = 0;
    for (body, before) in scene.bodies().iter().zip(com_before) {
        let after = body.com_pose();
        if after == before {
            continue;
        }
        moved += 1;
        if let Some(mass) = body.mass() {
            let dx = after.translation.vector - before.translation.vector;
            let dtheta = (after.rotation * before.rotation.inverse()).scaled_axis();
            let inertia = before.rotation.to_rotation_matrix();
            let inertia_world = inertia.matrix() * mass.inertia_body * inertia.matrix().transpose();
            squared += mass.mass * dx.norm_squared() + dtheta.dot(&(inertia_world * dtheta));
        }
    }
    (squared.sqrt(), moved)
}
