//! The right-hand side the integrators solve and its closed-form Jacobian: the deformation rate
//! of the friction law at the relative velocity `v_r = v − v_s` (support velocity from the
//! harmonic source and the input tracks), the body's equations from its drive, and the normal
//! load with lift-off.

// Jacobian assembly indexes rows and columns of several matrices in lockstep.
#![allow(clippy::needless_range_loop)]

use nalgebra::{SMatrix, SVector};

use super::drive::{DriveInputs, DriveKind, Jac};
use crate::physics::{FrictionLaw, Harmonic, InputTrack, Vector};
use crate::solver::expint::{Relaxing, Sample};
use crate::solver::{OdeSystem, Quad, MAX_DIM, MAX_SWITCH};
use crate::table::{InputId, Params};

/// The normal force below which the body has lifted off: the integrator's relative tolerance
/// of the reference load `f_n_ref` (1 N without one). The friction the contact could still carry is then
/// within the tolerance of none, and the laws stay well-conditioned down to it (a load that
/// tends to 0 makes the relaxation rate `|v_r|/s_ss` grow without bound).
pub(super) fn lift_off(reference: &Params, rtol: f64) -> f64 {
    rtol * if reference.f_n_ref > 0.0 {
        reference.f_n_ref
    } else {
        1.0
    }
}

/// The parameters at the normal force `f_n`: `F_N` replaced, the reference load
/// ([`Params::f_n_ref`], the scene's start value of `F_N`) kept. LuGre's static force `F_S` and
/// contact damping `zeta_t` follow the load as with a parameter `F_N` ([`Params::static_force`],
/// [`Params::damping_ratio`]), so that every friction force of the contact is proportional to
/// the load. `F_C = mu·F_N` and everything the laws derive from it (`s_ss`, LuGre's `g`) follow.
/// Without the scaling of the damping, LuGre's `h_t·ds/dt` would grow without bound against
/// `k_t·s` as the load, and with it `g`, tends to 0.
pub(super) fn loaded(reference: &Params, f_n: f64) -> Params {
    let mut p = *reference;
    if reference.f_n_ref <= 0.0 {
        // No reference load: no Stribeck peak, F_S = F_C, taken as it is.
        p.f_s = reference.mu * f_n;
    }
    p.f_n = f_n;
    p
}

/// The right-hand side: everything the integrator needs, nothing it changes.
#[derive(Clone, Copy, Debug)]
pub struct Dynamics<V: Vector, L: FrictionLaw, D: DriveKind<V>> {
    pub(super) law: L,
    pub(super) drive: D,
    pub(super) harmonic: Option<Harmonic>,
    /// Input tracks, indexed like [`InputId::ALL`].
    pub(super) tracks: [InputTrack; 5],
    /// With the normal force an input: the parameters, whose reference load `f_n_ref` (the
    /// scene's start value of `F_N`) the law at `F_N(t)` is scaled from.
    pub(super) load: Option<Params>,
    /// With the normal force an input: the load below which the body has lifted off.
    pub(super) lift_off: f64,
    /// The body has lifted off: no load until the input rises above [`Dynamics::lift_off`]
    /// again. Changes only between integrator segments (at the crossing instants and when the
    /// input is set), so that the law is smooth inside each.
    pub(super) lifted: bool,
    /// `x_kin` at the reference time of the `v_d` track.
    pub(super) x_kin_ref: f64,
    pub(super) f_c: f64,
    pub(super) _v: std::marker::PhantomData<V>,
}

