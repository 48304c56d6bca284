//! The demonstration scene: a pile of boxes and convex hulls on a fixed
//! ground, overlapping by a few percent of their size, as after a simulation
//! step that went slightly wrong. Feature `demo`.
//!
//! # Layout
//!
//! Bodies are generated one by one (shape, orientation, mass), then stacked
//! into *columns* of 1 to [`MAX_STACK_HEIGHT`] bodies: each body is dropped
//! along `-y` onto the column (a parry3d-f64 shape cast against the bodies
//! already in it) or onto the ground (top face `y = 0`), whichever it
//! meets first, and then sunk by [`OVERLAP_MIN`]..[`OVERLAP_MAX`] of the
//! smaller height of it and what it landed on. Columns are laid out in rows
//! along `x`; consecutive columns form *clusters* of 1 to
//! [`MAX_CLUSTER_COLUMNS`] columns: a column slides along `-x` until it
//! touches the cluster, then on by the same fraction of the width of the
//! first two bodies that touch. Clusters and rows are separated by
//! [`CLUSTER_GAP`].
//!
//! Every penetration is thus a few percent of a body's size, and islands
//! (which the fixed ground does not join) are bounded by a cluster: at most
//! `MAX_STACK_HEIGHT * MAX_CLUSTER_COLUMNS` bodies. Their number grows
//! linearly with the body count.
//!
//! # Shapes
//!
//! - Boxes: half extents `s * a_k` with size `s` in [`SIZE_MIN`]..[`SIZE_MAX`]
//!   and aspect `a_k` in 0.6..1.4; yaw up to [`MAX_YAW`], tilt up to [`MAX_TILT`];
//!   given by density.
//! - Hulls: 4 to 30 points: a jittered regular tetrahedron (so the hull has
//!   volume) plus points on or inside an ellipsoid of radii `s * a_k`, all
//!   shifted by a random offset so that the shape frame is not the centre of
//!   mass; any orientation; given by mass.
//!
//! Everything comes from one `ChaCha8Rng` seeded with `seed`: the scene is
//! the same on every platform and run.

use nalgebra::{Point3, UnitQuaternion, Vector3};
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::query::{ShapeCastOptions, cast_shapes};
use parry3d_f64::shape::{ConvexPolyhedron as ParryHull, Cuboid};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::body::{Body, BodyDesc, MassSpec, Shape};
use crate::scene::Scene;

/// Body count of the default demonstration (ground included).
pub const DEFAULT_BODY_COUNT: usize = 300;
/// Seed of the default demonstration.
pub const DEFAULT_SEED: u64 = 2026;
/// Most bodies in one column.
pub const MAX_STACK_HEIGHT: usize = 5;
/// Most columns in one cluster.
pub const MAX_CLUSTER_COLUMNS: usize = 4;
/// Smallest overlap of neighbouring AABBs, as a fraction of the smaller extent.
pub const OVERLAP_MIN: f64 = 0.01;
/// Largest overlap of neighbouring AABBs, as a fraction of the smaller extent.
pub const OVERLAP_MAX: f64 = 0.05;
/// Smallest body size (half extent or ellipsoid radius before aspect).
pub const SIZE_MIN: f64 = 0.15;
/// Largest body size.
pub const SIZE_MAX: f64 = 0.5;
/// Gap between clusters and between rows (length).
pub const CLUSTER_GAP: f64 = 0.4;
/// Largest tilt of a box from upright (radians).
pub const MAX_TILT: f64 = 0.08;
/// Largest yaw of a box about the vertical (radians): boxes stay roughly
/// aligned, as in a pile that was stacked and then disturbed, so that
/// neighbours in a cluster meet face to face.
pub const MAX_YAW: f64 = 0.35;
/// Share of hulls among the dynamic bodies.
pub const HULL_SHARE: f64 = 0.4;
/// Half height of the ground box.
pub const GROUND_HALF_HEIGHT: f64 = 0.5;

