//! The explicit path of a moving body on a planar Dahl contact (`kappa = 1`): force or spring
//! drive, or a velocity drive with the lateral motion free, whenever the motion leaves the x
//! axis (on the axis the closed form of `explicit.rs` applies); on a planar LuGre contact,
//! on the axis or off it, or in longitudinal motion; and on a planar Dupont contact off the
//! axis (or on it with the lateral motion free, which `explicit.rs` does not take) at a
//! moderate stiffness ([`DUPONT_LIMIT`]), whose weight `alpha(s)` leaves its rate
//! without the form below: its plastic relaxation is one more component of the explicit
//! method, and its direction test `s·v_r > 0`, which switches that relaxation on and off (a
//! jump of the rate off the axis), is not located but left to the error control (a tighter
//! one, [`DUPONT_TOL_FRACTION`], as on the 1-D path). LuGre's rate has the same form,
//! `ds/dt = (|v_r|/g)·(q − s)` with `q = g·v_r/|v_r|`, its length `g(v_r)` depending on the relative velocity where Dahl's
//! `s_ss` is constant: `λ = ∫|v_r|/g dt` and `q` take that `g`, and the force (with its
//! damping `h_t·ds/dt`) follows from the deformation at each stage as in the general model.
//! A force- or spring-driven body whose motion stays on the x axis (no lateral deformation,
//! velocity or support motion: LuGre, since Dahl there takes `explicit.rs`) is integrated in
//! one dimension, `[s, x, v]` with `∫F_Fx dt` and λ, by the same code ([`steps`], generic in
//! the vector type and the widths); its lateral components stay 0 as the planar equations keep
//! them (the results were those of the planar integration to the last bit on
//! VibratingContactLuGre, 0.1 s at tolerances 1e-6 and 1e-8), and the support velocity at
//! the stages comes from rotations of the harmonic phase as on the 1-D path; so it does at
//! the stages of a plain step off the axis ([`StageSupport`]).
//! On the x axis `|v_r|` has a kink at each sign change of `v_rx`, across which a step's error
//! estimate is not to be trusted: such a step is retaken to end just past the sign change, and a
//! step rejected across one is retried to end there; one that ends a little short of it is
//! followed by a bridge across it ([`BRIDGE`]). The body, the integrals
//! `∫F_Fx dt`, `∫F_Fy dt` and the relaxation arc length `λ = ∫|v_r|/s_ss dt` are integrated by
//! Dormand–Prince 5(4) with error control on the state; the integrals ride along with the
//! fifth-order weights and do not steer the step.
//!
//! The deformation obeys `ds/dλ = q − s` in `λ`, with the target `q = s_ss·v_r/|v_r|`: it
//! relaxes at the rate `|v_r|/s_ss` in time, which at a stiff contact is far beyond any step
//! the body's motion asks for. Where a step spans a relaxation of [`EXPONENTIAL_FROM`] or more
//! (less at tight tolerances: [`EXPONENTIAL_REACH`]), `s` is advanced exactly for `q` interpolated in `λ` (a polynomial through six points):
//! `s = P(λ) + (s0 − P(0))·exp(−λ)`, `P` the polynomial particular solution, of the same cost
//! at any `k_t`. The stages of the explicit method know the body's velocity to low order only,
//! so the step is taken twice: the first pass interpolates `q` through the stages so far, the
//! second through six points of the first pass's continuous extension; the deformation at the
//! end comes from the second pass's extension, its error from the interpolant of one degree
//! less. Shorter steps integrate `s` as one more component of the explicit method.
//!
//! Dahl's and LuGre's deformation rate `v_r − |v_r|·s/s_ss` is Lipschitz continuous
//! everywhere (its kink where `v_r` passes through zero in the plane is a point, found by the
//! error control). While
//! the body sticks it sits on the contact as on a spring `k_t`: the explicit method then steps
//! at about `3/sqrt(k_t/m)`, which the error control finds by itself; the path is taken while
//! that allows enough steps per averaging window ([`STIFF_LIMIT`]), and Radau IIA takes the
//! rest.

mod coulomb_limit;

use super::explicit::{reach_ahead, weighed, DUPONT_TOL_FRACTION, PUSH_MARGIN, WEIGH_UP_TO};
use super::stage_support::StageSupport;
use super::{Kept, Path, Shared};
use crate::model::drive::{Axial, DriveInputs, DriveKind};
use crate::model::dynamics::{Eval, System};
use crate::model::simulator::SimError;
use crate::physics::{trig, FrictionLaw, Vector, VelocityTerms};
use crate::solver::dopri::{factor, first_step, Dense, DoPriStep, C};
use crate::solver::{Quad, Radau5, SolverError, SolverStats};
use coulomb_limit::Limit;

/// The largest width of the integrated vector: the state (6 in planar motion), the integrals
/// of the friction force's `V::DIM` components and the relaxation arc length
/// `λ = ∫|v_r|/s_ss dt` over the step. A motion on the x axis is integrated in one dimension
/// (`[s, x, v]`, `∫F_Fx dt`, λ: 5).
const M_PLANAR: usize = 9;

/// The same on the x axis.
const M_AXIAL: usize = 5;

/// The largest product of a Dupont contact's fastest rate off the x axis, its plastic
/// relaxation `|v_r|/s_ss` (at the relative velocity and the support's velocity amplitude) or
/// its stuck oscillation `sqrt(k_t/m)`, and the averaging window for which the planar explicit
/// path takes it, integrating the relaxation as one more component of the explicit method.
/// VibratingContactDupont with a transverse vibration (angle pi/2), 50 ms at tolerance 1e-6,
/// wall time on a shared machine, against Radau IIA: 5.9 ms against 13.5 at `k_t` = 3e8
/// (product 34), 11.1 against 14.8 at 1e9 (114), 16.7 against 15.3 at 2e9 (228), 21.3
/// against 15.2 at 3e9 (342); the largest `F_Fx` error against Radau at 1e-11 1.5e-8 to
/// 3.4e-8 of `F_C` on the path, 1.0e-7 to 3.8e-7 on Radau. At the limit both cost about the
/// same, the path ten times more accurate.
const DUPONT_LIMIT: f64 = 200.0;

