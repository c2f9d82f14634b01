//! The exported FMI 2.0 functions: every common, Co-Simulation and Model Exchange function of
//! the standard (importers such as fmpy bind all of them when they load the library).
//!
//! This layer is thin: it checks pointers (a NULL instance returns `fmi2Error`; a NULL array
//! with a nonzero length returns `fmi2Error` with a log line), turns C strings and arrays into
//! Rust ones, catches every panic so that none crosses the C boundary, and calls
//! [`Instance`]. It is, with the importer, the only place of the crate with `unsafe` code.
//!
//! An `fmi2Component` is a `Box<Component>`; an `fmi2FMUstate` a `Box<StateBox>`. Both carry a
//! magic number so that a pointer of the wrong kind is refused rather than used. Nothing is
//! global: instances are independent and may live on any thread (one thread at a time per
//! instance, as the standard requires).
#![allow(non_snake_case, non_upper_case_globals, clippy::missing_safety_doc)]

use std::ffi::CString;
use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

use super::types::*;
use super::{co_simulation, Function};
use crate::description::log::Category;
use crate::fmi::c_boundary::{
    array, array_mut, component, deserialize_state, fill, free_state, get_state, run,
    serialize_state, set_state, set_states, state_size, string, Component, COMPONENT_MAGIC,
};
use crate::fmi::{Answer, Call, Instance, Interface, Logger, NoLogger, Refusal, Status};

/// The importer's logger callback, called with the format `"%s"` and the message as its one
/// argument, so that a `%` in a message is never interpreted.
struct CLogger {
    logger: fmi2CallbackLogger,
    env: fmi2ComponentEnvironment,
    name: CString,
}

impl Logger for CLogger {
    fn log(&self, status: Status, category: &str, message: &str) {
        let category = CString::new(category).unwrap_or_default();
        let message = CString::new(message.replace('\0', "\\0")).unwrap_or_default();
        // SAFETY: the importer's logger takes these five pointers plus the variadic arguments
        // of the format; "%s" consumes exactly one `char*`. All strings live until it returns.
        unsafe {
            (self.logger)(
                self.env,
                self.name.as_ptr(),
                status as fmi2Status,
                category.as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            )
        }
    }
}

/// Runs `body` on the instance behind `c` (see [`run`]); `fmi2Error` for a NULL or foreign
/// pointer.
unsafe fn call(
    c: fmi2Component,
    f: Function,
    body: impl FnOnce(&mut Instance, Call) -> Answer,
) -> fmi2Status {
    run(c, f.call(), body).map_or(fmi2Error, |s| s as fmi2Status)
}

