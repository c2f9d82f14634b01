//! The Coulomb limit of a stiff planar Dahl contact (`kappa = 1`), and of a stiff LuGre
//! contact on the x axis ([`Limit::lugre_point`]): a step kind of the planar explicit path
//! (`explicit_planar/`) in which the deformation is a function of the body's motion and only
//! the body is integrated.
//!
//! With `r = |v_r|`, `e = v_r/r` and `L = s_ss`, the law `ds/dt = v_r − r·s/L` reads
//! `s = L·e − (L/r)·ds/dt`: the deformation relaxes at the rate `r/L` (1e8/s and more at
//! `k_t` = 1e12) onto a slow manifold near `L·e`, where the friction force is Coulomb's
//! `F_C·e` up to small corrections. Writing `s = L·e + z` and `ė = P⊥·a_r/r`
//! (`P⊥ = I − e·eᵀ`, `a_r = dv_r/dt`) gives the fixed point
//! `z = −(L/r)²·P⊥·a_r(F(L·e + z)) − (L/r)·dz/dt`, whose iterates are
//!
//! - first order: `z1 = −(L/r)²·P⊥·a_r`, `a_r` the body's acceleration under the Coulomb force
//!   `F(L·e)` minus the support's ([`correction`]);
//! - second order: `z2 = −(L/r)²·P⊥·a_r(F(L·e + z1)) − (L/r)·dz1/dt`, the rate of `z1` in
//!   closed form from `a_r` and its rate (the support's jerk exact, the body's from its own
//!   acceleration function, affine in its state, force and inputs) ([`manifold`]).
//!
//! - third order, at tight tolerances ([`THIRD_ORDER_BELOW`]): `z3 = z2 − (L/r)²·P⊥·(a_r(F(L·e
//!   + z2)) − a_r(F(L·e + z1))) + (L/r)·d/dt((L/r)·dz1/dt)`, the second rate of `z1` in
//!   closed form from the relative velocity's snap (the support's exact, the body's from its
//!   acceleration's affine map) ([`third_order`]).
//!
//! Each order is smaller than the last by about `ε = (L/r)·Ω`, `Ω` the rate at which the motion
//! changes (the vibration, the turning of `e`, the body's oscillation on the contact): at
//! `k_t` = 1e12 on the transverse scenes, with `r` ≥ 1e-3 m/s, `|z1|` is a few 1e-4 of `L` and
//! `ε` a few 1e-4. The neglected third order is estimated from the largest terms over the step
//! ([`neglected`], checked against a tight integration of the full law). On the manifold the
//! body's equation is smooth and not stiff (its fastest rate is the Coulomb force's
//! `F_C/(m·r)`), so a plain Dormand–Prince step of the body, the deformation from the formula at
//! each stage, costs the same at any `k_t`; the deformation's error is the manifold's under the
//! body's error, `(L/r)·P⊥·δv`.
//!
//! The step is taken only where that is certified ([`Limit::start`], [`Limit::step`]): the
//! state's deformation on the manifold within a fraction of the tolerance at the start (after
//! a start or a reversal the exponential steps relax it first), `v_r` far from 0 at every stage
//! (the step is cut so that no sign change of `v_r` is within its reach), the expansion
//! converging and its neglected term below a fraction of the tolerance. Near a reversal or
//! while the body sticks it is not, and the exponential and plain steps take over. At the
//! default `k_t` = 1e8 (`ε` about 1) it never is, and the path is the one it was. An accepted
//! step leaves the manifold's deformation in the state, so that outputs, saved states and the
//! next call see it; nothing else is kept between calls.
//!
//! Measured at tolerance 1e-6 (CPU time on a shared machine, `examples/explicit_bench.rs`, the
//! cost at `k_t` = 1e12 against 1e8 per period): PaperTransverse 1.31 (4.2 without this step;
//! 23 steps and 187 right-hand sides per period, all on the manifold, against 42 and 678);
//! RigTransverse 1.36 from 0.1 s on (4.3), and 4.0 over its first 0.1 s from rest (5.8), where
//! the body still slides slowly in x and `v_r` passes near 0 twice a period: there the
//! exponential and plain steps resolve each passage. Against Radau IIA at 1e-10 from 0.1 to
//! 0.2 s, the largest `F_Fx` and `F_Fy` errors at 1e12 were 1.4e-8 and 5.6e-9 of `F_C`
//! (PaperTransverse) and 6.4e-8 and 2.5e-8 (RigTransverse) at tolerance 1e-6; 8.4e-11 and
//! 3.1e-11, 4.0e-9 and 1.3e-9 at 1e-7 (at 1e8 and 1e-6: 2.9e-9 and 2.9e-8, 1.0e-8 and 5.9e-8).
//! About a quarter of the manifold's attempts were rejected; DOPRI5's proportional-integral
//! controller on them (β = 0.04, 0.08) cost more (PaperTransverse 1.46 and 1.48 against 1.36
//! in the same run); Gustafsson's predictive step (`explicit_planar/`) halved them. Since the
//! planar path's plain steps became about 30 % cheaper (rotations of the harmonic phase,
//! stages in place), the ratios are PaperTransverse 1.8 and RigTransverse 1.8 from 0.1 s on,
//! 5.1 from rest, with the cost at 1e12 about what it was: a manifold stage takes a sine and
//! cosine of the support's phase and the manifold's own terms.
//!
//! At tolerance 1e-8 the neglected third order held the manifold's steps back from part of
//! every period (PaperTransverse at 1e12: 32 of 87 steps per period on it, 1102 right-hand
//! sides, 144 µs): taken to third order, every step is on it (53 steps, 350 right-hand
//! sides, 54 µs), `F_Fx` and `F_Fy` 3.1e-11 and 1.2e-11 of `F_C` off the path at 1e-10
//! (3.2e-11 and 1.3e-11 before). RigTransverse at 1e12 and 1e-8 over its first 0.1 s from
//! rest: 135 → 103 steps per period (49 on the manifold), 259 → 173 µs; `F_Fx` 5.6e-10 →
//! 7.9e-10 of `F_C` over that start (the body's global error along the spring, largest at
//! 20 ms), 3.3e-10 → 1.0e-10 from 0.1 to 0.3 s; `F_Fy` 1.2e-10 → 7.4e-11 and 1.1e-10 →
//! 3.5e-11.
//!
//! On VibratingContactLuGre (force drive along x, tolerance 1e-6, CPU time) at `k_t` = 1e12
//! the path with this step cost 7.1–7.5 times what it cost at 1e8 per period (8.1 since the
//! plain steps became cheaper; Radau IIA, which took such contacts before: 27 times): 137
//! steps per period, 10 of them on the
//! manifold (where `|v_r|` is above about 3e-4 m/s); the rest resolve each passage of `v_r`
//! through 0 and the contact's damped oscillation after it (about 40 plain steps of 1e-7 to
//! 3e-7 s each time, held there by the deformation's error), which this step does not reach.
//! Against Radau IIA at 1e-11 over 30 ms, the largest `F_Fx` error was 2.4e-6 of `F_C` at
//! 1e-6 (Radau at 1e-6: 2.2e-5) and 5.1e-8 at 1e-8 (6.5e-8); at 1e11, 4.3e-7 (1.9e-5) and
//! 3.8e-8 (9.6e-8). The window mean `F_mean` is less accurate than Radau's at tight
//! tolerances (at 1e11 and 1e-8: 1.2e-7 of `F_C` against 2.0e-8), with or without this step.

