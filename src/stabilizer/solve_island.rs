//! One projection step for one island, computed without touching the
//! scene; the caller applies the results in island order.
//!
//! An island that cannot be solved (every solver failed, or its problem is
//! invalid) is not an error of the call: its solution moves nothing and
//! says why ([`IslandOutcome::Failed`]), so that the other islands and the
//! passes already made keep their progress.

use crate::Error;
use crate::broad_phase::BodyPair;
use crate::contact::WarmStartCache;
use crate::island::{Island, IslandError};
use crate::projector::{BodyInertia, BodyState, ProjectionSettings, StepOutcome, projection_step};
use crate::scene::Scene;
use crate::vclip::VClip;

use super::island_provider::{IslandProvider, SceneGeometry};
use super::report::{IslandOutcome, IslandReport};
use super::settings::{ResolvedLengths, Settings};

/// The outcome of one island's step, to apply to the scene.
pub struct IslandSolution {
    /// What happened, for the report.
    pub report: IslandReport,
    /// New centre-of-mass states of the island's bodies (empty unless moved).
    pub states: Vec<(usize, BodyState)>,
    /// V-Clip warm starts of the island's pairs after the step.
    pub warm_starts: WarmStartCache,
    /// Linearization and solver time, seconds.
    pub solve_seconds: f64,
    /// Line-search time, seconds.
    pub line_search_seconds: f64,
}

impl IslandSolution {
    /// Moves the island's bodies and records the warm starts.
    pub fn apply(&self, scene: &mut Scene, cache: &mut WarmStartCache) -> Result<(), Error> {
        for (body, state) in &self.states {
            scene.body_mut(*body)?.set_com_pose(state.isometry())?;
        }
        cache.merge(self.warm_starts.clone());
        Ok(())
    }
}

/// The shared input of every island's step in one pass.
#[derive(Clone, Copy)]
pub struct PassInput<'a> {
    /// The scene at the pass's poses.
    pub scene: &'a Scene,
    /// Shapes and poses of every body.
    pub geometry: SceneGeometry<'a>,
    /// The pass's active pairs (islands index them).
    pub active_pairs: &'a [BodyPair],
    /// Signed value (distance, or minus the exact depth) of each active pair.
    pub active_values: &'a [f64],
    /// V-Clip warm starts.
    pub cache: &'a WarmStartCache,
    /// The stabilizer's settings.
    pub settings: &'a Settings,
    /// Resolved lengths.
    pub lengths: &'a ResolvedLengths,
    /// The projection's settings.
    pub projection: &'a ProjectionSettings,
}

/// One projection step on `island`; a failure moves nothing and is
/// reported in the solution.
pub fn solve_island(input: PassInput, island: &Island) -> IslandSolution {
    solve_island_or_fail(input, island).unwrap_or_else(|error| {
        log::debug!(
            "island of {} bodies (first {}) not solved: {error}",
            island.bodies.len(),
            island.bodies[0]
        );
        let depth = island
            .pairs
            .iter()
            .map(|&k| -input.active_values[k])
            .fold(0.0, f64::max);
        IslandSolution::failed(island, depth, error)
    })
}

impl IslandSolution {
    /// The solution of an island that could not be solved: nothing moves.
    fn failed(island: &Island, depth: f64, error: Error) -> Self {
        IslandSolution {
            report: IslandReport {
                bodies: island.bodies.clone(),
                pairs: island.pairs.len(),
                constraints: 0,
                solver: None,
                fallbacks: Vec::new(),
                cross_check: None,
                outcome: IslandOutcome::Failed(error),
                trust_scale: 1.0,
                alpha: None,
                line_search_trials: 0,
                depth_before: depth,
                depth_after: depth,
                displacement: 0.0,
            },
            states: Vec::new(),
            warm_starts: WarmStartCache::default(),
            solve_seconds: 0.0,
            line_search_seconds: 0.0,
        }
    }
}

