//! The planar explicit path's steps: the loop of error control, sign changes of `v_rx` and
//! the bridges across them, the step kinds (plain, exponential, on the Coulomb limit), and
//! how the deformation's error is weighed.

use super::super::attempts;
use super::exponential_step::exponential_step;
use super::rhs::{relative_velocity, Eqs, Kin, Relax};
use super::*;

/// What one call of [`steps`](fn@steps) works with: the system, its right-hand side, the
/// manifold's step where it applies, and the error control's settings.
struct Call<'s, 'a, V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize> {
    sys: &'s System<'a, V, L, D>,
    eqs: Eqs<'s, 'a, V, L, D, N, M>,
    manifold: Option<Limit<'s, 'a, V, L, D>>,
    tol: f64,
    t_target: f64,
    rtol: f64,
    /// The relaxation over a step from which it is an exponential step.
    exponential_from: f64,
    /// Whether a step's deformation error is weighed by what it leaves ([`settled`]).
    weigh: bool,
    /// Whether an exponential step's λ error is weighed by how far it moves the deformation
    /// ([`LAMBDA_BY_MOVES_FROM`]).
    by_moves: bool,
    /// What a deformation error pushes into the body per unit of time ([`settled`]).
    push: f64,
}

impl<'s, 'a, V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize>
    Call<'s, 'a, V, L, D, N, M>
{
    fn new(sys: &'s System<'a, V, L, D>, run: &Run) -> Self {
        let tol = run.tol;
        // Dupont's elastic part keeps each step's error where the relaxation of the others
        // damps it: its tighter fraction, as on the 1-D path (VibratingContactDupont across the
        // sliding direction, 50 ms at 1e-6: `F_Fx` 2.7e-7 of `F_C` off Radau at 1e-12 at 0.03,
        // 1.4e-6 at 0.1, in 12 % more time; at 0.5 rad 8.5e-6 against 3.0e-5, Radau at 1e-6
        // 2.0e-5).
        let fraction = match sys.dynamics.law.breakaway() {
            Some(_) => DUPONT_TOL_FRACTION,
            None => TOL_FRACTION,
        };
        let rtol = (fraction * tol).max(1e-14);
        let dynamics = sys.dynamics;
        // What a deformation error pushes into the body per unit of time, on the scale of the
        // errors: `(k_t/m)·(s_nom + |s|)/v_nom`, the velocity's nominal the body's last
        // component's; Dahl's contact only (`weigh`).
        // (RigTransverse at tolerance 1e-6, 0.1 s: 42.4 steps per period against 49.4 with the
        // deformation's own error, `F_Fx` 1.3e-8 and `F_Fy` 2.2e-6 of `F_C` from Radau at
        // 1e-11 against 3.7e-8 and 5.9e-6.)
        Call {
            sys,
            eqs: Eqs {
                sys,
                relax: Relax::new(dynamics.law),
            },
            manifold: Limit::new(sys, rtol),
            tol,
            t_target: run.t_target,
            rtol,
            exponential_from: EXPONENTIAL_FROM.min(EXPONENTIAL_REACH * libm::pow(rtol, 0.2)),
            weigh: dynamics.law.relaxation().is_some() && tol <= WEIGH_UP_TO,
            by_moves: dynamics.law.relaxation().is_none()
                && dynamics.law.breakaway().is_none()
                && (LAMBDA_BY_MOVES_FROM..=WEIGH_UP_TO).contains(&tol),
            push: run.push * (sys.scale[0] + dynamics.law.envelope()) / sys.scale[N - 1],
        }
    }
}

/// One attempt of [`steps`](fn@steps): its length and whether it ends the call, its scaled
/// error (infinite where anything is not finite), its end and the right-hand side there, whether it
/// was on the manifold or exponential, the sign change of `v_rx` it crosses, and, where it
/// ends on a cut, the bridge after it.
struct Attempt<const M: usize> {
    hh: f64,
    last: bool,
    err: f64,
    u1: [f64; M],
    k_end: [f64; M],
    limited: bool,
    exponential: bool,
    crossing: Option<f64>,
    bridge: Option<f64>,
}

