//! One step of Dormand–Prince 5(4) (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.5 and
//! §II.6, code DOPRI5): an explicit Runge–Kutta pair of orders 5 and 4 with the first stage
//! the last one of the previous step (FSAL), its error estimate and its continuous extension of
//! order 4. The caller owns the loop (step size, events, landing), since it knows where the
//! right-hand side is smooth; this file knows nothing of friction.

// The coefficients are the published rationals.
#![allow(clippy::excessive_precision)]

/// Stage times.
pub const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// The fifth-order weights minus the fourth-order ones.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
/// The continuous extension's coefficients (DOPRI5's `contd5`).
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// One attempted step of length `h` from `(t, y)` with `k1 = f(t, y)`.
#[derive(Clone, Copy, Debug)]
pub struct DoPriStep<const M: usize> {
    /// The stage values `Y_i` (the last is the fifth-order solution at `t + h`).
    pub stages: [[f64; M]; 7],
    /// The stage derivatives `k_i = f(t + C_i·h, Y_i)`; `k[6]` is `f` at the new point.
    pub k: [[f64; M]; 7],
    /// The difference between the fifth- and fourth-order solutions.
    pub err: [f64; M],
}

impl<const M: usize> DoPriStep<M> {
    /// Takes the step: six evaluations of `f` (the first derivative is given).
    #[inline(always)]
    pub fn take(
        f: &mut impl FnMut(f64, &[f64; M]) -> [f64; M],
        t: f64,
        y: &[f64; M],
        k1: &[f64; M],
        h: f64,
    ) -> Self {
        Self::take_staged(&mut |_, tt, yi| f(tt, yi), t, y, k1, h)
    }

    /// As [`DoPriStep::take`], with `f` also told the stage (1 to 6) it evaluates, so that a
    /// caller can look up what it computed for the stage times `t + C[i]·h` beforehand.
    #[inline(always)]
    pub fn take_staged(
        f: &mut impl FnMut(usize, f64, &[f64; M]) -> [f64; M],
        t: f64,
        y: &[f64; M],
        k1: &[f64; M],
        h: f64,
    ) -> Self {
        let mut step = Self::zeros();
        step.retake(f, t, y, k1, h);
        step
    }

    /// A step of zeros, to [`DoPriStep::retake`] steps into.
    pub fn zeros() -> Self {
        DoPriStep {
            stages: [[0.0; M]; 7],
            k: [[0.0; M]; 7],
            err: [0.0; M],
        }
    }

    /// As [`DoPriStep::take_staged`], the step written over this one: a caller that takes its
    /// steps into one place copies no stages or derivatives on the way (the same bits).
    #[inline(always)]
    pub fn retake(
        &mut self,
        f: &mut impl FnMut(usize, f64, &[f64; M]) -> [f64; M],
        t: f64,
        y: &[f64; M],
        k1: &[f64; M],
        h: f64,
    ) {
        let (stages, k) = (&mut self.stages, &mut self.k);
        stages[0] = *y;
        k[0] = *k1;
        for i in 1..7 {
            let mut yi = *y;
            for (j, kj) in k.iter().enumerate().take(i) {
                let a = A[i][j];
                if a != 0.0 {
                    for m in 0..M {
                        yi[m] += h * a * kj[m];
                    }
                }
            }
            stages[i] = yi;
            k[i] = f(i, t + C[i] * h, &yi);
        }
        let k = &self.k;
        self.err = std::array::from_fn(|m| h * (0..7).map(|i| E[i] * k[i][m]).sum::<f64>());
    }

    /// The solution at `t + h`.
    pub fn end(&self) -> [f64; M] {
        self.stages[6]
    }

    /// The continuous extension (order 4) of component `m` at `t + theta·h`, `theta` in [0, 1].
    pub fn dense(&self, m: usize, h: f64, theta: f64) -> f64 {
        let y0 = self.stages[0][m];
        let y1 = self.stages[6][m];
        let r2 = y1 - y0;
        let r3 = h * self.k[0][m] - r2;
        let r4 = r2 - h * self.k[6][m] - r3;
        let r5 = h * (0..7).map(|i| D[i] * self.k[i][m]).sum::<f64>();
        let s = 1.0 - theta;
        y0 + theta * (r2 + s * (r3 + theta * (r4 + s * r5)))
    }
}

/// The continuous extension of every component of one step, its coefficients computed once:
/// [`DoPriStep::dense`] at many points for the price of a few products per component and point.
#[derive(Clone, Copy, Debug)]
pub struct Dense<const M: usize> {
    y0: [f64; M],
    r: [[f64; M]; 4],
}

impl<const M: usize> DoPriStep<M> {
    /// The continuous extension's coefficients for a step of length `h`.
    pub fn dense_all(&self, h: f64) -> Dense<M> {
        let mut d = Dense {
            y0: self.stages[0],
            r: [[0.0; M]; 4],
        };
        for m in 0..M {
            let r2 = self.stages[6][m] - self.stages[0][m];
            let r3 = h * self.k[0][m] - r2;
            d.r[0][m] = r2;
            d.r[1][m] = r3;
            d.r[2][m] = r2 - h * self.k[6][m] - r3;
            d.r[3][m] = h * (0..7).map(|i| D[i] * self.k[i][m]).sum::<f64>();
        }
        d
    }
}

