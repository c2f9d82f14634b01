//! Taking a contact's complete state ([`ContactState`]) and restoring it, which checks every
//! field: a saved state is untrusted input (it may have been serialized, edited
//! and read back), so each value is checked as the call that sets it checks it and for
//! consistency with the rest; the first field that fails is named and nothing changes.

use super::contact::Contact;
use super::drive::DriveKind;
use super::paths::{self, Saved};
use super::simulator::{SimError, TOLERANCE_RANGE};
use super::state::{ContactState, StepMeanState, WindowState};
use super::time::{boundary_snap, MAX_INPUT_RATE, WINDOWS_MAX};
use super::window::{StepMean, Window};
use crate::physics::{FrictionLaw, Harmonic, Vector};
use crate::solver::{Radau5, MAX_QUAD};
use crate::table::{InputId, Params};

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Contact<V, L, D, N> {
    /// The complete state.
    pub(super) fn save(&self) -> ContactState {
        let h = self
            .dynamics
            .harmonic
            .unwrap_or(Harmonic::new(0.0, 0.0, 0.0, 0.0, 0.0));
        let mut integrator = Vec::with_capacity(Radau5::<N>::SAVED_LEN);
        self.paths
            .radau
            .integrator(&self.state)
            .save(&mut integrator);
        ContactState {
            config: self.config,
            params: self.params,
            tracks: self.dynamics.tracks,
            x_kin_ref: self.dynamics.x_kin_ref,
            harmonic_t_ref: h.t_ref,
            harmonic_theta_ref: h.theta_ref,
            window: WindowState {
                origin: self.window.origin,
                len: self.window.len,
                index: self.window.index,
                acc: self.window.acc,
                last: self.window.last,
            },
            integrator,
            exp_h: self.paths.h,
            direction: self.paths.direction(),
            step_mean: StepMeanState {
                last: self.step.last,
                h: self.step.h,
                f_start: self.step.f_start,
            },
            lifted: self.dynamics.lifted,
            epoch: self.epoch,
            t_abs: self.t_abs,
            sides: self.sides,
        }
    }

    /// The contact a state describes, after checking every field. `free_time`: the state of a
    /// Model Exchange importer, whose time may be anywhere `set_time` accepts; else the time
    /// lies in the averaging window in progress, as stepping leaves it.
    pub(super) fn load(&self, s: &ContactState, free_time: bool) -> Result<Self, SimError> {
        let bad = |what: String| Err(SimError::BadSnapshot(what));
        if s.config != self.config {
            return bad("taken from another scene (configuration)".into());
        }
        if let Some((name, x)) = s.numbers().into_iter().find(|(_, x)| !x.is_finite()) {
            return bad(format!("{name} is {x}: every number must be finite"));
        }
        let mut params = Params::default();
        for id in crate::table::ParamId::ALL {
            let value = id.get(&s.params);
            id.check_in(value, &self.config)
                .and_then(|_| id.set(&mut params, value))
                .map_err(|e| SimError::BadSnapshot(format!("parameter {e}")))?;
        }
        // The reference load is the scene's: it cannot change during a simulation.
        if (s.params.f_n_ref, s.params.mu_ref) != (self.params.f_n_ref, self.params.mu_ref) {
            return bad("taken from another scene (reference load)".into());
        }
        (params.f_n_ref, params.mu_ref) = (self.params.f_n_ref, self.params.mu_ref);
        for (t, id) in s.tracks.iter().zip(InputId::ALL) {
            if id.present(&self.config) && !id.rule().holds(t.value) {
                return bad(format!(
                    "input {} = {}: {}",
                    id.name(),
                    t.value,
                    id.rule().text(t.value, id.unit())
                ));
            }
            if t.slope.abs() > MAX_INPUT_RATE {
                return bad(format!(
                    "derivative of {} = {}: beyond {MAX_INPUT_RATE:e}",
                    id.name(),
                    t.slope
                ));
            }
        }
        // rem_euclid by 2 pi, which sets the reference, rounds a tiny negative phase to 2 pi
        // itself: the closed interval.
        let theta_ref = s.harmonic_theta_ref;
        if !(0.0..=std::f64::consts::TAU).contains(&theta_ref) {
            return bad(format!(
                "harmonic phase reference = {theta_ref}: must be in [0, 2 pi]"
            ));
        }
        let radau = Radau5::<N>::load(&s.integrator)
            .ok_or(SimError::BadSnapshot("integrator state".into()))?;
        let (lo, hi) = TOLERANCE_RANGE;
        if !(lo..=hi).contains(&radau.tolerance()) {
            return bad(format!(
                "tolerance = {}: must be in [{lo:e}, {hi:e}]",
                radau.tolerance()
            ));
        }
        let mut c = Contact::<V, L, D, N>::new_local(self.config, params, radau.tolerance());
        check_window(s, c.window.len, radau.t, free_time)?;
        let w = &s.window;
        if paths::step_proposal(s.exp_h).to_bits() != s.exp_h.to_bits() {
            return bad(format!(
                "step proposal of the explicit paths = {}: must be a length >= 0, or +inf where nothing bounds the step",
                s.exp_h
            ));
        }
        if s.step_mean.h < 0.0 {
            return bad("a step length is negative".into());
        }
        if ![-1.0, 0.0, 1.0].contains(&s.direction) {
            return bad(format!(
                "branch of the explicit path {}: must be -1, 0 or 1",
                s.direction
            ));
        }
        (c.epoch, c.t_abs) = (s.epoch, s.t_abs);
        c.dynamics.tracks = s.tracks;
        c.dynamics.x_kin_ref = s.x_kin_ref;
        if let Some(h) = &mut c.dynamics.harmonic {
            h.t_ref = s.harmonic_t_ref;
            h.theta_ref = theta_ref;
        }
        c.window = Window {
            origin: w.origin,
            len: w.len,
            index: w.index,
            acc: w.acc,
            last: w.last,
        };
        // The integrator's numbers: the shared state and the Radau path's history.
        let (state, history) = paths::split_integrator(radau);
        c.state = state;
        // The same breakaway ratio: the same shape, without fitting it again.
        let same_shape = c.params.r_ba == self.params.r_ba;
        let kept = Saved::new(s.exp_h, s.direction, history);
        c.paths.load(&self.paths, kept, same_shape);
        c.step = StepMean {
            acc: [0.0; MAX_QUAD],
            last: s.step_mean.last,
            h: s.step_mean.h,
            f_start: s.step_mean.f_start,
        };
        c.dynamics.lifted = s.lifted;
        if let Some(x) = s.sides.iter().find(|x| ![-1.0, 0.0, 1.0].contains(*x)) {
            return bad(format!("event indicator side = {x}: must be -1, 0 or 1"));
        }
        c.sides = s.sides;
        c.update_scale();
        Ok(c)
    }
}

