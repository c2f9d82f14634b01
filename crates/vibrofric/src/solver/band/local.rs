//! Newton's iteration of a few blocks alone, their neighbours' stage values held: where the
//! simplified Newton iteration of the whole chain has converged in all blocks but a few (a body
//! at a reversal of its contact, whose friction changes within the step), those blocks are
//! iterated on their own rows, at the cost of a block rather than of the chain, then their
//! neighbours outwards (Gauss–Seidel). Where that settles them (each converged alone, below the
//! Newton tolerance, the correction died out on either side before the budget, and at the end
//! each block of the set and each neighbour corrected, its neighbours now moved, needed no
//! correction), every block has
//! passed its own convergence test, each as strict as the whole system's, and the iteration
//! has converged; otherwise one more
//! iteration of the whole system follows, whose own test decides as before. Either way the
//! step's result is the collocation solution to the Newton tolerance. Accepting a settled
//! sweep instead of iterating the whole system once more: on a drill string of LuGre sections
//! (`examples/string_bench.rs`, tolerance 1e-6, 0.1 s) 1.6 % fewer instructions at 20
//! sections, 2.7 % at 100, the errors against `tests/string.rs`'s reference as before.
//!
//! A block's iteration is the whole system's restricted to its rows: the same transformed
//! residual `T⁻¹·F − (Λ/h)·W` on those rows, solved with the diagonal block of the step's
//! Jacobian (a real and a complex system of the block's size).

use nalgebra::Complex;

use super::lu::Band;
use super::radau::BandSystem;
use super::BandWork;
use crate::solver::radau::tableau::{ALPH, BETA, C, T, TI, U1};

/// The largest block iterated alone (a string's section has 3 components).
pub const MAX_BLOCK: usize = 4;
/// Iterations of a block alone at most (a drill string of 1000 sections took up to 12, most
/// blocks 1 or 2); beyond, the iteration of the whole system takes over.
const LOCAL_NIT: u32 = 12;
/// A block alone contracting slower than this is left to the iteration of the whole system.
const LOCAL_THETA: f64 = 0.9;
/// What a block alone is converged to, in units of the Newton tolerance: below it, so that the
/// whole system's iteration after the sweep finds it converged.
const LOCAL_GOAL: f64 = 0.3;
/// Neighbours corrected per block iterated alone at most (a reversal disturbs a few sections
/// on either side within a step).
const SPREAD: usize = 3;

/// Solves `(g·I − J_kk)·x = r` in place for the diagonal block `J_kk` (rows and columns
/// `at..at + b`) of `jac`, by Gaussian elimination with partial pivoting; `false` where
/// singular.
fn solve_block(
    jac: &Band<f64>,
    at: usize,
    b: usize,
    g: Complex<f64>,
    r: &mut [Complex<f64>; MAX_BLOCK],
) -> bool {
    let mut a = [[Complex::ZERO; MAX_BLOCK]; MAX_BLOCK];
    for (i, row) in a.iter_mut().enumerate().take(b) {
        for (j, e) in row.iter_mut().enumerate().take(b) {
            let v = Complex::new(-jac.get(at + i, at + j), 0.0);
            *e = if i == j { g + v } else { v };
        }
    }
    for c in 0..b {
        let p = (c..b)
            .max_by(|&x, &y| a[x][c].norm_sqr().total_cmp(&a[y][c].norm_sqr()))
            .unwrap_or(c);
        if a[p][c].norm_sqr() == 0.0 {
            return false;
        }
        a.swap(c, p);
        r.swap(c, p);
        for i in c + 1..b {
            let m = a[i][c] / a[c][c];
            for j in c..b {
                let d = m * a[c][j];
                a[i][j] -= d;
            }
            let d = m * r[c];
            r[i] -= d;
        }
    }
    for c in (0..b).rev() {
        let mut s = r[c];
        for j in c + 1..b {
            s -= a[c][j] * r[j];
        }
        r[c] = s / a[c][c];
    }
    true
}

