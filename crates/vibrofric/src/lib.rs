//! vibrofric: the friction contact of a body sliding on a vibrating support (Leus & Gutowski,
//! 2024), as FMI 2.0 and FMI 3.0 FMUs for Co-Simulation and Model Exchange: the library every FMU ships.
//!
//! Layers, from the bottom up, each importing only those below it (`tests/layers.rs` checks;
//! `docs/architecture.md` draws them):
//! - [`table`]: every parameter, input, output, continuous state and scene choice declared once;
//! - [`physics`]: friction laws, support motion (no FMI, no integrator);
//! - [`solver`]: the integrators (no physics, no XML);
//! - [`model`]: a contact as a [`model::Simulator`], specialised at compile time per scene;
//! - [`description`]: scenes and the generated model descriptions (the documentation pages and
//!   `docs/scenes.md` are written by the `vibrofric-docs` crate, outside the library);
//! - [`fmi`]: one instance and the thin `extern "C"` layers of FMI 2.0 and 3.0.
//!
//! `unsafe` code lives only in the C layers; everything else is safe Rust. The importer
//! (`vibrofric-import`), the export-time writers (`vibrofric-docs`) and the command line
//! (`vibrofric-cli`) are crates of their own: the shared library carries only what an FMU runs.
#![deny(unsafe_code)]
// The library's documentation is for its developers and is read with its private items
// (`cargo doc --no-deps --document-private-items`), where the paths, the solvers and the
// string link to each other's internals.
#![allow(rustdoc::private_intra_doc_links)]
// The C library's exp, ln, pow, sin, cos differ between Linux, Windows and macOS in the last bit;
// the model calls the `libm` crate's instead (`clippy.toml` forbids the others outside tests).
#![cfg_attr(test, allow(clippy::disallowed_methods))]

pub mod description;
pub mod fmi;
pub mod model;
pub mod physics;
pub mod solver;
pub mod table;