use crate::model::drive::{DriveInputs, DriveKind};
use crate::model::dynamics::System;
use crate::physics::{FrictionLaw, Vector};
use crate::solver::dopri::DoPriStep;
use crate::solver::MAX_DIM;
use crate::table::InputId;
use std::cell::Cell;

/// The largest first-order correction `|z1|/L` at which the expansion is used.
const FIRST_MAX: f64 = 1e-2;

/// The largest ratio `ε = |z2 − z1|/|z1|` of successive orders.
const RATIO_MAX: f64 = 0.1;

/// The relative tolerance of the error control (a tenth of the user's) at and below which a
/// Dahl contact's deformation on the manifold is taken to third order ([`third_order`]) at
/// the points where the second order is not certified by itself: the neglected third order
/// held the manifold's steps back from part of every period at tolerance 1e-8
/// (PaperTransverse at `k_t` = 1e12: 32 of 87 steps per period on it). At 1e-6 (relative
/// 1e-7) it would have taken RigTransverse's start from rest at 1e12 from 43.4 to 38.7 steps
/// per period (572 to 431 right-hand sides), `F_Fx` 1.11e-7 to 9.3e-8 of `F_C` off the path
/// at 1e-10 but `F_Fy` 2.20e-8 to 2.31e-8: not taken.
const THIRD_ORDER_BELOW: f64 = 1e-8;

/// The neglected third order ([`neglected`]) at most this fraction of `rtol·L` (the error
/// control's weight of a deformation component is about `2·rtol·L`).
const NEGLECT_FRACTION: f64 = 0.1;

/// The third order as a multiple of `ε·|z2 − z1|` ([`neglected`]).
const THIRD: f64 = 8.0;

/// The state's deformation at the start of a step at most this fraction of `rtol·L` off the
/// manifold.
const START_FRACTION: f64 = 1.0;

/// At every stage, `v_r + τ·a_r` stays at least this fraction of `|v_r|` away from 0 for `τ`
/// within half a step either side (the stages lie at most half a step apart): no sign change
/// of the relative velocity between them.
const REACH: f64 = 0.5;

/// The difference for the body's jerk over this time (s), or a 1e-12 of the time where that
/// is longer: the acceleration is affine, so that only rounding limits it (about 1e-11 of the
/// jerk on the transverse scenes). LuGre's `dz1/dt` is a central difference over the same
/// time either side, its truncation `(τ·Ω)²/6` relative (`Ω` the motion's rate: 3e-10 at
/// 2 kHz, 3e-4 at 20 MHz; at `t` = 1e5 s, where `τ` = 1e-7 s, 3e-7 at 2 kHz).
const JERK_STEP: f64 = 1e-9;

/// The first-order correction `z1 = −(L/r)²·P⊥·a_r` of the deformation on the slow manifold
/// (`L·e + z1`, `e = v_r/|v_r|`, `P⊥ = I − e·eᵀ`), given the relative velocity `vr ≠ 0` and
/// its rate `ar`.
#[inline(always)]
pub fn correction<V: Vector>(len: f64, vr: V, ar: V) -> V {
    let r2 = vr.dot(vr);
    let perp = ar - vr * (vr.dot(ar) / r2);
    perp * (-len * len / r2)
}

/// The change of the manifold's leading term `L·e` under a small change `dv` of the relative
/// velocity `vr`: `(L/r)·P⊥·dv`.
#[inline(always)]
fn correction_of_velocity<V: Vector>(len: f64, vr: V, dv: V) -> V {
    let r2 = vr.dot(vr);
    (dv - vr * (vr.dot(dv) / r2)) * (len / r2.sqrt())
}

/// A point of the slow manifold: the deformation there and what certifies it.
#[derive(Clone, Copy, Debug)]
pub struct Point<V> {
    /// The deformation to second order: Dahl's `L·e + z2`, LuGre's `sign(v_r)·g + z2`.
    pub s: V,
    /// `|z1|²`.
    pub first2: f64,
    /// `|z2 − z1|²`.
    pub second2: f64,
    /// `|z3 − z2|²` where the third order is taken (where the second order is not certified
    /// at the point, [`Limit::third`]).
    pub third2: Option<f64>,
    /// `v_r`.
    pub vr: V,
    /// `|v_r|`.
    pub r: f64,
    /// `a_r`: Dahl's under the Coulomb force, LuGre's to first order (with the damping's pull).
    pub ar: V,
    /// The manifold's length at the point: Dahl's `s_ss`, LuGre's `g(v_r)`.
    pub len: f64,
    /// A bound on what an error of the deformation weighs in the force, relative to `k_t`: 1
    /// for Dahl; LuGre's `1 + h_t·|v_r|/(k_t·g)`, its damping taking the rate
    /// `ds/dt = −(|v_r|/g)·z` (the factor itself is `|1 − h_t·|v_r|/(k_t·g)|`).
    pub weight: f64,
    /// LuGre's `d(sign(v_r)·g)/dv_r`: the manifold's change with the body's velocity (0 for
    /// Dahl, whose change is [`correction_of_velocity`]).
    pub slope: f64,
}

