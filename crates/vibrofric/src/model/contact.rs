//! One contact, generic over its vector type (`f64` longitudinal, `Planar`), its friction law
//! and its drive. Each combination compiles to its own code: a longitudinal contact has no
//! second component, a velocity drive integrates no body, Dahl evaluates no Stribeck curve.
//!
//! The integrated state is `[s (DIM) | body (D::N_BODY)]`. Positions that follow from the
//! inputs alone (the body's `x` under velocity drive, the spring's far end `x_d`) are exact
//! integrals of the input tracks, not integrator states.

// Jacobian assembly indexes rows and columns of several matrices in lockstep.
#![allow(clippy::needless_range_loop)]

use nalgebra::SVector;

use super::drive::DriveKind;
use super::dynamics::{lift_off, Dynamics, Eval, System};
use super::ode::{ContactOde, Ode};
use super::paths::{self, Integrated, Kept, Shared};
use super::simulator::{Integrator, SimError, Simulator, StepStats};
use super::state::ContactState;
use super::time::{boundary_snap, canonical_time, MAX_INPUT_RATE, WINDOWS_MAX};
use super::window::{affine_sums, StepMean, Window};
use crate::physics::{FrictionLaw, Harmonic, InputTrack, Vector, NO_FRICTION_LENGTH};
use crate::solver::{OdeSystem, Quad, SolverError, SolverStats, MAX_QUAD, MAX_SWITCH};
use crate::table::{Config, Drive, InputId, Inputs, OutputId, Outputs, ParamId, Params};

/// What every path reads of a contact ([`Shared`]), from its fields.
macro_rules! shared {
    ($c:expr) => {
        Shared {
            config: $c.config,
            params: &$c.params,
            dynamics: &$c.dynamics,
            scale: &$c.scale,
            force_scale: $c.force_scale,
            switch_scale: $c.switch_scale,
            window_len: $c.window.len,
        }
    };
}

/// A contact with its integrator: implements [`Simulator`].
#[derive(Clone, Debug)]
pub struct Contact<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> {
    pub(super) config: Config,
    pub(super) params: Params,
    pub(super) dynamics: Dynamics<V, L, D>,
    /// Natural magnitudes of the state components.
    pub(super) scale: [f64; N],
    /// Natural magnitude of the friction force, for the error of its integral.
    pub(super) force_scale: f64,
    /// Natural magnitudes of the switching functions `v_rx` and `s·v_r`.
    pub(super) switch_scale: [f64; MAX_SWITCH],
    /// What every path shares: the integrated state (time, state vector, work counters,
    /// tolerance, work limit), lent to the path that advances it.
    pub(super) state: Integrated<N>,
    /// What each path keeps of its own between calls (`paths/`: the explicit path's branch,
    /// Radau's history, ...), lent with the state.
    pub(super) paths: Kept<N>,
    pub(super) window: Window,
    pub(super) step: StepMean,
    /// The start time: every time inside the contact (integrator, input tracks, harmonic
    /// phase, windows) counts from it, so that a start time of 1e9 s keeps the resolution of
    /// one of 0.
    pub(super) epoch: f64,
    /// The current time as the importer gave it.
    pub(super) t_abs: f64,
    /// Model Exchange: the side of each switching function since the last event (0: not yet
    /// known), for the event indicators' hysteresis (`exchange.rs`).
    pub(super) sides: [f64; MAX_SWITCH],
}

