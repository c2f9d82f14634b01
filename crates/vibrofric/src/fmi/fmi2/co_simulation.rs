//! The status queries of FMI 2.0 Co-Simulation (`fmi2GetStatus` and its typed variants). They
//! exist for asynchronous steps, which this FMU never makes: every step completes before
//! `fmi2DoStep` returns.
#![allow(non_upper_case_globals)] // matched against the C names of fmi2StatusKind

use super::types::{fmi2DoStepStatus, fmi2LastSuccessfulTime, fmi2PendingStatus, fmi2Terminated};
use crate::fmi::state::Call;
use crate::fmi::{Instance, Status};

fn kind_name(kind: i32) -> String {
    match kind {
        fmi2DoStepStatus => "fmi2DoStepStatus".into(),
        fmi2PendingStatus => "fmi2PendingStatus".into(),
        fmi2LastSuccessfulTime => "fmi2LastSuccessfulTime".into(),
        fmi2Terminated => "fmi2Terminated".into(),
        k => format!("fmi2StatusKind {k} (unknown)"),
    }
}

/// A query with no answer: `fmi2Discard`, saying why.
fn unanswered(inst: &mut Instance, call: Call, kind: i32, what: &str) -> Status {
    if let Err(s) = inst.allow(call) {
        return s;
    }
    let why = match kind {
        fmi2DoStepStatus | fmi2PendingStatus => {
            "can be asked only after fmi2DoStep returned fmi2Pending; this FMU completes every step synchronously".to_string()
        }
        fmi2LastSuccessfulTime => "is a Real status: use fmi2GetRealStatus".into(),
        fmi2Terminated => "is a Boolean status: use fmi2GetBooleanStatus".into(),
        _ => "is not a status kind of FMI 2.0".into(),
    };
    inst.discard(call.name, format!("{} {why} ({what})", kind_name(kind)))
}

/// `fmi2GetStatus`: never available (no asynchronous steps); `fmi2Discard`.
pub fn get_status(inst: &mut Instance, call: Call, kind: i32) -> Status {
    unanswered(inst, call, kind, "fmi2Status")
}

/// `fmi2GetRealStatus`: `fmi2LastSuccessfulTime` is the instance's time.
pub fn get_real_status(inst: &mut Instance, call: Call, kind: i32) -> (Status, f64) {
    if kind == fmi2LastSuccessfulTime {
        if let Err(s) = inst.allow(call) {
            return (s, 0.0);
        }
        return (Status::Ok, inst.time());
    }
    (unanswered(inst, call, kind, "fmi2Real"), 0.0)
}

/// `fmi2GetIntegerStatus`: FMI 2.0 defines no Integer status; `fmi2Discard`.
pub fn get_integer_status(inst: &mut Instance, call: Call, kind: i32) -> Status {
    unanswered(inst, call, kind, "fmi2Integer")
}

/// `fmi2GetBooleanStatus`: `fmi2Terminated` is false (the slave never asks to stop).
pub fn get_boolean_status(inst: &mut Instance, call: Call, kind: i32) -> (Status, bool) {
    if kind == fmi2Terminated {
        if let Err(s) = inst.allow(call) {
            return (s, false);
        }
        return (Status::Ok, false);
    }
    (unanswered(inst, call, kind, "fmi2Boolean"), false)
}

/// `fmi2GetStringStatus`: no pending step, so no status string; `fmi2Discard`.
pub fn get_string_status(inst: &mut Instance, call: Call, kind: i32) -> Status {
    unanswered(inst, call, kind, "fmi2String")
}
