//! Banded matrices and their LU factorisation with partial pivoting (LINPACK's `dgbfa`/`dgbsl`
//! layout and algorithm): the Newton matrices of a chain of bodies, whose every row couples a
//! body only to its neighbours. Factoring an `n×n` matrix with `kl` sub- and `ku` super-diagonals
//! costs `O(n·kl·(kl + ku))`, solving `O(n·(2·kl + ku))`: linear in the length of the chain.

use crate::solver::lu::LuScalar;

/// An `n×n` band matrix with `kl` sub-diagonals and `ku` super-diagonals, stored by columns with
/// `kl` extra rows above for the fill-in of row interchanges: entry `(i, j)`, for
/// `j − ku ≤ i ≤ j + kl`, at `j·ld + kl + ku + i − j`, `ld = 2·kl + ku + 1`.
#[derive(Clone, Debug)]
pub struct Band<T> {
    n: usize,
    kl: usize,
    ku: usize,
    ld: usize,
    a: Vec<T>,
}

impl<T: LuScalar + Default> Band<T> {
    pub fn zeros(n: usize, kl: usize, ku: usize) -> Self {
        let ld = 2 * kl + ku + 1;
        Band {
            n,
            kl,
            ku,
            ld,
            a: vec![T::default(); ld * n],
        }
    }

    pub fn n(&self) -> usize {
        self.n
    }

    /// The sub- and super-diagonals `(kl, ku)`.
    pub fn bands(&self) -> (usize, usize) {
        (self.kl, self.ku)
    }

    /// Whether `(i, j)` lies inside the band.
    #[inline(always)]
    pub fn inside(&self, i: usize, j: usize) -> bool {
        i < self.n && j < self.n && i + self.ku >= j && j + self.kl >= i
    }

    #[inline(always)]
    fn idx(&self, i: usize, j: usize) -> usize {
        j * self.ld + self.kl + self.ku + i - j
    }

    /// Entry `(i, j)`; zero outside the band.
    #[inline(always)]
    pub fn get(&self, i: usize, j: usize) -> T {
        if self.inside(i, j) {
            self.a[self.idx(i, j)]
        } else {
            T::default()
        }
    }

    /// Sets entry `(i, j)`, which must lie inside the band.
    #[inline(always)]
    pub fn set(&mut self, i: usize, j: usize, v: T) {
        debug_assert!(self.inside(i, j), "({i}, {j}) outside the band");
        let k = self.idx(i, j);
        self.a[k] = v;
    }

    /// Every entry (and the fill-in rows) to zero.
    pub fn clear(&mut self) {
        self.a.fill(T::default());
    }
}

/// The factors `P·A = L·U` of a [`Band`] matrix, in its own storage.
#[derive(Clone, Debug)]
pub struct BandLu<T> {
    m: Band<T>,
    pivot: Vec<usize>,
    singular: bool,
}

impl<T: LuScalar + Default> BandLu<T> {
    pub fn zeros(n: usize, kl: usize, ku: usize) -> Self {
        BandLu {
            m: Band::zeros(n, kl, ku),
            pivot: vec![0; n],
            singular: false,
        }
    }

    /// The matrix to fill before [`BandLu::factor`] (its fill-in rows are cleared there).
    pub fn matrix(&mut self) -> &mut Band<T> {
        &mut self.m
    }

    /// Whether the last factorisation met a zero or non-finite pivot.
    pub fn singular(&self) -> bool {
        self.singular
    }

    /// Factors the matrix in place (Gaussian elimination with partial pivoting by columns, on
    /// contiguous slices of the column storage).
    pub fn factor(&mut self) {
        let (n, kl, ku, ld) = (self.m.n, self.m.kl, self.m.ku, self.m.ld);
        // Row of the diagonal in each column's storage.
        let d = kl + ku;
        let a = &mut self.m.a;
        // The fill-in rows (the kl topmost of each column) start at zero.
        for col in a.chunks_exact_mut(ld) {
            col[..kl].fill(T::default());
        }
        self.singular = false;
        // Last column touched by the row interchanges so far.
        let mut ju = 0usize;
        for k in 0..n {
            let lm = kl.min(n - 1 - k);
            let ck = k * ld + d;
            let (mut l, mut best) = (0, a[ck].mag());
            for q in 1..=lm {
                let v = a[ck + q].mag();
                if v > best {
                    best = v;
                    l = q;
                }
            }
            let p = k + l;
            self.pivot[k] = p;
            if best == 0.0 || !best.is_finite() {
                self.singular = true;
                return;
            }
            a.swap(ck + l, ck);
            // Multipliers, negated: L's column k.
            let inv = T::default() - a[ck];
            for v in &mut a[ck + 1..=ck + lm] {
                *v = *v / inv;
            }
            ju = ju.max((p + ku).min(n - 1));
            let (left, right) = a.split_at_mut((k + 1) * ld);
            let mult = &left[ck + 1..=ck + lm];
            for (jj, col) in right.chunks_exact_mut(ld).take(ju - k).enumerate() {
                // Column j = k + 1 + jj: entry (i, j) at row d + i − j of its storage.
                let top = d - 1 - jj; // row of (k, j)
                let t = col[top + l];
                if l != 0 {
                    col[top + l] = col[top];
                    col[top] = t;
                }
                for (x, &m) in col[top + 1..=top + lm].iter_mut().zip(mult) {
                    *x = *x + t * m;
                }
            }
        }
    }

