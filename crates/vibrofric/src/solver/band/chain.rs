//! The Newton matrices of a chain of bodies solved on the chain's own structure. Each body is a
//! block `[x, v, s]` (position, velocity, an internal state such as a contact's deformation):
//! `dx/dt` depends on `v` alone, `ds/dt` on the body's own `v` and `s`, and `dv/dt` on the
//! body's `x`, `v`, `s` and its neighbours' `x` and `v` (springs and dampers between bodies).
//! In `(γ·I − J)·z = r` the positions and internal states then follow from the body's own
//! velocity,
//!
//! ```text
//! x_i = (r_x,i + J_xv,i·v_i)/γ,     s_i = (r_s,i + J_sv,i·v_i)/(γ − J_ss,i),
//! ```
//!
//! and the velocities solve a tridiagonal system (their rows with `x` and `s` substituted),
//! eliminated without pivoting (Thomas). So a factorisation costs a few operations per body
//! instead of the band LU's `3·kl·(kl + ku)`. Where a pivot of that elimination is small against
//! its row (no diagonal dominance), [`ChainLu::factor`] says so and the caller factors the band
//! with pivoting instead.

use super::lu::Band;
use crate::solver::lu::LuScalar;

/// Components per body.
const B: usize = 3;

/// A pivot below this fraction of its row's magnitude is refused (the band LU pivots instead).
const PIVOT_FLOOR: f64 = 1e-8;

/// What the factorisation keeps per body: the substitutions of `x` and `s`, the coefficients of
/// the right-hand side's reduction, and the tridiagonal elimination's.
#[derive(Clone, Copy, Debug, Default)]
struct Body<T> {
    /// `J_xv/γ`: `x = r_x/γ + xv·v`.
    xv: T,
    /// `1/(γ − J_ss)`.
    inv_ss: T,
    /// `J_sv/(γ − J_ss)`: `s = inv_ss·r_s + sv·v`.
    sv: T,
    /// `J_vx` towards the previous body, this one and the next, over `γ`.
    px: [T; 3],
    /// `J_vs/(γ − J_ss)`.
    ps: T,
    /// The sub-diagonal of the tridiagonal system.
    lower: T,
    /// The eliminated super-diagonal.
    upper: T,
    /// `1/` the eliminated diagonal.
    inv_pivot: T,
}

/// The factors of `γ·I − J` for a chain-structured Jacobian `J` (see the module's comment).
#[derive(Clone, Debug)]
pub struct ChainLu<T> {
    inv_gamma: T,
    bodies: Vec<Body<T>>,
}

impl<T: LuScalar + Default> ChainLu<T> {
    /// Space for a chain of `n` components (`n/3` bodies).
    pub fn zeros(n: usize) -> Self {
        ChainLu {
            inv_gamma: T::default(),
            bodies: vec![Body::default(); n / B],
        }
    }

    /// Factors `γ·I − jac`; `false` (and nothing usable) where a pivot is not finite or is small
    /// against its row, for the caller to factor the band with pivoting instead.
    pub fn factor(&mut self, jac: &Band<f64>, gamma: T) -> bool {
        let nb = self.bodies.len();
        let one = T::from_real(1.0);
        let inv_g = one / gamma;
        self.inv_gamma = inv_g;
        // The substitutions first: the rows of v need the neighbours' `xv`.
        for (i, b) in self.bodies.iter_mut().enumerate() {
            let k = B * i;
            b.xv = T::from_real(jac.get(k, k + 1)) * inv_g;
            b.inv_ss = one / (gamma - T::from_real(jac.get(k + 2, k + 2)));
            b.sv = T::from_real(jac.get(k + 2, k + 1)) * b.inv_ss;
        }
        let mut upper_prev = T::default();
        for i in 0..nb {
            let (k, r) = (B * i, B * i + 1);
            let a = |j: usize| T::from_real(jac.get(r, j));
            let (a_x, a_v, a_s) = (a(k), a(k + 1), a(k + 2));
            let xv = self.bodies[i].xv;
            let mut diag = gamma - a_v - a_x * xv - a_s * self.bodies[i].sv;
            let mut mag = diag.mag();
            let (mut lower, mut upper) = (T::default(), T::default());
            let (mut px_prev, mut px_next) = (T::default(), T::default());
            if i > 0 {
                let (ax, av) = (a(k - B), a(k - B + 1));
                lower = T::default() - av - ax * self.bodies[i - 1].xv;
                px_prev = ax * inv_g;
                mag += lower.mag();
            }
            if i + 1 < nb {
                let (ax, av) = (a(k + B), a(k + B + 1));
                upper = T::default() - av - ax * self.bodies[i + 1].xv;
                px_next = ax * inv_g;
                mag += upper.mag();
            }
            // Thomas: the diagonal less the lower times the previous eliminated upper.
            diag = diag - lower * upper_prev;
            let pivot = diag.mag();
            if !(pivot.is_finite() && pivot > PIVOT_FLOOR * mag) {
                return false;
            }
            let inv_pivot = one / diag;
            let b = &mut self.bodies[i];
            b.px = [px_prev, a_x * inv_g, px_next];
            b.ps = a_s * b.inv_ss;
            b.lower = lower;
            b.upper = upper * inv_pivot;
            b.inv_pivot = inv_pivot;
            upper_prev = b.upper;
        }
        true
    }

