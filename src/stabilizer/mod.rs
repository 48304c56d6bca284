//! The stabilizer: the loop of docs/design.md section 1.
//!
//! Each pass:
//! 1. detection over the whole scene ([`crate::contact::detect`]): broad
//!    phase on the bodies' AABBs enlarged by the contact margin, V-Clip on
//!    every candidate pair of convex parts (a convex body is one part, a
//!    compound several, `contact::scene_parts`), warm-started from the
//!    pair's last query (kept across passes and calls), except the pairs
//!    whose parts did not move since their last answer or that a bound on
//!    their motion certifies separated beyond the contact margin
//!    (`contact::certificate`, kept across calls); if no penetration is
//!    deeper than the tolerance, stop;
//! 2. islands: union-find over the bodies of the pairs that penetrate or are within the
//!    contact margin (fixed bodies never join islands);
//! 3. for every island with a penetration deeper than the tolerance, one
//!    projection step ([`crate::projector::projection_step`]) with the
//!    island's contacts as constraint provider: linearize, solve the
//!    mass-weighted projection QP, backtracking line search on the true
//!    geometry, apply. Islands are independent: they are solved in parallel
//!    (feature `parallel`) and merged in island order, so the result is
//!    bit-identical whatever the number of threads.
//!
//! An island that cannot be solved (every solver failed, its problem was
//! invalid, or its line search stalled) keeps the poses it had before its
//! step; the other islands are applied and the call goes on with them. It
//! ends when no island moved in a pass ([`Status::Stalled`], or
//! [`Status::Unsolved`] if one failed), with the islands left and why in
//! the report.
//!
//! A call also ends when its time budget ([`Settings::time_budget`]) is
//! spent ([`Status::TimeLimit`]): it is the solvers' deadline
//! ([`crate::solver::SolverSettings::deadline`]) inside every pass, so an
//! island whose solver is stopped by it keeps its poses, and the call ends
//! after that pass; it is also checked after each pass's detection, so the
//! report's depth after is that of the configuration returned.
//!
//! [`Settings::method`] chooses this projection (the default) or the
//! nonlinear Gauss–Seidel baseline of `stabilizer::gauss_seidel`: the same
//! detection, report, log lines and guarantees, with the passes replaced
//! by its sweeps.
//!
//! Guarantees: a scene with no penetration deeper than the tolerance is not
//! touched (every pose bit-identical); bodies outside solved islands are not
//! touched; the merit of each island never rises; the scene is never
//! returned worse than it came: if the exact deepest penetration or the
//! merit over the whole scene rose (islands moved into each other), every
//! pose is put back and the report says so; on an error (invalid input)
//! every pose is as it was before the call.

pub(crate) mod gauss_seidel;
mod island_constraints;
mod joint_state;
pub(crate) mod region;
mod removal;
mod report;
#[cfg(feature = "serde")]
pub mod report_json;
pub(crate) mod solve_island;
mod solver_warm;
mod velocity;

use std::time::Instant;

use nalgebra::{Isometry3, Vector3};

pub use report::{
    IslandLeft, IslandOutcome, IslandReport, JointReport, PairPenetration, PassReport, Report,
    StageTimes, Status,
};
pub use velocity::{BodyVelocity, VelocityFriction, VelocityReport};

use crate::Error;
use crate::broad_phase::{BodyPair, IncrementalBroadPhase};
use crate::contact::SceneParts;
use crate::contact::{
    Detection, DetectionState, QueryMemo, SceneGeometry, SeparationCertificates, WarmStartCache,
    detect,
};
use crate::joints::JointErrors;
use crate::parallel;
use crate::scene::Scene;
use crate::settings::{Method, ResolvedLengths, Settings};
use crate::solver::KeptAnalyses;
use crate::vclip::VClip;
use joint_state::{
    joint_errors, joint_merit, joint_reports, largest_joint_error, violated_islands,
};
use solve_island::{IslandSolution, PassInput, solve_island};
use solver_warm::{SolverWarmCache, WarmLayers};

