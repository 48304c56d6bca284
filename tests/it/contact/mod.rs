//! The narrow phase: the exact penetration depth (`contact::query`), the
//! contact manifold and rows built on its normal, and the separation
//! certificates that let detection skip pairs.

mod certificate;
mod certificate_calls;
mod contact_row_jacobian;
mod depth;
mod gauss_map_arcs;
mod manifold;
mod part_pairs;
mod warm_start;
