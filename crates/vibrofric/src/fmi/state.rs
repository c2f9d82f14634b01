//! The states an instance can be in, and the set of states a call is allowed in. Each FMI
//! version's layer holds its own table of allowed states per function (`fmi2/functions.rs`,
//! `fmi3/functions.rs`) and hands the instance a [`Call`]: the function's name (for messages)
//! and where it is allowed, which the instance checks once at the entry of every call
//! ([`Instance::answer`](super::Instance::answer)).

use serde::{Deserialize, Serialize};

/// The states of the Co-Simulation and Model Exchange state machines this FMU can be in. A
/// synchronous slave is never in FMI 2.0's `stepInProgress` or `stepCanceled`; an instance for
/// Co-Simulation is never in the two modes of Model Exchange, and the converse.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum State {
    Instantiated,
    InitializationMode,
    StepComplete,
    /// After a step returned `Discard` (the integrator could not reach the end of the step;
    /// the instance is still at the step's start).
    StepFailed,
    Terminated,
    Error,
    Fatal,
    /// Model Exchange: discrete changes (events) are handled.
    EventMode,
    /// Model Exchange: the importer integrates the continuous states.
    ContinuousTimeMode,
}

impl State {
    pub const ALL: [State; 9] = [
        State::Instantiated,
        State::InitializationMode,
        State::StepComplete,
        State::StepFailed,
        State::Terminated,
        State::Error,
        State::Fatal,
        State::EventMode,
        State::ContinuousTimeMode,
    ];

    pub fn name(self) -> &'static str {
        match self {
            State::Instantiated => "Instantiated",
            State::InitializationMode => "InitializationMode",
            State::StepComplete => "StepComplete",
            State::StepFailed => "StepFailed",
            State::Terminated => "Terminated",
            State::Error => "Error",
            State::Fatal => "Fatal",
            State::EventMode => "EventMode",
            State::ContinuousTimeMode => "ContinuousTimeMode",
        }
    }
}

/// The interface an instance was made for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Interface {
    CoSimulation,
    ModelExchange,
}

impl Interface {
    pub fn name(self) -> &'static str {
        match self {
            Interface::CoSimulation => "Co-Simulation",
            Interface::ModelExchange => "Model Exchange",
        }
    }
}

/// A set of states.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct States(u32);

use State::{
    ContinuousTimeMode as Continuous, Error, EventMode as Event, InitializationMode as Init,
    Instantiated, StepComplete, StepFailed, Terminated,
};

impl States {
    pub const fn of(states: &[State]) -> States {
        let mut bits = 0;
        let mut k = 0;
        while k < states.len() {
            bits |= 1 << states[k] as u32;
            k += 1;
        }
        States(bits)
    }

    pub const fn contains(self, s: State) -> bool {
        self.0 & (1 << s as u32) != 0
    }

    /// Every state but `Fatal`.
    pub const ANY: States = States::of(&[
        Instantiated,
        Init,
        StepComplete,
        StepFailed,
        Terminated,
        Error,
        Event,
        Continuous,
    ]);
    /// Every state: calls that answer (with an error) even after a fatal one.
    pub const EVERY: States = States::of(&State::ALL);
    /// Getting values: from initialization on.
    pub const GET: States = States::of(&[
        Init,
        StepComplete,
        StepFailed,
        Terminated,
        Error,
        Event,
        Continuous,
    ]);
    /// Setting values: parameters and inputs before initialization ends; then, in
    /// Co-Simulation between steps, in Model Exchange tunable parameters and inputs in event
    /// mode and inputs in continuous-time mode (the instance checks which).
    pub const SET: States = States::of(&[Instantiated, Init, StepComplete, Event, Continuous]);
    /// Evaluating the model's equations (derivatives, event indicators, states): from
    /// initialization on, in the states of Model Exchange.
    pub const EVALUATE: States = States::of(&[Init, Event, Continuous, Terminated, Error]);
    /// Nominal values of the states: also before initialization.
    pub const NOMINALS: States =
        States::of(&[Instantiated, Init, Event, Continuous, Terminated, Error]);
    /// Directional derivatives: from initialization on (a Co-Simulation instance answers
    /// that it has none).
    pub const DIRECTIONAL: States = States::of(&[
        Init,
        StepComplete,
        StepFailed,
        Event,
        Continuous,
        Terminated,
        Error,
    ]);

    /// The states' names, comma-separated, in the order of [`State::ALL`].
    pub fn names(self) -> String {
        State::ALL
            .iter()
            .filter(|s| self.contains(**s))
            .map(|s| s.name())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// One call of the C interface as the instance sees it: its name, the states it is allowed in,
/// and the names of the version's other functions its messages may point the user to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Call {
    pub name: &'static str,
    pub allowed: States,
    /// The interface the function belongs to (`None`: a function common to both).
    pub only: Option<Interface>,
    pub words: &'static Vocabulary,
}

/// The names of an FMI version's functions and arguments that messages point the user to.
#[derive(Debug, PartialEq, Eq)]
pub struct Vocabulary {
    /// The standard's edition: "FMI 2.0", "FMI 3.0".
    pub edition: &'static str,
    pub reset: &'static str,
    pub set_state: &'static str,
    pub exit_initialization: &'static str,
    /// The call that sets the experiment (tolerance, start and stop time).
    pub setup_experiment: &'static str,
    pub do_step: &'static str,
    /// The call that sets the continuous states (Model Exchange).
    pub set_states: &'static str,
    pub last_successful_time: &'static str,
    /// The boolean false of the C interface.
    pub false_: &'static str,
    /// The FMU-state argument and type, and the functions that make and measure states.
    pub state_arg: &'static str,
    pub state_type: &'static str,
    pub get_state: &'static str,
    pub deserialize_state: &'static str,
    pub state_size: &'static str,
    /// The value reference of the independent variable `time` where the version declares it
    /// as a variable (FMI 3.0); `None` where it does not (FMI 2.0).
    pub time_vr: Option<u32>,
}
