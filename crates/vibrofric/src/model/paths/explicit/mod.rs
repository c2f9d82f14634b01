//! The explicit path of a moving body on a Dahl (`kappa = 1`) or Dupont contact, force or
//! spring drive, motion along x: between sign changes of `v_r` the deformation is a function
//! of the relative displacement `ξ` since the step's start alone, so the contact's stiff
//! relaxation (rate `|v_r|/s_ss`) leaves the equations. Dahl's is the closed form
//! `s(ξ) = s0 + (σ·s_ss − s0)·(1 − exp(−σ·ξ/s_ss))`, `σ = sgn(v_r)`; Dupont's is elastic,
//! `s0 + ξ`, until `σ·s` reaches the breakaway `s_ba`, then the plastic shape of
//! `physics::ElastoPlastic`. A step that passes the breakaway is retaken to end there (the
//! deformation's third derivative jumps), and, since the elastic part keeps every step's error
//! where Dahl's relaxation damps it, Dupont's error control is tighter
//! ([`DUPONT_TOL_FRACTION`]). What is left, `dξ/dt = v − v_s(t)`,
//! `dx/dt = v`, `m·dv/dt = F_d − k_t·s(ξ)`, is smooth and integrated by Dormand–Prince 5(4)
//! with error control, each step cut where `v_r` changes sign (located on the continuous
//! extension), and `∫F_Fx dt` integrated alongside with the fifth-order weights. The error
//! control weighs the deformation's error short of a call's end by its effect on the body
//! (it relaxes along the branch; [`PUSH_MARGIN`]), so that a stiff contact's swing after a
//! reversal costs few steps.
//!
//! A sign change of `v_r` counts once `σ·v_r` falls below `−band`, `band` a twentieth of the
//! tolerance of the velocity of the contact's own oscillation (`s_ss·sqrt(k_t/m)`): a stuck
//! body whose relative velocity hovers at zero does not chatter, and the deformation on the
//! wrong branch meanwhile is below a tenth of the tolerance. While the body sticks it sits on
//! the contact as on a spring `k_t`; the explicit method's step then follows its stability
//! bound (about `3/sqrt(k_t/m)`), which the error control finds by itself.

use super::attempts;
use super::elastic::{elastic_step, ElasticEnd, Forcing};
use super::stage_support::StageSupport;
use super::{Integrated, Kept, Path, Shape, Shared};
use crate::model::drive::DriveKind;
use crate::model::simulator::SimError;
use crate::physics::{trig, BranchStart, ElastoPlastic, FrictionLaw, Relaxation, Vector};
use crate::solver::dopri::{factor, first_step, DoPriStep, C};
use crate::solver::{Quad, SolverStats};
use crate::table::{Drive, InputId};
use std::sync::Arc;

/// The largest product of a stuck body's oscillation rate `sqrt(k_t/m)` and the averaging
/// window for which a Dahl contact that the vibration does not keep sliding
/// ([`Shared::vibration_unheld`]) takes the explicit path: while its body sticks the explicit
/// method steps at its stability bound, and Radau IIA is cheaper beyond it. VibratingContact
/// without vibration, `F_d` = 2 N (stuck), 1 s at tolerance 1e-6, CPU time: explicit 17.6, 56
/// and 174 ms at `k_t` = 1e10, 1e11 and 1e12 (products 42, 133, 423), Radau 23, 25 and 25 ms;
/// RigLongitudinal without vibration (sliding at `v_d`): 2.7, 7.1 and 21.5 ms against 7.1,
/// 10.4 and 9.3. Dupont keeps the path: its stuck body rings in closed form.
const HELD_LIMIT: f64 = 100.0;

/// The error control's tolerance as a fraction of the user's: the global error of `F_Fx` is
/// then below the tolerance times `F_C` (measured on VibratingContact against Radau at 1e-12,
/// 1 s in 1 ms steps: 5.0e-7 at 1e-6 and 9.4e-9 at 1e-8; at 0.45, 1.07e-8 at 1e-8 once the
/// deformation's error was weighed by its effect (see [`PUSH_MARGIN`]), 8.9e-9 before).
const TOL_FRACTION: f64 = 0.4;

