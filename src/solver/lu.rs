//! LU factorisation with partial pivoting for small fixed-size matrices, real or complex.
//! (nalgebra's own LU needs type-level bounds that const-generic callers cannot state.)

use nalgebra::{ComplexField, SMatrix, SVector};

/// `P·A = L·U` stored in one matrix, with the row permutation.
#[derive(Clone, Copy, Debug)]
pub struct Lu<T, const N: usize> {
    lu: SMatrix<T, N, N>,
    perm: [usize; N],
    singular: bool,
}

impl<T: ComplexField<RealField = f64> + Copy, const N: usize> Lu<T, N> {
    pub fn new(mut a: SMatrix<T, N, N>) -> Self {
        let mut perm = [0usize; N];
        let mut singular = false;
        for (k, p) in perm.iter_mut().enumerate() {
            // pivot: largest modulus in column k at or below the diagonal
            let mut piv = k;
            let mut best = a[(k, k)].modulus();
            for i in k + 1..N {
                let m = a[(i, k)].modulus();
                if m > best {
                    best = m;
                    piv = i;
                }
            }
            *p = piv;
            if piv != k {
                a.swap_rows(k, piv);
            }
            if best == 0.0 || !best.is_finite() {
                singular = true;
                continue;
            }
            let inv = T::one() / a[(k, k)];
            for i in k + 1..N {
                let l = a[(i, k)] * inv;
                a[(i, k)] = l;
                for j in k + 1..N {
                    let u = a[(k, j)];
                    a[(i, j)] -= l * u;
                }
            }
        }
        Lu {
            lu: a,
            perm,
            singular,
        }
    }

    /// Solves `A·x = b` in place; false when `A` is singular.
    pub fn solve_mut(&self, b: &mut SVector<T, N>) -> bool {
        if self.singular {
            return false;
        }
        for k in 0..N {
            b.swap_rows(k, self.perm[k]);
        }
        for i in 0..N {
            let mut s = b[i];
            for j in 0..i {
                s -= self.lu[(i, j)] * b[j];
            }
            b[i] = s;
        }
        for i in (0..N).rev() {
            let mut s = b[i];
            for j in i + 1..N {
                s -= self.lu[(i, j)] * b[j];
            }
            b[i] = s / self.lu[(i, i)];
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Complex, Matrix3, Vector3};

    #[test]
    fn solves_real_and_complex_systems() {
        let a = Matrix3::new(0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0);
        let x = Vector3::new(1.0, -2.0, 0.5);
        let mut b = a * x;
        assert!(Lu::new(a).solve_mut(&mut b));
        assert!((b - x).norm() < 1e-14);

        let ac = a.map(|v| Complex::new(v, 0.5 * v));
        let xc = x.map(|v| Complex::new(v, -v));
        let mut bc = ac * xc;
        assert!(Lu::new(ac).solve_mut(&mut bc));
        assert!((bc - xc).norm() < 1e-14);
    }
}
