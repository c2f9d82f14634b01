//! LU factorisation with partial pivoting of a small dense matrix held on the stack (at most
//! [`MAX`] rows): the Newton matrix `I − h·(A ⊗ J)` of the Radau stages (3N ≤ 18) and the error
//! estimator's `N×N` matrix. No heap allocation.

/// Largest matrix order.
pub const MAX: usize = 18;

#[derive(Clone, Copy, Debug)]
pub struct DenseLu {
    a: [[f64; MAX]; MAX],
    perm: [usize; MAX],
    n: usize,
    singular: bool,
}

impl DenseLu {
    pub fn zeros(n: usize) -> Self {
        assert!(n <= MAX);
        DenseLu {
            a: [[0.0; MAX]; MAX],
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
    #[inline(always)]
    pub fn factor(&mut self) {
        let n = self.n;
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
                self.a.swap(k, piv);
            }
            if best == 0.0 || !best.is_finite() {
                self.singular = true;
                return;
            }
            let inv = 1.0 / self.a[k][k];
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
            b[i] = (b[i] - s) / self.a[i][i];
        }
        b.iter().all(|v| v.is_finite())
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
        lu.factor();
        assert!(lu.solve(&mut b));
        for i in 0..3 {
            assert!((b[i] - x[i]).abs() < 1e-14);
        }
    }

    #[test]
    fn reports_singular() {
        let mut lu = DenseLu::zeros(2);
        lu.set(0, 0, 1.0);
        lu.set(0, 1, 2.0);
        lu.set(1, 0, 2.0);
        lu.set(1, 1, 4.0);
        lu.factor();
        assert!(!lu.solve(&mut [1.0, 1.0]));
    }
}