/// The same for Dupont, whose elastic part (up to the breakaway) keeps the errors of each step
/// where Dahl's relaxation damps them (VibratingContactDupont against Radau at 1e-12, 1 s in
/// 1 ms steps: `F_Fx` within 4.1e-7 of `F_C` at 1e-6 and 2.6e-9 at 1e-8, Radau's own at those
/// tolerances 2.3e-7 and 5.5e-9; 1.5e-7 and 2.0e-9 before the breakaway predictor; when the
/// fraction was chosen, before the reversal predictor: 0.03 gave 2.0e-7 and 1.9e-9, 0.1 1.1e-6
/// and 5.4e-9, 0.45 3e-6 and 1e-8).
/// Measured and not taken: a fraction for each part of the branch (the step's start on the
/// elastic part or past the breakaway), the same scene, 0.1 s, `examples/planar_probe.rs`
/// against Radau at 1e-12. Steps and rejected attempts per period, `F_Fx` off by (of `F_C`):
///
/// | elastic, plastic | tolerance 1e-6 | 1e-7 | 1e-8 |
/// |---|---|---|---|
/// | 0.03, 0.03 (this) | 18.1 + 1.1, 4.1e-7 | 26.2 + 3.0, 2.1e-8 | 41.2 + 3.0, 2.6e-9 |
/// | 0.4, 0.03 | 14.2 + 2.0, 8.1e-7 | 20.3 + 1.1, 6.0e-8 | 33.2 + 3.0, 4.3e-9 |
/// | 0.03, 0.1 | 17.1 + 1.0, 1.3e-6 | | 37.3 + 1.1, 7.7e-9 |
/// | 0.03, 0.4 | 16.1 + 1.0, 2.1e-6 | | 35.2 + 1.1, 3.8e-8 |
///
/// A looser elastic part saves a sixth to a quarter of the attempts but raises the error 1.6
/// to 3 times at 1e8 (at `k_t` = 1e10: 27.1 → 23.1 attempts per period at 1e-6, `F_Fx` 3.4e-8 →
/// 2.3e-8; 38.1 → 32.1 at 1e-7, 2.1e-10 → 4.1e-8); a looser plastic part buys little and
/// leaves the tolerance. Neither is cheaper at equal accuracy.
pub(super) const DUPONT_TOL_FRACTION: f64 = 0.03;

/// Short of a call's end, a step's error in the deformation is weighed by what it leaves: the
/// velocity it pushes into the body before the branch relaxes it, and what is left of it at
/// the call's end. This is the margin on the first (the bound takes `v_r` at the step's end
/// for the whole relaxation, and the error in `ξ` grows meanwhile with the error of the
/// velocity it feeds; at 1 the `F_Fx` error of VibratingContact was 1.4e-8 at tolerance 1e-8
/// over 0.1 s, at 3 1.09e-8, with TOL_FRACTION at 0.45). After a reversal of a stiff contact
/// this is what sets the steps: the deformation swings by `2·s_ss` within a few `s_ss` while
/// the body's velocity hardly notices (VibratingContact at `k_t` = 1e12: 16.1 steps per period
/// at tolerance 1e-6, 25.0 with the deformation's own error).
pub(super) const PUSH_MARGIN: f64 = 3.0;

/// The loosest tolerance at which the deformation's error is weighed by its effect (here and
/// on the planar path): from 1e-6 down to 1e-12 the outputs stay within the tolerance, as
/// measured against Radau at 1e-11; at looser ones the bound, taken at a step's end over
/// steps that long, does not hold (VibratingContact at 1e-4 over 20 ms: `F_Fx` 1.6e-4 of
/// `F_C` weighed, 2.3e-5 not; RigTransverse at 1e-5: `F_Fy` 2.2e-4 against 1.5e-5), and
/// the steps it would save are few (7.1 against 7.2 per period).
pub(super) const WEIGH_UP_TO: f64 = 1e-6;

/// How far past Dupont's breakaway (in `s_ss`) a step retaken to end on it may end: the
/// deformation there is taken as elastic, off by about the cube of this.
const BREAKAWAY_WITHIN: f64 = 1e-9;

/// How far past the reversal predicted from `v_r` and its rate at a step's start the step may
/// end.
const PAST_REVERSAL: f64 = 1.25;

/// How far past the breakaway predicted from `v_r` and its rate at a step's start the step may
/// end (it is then retaken to end there).
const PAST_BREAKAWAY: f64 = 1.25;

