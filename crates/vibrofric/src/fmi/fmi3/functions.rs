//! Every function of the FMI 3.0 C interface and the one table of the states each may be called
//! in (FMI 3.0, the state machine of Co-Simulation without event mode). Model Exchange,
//! Scheduled Execution, clocks, event mode and configuration mode are not offered: their
//! functions answer with an error in every state.

use crate::fmi::state::{Call, State, States, Vocabulary};

/// A function of the FMI 3.0 C interface that acts on an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    InstantiateCoSimulation,
    InstantiateModelExchange,
    InstantiateScheduledExecution,
    FreeInstance,
    SetDebugLogging,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    GetFloat64,
    SetFloat64,
    /// `fmi3Get<Type>` of a type this FMU has no variables of (the name in the argument).
    GetOther(&'static str),
    /// `fmi3Set<Type>` likewise.
    SetOther(&'static str),
    GetFMUState,
    SetFMUState,
    FreeFMUState,
    SerializedFMUStateSize,
    SerializeFMUState,
    DeserializeFMUState,
    GetOutputDerivatives,
    DoStep,
    /// A function of an interface or mode this FMU does not offer (the name in the argument).
    Unsupported(&'static str),
}

use State::{
    Error, InitializationMode as Init, Instantiated, StepComplete, StepFailed, Terminated,
};

/// Every state but `Fatal`.
const ANY: States = States::of(&[
    Instantiated,
    Init,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
]);
const EVERY: States = States::of(&State::ALL);
const GET: States = States::of(&[Init, StepComplete, StepFailed, Terminated, Error]);
const SET: States = States::of(&[Instantiated, Init, StepComplete]);

impl Function {
    /// The C name.
    pub const fn name(self) -> &'static str {
        use Function::*;
        match self {
            InstantiateCoSimulation => "fmi3InstantiateCoSimulation",
            InstantiateModelExchange => "fmi3InstantiateModelExchange",
            InstantiateScheduledExecution => "fmi3InstantiateScheduledExecution",
            FreeInstance => "fmi3FreeInstance",
            SetDebugLogging => "fmi3SetDebugLogging",
            EnterInitializationMode => "fmi3EnterInitializationMode",
            ExitInitializationMode => "fmi3ExitInitializationMode",
            Terminate => "fmi3Terminate",
            Reset => "fmi3Reset",
            GetFloat64 => "fmi3GetFloat64",
            SetFloat64 => "fmi3SetFloat64",
            GetOther(name) | SetOther(name) | Unsupported(name) => name,
            GetFMUState => "fmi3GetFMUState",
            SetFMUState => "fmi3SetFMUState",
            FreeFMUState => "fmi3FreeFMUState",
            SerializedFMUStateSize => "fmi3SerializedFMUStateSize",
            SerializeFMUState => "fmi3SerializeFMUState",
            DeserializeFMUState => "fmi3DeserializeFMUState",
            GetOutputDerivatives => "fmi3GetOutputDerivatives",
            DoStep => "fmi3DoStep",
        }
    }

    /// The states the function may be called in.
    pub const fn allowed(self) -> States {
        use Function::*;
        match self {
            InstantiateCoSimulation
            | InstantiateModelExchange
            | InstantiateScheduledExecution
            | FreeInstance
            | Unsupported(_) => EVERY,
            SetDebugLogging | Reset => ANY,
            EnterInitializationMode => States::of(&[Instantiated]),
            ExitInitializationMode => States::of(&[Init]),
            Terminate => States::of(&[StepComplete, StepFailed]),
            GetFloat64 | GetOther(_) => GET,
            SetFloat64 | SetOther(_) => SET,
            GetFMUState
            | SetFMUState
            | FreeFMUState
            | SerializedFMUStateSize
            | SerializeFMUState
            | DeserializeFMUState => ANY,
            GetOutputDerivatives => States::of(&[StepComplete, StepFailed, Terminated, Error]),
            DoStep => States::of(&[StepComplete]),
        }
    }

    /// The call as the instance sees it.
    pub const fn call(self) -> Call {
        Call {
            name: self.name(),
            allowed: self.allowed(),
            words: &WORDS,
        }
    }
}

/// What messages call the FMI 3.0 functions they point to.
pub static WORDS: Vocabulary = Vocabulary {
    reset: "fmi3Reset",
    set_state: "fmi3SetFMUState",
    exit_initialization: "fmi3ExitInitializationMode",
    setup_experiment: "fmi3EnterInitializationMode",
    do_step: "fmi3DoStep",
    set_states: "fmi3SetContinuousStates",
    last_successful_time: "lastSuccessfulTime of fmi3DoStep",
    false_: "fmi3False",
    state_arg: "FMUState",
    state_type: "fmi3FMUState",
    get_state: "fmi3GetFMUState",
    deserialize_state: "fmi3DeserializeFMUState",
    state_size: "fmi3SerializedFMUStateSize",
};
