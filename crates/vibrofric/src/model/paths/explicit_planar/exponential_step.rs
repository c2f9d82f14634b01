//! The planar explicit path's exponential step ([module docs](super)): the deformation advanced
//! exactly in the relaxation arc length for its target interpolated in λ.

use super::rhs::{Eqs, Kin};
use super::*;

/// One exponential step of length `hh` from `(t, u)` with the first derivative `k1`
/// ([module docs](self)), `kin_stage(i, tt, y)` what the right-hand side needs at stage `i`:
/// the step, its end (the deformation from the second pass's extension), the deformation's
/// largest scaled error (relative tolerance `rtol`, scales `scale`) and the rest's (λ's, or
/// infinite where the interpolation's nodes did not increase; `by_moves`: weighed by how far
/// it moves the deformation, [`LAMBDA_BY_MOVES_FROM`]), and whether the second pass
/// was taken (six more right-hand sides). `vr_at` gets `v_r` at the stages of the last pass.
#[allow(clippy::too_many_arguments)] // the step's own arguments, and what it needs
pub(super) fn exponential_step<
    V: Vector,
    L: FrictionLaw,
    D: DriveKind<V>,
    const N: usize,
    const M: usize,
>(
    eqs: &Eqs<'_, '_, V, L, D, N, M>,
    kin_stage: &impl Fn(usize, f64, &[f64; M]) -> Kin<V>,
    t: f64,
    u: &[f64; M],
    k1: &[f64; M],
    hh: f64,
    rtol: f64,
    scale: &[f64],
    by_moves: bool,
    vr_at: &mut [V; 7],
) -> (DoPriStep<M>, [f64; M], f64, f64, bool) {
    let il = N + V::DIM;
    let (mut err_s, mut err, mut second): (f64, f64, bool) = (0.0, 0.0, false);
    // The deformation at each stage from its equation in λ, `ds/dλ = q − s`, with
    // the target `q = s_ss·v_r/|v_r|` interpolated in λ through the stages so far
    // (their λ from the method's own stages of `dλ/dt = |v_r|/s_ss`): exact for
    // that polynomial whatever the relaxation over the step.
    let s0 = [u[0], if V::DIM == 2 { u[1] } else { 0.0 }];
    let mut hist = Stages::new(s0, eqs.kin(t, u).target(), 1);
    let step = {
        let mut stage = |tt: f64, y: &[f64; M]| -> [f64; M] {
            let i = hist.n;
            hist.n += 1;
            hist.lam[i] = y[il];
            let k = kin_stage(i, tt, y);
            hist.q[i] = k.target();
            vr_at[i] = k.vr;
            let s_i = match i {
                1 => hist.relax([0, 1]),
                2 => hist.relax([0, 1, 2]),
                3 => hist.relax([0, 1, 2, 3]),
                4 => hist.relax([0, 1, 2, 3, 4]),
                5 => hist.relax([0, 1, 2, 3, 4, 5]),
                _ => hist.relax([0, 1, 2, 3, 4, 6]),
            };
            eqs.rhs_with(y, V::read(&s_i[..V::DIM]), &k)
        };
        DoPriStep::take(&mut stage, t, u, k1, hh)
    };
    // The stages' velocities are of low order: a second pass with the deformation
    // at each stage from the first pass's continuous extension (q at six
    // equidistant points, the ends exact, λ from the same extension).
    let dense = step.dense_all(hh);
    let mut first = nodes::<V, N, M>(&step, &dense, hist.s0, hist.q[0], |theta, z| {
        eqs.kin(t + theta * hh, z).target()
    });
    first.bad |= hist.bad;
    let fit = first.fit([0, 1, 2, 3, 4, 5]);
    let big = first.lam[5];
    let step = match &fit {
        Some(fit) => {
            let (mut i, mut stage2) = (1, [0.0; 7]);
            for (k, c) in C.iter().enumerate() {
                stage2[k] = dense.at(il, *c) / big;
            }
            let mut stage = |tt: f64, y: &[f64; M]| -> [f64; M] {
                let s_i = fit.at(stage2[i]);
                i += 1;
                let k = kin_stage(i - 1, tt, y);
                vr_at[i - 1] = k.vr;
                eqs.rhs_with(y, V::read(&s_i[..V::DIM]), &k)
            };
            second = true;
            DoPriStep::take(&mut stage, t, u, k1, hh)
        }
        None => step,
    };
    let mut u1 = step.end();
    let dense = step.dense_all(hh);
    let mut fine = nodes::<V, N, M>(&step, &dense, hist.s0, hist.q[0], |theta, z| {
        eqs.kin(t + theta * hh, z).target()
    });
    fine.bad |= first.bad;
    let s5 = fine.relax([0, 1, 2, 3, 4, 5]);
    let s4 = fine.relax([0, 2, 3, 4, 5]);
    let bad = fine.bad;
    u1[..V::DIM].copy_from_slice(&s5[..V::DIM]);
    for c in 0..V::DIM {
        let w = rtol * (scale[c] + u[c].abs().max(s5[c].abs()));
        err_s = err_s.max((s5[c] - s4[c]).abs() / w);
    }
    // λ places the interpolation's nodes: its error relative to the step's λ.
    // λ's error moves the deformation by about `|s − q|` times it ([`LAMBDA_BY_MOVES_FROM`]).
    let mut moves = 1.0f64;
    if by_moves {
        moves = 0.0;
        for c in 0..V::DIM {
            moves = moves.max((s5[c] - fine.q[5][c]).abs() / (scale[c] + s5[c].abs()));
        }
        moves = moves.min(1.0);
    }
    err = err.max(step.err[il].abs() / (rtol * u1[il].max(1.0)) * moves);
    if bad {
        err = f64::INFINITY;
    }
    (step, u1, err_s, err, second)
}

