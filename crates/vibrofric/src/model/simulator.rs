//! The object-safe face of a contact: what the FMU layer and the tests step.

use super::ode::Ode;
use super::state::ContactState;
use super::time::MAX_INPUT_RATE;
use crate::solver::SolverError;
use crate::table::{number, Config, InputId, Inputs, OutputId, Outputs, StateId};
use crate::table::{ParamError, ParamId, Params};

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
    /// Parameters that each obey their rule but not together (the text names them).
    Inconsistent(String),
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
                "{} = {}: {}",
                id.name(),
                number(*value),
                id.rule().text(*value, id.unit())
            ),
            SimError::InputDerivative { id, value } => write!(
                f,
                "derivative of {} = {}: must be finite and at most {} {}/s in magnitude",
                id.name(),
                number(*value),
                number(MAX_INPUT_RATE),
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
                "step target time {} must be finite and later than the current time {}",
                number(*target),
                number(*now)
            ),
            SimError::Tolerance(t) => {
                write!(f, "tolerance = {}: must be finite and > 0", number(*t))
            }
            SimError::Solver(e) => write!(f, "{e}"),
            SimError::BadSnapshot(why) => write!(f, "state does not fit this instance: {why}"),
            SimError::Inconsistent(why) => write!(f, "{why}"),
            SimError::State { name, value } => {
                write!(
                    f,
                    "{name} = {}: a continuous state must be finite",
                    number(*value)
                )
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
    /// Of `steps`, those of the planar explicit path taken on the slow manifold of a stiff Dahl
    /// contact (the Coulomb limit: the body alone, the deformation a function of its motion).
    pub limit_steps: u64,
}

impl From<crate::solver::SolverStats> for StepStats {
    fn from(s: crate::solver::SolverStats) -> Self {
        StepStats {
            steps: s.steps,
            rejected: s.rejected,
            rhs_evals: s.rhs_evals,
            jacobians: s.jacobians,
            events: s.events,
            limit_steps: s.limit_steps,
        }
    }
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
    /// The integrator the next step takes: chosen again at every step from the contact's
    /// structure and, where a path holds only within limits, from its state and inputs (the
    /// motion leaving the x axis, a Dupont body sliding too fast for the planar explicit path).
    fn integrator(&self) -> Integrator;
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
pub enum Integrator {
    /// The deformation in closed form between sign changes of `v_r`, only the mean force by
    /// quadrature (longitudinal Dahl, `kappa = 1`, velocity drive).
    ClosedForm,
    /// The deformation by exponential integration in the relaxation arc length, explicit and
    /// of the same cost at any contact stiffness (velocity drives with the lateral motion
    /// guided and a law linear in `s`: planar Dahl, LuGre).
    Exponential,
    /// A moving body (force or spring drive) on a Dahl contact with `kappa = 1`, motion along
    /// x: the deformation in closed form in the relative displacement between sign changes of
    /// `v_r`, the body by Dormand–Prince 5(4) with error control, each step cut at a located
    /// sign change. Planar contacts take it while they move on x only.
    Explicit,
    /// A moving body on a planar Dahl contact with `kappa = 1` off the x axis, or on a planar
    /// LuGre contact: the whole state by Dormand–Prince 5(4) with error control, the deformation
    /// exponentially in the relaxation arc length where it relaxes fast, while the contact is
    /// not stiff on the scale of the averaging window (else Radau).
    ExplicitPlanar,
    /// Radau IIA of order 5 on the whole state: every other contact, and the reference the
    /// fast paths are tested against.
    Radau,
}

/// The relative tolerances the integrators accept; others are clamped to it. Below 1e-12 the
/// rounding of the sums dominates (the fast paths floor at 1e-13 and 1e-14 anyway) and Radau's
/// work grows without bound; above 1e-2 the error estimates no longer describe the error.
pub const TOLERANCE_RANGE: (f64, f64) = (1e-12, 1e-2);

/// Values indexed by [`StateId::index`] (0 where the configuration has no such state).
pub type StateVector = [f64; StateId::COUNT];

/// What an event update did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventUpdate {
    /// A continuous state jumped (a window restarted `F_int`, a lift-off cleared `s`).
    pub states_changed: bool,
    /// The next time event (the end of the averaging window), in the importer's time.
    pub next_time: Option<f64>,
}

/// The contact as Model Exchange sees it. Every method that returns an error leaves the
/// contact as it was.
pub trait Exchange {
    /// The continuous states now.
    fn states(&self) -> StateVector;
    /// Sets the states the configuration has (the others are ignored).
    fn set_states(&mut self, x: &StateVector) -> Result<(), SimError>;
    /// The states' derivatives at the current time, states and inputs.
    fn derivatives(&self) -> StateVector;
    /// Nominal magnitudes of the states.
    fn nominals(&self) -> StateVector;
    /// Moves the contact to the importer's time `t`; the states and the inputs keep their
    /// values.
    fn set_time(&mut self, t: f64) -> Result<(), SimError>;
    /// Sets an input from the current time on. Unlike [`Simulator::set_input`], a normal
    /// force crossing the lift-off load changes nothing until the event update.
    fn set_input_continuous(&mut self, id: InputId, value: f64) -> Result<(), SimError>;
    /// The event indicators, [`crate::table::Config::event_indicators`] of them.
    fn event_indicators(&self, z: &mut [f64]);
    /// The event update at the current time: completes the windows that have ended, takes the
    /// sides of the switching functions, lifts the body off or lands it.
    fn update_events(&mut self) -> EventUpdate;
    /// The directional derivative of the derivatives and of the outputs along a change `dx` of
    /// the states and `du` of the inputs, in closed form (forward mode through the law's
    /// partial derivatives).
    fn tangent(&self, dx: &StateVector, du: &Inputs) -> (StateVector, Outputs);
    /// Why the states an importer set are outside the model's domain (far from any
    /// trajectory: a deformation beyond [`super::DOMAIN_FACTOR`] times the law's
    /// bound), if they are.
    fn out_of_domain(&self) -> Option<String>;
    /// [`Simulator::restore`] of a state a Model Exchange importer drove: its time is where
    /// the importer set it (anywhere [`Exchange::set_time`] accepts), not necessarily inside
    /// the averaging window in progress.
    fn restore_exchange(&mut self, state: &ContactState) -> Result<(), SimError>;
}
