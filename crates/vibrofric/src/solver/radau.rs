//! Radau IIA, 3 stages, order 5 (Hairer & Wanner, *Solving ODEs II*, §IV.8, code RADAU5), on
//! fixed-size `nalgebra` vectors: no heap allocation per step, deterministic.
//!
//! It departs from RADAU5 where the contact's structure asks for it:
//! - Newton can use the Jacobian at each stage (a 3N×3N system, N ≤ 6) instead of one frozen at
//!   the step start. The contact's stiffness `|v_r(t)|/s_ss` varies by orders of magnitude inside
//!   a step; with stage Jacobians the deformation equation, linear in `s` for a given `v_r(t)`,
//!   converges in one iteration whatever the stiffness, where a frozen Jacobian diverges. A 1-D
//!   state always does so (its 3×3 system costs no more); larger states use RADAU5's simplified
//!   iteration (one Jacobian, split by the eigenvectors of the Butcher matrix into a real and a
//!   complex N×N system, 2–3× cheaper per attempt), stop it only on a measured contraction, and
//!   fall back to stage Jacobians for a few steps whenever it fails.
//! - It lands exactly on the requested end time (every call is a communication point or a
//!   window boundary).
//! - It locates sign changes of the system's switching functions (kinks or jumps of the
//!   right-hand side, such as `|v_r|` at `v_r = 0`) on the collocation polynomial, ends a step
//!   on each and restarts there, instead of stepping blindly over the kink.
//! - It hands every accepted step's stage values to the caller, so that quadratures (the mean
//!   friction force) are integrated with the collocation's order.
//! - It projects each accepted state onto the system's invariant set.

use nalgebra::{Complex, SMatrix, SVector};

use super::lu::{DenseLu, FixedLu};

/// Most switching functions a system may have.
pub const MAX_SWITCH: usize = 2;
/// Most integrands a system hands to the step's quadrature.
pub const MAX_QUAD: usize = 2;
/// The integrands of a quadrature, or their integrals over a step.
pub type Quad = [f64; MAX_QUAD];

/// An ODE `dy/dt = f(t, y)` of fixed dimension `N` (at most [`MAX_DIM`]).
pub trait OdeSystem<const N: usize> {
    fn rhs(&self, t: f64, y: &SVector<f64, N>) -> SVector<f64, N>;
    /// Natural magnitude of each component: the absolute tolerance is `rtol·scale`.
    fn scale(&self) -> SVector<f64, N>;
    /// Number of switching functions in use (0 to [`MAX_SWITCH`]).
    fn n_switch(&self) -> usize {
        0
    }
    /// Functions whose sign changes mark kinks or jumps of `rhs`; only the first
    /// [`OdeSystem::n_switch`] entries are read.
    fn switch(&self, _t: f64, _y: &SVector<f64, N>) -> [f64; MAX_SWITCH] {
        [1.0; MAX_SWITCH]
    }
    /// Natural magnitude of each switching function. A sign change that stays within
    /// `rtol·scale` of zero is no event: the kink it marks is below the tolerance, and the
    /// error control steps over it (a stuck contact whose velocity hovers at 1e-19 m/s does
    /// not chatter). Zero (the default): every sign change is an event.
    fn switch_scale(&self) -> [f64; MAX_SWITCH] {
        [0.0; MAX_SWITCH]
    }
    /// Projects a state onto the invariant set of the exact flow (no-op by default).
    fn project(&self, _t: f64, _y: &mut SVector<f64, N>) {}
    /// The Jacobian `∂f/∂y` at `(t, y)`, if the system has it in closed form; otherwise the
    /// integrator uses forward differences.
    fn jacobian(&self, _t: f64, _y: &SVector<f64, N>) -> Option<SMatrix<f64, N, N>> {
        None
    }

    /// The switching functions and the quadrature's integrand together, for systems that
    /// share work between them.
    fn observe(&self, t: f64, y: &SVector<f64, N>) -> ([f64; MAX_SWITCH], Quad) {
        (self.switch(t, y), self.quadrature(t, y))
    }

    /// `f(t, y)` and the Jacobian together, for systems that share work between them.
    fn rhs_jacobian(
        &self,
        t: f64,
        y: &SVector<f64, N>,
    ) -> (SVector<f64, N>, Option<SMatrix<f64, N, N>>) {
        (self.rhs(t, y), self.jacobian(t, y))
    }
    /// Up to [`MAX_QUAD`] integrands `q(t, y)` whose integrals over each step the integrator
    /// returns in [`Step::quad`], with their errors bounded like the state's.
    fn quadrature(&self, _t: f64, _y: &SVector<f64, N>) -> Quad {
        [0.0; MAX_QUAD]
    }
    /// Natural magnitude of every `q`: the error of each integral over a step of length `h` is
    /// kept below `rtol·scale·h`. Zero: no quadrature.
    fn quadrature_scale(&self) -> f64 {
        0.0
    }
}

/// Largest state dimension.
pub const MAX_DIM: usize = 6;

/// Why the integrator stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SolverError {
    /// The step size fell below the resolution of the time axis.
    StepSizeTooSmall { t: f64, h: f64 },
    /// The right-hand side returned NaN or infinity.
    NonFinite { t: f64 },
    /// The caller's budget of steps ran out at `t` (`limit` steps).
    WorkLimit { t: f64, limit: f64 },
}