/// One projection step on `island`, whose pairs index the pass's active
/// pairs.
fn solve_island_or_fail(input: PassInput, island: &Island) -> Result<IslandSolution, Error> {
    let PassInput {
        scene,
        geometry,
        active_pairs,
        active_values: _,
        cache,
        settings,
        lengths,
        projection,
    } = input;
    let pairs: Vec<BodyPair> = island.pairs.iter().map(|&k| active_pairs[k]).collect();
    let pair_count = pairs.len();
    let mut provider = IslandProvider::new(
        geometry,
        &island.bodies,
        pairs,
        cache,
        VClip::new(settings.vclip),
        lengths.contact_margin,
        settings.contact_manifold,
    );
    let (mut configuration, inertias) = island_state(scene, &island.bodies)?;
    let step = projection_step(&mut provider, &mut configuration, &inertias, projection)?;
    let mut warm_starts = WarmStartCache::default();
    provider.record_warm_starts(&mut warm_starts);
    let states = if step.outcome == StepOutcome::Moved {
        island.bodies.iter().copied().zip(configuration).collect()
    } else {
        Vec::new()
    };
    let solution = step.solution.as_ref();
    log::debug!(
        "island of {} bodies (first {}): {} pairs, {} rows, {:?}, alpha {:?}, depth {:.3e} -> {:.3e}",
        island.bodies.len(),
        island.bodies[0],
        pair_count,
        step.constraints,
        solution.map(|s| s.solver),
        step.alpha,
        step.depth_before,
        step.depth_after
    );
    Ok(IslandSolution {
        report: IslandReport {
            bodies: island.bodies.clone(),
            pairs: pair_count,
            constraints: step.constraints,
            solver: solution.map(|s| s.solver),
            fallbacks: solution.map(|s| s.fallbacks.clone()).unwrap_or_default(),
            cross_check: solution.and_then(|s| s.cross_check.clone()),
            outcome: step.outcome.into(),
            trust_scale: step.trust_scale,
            alpha: step.alpha,
            line_search_trials: step.line_search_trials,
            depth_before: step.depth_before,
            depth_after: step.depth_after,
            displacement: step.displacement,
        },
        states,
        warm_starts,
        solve_seconds: step.solve_seconds,
        line_search_seconds: step.line_search_seconds,
    })
}

/// States and inertias of the island's dynamic bodies.
fn island_state(
    scene: &Scene,
    bodies: &[usize],
) -> Result<(Vec<BodyState>, Vec<BodyInertia>), Error> {
    let mut states = Vec::with_capacity(bodies.len());
    let mut inertias = Vec::with_capacity(bodies.len());
    for &index in bodies {
        let body = scene.body(index)?;
        let pose = body.com_pose();
        states.push(BodyState {
            position: pose.translation.vector.into(),
            rotation: pose.rotation,
        });
        let Some(mass) = body.mass() else {
            return Err(IslandError::MasslessBody { body: index }.into());
        };
        inertias.push(BodyInertia {
            mass: mass.mass,
            inertia_body: mass.inertia_body,
        });
    }
    Ok((states, inertias))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::{BodyDesc, MassSpec, Shape};
    use nalgebra::Vector3;

    /// `IslandError::MasslessBody` cannot be reached through
    /// `Stabilizer::stabilize` (islands are formed from dynamic bodies
    /// only); this pins the typed error of the internal check itself: an
    /// island listing a fixed body is refused, naming that body, rather
    /// than its states and inertias falling out of step.
    #[test]
    fn an_island_listing_a_fixed_body_is_a_massless_body_error() {
        let mut scene = Scene::new();
        for (name, mass) in [("dynamic", MassSpec::Mass(1.0)), ("fixed", MassSpec::Fixed)] {
            let desc = BodyDesc {
                name: name.into(),
                shape: Shape::Cuboid {
                    half_extents: Vector3::new(0.5, 0.5, 0.5),
                },
                translation: Vector3::zeros(),
                rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
                mass,
            };
            scene.add_body(desc).expect("valid body");
        }
        let result = island_state(&scene, &[0, 1]);
        assert!(
            matches!(
                result,
                Err(Error::Island(IslandError::MasslessBody { body: 1 }))
            ),
            "{:?}",
            result.map(|(states, _)| states.len())
        );
        let (states, inertias) = island_state(&scene, &[0]).expect("dynamic body");
        assert_eq!((states.len(), inertias.len()), (1, 1));
        assert_eq!(inertias[0].mass, 1.0);
    }
}
