//! The exact penetration depth of two convex polyhedra and the feature pair
//! that realizes it (the minimum translation), found by a local search from
//! V-Clip's deepest vertex.
//!
//! # The quantity
//! Translating A by `t n` (unit `n`) separates it from B once
//! `t >= d(n) = h_B(n) + h_A(-n)`, with `h_X(n) = max_{x in X} n . x` the
//! support function. `d` is the support function of the Minkowski difference
//! `D = B - A`, which contains the origin when the bodies overlap, and the
//! penetration depth is `min_n d(n)`: the distance from the origin to the
//! boundary of `D`. That minimum is attained at the normal of a facet of `D`
//! (the facet whose plane is nearest the origin contains its foot point), and
//! the facets of `D` are exactly (the separating-axis theorem for polytopes):
//! - a face of B with the vertex of A deepest below it (`n` = the face's
//!   outward normal),
//! - a face of A with the vertex of B deepest below it (`n` = minus the
//!   face's outward normal), and
//! - an edge of A and an edge of B whose Gauss-map arcs cross (`n` along
//!   `e_a x e_b`, where the arc of B's edge meets the mirrored arc of A's).
//!
//! # The search
//! 1. **Seed.** V-Clip's deepest vertex–face pair (with its face
//!    refinement) gives an axis and a depth `d*`, an upper bound.
//! 2. **A cap that must hold the answer.** A contains the ball of radius
//!    `r_a` (its inradius) about its centre of mass, B the ball `r_b` about
//!    its own, at `c` in A's frame (A's centre at the origin). Hence
//!    `d(n) >= r_a + r_b + n . c` for every unit `n`, and an axis can only
//!    beat `d*` inside the spherical cap `n . c <= d* - r_a - r_b`.
//! 3. **Walk the Gauss maps inside the cap.** From the arcs at the seed's
//!    features (the edges of its face, the edges at the support vertices),
//!    a breadth-first walk visits the arcs of each body that meet the cap,
//!    moving to arcs that share a face (an end) or a vertex (a cell). Every
//!    face whose normal lies in the cap and every crossing pair of visited
//!    arcs is evaluated, `d(n)` by hill-climbing the two supports (warm from
//!    the last support vertex), and the least is kept. A body of at most
//!    [`ARC_SCAN_MAX_EDGES`] edges has every arc tested against the cap
//!    instead of walked: on boxes and small hulls the cap holds about half
//!    of the arcs, and the walk's bookkeeping costs more than the tests it
//!    saves.
//!
//! **It terminates**: each arc is visited once, each candidate evaluated
//! once, and each support climb strictly increases its objective.
//! **Its answer is the minimum**: every facet normal with `d(n) < d*` lies in
//! the cap (step 2). The arcs of one body that meet a convex cap form a
//! connected graph under "shares a face or a vertex": a path inside the cap
//! between two of them crosses a sequence of vertex cells, and consecutive
//! crossings are arcs of one cell (one vertex) or meet at a face normal. The
//! walk starts from arcs that meet the cap: the seed axis `n*` is in the
//! (closed) cap because `d(n*) = d* >= r_a + r_b + n* . c`; it ends the arcs
//! of the seed face and lies in the cell of each support vertex, and a
//! convex cap that holds a point of a cell and meets any arc meets an arc of
//! that cell. So every facet of `D` that could be shallower is evaluated.
//! **Ties**: a candidate replaces the best only if it is shallower by more
//! than [`DEPTH_TIE_RELATIVE`] of the pair's scale, or within that and
//! earlier in a fixed order (faces of B, faces of A, edge pairs; then by
//! index), so that a face contact is not replaced by an edge pair of the
//! same depth (a box resting on another), and so that the choice among
//! equally deep axes does not depend on where the walk started, except for
//! depths within rounding of one another (see [`DEPTH_TIE_RELATIVE`]).
//!
//! The cap is only as tight as the balls are round: for flat or long bodies
//! it is wide and the walk visits more arcs. Its cost is measured by
//! `benchmarks/contact_depth.rs` (`benchmarks/results/contact_depth.md`).
//!
//! Nearly parallel edges (the sine of their angle below
//! [`EDGE_PARALLEL_SINE`]) are skipped: their cross product is too short to
//! give a direction, and the facet they span is a sliver between the facets
//! of the neighbouring faces, which are evaluated.

