//! The contact as a simulator: configuration, inputs, outputs, and the object the FMU steps.
//!
//! Everything here is plain Rust with no knowledge of FMI. [`build`] turns a [`Config`] into a
//! [`Simulator`] whose arithmetic is specialised at compile time for the law, the motion and the
//! drive (see `contact.rs`); the support sources are chosen at run time, where they cost one
//! branch.

mod contact;
mod exact;
mod ids;
mod simulator;

pub use crate::table::{Config, Drive, Lateral, Law, Motion};
pub use contact::{canonical_time, MAX_INPUT_RATE};
pub use ids::{check_param, param_present, param_rule, InputId, Inputs, OutputId, Outputs};
pub use simulator::{build, build_on, Ode, Path, SimError, Simulator, StepStats, TOLERANCE_RANGE};