/// Largest sideways offset of a piece from its column's axis, as a
/// fraction of its extent.
pub const COLUMN_JITTER: f64 = 0.05;
/// Distance a piece starts away from what it is moved against.
const CAST_CLEARANCE: f64 = 1.0;
/// Longest shape cast (length): the clearance plus the largest possible
/// body extent, with room to spare.
const CAST_RANGE: f64 = 4.0 * CAST_CLEARANCE + 8.0 * SIZE_MAX;

/// A generated body being placed: `min`/`max` bound the rotated shape
/// relative to `desc.translation`; `collider` is the same shape for parry's
/// shape casts (shape frame).
struct Piece {
    desc: BodyDesc,
    rotation: UnitQuaternion<f64>,
    collider: Box<dyn parry3d_f64::shape::Shape>,
    min: Vector3<f64>,
    max: Vector3<f64>,
}

impl Piece {
    fn extent(&self) -> Vector3<f64> {
        self.max - self.min
    }

    fn world_min(&self) -> Vector3<f64> {
        self.desc.translation + self.min
    }

    fn world_max(&self) -> Vector3<f64> {
        self.desc.translation + self.max
    }

    /// The user pose (shape frame in world) as a parry pose.
    fn pose(&self) -> Pose {
        let t = self.desc.translation;
        let q = self.rotation.quaternion();
        Pose::from_parts(
            Vector::new(t.x, t.y, t.z),
            Rotation::from_xyzw(q.i, q.j, q.k, q.w),
        )
    }
}

/// A column of pieces, bottom first, and its footprint.
struct Column {
    pieces: Vec<Piece>,
    width: f64,
    depth: f64,
}

/// What a generated pile may vary: the overlap range and the share of
/// hulls. [`Default`] gives the demonstration's constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DemoOptions {
    /// Smallest overlap of neighbours, fraction of the smaller extent.
    pub overlap_min: f64,
    /// Largest overlap of neighbours, fraction of the smaller extent
    /// (greater than `overlap_min`).
    pub overlap_max: f64,
    /// Share of hulls among the dynamic bodies, in `[0, 1]`.
    pub hull_share: f64,
}

impl Default for DemoOptions {
    fn default() -> Self {
        DemoOptions {
            overlap_min: OVERLAP_MIN,
            overlap_max: OVERLAP_MAX,
            hull_share: HULL_SHARE,
        }
    }
}

/// The demonstration scene with `body_count` bodies in all: body 0 is the
/// fixed ground (if `body_count >= 1`), the others a pile on it.
pub fn demo_scene(body_count: usize, seed: u64) -> Scene {
    demo_scene_with(body_count, seed, &DemoOptions::default())
}

/// [`demo_scene`] with other overlaps or another share of hulls. Options
/// out of range are clamped: overlaps to `[0, 0.5]` (the larger one at
/// least the smaller plus 1e-9), the share to `[0, 1]`.
pub fn demo_scene_with(body_count: usize, seed: u64, options: &DemoOptions) -> Scene {
    let options = clamped(options);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let pieces: Vec<Piece> = (1..body_count)
        .map(|k| random_piece(&mut rng, k, options.hull_share))
        .collect();
    let columns = stack_into_columns(&mut rng, pieces, &options);
    let placed = lay_out(&mut rng, columns, &options);
    let mut scene = Scene::new();
    if body_count == 0 {
        return scene;
    }
    scene.push_body(ground(&placed));
    for piece in placed {
        scene.push_body(build(piece.desc));
    }
    log::debug!("demo scene: {} bodies, seed {seed}", scene.len());
    scene
}

/// Largest overlap fraction [`demo_scene_with`] accepts.
const OVERLAP_LIMIT: f64 = 0.5;
/// Smallest width of the overlap range.
const OVERLAP_RANGE_MIN: f64 = 1e-9;

/// The options within their ranges (NaN becomes the default).
fn clamped(options: &DemoOptions) -> DemoOptions {
    let default = DemoOptions::default();
    let finite = |v: f64, d: f64| if v.is_finite() { v } else { d };
    let overlap_min = finite(options.overlap_min, default.overlap_min).clamp(0.0, OVERLAP_LIMIT);
    let overlap_max = finite(options.overlap_max, default.overlap_max).clamp(
        overlap_min + OVERLAP_RANGE_MIN,
        OVERLAP_LIMIT + OVERLAP_RANGE_MIN,
    );
    DemoOptions {
        overlap_min,
        overlap_max,
        hull_share: finite(options.hull_share, default.hull_share).clamp(0.0, 1.0),
    }
}

