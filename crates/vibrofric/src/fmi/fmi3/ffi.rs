//! The exported FMI 3.0 functions: every function of the standard's C interface, so that any
//! importer binds the library. Co-Simulation without event mode works as in FMI 2.0, on the same
//! instance; `Float64` is the only variable type; the functions of Model Exchange, Scheduled
//! Execution, clocks, event mode and configuration mode answer with an error naming what this
//! FMU offers instead.
//!
//! Thin, like the FMI 2.0 layer: pointer and length checks, then the instance. Shared with it:
//! `fmi/c_boundary.rs` (boxes with magic numbers, panics caught, C arrays and strings).
#![allow(non_snake_case, clippy::missing_safety_doc, clippy::too_many_arguments)]

use std::ffi::CString;
use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::ptr;

use super::types::*;
use super::Function;
use crate::description::log::Category;
use crate::fmi::c_boundary::{
    array, array_mut, component, deserialize_state, fill, free_state, get_state, run,
    serialize_state, set_state, set_states, state_size, string, Component, COMPONENT_MAGIC,
};
use crate::fmi::{Answer, Call, Instance, Interface, Logger, NoLogger, Refusal, Status};

/// The importer's `fmi3LogMessageCallback`.
struct CLogger {
    callback: unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String),
    env: fmi3InstanceEnvironment,
}

impl Logger for CLogger {
    fn log(&self, status: Status, category: &str, message: &str) {
        let category = CString::new(category).unwrap_or_default();
        let message = CString::new(message.replace('\0', "\\0")).unwrap_or_default();
        // SAFETY: the callback takes these four arguments; the strings live until it returns.
        unsafe {
            (self.callback)(
                self.env,
                status as fmi3Status,
                category.as_ptr(),
                message.as_ptr(),
            )
        }
    }
}

/// Runs `body` on the instance (see [`run`]); `fmi3Error` for a NULL or foreign pointer.
unsafe fn call(
    c: fmi3Instance,
    f: Function,
    body: impl FnOnce(&mut Instance, Call) -> Answer,
) -> fmi3Status {
    run(c, f.call(), body).map_or(fmi3Error, |s| s as fmi3Status)
}

/// The error of a function this FMU does not offer.
unsafe fn unsupported(c: fmi3Instance, name: &'static str, why: &str) -> fmi3Status {
    call(c, Function::Unsupported(name), |_, _| {
        Err(Refusal::unsupported(why))
    })
}

const NO_SE: &str = "this FMU implements Model Exchange and Co-Simulation, not Scheduled Execution";
const NO_CLOCKS: &str = "this FMU has no clocks";
const NO_EVENTS: &str = "this FMU has no event mode (hasEventMode = false)";

