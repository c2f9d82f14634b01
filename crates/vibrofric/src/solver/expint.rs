//! Exponential integration of a deformation that relaxes toward a moving target at a scalar
//! rate, `ds/dt = a(t)·(q(t) − s)` with `a ≥ 0`, together with the integral of an observable
//! affine in `s`, `∫ (c(t)·s_x + d(t)) dt`.
//!
//! In the relaxation "arc length" `λ(t) = ∫ a dt` the equation reads `ds/dλ = q − s`, whose
//! solution is `s(λ) = e^{−λ}·s0 + ∫_0^λ e^{−(λ−μ)}·q(μ) dμ`. Over one step the target `q` is
//! interpolated as a polynomial in `λ` through its values at six Gauss nodes in time, and the
//! convolution is then exact (the φ-functions of exponential integrators). Its error is that of
//! the interpolation of `q`, whatever `a·h`: the method is explicit, needs no Newton iteration,
//! and costs the same at any stiffness. The step size follows from the interpolation error,
//! estimated by the difference that the target at the step's two ends (two more interpolation
//! points) makes to `s` at the end and to the observable's integral: the six Gauss nodes give
//! the end value far more accuracy than the interpolant has between them, which an estimate
//! from the nodes alone (the last Newton terms) misses by orders of magnitude.

// The tables are printed to 17 significant digits from a 40-digit computation.
#![allow(clippy::excessive_precision)]

use super::quadrature::{adaptive, Integral};
use super::SolverError;

/// Gauss–Legendre nodes on [0, 1].
const X: [f64; 6] = [
    3.376_524_289_842_398_6e-2,
    1.693_953_067_668_677_4e-1,
    3.806_904_069_584_015_5e-1,
    6.193_095_930_415_984_5e-1,
    8.306_046_932_331_322_6e-1,
    9.662_347_571_015_760_1e-1,
];
/// Gauss–Legendre weights on [0, 1].
const W: [f64; 6] = [
    8.566_224_618_958_517_3e-2,
    1.803_807_865_240_693e-1,
    2.339_569_672_863_455_2e-1,
    2.339_569_672_863_455_2e-1,
    1.803_807_865_240_693e-1,
    8.566_224_618_958_517_3e-2,
];
/// Inverse Vandermonde matrix of the nodes: monomial coefficients `c_m = Σ_k VINV[m][k]·f(X_k)`.
const VINV: [[f64; 6]; 6] = [
    [
        1.565_673_200_151_071_9,
        -9.404_628_431_763_489_3e-1,
        6.169_300_554_304_887_1e-1,
        -3.792_277_021_146_137_5e-1,
        1.918_000_140_386_679_5e-1,
        -5.471_272_432_926_591_3e-2,
    ],
    [
        -1.938_889_969_575_614_2e1,
        3.394_755_689_005_745_8e1,
        -2.429_050_650_593_736e1,
        1.531_522_402_826_687_6e1,
        -7.824_684_468_391_84,
        2.241_309_751_761_007_9,
    ],
    [
        8.335_617_166_520_660_5e1,
        -1.945_900_409_203_250_5e2,
        1.953_041_651_669_510_5e2,
        -1.345_461_228_632_236_6e2,
        7.113_553_845_590_593e1,
        -2.065_971_150_451_487_1e1,
    ],
    [
        -1.616_334_485_633_571_8e2,
        4.312_442_105_751_191_5e2,
        -5.234_162_607_908_361_8e2,
        4.198_507_411_387_223_7e2,
        -2.365_809_504_896_121_4e2,
        7.053_570_812_996_398_2e1,
    ],
    [
        1.448_933_610_434_784_3e2,
        -4.166_718_961_318_097_3e2,
        5.684_164_873_451_1e2,
        -5.166_337_275_190_531e2,
        3.193_402_660_890_562_2e2,
        -9.934_449_082_678_183_4e1,
    ],
    [
        -4.884_757_037_405_205_4e1,
        1.472_024_324_441_731_9e2,
        -2.170_100_429_728_326_2e2,
        2.170_100_429_728_326_2e2,
        -1.472_024_324_441_731_9e2,
        4.884_757_037_405_205_4e1,
    ],
];
const N: usize = 6;
/// Coefficients of the polynomials a step carries: the interpolant of the target through the
/// nodes (degree `N − 1`), and the difference to the interpolant through the nodes and both ends
/// of the step (degree `N + 1`), the error estimate.
const D: usize = N + 2;
/// `λ` at the nodes from the rates there: `LAM[j][k] = Σ_m X_j^{m+1}/(m + 1)·VINV[m][k]`
/// (the integral from 0 to `X_j` of the interpolant of `a`, per unit step).
const LAM: [[f64; N]; N] = {
    let mut out = [[0.0; N]; N];
    let mut j = 0;
    while j < N {
        let mut k = 0;
        while k < N {
            let (mut sum, mut xp, mut m) = (0.0, X[j], 0);
            while m < N {
                sum += xp / (m + 1) as f64 * VINV[m][k];
                xp *= X[j];
                m += 1;
            }
            out[j][k] = sum;
            k += 1;
        }
        j += 1;
    }
    out
};
/// Above this `Λ` per step the integral of the observable splits off the decaying transient
/// (integrated on its own scale); below it, Gauss in time resolves `e^{−λ}` directly.
const SPLIT: f64 = 2.0;
/// Up to this `Λ` per step the error estimate's solution is summed as a power series (32 terms:
/// to 3e-7 of it at `Λ` = 8, enough for an estimate).
const ESTIMATE_SERIES: f64 = 8.0;
/// Below this `Λ` per step the relaxation is negligible: `s` moves by `∫ a·(q − s0) dt`.
const NEGLIGIBLE: f64 = 1e-10;
const SAFE: f64 = 0.8;
/// The error estimate is this multiple of the difference the step's ends make to the
/// interpolant's solution (see `step`).
const ESTIMATE_FACTOR: f64 = 5.0;
/// Tightest relative tolerance: the interpolation's own rounding is about 1e-15.
pub const MIN_TOL: f64 = 1e-13;

