//! A section whose own error failed in a step of the whole string, integrated again over that
//! step alone (the multirate strategy of Savcenco, Hundsdorfer and Verwer, BIT 47, 2007): its
//! body on its contact by its own Radau IIA with its reversals located, its drive force, its
//! end element (first and last section) and its links acting on it, its neighbours moving as
//! the string's step has them (the step's collocation polynomial). A section reversing costs
//! its own short steps, not the whole string's.
//!
//! The state is `[Δx, v, s]`, `Δx` the displacement since the step's start (the position is
//! `x0 + Δx`): the integrator's relative tolerance on `Δx` bounds the error of a displacement,
//! not of a position that may have travelled kilometres.

use nalgebra::{SMatrix, SVector};

use crate::physics::FrictionLaw;
use crate::solver::{OdeSystem, Quad, Radau5, SolverError, Workspace, B, C, MAX_SWITCH};

use super::equations::{StringModel, PER_SECTION};

/// A neighbour's position and velocity over the step: the step's collocation polynomial (its
/// value at the start and its increments at the three stages), as `p0 + θ·(p1 + θ·(p2 + θ·p3))`
/// in the fraction `θ` of the step.
#[derive(Clone, Copy, Debug)]
pub(super) struct Trajectory {
    x: [f64; 4],
    v: [f64; 4],
}

/// The cubic through 0 at `θ = 0` and the increments `d` at the nodes `C`: its coefficients of
/// `θ`, `θ²`, `θ³`. The Lagrange basis `θ/C[k]·Π_{m≠k}(θ − C[m])/(C[k] − C[m])` multiplied out.
fn monomial(d: [f64; 3]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for k in 0..3 {
        let (a, b) = (C[(k + 1) % 3], C[(k + 2) % 3]);
        let w = d[k] / (C[k] * (C[k] - a) * (C[k] - b));
        c[0] += w * a * b;
        c[1] -= w * (a + b);
        c[2] += w;
    }
    c
}

impl Trajectory {
    pub(super) fn of(j: usize, y0: &[f64], stages: &[Vec<f64>; 3]) -> Self {
        let of = |i: usize| {
            let c = monomial(std::array::from_fn(|k| stages[k][i] - y0[i]));
            [y0[i], c[0], c[1], c[2]]
        };
        Trajectory {
            x: of(PER_SECTION * j),
            v: of(PER_SECTION * j + 1),
        }
    }

    #[inline(always)]
    pub(super) fn at(&self, theta: f64) -> (f64, f64) {
        let p = |c: &[f64; 4]| c[0] + theta * (c[1] + theta * (c[2] + theta * c[3]));
        (p(&self.x), p(&self.v))
    }
}

/// What holds section `i` besides its contact: its links' and end elements' stiffness and
/// damping, and its neighbours over the step.
#[derive(Clone, Copy, Debug)]
struct Holders {
    left: Option<(f64, f64, Trajectory)>,
    right: Option<(f64, f64, Trajectory)>,
    top: bool,
    bottom: bool,
    k_sum: f64,
    c_sum: f64,
}

/// Section `i` over one step of the string.
struct SectionOde<'a, L> {
    model: &'a StringModel<L>,
    i: usize,
    holders: Holders,
    x0: f64,
    t0: f64,
    inv_h: f64,
    scale: SVector<f64, 3>,
    force_scale: f64,
    v_scale: f64,
    bound: Option<f64>,
}

struct Eval<L> {
    /// The law at the section's load at that time.
    law: L,
    ds: f64,
    f: f64,
    /// The force of the links and end elements on the section.
    held: f64,
    vr: f64,
}

impl<L: FrictionLaw> SectionOde<'_, L> {
    #[inline(always)]
    fn eval(&self, t: f64, y: &SVector<f64, 3>) -> Eval<L> {
        let m = self.model;
        let (x, v, s) = (self.x0 + y[0], y[1], y[2]);
        let law = m.law(self.i, t);
        let vr = v - m.support(self.i, t);
        let (ds, f) = law.rate_force_at(s, vr, &law.velocity_terms(vr));
        let hd = &self.holders;
        let mut held = 0.0;
        let theta = (t - self.t0) * self.inv_h;
        for (k, c, tr) in [&hd.left, &hd.right].into_iter().flatten() {
            let (xn, vn) = tr.at(theta);
            held += k * (xn - x) + c * (vn - v);
        }
        if hd.top {
            held += m.top_force(t, x, v);
        }
        if hd.bottom {
            held -= m.bottom_force(t, x, v);
        }
        Eval {
            law,
            ds,
            f,
            held,
            vr,
        }
    }

    #[inline(always)]
    fn rhs_at(&self, t: f64, y: &SVector<f64, 3>, e: &Eval<L>) -> SVector<f64, 3> {
        let force = self.model.inputs.f_d[self.i].at(t) + e.held - e.f;
        SVector::from([y[1], force * self.model.sections[self.i].inv_m, e.ds])
    }
}

