//! An independent oracle for curved shapes: the signed distance of two
//! convex solids from their support functions alone.
//!
//! For convex `A`, `B` and a unit `n` (from B towards A), translating A by
//! `t n` separates them once `t >= o(n) = h_B(n) + h_A(-n)`. The
//! penetration depth is `min_n o(n)` when positive; when negative, `-min`
//! is the distance (the widest separating gap over all directions). So the
//! signed distance is `-min_n o(n)`, whatever the shapes.
//!
//! The minimum is found by dense sampling (a Fibonacci sphere of
//! [`SAMPLES`] directions), then a local refinement of the best
//! [`REFINED`] samples by a pattern search on the sphere (eight tangent
//! directions, the step halved when none improves, down to
//! [`FINEST_STEP`] rad; at most [`MOVES_PER_STEP`] moves at one step
//! before it is halved, so that a search creeping along a narrow valley of
//! the kinked overlap ends). Its answer is an `o(n)` actually reached:
//! never below the true minimum, so the depth it reports bounds the true
//! depth from above, and is within the refinement's reach of it.
//!
//! The depth alone ([`body_depth`]) needs no refinement when some sampled
//! direction already separates (`o(n) <= 0`: a separating plane, depth 0,
//! exactly); the direction between the solids' centres is tried first.
//!
//! The solids come from the bodies' [`Shape`] descriptions and user poses
//! only (nothing of the library's polyhedra, cores or narrow phase):
//! polyhedra by their vertices, round shapes by their core points plus the
//! radius, cylinders and cones by their exact support functions
//! (`c.n + h |u.n| + r sqrt(1 - (u.n)^2)` for a cylinder of axis `u`).

use std::f64::consts::PI;

use constraint_stabilization::body::{Body, Shape};
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};

/// Directions of the dense sampling.
pub const SAMPLES: usize = 4000;

/// Best samples refined.
pub const REFINED: usize = 12;

/// First step of the refinement (rad), about the sampling's spacing.
pub const FIRST_STEP: f64 = 0.1;

/// Last step of the refinement (rad).
pub const FINEST_STEP: f64 = 1e-13;

/// Improving moves at one step length before the step is halved anyway.
/// Without a bound the pattern search crept along narrow valleys of the
/// kinked overlap by steps of 1e-10 rad for seconds per pair (found by the
/// Rapier pile of round shapes, `examples/with_and_without.rs`); a
/// descent that needs more moves continues at the halved step, so the
/// answer stays an overlap reached.
pub const MOVES_PER_STEP: usize = 64;

/// `(cos, sin)` of the eight compass directions of the pattern search,
/// `k π/4`.
const COMPASS: [(f64, f64); 8] = [
    (1.0, 0.0),
    (
        std::f64::consts::FRAC_1_SQRT_2,
        std::f64::consts::FRAC_1_SQRT_2,
    ),
    (0.0, 1.0),
    (
        -std::f64::consts::FRAC_1_SQRT_2,
        std::f64::consts::FRAC_1_SQRT_2,
    ),
    (-1.0, 0.0),
    (
        -std::f64::consts::FRAC_1_SQRT_2,
        -std::f64::consts::FRAC_1_SQRT_2,
    ),
    (0.0, -1.0),
    (
        std::f64::consts::FRAC_1_SQRT_2,
        -std::f64::consts::FRAC_1_SQRT_2,
    ),
];

/// One convex solid in the world frame.
#[derive(Debug, Clone)]
pub enum Solid {
    /// The hull of points grown by a radius (0 for a polyhedron).
    Points {
        /// Points, world frame.
        points: Vec<Point3<f64>>,
        /// Radius.
        radius: f64,
    },
    /// A cylinder.
    Cylinder {
        /// Centre.
        centre: Point3<f64>,
        /// Unit axis.
        axis: Vector3<f64>,
        /// Half height.
        half_height: f64,
        /// Radius.
        radius: f64,
    },
    /// A cone, base at `centre - half_height axis`, apex at
    /// `centre + half_height axis`.
    Cone {
        /// Centre (of the axis segment).
        centre: Point3<f64>,
        /// Unit axis.
        axis: Vector3<f64>,
        /// Half height.
        half_height: f64,
        /// Base radius.
        radius: f64,
    },
}