impl std::fmt::Display for SolverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SolverError::StepSizeTooSmall { t, h } => {
                write!(f, "integrator step size {h:e} too small at t = {t}")
            }
            SolverError::NonFinite { t } => {
                write!(f, "right-hand side not finite at t = {t}")
            }
            SolverError::WorkLimit { t, limit } => write!(
                f,
                "more than max_steps = {limit:e} integrator steps in this communication step, at t = {t} since its start: use shorter communication steps, or raise the parameter max_steps"
            ),
        }
    }
}

impl std::error::Error for SolverError {}

/// Work counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolverStats {
    pub steps: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
    pub jacobians: u64,
    pub events: u64,
}

/// One accepted step, as handed to the caller: stage `i` lies at `t + C[i]·h`, and the
/// collocation quadrature of a function `g` over the step is `h·Σ B[i]·g(stage i)`.
pub struct Step<'a, const N: usize> {
    pub t: f64,
    pub h: f64,
    pub stages: &'a [SVector<f64, N>; 3],
    /// `∫ q dt` over the step (see [`OdeSystem::quadrature`]).
    pub quad: Quad,
}

const SQ6: f64 = 2.449_489_742_783_178;
/// Collocation nodes.
pub const C: [f64; 3] = [(4.0 - SQ6) / 10.0, (4.0 + SQ6) / 10.0, 1.0];
/// Quadrature weights (= last row of the Butcher matrix: the method is stiffly accurate).
pub const B: [f64; 3] = [(16.0 - SQ6) / 36.0, (16.0 + SQ6) / 36.0, 1.0 / 9.0];
/// Butcher matrix.
const A: [[f64; 3]; 3] = [
    [
        (88.0 - 7.0 * SQ6) / 360.0,
        (296.0 - 169.0 * SQ6) / 1800.0,
        (-2.0 + 3.0 * SQ6) / 225.0,
    ],
    [
        (296.0 + 169.0 * SQ6) / 1800.0,
        (88.0 + 7.0 * SQ6) / 360.0,
        (-2.0 - 3.0 * SQ6) / 225.0,
    ],
    [B[0], B[1], B[2]],
];

const C1M1: f64 = C[0] - 1.0;
const C2M1: f64 = C[1] - 1.0;
const C1MC2: f64 = C[0] - C[1];
/// Coefficients of the embedded error estimate.
const DD1: f64 = -(13.0 + 7.0 * SQ6) / 3.0;
const DD2: f64 = (-13.0 + 7.0 * SQ6) / 3.0;
const DD3: f64 = -1.0 / 3.0;
/// Real eigenvalue of the inverse Butcher matrix: 30/(6 + 81^(1/3) − 9^(1/3)).
const U1: f64 = 3.637_834_252_744_496;

/// Complex eigenvalue `ALPH ± i·BETA` of the inverse Butcher matrix.
const ALPH: f64 = 2.681_082_873_627_752;
const BETA: f64 = 3.050_430_199_247_411;
/// Eigenvectors `T` of the inverse Butcher matrix (`A⁻¹·T = T·diag(U1, [[ALPH, −BETA],
/// [BETA, ALPH]])`, RADAU5's normalisation) and `TI = T⁻¹`: they split the Newton system
/// into one real and one complex `N×N` system.
const T: [[f64; 3]; 3] = [
    [
        9.123_239_487_089_294e-2,
        -0.141_255_295_020_954_2,
        -3.002_919_410_514_742_4e-2,
    ],
    [
        0.241_717_932_707_107,
        0.204_129_352_293_799_9,
        0.382_942_112_757_261_9,
    ],
    [0.966_048_182_615_093, 1.0, 0.0],
];
const TI: [[f64; 3]; 3] = [
    [
        4.325_579_890_063_155,
        0.339_199_251_815_809_9,
        0.541_770_539_935_874_9,
    ],
    [
        -4.178_718_591_551_905,
        -0.327_682_820_761_062_4,
        0.476_623_554_500_550_5,
    ],
    [
        -0.502_872_634_945_786_9,
        2.571_926_949_855_605,
        -0.596_039_204_828_224_9,
    ],
];

const NIT: u32 = 7;
/// Steps taken with stage Jacobians after the simplified iteration failed to converge.
const FULL_STEPS_AFTER_FAILURE: u32 = 4;
const SAFE: f64 = 0.9;
const FAC_MAX_GROW: f64 = 8.0;
const FAC_MAX_SHRINK: f64 = 0.2;

/// The Newton matrix of the stage-Jacobian iteration (on the stack, sized for the largest
/// state), refilled entry by entry at every attempt: scratch space, not integrator state.
#[derive(Clone, Debug)]
pub struct Workspace {
    n: usize,
    m: DenseLu,
}

impl Workspace {
    pub fn new(n: usize) -> Self {
        Workspace {
            n,
            m: DenseLu::zeros(3 * n),
        }
    }
}