/// The largest breakaway ratio `r_ba` of a Dupont contact the planar explicit path takes:
/// beyond it the weight `alpha` rises from the breakaway to `s_ss` so steeply that the
/// explicit steps cost more than Radau's. VibratingContactDupont at 1.2 rad, 20 ms at
/// tolerance 1e-6, wall time: 5.6 ms against Radau's 8.2 at 0.9, 12.9 against 10.3 at 0.95,
/// 26.4 against 15.6 at 0.98, 248 against 68 over 0.1 s at 0.999 (the default is 0.5).
const DUPONT_BREAKAWAY_MAX: f64 = 0.9;

/// The relaxation over a step (`|v_r|·h/s_ss` at its start) from which the deformation is
/// advanced exponentially in `λ` instead of as one more component of the explicit method. Below
/// it the explicit method is accurate and about four to five times cheaper per attempted step
/// (an exponential step is taken twice and interpolates: 1.8 against 0.44 µs on RigTransverse
/// at `k_t` = 1e12 and 1e8, CPU time; the plain step about 30 % less since it is taken in
/// place and its support velocity comes from rotations of the phase, [`StageSupport`]); at
/// the default `k_t` = 1e8 nearly every step is below it,
/// from about 1e10 on nearly every step above. Between 0.5 and 1 the exponential step took no
/// longer steps: VibratingContactLuGre (whose steps span 0.2 to 0.8 at 1e8) cost 48 µs per
/// period at tolerance 1e-6 with a threshold of 0.5 and 36 µs with 1, its `F_Fx` error against
/// Radau at 1e-12 9.98e-7 and 8.80e-7 of `F_C` (1e-8: 108 and 75 µs, 3.36e-9 both).
const EXPONENTIAL_FROM: f64 = 1.0;

/// At tight tolerances the threshold falls as `EXPONENTIAL_REACH·rtol^(1/5)`: a plain step's
/// error in a relaxing component grows as the fifth power of its relaxation, so the error
/// control holds plain steps below about 80–125 times `rtol^(1/5)` (PaperTransverse at
/// `k_t` = 1e11: a threshold of 0.5 was out of their reach at tolerance 1e-11, one of 1 at
/// 1e-10, and the steps shrank to 2.6e-8 s, two million per 50 ms); a third of that keeps the
/// exponential step within reach. At tolerance 1e-6 the threshold is still 1.
const EXPONENTIAL_REACH: f64 = 25.0;

/// A step on the Coulomb limit's manifold is cut to the reach of its start (no sign change of
/// `v_r` within it) down to this fraction of the step proposed; below, the exponential step.
const REACH_CUT: f64 = 0.2;

/// The longest step, as a fraction of the step before it, that bridges the rest of the way
/// to a sign change of `v_rx` on the x axis which that step, ending on the sign change as
/// located, fell short of. Without it the next step found the sign change at its very start
/// and was retaken twice to end on it (VibratingContactLuGre at 1e-6: the rest 2e-4 of the
/// next step, then 2e-9), four attempts at each reversal of `v_rx` instead of one; across a
/// step this short the kink of `|v_r|` changes the solution by far less than its error.
const BRIDGE: f64 = 1e-3;

/// The tightest tolerance at which an exponential step's deformation error is weighed by what
/// it leaves ([`settled`]), as a plain step's is. RigTransverse from rest at `k_t` = 1e12,
/// tolerance 1e-6, 0.1 s: 43.9 steps per period against 49.6 with the exponential steps' own
/// error, `F_Fx` and `F_Fy` 6.9e-8 and 7.0e-9 of `F_C` from Radau at 1e-11 against 6.9e-8 and
/// 6.6e-9 (1e-8: 10,294 steps against 12,712 over 30 ms, 5.8e-10 and 5.5e-11 against 6.1e-10
/// and 4.8e-11); the same steps at 1e8 and on PaperTransverse. At 1e-10 (`k_t` = 1e11) the
/// body's position drifted past ten tolerances of Radau at 1e-12.
const WEIGH_EXPONENTIAL_DOWN_TO: f64 = 1e-8;

/// The smallest error the predictive step size on the manifold takes from a step (smaller
/// errors say nothing about a trend).
const PREDICT_FLOOR: f64 = 1e-4;

/// The error control's tolerance as a fraction of the user's, on the largest scaled error of
/// the state's components: the global errors of `F_Fx` and `F_Fy` are then at or below
/// Radau's at the same tolerance (measured on PaperTransverse and RigTransverse against a
/// tolerance-1e-12 run, 0.05 s: at 1e-6, `F_Fx` 3.1e-9 and 3.6e-8 of `F_C` against Radau's
/// 3.0e-8 and 3.2e-8, `F_Fy` 2.9e-8 and 3.9e-7 against 3.5e-8 and 2.1e-6).
const TOL_FRACTION: f64 = 0.1;

/// The largest product of the oscillation rate of a stuck body, `sqrt(k_t/m)`, and the
/// averaging window for which the planar explicit path is taken: while the body sticks the
/// explicit method steps at about `3/sqrt(k_t/m)` (about 300 steps per window at the limit);
/// the relaxation `|v_r|/s_ss`, however fast, is advanced exponentially. At 2 kHz the limit
/// is beyond `k_t` = 1e13 for the default mass.
pub(super) const STIFF_LIMIT: f64 = 1000.0;

/// The largest product of the damping rate of a stuck body on a LuGre contact, `c/m` with `c`
/// the contact damping `2·zeta_t·sqrt(m·k_t)` plus `h_v`, and the averaging window for which the
/// planar explicit path is taken. Up to it the path was measured more accurate than Radau IIA
/// at the same tolerance (VibratingContactLuGre against Radau at 1e-12, 0.05 s, at `k_t` = 1e8
/// to 1e10, where the product is 4.2 to 42 at 2 kHz: at 1e-10, `F_Fx` 1.4e-11 to 8.5e-11 of `F_C` against
/// Radau's 5e-11 to 3.5e-9); at 1e11 (134) the window means of the exponential steps were 9
/// times less accurate than Radau's at 1e-10, and Radau takes such contacts off the x axis.
/// On the axis the path keeps them within [`AXIAL_DAMPED_LIMIT`], the sliding on the slow
/// manifold (`coulomb_limit.rs`): there, at `zeta_t` = 1, its `F_Fx` was more accurate than
/// Radau's at the same tolerance (1e-6 to 1e-8 at `k_t` = 1e11 and 1e12) and its cost 3.6
/// times less at 1e12.
const DAMPED_LIMIT: f64 = 100.0;