fn random_piece(rng: &mut ChaCha8Rng, k: usize, hull_share: f64) -> Piece {
    let size = rng.random_range(SIZE_MIN..SIZE_MAX);
    let axes = Vector3::from_fn(|_, _| size * rng.random_range(0.6..1.4));
    if rng.random_bool(hull_share) {
        random_hull(rng, k, axes)
    } else {
        random_box(rng, k, axes)
    }
}

fn random_box(rng: &mut ChaCha8Rng, k: usize, half_extents: Vector3<f64>) -> Piece {
    let yaw =
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), rng.random_range(-MAX_YAW..MAX_YAW));
    let tilt_axis = Vector3::new(
        rng.random_range(-1.0..1.0),
        0.0,
        rng.random_range(-1.0..1.0),
    );
    let tilt = UnitQuaternion::from_scaled_axis(
        tilt_axis.try_normalize(0.0).unwrap_or_else(Vector3::x) * rng.random_range(0.0..MAX_TILT),
    );
    let rotation = tilt * yaw;
    let corners: Vec<Point3<f64>> = (0..8)
        .map(|i| {
            let sign = |bit: usize| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
            Point3::new(sign(0), sign(1), sign(2))
                .coords
                .component_mul(&half_extents)
                .into()
        })
        .collect();
    let density = rng.random_range(0.5..3.0);
    piece(
        format!("box-{k}"),
        Shape::Cuboid { half_extents },
        rotation,
        &corners,
        MassSpec::Density(density),
    )
}

const TAU: f64 = std::f64::consts::TAU;

fn random_hull(rng: &mut ChaCha8Rng, k: usize, radii: Vector3<f64>) -> Piece {
    let count = rng.random_range(4..=30usize);
    let offset = Vector3::from_fn(|_, _| rng.random_range(-0.3..0.3));
    // Regular tetrahedron (alternate cube corners), jittered by up to 10%.
    let tetrahedron = [
        [1.0, 1.0, 1.0],
        [1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
    ];
    let mut points: Vec<Point3<f64>> = tetrahedron
        .iter()
        .map(|c| {
            let jitter = Vector3::from_fn(|_, _| rng.random_range(-0.1..0.1));
            let unit = Vector3::from(*c) / 3f64.sqrt() + jitter;
            Point3::from(unit.component_mul(&radii) + offset)
        })
        .collect();
    while points.len() < count {
        let direction: Vector3<f64> = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let norm = direction.norm();
        if !(0.1..=1.0).contains(&norm) {
            continue; // rejection sampling of a uniform direction
        }
        let radius: f64 = rng.random_range(0.7..1.0);
        points.push(Point3::from(
            (direction / norm * radius).component_mul(&radii) + offset,
        ));
    }
    let rotation = random_rotation(rng);
    let mass = rng.random_range(0.2..5.0);
    piece(
        format!("hull-{k}"),
        Shape::ConvexHull {
            points: points.clone(),
        },
        rotation,
        &points,
        MassSpec::Mass(mass),
    )
}

/// A uniformly random rotation (Shoemake 1992, "Uniform random rotations").
fn random_rotation(rng: &mut ChaCha8Rng) -> UnitQuaternion<f64> {
    let (u1, u2, u3): (f64, f64, f64) = (
        rng.random_range(0.0..1.0),
        rng.random_range(0.0..TAU),
        rng.random_range(0.0..TAU),
    );
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        b * u3.cos(),
        a * u2.sin(),
        a * u2.cos(),
        b * u3.sin(),
    ))
}

fn piece(
    name: String,
    shape: Shape,
    rotation: UnitQuaternion<f64>,
    points_shape: &[Point3<f64>],
    mass: MassSpec,
) -> Piece {
    let mut min = Vector3::repeat(f64::INFINITY);
    let mut max = Vector3::repeat(f64::NEG_INFINITY);
    for p in points_shape {
        let p_rotated = rotation * p.coords;
        min = min.inf(&p_rotated);
        max = max.sup(&p_rotated);
    }
    let q = rotation.quaternion();
    Piece {
        collider: collider(&shape, points_shape),
        desc: BodyDesc {
            name,
            shape,
            translation: Vector3::zeros(),
            rotation_xyzw: [q.i, q.j, q.k, q.w],
            mass,
        },
        rotation,
        min,
        max,
    }
}

