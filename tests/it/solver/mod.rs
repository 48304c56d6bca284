//! The solvers: the projection QP end to end, its acceptance, equality
//! rows, the friction cone, Lemke, PGS, and the Siconos LCP test problems.

mod acceptance;
mod active_set_oracle;
mod augmented_lagrangian;
mod deadline;
mod dense_cholesky;
mod dense_limit;
mod dual_active_set;
mod dual_active_set_warm;
mod equality_elimination;
mod equality_rows;
mod exact_engine_states;
mod fallback_sizes;
mod friction_cone;
mod friction_cone_unit;
mod friction_finishes;
mod friction_rows;
mod interior_point_friction;
mod kept_analyses;
mod lcp_siconos;
mod lemke;
mod pgs;
mod precision_length;
mod projection;
mod warm_starts;
