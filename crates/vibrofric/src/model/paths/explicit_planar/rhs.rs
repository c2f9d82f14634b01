//! The right-hand side of the planar explicit path's integrated vector: the state, `∫F_F dt`
//! and the relaxation arc length λ, and what it needs at each stage.

use super::*;

/// The right-hand side of the integrated vector (the state, `∫F_F dt` and λ,
/// [`steps`](fn@steps)).
pub(super) struct Eqs<
    's,
    'a,
    V: Vector,
    L: FrictionLaw,
    D: DriveKind<V>,
    const N: usize,
    const M: usize,
> {
    pub(super) sys: &'s System<'a, V, L, D>,
    pub(super) relax: Relax<L>,
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize, const M: usize>
    Eqs<'_, '_, V, L, D, N, M>
{
    /// What the right-hand side needs at `(tt, u)` besides the deformation.
    #[inline(always)]
    pub(super) fn kin(&self, tt: f64, u: &[f64; M]) -> Kin<V> {
        Kin::at(self.sys, &self.relax, tt, &u[..N])
    }

    /// The right-hand side at `u` with the deformation `s` (the state's own, or an
    /// exponential or manifold stage's), given what it needs there, `kin`: the relative
    /// velocity and its decay rate `|v_r|/s_ss` (LuGre `|v_r|/g(v_r)`); the body's equations
    /// read only `u`'s body part.
    #[inline(always)]
    pub(super) fn rhs_with(&self, u: &[f64; M], s: V, kin: &Kin<V>) -> [f64; M] {
        let (ds, f) = self.sys.dynamics.law.rate_force_at(s, kin.vr, &kin.terms);
        let e = Eval {
            s,
            v: kin.v,
            vr: kin.vr,
            ds,
            f,
            drive: kin.drive,
        };
        let r = self.sys.rhs_at::<N>(&e, &u[..N]);
        let mut out = [0.0; M];
        out[..N].copy_from_slice(r.as_slice());
        out[N] = f.x();
        if V::DIM == 2 {
            out[N + 1] = f.y();
        }
        out[N + V::DIM] = kin.terms.decay;
        out
    }

    /// The right-hand side at `(tt, u)`.
    #[inline(always)]
    pub(super) fn rhs(&self, tt: f64, u: &[f64; M]) -> [f64; M] {
        self.rhs_with(u, V::read(&u[..V::DIM]), &self.kin(tt, u))
    }
}

/// `v_r` at `(t, u)`.
#[inline(always)]
pub(super) fn relative_velocity<
    V: Vector,
    L: FrictionLaw,
    D: DriveKind<V>,
    const N: usize,
    const M: usize,
>(
    sys: &System<'_, V, L, D>,
    t: f64,
    u: &[f64; M],
) -> V {
    let d = sys.dynamics.drive_inputs(t);
    sys.dynamics.drive.velocity(&u[V::DIM..N], &d) - sys.support(t)
}

/// What the right-hand side needs at one time and state besides the deformation: the drive's
/// inputs, the body's velocity, the relative velocity and its relaxation rate.
pub(super) struct Kin<V> {
    pub(super) drive: DriveInputs,
    pub(super) v: V,
    pub(super) vr: V,
    /// The relaxation rate `|v_r|/s_ss` (LuGre `|v_r|/g(v_r)`) and what the force needs.
    pub(super) terms: VelocityTerms,
}

impl<V: Vector> Kin<V> {
    #[inline(always)]
    pub(super) fn at<L: FrictionLaw, D: DriveKind<V>>(
        sys: &System<'_, V, L, D>,
        relax: &Relax<L>,
        t: f64,
        y: &[f64],
    ) -> Self {
        Self::with_support(sys, relax, t, y, sys.support(t))
    }

    /// As [`Kin::at`], with the support velocity `vs` at `t` given.
    #[inline(always)]
    pub(super) fn with_support<L: FrictionLaw, D: DriveKind<V>>(
        sys: &System<'_, V, L, D>,
        relax: &Relax<L>,
        t: f64,
        y: &[f64],
        vs: V,
    ) -> Self {
        let drive = sys.dynamics.drive_inputs(t);
        let v = sys.dynamics.drive.velocity(&y[V::DIM..], &drive);
        let vr = v - vs;
        Kin {
            drive,
            v,
            vr,
            terms: relax.terms(vr),
        }
    }

    /// Where the deformation relaxes to: `v_r/decay` (`s_ss·v_r/|v_r|`, LuGre
    /// `g(v_r)·v_r/|v_r|`), 0 at `v_r` = 0.
    #[inline(always)]
    pub(super) fn target(&self) -> [f64; 2] {
        if self.terms.decay > 0.0 {
            let q = self.vr * (1.0 / self.terms.decay);
            [q.x(), q.y()]
        } else {
            [0.0; 2]
        }
    }
}

/// The law's relaxation rate at a relative velocity: Dahl's at its constant length `s_ss`, or
/// a law linear in `s` (LuGre) at the length `g(v_r)` of its rate `ds/dt = (|v_r|/g)·(q − s)`.
pub(super) struct Relax<L> {
    pub(super) law: L,
    /// Dahl's `1/s_ss`.
    pub(super) dahl: Option<f64>,
}

impl<L: FrictionLaw> Relax<L> {
    pub(super) fn new(law: L) -> Self {
        Relax {
            law,
            dahl: law.relaxation().map(|r| 1.0 / r.length),
        }
    }

    /// The relaxation rate `dλ/dt` (`|v_r|/s_ss`, LuGre `|v_r|/g(v_r)`) and the law's other
    /// terms at `v_r`.
    #[inline(always)]
    pub(super) fn terms<V: Vector>(&self, vr: V) -> VelocityTerms {
        match self.dahl {
            Some(inv_len) => VelocityTerms {
                decay: vr.norm() * inv_len,
                damping: 0.0,
            },
            None => self.law.velocity_terms(vr),
        }
    }
}
