//! Newton's iteration of a few blocks alone, their neighbours' stage values held: where the
//! simplified Newton iteration of the whole chain has converged in all blocks but a few (a body
//! at a reversal of its contact, whose friction changes within the step), those blocks are
//! iterated on their own rows, at the cost of a block rather than of the chain, then their
//! neighbours outwards (Gauss–Seidel). Where that settles them (each converged alone, below the
//! Newton tolerance, the correction died out on either side before the budget, and then passes
//! over the blocks of the set, the neighbours corrected and, pass by pass, the neighbours of
//! what the pass before corrected, ended on a pass that corrected none), every block has passed
//! its own convergence test, each as strict as the whole system's, and the iteration has
//! converged; otherwise one more iteration of the whole system follows, whose own test decides
//! as before. Either way the step's result is the collocation solution to the Newton
//! tolerance. Accepting a settled sweep instead of iterating the whole system once more: on a
//! drill string of LuGre sections (`examples/string_bench.rs`, tolerance 1e-6, 0.1 s) 1.6 %
//! fewer instructions at 20 sections, 2.7 % at 100, the errors against `tests/string.rs`'s
//! reference as before.
//!
//! A block's iteration is the whole system's restricted to its rows: the same transformed
//! residual `T⁻¹·F − (Λ/h)·W` on those rows, solved with the diagonal block of the step's
//! Jacobian (a real and a complex system of the block's size). Where that contracts slowly
//! (a stiff contact slowing to a reversal: its deformation relaxes at a rate proportional to
//! its velocity, which may fall several-fold within the step), the block is solved by
//! Newton's method on its own collocation equations with its own Jacobian at each stage
//! ([`BandWork::block_newton`], a 9×9 system for a section).
//!
//! Where the whole system's iteration is too slow to converge, the blocks that have not
//! converged by their own contraction are swept alone the same way before the step is given
//! up ([`BandWork::sweep_slow`]): one stiff section no longer rejects the string's step. On
//! the drill string with contacts of 1e12 N/m (20 sections, 0.1 s): 3107 steps and 2150
//! rejected attempts before, 1783 and 681 after. A block's Newton matrices are factored once
//! per attempt ([`BlockLus`]), not at each of its iterations.

use nalgebra::{Complex, ComplexField};

use super::lu::Band;
use super::radau::BandSystem;
use super::BandWork;
use crate::solver::radau::tableau::{A, ALPH, BETA, C, T, TI, U1};

/// The largest block iterated alone (a string's section has 3 components).
pub const MAX_BLOCK: usize = 4;
/// Iterations of a block alone at most (a drill string of 1000 sections took up to 12, most
/// blocks 1 or 2); beyond, the iteration of the whole system takes over.
const LOCAL_NIT: u32 = 12;
/// What a block alone is converged to, in units of the Newton tolerance: below it, so that the
/// whole system's iteration after the sweep finds it converged.
const LOCAL_GOAL: f64 = 0.3;
/// A block alone contracting slower than this on the step's Jacobian is iterated by Newton's
/// method on its own collocation equations, with its own Jacobian at each stage
/// ([`BandWork::block_newton`]): a contact whose stiffness changes by orders of magnitude
/// within the step (the deformation of a stiff contact slowing towards a reversal relaxes at
/// a rate proportional to its velocity) is not described by one Jacobian from the step's start.
const OWN_JACOBIAN_THETA: f64 = 0.5;
/// Passes of the final check of a sweep at most: a pass that still corrects a block moved its
/// neighbours, which the next pass checks.
const CHECK_PASSES: usize = 4;
/// Neighbours corrected per block iterated alone at most (a reversal disturbs a few sections
/// on either side within a step).
const SPREAD: usize = 3;

