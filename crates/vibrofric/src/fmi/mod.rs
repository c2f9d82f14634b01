//! The FMI layer: one standard-neutral instance ([`instance`]: life cycle, staged values,
//! get/set by value reference, stepping, saved states) and a thin layer per FMI version
//! ([`fmi2`]: its C types, its table of allowed states and its `extern "C"` functions, the only
//! `unsafe` code of the FMU). `model_exchange.rs` adds the instance's Model Exchange functions.

#[allow(unsafe_code)]
mod c_boundary;
pub mod fmi2;
pub mod fmi3;
pub mod instance;
pub mod log;
pub mod model_exchange;
pub mod saved;
pub mod staging;
pub mod state;
mod status;
pub mod uri;

pub use instance::Instance;
pub use log::{Logger, NoLogger};
pub use saved::FmuState;
pub use state::{Call, Interface, State, States};
pub use status::Status;
