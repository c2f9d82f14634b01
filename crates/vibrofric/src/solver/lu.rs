//! LU factorisation with partial pivoting of a small dense matrix held on the stack (at most
//! [`MAX`] rows): the Newton matrix `I − h·(A ⊗ J)` of the Radau stages (3N ≤ 18) and the error
//! estimator's `N×N` matrix. No heap allocation.

/// Largest matrix order.
pub const MAX: usize = 18;

#[derive(Clone, Copy, Debug)]
pub struct DenseLu {
    a: [[f64; MAX]; MAX],
    /// Reciprocals of U's diagonal: the solve multiplies instead of dividing.
    inv_diag: [f64; MAX],
    perm: [usize; MAX],
    n: usize,
    singular: bool,
}

impl DenseLu {
    pub fn zeros(n: usize) -> Self {
        assert!(n <= MAX);
        DenseLu {
            a: [[0.0; MAX]; MAX],
            inv_diag: [0.0; MAX],
            perm: [0; MAX],
            n,
            singular: false,
        }
    }

    #[inline(always)]
    pub fn set(&mut self, r: usize, c: usize, v: f64) {
        self.a[r][c] = v;
    }

    /// Factors in place: `P·A = L·U`. Every entry of the leading `n×n` block must have been
    /// set since the last factorisation (the matrix is reused without clearing).
    /// The order `n` (equal to the one given to [`DenseLu::zeros`]) is passed in, so that a
    /// caller who knows it at compile time gets unrolled loops.
    #[inline(always)]
    pub fn factor(&mut self, n: usize) {
        debug_assert_eq!(n, self.n);
        self.singular = false;
        for k in 0..n {
            let mut piv = k;
            let mut best = self.a[k][k].abs();
            for i in k + 1..n {
                let m = self.a[i][k].abs();
                if m > best {
                    best = m;
                    piv = i;
                }
            }
            self.perm[k] = piv;
            if piv != k {
                let (top, rest) = self.a.split_at_mut(piv);
                top[k][..n].swap_with_slice(&mut rest[0][..n]);
            }
            if best == 0.0 || !best.is_finite() {
                self.singular = true;
                return;
            }
            let inv = 1.0 / self.a[k][k];
            self.inv_diag[k] = inv;
            let (top, rest) = self.a.split_at_mut(k + 1);
            let pivot_row = &top[k];
            for row in rest.iter_mut().take(n - k - 1) {
                let l = row[k] * inv;
                row[k] = l;
                if l != 0.0 {
                    for j in k + 1..n {
                        row[j] -= l * pivot_row[j];
                    }
                }
            }
        }
    }

    /// Solves `A·x = b` in place (after [`DenseLu::factor`]); false when `A` is singular.
    #[inline(always)]
    pub fn solve(&self, b: &mut [f64]) -> bool {
        let n = self.n;
        if self.singular || b.len() != n {
            return false;
        }
        for k in 0..n {
            b.swap(k, self.perm[k]);
        }
        for i in 0..n {
            let s: f64 = (0..i).map(|j| self.a[i][j] * b[j]).sum();
            b[i] -= s;
        }
        for i in (0..n).rev() {
            let s: f64 = (i + 1..n).map(|j| self.a[i][j] * b[j]).sum();
            b[i] = (b[i] - s) * self.inv_diag[i];
        }
        b.iter().all(|v| v.is_finite())
    }
}

/// Entries a [`FixedLu`] can factor: real or complex numbers.
pub trait LuScalar:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
{
    /// A magnitude for choosing pivots (|re| + |im| for complex numbers).
    fn mag(self) -> f64;
    /// The real number `v`.
    fn from_real(v: f64) -> Self;
}

impl LuScalar for f64 {
    #[inline(always)]
    fn mag(self) -> f64 {
        self.abs()
    }
    #[inline(always)]
    fn from_real(v: f64) -> Self {
        v
    }
}

impl LuScalar for nalgebra::Complex<f64> {
    #[inline(always)]
    fn mag(self) -> f64 {
        self.re.abs() + self.im.abs()
    }
    #[inline(always)]
    fn from_real(v: f64) -> Self {
        nalgebra::Complex::new(v, 0.0)
    }
}

