//! Scenes: bodies, the broad phase, islands, and the demo scene.

mod body;
mod broad_phase;
#[cfg(feature = "testbed")]
mod demo;
mod engine_mass;
mod island;
mod remove_bodies;
mod settings_builder;
mod settings_lengths;
