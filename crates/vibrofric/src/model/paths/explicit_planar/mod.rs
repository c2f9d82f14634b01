//! The explicit path of a moving body on a planar Dahl contact (`kappa = 1`): force or spring
//! drive, or a velocity drive with the lateral motion free, whenever the motion leaves the x
//! axis (on the axis the closed form of `explicit/` applies); on a planar LuGre contact,
//! on the axis or off it, or in longitudinal motion; and on a planar Dupont contact off the
//! axis (or on it with the lateral motion free, which `explicit/` does not take) at a
//! moderate stiffness ([`DUPONT_LIMIT`]), whose weight `alpha(s)` leaves its rate
//! without the form below: its plastic relaxation is one more component of the explicit
//! method, and its direction test `s·v_r > 0`, which switches that relaxation on and off (a
//! jump of the rate off the axis), is not located but left to the error control (a tighter
//! one, [`DUPONT_TOL_FRACTION`], as on the 1-D path). What locating it would save, counted on
//! VibratingContactDupont with a transverse vibration (angle pi/2, 50 ms from rest at
//! tolerance 1e-6, every attempt traced): 143 of the 414 rejected attempts had the switch
//! inside, all of them in the first 1.2 ms, while the body found its slide; from then on
//! `s·v_r` stays positive (82 steps and 2 rejected per period, held by the error of plain
//! steps on the plastic part), so a located switch would save those start-up attempts alone.
//! LuGre's rate has the same form, `ds/dt = (|v_r|/g)·(q − s)` with `q = g·v_r/|v_r|`, its
//! length `g(v_r)` depending on the relative velocity where Dahl's `s_ss` is constant:
//! `λ = ∫|v_r|/g dt` and `q` take that `g`, and the force (with its damping `h_t·ds/dt`)
//! follows from the deformation at each stage as in the general model.
//! A force- or spring-driven body whose motion stays on the x axis (no lateral deformation,
//! velocity or support motion: LuGre, since Dahl there takes `explicit/`) is integrated in
//! one dimension, `[s, x, v]` with `∫F_Fx dt` and λ, by the same code ([`steps`](fn@steps),
//! generic in the vector type and the widths); its lateral components stay 0 as the planar
//! equations keep them (the results were those of the planar integration to the last bit on
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
//! Where LuGre's steps go (VibratingContactLuGre, tolerance 1e-6, every attempt traced over
//! 0.1 to 0.1005 s). At `k_t` = 1e8 (40 steps per period, Dahl's closed form 10) nearly every
//! step is plain, 1e-5 to 2.5e-5 s: while sliding the deformation's error holds it (the
//! relaxation over a step 0.3 to 0.9, the body's error a tenth of its tolerance and less);
//! within about 1 mm/s of each reversal both the deformation's error (the support's
//! vibration integrated into `s` with an absolute tolerance of about 2e-14 m) and the body's
//! (the damping force `h_t(v_r)·ds/dt`, a Gaussian of `v_r` as wide as `v_e`, switching on and
//! off within a few steps). Taking a plain step's end deformation in closed form instead
//! (`exp(−Λ)·s0 + ∫exp(Λ(τ) − Λ)·v_r dτ`, the body's velocity from the continuous
//! extension, Gauss–Lobatto on five nodes against four) left the body's error in charge: 40 →
//! 36 steps per period at 1e8, but `F_Fx` 5.0e-6 of `F_C` off Radau at 1e-12 against 8.8e-7
//! (the damping passes the body's velocity error into the force), each step dearer; at 1e12
//! 136 → 107. At `k_t` = 1e12 about 40 plain steps of 1e-7 to 3e-7 s follow each reversal
//! until the relaxation per step reaches [`EXPONENTIAL_FROM`]: with `v_r ≈ a_r·t` the
//! deformation turns over as `exp(−a_r·t²/(2g))` (width `sqrt(2g/a_r)`, 8e-7 s), and the
//! damping's pull on the body, `h_t·ds/dt` with `h_t` near `h_t(0)` (`|v_r|` ≪ `v_e`), is a pulse
//! as narrow whose impulse is `h_t(0)·Δs`. The momentum `m·v + h_t(0)·s` carries that pulse
//! exactly where `s` is exact, leaving `(h_t − h_t(0))·ds/dt`, small near a reversal; taken
//! at the closed-form step's end only (the stages still on the explicit method's `s`) it gave
//! 36 steps and `F_Fx` 1.5e-6 at 1e8, 105 steps at 1e12: the deformation and the body are
//! to be solved together at the stages.
//!
//! Where the time goes at `k_t` = 1e12 (the same period traced; `examples/explicit_bench.rs`
//! with `KT=1e12`, 0.05 s): 159 attempts, 101 plain (the ~40 steps after each reversal, held
//! by the deformation's error at 0.3 to 0.8 of the tolerance while the body's is about 1e-3
//! of it), 49 exponential and 9 on the Coulomb limit, 155 µs per period at tolerance 1e-6;
//! at 1e8, 49 plain attempts, 18 µs (0.37 µs each). The exponential and manifold attempts,
//! about 2 µs each, take three quarters of the time at 1e12, so that steps saved after the
//! reversal buy little. Measured (three interleaved runs each, 1e8 unchanged by all; kept
//! on the side branch `issue-38-weigh-try`): LuGre's deformation error weighed by what it
//! leaves as Dahl's is ([`WEIGH_UP_TO`]), with the damping's impulse `h_t(0)·δs` added to
//! the push: 136 → 101 steps per period at 1e-6 (332 → 243 at 1e-8) but 155 → 152 µs (356 →
//! 339), `F_Fx` 2.86e-6 → 2.91e-6 of `F_C` off Radau at 1e-12 (5.18e-8 → 5.31e-8). The
//! exponential step taken from a relaxation of 0.2 per step where `g(v_r)` and `h_t(v_r)`
//! are within 1 % of their values at rest (`q` constant there; its deformation error 1e-7
//! of the tolerance where the plain step's is 0.5): 114 steps but 188 to 193 µs, `F_Fx`
//! 2.51e-6. Its λ, `∫|v_r|/g dt`, carries the body's velocity error amplified by `h/g` and
//! then holds the steps at 3e-7 to 6e-7 s; weighing λ's error by what it moves `s` by,
//! `|s − q|`, left 103 steps and the time as it was. Nor are these steps stability-limited:
//! `sqrt(k_t/m)` is 4.2e5 /s (m = 5.6 kg), `ω·h` 0.04 to 0.13 on them against DOPRI's bound
//! of about 3.3; an L-stable step on `(s, v)` pays only where it also resolves the turn-over
//! of `s` (width `sqrt(2g/a_r)`, 8e-7 s) at longer steps. What is left: the exponential
//! attempt's cost (two passes and the interpolation; in a profile of the whole bench at
//! 1e12, Radau's reference 15 %, `steps` 37 %, `exponential_step` 15.5 %, `next_size`'s power
//! 3.3 %, the certificate's `lugre_point` 3.2 %, the sign change's `root` 2.7 %) and their
//! number: about 5 rejected before each reversal with the sign change inside, and steps of
//! 5e-6 to 8e-6 s while sliding where 1e8 slides in plain steps of 1.5e-5 s, held there by
//! λ's error (0.5 to 2.3 of the tolerance, the deformation's and the body's below 0.1): at
//! tolerance 1e-6 that error now counts by how far it moves the deformation
//! ([`LAMBDA_BY_MOVES_FROM`]), 149–157 → 124–126 µs per period at 1e12 (the ratio to 1e8
//! from 0.1 to 0.2 s 8.3 → 7.1).
//!
//! Measured and not taken: LuGre's plain step in one dimension in integrating-factor form,
//! `s = q0 + exp(−λ)·(s0 − q0 + K)` with
//! `dK/dt = exp(λ)·(v_r − q0·dλ/dt)` and `q0` the start's target, exact in `s` for any `q0`,
//! `K` and λ integrated in place of `s` (neither stiff), the stages' deformation from them.
//! On a LuGre contact with `F_S = F_C` and no damping (Dahl's law) it halved the steps (45 →
//! 22 per period at 1e8, tolerance 1e-6); on VibratingContactLuGre the Stribeck and damping
//! Gaussians of `v_r` (as wide as `v_S` = `v_e`, about 3e-5 s of a period) hold the body and
//! `K` instead: 41.5 → 31.4 steps per period at 1e8 (taking steps up to a relaxation of 10
//! per step), `F_Fx` 1.96e-7 of `F_C` off Radau at 1e-12 against 8.8e-7, but each attempt
//! about 30 % dearer (the exponential and division at each stage), 133 → 143 thousand
//! instructions per period (valgrind; 293 → 274 at 1e-8, where `F_Fx` rose from 3.3e-9 to
//! 9.3e-9). At 1e12 up to a relaxation of 1 per step it cut the steps after each reversal
//! (129 → 82 per period, 988 → 910 thousand instructions from rest) but not from rest at 1e-8
//! (335 → 1165 steps per period over the first 0.02 s); beyond 1 its steps there failed
//! (548 steps per period). Nor did taking the harmonic source's displacement exactly in `K`
//! or λ, a larger tolerance fraction (0.1 → 0.4: 30.6 → 28.2 steps, `F_Fx` 2.0e-6), cutting
//! the step short of a predicted reversal (44–47 steps) or ending a rejected step's successor
//! on the sign change it located (41.5 → 41.0) pay.
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
use super::{Integrated, Kept, Path, Shared};
use crate::model::drive::{Axial, DriveInputs, DriveKind};
use crate::model::dynamics::{Eval, System};
use crate::model::simulator::SimError;
use crate::physics::{trig, FrictionLaw, Vector, VelocityTerms};
use crate::solver::dopri::{factor, first_step, Dense, DoPriStep, C};
use crate::solver::{Quad, SolverStats};
use coulomb_limit::Limit;
use steps::steps;

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
/// it leaves (`settled` in `steps.rs`), as a plain step's is. RigTransverse from rest at `k_t` =
/// 1e12, tolerance 1e-6, 0.1 s: 43.9 steps per period against 49.6 with the exponential steps' own
/// error, `F_Fx` and `F_Fy` 6.9e-8 and 7.0e-9 of `F_C` from Radau at 1e-11 against 6.9e-8 and
/// 6.6e-9 (1e-8: 10,294 steps against 12,712 over 30 ms, 5.8e-10 and 5.5e-11 against 6.1e-10
/// and 4.8e-11); the same steps at 1e8 and on PaperTransverse. At 1e-10 (`k_t` = 1e11) the
/// body's position drifted past ten tolerances of Radau at 1e-12.
const WEIGH_EXPONENTIAL_DOWN_TO: f64 = 1e-8;