/// Checks a saved state's averaging window (`len`: the length the parameters give) and its
/// time `t` in the contact's own time.
fn check_window(s: &ContactState, len: f64, t: f64, free_time: bool) -> Result<(), SimError> {
    let bad = |what: String| Err(SimError::BadSnapshot(what));
    // The averaging window: the length the parameters give, an index within range, the
    // current time inside the window.
    let w = &s.window;
    if w.len != len {
        return bad(format!(
            "window length = {}: the parameters give {}",
            w.len, len
        ));
    }
    if w.index as f64 > WINDOWS_MAX {
        return bad(format!(
            "window index = {}: must be at most {WINDOWS_MAX:e}",
            w.index
        ));
    }
    if (s.t_abs - s.epoch - t).abs() > 1e-9 * s.t_abs.abs().max(1.0) {
        return bad(format!(
            "time {} is not the start time {} plus the integrator's time {}",
            s.t_abs, s.epoch, t
        ));
    }
    if free_time {
        // As `set_time` checks the time an importer sets.
        let windows = (t - w.origin).abs() / w.len;
        if windows.is_nan() || windows > WINDOWS_MAX {
            return bad(format!(
                "time {} is {windows:e} averaging windows from the window origin {}: at most {WINDOWS_MAX:e}",
                s.t_abs,
                s.epoch + w.origin
            ));
        }
    } else {
        // Stepping ends inside the window in progress, or on its start within the
        // rounding `step_to` takes as on a boundary: the same arithmetic here.
        let (w_start, w_end) = (
            w.origin + w.index as f64 * w.len,
            w.origin + (w.index + 1) as f64 * w.len,
        );
        let on_start = t >= w_start || (w_start - t).abs() <= boundary_snap(t, s.t_abs, w.len);
        if !(on_start && t <= w_end) {
            return bad(format!(
                "time {} outside the averaging window [{w_start}, {w_end}]",
                t
            ));
        }
    }
    Ok(())
}