/// The manifold's deformation to second order ([module docs](self)) at the relative velocity
/// `vr ≠ 0`, given its rate `a0` under the Coulomb force (the deformation `L·e`), its rate
/// `a1` under the deformation `L·e + z1`, and the rate of `a0` along the motion, `jerk`:
/// `z2 = −(L/r)²·P⊥·a1 − (L/r)·dz1/dt`, with
/// `dz1/dt = −L²·(dp/dt/r² − 2·(e·a)·p/r³)`, `p = P⊥·a`,
/// `dp/dt = da/dt − ė·(e·a) − e·(ė·a + e·da/dt)`, `ė = p/r`.
#[inline(always)]
pub fn manifold<V: Vector>(len: f64, vr: V, a0: V, a1: V, jerk: V) -> Point<V> {
    let r = vr.norm();
    let inv_r = 1.0 / r;
    let e = vr * inv_r;
    let ea = e.dot(a0);
    let p = a0 - e * ea;
    let z1 = p * (-len * len * inv_r * inv_r);
    let e_dot = p * inv_r;
    let p_dot = jerk - e_dot * ea - e * (e_dot.dot(a0) + e.dot(jerk));
    let dz1 = (p_dot * (inv_r * inv_r) - p * (2.0 * ea * inv_r * inv_r * inv_r)) * (-len * len);
    let z2 = correction(len, vr, a1) - dz1 * (len * inv_r);
    Point {
        s: e * len + z2,
        first2: z1.dot(z1),
        second2: (z2 - z1).dot(z2 - z1),
        third2: None,
        vr,
        r,
        ar: a0,
        len,
        weight: 1.0,
        slope: 0.0,
    }
}

/// The estimate of the neglected third order from the largest first and second order terms
/// over a step: `THIRD·ε·|z2 − z1|` with `ε = |z2 − z1|/|z1|`. The factor [`THIRD`] was measured
/// against a tight integration of the full law (the unit test below: the third order 3.6 times
/// `ε·|z2 − z1|` for a transverse vibration).
#[inline(always)]
pub fn neglected(first: f64, second: f64) -> f64 {
    if second == 0.0 {
        0.0
    } else {
        THIRD * second / first * second
    }
}

/// The third-order term of the expansion's own rate, `(L/r)·d/dt((L/r)·dz1/dt)`
/// `= (L/r)²·(d²z1/dt² − (ṙ/r)·dz1/dt)`, at the relative velocity `vr ≠ 0` with its rate `a0`
/// (under the Coulomb force), its jerk `jerk` and its snap, `snap(ë)` given the second rate
/// of `e` (the force's second rate is `F(L·ë)`): with `c = e·a = ṙ`, `p = P⊥·a`, `ė = p/r`,
/// `ċ = ė·a + e·ȧ`, `ṗ = ȧ − ė·c − e·ċ`, `ë = ṗ/r − p·c/r²`,
/// `c̈ = ë·a + 2·ė·ȧ + e·ä`, `p̈ = ä − ë·c − 2·ė·ċ − e·c̈`, and `z1 = −L²·p·u`, `u = 1/r²`.
/// The rest of the third order, the body's response to `z2 − z1` (its force), is
/// [`correction`] of that response.
#[inline(always)]
pub fn third_order<V: Vector>(len: f64, vr: V, a0: V, jerk: V, snap: impl FnOnce(V) -> V) -> V {
    let r = vr.norm();
    let inv_r = 1.0 / r;
    let e = vr * inv_r;
    let c = e.dot(a0);
    let p = a0 - e * c;
    let e_dot = p * inv_r;
    let c_dot = e_dot.dot(a0) + e.dot(jerk);
    let p_dot = jerk - e_dot * c - e * c_dot;
    let e_ddot = p_dot * inv_r - p * (c * inv_r * inv_r);
    let snap = snap(e_ddot);
    let c_ddot = e_ddot.dot(a0) + 2.0 * e_dot.dot(jerk) + e.dot(snap);
    let p_ddot = snap - e_ddot * c - e_dot * (2.0 * c_dot) - e * c_ddot;
    let u = inv_r * inv_r;
    let u_dot = -2.0 * c * u * inv_r;
    let u_ddot = (-2.0 * c_dot * inv_r + 6.0 * c * c * u) * u;
    let l2 = -len * len;
    let dz1 = (p_dot * u + p * u_dot) * l2;
    let ddz1 = (p_ddot * u + p_dot * (2.0 * u_dot) + p * u_ddot) * l2;
    let k = len * inv_r;
    (ddz1 - dz1 * (c * inv_r)) * (k * k)
}

/// The end of a step on the manifold: its time, the body's state (its first `N_BODY`
/// components) and the point.
type End<V> = (f64, [f64; MAX_DIM], Point<V>);

/// Whose slow manifold.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// A planar Dahl contact with `kappa = 1`, of the length `s_ss` ([module docs](self)).
    Dahl { len: f64 },
    /// A LuGre contact on the x axis ([`Limit::lugre_point`]), whose body's acceleration
    /// along x changes by `b` per unit of friction force (it is affine in the force, with a
    /// slope that neither the body's state nor the drive's inputs change: `−1/m`).
    LuGre { b: f64 },
}

/// The largest gain `|B·κ·d(σ·g)/dv_r|` of the LuGre manifold's loop through the body
/// ([`Limit::lugre_first`]): where the damping's pull on the body comes near its inertia, the
/// manifold is not taken (its relaxation rate is about `(|v_r|/g)·(1 − gain)`: at least half
/// of it; a large negative gain, which would only speed it, is refused too, conservatively).
const LOOP_MAX: f64 = 0.5;

/// The manifold of one contact during one call of the planar explicit path.
pub(super) struct Limit<'s, 'a, V: Vector, L: FrictionLaw, D: DriveKind<V>> {
    sys: &'s System<'a, V, L, D>,
    kind: Kind,
    /// The step's relative tolerance (the error control's).
    rtol: f64,
    /// Whether Dahl's deformation is taken to third order ([`THIRD_ORDER_BELOW`]).
    third: bool,
    /// The end of the last step on the manifold: its time, body and point.
    last: Cell<Option<End<V>>>,
    /// The support's motion at the last time asked ([`Limit::support`]): a step's last two
    /// stages share their time.
    motion: Cell<(f64, [V; 4])>,
}