/// The tightest tolerance at which a LuGre contact's exponential step weighs the error of its
/// λ by how far it moves the deformation: `s = P(λ) + (s0 − P(0))·exp(−λ)` moves by `|s − q|`
/// times an error in λ at the step's end, and by about as much times its relative error
/// through the nodes of the interpolation, so that the error counts `|s − q|/(s_nom + |s|)`
/// (at most 1) of itself. λ, `∫|v_r|/g dt`, carries the body's velocity error amplified by
/// `h/g`; while sliding at a stiff contact it held the steps where the deformation had
/// followed its target to a few thousandths. VibratingContactLuGre at `k_t` = 1e12,
/// `examples/explicit_bench.rs` 0.05 s, four interleaved runs each: tolerance 1e-6, 136.4 →
/// 129.9 steps per period, 149–157 → 124–126 µs CPU, `F_Fx` 2.86e-6 → 1.81e-6 of `F_C` off
/// Radau at 1e-12 (1e8 and DrillStringAxial unchanged). At 1e-8 it cut the time by a third (332 → 276
/// steps) but `F_Fx` rose from 5.18e-8 to 6.18e-8; on Dahl's planar contacts it cost accuracy
/// (RigTransverse at 1e12, tolerance 1e-6: 1.1e-7 → 7.6e-7) and is not taken. Nor at
/// tolerances looser than [`WEIGH_UP_TO`] (not measured; there the deformation's error is
/// not weighed either).
const LAMBDA_BY_MOVES_FROM: f64 = 1e-6;

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
/// keep sliding ([`Shared::vibration_unheld`]): while it sticks the explicit method steps at
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
    fn applies(c: &Shared<'_, V, L, D, N>, r: &Integrated<N>, k: &Kept<N>) -> bool {
        if D::N_BODY == 0 || k.force_radau || c.dynamics.load.is_some() {
            return false;
        }
        let law = &c.dynamics.law;
        // Dupont off the x axis (on it, `explicit/`'s branches): its weight `alpha` depends
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
            // `explicit/`'s, or Radau's where that declines it (a stiff contact the
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
    /// since Dahl there takes `explicit/`) is integrated in one dimension, its lateral
    /// deformation, position and velocity left at 0 (nothing moves them): the same steps on
    /// a vector of 5 components instead of 9, about a quarter less time per step; so is a
    /// contact in longitudinal motion, on its own state (the same steps to the last bit:
    /// VibratingContactLuGre in longitudinal motion, `tests/fast_path.rs`).
    fn advance(
        c: &Shared<'_, V, L, D, N>,
        r: &mut Integrated<N>,
        k: &mut Kept<N>,
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
        k.propose(run.h);
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

mod exponential_step;
mod rhs;
mod steps;
