use constraint_stabilization::body::{BodyDesc, MassSpec, Shape};
use constraint_stabilization::internals::contact::IslandError;
use constraint_stabilization::internals::stabilizer::solve_island::*;
use constraint_stabilization::{Error, Scene};
use nalgebra::Vector3;

/// `IslandError::MasslessBody` cannot be reached through
/// `Stabilizer::stabilize` (islands are formed from dynamic bodies
/// only); this pins the typed error of the internal check itself: an
/// island listing a fixed body is refused, naming that body, rather
/// than its states and inertias falling out of step.
#[test]
fn an_island_listing_a_fixed_body_is_a_massless_body_error() {
    let mut scene = Scene::new();
    for (name, mass) in [("dynamic", MassSpec::Mass(1.0)), ("fixed", MassSpec::Fixed)] {
        let desc = BodyDesc {
            name: name.into(),
            shape: Shape::Cuboid {
                half_extents: Vector3::new(0.5, 0.5, 0.5),
            },
            translation: Vector3::zeros(),
            rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
            mass,
        };
        scene.add_body(desc).expect("valid body");
    }
    let result = island_state(&scene, &[0, 1]);
    assert!(
        matches!(
            result,
            Err(Error::Island(IslandError::MasslessBody { body: 1 }))
        ),
        "{:?}",
        result.map(|(states, _)| states.len())
    );
    let (states, inertias) = island_state(&scene, &[0]).expect("dynamic body");
    assert_eq!((states.len(), inertias.len()), (1, 1));
    assert_eq!(inertias[0].mass, 1.0);
}
