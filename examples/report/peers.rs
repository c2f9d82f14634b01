//! Rust peer integrators: the contact's equations ([`vibrofric::model::Ode`]) solved with
//! general-purpose Rust ODE crates, the way a user of those crates would, so the report can
//! set vibrofric's error against CPU time beside theirs.
//!
//! Every peer integrates the state augmented with the quadrature `Q' = F_Fx` (`Q(0) = 0`) from
//! `t = 0` to `t_end` with `rtol = tol`, `atol_i = tol·scale_i` and, for `Q`,
//! `atol = tol·f_scale·period`. `F_mean` is `(Q(t_end) − Q(t_a))/period`, `t_a = t_end − period`;
//! `Q(t_end)` is the solver's own state at `t_end` (every peer stops exactly there). The samples
//! of `F_Fx` are `f_fx` on the crate's dense output at the sample times (every peer has one, so
//! none stops at the sample times).
//! - diffsol peers: one run; `Q(t_a)` from diffsol's interpolant.
//! - differential-equations peers: two `solve_ode` calls, `[0, t_a]` and `[t_a, t_end]` (one
//!   restart), so `Q(t_a)` is a step end: that crate's DOP853 dense output is defective in 0.7.0
//!   (Hairer's `contd8` with `s` and `1 − s` swapped in its high-order part: on `y'' = −y` its
//!   interpolation errors are 500× its step-end errors, order ≈ 5 instead of 7), and Radau5's is
//!   the collocation polynomial (order 3). Its samples are still affected (DOP853: up to
//!   ~4e-4 N at tol 1e-8 on the paper case, against ~4e-6 N for diffsol BDF).
//!
//! Crates:
//! - `diffsol` (nalgebra backend, dense `NalgebraLU`): BDF (variable order 1–5, NDF-style as in
//!   diffsol), TR-BDF2 and ESDIRK34 (both SDIRK with diffsol's Hermite dense output). diffsol
//!   asks for a Jacobian–vector product, computed here from the closed-form
//!   [`Ode::jacobian`](vibrofric::model::Ode::jacobian); the row of `Q` (`∂F_Fx/∂y`, which the
//!   ODE does not give in closed form) is a forward difference of `f_fx`.
//! - `differential-equations` (no optional features, so no extra linear-algebra crate): DOP853
//!   (explicit Dormand–Prince 8(5,3), the crate's defaults apart from an unbounded step count;
//!   chosen over `ode_solvers` 0.6.2, whose DOP853 with `OutputType::Dense` returned a wrong
//!   solution on this problem, F_mean ≈ 5800 N instead of 4.3 N, and needed 34× the steps) and
//!   Radau5 (Radau IIA order 5, a port of Hairer's RADAU5, given the same
//!   Jacobian as diffsol). Radau5, like Hairer's code, tightens the tolerances internally
//!   (`rtol → 0.1·rtol^(2/3)`).
//!
//! Neither crate spawns threads in these configurations (no `rayon`; faer, pulled in by
//! diffsol's linear-algebra crate, is built without default features).

// Shared by the report and the `peers_check` example, each of which uses only part of it.
#![allow(dead_code)]

use std::panic::{catch_unwind, AssertUnwindSafe};

use cpu_time::ThreadTime;

use vibrofric::model::Ode;

/// A peer integrator from another Rust crate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RustPeer {
    /// `diffsol` BDF, orders 1–5, dense LU (nalgebra).
    DiffsolBdf,
    /// `diffsol` TR-BDF2 (SDIRK, order 2), dense LU (nalgebra).
    DiffsolTrBdf2,
    /// `diffsol` ESDIRK34 (order 3 with embedded 4), dense LU (nalgebra).
    DiffsolEsdirk34,
    /// `differential-equations` Radau5 (Radau IIA, order 5).
    DeRadau5,
    /// `differential-equations` DOP853 (explicit Dormand–Prince 8(5,3)).
    DeDop853,
    /// Radau5 with reversal handling: every sign change of `v_rx` located and the integration
    /// restarted there, steps at most an eighth of the period.
    DeRadau5Reversals,
    /// DOP853 with the same reversal handling.
    DeDop853Reversals,
}

impl RustPeer {
    pub const ALL: [RustPeer; 7] = [
        RustPeer::DiffsolBdf,
        RustPeer::DiffsolTrBdf2,
        RustPeer::DiffsolEsdirk34,
        RustPeer::DeRadau5,
        RustPeer::DeDop853,
        RustPeer::DeRadau5Reversals,
        RustPeer::DeDop853Reversals,
    ];

