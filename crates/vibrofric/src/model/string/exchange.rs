//! A string for an importer's own integrator (Model Exchange): its continuous states and their
//! derivatives, an event indicator per section, the event update and the exact directional
//! derivatives.
//!
//! The state vector is `[x_1 … x_N, v_1 … v_N, s_1 … s_N, x_top, x_bottom]`: every section's
//! position, velocity and deformation (the Co-Simulation integrator's state, there interleaved
//! per section), and the two points the end elements hold, which Co-Simulation integrates in
//! closed form from the held velocities and an importer integrates here (its inputs change
//! between its own steps, as the single contact's imposed position). The derivatives are the
//! right-hand side the band Radau integrates ([`BandSystem::rhs`]), the directional derivatives
//! its banded Jacobian ([`BandSystem::jacobian`]) with the ends' points and the inputs added.
//!
//! Events, as the single contact's: section `i`'s indicator is `v_r[i] + side·band`, `v_r` the
//! kink of `|v_r|` in its law, `side` its sign since the last event and `band = tol·v_nom` its
//! velocity's natural scale: a section stuck at `v_r = 0` gives no train of events. The step
//! means are the instantaneous forces (an importer's integrator has no communication steps).

use super::equations::PER_SECTION;
use super::{StringOutputs, StringSim};
use crate::model::exchange::DOMAIN_FACTOR;
use crate::model::simulator::SimError;
use crate::physics::{FrictionLaw, InputTrack};
use crate::solver::band::{Band, BandSystem};
use crate::table::number;

/// A direction in a string's inputs: per section the drive force, the support velocity and the
/// normal force (empty where it is a parameter), and the ends' velocities.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InputDirection {
    pub f_d: Vec<f64>,
    pub v_sx: Vec<f64>,
    pub f_n: Vec<f64>,
    pub v_top: f64,
    pub v_bottom: f64,
}

impl InputDirection {
    /// No change in any input of a string of `n` sections.
    pub fn zero(n: usize, normal_input: bool) -> Self {
        InputDirection {
            f_d: vec![0.0; n],
            v_sx: vec![0.0; n],
            f_n: vec![0.0; if normal_input { n } else { 0 }],
            v_top: 0.0,
            v_bottom: 0.0,
        }
    }
}

/// The Model Exchange side of a string; see the module's documentation for the state vector.
pub trait StringExchange {
    /// From now on the step means are the instantaneous forces (a Model Exchange instance).
    fn set_exchange(&mut self);
    fn exchange_states(&self) -> Vec<f64>;
    /// Sets the continuous states (`3N + 2` of them); every value is checked before any is
    /// written.
    fn set_exchange_states(&mut self, x: &[f64]) -> Result<(), SimError>;
    /// The time of the continuous states; the states keep their values, the inputs are held.
    fn set_exchange_time(&mut self, t: f64) -> Result<(), SimError>;
    fn exchange_derivatives(&self) -> Vec<f64>;
    fn exchange_nominals(&self) -> Vec<f64>;
    /// One indicator per section.
    fn event_indicators(&self) -> Vec<f64>;
    /// The event update: each indicator that left its band takes its side.
    fn update_events(&mut self);
    /// Why the states set are outside the model's domain, if they are.
    fn out_of_domain(&self) -> Option<String>;
    /// The derivatives' and the outputs' changes along a direction in the states (`dx`, laid
    /// out as the states) and the inputs (`du`).
    fn tangent(&self, dx: &[f64], du: &InputDirection) -> (Vec<f64>, StringOutputs);
}

/// Every input track of a string, mutably.
fn tracks(inp: &mut super::StringInputs) -> impl Iterator<Item = &mut InputTrack> {
    inp.f_d
        .iter_mut()
        .chain(inp.v_sx.iter_mut())
        .chain(inp.f_n.iter_mut())
        .chain([&mut inp.v_top, &mut inp.v_bottom])
}

/// The name of state `k` of a string of `n` sections (`x[3]`, `x_top`).
pub fn state_name(n: usize, k: usize) -> String {
    match k {
        _ if k < n => format!("x[{}]", k + 1),
        _ if k < 2 * n => format!("v_x[{}]", k - n + 1),
        _ if k < 3 * n => format!("s_x[{}]", k - 2 * n + 1),
        _ if k == 3 * n => "x_top".into(),
        _ => "x_bottom".into(),
    }
}