use std::cell::Cell;

use nalgebra::{Isometry3, Matrix3, Vector3};

use super::gauss_map::GreatArc;
use crate::geometry::{ConvexPolyhedron, Feature, Plane};
use crate::vclip::{BodyRole, DeepestVertex, descend};

/// Edge pairs whose directions make an angle with sine below this are not
/// candidate axes (their facet of `B - A` is a sliver; the neighbouring face
/// axes stand for it). Dimensionless: the error of the normalized cross
/// product is about `f64::EPSILON / sine`, 2e-9 at this threshold.
pub const EDGE_PARALLEL_SINE: f64 = 1e-7;

/// Two candidate depths closer than this fraction of the pair's scale (the
/// smaller circumradius) are a tie, broken by a fixed order of the features.
/// Rounding in a depth is about 1e-16 of the distances involved.
pub const DEPTH_TIE_RELATIVE: f64 = 1e-12;

/// An edge–edge minimum translation is built into a manifold on the best
/// face axis instead when that face's depth is within this fraction of the
/// exact depth (plus [`FACE_PREFERENCE_ABSOLUTE_RELATIVE`] of the scale), or
/// when the face's normal is within the angle of [`FACE_ALIGNMENT_COS`] of
/// the exact normal. Two nearly parallel faces pressed together (a box
/// resting on a box with a small relative tilt) have an edge–edge axis a
/// hair shallower than the face axis, spanned by two edges that cross at a
/// small angle; the row of that edge pair is a poor model (its crossing
/// point slides by the motion divided by the sine of that angle), and a
/// single row tilts the box pass after pass where the face manifold lifts
/// it flat (measured on the demo scene:
/// `benchmarks/results/contact_geometry.md`, "The face preference"). The
/// face rows are raised so that they ask for the exact depth, not the
/// face's, and the edge–edge row is kept beside them (see
/// [`super::manifold`]). Game engines prefer faces the same way
/// (D. Gregorius, "Robust contact creation for physics simulations", GDC
/// 2015).
pub const FACE_PREFERENCE_RELATIVE: f64 = 0.05;

/// The largest ratio of the face depth to the exact (edge–edge) depth for
/// which an aligned face ([`FACE_ALIGNMENT_COS`]) carries the manifold. A
/// face much deeper than the exact depth (a corner of a tilted box hanging
/// past the other's edge, far below its face plane) does not describe the
/// contact.
pub const FACE_ALIGNED_MAX_RATIO: f64 = 4.0;

/// Cosine of the largest angle between the exact (edge–edge) normal and the
/// best face normal for which the manifold is built on the face (see
/// [`FACE_PREFERENCE_RELATIVE`]): 0.1 rad. Crossing boxes, whose edge–edge
/// normals are tens of degrees from every face normal, keep their
/// edge–edge row.
pub const FACE_ALIGNMENT_COS: f64 = 0.995_004_165_278_025_8;

/// The absolute part of the face preference, relative to the pair's scale
/// (the smaller circumradius).
pub const FACE_PREFERENCE_ABSOLUTE_RELATIVE: f64 = 1e-6;

/// Bodies with at most this many edges have every arc tested against the
/// cap instead of walked from the seed: on the piles' boxes and small
/// hulls the cap holds about half of the arcs, and the walk's bookkeeping
/// (a mark per edge, a queue, eight to fourteen neighbours per arc found)
/// cost more than testing the arcs it skips (`arcs_in_cap`; measured with
/// callgrind on the engine states and the Rapier pile of 1,000
/// mid-settle: `benchmarks/results/call_cost.md`, twenty-first session).
/// Larger bodies keep the walk: a round body of many faces (the
/// 642-vertex sphere of `benchmarks/contact_depth.rs`) has a tight cap
/// that holds few of its arcs. The engine states' hulls have up to 22
/// vertices (about 60 edges); where between 48 and the sphere's 1,920
/// edges the scan starts to lose was not measured.
pub const ARC_SCAN_MAX_EDGES: usize = 48;

