//! Every function of the FMI 2.0 Co-Simulation and Model Exchange interfaces and the one table
//! of the states each may be called in (FMI 2.0, sections 3.2.3 and 4.2.4: the state machines
//! of a model and of a slave; an instance is in the states of one of them only).

use crate::fmi::state::{Call, Interface, State, States, Vocabulary};

/// A function of the FMI 2.0 C interface that acts on an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    Instantiate,
    FreeInstance,
    SetDebugLogging,
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    GetReal,
    GetInteger,
    GetBoolean,
    GetString,
    SetReal,
    SetInteger,
    SetBoolean,
    SetString,
    GetFMUstate,
    SetFMUstate,
    FreeFMUstate,
    SerializedFMUstateSize,
    SerializeFMUstate,
    DeSerializeFMUstate,
    GetDirectionalDerivative,
    SetRealInputDerivatives,
    GetRealOutputDerivatives,
    DoStep,
    CancelStep,
    GetStatus,
    GetRealStatus,
    GetIntegerStatus,
    GetBooleanStatus,
    GetStringStatus,
    EnterEventMode,
    NewDiscreteStates,
    EnterContinuousTimeMode,
    CompletedIntegratorStep,
    SetTime,
    SetContinuousStates,
    GetDerivatives,
    GetEventIndicators,
    GetContinuousStates,
    GetNominalsOfContinuousStates,
}

use State::{
    ContinuousTimeMode as Continuous, Error, EventMode as Event, InitializationMode as Init,
    Instantiated, StepComplete, StepFailed, Terminated,
};

const STATUS: States = States::of(&[StepComplete, StepFailed, Terminated]);