    pub fn name(self) -> &'static str {
        match self {
            RustPeer::DiffsolBdf => "diffsol BDF",
            RustPeer::DiffsolTrBdf2 => "diffsol TR-BDF2",
            RustPeer::DiffsolEsdirk34 => "diffsol ESDIRK34",
            RustPeer::DeRadau5 => "differential-equations Radau5",
            RustPeer::DeDop853 => "differential-equations DOP853",
            RustPeer::DeRadau5Reversals => "differential-equations Radau5 +rev",
            RustPeer::DeDop853Reversals => "differential-equations DOP853 +rev",
        }
    }

    /// Whether the run locates the sign changes of `v_rx` and restarts there. The diffsol peers
    /// always do (diffsol's root finding moves the state back to the root and goes on; it has
    /// no step bound); the differential-equations peers run both ways, because the step bound
    /// that makes the location reliable also costs steps.
    pub fn reversals(self) -> bool {
        !matches!(self, RustPeer::DeRadau5 | RustPeer::DeDop853)
    }

    /// Whether the method is meant for stiff problems (implicit, with a Jacobian).
    pub fn stiff_capable(self) -> bool {
        !matches!(self, RustPeer::DeDop853 | RustPeer::DeDop853Reversals)
    }
}

/// The outcome of one peer run.
#[derive(Clone, Debug)]
pub struct PeerRun {
    /// Mean of `F_Fx` over `[t_end − period, t_end]` from the quadrature; NaN on failure.
    pub f_mean: f64,
    /// `F_Fx` at `t = k·sample_dt`, `k = 0..=round(t_end/sample_dt)` (fewer on failure).
    pub samples: Vec<f64>,
    /// CPU time of this thread for the whole run (problem set-up and integration; neither crate
    /// spawns threads here) [s].
    pub cpu_s: f64,
    /// Reversals (sign changes of `v_rx`) located and stepped to.
    pub reversals: u64,
    /// Accepted steps, as the crate reports them (every peer here reports them).
    pub steps: u64,
    /// `Err("budget")` if the run went past `budget_s`; other errors are the crate's.
    pub status: Result<(), String>,
}

/// Integrates `ode` from t = 0 to `t_end`; `samples[k]` = F_Fx at t = k·sample_dt
/// (k = 0..=round(t_end/sample_dt), the last one clamped to `t_end`), from the crate's dense
/// output; `f_mean` = mean of F_Fx over [t_end − period, t_end] from the quadrature
/// `Q' = F_Fx` appended to the state: (Q(t_end) − Q(t_end − period))/period.
/// rtol = tol, atol_i = tol·scale_i (Q: tol·f_scale·period).
/// `budget_s`: gives up with status `Err("budget")` once the run has taken longer than this
/// (checked after every accepted step). Never panics: crate errors (and, as a last resort, a
/// panic inside a crate) become `status: Err(message)`.
#[allow(clippy::too_many_arguments)]
pub fn run(
    peer: RustPeer,
    ode: &dyn Ode,
    t_end: f64,
    sample_dt: f64,
    period: f64,
    f_scale: f64,
    tol: f64,
    budget_s: f64,
) -> PeerRun {
    let reversals = peer.reversals();
    let start = ThreadTime::now();
    let mut rec = Recorder::new(ode, t_end, sample_dt, period, start, budget_s);
    let bad_input = if !(t_end.is_finite() && t_end > 0.0) {
        Some(format!("t_end = {t_end}: must be finite and > 0"))
    } else if !(sample_dt.is_finite() && sample_dt > 0.0) {
        Some(format!("sample_dt = {sample_dt}: must be finite and > 0"))
    } else if !(period.is_finite() && period > 0.0 && period <= t_end * (1.0 + 1e-12)) {
        Some(format!("period = {period}: must be in (0, t_end]"))
    } else if !(tol.is_finite() && tol > 0.0) {
        Some(format!("tol = {tol}: must be finite and > 0"))
    } else {
        None
    };
    let outcome = match bad_input {
        Some(msg) => Err(msg),
        None => {
            let setup = Setup::new(ode, f_scale, period, tol, reversals);
            let rec_ref = &mut rec;
            catch_unwind(AssertUnwindSafe(move || match peer {
                RustPeer::DiffsolBdf | RustPeer::DiffsolTrBdf2 | RustPeer::DiffsolEsdirk34 => {
                    ds::run(peer, &setup, rec_ref, t_end)
                }
                RustPeer::DeRadau5
                | RustPeer::DeDop853
                | RustPeer::DeRadau5Reversals
                | RustPeer::DeDop853Reversals => de::run(peer, &setup, rec_ref, t_end),
            }))
            .unwrap_or_else(|p| {
                let msg = p
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| p.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown".into());
                Err(format!("panic in the crate: {msg}"))
            })
        }
    };
    let cpu_s = rec.start.elapsed().as_secs_f64();
    let (f_mean, steps, status) = match outcome {
        Ok(steps) => match (rec.q_a, rec.last) {
            (Some(q_a), Some((t, q_end))) if rec.at_end(t) && rec.next == rec.n_samples => {
                ((q_end - q_a) / period, steps, Ok(()))
            }
            _ => (
                f64::NAN,
                steps,
                Err("the integration ended before t_end".into()),
            ),
        },
        Err(msg) => (f64::NAN, rec.steps_seen, Err(msg)),
    };
    PeerRun {
        f_mean,
        samples: rec.samples,
        cpu_s,
        reversals: rec.reversals,
        steps,
        status,
    }
}

