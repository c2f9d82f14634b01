//! vibrofric: the friction contact of a body sliding on a vibrating support (Leus & Gutowski,
//! 2024), as an FMI 2.0 Co-Simulation FMU.
//!
//! Layers, each knowing only those above it in this list:
//! - [`physics`]: parameters, friction laws, support motion (no FMI, no integrator);
//! - [`solver`]: the stiff, event-locating integrator (no physics, no XML);
//! - [`model`]: a contact as a [`model::Simulator`], specialised at compile time per scene;
//! - [`description`]: the variable table, scenes, the generated `modelDescription.xml`;
//! - [`fmi`]: the FMI 2.0 instance state machine and the thin `extern "C"` layer.

pub mod description;
pub mod fmi;
pub mod model;
pub mod physics;
pub mod solver;
