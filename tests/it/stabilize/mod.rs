//! `Stabilizer::stabilize` end to end, and the projection loop on analytic
//! constraints (`projector_analytic`). Helpers of this area only:
//! [`support`] (the parry-and-SAT residual, runs, pose hashes),
//! [`one_row`] (the one-row minimal correction in closed form),
//! [`extreme`] (checks of the stiff, extreme and infeasible scenes).

mod extreme;
mod one_row;
pub mod support;

mod behaviour;
mod budget_and_slop;
mod compound;
mod deep;
mod degenerate_hulls;
mod faults;
mod friction;
mod friction_pyramid_rows;
mod infeasible;
#[cfg(feature = "serde")]
mod kept_pairs;
mod line_search_allowance;
mod minimal;
#[cfg(feature = "serde")]
mod permutation;
mod projector_analytic;
mod properties;
mod region_growth;
mod scale_extremes;
mod scenes;
#[cfg(feature = "testbed")]
mod seed;
mod solve_island_fixed;
mod stiff;
mod touching;
mod trust_region;
mod velocity;
mod warm_cache;
mod work;
