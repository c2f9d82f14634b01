//! The contact for an importer's own integrator (Model Exchange): its continuous states and
//! their derivatives, event indicators with a hysteresis band, the event update, and the
//! closed-form directional derivatives.
//!
//! The states are those of [`StateId`] (`src/table/states.rs`): the Co-Simulation solver's
//! `[s | body]`, the position the inputs impose (`x` under velocity drive, the spring's far end
//! `x_d`) and `∫F_Fx dt` over the averaging window in progress. The derivatives are the same
//! right-hand side the Co-Simulation solver integrates (`dynamics.rs`).
//!
//! Events, as the Co-Simulation solver has them:
//! - the switching functions `v_rx` (and `s·v_r` in planar Dupont), whose sign changes are
//!   kinks of the right-hand side. An indicator is `g + side·band`, with `side` the sign of `g`
//!   since the last event and `band = tol·scale`: it changes sign only when `g` has crossed
//!   the band, so a stuck contact hovering at `v_r = 0` gives no train of events, exactly as
//!   the Co-Simulation solver ignores sign changes within the band;
//! - the normal force input crossing the lift-off load (`F_N − F_lift`), at which the body
//!   leaves the support (its deformation is cleared) or lands;
//! - time events at the ends of the averaging windows, where `F_mean` takes `F_int/window`
//!   and `F_int` restarts from 0.

use super::contact::Contact;
use super::drive::{DriveInputs, DriveKind};
use super::simulator::{EventUpdate, Exchange, SimError, StateVector};
use super::time::{TIME_SNAP, WINDOWS_MAX};
use crate::physics::{FrictionLaw, LawJacobian, Vector};
use crate::solver::OdeSystem;
use crate::table::{Drive, InputId, Inputs, Outputs, StateId};

/// How far beyond the law's bound on the deformation (`FrictionLaw::envelope`) a state set by
/// an importer may lie before it is out of the model's domain: no trajectory leaves the bound,
/// an integrator's trial step overshoots it by far less, and an unstable integration passes
/// it within a few steps.
pub const DOMAIN_FACTOR: f64 = 1e3;

/// Where a state lives in the contact.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    /// Component of the integrated state `[s | body]`.
    Y(usize),
    /// The imposed position (`x` of a velocity drive, `x_d` of a spring).
    Imposed,
    /// `∫F_Fx dt` of the window in progress.
    Window,
}

