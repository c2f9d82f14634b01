//! Chebyshev series of a smooth function on an interval: fitted once from samples at the
//! Chebyshev points, then evaluated by Clenshaw's recurrence (a few flops per term) and
//! integrated term by term. Used for the shapes of a law that have no closed form (Dupont's
//! deformation along a branch, `elastoplastic.rs`).
//!
//! The fit samples `f` at the `n` points of the first kind `x_j = cos(π(j + 1/2)/n)` (mapped to
//! the interval; never its ends), takes the coefficients by the discrete cosine sum, and
//! doubles `n` until the last quarter of the coefficients is below a relative `1e-14`, the
//! series then truncated after its last coefficient above twice the rounding unit. An analytic function is
//! resolved to the rounding of its samples; one with a singularity close to the interval needs
//! more terms than the limit and is refused.

use std::f64::consts::PI;

/// `f(x) = Σ c_k·T_k(t)` on `[a, b]`, `t = (2x − a − b)/(b − a)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Chebyshev {
    a: f64,
    b: f64,
    c: Vec<f64>,
}

/// Relative size of the last quarter of the coefficients at which a fit has converged: the
/// coefficients of an analytic function fall geometrically to the rounding of the samples
/// (a few `1e-16` of the largest) and stay there.
const CONVERGED: f64 = 1e-14;

/// Relative size below which a converged series' trailing coefficients are dropped.
const NEGLIGIBLE: f64 = 2.0 * f64::EPSILON;

impl Chebyshev {
    /// The series of `f` on `[a, b]` with at most `max_terms` terms, or `None` where it needs
    /// more (or `f` is not finite at a sample).
    pub fn fit(f: impl Fn(f64) -> f64, a: f64, b: f64, max_terms: usize) -> Option<Self> {
        if a.partial_cmp(&b) != Some(std::cmp::Ordering::Less) {
            return None;
        }
        let mut n = 16;
        while n <= max_terms {
            let samples: Vec<f64> = (0..n)
                .map(|j| {
                    let t = libm::cos(PI * (j as f64 + 0.5) / n as f64);
                    f(0.5 * (a + b) + 0.5 * (b - a) * t)
                })
                .collect();
            if !samples.iter().all(|y| y.is_finite()) {
                return None;
            }
            // cos(π·k·(j + 1/2)/n) = cos(π·m/(2n)) with m = k·(2j + 1) mod 4n.
            let cos: Vec<f64> = (0..4 * n)
                .map(|m| libm::cos(PI * m as f64 / (2 * n) as f64))
                .collect();
            let c: Vec<f64> = (0..n)
                .map(|k| {
                    let sum: f64 = samples
                        .iter()
                        .enumerate()
                        .map(|(j, y)| y * cos[k * (2 * j + 1) % (4 * n)])
                        .sum();
                    sum * if k == 0 { 1.0 } else { 2.0 } / n as f64
                })
                .collect();
            let largest = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let largest = largest.max(f64::MIN_POSITIVE);
            let floor = NEGLIGIBLE * largest;
            if c[3 * n / 4..]
                .iter()
                .all(|x| x.abs() <= CONVERGED * largest)
            {
                let len = c.iter().rposition(|x| x.abs() > floor).map_or(1, |i| i + 1);
                return Some(Chebyshev {
                    a,
                    b,
                    c: c[..len].to_vec(),
                });
            }
            n *= 2;
        }
        None
    }

    /// The number of terms.
    #[cfg(test)]
    pub fn terms(&self) -> usize {
        self.c.len()
    }

    /// The value at `x` (Clenshaw's recurrence; `x` outside `[a, b]` extrapolates).
    #[inline]
    pub fn at(&self, x: f64) -> f64 {
        let t = (2.0 * x - self.a - self.b) / (self.b - self.a);
        let (mut b1, mut b2) = (0.0, 0.0);
        for &ck in self.c[1..].iter().rev() {
            (b1, b2) = (2.0 * t * b1 - b2 + ck, b1);
        }
        t * b1 - b2 + self.c[0]
    }

