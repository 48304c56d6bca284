//! Velocity consistency: after the poses are corrected, the velocities that
//! would drive the bodies back into their contacts are removed by the same
//! mass-weighted projection, at the velocity level.
//!
//! Positions alone leave an engine's body with the velocity it had: a heavy
//! box lifted out of the boxes it crushed keeps falling into them, and
//! needs a larger lift every step. For the contacts of the corrected
//! islands (pairs touching or penetrating at the corrected poses), with
//! `J` the same contact rows as the position projection and `v` the bodies'
//! velocities (`[v_com; omega]`, world frame),
//!
//! ```text
//! minimize 1/2 (v' - v)^T M (v' - v)   subject to   J_k v' >= 0
//! ```
//!
//! the smallest change in the kinetic-energy metric that removes every
//! approach velocity. Given the engine's time step `h`, the contacts within
//! the contact margin count too, as speculative contacts: a pair with gap
//! `phi >= 0` may close at most that gap in one step, `J_k v' >= -phi / h`
//! (so a body falling onto another is slowed to land, not stopped in the
//! air); without it only touching contacts (`phi` within the tolerance and
//! target margin) count, with `J_k v' >= 0`; with friction, the pyramid of
//! [`crate::projector::friction`] on every such row, with `dv` for `dq` and
//! its apex where the row becomes tight (`-(J_k v + phi / h)`, the
//! approach speed beyond what the gap allows): removing an approach adds
//! no sliding, and a contact that keeps separating (or keeps part of its
//! gap) may slide `1 / mu` of that margin, as in Anitescu and Tasora's
//! cone complementarity. It is the
//! position problem with `phi_k = J_k v`, target 0, so it is solved by the
//! same solvers ([`crate::solver::solve_projection`]). Fixed bodies
//! (kinematic ones included) are taken at rest. Velocities of bodies in
//! islands that are not asked for, or that need no change, are left bit
//! for bit.

use nalgebra::{DVector, Vector3, Vector6};

use super::Stabilizer;
use crate::Error;
use crate::broad_phase::BodyPair;
use crate::contact::{BodyGeometry, ContactFriction, Detection, contact_rows};
use crate::island::islands;
use crate::projector::{ConstraintRow, projection_qp};
use crate::scene::Scene;
use crate::solver::solve_projection;

/// A body's velocity: of its centre of mass, and its angular velocity,
/// both in the world frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyVelocity {
    /// Velocity of the centre of mass (length per time).
    pub linear: Vector3<f64>,
    /// Angular velocity (radians per time).
    pub angular: Vector3<f64>,
}

/// Options of [`Stabilizer::project_velocities`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VelocityOptions {
    /// The engine's time step `h`: contacts within the contact margin count
    /// as speculative contacts, `J_k v' >= -phi / h` (module docs). `None`:
    /// touching contacts only.
    pub time_step: Option<f64>,
    /// Apply the friction pyramid to the velocity change (the settings'
    /// friction coefficients). Default false: measured in
    /// `examples/with_and_without.rs`, the frictionless velocity projection
    /// keeps the heavy stacks standing and the friction-aware one does not
    /// (the pyramid lets a contact whose normal velocity is raised beyond
    /// its approach slide by `mu` times the excess, and a tilted stack then
    /// creeps; README).
    pub friction: bool,
}

/// What [`Stabilizer::project_velocities`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VelocityReport {
    /// Contact rows of the islands asked for.
    pub contacts: usize,
    /// Islands whose velocities were projected (some contact approaching).
    pub islands_solved: usize,
    /// Islands whose projection failed (their velocities left as they were).
    pub islands_failed: usize,
    /// Largest approach speed `max(0, -J_k v)` over those contacts, before.
    pub approach_before: f64,
    /// The same after.
    pub approach_after: f64,
}

impl Stabilizer {
    /// Removes the approach velocities at the contacts of the islands of
    /// `bodies` (scene indices, typically the bodies the last call moved)
    /// at the scene's current poses (module docs), as `options` say.
    /// `velocities` has one entry per scene body; fixed bodies' entries are
    /// ignored. An island whose projection fails keeps its velocities
    /// (counted in the report).
    pub fn project_velocities(
        &mut self,
        scene: &Scene,
        velocities: &mut [BodyVelocity],
        bodies: &[usize],
        options: &VelocityOptions,
    ) -> Result<VelocityReport, Error> {
        let time_step = options.time_step;
        if velocities.len() != scene.len() {
            return Err(Error::VelocityCount {
                velocities: velocities.len(),
                bodies: scene.len(),
            });
        }
        if let Some((index, _)) = velocities.iter().enumerate().find(|(_, v)| {
            !(v.linear
                .iter()
                .chain(v.angular.iter())
                .all(|x| x.is_finite()))
        }) {
            return Err(Error::NonFiniteVelocity { body: index });
        }
        if let Some(h) = time_step.filter(|h| !(h.is_finite() && *h > 0.0)) {
            return Err(Error::InvalidTimeStep(h));
        }
        let lengths = self.detect_at(scene)?;
        let detection = self.current_detection();
        let contact_gap = match time_step {
            Some(_) => lengths.contact_margin,
            None => lengths.tolerance + lengths.target_margin,
        };
        let gap_rate = time_step.map_or(0.0, |h| 1.0 / h);
        let mut report = VelocityReport::default();
        let fixed = scene.fixed_flags();
        let touching: Vec<usize> = (0..detection.active_pairs.len())
            .filter(|&k| detection.active_values[k] <= contact_gap)
            .collect();
        let pairs: Vec<BodyPair> = touching
            .iter()
            .map(|&k| detection.active_pairs[k])
            .collect();
        for island in islands(&fixed, &pairs)? {
            if !island.bodies.iter().any(|b| bodies.contains(b)) {
                continue;
            }
            let island_pairs: Vec<usize> = island.pairs.iter().map(|&i| touching[i]).collect();
            let contacts = IslandContacts {
                bodies: &island.bodies,
                pairs: &island_pairs,
                detection,
                contact_gap,
                gap_rate,
                friction: options.friction,
            };
            self.project_island(scene, velocities, &contacts, &mut report);
        }
        Ok(report)
    }