/// A breakaway within this fraction of a step from its start is taken along inside the step:
/// the jump of the deformation's third derivative so near the start costs the step nothing
/// measurable, where ending a step on it would leave a step of that length to grow from.
const BREAKAWAY_AT_START: f64 = 1e-3;

/// The first step on a new branch as a fraction of the time its relaxation over one `s_ss`
/// takes from rest (a whole one fails the error test by 20–100 on VibratingContact).
const RELAX_FIRST: f64 = 0.4;

/// What the explicit path keeps between calls.
#[derive(Clone, Debug)]
pub(in crate::model) struct ExplicitKept {
    /// The branch: the sign of `v_r` since its last located change (0: not yet known).
    pub(in crate::model) direction: f64,
    /// Dupont's deformation along a branch for this contact's breakaway ratio, fitted on first
    /// use (none where the law has no breakaway or the fit does not converge).
    pub(in crate::model) elastoplastic: Shape,
}

/// The explicit path.
pub(super) struct Explicit;

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Path<V, L, D, N> for Explicit {
    /// True when this contact takes the explicit path: a force or spring drive, Dahl with
    /// `kappa = 1` or Dupont at a constant load, and (planar scenes) the motion on x
    /// ([`Shared::on_x_axis`]); a stiff Dahl contact only where the vibration keeps the body
    /// sliding ([`HELD_LIMIT`]).
    fn applies(c: &Shared<'_, V, L, D, N>, r: &Integrated<N>, k: &Kept<N>) -> bool {
        if k.force_radau
            || c.dynamics.load.is_some()
            || !matches!(c.config.drive, Drive::Force | Drive::Spring)
            || branch_shape(c, k).is_none()
        {
            return false;
        }
        let dahl = c
            .dynamics
            .law
            .relaxation()
            .is_some_and(|r| r.exponent == 1.0);
        let stiff = (c.params.k_t / c.params.m).sqrt() * c.window_len > HELD_LIMIT;
        if dahl && stiff && !c.vibration_unheld() {
            return false;
        }
        c.on_x_axis(&r.y)
    }

    /// Advances the explicit path to `t_target`: `∫F_F dt` over the call.
    fn advance(
        c: &Shared<'_, V, L, D, N>,
        r: &mut Integrated<N>,
        k: &mut Kept<N>,
        t_target: f64,
        h_max: f64,
    ) -> Result<Quad, SimError> {
        advance_explicit(c, r, k, t_target, h_max)
    }
}

/// The law's relaxation in the relative displacement along a branch, where the explicit
/// path can follow it: Dahl with `kappa = 1` (exponential), or Dupont with the shape of its
/// breakaway ratio (elastic, then plastic), fitted on first use.
fn branch_shape<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
    c: &Shared<'_, V, L, D, N>,
    k: &Kept<N>,
) -> Option<(Relaxation, Option<Arc<ElastoPlastic>>)> {
    let law = &c.dynamics.law;
    if let Some(relax) = law.relaxation().filter(|r| r.exponent == 1.0) {
        return Some((relax, None));
    }
    let (relax, r_ba) = law.breakaway()?;
    let shape = k
        .explicit
        .elastoplastic
        .get_or_init(|| ElastoPlastic::new(r_ba).map(Arc::new));
    shape.clone().map(|shape| (relax, Some(shape)))
}

/// Dupont under a force drive, within the breakaway `s_ba`: the whole call in closed form
/// where the deformation provably stays elastic (a stuck body ringing on the contact), from
/// `[s, x, v]` at `t`.
fn elastic_call<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
    c: &Shared<'_, V, L, D, N>,
    s_ba: f64,
    k_t: f64,
    support: &StageSupport<V>,
    t: f64,
    t_target: f64,
    [s, x, v]: [f64; 3],
) -> Option<ElasticEnd> {
    if c.config.drive != Drive::Force || s.abs() >= s_ba || t >= t_target {
        return None;
    }
    let (amp, omega, phase, c0, c1) = support.along_x(t);
    let forcing = Forcing {
        d0: c.dynamics.drive_inputs(t).f_d,
        d1: c.dynamics.tracks[InputId::FD.index()].slope,
        amp,
        omega,
        phase,
        c0,
        c1,
    };
    elastic_step(s, x, v, t_target - t, k_t, c.params.m, s_ba, &forcing)
}