/// `g·I − J_kk` for the diagonal block `J_kk` (rows and columns `at..at + b`) of `jac`,
/// factored by Gaussian elimination with partial pivoting: the multipliers below the diagonal,
/// the row swaps in `swap`.
#[derive(Clone, Debug)]
struct BlockLu<T> {
    a: [[T; MAX_BLOCK]; MAX_BLOCK],
    swap: [usize; MAX_BLOCK],
    b: usize,
}

impl<T: ComplexField<RealField = f64> + Copy> BlockLu<T> {
    /// `None` where singular.
    fn new(jac: &Band<f64>, at: usize, b: usize, g: T) -> Option<Self> {
        let mut a = [[T::zero(); MAX_BLOCK]; MAX_BLOCK];
        for (i, row) in a.iter_mut().enumerate().take(b) {
            for (j, e) in row.iter_mut().enumerate().take(b) {
                let v = T::from_real(-jac.get(at + i, at + j));
                *e = if i == j { g + v } else { v };
            }
        }
        let mut swap = [0; MAX_BLOCK];
        for c in 0..b {
            let p = (c..b)
                .max_by(|&x, &y| {
                    a[x][c]
                        .modulus_squared()
                        .total_cmp(&a[y][c].modulus_squared())
                })
                .unwrap_or(c);
            if a[p][c].modulus_squared() == 0.0 {
                return None;
            }
            a.swap(c, p);
            swap[c] = p;
            for i in c + 1..b {
                let m = a[i][c] / a[c][c];
                a[i][c] = m;
                for j in c + 1..b {
                    let d = m * a[c][j];
                    a[i][j] -= d;
                }
            }
        }
        Some(BlockLu { a, swap, b })
    }