/// `m·v` for a 2×2 matrix of the law's partial derivatives.
fn mul<V: Vector>(m: &[[f64; 2]; 2], v: V) -> V {
    V::from_xy(
        m[0][0] * v.x() + m[0][1] * v.y(),
        m[1][0] * v.x() + m[1][1] * v.y(),
    )
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Contact<V, L, D, N> {
    fn slot(&self, id: StateId) -> Option<Slot> {
        let d = V::DIM;
        let planar = d == 2;
        let drive = self.config.drive;
        match id {
            StateId::Sx => Some(Slot::Y(0)),
            StateId::Sy => planar.then_some(Slot::Y(1)),
            StateId::Window => Some(Slot::Window),
            StateId::Xd => drive.has_spring().then_some(Slot::Imposed),
            _ if drive.imposes_velocity() => match id {
                StateId::X => Some(Slot::Imposed),
                StateId::Y if D::N_BODY == 2 => Some(Slot::Y(d)),
                StateId::Vy if D::N_BODY == 2 => Some(Slot::Y(d + 1)),
                _ => None,
            },
            StateId::X => Some(Slot::Y(d)),
            StateId::Vx => Some(Slot::Y(2 * d)),
            StateId::Y => planar.then_some(Slot::Y(d + 1)),
            StateId::Vy => planar.then_some(Slot::Y(2 * d + 1)),
        }
    }

    /// The imposed position now: the integral of the held `v_d` from its reference.
    fn imposed(&self) -> f64 {
        self.dynamics.x_kin_ref + self.dynamics.tracks[InputId::VD.index()].integral(self.state.t)
    }

    /// Half-width of the hysteresis band of switching function `k`.
    fn band(&self, k: usize) -> f64 {
        self.state.tolerance() * self.switch_scale[k]
    }

    fn n_switch(&self) -> usize {
        OdeSystem::<N>::n_switch(&self.system())
    }
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Exchange for Contact<V, L, D, N> {
    fn states(&self) -> StateVector {
        let mut x = [0.0; StateId::COUNT];
        for id in StateId::ALL {
            x[id.index()] = match self.slot(id) {
                Some(Slot::Y(i)) => self.state.y[i],
                Some(Slot::Imposed) => self.imposed(),
                Some(Slot::Window) => self.window.acc,
                None => 0.0,
            };
        }
        x
    }

    fn set_states(&mut self, x: &StateVector) -> Result<(), SimError> {
        for id in StateId::ALL {
            let value = x[id.index()];
            if self.slot(id).is_some() && !value.is_finite() {
                return Err(SimError::State {
                    name: id.name(),
                    value,
                });
            }
        }
        let t = self.state.t;
        for id in StateId::ALL {
            let value = x[id.index()];
            match self.slot(id) {
                Some(Slot::Y(i)) => self.state.y[i] = value,
                Some(Slot::Imposed) => {
                    let vd = &mut self.dynamics.tracks[InputId::VD.index()];
                    vd.value = vd.at(t);
                    vd.t_ref = t;
                    self.dynamics.x_kin_ref = value;
                }
                Some(Slot::Window) => self.window.acc = value,
                None => {}
            }
        }
        Ok(())
    }

    fn derivatives(&self) -> StateVector {
        let t = self.state.t;
        let sys = self.system();
        let y = self.state.y.as_slice();
        let e = sys.eval(t, y);
        let dy = sys.rhs_at::<N>(&e, y);
        let mut dx = [0.0; StateId::COUNT];
        for id in StateId::ALL {
            dx[id.index()] = match self.slot(id) {
                Some(Slot::Y(i)) => dy[i],
                Some(Slot::Imposed) => e.drive.v_d,
                Some(Slot::Window) => e.f.x(),
                None => 0.0,
            };
        }
        dx
    }

    fn nominals(&self) -> StateVector {
        let mut n = [1.0; StateId::COUNT];
        let x_nom = self.scale[0].max(self.params.u0 * self.config.harmonic as u8 as f64);
        for id in StateId::ALL {
            n[id.index()] = match self.slot(id) {
                Some(Slot::Y(i)) => self.scale[i],
                Some(Slot::Imposed) => x_nom,
                Some(Slot::Window) => self.force_scale * self.window.len,
                None => 1.0,
            };
        }
        n
    }

    fn out_of_domain(&self) -> Option<String> {
        let y = self.state.y.as_slice();
        let s = (0..V::DIM).map(|i| y[i] * y[i]).sum::<f64>().sqrt();
        // The largest deformation the law holds at the current load, or at the parameters'
        // (which a falling normal force input leaves behind until the contact slips).
        let envelope =
            (self.dynamics.law_at(self.state.t).envelope()).max(self.dynamics.law.envelope());
        let limit = DOMAIN_FACTOR * envelope;
        (s > limit || !s.is_finite()).then(|| {
            let names = if V::DIM == 2 { "(s_x, s_y)" } else { "s_x" };
            let values = (0..V::DIM)
                .map(|i| format!("{:e}", y[i]))
                .collect::<Vec<_>>()
                .join(", ");
            format!(
                "the states set give the deformation {names} = {values} m, |s| = {s:e} m, more than {DOMAIN_FACTOR:e} times the largest any trajectory reaches ({envelope:e} m, the law's bound at the current and the parameters' normal force)"
            )
        })
    }

    fn restore_exchange(&mut self, state: &super::state::ContactState) -> Result<(), SimError> {
        *self = self.load(state, true)?;
        Ok(())
    }

    fn set_time(&mut self, t: f64) -> Result<(), SimError> {
        let local = t - self.epoch;
        // Within the averaging windows whose index stays exact (as a Co-Simulation step).
        let windows = (local - self.window.origin).abs() / self.window.len;
        if !(local.is_finite() && windows <= WINDOWS_MAX) {
            return Err(SimError::Time {
                now: self.t_abs,
                target: t,
            });
        }
        // The states stay as the importer set them, whatever the order of its calls: the
        // imposed position keeps its value (the importer integrates it), the held inputs theirs.
        let x_imposed = self.imposed();
        for track in &mut self.dynamics.tracks {
            track.value = track.at(self.state.t);
            track.t_ref = local;
        }
        self.dynamics.x_kin_ref = x_imposed;
        self.state.t = local;
        self.t_abs = t;
        Ok(())
    }

    fn set_input_continuous(&mut self, id: InputId, value: f64) -> Result<(), SimError> {
        if !id.present(&self.config) {
            return Err(SimError::NoSuchInput(id.name()));
        }
        if !id.rule().holds(value) {
            return Err(SimError::Input { id, value });
        }
        let t = self.state.t;
        let track = &mut self.dynamics.tracks[id.index()];
        if id == InputId::VD {
            self.dynamics.x_kin_ref += track.integral(t);
        }
        track.t_ref = t;
        track.value = value;
        track.slope = 0.0;
        Ok(())
    }

    fn event_indicators(&self, z: &mut [f64]) {
        let t = self.state.t;
        let g = OdeSystem::<N>::switch(&self.system(), t, &self.state.y);
        let n = self.n_switch();
        for (k, (zk, gk)) in z.iter_mut().zip(g).take(n).enumerate() {
            *zk = gk + self.sides[k] * self.band(k);
        }
        if self.dynamics.load.is_some() {
            z[n] = self.dynamics.tracks[InputId::FN.index()].at(t) - self.dynamics.lift_off;
        }
    }

    fn update_events(&mut self) -> EventUpdate {
        let t = self.state.t;
        let mut changed = false;
        // Windows that have ended (the importer stops at each end: one, unless it overstepped).
        let end = self.window.end();
        if t >= end - TIME_SNAP * end.abs().max(self.window.len) {
            let elapsed = (t - self.window.start()).max(self.window.len);
            let n = ((t - self.window.origin) / self.window.len + TIME_SNAP).floor() as u64;
            self.window.last = Some(self.window.acc / elapsed);
            self.window.acc = 0.0;
            self.window.index = n.max(self.window.index + 1);
            changed = true;
        }
        // The sides of the switching functions: a function that left the band (or has no side
        // yet) takes the side it is on.
        let g = OdeSystem::<N>::switch(&self.system(), t, &self.state.y);
        for (k, &gk) in g.iter().enumerate().take(self.n_switch()) {
            if self.sides[k] == 0.0 || gk * self.sides[k] < -self.band(k) {
                self.sides[k] = if gk < 0.0 { -1.0 } else { 1.0 };
            }
        }
        // Lift-off and landing.
        if self.dynamics.load.is_some() {
            let off = self.dynamics.off_at(t);
            if off != self.dynamics.lifted {
                self.dynamics.lifted = off;
                if off {
                    let y = self.state.y.as_mut_slice();
                    changed |= y[..V::DIM].iter().any(|s| *s != 0.0);
                    y[..V::DIM].fill(0.0);
                }
            }
        }
        EventUpdate {
            states_changed: changed,
            next_time: (self.window.len.is_finite() && self.window.len > 0.0)
                .then(|| self.epoch + self.window.end()),
        }
    }

    fn tangent(&self, dx: &StateVector, du: &Inputs) -> (StateVector, Outputs) {
        let t = self.state.t;
        let sys = self.system();
        let y = self.state.y.as_slice();
        let e = sys.eval(t, y);
        let law = self.dynamics.law_at(t);
        let lj: LawJacobian = law.jacobian(e.s, e.vr, e.ds);
        // The direction in the integrated state and the drive's inputs.
        let mut dy = [0.0; 8];
        let mut d_imposed = 0.0;
        for id in StateId::ALL {
            match self.slot(id) {
                Some(Slot::Y(i)) => dy[i] = dx[id.index()],
                Some(Slot::Imposed) => d_imposed = dx[id.index()],
                _ => {}
            }
        }
        let ds_dir = V::read(&dy);
        let dbody = &dy[V::DIM..N];
        let dd = DriveInputs {
            f_d: du.f_d,
            v_d: du.v_d,
            x_kin: d_imposed,
        };
        // Everything below is linear in the direction: the drive's velocity, position, force
        // and body rates are linear homogeneous in (body, inputs), so they map the direction.
        let dv = self.dynamics.drive.velocity(dbody, &dd);
        let dvs = if self.config.input_support {
            V::from_xy(du.v_sx, du.v_sy)
        } else {
            V::default()
        };
        let dvr = dv - dvs;
        let mut d_rate = mul(&lj.rate_s, ds_dir) + mul(&lj.rate_v, dvr);
        let mut d_force = mul(&lj.force_s, ds_dir) + mul(&lj.force_v, dvr);
        // The normal force input: every friction force scales with the load (`dynamics.rs`,
        // `loaded`), so rate(s, v_r; F_N) = G(s/F_N, v_r) and F − h_v·v_r is homogeneous of
        // degree 1 in (s, F_N); Euler's relation gives the partial derivatives.
        let f_n = self.dynamics.load_at(t);
        let mut d_fc = 0.0;
        if self.dynamics.load.is_some() && f_n > 0.0 {
            let k = du.f_n / f_n;
            d_rate = d_rate - mul(&lj.rate_s, e.s) * k;
            d_force = d_force + (e.f - e.vr * law.viscous() - mul(&lj.force_s, e.s)) * k;
            d_fc = self.dynamics.f_c_at(t) * k;
        }
        let mut d_body = [0.0; 8];
        self.dynamics
            .drive
            .body_rate(dbody, d_force, &dd, &mut d_body[..D::N_BODY]);
        let mut dder = [0.0; StateId::COUNT];
        for id in StateId::ALL {
            dder[id.index()] = match self.slot(id) {
                Some(Slot::Y(i)) if i < V::DIM => [d_rate.x(), d_rate.y()][i],
                Some(Slot::Y(i)) => d_body[i - V::DIM],
                Some(Slot::Imposed) => du.v_d,
                Some(Slot::Window) => d_force.x(),
                None => 0.0,
            };
        }
        // The outputs (`contact.rs`, `outputs`), differentiated.
        let dpos = self.dynamics.drive.position(dbody, &dd);
        let elapsed = t - self.window.start();
        let f_mean = self.f_mean();
        let d_mean = match self.window.last {
            Some(_) => 0.0,
            None if elapsed > 0.0 => dx[StateId::Window.index()] / elapsed,
            None => d_force.x(),
        };
        let f_c = self.dynamics.f_c_at(t);
        // `reduction` (`contact.rs`), differentiated where it is 1 − F_mean/F_C.
        let d_reduction = if f_c / self.params.k_t <= crate::physics::NO_FRICTION_LENGTH {
            0.0
        } else if f_c * f_c >= f64::MIN_POSITIVE {
            -d_mean / f_c + f_mean * d_fc / (f_c * f_c)
        } else {
            // F_C² underflows: the same derivative without squaring F_C.
            (-d_mean + f_mean / f_c * d_fc) / f_c
        };
        // P_diss = F_F·v_r − k_t·s·ds/dt under every law (`physics/law.rs`, `dissipation`).
        let k_t = self.params.k_t;
        let d_diss = d_force.dot(e.vr) + e.f.dot(dvr) - k_t * (ds_dir.dot(e.ds) + e.s.dot(d_rate));
        let d_drive = match self.config.drive {
            Drive::Velocity => d_force.x(),
            _ => self.dynamics.drive.drive_force(dbody, &dd),
        };
        let outputs = Outputs {
            f_fx: d_force.x(),
            f_fy: d_force.y(),
            f_fx_step: d_force.x(),
            f_fy_step: d_force.y(),
            x: dpos.x(),
            y: dpos.y(),
            v_x: dv.x(),
            v_y: dv.y(),
            s_x: ds_dir.x(),
            s_y: ds_dir.y(),
            f_mean: d_mean,
            reduction: d_reduction,
            p_diss: d_diss,
            f_d: d_drive,
        };
        (dder, outputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{build, Lateral, Law, Motion, Simulator};
    use crate::table::Params;
    use crate::table::{Config, Known, OutputId};

    fn configs() -> Vec<Config> {
        let mut v = vec![];
        for law in Law::ALL {
            for motion in Motion::ALL {
                for drive in Drive::ALL {
                    for lateral in [Lateral::Guided, Lateral::Free] {
                        if lateral == Lateral::Free
                            && (motion == Motion::Longitudinal || drive != Drive::Velocity)
                        {
                            continue;
                        }
                        for normal_input in [false, true] {
                            v.push(Config {
                                law,
                                motion,
                                drive,
                                lateral,
                                harmonic: true,
                                input_support: true,
                                normal_input,
                            });
                        }
                    }
                }
            }
        }
        v
    }

    /// A contact at time `t` with inputs away from zero and the states at fraction `frac` of
    /// the deformation's bound, body moving.
    fn contact(c: Config, frac: f64, t: f64) -> Box<dyn Simulator> {
        let p = Params {
            h_v: 20.0,
            ..Params::default()
        };
        let mut sim = build(c, p, 0.0, 1e-6).unwrap();
        sim.set_time(t).unwrap();
        for (id, value) in [
            (InputId::FD, 3.0),
            (InputId::VD, 1.2e-3),
            (InputId::VSx, 2e-4),
            (InputId::VSy, -3e-4),
            (InputId::FN, 40.0),
        ] {
            if id.present(&c) {
                sim.set_input_continuous(id, value).unwrap();
            }
        }
        let s_ss = p.f_c() * 40.0 / 55.0 / p.k_t;
        let mut x = sim.states();
        x[StateId::Sx.index()] = frac * s_ss;
        x[StateId::Sy.index()] = 0.3 * frac * s_ss;
        x[StateId::X.index()] = 1.3e-6;
        x[StateId::Y.index()] = -0.4e-6;
        x[StateId::Vx.index()] = -2e-3;
        x[StateId::Vy.index()] = 1.1e-3 * frac;
        x[StateId::Xd.index()] = 2.1e-6;
        x[StateId::Window.index()] = 1e-4;
        sim.set_states(&x).unwrap();
        sim
    }

    fn outputs_of(sim: &dyn Simulator) -> [f64; OutputId::ALL.len()] {
        let o = sim.outputs();
        OutputId::ALL.map(|id| id.get(&o))
    }

    /// The closed-form directional derivatives against central differences, along every state
    /// and every input, for every law, motion, drive and load, in the regimes of each law.
    #[test]
    fn directional_derivatives_match_central_differences() {
        let inputs_step = [1e-4, 1e-8, 1e-8, 1e-8, 1e-4]; // F_d, v_d, v_sx, v_sy, F_N
        for c in configs() {
            let outputs: Vec<OutputId> = OutputId::ALL.to_vec();
            for (k, frac) in [0.1, 0.62, 0.8, 0.97, -0.7].into_iter().enumerate() {
                let t = 1.3e-4 * (k as f64 + 1.0);
                let sim = contact(c, frac, t);
                let nominal = sim.nominals();
                let mut directions: Vec<(String, StateVector, Inputs, f64)> = vec![];
                for id in StateId::ALL.into_iter().filter(|s| s.present(&c, &outputs)) {
                    let mut dx = [0.0; StateId::COUNT];
                    dx[id.index()] = 1.0;
                    let h = 1e-6 * nominal[id.index()].max(1e-7);
                    directions.push((id.name().into(), dx, Inputs::default(), h));
                }
                for (n, id) in InputId::ALL.into_iter().enumerate() {
                    if id.present(&c) {
                        let mut du = Inputs::default();
                        *id.slot(&mut du) = 1.0;
                        directions.push((
                            id.name().into(),
                            [0.0; StateId::COUNT],
                            du,
                            inputs_step[n],
                        ));
                    }
                }
                for (name, dx, du, h) in directions {
                    let (dder, dout) = sim.tangent(&dx, &du);
                    let shifted = |sign: f64| {
                        let mut s = sim.clone_box();
                        let mut x = s.states();
                        for i in 0..StateId::COUNT {
                            x[i] += sign * h * dx[i];
                        }
                        s.set_states(&x).unwrap();
                        for id in InputId::ALL.into_iter().filter(|i| i.present(&c)) {
                            let v = id.get(&s.inputs()) + sign * h * id.get(&du);
                            s.set_input_continuous(id, v).unwrap();
                        }
                        (s.derivatives(), outputs_of(s.as_ref()))
                    };
                    let ((dp, op), (dm, om)) = (shifted(1.0), shifted(-1.0));
                    let close = |what: &str, exact: f64, plus: f64, minus: f64| {
                        let fd = (plus - minus) / (2.0 * h);
                        let tol = 1e-5 * (fd.abs() + exact.abs())
                            + 1e-9 * plus.abs().max(minus.abs()) / h;
                        assert!(
                            (exact - fd).abs() <= tol,
                            "{c:?} frac {frac}: d {what} / d {name} = {exact} vs difference {fd}"
                        );
                    };
                    for id in StateId::ALL.into_iter().filter(|s| s.present(&c, &outputs)) {
                        let i = id.index();
                        close(id.derivative_name(), dder[i], dp[i], dm[i]);
                    }
                    for (j, id) in OutputId::ALL.into_iter().enumerate() {
                        if id.present(&c) {
                            close(id.name(), id.get(&dout), op[j], om[j]);
                        }
                    }
                }
            }
        }
    }

    /// The states are the importer's: setting the time before or after the states gives the
    /// same states and derivatives (fmpy sets the time first, fmi-sim the states).
    #[test]
    fn setting_time_and_states_in_either_order_is_the_same() {
        for c in configs() {
            let base = contact(c, 0.62, 1.3e-4);
            let mut x = base.states();
            for v in x.iter_mut() {
                *v = *v * 1.01 + 1e-9;
            }
            let mut a = base.clone_box();
            a.set_time(2.9e-4).unwrap();
            a.set_states(&x).unwrap();
            let mut b = base.clone_box();
            b.set_states(&x).unwrap();
            b.set_time(2.9e-4).unwrap();
            assert_eq!(a.states(), b.states(), "{c:?}");
            assert_eq!(a.derivatives(), b.derivatives(), "{c:?}");
            let present = |s: &StateId| s.present(&c, &OutputId::ALL);
            for id in StateId::ALL.into_iter().filter(present) {
                assert_eq!(b.states()[id.index()], x[id.index()], "{c:?} {}", id.name());
            }
        }
    }

    /// `ModelStructure/Derivatives` is exact: a derivative changes along a known exactly when
    /// the table lists the known among its dependencies (over states in every regime).
    #[test]
    fn derivative_dependencies_are_exact() {
        for c in configs() {
            let outputs: Vec<OutputId> = OutputId::ALL.to_vec();
            let present: Vec<StateId> = StateId::ALL
                .into_iter()
                .filter(|s| s.present(&c, &outputs))
                .collect();
            let mut knowns: Vec<Known> = present.iter().map(|s| Known::State(*s)).collect();
            knowns.extend(
                InputId::ALL
                    .into_iter()
                    .filter(|i| i.present(&c))
                    .map(Known::Input),
            );
            for der in &present {
                let declared = der.derivative_dependencies(&c, &outputs);
                for known in &knowns {
                    let mut seen = false;
                    for (k, frac) in [0.1, 0.62, 0.8, 0.97, -0.7].into_iter().enumerate() {
                        let sim = contact(c, frac, 1.3e-4 * (k as f64 + 1.0));
                        let mut dx = [0.0; StateId::COUNT];
                        let mut du = Inputs::default();
                        match known {
                            Known::State(s) => dx[s.index()] = 1.0,
                            Known::Input(i) => *i.slot(&mut du) = 1.0,
                        }
                        seen |= sim.tangent(&dx, &du).0[der.index()] != 0.0;
                    }
                    assert_eq!(
                        seen,
                        declared.contains(known),
                        "{c:?}: {} on {known:?} (declared {declared:?})",
                        der.derivative_name()
                    );
                }
            }
        }
    }
}
