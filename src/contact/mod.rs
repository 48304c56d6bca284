//! Narrow phase: what two bodies do to each other, and the constraint rows
//! that follow.
//!
//! A query runs V-Clip (warm-started). A separated pair keeps V-Clip's
//! distance and closest points. A penetrating pair goes on from V-Clip's
//! deepest vertex to the exact penetration depth and the feature pair that
//! realizes it ([`penetration`]: vertex–face of either body, or edge–edge),
//! and its rows come from a contact manifold built on that normal
//! ([`manifold`]).
//!
//! The signed value of a pair is its distance when separated and minus the
//! exact penetration depth when penetrating.
//!
//! Rows (`docs/design.md` section 3), with the normal `n` from B towards A:
//! - penetrating: one row per manifold point (at most four for a face
//!   contact, one for an edge–edge contact), `phi` = the point's separation
//!   along `n`; with the manifold off, the deepest point only;
//! - separated closer than the contact margin: the same manifold, on the
//!   axis of widest separation ([`widest_separation`]), so that two nearly
//!   touching faces get up to four rows, not one at an arbitrary closest
//!   point (chosen by measurement on the engine states of
//!   `tests/data/engine/`: `benchmarks/results/contact_geometry.md`); with
//!   the manifold off, one row at V-Clip's closest points,
//!   `n = (p_a - p_b) / d`. When `d` is too small for that quotient, the
//!   normal comes from the closest features (a face normal, or the cross
//!   product of two edges), else from the centres of mass.
//!
//! This room owns contacts, from the scene to the rows:
//! - `detection`: broad phase and narrow phase over the scene;
//! - this file: one pair's query (V-Clip, then the exact depth) and its rows;
//! - `penetration` (exact depth), `gauss_map` (arcs on the sphere),
//!   `manifold` (contact points), `contact_row` (a row's Jacobian);
//! - `island_contacts`: the constraint provider of an island, which
//!   re-queries its pairs at the line search's trial configurations;
//! - `memo` (the answers of a call, so that V-Clip runs once per pair per
//!   configuration), `warm_start` (V-Clip's last feature pairs, kept
//!   across calls) and `certificate` (pairs certified separated beyond the
//!   margin by a bound on their motion, not queried again).

pub mod certificate;
pub mod contact_row;
mod detection;
pub mod gauss_map;
pub mod island;
mod island_contacts;
pub mod manifold;
mod memo;
pub mod penetration;
pub mod round;
pub mod scene_parts;
mod warm_start;

use nalgebra::{Isometry3, Point3, Vector3};

use crate::geometry::curved::CurvedSolid;
use crate::geometry::{ConvexPolyhedron, Feature, Rounding};
use crate::rows::ConstraintRow;
use crate::settings::Settings;
use crate::vclip::{FeaturePair, Outcome, VClip, VClipError, VClipResult};
pub use certificate::SeparationCertificates;
pub use contact_row::{ContactSide, contact_row, contact_row_with_friction, tangent_basis};
pub use detection::{Detection, DetectionError, DetectionState, PairPenetration, detect};
pub use island::{Island, IslandError, islands, islands_with_joints};
pub use island_contacts::{IslandContacts, SceneGeometry, shape_pair};
pub use manifold::{ContactPoint, Manifold};
pub use memo::{PosedQuery, QueryMemo};
pub use penetration::{
    ContactAxis, Penetration, PenetrationFeatures, minimum_translation, scans_cap,
    widest_separation,
};
pub use round::RoundAnswer;
pub use scene_parts::SceneParts;
pub(crate) use warm_start::ShapeIdentity;
pub use warm_start::WarmStartCache;

/// Distance, relative to the pair's scale, below which the witness
/// difference of a separated pair is too small to give a normal.
pub const NORMAL_FROM_WITNESS_MIN_RELATIVE: f64 = 1e-9;

