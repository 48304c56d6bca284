//! V-Clip with the exact-depth search (`contact::query`) on two hulls
//! decoded from the bytes (4 to 19 points each, coordinates on a grid of
//! 1e-3 of the size, sizes 1e-3 to 1e3) at decoded poses, checked against
//! the brute-force separating-axis depth of `dev_support::sat`: a
//! penetrating answer's depth equals it (to `AGREEMENT` of the size), and a
//! separated answer has no axis-wise overlap beyond that, with a distance
//! at least the widest separating gap.

use constraint_stabilization::internals::contact::{BodyGeometry, query};
use constraint_stabilization::internals::geometry::ConvexPolyhedron;
use constraint_stabilization::internals::vclip::{Outcome, VClip, VClipSettings};
use dev_support::sat;
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};

/// Agreement of depths and distances, relative to the larger body's size.
const AGREEMENT: f64 = 1e-9;

/// Reads the bytes as a stream of numbers (zeros once they run out).
struct Bytes<'a>(std::slice::Iter<'a, u8>);

impl Bytes<'_> {
    fn byte(&mut self) -> u8 {
        self.0.next().copied().unwrap_or(0)
    }

    /// A number in [-1, 1) on a grid of 1/32768.
    fn unit(&mut self) -> f64 {
        f64::from(i16::from_le_bytes([self.byte(), self.byte()])) / 32768.0
    }

    fn vector(&mut self) -> Vector3<f64> {
        Vector3::new(self.unit(), self.unit(), self.unit())
    }

    /// 4 to 19 points within `size` of the origin.
    fn hull(&mut self, size: f64) -> Option<ConvexPolyhedron> {
        let count = 4 + usize::from(self.byte() % 16);
        let points: Vec<Point3<f64>> = (0..count)
            .map(|_| Point3::from(self.vector() * size))
            .collect();
        ConvexPolyhedron::from_points(&points).ok()
    }

    fn pose(&mut self, size: f64) -> Isometry3<f64> {
        let q = Quaternion::new(self.unit(), self.unit(), self.unit(), self.unit());
        let rotation = if q.norm() > 1e-3 {
            UnitQuaternion::from_quaternion(q)
        } else {
            UnitQuaternion::identity()
        };
        Isometry3::from_parts(Translation3::from(self.vector() * size), rotation)
    }
}

/// The check (module docs).
pub fn check(data: &[u8]) {
    let mut bytes = Bytes(data.iter());
    let size = 10f64.powi(i32::from(bytes.byte() % 7) - 3);
    let (Some(a), Some(b)) = (bytes.hull(size), bytes.hull(size)) else {
        return;
    };
    let (pose_a, pose_b) = (bytes.pose(size), bytes.pose(size));
    let geometry = |shape, pose| BodyGeometry::convex(shape, pose, None);
    let vclip = VClip::new(VClipSettings::default());
    let answer = query(&vclip, &geometry(&a, pose_a), &geometry(&b, pose_b), None)
        .expect("valid hulls and unit rotations are valid input");
    let oracle = sat::sat_axes(&a, &pose_a, &b, &pose_b).all;
    let slack = AGREEMENT * a.scale().max(b.scale());
    if std::env::var_os("FUZZ_DEBUG").is_some() {
        println!(
            "size {size}\nA {:?}\npose A {pose_a:?}\nB {:?}\npose B {pose_b:?}",
            a.vertices(),
            b.vertices()
        );
        println!("answer {answer:?}\noracle {oracle}");
    }
    match (&answer.penetration, &answer.vclip.outcome) {
        (Some(penetration), _) => {
            let depth = penetration.depth();
            assert!(
                (depth - oracle).abs() <= slack,
                "depth {depth:e}, brute force {oracle:e}"
            );
        }
        (None, Outcome::Separated { distance, .. }) => {
            assert!(
                oracle <= slack,
                "separated by {distance:e}, brute force overlap {oracle:e}"
            );
            assert!(
                *distance >= -oracle - slack,
                "distance {distance:e} below the gap {:e}",
                -oracle
            );
        }
        (None, Outcome::Penetrating(_)) => panic!("a penetration without its exact depth"),
    }
}