/// The system at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample {
    /// Decay rate `a ≥ 0`.
    pub a: f64,
    /// Target `q` (components beyond the dimension are ignored).
    pub q: [f64; 2],
    /// The observable is the vector `c·s + d` (components beyond the dimension are ignored).
    pub c: f64,
    pub d: [f64; 2],
}

/// A deformation of dimension 1 or 2 relaxing toward a target at a scalar rate.
pub trait Relaxing {
    /// Dimension of `s` (1 or 2).
    fn dim(&self) -> usize;
    fn sample(&self, t: f64) -> Sample;
}

/// `1/k!` for `k = 0..=31` (the series of [`phis`] reach `1/31!`).
const INV_FACT: [f64; 32] = {
    let mut t = [1.0; 32];
    let mut k = 1;
    while k < 32 {
        t[k] = t[k - 1] / k as f64;
        k += 1;
    }
    t
};

/// `φ_j(−x)` for `j = 1..=8`, `x ≥ 0`, where `φ_j(z) = Σ_m z^m/(m + j)!`. Below `x = 2` by that
/// series (24 terms: the first omitted is below 1e-19 of the sum); above, by
/// `φ_j(z) = (e^z − Σ_{m<j} z^m/m!)/z^j`, whose subtraction then loses at most two digits.
fn phis(x: f64) -> [f64; D] {
    let z = -x;
    let mut out = [0.0; D];
    if x < 2.0 {
        let mut pw = [1.0; 24];
        for m in 1..24 {
            pw[m] = pw[m - 1] * z;
        }
        for (i, o) in out.iter_mut().enumerate() {
            *o = (0..24).rev().map(|m| pw[m] * INV_FACT[m + i + 1]).sum();
        }
    } else {
        let e = libm::exp(-x);
        let (mut partial, mut zm, mut zj) = (0.0, 1.0, 1.0);
        for (i, o) in out.iter_mut().enumerate() {
            partial += zm * INV_FACT[i];
            zm *= z;
            zj *= z;
            *o = (e - partial) / zj;
        }
    }
    out
}

/// `x^m` for `m = 0..6`.
fn powers(x: f64) -> [f64; 7] {
    let mut p = [1.0; 7];
    for m in 1..7 {
        p[m] = p[m - 1] * x;
    }
    p
}

/// `1/(mu_j − mu_{j−k})` for the divided differences of [`fit`], shared by the components.
fn inverse_gaps(mu: &[f64; D]) -> [[f64; D]; D] {
    let mut inv = [[0.0; D]; D];
    for k in 1..D {
        for j in k..D {
            inv[k][j] = 1.0 / (mu[j] - mu[j - k]);
        }
    }
    inv
}

/// Monomial coefficients of `Π_{j<N} (μ − mu_j)`, the nodes' polynomial.
fn node_polynomial(mu: &[f64; D]) -> [f64; D] {
    let mut w = [0.0; D];
    w[0] = 1.0;
    for &m_j in &mu[..N] {
        for m in (1..D).rev() {
            w[m] = w[m - 1] - m_j * w[m];
        }
        w[0] *= -m_j;
    }
    w
}

/// From the values `v` at the points `mu` (the `N` nodes, then `μ = 0` and `μ = 1`, the step's
/// ends; `inv` is [`inverse_gaps`] of `mu`, `omega` the [`node_polynomial`]): the monomial
/// coefficients of the interpolant through the nodes, and of the difference between the
/// interpolant through all `D` points and it, `omega·(dd_N + dd_{N+1}·μ)` (the last two terms of
/// the Newton form, the point after the nodes being `μ = 0`).
fn fit(mu: &[f64; D], inv: &[[f64; D]; D], omega: &[f64; D], v: &[f64; D]) -> ([f64; D], [f64; D]) {
    let mut dd = *v;
    for k in 1..D {
        for j in (k..D).rev() {
            dd[j] = (dd[j] - dd[j - 1]) * inv[k][j];
        }
    }
    // Horner on the Newton form of the nodes' interpolant, in monomials.
    let mut poly = [0.0; D];
    poly[0] = dd[N - 1];
    for i in (0..N - 1).rev() {
        // poly ← poly·(μ − μ_i) + dd_i
        for m in (1..N).rev() {
            poly[m] = poly[m - 1] - mu[i] * poly[m];
        }
        poly[0] = -mu[i] * poly[0] + dd[i];
    }
    let mut extra = [0.0; D];
    for m in 0..D {
        extra[m] = dd[N] * omega[m] + if m > 0 { dd[N + 1] * omega[m - 1] } else { 0.0 };
    }
    (poly, extra)
}