/// `(n . centre, n . axis, |n x axis|)` for unit `n` and `axis`. The
/// last is the cross product's norm, not `sqrt(1 - (n . axis)^2)`: near the
/// axis that difference cancels, and its rounding (1e-16) became an error
/// of 1e-8 of the radius in the square root, below the true overlap (found
/// against the support-function narrow phase: a point under a cylinder's
/// cap, exact there, came out 1.1e-8 deeper than this oracle).
fn axial(n: &Vector3<f64>, centre: &Point3<f64>, axis: &Vector3<f64>) -> (f64, f64, f64) {
    (n.dot(&centre.coords), n.dot(axis), n.cross(axis).norm())
}

impl Solid {
    /// The support function at unit `n`.
    pub fn support(&self, n: &Vector3<f64>) -> f64 {
        match self {
            Solid::Points { points, radius } => {
                points
                    .iter()
                    .map(|p| n.dot(&p.coords))
                    .fold(f64::NEG_INFINITY, f64::max)
                    + radius
            }
            Solid::Cylinder {
                centre,
                axis,
                half_height,
                radius,
            } => {
                let (middle, along, across) = axial(n, centre, axis);
                middle + half_height * along.abs() + radius * across
            }
            Solid::Cone {
                centre,
                axis,
                half_height,
                radius,
            } => {
                let (middle, along, across) = axial(n, centre, axis);
                let apex = middle + half_height * along;
                let base = middle - half_height * along + radius * across;
                apex.max(base)
            }
        }
    }
}

impl Solid {
    /// Directions along the kinks of the support function at unit `n`
    /// (tangent to the sphere): where its two highest points tie (a
    /// polyhedron's or a segment's), or across a cylinder's or cone's axis.
    /// The minimum of a support-function overlap often lies on such a
    /// ridge, which a compass search cannot follow.
    pub fn ridges(&self, n: &Vector3<f64>) -> Vec<Vector3<f64>> {
        let across = |v: Vector3<f64>| n.cross(&v).try_normalize(1e-15);
        match self {
            Solid::Points { points, .. } => {
                // The three highest points along `n`, highest first.
                let mut top: [Option<&Point3<f64>>; 3] = [None; 3];
                let height =
                    |p: Option<&Point3<f64>>| p.map_or(f64::NEG_INFINITY, |p| n.dot(&p.coords));
                for p in points {
                    let mut carried = Some(p);
                    for slot in &mut top {
                        if height(carried) > height(*slot) {
                            std::mem::swap(slot, &mut carried);
                        }
                    }
                }
                top.windows(2)
                    .filter_map(|w| match (w[0], w[1]) {
                        (Some(p), Some(q)) => across(p - q),
                        _ => None,
                    })
                    .collect()
            }
            Solid::Cylinder { axis, .. } | Solid::Cone { axis, .. } => {
                across(*axis).into_iter().collect()
            }
        }
    }
}