impl<'s, 'a, V: Vector, L: FrictionLaw, D: DriveKind<V>> Limit<'s, 'a, V, L, D> {
    /// The manifold of a planar Dahl contact with `kappa = 1`, or of a LuGre contact on the
    /// x axis, at a constant load with a moving body; `None` for the others.
    pub(super) fn new(sys: &'s System<'a, V, L, D>, rtol: f64) -> Option<Self> {
        let dynamics = sys.dynamics;
        let law = &dynamics.law;
        if D::N_BODY == 0 || dynamics.load.is_some() {
            return None;
        }
        let kind = match law.relaxation() {
            // Dahl with kappa = 1: the relaxation's exponent 1, and a law linear in `s`.
            Some(relax)
                if V::DIM == 2
                    && relax.exponent == 1.0
                    && law.linear(V::from_xy(1.0, 0.0)).is_some() =>
            {
                Kind::Dahl { len: relax.length }
            }
            None if V::DIM == 1 && law.steady(1.0).is_some() => {
                let (body, d) = ([0.0; MAX_DIM], dynamics.drive_inputs(0.0));
                let acc = |f: f64| {
                    let force = V::from_xy(f, 0.0);
                    dynamics
                        .drive
                        .acceleration(&body[..D::N_BODY], force, &d, 0.0)
                        .x()
                };
                Kind::LuGre {
                    b: acc(1.0) - acc(0.0),
                }
            }
            _ => return None,
        };
        Some(Limit {
            sys,
            kind,
            rtol,
            third: matches!(kind, Kind::Dahl { .. }) && rtol <= THIRD_ORDER_BELOW,
            last: Cell::new(None),
            motion: Cell::new((f64::NAN, [V::default(); 4])),
        })
    }

    /// The support's velocity, acceleration, jerk and snap at `t`: the harmonic source's (one
    /// argument reduction), and the input tracks' values and slopes. The velocity has the
    /// right-hand side's bits and is remembered for the stage's evaluation at `t`.
    #[inline(always)]
    fn support(&self, t: f64) -> [V; 4] {
        let (known, motion) = self.motion.get();
        if known == t {
            self.sys.remember_support(t, motion[0]);
            return motion;
        }
        let dynamics = self.sys.dynamics;
        let (mut vs, mut acc) = (V::default(), V::default());
        let (mut jerk, mut snap) = (V::default(), V::default());
        if let Some(h) = &dynamics.harmonic {
            let ((vx, vy), (ax, ay)) = h.velocity_acceleration(t);
            (vs, acc) = (V::from_xy(vx, vy), V::from_xy(ax, ay));
            let w = std::f64::consts::TAU * h.f;
            jerk = vs * (-w * w);
            snap = acc * (-w * w);
        }
        if self.sys.input_support {
            let (x, y) = (
                &dynamics.tracks[InputId::VSx.index()],
                &dynamics.tracks[InputId::VSy.index()],
            );
            vs = vs + V::from_xy(x.at(t), y.at(t));
            acc = acc + V::from_xy(x.slope, y.slope);
        }
        self.sys.remember_support(t, vs);
        self.motion.set((t, [vs, acc, jerk, snap]));
        [vs, acc, jerk, snap]
    }

    /// The manifold at `(t, y)` (`y` the state, the body from `V::DIM` on); the body's jerk
    /// from a difference along its motion (its acceleration is affine in the body's state, the
    /// force and the drive's inputs: exact but for rounding and the spring's far end, quadratic
    /// in time under an input derivative of `v_d`).
    #[inline(always)]
    pub(super) fn point<const N: usize>(&self, t: f64, y: &[f64]) -> Option<Point<V>> {
        match self.kind {
            Kind::Dahl { len } => self.dahl_point::<N>(len, t, y),
            Kind::LuGre { b } => self.lugre_point::<N>(b, t, y),
        }
    }

    /// [`Limit::point`] of a planar Dahl contact of the length `len`.
    #[inline(always)]
    fn dahl_point<const N: usize>(&self, len: f64, t: f64, y: &[f64]) -> Option<Point<V>> {
        let dynamics = self.sys.dynamics;
        let law = &dynamics.law;
        let drive = &dynamics.drive;
        let a_d = dynamics.tracks[InputId::VD.index()].slope;
        let body = &y[V::DIM..N];
        let d = dynamics.drive_inputs(t);
        let [vs, acc_s, jerk_s, snap_s] = self.support(t);
        let vr = drive.velocity(body, &d) - vs;
        let r = vr.norm();
        if !(r > 0.0 && r.is_finite()) {
            return None;
        }
        // Dahl's force `k_t·s` (it reads neither `v_r` nor `ds/dt`).
        let force = |s: V| law.force(s, vr, V::default());
        let s0 = vr * (len / r);
        let f0 = force(s0);
        let acc0 = drive.acceleration(body, f0, &d, a_d);
        let a0 = acc0 - acc_s;
        let z1 = correction(len, vr, a0);
        let a1 = drive.acceleration(body, force(s0 + z1), &d, a_d) - acc_s;
        // The body's jerk along its motion under the Coulomb force, whose rate is
        // `F(L·ė)`, `ė = P⊥·a/r` (the law's force linear in `s`).
        let t2 = t + JERK_STEP.max(1e-12 * t.abs());
        let tau = t2 - t;
        let mut rate = [0.0; N];
        let mut moved = [0.0; N];
        drive.body_rate(body, f0, &d, &mut rate[..D::N_BODY]);
        for i in 0..D::N_BODY {
            moved[i] = body[i] + tau * rate[i];
        }
        let e_dot = (a0 - vr * (vr.dot(a0) / (r * r))) * (1.0 / r);
        let f2 = f0 + force(e_dot * len) * tau;
        let d2 = dynamics.drive_inputs(t2);
        let acc2 = drive.acceleration(&moved[..D::N_BODY], f2, &d2, a_d);
        let jerk = (acc2 - acc0) * (1.0 / tau) - jerk_s;
        let point = manifold(len, vr, a0, a1, jerk);
        if !self.third || self.converges(point.first2, point.second2, len, point.weight) {
            return Some(point);
        }
        // The third order ([`THIRD_ORDER_BELOW`]): the body's second rate along the motion
        // (the same difference of its rate), its snap from the acceleration's affine map at
        // `t` (the drive's inputs' second rates left out: zero but for the spring's far end
        // under an input derivative of `v_d`), and the body's response to `z2 − z1`.
        let mut rate2 = [0.0; N];
        drive.body_rate(&moved[..D::N_BODY], f2, &d2, &mut rate2[..D::N_BODY]);
        let mut bent = [0.0; N];
        for i in 0..D::N_BODY {
            bent[i] = body[i] + (rate2[i] - rate[i]);
        }
        let snap = |e_ddot: V| {
            let f = f0 + force(e_ddot * len) * tau;
            (drive.acceleration(&bent[..D::N_BODY], f, &d, a_d) - acc0) * (1.0 / tau) - snap_s
        };
        let a2 = drive.acceleration(body, force(point.s), &d, a_d) - acc_s;
        let z3 = correction(len, vr, a2 - a1) + third_order(len, vr, a0, jerk, snap);
        Some(Point {
            s: point.s + z3,
            third2: Some(z3.dot(z3)),
            ..point
        })
    }

