//! What a call returns, in words every FMI version shares (FMI 2.0 and 3.0 give them the same
//! numbers; `Pending` exists only in FMI 2.0's asynchronous Co-Simulation).

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
    Pending = 5,
}
