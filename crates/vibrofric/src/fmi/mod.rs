//! The FMI layer: one standard-neutral instance ([`instance`]: life cycle, values by value
//! reference, stepping, saved states, Model Exchange; a refusal is a [`Refusal`] value) and a
//! thin layer per FMI version ([`fmi2`], [`fmi3`]: its C types, its table of allowed states and
//! its `extern "C"` functions; these and `c_boundary.rs` are the only `unsafe` code of the FMU).

#[allow(unsafe_code)]
mod c_boundary;
pub mod fmi2;
pub mod fmi3;
pub mod instance;
pub mod log;
pub mod refusal;
pub mod saved;
pub mod staging;
pub mod state;
mod status;
pub mod uri;

pub use instance::{EventInfo, Instance};
pub use log::{Logger, NoLogger};
pub use refusal::{Answer, Refusal};
pub use saved::FmuState;
pub use state::{Call, Interface, State, States};
pub use status::Status;