impl<L: FrictionLaw> StringSim<L> {
    /// Half-width of section `i`'s hysteresis band.
    fn band(&self, i: usize) -> f64 {
        self.radau.tolerance() * self.nominal[PER_SECTION * i + 1]
    }

    /// `v_r` of section `i` now.
    fn slip(&self, i: usize) -> f64 {
        let t = self.radau.t;
        self.radau.y[PER_SECTION * i + 1] - self.model.support(i, t)
    }
}

impl<L: FrictionLaw> StringExchange for StringSim<L> {
    fn set_exchange(&mut self) {
        self.exchange = true;
    }

    fn exchange_states(&self) -> Vec<f64> {
        let n = self.model.n();
        let (t, y) = (self.radau.t, &self.radau.y);
        let mut x: Vec<f64> = (0..PER_SECTION)
            .flat_map(|c| (0..n).map(move |i| y[PER_SECTION * i + c]))
            .collect();
        x.push(self.model.inputs.x_top(t));
        x.push(self.model.inputs.x_bottom(t));
        x
    }

    fn set_exchange_states(&mut self, x: &[f64]) -> Result<(), SimError> {
        let n = self.model.n();
        if x.len() != PER_SECTION * n + 2 {
            return Err(SimError::Inconsistent(format!(
                "{} states given: a string of {n} sections has {}",
                x.len(),
                PER_SECTION * n + 2
            )));
        }
        if let Some((k, v)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(SimError::Inconsistent(format!(
                "{} = {}: a continuous state must be finite",
                state_name(n, k),
                number(*v)
            )));
        }
        for i in 0..n {
            for c in 0..PER_SECTION {
                self.radau.y[PER_SECTION * i + c] = x[c * n + i];
            }
        }
        let t = self.radau.t;
        let inp = &mut self.model.inputs;
        inp.v_top.hold_from(t);
        inp.v_bottom.hold_from(t);
        inp.x_top_ref = x[PER_SECTION * n];
        inp.x_bottom_ref = x[PER_SECTION * n + 1];
        self.radau.restart();
        Ok(())
    }

    fn set_exchange_time(&mut self, t: f64) -> Result<(), SimError> {
        let now = self.radau.t;
        if !t.is_finite() {
            return Err(SimError::Time { now, target: t });
        }
        let inp = &mut self.model.inputs;
        inp.x_top_ref = inp.x_top(now);
        inp.x_bottom_ref = inp.x_bottom(now);
        for tr in tracks(inp) {
            tr.hold_from(now);
            tr.t_ref = t;
        }
        self.radau.t = t;
        self.radau.restart();
        Ok(())
    }

    fn exchange_derivatives(&self) -> Vec<f64> {
        let n = self.model.n();
        let (t, y) = (self.radau.t, &self.radau.y);
        let mut dy = vec![0.0; PER_SECTION * n];
        self.model.rhs(t, y, &mut dy);
        let mut dx: Vec<f64> = (0..PER_SECTION)
            .flat_map(|c| (0..n).map(move |i| (i, c)))
            .map(|(i, c)| dy[PER_SECTION * i + c])
            .collect();
        dx.push(self.model.inputs.v_top.at(t));
        dx.push(self.model.inputs.v_bottom.at(t));
        dx
    }

    fn exchange_nominals(&self) -> Vec<f64> {
        let n = self.model.n();
        let mut x: Vec<f64> = (0..PER_SECTION)
            .flat_map(|c| (0..n).map(move |i| self.nominal[PER_SECTION * i + c]))
            .collect();
        x.push(self.nominal[0]);
        x.push(self.nominal[PER_SECTION * (n - 1)]);
        x
    }

    fn event_indicators(&self) -> Vec<f64> {
        (0..self.model.n())
            .map(|i| self.slip(i) + self.sides[i] * self.band(i))
            .collect()
    }

    fn update_events(&mut self) {
        for i in 0..self.model.n() {
            let (g, band) = (self.slip(i), self.band(i));
            if self.sides[i] == 0.0 || g * self.sides[i] < -band {
                self.sides[i] = if g < 0.0 { -1.0 } else { 1.0 };
            }
        }
    }