/// Whether the search tests every arc of `poly` against its cap (at most
/// [`ARC_SCAN_MAX_EDGES`] edges) rather than walking it.
pub fn scans_cap(poly: &ConvexPolyhedron) -> bool {
    poly.edges().len() <= ARC_SCAN_MAX_EDGES
}

/// Which features realize the minimum translation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PenetrationFeatures {
    /// A face of B (the reference face) with A's deepest vertex below it.
    FaceOfB {
        /// Face index in B.
        face_b: usize,
    },
    /// A face of A (the reference face) with B's deepest vertex below it.
    FaceOfA {
        /// Face index in A.
        face_a: usize,
    },
    /// An edge of A crossing an edge of B.
    EdgeEdge {
        /// Edge index in A.
        edge_a: usize,
        /// Edge index in B.
        edge_b: usize,
    },
    /// A pair with a round part (`contact::round`): the cores' features
    /// do not name the contact on the surfaces.
    Round,
}

impl PenetrationFeatures {
    /// A short name for logs and reports: `vertex_a_face_b` (a vertex of A
    /// below a face of B), `face_a_vertex_b`, `edge_edge`.
    pub fn kind(&self) -> &'static str {
        match self {
            PenetrationFeatures::FaceOfB { .. } => "vertex_a_face_b",
            PenetrationFeatures::FaceOfA { .. } => "face_a_vertex_b",
            PenetrationFeatures::EdgeEdge { .. } => "edge_edge",
            PenetrationFeatures::Round => "round",
        }
    }
}

/// An axis of the separating-axis test, evaluated: its features, the
/// overlap along it, and the support vertices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactAxis {
    /// The features that span the axis.
    pub features: PenetrationFeatures,
    /// Overlap along the axis (length, `>= 0`): translating A by
    /// `depth * normal_world` makes the bodies touch.
    pub depth: f64,
    /// Unit direction, world frame, from B towards A.
    pub normal_world: Vector3<f64>,
    /// Vertex of A deepest along `-normal_world` (A's support in that
    /// direction).
    pub support_a: usize,
    /// Vertex of B deepest along `normal_world`.
    pub support_b: usize,
}

/// The minimum translation of a penetrating pair, and the axis its contact
/// manifold is built on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Penetration {
    /// The minimum translation: `exact.depth` is the penetration depth.
    pub exact: ContactAxis,
    /// The axis of the contact manifold: `exact`, or a face axis nearly as
    /// shallow when `exact` is edge–edge (see [`FACE_PREFERENCE_RELATIVE`]).
    pub reference: ContactAxis,
    /// Candidate axes evaluated (cost indicator).
    pub candidates: usize,
}

impl Penetration {
    /// How much deeper the reference axis is than the exact one (0 when they
    /// are the same): the most the manifold raises its rows by, so that they
    /// ask for the exact depth along the reference normal.
    pub fn reference_offset(&self) -> f64 {
        (self.reference.depth - self.exact.depth).max(0.0)
    }

    /// The penetration depth.
    pub fn depth(&self) -> f64 {
        self.exact.depth
    }

    /// The direction of the minimum translation (world, from B to A).
    pub fn normal_world(&self) -> Vector3<f64> {
        self.exact.normal_world
    }

    /// The features of the minimum translation.
    pub fn features(&self) -> PenetrationFeatures {
        self.exact.features
    }
}

/// One body seen from A's frame. `sign` is +1 for B (its Gauss map) and -1
/// for A (the mirrored map, so that both maps hold the axis `n` itself).
/// A's frame is its own: `rotation` is `None` for A, and its images,
/// directions and points are its own vectors (no product with the
/// identity).
struct View<'a> {
    poly: &'a ConvexPolyhedron,
    rotation: Option<Matrix3<f64>>,
    translation: Vector3<f64>,
    sign: f64,
    /// The face images computed so far (NaN: not yet), on a body of at
    /// most [`ARC_SCAN_MAX_EDGES`] edges (empty above): every arc reads the
    /// images of its two faces, and a face borders several arcs that the
    /// scan and the edge pairs test. A large body's walk reads few of its
    /// faces, fewer than a cache of all of them would cost to set up.
    images: Vec<Cell<Vector3<f64>>>,
}