/// Advances the explicit path to `t_target`: `∫F_F dt` over the call. Out of line: its walk
/// is the hot loop, and kept apart from the choice of path it runs about 3 % faster.
#[inline(never)]
fn advance_explicit<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
    c: &Shared<'_, V, L, D, N>,
    r: &mut Integrated<N>,
    k: &mut Kept<N>,
    t_target: f64,
    h_max: f64,
) -> Result<Quad, SimError> {
    let (relax, plastic) = branch_shape(c, k).expect("explicit path without a relaxation");
    let plastic = plastic.as_deref();
    let (len, k_t) = (relax.length, relax.stiffness);
    let (ix, iv) = (V::DIM, 2 * V::DIM);
    let inv_m = 1.0 / c.params.m;
    let tol = r.tolerance();
    let sc = Scales::new(c, tol, relax, plastic.is_some());
    let band = sc.band;
    let dynamics = *c.dynamics;
    let input_support = c.config.input_support;
    let vs = |t: f64| dynamics.support_velocity(t, input_support).x();
    let mut body = [0.0; 4];
    body[..D::N_BODY].copy_from_slice(&r.y.as_slice()[V::DIM..]);
    let accel = move |t: f64, x: f64, v: f64, f: f64| {
        let mut b = body;
        b[0] = x;
        b[V::DIM] = v;
        let d = dynamics.drive_inputs(t);
        (dynamics.drive.drive_force(&b[..D::N_BODY], &d) - f) * inv_m
    };

    let mut t = r.t;
    let mut support = StageSupport::new(&dynamics, input_support, t);
    let y0 = r.y;
    let (mut s, mut x, mut v) = (y0[0], y0[ix], y0[iv]);
    let vr0 = v - vs(t);
    let mut sigma = k.explicit.direction;
    if sigma == 0.0 || sigma * vr0 < -band {
        // A new branch: `v_r`'s sign, or, at `v_r` = 0, the push's.
        sigma = if vr0 != 0.0 {
            vr0.signum()
        } else if accel(t, x, v, k_t * s) < 0.0 {
            -1.0
        } else {
            1.0
        };
    }
    let mut integral = 0.0;
    let limit = r.step_limit;
    if let Some(end) = plastic.and_then(|shape| {
        elastic_call(c, shape.r_ba() * len, k_t, &support, t, t_target, [s, x, v])
    }) {
        (s, x, v) = (end.s, end.x, end.v);
        integral += end.impulse;
        t = t_target;
        r.stats.steps += 1;
        if end.v_r != 0.0 {
            sigma = end.v_r.signum();
        }
    }
    let mut w = Walk {
        t,
        s,
        x,
        v,
        sigma,
        h: k.h,
        integral,
    };
    let calls = (&accel, &vs, t_target, h_max, limit);
    walk(&mut w, &sc, plastic, &mut support, &mut r.stats, calls)?;
    let Walk {
        s,
        x,
        v,
        sigma,
        h,
        integral,
        ..
    } = w;
    let mut y = r.y;
    y[0] = s;
    y[ix] = x;
    y[iv] = v;
    c.finish(r, t_target, y);
    k.propose(h);
    k.explicit.direction = sigma;
    Ok([integral, 0.0])
}

/// Where the explicit path's walk along the branches is: the time, `[s, x, v]`, the branch,
/// the proposed step and `∫F_Fx dt` so far.
#[derive(Clone, Copy)]
struct Walk {
    t: f64,
    s: f64,
    x: f64,
    v: f64,
    sigma: f64,
    h: f64,
    integral: f64,
}

/// The body's acceleration at `(t, x, v)` under the force `f` from the contact, the support
/// velocity along x at `t`, the target, the largest step and the work limit.
type Calls<'f, A, S> = (&'f A, &'f S, f64, f64, u64);

