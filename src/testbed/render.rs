//! Pictures of scenes: an SVG drawing in orthographic projection.
//!
//! The camera looks along `-v` (`v` the view direction, from the scene
//! towards the viewer) with an up vector `u` (world `y`, or world `z` when
//! `v` is nearly along `y`) and right vector `r = u x v` normalized. A world
//! point `p` is drawn at `(p . r, -p . u)` (SVG's y grows downwards),
//! scaled to fit the picture. Every face whose outward normal `n` has
//! `n . v > 0` is visible from outside its body; visible faces of all
//! bodies are drawn back to front by the depth `c . v` of their centroid
//! (the painter's algorithm: exact for the separate convex bodies of a
//! scene unless faces of different bodies interleave in depth, as
//! overlapping ones can). A face is shaded by its normal, `0.35 + 0.65
//! max(0, n . l)` for a light `l` from the viewer's upper right; dynamic
//! bodies get a hue of their own, fixed bodies grey. Bodies in a
//! penetrating pair are outlined in red and, for up to twenty pairs, each
//! pair's exact depth is written at the midpoint of its bodies.
//!
//! Every face polygon carries `class="face"` (`"face penetrating"` for a
//! body of a penetrating pair) and `data-body` (its scene index), so that
//! tests and scripts can read the picture.

use std::fmt::Write as _;

use nalgebra::{Point3, Vector3};

use crate::body::BodyPart;
use crate::contact::PairPenetration;
use crate::geometry::{ConvexPolyhedron, round_mass};
use crate::scene::Scene;

/// Picture width and height (SVG user units).
const SIZE: (f64, f64) = (800.0, 600.0);
/// Margin around the drawing (SVG user units).
const MARGIN: f64 = 30.0;
/// Ambient part of the shading.
const AMBIENT: f64 = 0.35;
/// Depths are written only for up to this many penetrating pairs (more
/// would cover the picture).
const MAX_LABELS: usize = 20;
/// `|v . y|` above which the up vector is world `z` instead of `y`.
const UP_SWITCH: f64 = 0.9;

/// Geodesic subdivisions of the directions that draw a round part.
const ROUND_DRAWING_SUBDIVISIONS: usize = 2;

/// The polyhedron that draws a round part (its core grown along the
/// directions of a geodesic sphere); `None` for a plain polyhedron, drawn
/// as it is (cylinders and cones by their polyhedra).
fn drawing(part: &BodyPart) -> Option<ConvexPolyhedron> {
    let rounding = part.rounding()?;
    let directions: Vec<Vector3<f64>> =
        ConvexPolyhedron::geodesic_sphere(1.0, ROUND_DRAWING_SUBDIVISIONS)
            .ok()?
            .vertices()
            .iter()
            .map(|v| v.coords)
            .collect();
    let points = match rounding.segment() {
        Some(ends) => ends
            .iter()
            .flat_map(|p| directions.iter().map(move |d| p + d * rounding.radius))
            .collect(),
        None => round_mass::rounded_hull_points(part.polyhedron(), rounding.radius, &directions),
    };
    ConvexPolyhedron::from_points(&points).ok()
}

/// Where the camera looks from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum View {
    /// From `+x`.
    X,
    /// From `+y`.
    Y,
    /// From `+z`.
    Z,
    /// From `(1, 1, 1)`.
    #[default]
    Iso,
}

impl View {
    /// The view named `x`, `y`, `z` or `iso`.
    pub fn from_name(name: &str) -> Option<View> {
        match name {
            "x" => Some(View::X),
            "y" => Some(View::Y),
            "z" => Some(View::Z),
            "iso" => Some(View::Iso),
            _ => None,
        }
    }

    /// Unit vector from the scene towards the viewer.
    pub fn direction(self) -> Vector3<f64> {
        match self {
            View::X => Vector3::x(),
            View::Y => Vector3::y(),
            View::Z => Vector3::z(),
            View::Iso => Vector3::new(1.0, 1.0, 1.0).normalize(),
        }
    }
}

/// One visible face, projected.
struct DrawnFace {
    body: usize,
    depth: f64,
    points: Vec<(f64, f64)>,
    shade: f64,
}