impl<'a> View<'a> {
    fn new(
        poly: &'a ConvexPolyhedron,
        rotation: Option<Matrix3<f64>>,
        translation: Vector3<f64>,
        sign: f64,
    ) -> Self {
        View {
            poly,
            rotation,
            translation,
            sign,
            images: match scans_cap(poly) {
                true => vec![Cell::new(Vector3::repeat(f64::NAN)); poly.faces().len()],
                false => Vec::new(),
            },
        }
    }

    /// `v` in A's frame (a direction of the body's own frame).
    fn rotate(&self, v: &Vector3<f64>) -> Vector3<f64> {
        match &self.rotation {
            Some(rotation) => rotation * v,
            None => *v,
        }
    }

    fn image(&self, face: usize) -> Vector3<f64> {
        let cell = self.images.get(face);
        if let Some(cached) = cell.map(Cell::get).filter(|c| !c.x.is_nan()) {
            return cached;
        }
        let image = self.rotate(&self.poly.faces()[face].plane.normal) * self.sign;
        if let Some(cell) = cell {
            cell.set(image);
        }
        image
    }

    fn arc(&self, edge: usize) -> GreatArc {
        let e = &self.poly.edges()[edge];
        GreatArc {
            from: self.image(e.left_face),
            to: self.image(e.right_face),
        }
    }

    fn direction(&self, edge: usize) -> Vector3<f64> {
        self.rotate(&self.poly.edges()[edge].direction)
    }

    /// `max_v dir . v` over the body's vertices (A's frame), by hill
    /// climbing from `start`.
    fn support(&self, dir: &Vector3<f64>, start: usize) -> (usize, f64) {
        let dir_body = match &self.rotation {
            Some(rotation) => rotation.tr_mul(dir),
            None => *dir,
        };
        let plane = Plane {
            normal: -dir_body,
            offset: 0.0,
        };
        let (vertex, height) = descend(self.poly, &plane, start);
        (vertex, dir.dot(&self.translation) - height)
    }

    /// Vertex `v` in A's frame.
    fn point(&self, v: usize) -> Vector3<f64> {
        self.rotate(&self.poly.vertices()[v].coords) + self.translation
    }

    /// The edges around vertex `v` and, for a face, its boundary.
    fn edges_at_vertex(&self, v: usize) -> &[usize] {
        self.poly.vertex_edges(v)
    }
}

/// An edge that may span the best axis, with its arc and direction in
/// A's frame: every edge of one body is tested against every edge of the
/// other, so each is computed once.
struct EdgeImage {
    edge: usize,
    arc: GreatArc,
    direction: Vector3<f64>,
}

/// A candidate axis, evaluated.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    features: PenetrationFeatures,
    depth: f64,
    /// Unit, A's frame, from B towards A.
    normal: Vector3<f64>,
    supports: [usize; 2],
}

struct Search<'a> {
    views: [View<'a>; 2],
    /// B's centre of mass in A's frame.
    centre_b: Vector3<f64>,
    /// `r_a + r_b`.
    radii: f64,
    /// `[r_a, r_b]`.
    inradii: [f64; 2],
    tie: f64,
    best: Candidate,
    /// The shallowest face axis (for the manifold's face preference).
    best_face: Candidate,
    /// Last support vertex of each body: the start of the next climb.
    hints: [usize; 2],
    evaluated: usize,
}

/// The minimum translation of A out of B, from V-Clip's deepest vertex
/// `seed` of the same poses.
pub fn minimum_translation(
    poly_a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    poly_b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
    seed: &DeepestVertex,
) -> Penetration {
    let (face_body, vertex_body) = match seed.vertex_body {
        BodyRole::A => (1, 0),
        BodyRole::B => (0, 1),
    };
    let poly = |body: usize| if body == 0 { poly_a } else { poly_b };
    let mut hints = [0, 0];
    hints[vertex_body] = seed.vertex;
    hints[face_body] = poly(face_body).faces()[seed.face].vertices[0];
    search_from(
        poly_a,
        pose_a,
        poly_b,
        pose_b,
        (face_body, seed.face),
        hints,
        true,
    )
}

