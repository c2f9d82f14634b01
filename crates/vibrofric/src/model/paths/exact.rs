//! The fast path of a longitudinal contact under velocity drive whose law relaxes in the
//! relative displacement (Dahl): the deformation in closed form between sign changes of `v_r`, the
//! sign changes in closed form or by a safeguarded Newton iteration on monotone pieces, and only
//! the integral of the friction force by quadrature. No step size, no Newton on the state, the
//! same cost at any contact stiffness.
//!
//! With `sigma = sgn(v_r)` on a segment, `phi(t) = |x_r(t) − x_r(a)|/s_ss` (relative
//! displacement since the segment's start `a`, in units of the relaxation length) and
//! `w = 1 − sigma·s/s_ss`, `w(t) = W(w(a), phi(t))` in closed form (`w(a)·exp(−phi)` for
//! `kappa = 1`, a power law otherwise: [`Relaxation::remaining`]), so that
//! `s = sigma·s_ss·(1 − w)` and `∫ s dt = sigma·s_ss·((b − a) − ∫ w dt)`.

use super::{Integrated, Kept, Path, Shared};
use crate::model::drive::DriveKind;
use crate::model::dynamics::Dynamics;
use crate::model::simulator::SimError;
use crate::physics::{trig, FrictionLaw, Relaxation, Vector};
use crate::solver::quadrature::{adaptive, Integral};
use crate::solver::Quad;
use crate::table::InputId;

/// The relative velocity along x over one call, from its start `t0`:
/// `v_r(t0 + tau) = b0 + b1·tau − amp·cos(theta0 + omega·tau)` (the importer's inputs are affine
/// in time over a communication step, the harmonic source is a cosine).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Forcing {
    pub b0: f64,
    pub b1: f64,
    /// `v_a·cos(angle)`: the harmonic support velocity's x amplitude.
    pub amp: f64,
    pub omega: f64,
    /// Phase at `t0`.
    pub theta0: f64,
}

/// The forcing seen from `tau`: phase, its sine and cosine, and the affine part there.
#[derive(Clone, Copy, Debug)]
struct Anchor {
    b0: f64,
    b1: f64,
    amp: f64,
    omega: f64,
    sin: f64,
    cos: f64,
}

impl Anchor {
    fn new(f: &Forcing, tau: f64) -> Self {
        let (sin, cos) = if f.amp != 0.0 {
            trig::sin_cos(f.theta0 + f.omega * tau)
        } else {
            (0.0, 1.0)
        };
        Anchor {
            b0: f.b0 + f.b1 * tau,
            b1: f.b1,
            amp: f.amp,
            omega: f.omega,
            sin,
            cos,
        }
    }

    /// `v_r` at the anchor.
    fn v(&self) -> f64 {
        self.b0 - self.amp * self.cos
    }

    /// `dv_r/dt` at the anchor.
    fn dv(&self) -> f64 {
        self.b1 + self.amp * self.omega * self.sin
    }

    /// `x_r(anchor + tau) − x_r(anchor)`, without cancellation for small `tau`:
    /// `sin(theta + w) − sin(theta) = cos(theta)·sin(w) − 2·sin(theta)·sin²(w/2)`.
    #[inline(always)]
    fn dx(&self, tau: f64) -> f64 {
        let lin = tau * (self.b0 + 0.5 * self.b1 * tau);
        if self.amp == 0.0 {
            return lin;
        }
        let (sh, ch) = trig::sin_cos(0.5 * self.omega * tau);
        lin - self.amp / self.omega * (2.0 * sh * (self.cos * ch - self.sin * sh))
    }
}

impl Forcing {
    /// `v_r(t0 + tau)` and its derivative.
    fn v_dv(&self, tau: f64) -> (f64, f64) {
        let a = Anchor::new(self, tau);
        (a.v(), a.dv())
    }

