//! The C types of the FMI 2.0 standard (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`), written by
//! hand for the "default" platform.
//!
//! Enumerations that arrive from the importer (`fmi2Type`, `fmi2StatusKind`) and the status the
//! FMU returns are plain `c_int`s here, never Rust enums: a Rust enum holding a value the
//! importer made up would be undefined behaviour. [`crate::fmi::Status`] is the safe
//! view of a status.
#![allow(non_camel_case_types, non_upper_case_globals, non_snake_case)]

use std::os::raw::{c_char, c_int, c_uint, c_void};

/// An FMU instance, as the importer sees it.
pub type fmi2Component = *mut c_void;
/// The importer's pointer, handed back to every callback.
pub type fmi2ComponentEnvironment = *mut c_void;
/// A saved FMU state.
pub type fmi2FMUstate = *mut c_void;
pub type fmi2ValueReference = c_uint;
pub type fmi2Real = f64;
pub type fmi2Integer = c_int;
pub type fmi2Boolean = c_int;
pub type fmi2Char = c_char;
pub type fmi2String = *const fmi2Char;
pub type fmi2Byte = c_char;

pub const fmi2True: fmi2Boolean = 1;
pub const fmi2False: fmi2Boolean = 0;

/// `fmi2Status`.
pub type fmi2Status = c_int;
pub const fmi2OK: fmi2Status = 0;
pub const fmi2Warning: fmi2Status = 1;
pub const fmi2Discard: fmi2Status = 2;
pub const fmi2Error: fmi2Status = 3;
pub const fmi2Fatal: fmi2Status = 4;
pub const fmi2Pending: fmi2Status = 5;

/// `fmi2Type`.
pub type fmi2Type = c_int;
pub const fmi2ModelExchange: fmi2Type = 0;
pub const fmi2CoSimulation: fmi2Type = 1;

/// `fmi2StatusKind`.
pub type fmi2StatusKind = c_int;
pub const fmi2DoStepStatus: fmi2StatusKind = 0;
pub const fmi2PendingStatus: fmi2StatusKind = 1;
pub const fmi2LastSuccessfulTime: fmi2StatusKind = 2;
pub const fmi2Terminated: fmi2StatusKind = 3;

/// `fmi2CallbackLogger`: `printf`-like, with the message format and its arguments last.
pub type fmi2CallbackLogger = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    ...
);
/// `fmi2CallbackAllocateMemory`.
pub type fmi2CallbackAllocateMemory = unsafe extern "C" fn(usize, usize) -> *mut c_void;
/// `fmi2CallbackFreeMemory`.
pub type fmi2CallbackFreeMemory = unsafe extern "C" fn(*mut c_void);
/// `fmi2StepFinished`.
pub type fmi2StepFinished = unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status);

/// `fmi2CallbackFunctions`. Every function pointer may be NULL (`None`); this FMU uses only the
/// logger (`canNotUseMemoryManagementFunctions="true"`, no asynchronous steps).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct fmi2CallbackFunctions {
    pub logger: Option<fmi2CallbackLogger>,
    pub allocateMemory: Option<fmi2CallbackAllocateMemory>,
    pub freeMemory: Option<fmi2CallbackFreeMemory>,
    pub stepFinished: Option<fmi2StepFinished>,
    pub componentEnvironment: fmi2ComponentEnvironment,
}

/// `fmi2EventInfo` (Model Exchange only; declared for completeness).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct fmi2EventInfo {
    pub newDiscreteStatesNeeded: fmi2Boolean,
    pub terminateSimulation: fmi2Boolean,
    pub nominalsOfContinuousStatesChanged: fmi2Boolean,
    pub valuesOfContinuousStatesChanged: fmi2Boolean,
    pub nextEventTimeDefined: fmi2Boolean,
    pub nextEventTime: fmi2Real,
}

/// `fmi2TypesPlatform`.
pub const TYPES_PLATFORM: &std::ffi::CStr = c"default";
/// `fmi2Version`.
pub const VERSION: &std::ffi::CStr = c"2.0";