/// The separating axis of two separated (or touching) bodies with the
/// largest gap, by the same search (the cap bound holds for any sign of
/// `d`), from the closest features `features` of V-Clip: `-depth` of the
/// answer is the gap along its axis, at most the distance. The contact
/// manifold of a near pair is built on it.
pub fn widest_separation(
    poly_a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    poly_b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
    features: [Feature; 2],
    near_faces: bool,
) -> Penetration {
    let polys = [poly_a, poly_b];
    let (face_body, face) = match features {
        [_, Feature::Face(f)] => (1, f),
        [Feature::Face(f), _] => (0, f),
        [_, Feature::Edge(e)] => (1, poly_b.edges()[e].left_face),
        [Feature::Edge(e), _] => (0, poly_a.edges()[e].left_face),
        [_, Feature::Vertex(v)] => (1, poly_b.edges()[poly_b.vertex_edges(v)[0]].left_face),
    };
    let hint = |body: usize| match features[body] {
        Feature::Vertex(v) => v,
        Feature::Edge(e) => polys[body].edges()[e].tail,
        Feature::Face(f) => polys[body].faces()[f].vertices[0],
    };
    search_from(
        poly_a,
        pose_a,
        poly_b,
        pose_b,
        (face_body, face),
        [hint(0), hint(1)],
        near_faces,
    )
}

/// Whether the best face axis (`face_depth`) is close enough to the exact
/// edge–edge axis (`exact_depth`) to carry the manifold, and whether it is
/// bounded for an aligned face (see [`FACE_PREFERENCE_RELATIVE`] and
/// [`FACE_ALIGNED_MAX_RATIO`]). The face is always the shallower axis
/// (`face_depth >= exact_depth`). For a penetrating pair the tests are
/// ratios of depths; for a separated one (negative depths: the gaps along
/// the axes, the exact axis the widest) the same ratios of gaps: the face
/// may keep a gap `FACE_PREFERENCE_RELATIVE` narrower than the widest, or
/// a quarter of it when aligned. Written with the depths' signs, the
/// penetrating tests read wrongly for gaps: the face of two level boxes a
/// hair apart is then never preferred, and their single edge–edge row lets
/// a step tilt one into the other (stacks take extra passes of short
/// line-search steps; `CHANGELOG.md`, 2026-12-02). `gap_ratios = false`
/// keeps the penetrating tests for gaps too, so that a near pair's
/// manifold stays on its widest separating axis
/// ([`crate::Settings::near_pair_faces`] off).
fn face_preference(
    face_depth: f64,
    exact_depth: f64,
    scale: f64,
    gap_ratios: bool,
) -> (bool, bool) {
    let absolute = FACE_PREFERENCE_ABSOLUTE_RELATIVE * scale;
    if exact_depth >= 0.0 || !gap_ratios {
        (
            face_depth <= exact_depth * (1.0 + FACE_PREFERENCE_RELATIVE) + absolute,
            face_depth <= exact_depth * FACE_ALIGNED_MAX_RATIO + absolute,
        )
    } else {
        (
            face_depth <= exact_depth * (1.0 - FACE_PREFERENCE_RELATIVE) + absolute,
            face_depth <= exact_depth / FACE_ALIGNED_MAX_RATIO + absolute,
        )
    }
}

