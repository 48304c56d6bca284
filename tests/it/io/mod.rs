//! Files and pictures: scene files (feature `serde`) and their joints,
//! LCP files, the SVG picture of a scene.

mod lcp_file;
#[cfg(feature = "testbed")]
mod render_svg;
#[cfg(feature = "serde")]
mod scene_file;
#[cfg(feature = "serde")]
mod scene_file_bad_input;
#[cfg(feature = "serde")]
mod scene_file_limits;
#[cfg(feature = "serde")]
mod scene_file_round;
#[cfg(feature = "serde")]
mod scene_file_settings;
#[cfg(feature = "serde")]
pub(crate) mod scene_joints;
#[cfg(feature = "serde")]
mod scene_joints_bad_input;