/// Most terms of the power series of `s(λ)` for `λ ≤` [`SPLIT`] (at `Λ` = 2 the 32nd is below
/// `2^24·8!/32! ≈ 3e-24` of the largest); [`Series`] ends them sooner where they fall faster.
const SERIES: usize = 32;

/// `1/(m + 1)`.
const RECIP: [f64; SERIES] = {
    let mut t = [1.0; SERIES];
    let mut m = 0;
    while m < SERIES {
        t[m] = 1.0 / (m + 1) as f64;
        m += 1;
    }
    t
};

/// Below this fraction of the largest of its first `N + 1` terms at `λ = Λ`, a term of the
/// series ends it: the terms after it shrink by `Λ/(m + 1) ≤ 1/4` each, so the whole tail is
/// below a third of it, under the rounding of the sum.
const SERIES_END: f64 = 1.0 / (1u64 << 60) as f64;

/// Power series of the solution of `ds/dλ = Q(λ/Λ) − s`, `s(0) = s0`, with
/// `Q = Σ_k p_k·μ^k`: `σ_{m+1} = (r_m − σ_m)/(m + 1)`, `r_m = p_m/Λ^m`, for `Λ ≤` [`SPLIT`], for
/// [`LANES`] right-hand sides at once (per component: the interpolant of the target and the
/// error estimate's polynomial), computed and evaluated in lockstep: each series is a chain of
/// dependent operations, and the lanes side by side keep the processor busy.
///
/// Beyond the degree of `Q` the terms at `λ ≤ Λ` fall like `Λ^m/m!`: the series end at the
/// first term at which every lane is below [`SERIES_END`] of the largest of its first `D + 1`
/// terms (at most [`SERIES`] terms; about 17 at `Λ` = 0.5, 27 at `Λ` = 2).
struct Series {
    sigma: [[f64; LANES]; SERIES],
    len: usize,
}

/// Lanes of a [`Series`]: two per component.
const LANES: usize = 4;

impl Series {
    fn new(p: &[[f64; D]; LANES], big: f64, s0: &[f64; LANES]) -> Self {
        let mut sigma = [[0.0; LANES]; SERIES];
        sigma[0] = *s0;
        let inv = 1.0 / big;
        let mut scale = 1.0;
        // |σ_m·Λ^m|: the terms at the step's end, the largest values they take on it.
        let mut power = 1.0;
        let mut largest = s0.map(f64::abs);
        for m in 0..SERIES - 1 {
            power *= big;
            let mut done = m >= D;
            for l in 0..LANES {
                let r = if m < D { p[l][m] * scale } else { 0.0 };
                let next = (r - sigma[m][l]) * RECIP[m];
                sigma[m + 1][l] = next;
                let term = (next * power).abs();
                if m < D {
                    largest[l] = largest[l].max(term);
                } else {
                    done &= term <= SERIES_END * largest[l];
                }
            }
            scale *= inv;
            if done {
                return Series { sigma, len: m + 2 };
            }
        }
        Series { sigma, len: SERIES }
    }

    /// Every lane at `λ = x` (`0 ≤ x ≤ Λ`).
    fn at(&self, x: f64) -> [f64; LANES] {
        let mut acc = [0.0; LANES];
        for row in self.sigma[..self.len].iter().rev() {
            for l in 0..LANES {
                acc[l] = acc[l] * x + row[l];
            }
        }
        acc
    }

    /// Every lane at each `λ` of `xs` (`0 ≤ x ≤ Λ`).
    fn at_each(&self, xs: &[f64; N]) -> [[f64; LANES]; N] {
        let mut acc = [[0.0; LANES]; N];
        for row in self.sigma[..self.len].iter().rev() {
            for j in 0..N {
                for l in 0..LANES {
                    acc[j][l] = acc[j][l] * xs[j] + row[l];
                }
            }
        }
        acc
    }
}

fn horner<const M: usize>(p: &[f64; M], x: f64) -> f64 {
    p.iter().rev().fold(0.0, |acc, &c| acc * x + c)
}

/// `∫_0^z e^{−(z−λ)}·Q(λ/Λ) dλ` for `Q = Σ_k p_k·μ^k`, at `z = mubar·Λ`.
fn convolve<const M: usize>(p: &[f64; M], mubar: f64, z: f64, phi: &[f64; D]) -> f64 {
    let mut sum = 0.0;
    let mut fact = 1.0;
    let mut mk = 1.0;
    for k in 0..M {
        if k > 0 {
            fact *= k as f64;
            mk *= mubar;
        }
        sum += p[k] * mk * fact * phi[k];
    }
    z * sum
}

/// `Σ_k (−1/Λ)^k P^(k)`: the particular solution of `ds/dλ = P(λ/Λ) − s`, in `μ = λ/Λ`.
fn particular(p: &[f64; D], big: f64) -> [f64; D] {
    let mut pcoef = [0.0; D];
    let mut deriv = *p;
    let mut factor = 1.0;
    for _ in 0..D {
        for m in 0..D {
            pcoef[m] += factor * deriv[m];
        }
        // deriv ← d/dμ deriv
        for m in 0..D - 1 {
            deriv[m] = deriv[m + 1] * (m + 1) as f64;
        }
        deriv[D - 1] = 0.0;
        factor *= -1.0 / big;
    }
    pcoef
}

