//! Scenes: bodies, the broad phase, islands, and the demo scene.

mod body;
mod broad_phase;
#[cfg(feature = "testbed")]
mod demo;
mod island;
