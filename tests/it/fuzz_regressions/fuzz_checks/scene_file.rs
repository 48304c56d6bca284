//! Scene reader plus stabilization: any text either fails to parse with a
//! typed error, or gives a scene that a call either rejects (every pose
//! left as it was) or stabilizes without NaN, never deeper than it came,
//! whose written file parses back to the same number of bodies.

use constraint_stabilization::body::Shape;
use constraint_stabilization::io::scene_file::{parse_scene, scene_to_string};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Settings, Stabilizer};

/// Scenes with more bodies are skipped.
const MAX_BODIES: usize = 24;

/// Hulls with more points are skipped.
const MAX_HULL_POINTS: usize = 64;

/// The pass limit is lowered to this (a file may ask for any).
const MAX_PASSES: usize = 20;

/// Compounds with more parts are skipped.
const MAX_PARTS: usize = 8;

fn small_shape(shape: &Shape) -> bool {
    match shape {
        Shape::ConvexHull { points } | Shape::RoundConvexHull { points, .. } => {
            points.len() <= MAX_HULL_POINTS
        }
        Shape::Cuboid { .. }
        | Shape::RoundCuboid { .. }
        | Shape::Sphere { .. }
        | Shape::Capsule { .. }
        | Shape::Cylinder { .. }
        | Shape::Cone { .. } => true,
        Shape::Compound { parts } => {
            parts.len() <= MAX_PARTS && parts.iter().all(|part| small_shape(&part.shape))
        }
    }
}

fn small(scene: &Scene) -> bool {
    scene.len() <= MAX_BODIES && scene.bodies().iter().all(|b| small_shape(b.shape()))
}

/// The check (module docs).
pub fn check(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(mut scene) = parse_scene(text) else {
        return;
    };
    if !small(&scene) {
        return;
    }
    let mut settings = Settings::default().with_scene_settings(scene.settings());
    settings.max_passes = settings.max_passes.min(MAX_PASSES);
    let mut stabilizer = Stabilizer::new(settings).expect("a parsed scene's settings are valid");
    // Numbers round-trip exactly (shortest form): equal text, equal bits.
    let before = scene_to_string(&scene, None);
    match stabilizer.stabilize(&mut scene) {
        Err(_) => assert_eq!(
            scene_to_string(&scene, None),
            before,
            "an error moved a body"
        ),
        Ok(report) => {
            for body in scene.bodies() {
                let finite = body.translation_user().iter().all(|c| c.is_finite())
                    && body.rotation_user_xyzw().iter().all(|c| c.is_finite());
                assert!(finite, "body {} has a non-finite pose", body.name());
            }
            assert!(report.depth_after.is_finite() && report.depth_before.is_finite());
            assert!(
                report.depth_after <= report.depth_before,
                "deeper after: {} > {}",
                report.depth_after,
                report.depth_before
            );
            let written = scene_to_string(&scene, None);
            let back = parse_scene(&written).expect("a written scene reads back");
            assert_eq!(back.len(), scene.len());
        }
    }
}