    /// [`Limit::point`] of a LuGre contact on the x axis. With `σ = sign(v_r)`, `r = |v_r|`,
    /// `g = g(v_r)` and `s = σ·g + z`, the law `ds/dt = v_r − (r/g)·s` reads
    /// `z = −(g/r)·D`, `D = ds/dt = σ·g'·a_r + dz/dt`, and the force
    /// `F = k_t·σ·g + h_v·v_r + κ·D` with `κ = h_t − k_t·g/r`. The body's acceleration is affine
    /// in the force, `a_r = a0 + B·(F − F0)` (`a0` under `F0 = k_t·σ·g + h_v·v_r`, `B` the slope
    /// `b` of [`Kind::LuGre`]), so that `D` follows exactly from its own equation where the
    /// damping's pull `κ` on the body is large ([`Limit::lugre_first`]):
    ///
    /// - first order: `D1 = σ·g'·a0/(1 − B·κ·σ·g')`, `z1 = −(g/r)·D1`;
    /// - second order: `z2 = z1 − (g/r)·(dz1/dt)/(1 − B·κ·σ·g')`, the rate of `z1` from `z1`
    ///   again along the motion a short time `τ` either side ([`JERK_STEP`]; a central
    ///   difference, its truncation `(τ·Ω)²/6` relative, the support's velocity and
    ///   acceleration there from their Taylor series).
    ///
    /// Each order is smaller than the last by about `(g/r)·Ω`; an error `δz` of the
    /// deformation weighs `|k_t − h_t·r/g|·δz` in the force, at most [`Point::weight`] times
    /// `k_t·δz`.
    #[inline(always)]
    fn lugre_point<const N: usize>(&self, b: f64, t: f64, y: &[f64]) -> Option<Point<V>> {
        let dynamics = self.sys.dynamics;
        let body = &y[V::DIM..N];
        let d = dynamics.drive_inputs(t);
        let [vs, acc_s, jerk_s, _] = self.support(t);
        let first = self.lugre_first(b, body, &d, vs, acc_s)?;
        // `z1` a time `τ` either side along the motion (the body moved by its rate under the
        // first-order force, the support by its Taylor series): a central difference.
        let tau = (t + JERK_STEP.max(1e-12 * t.abs())) - t;
        let mut rate = [0.0; N];
        dynamics.drive.body_rate(
            body,
            V::from_xy(first.force, 0.0),
            &d,
            &mut rate[..D::N_BODY],
        );
        let z1_at = |dt: f64| {
            let mut moved = [0.0; N];
            for i in 0..D::N_BODY {
                moved[i] = body[i] + dt * rate[i];
            }
            let vs_at = vs + acc_s * dt + jerk_s * (0.5 * dt * dt);
            let acc_s_at = acc_s + jerk_s * dt;
            let inputs = dynamics.drive_inputs(t + dt);
            self.lugre_first(b, &moved[..D::N_BODY], &inputs, vs_at, acc_s_at)
                .map(|p| p.z1)
        };
        let dz1 = (z1_at(tau)? - z1_at(-tau)?) / (2.0 * tau);
        let z2 = first.z1 - first.g / first.r * dz1 / first.denom;
        let g = first.g;
        let point = Point {
            s: V::from_xy(first.sigma * g + z2, 0.0),
            first2: first.z1 * first.z1,
            second2: (z2 - first.z1) * (z2 - first.z1),
            third2: None,
            vr: first.vr,
            r: first.r,
            ar: V::from_xy(first.ar, 0.0),
            len: g,
            weight: first.weight,
            slope: first.slope,
        };
        (point.s.x().is_finite() && point.second2.is_finite()).then_some(point)
    }

    /// The LuGre manifold's first order at the body `body` with the drive's inputs `d`, the
    /// support's velocity `vs` and acceleration `acc_s`, the acceleration's slope in the force
    /// `b` ([`Kind::LuGre`]) ([`Limit::lugre_point`]); `None` at `v_r = 0` or where the loop
    /// through the body is strong ([`LOOP_MAX`]).
    #[inline(always)]
    fn lugre_first(
        &self,
        b: f64,
        body: &[f64],
        d: &DriveInputs,
        vs: V,
        acc_s: V,
    ) -> Option<LuGreFirst<V>> {
        let dynamics = self.sys.dynamics;
        let (law, drive) = (&dynamics.law, &dynamics.drive);
        let a_d = dynamics.tracks[InputId::VD.index()].slope;
        let vr = drive.velocity(body, d) - vs;
        let v = vr.x();
        let r = v.abs();
        if !(r > 0.0 && r.is_finite()) {
            return None;
        }
        let st = law.steady(v)?;
        let sigma = v.signum();
        let f0 = law.force(V::from_xy(sigma * st.g, 0.0), vr, V::default());
        let acc0 = drive.acceleration(body, f0, d, a_d).x();
        let slope = sigma * st.dg;
        let kappa = st.damping - st.k_t * st.g / r;
        let gain = b * kappa * slope;
        if gain.is_nan() || gain.abs() > LOOP_MAX {
            return None;
        }
        let denom = 1.0 - gain;
        let ar = (acc0 - acc_s.x()) / denom;
        let rate = slope * ar;
        let z1 = -(st.g / r) * rate;
        let force = law.force(
            V::from_xy(sigma * st.g + z1, 0.0),
            vr,
            V::from_xy(rate, 0.0),
        );
        Some(LuGreFirst {
            vr,
            r,
            sigma,
            g: st.g,
            slope,
            denom,
            ar,
            z1,
            force: force.x(),
            weight: 1.0 + st.damping * r / (st.k_t * st.g),
        })
    }
}

