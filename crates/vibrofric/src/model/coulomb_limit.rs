//! The Coulomb limit of a stiff planar Dahl contact (`kappa = 1`): a step kind of the planar
//! explicit path (`explicit_planar.rs`) in which the deformation is a function of the body's
//! motion and only the body is integrated.
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
//! About a quarter of the manifold's attempts are rejected; DOPRI5's proportional-integral
//! controller on them (β = 0.04, 0.08) cost more (PaperTransverse 1.46 and 1.48 against 1.36
//! in the same run).

use super::drive::DriveKind;
use super::dynamics::System;
use crate::physics::{FrictionLaw, Vector};
use crate::solver::dopri::DoPriStep;
use crate::solver::MAX_DIM;
use crate::table::InputId;
use std::cell::Cell;

/// The largest first-order correction `|z1|/L` at which the expansion is used.
const FIRST_MAX: f64 = 1e-2;

/// The largest ratio `ε = |z2 − z1|/|z1|` of successive orders.
const RATIO_MAX: f64 = 0.1;

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
/// jerk on the transverse scenes).
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
    /// The deformation to second order, `L·e + z2`.
    pub s: V,
    /// `|z1|²`.
    pub first2: f64,
    /// `|z2 − z1|²`.
    pub second2: f64,
    /// `v_r`.
    pub vr: V,
    /// `|v_r|`.
    pub r: f64,
    /// `a_r` (under the Coulomb force).
    pub ar: V,
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
        vr,
        r,
        ar: a0,
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

/// The end of a step on the manifold: its time, the body's state (its first `N_BODY`
/// components) and the point.
type End<V> = (f64, [f64; MAX_DIM], Point<V>);

/// The manifold of one contact during one call of the planar explicit path.
pub(super) struct Limit<'s, 'a, V: Vector, L: FrictionLaw, D: DriveKind<V>> {
    sys: &'s System<'a, V, L, D>,
    /// `s_ss`.
    len: f64,
    /// The step's relative tolerance (the error control's).
    rtol: f64,
    /// The end of the last step on the manifold: its time, body and point.
    last: Cell<Option<End<V>>>,
}

impl<'s, 'a, V: Vector, L: FrictionLaw, D: DriveKind<V>> Limit<'s, 'a, V, L, D> {
    /// The manifold of a planar Dahl contact with `kappa = 1` at a constant load; `None` for
    /// other laws.
    pub(super) fn new(sys: &'s System<'a, V, L, D>, rtol: f64) -> Option<Self> {
        let dynamics = sys.dynamics;
        if V::DIM != 2 || D::N_BODY == 0 || dynamics.load.is_some() {
            return None;
        }
        let relax = dynamics.law.relaxation()?;
        // Dahl with kappa = 1: the relaxation's exponent 1, and a law linear in `s`.
        if relax.exponent != 1.0 || dynamics.law.linear(V::from_xy(1.0, 0.0)).is_none() {
            return None;
        }
        Some(Limit {
            sys,
            len: relax.length,
            rtol,
            last: Cell::new(None),
        })
    }

