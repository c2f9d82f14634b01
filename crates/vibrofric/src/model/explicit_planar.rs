//! The explicit path of a moving body on a planar Dahl contact (`kappa = 1`): force or spring
//! drive, or a velocity drive with the lateral motion free, whenever the motion leaves the x
//! axis (on the axis the closed form of `explicit.rs` applies). The whole state
//! `[s | body]` and the integrals `∫F_Fx dt`, `∫F_Fy dt` are integrated by Dormand–Prince 5(4)
//! with error control on the state; the integrals ride along with the fifth-order weights and
//! do not steer the step.
//!
//! The deformation's rate `v_r − |v_r|·s/s_ss` is Lipschitz continuous everywhere (its kink
//! where `v_r` passes through zero in the plane is a point, found by the error control), and
//! relaxes at `|v_r|/s_ss`; the body sits on the contact as on a spring `k_t` while it sticks.
//! The explicit method is stable while the step is below about `3/rate` for the larger of those
//! rates: the path is taken only while that bound allows steps of a fraction of the averaging
//! window ([`STIFF_LIMIT`]), and Radau IIA takes a stiffer contact.

use super::contact::Contact;
use super::drive::DriveKind;
use super::dynamics::System;
use super::simulator::SimError;
use crate::physics::{FrictionLaw, Vector};
use crate::solver::dopri::{factor, DoPriStep};
use crate::solver::{OdeSystem, Quad, SolverError};
use crate::table::InputId;

/// Width of the integrated vector: the largest state (6) and the two integrals.
const M: usize = 8;

/// The error control's tolerance as a fraction of the user's, on the largest scaled error of
/// the state's components: the global errors of `F_Fx` and `F_Fy` are then at or below
/// Radau's at the same tolerance (measured on PaperTransverse and RigTransverse against a
/// tolerance-1e-12 run, 0.05 s: at 1e-6, `F_Fx` 3.1e-9 and 3.6e-8 of `F_C` against Radau's
/// 3.0e-8 and 3.2e-8, `F_Fy` 2.9e-8 and 3.9e-7 against 3.5e-8 and 2.1e-6).
const TOL_FRACTION: f64 = 0.1;