/// Kinematic and force quantities at one state.
#[derive(Clone, Copy, Debug)]
pub(super) struct Eval<V> {
    pub(super) s: V,
    pub(super) v: V,
    pub(super) vr: V,
    pub(super) ds: V,
    pub(super) f: V,
    pub(super) drive: DriveInputs,
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>> Dynamics<V, L, D> {
    /// The same law, support motion and inputs with the body moved by `drive` in `W`'s
    /// dimension (a planar motion that stays on the x axis integrated in one dimension: the
    /// support's lateral motion is then left out).
    pub(super) fn with_drive<W: Vector, E: DriveKind<W>>(&self, drive: E) -> Dynamics<W, L, E> {
        Dynamics {
            law: self.law,
            drive,
            harmonic: self.harmonic,
            tracks: self.tracks,
            load: self.load,
            lift_off: self.lift_off,
            lifted: self.lifted,
            x_kin_ref: self.x_kin_ref,
            f_c: self.f_c,
            _v: std::marker::PhantomData,
        }
    }

    /// The normal force at `t` where it is an input: the track, or 0 while lifted off.
    #[inline(always)]
    pub(super) fn load_at(&self, t: f64) -> f64 {
        if self.lifted {
            0.0
        } else {
            self.tracks[InputId::FN.index()].at(t).max(0.0)
        }
    }

    /// Whether a body with the load input at `t` is off the support: at most the lift-off
    /// load, and not rising.
    pub(super) fn off_at(&self, t: f64) -> bool {
        let track = &self.tracks[InputId::FN.index()];
        let f_n = track.at(t);
        f_n < self.lift_off || (f_n == self.lift_off && track.slope <= 0.0)
    }

    /// The law at time `t`: with the normal force an input, made for `F_N(t)` with the static
    /// force `F_S` scaled with the load; else the law of the parameters.
    #[inline(always)]
    pub(super) fn law_at(&self, t: f64) -> L {
        match &self.load {
            None => self.law,
            Some(reference) => L::new(&loaded(reference, self.load_at(t))),
        }
    }

    /// `F_C` at time `t`.
    pub(super) fn f_c_at(&self, t: f64) -> f64 {
        match &self.load {
            None => self.f_c,
            Some(reference) => loaded(reference, self.load_at(t)).f_c(),
        }
    }

    /// The first time in `(t0, t1)` at which an extrapolated normal force input crosses the
    /// lift-off load, down while on or up while off: a kink of the law the integrator steps
    /// onto.
    pub(super) fn load_event(&self, t0: f64, t1: f64) -> Option<f64> {
        self.load.as_ref()?;
        let track = &self.tracks[InputId::FN.index()];
        if track.slope == 0.0 || (track.slope < 0.0) == self.lifted {
            return None;
        }
        let t = track.t_ref + (self.lift_off - track.value) / track.slope;
        (t > t0 && t < t1 && t - t0 > 1e-15 * t0.abs().max(t1 - t0)).then_some(t)
    }

    #[inline(always)]
    pub(super) fn drive_inputs(&self, t: f64) -> DriveInputs {
        let vd = &self.tracks[InputId::VD.index()];
        DriveInputs {
            f_d: self.tracks[InputId::FD.index()].at(t),
            v_d: vd.at(t),
            x_kin: self.x_kin_ref + vd.integral(t),
        }
    }

    /// Support velocity: the harmonic source plus the input tracks, as enabled.
    #[inline(always)]
    pub(super) fn support_velocity(&self, t: f64, input_support: bool) -> V {
        let mut vs = V::default();
        if let Some(h) = &self.harmonic {
            let (x, y) = h.velocity(t);
            vs = V::from_xy(x, y);
        }
        if input_support {
            vs = vs
                + V::from_xy(
                    self.tracks[InputId::VSx.index()].at(t),
                    self.tracks[InputId::VSy.index()].at(t),
                );
        }
        vs
    }

    /// Everything at `(t, y)`, given the support velocity `vs` at `t`.
    #[inline(always)]
    pub(super) fn eval(&self, t: f64, y: &[f64], vs: V) -> Eval<V> {
        let s = V::read(y);
        let body = &y[V::DIM..];
        let drive = self.drive_inputs(t);
        let v = self.drive.velocity(body, &drive);
        let vr = v - vs;
        let law = self.law_at(t);
        let ds = law.rate(s, vr);
        let f = law.force(s, vr, ds);
        Eval {
            s,
            v,
            vr,
            ds,
            f,
            drive,
        }
    }
}

/// A velocity drive's deformation as the exponential integrator sees it: `v_r(t)` known, the
/// law linear in `s` (see [`FrictionLaw::linear`]).
pub(super) struct Relaxation1<'a, V: Vector, L: FrictionLaw, D: DriveKind<V>> {
    pub(super) dynamics: &'a Dynamics<V, L, D>,
    pub(super) input_support: bool,
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>> Relaxing for Relaxation1<'_, V, L, D> {
    fn dim(&self) -> usize {
        V::DIM
    }
    #[inline(always)]
    fn sample(&self, t: f64) -> Sample {
        let dyn_ = self.dynamics;
        let vs = dyn_.support_velocity(t, self.input_support);
        let v = dyn_.drive.velocity(&[], &dyn_.drive_inputs(t));
        let vr = v - vs;
        match dyn_.law.linear(vr) {
            Some(l) => Sample {
                a: l.decay,
                q: [l.target.x(), l.target.y()],
                c: l.force_s,
                d: [l.force_0.x(), l.force_0.y()],
            },
            None => Sample::default(),
        }
    }
}