/// The path's steps from `(t, y)` to `run.t_target` on the system `sys` of state width `N`
/// (`y` updated), integrating `M` components (the state, the `V::DIM` components of `∫F_F dt`,
/// λ, and zeros to the width: [`M_PLANAR`] for every planar state): `∫F_F dt` over the call.
pub(super) fn steps<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize>(
    sys: &System<'_, V, L, D>,
    run: &mut Run,
    t: f64,
    y: &mut [f64],
) -> Result<Quad, SimError> {
    debug_assert!(M > N + V::DIM);
    let call = Call::<V, L, D, N, M>::new(sys, run);
    let Run {
        tol,
        t_target,
        h_max,
        limit,
        ..
    } = *run;
    // λ's component (the last but for a planar state shorter than the largest).
    let il = N + V::DIM;
    let scale = sys.scale;
    let bound = sys.dynamics.law.bound();
    let mut t = t;
    let mut u = [0.0; M];
    u[..N].copy_from_slice(y);
    let mut integral = [0.0; 2];
    let mut h = run.h;
    let mut fsal: Option<[f64; M]> = None;
    let mut rejected = false;
    // The end of a step retaken to end just past a sign change of `v_rx` on the x axis.
    // With whether it was located on an accepted step's extension.
    let mut cut: Option<(f64, bool)> = None;
    let stats = &mut run.stats;
    // The support velocity at the stage times by rotations of the harmonic phase.
    let mut support = StageSupport::<V>::new(sys.dynamics, sys.input_support, t);
    // The last accepted step on the manifold, with its error, while the steps stay on it.
    let mut on_manifold: Option<(f64, f64)> = None;
    // The plain steps' stages and derivatives, taken in place step after step.
    let mut plain = DoPriStep::zeros();
    while t < t_target {
        attempts::within_limit(stats, limit, t)?;
        u[N..].fill(0.0);
        let k1 = match fsal {
            Some(k) => k,
            None => {
                stats.rhs_evals += 1;
                call.eqs.rhs(t, &u)
            }
        };
        attempts::finite_start(&k1, t)?;
        if h <= 0.0 {
            let d = (0..N)
                .map(|i| (k1[i] / scale[i]).powi(2))
                .sum::<f64>()
                .sqrt();
            h = first_step(d, tol, h_max);
        }
        let mut hh = h.min(h_max);
        let mut last = false;
        if let Some((te, _)) = cut {
            hh = te - t;
        } else if t + 1.0001 * hh >= t_target {
            hh = t_target - t;
            last = true;
        }
        attempts::size_resolved(last, hh, t)?;
        let a = attempt(
            &call,
            stats,
            &mut support,
            &mut plain,
            t,
            &u,
            &k1,
            hh,
            last,
            cut,
        );
        let hh = a.hh;
        if a.err > 1.0 {
            h = attempts::rejected(stats, hh, a.err);
            rejected = true;
            // A sign change within the next step: the next step ends just past it.
            cut = a.crossing.filter(|&te| te - t <= h).map(|te| (te, false));
            fsal = Some(k1);
            continue;
        }
        if let Some(te) = a.crossing {
            cut = Some((te, true));
            h = hh;
            fsal = Some(k1);
            continue;
        }
        stats.steps += 1;
        stats.limit_steps += a.limited as u64;
        let mut u1 = a.u1;
        u1[il] = 0.0;
        integral[0] += u1[N];
        if V::DIM == 2 {
            integral[1] += u1[N + 1];
        }
        u = u1;
        // After an exponential step the end's deformation is not the last stage's (after a
        // step on the manifold it is).
        fsal = (!a.exponential || a.limited).then_some(a.k_end);
        t = if a.last { t_target } else { t + hh };
        // |s| ≤ s_ss holds for the equation; the step may overshoot it by its error.
        if let Some(b) = bound {
            let s = V::read(&u[..V::DIM]);
            let n = s.norm();
            if n > b {
                (s * (b / n)).write(&mut u[..V::DIM]);
                fsal = None;
            }
        }
        let mut h_new = next_size(hh, a.err, rejected, on_manifold.filter(|_| a.limited));
        on_manifold = a.limited.then_some((hh, a.err.max(PREDICT_FLOOR)));
        rejected = false;
        if (a.last || cut.is_some()) && hh < h {
            // A step clipped to the target or to a sign change says little about the size
            // (keeping the size proposed before it instead cost more on VibratingContactLuGre at
            // 1e8, tolerance 1e-6: 42.6 steps per period against 41).
            h_new = h_new.max(h);
        }
        cut = a.bridge.map(|te| (te, true));
        h = h_new;
    }
    y.copy_from_slice(&u[..N]);
    run.h = h;
    Ok(integral)
}