    /// The first point after `tau` where `dv_r/dt` vanishes (where `sin theta = −b1/(amp·omega)`),
    /// or infinity: between two such points `v_r` is monotone.
    fn next_critical(&self, tau: f64) -> f64 {
        if self.amp == 0.0 || self.omega == 0.0 {
            return f64::INFINITY;
        }
        let r = -self.b1 / (self.amp * self.omega);
        if r.abs() >= 1.0 {
            return f64::INFINITY;
        }
        let tau_pi = std::f64::consts::TAU;
        let theta = self.theta0 + self.omega * tau;
        let c1 = libm::asin(r);
        let next = |c: f64| c + tau_pi * ((theta - c) / tau_pi).floor() + tau_pi;
        let t = next(c1).min(next(std::f64::consts::PI - c1));
        // The phase of a critical point just behind `theta` may round to it: step past it.
        let dt = (t - self.theta0) / self.omega;
        if dt > tau {
            dt
        } else {
            tau + (tau_pi / self.omega) * 1e-12
        }
    }

    /// The sign change of `v_r` in `(p, q)`, on which it is monotone with `v_r(p)·v_r(q) < 0`:
    /// Newton's iteration kept inside a shrinking bracket, to full precision.
    fn root(&self, mut p: f64, vp: f64, mut q: f64, vq: f64) -> f64 {
        let up = vq > vp;
        let mut x = p - vp * (q - p) / (vq - vp);
        for _ in 0..100 {
            if !(x > p && x < q) {
                x = 0.5 * (p + q);
            }
            let (v, dv) = self.v_dv(x);
            if v == 0.0 {
                return x;
            }
            if (v > 0.0) == up {
                q = x;
            } else {
                p = x;
            }
            if q - p <= 4.0 * f64::EPSILON * q.abs() {
                break;
            }
            x -= v / dv;
        }
        0.5 * (p + q)
    }
}

/// Tightest tolerance the quadrature is asked for: below it the sums' rounding dominates.
pub const MIN_TOL: f64 = 1e-14;

/// The result of [`advance`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Advance {
    /// Deformation at the end.
    pub s: f64,
    /// `∫ s dt` over the call.
    pub integral_s: f64,
    /// `∫ |v_r| dt / s_ss`: `exp(−decay)` is how much of the initial deformation is left.
    pub decay: f64,
    /// Segments between sign changes.
    pub segments: u64,
    /// Sign changes of `v_r` located.
    pub roots: u64,
    /// Evaluations of the integrand.
    pub evals: u64,
}

/// Calls `at` with every sign change of `v_r` in `(0, span)`, in order.
pub fn sign_changes(forcing: &Forcing, span: f64, mut at: impl FnMut(f64)) {
    let mut p = 0.0;
    let (mut vp, _) = forcing.v_dv(0.0);
    while p < span {
        let q = forcing.next_critical(p).min(span);
        let (vq, _) = forcing.v_dv(q);
        if vp * vq < 0.0 {
            at(forcing.root(p, vp, q, vq));
        }
        (p, vp) = (q, vq);
    }
}

/// Advances the deformation from `s0` over `[t0, t0 + span]` under `forcing`, with the
/// integral of `s` to the relative tolerance `tol`.
pub fn advance(forcing: &Forcing, relax: Relaxation, s0: f64, span: f64, tol: f64) -> Advance {
    let tol = tol.max(MIN_TOL);
    let mut out = Advance {
        s: s0,
        ..Advance::default()
    };
    let mut seg_start = 0.0;
    sign_changes(forcing, span, |r| {
        segment(forcing, relax, seg_start, r, tol, &mut out);
        out.roots += 1;
        seg_start = r;
    });
    segment(forcing, relax, seg_start, span, tol, &mut out);
    out
}

