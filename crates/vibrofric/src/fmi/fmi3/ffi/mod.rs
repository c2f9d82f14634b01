//! The exported FMI 3.0 functions: every function of the standard's C interface, so that any
//! importer binds the library. Co-Simulation without event mode and Model Exchange work as in
//! FMI 2.0, on the same instance; `Float64` is the only variable type; the functions of
//! Scheduled Execution, clocks, event mode and configuration mode answer with an error naming
//! what this FMU offers instead.
//!
//! Thin, like the FMI 2.0 layer: pointer and length checks, then the instance. Shared with it:
//! `fmi/c_boundary.rs` (boxes with magic numbers, panics caught, C arrays and strings). Files:
//! this one (the instance's life: instantiation, modes, Co-Simulation's step), `variables.rs`
//! (getters and setters, the FMU state, derivatives), `model_exchange.rs` (Model Exchange, and
//! what is not offered).
#![allow(non_snake_case, clippy::missing_safety_doc, clippy::too_many_arguments)]

mod model_exchange;
mod variables;

use std::ffi::CString;
use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::ptr;

use super::types::*;
use super::Function;
use crate::description::log::Category;
use crate::fmi::c_boundary::{array, component, run, string, Component, COMPONENT_MAGIC};
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