/// The explicit path's steps from `state` to the call's end (`state` updated) with the error scales
/// `sc` on Dupont's `plastic` shape, if any, the support's stage velocities `support` and the
/// counts `stats`.
#[inline(always)]
fn walk<V: Vector, A: Fn(f64, f64, f64, f64) -> f64, S: Fn(f64) -> f64>(
    state: &mut Walk,
    sc: &Scales,
    plastic: Option<&ElastoPlastic>,
    support: &mut StageSupport<V>,
    stats: &mut SolverStats,
    calls: Calls<'_, A, S>,
) -> Result<(), SimError> {
    let (accel, vs, t_target, h_max, limit) = calls;
    let Walk {
        mut t,
        mut s,
        mut x,
        mut v,
        mut sigma,
        mut h,
        mut integral,
    } = *state;
    let (tol, len, k_t, band) = (sc.tol, sc.len, sc.k_t, sc.band);
    let mut fsal: Option<[f64; 4]> = None;
    // The end of a step retaken to end on an event, and whether the event is a reversal
    // (else Dupont's breakaway, where the deformation turns plastic).
    let mut event_target: Option<f64> = None;
    let mut reversal = false;
    let mut rejected = false;
    while t < t_target {
        attempts::within_limit(stats, limit, t)?;
        let s0 = s;
        let branch = Branch::new(s0, sigma, len, plastic);
        let u0 = [0.0, x, v, 0.0];
        let k1 = match fsal {
            Some(k) => k,
            None => {
                stats.rhs_evals += 1;
                let f = k_t * s0;
                let w = support.now(t);
                [v - w, v, accel(t, x, v, f), f]
            }
        };
        attempts::finite_start(&k1, t)?;
        if h <= 0.0 {
            h = sc.first_step(&k1, h_max);
        }
        let mut hh = h.min(h_max);
        if event_target.is_none() {
            let (vr, ar) = (k1[0], k1[2] - support.accel_now(t));
            hh = short_of_events(hh, sigma * vr, sigma * ar, &branch, len);
        }
        let mut last = false;
        if let Some(te) = event_target {
            hh = te - t;
            last = te >= t_target;
        } else if t + 1.0001 * hh >= t_target {
            hh = t_target - t;
            last = true;
        }
        attempts::size_resolved(last, hh, t)?;
        // The support velocity at the stage times, and the deformation the right-hand side
        // finds at each (the last one is the step's end).
        let vs_at = support.stages(t, hh).map(|w| w.x());
        let mut s_at = [s0; 7];
        let mut rhs = |i: usize, tt: f64, u: &[f64; 4]| {
            let si = branch.at(u[0]);
            s_at[i] = si;
            let f = k_t * si;
            let w = vs_at[i];
            [u[2] - w, u[2], accel(tt, u[1], u[2], f), f]
        };
        let step = DoPriStep::take_staged(&mut rhs, t, &u0, &k1, hh);
        stats.rhs_evals += 6;
        let u1 = step.end();
        // `dv_r/dt` at the step's end, from the last two stages' `v_r`.
        let vr_rate_end = || (step.k[6][0] - step.k[4][0]) / ((1.0 - C[4]) * hh);
        // Short of the call's end the deformation's error counts by what it leaves.
        let ahead = (!last && tol <= WEIGH_UP_TO).then(|| (t_target - (t + hh), vr_rate_end()));
        let err = sc.error(&step, &u1, &branch, [s0, x, v, s_at[6]], sigma, ahead);
        let err = attempts::finite_error(err, &u1);
        if err > 1.0 {
            h = attempts::rejected(stats, hh, err);
            event_target = None;
            rejected = true;
            fsal = Some(k1);
            continue;
        }
        // An event inside the step: retake the step to end on it (a reversal at the step's end
        // is there).
        if event_target.is_none() {
            if let Some(event) = event_in(&step, &vs_at, vs, &branch, band, t, hh) {
                fsal = Some(k1);
                let theta = match event {
                    Event::AtStart => {
                        // The reversal is at the step's start: the other branch from here.
                        // The attempt counts as rejected, so the work limit bounds any
                        // repetition.
                        sigma = -sigma;
                        stats.events += 1;
                        stats.rejected += 1;
                        continue;
                    }
                    Event::Reversal(theta) => {
                        reversal = true;
                        theta
                    }
                    Event::Breakaway(theta) => {
                        reversal = false;
                        theta
                    }
                };
                if theta < 1.0 || !reversal {
                    event_target = Some(t + theta * hh);
                    h = hh;
                    continue;
                }
                event_target = Some(t + hh);
            }
        }
        stats.steps += 1;
        s = s_at[6];
        x = u1[1];
        v = u1[2];
        integral += u1[3];
        t = if last { t_target } else { t + hh };
        fsal = Some(step.k[6]);
        if s.abs() > len {
            s = len.copysign(s);
            fsal = None;
        }
        // The event the step ended on: a reversal (the other branch from here) or the
        // breakaway.
        let ended_on = event_target.take().map(|_| reversal);
        if ended_on == Some(true) {
            sigma = -sigma;
            stats.events += 1;
        }
        let relax_first = || RELAX_FIRST * (2.0 * len / vr_rate_end().abs()).sqrt();
        h = size_after(hh, h, err, rejected, ended_on, last, relax_first);
        rejected = false;
    }
    *state = Walk {
        t,
        s,
        x,
        v,
        sigma,
        h,
        integral,
    };
    Ok(())
}

