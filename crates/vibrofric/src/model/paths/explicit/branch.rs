//! The explicit path's branches: the deformation along one as a function of the relative
//! displacement (Dahl's exponential, Dupont's elastic part and plastic shape), and the events
//! a step meets on it (a reversal of `v_r`, Dupont's breakaway), located on the step's
//! continuous extension.

use super::*;

/// An event inside an explicit step, at the fraction `theta` of it.
pub(super) enum Event {
    /// A sign change of `v_r` at the step's start.
    AtStart,
    /// A sign change of `v_r` just before `theta` (in `(0, 1]`).
    Reversal(f64),
    /// Dupont's breakaway just before `theta` (in `(0, 1)`).
    Breakaway(f64),
}

/// The first event inside `step` (of length `h` from `t`, the support velocity `vs_at` at its
/// stages and `vs` at any time): a sign change of `v_r` beyond `band`, located on the
/// continuous extension; else, on Dupont's elastic part, the breakaway, where the
/// deformation's third derivative jumps, which the error estimate does not see. A breakaway at
/// the step's start within the resolution of time is none.
pub(super) fn event_in(
    step: &DoPriStep<4>,
    vs_at: &[f64; 7],
    vs: &impl Fn(f64) -> f64,
    branch: &Branch,
    band: f64,
    t: f64,
    h: f64,
) -> Option<Event> {
    let sigma = branch.sigma;
    let g = |i: usize| sigma * (step.stages[i][2] - vs_at[i]) + band;
    if let Some(i) = (1..7).find(|&i| g(i) < 0.0) {
        let gd = |theta: f64| sigma * (step.dense(2, h, theta) - vs(t + theta * h)) + band;
        let theta = root(&gd, (C[i - 1], g(i - 1).max(0.0)), (C[i], g(i)), band);
        return Some(if t + theta * h <= t {
            Event::AtStart
        } else {
            Event::Reversal(theta)
        });
    }
    let room = branch.room()?;
    let gk = |theta: f64| room - sigma * step.dense(0, h, theta) * branch.inv_len;
    let end = gk(1.0);
    if end >= 0.0 {
        return None;
    }
    let theta = root(&gk, (0.0, room), (1.0, end), BREAKAWAY_WITHIN);
    (theta < 1.0 && theta > BREAKAWAY_AT_START && theta * h > 64.0 * f64::EPSILON * t.abs())
        .then_some(Event::Breakaway(theta))
}

/// The deformation along the branch `σ` from `s0`, as a function of the relative displacement
/// `ξ` since the step's start.
#[derive(Clone, Copy)]
pub(super) struct Branch<'a> {
    s0: f64,
    sigma: f64,
    len: f64,
    inv_len: f64,
    /// Dupont: its shape and the branch's elastic room and plastic start.
    plastic: Option<(&'a ElastoPlastic, BranchStart)>,
}

impl<'a> Branch<'a> {
    pub(super) fn new(s0: f64, sigma: f64, len: f64, shape: Option<&'a ElastoPlastic>) -> Self {
        let inv_len = 1.0 / len;
        Branch {
            s0,
            sigma,
            len,
            inv_len,
            plastic: shape.map(|shape| (shape, shape.start(sigma * s0 * inv_len))),
        }
    }

    /// The deformation after a relative displacement `xi` from `s0`.
    #[inline(always)]
    pub(super) fn at(&self, xi: f64) -> f64 {
        let Branch {
            s0,
            sigma,
            len,
            inv_len,
            ..
        } = *self;
        match self.plastic {
            Some((shape, start)) => {
                // Elastic up to the room left (and against the branch: a trial stage beyond a
                // reversal, where s and v_r point apart), then plastic.
                let du = sigma * xi * inv_len - start.room;
                if du <= 0.0 {
                    s0 + xi
                } else {
                    // z0·exp(−du), exp(−du) within the fast expm1's range.
                    let z = if du < 39.0 {
                        start.z0 * (1.0 + expm1(-du))
                    } else {
                        0.0
                    };
                    sigma * len * shape.plastic(z)
                }
            }
            None => {
                // Against the branch (a trial stage beyond a reversal) the expression grows
                // exponentially: bounded, so that the error estimate rejects the step.
                let e = (-sigma * xi * inv_len).min(50.0);
                // Below −39, expm1 is −1 to the last bit: no call on a relaxed branch.
                let em1 = if e < -39.0 { -1.0 } else { expm1(e) };
                s0 - (sigma * len - s0) * em1
            }
        }
    }