impl<const M: usize> Dense<M> {
    /// Component `m` at `t + theta·h`: the value of [`DoPriStep::dense`], to the last bit.
    #[inline(always)]
    pub fn at(&self, m: usize, theta: f64) -> f64 {
        let s = 1.0 - theta;
        let r = &self.r;
        self.y0[m] + theta * (r[0][m] + s * (r[1][m] + theta * (r[2][m] + s * r[3][m])))
    }
}

/// The first step from the scaled norm `d` of the state's rates at the start (each rate over
/// its component's nominal magnitude): a hundredth of the time the state takes to move by its
/// nominal magnitudes, times `tol^(1/5)`; `h_max` where nothing moves.
pub fn first_step(d: f64, tol: f64, h_max: f64) -> f64 {
    if d > 0.0 {
        1e-2 / d * libm::pow(tol, 0.2)
    } else {
        h_max
    }
}

/// The step-size factor after an attempt with scaled error `err` (accept when ≤ 1): the
/// fifth root with a safety factor, bounded to [0.2, 10] (DOPRI5's bounds).
pub fn factor(err: f64) -> f64 {
    // 0.9·err^(−1/5) is 10 at (0.09)^5 and 0.2 at 4.5^5: outside, the bound (and NaN).
    if err.is_nan() || err >= 1845.28125 {
        return 0.2;
    }
    if err <= 5.9049e-6 {
        return 10.0;
    }
    (0.9 * inv_fifth_root(err)).clamp(0.2, 10.0)
}

/// `x^(−1/5)` for positive normal `x`, to a few units in the last place: a first guess from
/// the bits (the exponent divided by −5), then Newton's iteration on `y^(−5) = x`,
/// `y ← y·(6 − x·y^5)/5`, whose relative error goes 7 % → 2e-2 → 1e-3 → 4e-6 → 5e-11 → below
/// the rounding. Plain arithmetic (cheaper than `exp` and `log`), the same bits on every
/// platform.
fn inv_fifth_root(x: f64) -> f64 {
    // The bits of 1.0; those of a positive normal x are below 2^63.
    const ONE: i64 = 0x3ff0_0000_0000_0000;
    let mut y = f64::from_bits((ONE + (ONE - x.to_bits() as i64) / 5) as u64);
    for _ in 0..5 {
        let y2 = y * y;
        y *= (6.0 - x * (y2 * y2 * y)) * 0.2;
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The step-size factor against `0.9·err^(−1/5)` through `pow`, and its bounds.
    #[test]
    fn factor_is_the_fifth_root_within_its_bounds() {
        for i in 0..=100_000 {
            let err = libm::pow(10.0, -12.0 + 16.0 * i as f64 / 100_000.0);
            let want = (0.9 * libm::pow(err, -0.2)).clamp(0.2, 10.0);
            let got = factor(err);
            assert!(
                (got - want).abs() <= 4.0 * f64::EPSILON * want,
                "{err}: {got} {want}"
            );
        }
        for (err, want) in [
            (0.0, 10.0),
            (f64::INFINITY, 0.2),
            (f64::NAN, 0.2),
            (1e300, 0.2),
        ] {
            assert_eq!(factor(err), want, "{err}");
        }
    }

    /// y' = −y·cos t: y = exp(−sin t). Fifth order: halving h divides the error by about 32;
    /// the continuous extension is accurate inside the step.
    #[test]
    fn order_five_and_a_dense_output_of_order_four() {
        let mut f = |t: f64, y: &[f64; 1]| [-y[0] * t.cos()];
        let exact = |t: f64| (-t.sin()).exp();
        let mut errs = vec![];
        for n in [20, 40, 80] {
            let h = 1.0 / n as f64;
            let (mut t, mut y) = (0.0, [1.0]);
            let mut dense_err: f64 = 0.0;
            for _ in 0..n {
                let k1 = f(t, &y);
                let st = DoPriStep::take(&mut f, t, &y, &k1, h);
                for theta in [0.25, 0.5, 0.75] {
                    let d = st.dense(0, h, theta) - exact(t + theta * h);
                    dense_err = dense_err.max(d.abs());
                }
                y = st.end();
                t += h;
            }
            errs.push(((y[0] - exact(1.0)).abs(), dense_err));
        }
        for w in errs.windows(2) {
            let ratio = w[0].0 / w[1].0;
            assert!(ratio > 20.0 && ratio < 40.0, "{errs:?}");
        }
        assert!(errs[2].1 < 1e-10, "{errs:?}");
    }

    /// The precomputed continuous extension is `dense`'s, bit for bit, in every component.
    #[test]
    fn dense_all_is_dense() {
        let mut f = |t: f64, y: &[f64; 2]| [y[1], -y[0] * (1.0 + t.sin())];
        let y = [0.3, -1.2];
        let k1 = f(0.1, &y);
        let h = 0.37;
        let st = DoPriStep::take(&mut f, 0.1, &y, &k1, h);
        let d = st.dense_all(h);
        for m in 0..2 {
            for theta in [0.0, 0.2, 0.55, 8.0 / 9.0, 1.0] {
                assert_eq!(d.at(m, theta).to_bits(), st.dense(m, h, theta).to_bits());
            }
        }
    }
}
