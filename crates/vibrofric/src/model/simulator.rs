//! The object-safe face of a contact: what the FMU layer and the tests step.

use super::exchange::Exchange;
use super::ode::Ode;
use super::state::ContactState;
use super::time::MAX_INPUT_RATE;
use crate::physics::{ParamError, ParamId, Params};
use crate::solver::SolverError;
use crate::table::{Config, InputId, Inputs, OutputId, Outputs};

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
    /// A continuous state set by a Model Exchange importer that is not finite.
    State { name: &'static str, value: f64 },
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
            SimError::State { name, value } => {
                write!(f, "{name} = {value}: a continuous state must be finite")
            }
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
pub trait Simulator: Send + Exchange {
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
    /// The complete state; [`Simulator::restore`] on a simulator built with the same
    /// configuration continues bit for bit.
    fn snapshot(&self) -> ContactState;
    /// Restores a state after checking every field (it is untrusted input); on error nothing
    /// changes.
    fn restore(&mut self, state: &ContactState) -> Result<(), SimError>;
    /// A copy of this simulator.
    fn clone_box(&self) -> Box<dyn Simulator>;
    /// The equations this simulator integrates, with its inputs as they are set now (held),
    /// as a plain ODE for another integrator.
    fn ode(&self) -> Box<dyn Ode>;
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