/// How many of the quadrature's integrands (`F_Fx`, `F_Fy`) steer Radau's step size.
pub(super) const QUAD_STEERS: usize = 1;

/// Number of support velocities a [`System`] remembers: the integrator evaluates the right-hand
/// side, its Jacobian, the switching functions and the quadrature at the same three stage times.
pub(super) const SUPPORT_CACHE: usize = 4;

/// The system the integrator sees during one call: dynamics, the run-time support flag, and a
/// memo of the support velocity (one `cos` per distinct time instead of one per evaluation).
pub(super) struct System<'a, V: Vector, L: FrictionLaw, D: DriveKind<V>> {
    pub(super) dynamics: &'a Dynamics<V, L, D>,
    pub(super) input_support: bool,
    pub(super) scale: &'a [f64],
    pub(super) force_scale: f64,
    pub(super) switch_scale: [f64; MAX_SWITCH],
    pub(super) cache: std::cell::Cell<([(f64, V); SUPPORT_CACHE], usize)>,
}

impl<'a, V: Vector, L: FrictionLaw, D: DriveKind<V>> System<'a, V, L, D> {
    pub(super) fn new(
        dynamics: &'a Dynamics<V, L, D>,
        input_support: bool,
        scale: &'a [f64],
        force_scale: f64,
        switch_scale: [f64; MAX_SWITCH],
    ) -> Self {
        System {
            dynamics,
            input_support,
            scale,
            force_scale,
            switch_scale,
            cache: std::cell::Cell::new(([(f64::NAN, V::default()); SUPPORT_CACHE], 0)),
        }
    }

    #[inline(always)]
    pub(super) fn support(&self, t: f64) -> V {
        let (mut slots, next) = self.cache.get();
        if let Some(&(_, v)) = slots.iter().find(|(ts, _)| *ts == t) {
            return v;
        }
        let v = self.dynamics.support_velocity(t, self.input_support);
        slots[next] = (t, v);
        self.cache.set((slots, (next + 1) % SUPPORT_CACHE));
        v
    }

    /// Remembers the support velocity `v` at `t` computed elsewhere (with the same bits as
    /// [`Dynamics::support_velocity`]), for the evaluations at `t` that follow.
    #[inline(always)]
    pub(super) fn remember_support(&self, t: f64, v: V) {
        let (mut slots, next) = self.cache.get();
        if slots.iter().any(|(ts, _)| *ts == t) {
            return;
        }
        slots[next] = (t, v);
        self.cache.set((slots, (next + 1) % SUPPORT_CACHE));
    }

    #[inline(always)]
    pub(super) fn eval(&self, t: f64, y: &[f64]) -> Eval<V> {
        self.dynamics.eval(t, y, self.support(t))
    }

    /// `dy/dt` from an evaluation at `y`.
    #[inline(always)]
    pub(super) fn rhs_at<const N: usize>(&self, e: &Eval<V>, y: &[f64]) -> SVector<f64, N> {
        let mut out = SVector::<f64, N>::zeros();
        let o = out.as_mut_slice();
        e.ds.write(o);
        if D::N_BODY > 0 {
            self.dynamics
                .drive
                .body_rate(&y[V::DIM..], e.f, &e.drive, &mut o[V::DIM..]);
        }
        out
    }

    /// `∂(dy/dt)/∂y` from an evaluation.
    #[inline(always)]
    pub(super) fn jacobian_at<const N: usize>(&self, t: f64, e: &Eval<V>) -> SMatrix<f64, N, N> {
        let lj = self.dynamics.law_at(t).jacobian(e.s, e.vr, e.ds);
        let mut jac: Jac = [[0.0; MAX_DIM]; MAX_DIM];
        for i in 0..V::DIM {
            for j in 0..V::DIM {
                jac[i][j] = lj.rate_s[i][j];
            }
        }
        self.dynamics.drive.jacobian(&lj, &mut jac);
        SMatrix::from_fn(|i, j| jac[i][j])
    }
}

