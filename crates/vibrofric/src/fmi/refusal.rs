//! Why a call is not carried out, as a value: the instance's functions and the C layers return
//! a [`Refusal`], and [`Instance::answer`](super::Instance::answer) turns it into the log
//! message, the change of state and the status, in that one place.

use std::fmt::Display;

/// A call that is not carried out, and why (the message names the variable or argument and
/// the rule; the instance adds the function's and its own name).
#[derive(Clone, Debug, PartialEq)]
pub enum Refusal {
    /// The call is wrong (state, argument, value): logged as an error, the instance enters
    /// `Error`, the status is `Error`. Nothing else changed.
    Error(String),
    /// The model cannot answer at these values (out of its domain): logged as a discard, the
    /// state stays, the status is `Discard`.
    Discard(String),
    /// The integrator could not complete a step: logged as a discard, the instance enters
    /// `StepFailed` (still at the step's start), the status is `Discard`.
    StepFailed(String),
    /// Something that cannot happen did (a caught panic, a missing simulator): the instance
    /// may be half-updated, so it only remains to be reset, restored or freed.
    Internal(String),
}

impl Refusal {
    pub fn error(msg: impl Display) -> Refusal {
        Refusal::Error(msg.to_string())
    }

    pub fn discard(msg: impl Display) -> Refusal {
        Refusal::Discard(msg.to_string())
    }

    /// A function of an interface or mode this FMU does not offer.
    pub fn unsupported(why: &str) -> Refusal {
        Refusal::Error(format!("not supported: {why}"))
    }

    /// A NULL array the call needs `n` elements of.
    pub fn null(arg: &str, n: usize) -> Refusal {
        Refusal::Error(format!(
            "{arg} = NULL with nvr = {n}: must point to {n} elements"
        ))
    }
}

/// What a function of the instance returns: its result, or why it was refused.
pub type Answer<T = super::Status> = Result<T, Refusal>;
