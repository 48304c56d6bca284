//! Reading and writing files: LCP problems in the Siconos format
//! ([`lcp_file`]); scene files (JSON, feature `serde`).

pub mod lcp_file;

pub use lcp_file::{LcpFileError, parse_lcp, read_lcp_file};