    /// Solves `(γ·I − J)·z = r` in place with the factors of the last successful
    /// [`ChainLu::factor`].
    pub fn solve(&self, r: &mut [T]) {
        let nb = self.bodies.len();
        debug_assert_eq!(r.len(), B * nb);
        let g = self.inv_gamma;
        // The reduced right-hand sides, eliminated forwards, into the velocities' slots.
        let mut prev = T::default();
        for i in 0..nb {
            let b = &self.bodies[i];
            let k = B * i;
            let mut rv = r[k + 1] + b.px[1] * r[k] + b.ps * r[k + 2];
            if i > 0 {
                rv = rv + b.px[0] * r[k - B];
            }
            if i + 1 < nb {
                rv = rv + b.px[2] * r[k + B];
            }
            prev = (rv - b.lower * prev) * b.inv_pivot;
            r[k + 1] = prev;
        }
        // Backwards: each velocity, then its body's position and internal state.
        let mut next = T::default();
        for i in (0..nb).rev() {
            let b = &self.bodies[i];
            let k = B * i;
            let v = r[k + 1] - b.upper * next;
            r[k + 1] = v;
            r[k] = r[k] * g + b.xv * v;
            r[k + 2] = r[k + 2] * b.inv_ss + b.sv * v;
            next = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Complex, DMatrix, DVector};

    /// A chain-structured Jacobian of `nb` bodies with pseudo-random entries where the structure
    /// allows them (`dx/dt = v`), and the same as a dense matrix.
    fn sample(nb: usize) -> (Band<f64>, DMatrix<f64>) {
        let n = B * nb;
        let mut band = Band::zeros(n, 4, 3);
        let mut dense = DMatrix::zeros(n, n);
        let mut seed = 2024u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let mut put = |i: usize, j: usize, v: f64| {
            band.set(i, j, v);
            dense[(i, j)] = v;
        };
        for i in 0..nb {
            let k = B * i;
            put(k, k + 1, 1.0);
            put(k + 2, k + 1, 3.0 * next());
            put(k + 2, k + 2, -5.0 * next().abs());
            for j in [k, k + 1, k + 2] {
                put(k + 1, j, 40.0 * next());
            }
            if i > 0 {
                put(k + 1, k - B, 10.0 * next());
                put(k + 1, k - B + 1, 10.0 * next());
            }
            if i + 1 < nb {
                put(k + 1, k + B, 10.0 * next());
                put(k + 1, k + B + 1, 10.0 * next());
            }
        }
        (band, dense)
    }

    #[test]
    fn solves_a_real_shifted_chain_as_a_dense_solve_does() {
        for nb in [1, 2, 7, 40] {
            let (band, dense) = sample(nb);
            let n = B * nb;
            let gamma = 60.0;
            let mut lu = ChainLu::zeros(n);
            assert!(lu.factor(&band, gamma), "{nb} bodies refused");
            let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin() + 1.0).collect();
            let mut z = rhs.clone();
            lu.solve(&mut z);
            let a = DMatrix::identity(n, n) * gamma - &dense;
            let r = a * DVector::from_vec(z) - DVector::from_vec(rhs);
            assert!(r.amax() < 1e-12, "{nb} bodies: residual {}", r.amax());
        }
    }

    #[test]
    fn solves_a_complex_shifted_chain_as_a_dense_solve_does() {
        let nb = 25;
        let (band, dense) = sample(nb);
        let n = B * nb;
        let gamma = Complex::new(45.0, -30.0);
        let mut lu = ChainLu::zeros(n);
        assert!(lu.factor(&band, gamma));
        let rhs: Vec<Complex<f64>> = (0..n)
            .map(|i| Complex::new(i as f64, 1.0 - i as f64 * 0.1))
            .collect();
        let mut z = rhs.clone();
        lu.solve(&mut z);
        let a = DMatrix::identity(n, n) * gamma - dense.map(|v| Complex::new(v, 0.0));
        let r = a * DVector::from_vec(z) - DVector::from_vec(rhs);
        let worst = r.iter().map(|v| v.norm()).fold(0.0, f64::max);
        assert!(worst < 1e-11, "residual {worst}");
    }

    #[test]
    fn a_vanishing_pivot_is_refused() {
        // One body whose velocity row is γ − a_v − a_x·J_xv/γ − ... = 0: γ·I − J singular.
        let mut band = Band::zeros(3, 4, 3);
        band.set(0, 1, 1.0);
        band.set(1, 1, 2.0); // a_v = γ: the diagonal vanishes
        let mut lu = ChainLu::zeros(3);
        assert!(!lu.factor(&band, 2.0));
    }
}