impl<L: FrictionLaw> OdeSystem<3> for SectionOde<'_, L> {
    #[inline(always)]
    fn rhs(&self, t: f64, y: &SVector<f64, 3>) -> SVector<f64, 3> {
        let e = self.eval(t, y);
        self.rhs_at(t, y, &e)
    }

    fn scale(&self) -> SVector<f64, 3> {
        self.scale
    }

    fn n_switch(&self) -> usize {
        1
    }

    /// The relative velocity: `|v_r|` has a kink where it passes through zero.
    #[inline(always)]
    fn switch(&self, t: f64, y: &SVector<f64, 3>) -> [f64; MAX_SWITCH] {
        [self.eval(t, y).vr, 1.0]
    }

    fn switch_scale(&self) -> [f64; MAX_SWITCH] {
        [self.v_scale, 0.0]
    }

    fn jacobian(&self, t: f64, y: &SVector<f64, 3>) -> Option<SMatrix<f64, 3, 3>> {
        self.rhs_jacobian(t, y).1
    }

    #[inline(always)]
    fn rhs_jacobian(
        &self,
        t: f64,
        y: &SVector<f64, 3>,
    ) -> (SVector<f64, 3>, Option<SMatrix<f64, 3, 3>>) {
        let e = self.eval(t, y);
        let lj = e.law.jacobian(y[2], e.vr, e.ds);
        let inv_m = self.model.sections[self.i].inv_m;
        let hd = &self.holders;
        #[rustfmt::skip]
        let jac = SMatrix::<f64, 3, 3>::from_row_slice(&[
            0.0, 1.0, 0.0,
            -hd.k_sum * inv_m, -(hd.c_sum + lj.force_v[0][0]) * inv_m, -lj.force_s[0][0] * inv_m,
            0.0, lj.rate_v[0][0], lj.rate_s[0][0],
        ]);
        (self.rhs_at(t, y, &e), Some(jac))
    }

    #[inline(always)]
    fn observe(&self, t: f64, y: &SVector<f64, 3>) -> ([f64; MAX_SWITCH], Quad) {
        let e = self.eval(t, y);
        ([e.vr, 1.0], [e.f, y[0]])
    }

    /// `F_Fx` (its step mean), and the displacement (whose integral gives the end elements'
    /// step means).
    #[inline(always)]
    fn quadrature(&self, t: f64, y: &SVector<f64, 3>) -> Quad {
        [self.eval(t, y).f, y[0]]
    }

    /// One evaluation of the law for both.
    #[inline(always)]
    fn rhs_quadrature(&self, t: f64, y: &SVector<f64, 3>) -> (SVector<f64, 3>, Quad) {
        let e = self.eval(t, y);
        (self.rhs_at(t, y, &e), [e.f, y[0]])
    }

    fn quadrature_scale(&self) -> f64 {
        self.force_scale
    }

    /// Neither steers: both integrals follow the state's accuracy, as the step means of the
    /// sections that were not integrated again follow the string's. Steering on `∫F_Fx dt`
    /// (its unfiltered embedded estimate, pessimistic where the contact is stiff) took 2.8
    /// times the section steps for no measurable gain: the errors against the tight reference
    /// integration (`tests/string.rs`) were the same to two digits with and without it.
    fn quadrature_steers(&self) -> usize {
        0
    }

    fn project(&self, _t: f64, y: &mut SVector<f64, 3>) {
        if let Some(bound) = self.bound {
            y[2] = y[2].clamp(-bound, bound);
        }
    }
}

/// A section integrated again: its state at the step's end, the integrals over the step of
/// its friction force and its position, and the step its integrator would take next.
pub struct Refined {
    pub y: [f64; 3],
    pub friction: f64,
    pub position: f64,
    pub stats: crate::solver::SolverStats,
    pub next_step: f64,
    /// Integrated together with the next section (`run.rs`): the link between them is
    /// resolved in their own steps, its impulse the same on both sides.
    pub joined_next: bool,
}