/// The integrator's complete state. `Copy`, so that a snapshot is a plain copy.
#[derive(Clone, Copy, Debug)]
pub struct Radau5<const N: usize> {
    pub t: f64,
    pub y: SVector<f64, N>,
    /// Relative tolerance requested by the user.
    tol: f64,
    /// RADAU5's internal tolerance `0.1·tol^(2/3)`, calibrated so that the global error is of
    /// the order of `tol`.
    rtol: f64,
    fnewt: f64,
    ln_fnewt: f64,
    /// Proposed next step size (0: not yet chosen).
    h: f64,
    h_old: f64,
    h_acc: f64,
    err_acc: f64,
    /// Newton's contraction estimate `theta/(1 − theta)` from the last iteration that measured
    /// it, relaxed towards 1 by `x ↦ x^0.8` at every attempt since (RADAU5). Kept as
    /// `ln(faccon)` and the accumulated exponent `0.8^k`, so that relaxing is one
    /// multiplication and the stopping test one logarithm instead of a power.
    ln_faccon: f64,
    faccon_exp: f64,
    first: bool,
    /// Dense-output coefficients of the last accepted step (valid when `has_cont`).
    cont: [SVector<f64, N>; 3],
    has_cont: bool,
    /// Step size to restart with after an event, learnt from the previous restart.
    h_event: f64,
    /// True while the first step after an event has not been accepted yet.
    after_event: bool,
    /// Sign of each switching function on the current side of the last event (0: unknown).
    switch_sign: [f64; MAX_SWITCH],
    n_accept: u64,
    /// Accepted steps still to take with stage Jacobians after the simplified Newton failed.
    full_left: u32,
    pub stats: SolverStats,
    /// Attempts (accepted and rejected) after which [`Radau5::integrate_with`] stops with
    /// [`SolverError::WorkLimit`], counted like `stats` (not part of the saved state).
    pub step_limit: u64,
}

impl<const N: usize> Radau5<N> {
    pub fn new(t: f64, y: SVector<f64, N>, tol: f64) -> Self {
        assert!(N <= MAX_DIM, "state dimension {N} above {MAX_DIM}");
        let rtol = 0.1 * tol.powf(2.0 / 3.0);
        let fnewt = (10.0 * f64::EPSILON / rtol).max(rtol.sqrt().min(0.03));
        Radau5 {
            t,
            y,
            tol,
            rtol,
            fnewt,
            ln_fnewt: fnewt.ln(),
            h: 0.0,
            h_old: 0.0,
            h_acc: 0.0,
            err_acc: 1e-2,
            ln_faccon: 0.0,
            faccon_exp: 1.0,
            first: true,
            cont: [SVector::zeros(); 3],
            has_cont: false,
            h_event: 0.0,
            after_event: false,
            switch_sign: [0.0; MAX_SWITCH],
            n_accept: 0,
            full_left: 0,
            stats: SolverStats::default(),
            step_limit: u64::MAX,
        }
    }

    pub fn tolerance(&self) -> f64 {
        self.tol
    }

    /// Tells the integrator that the right-hand side may have jumped at the current time (an
    /// input changed): the next step restarts without extrapolating the previous one.
    pub fn restart(&mut self) {
        self.first = true;
        self.switch_sign = [0.0; MAX_SWITCH];
    }

    /// Replaces the state at the current time (after a projection or a parameter change).
    pub fn set_state(&mut self, y: SVector<f64, N>) {
        self.y = y;
        self.restart();
    }

    fn scal(&self, y: &SVector<f64, N>, nominal: &SVector<f64, N>) -> SVector<f64, N> {
        SVector::from_fn(|i, _| self.rtol * (nominal[i] + y[i].abs()))
    }

