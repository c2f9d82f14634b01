//! What the integration tests share, in one place, kept in two kinds:
//! - [`reference`], [`configs`]: independent truth (closed forms, exact solutions, reference
//!   integrations written here) and named configurations; they never call the code under test;
//! - [`scenes`], [`fmu`]: the harness: the standard scenes, the core built from a scene, and the
//!   FMU built around this test run's library and driven through `vibrofric_import`.
//!
//! A test includes it with `mod support;` and uses what it needs; examples include
//! `reference.rs` or `configs.rs` alone by path.
#![allow(dead_code, unused_macros)]

pub mod configs;
#[macro_use]
pub mod fmu;
pub mod reference;
pub mod scenes;