    /// Solves `A·x = b` in place with the factors.
    pub fn solve(&self, b: &mut [T]) {
        let (n, kl, ku, ld) = (self.m.n, self.m.kl, self.m.ku, self.m.ld);
        let d = kl + ku;
        let a = &self.m.a;
        debug_assert_eq!(b.len(), n);
        for k in 0..n {
            let lm = kl.min(n - 1 - k);
            let p = self.pivot[k];
            let t = b[p];
            if p != k {
                b[p] = b[k];
                b[k] = t;
            }
            let ck = k * ld + d;
            for (x, &m) in b[k + 1..=k + lm].iter_mut().zip(&a[ck + 1..=ck + lm]) {
                *x = *x + t * m;
            }
        }
        for k in (0..n).rev() {
            let ck = k * ld + d;
            b[k] = b[k] / a[ck];
            let t = T::default() - b[k];
            let lo = k.saturating_sub(d);
            // Rows lo..k of column k, at storage rows d − (k − i).
            let col = &a[ck - (k - lo)..ck];
            for (x, &u) in b[lo..k].iter_mut().zip(col) {
                *x = *x + t * u;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Complex, DMatrix, DVector};

    /// A pseudo-random band matrix whose first pivots are small, so that rows must swap.
    fn sample(n: usize, kl: usize, ku: usize) -> (Band<f64>, DMatrix<f64>) {
        let mut b = Band::zeros(n, kl, ku);
        let mut d = DMatrix::zeros(n, n);
        let mut seed = 12345u64;
        for i in 0..n {
            for j in i.saturating_sub(kl)..(i + ku + 1).min(n) {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let v = ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5;
                let v = if i == j { 1e-3 * v } else { v };
                b.set(i, j, v);
                d[(i, j)] = v;
            }
        }
        (b, d)
    }

    #[test]
    fn solves_like_a_dense_factorisation_with_pivoting() {
        for &(n, kl, ku) in &[(1, 0, 0), (5, 1, 1), (12, 4, 3), (30, 2, 5), (7, 6, 6)] {
            let (band, dense) = sample(n, kl, ku);
            let mut lu = BandLu::zeros(n, kl, ku);
            for i in 0..n {
                for j in 0..n {
                    if band.inside(i, j) {
                        lu.matrix().set(i, j, band.get(i, j));
                    }
                }
            }
            lu.factor();
            assert!(!lu.singular());
            let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin() + 1.0).collect();
            let mut x = rhs.clone();
            lu.solve(&mut x);
            // The residual of the dense matrix, an independent product.
            let r = &dense * DVector::from_vec(x.clone()) - DVector::from_vec(rhs.clone());
            assert!(
                r.amax() < 1e-11,
                "n {n} kl {kl} ku {ku}: residual {}",
                r.amax()
            );
        }
    }

    #[test]
    fn solves_complex_systems() {
        let (n, kl, ku) = (20, 4, 3);
        let (band, dense) = sample(n, kl, ku);
        let shift = Complex::new(0.3, -2.0);
        let mut lu = BandLu::<Complex<f64>>::zeros(n, kl, ku);
        for i in 0..n {
            for j in 0..n {
                if band.inside(i, j) {
                    let d = if i == j { shift } else { Complex::ZERO };
                    lu.matrix().set(i, j, d + Complex::new(band.get(i, j), 0.0));
                }
            }
        }
        lu.factor();
        let rhs: Vec<Complex<f64>> = (0..n)
            .map(|i| Complex::new(i as f64, 1.0 - i as f64 * 0.1))
            .collect();
        let mut x = rhs.clone();
        lu.solve(&mut x);
        let a = dense.map(|v| Complex::new(v, 0.0)) + DMatrix::identity(n, n) * shift;
        let r = a * DVector::from_vec(x) - DVector::from_vec(rhs);
        let worst = r.iter().map(|v| v.norm()).fold(0.0, f64::max);
        assert!(worst < 1e-11, "residual {worst}");
    }

    #[test]
    fn a_zero_column_is_singular() {
        let mut lu = BandLu::<f64>::zeros(3, 1, 1);
        lu.matrix().set(0, 0, 1.0);
        lu.matrix().set(2, 2, 1.0);
        lu.factor();
        assert!(lu.singular());
    }
}