/// The search of the module docs from the face axis `seed` (body, face),
/// with support climbs starting at `hints`.
fn search_from(
    poly_a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    poly_b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
    seed: (usize, usize),
    hints: [usize; 2],
    gap_ratios: bool,
) -> Penetration {
    let b_in_a = pose_a.inv_mul(pose_b);
    let views = [
        View::new(poly_a, None, Vector3::zeros(), -1.0),
        View::new(
            poly_b,
            Some(b_in_a.rotation.to_rotation_matrix().into_inner()),
            b_in_a.translation.vector,
            1.0,
        ),
    ];
    let (face_body, seed_face) = seed;
    let seed_features = face_features(face_body, seed_face);
    let unevaluated = Candidate {
        features: seed_features,
        depth: f64::INFINITY,
        normal: Vector3::zeros(),
        supports: [0, 0],
    };
    let mut search = Search {
        centre_b: views[1].translation,
        radii: poly_a.inradius() + poly_b.inradius(),
        inradii: [poly_a.inradius(), poly_b.inradius()],
        tie: DEPTH_TIE_RELATIVE * poly_a.scale().min(poly_b.scale()),
        views,
        best: unevaluated,
        best_face: unevaluated,
        hints,
        evaluated: 0,
    };
    let seed_axis = search.face_axis(face_body, seed_face);
    search.best = search.evaluate(seed_features, seed_axis);
    search.best_face = search.best;
    search.walk_cap(face_body, seed_face);
    let scale = poly_a.scale().min(poly_b.scale());
    let exact = search.best;
    let face_aligned = search.best_face.normal.dot(&exact.normal) >= FACE_ALIGNMENT_COS;
    let is_edge = matches!(exact.features, PenetrationFeatures::EdgeEdge { .. });
    let (face_close, face_bounded) =
        face_preference(search.best_face.depth, exact.depth, scale, gap_ratios);
    let reference = if is_edge && (face_close || (face_aligned && face_bounded)) {
        search.best_face
    } else {
        exact
    };
    let axis = |candidate: Candidate| ContactAxis {
        features: candidate.features,
        depth: candidate.depth,
        normal_world: pose_a.rotation * candidate.normal,
        support_a: candidate.supports[0],
        support_b: candidate.supports[1],
    };
    Penetration {
        exact: axis(exact),
        reference: axis(reference),
        candidates: search.evaluated,
    }
}

fn face_features(body: usize, face: usize) -> PenetrationFeatures {
    if body == 0 {
        PenetrationFeatures::FaceOfA { face_a: face }
    } else {
        PenetrationFeatures::FaceOfB { face_b: face }
    }
}

