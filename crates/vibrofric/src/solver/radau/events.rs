//! Switching events: sign changes of the system's switching functions (kinks of the
//! right-hand side, such as `|v_r|` at `v_r = 0`) located on the collocation polynomial of the
//! attempted step, so that the step can be retaken to end on them. A sign change within
//! `rtol·scale` of zero is no event (a stuck contact hovers there). The dense output is the
//! collocation polynomial of Hairer & Wanner, *Solving ODEs II*, §IV.8 (RADAU5's `CONTR5`).

use nalgebra::SVector;

use super::tableau::{C, C1M1, C2M1};
use super::Radau5;
use crate::solver::system::{OdeSystem, Quad, MAX_SWITCH};

impl<const N: usize> Radau5<N> {
    /// At the start of a call: the side of each switching function, where it is known (a
    /// function within `rtol·scale` of zero keeps the side it had; zero counts as the positive
    /// side until the function leaves it).
    pub(super) fn init_switch_signs<S: OdeSystem<N>>(&mut self, sys: &S, n_switch: usize) {
        let band = sys.switch_scale().map(|v| self.rtol * v);
        if n_switch > 0 {
            let g = sys.switch(self.t, &self.y);
            for k in 0..n_switch {
                if self.switch_sign[k] == 0.0 || g[k].abs() > band[k] {
                    self.switch_sign[k] = if g[k] < 0.0 { -1.0 } else { 1.0 };
                }
            }
        }
    }

    /// Evaluates the dense output of a step ending in `y_new` at fraction `theta` of it.
    pub(super) fn dense(
        y_new: &SVector<f64, N>,
        cont: &[SVector<f64, N>; 3],
        theta: f64,
    ) -> SVector<f64, N> {
        let s = theta - 1.0;
        y_new + (cont[0] + (cont[1] + cont[2] * (s - C1M1)) * (s - C2M1)) * s
    }

    /// The first sign change of a switching function inside the attempted step, as a fraction
    /// of the step and the function's index, located on the collocation polynomial.
    pub(super) fn find_event<S: OdeSystem<N>>(
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