/// One attempt of length `hh` from `(t, u)` with the first derivative `k1` (`last`: it ends
/// the call; `cut`: it ends on a sign change of `v_rx`): on the manifold, exponential or
/// plain, its error, the sign change it crosses and the bridge after it.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn attempt<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize>(
    call: &Call<'_, '_, V, L, D, N, M>,
    stats: &mut SolverStats,
    support: &mut StageSupport<V>,
    plain: &mut DoPriStep<M>,
    t: f64,
    u: &[f64; M],
    k1: &[f64; M],
    mut hh: f64,
    mut last: bool,
    cut: Option<(f64, bool)>,
) -> Attempt<M> {
    let (sys, eqs, rtol) = (call.sys, &call.eqs, call.rtol);
    let scale = sys.scale;
    let il = N + V::DIM;
    // The largest scaled error of the deformation's components, and of the rest.
    let mut err_s: f64 = 0.0;
    let mut err: f64 = 0.0;
    // `v_r` at the stages of the step taken (of its last pass).
    let mut vr_at = [V::default(); 7];
    let exponential = k1[il] * hh >= call.exponential_from;
    // Where a stiff contact's deformation is certified on its slow manifold (planar Dahl,
    // LuGre on the x axis), the body alone (`coulomb_limit.rs`), the step cut to the
    // start's reach (no sign change of `v_r` within it); else the exponential step. The
    // 1-D stage support velocities below are for the step as cut.
    let start = match &call.manifold {
        Some(m) if exponential && cut.is_none() => {
            m.start::<N>(t, u).filter(|st| st.reach >= REACH_CUT * hh)
        }
        _ => None,
    };
    if let Some(st) = &start {
        if st.reach < hh {
            hh = st.reach;
            last = false;
        }
    }
    // The support velocity at the stage times by rotations of the harmonic phase
    // ([`StageSupport`]): in one dimension for every step, in the plane for a plain step
    // (the exponential and manifold steps there take it at each stage themselves).
    let stage_support = (V::DIM == 1 || !exponential).then(|| support.stages(t, hh));
    // What the right-hand side needs at stage `i` of the step, time `tt`.
    let kin_stage = |i: usize, tt: f64, y: &[f64; M]| match &stage_support {
        Some(w) => Kin::with_support(sys, &eqs.relax, tt, &y[..N], w[i]),
        None => eqs.kin(tt, y),
    };
    // `v_r` at the step's start.
    let vr_start = || match &stage_support {
        Some(w) => {
            let d = sys.dynamics.drive_inputs(t);
            sys.dynamics.drive.velocity(&u[V::DIM..N], &d) - w[0]
        }
        None => relative_velocity::<V, L, D, N, M>(sys, t, u),
    };
    let mut limit_evals = 0;
    let on_limit = match (&call.manifold, &start) {
        (Some(m), Some(st)) => m.step::<N, M>(st, t, u, k1, hh, |i, tt, y, s| {
            limit_evals += 1;
            let k = eqs.kin(tt, y);
            vr_at[i] = k.vr;
            eqs.rhs_with(y, s, &k)
        }),
        _ => None,
    };
    let limited = on_limit.is_some();
    // A step on the manifold counts its stages below with every other step's; an
    // attempt the certificate refused, and a first stage moved onto the manifold, here.
    stats.rhs_evals += limit_evals - if limited { 6 } else { 0 };
    let exp_step;
    let (step, u1) = if let Some((step, u1)) = &on_limit {
        // The deformation's error: the manifold's under the body's.
        err = scaled_error(err, &step.err, u, u1, scale, rtol, 0..V::DIM);
        (step, *u1)
    } else if exponential {
        let (step, u1, e_s, e, second) = exponential_step(
            eqs,
            &kin_stage,
            t,
            u,
            k1,
            hh,
            rtol,
            scale,
            call.by_moves,
            &mut vr_at,
        );
        if second {
            stats.rhs_evals += 6;
        }
        (err_s, err) = (e_s, e);
        exp_step = step;
        (&exp_step, u1)
    } else {
        let mut stage = |i: usize, tt: f64, y: &[f64; M]| -> [f64; M] {
            let k = kin_stage(i, tt, y);
            vr_at[i] = k.vr;
            eqs.rhs_with(y, V::read(&y[..V::DIM]), &k)
        };
        plain.retake(&mut stage, t, u, k1, hh);
        let u1 = plain.end();
        err_s = scaled_error(err_s, &plain.err, u, &u1, scale, rtol, 0..V::DIM);
        (&*plain, u1)
    };
    stats.rhs_evals += 6;
    err = scaled_error(err, &step.err, u, &u1, scale, rtol, V::DIM..N);
    // Short of the call's end a step's deformation error counts by what it leaves
    // ([`settled`]; Dahl's only: LuGre's force also takes `ds/dt`, whose error is not
    // left behind the same way). An
    // exponential step's, its interpolation's, is in the force all along the step: the
    // push's `h`; down to the tolerance [`WEIGH_EXPONENTIAL_DOWN_TO`].
    if !last && call.weigh && (!exponential || call.tol >= WEIGH_EXPONENTIAL_DOWN_TO) {
        err_s = settled(
            err_s,
            (k1[il], step.k[6][il]),
            hh,
            call.t_target - (t + hh),
            call.push,
        );
    }
    let err = attempts::finite_error(err.max(err_s), &u1);
    // On the x axis (no lateral relative velocity) `|v_r|`, and with it the rates, has a
    // kink wherever `v_rx` changes sign, on which the error estimate of a step across it
    // is not to be trusted: the step is retaken to end just past the sign change (located
    // on the continuous extension), so that the kink falls between steps. A step that ends
    // on a sign change located on a rejected step's extension is checked again.
    let crossing = if cut.is_none_or(|(_, trusted)| !trusted) {
        sign_change::<V, L, D, N, M>(sys, t, hh, vr_start(), &vr_at, step)
    } else {
        None
    };
    // A step that ends on a sign change of `v_rx` may end a little short of it.
    let bridge = match cut {
        Some(_) if !last && err <= 1.0 && crossing.is_none() => {
            bridge(t, hh, vr_start().x(), &vr_at, call.t_target)
        }
        _ => None,
    };
    Attempt {
        hh,
        last,
        err,
        u1,
        k_end: step.k[6],
        limited,
        exponential,
        crossing,
        bridge,
    }
}