/// Builds the contact with state dimension `N` (checked against the types).
pub fn boxed<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
    config: Config,
    params: Params,
    t_start: f64,
    tolerance: f64,
    force_radau: bool,
) -> Box<dyn Simulator> {
    assert_eq!(N, V::DIM + D::N_BODY, "state dimension of {config:?}");
    let mut c = Contact::<V, L, D, N>::new(config, params, t_start, tolerance);
    c.paths.force_radau = force_radau;
    Box::new(c)
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Contact<V, L, D, N> {
    /// A contact at rest at `t_start`; inside, times count from `t_start` (see `epoch`).
    fn new(config: Config, params: Params, t_start: f64, tolerance: f64) -> Self {
        let mut c = Self::new_local(config, params, tolerance);
        c.epoch = t_start;
        c.t_abs = t_start;
        c
    }

    pub(super) fn new_local(config: Config, params: Params, tolerance: f64) -> Self {
        let t_start = 0.0;
        let dynamics = Dynamics {
            law: L::new(&params),
            drive: D::new(&params),
            harmonic: config
                .harmonic
                .then(|| Harmonic::new(params.u0, params.f, params.angle, params.phase, t_start)),
            tracks: std::array::from_fn(|k| InputTrack {
                t_ref: t_start,
                value: if InputId::ALL[k] == InputId::FN {
                    params.f_n
                } else {
                    0.0
                },
                slope: 0.0,
            }),
            load: config.normal_input.then_some(params),
            lift_off: lift_off(&params, tolerance),
            lifted: false,
            x_kin_ref: 0.0,
            f_c: params.f_c(),
            _v: std::marker::PhantomData,
        };
        let mut c = Contact {
            config,
            params,
            dynamics,
            scale: [0.0; N],
            force_scale: 0.0,
            switch_scale: [0.0; MAX_SWITCH],
            state: Integrated::new(t_start, SVector::zeros(), tolerance),
            paths: Kept::new(tolerance),
            window: Window {
                origin: t_start,
                len: 0.0,
                index: 0,
                acc: 0.0,
                last: None,
            },
            step: StepMean::NONE,
            epoch: 0.0,
            t_abs: 0.0,
            sides: [0.0; MAX_SWITCH],
        };
        c.window.len = c.window_length();
        c.update_scale();
        c.update_lifted();
        c
    }

    /// Decides whether the body is off the support from the load input now; a body that lifts
    /// off leaves no deformation.
    fn update_lifted(&mut self) {
        if self.dynamics.load.is_none() {
            return;
        }
        self.dynamics.lifted = self.dynamics.off_at(self.state.t);
        self.clear_deformation_if_lifted();
    }

    /// A body off the support has no deformation.
    fn clear_deformation_if_lifted(&mut self) {
        if self.dynamics.lifted {
            let mut y = self.state.y;
            y.as_mut_slice()[..V::DIM].fill(0.0);
            self.state.y = y;
        }
    }

    /// The averaging window: the excitation period, or `T_avg` without a source, at `f` = 0
    /// and at a frequency whose period overflows (a subnormal `f`: no vibration either).
    fn window_length(&self) -> f64 {
        match &self.dynamics.harmonic {
            Some(h) if h.f > 0.0 && (1.0 / h.f).is_finite() => 1.0 / h.f,
            _ => self.params.t_avg,
        }
    }

    pub(super) fn update_scale(&mut self) {
        let p = &self.params;
        let s_nom = self.dynamics.law.s_scale();
        let v_a = self.dynamics.harmonic.map_or(0.0, |h| h.v_a());
        let x_nom = s_nom.max(p.u0 * self.config.harmonic as u8 as f64);
        let v_nom = v_a.max(s_nom * (p.k_t / p.m).sqrt()).max(1e-9);
        self.scale[..V::DIM].fill(s_nom);
        self.force_scale = (p.k_t * s_nom).max(p.h_v * v_nom).max(1e-300);
        self.switch_scale = [v_nom, s_nom * v_nom];
        self.dynamics
            .drive
            .scale(x_nom, v_nom, &mut self.scale[V::DIM..]);
    }

    /// What every path reads of the contact.
    pub(super) fn shared(&self) -> Shared<'_, V, L, D, N> {
        shared!(self)
    }

    /// What every path reads of the contact, with the state and what the paths keep, for a
    /// path to advance.
    fn lend(&mut self) -> (Shared<'_, V, L, D, N>, &mut Integrated<N>, &mut Kept<N>) {
        (shared!(self), &mut self.state, &mut self.paths)
    }

    pub(super) fn system(&self) -> System<'_, V, L, D> {
        self.shared().system()
    }

    /// The path the contact takes now (`paths::choose`).
    fn path(&self) -> Integrator {
        paths::choose(&self.shared(), &self.state, &self.paths)
    }

    /// Longest step that cannot hide a pair of sign changes of `v_r` from the harmonic source.
    fn h_max(&self) -> f64 {
        match &self.dynamics.harmonic {
            Some(h) if h.f > 0.0 && h.u0 > 0.0 => 0.25 / h.f,
            _ => f64::INFINITY,
        }
    }

    /// Everything at the current time and state.
    pub(super) fn eval_now(&self) -> Eval<V> {
        self.system().eval(self.state.t, self.state.y.as_slice())
    }

    fn track_index(&self, id: InputId) -> Result<usize, SimError> {
        if !id.present(&self.config) {
            return Err(SimError::NoSuchInput(id.name()));
        }
        Ok(id.index())
    }

    /// True when no input has a derivative set: the forcing is then periodic in the window.
    fn inputs_held(&self) -> bool {
        self.dynamics.tracks.iter().all(|t| t.slope == 0.0)
    }

    /// Skips `m` whole windows from the start of the current one in O(1), on a path where the
    /// map of a window is affine ([`paths::windows_affine`]) and the inputs held, so that the
    /// forcing is periodic in the window: `m` maps compose in closed form. The first window is
    /// integrated to learn `L` and `beta`; the windows skipped leave no mean.
    fn skip_windows(&mut self, m: u64, h_max: f64) -> Result<(), SimError> {
        let s0 = V::read(self.state.y.as_slice());
        let t_b = self.window.end();
        // The window's integral is affine in its initial deformation too, `I(s) = I_p + G·s`
        // with a scalar `G = ∫ ∂F/∂s·exp(−Λ(t)) dt`: a second run from `s0 + δ·e_x` gives `G`.
        let before = (self.state, self.paths.h);
        let delta = self.scale[0];
        let mut y = self.state.y;
        y[0] += delta;
        self.state.y = y;
        let probe = self.advance_window(t_b, h_max)?.1;
        let probe_stats = self.state.stats;
        (self.state, self.paths.h) = before;
        self.state.stats = probe_stats;
        let (decay, integral) = self.advance_window(t_b, h_max)?;
        let g = (probe[0] - integral[0]) / delta;
        let s1 = V::read(self.state.y.as_slice());
        let k = (m - 1) as f64;
        let beta = s1 - s0 * libm::exp(-decay);
        // Σ_{j<k} exp(−j·L) = (1 − exp(−k·L))/(1 − exp(−L)), k when L = 0.
        let sum = if decay > 0.0 {
            libm::expm1(-k * decay) / libm::expm1(-decay)
        } else {
            k
        };
        let s = s1 * libm::exp(-k * decay) + beta * sum;
        // ∫F_F dt over the k windows skipped: k·I_p + G·Σ_{j<k} s_j, s_j the j-th window's start.
        let (c_sum, d_sum) = affine_sums(libm::exp(-decay), beta, m - 1);
        let states = s1 * c_sum + d_sum;
        let i_p = V::from_xy(integral[0], integral[1]) - s0 * g;
        let skipped = i_p * k + states * g;
        self.step.acc[0] += integral[0] + skipped.x();
        self.step.acc[1] += integral[1] + skipped.y();
        self.window.last = Some(integral[0] / self.window.len);
        self.window.acc = 0.0;
        self.window.index += m;
        self.state.t = self.window.start();
        let mut y = self.state.y;
        s.write(y.as_mut_slice());
        OdeSystem::<N>::project(&self.system(), self.state.t, &mut y);
        self.state.y = y;
        self.state.stats.steps += 1;
        Ok(())
    }

    /// Advances a path whose map of a window is affine to `t_target`: the decay and `∫F_F dt`.
    fn advance_window(&mut self, t_target: f64, h_max: f64) -> Result<(f64, Quad), SimError> {
        let (shared, state, kept) = self.lend();
        paths::advance_affine(&shared, state, kept, t_target, h_max)
    }

    /// Integrates to `t_target` (≤ the current window's end) on the path the contact takes
    /// now, accumulating `∫F_F dt` in the window and the communication step.
    fn integrate(&mut self, t_target: f64, h_max: f64) -> Result<(), SimError> {
        let path = self.path();
        let (shared, state, kept) = self.lend();
        let integral = paths::advance(path, &shared, state, kept, t_target, h_max)?;
        self.window.acc += integral[0];
        self.step.acc[0] += integral[0];
        self.step.acc[1] += integral[1];
        Ok(())
    }

    /// Steps window by window to `t_end` (a communication point within `snap` of a window's
    /// end completes the window), within `limit` attempts in the work counters: many whole
    /// windows with the forcing periodic skipped, each window's mean and the step's integrals
    /// accumulated, the body lifted or put down at the load's events.
    fn windows_to(
        &mut self,
        t_end: f64,
        snap: f64,
        h_max: f64,
        limit: u64,
    ) -> Result<(), SimError> {
        while self.state.t < t_end {
            let st = &self.state.stats;
            if st.steps + st.rejected >= limit {
                return Err(SimError::Solver(SolverError::WorkLimit {
                    t: self.state.t,
                    limit: self.params.max_steps,
                }));
            }
            // Many whole windows ahead with the forcing periodic: skip all but the last
            // (whose mean is the output) in O(1).
            let whole = ((t_end - self.state.t) / self.window.len).floor();
            if whole >= 3.0
                && self.state.t == self.window.start()
                && self.inputs_held()
                && paths::windows_affine(&self.shared(), &self.state, &self.paths)
            {
                self.skip_windows(whole as u64 - 1, h_max)?;
                continue;
            }
            let mut t_b = self.window.end();
            if (t_b - t_end).abs() <= snap {
                // A communication point on a window boundary completes the window,
                // whichever side of it the importer's rounding put the point.
                t_b = t_end;
            }
            let mut target = t_b.min(t_end);
            let load_event = self.dynamics.load_event(self.state.t, target);
            if let Some(t_event) = load_event {
                target = t_event;
            }
            self.integrate(target, h_max)?;
            if load_event.is_some() {
                self.dynamics.lifted = !self.dynamics.lifted;
                self.clear_deformation_if_lifted();
                self.state.restart();
            }
            if target == t_b {
                self.window.last = Some(self.window.acc / self.window.len);
                self.window.acc = 0.0;
                self.window.index += 1;
            }
        }
        Ok(())
    }

    /// Input derivatives are valid for one step: holds the inputs from the time now on.
    fn hold_inputs(&mut self) {
        let t = self.state.t;
        for (k, track) in self.dynamics.tracks.iter_mut().enumerate() {
            if track.slope != 0.0 {
                if k == 1 {
                    self.dynamics.x_kin_ref += track.integral(t);
                    track.t_ref = t;
                }
                track.slope = 0.0;
                self.state.restart();
            }
        }
        // Keep x_kin anchored near the current time for precision.
        let vd = &mut self.dynamics.tracks[InputId::VD.index()];
        self.dynamics.x_kin_ref += vd.integral(t);
        vd.t_ref = t;
    }

    pub(super) fn f_mean(&self) -> f64 {
        if let Some(m) = self.window.last {
            return m;
        }
        let elapsed = self.state.t - self.window.start();
        if elapsed > 0.0 {
            self.window.acc / elapsed
        } else {
            self.eval_now().f.x()
        }
    }
}