/// The solid of a convex shape placed at `pose` (shape frame to world);
/// `None` for a compound.
pub fn solid(shape: &Shape, pose: &Isometry3<f64>) -> Option<Solid> {
    let place = |points: Vec<Point3<f64>>, radius: f64| Solid::Points {
        points: points.iter().map(|p| pose * p).collect(),
        radius,
    };
    let corners = |h: &Vector3<f64>| {
        (0..8)
            .map(|i| {
                let sign = |bit: usize| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
                Point3::new(sign(0) * h.x, sign(1) * h.y, sign(2) * h.z)
            })
            .collect::<Vec<_>>()
    };
    let axis = pose.rotation * Vector3::z();
    let centre = pose * Point3::origin();
    Some(match shape {
        Shape::Cuboid { half_extents } => place(corners(half_extents), 0.0),
        Shape::ConvexHull { points } => place(points.clone(), 0.0),
        Shape::Sphere { radius } => place(vec![Point3::origin()], *radius),
        Shape::Capsule {
            half_height,
            radius,
        } => place(
            vec![
                Point3::new(0.0, 0.0, -half_height),
                Point3::new(0.0, 0.0, *half_height),
            ],
            *radius,
        ),
        Shape::RoundCuboid {
            half_extents,
            radius,
        } => place(corners(half_extents), *radius),
        Shape::RoundConvexHull { points, radius } => place(points.clone(), *radius),
        Shape::Cylinder {
            half_height,
            radius,
        } => Solid::Cylinder {
            centre,
            axis,
            half_height: *half_height,
            radius: *radius,
        },
        Shape::Cone {
            half_height,
            radius,
        } => Solid::Cone {
            centre,
            axis,
            half_height: *half_height,
            radius: *radius,
        },
        Shape::Compound { .. } => return None,
    })
}

/// The solids of a body at its current pose (one per part of a compound).
pub fn solids_of(body: &Body) -> Vec<Solid> {
    let pose = body.user_pose();
    match body.shape() {
        Shape::Compound { parts } => parts
            .iter()
            .filter_map(|part| {
                let [x, y, z, w] = part.rotation_xyzw;
                let rotation = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
                let offset = Isometry3::from_parts(Translation3::from(part.translation), rotation);
                solid(&part.shape, &(pose * offset))
            })
            .collect(),
        shape => solid(shape, &pose).into_iter().collect(),
    }
}

/// `o(n) = h_B(n) + h_A(-n)` (module docs).
fn overlap(a: &Solid, b: &Solid, n: &Vector3<f64>) -> f64 {
    b.support(n) + a.support(&-n)
}

/// The Fibonacci sphere of [`SAMPLES`] directions.
fn sample_directions() -> impl Iterator<Item = Vector3<f64>> {
    let golden = PI * (3.0 - 5.0_f64.sqrt());
    (0..SAMPLES).map(move |i| {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / SAMPLES as f64;
        let ring = (1.0 - z * z).sqrt();
        let angle = golden * i as f64;
        Vector3::new(ring * angle.cos(), ring * angle.sin(), z)
    })
}

/// The sampled overlaps, least first.
fn sampled(a: &Solid, b: &Solid) -> Vec<(f64, Vector3<f64>)> {
    let mut samples: Vec<(f64, Vector3<f64>)> = sample_directions()
        .chain(feature_directions(a))
        .chain(feature_directions(b))
        .map(|n| (overlap(a, b, &n), n))
        .collect();
    samples.sort_by(|x, y| x.0.total_cmp(&y.0));
    samples
}

/// Most points of a solid whose plane normals are tried as directions.
pub const FEATURE_POINTS: usize = 16;

/// Directions where the overlap has isolated minima no sample hits
/// exactly: both ways along a cylinder's or cone's axis, and the normals
/// of the planes through three points of a point set of at most
/// [`FEATURE_POINTS`] points (its faces among them). A line or face
/// contact separates only along its exact normal, which a sampled
/// direction misses and a pattern search reaches only to its step (found:
/// a cylinder lying on a box, lifted to touching, measured 1.1e-4 deep).
fn feature_directions(solid: &Solid) -> Vec<Vector3<f64>> {
    match solid {
        Solid::Cylinder { axis, .. } | Solid::Cone { axis, .. } => vec![*axis, -axis],
        Solid::Points { points, .. } if points.len() <= FEATURE_POINTS => {
            let mut directions = Vec::new();
            for i in 0..points.len() {
                for j in i + 1..points.len() {
                    for k in j + 1..points.len() {
                        let normal = (points[j] - points[i]).cross(&(points[k] - points[i]));
                        if let Some(n) = normal.try_normalize(1e-12) {
                            directions.push(n);
                            directions.push(-n);
                        }
                    }
                }
            }
            directions
        }
        Solid::Points { .. } => Vec::new(),
    }
}