/// LU factorisation with partial pivoting of an `N×N` matrix whose order is known at compile
/// time (the split systems of the simplified Newton iteration and the error estimate).
#[derive(Clone, Copy, Debug)]
pub struct FixedLu<T: LuScalar, const N: usize> {
    a: [[T; N]; N],
    perm: [usize; N],
    singular: bool,
}

impl<T: LuScalar, const N: usize> FixedLu<T, N> {
    /// Factors `a` (row-major): `P·A = L·U`.
    #[inline(always)]
    pub fn new(mut a: [[T; N]; N]) -> Self {
        let mut perm = [0; N];
        for k in 0..N {
            let mut piv = k;
            let mut best = a[k][k].mag();
            for (i, row) in a.iter().enumerate().skip(k + 1) {
                let m = row[k].mag();
                if m > best {
                    best = m;
                    piv = i;
                }
            }
            perm[k] = piv;
            a.swap(k, piv);
            if best == 0.0 || !best.is_finite() {
                return FixedLu {
                    a,
                    perm,
                    singular: true,
                };
            }
            let pivot_row = a[k];
            for row in a.iter_mut().skip(k + 1) {
                let l = row[k] / pivot_row[k];
                row[k] = l;
                for j in k + 1..N {
                    row[j] = row[j] - l * pivot_row[j];
                }
            }
        }
        FixedLu {
            a,
            perm,
            singular: false,
        }
    }

    /// Solves `A·x = b` in place; false when `A` is singular or the result is not finite.
    #[inline(always)]
    pub fn solve(&self, b: &mut [T; N]) -> bool {
        if self.singular {
            return false;
        }
        for k in 0..N {
            b.swap(k, self.perm[k]);
        }
        for i in 0..N {
            for j in 0..i {
                b[i] = b[i] - self.a[i][j] * b[j];
            }
        }
        for i in (0..N).rev() {
            for j in i + 1..N {
                b[i] = b[i] - self.a[i][j] * b[j];
            }
            b[i] = b[i] / self.a[i][i];
        }
        b.iter().all(|v| v.mag().is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_pivoting_system() {
        let a = [[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]];
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| a[i][j] * x[j]).sum())
            .collect();
        let mut lu = DenseLu::zeros(3);
        for i in 0..3 {
            for j in 0..3 {
                lu.set(i, j, a[i][j]);
            }
        }
        lu.factor(lu.n);
        assert!(lu.solve(&mut b));
        for i in 0..3 {
            assert!((b[i] - x[i]).abs() < 1e-14);
        }
    }

    #[test]
    fn fixed_lu_solves_real_and_complex_systems() {
        use nalgebra::Complex;
        let a = [[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]];
        let x = [1.0, -2.0, 0.5];
        let mut b: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| a[i][j] * x[j]).sum());
        assert!(FixedLu::new(a).solve(&mut b));
        assert!((0..3).all(|i| (b[i] - x[i]).abs() < 1e-14));

        let c = |re, im| Complex::new(re, im);
        let a = [[c(0.0, 1.0), c(2.0, 0.0)], [c(1.0, -1.0), c(0.5, 3.0)]];
        let x = [c(1.0, 2.0), c(-0.5, 0.25)];
        let mut b: [Complex<f64>; 2] = std::array::from_fn(|i| a[i][0] * x[0] + a[i][1] * x[1]);
        assert!(FixedLu::new(a).solve(&mut b));
        assert!((0..2).all(|i| (b[i] - x[i]).norm() < 1e-14));
        assert!(!FixedLu::new([[1.0, 2.0], [2.0, 4.0]]).solve(&mut [1.0, 1.0]));
    }

    #[test]
    fn reports_singular() {
        let mut lu = DenseLu::zeros(2);
        lu.set(0, 0, 1.0);
        lu.set(0, 1, 2.0);
        lu.set(1, 0, 2.0);
        lu.set(1, 1, 4.0);
        lu.factor(lu.n);
        assert!(!lu.solve(&mut [1.0, 1.0]));
    }
}