/// The geometry of one body as a contact sees it.
#[derive(Debug, Clone, Copy)]
pub struct BodyGeometry<'a> {
    /// The polyhedron in its body frame.
    pub shape: &'a ConvexPolyhedron,
    /// Centre-of-mass pose (body frame to world).
    pub pose: Isometry3<f64>,
    /// Index in the configuration being corrected, `None` if the body does
    /// not move (fixed).
    pub configuration_index: Option<usize>,
    /// World centre of mass of the body the polyhedron belongs to (the
    /// origin of `pose` for a convex body; a compound's part is offset from
    /// it), the point about which the body turns.
    pub com_world: Point3<f64>,
    /// The part's core and radius when it is round (`shape` is then the
    /// core, or for a point or segment core only a bounding box).
    pub rounding: Option<Rounding>,
    /// A cylinder's or cone's true solid (`shape` is then its
    /// circumscribed approximation), used by the support-function narrow
    /// phase when [`crate::vclip::VClipSettings::curved_support_functions`]
    /// is on.
    pub curved: Option<CurvedSolid>,
}

impl<'a> BodyGeometry<'a> {
    /// A convex body: its polyhedron at its centre-of-mass pose.
    pub fn convex(
        shape: &'a ConvexPolyhedron,
        pose: Isometry3<f64>,
        configuration_index: Option<usize>,
    ) -> Self {
        BodyGeometry {
            shape,
            pose,
            configuration_index,
            com_world: Point3::from(pose.translation.vector),
            rounding: None,
            curved: None,
        }
    }

    /// The same part with a rounding (`None`: a plain polyhedron).
    pub fn rounded(self, rounding: Option<Rounding>) -> Self {
        BodyGeometry { rounding, ..self }
    }

    /// The same part with its true curved solid (`None`: none).
    pub fn curved(self, curved: Option<CurvedSolid>) -> Self {
        BodyGeometry { curved, ..self }
    }

    fn side(&self) -> ContactSide {
        self.configuration_index
            .map(|index| (index, self.com_world))
    }
}

/// A pair's narrow-phase answer: V-Clip's result and, when the bodies
/// penetrate, their minimum translation.
#[derive(Debug, Clone, PartialEq)]
pub struct PairQuery {
    /// V-Clip's answer (the final feature pair is the next warm start).
    pub vclip: VClipResult,
    /// The exact penetration, when V-Clip found the bodies penetrating
    /// (of the cores, for round parts).
    pub penetration: Option<Penetration>,
    /// For a pair with a round part: the radii, and the cores' answer when
    /// one is a point or a segment ([`round`]); `vclip` and `penetration`
    /// are then the cores' (two polyhedra) or a placeholder (closed form).
    /// Boxed: it is most of the answer's size (384 of 664 bytes inline),
    /// and the answers of polyhedral pairs, which have none, are copied
    /// into the memo, the certificates and the detection of every pass.
    pub round: Option<Box<RoundAnswer>>,
}

impl PairQuery {
    /// Distance when separated, minus the exact depth when penetrating
    /// (for round parts the cores' value minus both radii, [`round`]).
    pub fn signed_value(&self) -> f64 {
        match &self.round {
            None => self.core_value(),
            Some(round) => {
                let core = round
                    .closed_form
                    .map_or_else(|| self.core_value(), |c| c.signed_distance);
                core - round.radius_sum()
            }
        }
    }

    /// The exact depth when penetrating deeper than 0, else `None`.
    pub fn depth(&self) -> Option<f64> {
        let value = self.signed_value();
        (value < 0.0).then_some(-value)
    }

    /// The signed value of the polyhedra V-Clip answered.
    fn core_value(&self) -> f64 {
        match (&self.penetration, &self.vclip.outcome) {
            (Some(penetration), _) => -penetration.depth(),
            (None, Outcome::Separated { distance, .. }) => *distance,
            // V-Clip's deepest vertex, never reached: `query` always adds
            // the penetration of a penetrating outcome.
            (None, Outcome::Penetrating(deepest)) => -deepest.depth,
        }
    }
}

