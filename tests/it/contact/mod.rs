//! The narrow phase: the exact penetration depth (`contact::query`) and
//! the contact manifold and rows built on its normal.

mod depth;
mod manifold;