// ---- common functions -----------------------------------------------------------------------

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    TYPES_PLATFORM.as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    VERSION.as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: fmi2Type,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    // Without callback functions there is no logger to say why; every other NULL return logs.
    let Some(functions) = functions.as_ref() else {
        return ptr::null_mut();
    };
    let name = string(instanceName);
    let make_logger = || -> Box<dyn Logger> {
        match functions.logger {
            Some(logger) => Box::new(CLogger {
                logger,
                env: functions.componentEnvironment,
                name: CString::new(name.clone().unwrap_or_default()).unwrap_or_default(),
            }),
            None => Box::new(NoLogger),
        }
    };
    const F: Function = Function::Instantiate;
    let result = catch_unwind(AssertUnwindSafe(|| {
        let logger = make_logger();
        let refuse = |msg: String| {
            let error = Category::StatusError.name();
            logger.log(Status::Error, error, &format!("{}: {msg}", F.name()));
        };
        let Some(name) = name.clone() else {
            refuse("instanceName = NULL: must be a string".into());
            return None;
        };
        if let Some(why) = Instance::refuse_name(&name) {
            refuse(why);
            return None;
        }
        let interface = match fmuType {
            fmi2CoSimulation => Interface::CoSimulation,
            fmi2ModelExchange => Interface::ModelExchange,
            _ => {
                refuse(format!(
                    "fmuType = {fmuType}: must be fmi2ModelExchange ({fmi2ModelExchange}) or fmi2CoSimulation ({fmi2CoSimulation})"
                ));
                return None;
            }
        };
        let Some(location) = string(fmuResourceLocation) else {
            refuse("fmuResourceLocation = NULL: must be the file: URI of the FMU's resources folder, e.g. file:///path/to/fmu/resources/".into());
            return None;
        };
        let dir = match crate::fmi::uri::resource_dir(&location) {
            Ok(d) => d,
            Err(e) => {
                refuse(e);
                return None;
            }
        };
        let inst = Instance::instantiate(
            F.call(),
            interface,
            &name,
            "fmuGUID",
            string(fmuGUID).as_deref(),
            &dir,
            &format!("fmuResourceLocation = \"{location}\""),
            logger,
            loggingOn != fmi2False,
        )?;
        Some(Box::into_raw(Box::new(Component {
            magic: COMPONENT_MAGIC,
            inst,
        })))
    }));
    match result {
        Ok(Some(p)) => p as fmi2Component,
        Ok(None) => ptr::null_mut(),
        Err(_) => {
            make_logger().log(
                Status::Error,
                Category::StatusError.name(),
                &format!(
                    "{}: internal error (caught); no instance was created",
                    F.name()
                ),
            );
            ptr::null_mut()
        }
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    if let Some(comp) = component(c) {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            comp.inst.free(Function::FreeInstance.call())
        }));
        comp.magic = 0;
        let b = Box::from_raw(comp as *mut Component);
        let _ = catch_unwind(AssertUnwindSafe(move || drop(b)));
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    const F: Function = Function::SetDebugLogging;
    call(c, F, |inst, call| {
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
        inst.set_logging(call, loggingOn != fmi2False, &names)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    toleranceDefined: fmi2Boolean,
    tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    call(c, Function::SetupExperiment, |inst, call| {
        inst.set_experiment(
            call,
            (toleranceDefined != fmi2False).then_some(tolerance),
            startTime,
            (stopTimeDefined != fmi2False).then_some(stopTime),
        )
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    call(c, Function::EnterInitializationMode, |i, call| {
        i.enter_initialization(call)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    call(c, Function::ExitInitializationMode, |i, call| {
        i.exit_initialization(call)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    call(c, Function::Terminate, |i, call| i.terminate(call))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    call(c, Function::Reset, |i, call| i.reset(call))
}

// ---- getters and setters --------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    const F: Function = Function::GetReal;
    call(c, F, |inst, call| {
        let Some(vrs) = array(vr, nvr) else {
            return Err(Refusal::null("vr", nvr));
        };
        let Some(values) = array_mut(value, nvr) else {
            return Err(Refusal::null("value", nvr));
        };
        inst.get_values(call, vrs, values)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    const F: Function = Function::SetReal;
    call(c, F, |inst, call| {
        let Some(vrs) = array(vr, nvr) else {
            return Err(Refusal::null("vr", nvr));
        };
        let Some(values) = array(value, nvr) else {
            return Err(Refusal::null("value", nvr));
        };
        inst.set_values(call, vrs, values)
    })
}

/// The getters and setters of the types this FMU has no variables of.
unsafe fn no_variables<T>(
    c: fmi2Component,
    f: Function,
    type_name: &str,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const T,
) -> fmi2Status {
    call(c, f, |inst, _| {
        let Some(vrs) = array(vr, nvr) else {
            return Err(Refusal::null("vr", nvr));
        };
        if nvr > 0 && value.is_null() {
            return Err(Refusal::null("value", nvr));
        }
        inst.no_variables_of_type(type_name, vrs)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    no_variables(
        c,
        Function::GetInteger,
        "Integer",
        vr,
        nvr,
        value as *const _,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    no_variables(c, Function::SetInteger, "Integer", vr, nvr, value)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    no_variables(
        c,
        Function::GetBoolean,
        "Boolean",
        vr,
        nvr,
        value as *const _,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    no_variables(c, Function::SetBoolean, "Boolean", vr, nvr, value)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    no_variables(c, Function::GetString, "String", vr, nvr, value as *const _)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    no_variables(c, Function::SetString, "String", vr, nvr, value)
}

// ---- FMU state ------------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    call(c, Function::GetFMUstate, |i, call| {
        get_state(i, call, FMUstate)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    call(c, Function::SetFMUstate, |i, call| {
        set_state(i, call, FMUstate)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    call(c, Function::FreeFMUstate, |_, call| {
        free_state(call, FMUstate)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    call(c, Function::SerializedFMUstateSize, |i, call| {
        state_size(i, call, FMUstate, size)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    call(c, Function::SerializeFMUstate, |i, call| {
        serialize_state(i, call, FMUstate, serializedState as *mut u8, size)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    call(c, Function::DeSerializeFMUstate, |i, call| {
        deserialize_state(i, call, serializedState as *const u8, size, FMUstate)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    vUnknown_ref: *const fmi2ValueReference,
    nUnknown: usize,
    vKnown_ref: *const fmi2ValueReference,
    nKnown: usize,
    dvKnown: *const fmi2Real,
    dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    const F: Function = Function::GetDirectionalDerivative;
    call(c, F, |inst, call| {
        let Some(unknowns) = array(vUnknown_ref, nUnknown) else {
            return Err(Refusal::null("vUnknown_ref", nUnknown));
        };
        let Some(knowns) = array(vKnown_ref, nKnown) else {
            return Err(Refusal::null("vKnown_ref", nKnown));
        };
        let Some(dv_known) = array(dvKnown, nKnown) else {
            return Err(Refusal::null("dvKnown", nKnown));
        };
        let Some(dv_unknown) = array_mut(dvUnknown, nUnknown) else {
            return Err(Refusal::null("dvUnknown", nUnknown));
        };
        inst.get_directional_derivative(call, unknowns, knowns, dv_known, dv_unknown)
    })
}

// ---- Model Exchange -------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterEventMode(c: fmi2Component) -> fmi2Status {
    call(c, Function::EnterEventMode, |i, call| {
        i.enter_event_mode(call)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2NewDiscreteStates(
    c: fmi2Component,
    eventInfo: *mut fmi2EventInfo,
) -> fmi2Status {
    const F: Function = Function::NewDiscreteStates;
    call(c, F, |inst, call| {
        let Some(out) = eventInfo.as_mut() else {
            return Err(Refusal::error("eventInfo = NULL"));
        };
        let info = inst.update_events(call)?;
        let b = |x: bool| if x { fmi2True } else { fmi2False };
        *out = fmi2EventInfo {
            newDiscreteStatesNeeded: fmi2False,
            terminateSimulation: fmi2False,
            nominalsOfContinuousStatesChanged: fmi2False,
            valuesOfContinuousStatesChanged: b(info.values_of_continuous_states_changed),
            nextEventTimeDefined: b(info.next_event_time.is_some()),
            nextEventTime: info.next_event_time.unwrap_or(0.0),
        };
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: fmi2Component) -> fmi2Status {
    call(c, Function::EnterContinuousTimeMode, |i, _| {
        i.enter_continuous_time_mode()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
    c: fmi2Component,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
    enterEventMode: *mut fmi2Boolean,
    terminateSimulation: *mut fmi2Boolean,
) -> fmi2Status {
    const F: Function = Function::CompletedIntegratorStep;
    call(c, F, |_, _| {
        let (Some(event), Some(terminate)) =
            (enterEventMode.as_mut(), terminateSimulation.as_mut())
        else {
            return Err(Refusal::error(
                "enterEventMode or terminateSimulation = NULL",
            ));
        };
        // Nothing to do (no step events); never asks for an event or to terminate.
        (*event, *terminate) = (fmi2False, fmi2False);
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetTime(c: fmi2Component, time: fmi2Real) -> fmi2Status {
    call(c, Function::SetTime, |i, _| i.set_time(time))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetContinuousStates(
    c: fmi2Component,
    x: *const fmi2Real,
    nx: usize,
) -> fmi2Status {
    call(c, Function::SetContinuousStates, |i, _| {
        set_states(i, "x", x, nx)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDerivatives(
    c: fmi2Component,
    derivatives: *mut fmi2Real,
    nx: usize,
) -> fmi2Status {
    call(c, Function::GetDerivatives, |i, call| {
        fill(
            i,
            call,
            "derivatives",
            derivatives,
            nx,
            Instance::get_derivatives,
        )
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetEventIndicators(
    c: fmi2Component,
    eventIndicators: *mut fmi2Real,
    ni: usize,
) -> fmi2Status {
    call(c, Function::GetEventIndicators, |i, call| {
        fill(
            i,
            call,
            "eventIndicators",
            eventIndicators,
            ni,
            Instance::get_event_indicators,
        )
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetContinuousStates(
    c: fmi2Component,
    x: *mut fmi2Real,
    nx: usize,
) -> fmi2Status {
    call(c, Function::GetContinuousStates, |i, call| {
        fill(i, call, "x", x, nx, Instance::get_continuous_states)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(
    c: fmi2Component,
    x_nominal: *mut fmi2Real,
    nx: usize,
) -> fmi2Status {
    call(c, Function::GetNominalsOfContinuousStates, |i, call| {
        fill(i, call, "x_nominal", x_nominal, nx, Instance::get_nominals)
    })
}

// ---- Co-Simulation --------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    const F: Function = Function::SetRealInputDerivatives;
    call(c, F, |inst, _| {
        let Some(vrs) = array(vr, nvr) else {
            return Err(Refusal::null("vr", nvr));
        };
        let Some(orders) = array(order, nvr) else {
            return Err(Refusal::null("order", nvr));
        };
        let Some(values) = array(value, nvr) else {
            return Err(Refusal::null("value", nvr));
        };
        inst.set_input_derivatives(vrs, orders, values)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *mut fmi2Real,
) -> fmi2Status {
    const F: Function = Function::GetRealOutputDerivatives;
    call(c, F, |inst, call| {
        let Some(vrs) = array(vr, nvr) else {
            return Err(Refusal::null("vr", nvr));
        };
        let Some(orders) = array(order, nvr) else {
            return Err(Refusal::null("order", nvr));
        };
        let Some(values) = array_mut(value, nvr) else {
            return Err(Refusal::null("value", nvr));
        };
        inst.get_output_derivatives(call, vrs, orders, values)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    call(c, Function::DoStep, |i, call| {
        i.step(call, currentCommunicationPoint, communicationStepSize)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    call(c, Function::CancelStep, |i, _| i.cancel_step())
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    _value: *mut fmi2Status,
) -> fmi2Status {
    call(c, Function::GetStatus, |_, _| co_simulation::get_status(s))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    const F: Function = Function::GetRealStatus;
    call(c, F, |inst, _| {
        let Some(out) = value.as_mut() else {
            return Err(Refusal::error("value = NULL"));
        };
        *out = co_simulation::get_real_status(inst, s)?;
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    call(c, Function::GetIntegerStatus, |_, _| {
        co_simulation::get_integer_status(s)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    const F: Function = Function::GetBooleanStatus;
    call(c, F, |_, _| {
        let Some(out) = value.as_mut() else {
            return Err(Refusal::error("value = NULL"));
        };
        let v = co_simulation::get_boolean_status(s)?;
        *out = if v { fmi2True } else { fmi2False };
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    _value: *mut fmi2String,
) -> fmi2Status {
    call(c, Function::GetStringStatus, |_, _| {
        co_simulation::get_string_status(s)
    })
}