/// The SVG drawing of `scene` seen from `view`, with the bodies of
/// `penetrations` outlined in red and their depths written.
pub fn render_svg(scene: &Scene, view: View, penetrations: &[PairPenetration]) -> String {
    let v = view.direction();
    let up = if v.y.abs() > UP_SWITCH {
        Vector3::z()
    } else {
        Vector3::y()
    };
    let right = up.cross(&v).normalize();
    let up = v.cross(&right);
    let light = (v + right * 0.5 + up * 0.8).normalize();
    let project = |p: &Point3<f64>| (p.coords.dot(&right), -p.coords.dot(&up));
    let mut faces = Vec::new();
    for (index, body) in scene.bodies().iter().enumerate() {
        for (part, pose) in body.parts().iter().zip(body.part_poses()) {
            let drawn = drawing(part);
            let shape = drawn.as_ref().unwrap_or(part.polyhedron());
            let world: Vec<Point3<f64>> = shape.vertices().iter().map(|p| pose * p).collect();
            for face in shape.faces() {
                let normal = pose.rotation * face.plane.normal;
                if normal.dot(&v) <= 0.0 {
                    continue;
                }
                let corners: Vec<&Point3<f64>> = face.vertices.iter().map(|&i| &world[i]).collect();
                let centroid =
                    corners.iter().map(|p| p.coords).sum::<Vector3<f64>>() / corners.len() as f64;
                faces.push(DrawnFace {
                    body: index,
                    depth: centroid.dot(&v),
                    points: corners.iter().map(|p| project(p)).collect(),
                    shade: AMBIENT + (1.0 - AMBIENT) * normal.dot(&light).max(0.0),
                });
            }
        }
    }
    faces.sort_by(|a, b| a.depth.total_cmp(&b.depth));
    let marked: Vec<bool> = (0..scene.len())
        .map(|i| penetrations.iter().any(|p| p.body_a == i || p.body_b == i))
        .collect();
    let fit = Fit::of(faces.iter().flat_map(|f| f.points.iter().copied()));
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n\
         <rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n",
        w = SIZE.0,
        h = SIZE.1
    );
    for face in &faces {
        let body = &scene.bodies()[face.body];
        let (r, g, b) = base_colour(face.body, body.is_fixed());
        let shade = |c: f64| (c * face.shade).round().clamp(0.0, 255.0);
        let points: Vec<String> = face
            .points
            .iter()
            .map(|&p| {
                let (x, y) = fit.apply(p);
                format!("{x:.2},{y:.2}")
            })
            .collect();
        let (class, stroke, width) = if marked[face.body] {
            ("face penetrating", "rgb(220,20,20)", 2.0)
        } else {
            ("face", "rgb(40,40,40)", 0.6)
        };
        let _ = writeln!(
            svg,
            "<polygon class=\"{class}\" data-body=\"{}\" points=\"{}\" fill=\"rgb({},{},{})\" stroke=\"{stroke}\" stroke-width=\"{width}\" stroke-linejoin=\"round\"/>",
            face.body,
            points.join(" "),
            shade(r),
            shade(g),
            shade(b)
        );
    }
    for pair in penetrations
        .iter()
        .filter(|_| penetrations.len() <= MAX_LABELS)
    {
        let (a, b) = (&scene.bodies()[pair.body_a], &scene.bodies()[pair.body_b]);
        let middle =
            Point3::from((a.com_pose().translation.vector + b.com_pose().translation.vector) / 2.0);
        let (x, y) = fit.apply(project(&middle));
        let _ = writeln!(
            svg,
            "<text class=\"depth\" x=\"{x:.1}\" y=\"{y:.1}\" font-family=\"sans-serif\" font-size=\"13\" fill=\"rgb(170,0,0)\">{:.2e}</text>",
            pair.depth
        );
    }
    svg.push_str("</svg>\n");
    svg
}

/// Colour of a body before shading: grey for fixed bodies, else a hue by
/// index (golden-angle steps, so neighbours differ).
fn base_colour(index: usize, fixed: bool) -> (f64, f64, f64) {
    if fixed {
        return (170.0, 170.0, 170.0);
    }
    let hue = (index as f64 * 137.508) % 360.0;
    let sector = hue / 60.0;
    let x = 1.0 - (sector % 2.0 - 1.0).abs();
    let (r, g, b) = match sector as u32 {
        0 => (1.0, x, 0.0),
        1 => (x, 1.0, 0.0),
        2 => (0.0, 1.0, x),
        3 => (0.0, x, 1.0),
        4 => (x, 0.0, 1.0),
        _ => (1.0, 0.0, x),
    };
    let pastel = |c: f64| 255.0 * (0.45 + 0.5 * c);
    (pastel(r), pastel(g), pastel(b))
}

/// The scaling of projected points into the picture (aspect kept).
struct Fit {
    scale: f64,
    offset: (f64, f64),
}

impl Fit {
    fn of(points: impl Iterator<Item = (f64, f64)>) -> Fit {
        let (mut lo, mut hi) = (
            (f64::INFINITY, f64::INFINITY),
            (f64::NEG_INFINITY, f64::NEG_INFINITY),
        );
        for (x, y) in points {
            lo = (lo.0.min(x), lo.1.min(y));
            hi = (hi.0.max(x), hi.1.max(y));
        }
        if !(lo.0.is_finite() && hi.0.is_finite()) {
            return Fit {
                scale: 1.0,
                offset: (0.0, 0.0),
            };
        }
        let span = (
            (hi.0 - lo.0).max(f64::MIN_POSITIVE),
            (hi.1 - lo.1).max(f64::MIN_POSITIVE),
        );
        let scale = ((SIZE.0 - 2.0 * MARGIN) / span.0).min((SIZE.1 - 2.0 * MARGIN) / span.1);
        let offset = (
            (SIZE.0 - scale * span.0) / 2.0 - scale * lo.0,
            (SIZE.1 - scale * span.1) / 2.0 - scale * lo.1,
        );
        Fit { scale, offset }
    }

    fn apply(&self, (x, y): (f64, f64)) -> (f64, f64) {
        (
            self.scale * x + self.offset.0,
            self.scale * y + self.offset.1,
        )
    }
}
