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
//! target margin) count, with `J_k v' >= 0`. It is the position problem
//! with `phi_k = J_k v`, target 0, so it is solved by the same solvers
//! ([`crate::solver::solve_projection`]). Fixed bodies (kinematic ones
//! included) are taken at rest. Velocities of bodies in islands that are
//! not asked for, or that need no change, are left bit for bit. Islands
//! share no dynamic body, so each is projected on its own (on rayon's
//! threads with the `parallel` feature, as the position passes) and the
//! answers are merged in island order: the same bits on any number of
//! threads.
//!
//! **Friction** ([`VelocityFriction`], the pair's `mu` as in the position
//! projection), two formulations:
//!
//! - *On the change* ([`VelocityFriction::OnChange`]): the pyramid of
//!   [`crate::projector::friction`] on every row, with `dv = v' - v` for
//!   `dq` and its apex where the row becomes tight (`-(J_k v + phi / h)`,
//!   the approach speed beyond what the gap allows):
//!   `mu |J_t dv| <= J_n dv + J_n v + phi / h`. Removing an approach adds
//!   no sliding, but the sliding velocity `v` already had is kept, and a
//!   contact whose normal velocity the projection raises beyond its
//!   approach may slide `1 / mu` of the excess.
//! - *On the velocity* ([`VelocityFriction::OnVelocity`]): the kinematic
//!   cone of Anitescu and Tasora's cone complementarity problem ("An
//!   iterative approach for cone complementarity problems for nonsmooth
//!   dynamics", Comput. Optim. Appl. 47, 2010) on the relative velocity
//!   after the projection, for every contact with friction:
//!
//!   ```text
//!   mu |J_t v'| <= J_n v' + phi / h                                (1)
//!   ```
//!
//!   (`J_t` the Jacobian of the relative tangential velocity along the two
//!   tangents, `phi / h` as above, 0 without a time step). It is linearized
//!   as a friction pyramid of `K` directions `d_k`
//!   ([`crate::Settings::friction_directions`]), whatever
//!   [`crate::Settings::friction_model`] the position projection uses (the
//!   cone on the velocity is not implemented):
//!
//!   ```text
//!   (J_n - mu d_k J_t) v' >= -phi / h,      k = 0..K-1               (2)
//!   ```
//!
//!   rows of the same form as the contact rows, so they are solved as such
//!   (`phi_k = (J_n - mu d_k J_t) v + phi / h`, target 0). *Convex*: (1) is
//!   a second-order cone in `v'` and (2) its polyhedral outer
//!   approximation, half-spaces in `v'`; the objective is a positive
//!   definite quadratic, so the problem is a strictly convex QP with a
//!   unique answer and an LCP for Lemke, as the frictionless one. It is
//!   *always feasible*: `v' = 0` satisfies every row, since fixed bodies
//!   are at rest and `phi / h >= 0` (gaps are clamped at 0). *Why*: the
//!   multipliers of (2) are contact impulses `beta_k (n - mu d_k)`, inside
//!   Coulomb's pyramid, and a resting contact (`phi = 0`) that the
//!   projection leaves closed (`J_n v' = 0`) has no relative tangential
//!   velocity at all: it sticks. A
//!   heavy body's large normal impulse through slightly tilted normals
//!   (as after an engine step) cannot push the light bodies below
//!   it sideways, which the frictionless projection does
//!   (`docs/coupling.md`).
//!   Averaging (2) over symmetric directions gives the contact row, so the
//!   contact row is implied; it is kept all the same (its approach is the
//!   one reported). *Artefact*, as in Anitescu and Tasora's scheme: a
//!   contact can satisfy (1) while sliding only by separating, so a
//!   sliding contact (`|J_t v'| > 0`) leaves with a separating normal
//!   velocity of `mu |J_t v'| - phi / h` (within the pyramid's excess over
//!   the cone), and the projection takes that (part lift, part braking)
//!   where it is cheaper than stopping the slide: a body sliding at `v_t`
//!   along a facet's direction `d_k` and approaching at `v_n < v_t / mu`,
//!   at one contact without lever, leaves with
//!   `v_t' = (v_t - mu v_n) / (1 + mu^2)` and a lift of `mu v_t'` (the
//!   projection on that facet's half-space); with `v_n >= v_t / mu` it
//!   stops. The engine's gravity then brings it back: a hop of about
//!   `mu v_t' h` per step.
//!
//! An island is projected when one of its contacts approaches (beyond what
//! its gap allows), with or without friction; a contact outside its cone
//! alone does not start a projection (it is reported, `cone_before`):
//! projecting on it too triples the creep of a settled pile (measured with
//! `examples/with_and_without.rs`: `benchmarks/results/coupling.md`,
//! "Velocity friction, the bridge's choice").

use nalgebra::{DVector, Vector3, Vector6};