/// One step's outcome.
#[derive(Clone, Copy, Debug)]
struct StepOut {
    s: [f64; 2],
    integral: [f64; 2],
    /// `Λ = ∫ a dt` over the step.
    decay: f64,
    /// Error estimate of `s` at the step's end, in units of the tolerance.
    err: f64,
    evals: u64,
}

/// The integrator's state between calls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExpIntegrator {
    /// Proposed next step (0: choose one).
    pub h: f64,
    pub tol: f64,
    pub steps: u64,
    pub rejected: u64,
    pub evals: u64,
    /// `∫ a dt` over the accepted steps: `exp(−decay)` is what is left of the initial `s`.
    pub decay: f64,
}

impl ExpIntegrator {
    /// An integrator for the relative tolerance `tol`, floored at [`MIN_TOL`] where the
    /// interpolation's rounding dominates.
    pub fn new(tol: f64) -> Self {
        ExpIntegrator {
            h: 0.0,
            tol: tol.max(MIN_TOL),
            steps: 0,
            rejected: 0,
            evals: 0,
            decay: 0.0,
        }
    }

    /// Integrates `s` from `t0` to `t1` (exactly), returning `∫ (c·s + d) dt`. `scale_s` is
    /// the natural magnitude of `s` (absolute tolerance `tol·scale_s`), `scale_f` that of the
    /// observable, `h_max` the longest step.
    #[allow(clippy::too_many_arguments)]
    // With `step` inlined here; inlined into its caller it took 6 % more instructions.
    #[inline(never)]
    pub fn integrate(
        &mut self,
        sys: &impl Relaxing,
        t0: f64,
        t1: f64,
        s: &mut [f64; 2],
        scale_s: f64,
        scale_f: f64,
        h_max: f64,
    ) -> Result<[f64; 2], SolverError> {
        let mut t = t0;
        let mut integral = [0.0; 2];
        let rtol = self.tol;
        if self.h <= 0.0 {
            self.h = (t1 - t0).min(h_max);
        }
        let mut rejected = false;
        // The system at the current step's start (the last step's end).
        let mut start = sys.sample(t);
        self.evals += 1;
        while t < t1 {
            let mut h = self.h.min(h_max);
            let last = t + 1.0001 * h >= t1;
            if last {
                h = t1 - t;
            }
            if h <= 8.0 * f64::EPSILON * t.abs().max(h_max.min(1.0)) && !last {
                return Err(SolverError::StepSizeTooSmall { t, h });
            }
            let end = sys.sample(t + h);
            let out = step(sys, t, h, [&start, &end], *s, scale_s, scale_f, rtol);
            self.evals += out.evals + 1;
            let err = if out.err.is_finite() { out.err } else { 1e10 };
            // SAFE·err^(−1/6), as a square root and a cube root (a third of `pow`'s cost).
            let fac = (SAFE / libm::cbrt(err.max(1e-10).sqrt())).clamp(0.2, 2.0);
            if err > 1.0 {
                self.rejected += 1;
                self.h = h * fac.min(0.9);
                rejected = true;
                continue;
            }
            self.steps += 1;
            *s = out.s;
            integral[0] += out.integral[0];
            integral[1] += out.integral[1];
            self.decay += out.decay;
            t = if last { t1 } else { t + h };
            start = end;
            // No growth right after a rejection: the estimate varies along the forcing.
            let fac = if rejected { fac.min(1.0) } else { fac };
            rejected = false;
            if !last || h >= self.h {
                self.h = h * fac;
            }
        }
        Ok(integral)
    }
}

/// The system at a step's Gauss nodes (`c` of the observable) and `λ`, as [`step`] computed them.
struct Nodes<'a> {
    h: f64,
    samples: &'a [Sample; N],
    /// The rate `a` at the nodes, and its interpolant's coefficients in the step's fraction `x`.
    a: &'a [f64; N],
    alpha: &'a [f64; N],
    /// `λ` at the nodes, and `Λ` over the whole step.
    lam: &'a [f64; N],
    big: f64,
    c: &'a [f64; N],
}

impl Nodes<'_> {
    /// `λ` at the fraction `x` of the step.
    fn lambda_at(&self, x: f64) -> f64 {
        let p = powers(x);
        self.h
            * (0..N)
                .map(|m| self.alpha[m] * p[m + 1] * RECIP[m])
                .sum::<f64>()
    }
}

/// What a step's error is measured against.
struct Tolerance {
    rtol: f64,
    scale_s: f64,
    scale_f: f64,
    h: f64,
}

impl Tolerance {
    /// The error estimate in units of the tolerance, from the differences the interpolant through
    /// both ends too makes to `s_end` (`d_end`) and to the observable's integral (`d_integral`).
    #[inline(always)]
    fn estimate(&self, s_end: f64, d_end: f64, d_integral: f64) -> f64 {
        let e_s = d_end.abs() / (self.rtol * (self.scale_s + s_end.abs()));
        let e_i = d_integral.abs() / (self.rtol * self.scale_f * self.h);
        ESTIMATE_FACTOR * e_s.max(e_i)
    }
}

