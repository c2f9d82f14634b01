//! The simplified Newton iteration on the stage equations of Radau IIA (Hairer & Wanner,
//! *Solving ODEs II*, §IV.8): the iteration matrices of one attempt, the iteration with its
//! convergence test and rate estimate, and the Jacobian (the system's, or forward differences).

use nalgebra::{Complex, SMatrix, SVector};

use super::tableau::{A, ALPH, BETA, C, T, TI, U1};
use super::Radau5;
use crate::solver::lu::{DenseLu, FixedLu};
use crate::solver::system::{OdeSystem, MAX_DIM};

/// Most Newton iterations per attempt.
pub(super) const NIT: u32 = 7;
/// Steps taken with stage Jacobians after the simplified iteration failed to converge.
pub(super) const FULL_STEPS_AFTER_FAILURE: u32 = 4;

/// The matrices of one attempt's iteration.
pub(super) struct NewtonSetup<const N: usize> {
    /// RADAU5's simplified iteration (else stage Jacobians).
    pub simplified: bool,
    /// The Jacobian at each stage (the step start's, three times, when simplified).
    pub jac: [SMatrix<f64, N, N>; 3],
    /// The real and complex systems of the simplified iteration, factored.
    pub split: Option<(FixedLu<f64, N>, FixedLu<Complex<f64>, N>)>,
}

/// How the iteration ended.
pub(super) enum Newton {
    Converged {
        iterations: u32,
    },
    /// Diverged or too slow: retake the step `shrink` times as long.
    Failed {
        shrink: f64,
    },
}

impl<const N: usize> Radau5<N> {
    /// The iteration matrices of one attempt, and `f` at the starting stage values. Two kinds:
    /// the simplified iteration (RADAU5's: one Jacobian at the step start, split by the
    /// transformation `T` into a real and a complex N×N system), or stage Jacobians
    /// (`I − h·(A ⊗ J_j)`, a 3N×3N system, which converges where `J` changes by orders of
    /// magnitude within the step).
    pub(super) fn newton_setup<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        m: &mut DenseLu,
        h: f64,
        z: &[SVector<f64, N>; 3],
        jac_start: &mut Option<SMatrix<f64, N, N>>,
        nominal: &SVector<f64, N>,
    ) -> (NewtonSetup<N>, [SVector<f64, N>; 3]) {
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
            let j0 = match *jac_start {
                Some(j) => j,
                None => {
                    let (t, y) = (self.t, self.y);
                    let j = self.rhs_jacobian(sys, t, &y, nominal).1;
                    *jac_start = Some(j);
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
                (fz[i], jac[i]) = self.rhs_jacobian(sys, ti, &yi, nominal);
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
        (
            NewtonSetup {
                simplified,
                jac,
                split,
            },
            fz,
        )
    }

    /// The Newton iteration on the stage increments `z` (Hairer & Wanner IV.8): at most
    /// [`NIT`] iterations, stopped on RADAU5's test with the measured contraction, or abandoned
    /// when it diverges or converges too slowly (with the factor to shrink the step by).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn newton_iterate<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        m: &DenseLu,
        setup: &NewtonSetup<N>,
        h: f64,
        z: &mut [SVector<f64, N>; 3],
        fz: &mut [SVector<f64, N>; 3],
        scal: &SVector<f64, N>,
    ) -> Newton {
        // Newton iteration.
        self.faccon_exp *= 0.8;
        let mut dyno_old = 0.0;
        let mut thq_old = 0.0;
        let mut newt = 0;
        let mut shrink = 0.5;
        loop {
            if newt >= NIT {
                break Newton::Failed { shrink };
            }
            if newt > 0 {
                for i in 0..3 {
                    fz[i] = sys.rhs(self.t + C[i] * h, &(self.y + z[i]));
                }
                self.stats.rhs_evals += 3;
            }
            if !fz.iter().all(|f| f.iter().all(|v| v.is_finite())) {
                break Newton::Failed { shrink };
            }
            let dz: [SVector<f64, N>; 3] = if let Some((e_real, e_complex)) = &setup.split {
                // In W = (T⁻¹ ⊗ I)·Z the system reads (Λ/h ⊗ I − I ⊗ J)·ΔW =
                // (T⁻¹ ⊗ I)·F − (Λ/h ⊗ I)·W, Λ = diag(U1, [[ALPH, −BETA], [BETA, ALPH]]).
                let tf = |m: &[[f64; 3]; 3], v: &[SVector<f64, N>; 3], k: usize| {
                    v[0] * m[k][0] + v[1] * m[k][1] + v[2] * m[k][2]
                };
                let (a, w) = (
                    [tf(&TI, fz, 0), tf(&TI, fz, 1), tf(&TI, fz, 2)],
                    [tf(&TI, z, 0), tf(&TI, z, 1), tf(&TI, z, 2)],
                );
                let r1 = a[0] - w[0] * (U1 / h);
                let r2 = a[1] - w[1] * (ALPH / h) + w[2] * (BETA / h);
                let r3 = a[2] - w[1] * (BETA / h) - w[2] * (ALPH / h);
                let mut dw0: [f64; N] = r1.into();
                let mut dw12: [Complex<f64>; N] =
                    std::array::from_fn(|i| Complex::new(r2[i], r3[i]));
                if !(e_real.solve(&mut dw0) && e_complex.solve(&mut dw12)) {
                    break Newton::Failed { shrink };
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
                    break Newton::Failed { shrink };
                }
                std::array::from_fn(|i| SVector::from_column_slice(&rhs[i * N..(i + 1) * N]))
            };
            newt += 1;
            let dyno = ((0..3)
                .map(|k| dz[k].component_div(scal).norm_squared())
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
                    self.ln_faccon = libm::log(faccon);
                    self.faccon_exp = 1.0;
                    let dyth = faccon * dyno * theta.powi((NIT - 1 - newt) as i32) / self.fnewt;
                    if dyth >= 1.0 {
                        // Convergence too slow for this step: shrink it.
                        let qnewt = dyth.clamp(1e-4, 20.0);
                        shrink = 0.8 * libm::pow(qnewt, -1.0 / (4.0 + (NIT - 1 - newt) as f64));
                        break Newton::Failed { shrink };
                    }
                } else {
                    break Newton::Failed { shrink };
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
            if (newt > 1 || !setup.simplified) && self.newton_converged(dyno) {
                break Newton::Converged { iterations: newt };
            }
        }
    }

    /// `f(t, y)` and the system's Jacobian there, or forward differences.
    pub(super) fn rhs_jacobian<S: OdeSystem<N>>(
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
        self.faccon_exp * self.ln_faccon + libm::log(dyno) <= self.ln_fnewt
    }
}