    /// The largest `|ds/dξ|` over a step that ends at `xi_end`, by which the error of `ξ` makes
    /// that of `s`. Dahl: at the step's start, or its end on a step that went a little against
    /// `σ`. Dupont: 1 on an elastic part (or against the branch), else the plastic slope at the
    /// step's start, which falls along the step.
    pub(super) fn slope(&self, xi_end: f64) -> f64 {
        let back = -self.sigma * xi_end * self.inv_len;
        let p0 = self.sigma * self.s0 * self.inv_len;
        match self.plastic {
            Some((_, start)) if start.room > 0.0 || back > 0.0 => 1.0,
            Some((shape, _)) => shape.slope(p0),
            None => (1.0 - p0).abs() * if back > 0.0 { libm::exp(back) } else { 1.0 },
        }
    }

    /// The share of a deformation error at the relative displacement `xi` left after a further
    /// `reach` (≥ 0) along the branch: an elastic part keeps it, a relaxing part damps it as
    /// `exp(−ξ/s_ss)` (Dahl's exactly, Dupont's plastic part about so).
    pub(super) fn kept(&self, xi: f64, reach: f64) -> f64 {
        let room = self.plastic.map_or(0.0, |(_, start)| {
            (start.room - self.sigma * xi * self.inv_len).max(0.0)
        });
        let du = reach * self.inv_len - room;
        if du > 40.0 {
            0.0
        } else if du > 0.0 {
            trig::exp(-du)
        } else {
            1.0
        }
    }

    /// Dupont: the elastic room left before the breakaway, where there is some.
    pub(super) fn room(&self) -> Option<f64> {
        self.plastic
            .map(|(_, start)| start.room)
            .filter(|&r| r > 0.0)
    }
}

/// A point just past the root of `g` in `(a, b)`, from `g(a) = ga ≥ 0 > g(b) = gb`, by the
/// Illinois method: the first `b` found with `−within ≤ g(b) < 0`, or the bracket's end at the
/// resolution of `theta`.
pub(in crate::model::paths) fn root(
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

#[cfg(test)]
mod tests {
    use super::Branch;
    use crate::physics::ElastoPlastic;

    /// What a branch leaves of a deformation error after a further relative displacement: Dahl's
    /// relaxation `exp(−reach/s_ss)` (none beyond 40 `s_ss`); Dupont's elastic room all of it,
    /// then its plastic part's `exp(−(reach − room)/s_ss)`.
    #[test]
    fn a_branch_keeps_what_its_relaxation_leaves() {
        let len = 1.1e-7;
        let dahl = Branch::new(-len, 1.0, len, None);
        for reach in [0.0, 0.5, 3.0, 30.0, 39.0] {
            let (kept, want) = (dahl.kept(0.0, reach * len), (-reach).exp());
            assert!(
                (kept - want).abs() <= 1e-14 * want,
                "{reach}: {kept} vs {want}"
            );
        }
        assert_eq!(dahl.kept(0.0, 41.0 * len), 0.0);
        // From the other branch's steady state, p0 = −1: the elastic room to r_ba = 0.5 is 1.5.
        let shape = ElastoPlastic::new(0.5).unwrap();
        let dupont = Branch::new(-len, 1.0, len, Some(&shape));
        assert_eq!(dupont.room(), Some(1.5));
        assert_eq!(dupont.kept(0.0, 1.5 * len), 1.0);
        let beyond = dupont.kept(0.0, 2.5 * len);
        assert!((beyond - (-1.0f64).exp()).abs() <= 1e-14, "{beyond}");
        // A step on: 1 s_ss of the room used, 0.5 left.
        assert_eq!(dupont.kept(len, 0.5 * len), 1.0);
        let on = dupont.kept(len, 1.5 * len);
        assert!((on - (-1.0f64).exp()).abs() <= 1e-14, "{on}");
    }
}