    /// `f(t, y)` and the system's Jacobian there, or forward differences.
    fn rhs_jacobian<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &SVector<f64, N>,
        nominal: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        self.stats.jacobians += 1;
        self.stats.rhs_evals += 1;
        let (f, jac) = sys.rhs_jacobian(t, y);
        if let Some(jac) = jac {
            return (f, jac);
        }
        let mut jac = SMatrix::<f64, N, N>::zeros();
        let mut yp = *y;
        for j in 0..N {
            let yj = yp[j];
            let delta = f64::EPSILON.sqrt() * yj.abs().max(nominal[j]);
            yp[j] = yj + delta;
            let f1 = sys.rhs(t, &yp);
            yp[j] = yj;
            jac.set_column(j, &((f1 - f) / delta));
        }
        self.stats.rhs_evals += N as u64;
        (f, jac)
    }

    /// RADAU5's stopping test `faccon·dyno ≤ fnewt` with the relaxed `faccon`, in logarithms.
    #[inline(always)]
    fn newton_converged(&self, dyno: f64) -> bool {
        self.faccon_exp * self.ln_faccon + dyno.ln() <= self.ln_fnewt
    }

    /// Evaluates the dense output of a step ending in `y_new` at fraction `theta` of it.
    fn dense(y_new: &SVector<f64, N>, cont: &[SVector<f64, N>; 3], theta: f64) -> SVector<f64, N> {
        let s = theta - 1.0;
        y_new + (cont[0] + (cont[1] + cont[2] * (s - C1M1)) * (s - C2M1)) * s
    }

    /// Integrates exactly to `t_end` (> current time), calling `on_step` for every accepted step.
    /// `h_max` bounds the step size (so that no pair of switching events hides in one step).
    pub fn integrate<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t_end: f64,
        h_max: f64,
        on_step: impl FnMut(&Step<N>),
    ) -> Result<(), SolverError> {
        self.integrate_with(&mut Workspace::new(N), sys, t_end, h_max, on_step)
    }

    /// [`Radau5::integrate`] with the linear-algebra workspace supplied by the caller, so that
    /// short calls (small communication steps) do not clear it every time.
    pub fn integrate_with<S: OdeSystem<N>>(
        &mut self,
        work: &mut Workspace,
        sys: &S,
        t_end: f64,
        h_max: f64,
        mut on_step: impl FnMut(&Step<N>),
    ) -> Result<(), SolverError> {
        assert_eq!(work.n, N, "workspace for another dimension");
        let m = &mut work.m;
        // Jacobian at the current step start, for the simplified Newton iteration.
        let mut jac_start: Option<SMatrix<f64, N, N>> = None;
        let nominal = sys.scale();
        let q_scale = sys.quadrature_scale();
        let n_switch = sys.n_switch().min(MAX_SWITCH);
        let band = sys.switch_scale().map(|v| self.rtol * v);
        if n_switch > 0 {
            let g = sys.switch(self.t, &self.y);
            for k in 0..n_switch {
                if self.switch_sign[k] == 0.0 || g[k].abs() > band[k] {
                    // Zero counts as the positive side until the function leaves it.
                    self.switch_sign[k] = if g[k] < 0.0 { -1.0 } else { 1.0 };
                }
            }
        }
        let mut f0 = sys.rhs(self.t, &self.y);
        let mut q0 = sys.quadrature(self.t, &self.y);
        self.stats.rhs_evals += 1;
        if !f0.iter().all(|v| v.is_finite()) {
            return Err(SolverError::NonFinite { t: self.t });
        }
        if self.h <= 0.0 {
            self.h = self.initial_step(&f0, &nominal, t_end - self.t);
        }
        let mut reject = false;
        // An event the current attempt must end on (time, function), found on a previous
        // attempt's dense output.
        let mut event_target: Option<(f64, usize)> = None;

        while self.t < t_end {
            if self.stats.steps + self.stats.rejected >= self.step_limit {
                return Err(SolverError::WorkLimit {
                    t: self.t,
                    limit: self.step_limit as f64,
                });
            }
            // Choose the step, landing exactly on an event or on t_end.
            let mut h = self.h.min(h_max);
            let mut h_unclipped = h;
            let mut target = None;
            if let Some((te, _)) = event_target {
                h_unclipped = self.h;
                target = Some(te);
            } else if self.t + 1.0001 * h >= t_end {
                target = Some(t_end);
            } else if h <= 10.0 * self.t.abs() * f64::EPSILON {
                return Err(SolverError::StepSizeTooSmall { t: self.t, h });
            }
            let t_new = target.unwrap_or(self.t + h);
            h = t_new - self.t;

            let scal = self.scal(&self.y, &nominal);

            // Starting values: the previous step's collocation polynomial, extrapolated.
            let mut z = [SVector::<f64, N>::zeros(); 3];
            if !self.first && self.has_cont {
                let c3q = h / self.h_old;
                for (i, zi) in z.iter_mut().enumerate() {
                    let cq = C[i] * c3q;
                    *zi = (self.cont[0]
                        + (self.cont[1] + self.cont[2] * (cq - C1M1)) * (cq - C2M1))
                        * cq;
                }
            }

            // Newton iteration matrix. Two kinds:
            // - simplified (RADAU5's): one Jacobian J at the step start, and the transformation
            //   T splits I − h·(A ⊗ J) into a real and a complex N×N system;
            // - stage Jacobians: I − h·(A ⊗ J_j) with J_j at each stage, a 3N×3N system. It
            //   converges where J changes by orders of magnitude within the step (across a
            //   sign change of v_r), where the simplified iteration fails.
            // A 1-D state always takes stage Jacobians (its 3×3 system is as cheap); larger
            // states try the simplified iteration and fall back for a few steps when it fails.
            let simplified = N > 1 && self.full_left == 0;
            let mut jac = [SMatrix::<f64, N, N>::zeros(); 3];
            let mut fz = [SVector::<f64, N>::zeros(); 3];
            let mut split = None;
            if simplified {
                let j0 = match jac_start {
                    Some(j) => j,
                    None => {
                        let (t, y) = (self.t, self.y);
                        let j = self.rhs_jacobian(sys, t, &y, &nominal).1;
                        jac_start = Some(j);
                        j
                    }
                };
                jac = [j0; 3];
                for i in 0..3 {
                    fz[i] = sys.rhs(self.t + C[i] * h, &(self.y + z[i]));
                }
                self.stats.rhs_evals += 3;
                let e_real = FixedLu::new(std::array::from_fn(|r| {
                    std::array::from_fn(|c| (if r == c { U1 / h } else { 0.0 }) - j0[(r, c)])
                }));
                let e_complex = FixedLu::new(std::array::from_fn(|r| {
                    std::array::from_fn(|c| {
                        let d = if r == c {
                            Complex::new(ALPH / h, BETA / h)
                        } else {
                            Complex::ZERO
                        };
                        d - Complex::new(j0[(r, c)], 0.0)
                    })
                }));
                split = Some((e_real, e_complex));
            } else {
                for i in 0..3 {
                    let (ti, yi) = (self.t + C[i] * h, self.y + z[i]);
                    (fz[i], jac[i]) = self.rhs_jacobian(sys, ti, &yi, &nominal);
                }
                for i in 0..3 {
                    for j in 0..3 {
                        for r in 0..N {
                            for c in 0..N {
                                let id = if i == j && r == c { 1.0 } else { 0.0 };
                                m.set(i * N + r, j * N + c, id - h * A[i][j] * jac[j][(r, c)]);
                            }
                        }
                    }
                }
                m.factor(3 * N);
            }

            // Newton iteration.
            self.faccon_exp *= 0.8;
            let mut dyno_old = 0.0;
            let mut thq_old = 0.0;
            let mut newt = 0;
            let mut shrink = 0.5;
            let converged = loop {
                if newt >= NIT {
                    break false;
                }
                if newt > 0 {
                    for i in 0..3 {
                        fz[i] = sys.rhs(self.t + C[i] * h, &(self.y + z[i]));
                    }
                    self.stats.rhs_evals += 3;
                }
                if !fz.iter().all(|f| f.iter().all(|v| v.is_finite())) {
                    break false;
                }
                let dz: [SVector<f64, N>; 3] = if let Some((e_real, e_complex)) = &split {
                    // In W = (T⁻¹ ⊗ I)·Z the system reads (Λ/h ⊗ I − I ⊗ J)·ΔW =
                    // (T⁻¹ ⊗ I)·F − (Λ/h ⊗ I)·W, Λ = diag(U1, [[ALPH, −BETA], [BETA, ALPH]]).
                    let tf = |m: &[[f64; 3]; 3], v: &[SVector<f64, N>; 3], k: usize| {
                        v[0] * m[k][0] + v[1] * m[k][1] + v[2] * m[k][2]
                    };
                    let (a, w) = (
                        [tf(&TI, &fz, 0), tf(&TI, &fz, 1), tf(&TI, &fz, 2)],
                        [tf(&TI, &z, 0), tf(&TI, &z, 1), tf(&TI, &z, 2)],
                    );
                    let r1 = a[0] - w[0] * (U1 / h);
                    let r2 = a[1] - w[1] * (ALPH / h) + w[2] * (BETA / h);
                    let r3 = a[2] - w[1] * (BETA / h) - w[2] * (ALPH / h);
                    let mut dw0: [f64; N] = r1.into();
                    let mut dw12: [Complex<f64>; N] =
                        std::array::from_fn(|i| Complex::new(r2[i], r3[i]));
                    if !(e_real.solve(&mut dw0) && e_complex.solve(&mut dw12)) {
                        break false;
                    }
                    let dw = [
                        SVector::from(dw0),
                        SVector::from_fn(|i, _| dw12[i].re),
                        SVector::from_fn(|i, _| dw12[i].im),
                    ];
                    [tf(&T, &dw, 0), tf(&T, &dw, 1), tf(&T, &dw, 2)]
                } else {
                    // Residual −(Z_i − h·Σ_j a_ij·F_j), solved for the update.
                    let mut rhs = [0.0f64; 3 * MAX_DIM];
                    for i in 0..3 {
                        let r = (fz[0] * A[i][0] + fz[1] * A[i][1] + fz[2] * A[i][2]) * h - z[i];
                        rhs[i * N..(i + 1) * N].copy_from_slice(r.as_slice());
                    }
                    if !m.solve(&mut rhs[..3 * N]) {
                        break false;
                    }
                    std::array::from_fn(|i| SVector::from_column_slice(&rhs[i * N..(i + 1) * N]))
                };
                newt += 1;
                let dyno = ((0..3)
                    .map(|k| dz[k].component_div(&scal).norm_squared())
                    .sum::<f64>()
                    / (3 * N) as f64)
                    .sqrt();
                if newt > 1 && newt < NIT {
                    let thq = dyno / dyno_old;
                    let theta = if newt == 2 {
                        thq
                    } else {
                        (thq * thq_old).sqrt()
                    };
                    thq_old = thq;
                    if theta < 0.99 {
                        let faccon = (theta / (1.0 - theta)).max(f64::EPSILON);
                        self.ln_faccon = faccon.ln();
                        self.faccon_exp = 1.0;
                        let dyth = faccon * dyno * theta.powi((NIT - 1 - newt) as i32) / self.fnewt;
                        if dyth >= 1.0 {
                            // Convergence too slow for this step: shrink it.
                            let qnewt = dyth.clamp(1e-4, 20.0);
                            shrink = 0.8 * qnewt.powf(-1.0 / (4.0 + (NIT - 1 - newt) as f64));
                            break false;
                        }
                    } else {
                        break false;
                    }
                }
                dyno_old = dyno.max(f64::EPSILON);
                for k in 0..3 {
                    z[k] += dz[k];
                }
                // The simplified iteration stops only on a contraction it has measured: its
                // Jacobian is frozen at the step start, and an estimate carried over from earlier
                // steps once accepted a half-converged iterate at a reversal (planar Dupont,
                // tolerance 1e-10: an error of 6e-5·F_C).
                if (newt > 1 || !simplified) && self.newton_converged(dyno) {
                    break true;
                }
            };
            if !converged && simplified {
                // Retake the same step with stage Jacobians.
                self.full_left = FULL_STEPS_AFTER_FAILURE;
                self.stats.rejected += 1;
                continue;
            }
            if !converged {
                self.h = h * shrink;
                self.stats.rejected += 1;
                reject = true;
                event_target = None;
                continue;
            }

            // Newton converged: compute the dense output and look for switching events first. A
            // step across a kink has a meaningless error estimate; it is retaken to end on it.
            let y_new = self.y + z[2];
            let cont0 = (z[1] - z[2]) / C2M1;
            let ak = (z[0] - z[1]) / C1MC2;
            let acont3 = (ak - z[0] / C[0]) / C[1];
            let cont1 = (ak - cont0) / C1M1;
            let cont = [cont0, cont1, cont1 - acont3];

            // Switching functions and the quadrature's integrand at the stages.
            let observed: [([f64; MAX_SWITCH], Quad); 3] = if n_switch > 0 || q_scale > 0.0 {
                std::array::from_fn(|i| sys.observe(self.t + C[i] * h, &(self.y + z[i])))
            } else {
                [([0.0; MAX_SWITCH], [0.0; MAX_QUAD]); 3]
            };

            // Switching events.
            let mut event_here = None;
            if n_switch > 0 {
                if let Some((_, k)) = event_target {
                    event_here = Some(k);
                } else if let Some((theta_e, k)) =
                    self.find_event(sys, n_switch, h, &observed, &y_new, &cont)
                {
                    if theta_e < 1.0 - 1e-12 {
                        let te = self.t + theta_e * h;
                        if te > self.t {
                            event_target = Some((te, k));
                            self.h = h;
                            continue;
                        }
                        // The crossing is at the current time: flip and restart.
                        self.switch_sign[k] = -self.switch_sign[k];
                        self.stats.events += 1;
                        self.first = true;
                        continue;
                    }
                    event_here = Some(k);
                }
            }

            // Error estimate (Hairer & Wanner IV.8). Its filter `(U1/h − J)⁻¹` needs only an
            // approximate Jacobian (RADAU5 keeps one for many steps): the first stage's.
            let e1 = match split {
                Some((e_real, _)) => e_real,
                None => FixedLu::new(std::array::from_fn(|r| {
                    std::array::from_fn(|c| (if r == c { U1 / h } else { 0.0 }) - jac[0][(r, c)])
                })),
            };
            let solve = |v: SVector<f64, N>| {
                let mut b: [f64; N] = v.into();
                e1.solve(&mut b);
                SVector::from(b)
            };
            let f2 = (z[0] * DD1 + z[1] * DD2 + z[2] * DD3) / h;
            let est = solve(f0 + f2);
            let mut err = rms(&est, &scal).max(1e-10);
            if err >= 1.0 && (self.first || reject) {
                let fy = sys.rhs(self.t, &(self.y + est));
                self.stats.rhs_evals += 1;
                let est2 = solve(fy + f2);
                err = rms(&est2, &scal).max(1e-10);
            }
            // The quadrature: collocation integral and its embedded error estimate.
            let mut quad = [0.0; MAX_QUAD];
            if q_scale > 0.0 {
                for k in 0..MAX_QUAD {
                    let q: [f64; 3] = std::array::from_fn(|i| observed[i].1[k]);
                    let zq: [f64; 3] = std::array::from_fn(|i| {
                        h * (A[i][0] * q[0] + A[i][1] * q[1] + A[i][2] * q[2])
                    });
                    quad[k] = zq[2];
                    let est_q = (h / U1) * (q0[k] + (DD1 * zq[0] + DD2 * zq[1] + DD3 * zq[2]) / h);
                    err = err.max(est_q.abs() / (self.rtol * q_scale * h));
                }
            }
            if !err.is_finite() {
                err = 1e10;
            }
            let fac = SAFE.min(SAFE * (1.0 + 2.0 * NIT as f64) / (newt as f64 + 2.0 * NIT as f64));
            let mut quot =
                (err.sqrt().sqrt() / fac).clamp(1.0 / FAC_MAX_GROW, 1.0 / FAC_MAX_SHRINK);
            let mut h_new = h / quot;

            if err >= 1.0 {
                self.stats.rejected += 1;
                reject = true;
                event_target = None;
                self.h = if self.first { 0.1 * h } else { h_new };
                continue;
            }

            // Accept.
            if self.n_accept > 0 && !self.first {
                let facgus = (self.h_acc / h) * (err * err / self.err_acc).sqrt().sqrt() / SAFE;
                let facgus = facgus.clamp(1.0 / FAC_MAX_GROW, 1.0 / FAC_MAX_SHRINK);
                quot = quot.max(facgus);
                h_new = h / quot;
            }
            self.h_acc = h;
            self.err_acc = err.max(1e-2);
            self.n_accept += 1;
            self.stats.steps += 1;
            let stages = [self.y + z[0], self.y + z[1], y_new];
            on_step(&Step {
                t: self.t,
                h,
                stages: &stages,
                quad,
            });
            let mut y_acc = y_new;
            sys.project(t_new, &mut y_acc);
            self.y = y_acc;
            self.t = t_new;
            self.cont = cont;
            self.has_cont = true;
            self.h_old = h;
            if reject {
                h_new = h_new.min(h);
            }
            if target.is_some() && h_unclipped > h {
                // A clipped step says little about the natural step size.
                h_new = h_new.max(h_unclipped);
            }
            if self.after_event {
                // Learn the restart step: what this first step after the event proposes next.
                self.h_event = h_new;
                self.after_event = false;
            }
            self.first = false;
            reject = false;
            self.h = h_new;
            jac_start = None;
            if !simplified {
                self.full_left = self.full_left.saturating_sub(1);
            }
            if let Some(k) = event_here {
                event_target = None;
                self.switch_sign[k] = -self.switch_sign[k];
                self.stats.events += 1;
                self.first = true;
                self.after_event = true;
                if self.h_event > 0.0 {
                    self.h = self.h_event;
                }
            }
            f0 = sys.rhs(self.t, &self.y);
            q0 = sys.quadrature(self.t, &self.y);
            self.stats.rhs_evals += 1;
        }
        Ok(())
    }

    /// The first sign change of a switching function inside the attempted step, as a fraction
    /// of the step and the function's index, located on the collocation polynomial.
    fn find_event<S: OdeSystem<N>>(
        &self,
        sys: &S,
        n_switch: usize,
        h: f64,
        observed: &[([f64; MAX_SWITCH], Quad); 3],
        y_new: &SVector<f64, N>,
        cont: &[SVector<f64, N>; 3],
    ) -> Option<(f64, usize)> {
        let band = sys.switch_scale().map(|v| self.rtol * v);
        // Nodes: the stages (exact stage values); the last stage is the step's end.
        let mut a = 0.0;
        let mut ga = [0.0f64; MAX_SWITCH];
        for (i, &c) in C.iter().enumerate() {
            let gc = observed[i].0;
            let mut best: Option<(f64, usize)> = None;
            for k in 0..n_switch {
                if gc[k] * self.switch_sign[k] < -band[k] {
                    let sign = self.switch_sign[k];
                    let g = |theta: f64| {
                        let y = if theta == 1.0 {
                            *y_new
                        } else {
                            Self::dense(y_new, cont, theta)
                        };
                        sys.switch(self.t + theta * h, &y)[k] * sign
                    };
                    let ga_k = (ga[k] * sign).max(0.0);
                    let theta = illinois(&g, a, ga_k, c, gc[k] * sign);
                    if best.is_none_or(|(b, _)| theta < b) {
                        best = Some((theta, k));
                    }
                }
            }
            if best.is_some() {
                return best;
            }
            a = c;
            ga = gc;
        }
        None
    }

    /// A first step from the size of the derivative, with the usual order scaling.
    fn initial_step(&self, f0: &SVector<f64, N>, nominal: &SVector<f64, N>, span: f64) -> f64 {
        let d1 = rms(f0, &nominal.map(|v| v.max(f64::MIN_POSITIVE)));
        let h = if d1 > 0.0 { 1e-2 / d1 } else { span };
        (h * self.tol.powf(0.2))
            .min(span)
            .max(1e-14 * (1.0 + self.t.abs()))
    }

    /// Appends the complete state to `out` as numbers.
    pub fn save(&self, out: &mut Vec<f64>) {
        out.extend_from_slice(&[self.t, self.tol]);
        out.extend(self.y.iter());
        out.extend_from_slice(&[
            self.h,
            self.h_old,
            self.h_acc,
            self.err_acc,
            self.ln_faccon,
            self.faccon_exp,
            self.first as u8 as f64,
            self.has_cont as u8 as f64,
            self.h_event,
            self.after_event as u8 as f64,
            self.switch_sign[0],
            self.switch_sign[1],
            self.n_accept as f64,
            self.full_left as f64,
            self.stats.steps as f64,
            self.stats.rejected as f64,
            self.stats.rhs_evals as f64,
            self.stats.jacobians as f64,
            self.stats.events as f64,
        ]);
        for c in &self.cont {
            out.extend(c.iter());
        }
    }

    /// Number of numbers [`Radau5::save`] writes.
    pub const SAVED_LEN: usize = 2 + N + 19 + 3 * N;

    /// Restores a state written by [`Radau5::save`].
    pub fn load(data: &[f64]) -> Option<Self> {
        if data.len() != Self::SAVED_LEN {
            return None;
        }
        let mut it = data.iter().copied();
        let mut next = || it.next().unwrap_or(0.0);
        let t = next();
        let tol = next();
        if !(tol.is_finite() && tol > 0.0) {
            return None;
        }
        let mut r: Radau5<N> = Radau5::new(t, SVector::zeros(), tol);
        for i in 0..N {
            r.y[i] = next();
        }
        r.h = next();
        r.h_old = next();
        r.h_acc = next();
        r.err_acc = next();
        r.ln_faccon = next();
        r.faccon_exp = next();
        r.first = next() != 0.0;
        r.has_cont = next() != 0.0;
        r.h_event = next();
        r.after_event = next() != 0.0;
        r.switch_sign = [next(), next()];
        r.n_accept = next() as u64;
        r.full_left = next() as u32;
        r.stats.steps = next() as u64;
        r.stats.rejected = next() as u64;
        r.stats.rhs_evals = next() as u64;
        r.stats.jacobians = next() as u64;
        r.stats.events = next() as u64;
        for c in r.cont.iter_mut() {
            for i in 0..N {
                c[i] = next();
            }
        }
        Some(r)
    }
}

