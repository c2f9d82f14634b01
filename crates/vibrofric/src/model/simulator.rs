//! The object-safe face of a contact: what the FMU layer and the tests step.

use super::contact::{boxed, Force, Spring, VelocityFree, VelocityGuided, MAX_INPUT_RATE};
use super::{Config, Drive, InputId, Inputs, Lateral, Law, Motion, OutputId, Outputs};
use crate::physics::{Dahl, Dupont, LuGre, ParamError, ParamId, Params, Planar};
use crate::solver::SolverError;

/// Why a simulator refused a call. The simulator is unchanged when an error is returned.
#[derive(Clone, Debug, PartialEq)]
pub enum SimError {
    /// A parameter out of its physical range.
    Param(ParamError),
    /// A parameter that cannot change after initialisation.
    NotTunable(&'static str),
    /// An input out of its range (see [`InputId::rule`]).
    Input { id: InputId, value: f64 },
    /// An input derivative that is not finite or beyond [`MAX_INPUT_RATE`].
    InputDerivative { id: InputId, value: f64 },
    /// An input the configuration does not have.
    NoSuchInput(&'static str),
    /// A parameter that is an input in this configuration (`F_N` with `normal = "input"`).
    NoSuchParam(&'static str),
    /// A target time that is not after the current time, or not finite.
    Time { now: f64, target: f64 },
    /// A tolerance that is not finite and > 0.
    Tolerance(f64),
    /// The integrator could not reach the target (step size underflow, Newton failure).
    Solver(SolverError),
    /// A saved state that does not belong to this configuration.
    BadSnapshot(String),
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SimError::Param(e) => write!(f, "{e}"),
            SimError::NotTunable(n) => write!(
                f,
                "{n}: has variability fixed and cannot change after initialization"
            ),
            SimError::Input { id, value } => write!(
                f,
                "{} = {value}: {}",
                id.name(),
                id.rule().text(*value, id.unit())
            ),
            SimError::InputDerivative { id, value } => write!(
                f,
                "derivative of {} = {value}: must be finite and at most {MAX_INPUT_RATE:e} {}/s in magnitude",
                id.name(),
                id.unit()
            ),
            SimError::NoSuchInput(n) => write!(f, "{n}: this scene has no such input"),
            SimError::NoSuchParam(n) => {
                write!(
                    f,
                    "{n}: an input in this scene (normal = \"input\"), not a parameter"
                )
            }
            SimError::Time { now, target } => write!(
                f,
                "step target time {target} must be finite and later than the current time {now}"
            ),
            SimError::Tolerance(t) => write!(f, "tolerance = {t}: must be finite and > 0"),
            SimError::Solver(e) => write!(f, "{e}"),
            SimError::BadSnapshot(why) => write!(f, "state does not fit this instance: {why}"),
        }
    }
}

impl std::error::Error for SimError {}

impl From<ParamError> for SimError {
    fn from(e: ParamError) -> Self {
        SimError::Param(e)
    }
}

/// Work done by the integrator, cumulative since the simulator was built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepStats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps (error test or Newton failure).
    pub rejected: u64,
    /// Right-hand-side evaluations (Jacobian columns included).
    pub rhs_evals: u64,
    /// Jacobian evaluations.
    pub jacobians: u64,
    /// Located switching events (sign changes of the relative velocity, ...).
    pub events: u64,
}

/// A contact that can be stepped in time. Every method that returns an error leaves the
/// simulator exactly as it was.
pub trait Simulator: Send {
    fn config(&self) -> Config;
    fn params(&self) -> &Params;
    /// Changes a parameter during the simulation. Only the parameters for which
    /// [`ParamId::tunable`] is true may change; the source stays continuous in phase.
    fn set_param(&mut self, id: ParamId, value: f64) -> Result<(), SimError>;
    /// Current time.
    fn time(&self) -> f64;
    /// Relative tolerance of the integrator.
    fn tolerance(&self) -> f64;
    /// Sets an input; the value holds from the current time on (plus its derivative, if set).
    fn set_input(&mut self, id: InputId, value: f64) -> Result<(), SimError>;
    /// Sets the first time derivative of an input, used for linear extrapolation over the next
    /// [`Simulator::step_to`] only.
    fn set_input_derivative(&mut self, id: InputId, value: f64) -> Result<(), SimError>;
    /// Inputs at the current time.
    fn inputs(&self) -> Inputs;
    /// Integrates exactly to `t_end`.
    fn step_to(&mut self, t_end: f64) -> Result<(), SimError>;
    /// Outputs at the current time.
    fn outputs(&self) -> Outputs;
    /// Integrator work since the simulator was built.
    /// The exact first time derivative of an output at the current time, where the model has
    /// one (see the implementation for which); `None` elsewhere.
    fn output_derivative(&self, id: OutputId) -> Option<f64>;
    fn stats(&self) -> StepStats;
    /// The integrator this simulator steps with.
    fn path(&self) -> Path;
    /// The complete state as numbers; [`Simulator::restore`] on a simulator built with the same
    /// configuration continues bit-for-bit.
    fn snapshot(&self) -> Vec<f64>;
    fn restore(&mut self, state: &[f64]) -> Result<(), SimError>;
    /// A copy of this simulator.
    fn clone_box(&self) -> Box<dyn Simulator>;
    /// The equations this simulator integrates, with its inputs as they are set now (held),
    /// as a plain ODE for another integrator.
    fn ode(&self) -> Box<dyn Ode>;
}