/// One step of length `h` from `(t, s0)`; `ends` are the system at `t` and `t + h`. The system
/// at the nodes ([`Nodes`]), the target interpolated in `μ = λ/Λ` ([`interpolate`]), then
/// [`nearly_still`], [`by_series`] (`Λ ≤` [`SPLIT`]) or [`by_phis`] (beyond).
#[allow(clippy::too_many_arguments)]
fn step(
    sys: &impl Relaxing,
    t: f64,
    h: f64,
    ends: [&Sample; 2],
    s0: [f64; 2],
    scale_s: f64,
    scale_f: f64,
    rtol: f64,
) -> StepOut {
    let dim = sys.dim();
    // A loop: `array::from_fn`'s closure was left out of line here (more instructions).
    let mut samples = [Sample::default(); N];
    for (j, sample) in samples.iter_mut().enumerate() {
        *sample = sys.sample(t + h * X[j]);
    }
    let a: [f64; N] = std::array::from_fn(|j| samples[j].a);
    // a(x) = Σ alpha_m x^m; λ(x) = h·Σ alpha_m x^{m+1}/(m + 1), at the nodes h·Σ LAM[j][k]·a_k.
    let alpha: [f64; N] = std::array::from_fn(|m| (0..N).map(|k| VINV[m][k] * a[k]).sum());
    let lam: [f64; N] = std::array::from_fn(|j| h * (0..N).map(|k| LAM[j][k] * a[k]).sum::<f64>());
    let big = h * (0..N).map(|k| W[k] * a[k]).sum::<f64>();
    let smooth_d: [f64; 2] =
        std::array::from_fn(|i| h * (0..N).map(|k| W[k] * samples[k].d[i]).sum::<f64>());
    let c: [f64; N] = std::array::from_fn(|j| samples[j].c);
    let evals = N as u64;
    let nodes = Nodes {
        h,
        samples: &samples,
        a: &a,
        alpha: &alpha,
        lam: &lam,
        big,
        c: &c,
    };

    if big < NEGLIGIBLE {
        let (s, integral) = nearly_still(&nodes, dim, s0, &smooth_d);
        return StepOut {
            s,
            integral,
            decay: big,
            err: 0.0,
            evals,
        };
    }
    let inv_big = 1.0 / big;
    let mu: [f64; N] = std::array::from_fn(|j| nodes.lam[j] * inv_big);
    if !(mu.windows(2).all(|w| w[1] > w[0]) && mu[0] > 0.0 && mu[N - 1] < 1.0) {
        // The interpolant of a went negative between nodes: the step is too long.
        return StepOut {
            s: s0,
            integral: [0.0; 2],
            decay: 0.0,
            err: f64::INFINITY,
            evals,
        };
    }
    let mut fits = [([0.0; D], [0.0; D]); 2];
    interpolate(&nodes, ends, &mu, dim, &mut fits);
    let tol = Tolerance {
        rtol,
        scale_s,
        scale_f,
        h,
    };
    let mut integral = smooth_d;
    let (s, err) = if big <= SPLIT {
        by_series(&nodes, &fits, s0, dim, &tol, &mut integral)
    } else {
        by_phis(&nodes, &fits, &mu, s0, dim, &tol, &mut integral)
    };
    StepOut {
        s,
        integral,
        decay: big,
        err,
        evals,
    }
}

/// A step with next to no relaxation (`Λ` below [`NEGLIGIBLE`]): `s(x) = s0 + ∫_0^x a·(q − s0)`,
/// to first order in `Λ`, and the observable's integral at `s0`.
#[inline(always)]
fn nearly_still(
    nodes: &Nodes,
    dim: usize,
    s0: [f64; 2],
    smooth_d: &[f64; 2],
) -> ([f64; 2], [f64; 2]) {
    let h = nodes.h;
    let mut s = s0;
    for i in 0..dim {
        s[i] += h
            * (0..N)
                .map(|k| W[k] * nodes.a[k] * (nodes.samples[k].q[i] - s0[i]))
                .sum::<f64>();
    }
    let mean_c = h * (0..N).map(|k| W[k] * nodes.c[k]).sum::<f64>();
    let integral = std::array::from_fn(|i| mean_c * s0[i] + smooth_d[i]);
    (s, integral)
}

/// Into `fits`, per component, the target's interpolant in `μ = λ/Λ` through the nodes and the
/// difference the step's two ends make to it (the error estimate's polynomial; see [`fit`]).
#[inline(always)]
fn interpolate(
    nodes: &Nodes,
    ends: [&Sample; 2],
    mu: &[f64; N],
    dim: usize,
    fits: &mut [([f64; D], [f64; D]); 2],
) {
    // The nodes, then the step's ends.
    let mu_all: [f64; D] = std::array::from_fn(|j| if j < N { mu[j] } else { (j - N) as f64 });
    let inv = inverse_gaps(&mu_all);
    let omega = node_polynomial(&mu_all);
    let target = |i: usize| -> [f64; D] {
        std::array::from_fn(|j| {
            if j < N {
                nodes.samples[j].q[i]
            } else {
                ends[j - N].q[i]
            }
        })
    };
    for (i, f) in fits.iter_mut().enumerate().take(dim) {
        *f = fit(&mu_all, &inv, &omega, &target(i));
    }
}