/// One segment `[a, b]` without a sign change of `v_r` inside.
fn segment(forcing: &Forcing, relax: Relaxation, a: f64, b: f64, tol: f64, out: &mut Advance) {
    let len = b - a;
    if len <= 0.0 {
        return;
    }
    out.segments += 1;
    let anchor = Anchor::new(forcing, a);
    let sigma = forcing.v_dv(0.5 * (a + b)).0.signum();
    let s_a = out.s;
    if sigma == 0.0 || !sigma.is_finite() {
        out.integral_s += s_a * len; // no relative motion: nothing relaxes
        return;
    }
    let inv_l = 1.0 / relax.length;
    let phi = |tau: f64| (sigma * anchor.dx(tau) * inv_l).max(0.0);
    let phi_end = phi(len);
    let target = sigma * relax.length;
    // w = 1 − sigma·s/s_ss: what is left to relax, in [0, 2] while |s| ≤ s_ss.
    let w_a = (1.0 - sigma * s_a * inv_l).clamp(0.0, 2.0);
    out.s = (target * (1.0 - relax.remaining(w_a, phi_end))).clamp(-relax.length, relax.length);
    out.decay += phi_end;

    // ∫ w dt over the segment. phi grows from 0 like phi1·tau + phi2·tau²/2; panels double in
    // length from the boundary-layer scale tau_b (phi ≈ 1 there) until w is below the
    // tolerance, or exhausted (kappa < 1: w = 0 from phi* on, a kink the panels end on).
    let budget = 0.05 * tol * len;
    let phi_cut = if relax.exponent == 1.0 {
        libm::log((w_a / (0.05 * tol)).max(1.0)) + 3.0
    } else {
        relax.exhaustion(w_a)
    };
    let end = if phi_end > phi_cut {
        // The first tau with phi(tau) = phi_cut, by bisection on the monotone phi.
        let (mut lo, mut hi) = (0.0, len);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if phi(mid) < phi_cut {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    } else {
        len
    };
    let phi1 = anchor.v().abs() * inv_l;
    let phi2 = (sigma * anchor.dv()).max(0.0) * inv_l;
    let tau_b = 1.0 / (phi1 + (0.5 * phi2).sqrt());
    let mut f = |tau: f64| relax.remaining(w_a, phi(tau));
    let mut j = Integral::default();
    if w_a > 0.0 && end > 0.0 {
        if !(tau_b.is_finite() && 4.0 * tau_b < end) {
            j = adaptive(&mut f, 0.0, end, budget);
        } else {
            // A layer thinner than 2^-60 of the segment weighs nothing: start there at most.
            let (mut lo, mut width) = (0.0, (2.0 * tau_b).max(end * 2f64.powi(-60)));
            loop {
                let hi = (lo + width).min(end);
                j += adaptive(&mut f, lo, hi, budget * (hi - lo) / len);
                if hi >= end {
                    break;
                }
                lo = hi;
                width *= 2.0;
            }
        }
    }
    out.evals += j.evals;
    out.integral_s += target * (len - j.value);
}

/// The closed-form path's relaxation, where this contact takes it: a longitudinal velocity
/// drive (no body state) with a law that relaxes in the relative displacement (Dahl).
pub(super) fn relaxation<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
    c: &Shared<'_, V, L, D, N>,
    k: &Kept<N>,
) -> Option<Relaxation> {
    if V::DIM == 1 && D::N_BODY == 0 && !k.force_radau && c.dynamics.load.is_none() {
        c.dynamics.law.relaxation()
    } else {
        None
    }
}

/// The closed-form path (longitudinal Dahl under velocity drive).
pub(super) struct ClosedForm;

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Path<V, L, D, N> for ClosedForm {
    fn applies(c: &Shared<'_, V, L, D, N>, _: &Integrated<N>, k: &Kept<N>) -> bool {
        relaxation(c, k).is_some()
    }

    fn advance(
        c: &Shared<'_, V, L, D, N>,
        r: &mut Integrated<N>,
        k: &mut Kept<N>,
        t_target: f64,
        _: f64,
    ) -> Result<Quad, SimError> {
        let relax = relaxation(c, k).expect("closed-form path without a relaxation");
        Ok(advance_exact(c, r, relax, t_target).1)
    }
}