/// The contact's equations as a plain ODE `dy/dt = f(t, y)`, with the inputs held: what another
/// integrator (the report's peers, or a user's own solver) needs to solve the same problem.
/// The state is `[s | body]` as in the simulator; harmonic source and input tracks are
/// evaluated exactly as the simulator does.
pub trait Ode: Send + Sync {
    /// Number of state components.
    fn dim(&self) -> usize;
    /// The simulator's state when the view was taken.
    fn state(&self) -> Vec<f64>;
    /// Natural magnitude of each component (for absolute tolerances).
    fn scale(&self) -> Vec<f64>;
    /// `dy = f(t, y)`.
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]);
    /// `∂f/∂y` at `(t, y)`, row-major `dim × dim`, in closed form.
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut [f64]);
    /// Friction force `F_Fx` at `(t, y)`.
    fn f_fx(&self, t: f64, y: &[f64]) -> f64;
    /// `v_rx`, whose sign changes are the kinks of `f`.
    fn v_rx(&self, t: f64, y: &[f64]) -> f64;
}

/// The integrator a simulator steps with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Path {
    /// The deformation in closed form between sign changes of `v_r`, only the mean force by
    /// quadrature (longitudinal Dahl, `kappa = 1`, velocity drive).
    ClosedForm,
    /// The deformation by exponential integration in the relaxation arc length, explicit and
    /// of the same cost at any contact stiffness (velocity drives with the lateral motion
    /// guided and a law linear in `s`: planar Dahl, LuGre).
    Exponential,
    /// Radau IIA of order 5 on the whole state: every other contact, and the reference the
    /// fast paths are tested against.
    Radau,
}

/// The relative tolerances the integrators accept; others are clamped to it. Below 1e-12 the
/// rounding of the sums dominates (the fast paths floor at 1e-13 and 1e-14 anyway) and Radau's
/// work grows without bound; above 1e-2 the error estimates no longer describe the error.
pub const TOLERANCE_RANGE: (f64, f64) = (1e-12, 1e-2);

/// Builds the simulator for a configuration, with the body at rest at the origin, zero
/// deformation, zero inputs, starting at `t_start` with relative tolerance `tolerance`. It takes
/// the fastest path the configuration allows.
pub fn build(
    config: Config,
    params: Params,
    t_start: f64,
    tolerance: f64,
) -> Result<Box<dyn Simulator>, SimError> {
    build_on(config, params, t_start, tolerance, Path::ClosedForm)
}

/// [`build`] with the path chosen: [`Path::Radau`] forces the general integrator (for tests and
/// benchmarks of the fast paths); any other takes the fastest that applies.
pub fn build_on(
    config: Config,
    params: Params,
    t_start: f64,
    tolerance: f64,
    path: Path,
) -> Result<Box<dyn Simulator>, SimError> {
    params.validate()?;
    for id in ParamId::ALL {
        if super::param_present(id, &config) {
            super::check_param(id, id.get(&params), &config)?;
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
    let c = config;
    // One arm per (motion, drive) gives the state dimension N at compile time; the law is a
    // type parameter, so every combination is a separately optimised code path.
    macro_rules! with_law {
        ($v:ty, $d:ty, $n:literal) => {
            match c.law {
                Law::Dahl => boxed::<$v, Dahl, $d, $n>(c, params, t_start, tolerance, path),
                Law::Dupont => boxed::<$v, Dupont, $d, $n>(c, params, t_start, tolerance, path),
                Law::LuGre => boxed::<$v, LuGre, $d, $n>(c, params, t_start, tolerance, path),
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