/// `Λ ≤` [`SPLIT`] (`e^{−λ}` varies by at most e²): `s(λ)` by its power series from
/// `ds/dλ = Q(λ) − s`, at the end and the nodes, the observable by Gauss in time (added to
/// `integral`). Returns `s` at the end and the error estimate.
#[inline(always)]
fn by_series(
    nodes: &Nodes,
    fits: &[([f64; D], [f64; D]); 2],
    s0: [f64; 2],
    dim: usize,
    tol: &Tolerance,
    integral: &mut [f64; 2],
) -> ([f64; 2], f64) {
    let (h, c) = (nodes.h, &nodes.c);
    // Lanes 2i, 2i + 1: the interpolant of component i and the estimate's polynomial.
    let mut p = [[0.0; D]; LANES];
    let mut start = [0.0; LANES];
    for i in 0..dim {
        (p[2 * i], p[2 * i + 1]) = fits[i];
        start[2 * i] = s0[i];
    }
    let series = Series::new(&p, nodes.big, &start);
    let end = series.at(nodes.big);
    let at_nodes = series.at_each(nodes.lam);
    let mut s = [0.0; 2];
    let mut err: f64 = 0.0;
    for i in 0..dim {
        s[i] = end[2 * i];
        let (mut sum, mut diff) = (0.0, 0.0);
        for j in 0..N {
            sum += W[j] * c[j] * at_nodes[j][2 * i];
            diff += W[j] * c[j] * at_nodes[j][2 * i + 1];
        }
        integral[i] += h * sum;
        err = err.max(tol.estimate(s[i], end[2 * i + 1], h * diff));
    }
    (s, err)
}

/// `Λ >` [`SPLIT`]: `s` at the end by the φ-functions, the observable's integral (added to
/// `integral`) from the particular solution `P` by Gauss plus the transient `e^{−λ}·(s0 − P(0))`
/// ([`transient_layer`]); the estimate's solution by its power series up to `Λ =`
/// [`ESTIMATE_SERIES`], beyond by the same split. Returns `s` at the end and the error estimate.
#[inline(always)]
fn by_phis(
    nodes: &Nodes,
    fits: &[([f64; D], [f64; D]); 2],
    mu: &[f64; N],
    s0: [f64; 2],
    dim: usize,
    tol: &Tolerance,
    integral: &mut [f64; 2],
) -> ([f64; 2], f64) {
    let (h, big, c) = (nodes.h, nodes.big, &nodes.c);
    let phi_end = phis(big);
    let decay_end = libm::exp(-big);
    let mut s = [0.0; 2];
    let mut err: f64 = 0.0;
    let mut transient = [0.0; 2];
    let c_max = c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    // ∫ e^{−λ} dt ≤ min(h, 1/a(0)).
    let a0 = nodes.alpha[0].max(nodes.a[0]).max(f64::MIN_POSITIVE);
    let layer_bound = h.min(1.0 / a0);
    let estimate_series = (big <= ESTIMATE_SERIES).then(|| {
        let mut p = [[0.0; D]; LANES];
        for i in 0..dim {
            p[2 * i + 1] = fits[i].1;
        }
        let series = Series::new(&p, big, &[0.0; LANES]);
        (series.at(big), series.at_each(nodes.lam))
    });
    for i in 0..dim {
        let (p, extra) = &fits[i];
        s[i] = decay_end * s0[i] + convolve(p, 1.0, big, &phi_end);
        // s = P(μ) + e^{−λ}·(s0 − P(0)) with P = Σ_k (−1/Λ)^k Q^(k) the particular solution.
        let pcoef = particular(p, big);
        integral[i] += h
            * (0..N)
                .map(|j| W[j] * c[j] * horner(&pcoef, mu[j]))
                .sum::<f64>();
        transient[i] = s0[i] - pcoef[0];
        let (d_end, d_integral) = match &estimate_series {
            Some((end, at_nodes)) => (
                end[2 * i + 1],
                h * (0..N)
                    .map(|j| W[j] * c[j] * at_nodes[j][2 * i + 1])
                    .sum::<f64>(),
            ),
            None => {
                // Its particular solution by Gauss, its transient (no longer amplified
                // by 1/Λ^k) bounded.
                let pe = particular(extra, big);
                let gauss = (0..N)
                    .map(|j| W[j] * c[j] * horner(&pe, mu[j]))
                    .sum::<f64>();
                (
                    convolve(extra, 1.0, big, &phi_end),
                    (h * gauss).abs() + pe[0].abs() * c_max * layer_bound,
                )
            }
        };
        err = err.max(tol.estimate(s[i], d_end, d_integral));
    }
    // The decaying transient of every component shares `∫ c·e^{−λ} dt`.
    let transient_max = transient[0].abs().max(transient[1].abs());
    let mut layer = 0.0;
    // Skip the layer where it cannot matter.
    if transient_max * c_max * layer_bound > 1e-3 * tol.rtol * tol.scale_f * h {
        layer = transient_layer(nodes, a0, transient_max, tol);
    }
    for i in 0..dim {
        integral[i] += transient[i] * layer;
    }
    (s, err)
}

