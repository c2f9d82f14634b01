//! Dupont's deformation along one branch of a line contact, as a function of the relative
//! displacement since the branch began.
//!
//! While `v_r` keeps its sign `σ`, Dupont's rate `ds/dt = v_r − alpha(s, v_r)·|v_r|·s/s_ss`
//! divided by `v_r` depends on `s` alone: in `p = σ·s/s_ss` and the relative displacement
//! `u = σ·Δx_r/s_ss` along the branch (`docs/model.md`),
//!
//! `dp/du = 1 − alpha(p)·p`, with `alpha = 0` for `p ≤ r` (`r = r_ba`; this covers `p < 0`,
//! where `s` and `v_r` point apart) and `alpha = cos²(πq/2)` for `p > r`, `q = (1 − p)/w`,
//! `w = 1 − r` (the spec's `1/2·sin(π(|s| − (s_ss + s_ba)/2)/(s_ss − s_ba)) + 1/2`).
//!
//! So `p` is linear in `u` up to `r` (elastic), then follows the plastic part, which tends to 1
//! (`s_ss`) as `u` grows without reaching it. The plastic part is the flow of an autonomous
//! equation: with `T(p) = ∫_r^p dp'/(1 − alpha·p')` the displacement it takes from `r` to `p`,
//! the deformation after a further `Δu` is `T⁻¹(T(p0) + Δu)`. Split off its logarithm,
//! `T = −ln q + R(q)`, `R(q) = −∫_q^1 g(x) dx`, `g(x) = p·S/(x·(w·x + p·S))`, `S = sin²(πx/2)`,
//! `p = 1 − w·x`: `g` is analytic on `[0, 1]` (it tends to `π²/(4w)` as `x → 0`), and so is
//! the inverse in `z = exp(−T) = q·exp(−R(q))`: `q = z·P(z)` with `P = exp(R(q))`. Both `R`
//! and `P` are Chebyshev series on eight pieces of `[0, 1]` fitted once for the breakaway
//! ratio; a deformation then costs one exponential and a short series:
//! `z = z0·exp(−Δu)`, `p = 1 − w·z·P(z)`.
//!
//! Near `r = 1` the transition is narrow, `g` has a pole at about `x = −4w/π²`, close to the
//! interval, and the series need more terms: 45 and 43 at `r_ba` = 0.5, 91 and 90 at 0.9,
//! 207 and 255 at 0.98; from 0.99 on more than [`MAX_TERMS`], and [`ElastoPlastic::new`]
//! refuses (the contact keeps the general integrator). Fitting takes 0.1 ms at 0.5, 9 ms at
//! 0.98, once per contact.

use super::chebyshev::{Chebyshev, Piecewise};
use std::f64::consts::PI;

/// The most terms a series may take (more would cost more per deformation than the general
/// integrator's step saves).
const MAX_TERMS: usize = 256;

/// The pieces of the series of `R` and `P`: `P` is evaluated at every stage of the explicit
/// path, `R` at every step's start; at `r_ba` = 0.5 they take 14 terms a piece where one series
/// takes 45.
const PIECES: usize = 8;

/// Dupont's normalized deformation along a branch for one breakaway ratio.
#[derive(Clone, Debug, PartialEq)]
pub struct ElastoPlastic {
    /// The breakaway ratio `r = s_ba/s_ss`.
    r: f64,
    /// `1 − r`, the transition's width.
    w: f64,
    /// `R(q)` on `[0, 1]`, in [`PIECES`] pieces.
    log_rest: Piecewise,
    /// `P(z) = q/z` on `[0, 1]`, in [`PIECES`] pieces.
    inverse: Piecewise,
}

/// Where a branch starts: the elastic displacement left before the plastic part
/// (`room = r − p0`, 0 when it starts plastic) and the plastic part's `z` at its start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BranchStart {
    pub room: f64,
    pub z0: f64,
}