    /// The support's velocity, acceleration and jerk at `t`: the harmonic source's (one
    /// argument reduction), and the input tracks' values and slopes. The velocity has the
    /// right-hand side's bits and is remembered for the stage's evaluation at `t`.
    #[inline(always)]
    fn support(&self, t: f64) -> [V; 3] {
        let dynamics = self.sys.dynamics;
        let (mut vs, mut acc, mut jerk) = (V::default(), V::default(), V::default());
        if let Some(h) = &dynamics.harmonic {
            let ((vx, vy), (ax, ay)) = h.velocity_acceleration(t);
            (vs, acc) = (V::from_xy(vx, vy), V::from_xy(ax, ay));
            let w = std::f64::consts::TAU * h.f;
            jerk = vs * (-w * w);
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
        [vs, acc, jerk]
    }

    /// The manifold at `(t, y)` (`y` the state, the body from `V::DIM` on); the body's jerk
    /// from a difference along its motion (its acceleration is affine in the body's state, the
    /// force and the drive's inputs: exact but for rounding and the spring's far end, quadratic
    /// in time under an input derivative of `v_d`).
    #[inline(always)]
    pub(super) fn point<const N: usize>(&self, t: f64, y: &[f64]) -> Option<Point<V>> {
        let dynamics = self.sys.dynamics;
        let law = &dynamics.law;
        let drive = &dynamics.drive;
        let a_d = dynamics.tracks[InputId::VD.index()].slope;
        let body = &y[V::DIM..N];
        let d = dynamics.drive_inputs(t);
        let [vs, acc_s, jerk_s] = self.support(t);
        let vr = drive.velocity(body, &d) - vs;
        let r = vr.norm();
        if !(r > 0.0 && r.is_finite()) {
            return None;
        }
        // Dahl's force `k_t·s` (it reads neither `v_r` nor `ds/dt`).
        let force = |s: V| law.force(s, vr, V::default());
        let s0 = vr * (self.len / r);
        let f0 = force(s0);
        let acc0 = drive.acceleration(body, f0, &d, a_d);
        let a0 = acc0 - acc_s;
        let z1 = correction(self.len, vr, a0);
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
        let f2 = f0 + force(e_dot * self.len) * tau;
        let acc2 = drive.acceleration(&moved[..D::N_BODY], f2, &dynamics.drive_inputs(t2), a_d);
        let jerk = (acc2 - acc0) * (1.0 / tau) - jerk_s;
        Some(manifold(self.len, vr, a0, a1, jerk))
    }

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
        let on = (s0 - point.s).norm() <= START_FRACTION * self.rtol * self.len;
        (on && self.small(&point) && self.converges(point.first2, point.second2)).then(|| Start {
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
        let (mut first2, mut second2) = (p0.first2, p0.second2);
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
                        first2 = first2.max(p.first2);
                        second2 = second2.max(p.second2);
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
        if !ok || !self.converges(first2, second2) {
            return None;
        }
        let (te, pe) = end?;
        let mut u1 = step.end();
        pe.s.write(&mut u1[..V::DIM]);
        // The deformation's error estimate: the manifold's change under the body's, to first
        // order `(L/r)·P⊥·δv` (the body's velocity is affine in its state).
        let mut step = step;
        let dynamics = self.sys.dynamics;
        let d = dynamics.drive_inputs(te);
        let zero = [0.0; MAX_DIM];
        let dv = dynamics.drive.velocity(&step.err[V::DIM..N], &d)
            - dynamics.drive.velocity(&zero[..D::N_BODY], &d);
        correction_of_velocity(self.len, pe.vr, dv).write(&mut step.err[..V::DIM]);
        let mut be = [0.0; MAX_DIM];
        be[..D::N_BODY].copy_from_slice(&u1[V::DIM..N]);
        self.last.set(Some((te, be, pe)));
        Some((step, u1))
    }

    /// Whether the expansion converges ([`RATIO_MAX`]) and its neglected third order
    /// ([`neglected`]) is below its share of the tolerance, given the squares of the largest
    /// first and second order terms over a step.
    #[inline(always)]
    fn converges(&self, first2: f64, second2: f64) -> bool {
        second2 == 0.0
            || (second2 <= RATIO_MAX * RATIO_MAX * first2
                && neglected(first2.sqrt(), second2.sqrt())
                    <= NEGLECT_FRACTION * self.rtol * self.len)
    }

    /// Whether the first-order term is within [`FIRST_MAX`] and the deformation finite.
    #[inline(always)]
    fn small(&self, p: &Point<V>) -> bool {
        let most = FIRST_MAX * self.len;
        p.first2 <= most * most && p.s.x().is_finite() && p.s.y().is_finite()
    }

    /// Whether one point is within the expansion's reach over a step of length `h`.
    #[inline(always)]
    fn fits(&self, p: &Point<V>, h: f64) -> bool {
        self.small(p) && h <= reach(p)
    }
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
    use crate::physics::Planar;

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
            let rate = |t: f64, s: Planar| {
                let v = vr(t);
                v - s * (v.norm() / len)
            };
            // Classical Runge–Kutta at a step far below the relaxation time L/|v_r|.
            let h = 0.02 * len / (v0 * 3.0);
            let (mut t, mut s) = (0.0, Planar::default());
            let t_end = 1.3e-4;
            let (mut worst, mut worst_first): (f64, f64) = (0.0, 0.0);
            let (mut first, mut second): (f64, f64) = (0.0, 0.0);
            let mut steps = 0u64;
            while t < t_end {
                let k1 = rate(t, s);
                let k2 = rate(t + h / 2.0, s + k1 * (h / 2.0));
                let k3 = rate(t + h / 2.0, s + k2 * (h / 2.0));
                let k4 = rate(t + h, s + k3 * h);
                s = s + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
                t += h;
                steps += 1;
                // Well past the start's relaxation (its time L/|v_r| is below 1e-7 s).
                if t > 2e-5 && steps.is_multiple_of(97) {
                    let p = manifold(len, vr(t), ar(t), ar(t), jerk(t));
                    worst = worst.max((p.s - s).norm() / len);
                    let s1 = vr(t) * (len / vr(t).norm()) + correction(len, vr(t), ar(t));
                    worst_first = worst_first.max((s1 - s).norm() / len);
                    first = first.max(p.first2.sqrt() / len);
                    second = second.max(p.second2.sqrt() / len);
                }
            }
            // The second order is the first order's error; the third order, the second's,
            // within the certificate's estimate (ε = (L/r)·Ω, about 4e-4 at L = 1.1e-11 and
            // 4e-3 at 1.1e-10: r ≥ 1e-3 m/s, Ω ≈ 3e4/s).
            assert!(
                worst_first > 0.9 * second && worst_first < 1.1 * second,
                "{len}: {worst_first:e} {second:e}"
            );
            let bound = neglected(first, second);
            assert!(
                worst <= bound && worst >= 0.2 * bound,
                "{len}: {worst:e} {bound:e}"
            );
        }
    }
}
