//! The SVG picture of a scene (`render`): it parses as XML (roxmltree),
//! has one polygon per face that faces the viewer, and marks the bodies
//! of penetrating pairs, and only those.

use constraint_stabilization::body::MassSpec;
use constraint_stabilization::testbed::render::{View, render_svg};
use constraint_stabilization::{Settings, Stabilizer};
use dev_support::scene::{IDENTITY_XYZW, cuboid, ground, scene_of, unit_cube_sunk};

#[test]
fn the_picture_parses_has_one_polygon_per_visible_face_and_marks_penetrations() {
    let scene = scene_of(&[
        ground(),
        unit_cube_sunk("sunk", 0.05),
        cuboid(
            "resting",
            [0.5, 0.5, 0.5],
            [3.0, 0.5, 0.0],
            [0.0, 0.382_683_432_365_089_8, 0.0, 0.923_879_532_511_286_7],
            MassSpec::Mass(1.0),
        ),
        cuboid(
            "floating",
            [0.3, 0.2, 0.4],
            [-3.0, 2.0, 1.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
    ]);
    let penetrations = Stabilizer::new(Settings::default())
        .expect("default settings")
        .penetrations(&scene)
        .expect("valid scene");
    assert_eq!(penetrations.len(), 1, "{penetrations:?}");
    for view in [View::X, View::Y, View::Z, View::Iso] {
        let svg = render_svg(&scene, view, &penetrations);
        let document = roxmltree::Document::parse(&svg).expect("well-formed XML");
        let polygons: Vec<_> = document
            .descendants()
            .filter(|n| n.has_tag_name("polygon"))
            .collect();
        // Faces whose outward normal has a positive component towards the
        // viewer, counted from the scene independently of the renderer.
        let v = view.direction();
        let visible: usize = scene
            .bodies()
            .iter()
            .map(|b| {
                let rotation = b.com_pose().rotation;
                b.polyhedron()
                    .expect("a convex body")
                    .faces()
                    .iter()
                    .filter(|f| (rotation * f.plane.normal).dot(&v) > 0.0)
                    .count()
            })
            .sum();
        assert_eq!(polygons.len(), visible, "{view:?}");
        for polygon in &polygons {
            let body: usize = polygon
                .attribute("data-body")
                .and_then(|b| b.parse().ok())
                .expect("data-body");
            let marked = polygon.attribute("class") == Some("face penetrating");
            assert_eq!(marked, body <= 1, "{view:?}: body {body}");
            let points = polygon.attribute("points").expect("points");
            assert!(points.split(' ').count() >= 3);
            assert!(!points.contains("NaN") && !points.contains("inf"));
        }
        let labels: Vec<_> = document
            .descendants()
            .filter(|n| n.attribute("class") == Some("depth"))
            .collect();
        assert_eq!(labels.len(), 1);
        assert_eq!(labels[0].text(), Some("5.00e-2"));
    }
    // Without penetrations nothing is marked.
    let plain = render_svg(&scene, View::Iso, &[]);
    assert!(!plain.contains("penetrating") && !plain.contains("class=\"depth\""));
}