    fn out_of_domain(&self) -> Option<String> {
        let t = self.radau.t;
        (0..self.model.n()).find_map(|i| {
            let s = self.radau.y[PER_SECTION * i + 2];
            let sec = &self.model.sections[i];
            let envelope = self.model.law(i, t).envelope().max(sec.law.envelope());
            (s.abs() > DOMAIN_FACTOR * envelope || !s.is_finite()).then(|| {
                format!(
                    "the states set give the deformation s_x[{}] = {s:e} m, more than {DOMAIN_FACTOR:e} times the largest any trajectory reaches ({envelope:e} m, the law's bound at the section's current and start normal force)",
                    i + 1
                )
            })
        })
    }

    fn tangent(&self, dx: &[f64], du: &InputDirection) -> (Vec<f64>, StringOutputs) {
        let m = &self.model;
        let n = m.n();
        let (t, y) = (self.radau.t, &self.radau.y);
        let dim = PER_SECTION * n;
        // The direction in the integrated (interleaved) state, through the banded Jacobian.
        let mut d = vec![0.0; dim];
        for i in 0..n {
            for c in 0..PER_SECTION {
                d[PER_SECTION * i + c] = dx[c * n + i];
            }
        }
        let (kl, ku) = m.bands();
        let mut jac = Band::zeros(dim, kl, ku);
        m.jacobian(t, y, &mut jac);
        let mut dd: Vec<f64> = (0..dim)
            .map(|r| {
                let cols = r.saturating_sub(kl)..(r + ku + 1).min(dim);
                cols.map(|c| jac.get(r, c) * d[c]).sum()
            })
            .collect();
        // The ends' points and velocities.
        let l = &m.links;
        let (d_top, d_bottom) = (dx[dim], dx[dim + 1]);
        let last = PER_SECTION * (n - 1);
        dd[1] += (l.k_top * d_top + l.c_top * du.v_top) * m.sections[0].inv_m;
        dd[last + 1] +=
            (l.k_bottom * d_bottom + l.c_bottom * du.v_bottom) * m.sections[n - 1].inv_m;
        // Each section's inputs, and its friction force along the whole direction.
        let mut d_force = vec![0.0; n];
        for (i, d_force) in d_force.iter_mut().enumerate() {
            let k = PER_SECTION * i;
            let (v, s) = (y[k + 1], y[k + 2]);
            let (law, vr, ds, lj) = m.partials(i, t, v, s);
            let dvs = du.v_sx.get(i).copied().unwrap_or(0.0);
            let (mut d_rate, mut df) = (-lj.rate_v[0][0] * dvs, -lj.force_v[0][0] * dvs);
            // The normal force input: the law scales with the load (rate(s, v_r; F_N) =
            // G(s/F_N, v_r), F − h_v·v_r homogeneous of degree 1 in (s, F_N)), as the single
            // contact's (`model/exchange.rs`).
            if let (Some(track), Some(&dfn)) = (m.inputs.f_n.get(i), du.f_n.get(i)) {
                let f_n = track.at(t);
                if f_n > 0.0 {
                    let q = dfn / f_n;
                    let f = law.force(s, vr, ds);
                    d_rate -= lj.rate_s[0][0] * s * q;
                    df += (f - vr * law.viscous() - lj.force_s[0][0] * s) * q;
                }
            }
            let inv_m = m.sections[i].inv_m;
            dd[k + 1] += (du.f_d.get(i).copied().unwrap_or(0.0) - df) * inv_m;
            dd[k + 2] += d_rate;
            *d_force = df + lj.force_s[0][0] * d[k + 2] + lj.force_v[0][0] * d[k + 1];
        }
        let mut dder: Vec<f64> = (0..PER_SECTION)
            .flat_map(|c| (0..n).map(move |i| (i, c)))
            .map(|(i, c)| dd[PER_SECTION * i + c])
            .collect();
        dder.push(du.v_top);
        dder.push(du.v_bottom);
        let f_top = l.k_top * (d_top - d[0]) + l.c_top * (du.v_top - d[1]);
        let f_bottom = l.k_bottom * (d[last] - d_bottom) + l.c_bottom * (d[last + 1] - du.v_bottom);
        let outputs = StringOutputs {
            x: dx[..n].to_vec(),
            v_x: dx[n..2 * n].to_vec(),
            s_x: dx[2 * n..3 * n].to_vec(),
            f_fx: d_force.clone(),
            f_fx_step: d_force,
            f_link: (0..n.saturating_sub(1)).map(|i| m.link(i, &d)).collect(),
            f_top,
            f_bottom,
            f_top_step: f_top,
            f_bottom_step: f_bottom,
        };
        (dder, outputs)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{build_string, StringConfig, StringInput, StringParams, StringSimulator};
    use super::*;
    use crate::table::{Law, Params};

    const N: usize = 4;

    fn configs() -> Vec<StringConfig> {
        let mut v = vec![];
        for law in Law::ALL {
            for normal_input in [false, true] {
                v.push(StringConfig {
                    law,
                    harmonic: true,
                    normal_input,
                });
            }
        }
        v
    }

    /// The inputs of a string: a push on every section, the wall moving, the ends' points
    /// moving, the load at 40 N where it is an input.
    fn inputs(c: &StringConfig) -> Vec<(StringInput, f64)> {
        let mut u = vec![(StringInput::VTop, 1.2e-3), (StringInput::VBottom, -0.5e-3)];
        for i in 0..N {
            u.push((StringInput::Fd(i), 3.0 + i as f64));
            u.push((StringInput::Vsx(i), 2e-4 * (i as f64 - 1.0)));
            if c.normal_input {
                u.push((StringInput::Fn(i), 40.0 + 5.0 * i as f64));
            }
        }
        u
    }

    fn params() -> StringParams {
        let shared = Params {
            h_v: 20.0,
            ..Params::default()
        };
        let mut p = StringParams::uniform(N, shared, 1e5, 10.0);
        p.m[2] = 2.0 * shared.m;
        p.links.k_top = 2e4;
        p.links.c_top = 5.0;
        p.links.k_bottom = 3e4;
        p.links.c_bottom = 7.0;
        p
    }

    /// A string at time `t` with its inputs set and its sections in the regimes of each law:
    /// the deformation at fractions `frac` of its steady value (reversed at the last), moving.
    fn string(c: StringConfig, t: f64, frac: f64) -> Box<dyn StringSimulator> {
        let p = params();
        let mut sim = build_string(c, p.clone(), 0.0, 1e-6).unwrap();
        sim.set_exchange();
        sim.set_exchange_time(t).unwrap();
        for (input, value) in inputs(&c) {
            sim.set_input(input, value).unwrap();
        }
        let s_ss = p.section(0).f_c() * 40.0 / 55.0 / p.shared.k_t;
        let mut x = vec![0.0; PER_SECTION * N + 2];
        for i in 0..N {
            let f = [frac, 0.5 * frac, 0.9 * frac, -0.7 * frac][i];
            x[i] = 1e-6 * (i as f64 + 1.3);
            x[N + i] = [-2e-3, 1e-3, 3e-4, -4e-4][i];
            x[2 * N + i] = f * s_ss;
        }
        x[3 * N] = 2.1e-6;
        x[3 * N + 1] = 5.5e-6;
        sim.set_exchange_states(&x).unwrap();
        sim
    }

    fn outputs_vec(o: &StringOutputs) -> Vec<f64> {
        let mut v = [&o.x, &o.v_x, &o.s_x, &o.f_fx, &o.f_fx_step, &o.f_link]
            .into_iter()
            .flatten()
            .copied()
            .collect::<Vec<_>>();
        v.extend([o.f_top, o.f_bottom, o.f_top_step, o.f_bottom_step]);
        v
    }

    /// The closed-form directional derivatives against central differences, along every state
    /// and every input, for every law, with and without the load as an input, in each law's
    /// regimes: relative 1e-6 (with the differences' rounding).
    #[test]
    fn directional_derivatives_match_central_differences() {
        for c in configs() {
            for (k, frac) in [0.1, 0.62, 0.97].into_iter().enumerate() {
                let sim = string(c, 1.3e-4 * (k as f64 + 1.0), frac);
                let nominal = sim.exchange_nominals();
                let dim = PER_SECTION * N + 2;
                let mut directions: Vec<(String, Vec<f64>, InputDirection, f64)> = vec![];
                for j in 0..dim {
                    let mut dx = vec![0.0; dim];
                    dx[j] = 1.0;
                    let h = 1e-6 * nominal[j].max(1e-7);
                    let du = InputDirection::zero(N, c.normal_input);
                    directions.push((state_name(N, j), dx, du, h));
                }
                for (input, _) in inputs(&c) {
                    let mut du = InputDirection::zero(N, c.normal_input);
                    let h = match input {
                        StringInput::Fd(i) => {
                            du.f_d[i] = 1.0;
                            1e-4
                        }
                        StringInput::Vsx(i) => {
                            du.v_sx[i] = 1.0;
                            1e-8
                        }
                        StringInput::Fn(i) => {
                            du.f_n[i] = 1.0;
                            1e-4
                        }
                        StringInput::VTop => {
                            du.v_top = 1.0;
                            1e-8
                        }
                        StringInput::VBottom => {
                            du.v_bottom = 1.0;
                            1e-8
                        }
                    };
                    directions.push((format!("{input:?}"), vec![0.0; dim], du, h));
                }
                for (name, dx, du, h) in directions {
                    let (dder, dout) = sim.tangent(&dx, &du);
                    let shifted = |sign: f64| {
                        let mut s = sim.clone_box();
                        let x: Vec<f64> = (s.exchange_states().iter().zip(&dx))
                            .map(|(x, d)| x + sign * h * d)
                            .collect();
                        s.set_exchange_states(&x).unwrap();
                        for (input, value) in inputs(&c) {
                            let d = match input {
                                StringInput::Fd(i) => du.f_d[i],
                                StringInput::Vsx(i) => du.v_sx[i],
                                StringInput::Fn(i) => du.f_n[i],
                                StringInput::VTop => du.v_top,
                                StringInput::VBottom => du.v_bottom,
                            };
                            s.set_input(input, value + sign * h * d).unwrap();
                        }
                        (s.exchange_derivatives(), outputs_vec(&s.outputs()))
                    };
                    let ((dp, op), (dm, om)) = (shifted(1.0), shifted(-1.0));
                    let exact = dder
                        .iter()
                        .chain(&outputs_vec(&dout))
                        .copied()
                        .collect::<Vec<_>>();
                    let plus = dp.iter().chain(&op).copied().collect::<Vec<_>>();
                    let minus = dm.iter().chain(&om).copied().collect::<Vec<_>>();
                    for (j, ((e, p), m)) in exact.iter().zip(&plus).zip(&minus).enumerate() {
                        let fd = (p - m) / (2.0 * h);
                        let tol = 1e-6 * (fd.abs() + e.abs()) + 1e-9 * p.abs().max(m.abs()) / h;
                        assert!(
                            (e - fd).abs() <= tol,
                            "{c:?} frac {frac}: component {j} along {name}: {e} vs difference {fd}"
                        );
                    }
                }
            }
        }
    }

    /// The derivatives are what Co-Simulation integrates: the second-order forward difference
    /// of the Co-Simulation string's states over two steps of 0.25 µs (integrated at tolerance
    /// 1e-10) agrees with them, every state of every law.
    #[test]
    fn derivatives_are_what_co_simulation_integrates() {
        for c in configs() {
            let mut sim = build_string(c, params(), 0.0, 1e-10).unwrap();
            for (input, value) in inputs(&c) {
                sim.set_input(input, value).unwrap();
            }
            sim.step_to(2e-3).unwrap();
            let (x0, der, nominal) = (
                sim.exchange_states(),
                sim.exchange_derivatives(),
                sim.exchange_nominals(),
            );
            let h = 2.5e-7;
            sim.step_to(2e-3 + h).unwrap();
            let x1 = sim.exchange_states();
            sim.step_to(2e-3 + 2.0 * h).unwrap();
            let x2 = sim.exchange_states();
            let mut worst: f64 = 0.0;
            for j in 0..x0.len() {
                let fd = (-3.0 * x0[j] + 4.0 * x1[j] - x2[j]) / (2.0 * h);
                let scale = der[j].abs().max(nominal[j] / 1e-3);
                let err = (fd - der[j]).abs() / scale;
                worst = worst.max(err);
                assert!(
                    err < 3e-5,
                    "{c:?}: {} rate {} vs difference {fd}",
                    state_name(N, j),
                    der[j]
                );
            }
            println!("{c:?}: worst {worst:.1e}");
        }
    }
}
