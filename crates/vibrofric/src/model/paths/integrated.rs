//! The integrated state every path advances: the one part of a contact's integration that all
//! paths share (what only one path needs lives in its room, in [`super::Kept`]).

use nalgebra::SVector;

use crate::solver::SolverStats;

/// The contact's integrated state, lent to the path that advances it. Every field is read or
/// written by every path: the time and the state vector (`[s | body]`), the work counters
/// (attempts of any path count against the work limit), the tolerance and the work limit of
/// the communication step in progress.
#[derive(Clone, Copy, Debug)]
pub(in crate::model) struct Integrated<const N: usize> {
    /// The time, counted from the contact's start.
    pub(in crate::model) t: f64,
    pub(in crate::model) y: SVector<f64, N>,
    /// The work counters of every path since the start.
    pub(in crate::model) stats: SolverStats,
    /// The attempts (in `stats`, accepted and rejected) after which a path stops with the
    /// work limit; `u64::MAX` outside a communication step. Not part of the saved state.
    pub(in crate::model) step_limit: u64,
    /// The relative tolerance requested by the user.
    tol: f64,
    /// Set when the state changed outside a path's own steps (an input, a parameter, a load
    /// event, a path's end) since the Radau path last ran: its history (the previous step's
    /// extrapolation, the sides of its switching functions) then restarts.
    restarted: bool,
}

impl<const N: usize> Integrated<N> {
    pub(in crate::model) fn new(t: f64, y: SVector<f64, N>, tol: f64) -> Self {
        Integrated {
            t,
            y,
            stats: SolverStats::default(),
            step_limit: u64::MAX,
            tol,
            restarted: false,
        }
    }

    pub(in crate::model) fn tolerance(&self) -> f64 {
        self.tol
    }

    /// Tells the paths that the right-hand side may have jumped at the current time (an input
    /// changed) or the state was set from outside: no path extrapolates its previous step.
    pub(in crate::model) fn restart(&mut self) {
        self.restarted = true;
    }

    /// Replaces the state at the current time (after a projection or a parameter change).
    pub(in crate::model) fn set_state(&mut self, y: SVector<f64, N>) {
        self.y = y;
        self.restart();
    }

    /// Whether a restart is pending, cleared (the Radau path, as it takes the state).
    pub(super) fn take_restart(&mut self) -> bool {
        std::mem::take(&mut self.restarted)
    }

    /// Whether a restart is pending (saved states).
    pub(super) fn restarted(&self) -> bool {
        self.restarted
    }
}