/// The largest of `err` and the errors `e` of components `range` of a step from `u` to `u1`,
/// each against `rtol` times its scale plus its magnitude.
#[inline(always)]
fn scaled_error(
    err: f64,
    e: &[f64],
    u: &[f64],
    u1: &[f64],
    scale: &[f64],
    rtol: f64,
    range: std::ops::Range<usize>,
) -> f64 {
    range.fold(err, |err, c| {
        let w = rtol * (scale[c] + u[c].abs().max(u1[c].abs()));
        err.max((e[c] / w).abs())
    })
}

/// Where the step after an accepted one of length `hh` from `t`, which ended on a sign change
/// of `v_rx` located on a continuous extension, is to end when that one ended a little short
/// of the sign change (by the extension's error), `vr0` and `vr_at` its `v_rx` at its start
/// and stages: a bridge across the rest, twice the time `v_rx` takes to vanish at its rate at
/// the end (at least a few units of the time's resolution), where that is a sliver of the
/// step ([`BRIDGE`]) and short of the call's end `t_target`; `None` where the step ended past
/// it.
fn bridge<V: Vector>(t: f64, hh: f64, vr0: f64, vr_at: &[V; 7], t_target: f64) -> Option<f64> {
    let vr1 = vr_at[6].x();
    let dvr = (vr1 - vr_at[4].x()) / ((1.0 - C[4]) * hh);
    let b = -2.0 * vr1 / dvr;
    let b = (b > 0.0).then(|| b.max(64.0 * f64::EPSILON * (t + hh).abs()));
    b.filter(|&b| vr0 * vr1 > 0.0 && b <= BRIDGE * hh && t + hh + b < t_target)
        .map(|b| t + hh + b)
}