impl<const N: usize, V: Vector, L: FrictionLaw, D: DriveKind<V>> OdeSystem<N>
    for System<'_, V, L, D>
{
    #[inline(always)]
    fn rhs(&self, t: f64, y: &SVector<f64, N>) -> SVector<f64, N> {
        let y = y.as_slice();
        self.rhs_at(&self.eval(t, y), y)
    }

    fn scale(&self) -> SVector<f64, N> {
        SVector::<f64, N>::from_column_slice(self.scale)
    }

    fn n_switch(&self) -> usize {
        if V::DIM == 2 && L::PLANAR_SWITCH {
            2
        } else {
            1
        }
    }

    /// `v_rx` (the kink of `|v_r|` in 1-D, and wherever `v_r` passes through zero along x),
    /// and in planar Dupont the direction test `s·v_r`.
    #[inline(always)]
    fn switch(&self, t: f64, y: &SVector<f64, N>) -> [f64; MAX_SWITCH] {
        let e = self.eval(t, y.as_slice());
        [e.vr.x(), e.s.dot(e.vr)]
    }

    /// In closed form from the law's partial derivatives and the drive's structure.
    fn jacobian(&self, t: f64, y: &SVector<f64, N>) -> Option<SMatrix<f64, N, N>> {
        Some(self.jacobian_at(t, &self.eval(t, y.as_slice())))
    }

    /// One evaluation serves both.
    #[inline(always)]
    fn rhs_jacobian(
        &self,
        t: f64,
        y: &SVector<f64, N>,
    ) -> (SVector<f64, N>, Option<SMatrix<f64, N, N>>) {
        let e = self.eval(t, y.as_slice());
        (self.rhs_at(&e, y.as_slice()), Some(self.jacobian_at(t, &e)))
    }

    #[inline(always)]
    fn observe(&self, t: f64, y: &SVector<f64, N>) -> ([f64; MAX_SWITCH], Quad) {
        let e = self.eval(t, y.as_slice());
        ([e.vr.x(), e.s.dot(e.vr)], [e.f.x(), e.f.y()])
    }

    /// `F_Fx` and `F_Fy`: their integrals give the window's mean friction force and the
    /// communication step's means.
    #[inline(always)]
    fn quadrature(&self, t: f64, y: &SVector<f64, N>) -> Quad {
        let f = self.eval(t, y.as_slice()).f;
        [f.x(), f.y()]
    }

    /// One evaluation of the contact for both.
    #[inline(always)]
    fn rhs_quadrature(&self, t: f64, y: &SVector<f64, N>) -> (SVector<f64, N>, Quad) {
        let e = self.eval(t, y.as_slice());
        (self.rhs_at(&e, y.as_slice()), [e.f.x(), e.f.y()])
    }

    fn quadrature_scale(&self) -> f64 {
        self.force_scale
    }

    /// `∫F_Fx dt` (the window's `F_mean`) steers the step as it did before the step means;
    /// `∫F_Fy dt` (only the step mean `F_Fy_step` reads it) is integrated alongside.
    fn quadrature_steers(&self) -> usize {
        QUAD_STEERS
    }

    fn switch_scale(&self) -> [f64; MAX_SWITCH] {
        self.switch_scale
    }

    /// `|s| ≤ s_ss` where the law keeps it invariant (a constant load). Under a varying normal
    /// force the laws keep no such bound (a falling `s_ss` outruns the relaxation); the
    /// deformation follows the law, except that a contact without load (lifted off) has none.
    fn project(&self, t: f64, y: &mut SVector<f64, N>) {
        let bound = match self.dynamics.load {
            None => self.dynamics.law.bound(),
            Some(_) => (self.dynamics.law_at(t).envelope() == 0.0).then_some(0.0),
        };
        if let Some(bound) = bound {
            let s = V::read(y.as_slice());
            let n = s.norm();
            if n > bound {
                let s = if bound > 0.0 {
                    s * (bound / n)
                } else {
                    V::default()
                };
                s.write(y.as_mut_slice());
            }
        }
    }
}