fn rms<const N: usize>(v: &SVector<f64, N>, scal: &SVector<f64, N>) -> f64 {
    (v.component_div(scal).norm_squared() / N as f64).sqrt()
}

/// Root of `g` in `[a, b]` with `g(a) ≥ 0 > g(b)`, by the Illinois variant of regula falsi,
/// to the resolution of `f64`. Returns a point where `g` has just turned negative or is zero.
fn illinois(g: &impl Fn(f64) -> f64, mut a: f64, mut ga: f64, mut b: f64, mut gb: f64) -> f64 {
    let mut side = 0;
    for _ in 0..200 {
        if b - a <= 4.0 * f64::EPSILON * b.abs().max(1e-300) {
            break;
        }
        let mut c = (a * gb - b * ga) / (gb - ga);
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let gc = g(c);
        if gc < 0.0 {
            b = c;
            gb = gc;
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
        } else {
            a = c;
            ga = gc;
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    /// Prothero–Robinson: y' = −λ(y − sin t) + cos t, exact y = sin t, arbitrarily stiff.
    struct Prothero {
        lambda: f64,
    }
    impl OdeSystem<1> for Prothero {
        fn rhs(&self, t: f64, y: &SVector<f64, 1>) -> SVector<f64, 1> {
            SVector::<f64, 1>::new(-self.lambda * (y[0] - t.sin()) + t.cos())
        }
        fn scale(&self) -> SVector<f64, 1> {
            SVector::<f64, 1>::new(1.0)
        }
    }

    #[test]
    fn prothero_robinson_is_accurate_and_cheap_at_any_stiffness() {
        let mut cost = vec![];
        for &lambda in &[1.0, 1e4, 1e8, 1e12] {
            let sys = Prothero { lambda };
            let mut r = Radau5::new(0.0, SVector::<f64, 1>::new(0.0), 1e-8);
            r.integrate(&sys, 10.0, f64::INFINITY, |_| {}).unwrap();
            assert_eq!(r.t, 10.0);
            let e = (r.y[0] - 10f64.sin()).abs();
            assert!(e < 1e-7, "lambda {lambda}: error {e}");
            cost.push(r.stats.steps);
        }
        // stiffness does not drive the step count up
        assert!(cost[3] <= 2 * cost[0] + 20, "{cost:?}");
    }

    /// Harmonic oscillator y'' = −y: exact solution cos t; checks the order and the landing.
    struct Osc;
    impl OdeSystem<2> for Osc {
        fn rhs(&self, _t: f64, y: &Vector2<f64>) -> Vector2<f64> {
            Vector2::new(y[1], -y[0])
        }
        fn scale(&self) -> Vector2<f64> {
            Vector2::new(1.0, 1.0)
        }
    }

    #[test]
    fn oscillator_error_follows_tolerance() {
        let mut prev = f64::INFINITY;
        for &tol in &[1e-4, 1e-7, 1e-10] {
            let mut r = Radau5::new(0.0, Vector2::new(1.0, 0.0), tol);
            // many communication points
            for k in 1..=100 {
                r.integrate(&Osc, 0.1 * k as f64, f64::INFINITY, |_| {})
                    .unwrap();
            }
            let e = (r.y[0] - 10f64.cos())
                .abs()
                .max((r.y[1] + 10f64.sin()).abs());
            assert!(e < 20.0 * tol, "tol {tol}: {e}");
            assert!(e < prev);
            prev = e;
        }
    }

    /// y' = |t − 0.3| − has a kink at 0.3 (switch = t − 0.3); quadrature through on_step.
    struct Kink;
    impl OdeSystem<1> for Kink {
        fn rhs(&self, t: f64, _y: &SVector<f64, 1>) -> SVector<f64, 1> {
            SVector::<f64, 1>::new((t - 0.3).abs())
        }
        fn scale(&self) -> SVector<f64, 1> {
            SVector::<f64, 1>::new(1.0)
        }
        fn n_switch(&self) -> usize {
            1
        }
        fn switch(&self, t: f64, _y: &SVector<f64, 1>) -> [f64; MAX_SWITCH] {
            [t - 0.3, 1.0]
        }
        fn quadrature(&self, t: f64, _y: &SVector<f64, 1>) -> Quad {
            [(t - 0.3).abs(), 0.0]
        }
        fn quadrature_scale(&self) -> f64 {
            1.0
        }
    }

    #[test]
    fn kink_is_located_and_integrated_exactly() {
        let mut r = Radau5::new(0.0, SVector::<f64, 1>::new(0.0), 1e-6);
        let mut quad = 0.0;
        let mut ends = vec![];
        r.integrate(&Kink, 1.0, 0.25, |s| {
            quad += s.h
                * (0..3)
                    .map(|i| B[i] * (s.t + C[i] * s.h - 0.3).abs())
                    .sum::<f64>();
            ends.push(s.t + s.h);
        })
        .unwrap();
        let exact = 0.3f64.powi(2) / 2.0 + 0.7f64.powi(2) / 2.0;
        assert!((r.y[0] - exact).abs() < 1e-14, "{}", r.y[0] - exact);
        assert!((quad - exact).abs() < 1e-14);
        assert_eq!(r.stats.events, 1);
        assert!(ends.iter().any(|&e| (e - 0.3).abs() < 1e-15), "{ends:?}");
    }

    /// `T` diagonalises `A⁻¹` into `U1` and the block `[[ALPH, −BETA], [BETA, ALPH]]`, and
    /// `TI` is its inverse, to rounding.
    #[test]
    fn transformation_constants_diagonalise_the_inverse_butcher_matrix() {
        let a = nalgebra::Matrix3::from_fn(|i, j| A[i][j]);
        let ainv = a.try_inverse().unwrap();
        let t = nalgebra::Matrix3::from_fn(|i, j| T[i][j]);
        let ti = nalgebra::Matrix3::from_fn(|i, j| TI[i][j]);
        let lambda = nalgebra::Matrix3::new(U1, 0.0, 0.0, 0.0, ALPH, -BETA, 0.0, BETA, ALPH);
        assert!((ti * t - nalgebra::Matrix3::identity()).amax() < 1e-14);
        assert!(
            (ainv * t - t * lambda).amax() < 1e-13,
            "{}",
            ainv * t - t * lambda
        );
    }

    #[test]
    fn save_load_round_trip_continues_bit_for_bit() {
        let mut a = Radau5::new(0.0, Vector2::new(1.0, 0.0), 1e-6);
        a.integrate(&Osc, 1.0, f64::INFINITY, |_| {}).unwrap();
        let mut buf = vec![];
        a.save(&mut buf);
        assert_eq!(buf.len(), Radau5::<2>::SAVED_LEN);
        let mut b = Radau5::<2>::load(&buf).unwrap();
        a.integrate(&Osc, 2.0, f64::INFINITY, |_| {}).unwrap();
        b.integrate(&Osc, 2.0, f64::INFINITY, |_| {}).unwrap();
        assert_eq!(a.y[0].to_bits(), b.y[0].to_bits());
        assert_eq!(a.y[1].to_bits(), b.y[1].to_bits());
    }
}