/// The largest product of the contact's fastest rate (relaxation `|v_r|/s_ss`, or the
/// oscillation `sqrt(k_t/m)` of a stuck body) and the averaging window for which the explicit
/// path is taken: its stability bound then allows about 60 steps per window, about what the
/// accuracy asks at tolerance 1e-6 (at the default `k_t` = 1e8 and 2 kHz the product is about
/// 16; from about 1e10 on it is beyond the limit).
pub(super) const STIFF_LIMIT: f64 = 200.0;

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Contact<V, L, D, N> {
    /// True when this contact takes the planar explicit path: a planar Dahl contact with
    /// `kappa = 1` at a constant load whose body moves (force, spring or free lateral motion),
    /// not stiff on the scale of the averaging window ([`STIFF_LIMIT`]).
    pub(super) fn planar_explicit_path(&self) -> bool {
        if V::DIM != 2 || D::N_BODY == 0 || self.radau_only || self.dynamics.load.is_some() {
            return false;
        }
        let Some(relax) = self.dynamics.law.relaxation() else {
            return false;
        };
        if relax.exponent != 1.0 {
            return false;
        }
        let rate = self.fastest_rate(relax.length, relax.stiffness);
        rate * self.window.len <= STIFF_LIMIT
    }

    /// The contact's fastest rate: the relaxation at the relative speed the parameters and
    /// inputs impose (the vibration's amplitude, the drive velocity and the support inputs, not
    /// the state, so that the path does not change along a trajectory with held inputs) or the
    /// oscillation of a stuck body. A body that moves faster makes the error control take
    /// shorter steps, not wrong ones.
    fn fastest_rate(&self, s_ss: f64, k_t: f64) -> f64 {
        let t = self.radau.t;
        let v_a = self.dynamics.harmonic.map_or(0.0, |h| h.v_a());
        let tracks = &self.dynamics.tracks;
        let mut v_ref = v_a;
        for id in [InputId::VD, InputId::VSx, InputId::VSy] {
            if id.present(&self.config) {
                v_ref += tracks[id.index()].at(t).abs();
            }
        }
        let omega = (k_t / self.params.m).sqrt();
        (v_ref / s_ss).max(omega)
    }

    /// Advances the planar explicit path to `t_target`: `∫F_F dt` over the call.
    pub(super) fn advance_planar(&mut self, t_target: f64, h_max: f64) -> Result<Quad, SimError> {
        let tol = self.radau.tolerance();
        let rtol = (TOL_FRACTION * tol).max(1e-14);
        let dynamics = self.dynamics;
        let scale = self.scale;
        let sys = System::new(
            &dynamics,
            self.config.input_support,
            &scale,
            self.force_scale,
            self.switch_scale,
        );
        let bound = dynamics.law.bound();
        let rhs = |tt: f64, u: &[f64; M]| -> [f64; M] {
            let e = sys.eval(tt, &u[..N]);
            let r = sys.rhs_at::<N>(&e, &u[..N]);
            let mut out = [0.0; M];
            out[..N].copy_from_slice(r.as_slice());
            out[N] = e.f.x();
            out[N + 1] = e.f.y();
            out
        };
        let mut rhs = rhs;
        let mut t = self.radau.t;
        let mut u = [0.0; M];
        u[..N].copy_from_slice(self.radau.y.as_slice());
        let mut integral = [0.0; 2];
        let mut h = self.exp_h;
        let mut fsal: Option<[f64; M]> = None;
        let mut rejected = false;
        let limit = self.radau.step_limit;
        let stats = &mut self.radau.stats;
        while t < t_target {
            if stats.steps + stats.rejected >= limit {
                return Err(SimError::Solver(SolverError::WorkLimit {
                    t,
                    limit: limit as f64,
                }));
            }
            u[N] = 0.0;
            u[N + 1] = 0.0;
            let k1 = match fsal {
                Some(k) => k,
                None => {
                    stats.rhs_evals += 1;
                    rhs(t, &u)
                }
            };
            if !k1.iter().all(|z| z.is_finite()) {
                return Err(SimError::Solver(SolverError::NonFinite { t }));
            }
            if h <= 0.0 {
                let d = (0..N)
                    .map(|i| (k1[i] / scale[i]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                h = if d > 0.0 {
                    1e-2 / d * libm::pow(tol, 0.2)
                } else {
                    h_max
                };
            }
            let mut hh = h.min(h_max);
            let mut last = false;
            if t + 1.0001 * hh >= t_target {
                hh = t_target - t;
                last = true;
            }
            if !last && hh <= 16.0 * f64::EPSILON * t.abs().max(hh) {
                return Err(SimError::Solver(SolverError::StepSizeTooSmall { t, h: hh }));
            }
            let step = DoPriStep::take(&mut rhs, t, &u, &k1, hh);
            stats.rhs_evals += 6;
            let u1 = step.end();
            let mut err: f64 = 0.0;
            for i in 0..N {
                let w = rtol * (scale[i] + u[i].abs().max(u1[i].abs()));
                err = err.max((step.err[i] / w).abs());
            }
            let err = if u1.iter().all(|z| z.is_finite()) && err.is_finite() {
                err
            } else {
                f64::INFINITY
            };
            if err > 1.0 {
                stats.rejected += 1;
                h = hh * factor(err).min(0.9);
                rejected = true;
                fsal = Some(k1);
                continue;
            }
            stats.steps += 1;
            integral[0] += u1[N];
            integral[1] += u1[N + 1];
            u = u1;
            fsal = Some(step.k[6]);
            t = if last { t_target } else { t + hh };
            // |s| ≤ s_ss holds for the equation; the step may overshoot it by its error.
            if let Some(b) = bound {
                let s = V::read(&u[..V::DIM]);
                let n = s.norm();
                if n > b {
                    (s * (b / n)).write(&mut u[..V::DIM]);
                    fsal = None;
                }
            }
            let mut h_new = hh * factor(err);
            if rejected {
                h_new = h_new.min(hh);
            }
            rejected = false;
            if last && hh < h {
                h_new = h_new.max(h);
            }
            h = h_new;
        }
        let mut y = self.radau.y;
        y.as_mut_slice().copy_from_slice(&u[..N]);
        OdeSystem::<N>::project(&self.system(), t_target, &mut y);
        self.radau.y = y;
        self.radau.t = t_target;
        self.radau.restart();
        self.exp_h = h;
        Ok(integral)
    }
}