/// V-Clip on two bodies, `a` the pair's first body, then, if they
/// penetrate, the exact depth search from V-Clip's deepest vertex.
pub fn query(
    vclip: &VClip,
    a: &BodyGeometry,
    b: &BodyGeometry,
    warm_start: Option<FeaturePair>,
) -> Result<PairQuery, VClipError> {
    if vclip.settings.curved_support_functions && (a.curved.is_some() || b.curved.is_some()) {
        let radii = round::radii(a, b).unwrap_or([0.0; 2]);
        return Ok(closed_form_query(radii, round::support_pair::contact(a, b)));
    }
    let radii = round::radii(a, b);
    if let (Some(radii), Some(contact)) = (radii, round::closed_form(a, b)) {
        return Ok(closed_form_query(radii, contact));
    }
    // The exact search needs only some vertex–face pair as its start (its
    // cap holds the answer from any upper bound): V-Clip's face refinement
    // tightens the cap, which pays only where the search walks it (a body
    // of more than `ARC_SCAN_MAX_EDGES` edges); below, it cost more than
    // it saved (`benchmarks/results/call_cost.md`, twenty-first session).
    let refine = vclip.settings.refine_face && !(scans_cap(a.shape) && scans_cap(b.shape));
    let posed =
        |warm_start| vclip.query_refining(a.shape, &a.pose, b.shape, &b.pose, warm_start, refine);
    let result = match posed(warm_start) {
        // A warm start is a hint: one that does not fit these shapes is
        // dropped and the query starts cold.
        Err(VClipError::InvalidWarmStart { .. }) => posed(None)?,
        answer => answer?,
    };
    let penetration = match &result.outcome {
        Outcome::Penetrating(deepest) => Some(minimum_translation(
            a.shape, &a.pose, b.shape, &b.pose, deepest,
        )),
        Outcome::Separated { .. } => None,
    };
    Ok(PairQuery {
        vclip: result,
        penetration,
        round: radii.map(|radii| {
            Box::new(RoundAnswer {
                radii,
                closed_form: None,
            })
        }),
    })
}

/// The answer of a pair with a point or segment core: V-Clip did not run,
/// its fields hold the closest points and the cold start.
fn closed_form_query(radii: [f64; 2], contact: round::CoreContact) -> PairQuery {
    let closest = contact.points[0];
    PairQuery {
        vclip: VClipResult {
            outcome: Outcome::Separated {
                distance: contact.signed_distance.max(0.0),
                witness_a_world: closest.on_a,
                witness_b_world: closest.on_b,
            },
            final_pair: FeaturePair::cold(),
            iterations: 0,
            fallback: None,
            resolved_cycle: false,
        },
        penetration: None,
        round: Some(Box::new(RoundAnswer {
            radii,
            closed_form: Some(contact),
        })),
    }
}

/// Coulomb friction of a pair's rows: coefficient `mu`, given to every row
/// of the pair, open ones included (the pyramid's apex is where a row
/// reaches its target, [`crate::projector::friction`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactFriction {
    /// Friction coefficient (0: frictionless rows).
    pub mu: f64,
}

impl ContactFriction {
    /// No friction.
    pub const NONE: ContactFriction = ContactFriction { mu: 0.0 };

    /// The row of a contact point, with friction if the pair has any.
    fn row(
        &self,
        p_a: &Point3<f64>,
        p_b: &Point3<f64>,
        normal: &Vector3<f64>,
        a: &BodyGeometry,
        b: &BodyGeometry,
    ) -> ConstraintRow {
        if self.mu > 0.0 {
            contact_row_with_friction(p_a, p_b, normal, a.side(), b.side(), self.mu)
        } else {
            contact_row(p_a, p_b, normal, a.side(), b.side())
        }
    }
}

/// The body whose rotation carries a pair's contact normal: the body of
/// the reference face ([`PenetrationFeatures::FaceOfA`] or
/// [`PenetrationFeatures::FaceOfB`]); B for an edge–edge contact and for
/// the closest points of a near pair without manifold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalBody {
    /// The pair's first body.
    A,
    /// The pair's second body.
    B,
}