impl BandWork {
    /// After an iteration of the whole system (its update still in `dw`, `dwc`) that has not
    /// converged, where at most [`BandSystem::max_local`] blocks fail their own test, iterates
    /// them alone ([`Self::local_sweep`]): `None` where it did not, else whether that settled
    /// them.
    pub(super) fn sweep_unconverged<S: BandSystem>(
        &mut self,
        sys: &S,
        step: (f64, f64, &[f64]),
        (fnewt, faccon): (f64, f64),
    ) -> Option<bool> {
        if !self.few_unconverged(sys.block(), sys.max_local(), fnewt, faccon) {
            return None;
        }
        Some(self.local_sweep(sys, step, (fnewt, faccon)))
    }

    /// Whether, after an iteration of the whole system (its update still in `dw`, `dwc`), at
    /// least one and at most `most` blocks of `b` components fail their own convergence test
    /// (their scaled update's RMS times `faccon` above `fnewt`): those blocks into `local`.
    fn few_unconverged(&mut self, b: usize, most: usize, fnewt: f64, faccon: f64) -> bool {
        self.local.clear();
        if b == 0 || b > MAX_BLOCK || most == 0 {
            return false;
        }
        let limit = (fnewt / faccon).powi(2) * (3 * b) as f64;
        let n = self.scal.len();
        let (dwr, dwc, scal) = (&self.dw[..n], &self.dwc[..n], &self.scal[..n]);
        for (k, ((dr, dc), sc)) in dwr
            .chunks(b)
            .zip(dwc.chunks(b))
            .zip(scal.chunks(b))
            .enumerate()
        {
            let mut sum = 0.0;
            for ((r, c), s) in dr.iter().zip(dc).zip(sc) {
                let dw = [*r, c.re, c.im];
                for t in T {
                    let q = (t[0] * dw[0] + t[1] * dw[1] + t[2] * dw[2]) / s;
                    sum += q * q;
                }
            }
            if sum > limit {
                if self.local.len() == most {
                    self.local.clear();
                    return false;
                }
                self.local.push(k);
            }
        }
        !self.local.is_empty()
    }

    /// Iterates the blocks in `local` alone, then their neighbours outwards while a
    /// neighbour's first update is not negligible (at most [`SPREAD`] per block in `local`),
    /// from the stage increments `z` of the step `(t, h)` from `y`; `faccon` is the whole
    /// system's contraction factor, `fnewt` its Newton tolerance. Blocks that do not contract
    /// alone are left as they were. Whether the sweep settled them: every block converged
    /// alone, the walk from it ended either way on a neighbour that needed no correction, at an
    /// end of the chain or at another block of the set (not on the budget), and then every
    /// block of the set and every neighbour a walk corrected needed no correction.
    fn local_sweep<S: BandSystem>(
        &mut self,
        sys: &S,
        step: (f64, f64, &[f64]),
        (fnewt, faccon): (f64, f64),
    ) -> bool {
        let y = step.2;
        let mut settled = true;
        for k in 0..3 {
            for ((s, y), z) in self.stages[k].iter_mut().zip(y).zip(&self.z[k]) {
                *s = y + z;
            }
        }
        let goal = (LOCAL_GOAL * fnewt, faccon);
        let blocks = std::mem::take(&mut self.local);
        let n = self.scal.len() / sys.block();
        let mut budget = SPREAD * blocks.len();
        // The neighbours a walk corrected: each converged against the next one's old values.
        let mut moved = Vec::new();
        for &k in &blocks {
            if self.local_newton(sys, step, k, goal).is_none() {
                settled = false;
                continue;
            }
            // Left, then right: until a neighbour needs no correction, is in the set, does
            // not contract alone or the budget is spent.
            for dir in [-1isize, 1] {
                let mut j = k as isize + dir;
                while (0..n as isize).contains(&j) && !blocks.contains(&(j as usize)) {
                    if budget == 0 {
                        settled = false;
                        break;
                    }
                    budget -= 1;
                    match self.local_newton(sys, step, j as usize, goal) {
                        Some(first) if faccon * first > goal.0 => {
                            moved.push(j as usize);
                            j += dir;
                        }
                        Some(_) => break,
                        None => {
                            settled = false;
                            break;
                        }
                    }
                }
            }
        }
        // A block of the set, or a neighbour a walk corrected, was iterated against its
        // neighbours' values before the walks moved them: settled where it now needs no
        // correction.
        if settled {
            settled = blocks.iter().chain(&moved).all(|&k| {
                self.local_newton(sys, step, k, goal)
                    .is_some_and(|first| faccon * first <= goal.0)
            });
        }
        self.local = blocks;
        settled
    }

