//! FMI 3.0 Co-Simulation over the same instance as FMI 2.0: the C types, the functions and the
//! states each is allowed in, and the exported `extern "C"` functions (`ffi/`).

#[allow(unsafe_code)]
pub mod ffi;
pub mod functions;
pub mod types;

pub use functions::Function;

use super::Status;

/// The `fmi3Status` name of a status.
pub fn status_name(s: Status) -> &'static str {
    match s {
        Status::Ok => "fmi3OK",
        Status::Warning => "fmi3Warning",
        Status::Discard => "fmi3Discard",
        Status::Error => "fmi3Error",
        Status::Fatal | Status::Pending => "fmi3Fatal",
    }
}