/// `reduction = 1 − F_mean/F_C` (`docs/model.md`; an output of velocity drives only): the
/// fraction by which the vibration lowers the mean friction. 0 where the Coulomb force acts as
/// none (`F_C/k_t` at most [`NO_FRICTION_LENGTH`], `F_C` = 0 included): there is no Coulomb
/// force to compare with.
pub(super) fn reduction(f_mean: f64, f_c: f64, k_t: f64) -> f64 {
    if f_c / k_t > NO_FRICTION_LENGTH {
        1.0 - f_mean / f_c
    } else {
        0.0
    }
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Simulator for Contact<V, L, D, N> {
    fn config(&self) -> Config {
        self.config
    }

    fn params(&self) -> &Params {
        &self.params
    }

    fn set_param(&mut self, id: ParamId, value: f64) -> Result<(), SimError> {
        if !id.tunable() {
            return Err(SimError::NotTunable(id.name()));
        }
        if id == ParamId::FN && self.config.normal_input {
            return Err(SimError::NoSuchParam(id.name()));
        }
        let mut params = self.params;
        id.set(&mut params, value)?;
        if params == self.params {
            return Ok(());
        }
        let t = self.state.t;
        self.params = params;
        self.dynamics.law = L::new(&params);
        if let Some(reference) = &mut self.dynamics.load {
            *reference = params;
        }
        self.dynamics.drive = D::new(&params);
        self.dynamics.f_c = params.f_c();
        if let Some(h) = &mut self.dynamics.harmonic {
            h.rebase(t);
            if id == ParamId::Phase {
                h.theta_ref = value.rem_euclid(std::f64::consts::TAU);
            }
            h.u0 = params.u0;
            h.f = params.f;
            h.dir = (libm::cos(params.angle), libm::sin(params.angle));
        }
        // A new source or load starts a new averaging window.
        self.window = Window {
            origin: t,
            len: 0.0,
            index: 0,
            acc: 0.0,
            last: None,
        };
        self.window.len = self.window_length();
        self.update_scale();
        let mut y = self.state.y;
        OdeSystem::<N>::project(&self.system(), t, &mut y);
        self.state.set_state(y);
        Ok(())
    }

    fn time(&self) -> f64 {
        self.t_abs
    }

    fn tolerance(&self) -> f64 {
        self.state.tolerance()
    }

    fn set_input(&mut self, id: InputId, value: f64) -> Result<(), SimError> {
        let k = self.track_index(id)?;
        if !id.rule().holds(value) {
            return Err(SimError::Input { id, value });
        }
        let t = self.state.t;
        let track = &mut self.dynamics.tracks[k];
        if track.value.to_bits() == value.to_bits() && track.t_ref == t {
            return Ok(());
        }
        if id == InputId::VD {
            self.dynamics.x_kin_ref += track.integral(t);
        }
        track.t_ref = t;
        track.value = value;
        if id == InputId::FN {
            self.update_lifted();
        }
        self.state.restart();
        Ok(())
    }

    fn set_input_derivative(&mut self, id: InputId, value: f64) -> Result<(), SimError> {
        let k = self.track_index(id)?;
        if !(value.is_finite() && value.abs() <= MAX_INPUT_RATE) {
            return Err(SimError::InputDerivative { id, value });
        }
        let t = self.state.t;
        let track = &mut self.dynamics.tracks[k];
        if id == InputId::VD {
            self.dynamics.x_kin_ref += track.integral(t);
        }
        track.value = track.at(t);
        track.t_ref = t;
        track.slope = value;
        if id == InputId::FN {
            self.update_lifted();
        }
        self.state.restart();
        Ok(())
    }

    fn inputs(&self) -> Inputs {
        let mut i = Inputs::default();
        for (k, id) in InputId::ALL.iter().enumerate() {
            *id.slot(&mut i) = self.dynamics.tracks[k].value;
        }
        i
    }

    fn step_to(&mut self, t_end: f64) -> Result<(), SimError> {
        let now = self.t_abs;
        let t0 = self.state.t;
        // In the contact's own time, counted from its start (the subtraction is exact where the
        // importer's times lie near the start or far above it), taken as the short decimal the
        // importer meant where it is one.
        let requested = t_end - self.epoch;
        let t_end = match canonical_time(requested) {
            c if c > t0 => c,
            _ => requested,
        };
        if !(requested.is_finite() && requested > t0 && t_end > t0) {
            return Err(SimError::Time {
                now,
                target: t_end + self.epoch,
            });
        }
        let t_end_abs = self.epoch + t_end;
        // How close to a window boundary a communication point counts as on it: the importer's
        // rounding, relative to the time it counts in.
        let snap = boundary_snap(t_end, t_end_abs, self.window.len);
        let saved = (
            self.state,
            self.window,
            self.paths.save(),
            self.step,
            self.dynamics.lifted,
        );
        let f_start = self.eval_now().f;
        self.step.acc = [0.0; MAX_QUAD];
        let h_max = self.h_max();
        // The work limit: integrator attempts in this call, on every path.
        let max_steps = self.params.max_steps;
        let work = |s: &SolverStats| s.steps + s.rejected;
        let work_start = work(&self.state.stats);
        let limit = work_start.saturating_add(max_steps as u64);
        self.state.step_limit = limit;
        let over_limit = |t: f64| {
            SimError::Solver(SolverError::WorkLimit {
                t,
                limit: max_steps,
            })
        };
        // A step over more windows than their index counts exactly is beyond any work limit.
        if (t_end - t0) / self.window.len > WINDOWS_MAX {
            return Err(over_limit(t0));
        }
        let result = self.windows_to(t_end, snap, h_max, limit);
        // fmi2OK never comes with a non-finite output.
        let result = result.and_then(|_| {
            let o = self.outputs();
            if OutputId::ALL.iter().all(|id| id.get(&o).is_finite()) {
                Ok(())
            } else {
                Err(SimError::Solver(SolverError::NonFinite { t: self.state.t }))
            }
        });
        self.state.step_limit = u64::MAX;
        if let Err(e) = result {
            // Leave the simulator as it was before the call.
            let e = match e {
                SimError::Solver(SolverError::WorkLimit { t, .. }) => over_limit(t),
                e => e,
            };
            let kept;
            (
                self.state,
                self.window,
                kept,
                self.step,
                self.dynamics.lifted,
            ) = saved;
            self.paths.restore(kept);
            return Err(e);
        }
        self.t_abs = t_end_abs;
        let h = self.state.t - t0;
        self.step.last = Some(self.step.acc.map(|a| a / h));
        self.step.h = h;
        self.step.f_start = [f_start.x(), f_start.y()];
        self.hold_inputs();
        Ok(())
    }

    fn outputs(&self) -> Outputs {
        let e = self.eval_now();
        let body = &self.state.y.as_slice()[V::DIM..];
        let pos = self.dynamics.drive.position(body, &e.drive);
        let f_mean = self.f_mean();
        let f_c = self.dynamics.f_c_at(self.state.t);
        let f_d = match self.config.drive {
            Drive::Velocity => e.f.x(),
            _ => self.dynamics.drive.drive_force(body, &e.drive),
        };
        let step_mean = self.step.last.unwrap_or([e.f.x(), e.f.y()]);
        Outputs {
            f_fx: e.f.x(),
            f_fy: e.f.y(),
            f_fx_step: step_mean[0],
            f_fy_step: step_mean[1],
            x: pos.x(),
            y: pos.y(),
            v_x: e.v.x(),
            v_y: e.v.y(),
            s_x: e.s.x(),
            s_y: e.s.y(),
            f_mean,
            reduction: reduction(f_mean, f_c, self.params.k_t),
            p_diss: self
                .dynamics
                .law_at(self.state.t)
                .dissipation(e.s, e.vr, e.ds),
            f_d,
        }
    }

    /// Exact first time derivatives: the body's position and velocity (its acceleration from the
    /// forces on it, or the input derivative of an imposed `v_d`), the deformation (the law's
    /// rate), and the step means as moving means over the last step's length `h`,
    /// `d/dt (1/h)∫_{t−h}^t F dτ = (F(t) − F(t − h))/h`. None for the rest: window means and
    /// forces whose rate would need the second derivative of the deformation.
    fn output_derivative(&self, id: OutputId) -> Option<f64> {
        let e = self.eval_now();
        let body = &self.state.y.as_slice()[V::DIM..];
        let a_d = self.dynamics.tracks[InputId::VD.index()].slope;
        match id {
            OutputId::X => Some(e.v.x()),
            OutputId::Y => Some(e.v.y()),
            OutputId::Vx => Some(
                self.dynamics
                    .drive
                    .acceleration(body, e.f, &e.drive, a_d)
                    .x(),
            ),
            OutputId::Vy => Some(
                self.dynamics
                    .drive
                    .acceleration(body, e.f, &e.drive, a_d)
                    .y(),
            ),
            OutputId::Sx => Some(e.ds.x()),
            OutputId::Sy => Some(e.ds.y()),
            OutputId::FFxStep | OutputId::FFyStep if self.step.last.is_some() => {
                let k = (id == OutputId::FFyStep) as usize;
                let now = [e.f.x(), e.f.y()][k];
                Some((now - self.step.f_start[k]) / self.step.h)
            }
            _ => None,
        }
    }

    fn stats(&self) -> StepStats {
        self.state.stats.into()
    }

    fn integrator(&self) -> Integrator {
        self.path()
    }

    fn snapshot(&self) -> ContactState {
        self.save()
    }

    fn restore(&mut self, state: &ContactState) -> Result<(), SimError> {
        *self = self.load(state, false)?;
        Ok(())
    }

    fn clone_box(&self) -> Box<dyn Simulator> {
        Box::new(self.clone())
    }

    fn ode(&self) -> Box<dyn Ode> {
        Box::new(ContactOde::<V, L, D, N> {
            dynamics: self.dynamics,
            input_support: self.config.input_support,
            y: self.state.y.into(),
            scale: self.scale,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::drive::{Force, Spring, VelocityFree, VelocityGuided};
    use crate::model::{Drive, Lateral, Law, Motion};
    use crate::physics::{Dahl, Dupont, LuGre, Planar};
    use nalgebra::SMatrix;

    /// The closed-form Jacobian against central differences at states spread over the regimes
    /// of each law (pre-sliding, the Dupont transition, sliding near |s| = s_ss, both signs of
    /// v_r), for every law, motion and drive.
    fn check<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(c: Config, p: Params) {
        let mut contact = Contact::<V, L, D, N>::new(c, p, 0.0, 1e-6);
        contact.dynamics.tracks[InputId::FD.index()].value = 3.0; // F_d
        contact.dynamics.tracks[InputId::VD.index()].value = 1.2e-3; // v_d
        contact.dynamics.tracks[InputId::VSx.index()].value = 2e-4; // v_sx
        contact.dynamics.tracks[InputId::VSy.index()].value = -3e-4; // v_sy
        let sys = contact.system();
        let s_ss = p.f_c() / p.k_t;
        for (k, frac) in [0.1, 0.62, 0.8, 0.97, -0.7].into_iter().enumerate() {
            let t = 1.3e-4 * (k as f64 + 1.0);
            let mut y = SVector::<f64, N>::zeros();
            y[0] = frac * s_ss;
            if V::DIM == 2 {
                y[1] = 0.3 * frac * s_ss;
            }
            for i in V::DIM..N {
                // positions ~ µm, velocities ~ mm/s, with both signs
                y[i] = if i % 2 == 0 { 1e-6 } else { -2e-3 } * (1.0 + 0.1 * i as f64);
            }
            let jac = OdeSystem::<N>::jacobian(&sys, t, &y).unwrap();
            let scale = OdeSystem::<N>::scale(&sys);
            for j in 0..N {
                let h = 1e-7 * scale[j];
                let (mut yp, mut ym) = (y, y);
                yp[j] += h;
                ym[j] -= h;
                let fd = (OdeSystem::<N>::rhs(&sys, t, &yp) - OdeSystem::<N>::rhs(&sys, t, &ym))
                    / (2.0 * h);
                for i in 0..N {
                    let tol = 1e-5 * (fd[i].abs() + jac[(i, j)].abs()) + 1e-9 * scale_of(&jac, i);
                    assert!(
                        (jac[(i, j)] - fd[i]).abs() <= tol,
                        "{c:?} state {k}: J[{i}][{j}] = {} vs difference {}",
                        jac[(i, j)],
                        fd[i]
                    );
                }
            }
        }
    }

    fn scale_of<const N: usize>(jac: &SMatrix<f64, N, N>, row: usize) -> f64 {
        (0..N).map(|j| jac[(row, j)].abs()).fold(0.0, f64::max)
    }

    #[test]
    fn closed_form_jacobian_matches_finite_differences() {
        let mut p = Params {
            h_v: 20.0,
            ..Params::default()
        };
        for law in [Law::Dahl, Law::Dupont, Law::LuGre] {
            macro_rules! run {
                ($v:ty, $d:ty, $n:literal, $motion:expr, $drive:expr, $lateral:expr) => {{
                    let c = Config {
                        law,
                        motion: $motion,
                        drive: $drive,
                        lateral: $lateral,
                        harmonic: true,
                        input_support: true,
                        normal_input: false,
                    };
                    match law {
                        Law::Dahl => check::<$v, Dahl, $d, $n>(c, p),
                        Law::Dupont => check::<$v, Dupont, $d, $n>(c, p),
                        Law::LuGre => check::<$v, LuGre, $d, $n>(c, p),
                    }
                }};
            }
            use Motion::{Longitudinal as L1, Planar as P2};
            run!(f64, VelocityGuided, 1, L1, Drive::Velocity, Lateral::Guided);
            run!(f64, Force, 3, L1, Drive::Force, Lateral::Guided);
            run!(f64, Spring, 3, L1, Drive::Spring, Lateral::Guided);
            run!(
                Planar,
                VelocityGuided,
                2,
                P2,
                Drive::Velocity,
                Lateral::Guided
            );
            run!(Planar, VelocityFree, 4, P2, Drive::Velocity, Lateral::Free);
            run!(Planar, Force, 6, P2, Drive::Force, Lateral::Guided);
            run!(Planar, Spring, 6, P2, Drive::Spring, Lateral::Guided);
        }
        // Dahl with an exponent (longitudinal only).
        p.kappa = 2.0;
        let c = Config {
            law: Law::Dahl,
            motion: Motion::Longitudinal,
            drive: Drive::Force,
            lateral: Lateral::Guided,
            harmonic: true,
            input_support: true,
            normal_input: false,
        };
        check::<f64, Dahl, Force, 3>(c, p);
    }
}
