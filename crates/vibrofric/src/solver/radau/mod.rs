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
//!
//! Files: `tableau.rs` (the coefficients), `newton.rs` (the stage equations' iteration),
//! `events.rs` (switching events on the dense output), `control.rs` (error estimate and step
//! size), `attempt.rs` (an attempt's interval, starting values, dense output, what its events
//! decide, an accepted step's bookkeeping); this file holds the integrator's state and the step
//! loop that combines them.

mod attempt;
mod control;
mod events;
mod newton;
pub(super) mod tableau;

use nalgebra::{SMatrix, SVector};

use super::lu::DenseLu;
use super::system::{OdeSystem, SolverError, SolverStats, Step, MAX_DIM, MAX_QUAD, MAX_SWITCH};
use attempt::Switching;
use newton::{Newton, FULL_STEPS_AFTER_FAILURE};
pub use tableau::{B, C};

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
        let rtol = 0.1 * libm::pow(tol, 2.0 / 3.0);
        let fnewt = (10.0 * f64::EPSILON / rtol).max(rtol.sqrt().min(0.03));
        Radau5 {
            t,
            y,
            tol,
            rtol,
            fnewt,
            ln_fnewt: libm::log(fnewt),
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

    /// The step the integrator would try next (0 before it has chosen one).
    pub fn proposed_step(&self) -> f64 {
        self.h
    }

    /// The step to try first, where the caller knows one better than the integrator's own
    /// guess from the first derivative.
    pub fn first_step(mut self, h: f64) -> Self {
        if h.is_finite() && h > 0.0 {
            self.h = h;
        }
        self
    }

    /// Tells the integrator that the right-hand side may have jumped at the current time (an
    /// input changed): the next step restarts without extrapolating the previous one.
    pub fn restart(&mut self) {
        self.start_afresh();
        self.switch_sign = [0.0; MAX_SWITCH];
    }

    /// The next step starts afresh (after an input change or a switching event): Newton
    /// starts from zero stage increments, and stops only on the test with `faccon = 1`, as at
    /// the integrator's start, or on a contraction it measures. The contraction carried over
    /// belongs to steps on the other side of the jump, possibly far shorter (a step landing on
    /// an event): one measured at 2e-13 on a landing step of 1.2e-7 (a string's section
    /// integrated again) let the 450 times longer step after the event stop after its first
    /// stage-Jacobian iteration, its stage residuals 10³ times the error scale, the section's
    /// momentum off by 5e-3 of its friction impulse.
    fn start_afresh(&mut self) {
        self.first = true;
        self.ln_faccon = 0.0;
        self.faccon_exp = 1.0;
    }

    /// Replaces the state at the current time (after a projection or a parameter change).
    pub fn set_state(&mut self, y: SVector<f64, N>) {
        self.y = y;
        self.restart();
    }

    fn scal(&self, y: &SVector<f64, N>, nominal: &SVector<f64, N>) -> SVector<f64, N> {
        SVector::from_fn(|i, _| self.rtol * (nominal[i] + y[i].abs()))
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
    ///
    /// Each attempt: its interval ([`Radau5::span`]), Newton's starting values and iteration
    /// (`newton.rs`; a failure retakes the step with stage Jacobians or shorter), the dense
    /// output, the switching events on it ([`Radau5::switching`]: an event inside is retaken to
    /// end on it), the error estimate and step quotient (`control.rs`: an error ≥ 1 rejects),
    /// and an accepted step's bookkeeping ([`Radau5::accept`]).
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
        let q_steers = sys.quadrature_steers().min(MAX_QUAD);
        let n_switch = sys.n_switch().min(MAX_SWITCH);
        self.init_switch_signs(sys, n_switch);
        let (mut f0, mut q0) = sys.rhs_quadrature(self.t, &self.y);
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
            let span = self.span(t_end, h_max, event_target)?;
            let h = span.h;
            let scal = self.scal(&self.y, &nominal);
            let mut z = self.starting_values(h);

            let (setup, mut fz) = self.newton_setup(sys, m, h, &z, &mut jac_start, &nominal);
            let simplified = setup.simplified;
            let newton = self.newton_iterate(sys, m, &setup, h, &mut z, &mut fz, &scal);
            let newt = match newton {
                Newton::Converged { iterations } => iterations,
                Newton::Failed { .. } if simplified => {
                    // Retake the same step with stage Jacobians.
                    self.full_left = FULL_STEPS_AFTER_FAILURE;
                    self.stats.rejected += 1;
                    continue;
                }
                Newton::Failed { shrink } => {
                    self.h = h * shrink;
                    self.stats.rejected += 1;
                    reject = true;
                    event_target = None;
                    continue;
                }
            };

            // Newton converged: the dense output, and switching events before the error.
            let (y_new, cont) = self.dense_output(&z);
            let observed = self.observe(sys, n_switch, q_scale, h, &z);
            let event_here = match self.switching(
                sys,
                n_switch,
                h,
                &observed,
                &y_new,
                &cont,
                &mut event_target,
            ) {
                Switching::Retake => continue,
                Switching::Proceed(event_here) => event_here,
            };

            let (err, quad) = self.error_estimate(
                sys, &setup, h, &z, &f0, &q0, &observed, &scal, q_scale, q_steers, reject,
            );
            let quot = Self::step_quotient(err, newt);
            if err >= 1.0 {
                self.stats.rejected += 1;
                reject = true;
                event_target = None;
                self.h = if self.first { 0.1 * h } else { h / quot };
                continue;
            }

            self.accept(
                sys,
                &mut on_step,
                &span,
                &z,
                y_new,
                cont,
                err,
                quot,
                quad,
                reject,
                simplified,
                event_here,
            );
            reject = false;
            jac_start = None;
            if event_here.is_some() {
                event_target = None;
            }
            (f0, q0) = sys.rhs_quadrature(self.t, &self.y);
            self.stats.rhs_evals += 1;
        }
        Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::system::Quad;
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

    /// `y' = 1 + |t − 0.5| + y²/2` from `y = 0`: nonlinear, with a kink at 0.5 (its switching
    /// function `t − 0.5`).
    struct SquareKink;
    impl OdeSystem<1> for SquareKink {
        fn rhs(&self, t: f64, y: &SVector<f64, 1>) -> SVector<f64, 1> {
            SVector::<f64, 1>::new(1.0 + (t - 0.5).abs() + 0.5 * y[0] * y[0])
        }
        fn scale(&self) -> SVector<f64, 1> {
            SVector::<f64, 1>::new(1.0)
        }
        fn n_switch(&self) -> usize {
            1
        }
        fn switch(&self, t: f64, _y: &SVector<f64, 1>) -> [f64; MAX_SWITCH] {
            [t - 0.5, 1.0]
        }
    }

    /// Every accepted step solves its collocation equations to Newton's tolerance: the state
    /// changes over it by the quadrature of `f` on its stages (what a caller's integrals of
    /// the forces rely on, such as the string's momentum balance), also on the step after an
    /// event that a very short step landed on, from a restart (starting values zero). A
    /// contraction measured on that short step once let the long one after the event stop
    /// after one iteration, hundreds of tolerances off.
    #[test]
    fn every_step_solves_its_collocation_equations_across_an_event() {
        for tol in [1e-6, 1e-9] {
            for gap in [1e-3, 1e-5, 1e-7, 1e-9, 1e-11] {
                let mut r = Radau5::new(0.0, SVector::<f64, 1>::new(0.0), tol);
                let mut worst: f64 = 0.0;
                let mut y_prev = r.y[0];
                let mut check = |s: &Step<1>| {
                    let quad: f64 = (0..3)
                        .map(|i| B[i] * s.h * SquareKink.rhs(s.t + C[i] * s.h, &s.stages[i])[0])
                        .sum();
                    let y1 = s.stages[2][0];
                    worst = worst.max((y1 - y_prev - quad).abs() / (tol * (1.0 + y1.abs())));
                    y_prev = y1;
                };
                r.integrate(&SquareKink, 0.5 - gap, f64::INFINITY, &mut check)
                    .unwrap();
                r.restart();
                r.integrate(&SquareKink, 1.0, f64::INFINITY, &mut check)
                    .unwrap();
                assert_eq!(r.stats.events, 1);
                // 7e-3 at most; 2e2 and 2e3 (tolerance 1e-9, gap 1e-7; 1e-6, 1e-5) when the
                // contraction measured on the landing step was carried over the event.
                assert!(
                    worst < 0.05,
                    "tol {tol:e}, gap {gap:e}: {worst:e} tolerances"
                );
            }
        }
    }
}
