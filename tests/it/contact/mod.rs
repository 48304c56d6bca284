//! The narrow phase: the exact penetration depth (`contact::query`) and
//! the contact manifold and rows built on its normal.

mod contact_row_jacobian;
mod depth;
mod gauss_map_arcs;
mod manifold;