/// The largest [`DAMPED_LIMIT`]'s product for a LuGre contact whose body the vibration does not
/// keep sliding ([`Contact::vibration_unheld`]): while it sticks the explicit method steps at
/// the damping's stability bound. VibratingContactLuGre without vibration, `F_d` = 2 N (stuck),
/// 1 s at tolerance 1e-6, CPU time: 1.6 ms at `k_t` = 1e9 (product 13), 110 ms at 3e9 (23),
/// 143 ms at 1e10 (42) and, before this limit, 22 s at 1e12 (17.6 million steps); Radau IIA 4.2
/// to 4.5 ms at each.
const HELD_DAMPED_LIMIT: f64 = 20.0;

/// The largest [`DAMPED_LIMIT`]'s product for a LuGre contact on the x axis, whose damping
/// ratio must also be at most 1 (`c ≤ 2·sqrt(m·k_t)`, the viscous coefficient included): the
/// range measured (VibratingContactLuGre at `zeta_t` = 1, `k_t` up to 1e12, where the product is
/// 423 at 2 kHz). Beyond it the path was less accurate than Radau and could cost far more: at
/// `k_t` = 1e12, `zeta_t` = 30, tolerance 1e-6, `F_Fx` 9.2e-4 of `F_C` off Radau at 1e-10
/// against Radau's 9.3e-6 at 1e-6, in 11,401 steps over 5 ms against 4,878; at `zeta_t` = 1000
/// 1.3 million steps; at `k_t` = 1e13 (`zeta_t` = 1) the window mean 18 tolerances off against
/// Radau's 0.9.
const AXIAL_DAMPED_LIMIT: f64 = 500.0;

/// The tightest tolerance at which a LuGre contact on the x axis beyond [`DAMPED_LIMIT`] takes
/// the path: below it the body's global error grew beyond what Radau IIA keeps (at `k_t` =
/// 1e11 and tolerance 1e-9, the position 2.0e-13 m off Radau at 1e-12 after 5 ms, twenty
/// tolerances 1.7e-13; the window mean 2.1e-8 of `F_C`).
const DAMPED_AXIAL_TOL: f64 = 1e-8;

/// The planar explicit path.
pub(super) struct ExplicitPlanar;

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Path<V, L, D, N>
    for ExplicitPlanar
{
    /// True when this contact takes the planar explicit path: a planar Dahl contact with
    /// `kappa = 1`, a LuGre contact (planar or longitudinal) or a planar Dupont contact off the
    /// x axis, at a constant load, whose body moves (force, spring or free lateral motion),
    /// whose stuck oscillation is not fast on the scale of the averaging window
    /// ([`STIFF_LIMIT`]; with LuGre's contact damping, [`DAMPED_LIMIT`]; Dupont's plastic
    /// relaxation too, [`DUPONT_LIMIT`], up to the breakaway ratio [`DUPONT_BREAKAWAY_MAX`]).
    fn applies(c: &Shared<'_, V, L, D, N>, r: &Radau5<N>, k: &Kept) -> bool {
        if D::N_BODY == 0 || k.force_radau || c.dynamics.load.is_some() {
            return false;
        }
        let law = &c.dynamics.law;
        // Dupont off the x axis (on it, `explicit.rs`'s branches): its weight `alpha` depends
        // on `s`, so its plastic relaxation `|v_r|/s_ss` has no exponential form here and the
        // explicit method integrates it, while that rate (at the relative velocity now and
        // the support's velocity amplitude beyond it) and the stuck body's oscillation stay
        // within [`DUPONT_LIMIT`] per window.
        if let Some((relax, r_ba)) = law.breakaway() {
            if V::DIM != 2
                || r_ba > DUPONT_BREAKAWAY_MAX
                || (c.dynamics.drive.axial().is_some() && c.on_x_axis(&r.y))
            {
                return false;
            }
            let v = c.eval_now(r).vr.norm() + c.dynamics.harmonic.map_or(0.0, |h| h.v_a());
            let rate = (relax.stiffness / c.params.m).sqrt().max(v / relax.length);
            return rate * c.window_len <= DUPONT_LIMIT;
        }
        // The fastest rate of a stuck body: its oscillation on the spring `k_t`, or, with a
        // contact damping `c` (LuGre), `c/m` where that is faster.
        let rate = match law.relaxation() {
            // A Dahl contact whose force- or spring-driven motion stays on the x axis is
            // `explicit.rs`'s, or Radau's where that declines it (a stiff contact the
            // vibration does not keep sliding).
            Some(_) if c.dynamics.drive.axial().is_some() && c.on_x_axis(&r.y) => {
                return false;
            }
            Some(relax) if relax.exponent == 1.0 => (relax.stiffness / c.params.m).sqrt(),
            Some(_) => return false,
            None => {
                // A law linear in `s` (LuGre): at a vanishing `v_r` its force is
                // `k_t·s + c·v_r`, `c` the contact damping and the viscous coefficient.
                let v = 1e-30;
                let Some(lin) = law.linear(V::from_xy(v, 0.0)) else {
                    return false;
                };
                let damping = lin.force_0.x() / v;
                let damped = damping / c.params.m * c.window_len;
                // A body the vibration does not keep sliding may stick for long, stepped at
                // the damping's stability bound: [`HELD_DAMPED_LIMIT`]. Where it does, on the
                // x axis, a stiff contact's deformation is taken on its slow manifold
                // (`coulomb_limit.rs`) within [`AXIAL_DAMPED_LIMIT`], down to the tolerance
                // [`DAMPED_AXIAL_TOL`].
                let limit = if !c.vibration_unheld() {
                    HELD_DAMPED_LIMIT
                } else if damping <= 2.0 * (c.params.m * c.params.k_t).sqrt()
                    && c.dynamics.drive.axial().is_some()
                    && c.on_x_axis(&r.y)
                    && r.tolerance() >= DAMPED_AXIAL_TOL
                {
                    AXIAL_DAMPED_LIMIT
                } else {
                    DAMPED_LIMIT
                };
                if damped > limit {
                    return false;
                }
                (lin.force_s / c.params.m).sqrt()
            }
        };
        rate * c.window_len <= STIFF_LIMIT
    }

    /// Advances the planar explicit path to `t_target`: `∫F_F dt` over the call. A force- or
    /// spring-driven body whose motion stays on the x axis ([`Shared::on_x_axis`]: LuGre,
    /// since Dahl there takes `explicit.rs`) is integrated in one dimension, its lateral
    /// deformation, position and velocity left at 0 (nothing moves them): the same steps on
    /// a vector of 5 components instead of 9, about a quarter less time per step; so is a
    /// contact in longitudinal motion, on its own state (the same steps to the last bit:
    /// VibratingContactLuGre in longitudinal motion, `tests/fast_path.rs`).
    fn advance(
        c: &Shared<'_, V, L, D, N>,
        r: &mut Radau5<N>,
        k: &mut Kept,
        t_target: f64,
        h_max: f64,
    ) -> Result<Quad, SimError> {
        let mut run = Run {
            tol: r.tolerance(),
            t_target,
            h_max,
            h: k.h,
            limit: r.step_limit,
            stats: r.stats,
            push: PUSH_MARGIN * c.params.k_t / c.params.m,
        };
        let t = r.t;
        let mut y = r.y;
        let axial = match c.dynamics.drive.axial() {
            Some(drive) if V::DIM == 2 && c.on_x_axis(&r.y) => Some(drive),
            _ => None,
        };
        let integral = match axial {
            Some(drive) => {
                // `[s_x, s_y, x, y, v_x, v_y]` on `[s, x, v]`.
                let y = y.as_mut_slice();
                let mut y1 = [y[0], y[2], y[4]];
                let scale = [c.scale[0], c.scale[2], c.scale[4]];
                let ix = match drive {
                    Axial::Force(d) => axial_steps(c, d, &scale, &mut run, t, &mut y1),
                    Axial::Spring(d) => axial_steps(c, d, &scale, &mut run, t, &mut y1),
                };
                [y[0], y[2], y[4]] = y1;
                ix.map(|ix| [ix[0], 0.0])
            }
            None => {
                let sys = c.system();
                if V::DIM == 1 {
                    steps::<V, L, D, N, M_AXIAL>(&sys, &mut run, t, y.as_mut_slice())
                } else {
                    steps::<V, L, D, N, M_PLANAR>(&sys, &mut run, t, y.as_mut_slice())
                }
            }
        };
        r.stats = run.stats;
        let integral = integral?;
        c.finish(r, t_target, y);
        k.h = run.h;
        Ok(integral)
    }
}