/// The size proposed after an accepted step of length `hh` with the scaled error `err`
/// (`rejected` whether an attempt before it was), and where that step and the last accepted
/// one were both on the manifold, that one's length and error (`on_manifold`).
///
/// The plain controller, `hh·0.9·err^(−1/5)`, at most `hh` after a rejection. Gustafsson's
/// proportional-integral one (DOPRI5's, with the last accepted error to the power β) was
/// measured on VibratingContactLuGre at `k_t` = 1e8, tolerance 1e-6: it cut the rejections
/// per period from 10.1 to 6.2 (β = 0.04) and 3.9 (0.08) but took more steps (41 to 46 and
/// 57), more attempts in all and more time; β = 0.02 likewise (44 steps, 8.9 rejections).
///
/// From one step on the manifold to the next, also Gustafsson's predictive step (RADAU5's,
/// `h·(h/h_prev)·(err_prev/err²)^(1/5)`, the errors at least [`PREDICT_FLOOR`]), the smaller
/// of the two: there the error grows from step to step as `v_r` turns, and a step as long as
/// the last was rejected every other time (PaperTransverse at `k_t` = 1e12, tolerance 1e-6:
/// 4.0 rejected steps per period against 8.0, 164 right-hand sides against 188, `F_Fx` 1.3e-8
/// of `F_C` from Radau at 1e-11 as before; on every step, at 1e8 it cost
/// VibratingContactLuGre 8 % more right-hand sides).
fn next_size(hh: f64, err: f64, rejected: bool, on_manifold: Option<(f64, f64)>) -> f64 {
    let mut h_new = hh * factor(err);
    if rejected {
        h_new = h_new.min(hh);
    }
    if let Some((h_prev, err_prev)) = on_manifold {
        let e = err.max(PREDICT_FLOOR);
        // `factor` is 0.9·x^(−1/5).
        let predicted = hh * (hh / h_prev) * factor(e * e / err_prev) / 0.9;
        h_new = h_new.min(predicted.max(0.2 * hh));
    }
    h_new
}

/// Just past the first sign change of `v_rx` within a step of length `hh` from `t` on the x axis
/// (no lateral relative velocity at any stage), located on the step's continuous extension to
/// within 1e-9 of the bracketing stages' swing, given `v_r` at the step's start (`vr0`) and at
/// its stages (`vr_at`); `None` without one, or where it falls at the step's end or too near
/// its start to cut there.
fn sign_change<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize>(
    sys: &System<'_, V, L, D>,
    t: f64,
    hh: f64,
    vr0: V,
    vr_at: &[V; 7],
    step: &DoPriStep<M>,
) -> Option<f64> {
    let sigma = vr0.x().signum();
    let vr_i = |i: usize| if i == 0 { vr0 } else { vr_at[i] };
    let on_axis = vr0.y() == 0.0 && (1..7).all(|i| vr_i(i).y() == 0.0);
    let g = |i: usize| sigma * vr_i(i).x();
    match (1..7).find(|&i| g(i) < 0.0) {
        Some(i) if vr0.x() != 0.0 && on_axis => {
            let end = step.end();
            let dense = step.dense_all(hh);
            let gd = |theta: f64| {
                let mut z = end;
                for (j, zj) in z.iter_mut().enumerate().take(N).skip(V::DIM) {
                    *zj = dense.at(j, theta);
                }
                sigma * relative_velocity::<V, L, D, N, M>(sys, t + theta * hh, &z).x()
            };
            let (ga, gb) = (g(i - 1).max(0.0), g(i));
            // Just past the sign change: within 1e-9 of the bracket's swing.
            let theta =
                super::super::explicit::root(&gd, (C[i - 1], ga), (C[i], gb), 1e-9 * (ga - gb));
            let te = t + theta * hh;
            (theta < 1.0 && te > t + 16.0 * f64::EPSILON * t.abs().max(hh)).then_some(te)
        }
        _ => None,
    }
}