/// `∫ c(t)·e^{−λ(t)} dt` over the step (the transient's share of the observable), on panels
/// doubling from the relaxation time `1/a(0)` until `e^{−λ}` is negligible.
fn transient_layer(nodes: &Nodes, a0: f64, transient_max: f64, tol: &Tolerance) -> f64 {
    let h = nodes.h;
    let gamma: [f64; N] = std::array::from_fn(|m| (0..N).map(|k| VINV[m][k] * nodes.c[k]).sum());
    let mut f = |x: f64| horner(&gamma, x) * libm::exp(-nodes.lambda_at(x));
    let budget = 1e-3 * tol.rtol * tol.scale_f / transient_max;
    let x_b = (1.0 / (h * a0)).clamp(1e-12, 1.0);
    let phi_cut = libm::log(1.0 / (1e-3 * tol.rtol)) + 3.0;
    let (mut lo, mut width) = (0.0, x_b);
    let mut j = Integral::default();
    loop {
        let hi = (lo + width).min(1.0);
        j += adaptive(&mut f, lo, hi, budget * (hi - lo));
        if hi >= 1.0 || nodes.lambda_at(hi) > phi_cut {
            break;
        }
        lo = hi;
        width *= 2.0;
    }
    h * j.value
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phi_functions_against_their_definition() {
        // φ_j(z) = ∫_0^1 e^{(1−θ)z} θ^{j−1}/(j−1)! dθ, by composite Simpson.
        for &x in &[0.0, 1e-8, 0.3, 1.9, 2.5, 6.5, 7.9, 8.1, 40.0] {
            let p = phis(x);
            for j in 1..=7usize {
                let n = 20_000;
                let f = |th: f64| {
                    (-(1.0 - th) * x).exp() * th.powi(j as i32 - 1)
                        / (1..j).map(|k| k as f64).product::<f64>()
                };
                let h = 1.0 / n as f64;
                let mut s = f(0.0) + f(1.0);
                for k in 1..n {
                    s += if k % 2 == 1 { 4.0 } else { 2.0 } * f(k as f64 * h);
                }
                let exact = s * h / 3.0;
                assert!(
                    (p[j - 1] - exact).abs() <= 1e-12 * exact.abs() + 1e-300,
                    "phi_{j}(-{x}) = {} vs {exact}",
                    p[j - 1]
                );
            }
        }
        // Far in the stiff range, against the closed forms of φ_1 and φ_2.
        let x = 1e4;
        let p = phis(x);
        assert!((p[0] - (1.0 - (-x).exp()) / x).abs() <= 1e-15 * p[0]);
        assert!((p[1] - (x - 1.0 + (-x).exp()) / (x * x)).abs() <= 1e-15 * p[1]);
    }

    /// `ds/dt = a(t)·(q(t) − s)` with `a = k·(1 + 0.5 sin t)`, `q = cos(3t)`: against a
    /// reference by the integrating factor and adaptive quadrature, from stiffness 1 to 1e9.
    struct Test {
        k: f64,
    }
    impl Relaxing for Test {
        fn dim(&self) -> usize {
            1
        }
        fn sample(&self, t: f64) -> Sample {
            Sample {
                a: self.k * (1.0 + 0.5 * t.sin()),
                q: [(3.0 * t).cos(), 0.0],
                c: 2.0,
                d: [t, 0.0],
            }
        }
    }

    #[test]
    fn relaxation_is_accurate_at_any_stiffness() {
        for k in [1.0, 1e3, 1e9] {
            let sys = Test { k };
            let mut int = ExpIntegrator::new(1e-10);
            let mut s = [0.5, 0.0];
            let integral = int
                .integrate(&sys, 0.0, 2.0, &mut s, 1.0, 2.0, 0.5)
                .unwrap();
            // Reference: Λ(t) = k·(t + 0.5(1 − cos t)); s(T) = e^{−Λ(T)} s0 +
            // ∫ e^{−(Λ(T)−Λ(τ))} a(τ) q(τ) dτ; for k = 1 by dense Simpson, for stiff k the
            // asymptotic expansion s ≈ q − q'/a + … (error O(1/k²)).
            let big = |t: f64| k * (t + 0.5 * (1.0 - t.cos()));
            let t_end = 2.0;
            let s_ref = if k == 1.0 {
                let n = 400_000;
                let hh = t_end / n as f64;
                let f = |tau: f64| {
                    (-(big(t_end) - big(tau))).exp() * sys.sample(tau).a * (3.0 * tau).cos()
                };
                let mut sum = f(0.0) + f(t_end);
                for i in 1..n {
                    sum += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i as f64 * hh);
                }
                (-big(t_end)).exp() * 0.5 + sum * hh / 3.0
            } else {
                let a = sys.sample(t_end).a;
                (3.0 * t_end).cos() + 3.0 * (3.0 * t_end).sin() / a
            };
            let tol = if k == 1.0 {
                1e-9
            } else {
                20.0 / (k * k) + 1e-9
            };
            assert!((s[0] - s_ref).abs() < tol, "k {k}: {} vs {s_ref}", s[0]);
            // ∫(2s + t) dt: at large k, s ≈ q, so 2∫cos 3t + 2 = 2 sin(6)/3 + 2 (error O(1/k)).
            if k > 1.0 {
                let i_ref = 2.0 * (6.0f64).sin() / 3.0 + 2.0;
                assert!(
                    (integral[0] - i_ref).abs() < 10.0 / k + 1e-8,
                    "k {k}: {integral:?} vs {i_ref}"
                );
            }
            // Same work at 1e3 and 1e9.
            assert!(int.steps < 200, "k {k}: {} steps", int.steps);
        }
    }

    /// The deformation of a Dahl contact (`s_ss` = 1e-7 m at `k_t` = 1e8 N/m, or 1e-10 m at
    /// 1e11, `F_C` = 10 N) under a velocity drive of 1 mm/s along x with the support vibrating
    /// across it at 2 kHz, amplitude 0.2 µm (PaperTransverseGuided): `a = |v_r|/s_ss`,
    /// `q = s_ss·v_r/|v_r|`, observable `k_t·s`.
    struct Transverse {
        s_ss: f64,
    }
    impl Relaxing for Transverse {
        fn dim(&self) -> usize {
            2
        }
        fn sample(&self, t: f64) -> Sample {
            let omega = 2.0 * std::f64::consts::PI * 2000.0;
            let (vx, vy) = (1e-3, -omega * 2e-7 * (omega * t).cos());
            let n = (vx * vx + vy * vy).sqrt();
            Sample {
                a: n / self.s_ss,
                q: [self.s_ss * vx / n, self.s_ss * vy / n],
                c: 10.0 / self.s_ss,
                d: [0.0; 2],
            }
        }
    }

    /// One step's error estimate bounds its errors in `s` at the end and in the observable's
    /// integral, against classical Runge–Kutta on `ds/dt = a·(q − s)` (with the integral as a
    /// third state) at thousands of steps per step, for steps from 1/50 to 1/2 of the period
    /// starting along the period: `Λ` from 0.1 to 7 at `k_t` = 1e8 from a deformation off the
    /// target, 100 to 7000 at 1e11 from the target (the stiff contact's state).
    #[test]
    fn the_error_estimate_bounds_the_error_of_a_step() {
        for (s_ss, substeps, starts) in [(1e-7, 4000, 50), (1e-10, 40_000, 5)] {
            let sys = Transverse { s_ss };
            let scale_s = s_ss;
            let scale_f = 10.0;
            let rhs = |t: f64, y: [f64; 3]| {
                let p = sys.sample(t);
                [p.a * (p.q[0] - y[0]), p.a * (p.q[1] - y[1]), p.c * y[0]]
            };
            check_estimate(&sys, s_ss, scale_s, scale_f, substeps, starts, rhs);
        }
    }

    /// The tolerance of the steps checked (their quadratures of the transient follow it).
    const RTOL: f64 = 1e-9;

    fn check_estimate(
        sys: &Transverse,
        s_ss: f64,
        scale_s: f64,
        scale_f: f64,
        substeps: usize,
        starts: usize,
        rhs: impl Fn(f64, [f64; 3]) -> [f64; 3],
    ) {
        let (mut worst_s, mut worst_i, mut checked) = (0.0f64, 0.0f64, 0);
        for h in [
            1e-5, 2e-5, 3e-5, 5e-5, 7e-5, 1e-4, 1.25e-4, 1.6e-4, 2e-4, 2.5e-4,
        ] {
            for k in 0..starts {
                let t = k as f64 * 5e-4 / starts as f64;
                let ends = [sys.sample(t), sys.sample(t + h)];
                let s0 = if s_ss > 1e-9 {
                    [0.6 * s_ss, -0.4 * s_ss]
                } else {
                    ends[0].q
                };
                let out = step(sys, t, h, [&ends[0], &ends[1]], s0, scale_s, scale_f, RTOL);
                let n = substeps;
                let dt = h / n as f64;
                let mut y = [s0[0], s0[1], 0.0];
                for m in 0..n {
                    let tm = t + m as f64 * dt;
                    let k1 = rhs(tm, y);
                    let k2 = rhs(
                        tm + 0.5 * dt,
                        std::array::from_fn(|i| y[i] + 0.5 * dt * k1[i]),
                    );
                    let k3 = rhs(
                        tm + 0.5 * dt,
                        std::array::from_fn(|i| y[i] + 0.5 * dt * k2[i]),
                    );
                    let k4 = rhs(tm + dt, std::array::from_fn(|i| y[i] + dt * k3[i]));
                    for i in 0..3 {
                        y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                    }
                }
                // In units of the tolerance, as the estimate; above the reference's own error
                // (about 1e-12 of the scales).
                let e_s = (0..2)
                    .map(|i| (out.s[i] - y[i]).abs() / (RTOL * (scale_s + out.s[i].abs())))
                    .fold(0.0, f64::max);
                let e_i = (out.integral[0] - y[2]).abs() / (RTOL * scale_f * h);
                if e_s.max(e_i) > 1e-11 / RTOL {
                    checked += 1;
                    worst_s = worst_s.max(e_s / out.err);
                    worst_i = worst_i.max(e_i / out.err);
                }
            }
        }
        eprintln!(
            "s_ss {s_ss:e}: {checked} steps checked; error/estimate at most {worst_s:.2} (s), \
             {worst_i:.2} (integral)"
        );
        assert!(checked >= 5 * starts, "{checked}");
        assert!(worst_s <= 1.0 && worst_i <= 1.0, "{worst_s} {worst_i}");
    }
}
