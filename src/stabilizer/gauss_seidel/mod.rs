//! Nonlinear Gauss–Seidel position correction: the game-engine baseline
//! ([`crate::stabilizer::Method::GaussSeidel`]).
//!
//! **Source.** Box2D v2.4, `b2ContactSolver::SolvePositionConstraints`
//! (Erin Catto; the "nonlinear Gauss–Seidel" of his GDC talks on
//! constraint solvers), written here in 3D and `f64`; Bullet's split
//! impulse follows the same idea (positions corrected apart from the
//! velocities). No velocity is changed: the method moves poses only, as
//! the projection does. No code was copied; the facts taken are the update
//! below and Box2D's defaults ([`settings`]).
//!
//! **Method.** Contacts are visited one at a time, in a fixed order; each
//! pushes its two bodies apart along its normal by a Baumgarte fraction
//! `beta` of its depth beyond a slop, capped, the separation measured again
//! at each visit from the point's body-frame coordinates and the current
//! poses ([`point`]):
//!
//! ```text
//! C      = clamp(beta (s + slop), -max_correction, 0)
//! K      = 1/m_a + 1/m_b + (r_a x n)^T I_a^-1 (r_a x n) + (r_b x n)^T I_b^-1 (r_b x n)
//! lambda = -C / K  (K > 0);   x_a += lambda n / m_a,  theta_a += lambda I_a^-1 (r_a x n),
//!                             x_b -= lambda n / m_b,  theta_b -= lambda I_b^-1 (r_b x n)
//! ```
//!
//! with `n` from B towards A (fixed bodies: infinite mass). To first order a
//! visit raises the point's separation by `-C`: a lone contact under the
//! centre of mass loses the fraction `beta` of its depth per sweep, `(1 -
//! beta)^k d` after `k` sweeps, and never goes below the slop.
//!
//! **Joints** ([`joints`]). After the points, each joint of the visited
//! islands has its locked axes relaxed one at a time as bilateral rows
//! (`C = e`, the constraint's value; no slop, no cap, no clamp on
//! `lambda`) and its limits as unilateral ones (`C = clamp(e + slop,
//! -max_correction, 0)`), each linearized at the current poses by
//! [`crate::joints::JointConstraint::linearize`]:
//!
//! ```text
//! k = g_a^T M_a^-1 g_a + g_b^T M_b^-1 g_b,  lambda = -C / k,  dq_i = lambda M_i^-1 g_i
//! ```
//!
//! (a contact's `K` above is this `k` for `g_a = [n; r_a x n]`, `g_b =
//! [-n; -(r_b x n)]`). Islands join jointed bodies; the stop rule, the
//! pass reports and the best configuration count joint errors as the
//! projection's do.
//!
//! **Sweeps.** One sweep (Box2D's position iteration) detects the pairs at
//! the current poses with the library's own detection (broad phase, V-Clip,
//! exact depth, contact manifold: the geometry the projection measures),
//! stores their points, then visits them; the next sweep detects again (the
//! geometry re-measured, with new contacts). The call stops when a sweep's
//! detection finds no penetration deeper than the tolerance and the joint
//! errors at its poses are within it too, or after
//! [`GaussSeidelSettings::iterations`] sweeps and a last detection, and
//! returns the best configuration measured (`call`).
//!
//! It is the baseline of the error-against-run-time benchmark: the same
//! detection and the same report as the projection, with the solve replaced
//! by the engine's sweep.
//!
//! Files:
//! - `point`: a contact point in body frames, measured at any poses;
//! - `contacts`: the points and joints of a sweep, from a detection;
//! - `sweep`: the visits, the relaxation of one row, the push of one point;
//! - `joints`: a joint's rows relaxed in a sweep;
//! - `call`: the loop of sweeps, the best configuration, the report.

pub(crate) mod call;
mod contacts;
pub mod joints;
pub mod point;
pub mod sweep;