/// Integrates section `i` again from `t0` (state `y0`) to `t1` with its neighbours on the
/// string's step (`stages`), to the internal tolerance `0.3·tol`, with the natural scales
/// `scales` of its velocity and deformation (`[_, v, s]` per section, as the string's error
/// scale at rest) and `x_scale` of its position (the string's at `y0`), starting with the step
/// `own_step` its last refinement ended with (0: none yet).
#[allow(clippy::too_many_arguments)]
pub fn refine<L: FrictionLaw>(
    model: &StringModel<L>,
    i: usize,
    t0: f64,
    t1: f64,
    y0: &[f64],
    stages: &[Vec<f64>; 3],
    scales: &[f64],
    x_scale: f64,
    tol: f64,
    own_step: f64,
    work: &mut Workspace,
) -> Result<Refined, SolverError> {
    let n = model.n();
    let l = &model.links;
    let left = (i > 0).then(|| {
        (
            l.k_s[i - 1],
            l.c_s[i - 1],
            Trajectory::of(i - 1, y0, stages),
        )
    });
    let right = (i + 1 < n).then(|| (l.k_s[i], l.c_s[i], Trajectory::of(i + 1, y0, stages)));
    let (top, bottom) = (i == 0, i + 1 == n);
    let (k_sum, c_sum) = model.holding(i);
    let sec = &model.sections[i];
    let k = PER_SECTION * i;
    let s_nom = sec.law.s_scale();
    let p = &sec.params;
    let ode = SectionOde {
        model,
        i,
        holders: Holders {
            left,
            right,
            top,
            bottom,
            k_sum,
            c_sum,
        },
        x0: y0[k],
        t0,
        inv_h: 1.0 / (t1 - t0),
        scale: SVector::from([x_scale, scales[k + 1], scales[k + 2]]),
        force_scale: (p.k_t * s_nom).max(p.h_v * scales[k + 1]).max(1e-300),
        v_scale: scales[k + 1],
        bound: if model.inputs.f_n.is_empty() {
            sec.law.bound()
        } else {
            None
        },
    };
    // RADAU5 holds `0.1·tol'^(2/3)`: `tol' = (3·tol)^1.5` gives `0.3·tol`, three times the
    // string's own `0.1·tol`. Measured (`examples/string_bench.rs`, LuGre, tolerance 1e-6,
    // tool on, 0.1 s at 20 and 100 sections): 17 % fewer own steps of the sections than at
    // `0.1·tol` and 4.6 % fewer instructions, the errors against `tests/string.rs`'s reference
    // the same to their second digit at twelve tolerances from 6e-9 to 2e-6 (at `tol` itself,
    // 10 % fewer instructions, but errors up to 1.4 times as large at 1e-6).
    // It is integrated again because the string's step was too long for it: it starts where
    // its last refinement left off (a section at a reversal is refined over several of the
    // string's steps), at most the whole step; a quarter of it the first time.
    let first = if own_step > 0.0 {
        own_step.min(t1 - t0)
    } else {
        0.25 * (t1 - t0)
    };
    let mut r = Radau5::new(
        t0,
        SVector::from([0.0, y0[k + 1], y0[k + 2]]),
        libm::pow(3.0 * tol, 1.5),
    )
    .first_step(first);
    let mut q = [0.0; 2];
    r.integrate_with(work, &ode, t1, f64::INFINITY, |st| {
        q[0] += st.quad[0];
        q[1] += st.quad[1];
    })?;
    Ok(Refined {
        y: [y0[k] + r.y[0], r.y[1], r.y[2]],
        friction: q[0],
        position: y0[k] * (t1 - t0) + q[1],
        stats: r.stats,
        next_step: r.proposed_step(),
        joined_next: false,
    })
}

