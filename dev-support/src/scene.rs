//! Scene builders and pose snapshots shared by the test areas (and
//! `xyzw` by the benchmarks): body descriptions (boxes, hulls, the ground slab),
//! scenes from descriptions, scaling, bit-exact pose snapshots, and a
//! far-away bystander pair that a stabilization must leave untouched.

use constraint_stabilization::body::{BodyDesc, MassSpec, Shape};
use constraint_stabilization::scene::Scene;
use nalgebra::{Point3, UnitQuaternion, Vector3};

/// The identity rotation `[x, y, z, w]`.
pub const IDENTITY_XYZW: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

/// A body description of `shape` placed by its shape frame.
pub fn body(
    name: &str,
    shape: Shape,
    translation: [f64; 3],
    rotation_xyzw: [f64; 4],
    mass: MassSpec,
) -> BodyDesc {
    BodyDesc {
        name: name.into(),
        shape,
        translation: Vector3::from(translation),
        rotation_xyzw,
        mass,
    }
}

/// A body description of a box.
pub fn cuboid(
    name: &str,
    half_extents: [f64; 3],
    translation: [f64; 3],
    rotation_xyzw: [f64; 4],
    mass: MassSpec,
) -> BodyDesc {
    let half_extents = Vector3::from(half_extents);
    body(
        name,
        Shape::Cuboid { half_extents },
        translation,
        rotation_xyzw,
        mass,
    )
}

/// The fixed ground of the scenes: a slab whose top face is the plane
/// `y = 0`.
pub fn ground() -> BodyDesc {
    floor_slab("ground", [20.0, 0.5, 20.0])
}

/// A fixed box of half extents `half` whose top face is the plane `y = 0`.
pub fn floor_slab(name: &str, half: [f64; 3]) -> BodyDesc {
    cuboid(
        name,
        half,
        [0.0, -half[1], 0.0],
        IDENTITY_XYZW,
        MassSpec::Fixed,
    )
}

/// A unit cube of mass 1, face down on [`ground`], sunk by `depth`.
pub fn unit_cube_sunk(name: &str, depth: f64) -> BodyDesc {
    cuboid(
        name,
        [0.5, 0.5, 0.5],
        [0.0, 0.5 - depth, 0.0],
        IDENTITY_XYZW,
        MassSpec::Mass(1.0),
    )
}

/// A body description of a convex hull.
pub fn hull(
    name: &str,
    points: Vec<Point3<f64>>,
    translation: [f64; 3],
    rotation_xyzw: [f64; 4],
    mass: MassSpec,
) -> BodyDesc {
    body(
        name,
        Shape::ConvexHull { points },
        translation,
        rotation_xyzw,
        mass,
    )
}

/// `[x, y, z, w]` of a unit quaternion.
pub fn xyzw(rotation: &UnitQuaternion<f64>) -> [f64; 4] {
    let q = rotation.quaternion();
    [q.i, q.j, q.k, q.w]
}

/// A description scaled by `s` about the world origin: translation, box
/// half extents and hull points times `s`; masses times `s^3` (density
/// unchanged), so that the mass-weighted problem is the same up to scale.
pub fn scaled(desc: &BodyDesc, s: f64) -> BodyDesc {
    let shape = match &desc.shape {
        Shape::Cuboid { half_extents } => Shape::Cuboid {
            half_extents: half_extents * s,
        },
        Shape::ConvexHull { points } => Shape::ConvexHull {
            points: points.iter().map(|p| p * s).collect(),
        },
        _ => panic!("scaled: cuboids and hulls only"),
    };
    let mass = match desc.mass {
        MassSpec::Mass(m) => MassSpec::Mass(m * s * s * s),
        other => other,
    };
    BodyDesc {
        name: desc.name.clone(),
        shape,
        translation: desc.translation * s,
        rotation_xyzw: desc.rotation_xyzw,
        mass,
    }
}

/// Builds a scene from descriptions (panics on an invalid one: the tests
/// build valid scenes).
pub fn scene_of(descs: &[BodyDesc]) -> Scene {
    let mut scene = Scene::new();
    for desc in descs {
        scene.add_body(desc.clone()).expect("test bodies are valid");
    }
    scene
}

/// Every user pose as raw f64 bits: translation then rotation `[x, y, z, w]`.
pub type PoseBits = [u64; 7];

/// The user poses of all bodies, bit for bit.
pub fn pose_bits(scene: &Scene) -> Vec<PoseBits> {
    scene
        .bodies()
        .iter()
        .map(|b| {
            let t = b.translation_user();
            let q = b.rotation_user_xyzw();
            [
                t.x.to_bits(),
                t.y.to_bits(),
                t.z.to_bits(),
                q[0].to_bits(),
                q[1].to_bits(),
                q[2].to_bits(),
                q[3].to_bits(),
            ]
        })
        .collect()
}

/// Asserts that the bodies `indices` have exactly the poses of `before`.
pub fn assert_untouched(scene: &Scene, before: &[PoseBits], indices: &[usize]) {
    let now = pose_bits(scene);
    for &i in indices {
        assert_eq!(
            now[i],
            before[i],
            "body {i} ({}) moved but must be bit-identical",
            scene.bodies()[i].name()
        );
    }
}

/// Asserts that no pose component is NaN or infinite.
pub fn assert_finite(scene: &Scene) {
    for body in scene.bodies() {
        let finite = body.translation_user().iter().all(|c| c.is_finite())
            && body.rotation_user_xyzw().iter().all(|c| c.is_finite());
        assert!(finite, "body {} has a non-finite pose", body.name());
    }
}

/// A far-away pair that must not be touched: two unit boxes side by side
/// along x with a gap of `gap` (within the contact margin when small, so
/// they form an island of their own that does not penetrate), centred at
/// `at`. Returns the two descriptions.
pub fn bystander_pair(at: [f64; 3], gap: f64) -> [BodyDesc; 2] {
    let h = 0.5;
    [
        cuboid(
            "bystander_a",
            [h, h, h],
            [at[0] - h - gap / 2.0, at[1], at[2]],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
        cuboid(
            "bystander_b",
            [h, h, h],
            [at[0] + h + gap / 2.0, at[1], at[2]],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
    ]
}
