//! FMI 2.0 layer: the instance state machine ([`instance`], safe Rust) and the thin
//! `extern "C"` functions an importer calls ([`ffi`], the only `unsafe` code of the FMU).

#[allow(unsafe_code)]
pub mod ffi;
pub mod instance;
pub mod types;
pub mod uri;

pub use instance::{FmiState, FmuState, Instance, Logger, Status};