/// The manifold's steps: where one starts, and the step of the body alone on it.
impl<V: Vector, L: FrictionLaw, D: DriveKind<V>> Limit<'_, '_, V, L, D> {
    /// The manifold at the start of a step from `(t, u)` where the state's deformation is on
    /// it (within the tolerance's fraction [`START_FRACTION`]) and the expansion converges
    /// there; `None` where not (the caller then takes its other steps). With the longest step
    /// within reach of the start ([`Start::reach`]). The end of the last step taken on the
    /// manifold is remembered.
    pub(super) fn start<const N: usize>(&self, t: f64, u: &[f64]) -> Option<Start<V>> {
        let body = &u[V::DIM..N];
        let point = match self.last.get() {
            Some((te, ref be, p)) if te == t && be[..D::N_BODY] == *body => p,
            _ => self.point::<N>(t, u)?,
        };
        let s0 = V::read(&u[..V::DIM]);
        let on = (s0 - point.s).norm() <= START_FRACTION * self.rtol * point.len;
        let converges = self.certified(&point);
        (on && self.small(&point) && converges).then(|| Start {
            point,
            reach: reach(&point),
        })
    }

    /// One Dormand–Prince step of length `h` (at most the start's reach) on the manifold from
    /// `start` at `(t, u)`, or `None` where it is not certified (the caller then takes its
    /// other steps). `stage(i, t, y, s)` is the right-hand side at stage `i` with the
    /// deformation `s`. On success the step's stages carry the manifold's deformation wherever
    /// they were evaluated, and the end state (returned with the step) the manifold's
    /// deformation at the end; its first stage is `(t, u)` with the deformation moved onto the
    /// manifold (by at most [`START_FRACTION`] of the tolerance), the first derivative `k1`
    /// recomputed where it moved.
    #[allow(clippy::too_many_arguments)] // the step's own arguments, and the start
    #[inline(always)]
    pub(super) fn step<const N: usize, const M: usize>(
        &self,
        start: &Start<V>,
        t: f64,
        u: &[f64; M],
        k1: &[f64; M],
        h: f64,
        mut stage: impl FnMut(usize, f64, &[f64; M], V) -> [f64; M],
    ) -> Option<(DoPriStep<M>, [f64; M])> {
        let p0 = start.point;
        let mut ok = self.fits(&p0, h);
        if !ok {
            return None;
        }
        // The largest terms over the step's points taken to second order (each point taken to
        // third order is certified by itself).
        let (mut first2, mut second2, mut len, mut weight) = match p0.third2 {
            None => (p0.first2, p0.second2, p0.len, p0.weight),
            Some(_) => (0.0, 0.0, f64::INFINITY, 0.0),
        };
        if p0.third2.is_some() && !self.certified(&p0) {
            return None;
        }
        let s0 = V::read(&u[..V::DIM]);
        let mut u0 = *u;
        p0.s.write(&mut u0[..V::DIM]);
        let k1 = if p0.s == s0 {
            *k1
        } else {
            stage(0, t, &u0, p0.s)
        };
        let mut end = None;
        let step = DoPriStep::take_staged(
            &mut |i: usize, tt: f64, y: &[f64; M]| {
                let p = self.point::<N>(tt, y);
                let s = match p {
                    Some(p) if ok && self.fits(&p, h) => {
                        if p.third2.is_some() {
                            ok = self.certified(&p);
                        } else {
                            first2 = first2.max(p.first2);
                            second2 = second2.max(p.second2);
                            len = len.min(p.len);
                            weight = weight.max(p.weight);
                        }
                        if i == 6 {
                            end = Some((tt, p));
                        }
                        p.s
                    }
                    _ => {
                        ok = false;
                        V::read(&y[..V::DIM])
                    }
                };
                stage(i, tt, y, s)
            },
            t,
            &u0,
            &k1,
            h,
        );
        if !ok || !self.converges(first2, second2, len, weight) {
            return None;
        }
        let (te, pe) = end?;
        let mut u1 = step.end();
        pe.s.write(&mut u1[..V::DIM]);
        // The deformation's error estimate: the manifold's change under the body's, to first
        // order `(L/r)·P⊥·δv` (Dahl), `d(σ·g)/dv_r·δv` (LuGre) (the body's velocity is affine
        // in its state).
        let mut step = step;
        let dynamics = self.sys.dynamics;
        let d = dynamics.drive_inputs(te);
        let zero = [0.0; MAX_DIM];
        let dv = dynamics.drive.velocity(&step.err[V::DIM..N], &d)
            - dynamics.drive.velocity(&zero[..D::N_BODY], &d);
        let ds = match self.kind {
            Kind::Dahl { len } => correction_of_velocity(len, pe.vr, dv),
            Kind::LuGre { .. } => dv * pe.slope,
        };
        ds.write(&mut step.err[..V::DIM]);
        let mut be = [0.0; MAX_DIM];
        be[..D::N_BODY].copy_from_slice(&u1[V::DIM..N]);
        self.last.set(Some((te, be, pe)));
        Some((step, u1))
    }

    /// Whether the expansion converges ([`RATIO_MAX`]) and its neglected third order
    /// ([`neglected`]), weighed by `weight` ([`Point::weight`]), is below its share of the
    /// tolerance on the length `len`, given the squares of the largest first and second order
    /// terms over a step.
    #[inline(always)]
    fn converges(&self, first2: f64, second2: f64, len: f64, weight: f64) -> bool {
        second2 == 0.0
            || (second2 <= RATIO_MAX * RATIO_MAX * first2
                && neglected(first2.sqrt(), second2.sqrt()) * weight
                    <= NEGLECT_FRACTION * self.rtol * len)
    }