/// The path's steps in one dimension, the drive `drive` on the axis, from `(t, y1)` (`[s, x,
/// v]`, updated) with the scales `scale`.
fn axial_steps<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, E: DriveKind<f64>>(
    c: &Shared<'_, V, L, D, N>,
    drive: E,
    scale: &[f64; 3],
    run: &mut Run,
    t: f64,
    y1: &mut [f64; 3],
) -> Result<Quad, SimError> {
    let dynamics = c.dynamics.with_drive::<f64, _>(drive);
    let sys = c.system_on(&dynamics, scale);
    steps::<f64, L, _, 3, M_AXIAL>(&sys, run, t, y1)
}

/// What one call of the path works to and with: the tolerance, the target, the largest step,
/// the proposed step (updated), the work limit and the counts (updated).
struct Run {
    tol: f64,
    t_target: f64,
    h_max: f64,
    h: f64,
    limit: u64,
    stats: SolverStats,
    /// `k_t/m` with the margin [`PUSH_MARGIN`].
    push: f64,
}

/// The path's steps from `(t, y)` to `run.t_target` on the system `sys` of state width `N`
/// (`y` updated), integrating `M` components (the state, the `V::DIM` components of `∫F_F dt`,
/// λ, and zeros to the width: [`M_PLANAR`] for every planar state): `∫F_F dt` over the call.
fn steps<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize>(
    sys: &System<'_, V, L, D>,
    run: &mut Run,
    t: f64,
    y: &mut [f64],
) -> Result<Quad, SimError> {
    debug_assert!(M > N + V::DIM);
    let Run {
        tol,
        t_target,
        h_max,
        limit,
        ..
    } = *run;
    // λ's component (the last but for a planar state shorter than the largest).
    let il = N + V::DIM;
    // Dupont's elastic part keeps each step's error where the relaxation of the others damps
    // it: its tighter fraction, as on the 1-D path (VibratingContactDupont across the sliding
    // direction, 50 ms at 1e-6: `F_Fx` 2.7e-7 of `F_C` off Radau at 1e-12 at 0.03, 1.4e-6 at
    // 0.1, in 12 % more time; at 0.5 rad 8.5e-6 against 3.0e-5, Radau at 1e-6 2.0e-5).
    let fraction = match sys.dynamics.law.breakaway() {
        Some(_) => DUPONT_TOL_FRACTION,
        None => TOL_FRACTION,
    };
    let rtol = (fraction * tol).max(1e-14);
    let exponential_from = EXPONENTIAL_FROM.min(EXPONENTIAL_REACH * libm::pow(rtol, 0.2));
    let dynamics = sys.dynamics;
    let scale = sys.scale;
    let bound = dynamics.law.bound();
    let eqs = Eqs::<V, L, D, N, M> {
        sys,
        relax: Relax::new(dynamics.law),
    };
    let manifold = Limit::new(sys, rtol);
    // What a deformation error pushes into the body per unit of time, on the scale of the
    // errors: `(k_t/m)·(s_nom + |s|)/v_nom`, the velocity's nominal the body's last
    // component's; Dahl's contact only (`weigh`).
    // (RigTransverse at tolerance 1e-6, 0.1 s: 42.4 steps per period against 49.4 with the
    // deformation's own error, `F_Fx` 1.3e-8 and `F_Fy` 2.2e-6 of `F_C` from Radau at
    // 1e-11 against 3.7e-8 and 5.9e-6.)
    let weigh = dynamics.law.relaxation().is_some() && tol <= WEIGH_UP_TO;
    let push = run.push * (scale[0] + dynamics.law.envelope()) / scale[N - 1];
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
    let mut support = StageSupport::<V>::new(dynamics, sys.input_support, t);
    // The last accepted step on the manifold, with its error, while the steps stay on it.
    let mut on_manifold: Option<(f64, f64)> = None;
    // The plain steps' stages and derivatives, taken in place step after step.
    let mut plain = DoPriStep::zeros();
    while t < t_target {
        if stats.steps + stats.rejected >= limit {
            return Err(SimError::Solver(SolverError::WorkLimit {
                t,
                limit: limit as f64,
            }));
        }
        u[N..].fill(0.0);
        let k1 = match fsal {
            Some(k) => k,
            None => {
                stats.rhs_evals += 1;
                eqs.rhs(t, &u)
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
        if !last && hh <= 16.0 * f64::EPSILON * t.abs().max(hh) {
            return Err(SimError::Solver(SolverError::StepSizeTooSmall { t, h: hh }));
        }
        // The largest scaled error of the deformation's components, and of the rest.
        let mut err_s: f64 = 0.0;
        let mut err: f64 = 0.0;
        // `v_r` at the stages of the step taken (of its last pass).
        let mut vr_at = [V::default(); 7];
        let exponential = k1[il] * hh >= exponential_from;
        // Where a stiff contact's deformation is certified on its slow manifold (planar Dahl,
        // LuGre on the x axis), the body alone (`coulomb_limit.rs`), the step cut to the
        // start's reach (no sign change of `v_r` within it); else the exponential step. The
        // 1-D stage support velocities below are for the step as cut.
        let start = match &manifold {
            Some(m) if exponential && cut.is_none() => {
                m.start::<N>(t, &u).filter(|st| st.reach >= REACH_CUT * hh)
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
            None => relative_velocity::<V, L, D, N, M>(sys, t, &u),
        };
        let mut limit_evals = 0;
        let on_limit = match (&manifold, &start) {
            (Some(m), Some(st)) => m.step::<N, M>(st, t, &u, &k1, hh, |i, tt, y, s| {
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
        let (step, mut u1) = if let Some((step, u1)) = &on_limit {
            // The deformation's error: the manifold's under the body's.
            for c in 0..V::DIM {
                let w = rtol * (scale[c] + u[c].abs().max(u1[c].abs()));
                err = err.max((step.err[c] / w).abs());
            }
            (step, *u1)
        } else if exponential {
            let (step, u1, e_s, e, second) =
                exponential_step(&eqs, &kin_stage, t, &u, &k1, hh, rtol, scale, &mut vr_at);
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
            plain.retake(&mut stage, t, &u, &k1, hh);
            let u1 = plain.end();
            for c in 0..V::DIM {
                let w = rtol * (scale[c] + u[c].abs().max(u1[c].abs()));
                err_s = err_s.max((plain.err[c] / w).abs());
            }
            (&plain, u1)
        };
        stats.rhs_evals += 6;
        for i in V::DIM..N {
            let w = rtol * (scale[i] + u[i].abs().max(u1[i].abs()));
            err = err.max((step.err[i] / w).abs());
        }
        // Short of the call's end a step's deformation error counts by what it leaves
        // ([`settled`]; Dahl's only: LuGre's force also takes `ds/dt`, whose error is not
        // left behind the same way). An
        // exponential step's, its interpolation's, is in the force all along the step: the
        // push's `h`; down to the tolerance [`WEIGH_EXPONENTIAL_DOWN_TO`].
        if !last && weigh && (!exponential || tol >= WEIGH_EXPONENTIAL_DOWN_TO) {
            err_s = settled(
                err_s,
                (k1[il], step.k[6][il]),
                hh,
                t_target - (t + hh),
                push,
            );
        }
        let err = err.max(err_s);
        let err = if u1.iter().all(|z| z.is_finite()) && err.is_finite() {
            err
        } else {
            f64::INFINITY
        };
        // On the x axis (no lateral relative velocity) `|v_r|`, and with it the rates, has a
        // kink wherever `v_rx` changes sign, on which the error estimate of a step across it
        // is not to be trusted: the step is retaken to end just past the sign change
        // (located on the continuous extension), so that the kink falls between steps. A
        // step that ends on a sign change located on a rejected step's extension is checked
        // again.
        let crossing = if cut.is_none_or(|(_, trusted)| !trusted) {
            sign_change::<V, L, D, N, M>(sys, t, hh, vr_start(), &vr_at, step)
        } else {
            None
        };
        if err > 1.0 {
            stats.rejected += 1;
            h = hh * factor(err).min(0.9);
            rejected = true;
            // A sign change within the next step: the next step ends just past it.
            cut = crossing.filter(|&te| te - t <= h).map(|te| (te, false));
            fsal = Some(k1);
            continue;
        }
        if let Some(te) = crossing {
            cut = Some((te, true));
            h = hh;
            fsal = Some(k1);
            continue;
        }
        stats.steps += 1;
        stats.limit_steps += limited as u64;
        // A step that ends on a sign change of `v_rx` may end a little short of it.
        let bridge = match cut {
            Some(_) if !last => bridge(t, hh, vr_start().x(), &vr_at, t_target),
            _ => None,
        };
        u1[il] = 0.0;
        integral[0] += u1[N];
        if V::DIM == 2 {
            integral[1] += u1[N + 1];
        }
        u = u1;
        // After an exponential step the end's deformation is not the last stage's (after a
        // step on the manifold it is).
        fsal = (!exponential || limited).then_some(step.k[6]);
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
        let mut h_new = next_size(hh, err, rejected, on_manifold.filter(|_| limited));
        on_manifold = limited.then_some((hh, err.max(PREDICT_FLOOR)));
        rejected = false;
        if (last || cut.is_some()) && hh < h {
            // A step clipped to the target or to a sign change says little about the size
            // (keeping the size proposed before it instead cost more on VibratingContactLuGre at
            // 1e8, tolerance 1e-6: 42.6 steps per period against 41).
            h_new = h_new.max(h);
        }
        cut = bridge.map(|te| (te, true));
        h = h_new;
    }
    y.copy_from_slice(&u[..N]);
    run.h = h;
    Ok(integral)
}

/// The right-hand side of the integrated vector (the state, `∫F_F dt` and λ, [`steps`]).
struct Eqs<'s, 'a, V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize> {
    sys: &'s System<'a, V, L, D>,
    relax: Relax<L>,
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize>
    Eqs<'_, '_, V, L, D, N, M>
{
    /// What the right-hand side needs at `(tt, u)` besides the deformation.
    #[inline(always)]
    fn kin(&self, tt: f64, u: &[f64; M]) -> Kin<V> {
        Kin::at(self.sys, &self.relax, tt, &u[..N])
    }

    /// The right-hand side at `u` with the deformation `s` (the state's own, or an
    /// exponential or manifold stage's), given what it needs there, `kin`: the relative
    /// velocity and its decay rate `|v_r|/s_ss` (LuGre `|v_r|/g(v_r)`); the body's equations
    /// read only `u`'s body part.
    #[inline(always)]
    fn rhs_with(&self, u: &[f64; M], s: V, kin: &Kin<V>) -> [f64; M] {
        let (ds, f) = self.sys.dynamics.law.rate_force_at(s, kin.vr, &kin.terms);
        let e = Eval {
            s,
            v: kin.v,
            vr: kin.vr,
            ds,
            f,
            drive: kin.drive,
        };
        let r = self.sys.rhs_at::<N>(&e, &u[..N]);
        let mut out = [0.0; M];
        out[..N].copy_from_slice(r.as_slice());
        out[N] = f.x();
        if V::DIM == 2 {
            out[N + 1] = f.y();
        }
        out[N + V::DIM] = kin.terms.decay;
        out
    }

    /// The right-hand side at `(tt, u)`.
    #[inline(always)]
    fn rhs(&self, tt: f64, u: &[f64; M]) -> [f64; M] {
        self.rhs_with(u, V::read(&u[..V::DIM]), &self.kin(tt, u))
    }
}

/// One exponential step of length `hh` from `(t, u)` with the first derivative `k1`
/// ([module docs](self)), `kin_stage(i, tt, y)` what the right-hand side needs at stage `i`:
/// the step, its end (the deformation from the second pass's extension), the deformation's
/// largest scaled error (relative tolerance `rtol`, scales `scale`) and the rest's (λ's, or
/// infinite where the interpolation's nodes did not increase), and whether the second pass
/// was taken (six more right-hand sides). `vr_at` gets `v_r` at the stages of the last pass.
#[allow(clippy::too_many_arguments)] // the step's own arguments, and what it needs
fn exponential_step<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize>(
    eqs: &Eqs<'_, '_, V, L, D, N, M>,
    kin_stage: &impl Fn(usize, f64, &[f64; M]) -> Kin<V>,
    t: f64,
    u: &[f64; M],
    k1: &[f64; M],
    hh: f64,
    rtol: f64,
    scale: &[f64],
    vr_at: &mut [V; 7],
) -> (DoPriStep<M>, [f64; M], f64, f64, bool) {
    let il = N + V::DIM;
    let (mut err_s, mut err, mut second): (f64, f64, bool) = (0.0, 0.0, false);
    // The deformation at each stage from its equation in λ, `ds/dλ = q − s`, with
    // the target `q = s_ss·v_r/|v_r|` interpolated in λ through the stages so far
    // (their λ from the method's own stages of `dλ/dt = |v_r|/s_ss`): exact for
    // that polynomial whatever the relaxation over the step.
    let s0 = [u[0], if V::DIM == 2 { u[1] } else { 0.0 }];
    let mut hist = Stages::new(s0, eqs.kin(t, u).target(), 1);
    let step = {
        let mut stage = |tt: f64, y: &[f64; M]| -> [f64; M] {
            let i = hist.n;
            hist.n += 1;
            hist.lam[i] = y[il];
            let k = kin_stage(i, tt, y);
            hist.q[i] = k.target();
            vr_at[i] = k.vr;
            let s_i = match i {
                1 => hist.relax([0, 1]),
                2 => hist.relax([0, 1, 2]),
                3 => hist.relax([0, 1, 2, 3]),
                4 => hist.relax([0, 1, 2, 3, 4]),
                5 => hist.relax([0, 1, 2, 3, 4, 5]),
                _ => hist.relax([0, 1, 2, 3, 4, 6]),
            };
            eqs.rhs_with(y, V::read(&s_i[..V::DIM]), &k)
        };
        DoPriStep::take(&mut stage, t, u, k1, hh)
    };
    // The stages' velocities are of low order: a second pass with the deformation
    // at each stage from the first pass's continuous extension (q at six
    // equidistant points, the ends exact, λ from the same extension).
    let dense = step.dense_all(hh);
    let mut first = nodes::<V, N, M>(&step, &dense, hist.s0, hist.q[0], |theta, z| {
        eqs.kin(t + theta * hh, z).target()
    });
    first.bad |= hist.bad;
    let fit = first.fit([0, 1, 2, 3, 4, 5]);
    let big = first.lam[5];
    let step = match &fit {
        Some(fit) => {
            let (mut i, mut stage2) = (1, [0.0; 7]);
            for (k, c) in C.iter().enumerate() {
                stage2[k] = dense.at(il, *c) / big;
            }
            let mut stage = |tt: f64, y: &[f64; M]| -> [f64; M] {
                let s_i = fit.at(stage2[i]);
                i += 1;
                let k = kin_stage(i - 1, tt, y);
                vr_at[i - 1] = k.vr;
                eqs.rhs_with(y, V::read(&s_i[..V::DIM]), &k)
            };
            second = true;
            DoPriStep::take(&mut stage, t, u, k1, hh)
        }
        None => step,
    };
    let mut u1 = step.end();
    let dense = step.dense_all(hh);
    let mut fine = nodes::<V, N, M>(&step, &dense, hist.s0, hist.q[0], |theta, z| {
        eqs.kin(t + theta * hh, z).target()
    });
    fine.bad |= first.bad;
    let s5 = fine.relax([0, 1, 2, 3, 4, 5]);
    let s4 = fine.relax([0, 2, 3, 4, 5]);
    let bad = fine.bad;
    u1[..V::DIM].copy_from_slice(&s5[..V::DIM]);
    for c in 0..V::DIM {
        let w = rtol * (scale[c] + u[c].abs().max(s5[c].abs()));
        err_s = err_s.max((s5[c] - s4[c]).abs() / w);
    }
    // λ places the interpolation's nodes: its error relative to the step's λ.
    err = err.max(step.err[il].abs() / (rtol * u1[il].max(1.0)));
    if bad {
        err = f64::INFINITY;
    }
    (step, u1, err_s, err, second)
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
            let theta = super::explicit::root(&gd, (C[i - 1], ga), (C[i], gb), 1e-9 * (ga - gb));
            let te = t + theta * hh;
            (theta < 1.0 && te > t + 16.0 * f64::EPSILON * t.abs().max(hh)).then_some(te)
        }
        _ => None,
    }
}

/// λ and `q` at six equidistant points of a step from its continuous extension `dense`
/// (the start's `q` given, the end's from the end state; `target(theta, z)` is `q` at
/// `t + theta·h` and the state `z`).
fn nodes<V: Vector, const N: usize, const M: usize>(
    step: &DoPriStep<M>,
    dense: &Dense<M>,
    s0: [f64; 2],
    q0: [f64; 2],
    target: impl Fn(f64, &[f64; M]) -> [f64; 2],
) -> Stages {
    let mut fine = Stages::new(s0, q0, 0);
    let end = step.end();
    fine.lam[5] = end[N + V::DIM];
    fine.q[5] = target(1.0, &end);
    for k in 1..5 {
        let theta = k as f64 * 0.2;
        let mut z = end;
        for (i, zi) in z.iter_mut().enumerate().take(N).skip(V::DIM) {
            *zi = dense.at(i, theta);
        }
        fine.lam[k] = dense.at(N + V::DIM, theta);
        fine.q[k] = target(theta, &z);
    }
    fine
}

/// `v_r` at `(t, u)`.
#[inline(always)]
fn relative_velocity<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize>(
    sys: &System<'_, V, L, D>,
    t: f64,
    u: &[f64; M],
) -> V {
    let d = sys.dynamics.drive_inputs(t);
    sys.dynamics.drive.velocity(&u[V::DIM..N], &d) - sys.support(t)
}

/// What the right-hand side needs at one time and state besides the deformation: the drive's
/// inputs, the body's velocity, the relative velocity and its relaxation rate.
struct Kin<V> {
    drive: DriveInputs,
    v: V,
    vr: V,
    /// The relaxation rate `|v_r|/s_ss` (LuGre `|v_r|/g(v_r)`) and what the force needs.
    terms: VelocityTerms,
}

impl<V: Vector> Kin<V> {
    #[inline(always)]
    fn at<L: FrictionLaw, D: DriveKind<V>>(
        sys: &System<'_, V, L, D>,
        relax: &Relax<L>,
        t: f64,
        y: &[f64],
    ) -> Self {
        Self::with_support(sys, relax, t, y, sys.support(t))
    }

    /// As [`Kin::at`], with the support velocity `vs` at `t` given.
    #[inline(always)]
    fn with_support<L: FrictionLaw, D: DriveKind<V>>(
        sys: &System<'_, V, L, D>,
        relax: &Relax<L>,
        t: f64,
        y: &[f64],
        vs: V,
    ) -> Self {
        let drive = sys.dynamics.drive_inputs(t);
        let v = sys.dynamics.drive.velocity(&y[V::DIM..], &drive);
        let vr = v - vs;
        Kin {
            drive,
            v,
            vr,
            terms: relax.terms(vr),
        }
    }

    /// Where the deformation relaxes to: `v_r/decay` (`s_ss·v_r/|v_r|`, LuGre
    /// `g(v_r)·v_r/|v_r|`), 0 at `v_r` = 0.
    #[inline(always)]
    fn target(&self) -> [f64; 2] {
        if self.terms.decay > 0.0 {
            let q = self.vr * (1.0 / self.terms.decay);
            [q.x(), q.y()]
        } else {
            [0.0; 2]
        }
    }
}

/// The law's relaxation rate at a relative velocity: Dahl's at its constant length `s_ss`, or
/// a law linear in `s` (LuGre) at the length `g(v_r)` of its rate `ds/dt = (|v_r|/g)·(q − s)`.
struct Relax<L> {
    law: L,
    /// Dahl's `1/s_ss`.
    dahl: Option<f64>,
}

impl<L: FrictionLaw> Relax<L> {
    fn new(law: L) -> Self {
        Relax {
            law,
            dahl: law.relaxation().map(|r| 1.0 / r.length),
        }
    }

    /// The relaxation rate `dλ/dt` (`|v_r|/s_ss`, LuGre `|v_r|/g(v_r)`) and the law's other
    /// terms at `v_r`.
    #[inline(always)]
    fn terms<V: Vector>(&self, vr: V) -> VelocityTerms {
        match self.dahl {
            Some(inv_len) => VelocityTerms {
                decay: vr.norm() * inv_len,
                damping: 0.0,
            },
            None => self.law.velocity_terms(vr),
        }
    }
}

/// The stages of one exponential step: `λ` and the target `q` at each, the deformation at the
/// step's start, and at its end from the interpolants of degree 5 and 4.
struct Stages {
    lam: [f64; 7],
    q: [[f64; 2]; 7],
    s0: [f64; 2],
    n: usize,
    /// The nodes were not increasing in λ: the step is rejected.
    bad: bool,
    /// `1/(λ_j − λ_k)` for `k < j` once a fit has needed it (0 until then): the divided
    /// differences of both components and every fit through the same nodes share them.
    inv: [[f64; 7]; 7],
}

impl Stages {
    fn new(s0: [f64; 2], q0: [f64; 2], n: usize) -> Self {
        let mut q = [[0.0; 2]; 7];
        q[0] = q0;
        Stages {
            lam: [0.0; 7],
            q,
            s0,
            n,
            bad: false,
            inv: [[0.0; 7]; 7],
        }
    }

    /// `s` at the last of `nodes` (see [`Fit`]).
    fn relax<const K: usize>(&mut self, nodes: [usize; K]) -> [f64; 2] {
        match self.fit(nodes) {
            Some(f) => f.at(1.0),
            None => self.s0,
        }
    }

    /// The interpolant of `q` through `nodes` in `μ = λ/Λ`, `Λ` the last node's `λ`; `None`
    /// (and the step marked bad) where the nodes do not increase in λ. The number of nodes is
    /// a constant, so that the loops unroll and the coefficients stay in registers.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // the divided differences index in lockstep
    fn fit<const K: usize>(&mut self, nodes: [usize; K]) -> Option<Fit<K>> {
        let n = K;
        let big = self.lam[nodes[n - 1]];
        for k in 1..n {
            if self.lam[nodes[k]] <= self.lam[nodes[k - 1]] {
                self.bad = true;
            }
        }
        if self.bad || big.is_nan() || big <= 0.0 {
            self.bad = true;
            return None;
        }
        let inv_big = 1.0 / big;
        let mut mu = [0.0; K];
        for (k, &j) in nodes.iter().enumerate() {
            mu[k] = self.lam[j] * inv_big;
        }
        // `1/(μ_j − μ_(j−k)) = Λ/(λ_j − λ_(j−k))` for the divided differences.
        let mut w = [[0.0; K]; K];
        for k in 1..n {
            for j in k..n {
                let (a, b) = (nodes[j], nodes[j - k]);
                if self.inv[a][b] == 0.0 {
                    self.inv[a][b] = 1.0 / (self.lam[a] - self.lam[b]);
                }
                w[k][j] = big * self.inv[a][b];
            }
        }
        let mut poly = [[0.0; K]; 2];
        // A component that is 0 throughout (the lateral one of a motion on the x axis) stays 0.
        let comps = if self.s0[1] == 0.0 && nodes.iter().all(|&j| self.q[j][1] == 0.0) {
            1
        } else {
            2
        };
        for (c, pc) in poly.iter_mut().enumerate().take(comps) {
            // Divided differences, then the monomial coefficients by Horner on the Newton form.
            let mut dd = [0.0; K];
            for (k, &j) in nodes.iter().enumerate() {
                dd[k] = self.q[j][c];
            }
            for k in 1..n {
                for j in (k..n).rev() {
                    dd[j] = (dd[j] - dd[j - 1]) * w[k][j];
                }
            }
            pc[0] = dd[n - 1];
            for i in (0..n - 1).rev() {
                for m in (1..n).rev() {
                    pc[m] = pc[m - 1] - mu[i] * pc[m];
                }
                pc[0] = -mu[i] * pc[0] + dd[i];
            }
        }
        // `s0 − P(0)`: G_m(0) = (−x)^m·m! (see `Fit::at`).
        let mut g0 = [1.0; K];
        for m in 1..n {
            g0[m] = -inv_big * m as f64 * g0[m - 1];
        }
        let mut c0 = [0.0; 2];
        for c in 0..comps {
            let p0: f64 = (0..n).map(|m| poly[c][m] * g0[m]).sum();
            c0[c] = self.s0[c] - p0;
        }
        Some(Fit {
            poly,
            comps,
            big,
            inv_big,
            c0,
        })
    }
}

/// The solution of `ds/dλ = p(λ) − s`, `s(0) = s0`, `p` a polynomial of degree `K − 1` in
/// `μ = λ/Λ`: `s = P(λ) + (s0 − P(0))·exp(−λ)` with the polynomial particular solution
/// `P = Σ_k (−1)^k·d^k p/dλ^k`. Its terms shrink with `1/Λ`; the exponential path is taken
/// from a relaxation of [`EXPONENTIAL_FROM`] per step on.
struct Fit<const K: usize> {
    poly: [[f64; K]; 2],
    /// The components fitted (the second is 0 when only one is).
    comps: usize,
    big: f64,
    inv_big: f64,
    /// `s0 − P(0)`.
    c0: [f64; 2],
}

impl<const K: usize> Fit<K> {
    /// `s` at `λ = μ·Λ`.
    #[inline(always)]
    fn at(&self, mu: f64) -> [f64; 2] {
        // G_m(μ) = Σ_k (−x)^k·m!/(m − k)!·μ^(m−k) = μ^m − x·m·G_(m−1)(μ), x = 1/Λ.
        let x = self.inv_big;
        let (mut g, mut pw) = ([1.0; K], 1.0);
        for m in 1..K {
            pw *= mu;
            g[m] = pw - x * m as f64 * g[m - 1];
        }
        let decay = exp_neg(self.big * mu);
        let mut out = [0.0; 2];
        for (c, o) in out.iter_mut().enumerate().take(self.comps) {
            let p: f64 = (0..K).map(|m| self.poly[c][m] * g[m]).sum();
            *o = p + self.c0[c] * decay;
        }
        out
    }
}

/// `exp(−z)` for `z ≥ 0` up to rounding, from the explicit path's arithmetic `expm1`:
/// `expm1(−z) + 1`, exact to about 1e-16 absolute (all the relaxation's factor needs), and 0
/// beyond `z` = 39 where it is below 1.2e-17.
#[inline(always)]
fn exp_neg(z: f64) -> f64 {
    if z > 39.0 {
        0.0
    } else {
        super::explicit::expm1(-z.max(-1.0)) + 1.0
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
