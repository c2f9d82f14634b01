//! The exponential path: a velocity drive with the lateral motion guided (no body state) and
//! a law linear in `s` where the closed form does not apply, integrated by the exponential
//! integrator in the relaxation arc length (`solver/expint.rs`; the contact's side,
//! [`Relaxation1`], in `dynamics.rs`), its steps ending on every sign change of `v_rx`.

use super::exact::{forcing_x, sign_changes};
use super::{exact, Integrated, Kept, Path, Shared};
use crate::model::drive::DriveKind;
use crate::model::dynamics::Relaxation1;
use crate::model::simulator::SimError;
use crate::physics::{FrictionLaw, Vector};
use crate::solver::expint::ExpIntegrator;
use crate::solver::{Quad, MAX_QUAD};

/// The exponential path.
pub(super) struct Exponential;

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Path<V, L, D, N> for Exponential {
    /// A velocity drive with the lateral motion guided (no body state) and a law linear in
    /// `s`, where the closed form does not apply.
    fn applies(c: &Shared<'_, V, L, D, N>, _: &Integrated<N>, k: &Kept<N>) -> bool {
        D::N_BODY == 0
            && !k.force_radau
            && c.dynamics.load.is_none()
            && exact::relaxation(c, k).is_none()
            && c.dynamics.law.linear(V::from_xy(1.0, 0.0)).is_some()
    }

    fn advance(
        c: &Shared<'_, V, L, D, N>,
        r: &mut Integrated<N>,
        k: &mut Kept<N>,
        t_target: f64,
        h_max: f64,
    ) -> Result<Quad, SimError> {
        Ok(advance_exp(c, r, k, t_target, h_max)?.1)
    }
}

/// Advances the exponential integrator to `t_target`, steps ending on every sign change of
/// `v_rx` (a kink of `|v_r|` where `v_ry` vanishes too); returns `∫ a dt` (the decay) and
/// `∫F_F dt`.
pub(super) fn advance_exp<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
    c: &Shared<'_, V, L, D, N>,
    r: &mut Integrated<N>,
    k: &mut Kept<N>,
    t_target: f64,
    h_max: f64,
) -> Result<(f64, Quad), SimError> {
    let t0 = r.t;
    let forcing = forcing_x(c.dynamics, t0, c.config.input_support);
    let mut knots = [0.0f64; 8];
    let mut n = 0;
    sign_changes(&forcing, t_target - t0, |root| {
        if n < knots.len() {
            knots[n] = t0 + root;
            n += 1;
        }
    });
    let sys = Relaxation1 {
        dynamics: c.dynamics,
        input_support: c.config.input_support,
    };
    let mut ei = ExpIntegrator::new(r.tolerance());
    ei.h = k.h;
    let mut s = [0.0; 2];
    s[..V::DIM].copy_from_slice(&r.y.as_slice()[..V::DIM]);
    let s_scale = c.scale[0];
    let mut integral = [0.0; MAX_QUAD];
    let mut a = t0;
    for &b in knots[..n].iter().chain(std::iter::once(&t_target)) {
        if b > a {
            let i = ei
                .integrate(&sys, a, b, &mut s, s_scale, c.force_scale, h_max)
                .map_err(SimError::Solver)?;
            integral[0] += i[0];
            integral[1] += i[1];
            a = b;
        }
    }
    let mut y = r.y;
    y.as_mut_slice()[..V::DIM].copy_from_slice(&s[..V::DIM]);
    c.finish(r, t_target, y);
    k.propose(ei.h);
    let st = &mut r.stats;
    st.steps += ei.steps;
    st.rejected += ei.rejected;
    st.rhs_evals += ei.evals;
    st.events += n as u64;
    Ok((ei.decay, integral))
}