    /// Whether one point's expansion is certified: to second order as [`Limit::converges`];
    /// taken to third order, its orders converging and its neglected fourth order
    /// ([`neglected`] of the second and third) below the same share of the tolerance.
    #[inline(always)]
    fn certified(&self, p: &Point<V>) -> bool {
        match p.third2 {
            None => self.converges(p.first2, p.second2, p.len, p.weight),
            Some(third2) => {
                let r2 = RATIO_MAX * RATIO_MAX;
                p.second2 <= r2 * p.first2
                    && (third2 == 0.0
                        || (third2 <= r2 * p.second2
                            && neglected(p.second2.sqrt(), third2.sqrt()) * p.weight
                                <= NEGLECT_FRACTION * self.rtol * p.len))
            }
        }
    }

    /// Whether the first-order term is within [`FIRST_MAX`] and the deformation finite.
    #[inline(always)]
    fn small(&self, p: &Point<V>) -> bool {
        let most = FIRST_MAX * p.len;
        p.first2 <= most * most && p.s.x().is_finite() && p.s.y().is_finite()
    }

    /// Whether one point is within the expansion's reach over a step of length `h`.
    #[inline(always)]
    fn fits(&self, p: &Point<V>, h: f64) -> bool {
        self.small(p) && h <= reach(p)
    }
}

/// The LuGre manifold's first order at one point ([`Limit::lugre_first`]).
#[derive(Clone, Copy, Debug)]
struct LuGreFirst<V> {
    vr: V,
    r: f64,
    sigma: f64,
    g: f64,
    /// `d(σ·g)/dv_r`.
    slope: f64,
    /// `1 − B·κ·σ·g'`.
    denom: f64,
    /// `a_r` to first order.
    ar: f64,
    z1: f64,
    /// The force along x to first order.
    force: f64,
    /// [`Point::weight`].
    weight: f64,
}

/// The manifold at the start of a step, certified there.
#[derive(Clone, Copy, Debug)]
pub(super) struct Start<V> {
    point: Point<V>,
    /// The longest step within reach of the start: `v_r + τ·a_r` at least [`REACH`] of
    /// `|v_r|` away from 0 for `|τ|` up to half of it.
    pub(super) reach: f64,
}

