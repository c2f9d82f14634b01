//! The explicit path of a moving body on a Dahl contact (`kappa = 1`), force or spring drive,
//! motion along x: between sign changes of `v_r` the deformation is a closed-form function of
//! the relative displacement `ξ` since the step's start,
//! `s(ξ) = s0 + (σ·s_ss − s0)·(1 − exp(−σ·ξ/s_ss))`, `σ = sgn(v_r)`, so the contact's stiff
//! relaxation (rate `|v_r|/s_ss`) leaves the equations. What is left, `dξ/dt = v − v_s(t)`,
//! `dx/dt = v`, `m·dv/dt = F_d − k_t·s(ξ)`, is smooth and integrated by Dormand–Prince 5(4)
//! with error control, each step cut where `v_r` changes sign (located on the continuous
//! extension), and `∫F_Fx dt` integrated alongside with the fifth-order weights.
//!
//! A sign change of `v_r` counts once `σ·v_r` falls below `−band`, `band` a twentieth of the
//! tolerance of the velocity of the contact's own oscillation (`s_ss·sqrt(k_t/m)`): a stuck
//! body whose relative velocity hovers at zero does not chatter, and the deformation on the
//! wrong branch meanwhile is below a tenth of the tolerance. While the body sticks it sits on
//! the contact as on a spring `k_t`; the explicit method's step then follows its stability
//! bound (about `3/sqrt(k_t/m)`), which the error control finds by itself.

use super::contact::Contact;
use super::drive::DriveKind;
use super::simulator::SimError;
use crate::physics::{FrictionLaw, Vector};
use crate::solver::dopri::{factor, DoPriStep, C};
use crate::solver::{OdeSystem, Quad, SolverError};
use crate::table::{Drive, InputId};

/// The error control's tolerance as a fraction of the user's: the global error of `F_Fx` is
/// then about the tolerance times `F_C` (measured on VibratingContact: 1.1e-6 at 1e-6, 1.8e-9
/// at 1e-9; Radau: 2.0e-6 and 5.5e-9).
const TOL_FRACTION: f64 = 0.5;