/// What every peer needs: the ODE, its augmented dimension and tolerances.
struct Setup<'a> {
    ode: &'a dyn Ode,
    /// Dimension of the contact's state (the quadrature is component `n`).
    n: usize,
    y0: Vec<f64>,
    scale: Vec<f64>,
    rtol: f64,
    atol: Vec<f64>,
    /// Locate every sign change of `v_rx` (the kinks of the right-hand side) and restart the
    /// integration there.
    reversals: bool,
    /// Largest step (where the crate takes one): an eighth of the vibration period with
    /// reversal handling, so that no step spans a whole lobe of `v_rx` (a step over both sign
    /// changes of a lobe sees no sign change, and in saturated sliding its error estimate does
    /// not see the lobe either); unbounded without.
    h_max: f64,
}

impl<'a> Setup<'a> {
    fn new(ode: &'a dyn Ode, f_scale: f64, period: f64, tol: f64, reversals: bool) -> Self {
        let n = ode.dim();
        let mut y0 = ode.state();
        y0.push(0.0);
        let scale = ode.scale();
        let mut atol: Vec<f64> = scale.iter().map(|s| tol * s).collect();
        atol.push(tol * f_scale * period);
        Setup {
            ode,
            n,
            y0,
            scale,
            rtol: tol,
            atol,
            reversals,
            h_max: if reversals {
                period / 8.0
            } else {
                f64::INFINITY
            },
        }
    }

    /// `v_rx` on the augmented state.
    fn v_rx(&self, t: f64, y: &[f64]) -> f64 {
        self.ode.v_rx(t, &y[..self.n])
    }

    /// Augmented right-hand side: `[f(t, y); F_Fx(t, y)]`.
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.n;
        self.ode.rhs(t, &y[..n], &mut dy[..n]);
        dy[n] = self.ode.f_fx(t, &y[..n]);
    }

    /// Augmented Jacobian, row-major `(n+1)×(n+1)`: the closed form for the contact's rows,
    /// a forward difference of `f_fx` for the quadrature's row, zeros in the last column.
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut [f64], work: &mut Vec<f64>) {
        let n = self.n;
        let m = n + 1;
        work.resize(n * n, 0.0);
        self.ode.jacobian(t, &y[..n], work);
        for i in 0..n {
            jac[i * m..i * m + n].copy_from_slice(&work[i * n..(i + 1) * n]);
            jac[i * m + n] = 0.0;
        }
        let f0 = self.ode.f_fx(t, &y[..n]);
        let mut yp = y[..n].to_vec();
        for j in 0..n {
            let h = f64::EPSILON.sqrt() * y[j].abs().max(self.scale[j]).max(f64::MIN_POSITIVE);
            yp[j] = y[j] + h;
            let h = yp[j] - y[j];
            jac[n * m + j] = (self.ode.f_fx(t, &yp) - f0) / h;
            yp[j] = y[j];
        }
        jac[n * m + n] = 0.0;
    }
}