/// The size proposed after an accepted step of length `hh` (`h` proposed before it) with the
/// scaled error `err`, `rejected` whether an attempt before it was, `ended_on` the event it
/// ended on (a reversal: `true`; the breakaway: `false`), `last` whether it ended the call,
/// `relax_first` the first step's share of the new branch's relaxation.
#[inline(always)]
fn size_after(
    hh: f64,
    h: f64,
    err: f64,
    rejected: bool,
    ended_on: Option<bool>,
    last: bool,
    relax_first: impl FnOnce() -> f64,
) -> f64 {
    let mut h_new = hh * factor(err);
    if rejected {
        h_new = h_new.min(hh);
    }
    match ended_on {
        // Just past the breakaway: on along the same branch, with no longer a step than
        // was proposed before it (the plastic part bends at once).
        Some(false) => h_new = h_new.min(h),
        // The reversal: the step that ended on it was clipped and says little about the
        // step size. The new branch relaxes over one s_ss of relative displacement, which
        // from rest takes sqrt(2·s_ss/|dv_r/dt|): the first step a fraction of that (a stiff
        // contact would otherwise pay for it in rejected steps).
        Some(true) => {
            h_new = h_new.max(h);
            let relax = relax_first();
            if relax.is_finite() && relax > 0.0 {
                h_new = h_new.min(relax);
            }
        }
        None if last && hh < h => h_new = h_new.max(h),
        None => {}
    }
    h_new
}

/// A step's length `hh` cut a little past the next event where it heads for one at the relative
/// velocity `u = σ·v_r` and its rate of change `w = σ·dv_r/dt`: a reversal (a step far across
/// it is wasted: against the branch the deformation swings by 2·s_ss within a few s_ss of
/// relative displacement), where `v_r` would vanish at its present rate of change; Dupont's
/// breakaway, where the elastic room of the branch would be used up.
#[inline(always)]
fn short_of_events(hh: f64, u: f64, w: f64, branch: &Branch, len: f64) -> f64 {
    let mut hh = hh;
    if u > 0.0 && w < 0.0 {
        hh = hh.min(PAST_REVERSAL * (-u / w));
    }
    if let Some(room) = branch.room() {
        let d = room * len;
        // The root of `u·τ + w·τ²/2 = d`, in the form that is exact for `w = 0`.
        let disc = u * u + 2.0 * w * d;
        let tau = 2.0 * d / (u + disc.max(0.0).sqrt());
        if u > 0.0 && disc >= 0.0 && tau > BREAKAWAY_AT_START * hh {
            hh = hh.min(PAST_BREAKAWAY * tau);
        }
    }
    hh
}

/// What a step's error is scaled with: the nominal `s`, `x`, `v`, the relative tolerance,
/// `k_t`, `1/m` and `s_ss`.
struct Scales {
    nom: [f64; 3],
    tol: f64,
    rtol: f64,
    k_t: f64,
    inv_m: f64,
    len: f64,
    /// How far `σ·v_r` falls below 0 before a reversal counts (the module's docs).
    band: f64,
}