/// A deformation error `err_s` (scaled) of a step of length `h` that ends short of its call's
/// end (by `ahead`), weighed by what it leaves: it grew along the step (an exponential step's
/// is its interpolation's, estimated at the step's end and taken to have been of that size
/// all along: an assumption, borne out by the measurements at [`WEIGH_EXPONENTIAL_DOWN_TO`])
/// and relaxes after
/// it at the rate `dλ/dt = |v_r|/s_ss` in every direction (`rates` at the step's start and
/// end), having pushed the body by at most `(k_t/m)·δs·(h + 1/(dλ/dt))` in velocity (`push` is
/// `k_t/m` on the scale of the errors, with a margin); what is left of it at the call's end,
/// `exp(−λ)` over the time ahead (up to where the rate would vanish at its present rate of
/// change), is its share of the outputs' error there.
fn settled(err_s: f64, (r0, r1): (f64, f64), h: f64, ahead: f64, push: f64) -> f64 {
    let rate = r0.min(r1);
    let lambda = reach_ahead(r1, (r1 - r0) / h, ahead);
    // No rate to weigh by: `pushed` NaN or infinite, or the relaxation ahead unknown.
    let pushed = if lambda.is_finite() {
        err_s * push * (h + 1.0 / rate)
    } else {
        f64::NAN
    };
    // exp(−λ) below 1e-17 (λ > 40) leaves the push alone.
    let left = || {
        if lambda < 40.0 {
            trig::exp(-lambda)
        } else {
            0.0
        }
    };
    weighed(err_s, pushed, left)
}

#[cfg(test)]
mod tests {
    use super::{bridge, next_size, settled, BRIDGE, C, PREDICT_FLOOR};

    /// The step size proposed: `hh·0.9·err^(−1/5)` (within DOPRI5's bounds 0.2 and 10), at
    /// most `hh` after a rejection, and between steps on the manifold at most Gustafsson's
    /// predicted `hh·(hh/h_prev)·(err_prev/err²)^(1/5)` (at least `0.2·hh`).
    #[test]
    fn next_size_is_the_controllers() {
        let (hh, err): (f64, f64) = (2e-5, 0.32);
        let plain = hh * 0.9 * err.powf(-0.2);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * b;
        assert!(close(next_size(hh, err, false, None), plain));
        assert_eq!(next_size(hh, err, true, None), hh);
        assert!(close(next_size(hh, 1e-9, false, None), 10.0 * hh));
        assert!(close(next_size(hh, 1e9, false, None), 0.2 * hh));
        // The error grows from 0.1 to 0.32 over steps of the same length: the prediction,
        // (0.1/0.1024)^(1/5)·hh, is below the plain proposal.
        let predicted = hh * (0.1 / (err * err)).powf(0.2);
        assert!(predicted < plain);
        assert!(close(next_size(hh, err, false, Some((hh, 0.1))), predicted));
        // A falling error predicts a longer step than the plain one: the plain one stands.
        assert!(close(next_size(hh, err, false, Some((hh, 0.9))), plain));
        // Errors below the floor count as the floor.
        let floor = hh * (PREDICT_FLOOR / (PREDICT_FLOOR * PREDICT_FLOOR)).powf(0.2);
        assert!(floor < 10.0 * hh);
        let tiny = next_size(hh, 1e-9, false, Some((hh, PREDICT_FLOOR)));
        assert!(close(tiny, floor));
        // After a longer step the prediction shrinks by `hh/h_prev`.
        let shorter = predicted * hh / (1.5 * hh);
        assert!(close(
            next_size(hh, err, false, Some((1.5 * hh, 0.1))),
            shorter
        ));
        // A prediction below 0.2·hh (after a step ten times longer) is held there.
        let held = next_size(hh, err, false, Some((10.0 * hh, 0.1)));
        assert!(predicted * 0.1 < 0.2 * hh);
        assert!(close(held, 0.2 * hh));
    }

