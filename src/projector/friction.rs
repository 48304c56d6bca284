//! Coulomb friction at the position level, as a friction pyramid of linear
//! rows.
//!
//! A contact may slide only as far as its friction allows. With
//! `dn = J_n dq` the relative displacement along the contact normal,
//! `dt = (J_t1 dq, J_t2 dq)` the relative displacement in its tangent
//! plane, and `r = target - phi` the normal displacement at which the
//! contact's row reaches its target (its penetration plus the target
//! margin for a penetrating contact; minus its gap beyond the target, a
//! negative number, for an open one),
//!
//! ```text
//! mu |dt| <= dn - r                                        (1)
//! ```
//!
//! Why `mu` multiplies `dt`: the contact forces of the projection are the
//! multipliers of its constraints, and they lie in the dual cone of the
//! constraint's cone. The dual of `{mu |dt| <= dn}` is `{|f_t| <= mu f_n}`,
//! Coulomb's cone: a larger `mu` allows a larger tangential force, hence
//! less sliding, and `mu -> 0` allows any sliding (the frictionless
//! problem, which `mu = 0` gives exactly since no row is then added). Only
//! the opening beyond the row's target counts: removing a penetration buys
//! no sliding, so a light box under a heavy one whose contact normals are
//! tilted (as after an engine step) is not slid sideways to spare the
//! heavy box's lift.
//!
//! **Open contacts.** Every row of the problem gets (1), the open ones
//! (gap within the contact margin) too, with the cone's apex where the
//! row reaches its target: a contact open by `g = phi - target` may slide
//! `(g + dn) / mu`, the gap it keeps, and a contact that the correction
//! closes onto its target may not slide at all. This is the convex
//! relaxation of Anitescu and Tasora's cone complementarity problem
//! (`phi / h + J_n v >= mu |J_t v|` at the velocity level, "An iterative
//! approach for cone complementarity problems for nonsmooth dynamics",
//! Comput. Optim. Appl. 2010) with the displacement for `h v`. Without it
//! an open contact has no friction row and may close while sliding
//! freely, whatever `mu`: an engine step that leaves a light box's lower
//! contact slightly open lets the call slide it (measured on the 1:1000
//! stack of `examples/probes/slide_probe.rs`: `benchmarks/results/coupling.md`,
//! "Friction in the position projection"). The relaxation's price, as in
//! Anitescu and Tasora's scheme: an open contact that stays open may
//! slide only by `mu` times the gap it keeps; beyond that the correction
//! opens it further.
//!
//! (1) is a second-order cone in `dq`, so the projection
//! `min 1/2 dq^T M dq` subject to the contact rows and (1) stays convex. It
//! can be linearized as the friction pyramid of Anitescu and Potra: with
//! `K` directions `d_k = cos(theta_k) t_1 + sin(theta_k) t_2`,
//! `theta_k = 2 pi k / K`,
//!
//! ```text
//! (J_n - mu cos(theta_k) J_t1 - mu sin(theta_k) J_t2) dq >= r,   k = 0..K-1   (2)
//! ```
//!
//! each an ordinary row with `phi = -r` and target 0. The rows (2) are
//! half-spaces, so the problem is still a convex QP with linear
//! constraints, and its KKT conditions are an LCP with one nonnegative,
//! complementary multiplier per facet: every solver (clarabel, Lemke, PGS)
//! solves the same problem, and the cross-check between them holds on it.
//! `dq = 0` satisfies (2) exactly when it satisfies the contact row, so
//! the pyramid never makes a configuration that needs no correction
//! infeasible. The polygon (2) has inradius `(dn - r) / mu`: it contains
//! the cone (1) and exceeds it by at most `1 / cos(pi / K)` in its corners
//! (41 % for `K = 4`, 8 % for `K = 8`). Wherever the frictionless answer
//! slides nothing, it satisfies (2) and is the answer with friction too.
//!
//! **Which one is solved** ([`crate::FrictionModel`]): the pyramid (2)
//! for every solver ([`crate::FrictionModel::Pyramid`]), or the cone (1)
//! itself as a second-order cone of clarabel's primal form
//! ([`crate::FrictionModel::Cone`], [`crate::solver::friction_cone`]),
//! with Lemke and PGS on the pyramid (they take linear rows only).
//!
//! A multiplier `beta_k >= 0` of a facet is a force on the contact
//! `beta_k (n - mu d_k)`: normal part `beta_k`, tangential part
//! `mu beta_k`, so the contact's total force lies in Coulomb's pyramid of
//! coefficient `mu`: frictional forces appear only when the contact would
//! slide.

use crate::rows::ConstraintRow;
use crate::solver::{FrictionCone, JacobianRow};

/// The cone (1) of every row with friction, for contact rows with target
/// `target` (apex where the row reaches its target, for open rows too),
/// and the index of the contact row of each.
pub fn friction_cones(rows: &[ConstraintRow], target: f64) -> (Vec<FrictionCone>, Vec<usize>) {
    rows.iter()
        .enumerate()
        .filter_map(|(index, row)| {
            let friction = row.friction.as_ref()?;
            let tangent = |t: usize| JacobianRow {
                blocks: friction.tangents[t].clone(),
            };
            let cone = FrictionCone {
                normal: JacobianRow {
                    blocks: row.blocks.clone(),
                },
                tangents: [tangent(0), tangent(1)],
                mu: friction.mu,
                phi: row.phi,
                target,
            };
            Some((cone, index))
        })
        .unzip()
}

/// The pyramid rows (2) of every row with friction, for contact rows with
/// target `target`: Jacobians, `phi = -r = phi_row - target` (module docs:
/// the apex where the row reaches its target, for open rows too), and the
/// index of the contact row of each.
pub fn pyramid_rows(
    rows: &[ConstraintRow],
    target: f64,
    directions: usize,
) -> (Vec<JacobianRow>, Vec<f64>, Vec<usize>) {
    let (cones, parents) = friction_cones(rows, target);
    let mut pyramid = Vec::new();
    let mut phi = Vec::new();
    let mut facet_parents = Vec::new();
    for (cone, parent) in cones.iter().zip(parents) {
        for (facet, facet_phi) in cone.facets(directions) {
            pyramid.push(facet);
            phi.push(facet_phi);
            facet_parents.push(parent);
        }
    }
    (pyramid, phi, facet_parents)
}