/// The contact points of one pair, world frame, and the body that carries
/// their normal.
#[derive(Debug, Clone, PartialEq)]
pub struct PairContactPoints {
    /// The points (see [`contact_points`]).
    pub points: Vec<ContactPoint>,
    /// The body of the reference face.
    pub normal_body: NormalBody,
}

/// The constraint rows of a pair with narrow-phase answer `query` (no row
/// for a separated pair at or beyond `margin`). Without
/// [`Settings::contact_manifold`], the deepest point of a penetration only. Every row gets `friction`
/// ([`ContactFriction`]).
pub fn contact_rows(
    query: &PairQuery,
    a: &BodyGeometry,
    b: &BodyGeometry,
    margin: f64,
    settings: &Settings,
    friction: ContactFriction,
) -> Vec<ConstraintRow> {
    contact_points(query, a, b, margin, settings)
        .points
        .iter()
        .map(|point| {
            friction.row(
                &point.point_a_world,
                &point.point_b_world,
                &point.normal_world,
                a,
                b,
            )
        })
        .collect()
}

/// The contact points of a pair with narrow-phase answer `query`, one per
/// row of [`contact_rows`] and in the same order (none for a separated pair
/// at or beyond `margin`): the manifold of a penetrating pair, or of a near
/// pair on its widest separating axis; with `manifold = false`, the deepest
/// point of a penetration, or V-Clip's closest points of a near pair.
pub fn contact_points(
    query: &PairQuery,
    a: &BodyGeometry,
    b: &BodyGeometry,
    margin: f64,
    settings: &Settings,
) -> PairContactPoints {
    if let Some(round) = &query.round {
        return round_contact_points(query, round, a, b, margin, settings);
    }
    let manifold = settings.contact_manifold;
    let near = match (&query.penetration, &query.vclip.outcome) {
        (Some(penetration), _) => Some(*penetration),
        (None, Outcome::Separated { distance, .. }) if *distance < margin && manifold => {
            Some(widest_separation(
                a.shape,
                &a.pose,
                b.shape,
                &b.pose,
                query.vclip.final_pair.to_array(),
                settings.near_pair_faces,
            ))
        }
        _ => None,
    };
    if let Some(penetration) = near {
        let normal_body = match penetration.reference.features {
            PenetrationFeatures::FaceOfA { .. } => NormalBody::A,
            _ => NormalBody::B,
        };
        return PairContactPoints {
            points: manifold::manifold(&penetration, a, b, margin, manifold).points,
            normal_body,
        };
    }
    let points = match &query.vclip.outcome {
        Outcome::Separated {
            distance,
            witness_a_world,
            witness_b_world,
        } if *distance < margin => {
            let normal = separation_normal(
                &query.vclip,
                a,
                b,
                witness_a_world,
                witness_b_world,
                *distance,
            );
            vec![ContactPoint {
                point_a_world: *witness_a_world,
                point_b_world: *witness_b_world,
                normal_world: normal,
                separation: normal.dot(&(witness_a_world - witness_b_world)),
            }]
        }
        _ => Vec::new(),
    };
    PairContactPoints {
        points,
        normal_body: NormalBody::B,
    }
}

/// Unit normal from B towards A of a separated pair.
fn separation_normal(
    result: &VClipResult,
    a: &BodyGeometry,
    b: &BodyGeometry,
    witness_a: &Point3<f64>,
    witness_b: &Point3<f64>,
    distance: f64,
) -> Vector3<f64> {
    let scale = a.shape.scale().min(b.shape.scale());
    if distance > NORMAL_FROM_WITNESS_MIN_RELATIVE * scale {
        return (witness_a - witness_b) / distance;
    }
    let centres = a.pose.translation.vector - b.pose.translation.vector;
    let from_features = feature_normal(result.final_pair, a, b);
    let normal = from_features.unwrap_or(centres);
    let oriented = if normal.dot(&centres) < 0.0 {
        -normal
    } else {
        normal
    };
    oriented.try_normalize(0.0).unwrap_or_else(Vector3::z)
}