/// λ and `q` at six equidistant points of a step from its continuous extension `dense`
/// (the start's `q` given, the end's from the end state; `target(theta, z)` is `q` at
/// `t + theta·h` and the state `z`).
fn nodes<V: Vector, const N: usize, const M: usize>(
    step: &DoPriStep<M>,
    dense: &Dense<M>,
    s0: [f64; 2],
    q0: [f64; 2],
    target: impl Fn(f64, &[f64; M]) -> [f64; 2],
) -> Stages {
    let mut fine = Stages::new(s0, q0, 0);
    let end = step.end();
    fine.lam[5] = end[N + V::DIM];
    fine.q[5] = target(1.0, &end);
    for k in 1..5 {
        let theta = k as f64 * 0.2;
        let mut z = end;
        for (i, zi) in z.iter_mut().enumerate().take(N).skip(V::DIM) {
            *zi = dense.at(i, theta);
        }
        fine.lam[k] = dense.at(N + V::DIM, theta);
        fine.q[k] = target(theta, &z);
    }
    fine
}

/// The stages of one exponential step: `λ` and the target `q` at each, the deformation at the
/// step's start, and at its end from the interpolants of degree 5 and 4.
struct Stages {
    lam: [f64; 7],
    q: [[f64; 2]; 7],
    s0: [f64; 2],
    n: usize,
    /// The nodes were not increasing in λ: the step is rejected.
    bad: bool,
    /// `1/(λ_j − λ_k)` for `k < j` once a fit has needed it (0 until then): the divided
    /// differences of both components and every fit through the same nodes share them.
    inv: [[f64; 7]; 7],
}

impl Stages {
    fn new(s0: [f64; 2], q0: [f64; 2], n: usize) -> Self {
        let mut q = [[0.0; 2]; 7];
        q[0] = q0;
        Stages {
            lam: [0.0; 7],
            q,
            s0,
            n,
            bad: false,
            inv: [[0.0; 7]; 7],
        }
    }

    /// `s` at the last of `nodes` (see [`Fit`]).
    fn relax<const K: usize>(&mut self, nodes: [usize; K]) -> [f64; 2] {
        match self.fit(nodes) {
            Some(f) => f.at(1.0),
            None => self.s0,
        }
    }