/// Checks [`Ode::jacobian`] against central differences of [`Ode::rhs`] at `(t, y)`: the largest
/// difference of an entry, `|J_ij − D_ij|·scale_j`, relative to its row's largest
/// `|J_ik|·scale_k`, with the step `h_j = 1e-6·max(|y_j|, scale_j)`. A column whose forward and
/// backward differences disagree by more than 1e-3 of the row (a kink of the right-hand side, such
/// as a reversal or a law's switching point, within `±h_j`) is left out. Returns the largest
/// difference and the number of columns left out.
pub fn jacobian_check(ode: &dyn Ode, t: f64, y: &[f64]) -> (f64, usize) {
    let n = ode.dim();
    let scale = ode.scale();
    let mut jac = vec![0.0; n * n];
    ode.jacobian(t, y, &mut jac);
    let f0 = {
        let mut f = vec![0.0; n];
        ode.rhs(t, y, &mut f);
        f
    };
    let row_scale: Vec<f64> = (0..n)
        .map(|i| {
            (0..n)
                .map(|k| (jac[i * n + k] * scale[k]).abs())
                .fold(0.0, f64::max)
                .max(f64::MIN_POSITIVE)
        })
        .collect();
    let (mut worst, mut skipped) = (0.0_f64, 0);
    let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
    for j in 0..n {
        let h = 1e-6 * y[j].abs().max(scale[j]);
        let mut yp = y.to_vec();
        yp[j] = y[j] + h;
        ode.rhs(t, &yp, &mut fp);
        yp[j] = y[j] - h;
        ode.rhs(t, &yp, &mut fm);
        let kink = (0..n).any(|i| {
            let fwd = (fp[i] - f0[i]) / h;
            let bwd = (f0[i] - fm[i]) / h;
            (fwd - bwd).abs() * scale[j] > 1e-3 * row_scale[i]
        });
        if kink {
            skipped += 1;
            continue;
        }
        for i in 0..n {
            let d = (fp[i] - fm[i]) / (2.0 * h);
            worst = worst.max((jac[i * n + j] - d).abs() * scale[j] / row_scale[i]);
        }
    }
    (worst, skipped)
}

/// The sign change of `g` in `[a, b]`, where `g(a)` and `g(b)` are nonzero and of opposite
/// signs: the Illinois variant of regula falsi, to a bracket of width `4ε·|b|`. Returns the end of
/// the final bracket on `b`'s side (`g` already has `g(b)`'s sign there), so that a restart from it
/// does not find the same reversal again.
fn locate(
    mut a: f64,
    mut ga: f64,
    mut b: f64,
    mut gb: f64,
    g: &mut dyn FnMut(f64) -> Result<f64, String>,
) -> Result<f64, String> {
    let mut side = 0;
    for _ in 0..200 {
        if (b - a).abs() <= 4.0 * f64::EPSILON * b.abs().max(a.abs()) {
            break;
        }
        let mut c = b - gb * (b - a) / (gb - ga);
        if !(c > a.min(b) && c < a.max(b)) {
            c = 0.5 * (a + b);
        }
        let gc = g(c)?;
        if gc == 0.0 {
            return Ok(c);
        }
        if gc.signum() == gb.signum() {
            b = c;
            gb = gc;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        } else {
            a = c;
            ga = gc;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        }
    }
    Ok(b)
}

/// Collects the samples and `Q(t_end − period)` from dense output, step by step.
struct Recorder<'a> {
    ode: &'a dyn Ode,
    n_samples: usize,
    sample_dt: f64,
    t_end: f64,
    next: usize,
    samples: Vec<f64>,
    t_a: f64,
    q_a: Option<f64>,
    start: ThreadTime,
    budget_s: f64,
    steps_seen: u64,
    /// Reversals located (the integration stopped at each and restarted from it).
    reversals: u64,
    /// `(t, Q(t))` at the end of the last accepted step.
    last: Option<(f64, f64)>,
}

impl<'a> Recorder<'a> {
    fn new(
        ode: &'a dyn Ode,
        t_end: f64,
        sample_dt: f64,
        period: f64,
        start: ThreadTime,
        budget_s: f64,
    ) -> Self {
        let n_samples = if t_end > 0.0 && sample_dt > 0.0 {
            (t_end / sample_dt).round() as usize + 1
        } else {
            0
        };
        Recorder {
            ode,
            n_samples,
            sample_dt,
            t_end,
            next: 0,
            samples: Vec::with_capacity(n_samples),
            t_a: (t_end - period).max(0.0),
            q_a: None,
            start,
            budget_s,
            steps_seen: 0,
            reversals: 0,
            last: None,
        }
    }

    fn sample_time(&self, k: usize) -> f64 {
        (k as f64 * self.sample_dt).min(self.t_end)
    }

    /// Takes what falls at or before `t` from the initial state (`y0`, augmented).
    fn initial(&mut self, y0: &[f64]) {
        self.take(0.0, 0.0, true, &mut |_| Ok(y0.to_vec()))
            .expect("the initial state needs no interpolation");
    }

