//! From a configuration to the simulator of its type ([`build`], [`build_on`]), and the rules
//! between parameters checked before ([`consistent`]).

use super::contact::boxed;
use super::drive::{Force, Spring, VelocityFree, VelocityGuided};
use super::simulator::{SimError, Simulator, TOLERANCE_RANGE};
use crate::physics::{Dahl, Dupont, LuGre, Planar};
use crate::table::{Config, Drive, Lateral, Law, Motion, ParamId, Params};

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
/// ([`Integrator::Radau`](super::Integrator::Radau)) at every step even where a faster path applies (the reference of
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
pub(super) fn build_inconsistent(
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