use super::Stabilizer;
use crate::Error;
use crate::broad_phase::BodyPair;
use crate::contact::SceneParts;
use crate::contact::{BodyGeometry, ContactFriction, Detection, SceneGeometry, contact_rows};
use crate::contact::{Island, islands_with_joints};
use crate::projector::friction::pyramid_rows;
use crate::projector::projection_qp;
use crate::rows::{ConstraintRow, RowKind};
use crate::scene::Scene;
use crate::settings::FrictionModel;
use crate::solver::solve_projection_kept;

/// A body's velocity: of its centre of mass, and its angular velocity,
/// both in the world frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyVelocity {
    /// Velocity of the centre of mass (length per time).
    pub linear: Vector3<f64>,
    /// Angular velocity (radians per time).
    pub angular: Vector3<f64>,
}

/// Where the velocity projection applies Coulomb friction (module docs),
/// with the pairs' coefficients (`Body::set_friction`, else
/// [`crate::Settings::friction`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VelocityFriction {
    /// No friction: the contact rows only.
    #[default]
    None,
    /// The friction pyramid on the velocity change `v' - v`, apex where a
    /// row becomes tight: removing an approach adds no sliding, the
    /// sliding `v` had is kept.
    OnChange,
    /// The kinematic cone on the velocity after the projection,
    /// `mu |J_t v'| <= J_n v' + phi / h` (Anitescu and Tasora), as a
    /// pyramid: resting contacts stick; a sliding one separates by about
    /// `mu |J_t v'|`.
    OnVelocity,
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
    /// With [`VelocityFriction::OnVelocity`], the largest violation of a
    /// pyramid facet (2), `max(0, -((J_n - mu d_k J_t) v + phi / h))`,
    /// over the same contacts, before (speed; 0 otherwise).
    pub cone_before: f64,
    /// The same after.
    pub cone_after: f64,
    /// Largest relative speed along a joint's locked axis, or into a
    /// joint's limit beyond what its margin allows (speed; angular rates
    /// times the scene's scale), over the joints of the islands asked for,
    /// before.
    pub joint_rate_before: f64,
    /// The same after.
    pub joint_rate_after: f64,
}

impl Stabilizer {
    /// Removes the approach velocities at the contacts of the islands of
    /// `bodies` (scene indices, typically the bodies the last call moved)
    /// at the scene's current poses (module docs). `velocities` has one
    /// entry per scene body; fixed bodies' entries are ignored.
    ///
    /// `time_step` is the engine's step `h`: contacts within the contact
    /// margin then count as speculative contacts, `J_k v' >= -phi / h`
    /// (module docs); `None` takes touching contacts only. `friction` is
    /// the projection's friction ([`VelocityFriction::None`] for none;
    /// friction on the change lets a heavy stack fall in an engine loop,
    /// `benchmarks/results/coupling.md`). An island whose projection fails
    /// keeps its velocities (counted in the report).
    pub fn project_velocities(
        &mut self,
        scene: &Scene,
        velocities: &mut [BodyVelocity],
        bodies: &[usize],
        time_step: Option<f64>,
        friction: VelocityFriction,
    ) -> Result<VelocityReport, Error> {
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
            .map(|&k| detection.active_bodies[k])
            .collect();
        let parts = SceneParts::of(scene);
        let body_poses: Vec<_> = scene.bodies().iter().map(|b| *b.com_pose()).collect();
        let part_poses = parts.poses(&body_poses);
        let geometry = SceneGeometry {
            parts: &parts,
            poses: &part_poses,
        };
        let joint_pairs = super::joint_state::joint_pairs(scene);
        // The islands asked for, each with its pairs as indices into the
        // detection's active pairs.
        let asked: Vec<(Island, Vec<usize>)> = islands_with_joints(&fixed, &pairs, &joint_pairs)?
            .into_iter()
            .filter(|island| island.bodies.iter().any(|b| bodies.contains(b)))
            .map(|island| {
                let island_pairs = island.pairs.iter().map(|&i| touching[i]).collect();
                (island, island_pairs)
            })
            .collect();
        // Islands share no dynamic body: each is projected on its own (on
        // rayon's threads with the `parallel` feature) from the velocities
        // as given, and the answers are merged in island order.
        let given: &[BodyVelocity] = velocities;
        let outcomes = crate::parallel::map(&asked, |(island, island_pairs)| {
            let contacts = IslandContacts {
                geometry,
                bodies: &island.bodies,
                pairs: island_pairs,
                joints: &island.joints,
                scale: lengths.scale,
                detection,
                contact_gap,
                gap_rate,
                friction,
            };
            self.project_island(scene, given, &contacts)
        });
        for outcome in outcomes {
            outcome.merge_into(&mut report, velocities);
        }
        Ok(report)
    }