    /// Takes every sample (and `Q(t_a)`) in `(t_prev, t]` (or `[t_prev, t]` if `first`),
    /// `y(s)` (augmented) from `interp`. The step that reaches `t_end` to within rounding takes
    /// the samples at `t_end` too, evaluated at its end `t`.
    fn take(
        &mut self,
        t_prev: f64,
        t: f64,
        first: bool,
        interp: &mut dyn FnMut(f64) -> Result<Vec<f64>, String>,
    ) -> Result<(), String> {
        let n = self.ode.dim();
        let t_hi = if self.at_end(t) { self.t_end.max(t) } else { t };
        let within = |s: f64| (s > t_prev || (first && s >= t_prev)) && s <= t_hi;
        while self.next < self.n_samples && within(self.sample_time(self.next)) {
            let s = self.sample_time(self.next).min(t);
            let y = interp(s)?;
            self.samples.push(self.ode.f_fx(s, &y[..n]));
            self.next += 1;
        }
        if self.q_a.is_none() && within(self.t_a) {
            self.q_a = Some(if self.t_a == 0.0 {
                0.0
            } else {
                interp(self.t_a.min(t))?[n]
            });
        }
        Ok(())
    }

    fn at_end(&self, t: f64) -> bool {
        t >= self.t_end * (1.0 - 1e-12)
    }

    /// After an accepted step ending at `(t, Q(t))`: counts it and checks the budget.
    fn stepped(&mut self, t: f64, q: f64) -> Result<(), String> {
        self.steps_seen += 1;
        self.last = Some((t, q));
        // Not after the last step: the work is done by then.
        if !self.at_end(t) && self.start.elapsed().as_secs_f64() > self.budget_s {
            Err("budget".into())
        } else {
            Ok(())
        }
    }
}

/// The `diffsol` peers.
mod ds {
    use super::{Recorder, RustPeer, Setup};
    use diffsol::{
        NalgebraLU, NalgebraMat, OdeBuilder, OdeEquations, OdeSolverMethod, OdeSolverStopReason,
        Vector,
    };
    use std::cell::RefCell;

    type M = NalgebraMat<f64>;
    type LS = NalgebraLU<f64>;

    /// The Jacobian at the last point asked for: diffsol builds its dense Jacobian one
    /// Jacobian–vector product per column, all at the same `(t, x)`.
    struct Cache {
        t: f64,
        x: Vec<f64>,
        jac: Vec<f64>,
        work: Vec<f64>,
        valid: bool,
    }

