//! Adjacent sections whose own errors failed in the same step of the string, integrated again
//! together over that step: a short string of their own, by the band Radau IIA of the whole
//! string ([`BandRadau`]), its two outer neighbours moving as the string's step has them (the
//! step's collocation polynomial, as in `refine.rs`). Integrated one by one, each would feel the
//! other on the string's step, which is the step that failed for it: where that step was far off
//! for one of them, its neighbour's own integration was wrong by as much, and the string's
//! step had to be rejected and shortened for every section. Together, the link between them
//! is resolved inside their own steps, and its impulse is the same on both sides.
//!
//! The state is `[Δx, v, s]` per section, `Δx` the displacement since the step's start, as in
//! `refine.rs`. The reversals of the sections' relative velocities are not located: the error
//! control steps over them, as in the string's own steps.

use crate::physics::FrictionLaw;
use crate::solver::band::{Band, BandRadau, BandSystem, BandWork};
use crate::solver::{SolverError, B, C};

use super::equations::{StringModel, PER_SECTION};
use super::refine::{Refined, Trajectory};

/// The run's tolerance as a fraction of the string's (its band Radau holds a tenth of it
/// internally: `0.01·tol`, against the string's `0.1·tol` and a section alone's `0.3·tol`). The
/// reversals inside a run are stepped over, not located, and its error estimate across them is
/// not to be trusted at the single section's tolerance. Measured on `tests/string.rs`'s 16
/// sections against its reference (largest error of positions, velocities and forces, in units
/// of the tolerance, at six tolerances from 0.6 to 2 times 1e-6, then 1e-8), and on the drill
/// string of `examples/string_bench.rs` (instructions, 0.1 s, 1,000 sections):
///
/// | fraction | errors around 1e-6 | around 1e-8 | 1,000 sections |
/// |---|---|---|---|
/// | 3 (`0.3·tol`) | 1.3–2.2 | 1.6–312 | 1.94G |
/// | 0.3 | 1.3–2.2 | 0.9–76 | 2.15G |
/// | **0.1** | 1.3–2.2 | 0.9–6.0 | 2.31G |
/// | 0.03, 0.01 | 1.3–2.3 | 1.0–6.1 | |
/// | (no runs: the string's step rejected instead) | 0.73–3.75 | 0.84–2.40 | 2.82G |
///
/// (The largest error of the last rows but one, at 1.6e-8, comes from the string's own steps,
/// not the runs': it stays at tighter fractions.)
const RUN_TOL: f64 = 0.1;

/// Sections `first .. first + len` over one step of the string.
struct RunOde<'a, L> {
    model: &'a StringModel<L>,
    first: usize,
    len: usize,
    /// The link to the section before the run and that section over the step (none at the top).
    left: Option<(f64, f64, Trajectory)>,
    /// The link to the section after the run and that section (none at the bottom).
    right: Option<(f64, f64, Trajectory)>,
    /// The sections' positions at the step's start.
    x0: Vec<f64>,
    t0: f64,
    inv_h: f64,
    /// The error scales `[x, v, s]` of the sections (to which `|y|` is added).
    scale: Vec<f64>,
}

impl<L: FrictionLaw> RunOde<'_, L> {
    /// `[x, v]` of the run's section `j` (the neighbours on the string's step outside it).
    #[inline(always)]
    fn at(&self, j: usize, y: &[f64]) -> (f64, f64) {
        let k = PER_SECTION * j;
        (self.x0[j] + y[k], y[k + 1])
    }
}

