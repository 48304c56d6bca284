//! File formats: scene JSON (feature `serde`).

#[cfg(feature = "serde")]
pub mod scene_file;
#[cfg(feature = "serde")]
mod strict_json;
