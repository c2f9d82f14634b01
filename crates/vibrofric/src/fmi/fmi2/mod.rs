//! FMI 2.0, Co-Simulation and Model Exchange: the C types, the functions and the states each
//! is allowed in, the status queries, and the exported `extern "C"` functions (`ffi.rs`, the
//! only `unsafe` code of the FMU). Everything else is the standard-neutral
//! [`Instance`](super::Instance).

pub mod co_simulation;
#[allow(unsafe_code)]
pub mod ffi;
pub mod functions;
pub mod types;

pub use functions::Function;

use super::Status;

/// The `fmi2Status` name of a status.
pub fn status_name(s: Status) -> &'static str {
    match s {
        Status::Ok => "fmi2OK",
        Status::Warning => "fmi2Warning",
        Status::Discard => "fmi2Discard",
        Status::Error => "fmi2Error",
        Status::Fatal => "fmi2Fatal",
        Status::Pending => "fmi2Pending",
    }
}
