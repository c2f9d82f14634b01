//! The contact as a simulator: the object the FMU steps, with no knowledge of FMI.
//!
//! [`build`] turns a [`Config`] into a [`Simulator`] whose arithmetic is specialised at compile
//! time for the law, the motion and the drive; the support sources are chosen at run time, where
//! they cost one branch. The files, each one job:
//! - `simulator.rs`: the object-safe [`Simulator`] trait, its errors and work counters;
//! - `setup.rs`: [`Setup`], the one way from a configuration, parameters and inputs to a
//!   simulator (used by the FMU instance, the command line, the tests and the examples);
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
pub use exchange::DOMAIN_FACTOR;
pub use ode::Ode;
pub use setup::Setup;
pub use simulator::{
    EventUpdate, Exchange, Integrator, SimError, Simulator, StateVector, StepStats, TOLERANCE_RANGE,
};
pub use state::{ContactState, StepMeanState, WindowState};
pub use time::{canonical_time, MAX_INPUT_RATE, WINDOWS_MAX};

use crate::physics::{Dahl, Dupont, LuGre, Planar};
use crate::table::{ParamId, Params};
use contact::boxed;
use drive::{Force, Spring, VelocityFree, VelocityGuided};

/// Builds the simulator for a configuration, with the body at rest at the origin, zero
/// deformation, zero inputs, starting at `t_start` with relative tolerance `tolerance`. It takes
/// the fastest path the configuration allows.
pub fn build(
    config: Config,
    params: Params,
    t_start: f64,
    tolerance: f64,
) -> Result<Box<dyn Simulator>, SimError> {
    build_on(config, params, t_start, tolerance, false)
}

/// [`build`], with `force_radau` whether the simulator takes the general integrator
/// ([`Integrator::Radau`]) at every step even where a faster path applies (the reference of
/// the tests and benchmarks of the fast paths).
pub fn build_on(
    config: Config,
    params: Params,
    t_start: f64,
    tolerance: f64,
    force_radau: bool,
) -> Result<Box<dyn Simulator>, SimError> {
    consistent(config, &params)?;
    build_inconsistent(config, params, t_start, tolerance, force_radau)
}

/// The rules between parameters that each obey their own range: what a simulation refuses to
/// start from (LuGre's static force below the Coulomb force at the reference load). An FMU
/// applies them when initialization ends, not to the values it reads before.
pub fn consistent(config: Config, params: &Params) -> Result<(), SimError> {
    if config.law.has_static_force() {
        if let Some(why) = params.static_force_inverted() {
            return Err(SimError::Inconsistent(why));
        }
    }
    Ok(())
}

/// [`build_on`] without the rules of [`consistent`]: the model at parameters that are not
/// final yet, for reading values (each parameter still obeys its own range).
fn build_inconsistent(
    config: Config,
    params: Params,
    t_start: f64,
    tolerance: f64,
    force_radau: bool,
) -> Result<Box<dyn Simulator>, SimError> {
    params.validate()?;
    for id in ParamId::ALL {
        if id.present(&config) {
            id.check_in(id.get(&params), &config)?;
        }
    }
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(SimError::Tolerance(tolerance));
    }
    let tolerance = tolerance.clamp(TOLERANCE_RANGE.0, TOLERANCE_RANGE.1);
    if !t_start.is_finite() {
        return Err(SimError::Time {
            now: t_start,
            target: t_start,
        });
    }
    let (c, radau) = (config, force_radau);
    // One arm per (motion, drive) gives the state dimension N at compile time; the law is a
    // type parameter, so every combination is a separately optimised code path.
    macro_rules! with_law {
        ($v:ty, $d:ty, $n:literal) => {
            match c.law {
                Law::Dahl => boxed::<$v, Dahl, $d, $n>(c, params, t_start, tolerance, radau),
                Law::Dupont => boxed::<$v, Dupont, $d, $n>(c, params, t_start, tolerance, radau),
                Law::LuGre => boxed::<$v, LuGre, $d, $n>(c, params, t_start, tolerance, radau),
            }
        };
    }
    Ok(match (c.motion, c.drive, c.lateral) {
        (Motion::Longitudinal, Drive::Velocity, _) => with_law!(f64, VelocityGuided, 1),
        (Motion::Longitudinal, Drive::Force, _) => with_law!(f64, Force, 3),
        (Motion::Longitudinal, Drive::Spring, _) => with_law!(f64, Spring, 3),
        (Motion::Planar, Drive::Velocity, Lateral::Guided) => {
            with_law!(Planar, VelocityGuided, 2)
        }
        (Motion::Planar, Drive::Velocity, Lateral::Free) => with_law!(Planar, VelocityFree, 4),
        (Motion::Planar, Drive::Force, _) => with_law!(Planar, Force, 6),
        (Motion::Planar, Drive::Spring, _) => with_law!(Planar, Spring, 6),
    })
}