// ---- common functions -----------------------------------------------------------------------

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    VERSION.as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    const F: Function = Function::SetDebugLogging;
    call(instance, F, |inst, call| {
        let Some(cats) = array(categories, nCategories) else {
            return Err(Refusal::error(format!(
                "categories = NULL with nCategories = {nCategories}"
            )));
        };
        let mut names = Vec::with_capacity(cats.len());
        for (k, &p) in cats.iter().enumerate() {
            match string(p) {
                Some(s) => names.push(s),
                None => return Err(Refusal::error(format!("categories[{k}] = NULL"))),
            }
        }
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        inst.set_logging(call, loggingOn, &names)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    _earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    _nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _intermediateUpdate: fmi3IntermediateUpdateCallback,
) -> fmi3Instance {
    let refusal = eventModeUsed.then(|| format!("eventModeUsed = true: {NO_EVENTS}"));
    instantiate(
        Function::InstantiateCoSimulation,
        Interface::CoSimulation,
        refusal,
        [instanceName, instantiationToken, resourcePath],
        loggingOn,
        instanceEnvironment,
        logMessage,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
) -> fmi3Instance {
    instantiate(
        Function::InstantiateModelExchange,
        Interface::ModelExchange,
        None,
        [instanceName, instantiationToken, resourcePath],
        loggingOn,
        instanceEnvironment,
        logMessage,
    )
}

/// Both instantiation functions: the name, token and resources path checked, the reason of a
/// refusal logged (`refusal`: one the caller found).
unsafe fn instantiate(
    f: Function,
    interface: Interface,
    refusal: Option<String>,
    [instanceName, instantiationToken, resourcePath]: [fmi3String; 3],
    loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
) -> fmi3Instance {
    let make_logger = || -> Box<dyn Logger> {
        match logMessage {
            Some(callback) => Box::new(CLogger {
                callback,
                env: instanceEnvironment,
            }),
            None => Box::new(NoLogger),
        }
    };
    let result = catch_unwind(AssertUnwindSafe(|| {
        let logger = make_logger();
        let refuse = |msg: String| {
            let error = Category::StatusError.name();
            logger.log(Status::Error, error, &format!("{}: {msg}", f.name()));
        };
        let Some(name) = string(instanceName) else {
            refuse("instanceName = NULL: must be a string".into());
            return None;
        };
        if let Some(why) = Instance::refuse_name(&name) {
            refuse(why);
            return None;
        }
        if let Some(why) = refusal.clone() {
            refuse(why);
            return None;
        }
        let Some(path) = string(resourcePath) else {
            refuse("resourcePath = NULL: must be the path of the FMU's resources folder".into());
            return None;
        };
        let inst = Instance::instantiate(
            f.call(),
            interface,
            &name,
            "instantiationToken",
            string(instantiationToken).as_deref(),
            &PathBuf::from(&path),
            &format!("resourcePath = \"{path}\""),
            logger,
            loggingOn,
        )?;
        Some(Box::into_raw(Box::new(Component {
            magic: COMPONENT_MAGIC,
            inst,
        })))
    }));
    match result {
        Ok(Some(p)) => p as fmi3Instance,
        Ok(None) => ptr::null_mut(),
        Err(_) => {
            make_logger().log(
                Status::Error,
                Category::StatusError.name(),
                &format!(
                    "{}: internal error (caught); no instance was created",
                    f.name()
                ),
            );
            ptr::null_mut()
        }
    }
}

/// The instantiation functions of the interfaces this FMU does not offer: no instance, and the
/// reason through the logger.
unsafe fn refuse_instantiation(
    f: Function,
    env: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
) -> fmi3Instance {
    if let Some(callback) = logMessage {
        let logger = CLogger { callback, env };
        let _ = catch_unwind(AssertUnwindSafe(|| {
            logger.log(
                Status::Error,
                Category::StatusError.name(),
                &format!("{}: not supported: {NO_SE}", f.name()),
            )
        }));
    }
    ptr::null_mut()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _clockUpdate: fmi3ClockUpdateCallback,
    _lockPreemption: fmi3LockPreemptionCallback,
    _unlockPreemption: fmi3UnlockPreemptionCallback,
) -> fmi3Instance {
    refuse_instantiation(
        Function::InstantiateScheduledExecution,
        instanceEnvironment,
        logMessage,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
    if let Some(comp) = component(instance) {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            comp.inst.free(Function::FreeInstance.call())
        }));
        comp.magic = 0;
        let b = Box::from_raw(comp as *mut Component);
        let _ = catch_unwind(AssertUnwindSafe(move || drop(b)));
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: fmi3Instance,
    toleranceDefined: fmi3Boolean,
    tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    call(instance, Function::EnterInitializationMode, |inst, call| {
        inst.enter_initialization_with(
            call,
            toleranceDefined.then_some(tolerance),
            startTime,
            stopTimeDefined.then_some(stopTime),
        )
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::ExitInitializationMode, |i, call| {
        i.exit_initialization(call)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterEventMode(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::EnterEventMode, |i, call| {
        i.enter_event_mode(call)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::Terminate, |i, call| i.terminate(call))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::Reset, |i, call| i.reset(call))
}

// ---- getters and setters --------------------------------------------------------------------

/// Checks that a scalar call's `nValues` equals `nValueReferences` (every variable is a
/// scalar).
fn scalar_count(nvr: usize, n_values: usize) -> Answer<()> {
    if nvr != n_values {
        return Err(Refusal::error(format!("nValues = {n_values} with nValueReferences = {nvr}: every variable of this FMU is a scalar, so they must be equal")));
    }
    Ok(())
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    const F: Function = Function::GetFloat64;
    call(instance, F, |inst, call| {
        // A string's arrays: their value references hold all their elements (checked there).
        if !inst.has_arrays() {
            scalar_count(nValueReferences, nValues)?;
        }
        let Some(vrs) = array(valueReferences, nValueReferences) else {
            return Err(Refusal::null("valueReferences", nValueReferences));
        };
        let Some(values) = array_mut(values, nValues) else {
            return Err(Refusal::null("values", nValues));
        };
        inst.get_values(call, vrs, values)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    const F: Function = Function::SetFloat64;
    call(instance, F, |inst, call| {
        // A string's arrays: their value references hold all their elements (checked there).
        if !inst.has_arrays() {
            scalar_count(nValueReferences, nValues)?;
        }
        let Some(vrs) = array(valueReferences, nValueReferences) else {
            return Err(Refusal::null("valueReferences", nValueReferences));
        };
        let Some(values) = array(values, nValues) else {
            return Err(Refusal::null("values", nValues));
        };
        inst.set_values(call, vrs, values)
    })
}

/// The getters and setters of the types this FMU has no variables of: nothing to do for no
/// value reference, an error naming the variable's type otherwise.
unsafe fn no_variables(
    instance: fmi3Instance,
    f: Function,
    type_name: &str,
    vrs: *const fmi3ValueReference,
    nvr: usize,
) -> fmi3Status {
    call(instance, f, |inst, _| {
        let Some(vrs) = array(vrs, nvr) else {
            return Err(Refusal::null("valueReferences", nvr));
        };
        inst.no_variables_of_type(type_name, vrs)
    })
}

macro_rules! other_types {
    ($($get:ident, $set:ident, $t:ty, $name:literal;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            _values: *mut $t,
            _nValues: usize,
        ) -> fmi3Status {
            let f = Function::GetOther(stringify!($get));
            no_variables(instance, f, $name, valueReferences, nValueReferences)
        }

        #[no_mangle]
        pub unsafe extern "C" fn $set(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            _values: *const $t,
            _nValues: usize,
        ) -> fmi3Status {
            let f = Function::SetOther(stringify!($set));
            no_variables(instance, f, $name, valueReferences, nValueReferences)
        }
    )*};
}

other_types! {
    fmi3GetFloat32, fmi3SetFloat32, fmi3Float32, "Float32";
    fmi3GetInt8, fmi3SetInt8, fmi3Int8, "Int8";
    fmi3GetUInt8, fmi3SetUInt8, fmi3UInt8, "UInt8";
    fmi3GetInt16, fmi3SetInt16, fmi3Int16, "Int16";
    fmi3GetUInt16, fmi3SetUInt16, fmi3UInt16, "UInt16";
    fmi3GetInt32, fmi3SetInt32, fmi3Int32, "Int32";
    fmi3GetUInt32, fmi3SetUInt32, fmi3UInt32, "UInt32";
    fmi3GetInt64, fmi3SetInt64, fmi3Int64, "Int64";
    fmi3GetUInt64, fmi3SetUInt64, fmi3UInt64, "UInt64";
    fmi3GetBoolean, fmi3SetBoolean, fmi3Boolean, "Boolean";
    fmi3GetString, fmi3SetString, fmi3String, "String";
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _valueSizes: *mut usize,
    _values: *mut fmi3Binary,
    _nValues: usize,
) -> fmi3Status {
    let f = Function::GetOther("fmi3GetBinary");
    no_variables(instance, f, "Binary", valueReferences, nValueReferences)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _valueSizes: *const usize,
    _values: *const fmi3Binary,
    _nValues: usize,
) -> fmi3Status {
    let f = Function::SetOther("fmi3SetBinary");
    no_variables(instance, f, "Binary", valueReferences, nValueReferences)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetClock(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _values: *mut fmi3Clock,
) -> fmi3Status {
    unsupported(instance, "fmi3GetClock", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetClock(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _values: *const fmi3Clock,
) -> fmi3Status {
    unsupported(instance, "fmi3SetClock", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(
    instance: fmi3Instance,
    _valueReference: fmi3ValueReference,
    _nDependencies: *mut usize,
) -> fmi3Status {
    unsupported(
        instance,
        "fmi3GetNumberOfVariableDependencies",
        "the dependencies are in modelDescription.xml (ModelStructure)",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetVariableDependencies(
    instance: fmi3Instance,
    _dependent: fmi3ValueReference,
    _elementIndicesOfDependent: *mut usize,
    _independents: *mut fmi3ValueReference,
    _elementIndicesOfIndependents: *mut usize,
    _dependencyKinds: *mut fmi3DependencyKind,
    _nDependencies: usize,
) -> fmi3Status {
    unsupported(
        instance,
        "fmi3GetVariableDependencies",
        "the dependencies are in modelDescription.xml (ModelStructure)",
    )
}

// ---- FMU state ------------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::GetFMUState, |i, call| {
        get_state(i, call, FMUState)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::SetFMUState, |i, call| {
        set_state(i, call, FMUState)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::FreeFMUState, |_, call| {
        free_state(call, FMUState)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    call(instance, Function::SerializedFMUStateSize, |i, call| {
        state_size(i, call, FMUState, size)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    call(instance, Function::SerializeFMUState, |i, call| {
        serialize_state(i, call, FMUState, serializedState, size)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: usize,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::DeserializeFMUState, |i, call| {
        deserialize_state(i, call, serializedState, size, FMUState)
    })
}

// ---- derivatives ----------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
    instance: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    nUnknowns: usize,
    knowns: *const fmi3ValueReference,
    nKnowns: usize,
    seed: *const fmi3Float64,
    nSeed: usize,
    sensitivity: *mut fmi3Float64,
    nSensitivity: usize,
) -> fmi3Status {
    const F: Function = Function::GetDirectionalDerivative;
    call(instance, F, |inst, _| {
        // Every variable is a scalar: one seed per known, one sensitivity per unknown.
        if nSeed != nKnowns || nSensitivity != nUnknowns {
            return Err(Refusal::error(format!("nSeed = {nSeed}, nSensitivity = {nSensitivity}: must equal nKnowns = {nKnowns} and nUnknowns = {nUnknowns} (every variable is a scalar)")));
        }
        let Some(unknowns) = array(unknowns, nUnknowns) else {
            return Err(Refusal::null("unknowns", nUnknowns));
        };
        let Some(knowns) = array(knowns, nKnowns) else {
            return Err(Refusal::null("knowns", nKnowns));
        };
        let Some(seed) = array(seed, nSeed) else {
            return Err(Refusal::null("seed", nSeed));
        };
        let Some(sensitivity) = array_mut(sensitivity, nSensitivity) else {
            return Err(Refusal::null("sensitivity", nSensitivity));
        };
        inst.get_directional_derivative(unknowns, knowns, seed, sensitivity)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetAdjointDerivative(
    instance: fmi3Instance,
    _unknowns: *const fmi3ValueReference,
    _nUnknowns: usize,
    _knowns: *const fmi3ValueReference,
    _nKnowns: usize,
    _seed: *const fmi3Float64,
    _nSeed: usize,
    _sensitivity: *mut fmi3Float64,
    _nSensitivity: usize,
) -> fmi3Status {
    unsupported(
        instance,
        "fmi3GetAdjointDerivative",
        "this FMU provides no adjoint derivatives (providesAdjointDerivatives = false)",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetOutputDerivatives(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    orders: *const fmi3Int32,
    values: *mut fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    const F: Function = Function::GetOutputDerivatives;
    call(instance, F, |inst, call| {
        scalar_count(nValueReferences, nValues)?;
        let Some(vrs) = array(valueReferences, nValueReferences) else {
            return Err(Refusal::null("valueReferences", nValueReferences));
        };
        let Some(orders) = array(orders, nValueReferences) else {
            return Err(Refusal::null("orders", nValueReferences));
        };
        let Some(values) = array_mut(values, nValues) else {
            return Err(Refusal::null("values", nValues));
        };
        inst.get_output_derivatives(call, vrs, orders, values)
    })
}

// ---- configuration, clocks and event mode: not offered ---------------------------------------

macro_rules! not_offered {
    ($($name:ident ( $($arg:ident : $t:ty),* ) => $why:expr;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $name(instance: fmi3Instance, $($arg: $t),*) -> fmi3Status {
            $(let _ = $arg;)*
            unsupported(instance, stringify!($name), $why)
        }
    )*};
}

not_offered! {
    fmi3EnterConfigurationMode() => "this FMU has no structural parameters";
    fmi3ExitConfigurationMode() => "this FMU has no structural parameters";
    fmi3GetIntervalDecimal(_vr: *const fmi3ValueReference, _n: usize, _intervals: *mut fmi3Float64, _qualifiers: *mut fmi3IntervalQualifier) => NO_CLOCKS;
    fmi3GetIntervalFraction(_vr: *const fmi3ValueReference, _n: usize, _counters: *mut fmi3UInt64, _resolutions: *mut fmi3UInt64, _qualifiers: *mut fmi3IntervalQualifier) => NO_CLOCKS;
    fmi3GetShiftDecimal(_vr: *const fmi3ValueReference, _n: usize, _shifts: *mut fmi3Float64) => NO_CLOCKS;
    fmi3GetShiftFraction(_vr: *const fmi3ValueReference, _n: usize, _counters: *mut fmi3UInt64, _resolutions: *mut fmi3UInt64) => NO_CLOCKS;
    fmi3SetIntervalDecimal(_vr: *const fmi3ValueReference, _n: usize, _intervals: *const fmi3Float64) => NO_CLOCKS;
    fmi3SetIntervalFraction(_vr: *const fmi3ValueReference, _n: usize, _counters: *const fmi3UInt64, _resolutions: *const fmi3UInt64) => NO_CLOCKS;
    fmi3SetShiftDecimal(_vr: *const fmi3ValueReference, _n: usize, _shifts: *const fmi3Float64) => NO_CLOCKS;
    fmi3SetShiftFraction(_vr: *const fmi3ValueReference, _n: usize, _counters: *const fmi3UInt64, _resolutions: *const fmi3UInt64) => NO_CLOCKS;
    fmi3EvaluateDiscreteStates() => NO_EVENTS;
    fmi3EnterStepMode() => NO_EVENTS;
    fmi3ActivateModelPartition(_clock: fmi3ValueReference, _time: fmi3Float64) => "this FMU has no Scheduled Execution (no clocks)";
}

// ---- Model Exchange -------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
    instance: fmi3Instance,
    discreteStatesNeedUpdate: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
    valuesOfContinuousStatesChanged: *mut fmi3Boolean,
    nextEventTimeDefined: *mut fmi3Boolean,
    nextEventTime: *mut fmi3Float64,
) -> fmi3Status {
    const F: Function = Function::UpdateDiscreteStates;
    call(instance, F, |inst, call| {
        let (Some(need), Some(terminate), Some(nominals), Some(values), Some(defined), Some(next)) = (
            discreteStatesNeedUpdate.as_mut(),
            terminateSimulation.as_mut(),
            nominalsOfContinuousStatesChanged.as_mut(),
            valuesOfContinuousStatesChanged.as_mut(),
            nextEventTimeDefined.as_mut(),
            nextEventTime.as_mut(),
        ) else {
            return Err(Refusal::error("an output argument is NULL"));
        };
        let info = inst.update_events(call)?;
        (*need, *terminate, *nominals) = (false, false, false);
        *values = info.values_of_continuous_states_changed;
        *defined = info.next_event_time.is_some();
        *next = info.next_event_time.unwrap_or(0.0);
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterContinuousTimeMode(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::EnterContinuousTimeMode, |i, _| {
        i.enter_continuous_time_mode()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3CompletedIntegratorStep(
    instance: fmi3Instance,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    enterEventMode: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
) -> fmi3Status {
    const F: Function = Function::CompletedIntegratorStep;
    call(instance, F, |_, _| {
        let (Some(event), Some(terminate)) =
            (enterEventMode.as_mut(), terminateSimulation.as_mut())
        else {
            return Err(Refusal::error(
                "enterEventMode or terminateSimulation = NULL",
            ));
        };
        // Nothing to do (no step events); never asks for an event or to terminate.
        (*event, *terminate) = (false, false);
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetTime(instance: fmi3Instance, time: fmi3Float64) -> fmi3Status {
    call(instance, Function::SetTime, |i, _| i.set_time(time))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetContinuousStates(
    instance: fmi3Instance,
    continuousStates: *const fmi3Float64,
    nContinuousStates: usize,
) -> fmi3Status {
    call(instance, Function::SetContinuousStates, |i, _| {
        set_states(i, "continuousStates", continuousStates, nContinuousStates)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetContinuousStateDerivatives(
    instance: fmi3Instance,
    derivatives: *mut fmi3Float64,
    nContinuousStates: usize,
) -> fmi3Status {
    call(
        instance,
        Function::GetContinuousStateDerivatives,
        |i, call| {
            fill(
                i,
                call,
                "derivatives",
                derivatives,
                nContinuousStates,
                Instance::get_derivatives,
            )
        },
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetEventIndicators(
    instance: fmi3Instance,
    eventIndicators: *mut fmi3Float64,
    nEventIndicators: usize,
) -> fmi3Status {
    call(instance, Function::GetEventIndicators, |i, call| {
        fill(
            i,
            call,
            "eventIndicators",
            eventIndicators,
            nEventIndicators,
            Instance::get_event_indicators,
        )
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetContinuousStates(
    instance: fmi3Instance,
    continuousStates: *mut fmi3Float64,
    nContinuousStates: usize,
) -> fmi3Status {
    call(instance, Function::GetContinuousStates, |i, call| {
        fill(
            i,
            call,
            "continuousStates",
            continuousStates,
            nContinuousStates,
            Instance::get_continuous_states,
        )
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNominalsOfContinuousStates(
    instance: fmi3Instance,
    nominals: *mut fmi3Float64,
    nContinuousStates: usize,
) -> fmi3Status {
    call(
        instance,
        Function::GetNominalsOfContinuousStates,
        |i, call| {
            fill(
                i,
                call,
                "nominals",
                nominals,
                nContinuousStates,
                Instance::get_nominals,
            )
        },
    )
}

/// `fmi3GetNumberOf...`: a count written to `n`.
unsafe fn get_count(
    instance: fmi3Instance,
    f: Function,
    n: *mut usize,
    count: impl FnOnce(&Instance) -> usize,
) -> fmi3Status {
    call(instance, f, |inst, _| {
        let out = n
            .as_mut()
            .ok_or_else(|| Refusal::error("the count's pointer is NULL"))?;
        *out = count(inst);
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(
    instance: fmi3Instance,
    nEventIndicators: *mut usize,
) -> fmi3Status {
    let f = Function::GetNumberOfEventIndicators;
    get_count(instance, f, nEventIndicators, |i| {
        i.number_of_event_indicators()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(
    instance: fmi3Instance,
    nContinuousStates: *mut usize,
) -> fmi3Status {
    let f = Function::GetNumberOfContinuousStates;
    get_count(instance, f, nContinuousStates, |i| i.number_of_states())
}

// ---- Co-Simulation --------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    instance: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    const F: Function = Function::DoStep;
    call(instance, F, |inst, call| {
        let (Some(event), Some(terminate), Some(early), Some(last)) = (
            eventHandlingNeeded.as_mut(),
            terminateSimulation.as_mut(),
            earlyReturn.as_mut(),
            lastSuccessfulTime.as_mut(),
        ) else {
            return Err(Refusal::error("eventHandlingNeeded, terminateSimulation, earlyReturn and lastSuccessfulTime must not be NULL"));
        };
        let s = inst.step(call, currentCommunicationPoint, communicationStepSize);
        *event = false;
        *terminate = false;
        *early = false;
        *last = inst.time();
        s
    })
}