impl ElastoPlastic {
    /// The shape for the breakaway ratio `r_ba` in `[0, 1)`, or `None` where its series do
    /// not converge within 256 terms.
    pub fn new(r_ba: f64) -> Option<Self> {
        if !(0.0..1.0).contains(&r_ba) {
            return None;
        }
        let (r, w) = (r_ba, 1.0 - r_ba);
        let g = move |x: f64| g(w, x);
        let integral = Chebyshev::fit(g, 0.0, 1.0, MAX_TERMS)?.integral();
        let whole = integral.at(1.0);
        let log_rest = |q: f64| integral.at(q) - whole;
        // q at each z by Newton in y = ln q on F(y) = y − R(e^y) − ln z, F' = 1 − q·g(q) > 0.
        let solve = |z: f64| {
            let ln_z = libm::log(z);
            let mut y = (ln_z + log_rest(z)).min(0.0);
            for _ in 0..60 {
                let q = libm::exp(y);
                let step = (y - log_rest(q) - ln_z) / (1.0 - q * g(q));
                y = (y - step).min(0.0);
                if step.abs() <= 4.0 * f64::EPSILON * y.abs().max(1.0) {
                    break;
                }
            }
            libm::exp(y)
        };
        let inverse = Piecewise::fit(|z| solve(z) / z, 0.0, 1.0, PIECES, MAX_TERMS)?;
        let log_rest = Piecewise::fit(log_rest, 0.0, 1.0, PIECES, MAX_TERMS)?;
        Some(ElastoPlastic {
            r,
            w,
            log_rest,
            inverse,
        })
    }

    /// The branch that starts from the normalized deformation `p0 = σ·s0/s_ss`.
    pub fn start(&self, p0: f64) -> BranchStart {
        if p0 <= self.r {
            return BranchStart {
                room: self.r - p0,
                z0: 1.0,
            };
        }
        let q0 = ((1.0 - p0) / self.w).clamp(0.0, 1.0);
        BranchStart {
            room: 0.0,
            z0: q0 * libm::exp(-self.log_rest.at(q0)),
        }
    }

    /// The normalized deformation at `z = z0·exp(−du)` of the plastic part, after a plastic
    /// displacement `du ≥ 0` beyond the elastic room of a branch whose plastic part starts at
    /// `z0` (the caller takes the exponential, so that it may take its own).
    #[inline]
    pub fn plastic(&self, z: f64) -> f64 {
        1.0 - self.w * z * self.inverse.at(z)
    }

    /// `dp/du` at `p`: 1 where elastic (`p ≤ r`), `1 − alpha·p` beyond; it falls along the
    /// plastic part, so its value at a step's start bounds it over the step.
    pub fn slope(&self, p: f64) -> f64 {
        if p <= self.r {
            return 1.0;
        }
        let q = ((1.0 - p) / self.w).clamp(0.0, 1.0);
        let sin = libm::sin(0.5 * PI * q);
        // alpha = cos²(πq/2) = 1 − sin²(πq/2): 1 − alpha·p = (1 − p) + p·sin².
        (1.0 - p).max(0.0) + p * sin * sin
    }

    /// The breakaway ratio.
    pub fn r_ba(&self) -> f64 {
        self.r
    }
}

/// `g(x) = p·S/(x·(w·x + p·S))`, `p = 1 − w·x`, `S = sin²(πx/2)`: the plastic rate's departure
/// from the logarithm's, written without cancellation (`S/x` stays accurate as `x → 0`).
fn g(w: f64, x: f64) -> f64 {
    let sin = libm::sin(0.5 * PI * x);
    let p = 1.0 - w * x;
    let s = sin * sin;
    p * (sin / x) * sin / (w * x + p * s)
}

#[cfg(test)]
mod tests {
    use super::ElastoPlastic;
    use std::f64::consts::PI;

