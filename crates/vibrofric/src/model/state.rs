//! A contact's complete state, by name: what a saved FMU state holds and what restores it
//! (`snapshot.rs` takes and checks it).

use serde::{Deserialize, Serialize};

use crate::physics::InputTrack;
use crate::solver::{MAX_QUAD, MAX_SWITCH};
use crate::table::{Config, InputId, Params};

/// Everything a contact needs to continue bit for bit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactState {
    /// The scene's structural choices; a state restores only into the same configuration.
    pub config: Config,
    pub params: Params,
    /// Input tracks, indexed like [`InputId::ALL`].
    pub tracks: [InputTrack; InputId::ALL.len()],
    /// The body's position under velocity drive at the tracks' reference time.
    pub x_kin_ref: f64,
    /// The harmonic source's phase reference: time and phase there (0 without the source).
    pub harmonic_t_ref: f64,
    pub harmonic_theta_ref: f64,
    pub window: WindowState,
    /// The Radau integrator's state, as `Radau5::save` writes it.
    pub integrator: Vec<f64>,
    /// The explicit paths' proposed step (0: none yet; +inf where nothing bounds it).
    pub exp_h: f64,
    /// The explicit path's branch, the sign of `v_r` (−1, +1; 0 before it is known).
    pub direction: f64,
    pub step_mean: StepMeanState,
    /// The body has lifted off (normal force input below the lift-off load).
    pub lifted: bool,
    /// The start time every inner time counts from, and the current time as the importer
    /// gave it.
    pub epoch: f64,
    pub t_abs: f64,
    /// Model Exchange: the side of each switching function since the last event (−1, +1; 0
    /// before the first event update).
    pub sides: [f64; MAX_SWITCH],
}

/// The averaging window of `F_mean`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WindowState {
    pub origin: f64,
    pub len: f64,
    pub index: u64,
    /// `∫F_Fx dt` since the window's start.
    pub acc: f64,
    /// The mean of the last completed window.
    pub last: Option<f64>,
}

/// The means over the last communication step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepMeanState {
    pub last: Option<[f64; MAX_QUAD]>,
    pub h: f64,
    pub f_start: [f64; MAX_QUAD],
}

impl ContactState {
    /// Every number of the state with its name, for the finiteness check.
    pub(super) fn numbers(&self) -> Vec<(String, f64)> {
        let mut v = vec![];
        for (t, id) in self.tracks.iter().zip(InputId::ALL) {
            let n = id.name();
            v.push((format!("input track {n} reference time"), t.t_ref));
            v.push((format!("input {n}"), t.value));
            v.push((format!("derivative of {n}"), t.slope));
        }
        v.push(("velocity-drive position reference".into(), self.x_kin_ref));
        v.push(("harmonic time reference".into(), self.harmonic_t_ref));
        v.push(("harmonic phase reference".into(), self.harmonic_theta_ref));
        let w = &self.window;
        v.push(("window origin".into(), w.origin));
        v.push(("window length".into(), w.len));
        v.push(("window integral".into(), w.acc));
        v.push(("last window mean".into(), w.last.unwrap_or(0.0)));
        for (k, x) in self.integrator.iter().enumerate() {
            v.push((format!("integrator number {k}"), *x));
        }
        // The step proposal `exp_h` has its own rule (+inf allowed): `Contact::load`.
        v.push(("branch of the explicit path".into(), self.direction));
        let s = &self.step_mean;
        let last = s.last.unwrap_or([0.0; MAX_QUAD]);
        v.push(("last step mean of F_Fx".into(), last[0]));
        v.push(("last step mean of F_Fy".into(), last[1]));
        v.push(("last step length".into(), s.h));
        v.push(("step-start F_Fx".into(), s.f_start[0]));
        v.push(("step-start F_Fy".into(), s.f_start[1]));
        v.push(("start time".into(), self.epoch));
        v.push(("time".into(), self.t_abs));
        v
    }
}