    /// The antiderivative that vanishes at `a`: `∫_a^x f`.
    pub fn integral(&self) -> Chebyshev {
        let n = self.c.len();
        let half = 0.5 * (self.b - self.a);
        let at = |k: usize| self.c.get(k).copied().unwrap_or(0.0);
        // ∫T_0 = T_1, ∫T_1 = T_2/4, ∫T_k = T_{k+1}/(2(k+1)) − T_{k−1}/(2(k−1)) for k ≥ 2.
        let mut c = vec![0.0; n + 1];
        for (j, cj) in c.iter_mut().enumerate().skip(1) {
            let below = if j == 1 { 2.0 * at(0) } else { at(j - 1) };
            *cj = half * (below - at(j + 1)) / (2 * j) as f64;
        }
        // T_j(−1) = (−1)^j: the constant that makes the value at a zero.
        c[0] = -c
            .iter()
            .enumerate()
            .skip(1)
            .map(|(j, cj)| if j % 2 == 0 { *cj } else { -cj })
            .sum::<f64>();
        Chebyshev {
            a: self.a,
            b: self.b,
            c,
        }
    }
}

/// A function on `[a, b]` as Chebyshev series on `K` equal pieces: a few terms each where one
/// series would need many, so that a value costs a short recurrence.
#[derive(Clone, Debug, PartialEq)]
pub struct Piecewise {
    a: f64,
    /// Pieces per unit of `x`.
    density: f64,
    pieces: Vec<Chebyshev>,
}

impl Piecewise {
    /// The series of `f` on `pieces` equal pieces of `[a, b]`, each with at most `max_terms`
    /// terms (`None` where one needs more).
    pub fn fit(
        f: impl Fn(f64) -> f64,
        a: f64,
        b: f64,
        pieces: usize,
        max_terms: usize,
    ) -> Option<Self> {
        let width = (b - a) / pieces as f64;
        let pieces = (0..pieces)
            .map(|i| {
                let lo = a + i as f64 * width;
                let hi = if i + 1 == pieces { b } else { lo + width };
                Chebyshev::fit(&f, lo, hi, max_terms)
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Piecewise {
            a,
            density: 1.0 / width,
            pieces,
        })
    }

    /// The value at `x` (outside `[a, b]`, the end piece extrapolates).
    #[inline]
    pub fn at(&self, x: f64) -> f64 {
        // `as` saturates: below a, piece 0.
        let i = (((x - self.a) * self.density) as usize).min(self.pieces.len() - 1);
        self.pieces[i].at(x)
    }

    /// The most terms of a piece.
    #[cfg(test)]
    pub fn terms(&self) -> usize {
        self.pieces.iter().map(Chebyshev::terms).max().unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::Chebyshev;

    /// Fits, values and antiderivatives against closed forms.
    #[test]
    fn fits_and_integrates_analytic_functions_to_rounding() {
        let f = |x: f64| libm::exp(-x) * libm::sin(3.0 * x) + 1.0 / (2.0 + x);
        let antiderivative = |x: f64| {
            // ∫ e^{−x} sin 3x dx = −e^{−x}(sin 3x + 3 cos 3x)/10; ∫ 1/(2+x) = ln(2+x).
            -libm::exp(-x) * (libm::sin(3.0 * x) + 3.0 * libm::cos(3.0 * x)) / 10.0
                + libm::log(2.0 + x)
        };
        let (a, b) = (-0.5, 2.0);
        let cheb = Chebyshev::fit(f, a, b, 256).expect("an analytic function fits");
        assert!(cheb.terms() < 64, "{} terms", cheb.terms());
        let int = cheb.integral();
        for i in 0..=1000 {
            let x = a + (b - a) * i as f64 / 1000.0;
            assert!(
                (cheb.at(x) - f(x)).abs() < 2e-15,
                "f at {x}: {}",
                cheb.at(x) - f(x)
            );
            let exact = antiderivative(x) - antiderivative(a);
            assert!(
                (int.at(x) - exact).abs() < 2e-15,
                "∫f at {x}: {}",
                int.at(x) - exact
            );
        }
    }

    /// A piecewise fit of a function with a pole near its interval: few terms a piece.
    #[test]
    fn piecewise_fit_resolves_a_nearby_pole_with_short_pieces() {
        let f = |x: f64| 1.0 / (x + 0.05);
        let pw = super::Piecewise::fit(f, 0.0, 1.0, 8, 256).expect("fits");
        for i in 0..=1000 {
            let x = i as f64 / 1000.0;
            assert!(((pw.at(x) - f(x)) / f(x)).abs() < 4e-15, "at {x}");
        }
        assert!(pw.terms() <= 32, "{} terms", pw.terms());
    }

    /// A pole close to the interval needs more terms than allowed: refused, not wrong.
    #[test]
    fn refuses_a_function_it_cannot_resolve() {
        let f = |x: f64| 1.0 / (x + 1e-4);
        assert!(Chebyshev::fit(f, 0.0, 1.0, 128).is_none());
        assert!(Chebyshev::fit(|x| if x > 0.5 { f64::NAN } else { x }, 0.0, 1.0, 128).is_none());
    }
}