    /// `dp/du = 1 − alpha(p)·p` with the spec's weight, by the classical Runge–Kutta method
    /// with 200,000 steps per unit of `u` (error far below 1e-14 on this smooth right-hand
    /// side), from `p0` over `u`.
    fn reference(r: f64, p0: f64, u: f64) -> f64 {
        let alpha = |p: f64| {
            if p <= r {
                0.0
            } else if p >= 1.0 {
                1.0
            } else {
                0.5 * libm::sin(PI * (p - 0.5 * (1.0 + r)) / (1.0 - r)) + 0.5
            }
        };
        let rate = |p: f64| 1.0 - alpha(p) * p;
        // The elastic part exactly: the weight has a kink in its second derivative at r.
        let elastic = (r - p0).max(0.0).min(u);
        let (mut p, rest) = (p0 + elastic, u - elastic);
        let n = (rest * 200_000.0).ceil().max(1.0) as usize;
        let h = rest / n as f64;
        for _ in 0..n {
            let k1 = rate(p);
            let k2 = rate(p + 0.5 * h * k1);
            let k3 = rate(p + 0.5 * h * k2);
            let k4 = rate(p + h * k3);
            p += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        p
    }

    fn at(shape: &ElastoPlastic, p0: f64, u: f64) -> f64 {
        let start = shape.start(p0);
        if u <= start.room {
            p0 + u
        } else {
            shape.plastic(start.z0 * libm::exp(start.room - u))
        }
    }

    /// Elastic starts, plastic starts and starts against the branch, over the ratios the
    /// shape accepts, against the reference integration.
    #[test]
    fn branch_follows_the_rate_to_rounding() {
        for r in [0.0, 0.2, 0.5, 0.8, 0.9] {
            let shape = ElastoPlastic::new(r).expect("converges");
            for p0 in [-1.0, -0.3, 0.0, r, 0.5 * (1.0 + r), 0.99, 1.0] {
                for u in [0.0, 0.01, 0.3, 1.0, 2.5, 6.0] {
                    let (got, want) = (at(&shape, p0, u), reference(r, p0, u));
                    assert!(
                        (got - want).abs() < 2e-13,
                        "r {r}, p0 {p0}, u {u}: {got} against {want}"
                    );
                    assert!(got <= 1.0, "above s_ss: {got}");
                }
            }
        }
    }

    /// The plastic part: continuous with the elastic one at `r`, monotone, `s_ss` in the limit.
    #[test]
    fn plastic_part_joins_the_elastic_one_and_tends_to_s_ss() {
        let shape = ElastoPlastic::new(0.5).unwrap();
        assert!((shape.plastic(1.0) - 0.5).abs() < 1e-15);
        let mut last = 0.5;
        for i in 1..=400 {
            let p = shape.plastic(libm::exp(-0.1 * i as f64));
            assert!(p >= last && p <= 1.0, "{p} after {last}");
            last = p;
        }
        assert_eq!(shape.plastic(0.0), 1.0);
        assert_eq!(shape.start(1.0).z0, 0.0);
    }

    /// The slope against central differences of the branch.
    #[test]
    fn slope_is_the_derivative_of_the_branch() {
        let shape = ElastoPlastic::new(0.5).unwrap();
        for p0 in [-0.5, 0.2, 0.6, 0.75, 0.9, 0.999] {
            let h = 1e-6;
            let d = (at(&shape, p0, 2.0 * h) - at(&shape, p0, 0.0)) / (2.0 * h);
            let mid = at(&shape, p0, h);
            assert!(
                (shape.slope(mid) - d).abs() < 1e-8,
                "p0 {p0}: {} vs {d}",
                shape.slope(mid)
            );
        }
        assert_eq!(shape.slope(1.0), 0.0);
    }

    /// Ratios beyond the series' reach are refused, not approximated.
    #[test]
    fn refuses_narrow_transitions_and_bad_ratios() {
        assert!(ElastoPlastic::new(0.999).is_none());
        assert!(ElastoPlastic::new(1.0).is_none());
        assert!(ElastoPlastic::new(-0.1).is_none());
    }
}
