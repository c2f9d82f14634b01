//! The status queries of FMI 2.0 Co-Simulation (`fmi2GetStatus` and its typed variants). They
//! exist for asynchronous steps, which this FMU never makes: every step completes before
//! `fmi2DoStep` returns.
#![allow(non_upper_case_globals)] // matched against the C names of fmi2StatusKind

use super::types::{fmi2DoStepStatus, fmi2LastSuccessfulTime, fmi2PendingStatus, fmi2Terminated};
use crate::fmi::{Answer, Instance, Refusal};

fn kind_name(kind: i32) -> String {
    match kind {
        fmi2DoStepStatus => "fmi2DoStepStatus".into(),
        fmi2PendingStatus => "fmi2PendingStatus".into(),
        fmi2LastSuccessfulTime => "fmi2LastSuccessfulTime".into(),
        fmi2Terminated => "fmi2Terminated".into(),
        k => format!("fmi2StatusKind {k} (unknown)"),
    }
}

/// A query with no answer: a discard, saying why.
fn unanswered(kind: i32, what: &str) -> Refusal {
    let why = match kind {
        fmi2DoStepStatus | fmi2PendingStatus => {
            "can be asked only after fmi2DoStep returned fmi2Pending; this FMU completes every step synchronously".to_string()
        }
        fmi2LastSuccessfulTime => "is a Real status: use fmi2GetRealStatus".into(),
        fmi2Terminated => "is a Boolean status: use fmi2GetBooleanStatus".into(),
        _ => "is not a status kind of FMI 2.0".into(),
    };
    Refusal::discard(format!("{} {why} ({what})", kind_name(kind)))
}

/// `fmi2GetStatus`: never available (no asynchronous steps); `fmi2Discard`.
pub fn get_status(kind: i32) -> Answer {
    Err(unanswered(kind, "fmi2Status"))
}

/// `fmi2GetRealStatus`: `fmi2LastSuccessfulTime` is the instance's time.
pub fn get_real_status(inst: &Instance, kind: i32) -> Answer<f64> {
    if kind == fmi2LastSuccessfulTime {
        return Ok(inst.time());
    }
    Err(unanswered(kind, "fmi2Real"))
}

/// `fmi2GetIntegerStatus`: FMI 2.0 defines no Integer status; `fmi2Discard`.
pub fn get_integer_status(kind: i32) -> Answer {
    Err(unanswered(kind, "fmi2Integer"))
}

/// `fmi2GetBooleanStatus`: `fmi2Terminated` is false (the slave never asks to stop).
pub fn get_boolean_status(kind: i32) -> Answer<bool> {
    if kind == fmi2Terminated {
        return Ok(false);
    }
    Err(unanswered(kind, "fmi2Boolean"))
}

/// `fmi2GetStringStatus`: no pending step, so no status string; `fmi2Discard`.
pub fn get_string_status(kind: i32) -> Answer {
    Err(unanswered(kind, "fmi2String"))
}