    /// Iterates block `k` alone (its neighbours' stages held in `stages`) until its own
    /// scaled update times its contraction factor (the whole system's `faccon` in the first
    /// iteration) is below `goal`: the first update's norm, or `None` (the block left as it
    /// was) where it does not contract.
    fn local_newton<S: BandSystem>(
        &mut self,
        sys: &S,
        (t, h, y): (f64, f64, &[f64]),
        k: usize,
        (goal, faccon): (f64, f64),
    ) -> Option<f64> {
        let b = sys.block();
        let at = k * b;
        let mut saved = [[0.0; MAX_BLOCK]; 3];
        for (s, z) in saved.iter_mut().zip(&self.z) {
            s[..b].copy_from_slice(&z[at..at + b]);
        }
        let (u1, alph, beta) = (U1 / h, ALPH / h, BETA / h);
        let (mut old, mut first) = (0.0, 0.0);
        for it in 0..LOCAL_NIT {
            let mut f = [[0.0; MAX_BLOCK]; 3];
            for (s, fs) in f.iter_mut().enumerate() {
                sys.rhs_block(t + C[s] * h, &self.stages[s], k, &mut fs[..b]);
            }
            if !f.iter().all(|fs| fs[..b].iter().all(|v| v.is_finite())) {
                break;
            }
            // As the whole system's iteration, on the block's rows.
            let (mut r, mut c) = ([Complex::ZERO; MAX_BLOCK], [Complex::ZERO; MAX_BLOCK]);
            for i in 0..b {
                let (f1, f2, f3) = (f[0][i], f[1][i], f[2][i]);
                let (z1, z2, z3) = (self.z[0][at + i], self.z[1][at + i], self.z[2][at + i]);
                let a = |q: usize| TI[q][0] * f1 + TI[q][1] * f2 + TI[q][2] * f3;
                let w = |q: usize| TI[q][0] * z1 + TI[q][1] * z2 + TI[q][2] * z3;
                let (w1, w2, w3) = (w(0), w(1), w(2));
                r[i] = Complex::new(a(0) - w1 * u1, 0.0);
                c[i] = Complex::new(a(1) - w2 * alph + w3 * beta, a(2) - w2 * beta - w3 * alph);
            }
            let real = solve_block(&self.jac, at, b, Complex::new(u1, 0.0), &mut r);
            if !(real && solve_block(&self.jac, at, b, Complex::new(alph, beta), &mut c)) {
                break;
            }
            let mut sum = 0.0;
            for i in 0..b {
                let dw = [r[i].re, c[i].re, c[i].im];
                for s in 0..3 {
                    let dz = T[s][0] * dw[0] + T[s][1] * dw[1] + T[s][2] * dw[2];
                    let q = dz / self.scal[at + i];
                    sum += q * q;
                    self.z[s][at + i] += dz;
                    self.stages[s][at + i] = y[at + i] + self.z[s][at + i];
                }
            }
            let norm = (sum / (3 * b) as f64).sqrt();
            if !norm.is_finite() {
                break;
            }
            if it == 0 {
                first = norm;
                if faccon * norm <= goal {
                    return Some(first);
                }
            } else {
                let theta = norm / old;
                if theta >= LOCAL_THETA {
                    break;
                }
                if theta / (1.0 - theta) * norm <= goal {
                    return Some(first);
                }
            }
            old = norm.max(f64::EPSILON);
        }
        for (s, (z, st)) in saved.iter().zip(self.z.iter_mut().zip(&mut self.stages)) {
            z[at..at + b].copy_from_slice(&s[..b]);
            for i in at..at + b {
                st[i] = y[i] + z[i];
            }
        }
        None
    }
}