    /// One island's velocity projection, from `velocities` (one per scene
    /// body).
    fn project_island(
        &self,
        scene: &Scene,
        velocities: &[BodyVelocity],
        contacts: &IslandContacts,
    ) -> IslandOutcome {
        let settings = &self.settings;
        let bodies = contacts.bodies;
        let mut outcome = IslandOutcome::default();
        // Islands hold dynamic bodies only, so their states exist; an
        // inconsistency is reported as a failed island, velocities kept.
        let Ok((configuration, inertias)) = super::solve_island::island_state(scene, bodies) else {
            outcome.failed = true;
            return outcome;
        };
        let Ok((mut rows, gaps, counts)) = self.island_rows(scene, contacts, &configuration) else {
            outcome.failed = true;
            return outcome;
        };
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
        outcome.contacts = counts.contacts;
        let before = Violations::of(&rows, counts);
        outcome.before = Some(before);
        // An approach or a joint's relative motion starts a projection, a
        // cone violation alone does not (module docs).
        if before.approach <= 0.0 && before.joint_rate <= 0.0 {
            return outcome;
        }
        let (qp, _) = projection_qp(
            &configuration,
            &inertias,
            &rows,
            0.0,
            settings.friction_directions,
            // The velocity projection keeps the pyramid (module docs).
            FrictionModel::Pyramid,
        );
        match solve_projection_kept(&qp, &settings.solver, None, Some(&self.kept_analyses)) {
            Ok(solution) => {
                outcome.solved = true;
                let v_new = &v + &solution.dq;
                rate(&mut rows, &v_new);
                outcome.after = Some(Violations::of(&rows, counts));
                outcome.velocities = bodies
                    .iter()
                    .enumerate()
                    .map(|(i, &body)| {
                        let block: Vector6<f64> = v_new.fixed_rows::<6>(6 * i).into_owned();
                        let velocity = BodyVelocity {
                            linear: block.fixed_rows::<3>(0).into_owned(),
                            angular: block.fixed_rows::<3>(3).into_owned(),
                        };
                        (body, velocity)
                    })
                    .collect();
            }
            Err(error) => {
                log::debug!(
                    "velocity projection of the island of body {} failed: {error}",
                    bodies[0]
                );
                outcome.failed = true;
                outcome.after = Some(before);
            }
        }
        outcome
    }

    /// The rows of an island's projection, each with its gap rate
    /// `max(0, phi) / h` (0 without a time step; 0 for a joint's locked
    /// axis), and how many of them are joint rows (first) and contact rows
    /// (next; the others: the cone rows of friction on the velocity,
    /// module docs).
    fn island_rows(
        &self,
        scene: &Scene,
        contacts: &IslandContacts,
        configuration: &[crate::rows::BodyState],
    ) -> Result<(Vec<ConstraintRow>, Vec<f64>, RowCounts), Error> {
        let settings = &self.settings;
        let joints = super::joint_state::island_joints(
            scene,
            contacts.joints,
            contacts.bodies,
            contacts.scale,
            contacts.contact_gap,
        )?;
        let mut rows: Vec<ConstraintRow> = joints.rows(configuration);
        let mut gaps: Vec<f64> = rows
            .iter()
            .map(|row| match row.kind {
                RowKind::Equality => 0.0,
                RowKind::Inequality => row.phi.max(0.0) * contacts.gap_rate,
            })
            .collect();
        let joint_count = rows.len();
        let parts = contacts.geometry.parts;
        let geometry = |part: usize| {
            let owner = parts.owner(part);
            BodyGeometry {
                configuration_index: contacts.bodies.binary_search(&owner).ok(),
                com_world: scene.bodies()[owner].com_world(),
                ..contacts.geometry.held(part)
            }
        };
        for &k in contacts.pairs {
            let pair = contacts.detection.active_pairs[k];
            let (a, b) = (geometry(pair.body_a), geometry(pair.body_b));
            let friction = match contacts.friction {
                VelocityFriction::None => ContactFriction::NONE,
                VelocityFriction::OnChange | VelocityFriction::OnVelocity => ContactFriction {
                    mu: super::solve_island::pair_friction(scene, settings, parts.owner_pair(pair)),
                },
            };
            let query = &contacts.detection.active_queries[k];
            let gap = contacts.contact_gap;
            let pair_rows = contact_rows(query, &a, &b, gap, settings, friction);
            for row in pair_rows.into_iter().filter(|row| row.phi <= gap) {
                gaps.push(row.phi.max(0.0) * contacts.gap_rate);
                rows.push(row);
            }
        }
        let counts = RowCounts {
            joints: joint_count,
            contacts: rows.len() - joint_count,
        };
        if contacts.friction == VelocityFriction::OnVelocity {
            append_velocity_cones(&mut rows, &mut gaps, counts, settings.friction_directions);
        }
        Ok((rows, gaps, counts))
    }
}

