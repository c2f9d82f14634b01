//! The general path: Radau IIA of order 5 (`solver/radau/`) on the whole state, with event
//! location at every sign change of the switching functions, for every contact no faster path
//! takes. Its history between calls (step sizes, Newton's contraction, the last step's dense
//! output, the sides of the switching functions) and its scratch matrices are its own
//! ([`RadauKept`]); the time, state vector, counters, tolerance and work limit are the
//! contact's ([`Integrated`]), taken on entry and handed back on exit.

use super::{Integrated, Kept, Path, Shared};
use crate::model::drive::DriveKind;
use crate::model::simulator::SimError;
use crate::physics::{FrictionLaw, Vector};
use crate::solver::{Quad, Radau5, Step, Workspace, MAX_QUAD};

/// What only the Radau path keeps between calls.
#[derive(Clone, Debug)]
pub(in crate::model) struct RadauKept<const N: usize> {
    /// The integrator with its history. Its own time, vector and counters are the shared
    /// state's, copied in when the path starts and out when it ends: they mean nothing
    /// between calls.
    history: Radau5<N>,
    /// The Newton matrix's storage: scratch.
    work: Workspace,
}

impl<const N: usize> RadauKept<N> {
    /// No history yet, at tolerance `tol`.
    pub(super) fn new(tol: f64) -> Self {
        RadauKept {
            history: Radau5::new(0.0, nalgebra::SVector::zeros(), tol),
            work: Workspace::new(N),
        }
    }

    /// The history a failed communication step restores (the scratch matrices stay).
    pub(super) fn history(&self) -> Radau5<N> {
        self.history
    }

    pub(super) fn set_history(&mut self, history: Radau5<N>) {
        self.history = history;
    }

    /// The integrator as the saved state's `integrator` numbers describe it: the shared state
    /// in the history, a pending restart applied (the format of [`Radau5::save`]).
    pub(in crate::model) fn integrator(&self, r: &Integrated<N>) -> Radau5<N> {
        let mut h = self.history;
        h.t = r.t;
        h.y = r.y;
        h.stats = r.stats;
        if r.restarted() {
            h.restart();
        }
        h
    }
}

/// The shared state and the Radau path's history of an integrator a saved state describes.
pub(in crate::model) fn split<const N: usize>(h: Radau5<N>) -> (Integrated<N>, Radau5<N>) {
    let mut r = Integrated::new(h.t, h.y, h.tolerance());
    r.stats = h.stats;
    (r, h)
}

/// The Radau IIA path.
pub(super) struct Radau;

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Path<V, L, D, N> for Radau {
    /// Always: the path of last resort.
    fn applies(_: &Shared<'_, V, L, D, N>, _: &Integrated<N>, _: &Kept<N>) -> bool {
        true
    }

    fn advance(
        c: &Shared<'_, V, L, D, N>,
        r: &mut Integrated<N>,
        k: &mut Kept<N>,
        t_target: f64,
        h_max: f64,
    ) -> Result<Quad, SimError> {
        let sys = c.system();
        let RadauKept { history: h, work } = &mut k.radau;
        h.t = r.t;
        h.y = r.y;
        h.stats = r.stats;
        h.step_limit = r.step_limit;
        if r.take_restart() {
            h.restart();
        }
        let mut acc = [0.0; MAX_QUAD];
        let result = h.integrate_with(work, &sys, t_target, h_max, |step: &Step<N>| {
            acc[0] += step.quad[0];
            acc[1] += step.quad[1];
        });
        r.t = h.t;
        r.y = h.y;
        r.stats = h.stats;
        result.map_err(SimError::Solver)?;
        Ok(acc)
    }
}
