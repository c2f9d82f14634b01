//! vibrofric: the friction contact of a body sliding on a vibrating support (Leus & Gutowski,
//! 2024), as an FMI 2.0 Co-Simulation FMU.
//!
//! Layers, each knowing only those above it in this list:
//! - [`physics`]: parameters, friction laws, support motion (no FMI, no integrator);
//! - [`solver`]: the stiff, event-locating integrator (no physics, no XML);
//! - [`model`]: a contact as a [`model::Simulator`], specialised at compile time per scene;
//! - [`description`]: the variable table, scenes, the generated `modelDescription.xml`;
//! - [`fmi`]: the FMI 2.0 instance state machine and the thin `extern "C"` layer;
//! - [`importer`]: a small FMI 2.0 Co-Simulation importer (tests and the exporter's self-check);
//! - [`elf`]: the glibc symbol versions a shipped shared library requires.
//!
//! `unsafe` code lives only in `fmi::ffi` (the exported C functions) and `importer` (which
//! calls an FMU's C functions); everything else is safe Rust.
#![deny(unsafe_code)]

pub mod cli_simulate;
pub mod description;
pub mod elf;
pub mod fmi;
#[allow(unsafe_code)]
pub mod importer;
pub mod model;
pub mod physics;
pub mod solver;
pub mod table;