/// Removes interpenetration from scenes; owns its settings and the V-Clip
/// warm starts of earlier queries (temporal coherence across calls).
#[derive(Debug, Clone, Default)]
pub struct Stabilizer {
    settings: Settings,
    /// Lengths a caller set for the next calls instead of the settings'
    /// resolution ([`Stabilizer::set_call_lengths`]).
    call_lengths: Option<ResolvedLengths>,
    cache: WarmStartCache,
    /// The last exact answer of each pair, to certify later that it is
    /// still separated beyond the margin (`contact::certificate`).
    certificates: SeparationCertificates,
    /// The solver's warm starts for the next call: the multipliers of the
    /// last call's first pass (`solver_warm`).
    solver_warm: SolverWarmCache,
    /// The sparse symbolic analyses of the solvers, kept while their
    /// pattern holds (`crate::solver::kept_analyses`).
    kept_analyses: KeptAnalyses,
    /// The last detection of the last call, with the poses it was made at
    /// (for [`Stabilizer::project_velocities`] at those poses).
    last_detection: Option<(Vec<Isometry3<f64>>, Detection)>,
}

impl Stabilizer {
    /// A stabilizer with validated settings.
    pub fn new(settings: Settings) -> Result<Self, Error> {
        settings.validate()?;
        Ok(Stabilizer {
            settings,
            call_lengths: None,
            cache: WarmStartCache::default(),
            certificates: SeparationCertificates::default(),
            solver_warm: SolverWarmCache::default(),
            kept_analyses: KeptAnalyses::default(),
            last_detection: None,
        })
    }