impl Scales {
    /// For the contact `c` at the tolerance `tol` on the branches of `relax`, `plastic` with
    /// Dupont's breakaway.
    fn new<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
        c: &Shared<'_, V, L, D, N>,
        tol: f64,
        relax: Relaxation,
        plastic: bool,
    ) -> Self {
        let (len, k_t) = (relax.length, relax.stiffness);
        let inv_m = 1.0 / c.params.m;
        let fraction = if plastic {
            DUPONT_TOL_FRACTION
        } else {
            TOL_FRACTION
        };
        let band = 0.05 * tol * len * (k_t * inv_m).sqrt();
        Scales {
            nom: [c.scale[0], c.scale[V::DIM], c.scale[2 * V::DIM]],
            tol,
            rtol: (fraction * tol).max(1e-14),
            k_t,
            inv_m,
            len,
            band: if band.is_finite() { band } else { 0.0 },
        }
    }

    /// The first step's size from the first stage `k1`, at most `h_max`.
    fn first_step(&self, k1: &[f64; 4], h_max: f64) -> f64 {
        let [nom_s, nom_x, nom_v] = self.nom;
        let d =
            ((k1[0] / nom_s).powi(2) + (k1[1] / nom_x).powi(2) + (k1[2] / nom_v).powi(2)).sqrt();
        first_step(d, self.tol, h_max)
    }

    /// The scaled error of a step on `branch` from `[s0, x, v]` to the end `s1` (the
    /// deformation) on the branch `sigma`; `ahead`, where the step ends short of its call's
    /// end (by the time given, with `dv_r/dt` at the step's end), weighs the deformation's
    /// error by what it leaves ([`PUSH_MARGIN`]): it relaxes along the branch (after Dupont's
    /// elastic room), having pushed the body by at most `(k_t/m)·δξ·|σ·s_ss − s|/|v_r|` in
    /// velocity (the force error `k_t·ds/dξ·δξ` over the time `∫ds/dξ dξ/|v_r|` the branch
    /// takes to relax); what is left of it at the call's end, after the relative
    /// displacement `reach` still ahead (up to a reversal), is its share of the output's
    /// error there.
    #[inline(always)]
    fn error(
        &self,
        step: &DoPriStep<4>,
        u1: &[f64; 4],
        branch: &Branch,
        [s0, x, v, s1]: [f64; 4],
        sigma: f64,
        ahead: Option<(f64, f64)>,
    ) -> f64 {
        let ([nom_s, nom_x, nom_v], rtol) = (self.nom, self.rtol);
        let slope = branch.slope(u1[0]);
        let v_scale = nom_v + v.abs().max(u1[2].abs());
        let mut e_s = step.err[0] * slope / (rtol * (nom_s + s0.abs()));
        if let Some((time_ahead, ar)) = ahead {
            let vr = step.k[6][0];
            let reach = reach_ahead(vr.abs(), sigma * ar, time_ahead);
            let pushed =
                PUSH_MARGIN * step.err[0] * self.k_t * self.inv_m * (sigma * self.len - s1).abs()
                    / (vr.abs() * rtol * v_scale);
            e_s = weighed(e_s.abs(), pushed.abs(), || branch.kept(u1[0], reach));
        }
        let e = [
            e_s,
            step.err[1] / (rtol * (nom_x + x.abs().max(u1[1].abs()))),
            step.err[2] / (rtol * v_scale),
        ];
        ((e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) / 3.0).sqrt()
    }
}

/// A step's deformation error `err` (scaled, at least 0) weighed by what it leaves, here and
/// on the planar path ([`PUSH_MARGIN`]): given `pushed`, the velocity it pushes into the body
/// on the same scale, and `left`, the fraction of it still in the deformation at the call's
/// end, it counts as `max(err·left, pushed)` where `pushed < err`, else (or where `pushed` is
/// NaN) as `err`.
#[inline(always)]
pub(super) fn weighed(err: f64, pushed: f64, left: impl FnOnce() -> f64) -> f64 {
    if pushed < err {
        (err * left()).max(pushed)
    } else {
        err
    }
}

/// How far a positive quantity, now `x` and changing at `rate`, integrates over the time
/// `ahead`: `x·ahead`, or where it falls, at most what it integrates to before it would vanish
/// at that rate, `x²/(2·|rate|)`. On the explicit paths, the relative displacement (`x = |v_r|`)
/// or the relaxation arc length (`x = |v_r|/s_ss`) still ahead of a call's end, short of a
/// reversal.
#[inline(always)]
pub(super) fn reach_ahead(x: f64, rate: f64, ahead: f64) -> f64 {
    if rate >= 0.0 {
        x * ahead
    } else {
        (x * ahead).min(0.5 * x * x / -rate)
    }
}

/// The right-hand side's one elementary function (in the physics layer, beside the `exp` of
/// the same kernel that LuGre's velocity terms take).
pub(super) use crate::physics::trig::expm1;

mod branch;

pub(super) use branch::root;
use branch::{event_in, Branch, Event};
