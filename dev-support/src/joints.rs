//! Joint errors computed independently of the library (from the bodies'
//! user poses and the joints' anchor frames, with nalgebra alone), and
//! jointed scenes for the tests, examples and benchmarks: chains of links
//! on a ground, a pendulum off its pivot, two cubes on a ball joint.

use constraint_stabilization::body::MassSpec;
use constraint_stabilization::joints::{Joint, JointKind};
use constraint_stabilization::scene::Scene;
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

use crate::scene::{IDENTITY_XYZW, bystander_pair, cuboid, ground, xyzw};

/// A joint's errors as the tests judge them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OracleJointErrors {
    /// Norm of `(o_b - o_a) . l_k` over the locked linear axes.
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
        .map(|k| (fa.rotation * Vector3::ith(k, 1.0)).dot(&d).powi(2))
        .sum::<f64>()
        .sqrt();
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

/// Adds to `scene` a free chain of `n` bars (mass 1) lying on the ground
/// along x, hinged about z (vertical axes) end to end, link `sunk` sunk
/// `depth` into the ground (`usize::MAX`: none); returns the links.
pub fn chain_on_ground(scene: &mut Scene, n: usize, sunk: usize, depth: f64) -> Vec<usize> {
    let (h, w) = (0.2, 0.04);
    let mut links = Vec::new();
    for i in 0..n {
        let y = if i == sunk { w - depth } else { w };
        links.push(
            scene
                .add_body(cuboid(
                    &format!("link {i}"),
                    [0.9 * h, w, w],
                    [(2 * i + 1) as f64 * h, y, 0.0],
                    IDENTITY_XYZW,
                    MassSpec::Mass(1.0),
                ))
                .expect("valid link"),
        );
    }
    let vertical = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2);
    for i in 1..n {
        scene
            .add_joint(Joint {
                name: format!("hinge {i}"),
                kind: JointKind::Revolute { limit: None },
                body_a: links[i - 1],
                body_b: links[i],
                frame_a: Isometry3::from_parts(Vector3::new(h, 0.0, 0.0).into(), vertical),
                frame_b: Isometry3::from_parts(Vector3::new(-h, 0.0, 0.0).into(), vertical),
            })
            .expect("valid hinge");
    }
    links
}

/// A link (mass 1) on a ball joint below a fixed pivot at `(0, 2, 0)`,
/// tilted by 0.3 rad about z and moved off the pivot by about 0.07: the
/// anchors start more than 0.05 apart. Returns the scene (pivot first).
pub fn pendulum_off_pivot() -> Scene {
    let mut scene = Scene::new();
    scene
        .add_body(cuboid(
            "pivot",
            [0.05; 3],
            [0.0, 2.0, 0.0],
            IDENTITY_XYZW,
            MassSpec::Fixed,
        ))
        .expect("valid pivot");
    let tilt = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.3);
    scene
        .add_body(cuboid(
            "link",
            [0.05, 0.5, 0.05],
            [0.07, 1.45, 0.02],
            xyzw(&tilt),
            MassSpec::Mass(1.0),
        ))
        .expect("valid link");
    scene
        .add_joint(Joint {
            name: "pivot".into(),
            kind: JointKind::Spherical,
            body_a: 0,
            body_b: 1,
            frame_a: Isometry3::translation(0.0, -0.1, 0.0),
            frame_b: Isometry3::translation(0.0, 0.5, 0.0),
        })
        .expect("valid joint");
    scene
}

/// Two cubes of half size 0.25 and masses `m_a`, `m_b` on a ball joint
/// whose anchors (each 0.5 from its centre of mass along x) are pulled
/// `d` apart along x; `a` at the origin. Returns the scene (`a`, `b`).
pub fn ball_joint_pulled_apart(m_a: f64, m_b: f64, d: f64) -> Scene {
    let mut scene = Scene::new();
    for (name, x, mass) in [("a", 0.0, m_a), ("b", 1.0 + d, m_b)] {
        scene
            .add_body(cuboid(
                name,
                [0.25; 3],
                [x, 0.0, 0.0],
                IDENTITY_XYZW,
                MassSpec::Mass(mass),
            ))
            .expect("valid cube");
    }
    scene
        .add_joint(Joint {
            name: "ball".into(),
            kind: JointKind::Spherical,
            body_a: 0,
            body_b: 1,
            frame_a: Isometry3::translation(0.5, 0.0, 0.0),
            frame_b: Isometry3::translation(-0.5, 0.0, 0.0),
        })
        .expect("valid joint");
    scene
}

/// The ground, a chain of 6 links on it ([`chain_on_ground`]) with link 3
/// sunk `sunk`, a bystander pair far away (within the contact margin, not
/// penetrating) and a second chain of 3 links at rest 30 away along z.
/// Returns the scene and the bodies of the bystanders and of the second
/// chain, which a call must leave bit-identical.
pub fn sunk_chain_with_bystanders(sunk: f64) -> (Scene, Vec<usize>) {
    let mut scene = Scene::new();
    scene.add_body(ground()).expect("valid ground");
    chain_on_ground(&mut scene, 6, 3, sunk);
    let mut untouched: Vec<usize> = bystander_pair([50.0, 5.0, 0.0], 1e-3)
        .into_iter()
        .map(|d| scene.add_body(d).expect("valid bystander"))
        .collect();
    let far = chain_on_ground(&mut scene, 3, usize::MAX, 0.0);
    for &link in &far {
        let t = *scene.bodies()[link].translation_user() + Vector3::new(0.0, 0.0, 30.0);
        scene.bodies_mut()[link]
            .set_user_pose(t, IDENTITY_XYZW)
            .expect("valid pose");
    }
    untouched.extend(far);
    (scene, untouched)
}