    pub(super) fn run(
        peer: RustPeer,
        setup: &Setup<'_>,
        rec: &mut Recorder<'_>,
        t_end: f64,
    ) -> Result<u64, String> {
        let m = setup.n + 1;
        let cache = RefCell::new(Cache {
            t: f64::NAN,
            x: vec![f64::NAN; m],
            jac: vec![0.0; m * m],
            work: Vec::new(),
            valid: false,
        });
        let y0 = setup.y0.clone();
        let problem = OdeBuilder::<M>::new()
            .t0(0.0)
            .rtol(setup.rtol)
            .atol(setup.atol.iter().copied())
            .rhs_implicit(
                |x: &[f64], _p: &[f64], t: f64, y: &mut [f64]| setup.rhs(t, x, y),
                |x: &[f64], _p: &[f64], t: f64, v: &[f64], y: &mut [f64]| {
                    let mut c = cache.borrow_mut();
                    let c = &mut *c;
                    if !(c.valid && c.t == t && c.x == x) {
                        setup.jacobian(t, x, &mut c.jac, &mut c.work);
                        c.t = t;
                        c.x.copy_from_slice(x);
                        c.valid = true;
                    }
                    for (i, yi) in y.iter_mut().enumerate() {
                        *yi = c.jac[i * m..(i + 1) * m]
                            .iter()
                            .zip(v)
                            .map(|(a, b)| a * b)
                            .sum();
                    }
                },
            )
            .init(
                move |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&y0),
                m,
            )
            // diffsol's root finding: a step across a sign change of v_rx reports the root,
            // and `drive` moves the state back to it (`state_mut_back`) before going on.
            .root(
                |x: &[f64], _p: &[f64], t: f64, g: &mut [f64]| {
                    g[0] = if setup.reversals {
                        setup.v_rx(t, x)
                    } else {
                        1.0
                    }
                },
                1,
            )
            .build()
            .map_err(|e| format!("diffsol: {e}"))?;
        match peer {
            RustPeer::DiffsolBdf => {
                let solver = problem.bdf::<LS>().map_err(|e| format!("diffsol: {e}"))?;
                drive(solver, setup, rec, t_end)
            }
            RustPeer::DiffsolTrBdf2 => {
                let solver = problem
                    .tr_bdf2::<LS>()
                    .map_err(|e| format!("diffsol: {e}"))?;
                drive(solver, setup, rec, t_end)
            }
            _ => {
                let solver = problem
                    .esdirk34::<LS>()
                    .map_err(|e| format!("diffsol: {e}"))?;
                drive(solver, setup, rec, t_end)
            }
        }
    }

    /// Steps to `t_end` (diffsol's stop time: the last step lands on it), sampling the
    /// solver's interpolant after every step.
    fn drive<'a, Eqn, S>(
        mut solver: S,
        setup: &Setup<'_>,
        rec: &mut Recorder<'_>,
        t_end: f64,
    ) -> Result<u64, String>
    where
        Eqn: OdeEquations<T = f64> + 'a,
        S: OdeSolverMethod<'a, Eqn>,
    {
        let m = setup.n + 1;
        let to_vec = |v: &Eqn::V| (0..m).map(|i| v.get_index(i)).collect::<Vec<f64>>();
        rec.initial(&setup.y0);
        solver
            .set_stop_time(t_end)
            .map_err(|e| format!("diffsol: {e}"))?;
        let mut t_prev = 0.0;
        loop {
            let reason = solver.step().map_err(|e| format!("diffsol: {e}"))?;
            let mut t = solver.state().t;
            let done = matches!(reason, OdeSolverStopReason::TstopReached);
            let root = match reason {
                OdeSolverStopReason::RootFound(t_root, _) if t_root > t_prev && t_root < t => {
                    Some(t_root)
                }
                _ => None,
            };
            if let Some(t_root) = root {
                // Samples up to the reversal from the step's interpolant, then on from it.
                {
                    let solver_ref = &solver;
                    let mut interp = |s: f64| -> Result<Vec<f64>, String> {
                        solver_ref
                            .interpolate(s)
                            .map(|v| to_vec(&v))
                            .map_err(|e| format!("diffsol interpolate: {e}"))
                    };
                    rec.take(t_prev, t_root, false, &mut interp)?;
                }
                solver
                    .state_mut_back(t_root)
                    .map_err(|e| format!("diffsol state_mut_back: {e}"))?;
                rec.reversals += 1;
                t = t_root;
                t_prev = t;
                rec.stepped(t, solver.state().y.get_index(setup.n))?;
                continue;
            }
            let solver_ref = &solver;
            let mut interp = |s: f64| -> Result<Vec<f64>, String> {
                if s == t {
                    Ok(to_vec(solver_ref.state().y))
                } else {
                    solver_ref
                        .interpolate(s)
                        .map(|v| to_vec(&v))
                        .map_err(|e| format!("diffsol interpolate: {e}"))
                }
            };
            rec.take(t_prev, t, false, &mut interp)?;
            t_prev = t;
            rec.stepped(t, solver.state().y.get_index(setup.n))?;
            if done {
                break;
            }
        }
        Ok(solver.get_statistics().number_of_steps as u64)
    }
}

/// The `differential-equations` peer (Radau5). The state is a fixed-size array `[f64; M]`
/// (M = dim + 1, dispatched at run time): the crate's Radau5 (0.7.0) starts its Newton
/// iteration from `Y::zeros()`, which for a `Vec<f64>` state is empty and panics
/// ("State length mismatch"); arrays are also what the crate's examples use.
mod de {
    use super::{locate, Recorder, RustPeer, Setup};
    use differential_equations::control::ControlFlag;
    use differential_equations::error::Error;
    use differential_equations::interpolate::Interpolation;
    use differential_equations::linalg::Matrix;
    use differential_equations::methods::{ExplicitRungeKutta, ImplicitRungeKutta};
    use differential_equations::ode::{solve_ode, ODE};
    use differential_equations::solout::Solout;
    use differential_equations::solution::Solution;
    use differential_equations::tolerance::Tolerance;
    use std::cell::RefCell;

    struct Sys<'s, 'a> {
        setup: &'s Setup<'a>,
        work: RefCell<(Vec<f64>, Vec<f64>)>,
    }

    impl<const M: usize> ODE<f64, [f64; M]> for Sys<'_, '_> {
        fn diff(&self, t: f64, y: &[f64; M], dydt: &mut [f64; M]) {
            self.setup.rhs(t, y, dydt);
        }