impl<L: FrictionLaw> BandSystem for RunOde<'_, L> {
    fn dim(&self) -> usize {
        PER_SECTION * self.len
    }

    fn bands(&self) -> (usize, usize) {
        // As the string's: v_i depends on x_{i−1} and v_{i+1}.
        (4, 3)
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let m = self.model;
        let theta = (t - self.t0) * self.inv_h;
        let last = self.len - 1;
        // The tension of the link on the section's left (an inner link's computed once, as
        // the right link of the section before): `k·Δx + c·Δv` across it.
        let mut left = match &self.left {
            Some((k, c, tr)) => {
                let (xn, vn) = tr.at(theta);
                let (x, v) = self.at(0, y);
                k * (x - xn) + c * (v - vn)
            }
            None => 0.0,
        };
        for j in 0..self.len {
            let i = self.first + j;
            let (x, v) = self.at(j, y);
            let s = y[PER_SECTION * j + 2];
            let (ds, f) = m.contact(i, t, v, s);
            let towards = |k: f64, c: f64, (xn, vn): (f64, f64)| k * (xn - x) + c * (vn - v);
            let right = match (j == last, &self.right) {
                (true, Some((k, c, tr))) => towards(*k, *c, tr.at(theta)),
                (true, None) => 0.0,
                (false, _) => towards(m.links.k_s[i], m.links.c_s[i], self.at(j + 1, y)),
            };
            let mut held = right - left;
            left = right;
            if i == 0 {
                held += m.top_force(t, x, v);
            }
            if i + 1 == m.n() {
                held -= m.bottom_force(t, x, v);
            }
            let force = m.inputs.f_d[i].at(t) + held - f;
            let k = PER_SECTION * j;
            dy[k] = v;
            dy[k + 1] = force * m.sections[i].inv_m;
            dy[k + 2] = ds;
        }
    }

    /// The string's Jacobian ([`StringModel`]'s) on the run's rows and columns.
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut Band<f64>) {
        for j in 0..self.len {
            let k = PER_SECTION * j;
            let inside = (j > 0, j + 1 < self.len);
            let yj = &y[k..k + PER_SECTION];
            self.model
                .section_jacobian(self.first + j, t, yj, k, inside, jac);
        }
    }

    fn error_scale(&self, y: &[f64], out: &mut [f64]) {
        for ((o, s), y) in out.iter_mut().zip(&self.scale).zip(y) {
            *o = s + y.abs();
        }
    }

    fn chain(&self) -> bool {
        true
    }

    /// Each section's error is held to the tolerance on its own (none taken over:
    /// [`BandSystem::max_refined`] is 0), not their mean over the run.
    fn block(&self) -> usize {
        PER_SECTION
    }
}

