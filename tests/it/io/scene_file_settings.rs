//! The settings a scene file carries take effect in the library, not only
//! in the command-line tool: `Scene::stabilizer` applies every field the
//! file sets (tolerance, margins, pass limit, solver, cross-check), and
//! `Stabilizer::new(Settings::default())` visibly does not. Each field is
//! checked by an effect a report shows (the tolerance used, the passes,
//! the solver of every island), on a box sunk into the ground.

use constraint_stabilization::io::scene_file::parse_scene;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::solver::SolverKind;
use constraint_stabilization::{Settings, Stabilizer, Status};

/// How deep the box is sunk into the ground: above the default tolerance
/// (1e-6 of the box's circumradius), below the file's tolerance.
const SUNK: f64 = 1e-4;

/// The file's tolerance, ten times the depth.
const FILE_TOLERANCE: f64 = 1e-3;

fn box_on_ground(settings: &str) -> Scene {
    let text = format!(
        r#"{{"bodies": [
          {{"name": "ground", "shape": {{"cuboid": [5, 0.5, 5]}}, "translation": [0, -0.5, 0],
            "rotation": [0, 0, 0, 1], "fixed": true}},
          {{"name": "box", "shape": {{"cuboid": [0.5, 0.5, 0.5]}}, "translation": [0, {y}, 0],
            "rotation": [0, 0, 0, 1], "mass": 1}}],
          "settings": {settings}}}"#,
        y = 0.5 - SUNK
    );
    parse_scene(&text).expect("valid scene")
}

#[test]
fn file_tolerance_is_applied_by_scene_stabilizer() {
    let settings = format!(r#"{{"tolerance": {FILE_TOLERANCE}}}"#);
    let mut scene = box_on_ground(&settings);
    let mut stabilizer = Stabilizer::for_scene(&scene).expect("valid settings");
    let report = stabilizer.stabilize(&mut scene).expect("stabilizes");
    assert_eq!(report.tolerance, FILE_TOLERANCE);
    assert_eq!(report.status, Status::NothingToDo, "depth {SUNK} is within");

    // The defaults ignore the file: the box is lifted.
    let mut scene = box_on_ground(&settings);
    let mut defaults = Stabilizer::new(Settings::default()).expect("valid settings");
    let report = defaults.stabilize(&mut scene).expect("stabilizes");
    assert!(report.tolerance < SUNK);
    assert_eq!(report.status, Status::Converged);
}

#[test]
fn file_pass_limit_solver_and_margins_are_applied() {
    let settings = r#"{"max_passes": 1, "solver": "pgs", "cross_check": true,
        "contact_margin": 0.25, "target_margin": 1e-5}"#;
    let scene = box_on_ground(settings);
    let resolved = Settings::default().with_scene_settings(scene.settings());
    assert_eq!(resolved.max_passes, 1);
    assert_eq!(resolved.contact_margin_absolute, Some(0.25));
    assert_eq!(resolved.target_margin_absolute, Some(1e-5));
    assert!(resolved.solver.cross_check);
    let mut scene = scene;
    let report = Stabilizer::for_scene(&scene)
        .expect("valid settings")
        .stabilize(&mut scene)
        .expect("stabilizes");
    assert!(report.passes <= 1, "{} passes", report.passes);
    let islands: Vec<_> = report.pass_reports.iter().flat_map(|p| &p.solved).collect();
    assert!(!islands.is_empty());
    for island in islands {
        assert_eq!(island.solver, Some(SolverKind::Pgs));
        assert!(
            island.cross_check.is_some(),
            "cross-check asked by the file"
        );
    }
    // The target margin: the box ends at least that far above the ground.
    let lift = scene.bodies()[1].translation_user().y - 0.5;
    assert!(lift >= 1e-5 * 0.99, "lifted to {lift:e} above contact");
}

#[test]
fn no_file_settings_means_the_given_base() {
    let scene = box_on_ground("{}");
    let base = {
        let mut settings = Settings::default();
        settings.max_passes = 7;
        settings
    };
    assert_eq!(base.clone().with_scene_settings(scene.settings()), base);
}

#[test]
fn file_method_chooses_gauss_seidel_and_round_trips() {
    use constraint_stabilization::Method;
    use constraint_stabilization::io::scene_file::scene_to_string;
    let scene = box_on_ground(r#"{"method": "gauss_seidel"}"#);
    let resolved = Settings::default().with_scene_settings(scene.settings());
    assert_eq!(resolved.method, Method::GaussSeidel);
    let mut moved = scene.clone();
    let report = Stabilizer::for_scene(&moved)
        .expect("valid settings")
        .stabilize(&mut moved)
        .expect("stabilizes");
    // Gauss–Seidel with Box2D's defaults: three sweeps, no island solved,
    // and the box, sunk less than the slop (0.005 of its circumradius), is
    // left where it is: the call cannot resolve it.
    assert_eq!(report.passes, 3);
    assert_eq!(report.islands_solved(), 0);
    assert_eq!(report.status, Status::PassLimit);
    assert_eq!(report.bodies_moved, 0);
    let text = scene_to_string(&scene, None);
    assert!(text.contains(r#""method": "gauss_seidel""#), "{text}");
    let again = parse_scene(&text).expect("reads back");
    assert_eq!(again.settings(), scene.settings());
}

#[test]
fn file_method_must_be_known() {
    use constraint_stabilization::io::scene_file::parse_scene as parse;
    let text = r#"{"bodies": [], "settings": {"method": "newton"}}"#;
    let error = parse(text).expect_err("unknown method");
    let message = error.to_string();
    assert!(message.contains("method"), "{message}");
}

#[test]
fn file_friction_model_chooses_the_cone_and_round_trips() {
    use constraint_stabilization::FrictionModel;
    use constraint_stabilization::io::scene_file::scene_to_string;
    let scene = box_on_ground(r#"{"friction_model": "cone"}"#);
    let resolved = Settings::default().with_scene_settings(scene.settings());
    assert_eq!(resolved.friction_model, FrictionModel::Cone);
    assert_eq!(
        Settings::default().friction_model,
        FrictionModel::Pyramid,
        "the file changed the model, not the default"
    );
    let text = scene_to_string(&scene, None);
    assert!(text.contains(r#""friction_model": "cone""#), "{text}");
    let again = parse_scene(&text).expect("reads back");
    assert_eq!(again.settings(), scene.settings());
    let bad = r#"{"bodies": [], "settings": {"friction_model": "ellipse"}}"#;
    let message = parse_scene(bad).expect_err("unknown model").to_string();
    assert!(message.contains("friction_model"), "{message}");
}

#[test]
fn file_friction_rows_are_read_applied_and_round_trip() {
    use constraint_stabilization::FrictionRows;
    use constraint_stabilization::io::scene_file::scene_to_string;
    let scene = box_on_ground(r#"{"friction_rows": "generated"}"#);
    let resolved = Settings::default().with_scene_settings(scene.settings());
    assert_eq!(resolved.friction_rows, FrictionRows::Generated);
    assert_eq!(Settings::default().friction_rows, FrictionRows::Implied);
    let text = scene_to_string(&scene, None);
    assert!(text.contains(r#""friction_rows": "generated""#), "{text}");
    let again = parse_scene(&text).expect("reads back");
    assert_eq!(again.settings(), scene.settings());
    let bad = r#"{"bodies": [], "settings": {"friction_rows": "some"}}"#;
    let message = parse_scene(bad).expect_err("unknown way").to_string();
    assert!(message.contains("friction_rows"), "{message}");
}