/// The least overlap after refining the best [`REFINED`] samples, and its
/// direction.
fn least_refined(a: &Solid, b: &Solid, samples: &[(f64, Vector3<f64>)]) -> (f64, Vector3<f64>) {
    samples
        .iter()
        .take(REFINED)
        .map(|&(value, n)| refine(a, b, value, n))
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .unwrap_or((f64::INFINITY, Vector3::z()))
}

/// The signed distance of `a` and `b` (distance, or minus the depth) and
/// the direction that reaches it (from B towards A), module docs.
pub fn signed_distance(a: &Solid, b: &Solid) -> (f64, Vector3<f64>) {
    let (value, n) = least_refined(a, b, &sampled(a, b));
    (-value, n)
}

/// A point inside the solid (the mean of its points, or its centre).
fn inner_point(solid: &Solid) -> Point3<f64> {
    match solid {
        Solid::Points { points, .. } => {
            let sum = points.iter().fold(Vector3::zeros(), |s, p| s + p.coords);
            Point3::from(sum / points.len().max(1) as f64)
        }
        Solid::Cylinder { centre, .. } | Solid::Cone { centre, .. } => *centre,
    }
}

/// The penetration depth of `a` and `b` (0 when apart or touching): as
/// [`signed_distance`], but 0 as soon as a direction separates (the one
/// between the solids' inner points first, then the samples), without
/// refinement.
pub fn depth(a: &Solid, b: &Solid) -> f64 {
    let between = (inner_point(a) - inner_point(b)).try_normalize(0.0);
    if between.is_some_and(|n| overlap(a, b, &n) <= 0.0) {
        return 0.0;
    }
    if sample_directions()
        .chain(feature_directions(a))
        .chain(feature_directions(b))
        .any(|n| overlap(a, b, &n) <= 0.0)
    {
        return 0.0;
    }
    least_refined(a, b, &sampled(a, b)).0.max(0.0)
}

/// Pattern search on the sphere from `n` (module docs).
fn refine(a: &Solid, b: &Solid, mut value: f64, mut n: Vector3<f64>) -> (f64, Vector3<f64>) {
    let mut step = FIRST_STEP;
    let mut moves = 0;
    while step > FINEST_STEP {
        let helper = if n.x.abs() < 0.6 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let t1 = n.cross(&helper).normalize();
        let t2 = n.cross(&t1);
        let compass = COMPASS.iter().map(|&(c, s)| t1 * c + t2 * s);
        let ridges = b.ridges(&n).into_iter().chain(a.ridges(&-n));
        let along_ridges = ridges.flat_map(|ridge| [ridge, -ridge]);
        let improvement = compass.chain(along_ridges).find_map(|direction| {
            let trial = (n + direction * step).normalize();
            let trial_value = overlap(a, b, &trial);
            (trial_value < value).then_some((trial_value, trial))
        });
        match improvement {
            Some((trial_value, trial)) if moves < MOVES_PER_STEP => {
                value = trial_value;
                n = trial;
                moves += 1;
            }
            Some((trial_value, trial)) => {
                value = trial_value;
                n = trial;
                step /= 2.0;
                moves = 0;
            }
            None => {
                step /= 2.0;
                moves = 0;
            }
        }
    }
    (value, n)
}

/// The signed distance of bodies `a` and `b` (for compounds the least over
/// their part pairs).
pub fn body_signed_distance(a: &Body, b: &Body) -> f64 {
    let (solids_a, solids_b) = (solids_of(a), solids_of(b));
    let mut least = f64::INFINITY;
    for sa in &solids_a {
        for sb in &solids_b {
            least = least.min(signed_distance(sa, sb).0);
        }
    }
    least
}

/// The penetration depth of bodies `a` and `b` by this oracle (0 when
/// apart).
pub fn body_depth(a: &Body, b: &Body) -> f64 {
    let (solids_a, solids_b) = (solids_of(a), solids_of(b));
    let mut deepest: f64 = 0.0;
    for sa in &solids_a {
        for sb in &solids_b {
            deepest = deepest.max(depth(sa, sb));
        }
    }
    deepest
}