        fn jacobian(&self, t: f64, y: &[f64; M], j: &mut Matrix<f64>) {
            let mut w = self.work.borrow_mut();
            let (jac, work) = &mut *w;
            jac.resize(M * M, 0.0);
            self.setup.jacobian(t, y, jac, work);
            for r in 0..M {
                for c in 0..M {
                    j[(r, c)] = jac[r * M + c];
                }
            }
        }
    }

    /// Samples from the method's interpolant after every accepted step, and stops the
    /// integration once the budget is spent, or at a located reversal (the caller restarts
    /// from it).
    struct Out<'r, 'a> {
        rec: &'r mut Recorder<'a>,
        setup: &'r Setup<'a>,
        /// The next call is the one `solve_ode` makes before the first step.
        first: bool,
        /// Whether that call's state is the run's initial state (first segment only).
        record_initial: bool,
        /// State at the end of the last accepted step (or at the located reversal).
        y_last: Vec<f64>,
        /// Sign of `v_rx` after the last accepted step (0 before any nonzero value).
        sign: f64,
        /// The reversal this segment stopped at.
        reversal: Option<f64>,
        failure: Option<String>,
    }

    impl<const M: usize> Solout<f64, [f64; M]> for Out<'_, '_> {
        fn solout<I>(
            &mut self,
            t_curr: f64,
            t_prev: f64,
            y_curr: &[f64; M],
            y_prev: &[f64; M],
            interpolator: &mut I,
            _solution: &mut Solution<f64, [f64; M]>,
        ) -> ControlFlag<f64, [f64; M]>
        where
            I: Interpolation<f64, [f64; M]> + ?Sized,
        {
            if self.first {
                // Called once before the first step, at t0 with the initial state.
                self.first = false;
                if self.record_initial {
                    self.rec.initial(y_curr);
                    self.sign = self.setup.v_rx(t_curr, y_curr).signum();
                }
                return ControlFlag::Continue;
            }
            let mut interp = |s: f64| -> Result<Vec<f64>, String> {
                if s == t_curr {
                    Ok(y_curr.to_vec())
                } else {
                    interpolator
                        .interpolate(s)
                        .map(|y| y.to_vec())
                        .map_err(|e| describe(&e))
                }
            };
            let r = (|| {
                let g1 = self.setup.v_rx(t_curr, y_curr);
                let mut t_stop = t_curr;
                if self.setup.reversals && g1 != 0.0 && self.sign != 0.0 && g1.signum() != self.sign
                {
                    // g at the step's start; at a restart point v_rx may be zero or of the
                    // old sign by rounding: the bracket's start then counts with the sign
                    // tracked from the step that located the last reversal.
                    let g0 = self.setup.v_rx(t_prev, y_prev);
                    let g0 = if g0.signum() == self.sign && g0 != 0.0 {
                        g0
                    } else {
                        self.sign * f64::MIN_POSITIVE
                    };
                    let setup = self.setup;
                    t_stop = locate(t_prev, g0, t_curr, g1, &mut |s| {
                        Ok(setup.v_rx(s, &interp(s)?))
                    })?;
                    self.reversal = Some(t_stop);
                }
                if g1 != 0.0 {
                    self.sign = g1.signum();
                }
                self.rec.take(t_prev, t_stop, false, &mut interp)?;
                let y = interp(t_stop)?;
                self.rec.stepped(t_stop, y[M - 1])?;
                self.y_last = y;
                Ok::<(), String>(())
            })();
            match r {
                Ok(()) if self.reversal.is_some() => {
                    self.rec.reversals += 1;
                    ControlFlag::Terminate
                }
                Ok(()) => ControlFlag::Continue,
                Err(msg) => {
                    self.failure = Some(msg);
                    ControlFlag::Terminate
                }
            }
        }
    }

    fn describe<const M: usize>(e: &Error<f64, [f64; M]>) -> String {
        let what = match e {
            Error::BadInput { msg } => format!("bad input: {msg}"),
            Error::MaxSteps { t, .. } => format!("maximum number of steps reached at t = {t}"),
            Error::StepSize { t, .. } => format!("step size too small at t = {t}"),
            Error::Stiffness { t, .. } => format!("stiffness detected at t = {t}"),
            Error::OutOfBounds {
                t_interp,
                t_prev,
                t_curr,
            } => format!("interpolation at {t_interp} outside [{t_prev}, {t_curr}]"),
            Error::LinearAlgebra { t, msg, .. } => format!("linear algebra at t = {t}: {msg}"),
            other => format!("{other:?}"),
        };
        format!("differential-equations: {what}")
    }

