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

impl<T: LuScalar + Default + std::ops::Neg<Output = T>> BandLu<T> {
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

    /// Factors the matrix in place (Gaussian elimination with partial pivoting by columns).
    pub fn factor(&mut self) {
        let (n, kl, ku) = (self.m.n, self.m.kl, self.m.ku);
        let ld = self.m.ld;
        // The fill-in rows (the kl topmost of each column) start at zero.
        for j in 0..n {
            for r in 0..kl {
                self.m.a[j * ld + r] = T::default();
            }
        }
        self.singular = false;
        // Last column touched by the row interchanges so far.
        let mut ju = 0usize;
        for k in 0..n {
            let lm = kl.min(n - 1 - k);
            let mut p = k;
            let mut best = self.m.get(k, k).mag();
            for i in k + 1..=k + lm {
                let v = self.m.get(i, k).mag();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            self.pivot[k] = p;
            if best == 0.0 || !best.is_finite() {
                self.singular = true;
                return;
            }
            if p != k {
                let (ip, ik) = (self.m.idx(p, k), self.m.idx(k, k));
                self.m.a.swap(ip, ik);
            }
            // Multipliers, negated: L's column k.
            let inv = T::default() - self.m.get(k, k);
            for i in k + 1..=k + lm {
                let ix = self.m.idx(i, k);
                self.m.a[ix] = self.m.a[ix] / inv;
            }
            ju = ju.max((p + ku).min(n - 1));
            for j in k + 1..=ju {
                let (ip, ik) = (self.m.idx(p, j), self.m.idx(k, j));
                let t = self.m.a[ip];
                if p != k {
                    self.m.a[ip] = self.m.a[ik];
                    self.m.a[ik] = t;
                }
                for i in k + 1..=k + lm {
                    let (ij, ikk) = (self.m.idx(i, j), self.m.idx(i, k));
                    self.m.a[ij] = self.m.a[ij] + t * self.m.a[ikk];
                }
            }
        }
    }

    /// Solves `A·x = b` in place with the factors.
    pub fn solve(&self, b: &mut [T]) {
        let (n, kl, ku) = (self.m.n, self.m.kl, self.m.ku);
        debug_assert_eq!(b.len(), n);
        for k in 0..n {
            let lm = kl.min(n - 1 - k);
            let p = self.pivot[k];
            let t = b[p];
            if p != k {
                b[p] = b[k];
                b[k] = t;
            }
            for i in k + 1..=k + lm {
                b[i] = b[i] + t * self.m.a[self.m.idx(i, k)];
            }
        }
        for k in (0..n).rev() {
            b[k] = b[k] / self.m.a[self.m.idx(k, k)];
            let t = -b[k];
            for i in k.saturating_sub(kl + ku)..k {
                b[i] = b[i] + t * self.m.a[self.m.idx(i, k)];
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