/// Advances the closed-form path to `t_target`; returns `exp(−decay)`'s exponent and
/// `∫F_F dt` over the call (longitudinal: `F_Fy` = 0).
pub(super) fn advance_exact<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
    c: &Shared<'_, V, L, D, N>,
    r: &mut Integrated<N>,
    relax: Relaxation,
    t_target: f64,
) -> (f64, Quad) {
    let t0 = r.t;
    let forcing = forcing_x(c.dynamics, t0, c.config.input_support);
    let a = advance(&forcing, relax, r.y[0], t_target - t0, r.tolerance());
    r.t = t_target;
    r.y[0] = a.s;
    r.restart();
    let st = &mut r.stats;
    st.steps += a.segments;
    st.events += a.roots;
    st.rhs_evals += a.evals;
    (a.decay, [relax.stiffness * a.integral_s, 0.0])
}

/// The relative velocity along x of a velocity drive from `t` on, for the closed-form and
/// exponential paths: the affine input tracks and the harmonic source's x component.
pub(super) fn forcing_x<V: Vector, L: FrictionLaw, D: DriveKind<V>>(
    dynamics: &Dynamics<V, L, D>,
    t: f64,
    input_support: bool,
) -> Forcing {
    let (vd, vsx) = (
        &dynamics.tracks[InputId::VD.index()],
        &dynamics.tracks[InputId::VSx.index()],
    );
    let (mut b0, mut b1) = (vd.at(t), vd.slope);
    if input_support {
        b0 -= vsx.at(t);
        b1 -= vsx.slope;
    }
    let (amp, omega, theta0) = match &dynamics.harmonic {
        Some(h) => (h.v_a() * h.dir.0, std::f64::consts::TAU * h.f, h.theta(t)),
        None => (0.0, 0.0, 0.0),
    };
    Forcing {
        b0,
        b1,
        amp,
        omega,
        theta0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tight reference: `∫ s dt` by composite Simpson on the closed form at 2e5 points per
    /// segment, with the roots from the held-input closed form `cos theta = b0/amp`.
    #[test]
    fn held_inputs_match_a_dense_reference() {
        let f = Forcing {
            b0: 1e-3,
            b1: 0.0,
            amp: 2.513e-3,
            omega: 2.0 * std::f64::consts::PI * 2000.0,
            theta0: 0.3,
        };
        let relax = Relaxation {
            length: 1.1e-7,
            stiffness: 1e8,
            exponent: 1.0,
        };
        let span = 5e-4;
        let adv = advance(&f, relax, 0.2e-7, span, 1e-10);
        assert_eq!(adv.roots, 2);
        // The two roots of b0 − amp·cos(theta) in theta0 + omega·[0, span].
        let base = (f.b0 / f.amp).acos();
        let mut roots: Vec<f64> = [
            base,
            std::f64::consts::TAU - base,
            std::f64::consts::TAU + base,
        ]
        .iter()
        .map(|th| (th - f.theta0) / f.omega)
        .filter(|&t| t > 0.0 && t < span)
        .collect();
        roots.sort_by(f64::total_cmp);
        let mut knots = vec![0.0];
        knots.extend(roots);
        knots.push(span);
        let x =
            |t: f64| f.b0 * t - f.amp / f.omega * ((f.theta0 + f.omega * t).sin() - f.theta0.sin());
        let (mut s, mut integral) = (0.2e-7, 0.0);
        for w in knots.windows(2) {
            let (a, b) = (w[0], w[1]);
            let sigma = (f.b0 - f.amp * (f.theta0 + f.omega * 0.5 * (a + b)).cos()).signum();
            let tgt = sigma * relax.length;
            let s_at = |t: f64| tgt + (s - tgt) * (-(sigma * (x(t) - x(a)) / relax.length)).exp();
            let n = 200_000;
            let h = (b - a) / n as f64;
            let mut sum = s_at(a) + s_at(b);
            for k in 1..n {
                sum += if k % 2 == 1 { 4.0 } else { 2.0 } * s_at(a + k as f64 * h);
            }
            integral += sum * h / 3.0;
            s = s_at(b);
        }
        assert!((adv.s - s).abs() < 1e-12 * relax.length, "{} vs {s}", adv.s);
        assert!(
            (adv.integral_s - integral).abs() < 1e-10 * relax.length * span,
            "{} vs {integral}",
            adv.integral_s
        );
    }
}