    /// Solves the factored system for `r` in place.
    fn solve(&self, r: &mut [T; MAX_BLOCK]) {
        let (a, b) = (&self.a, self.b);
        for c in 0..b {
            r.swap(c, self.swap[c]);
            for i in c + 1..b {
                let d = a[i][c] * r[c];
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
    }
}

/// The real and complex Newton matrices of a block alone, factored.
type BlockPair = (BlockLu<f64>, BlockLu<Complex<f64>>);

/// The factored Newton matrices of the blocks iterated alone, kept while the step's Newton
/// matrices are (a block is iterated alone many times in an attempt: its sweep, the walks of
/// its neighbours, the checks), each stamped with the factorisation it belongs to.
#[derive(Clone, Debug, Default)]
pub struct BlockLus {
    generation: u64,
    lus: Vec<(u64, Option<BlockPair>)>,
}

impl BlockLus {
    /// The step's Newton matrices changed.
    pub fn invalidate(&mut self) {
        self.generation += 1;
    }

    /// Block `k`'s pair for `jac` and the step `h` (`None` where singular).
    fn get(&mut self, jac: &Band<f64>, k: usize, b: usize, h: f64) -> Option<&BlockPair> {
        if self.lus.len() <= k {
            self.lus.resize_with(k + 1, || (0, None));
        }
        let g = self.generation + 1;
        let slot = &mut self.lus[k];
        if slot.0 != g {
            let at = k * b;
            let real = BlockLu::new(jac, at, b, U1 / h);
            let complex = BlockLu::new(jac, at, b, Complex::new(ALPH / h, BETA / h));
            *slot = (g, real.zip(complex));
        }
        slot.1.as_ref()
    }
}

/// The largest stage system of a block alone: 3 stages of [`MAX_BLOCK`] components.
const STAGE_SYSTEM: usize = 3 * MAX_BLOCK;

/// Solves `a·x = r` in place for the leading `m` rows and columns, by Gaussian elimination
/// with partial pivoting; `false` where singular.
fn solve_dense(
    a: &mut [[f64; STAGE_SYSTEM]; STAGE_SYSTEM],
    r: &mut [f64; STAGE_SYSTEM],
    m: usize,
) -> bool {
    for c in 0..m {
        let p = (c..m)
            .max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))
            .unwrap_or(c);
        if a[p][c] == 0.0 {
            return false;
        }
        a.swap(c, p);
        r.swap(c, p);
        for i in c + 1..m {
            let f = a[i][c] / a[c][c];
            if f == 0.0 {
                continue;
            }
            for j in c + 1..m {
                a[i][j] -= f * a[c][j];
            }
            r[i] -= f * r[c];
        }
    }
    for c in (0..m).rev() {
        let mut s = r[c];
        for j in c + 1..m {
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
        Some(self.local_sweep(sys, step, (fnewt, faccon), false))
    }

    /// Where the iteration of the whole system is too slow (one block holding it back): the
    /// blocks not converged by their own contraction (`norms`: their updates in this iteration
    /// and the one before), if at most `most`, iterated alone ([`Self::local_sweep`]) against
    /// the Newton tolerance: `None` where it did not, else whether that settled them.
    pub(super) fn sweep_slow<S: BandSystem>(
        &mut self,
        sys: &S,
        step: (f64, f64, &[f64]),
        fnewt: f64,
        most: usize,
    ) -> Option<bool> {
        self.local.clear();
        let b = sys.block();
        if b == 0 || b > MAX_BLOCK || self.norms[0].is_empty() {
            return None;
        }
        for (k, (&now, &before)) in self.norms[0].iter().zip(&self.norms[1]).enumerate() {
            let theta = now / before.max(f64::MIN_POSITIVE);
            let unconverged = if theta >= 0.99 {
                now > 0.01 * fnewt
            } else {
                now * (theta / (1.0 - theta)).max(1.0) > fnewt
            };
            if unconverged {
                if self.local.len() == most {
                    self.local.clear();
                    return None;
                }
                self.local.push(k);
            }
        }
        if self.local.is_empty() {
            return None;
        }
        Some(self.local_sweep(sys, step, (fnewt, 1.0), true))
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
    /// `all_or_nothing`: the caller gives the step up unless the sweep settles, so the sweep
    /// stops where it no longer can.
    fn local_sweep<S: BandSystem>(
        &mut self,
        sys: &S,
        step: (f64, f64, &[f64]),
        (fnewt, faccon): (f64, f64),
        all_or_nothing: bool,
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
            if !settled && all_or_nothing {
                break;
            }
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
        // neighbours' values before the walks moved them: settled where a pass over them
        // corrects none. A pass that corrects some moved them, so the next checks them and
        // their neighbours, up to [`CHECK_PASSES`] passes.
        let mut check: Vec<usize> = blocks.iter().chain(&moved).copied().collect();
        let mut passes = 0;
        while settled {
            if passes == CHECK_PASSES {
                settled = false;
                break;
            }
            passes += 1;
            let mut corrected = Vec::new();
            for &k in &check {
                match self.local_newton(sys, step, k, goal) {
                    Some(first) if faccon * first <= goal.0 => {}
                    Some(_) => corrected.push(k),
                    None => {
                        settled = false;
                        break;
                    }
                }
            }
            if corrected.is_empty() {
                break;
            }
            check.clear();
            for &k in &corrected {
                for j in k.saturating_sub(1)..=(k + 1).min(n - 1) {
                    if !check.contains(&j) {
                        check.push(j);
                    }
                }
            }
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
        // The block's real and complex Newton matrices, factored once for the attempt.
        let (lu_real, lu_complex) = self.block_lus.get(&self.jac, k, b, h).cloned()?;
        for it in 0..LOCAL_NIT {
            let mut f = [[0.0; MAX_BLOCK]; 3];
            for (s, fs) in f.iter_mut().enumerate() {
                sys.rhs_block(t + C[s] * h, &self.stages[s], k, &mut fs[..b]);
            }
            if !f.iter().all(|fs| fs[..b].iter().all(|v| v.is_finite())) {
                break;
            }
            // As the whole system's iteration, on the block's rows.
            let (mut r, mut c) = ([0.0; MAX_BLOCK], [Complex::ZERO; MAX_BLOCK]);
            for i in 0..b {
                let (f1, f2, f3) = (f[0][i], f[1][i], f[2][i]);
                let (z1, z2, z3) = (self.z[0][at + i], self.z[1][at + i], self.z[2][at + i]);
                let a = |q: usize| TI[q][0] * f1 + TI[q][1] * f2 + TI[q][2] * f3;
                let w = |q: usize| TI[q][0] * z1 + TI[q][1] * z2 + TI[q][2] * z3;
                let (w1, w2, w3) = (w(0), w(1), w(2));
                r[i] = a(0) - w1 * u1;
                c[i] = Complex::new(a(1) - w2 * alph + w3 * beta, a(2) - w2 * beta - w3 * alph);
            }
            lu_real.solve(&mut r);
            lu_complex.solve(&mut c);
            let mut sum = 0.0;
            for i in 0..b {
                let dw = [r[i], c[i].re, c[i].im];
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
                if theta > OWN_JACOBIAN_THETA {
                    if self.block_newton(sys, (t, h, y), k, goal) {
                        return Some(first);
                    }
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

    /// Newton's method on block `k`'s own collocation equations
    /// `z_s = h·Σ_j A_sj·f(t + C_j·h, y + z_j)` (its neighbours' stages held), with the
    /// block's Jacobian at each stage ([`BandSystem::jacobian_block`]), from its current
    /// increments, until its update times its contraction is below `goal`: whether it
    /// converged (else [`Self::local_newton`], its only caller, puts the block back as it
    /// was). The same equations as the whole system's iteration, so the same solution.
    fn block_newton<S: BandSystem>(
        &mut self,
        sys: &S,
        (t, h, y): (f64, f64, &[f64]),
        k: usize,
        goal: f64,
    ) -> bool {
        let b = sys.block();
        let at = k * b;
        let mut old = 0.0;
        for it in 0..LOCAL_NIT {
            let mut f = [[0.0; MAX_BLOCK]; 3];
            let mut jac = [[0.0; MAX_BLOCK * MAX_BLOCK]; 3];
            let mut provided = true;
            for s in 0..3 {
                let ts = t + C[s] * h;
                sys.rhs_block(ts, &self.stages[s], k, &mut f[s][..b]);
                provided &= sys.jacobian_block(ts, &self.stages[s], k, &mut jac[s][..b * b]);
            }
            let finite = f
                .as_flattened()
                .iter()
                .chain(jac.as_flattened())
                .all(|v| v.is_finite());
            if !(provided && finite) {
                break;
            }
            // (I − h·(A ⊗ J_j))·Δ = −(z − h·(A ⊗ I)·F), of size 3·b.
            let mut m = [[0.0; STAGE_SYSTEM]; STAGE_SYSTEM];
            let mut r = [0.0; STAGE_SYSTEM];
            for s in 0..3 {
                for i in 0..b {
                    let row = s * b + i;
                    let hf: f64 = (0..3).map(|j| A[s][j] * f[j][i]).sum::<f64>() * h;
                    r[row] = hf - self.z[s][at + i];
                    m[row][row] = 1.0;
                    for j in 0..3 {
                        for l in 0..b {
                            m[row][j * b + l] -= h * A[s][j] * jac[j][i * b + l];
                        }
                    }
                }
            }
            if !solve_dense(&mut m, &mut r, 3 * b) {
                break;
            }
            let mut sum = 0.0;
            for s in 0..3 {
                for i in 0..b {
                    let dz = r[s * b + i];
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
            if it > 0 {
                let theta = norm / old;
                if theta < 1.0 && theta / (1.0 - theta) * norm <= goal {
                    return true;
                }
            }
            old = norm.max(f64::EPSILON);
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One block `[x, v, s]` with `dx/dt = v`, `dv/dt = 0` and `ds/dt = λ·s`, whose band
    /// Jacobian (the step's) says `λ0` instead: the step's Jacobian no longer describes it.
    struct Relaxing {
        lambda: f64,
        lambda0: f64,
    }

    impl BandSystem for Relaxing {
        fn dim(&self) -> usize {
            3
        }
        fn bands(&self) -> (usize, usize) {
            (2, 2)
        }
        fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
            dy[..3].copy_from_slice(&[y[1], 0.0, self.lambda * y[2]]);
        }
        fn jacobian(&self, _t: f64, _y: &[f64], jac: &mut Band<f64>) {
            jac.set(0, 1, 1.0);
            jac.set(2, 2, self.lambda0);
        }
        fn error_scale(&self, y: &[f64], out: &mut [f64]) {
            for (o, y) in out.iter_mut().zip(y) {
                *o = 1e-9 + y.abs();
            }
        }
        fn block(&self) -> usize {
            3
        }
        fn max_local(&self) -> usize {
            1
        }
        fn rhs_block(&self, t: f64, y: &[f64], _k: usize, out: &mut [f64]) {
            self.rhs(t, y, out);
        }
        fn jacobian_block(&self, _t: f64, _y: &[f64], _k: usize, out: &mut [f64]) -> bool {
            out[..9].copy_from_slice(&[0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, self.lambda]);
            true
        }
    }

    /// Radau IIA's stability function, the (2, 3) Padé approximation of `exp(z)`.
    fn stability(z: f64) -> f64 {
        (1.0 + 0.4 * z + z * z / 20.0) / (1.0 - 0.6 * z + 0.15 * z * z - z * z * z / 60.0)
    }

    /// Iterates the block alone from zero increments over a step `h` from `y` with the step's
    /// Jacobian at `lambda0`: the first update's norm, and the state at the step's end.
    fn solve_alone(lambda: f64, lambda0: f64, h: f64, y: [f64; 3]) -> (Option<f64>, [f64; 3]) {
        let sys = Relaxing { lambda, lambda0 };
        let mut work = BandWork::new(3, 2, 2);
        sys.jacobian(0.0, &y, &mut work.jac);
        sys.error_scale(&y, &mut work.scal);
        for s in work.scal.iter_mut() {
            *s *= 1e-10;
        }
        for k in 0..3 {
            work.z[k].fill(0.0);
            work.stages[k].copy_from_slice(&y);
        }
        let first = work.local_newton(&sys, (0.0, h, &y), 0, (1e-3, 1.0));
        let end = std::array::from_fn(|i| work.stages[2][i]);
        (first, end)
    }

    /// A relaxation 1000 times faster than the step's Jacobian says (h·λ = −100 against −0.1):
    /// on that Jacobian the block's iteration diverges; with its own Jacobian it ends where
    /// Radau IIA's stability function puts it, `R(h·λ)·s0`, and the rest of the block exactly
    /// on its closed form.
    #[test]
    fn a_block_the_steps_jacobian_misdescribes_is_solved_with_its_own() {
        let (h, lambda, s0) = (1e-3, -1e5, 2e-6);
        let y = [0.3, 0.02, s0];
        let (first, end) = solve_alone(lambda, -1e2, h, y);
        assert!(first.is_some(), "not converged");
        let exact = stability(h * lambda) * s0;
        assert!(
            (end[2] - exact).abs() <= 1e-12 * s0,
            "s {} against R(hλ)·s0 = {exact}",
            end[2]
        );
        assert!((end[0] - (y[0] + h * y[1])).abs() <= 1e-15, "x {}", end[0]);
        assert_eq!(end[1], y[1]);
        // The same block, described by the step's Jacobian: one simplified iteration, the
        // same end to rounding.
        let (first, same) = solve_alone(lambda, lambda, h, y);
        assert!(first.is_some());
        assert!((same[2] - exact).abs() <= 1e-12 * s0, "s {}", same[2]);
    }
}