    /// The interpolant of `q` through `nodes` in `μ = λ/Λ`, `Λ` the last node's `λ`; `None`
    /// (and the step marked bad) where the nodes do not increase in λ. The number of nodes is
    /// a constant, so that the loops unroll and the coefficients stay in registers.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // the divided differences index in lockstep
    fn fit<const K: usize>(&mut self, nodes: [usize; K]) -> Option<Fit<K>> {
        let n = K;
        let big = self.lam[nodes[n - 1]];
        for k in 1..n {
            if self.lam[nodes[k]] <= self.lam[nodes[k - 1]] {
                self.bad = true;
            }
        }
        if self.bad || big.is_nan() || big <= 0.0 {
            self.bad = true;
            return None;
        }
        let inv_big = 1.0 / big;
        let mut mu = [0.0; K];
        for (k, &j) in nodes.iter().enumerate() {
            mu[k] = self.lam[j] * inv_big;
        }
        // `1/(μ_j − μ_(j−k)) = Λ/(λ_j − λ_(j−k))` for the divided differences.
        let mut w = [[0.0; K]; K];
        for k in 1..n {
            for j in k..n {
                let (a, b) = (nodes[j], nodes[j - k]);
                if self.inv[a][b] == 0.0 {
                    self.inv[a][b] = 1.0 / (self.lam[a] - self.lam[b]);
                }
                w[k][j] = big * self.inv[a][b];
            }
        }
        let mut poly = [[0.0; K]; 2];
        // A component that is 0 throughout (the lateral one of a motion on the x axis) stays 0.
        let comps = if self.s0[1] == 0.0 && nodes.iter().all(|&j| self.q[j][1] == 0.0) {
            1
        } else {
            2
        };
        for (c, pc) in poly.iter_mut().enumerate().take(comps) {
            // Divided differences, then the monomial coefficients by Horner on the Newton form.
            let mut dd = [0.0; K];
            for (k, &j) in nodes.iter().enumerate() {
                dd[k] = self.q[j][c];
            }
            for k in 1..n {
                for j in (k..n).rev() {
                    dd[j] = (dd[j] - dd[j - 1]) * w[k][j];
                }
            }
            pc[0] = dd[n - 1];
            for i in (0..n - 1).rev() {
                for m in (1..n).rev() {
                    pc[m] = pc[m - 1] - mu[i] * pc[m];
                }
                pc[0] = -mu[i] * pc[0] + dd[i];
            }
        }
        // `s0 − P(0)`: G_m(0) = (−x)^m·m! (see `Fit::at`).
        let mut g0 = [1.0; K];
        for m in 1..n {
            g0[m] = -inv_big * m as f64 * g0[m - 1];
        }
        let mut c0 = [0.0; 2];
        for c in 0..comps {
            let p0: f64 = (0..n).map(|m| poly[c][m] * g0[m]).sum();
            c0[c] = self.s0[c] - p0;
        }
        Some(Fit {
            poly,
            comps,
            big,
            inv_big,
            c0,
        })
    }
}

/// The solution of `ds/dλ = p(λ) − s`, `s(0) = s0`, `p` a polynomial of degree `K − 1` in
/// `μ = λ/Λ`: `s = P(λ) + (s0 − P(0))·exp(−λ)` with the polynomial particular solution
/// `P = Σ_k (−1)^k·d^k p/dλ^k`. Its terms shrink with `1/Λ`; the exponential path is taken
/// from a relaxation of [`EXPONENTIAL_FROM`] per step on.
struct Fit<const K: usize> {
    poly: [[f64; K]; 2],
    /// The components fitted (the second is 0 when only one is).
    comps: usize,
    big: f64,
    inv_big: f64,
    /// `s0 − P(0)`.
    c0: [f64; 2],
}

impl<const K: usize> Fit<K> {
    /// `s` at `λ = μ·Λ`.
    #[inline(always)]
    fn at(&self, mu: f64) -> [f64; 2] {
        // G_m(μ) = Σ_k (−x)^k·m!/(m − k)!·μ^(m−k) = μ^m − x·m·G_(m−1)(μ), x = 1/Λ.
        let x = self.inv_big;
        let (mut g, mut pw) = ([1.0; K], 1.0);
        for m in 1..K {
            pw *= mu;
            g[m] = pw - x * m as f64 * g[m - 1];
        }
        let decay = exp_neg(self.big * mu);
        let mut out = [0.0; 2];
        for (c, o) in out.iter_mut().enumerate().take(self.comps) {
            let p: f64 = (0..K).map(|m| self.poly[c][m] * g[m]).sum();
            *o = p + self.c0[c] * decay;
        }
        out
    }
}

/// `exp(−z)` for `z ≥ 0` up to rounding, from the explicit path's arithmetic `expm1`:
/// `expm1(−z) + 1`, exact to about 1e-16 absolute (all the relaxation's factor needs), and 0
/// beyond `z` = 39 where it is below 1.2e-17.
#[inline(always)]
fn exp_neg(z: f64) -> f64 {
    if z > 39.0 {
        0.0
    } else {
        super::super::explicit::expm1(-z.max(-1.0)) + 1.0
    }
}
