//! Settling by simulation: what many users do to remove overlaps (scene
//! generators run a physics engine until things separate). The scene's
//! Rapier world (`rapier_bridge::world_from_scene`: one rigid body and
//! one collider per body, f32, Rapier's default integration parameters),
//! gravity off, every dynamic body's velocity set to zero after each step
//! so that only the engine's penetration correction moves the bodies.
//! Sleeping stays on (Rapier's default).

#[cfg(feature = "rapier")]
pub use with_rapier::{parameters, run};

#[cfg(not(feature = "rapier"))]
pub fn run(
    _scene: &constraint_stabilization::scene::Scene,
    _checkpoints: &[usize],
) -> Result<Vec<crate::methods::RunPoint>, String> {
    Err("settling needs the feature `rapier`".into())
}

#[cfg(not(feature = "rapier"))]
pub fn parameters() -> String {
    "not measured: build with `--features rapier`".into()
}

#[cfg(feature = "rapier")]
mod with_rapier {
    use std::time::Instant;

    use constraint_stabilization::rapier_bridge::{pose_to_f64, world_from_scene};
    use constraint_stabilization::scene::Scene;
    use nalgebra::Vector3;
    use rapier3d::dynamics::IntegrationParameters;
    use rapier3d::math::Vector;

    use crate::methods::RunPoint;

    /// Rapier's default integration parameters that govern contacts.
    pub fn parameters() -> String {
        let p = IntegrationParameters::default();
        format!(
            "dt {} s, {} solver iterations, {} internal PGS and {} stabilization iterations, \
             contact softness {:?}, allowed linear error {} (normalized by the length unit {}), \
             max corrective velocity {} (normalized), prediction distance {} (normalized), \
             warm start {}",
            p.dt,
            p.num_solver_iterations,
            p.num_internal_pgs_iterations,
            p.num_internal_stabilization_iterations,
            p.contact_softness,
            p.normalized_allowed_linear_error,
            p.length_unit,
            p.normalized_max_corrective_velocity,
            p.normalized_prediction_distance,
            p.warmstart_coefficient
        )
    }

    /// One run of `checkpoints.last()` steps; a point after each checkpoint.
    pub fn run(scene: &Scene, checkpoints: &[usize]) -> Result<Vec<RunPoint>, String> {
        let mut built = world_from_scene(scene, Vector3::zeros()).map_err(|e| e.to_string())?;
        let dynamic: Vec<usize> = (0..scene.len())
            .filter(|&i| !scene.bodies()[i].is_fixed())
            .collect();
        let last = checkpoints.iter().copied().max().unwrap_or(0);
        let mut seconds = 0.0;
        let mut points = Vec::with_capacity(checkpoints.len());
        for step in 1..=last {
            let start = Instant::now();
            built.world.step();
            for &i in &dynamic {
                let body = &mut built.world.bodies[built.bodies[i]];
                body.set_linvel(Vector::ZERO, false);
                body.set_angvel(Vector::ZERO, false);
            }
            seconds += start.elapsed().as_secs_f64();
            if !checkpoints.contains(&step) {
                continue;
            }
            let mut after = scene.clone();
            let mut sleeping = 0;
            for &i in &dynamic {
                let body = &built.world.bodies[built.bodies[i]];
                sleeping += usize::from(body.is_sleeping());
                let pose = pose_to_f64(body.position());
                let q = pose.rotation.quaternion();
                after.bodies_mut()[i]
                    .set_user_pose(pose.translation.vector, [q.i, q.j, q.k, q.w])
                    .map_err(|e| e.to_string())?;
            }
            points.push(RunPoint {
                parameter: format!("steps={step}"),
                seconds,
                scene: after,
                iterations: step,
                status: format!("{sleeping} asleep"),
                largest_island_rows: 0,
                rows_solved: 0,
            });
        }
        Ok(points)
    }
}
