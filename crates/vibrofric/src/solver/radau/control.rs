//! Step-size control: the error estimate of the embedded formula (Hairer & Wanner, *Solving
//! ODEs II*, §IV.8, with the quadrature's own estimate), the step-size quotient with
//! Gustafsson's predictive controller, and the first step.

use nalgebra::SVector;

use super::newton::{NewtonSetup, NIT};
use super::tableau::{A, DD1, DD2, DD3, U1};
use super::Radau5;
use crate::solver::lu::FixedLu;
use crate::solver::system::{OdeSystem, Quad, MAX_QUAD, MAX_SWITCH};

/// Safety factor of the step-size proposal.
const SAFE: f64 = 0.9;
/// Largest growth and shrinking of the step from one attempt to the next.
const FAC_MAX_GROW: f64 = 8.0;
const FAC_MAX_SHRINK: f64 = 0.2;

impl<const N: usize> Radau5<N> {
    /// The scaled error of the attempted step (accept when < 1) and the step's quadrature
    /// (the collocation integral of each integrand).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn error_estimate<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        setup: &NewtonSetup<N>,
        h: f64,
        z: &[SVector<f64, N>; 3],
        f0: &SVector<f64, N>,
        q0: &Quad,
        observed: &[([f64; MAX_SWITCH], Quad); 3],
        scal: &SVector<f64, N>,
        q_scale: f64,
        q_steers: usize,
        reject: bool,
    ) -> (f64, Quad) {
        // Error estimate (Hairer & Wanner IV.8). Its filter `(U1/h − J)⁻¹` needs only an
        // approximate Jacobian (RADAU5 keeps one for many steps): the first stage's.
        let e1 = match setup.split {
            Some((e_real, _)) => e_real,
            None => FixedLu::new(std::array::from_fn(|r| {
                std::array::from_fn(|c| (if r == c { U1 / h } else { 0.0 }) - setup.jac[0][(r, c)])
            })),
        };
        let solve = |v: SVector<f64, N>| {
            let mut b: [f64; N] = v.into();
            e1.solve(&mut b);
            SVector::from(b)
        };
        let f2 = (z[0] * DD1 + z[1] * DD2 + z[2] * DD3) / h;
        let est = solve(f0 + f2);
        let mut err = rms(&est, scal).max(1e-10);
        if err >= 1.0 && (self.first || reject) {
            let fy = sys.rhs(self.t, &(self.y + est));
            self.stats.rhs_evals += 1;
            let est2 = solve(fy + f2);
            err = rms(&est2, scal).max(1e-10);
        }
        // The quadrature: collocation integral and its embedded error estimate.
        let mut quad = [0.0; MAX_QUAD];
        if q_scale > 0.0 {
            for k in 0..MAX_QUAD {
                let q: [f64; 3] = std::array::from_fn(|i| observed[i].1[k]);
                let zq: [f64; 3] =
                    std::array::from_fn(|i| h * (A[i][0] * q[0] + A[i][1] * q[1] + A[i][2] * q[2]));
                quad[k] = zq[2];
                if k >= q_steers {
                    continue;
                }
                let est_q = (h / U1) * (q0[k] + (DD1 * zq[0] + DD2 * zq[1] + DD3 * zq[2]) / h);
                err = err.max(est_q.abs() / (self.rtol * q_scale * h));
            }
        }
        if !err.is_finite() {
            err = 1e10;
        }
        (err, quad)
    }

    /// The quotient `h/h_new` proposed after an attempt with error `err` that took `newt`
    /// Newton iterations.
    pub(super) fn step_quotient(err: f64, newt: u32) -> f64 {
        let fac = SAFE.min(SAFE * (1.0 + 2.0 * NIT as f64) / (newt as f64 + 2.0 * NIT as f64));
        (err.sqrt().sqrt() / fac).clamp(1.0 / FAC_MAX_GROW, 1.0 / FAC_MAX_SHRINK)
    }

    /// After an accepted step: Gustafsson's predictive quotient where the last accepted step
    /// allows it, if it is the more cautious one.
    pub(super) fn gustafsson(&self, h: f64, err: f64, quot: f64) -> f64 {
        if self.n_accept > 0 && !self.first {
            let facgus = (self.h_acc / h) * (err * err / self.err_acc).sqrt().sqrt() / SAFE;
            let facgus = facgus.clamp(1.0 / FAC_MAX_GROW, 1.0 / FAC_MAX_SHRINK);
            quot.max(facgus)
        } else {
            quot
        }
    }

    /// A first step from the size of the derivative, with the usual order scaling.
    pub(super) fn initial_step(
        &self,
        f0: &SVector<f64, N>,
        nominal: &SVector<f64, N>,
        span: f64,
    ) -> f64 {
        let d1 = rms(f0, &nominal.map(|v| v.max(f64::MIN_POSITIVE)));
        let h = if d1 > 0.0 { 1e-2 / d1 } else { span };
        (h * libm::pow(self.tol, 0.2))
            .min(span)
            .max(1e-14 * (1.0 + self.t.abs()))
    }
}

/// The root mean square of `v` in units of `scal`.
pub(super) fn rms<const N: usize>(v: &SVector<f64, N>, scal: &SVector<f64, N>) -> f64 {
    (v.component_div(scal).norm_squared() / N as f64).sqrt()
}
