//! The solvers: the projection QP end to end, its acceptance, the friction
//! cone, Lemke, PGS, and the Siconos LCP test problems.

mod acceptance;
mod friction_cone;
mod lcp_siconos;
mod lemke;
mod pgs;
mod projection;