/// Makes the links' impulses over a step agree on both sides where sections were integrated
/// again (as at the faces between coarse and fine cells of adaptive mesh refinement): a section
/// integrated again felt its links with its own new motion and its neighbours on the string's
/// step, its neighbours felt them with its motion on the string's step. Each link touching such a
/// section gets one impulse (the sections' own, their mean where both ends were integrated
/// again), and every section the difference it did not get, as a change of its velocity (and
/// of its position by half the step times it). Then the string's momentum changes over the step
/// by exactly the external impulses, as its equations say. Writes the new states of the
/// sections integrated again (`refined`, ascending) into the last stage. The step's integrals
/// are taken before: a section's momentum changes by the quadrature of its forces on the stages
/// Newton solved (and the correction's impulse), so its friction integral on the corrected
/// stage would miss that by `B₃·h·∂F/∂v·Δv`.
pub fn reflux<L: FrictionLaw>(
    model: &StringModel<L>,
    h: f64,
    y0: &[f64],
    stages: &mut [Vec<f64>; 3],
    refined: &[(usize, Refined)],
) {
    let n = model.n();
    // `refined` ascends: a section's own integration, if any, by a walk along it.
    let own = |i: usize, from: &mut usize| {
        while *from < refined.len() && refined[*from].0 < i {
            *from += 1;
        }
        refined.get(*from).filter(|r| r.0 == i).map(|r| &r.1)
    };
    // A section's position integral and displacement over the step: on the string's step, or
    // its own.
    let coarse = |i: usize| {
        let k = PER_SECTION * i;
        let integral: f64 = (0..3).map(|q| B[q] * h * stages[q][k]).sum();
        (integral, stages[2][k] - y0[k])
    };
    let fine = |i: usize, r: &Refined| (r.position, r.y[0] - y0[PER_SECTION * i]);
    // The impulse each section did not get, for the sections beside a link that touches a
    // section integrated again (ascending, at most two links each).
    let mut dp: Vec<(usize, f64)> = Vec::with_capacity(3 * refined.len());
    let mut add = |i: usize, p: f64| match dp.last_mut() {
        Some(last) if last.0 == i => last.1 += p,
        _ => dp.push((i, p)),
    };
    // The links touching a section integrated again, each once and in order: the one on its
    // left unless that section was integrated again too (its right link), and the one on its
    // right.
    let (mut at_a, mut at_b) = (0, 0);
    let mut last_link = None;
    for &(i, _) in refined {
        for a in [i.checked_sub(1), (i + 1 < n).then_some(i)]
            .into_iter()
            .flatten()
        {
            if last_link.is_some_and(|l| l >= a) {
                continue;
            }
            last_link = Some(a);
            let b = a + 1;
            let (ra, rb) = (own(a, &mut at_a), own(b, &mut at_b));
            if ra.is_some_and(|r| r.joined_next) {
                // Inside a run integrated together: both felt the same impulse.
                continue;
            }
            let (k, c) = (model.links.k_s[a], model.links.c_s[a]);
            let impulse =
                |(xa, da): (f64, f64), (xb, db): (f64, f64)| k * (xb - xa) + c * (db - da);
            let on_step = impulse(coarse(a), coarse(b));
            // What each end felt: section a gets +J, section b −J.
            let felt_a = ra.map_or(on_step, |r| impulse(fine(a, r), coarse(b)));
            let felt_b = rb.map_or(on_step, |r| impulse(coarse(a), fine(b, r)));
            let agreed = match (ra, rb) {
                (Some(_), Some(_)) => 0.5 * (felt_a + felt_b),
                (Some(_), None) => felt_a,
                _ => felt_b,
            };
            add(a, agreed - felt_a);
            add(b, -(agreed - felt_b));
        }
    }
    for (i, r) in refined {
        let k = PER_SECTION * i;
        stages[2][k..k + PER_SECTION].copy_from_slice(&r.y);
    }
    for &(i, p) in &dp {
        if p != 0.0 {
            let dv = p * model.sections[i].inv_m;
            let k = PER_SECTION * i;
            stages[2][k + 1] += dv;
            stages[2][k] += 0.5 * h * dv;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The increments of a cubic through 0 at the nodes give back its coefficients.
    #[test]
    fn a_trajectory_is_the_cubic_through_its_stages() {
        let q = |t: f64| 0.3 * t - 1.7 * t * t + 2.9 * t * t * t;
        let c = monomial(std::array::from_fn(|k| q(C[k])));
        for (got, want) in c.iter().zip([0.3, -1.7, 2.9]) {
            assert!((got - want).abs() < 1e-13, "{c:?}");
        }
        let y0 = vec![5.0, -2.0, 0.1];
        let stages: [Vec<f64>; 3] =
            std::array::from_fn(|k| vec![5.0 + q(C[k]), -2.0 + 2.0 * q(C[k]), 0.0]);
        let tr = Trajectory::of(0, &y0, &stages);
        for theta in [0.0, 0.25, C[0], 0.5, C[1], 1.0] {
            let (x, v) = tr.at(theta);
            assert!((x - (5.0 + q(theta))).abs() < 1e-13, "x at {theta}");
            assert!((v - (-2.0 + 2.0 * q(theta))).abs() < 1e-13, "v at {theta}");
        }
    }
}
