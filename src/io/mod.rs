//! Reading and writing files: LCP problems in the Siconos format
//! ([`lcp_file`]); scene files (JSON, feature `serde`, [`scene_file`], their joints in
//! [`scene_joints`]).

pub mod lcp_file;
#[cfg(feature = "serde")]
mod object_reader;
#[cfg(feature = "serde")]
mod round_shapes;
#[cfg(feature = "serde")]
pub mod scene_file;
#[cfg(feature = "serde")]
pub mod scene_joints;
#[cfg(feature = "serde")]
mod strict_json;

pub use lcp_file::{LcpFileError, parse_lcp, read_lcp_file};