    /// One island's velocity projection.
    fn project_island(
        &self,
        scene: &Scene,
        velocities: &mut [BodyVelocity],
        contacts: &IslandContacts,
        report: &mut VelocityReport,
    ) {
        let settings = &self.settings;
        let bodies = contacts.bodies;
        let geometry = |body: usize| {
            let b = &scene.bodies()[body];
            BodyGeometry {
                shape: b.polyhedron(),
                pose: *b.com_pose(),
                configuration_index: bodies.binary_search(&body).ok(),
            }
        };
        let mut rows: Vec<ConstraintRow> = Vec::new();
        let mut gaps: Vec<f64> = Vec::new();
        for &k in contacts.pairs {
            let pair = contacts.detection.active_pairs[k];
            let (a, b) = (geometry(pair.body_a), geometry(pair.body_b));
            let friction = match contacts.friction {
                true => ContactFriction {
                    mu: super::solve_island::pair_friction(scene, settings, pair),
                },
                false => ContactFriction::NONE,
            };
            let query = &contacts.detection.active_queries[k];
            let gap = contacts.contact_gap;
            let pair_rows = contact_rows(query, &a, &b, gap, settings.contact_manifold, friction);
            for row in pair_rows.into_iter().filter(|row| row.phi <= gap) {
                gaps.push(row.phi.max(0.0) * contacts.gap_rate);
                rows.push(row);
            }
        }
        let v = island_velocity(velocities, bodies);
        let rate = |rows: &mut [ConstraintRow], v: &DVector<f64>| {
            for (row, gap) in rows.iter_mut().zip(&gaps) {
                let approach: f64 = row
                    .blocks
                    .iter()
                    .map(|(i, block)| block.dot(&v.fixed_rows::<6>(6 * i)))
                    .sum();
                row.phi = approach + gap;
            }
        };
        rate(&mut rows, &v);
        report.contacts += rows.len();
        let approach = |rows: &[ConstraintRow]| rows.iter().fold(0.0, |m: f64, r| m.max(-r.phi));
        let before = approach(&rows);
        report.approach_before = report.approach_before.max(before);
        if before <= 0.0 {
            return;
        }
        // Islands hold dynamic bodies only, so their states exist; an
        // inconsistency is reported as a failed island, velocities kept.
        let Ok((configuration, inertias)) = super::solve_island::island_state(scene, bodies) else {
            report.islands_failed += 1;
            report.approach_after = report.approach_after.max(before);
            return;
        };
        let (qp, _) = projection_qp(
            &configuration,
            &inertias,
            &rows,
            0.0,
            settings.friction_directions,
        );
        match solve_projection(&qp, &settings.solver) {
            Ok(solution) => {
                report.islands_solved += 1;
                let v_new = &v + &solution.dq;
                rate(&mut rows, &v_new);
                report.approach_after = report.approach_after.max(approach(&rows));
                for (i, &body) in bodies.iter().enumerate() {
                    let block: Vector6<f64> = v_new.fixed_rows::<6>(6 * i).into_owned();
                    velocities[body] = BodyVelocity {
                        linear: block.fixed_rows::<3>(0).into_owned(),
                        angular: block.fixed_rows::<3>(3).into_owned(),
                    };
                }
            }
            Err(error) => {
                log::debug!(
                    "velocity projection of the island of body {} failed: {error}",
                    bodies[0]
                );
                report.islands_failed += 1;
                report.approach_after = report.approach_after.max(before);
            }
        }
    }
}

/// The contacts of one island's velocity projection.
struct IslandContacts<'a> {
    /// Dynamic bodies, ascending.
    bodies: &'a [usize],
    /// Indices of the island's pairs into the detection's active pairs.
    pairs: &'a [usize],
    detection: &'a Detection,
    /// Rows of points further apart than this are left out.
    contact_gap: f64,
    /// `1 / h`, or 0 without speculative contacts.
    gap_rate: f64,
    /// Whether the rows get friction.
    friction: bool,
}

/// The stacked `[v; omega]` of an island's bodies.
fn island_velocity(velocities: &[BodyVelocity], bodies: &[usize]) -> DVector<f64> {
    let mut v = DVector::zeros(6 * bodies.len());
    for (i, &body) in bodies.iter().enumerate() {
        v.fixed_rows_mut::<3>(6 * i)
            .copy_from(&velocities[body].linear);
        v.fixed_rows_mut::<3>(6 * i + 3)
            .copy_from(&velocities[body].angular);
    }
    v
}
