//! vibrofric: the friction contact of a body sliding on a vibrating support (Leus & Gutowski,
//! 2024), as an FMI 2.0 Co-Simulation FMU.
//!
//! Layers, each knowing only those above it in this list:
//! - [`physics`]: parameters, friction laws, support motion (no FMI, no integrator);
//! - [`solver`]: the stiff, event-locating integrator (no physics, no XML);
//! - [`model`]: a contact as a [`model::Simulator`], specialised at compile time per scene;
//! - [`description`]: the variable table, scenes, the generated `modelDescription.xml`;
//! - [`fmi`]: the FMI 2.0 instance state machine and the thin `extern "C"` layer.
//!
//! Below them all, [`table`] declares every variable once. `unsafe` code lives only in the C
//! layer (`fmi::ffi`, the exported C functions); everything else is safe Rust. The importer
//! (`vibrofric-import`) and the command line (`vibrofric-cli`) are crates of their own: the
//! shared library carries only what an FMU runs.
#![deny(unsafe_code)]

pub mod description;
pub mod fmi;
pub mod model;
pub mod physics;
pub mod solver;
pub mod table;
