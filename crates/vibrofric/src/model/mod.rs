//! The contact as a simulator: the object the FMU steps, with no knowledge of FMI.
//!
//! [`build`](fn@build) turns a [`Config`] into a [`Simulator`] whose arithmetic is specialised at
//! compile time for the law, the motion and the drive; the support sources are chosen at run
//! time, where they cost one branch. The files, each one job:
//! - `simulator.rs`: the object-safe [`Simulator`] trait, its errors and work counters;
//! - `setup.rs`: [`Setup`], the one way from a configuration, parameters and inputs to a
//!   simulator (used by the FMU instance, the command line, the tests and the examples);
//! - `build.rs`: [`build`](fn@build), the simulator's type for a configuration, and the checks
//!   before;
//! - `drive.rs`: how the body is moved (force, velocity, spring drive) and its equations;
//! - `dynamics.rs`: the right-hand side and its Jacobian: deformation rate of the law, body,
//!   normal load and lift-off, the relative velocity from the sources;
//! - `contact.rs`: the contact the simulator steps: communication steps, averaging windows,
//!   outputs;
//! - `paths/`: the ways a contact is advanced, one room each (the closed form, the exponential
//!   path, the explicit path, the planar explicit path with its steps on the Coulomb limit,
//!   Radau IIA), behind one interface, and the one choice between them (`paths/mod.rs`);
//! - `state.rs`, `snapshot.rs`: the contact's complete state by name; taking it and restoring
//!   it with every field checked;
//! - `window.rs`: the running means (`F_mean` over averaging windows, the step means);
//! - `time.rs`: communication points as importers compute them, and time limits;
//! - `ode.rs`: the equations as a plain ODE for other integrators;
//! - `exchange.rs`: the contact for an importer's integrator (Model Exchange): states,
//!   derivatives, event indicators and updates, directional derivatives.

mod build;
mod contact;
mod drive;
mod dynamics;
mod exchange;
mod ode;
mod paths;
mod setup;
mod simulator;
mod snapshot;
mod state;
pub mod string;
mod time;
mod window;

pub use crate::table::{
    Config, Drive, InputId, Inputs, Lateral, Law, Motion, OutputId, Outputs, StateId,
};
pub use build::{build, build_on, consistent};
pub use exchange::DOMAIN_FACTOR;
pub use ode::Ode;
pub use setup::Setup;
pub use simulator::{
    EventUpdate, Exchange, Integrator, SimError, Simulator, StateVector, StepStats, TOLERANCE_RANGE,
};
pub use state::{ContactState, StepMeanState, WindowState};
pub use time::{canonical_time, MAX_INPUT_RATE, WINDOWS_MAX};
