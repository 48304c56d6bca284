//! The `stabilize` command line (its binary needs feature `cli`, which
//! this module is compiled with): `stabilize scene`, `stabilize demo`,
//! `stabilize lcp`.

mod lcp;
mod scene;