    pub(super) fn run<'a>(
        peer: RustPeer,
        setup: &Setup<'a>,
        rec: &mut Recorder<'a>,
        t_end: f64,
    ) -> Result<u64, String> {
        match setup.n + 1 {
            2 => run_m::<2>(peer, setup, rec, t_end),
            3 => run_m::<3>(peer, setup, rec, t_end),
            4 => run_m::<4>(peer, setup, rec, t_end),
            5 => run_m::<5>(peer, setup, rec, t_end),
            6 => run_m::<6>(peer, setup, rec, t_end),
            7 => run_m::<7>(peer, setup, rec, t_end),
            8 => run_m::<8>(peer, setup, rec, t_end),
            m => Err(format!(
                "differential-equations peers: augmented dimension {m} not instantiated (2..=8)"
            )),
        }
    }

    fn run_m<'a, const M: usize>(
        peer: RustPeer,
        setup: &Setup<'a>,
        rec: &mut Recorder<'a>,
        t_end: f64,
    ) -> Result<u64, String> {
        let sys = Sys {
            setup,
            work: RefCell::new((Vec::new(), Vec::new())),
        };
        let y0: [f64; M] = setup
            .y0
            .as_slice()
            .try_into()
            .map_err(|_| "state dimension mismatch".to_string())?;
        let mut out = Out {
            rec,
            setup,
            first: true,
            record_initial: true,
            y_last: Vec::with_capacity(M),
            sign: 0.0,
            reversal: None,
            failure: None,
        };
        // Segments end at t_a = t_end − period and t_end, so that Q(t_a) is a step end:
        // DOP853's dense output in this crate (0.7.0) evaluates Hairer's `contd8` with `s` and
        // `1 − s` swapped in its high-order part (interpolation errors ~500× the step-end errors,
        // order ≈ 5 instead of 7, seen on y'' = −y), and Radau5's is the order-3 collocation
        // polynomial. The samples still come from the dense output. With reversal handling a
        // segment also ends at every located sign change of v_rx, and the next starts from the
        // state interpolated there (as with scipy's terminal events).
        let t_a = out.rec.t_a;
        let mut steps = 0;
        let mut y_start = y0;
        let mut t_start = 0.0;
        for t_stop in [t_a, t_end] {
            while t_stop > t_start {
                out.first = true;
                out.reversal = None;
                steps += segment(peer, setup, &sys, t_start, t_stop, &y_start, &mut out)?;
                if out.failure.is_some() {
                    break;
                }
                y_start = out
                    .y_last
                    .as_slice()
                    .try_into()
                    .map_err(|_| "differential-equations: no step taken".to_string())?;
                out.record_initial = false;
                match out.reversal {
                    // A reversal within rounding of the segment's end: the segment is done.
                    Some(t_r) if t_stop - t_r > 1e-12 * t_stop.abs().max(1e-300) => t_start = t_r,
                    _ => {
                        if out.rec.q_a.is_none() && t_stop == t_a {
                            out.rec.q_a = Some(out.y_last[M - 1]);
                        }
                        t_start = t_stop
                    }
                }
            }
            if out.failure.is_some() {
                break;
            }
        }
        match out.failure {
            Some(msg) => Err(msg),
            None => Ok(steps),
        }
    }

    /// One `solve_ode` call from `t0` to `tf`; accepted steps.
    fn segment<const M: usize>(
        peer: RustPeer,
        setup: &Setup<'_>,
        sys: &Sys<'_, '_>,
        t0: f64,
        tf: f64,
        y0: &[f64; M],
        out: &mut Out<'_, '_>,
    ) -> Result<u64, String> {
        let rtol = Tolerance::Scalar(setup.rtol);
        let atol = Tolerance::Vector(setup.atol.clone());
        // The budget, not a step count, bounds the work.
        let max_steps = usize::MAX / 2;
        let result = match peer {
            RustPeer::DeDop853 | RustPeer::DeDop853Reversals => {
                let mut method = ExplicitRungeKutta::dop853()
                    .rtol(rtol)
                    .atol(atol)
                    .h_max(setup.h_max)
                    .max_steps(max_steps);
                solve_ode(&mut method, sys, t0, tf, y0, out)
            }
            _ => {
                let mut method = ImplicitRungeKutta::radau5()
                    .rtol(rtol)
                    .atol(atol)
                    .h_max(setup.h_max)
                    .max_steps(max_steps);
                solve_ode(&mut method, sys, t0, tf, y0, out)
            }
        };
        if out.failure.is_some() {
            return Ok(0);
        }
        let sol = result.map_err(|e| describe(&e))?;
        Ok(sol.steps.accepted as u64)
    }
}