impl VelocityReport {
    fn record_before(&mut self, violations: Violations) {
        self.approach_before = self.approach_before.max(violations.approach);
        self.cone_before = self.cone_before.max(violations.cone);
        self.joint_rate_before = self.joint_rate_before.max(violations.joint_rate);
    }

    fn record_after(&mut self, violations: Violations) {
        self.approach_after = self.approach_after.max(violations.approach);
        self.cone_after = self.cone_after.max(violations.cone);
        self.joint_rate_after = self.joint_rate_after.max(violations.joint_rate);
    }
}

/// What one island's velocity projection found and did.
#[derive(Debug, Default)]
struct IslandOutcome {
    /// Its contact rows.
    contacts: usize,
    /// Its violations before, once its rows were built.
    before: Option<Violations>,
    /// Its violations after, when it was projected or failed.
    after: Option<Violations>,
    /// Projected.
    solved: bool,
    /// Its state, rows or projection failed (velocities kept).
    failed: bool,
    /// The projected velocities of its bodies (scene indices).
    velocities: Vec<(usize, BodyVelocity)>,
}

impl IslandOutcome {
    /// Adds this island to the call's report and writes its velocities.
    fn merge_into(self, report: &mut VelocityReport, velocities: &mut [BodyVelocity]) {
        report.contacts += self.contacts;
        report.islands_solved += usize::from(self.solved);
        report.islands_failed += usize::from(self.failed);
        if let Some(before) = self.before {
            report.record_before(before);
        }
        if let Some(after) = self.after {
            report.record_after(after);
        }
        for (body, velocity) in self.velocities {
            velocities[body] = velocity;
        }
    }
}

/// How many rows of an island's velocity projection are joint rows (first)
/// and contact rows (next); cone rows follow.
#[derive(Debug, Clone, Copy)]
struct RowCounts {
    joints: usize,
    contacts: usize,
}

/// The largest violations of an island's rows at some velocity (speeds,
/// 0 if none): of the contact rows (approach), of the cone rows, and of
/// the joint rows (a locked axis's rate either way, a limit's approach).
#[derive(Debug, Clone, Copy)]
struct Violations {
    approach: f64,
    cone: f64,
    joint_rate: f64,
}

impl Violations {
    /// Of `rows` rated at a velocity (`phi` the row's rate), counted by
    /// `counts`.
    fn of(rows: &[ConstraintRow], counts: RowCounts) -> Self {
        let violation = |r: &ConstraintRow| match r.kind {
            RowKind::Equality => r.phi.abs(),
            RowKind::Inequality => -r.phi,
        };
        let largest =
            |rows: &[ConstraintRow]| rows.iter().fold(0.0, |m: f64, r| m.max(violation(r)));
        let (joint_rows, rest) = rows.split_at(counts.joints);
        let (contact_rows, cone_rows) = rest.split_at(counts.contacts);
        Violations {
            approach: largest(contact_rows),
            cone: largest(cone_rows),
            joint_rate: largest(joint_rows),
        }
    }
}

/// Friction on the velocity: replaces the friction of every contact row by
/// the rows (2) of its pyramid (module docs), frictionless rows of their
/// own appended to `rows`, each with its contact row's gap rate in `gaps`
/// (joint rows, first in `rows`, have no friction).
fn append_velocity_cones(
    rows: &mut Vec<ConstraintRow>,
    gaps: &mut Vec<f64>,
    counts: RowCounts,
    directions: usize,
) {
    // The pyramid's Jacobians; its `phi` (apex for the position problem)
    // is not used: a cone row is rated at the velocity like a contact row.
    debug_assert!(rows[..counts.joints].iter().all(|r| r.friction.is_none()));
    let (facets, _, parents) = pyramid_rows(rows, 0.0, directions);
    for (facet, parent) in facets.into_iter().zip(parents) {
        gaps.push(gaps[parent]);
        rows.push(ConstraintRow {
            kind: RowKind::Inequality,
            phi: 0.0,
            blocks: facet.blocks,
            friction: None,
        });
    }
    for row in rows.iter_mut() {
        row.friction = None;
    }
}

/// The contacts of one island's velocity projection.
struct IslandContacts<'a> {
    /// The scene's parts at the detection's poses.
    geometry: SceneGeometry<'a>,
    /// Dynamic bodies, ascending.
    bodies: &'a [usize],
    /// Indices of the island's pairs into the detection's active (part)
    /// pairs.
    pairs: &'a [usize],
    /// The island's joints (scene indices).
    joints: &'a [usize],
    /// The scene's length scale (angles to lengths).
    scale: f64,
    detection: &'a Detection,
    /// Rows of points further apart than this are left out.
    contact_gap: f64,
    /// `1 / h`, or 0 without speculative contacts.
    gap_rate: f64,
    /// The friction of the rows.
    friction: VelocityFriction,
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