    /// The bridge across a sign change of `v_rx` that a step ended short of: for `v_rx`
    /// linear in time, twice the exact time to its root from the step's end, and none where
    /// the step ended past the root, where that is more than a sliver of the step, or where
    /// it would reach the call's end.
    #[test]
    fn bridge_crosses_the_rest_of_a_sign_change() {
        let (t, hh) = (0.25, 1e-5);
        let rate = -3.0;
        let root = t + hh + 2e-9;
        let vr = |tt: f64| rate * (tt - root);
        let vr_at = C.map(|ci| vr(t + ci * hh));
        let end = bridge(t, hh, vr(t), &vr_at, 1.0).unwrap();
        // The bridge's length, 4e-9, from velocities of about 3e-5 m/s that carry the times'
        // rounding (1e-17 s in 1e-5 s): to about 1e-8 of it.
        let length = end - (t + hh);
        assert!((length - 4e-9).abs() <= 1e-6 * 4e-9, "{length}");
        // Ended past the root (inside the step): no bridge.
        let early = |tt: f64| rate * (tt - (t + hh - 2e-9));
        let past = C.map(|ci| early(t + ci * hh));
        assert_eq!(bridge(t, hh, early(t), &past, 1.0), None);
        // The root farther ahead than a sliver of the step.
        let far = t + hh + BRIDGE * hh;
        let vr_far = |tt: f64| rate * (tt - far);
        assert_eq!(
            bridge(t, hh, vr_far(t), &C.map(|ci| vr_far(t + ci * hh)), 1.0),
            None
        );
        // The bridge would reach the call's end.
        assert_eq!(bridge(t, hh, vr(t), &vr_at, t + hh + 3e-9), None);
    }

    /// The weighed deformation error is never above the error itself, is the error where there
    /// is no rate to weigh by, and otherwise the larger of what the body keeps
    /// (`push·(h + 1/rate)` of it) and what is left at the call's end (`exp(−rate·ahead)` of
    /// it), with the relaxation ahead cut where the rate would vanish.
    #[test]
    fn settled_weighs_by_what_the_error_leaves() {
        let (err, h, push) = (0.8, 1e-5, 50.0);
        // No rate (a body at rest relative to the support) or none defined: the error as is.
        assert_eq!(settled(err, (0.0, 0.0), h, 1e-3, push), err);
        assert_eq!(settled(err, (f64::NAN, f64::NAN), h, 1e-3, push), err);
        // A steady rate of 2e4/s, 1e-4 s ahead: λ = 2, the push 50·(1e-5 + 5e-5) = 3e-3.
        let w = settled(err, (2e4, 2e4), h, 1e-4, push);
        let want = (err * (-2.0f64).exp()).max(err * push * (h + 1.0 / 2e4));
        assert!((w - want).abs() <= 1e-14 * want, "{w} vs {want}");
        // Far ahead the push alone.
        let w = settled(err, (2e4, 2e4), h, 1.0, push);
        assert!((w - err * push * 6e-5).abs() <= 1e-15, "{w}");
        // A rate falling by 1e9/s from 2e4 vanishes in 2e-5 s: λ ≤ 2e4²/(2·1e9) = 0.2 however
        // far the call's end.
        let w = settled(err, (2e4 + 1e4, 2e4), h, 1.0, push);
        assert!((w - err * (-0.2f64).exp()).abs() <= 1e-14, "{w}");
        // Where the push is the larger, the error as is.
        assert_eq!(settled(err, (10.0, 10.0), h, 1.0, push), err);
        for rates in [(1.0, 1e9), (1e9, 1.0), (3e3, 3e3)] {
            for ahead in [0.0, 1e-6, 1e-3] {
                assert!(settled(err, rates, h, ahead, push) <= err);
            }
        }
    }
}