impl Search<'_> {
    fn face_axis(&self, body: usize, face: usize) -> Vector3<f64> {
        self.views[body].image(face)
    }

    /// `d(n)` and the support vertices, climbing from the hints.
    fn evaluate(&mut self, features: PenetrationFeatures, normal: Vector3<f64>) -> Candidate {
        self.evaluated += 1;
        let (vertex_b, h_b) = self.views[1].support(&normal, self.hints[1]);
        let (vertex_a, h_a) = self.views[0].support(&-normal, self.hints[0]);
        self.hints = [vertex_a, vertex_b];
        Candidate {
            features,
            depth: h_b + h_a,
            normal,
            supports: [vertex_a, vertex_b],
        }
    }

    /// Whether `candidate` replaces `best` (shallower, or tied and first in
    /// the fixed order).
    fn replaces(&self, candidate: &Candidate, best: &Candidate) -> bool {
        let shallower = candidate.depth < best.depth - self.tie;
        let tied_first =
            candidate.depth <= best.depth + self.tie && candidate.features < best.features;
        shallower || tied_first
    }

    /// A lower bound of `d(n)` for the axis of face `face` of `body`: that
    /// body's support along the axis is the face itself, the other body's
    /// is at least its inradius about its centre of mass.
    fn face_bound(&self, body: usize, face: usize) -> f64 {
        let view = &self.views[body];
        let normal = view.image(face);
        let on_face = view.point(view.poly.faces()[face].vertices[0]);
        if body == 1 {
            // h_B(n) = n . p_f, h_A(-n) >= r_a (A's centre is the origin).
            normal.dot(&on_face) + self.inradii[0]
        } else {
            // h_A(-n) = -n . p_f, h_B(n) >= r_b + n . c_b.
            normal.dot(&(self.centre_b - on_face)) + self.inradii[1]
        }
    }

    /// Whether the lower bound of `d(n)` over the axes on the arc of
    /// `edge` of `body` is below `threshold`: that body's support along
    /// them is the edge itself (the arc is where the edge supports it), the
    /// other body's at least its inradius about its centre of mass, so the
    /// bound is the arc's least `n . p` (`p` a point of the edge, or
    /// `c_b - p` for A) plus that inradius.
    fn edge_may_beat(&self, body: usize, edge: usize, threshold: f64) -> bool {
        let view = &self.views[body];
        let on_edge = view.point(view.poly.edges()[edge].tail);
        let arc = view.arc(edge);
        let t = if body == 1 {
            on_edge
        } else {
            self.centre_b - on_edge
        };
        let inradius = self.inradii[1 - body];
        arc.dips(&t, |linear| linear + inradius < threshold)
    }

    fn consider_face(&mut self, body: usize, face: usize) {
        if self.face_bound(body, face) >= self.best_face.depth + self.tie {
            return;
        }
        let candidate = self.evaluate(face_features(body, face), self.face_axis(body, face));
        if self.replaces(&candidate, &self.best) {
            self.best = candidate;
        }
        if self.replaces(&candidate, &self.best_face) {
            self.best_face = candidate;
        }
    }

    /// An edge pair whose arcs cross at `normal`: the edges are the two
    /// supports there, so `d = n . (p_b - p_a)` for any points of them.
    fn consider_edges(&mut self, edge_a: usize, edge_b: usize, normal: Vector3<f64>) {
        self.evaluated += 1;
        let tails = [
            self.views[0].poly.edges()[edge_a].tail,
            self.views[1].poly.edges()[edge_b].tail,
        ];
        let depth = normal.dot(&(self.views[1].point(tails[1]) - self.views[0].point(tails[0])));
        let features = PenetrationFeatures::EdgeEdge { edge_a, edge_b };
        let mut candidate = Candidate {
            features,
            depth,
            normal,
            supports: tails,
        };
        if !self.replaces(&candidate, &self.best) {
            return;
        }
        // The crossing test is ill-conditioned on a thin body, whose edge
        // arcs span nearly half a circle: a crossing it reports may be
        // false, and `n . (p_b - p_a)` then falls below the overlap along
        // `n` (the kept fuzz input
        // tests/data/fuzz/vclip_depth/crash-negative-depth;
        // benchmarks/results/fuzzing.md). The supports confirm it; the
        // overlap along any axis bounds the depth from above, so the
        // confirmed value is never too small.
        let confirmed = self.evaluate(features, normal);
        if confirmed.depth > candidate.depth + self.tie {
            candidate = confirmed;
        }
        if self.replaces(&candidate, &self.best) {
            self.best = candidate;
        }
    }

    /// Step 3 of the module docs: every face and crossing edge pair whose
    /// Gauss image meets the cap of the current best, from the seed face
    /// `face` of body `face_body`.
    fn walk_cap(&mut self, face_body: usize, face: usize) {
        let limit = self.best.depth - self.radii;
        let scanned = self.views.each_ref().map(|view| scans_cap(view.poly));
        let arcs: [Vec<usize>; 2] = std::array::from_fn(|body| {
            let view = &self.views[body];
            if scanned[body] {
                return scan_arcs_in_cap(view, &self.centre_b, limit);
            }
            let mut starts: Vec<usize> = view.edges_at_vertex(self.best.supports[body]).to_vec();
            if body == face_body {
                starts.extend_from_slice(&view.poly.faces()[face].edges);
            }
            arcs_in_cap(view, &self.centre_b, limit, &starts)
        });
        for (body, body_arcs) in arcs.iter().enumerate() {
            let faces = if scanned[body] {
                scan_faces_in_cap(&self.views[body], &self.centre_b, limit)
            } else {
                faces_in_cap(&self.views[body], body_arcs, &self.centre_b, limit)
            };
            for face in faces {
                self.consider_face(body, face);
            }
        }
        // Only edges whose own bound can still beat the best can span it.
        let promising = |search: &Self, body: usize, found: &[usize]| -> Vec<EdgeImage> {
            let threshold = search.best.depth + search.tie;
            let view = &search.views[body];
            found
                .iter()
                .copied()
                .filter(|&edge| search.edge_may_beat(body, edge, threshold))
                .map(|edge| EdgeImage {
                    edge,
                    arc: view.arc(edge),
                    direction: view.direction(edge),
                })
                .collect()
        };
        let edges_a = promising(self, 0, &arcs[0]);
        let edges_b = promising(self, 1, &arcs[1]);
        for edge_a in &edges_a {
            for edge_b in &edges_b {
                if let Some(normal) = crossing(edge_a, edge_b) {
                    self.consider_edges(edge_a.edge, edge_b.edge, normal);
                }
            }
        }
    }
}

