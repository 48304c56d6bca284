//! Joint errors computed independently of the library (from the bodies'
//! user poses and the joints' anchor frames, with nalgebra alone), and
//! jointed scenes for the tests, examples and benchmarks: chains of links
//! and a four-bar linkage.

use constraint_stabilization::body::MassSpec;
use constraint_stabilization::joints::{Joint, JointKind};
use constraint_stabilization::scene::Scene;
use nalgebra::{Isometry3, Vector3};

use crate::scene::{IDENTITY_XYZW, cuboid};

/// A joint's errors as the tests judge them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OracleJointErrors {
    /// Largest `|(o_b - o_a) . l_k|` over the locked linear axes.
    pub linear: f64,
    /// Distance between the anchor points.
    pub separation: f64,
    /// Angle between the frames' rotations (all three locked), or between
    /// their `x` axes (a hinge): radians.
    pub angular: f64,
}

/// The world anchor frames of `joint` from the bodies' user poses.
pub fn world_frames(scene: &Scene, joint: &Joint) -> (Isometry3<f64>, Isometry3<f64>) {
    let a = scene.bodies()[joint.body_a].user_pose();
    let b = scene.bodies()[joint.body_b].user_pose();
    (a * joint.frame_a, b * joint.frame_b)
}

/// The errors of `joint` at the scene's poses.
pub fn oracle_joint_errors(scene: &Scene, joint: &Joint) -> OracleJointErrors {
    let (fa, fb) = world_frames(scene, joint);
    let d = fb.translation.vector - fa.translation.vector;
    let locked = joint.kind.locked_axes();
    let linear = (0..3)
        .filter(|&k| locked.linear[k])
        .map(|k| (fa.rotation * Vector3::ith(k, 1.0)).dot(&d).abs())
        .fold(0.0, f64::max);
    let angular = match joint.kind {
        JointKind::Revolute { .. } => {
            let (xa, xb) = (fa.rotation * Vector3::x(), fb.rotation * Vector3::x());
            xa.cross(&xb).norm().atan2(xa.dot(&xb))
        }
        JointKind::Fixed | JointKind::Prismatic { .. } => fa.rotation.angle_to(&fb.rotation),
        _ => 0.0,
    };
    OracleJointErrors {
        linear,
        separation: d.norm(),
        angular,
    }
}

/// The largest linear and angular oracle errors over the scene's joints.
pub fn worst_joint_errors(scene: &Scene) -> (f64, f64) {
    scene.joints().iter().fold((0.0, 0.0), |(l, a), joint| {
        let e = oracle_joint_errors(scene, joint);
        (l.max(e.linear), a.max(e.angular))
    })
}

/// A horizontal chain of `links` bars (half extents `[half_length, w, w]`,
/// mass 1, along `+x` from `origin`) on revolute joints about `z`, hung
/// from a fixed anchor block at `origin`; the last link carries a box of
/// mass `end_mass` at its end on a fixed joint. Returns the scene (anchor
/// first, then links, then the end box).
pub fn revolute_chain(links: usize, half_length: f64, end_mass: f64, origin: [f64; 3]) -> Scene {
    let w = 0.2 * half_length;
    let mut scene = Scene::new();
    let at = |x: f64| [origin[0] + x, origin[1], origin[2]];
    let anchor = scene
        .add_body(cuboid(
            "anchor",
            [w, w, w],
            at(-w),
            IDENTITY_XYZW,
            MassSpec::Fixed,
        ))
        .expect("valid anchor");
    // Hinge about z: the joint frame's x axis along world z.
    let hinge =
        nalgebra::UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -std::f64::consts::FRAC_PI_2);
    let mut previous = anchor;
    let mut previous_end = Vector3::new(w, 0.0, 0.0);
    for i in 0..links {
        let center = (2 * i + 1) as f64 * half_length;
        let link = scene
            .add_body(cuboid(
                &format!("link {i}"),
                [half_length * 0.9, w, w],
                at(center),
                IDENTITY_XYZW,
                MassSpec::Mass(1.0),
            ))
            .expect("valid link");
        scene
            .add_joint(Joint {
                name: format!("hinge {i}"),
                kind: JointKind::Revolute { limit: None },
                body_a: previous,
                body_b: link,
                frame_a: Isometry3::from_parts(previous_end.into(), hinge),
                frame_b: Isometry3::from_parts(Vector3::new(-half_length, 0.0, 0.0).into(), hinge),
            })
            .expect("valid hinge");
        previous = link;
        previous_end = Vector3::new(half_length, 0.0, 0.0);
    }
    let size = 2.0 * w;
    let end = scene
        .add_body(cuboid(
            "end box",
            [size, size, size],
            at(2.0 * links as f64 * half_length + size),
            IDENTITY_XYZW,
            MassSpec::Mass(end_mass),
        ))
        .expect("valid end box");
    scene
        .add_joint(Joint {
            name: "end".into(),
            kind: JointKind::Fixed,
            body_a: previous,
            body_b: end,
            frame_a: Isometry3::translation(half_length, 0.0, 0.0),
            frame_b: Isometry3::translation(-size, 0.0, 0.0),
        })
        .expect("valid end joint");
    scene
}