/// A normal of touching features: a face's normal, or the cross product of
/// two edges (orientation left to the caller).
fn feature_normal(pair: FeaturePair, a: &BodyGeometry, b: &BodyGeometry) -> Option<Vector3<f64>> {
    match (pair.a, pair.b) {
        (_, Feature::Face(f)) => Some(b.pose.rotation * b.shape.faces()[f].plane.normal),
        (Feature::Face(f), _) => Some(-(a.pose.rotation * a.shape.faces()[f].plane.normal)),
        (Feature::Edge(ea), Feature::Edge(eb)) => {
            let da = a.pose.rotation * a.shape.edges()[ea].direction;
            let db = b.pose.rotation * b.shape.edges()[eb].direction;
            da.cross(&db).try_normalize(f64::EPSILON)
        }
        _ => None,
    }
}

/// Distance, relative to the pair's size, by which the cores' manifold axis
/// may fall short of their distance before the closest points replace it
/// (cores whose closest features are not a face or an edge pair).
pub const ROUND_AXIS_SHORTFALL_RELATIVE: f64 = 1e-9;

/// The contact points of a pair with a round part: the cores' points with
/// the margin raised by the radii, put on the surfaces ([`round`]).
fn round_contact_points(
    query: &PairQuery,
    round: &RoundAnswer,
    a: &BodyGeometry,
    b: &BodyGeometry,
    margin: f64,
    settings: &Settings,
) -> PairContactPoints {
    let mut points: Vec<ContactPoint> = match &round.closed_form {
        Some(contact) => {
            let (core_points, count) = contact.points_of(a, b, margin + round.radius_sum());
            core_points[..count]
                .iter()
                .map(|p| round.on_surfaces(p))
                .collect()
        }
        None => {
            let core = PairQuery {
                round: None,
                ..*query
            };
            let raised = margin + round.radius_sum();
            let mut core_points = contact_points(&core, a, b, raised, settings).points;
            if let Outcome::Separated {
                distance,
                witness_a_world,
                witness_b_world,
            } = &query.vclip.outcome
            {
                // The manifold's axis is the widest facet axis, short of
                // the distance when the closest features are a vertex and
                // a vertex or an edge: the closest points then carry the
                // single row. When instead every manifold point is farther
                // apart than the distance (its clipped face misses the
                // closest points: a narrow side of a cylinder's prism),
                // the closest points join it, so that some row carries
                // the pair's signed distance.
                let size = a.shape.scale().min(b.shape.scale());
                let shallowest = core_points
                    .iter()
                    .map(|p| p.separation)
                    .fold(f64::INFINITY, f64::min);
                let far_enough = *distance > NORMAL_FROM_WITNESS_MIN_RELATIVE * size;
                let slack = ROUND_AXIS_SHORTFALL_RELATIVE * size;
                if far_enough && *distance < raised {
                    let normal = (witness_a_world - witness_b_world) / *distance;
                    let closest = ContactPoint {
                        point_a_world: *witness_a_world,
                        point_b_world: *witness_b_world,
                        normal_world: normal,
                        separation: *distance,
                    };
                    if shallowest < distance - slack {
                        core_points = vec![closest];
                    } else if shallowest > distance + slack {
                        core_points.push(closest);
                    }
                }
            }
            core_points
                .iter()
                .map(|p| {
                    let core = round::CorePoint {
                        on_a: p.point_a_world,
                        on_b: p.point_b_world,
                        separation: p.separation,
                        normal: p.normal_world,
                    };
                    round.on_surfaces(&core)
                })
                .collect()
        }
    };
    points.retain(|p| p.separation < margin);
    points.sort_by(|p, q| p.separation.total_cmp(&q.separation));
    if !settings.contact_manifold {
        points.truncate(1);
    }
    PairContactPoints {
        points,
        normal_body: NormalBody::B,
    }
}