/// The parry shape of `shape` (its hull from `points_shape`), or, should
/// parry find the hull degenerate, the shape's bounding box.
fn collider(shape: &Shape, points_shape: &[Point3<f64>]) -> Box<dyn parry3d_f64::shape::Shape> {
    let glam = |p: &Point3<f64>| Vector::new(p.x, p.y, p.z);
    let points: Vec<Vector> = points_shape.iter().map(glam).collect();
    if let Shape::ConvexHull { .. } = shape
        && let Some(hull) = ParryHull::from_convex_hull(&points)
    {
        return Box::new(hull);
    }
    let half = points.iter().fold(Vector::ZERO, |acc, p| acc.max(p.abs()));
    Box::new(Cuboid::new(half))
}

fn overlap_fraction(rng: &mut ChaCha8Rng, options: &DemoOptions) -> f64 {
    rng.random_range(options.overlap_min..options.overlap_max)
}

/// How far `moving` can travel along the unit `direction` before it
/// touches one of `obstacles` (parry3d-f64 shape cast), and the obstacle it
/// touches first; `None` if it passes them all within [`CAST_RANGE`].
fn travel_until_contact<'a>(
    moving: &Piece,
    direction: Vector,
    obstacles: &'a [Piece],
) -> Option<(f64, &'a Piece)> {
    let options = ShapeCastOptions::with_max_time_of_impact(CAST_RANGE);
    let pose = moving.pose();
    obstacles
        .iter()
        .filter_map(|obstacle| {
            let hit = cast_shapes(
                &pose,
                direction,
                moving.collider.as_ref(),
                &obstacle.pose(),
                Vector::ZERO,
                obstacle.collider.as_ref(),
                options,
            );
            hit.ok().flatten().map(|h| (h.time_of_impact, obstacle))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// Stacks the pieces into columns, setting each piece's height (`y`): each
/// piece is dropped onto the column (or the ground, top face `y = 0`) and
/// then sunk by a few percent of its height.
fn stack_into_columns(
    rng: &mut ChaCha8Rng,
    pieces: Vec<Piece>,
    options: &DemoOptions,
) -> Vec<Column> {
    let mut columns = Vec::new();
    let mut pieces = pieces.into_iter().peekable();
    while pieces.peek().is_some() {
        let height = rng.random_range(1..=MAX_STACK_HEIGHT);
        let mut column: Vec<Piece> = Vec::new();
        for mut piece in pieces.by_ref().take(height) {
            // Centred on the column axis (x = z = 0) up to a small jitter.
            let jitter = piece.extent() * rng.random_range(-COLUMN_JITTER..COLUMN_JITTER);
            piece.desc.translation.x = jitter.x - (piece.min.x + piece.max.x) / 2.0;
            piece.desc.translation.z = jitter.z - (piece.min.z + piece.max.z) / 2.0;
            let top = column.iter().map(|p| p.world_max().y).fold(0.0, f64::max);
            piece.desc.translation.y = top + CAST_CLEARANCE - piece.min.y;
            let to_ground = piece.world_min().y;
            let (fall, below_height) = match travel_until_contact(&piece, -Vector::Y, &column) {
                Some((t, below)) if t < to_ground => (t, below.extent().y),
                _ => (to_ground, f64::INFINITY),
            };
            let sink = overlap_fraction(rng, options) * piece.extent().y.min(below_height);
            piece.desc.translation.y -= fall + sink;
            column.push(piece);
        }
        let width = column.iter().map(|p| p.extent().x).fold(0.0, f64::max);
        let depth = column.iter().map(|p| p.extent().z).fold(0.0, f64::max);
        columns.push(Column {
            pieces: column,
            width,
            depth,
        });
    }
    columns
}

/// Places the columns in rows of clusters (sets `x` and `z`), returning
/// the pieces in column order. Within a cluster a column slides along `-x`
/// until it touches the cluster so far, then a few percent of the size of
/// the first two pieces that touch further.
fn lay_out(rng: &mut ChaCha8Rng, columns: Vec<Column>, options: &DemoOptions) -> Vec<Piece> {
    let per_row = (columns.len() as f64).sqrt().ceil().max(1.0) as usize;
    let mut placed: Vec<Piece> = Vec::new();
    let mut row_z = 0.0;
    let mut columns = columns.into_iter().peekable();
    while columns.peek().is_some() {
        let row: Vec<Column> = columns.by_ref().take(per_row).collect();
        let row_depth = row.iter().map(|c| c.depth).fold(0.0, f64::max);
        let centre_z = row_z + row_depth / 2.0;
        let mut right = 0.0; // right edge of the row so far
        let mut left_in_cluster = 0;
        let mut cluster: Vec<Piece> = Vec::new();
        for column in row {
            let starts_cluster = left_in_cluster == 0;
            if starts_cluster {
                left_in_cluster = rng.random_range(1..=MAX_CLUSTER_COLUMNS);
                placed.append(&mut cluster);
            }
            left_in_cluster -= 1;
            let gap = if starts_cluster {
                CLUSTER_GAP
            } else {
                CAST_CLEARANCE
            };
            let centre_x = right + gap + column.width / 2.0;
            let mut pieces = column.pieces;
            for piece in &mut pieces {
                piece.desc.translation.x += centre_x;
                piece.desc.translation.z += centre_z;
            }
            if !starts_cluster {
                let fraction = overlap_fraction(rng, options);
                let slide = pieces
                    .iter()
                    .filter_map(|p| {
                        let (t, touched) = travel_until_contact(p, -Vector::X, &cluster)?;
                        Some((t, fraction * p.extent().x.min(touched.extent().x)))
                    })
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map_or(CAST_CLEARANCE, |(t, push)| t + push);
                for piece in &mut pieces {
                    piece.desc.translation.x -= slide;
                }
            }
            right = pieces.iter().map(|p| p.world_max().x).fold(right, f64::max);
            cluster.append(&mut pieces);
        }
        placed.append(&mut cluster);
        row_z += row_depth + CLUSTER_GAP;
    }
    placed
}

/// A fixed box whose top face is `y = 0`, covering every piece's footprint.
fn ground(pieces: &[Piece]) -> Body {
    let mut min = Vector3::new(-1.0, 0.0, -1.0);
    let mut max = Vector3::new(1.0, 0.0, 1.0);
    for piece in pieces {
        min = min.inf(&(piece.desc.translation + piece.min));
        max = max.sup(&(piece.desc.translation + piece.max));
    }
    let centre = (min + max) / 2.0;
    let half_extents = Vector3::new(
        (max.x - min.x) / 2.0 + CLUSTER_GAP,
        GROUND_HALF_HEIGHT,
        (max.z - min.z) / 2.0 + CLUSTER_GAP,
    );
    build(BodyDesc {
        name: "ground".into(),
        shape: Shape::Cuboid { half_extents },
        translation: Vector3::new(centre.x, -GROUND_HALF_HEIGHT, centre.z),
        rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
        mass: MassSpec::Fixed,
    })
}

/// Builds a generated body. A hull that fails to build (it cannot: it
/// contains a jittered regular tetrahedron) is replaced by a unit-density
/// cube of half extent `SIZE_MIN` rather than dropped, so that the body
/// count is exact.
fn build(desc: BodyDesc) -> Body {
    let fallback = BodyDesc {
        shape: Shape::Cuboid {
            half_extents: Vector3::repeat(SIZE_MIN),
        },
        mass: if desc.mass == MassSpec::Fixed {
            MassSpec::Fixed
        } else {
            MassSpec::Density(1.0)
        },
        ..desc.clone()
    };
    Body::new(desc).unwrap_or_else(|error| {
        log::debug!("demo: body replaced by a box: {error}");
        // A cube of positive finite size at a finite translation with a
        // unit rotation (from nalgebra) and positive density is valid.
        Body::new(fallback).expect("a valid cuboid")
    })
}
