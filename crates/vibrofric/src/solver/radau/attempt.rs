//! The pieces of one attempt of [`Radau5::integrate_with`] that are not the Newton iteration
//! (`newton.rs`), the error estimate and step-size rule (`control.rs`) or the location of a
//! sign change (`events.rs`): the interval an attempt covers, its starting values, its dense
//! output, what its switching events decide, and the bookkeeping of an accepted step.

use nalgebra::SVector;

use super::tableau::{C, C1M1, C1MC2, C2M1};
use super::Radau5;
use crate::solver::system::{OdeSystem, Quad, SolverError, Step, MAX_QUAD, MAX_SWITCH};

/// The interval of one attempt.
pub(super) struct Span {
    /// Its end and length.
    pub t_new: f64,
    pub h: f64,
    /// The step proposed before it was cut to land on an event or on the end time.
    pub h_unclipped: f64,
    /// Whether the attempt lands on an event or on the end time.
    pub landing: bool,
}

/// What the switching functions say of an attempt whose Newton iteration converged.
pub(super) enum Switching {
    /// Retake it: shorter, to end on a sign change found inside, or from the current time on
    /// the other side of a crossing found there.
    Retake,
    /// Go on to its error estimate; it ends on the event of switching function `k` if `Some(k)`.
    Proceed(Option<usize>),
}

/// The switching functions and the quadrature's integrand at the three stages.
pub(super) type Observed = [([f64; MAX_SWITCH], Quad); 3];

impl<const N: usize> Radau5<N> {
    /// The next attempt's interval: the proposed step, at most `h_max`, landing exactly on the
    /// event `event_target` found by the last attempt or on `t_end` when that is near. Stops at
    /// the work limit and at a step too small for the time's precision.
    #[inline]
    pub(super) fn span(
        &self,
        t_end: f64,
        h_max: f64,
        event_target: Option<(f64, usize)>,
    ) -> Result<Span, SolverError> {
        if self.stats.steps + self.stats.rejected >= self.step_limit {
            return Err(SolverError::WorkLimit {
                t: self.t,
                limit: self.step_limit as f64,
            });
        }
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
        Ok(Span {
            t_new,
            h,
            h_unclipped,
            landing: target.is_some(),
        })
    }

    /// Newton's starting values for a step `h`: the previous step's collocation polynomial,
    /// extrapolated (zero after a restart).
    #[inline]
    pub(super) fn starting_values(&self, h: f64) -> [SVector<f64, N>; 3] {
        let mut z = [SVector::<f64, N>::zeros(); 3];
        if !self.first && self.has_cont {
            let c3q = h / self.h_old;
            for (i, zi) in z.iter_mut().enumerate() {
                let cq = C[i] * c3q;
                *zi =
                    (self.cont[0] + (self.cont[1] + self.cont[2] * (cq - C1M1)) * (cq - C2M1)) * cq;
            }
        }
        z
    }

    /// The state at the end of a converged attempt with stage increments `z`, and the
    /// coefficients of its dense output (the collocation polynomial).
    #[inline]
    pub(super) fn dense_output(
        &self,
        z: &[SVector<f64, N>; 3],
    ) -> (SVector<f64, N>, [SVector<f64, N>; 3]) {
        let y_new = self.y + z[2];
        let cont0 = (z[1] - z[2]) / C2M1;
        let ak = (z[0] - z[1]) / C1MC2;
        let acont3 = (ak - z[0] / C[0]) / C[1];
        let cont1 = (ak - cont0) / C1M1;
        (y_new, [cont0, cont1, cont1 - acont3])
    }

    /// The switching functions and the quadrature's integrand at the stages of a step `h`
    /// (not evaluated, zero, when the system has neither).
    #[inline]
    pub(super) fn observe<S: OdeSystem<N>>(
        &self,
        sys: &S,
        n_switch: usize,
        q_scale: f64,
        h: f64,
        z: &[SVector<f64, N>; 3],
    ) -> Observed {
        if n_switch > 0 || q_scale > 0.0 {
            std::array::from_fn(|i| sys.observe(self.t + C[i] * h, &(self.y + z[i])))
        } else {
            [([0.0; MAX_SWITCH], [0.0; MAX_QUAD]); 3]
        }
    }

    /// Switching events on a converged attempt. A step across a kink has a meaningless error
    /// estimate, so a sign change inside it makes the attempt end on it (`event_target`, and the
    /// same proposal `h` kept); one at the current time flips its side and restarts; an attempt
    /// that lands on the event it was aimed at, or whose sign change is at its end, proceeds.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(super) fn switching<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        n_switch: usize,
        h: f64,
        observed: &Observed,
        y_new: &SVector<f64, N>,
        cont: &[SVector<f64, N>; 3],
        event_target: &mut Option<(f64, usize)>,
    ) -> Switching {
        if n_switch == 0 {
            return Switching::Proceed(None);
        }
        if let Some((_, k)) = *event_target {
            return Switching::Proceed(Some(k));
        }
        let Some((theta_e, k)) = self.find_event(sys, n_switch, h, observed, y_new, cont) else {
            return Switching::Proceed(None);
        };
        if theta_e >= 1.0 - 1e-12 {
            return Switching::Proceed(Some(k));
        }
        let te = self.t + theta_e * h;
        if te > self.t {
            *event_target = Some((te, k));
            self.h = h;
            return Switching::Retake;
        }
        // The crossing is at the current time: flip and restart.
        self.switch_sign[k] = -self.switch_sign[k];
        self.stats.events += 1;
        self.start_afresh();
        Switching::Retake
    }

    /// An accepted attempt (scaled error `err` < 1, step quotient `quot`): hands its stages and
    /// quadrature to `on_step`, moves to its end (projected onto the invariant set), keeps its
    /// dense output, and proposes the next step: Gustafsson's, no longer than this one after a
    /// rejection, not shortened by a landing, the step after an event learnt. On an event
    /// (`event_here`) the side of its switching function flips and the integrator restarts.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(super) fn accept<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        on_step: &mut impl FnMut(&Step<N>),
        span: &Span,
        z: &[SVector<f64, N>; 3],
        y_new: SVector<f64, N>,
        cont: [SVector<f64, N>; 3],
        err: f64,
        quot: f64,
        quad: Quad,
        reject: bool,
        simplified: bool,
        event_here: Option<usize>,
    ) {
        let h = span.h;
        let mut h_new = h / self.gustafsson(h, err, quot);
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
        sys.project(span.t_new, &mut y_acc);
        self.y = y_acc;
        self.t = span.t_new;
        self.cont = cont;
        self.has_cont = true;
        self.h_old = h;
        if reject {
            h_new = h_new.min(h);
        }
        if span.landing && span.h_unclipped > h {
            // A clipped step says little about the natural step size.
            h_new = h_new.max(span.h_unclipped);
        }
        if self.after_event {
            // Learn the restart step: what this first step after the event proposes next.
            self.h_event = h_new;
            self.after_event = false;
        }
        self.first = false;
        self.h = h_new;
        if !simplified {
            self.full_left = self.full_left.saturating_sub(1);
        }
        if let Some(k) = event_here {
            self.switch_sign[k] = -self.switch_sign[k];
            self.stats.events += 1;
            self.start_afresh();
            self.after_event = true;
            if self.h_event > 0.0 {
                self.h = self.h_event;
            }
        }
    }
}
