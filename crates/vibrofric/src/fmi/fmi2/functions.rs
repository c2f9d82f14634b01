//! Every function of the FMI 2.0 Co-Simulation interface and the one table of the states each
//! may be called in (FMI 2.0, section 4.2.4, the state machine of a Co-Simulation slave).

use crate::fmi::state::{Call, State, States, Vocabulary};

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
/// Every state: calls that answer (with an error) even after a fatal one.
const EVERY: States = States::of(&State::ALL);
const GET: States = States::of(&[Init, StepComplete, StepFailed, Terminated, Error]);
const SET: States = States::of(&[Instantiated, Init, StepComplete]);
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
        }
    }

    /// The states the function may be called in. Instantiation and freeing have no state
    /// before them; `fmi2CancelStep` and `fmi2GetDirectionalDerivative` answer in every state
    /// (with an error saying why this FMU has nothing for them).
    pub const fn allowed(self) -> States {
        use Function::*;
        match self {
            Instantiate | FreeInstance | CancelStep | GetDirectionalDerivative => EVERY,
            SetDebugLogging | Reset => ANY,
            SetupExperiment | EnterInitializationMode => States::of(&[Instantiated]),
            ExitInitializationMode => States::of(&[Init]),
            Terminate => States::of(&[StepComplete, StepFailed]),
            GetReal | GetInteger | GetBoolean | GetString => GET,
            SetReal | SetInteger | SetBoolean | SetString | SetRealInputDerivatives => SET,
            GetFMUstate
            | SetFMUstate
            | FreeFMUstate
            | SerializedFMUstateSize
            | SerializeFMUstate
            | DeSerializeFMUstate => ANY,
            GetRealOutputDerivatives => States::of(&[StepComplete, StepFailed, Terminated, Error]),
            DoStep => States::of(&[StepComplete]),
            GetStatus | GetRealStatus | GetIntegerStatus | GetBooleanStatus | GetStringStatus => {
                STATUS
            }
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

/// What messages call the FMI 2.0 functions they point to.
pub static WORDS: Vocabulary = Vocabulary {
    reset: "fmi2Reset",
    set_state: "fmi2SetFMUstate",
    exit_initialization: "fmi2ExitInitializationMode",
    setup_experiment: "fmi2SetupExperiment",
    do_step: "fmi2DoStep",
    last_successful_time: "fmi2LastSuccessfulTime",
    false_: "fmi2False",
    state_arg: "FMUstate",
    state_type: "fmi2FMUstate",
    get_state: "fmi2GetFMUstate",
    deserialize_state: "fmi2DeSerializeFMUstate",
    state_size: "fmi2SerializedFMUstateSize",
};