impl Function {
    /// The C name.
    pub const fn name(self) -> &'static str {
        use Function::*;
        match self {
            Instantiate => "fmi2Instantiate",
            FreeInstance => "fmi2FreeInstance",
            SetDebugLogging => "fmi2SetDebugLogging",
            SetupExperiment => "fmi2SetupExperiment",
            EnterInitializationMode => "fmi2EnterInitializationMode",
            ExitInitializationMode => "fmi2ExitInitializationMode",
            Terminate => "fmi2Terminate",
            Reset => "fmi2Reset",
            GetReal => "fmi2GetReal",
            GetInteger => "fmi2GetInteger",
            GetBoolean => "fmi2GetBoolean",
            GetString => "fmi2GetString",
            SetReal => "fmi2SetReal",
            SetInteger => "fmi2SetInteger",
            SetBoolean => "fmi2SetBoolean",
            SetString => "fmi2SetString",
            GetFMUstate => "fmi2GetFMUstate",
            SetFMUstate => "fmi2SetFMUstate",
            FreeFMUstate => "fmi2FreeFMUstate",
            SerializedFMUstateSize => "fmi2SerializedFMUstateSize",
            SerializeFMUstate => "fmi2SerializeFMUstate",
            DeSerializeFMUstate => "fmi2DeSerializeFMUstate",
            GetDirectionalDerivative => "fmi2GetDirectionalDerivative",
            SetRealInputDerivatives => "fmi2SetRealInputDerivatives",
            GetRealOutputDerivatives => "fmi2GetRealOutputDerivatives",
            DoStep => "fmi2DoStep",
            CancelStep => "fmi2CancelStep",
            GetStatus => "fmi2GetStatus",
            GetRealStatus => "fmi2GetRealStatus",
            GetIntegerStatus => "fmi2GetIntegerStatus",
            GetBooleanStatus => "fmi2GetBooleanStatus",
            GetStringStatus => "fmi2GetStringStatus",
            EnterEventMode => "fmi2EnterEventMode",
            NewDiscreteStates => "fmi2NewDiscreteStates",
            EnterContinuousTimeMode => "fmi2EnterContinuousTimeMode",
            CompletedIntegratorStep => "fmi2CompletedIntegratorStep",
            SetTime => "fmi2SetTime",
            SetContinuousStates => "fmi2SetContinuousStates",
            GetDerivatives => "fmi2GetDerivatives",
            GetEventIndicators => "fmi2GetEventIndicators",
            GetContinuousStates => "fmi2GetContinuousStates",
            GetNominalsOfContinuousStates => "fmi2GetNominalsOfContinuousStates",
        }
    }

    /// The states the function may be called in. Instantiation and freeing have no state
    /// before them; `fmi2CancelStep` answers in every state (with an error saying why this
    /// FMU has nothing for it).
    pub const fn allowed(self) -> States {
        use Function::*;
        match self {
            Instantiate | FreeInstance | CancelStep => States::EVERY,
            SetDebugLogging | Reset => States::ANY,
            SetupExperiment | EnterInitializationMode => States::of(&[Instantiated]),
            ExitInitializationMode => States::of(&[Init]),
            Terminate => States::of(&[StepComplete, StepFailed, Event, Continuous]),
            GetDirectionalDerivative => States::DIRECTIONAL,
            EnterEventMode => States::of(&[Event, Continuous]),
            NewDiscreteStates | EnterContinuousTimeMode => States::of(&[Event]),
            CompletedIntegratorStep | SetContinuousStates => States::of(&[Continuous]),
            SetTime => States::of(&[Event, Continuous]),
            GetDerivatives | GetEventIndicators | GetContinuousStates => States::EVALUATE,
            GetNominalsOfContinuousStates => States::NOMINALS,
            GetReal | GetInteger | GetBoolean | GetString => States::GET,
            SetReal | SetInteger | SetBoolean | SetString => States::SET,
            SetRealInputDerivatives => States::of(&[Instantiated, Init, StepComplete]),
            GetFMUstate
            | SetFMUstate
            | FreeFMUstate
            | SerializedFMUstateSize
            | SerializeFMUstate
            | DeSerializeFMUstate => States::ANY,
            GetRealOutputDerivatives => States::of(&[StepComplete, StepFailed, Terminated, Error]),
            DoStep => States::of(&[StepComplete]),
            GetStatus | GetRealStatus | GetIntegerStatus | GetBooleanStatus | GetStringStatus => {
                STATUS
            }
        }
    }

    /// The interface the function belongs to: FMI 2.0's Co-Simulation functions (section
    /// 4.2: input and output derivatives, steps and their status) and Model Exchange
    /// functions (section 3.2: time, modes, continuous states, event indicators) are answered
    /// only by an instance of that interface; `None` for the common functions (section 2.1).
    pub const fn only(self) -> Option<Interface> {
        use Function::*;
        match self {
            SetRealInputDerivatives
            | GetRealOutputDerivatives
            | DoStep
            | CancelStep
            | GetStatus
            | GetRealStatus
            | GetIntegerStatus
            | GetBooleanStatus
            | GetStringStatus => Some(Interface::CoSimulation),
            EnterEventMode
            | NewDiscreteStates
            | EnterContinuousTimeMode
            | CompletedIntegratorStep
            | SetTime
            | SetContinuousStates
            | GetDerivatives
            | GetEventIndicators
            | GetContinuousStates
            | GetNominalsOfContinuousStates => Some(Interface::ModelExchange),
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

/// What messages call the FMI 2.0 functions they point to.
pub static WORDS: Vocabulary = Vocabulary {
    edition: "FMI 2.0",
    reset: "fmi2Reset",
    set_state: "fmi2SetFMUstate",
    exit_initialization: "fmi2ExitInitializationMode",
    setup_experiment: "fmi2SetupExperiment",
    do_step: "fmi2DoStep",
    set_states: "fmi2SetContinuousStates",
    last_successful_time: "fmi2LastSuccessfulTime",
    false_: "fmi2False",
    state_arg: "FMUstate",
    state_type: "fmi2FMUstate",
    get_state: "fmi2GetFMUstate",
    deserialize_state: "fmi2DeSerializeFMUstate",
    state_size: "fmi2SerializedFMUstateSize",
    time_vr: None,
};
