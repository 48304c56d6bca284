//! LCP and QP solvers.