/// The axis where the arcs of `edge_a` (A's, mirrored) and `edge_b` cross.
fn crossing(edge_a: &EdgeImage, edge_b: &EdgeImage) -> Option<Vector3<f64>> {
    let cross = edge_a.direction.cross(&edge_b.direction);
    let sine = cross.norm();
    if sine < EDGE_PARALLEL_SINE {
        return None;
    }
    let axis = cross / sine;
    [axis, -axis]
        .into_iter()
        .find(|n| edge_a.arc.contains(n) && edge_b.arc.contains(n))
}

/// Every arc of `view` that meets the cap `n . centre <= limit`, ascending,
/// each arc tested in turn (bodies of at most [`ARC_SCAN_MAX_EDGES`]
/// edges).
///
/// The arcs that meet the cap are connected (module docs), so the scan
/// finds the walk's arcs ([`arcs_in_cap`]); where rounding would
/// disconnect one, the scan also finds it, and an extra arc only adds
/// candidates, each evaluated exactly: the least depth found can only be
/// the same or smaller.
fn scan_arcs_in_cap(view: &View, centre: &Vector3<f64>, limit: f64) -> Vec<usize> {
    (0..view.poly.edges().len())
        .filter(|&edge| view.arc(edge).dips(centre, |value| value <= limit))
        .collect()
}

/// Every face of `view` whose axis lies in the cap, ascending: the faces
/// [`faces_in_cap`] takes from the scanned arcs (a face in the cap is an
/// end, inside the cap, of each of its arcs, so all of them were found).
fn scan_faces_in_cap(view: &View, centre: &Vector3<f64>, limit: f64) -> Vec<usize> {
    (0..view.poly.faces().len())
        .filter(|&face| view.image(face).dot(centre) <= limit)
        .collect()
}

/// The arcs of `view` that meet the cap `n . centre <= limit`, reachable
/// from `starts` through arcs that meet it (breadth first).
fn arcs_in_cap(view: &View, centre: &Vector3<f64>, limit: f64, starts: &[usize]) -> Vec<usize> {
    let poly = view.poly;
    // Each arc is tested once: `tested` holds the arcs whose test ran,
    // whatever its result.
    let mut tested = vec![false; poly.edges().len()];
    let mut meets = |edge: usize| {
        let first = !tested[edge];
        tested[edge] = true;
        first && view.arc(edge).dips(centre, |value| value <= limit)
    };
    let mut found = Vec::with_capacity(poly.edges().len());
    let mut queue = std::collections::VecDeque::with_capacity(poly.edges().len());
    for &edge in starts {
        if meets(edge) {
            queue.push_back(edge);
        }
    }
    while let Some(edge) = queue.pop_front() {
        found.push(edge);
        let e = &poly.edges()[edge];
        let neighbours = poly.faces()[e.left_face]
            .edges
            .iter()
            .chain(&poly.faces()[e.right_face].edges)
            .chain(poly.vertex_edges(e.tail))
            .chain(poly.vertex_edges(e.head));
        for &next in neighbours {
            if meets(next) {
                queue.push_back(next);
            }
        }
    }
    found.sort_unstable();
    found
}

/// The faces at the ends of `arcs` whose axis lies in the cap, ascending.
fn faces_in_cap(view: &View, arcs: &[usize], centre: &Vector3<f64>, limit: f64) -> Vec<usize> {
    let mut faces: Vec<usize> = arcs
        .iter()
        .flat_map(|&edge| {
            let e = &view.poly.edges()[edge];
            [e.left_face, e.right_face]
        })
        .filter(|&face| view.image(face).dot(centre) <= limit)
        .collect();
    faces.sort_unstable();
    faces.dedup();
    faces
}