/// Integrates sections `first .. first + len` (at least two, side by side) again together from
/// `t0` (the string's state `y0`) to `t1` with their outer neighbours on the string's step
/// (`stages`), to the internal tolerance `0.01·tol` ([`RUN_TOL`]), the sections' natural
/// scales of velocity and deformation in `scales` (`[_, v, s]` per section, as the string's
/// error scale at rest) and of position in `x_scales` (the string's at `y0`), starting with the
/// shortest of the steps `own_steps` their last refinements ended with (0: none yet). Their
/// results in order; the first carries the run's solver statistics.
#[allow(clippy::too_many_arguments)]
pub fn refine_run<L: FrictionLaw>(
    model: &StringModel<L>,
    (first, len): (usize, usize),
    t0: f64,
    t1: f64,
    y0: &[f64],
    stages: &[Vec<f64>; 3],
    (scales, x_scales): (&[f64], &[f64]),
    tol: f64,
    own_steps: &[f64],
) -> Result<Vec<Refined>, SolverError> {
    debug_assert!(len >= 2 && first + len <= model.n());
    let n = model.n();
    let l = &model.links;
    let end = first + len;
    let left = (first > 0).then(|| {
        let i = first - 1;
        (l.k_s[i], l.c_s[i], Trajectory::of(i, y0, stages))
    });
    let right = (end < n).then(|| {
        (
            l.k_s[end - 1],
            l.c_s[end - 1],
            Trajectory::of(end, y0, stages),
        )
    });
    let span = PER_SECTION * first..PER_SECTION * end;
    let mut scale = scales[span.clone()].to_vec();
    for (j, s) in scale.chunks_mut(PER_SECTION).enumerate() {
        s[0] = x_scales[PER_SECTION * (first + j)];
    }
    let ode = RunOde {
        model,
        first,
        len,
        left,
        right,
        x0: (first..end).map(|i| y0[PER_SECTION * i]).collect(),
        t0,
        inv_h: 1.0 / (t1 - t0),
        scale,
    };
    let mut start = y0[span].to_vec();
    for s in start.chunks_mut(PER_SECTION) {
        s[0] = 0.0;
    }
    let mut radau = BandRadau::new(t0, start, RUN_TOL * tol);
    let own = own_steps[first..end]
        .iter()
        .copied()
        .filter(|h| *h > 0.0)
        .fold(f64::INFINITY, f64::min);
    radau.h = if own.is_finite() {
        own.min(t1 - t0)
    } else {
        0.25 * (t1 - t0)
    };
    // Far beyond what a step of the string has ever needed: a bound, not a budget.
    radau.step_limit = 1_000_000;
    let (kl, ku) = ode.bands();
    let mut work = BandWork::new(ode.dim(), kl, ku);
    // The integrals over the step of each section's friction and displacement.
    let mut q = vec![[0.0; 2]; len];
    radau.integrate(&ode, &mut work, t1, |st| {
        for (k, stage) in st.stages.iter().enumerate() {
            let tk = st.t + C[k] * st.h;
            for (j, q) in q.iter_mut().enumerate() {
                let at = PER_SECTION * j;
                let f = model.contact(first + j, tk, stage[at + 1], stage[at + 2]).1;
                q[0] += B[k] * st.h * f;
                q[1] += B[k] * st.h * stage[at];
            }
        }
        Ok(())
    })?;
    let next_step = radau.h;
    let mut stats = radau.stats;
    Ok((0..len)
        .map(|j| {
            let at = PER_SECTION * j;
            let x0 = ode.x0[j];
            Refined {
                y: [x0 + radau.y[at], radau.y[at + 1], radau.y[at + 2]],
                friction: q[j][0],
                position: x0 * (t1 - t0) + q[j][1],
                stats: std::mem::take(&mut stats),
                next_step,
                joined_next: j + 1 < len,
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::string::equations::tests::model;
    use crate::physics::{Dahl, LuGre};

    /// Classic RK4 in `steps` equal steps on the string's own right-hand side from `y0` over
    /// `[t0, t1]`, each section's friction impulse integrated with it (one more component
    /// each): the end state and the impulses.
    fn rk4<L: FrictionLaw>(
        m: &StringModel<L>,
        y0: &[f64],
        (t0, t1): (f64, f64),
        steps: usize,
    ) -> (Vec<f64>, Vec<f64>) {
        let (n, sections) = (y0.len(), m.n());
        let h = (t1 - t0) / steps as f64;
        let f = |t: f64, y: &[f64]| {
            let mut dy = vec![0.0; n + sections];
            m.rhs(t, &y[..n], &mut dy[..n]);
            for i in 0..sections {
                let k = PER_SECTION * i;
                dy[n + i] = m.contact(i, t, y[k + 1], y[k + 2]).1;
            }
            dy
        };
        let at = |y: &[f64], k: &[f64], c: f64| -> Vec<f64> {
            y.iter().zip(k).map(|(y, k)| y + c * k).collect()
        };
        let mut y = y0.to_vec();
        y.resize(n + sections, 0.0);
        for s in 0..steps {
            let t = t0 + s as f64 * h;
            let k1 = f(t, &y);
            let k2 = f(t + 0.5 * h, &at(&y, &k1, 0.5 * h));
            let k3 = f(t + 0.5 * h, &at(&y, &k2, 0.5 * h));
            let k4 = f(t + h, &at(&y, &k3, h));
            for i in 0..y.len() {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        let friction = y.split_off(n);
        (y, friction)
    }

    /// A run over the whole string (no outer neighbours) from a sliding, vibrating state: its
    /// end and its friction impulses are those of a tight RK4 integration of the string's
    /// equations.
    fn the_whole_string_as_a_run<L: FrictionLaw>() {
        let n = 4;
        let m = model::<L>(n, true, true);
        let (t0, t1) = (0.01, 0.0104);
        let mut y0 = vec![0.0; PER_SECTION * n];
        for i in 0..n {
            let k = PER_SECTION * i;
            y0[k] = 1e-6 * i as f64;
            y0[k + 1] = 2e-3 * (1.0 - i as f64);
            y0[k + 2] = 0.0;
        }
        let stages = [y0.clone(), y0.clone(), y0.clone()];
        let mut scales = vec![0.0; y0.len()];
        m.error_scale(&y0, &mut scales);
        let run = refine_run(
            &m,
            (0, n),
            t0,
            t1,
            &y0,
            &stages,
            (&scales, &scales),
            1e-9,
            &vec![0.0; n],
        )
        .unwrap();
        let (y, friction) = rk4(&m, &y0, (t0, t1), 40_000);
        let (yf, ff) = rk4(&m, &y0, (t0, t1), 80_000);
        for i in 0..n {
            let k = PER_SECTION * i;
            let f_scale = m.sections[i].params.mu * m.sections[i].params.f_n;
            // The reference's own error (RK4 against half its steps), far below what is
            // compared.
            assert!((ff[i] - friction[i]).abs() < 1e-12 * (t1 - t0) * f_scale);
            for c in 0..PER_SECTION {
                let w = scales[k + c] + y[k + c].abs();
                let (err, own) = (
                    (run[i].y[c] - y[k + c]).abs() / w,
                    (yf[k + c] - y[k + c]).abs() / w,
                );
                assert!(own < 1e-12, "the reference's own error {own:e}");
                assert!(
                    err < 1e-8,
                    "section {i} component {c}: {err:e} of its scale"
                );
            }
            let err = (run[i].friction - friction[i]).abs() / ((t1 - t0) * f_scale);
            assert!(
                err < 1e-8,
                "section {i} friction impulse off by {err:e} of F_C·h"
            );
        }
    }

    #[test]
    fn the_whole_string_as_a_run_is_the_string_lugre() {
        the_whole_string_as_a_run::<LuGre>();
    }

    #[test]
    fn the_whole_string_as_a_run_is_the_string_dahl() {
        the_whole_string_as_a_run::<Dahl>();
    }

    /// Sections 2 and 3 of 6 as a run, their neighbours on stages of the string's motion
    /// (RK4's): the run's momentum changes by exactly the impulses on it (the drive forces,
    /// the outer links with the neighbours' collocation polynomial, its friction impulses),
    /// to its Newton iteration's residual, and the end lies near the whole string's.
    #[test]
    fn a_run_changes_its_momentum_by_the_impulses_on_it() {
        let n = 6;
        // (The loads as parameters: one that ramps through 0 would take the reference's
        // steps with it.)
        let m = model::<LuGre>(n, true, false);
        let (t0, t1) = (0.01, 0.0104);
        let h = t1 - t0;
        let mut y0 = vec![0.0; PER_SECTION * n];
        for i in 0..n {
            y0[PER_SECTION * i + 1] = 1e-3 * (2.0 - i as f64);
        }
        let stages: [Vec<f64>; 3] =
            std::array::from_fn(|k| rk4(&m, &y0, (t0, t0 + C[k] * h), 80_000).0);
        let mut scales = vec![0.0; y0.len()];
        m.error_scale(&y0, &mut scales);
        let (first, len) = (2, 2);
        let run = refine_run(
            &m,
            (first, len),
            t0,
            t1,
            &y0,
            &stages,
            (&scales, &scales),
            1e-8,
            &vec![0.0; n],
        )
        .unwrap();
        let l = &m.links;
        let x_int =
            |i: usize| -> f64 { (0..3).map(|k| B[k] * h * stages[k][PER_SECTION * i]).sum() };
        // A neighbour's displacement as the run felt it: its velocity's polynomial through
        // the stages integrated (the stages' own displacement where they are a collocation
        // solution, as the string's are; these are RK4's).
        let dx = |i: usize| -> f64 {
            (0..3)
                .map(|k| B[k] * h * stages[k][PER_SECTION * i + 1])
                .sum()
        };
        let (a, b) = (first - 1, first + len);
        let (ra, rb) = (&run[0], &run[len - 1]);
        let top = l.k_s[a] * (ra.position - x_int(a))
            + l.c_s[a] * ((ra.y[0] - y0[PER_SECTION * first]) - dx(a));
        let bottom = l.k_s[b - 1] * (x_int(b) - rb.position)
            + l.c_s[b - 1] * (dx(b) - (rb.y[0] - y0[PER_SECTION * (b - 1)]));
        let mut impulse = bottom - top;
        let mut momentum = 0.0;
        let mut scale = 0.0;
        for (j, r) in run.iter().enumerate() {
            let i = first + j;
            let f_d: f64 = (0..3)
                .map(|k| B[k] * h * m.inputs.f_d[i].at(t0 + C[k] * h))
                .sum();
            impulse += f_d - r.friction;
            momentum += m.sections[i].params.m * (r.y[1] - y0[PER_SECTION * i + 1]);
            scale += m.sections[i].params.mu * m.sections[i].params.f_n * h;
        }
        assert!(
            (momentum - impulse).abs() < 1e-9 * scale,
            "momentum {momentum:e} against the impulses {impulse:e}"
        );
        // Near the whole string's end, to what cubics through three stages leave of the
        // neighbours' motion (measured: 1.5e-6 of the scale at most).
        let (end, _) = rk4(&m, &y0, (t0, t1), 80_000);
        for (j, r) in run.iter().enumerate() {
            let k = PER_SECTION * (first + j);
            for c in 0..PER_SECTION {
                let err = (r.y[c] - end[k + c]).abs() / (scales[k + c] + end[k + c].abs());
                assert!(err < 5e-6, "section {} component {c}: {err:e}", first + j);
            }
        }
    }
}