/// The longest step `h` for which `v_r + τ·a_r` stays at least [`REACH`]`·|v_r|` away from 0
/// for `|τ| ≤ h/2` (infinite where its line passes 0 farther than that).
#[inline(always)]
fn reach<V: Vector>(p: &Point<V>) -> f64 {
    let (a2, b, r2) = (p.ar.dot(p.ar), p.vr.dot(p.ar), p.r * p.r);
    let floor = REACH * REACH * r2;
    // |v_r + τ·a_r|² = r2 + 2·b·τ + a2·τ², its least value r2 − b²/a2.
    let disc = b * b - a2 * (r2 - floor);
    if a2.is_nan() || a2 <= 0.0 || disc <= 0.0 {
        return f64::INFINITY;
    }
    // The root of |v_r + τ·a_r|² = floor nearest 0, in the stable form.
    2.0 * (r2 - floor) / (b.abs() + disc.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::contact::Contact;
    use crate::model::drive::Force;
    use crate::physics::{LuGre, Planar};
    use crate::solver::OdeSystem;
    use crate::table::{Config, Drive, Lateral, Law, Motion, Params};
    use nalgebra::SVector;

    /// The LuGre manifold against a tight integration of the full law with its body: a
    /// longitudinal LuGre contact at `k_t` = 1e10 under a force drive, the body sliding at about
    /// `v_S` over a support vibrating at a fifth of that (so `v_r` stays within 0.8 to 1.6
    /// `v_S`, where `g` varies most), its contact damping `2·sqrt(m·k_t)` and viscous term on.
    /// Classical Runge–Kutta of the whole right-hand side at a step of 1/100 of the relaxation
    /// time `g/|v_r|`, from a start on the manifold: past the start's relaxation the manifold's
    /// deformation agrees with the integration within the neglected third order estimated by
    /// the certificate ([`neglected`]), and the first order alone is off by about the
    /// second-order term. (Measured: first order 5.7e-4 of `g`, second 1.3e-5, the first order
    /// alone off by 1.32e-5, the second by 2.7e-7 against the estimate's 2.4e-6.)
    #[test]
    fn lugre_manifold_is_the_relaxed_deformation() {
        let c = Config {
            law: Law::LuGre,
            motion: Motion::Longitudinal,
            drive: Drive::Force,
            lateral: Lateral::Guided,
            harmonic: true,
            input_support: false,
            normal_input: false,
        };
        let p = Params {
            k_t: 1e10,
            u0: 2e-8,
            h_v: 20.0,
            ..Params::default()
        };
        let mut contact = Contact::<f64, LuGre, Force, 3>::new_local(c, p, 1e-6);
        let v0 = 1.2e-3;
        // About the friction at v0, so that the body slides on.
        let steady = contact.dynamics.law.steady(v0).unwrap();
        let f_d = steady.k_t * steady.g + p.h_v * v0;
        contact.dynamics.tracks[InputId::FD.index()].value = f_d;
        let sys = contact.system();
        let limit = Limit::new(&sys, 1e-7).expect("a LuGre contact on x has the manifold");
        let rhs = |t: f64, y: &SVector<f64, 3>| OdeSystem::<3>::rhs(&sys, t, y);
        let mut y = SVector::<f64, 3>::new(0.0, 0.0, v0);
        y[0] = limit.point::<3>(0.0, y.as_slice()).unwrap().s;
        let h = 0.01 * steady.g / (0.8 * p.v_s);
        let (mut t, t_end) = (0.0, 2e-4);
        let (mut worst, mut worst_first): (f64, f64) = (0.0, 0.0);
        let (mut first, mut second): (f64, f64) = (0.0, 0.0);
        let (mut steps, mut samples) = (0u64, 0);
        while t < t_end {
            let k1 = rhs(t, &y);
            let k2 = rhs(t + h / 2.0, &(y + k1 * (h / 2.0)));
            let k3 = rhs(t + h / 2.0, &(y + k2 * (h / 2.0)));
            let k4 = rhs(t + h, &(y + k3 * h));
            y += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
            t += h;
            steps += 1;
            if t > 2e-5 && steps.is_multiple_of(101) {
                let pt = limit.point::<3>(t, y.as_slice()).unwrap();
                let vr = pt.vr;
                assert!(
                    (0.8 * p.v_s..1.6 * p.v_s).contains(&vr),
                    "{t}: v_r {vr} left the range"
                );
                let g = pt.len;
                worst = worst.max((pt.s - y[0]).abs() / g);
                // The first order alone: z1 from the point's own first order.
                let z1 = pt.first2.sqrt() * (pt.s - vr.signum() * g).signum();
                worst_first = worst_first.max((vr.signum() * g + z1 - y[0]).abs() / g);
                first = first.max(pt.first2.sqrt() / g);
                second = second.max(pt.second2.sqrt() / g);
                samples += 1;
            }
        }
        assert!(samples > 50, "{samples}");
        assert!(first > 1e-5, "a first order worth testing: {first:e}");
        assert_orders("LuGre", worst_first, worst, first, second, 0.05);
    }

    /// The expansion's orders against a tight integration of the full law, each relative to
    /// the manifold's length: the first order alone is off by the second-order term (the
    /// largest of each within 10 %), and the second order by at most the certificate's
    /// estimate of the third ([`neglected`]) and at least `floor` of it (the estimate is not
    /// loose by more).
    fn assert_orders(
        what: &str,
        worst_first: f64,
        worst: f64,
        first: f64,
        second: f64,
        floor: f64,
    ) {
        assert!(
            worst_first > 0.9 * second && worst_first < 1.1 * second,
            "{what}: {worst_first:e} {second:e}"
        );
        let bound = neglected(first, second);
        assert!(
            worst <= bound && worst >= floor * bound,
            "{what}: {worst:e} {bound:e}"
        );
    }

    /// A tight integration of the full `ds/dt = v_r − |v_r|·s/L` from rest to 1.3e-4 s
    /// (classical Runge–Kutta at a step far below the relaxation time `L/|v_r|`, `v_r` at
    /// least `v0`), handing `sample` the time and deformation at every 97th step after 2e-5 s,
    /// well past the start's relaxation (its time is below 1e-7 s).
    fn relax(len: f64, v0: f64, vr: impl Fn(f64) -> Planar, mut sample: impl FnMut(f64, Planar)) {
        let rate = |t: f64, s: Planar| {
            let v = vr(t);
            v - s * (v.norm() / len)
        };
        let h = 0.02 * len / (v0 * 3.0);
        let (mut t, mut s) = (0.0, Planar::default());
        let mut steps = 0u64;
        while t < 1.3e-4 {
            let k1 = rate(t, s);
            let k2 = rate(t + h / 2.0, s + k1 * (h / 2.0));
            let k3 = rate(t + h / 2.0, s + k2 * (h / 2.0));
            let k4 = rate(t + h, s + k3 * h);
            s = s + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
            t += h;
            steps += 1;
            if t > 2e-5 && steps.is_multiple_of(97) {
                sample(t, s);
            }
        }
    }

    /// The third order ([`third_order`]) against the same tight integration as
    /// [`manifold_is_the_relaxed_deformation`], at lengths where it stands out of the
    /// integration's rounding: the second order alone is off by about the third-order term,
    /// and the third order by at most the estimate of the fourth ([`neglected`] of the
    /// second and third).
    #[test]
    fn third_order_is_the_relaxed_deformation() {
        let (v0, amp, omega) = (1e-3, 2.5e-3, std::f64::consts::TAU * 2000.0);
        let w2 = omega * omega;
        let vr = move |t: f64| Planar::from_xy(v0, amp * (omega * t).cos());
        let ar = move |t: f64| Planar::from_xy(0.0, -amp * omega * (omega * t).sin());
        let jerk = move |t: f64| vr(t) * (-w2) + Planar::from_xy(v0 * w2, 0.0);
        let snap = move |t: f64| ar(t) * (-w2);
        for len in [1.1e-10, 1.1e-9] {
            let (mut worst, mut worst_second): (f64, f64) = (0.0, 0.0);
            let (mut second, mut third): (f64, f64) = (0.0, 0.0);
            relax(len, v0, vr, |t, s| {
                let p = manifold(len, vr(t), ar(t), ar(t), jerk(t));
                let z3 = third_order(len, vr(t), ar(t), jerk(t), |_| snap(t));
                worst = worst.max((p.s + z3 - s).norm() / len);
                worst_second = worst_second.max((p.s - s).norm() / len);
                second = second.max(p.second2.sqrt() / len);
                third = third.max(z3.norm() / len);
            });
            assert!(third > 1e-9, "a third order worth testing: {third:e}");
            assert_orders(
                &format!("L = {len}"),
                worst_second,
                worst,
                second,
                third,
                0.02,
            );
        }
    }

    /// The manifold against a tight integration of the full `ds/dt = v_r − |v_r|·s/L` for a
    /// prescribed smooth `v_r(t)` (a sliding velocity and a transverse vibration, the
    /// transverse scenes' shape): after the start's relaxation has died away, the second-order
    /// deformation agrees with the integration to within the neglected third order, and the
    /// first order alone is off by about the second-order term it leaves out.
    #[test]
    fn manifold_is_the_relaxed_deformation() {
        let (v0, amp, omega) = (1e-3, 2.5e-3, std::f64::consts::TAU * 2000.0);
        let vr = move |t: f64| Planar::from_xy(v0, amp * (omega * t).cos());
        let ar = move |t: f64| Planar::from_xy(0.0, -amp * omega * (omega * t).sin());
        let jerk = move |t: f64| Planar::from_xy(0.0, -amp * omega * omega * (omega * t).cos());
        for len in [1.1e-11, 1.1e-10] {
            let (mut worst, mut worst_first): (f64, f64) = (0.0, 0.0);
            let (mut first, mut second): (f64, f64) = (0.0, 0.0);
            relax(len, v0, vr, |t, s| {
                let p = manifold(len, vr(t), ar(t), ar(t), jerk(t));
                worst = worst.max((p.s - s).norm() / len);
                let s1 = vr(t) * (len / vr(t).norm()) + correction(len, vr(t), ar(t));
                worst_first = worst_first.max((s1 - s).norm() / len);
                first = first.max(p.first2.sqrt() / len);
                second = second.max(p.second2.sqrt() / len);
            });
            // ε = (L/r)·Ω, about 4e-4 at L = 1.1e-11 and 4e-3 at 1.1e-10: r ≥ 1e-3 m/s,
            // Ω ≈ 3e4/s.
            assert_orders(
                &format!("L = {len}"),
                worst_first,
                worst,
                first,
                second,
                0.2,
            );
        }
    }
}
