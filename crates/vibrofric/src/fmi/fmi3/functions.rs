//! Every function of the FMI 3.0 C interface and the one table of the states each may be called
//! in (FMI 3.0, the state machines of Model Exchange and of Co-Simulation without event mode;
//! an instance is in the states of one of them only). Scheduled Execution, clocks, the event
//! mode of Co-Simulation and configuration mode are not offered: their functions answer with an
//! error in every state.

use crate::description::xml3::TIME_VR;
use crate::fmi::state::{Call, Interface, State, States, Vocabulary};

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
    GetDirectionalDerivative,
    EnterEventMode,
    UpdateDiscreteStates,
    EnterContinuousTimeMode,
    CompletedIntegratorStep,
    SetTime,
    SetContinuousStates,
    GetContinuousStateDerivatives,
    GetEventIndicators,
    GetContinuousStates,
    GetNominalsOfContinuousStates,
    GetNumberOfEventIndicators,
    GetNumberOfContinuousStates,
    /// A function of an interface or mode this FMU does not offer (the name in the argument).
    Unsupported(&'static str),
}

use State::{
    ContinuousTimeMode as Continuous, Error, EventMode as Event, InitializationMode as Init,
    Instantiated, StepComplete, StepFailed, Terminated,
};

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
            GetDirectionalDerivative => "fmi3GetDirectionalDerivative",
            EnterEventMode => "fmi3EnterEventMode",
            UpdateDiscreteStates => "fmi3UpdateDiscreteStates",
            EnterContinuousTimeMode => "fmi3EnterContinuousTimeMode",
            CompletedIntegratorStep => "fmi3CompletedIntegratorStep",
            SetTime => "fmi3SetTime",
            SetContinuousStates => "fmi3SetContinuousStates",
            GetContinuousStateDerivatives => "fmi3GetContinuousStateDerivatives",
            GetEventIndicators => "fmi3GetEventIndicators",
            GetContinuousStates => "fmi3GetContinuousStates",
            GetNominalsOfContinuousStates => "fmi3GetNominalsOfContinuousStates",
            GetNumberOfEventIndicators => "fmi3GetNumberOfEventIndicators",
            GetNumberOfContinuousStates => "fmi3GetNumberOfContinuousStates",
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
            | Unsupported(_) => States::EVERY,
            SetDebugLogging | Reset => States::ANY,
            EnterInitializationMode => States::of(&[Instantiated]),
            ExitInitializationMode => States::of(&[Init]),
            Terminate => States::of(&[StepComplete, StepFailed, Event, Continuous]),
            GetFloat64 | GetOther(_) => States::GET,
            SetFloat64 | SetOther(_) => States::SET,
            GetFMUState
            | SetFMUState
            | FreeFMUState
            | SerializedFMUStateSize
            | SerializeFMUState
            | DeserializeFMUState => States::ANY,
            GetOutputDerivatives => States::of(&[StepComplete, StepFailed, Terminated, Error]),
            DoStep => States::of(&[StepComplete]),
            GetDirectionalDerivative => States::DIRECTIONAL,
            EnterEventMode => States::of(&[Event, Continuous]),
            UpdateDiscreteStates | EnterContinuousTimeMode => States::of(&[Event]),
            CompletedIntegratorStep | SetContinuousStates => States::of(&[Continuous]),
            SetTime => States::of(&[Event, Continuous]),
            GetContinuousStateDerivatives | GetEventIndicators | GetContinuousStates => {
                States::EVALUATE
            }
            GetNominalsOfContinuousStates => States::NOMINALS,
            GetNumberOfEventIndicators | GetNumberOfContinuousStates => States::ANY,
        }
    }

    /// The interface the function belongs to: Co-Simulation's steps and output derivatives,
    /// Model Exchange's time, modes, continuous states and event indicators are answered only
    /// by an instance of that interface (the event mode of Co-Simulation is not offered, so
    /// `fmi3EnterEventMode` and `fmi3UpdateDiscreteStates` are Model Exchange's here); `None`
    /// for the functions common to both.
    pub const fn only(self) -> Option<Interface> {
        use Function::*;
        match self {
            GetOutputDerivatives | DoStep => Some(Interface::CoSimulation),
            EnterEventMode
            | UpdateDiscreteStates
            | EnterContinuousTimeMode
            | CompletedIntegratorStep
            | SetTime
            | SetContinuousStates
            | GetContinuousStateDerivatives
            | GetEventIndicators
            | GetContinuousStates
            | GetNominalsOfContinuousStates
            | GetNumberOfEventIndicators
            | GetNumberOfContinuousStates => Some(Interface::ModelExchange),
            _ => None,
        }
    }

    /// The call as the instance sees it.
    pub const fn call(self) -> Call {
        Call {
            name: self.name(),
            allowed: self.allowed(),
            only: self.only(),
            words: &WORDS,
        }
    }
}

/// What messages call the FMI 3.0 functions they point to.
pub static WORDS: Vocabulary = Vocabulary {
    edition: "FMI 3.0",
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
    time_vr: Some(TIME_VR),
};