    /// A stabilizer with the default settings overridden by every field
    /// that `scene`'s settings set ([`Settings::with_scene_settings`]):
    /// what a scene file asks for, as the command-line tool applies it.
    /// Fails only if the combination is invalid.
    pub fn for_scene(scene: &Scene) -> Result<Self, Error> {
        Stabilizer::new(Settings::default().with_scene_settings(scene.settings()))
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The lengths of a call on `scene`: those set by
    /// `Stabilizer::set_call_lengths`, else the settings' resolved at the
    /// scene's scale ([`Settings::resolve`]).
    pub fn lengths(&self, scene: &Scene) -> ResolvedLengths {
        self.call_lengths
            .unwrap_or_else(|| self.settings.resolve(scene_scale(scene)))
    }

    /// Makes the next calls use `lengths` as they are, instead of resolving
    /// the settings' (`None` goes back to them): for a caller, like the
    /// Rapier bridge, that derives each call's lengths itself.
    #[cfg(feature = "rapier")]
    pub(crate) fn set_call_lengths(&mut self, lengths: Option<ResolvedLengths>) {
        self.call_lengths = lengths;
    }

    /// Number of body pairs with a cached V-Clip warm start.
    pub fn warm_starts(&self) -> usize {
        self.cache.len()
    }

    /// The V-Clip warm starts kept between calls, for the library's tests.
    #[doc(hidden)]
    pub fn warm_start_cache(&self) -> &WarmStartCache {
        &self.cache
    }

    /// Number of part pairs whose last exact answer is kept to certify
    /// them, or answer them again, in later calls (`contact::certificate`;
    /// freed when their shapes go, when bodies are removed through the
    /// stabilizer, and when unused for a call).
    pub fn separation_certificates(&self) -> usize {
        self.certificates.len()
    }

    /// Number of multipliers kept as the solver's warm starts of the next
    /// call ([`Report::solver_warm_multipliers`]).
    pub fn solver_warm_multipliers(&self) -> usize {
        self.solver_warm.multipliers()
    }

    /// The sparse symbolic analyses kept for the next solves: their number
    /// and the bytes they hold ([`Report::kept_analyses`]; at most
    /// [`crate::solver::kept_analyses::KEPT_ANALYSES_CAPACITY`], freed when
    /// bodies are removed through the stabilizer).
    pub fn kept_analyses(&self) -> (usize, usize) {
        (self.kept_analyses.len(), self.kept_analyses.bytes())
    }

    /// Replaces the settings (validated first; on error they are kept),
    /// keeping the warm starts: for a caller whose lengths follow the
    /// scene from call to call. The lengths of the next calls are the new
    /// settings' again.
    pub fn set_settings(&mut self, settings: Settings) -> Result<(), Error> {
        settings.validate()?;
        self.settings = settings;
        self.call_lengths = None;
        Ok(())
    }

    /// Moves the dynamic bodies of `scene` by the smallest mass-weighted
    /// correction that removes their interpenetration.
    ///
    /// An island that cannot be solved keeps its poses and the call goes
    /// on with the others (status [`Status::Unsolved`] or
    /// [`Status::Stalled`] when nothing more can move, the islands left in
    /// [`Report::islands_left`]); the scene is never returned worse than it
    /// came (see [`Report::restored_input`]). On error (invalid input) the
    /// poses are as they were.
    pub fn stabilize(&mut self, scene: &mut Scene) -> Result<Report, Error> {
        self.stabilize_observed(scene, &mut |_| {})
    }

    /// [`Stabilizer::stabilize`], calling `observer` after every pass with
    /// that pass's report (for a progress indicator on long calls).
    pub fn stabilize_observed(
        &mut self,
        scene: &mut Scene,
        observer: &mut dyn FnMut(&PassReport),
    ) -> Result<Report, Error> {
        let start = Instant::now();
        let before: Vec<([f64; 3], [f64; 4])> = scene
            .bodies()
            .iter()
            .map(|b| ((*b.translation_user()).into(), b.rotation_user_xyzw()))
            .collect();
        let com_before: Vec<Isometry3<f64>> =
            scene.bodies().iter().map(|b| *b.com_pose()).collect();
        let joints_before = joint_errors(scene)?;
        let result = self
            .run(scene, start, observer)
            .and_then(|report| Ok((report, joint_errors(scene)?)));
        if result.is_err() {
            restore(scene, &before);
        }
        let (mut report, mut joints_after) = result?;
        if worse_than_input(&report, &joints_before, &joints_after) {
            log::warn!(
                "stabilize: the result was worse than the input (depth {:.3e} -> {:.3e}); input poses restored",
                report.depth_before,
                report.depth_after
            );
            restore(scene, &before);
            report.restored_input = true;
            report.depth_after = report.depth_before;
            report.penetrations_after = report.penetrations_before.clone();
            joints_after = joints_before.clone();
        }
        report.joint_error_before = largest_joint_error(&joints_before, report.scale);
        report.joint_error_after = largest_joint_error(&joints_after, report.scale);
        report.joints = joint_reports(scene, &joints_before, &joints_after);
        let (displacement, moved) = scene_displacement(scene, &com_before);
        report.displacement = displacement;
        report.bodies_moved = moved;
        report.times.total = start.elapsed().as_secs_f64();
        log::info!(
            "stabilize: {} bodies, {} joints, {} ({} passes, {} islands solved, {} left), depth {:.3e} -> {:.3e}, joint error {:.3e} -> {:.3e} (tol {:.1e}), {} moved, {:.3} ms",
            scene.len(),
            scene.joints().len(),
            report.status.name(),
            report.passes,
            report.islands_solved(),
            report.islands_left.len(),
            report.depth_before,
            report.depth_after,
            report.joint_error_before,
            report.joint_error_after,
            report.tolerance,
            report.bodies_moved,
            report.times.total * 1e3
        );
        Ok(report)
    }

    /// The pairs of `scene` penetrating deeper than the tolerance at its
    /// current poses, with their exact depths (the scene is not changed).
    pub fn penetrations(&mut self, scene: &Scene) -> Result<Vec<PairPenetration>, Error> {
        self.detect_at(scene)?;
        Ok(self.current_detection().penetrations.clone())
    }

    /// Makes [`Stabilizer::current_detection`] the detection at the scene's
    /// current poses: the last call's if it was made at them (nothing is
    /// queried), else a new one; returns the call's lengths.
    fn detect_at(&mut self, scene: &Scene) -> Result<ResolvedLengths, Error> {
        let lengths = self.lengths(scene);
        let poses: Vec<Isometry3<f64>> = scene.bodies().iter().map(|b| *b.com_pose()).collect();
        if self
            .last_detection
            .as_ref()
            .is_some_and(|(at, _)| *at == poses)
        {
            return Ok(lengths);
        }
        let parts = SceneParts::of(scene);
        let part_poses = parts.poses(&poses);
        let geometry = SceneGeometry {
            parts: &parts,
            poses: &part_poses,
        };
        let certify = self.settings.vclip.motion_certificates;
        self.certificates.use_settings(&self.settings.vclip);
        let state = DetectionState {
            broad_phase: &mut IncrementalBroadPhase::new(),
            cache: &mut self.cache,
            memo: &mut QueryMemo::default(),
            certificates: certify.then_some(&mut self.certificates),
            kept_pairs: &[],
        };
        let detection = detect(
            scene,
            geometry,
            state,
            &VClip::new(self.settings.vclip),
            &lengths,
        )?;
        self.last_detection = Some((poses, detection));
        Ok(lengths)
    }

    /// The detection [`Stabilizer::detect_at`] made current.
    fn current_detection(&self) -> &Detection {
        // `detect_at` returns only after storing a detection, and every
        // caller calls it first: this cannot fail.
        &self
            .last_detection
            .as_ref()
            .expect("detect_at stores a detection")
            .1
    }

    fn run(
        &mut self,
        scene: &mut Scene,
        start: Instant,
        observer: &mut dyn FnMut(&PassReport),
    ) -> Result<Report, Error> {
        if self.settings.method == Method::GaussSeidel {
            self.cache.forget_dropped_shapes();
            let lengths = self.lengths(scene);
            let (report, last) = gauss_seidel::call::run(
                scene,
                &self.settings,
                &lengths,
                &mut self.cache,
                start,
                observer,
            )?;
            self.last_detection = Some(last);
            return Ok(report);
        }
        let lengths = self.lengths(scene);
        let vclip = VClip::new(self.settings.vclip);
        // The call's own settings: every solver stops at the budget's end.
        let mut call_settings = self.settings.clone();
        call_settings.solver.deadline = self.deadline(start);
        let parts = SceneParts::of(scene);
        let mut report = Report::new(&lengths);
        self.cache.forget_dropped_shapes();
        self.certificates.begin_call(&self.settings.vclip);
        let certify = self.settings.vclip.motion_certificates;
        self.solver_warm.forget_dropped_shapes();
        // The first pass starts from the last call's first pass, each
        // later one from the passes before it: the entries of the passes
        // after the first lie over the kept cache (`WarmLayers`).
        let mut later_passes_warm = SolverWarmCache::default();
        let mut memo = QueryMemo::default();
        let mut broad_phase = IncrementalBroadPhase::new();
        // Bodies of the islands whose friction could not be honoured in an
        // earlier pass of this call (`solve_island`'s "Friction").
        let mut without_friction = vec![false; scene.bodies().len()];
        // Part pairs that penetrated in an earlier pass, ascending
        // (`Settings::keep_penetrated_pairs`).
        let mut kept_pairs: Vec<BodyPair> = Vec::new();
        let mut first_deepest = 0.0;
        loop {
            let poses: Vec<Isometry3<f64>> = scene.bodies().iter().map(|b| *b.com_pose()).collect();
            let part_poses = parts.poses(&poses);
            let geometry = SceneGeometry {
                parts: &parts,
                poses: &part_poses,
            };
            log::debug!("pass {}: detection", report.passes + 1);
            let state = DetectionState {
                broad_phase: &mut broad_phase,
                cache: &mut self.cache,
                memo: &mut memo,
                certificates: certify.then_some(&mut self.certificates),
                kept_pairs: &kept_pairs,
            };
            let detection = detect(scene, geometry, state, &vclip, &lengths)?;
            report.record_detection(&detection);
            if self.settings.keep_penetrated_pairs {
                keep_penetrating(&detection, lengths.tolerance, &mut kept_pairs);
            }
            let joints = joint_errors(scene)?;
            let mut pass = pass_report(&detection, lengths.tolerance);
            pass.joint_error = largest_joint_error(&joints, lengths.scale);
            let finished = Status::after_detection(
                detection.deepest.max(pass.joint_error),
                lengths.tolerance,
                report.passes,
                self.settings.max_passes,
                || self.time_left(start) == Some(0.0),
            );
            if let Some(status) = finished {
                log::debug!(
                    "stop: deepest penetration {:.3e}, largest joint error {:.3e}, tolerance {:.1e}: {}",
                    detection.deepest,
                    pass.joint_error,
                    lengths.tolerance,
                    status.name()
                );
                report.pass_reports.push(pass);
                report.status = status;
                report.solver_warm_multipliers = self.solver_warm.multipliers();
                report.kept_analyses = self.kept_analyses();
                self.last_detection = Some((poses, detection));
                return Ok(report);
            }
            // Later passes correct the linearization's error: answered to
            // the first pass's precision (`SolverSettings::precision_length`).
            match report.passes {
                0 => first_deepest = detection.deepest.max(pass.joint_error),
                _ => call_settings.solver.precision_length = Some(first_deepest),
            }
            let mut solutions = self.solve_pass(
                scene,
                geometry,
                &detection,
                &joints,
                &call_settings,
                &lengths,
                &without_friction,
                &mut pass,
                WarmLayers {
                    newer: &later_passes_warm,
                    older: &self.solver_warm,
                },
            )?;
            report.passes += 1;
            for solution in &mut solutions {
                let warm = std::mem::take(&mut solution.solver_warm);
                match report.passes {
                    1 => self.solver_warm.merge(warm),
                    _ => later_passes_warm.merge(warm),
                }
            }
            report.solver_warm_multipliers = self.solver_warm.multipliers();
            let stuck = self.apply(scene, &parts, solutions, &mut memo, &mut report, &mut pass)?;
            for island in pass.solved.iter().filter(|i| i.friction_dropped) {
                island
                    .bodies
                    .iter()
                    .for_each(|&body| without_friction[body] = true);
            }
            log_pass(report.passes, &pass, &report.islands_left, start);
            observer(&pass);
            report.pass_reports.push(pass);
            if let Some(status) = stuck {
                // Islands that failed because the budget ran out inside the
                // pass: the budget ended the call.
                let spent = self.time_left(start) == Some(0.0);
                report.status = if spent { Status::TimeLimit } else { status };
                return Ok(report);
            }
        }
    }

    /// The instant the time budget ends, or the solver settings' own
    /// deadline when that is earlier; `None` without either (or when the
    /// budget is too long to represent).
    fn deadline(&self, start: Instant) -> Option<Instant> {
        let budget_end = self
            .settings
            .time_budget
            .and_then(|budget| start.checked_add(budget));
        match (budget_end, self.settings.solver.deadline) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Seconds left of the time budget (0 when spent); `None` without one.
    fn time_left(&self, start: Instant) -> Option<f64> {
        let budget = self.settings.time_budget?;
        Some(budget.saturating_sub(start.elapsed()).as_secs_f64())
    }

    /// Applies the islands' corrections in island order (a stalled or
    /// failed island moves nothing) and records them; returns the status
    /// that ends the call when no island moved.
    fn apply(
        &mut self,
        scene: &mut Scene,
        parts: &SceneParts,
        solutions: Vec<IslandSolution>,
        memo: &mut QueryMemo,
        report: &mut Report,
        pass: &mut PassReport,
    ) -> Result<Option<Status>, Error> {
        report.islands_left = solutions
            .iter()
            .filter(|s| {
                matches!(
                    s.report.outcome,
                    IslandOutcome::Stalled | IslandOutcome::Failed(_)
                )
            })
            .map(|s| IslandLeft {
                bodies: s.report.bodies.clone(),
                outcome: s.report.outcome.clone(),
            })
            .collect();
        let any_moved = solutions.iter().any(|s| s.report.outcome.moved());
        let any_failed = report
            .islands_left
            .iter()
            .any(|left| matches!(left.outcome, IslandOutcome::Failed(_)));
        for mut solution in solutions {
            report.times.solve += solution.solve_seconds;
            report.times.line_search += solution.line_search_seconds;
            report.times.narrow_phase += solution.query_seconds;
            report.pair_queries += solution.queries;
            solution.apply(scene, parts.shapes(), &mut self.cache)?;
            for (pair, answer) in std::mem::take(&mut solution.answers) {
                if self.settings.vclip.motion_certificates {
                    self.certificates
                        .record(pair, parts, answer.poses, &answer.query);
                }
                memo.insert(pair, answer);
            }
            pass.solved.push(solution.report);
        }
        Ok(match (any_moved, any_failed) {
            (true, _) => None,
            (false, true) => Some(Status::Unsolved),
            (false, false) => Some(Status::Stalled),
        })
    }

    /// Forms islands from the detection and solves those that penetrate.
    // The pass's inputs are distinct borrows of the call's state; a struct
    // of them would only rename them.
    #[allow(clippy::too_many_arguments)]
    fn solve_pass(
        &self,
        scene: &Scene,
        geometry: SceneGeometry,
        detection: &Detection,
        joints: &[JointErrors],
        settings: &Settings,
        lengths: &ResolvedLengths,
        without_friction: &[bool],
        pass: &mut PassReport,
        solver_warm: WarmLayers,
    ) -> Result<Vec<IslandSolution>, Error> {
        let (penetrating, count) = violated_islands(scene, detection, joints, lengths)?;
        pass.islands = count;
        let input = PassInput {
            scene,
            geometry,
            active_pairs: &detection.active_pairs,
            active_bodies: &detection.active_bodies,
            active_values: &detection.active_values,
            active_queries: &detection.active_queries,
            settings,
            lengths,
            hold_rows: false,
            frictional: true,
            without_friction,
            solver_warm,
            kept_analyses: &self.kept_analyses,
        };
        Ok(parallel::map(&penetrating, |island| {
            solve_island(input, island)
        }))
    }
}

/// Adds the detection's pairs penetrating deeper than `tolerance` to
/// `kept` (ascending, without repeats).
fn keep_penetrating(detection: &Detection, tolerance: f64, kept: &mut Vec<BodyPair>) {
    let before = kept.len();
    kept.extend(
        detection
            .active_pairs
            .iter()
            .zip(&detection.active_values)
            .filter(|(_, value)| -**value > tolerance)
            .map(|(pair, _)| *pair),
    );
    if kept.len() > before {
        kept.sort_unstable();
        kept.dedup();
    }
}

/// Whether the call's last detection is worse than its first: an exact
/// penetration deeper than both the input's deepest and the tolerance, a
/// joint error that rose beyond the tolerance, or a larger merit
/// (penetrations' and joints' beyond the tolerance together). A contact
/// within the tolerance may deepen within it: removing a joint's error may
/// press a resting part a little into the ground.
fn worse_than_input(
    report: &Report,
    joints_before: &[JointErrors],
    joints_after: &[JointErrors],
) -> bool {
    let tolerance = report.tolerance;
    let merit = |penetrations: &[PairPenetration], joints: &[JointErrors]| {
        Report::merit(penetrations, tolerance) + joint_merit(joints, report.scale, tolerance)
    };
    let joint_before = largest_joint_error(joints_before, report.scale);
    let joint_after = largest_joint_error(joints_after, report.scale);
    report.depth_after > report.depth_before.max(tolerance)
        || joint_after > joint_before.max(tolerance)
        || merit(&report.penetrations_after, joints_after)
            > merit(&report.penetrations_before, joints_before)
}

/// The debug line of a pass.
fn log_pass(number: usize, pass: &PassReport, left: &[IslandLeft], start: Instant) {
    log::debug!(
        "pass {number} done: {} candidates ({} queried, {} certified, {} reused), {} active, {} penetrating, {} islands, \
         {} solved ({} left), deepest {:.3e}, joint error {:.3e}, {:.3} ms so far",
        pass.candidate_pairs,
        pass.queried_pairs,
        pass.certified_pairs,
        pass.reused_pairs,
        pass.active_pairs,
        pass.penetrating_pairs,
        pass.islands,
        pass.solved.len(),
        left.len(),
        pass.deepest,
        pass.joint_error,
        start.elapsed().as_secs_f64() * 1e3
    );
}

/// The report of a pass from its detection (no island solved yet).
pub(crate) fn pass_report(detection: &Detection, tolerance: f64) -> PassReport {
    PassReport {
        candidate_pairs: detection.candidates,
        queried_pairs: detection.queried,
        certified_pairs: detection.certified,
        reused_pairs: detection.reused,
        penetrating_pairs: detection.penetrating(tolerance),
        active_pairs: detection.active_pairs.len(),
        islands: 0,
        deepest: detection.deepest,
        joint_error: 0.0,
        solved: Vec::new(),
    }
}

/// The scene's length scale: the circumradius of its smallest dynamic body
/// (of its smallest body if all are fixed; 1 for an empty scene), a
/// compound's being its smallest part's ([`crate::body::Body::scale`]).
pub fn scene_scale(scene: &Scene) -> f64 {
    let smallest = |dynamic_only: bool| {
        scene
            .bodies()
            .iter()
            .filter(|b| !dynamic_only || !b.is_fixed())
            .map(|b| b.scale())
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

/// Mass-weighted displacement `sqrt(sum m |dx|^2 + dtheta^T I dtheta)` (world
/// inertia before) between `com_before` and the scene's poses,
/// and the number of bodies whose pose changed.
pub fn scene_displacement(scene: &Scene, com_before: &[Isometry3<f64>]) -> (f64, usize) {
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