/// The first step on a new branch as a fraction of the time its relaxation over one `s_ss`
/// takes from rest (a whole one fails the error test by 20–100 on VibratingContact).
const RELAX_FIRST: f64 = 0.4;

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Contact<V, L, D, N> {
    /// True when this contact takes the explicit path: a force or spring drive, Dahl with
    /// `kappa = 1` at a constant load, and (planar scenes) the motion on x: no lateral
    /// deformation, velocity or support motion now.
    pub(super) fn explicit_path(&self) -> bool {
        if self.radau_only
            || self.dynamics.load.is_some()
            || !matches!(self.config.drive, Drive::Force | Drive::Spring)
            || !self
                .dynamics
                .law
                .relaxation()
                .is_some_and(|r| r.exponent == 1.0)
        {
            return false;
        }
        if V::DIM == 1 {
            return true;
        }
        let y = self.radau.y.as_slice();
        let lateral_support = self
            .dynamics
            .harmonic
            .is_some_and(|h| h.dir.1 != 0.0 && h.u0 != 0.0 && h.f != 0.0)
            || (self.config.input_support && {
                let t = &self.dynamics.tracks[InputId::VSy.index()];
                t.value != 0.0 || t.slope != 0.0
            });
        y[1] == 0.0 && y[2 * V::DIM + 1] == 0.0 && !lateral_support
    }

    /// Advances the explicit path to `t_target`: `∫F_F dt` over the call.
    pub(super) fn advance_explicit(&mut self, t_target: f64, h_max: f64) -> Result<Quad, SimError> {
        let relax = self
            .dynamics
            .law
            .relaxation()
            .expect("explicit path without a relaxation");
        let (len, k_t) = (relax.length, relax.stiffness);
        let inv_len = 1.0 / len;
        let (ix, iv) = (V::DIM, 2 * V::DIM);
        let inv_m = 1.0 / self.params.m;
        let tol = self.radau.tolerance();
        let rtol = (TOL_FRACTION * tol).max(1e-14);
        let band = 0.05 * tol * len * (k_t * inv_m).sqrt();
        let band = if band.is_finite() { band } else { 0.0 };
        let (nom_s, nom_x, nom_v) = (self.scale[0], self.scale[ix], self.scale[iv]);
        let dynamics = self.dynamics;
        let input_support = self.config.input_support;
        let vs = |t: f64| dynamics.support_velocity(t, input_support).x();
        let mut body = [0.0; 4];
        body[..D::N_BODY].copy_from_slice(&self.radau.y.as_slice()[V::DIM..]);
        let accel = move |t: f64, x: f64, v: f64, f: f64| {
            let mut b = body;
            b[0] = x;
            b[V::DIM] = v;
            let d = dynamics.drive_inputs(t);
            (dynamics.drive.drive_force(&b[..D::N_BODY], &d) - f) * inv_m
        };

        let mut t = self.radau.t;
        let y0 = self.radau.y;
        let (mut s, mut x, mut v) = (y0[0], y0[ix], y0[iv]);
        let vr0 = v - vs(t);
        let mut sigma = self.direction;
        if sigma == 0.0 || sigma * vr0 < -band {
            sigma = if vr0 != 0.0 {
                vr0.signum()
            } else {
                let push = accel(t, x, v, k_t * s);
                if push < 0.0 {
                    -1.0
                } else {
                    1.0
                }
            };
        }
        let mut integral = 0.0;
        let mut h = self.exp_h;
        let mut fsal: Option<[f64; 4]> = None;
        let mut event_target: Option<f64> = None;
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
            let s0 = s;
            // The deformation after a relative displacement ξ from s0 on the branch σ.
            let s_of = |xi: f64, sigma: f64| {
                // Against the branch (a trial stage beyond a reversal) the expression grows
                // exponentially: bounded, so that the error estimate rejects the step.
                let e = (-sigma * xi * inv_len).min(50.0);
                // Below −39, expm1 is −1 to the last bit: no call on a relaxed branch.
                let em1 = if e < -39.0 { -1.0 } else { libm::expm1(e) };
                s0 - (sigma * len - s0) * em1
            };
            // The support velocity at the stage times, recorded by the right-hand side.
            let vs_at = std::cell::Cell::new([0.0; 7]);
            let calls = std::cell::Cell::new(0usize);
            let mut rhs = |tt: f64, u: &[f64; 4]| {
                let f = k_t * s_of(u[0], sigma);
                let w = vs(tt);
                let mut a = vs_at.get();
                a[calls.get() % 7] = w;
                vs_at.set(a);
                calls.set(calls.get() + 1);
                [u[2] - w, u[2], accel(tt, u[1], u[2], f), f]
            };
            let u0 = [0.0, x, v, 0.0];
            let k1 = match fsal {
                Some(k) => k,
                None => {
                    stats.rhs_evals += 1;
                    rhs(t, &u0)
                }
            };
            let mut a = vs_at.get();
            a[0] = v - k1[0];
            vs_at.set(a);
            calls.set(1);
            if !k1.iter().all(|z| z.is_finite()) {
                return Err(SimError::Solver(SolverError::NonFinite { t }));
            }
            if h <= 0.0 {
                let d =
                    ((k1[0] / nom_s).powi(2) + (k1[1] / nom_x).powi(2) + (k1[2] / nom_v).powi(2))
                        .sqrt();
                h = if d > 0.0 {
                    1e-2 / d * libm::pow(tol, 0.2)
                } else {
                    h_max
                };
            }
            let mut hh = h.min(h_max);
            let mut last = false;
            if let Some(te) = event_target {
                hh = te - t;
                last = te >= t_target;
            } else if t + 1.0001 * hh >= t_target {
                hh = t_target - t;
                last = true;
            }
            if !last && hh <= 16.0 * f64::EPSILON * t.abs().max(hh) {
                return Err(SimError::Solver(SolverError::StepSizeTooSmall { t, h: hh }));
            }
            let step = DoPriStep::take(&mut rhs, t, &u0, &k1, hh);
            stats.rhs_evals += 6;
            let u1 = step.end();
            // The error of s from that of ξ (ds/dξ is largest at the step's start, or its
            // end on a step that went a little against σ).
            let back = -sigma * u1[0] * inv_len;
            let slope =
                (1.0 - sigma * s0 * inv_len).abs() * if back > 0.0 { libm::exp(back) } else { 1.0 };
            let e = [
                step.err[0] * slope / (rtol * (nom_s + s0.abs())),
                step.err[1] / (rtol * (nom_x + x.abs().max(u1[1].abs()))),
                step.err[2] / (rtol * (nom_v + v.abs().max(u1[2].abs()))),
            ];
            let err = ((e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) / 3.0).sqrt();
            let err = if u1.iter().all(|z| z.is_finite()) && err.is_finite() {
                err
            } else {
                f64::INFINITY
            };
            if err > 1.0 {
                stats.rejected += 1;
                h = hh * factor(err).min(0.9);
                event_target = None;
                rejected = true;
                fsal = Some(k1);
                continue;
            }
            // A sign change of v_r inside the step: retake the step to end on it.
            if event_target.is_none() {
                let vs_at = vs_at.get();
                let g = |i: usize| sigma * (step.stages[i][2] - vs_at[i]) + band;
                if let Some(i) = (1..7).find(|&i| g(i) < 0.0) {
                    let vs_fn = &vs;
                    let gd = |theta: f64| {
                        sigma * (step.dense(2, hh, theta) - vs_fn(t + theta * hh)) + band
                    };
                    let theta = root(&gd, (C[i - 1], g(i - 1).max(0.0)), (C[i], g(i)), band);
                    let te = t + theta * hh;
                    fsal = Some(k1);
                    if te <= t {
                        // The reversal is at the step's start: the other branch from here. The
                        // attempt counts as rejected, so the work limit bounds any repetition.
                        sigma = -sigma;
                        stats.events += 1;
                        stats.rejected += 1;
                        continue;
                    }
                    if theta < 1.0 {
                        event_target = Some(te);
                        h = hh;
                        continue;
                    }
                    // At the step's end: the reversal is there.
                    event_target = Some(t + hh);
                }
            }
            stats.steps += 1;
            s = s_of(u1[0], sigma);
            x = u1[1];
            v = u1[2];
            integral += u1[3];
            t = if last { t_target } else { t + hh };
            fsal = Some(step.k[6]);
            if s.abs() > len {
                s = len.copysign(s);
                fsal = None;
            }
            let mut h_new = hh * factor(err);
            if rejected {
                h_new = h_new.min(hh);
            }
            rejected = false;
            if event_target.is_some() {
                // The reversal: the other branch from here; the step that ended on it was
                // clipped and says little about the step size.
                sigma = -sigma;
                stats.events += 1;
                event_target = None;
                h_new = h_new.max(h);
                // The new branch relaxes over one s_ss of relative displacement, which from
                // rest takes sqrt(2·s_ss/|dv_r/dt|): the first step a fraction of that (a
                // stiff contact would otherwise pay for it in rejected steps).
                let dvr = (step.k[6][0] - step.k[4][0]) / ((1.0 - C[4]) * hh);
                let relax = RELAX_FIRST * (2.0 * len / dvr.abs()).sqrt();
                if relax.is_finite() && relax > 0.0 {
                    h_new = h_new.min(relax);
                }
            } else if last && hh < h {
                h_new = h_new.max(h);
            }
            h = h_new;
        }
        let mut y = self.radau.y;
        y[0] = s;
        y[ix] = x;
        y[iv] = v;
        OdeSystem::<N>::project(&self.system(), t_target, &mut y);
        self.radau.y = y;
        self.radau.t = t_target;
        self.radau.restart();
        self.exp_h = h;
        self.direction = sigma;
        Ok([integral, 0.0])
    }
}

/// A point just past the root of `g` in `(a, b)`, from `g(a) = ga ≥ 0 > g(b) = gb`, by the
/// Illinois method: the first `b` found with `−within ≤ g(b) < 0`, or the bracket's end at the
/// resolution of `theta`.
pub(super) fn root(
    g: &impl Fn(f64) -> f64,
    (mut a, mut ga): (f64, f64),
    (mut b, mut gb): (f64, f64),
    within: f64,
) -> f64 {
    let mut side = 0;
    for _ in 0..60 {
        if b - a <= 1e-15 || gb >= -within {
            break;
        }
        let secant = b - gb * (b - a) / (gb - ga);
        let m = if secant.is_finite() {
            secant.max(a + 0.01 * (b - a)).min(b - 0.01 * (b - a))
        } else {
            0.5 * (a + b)
        };
        let gm = g(m);
        if !gm.is_finite() {
            break;
        }
        if gm >= 0.0 {
            a = m;
            ga = gm;
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        } else {
            b = m;
            gb = gm;
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
        }
        if gm == 0.0 {
            break;
        }
    }
    b
}
