//! One contact, generic over its vector type (`f64` longitudinal, `Planar`), its friction law
//! and its drive. Each combination compiles to its own code: a longitudinal contact has no
//! second component, a velocity drive integrates no body, Dahl evaluates no Stribeck curve.
//!
//! The integrated state is `[s (DIM) | body (D::N_BODY)]`. Positions that follow from the
//! inputs alone (the body's `x` under velocity drive, the spring's far end `x_d`) are exact
//! integrals of the input tracks, not integrator states.

// Jacobian assembly indexes rows and columns of several matrices in lockstep.
#![allow(clippy::needless_range_loop)]

use nalgebra::{SMatrix, SVector};

use super::exact::{self, Forcing};
use super::simulator::{Ode, Path, SimError, Simulator, StepStats};
use super::{Config, InputId, Inputs, Outputs};
use crate::physics::{
    FrictionLaw, Harmonic, InputTrack, LawJacobian, ParamId, Params, Relaxation, Vector,
};
use crate::solver::expint::{ExpIntegrator, Relaxing, Sample};
use crate::solver::{OdeSystem, Radau5, Step, Workspace, MAX_DIM, MAX_SWITCH};

/// Forces and motions the drive needs at one instant.
#[derive(Clone, Copy, Debug)]
pub struct DriveInputs {
    /// `F_d(t)` (force drive).
    pub f_d: f64,
    /// `v_d(t)` (velocity and spring drives).
    pub v_d: f64,
    /// Far-end position of the spring, or the imposed position of the body (velocity drive).
    pub x_kin: f64,
}

/// How the body moves: its states, its velocity, and their rates.
pub trait DriveKind<V: Vector>: Copy + Send + Sync + std::fmt::Debug + 'static {
    /// Number of integrated body states.
    const N_BODY: usize;
    fn new(p: &Params) -> Self;
    /// Body velocity.
    fn velocity(&self, body: &[f64], d: &DriveInputs) -> V;
    /// Body position.
    fn position(&self, body: &[f64], d: &DriveInputs) -> V;
    /// Driving force along x acting on the body.
    fn drive_force(&self, body: &[f64], d: &DriveInputs) -> f64;
    /// Rates of the body states under the friction force `f_f` (the support pushes with `−f_f`).
    fn body_rate(&self, body: &[f64], f_f: V, d: &DriveInputs, out: &mut [f64]);
    /// Natural magnitudes of the body states (positions, then velocities).
    fn scale(&self, x_nom: f64, v_nom: f64, out: &mut [f64]);
    /// Fills the Jacobian's body rows, and the deformation rows' columns of the body velocity,
    /// from the law's partial derivatives. Rows and columns index the whole state, the
    /// deformation first; every other entry is left as it is (zero).
    fn jacobian(&self, lj: &LawJacobian, jac: &mut Jac);
}

/// The Jacobian of the largest state, indexed `[row][column]`.
pub type Jac = [[f64; MAX_DIM]; MAX_DIM];

/// Jacobian entries of a body `[position (DIM), velocity (DIM)]` pushed by `F_d·e_x − F_F`.
fn body_jacobian<V: Vector>(inv_m: f64, lj: &LawJacobian, jac: &mut Jac) {
    let d = V::DIM;
    for i in 0..d {
        jac[d + i][2 * d + i] = 1.0;
        for j in 0..d {
            jac[i][2 * d + j] = lj.rate_v[i][j];
            jac[2 * d + i][j] = -lj.force_s[i][j] * inv_m;
            jac[2 * d + i][2 * d + j] = -lj.force_v[i][j] * inv_m;
        }
    }
}

/// Velocity drive with the body guided in y (longitudinal contacts and `lateral = "guided"`):
/// no body state at all.
#[derive(Clone, Copy, Debug)]
pub struct VelocityGuided;

impl<V: Vector> DriveKind<V> for VelocityGuided {
    const N_BODY: usize = 0;
    fn new(_: &Params) -> Self {
        VelocityGuided
    }
    #[inline(always)]
    fn velocity(&self, _: &[f64], d: &DriveInputs) -> V {
        V::from_xy(d.v_d, 0.0)
    }
    fn position(&self, _: &[f64], d: &DriveInputs) -> V {
        V::from_xy(d.x_kin, 0.0)
    }
    fn drive_force(&self, _: &[f64], _: &DriveInputs) -> f64 {
        f64::NAN // the caller reports F_Fx: the force that imposes v_d
    }
    #[inline(always)]
    fn body_rate(&self, _: &[f64], _: V, _: &DriveInputs, _: &mut [f64]) {}
    fn scale(&self, _: f64, _: f64, _: &mut [f64]) {}
    fn jacobian(&self, _: &LawJacobian, _: &mut Jac) {}
}

/// Velocity drive in x with free lateral motion `m·dv_y/dt = −F_Fy` (planar only): body `[y, v_y]`.
#[derive(Clone, Copy, Debug)]
pub struct VelocityFree {
    inv_m: f64,
}

impl<V: Vector> DriveKind<V> for VelocityFree {
    const N_BODY: usize = 2;
    fn new(p: &Params) -> Self {
        VelocityFree { inv_m: 1.0 / p.m }
    }
    #[inline(always)]
    fn velocity(&self, body: &[f64], d: &DriveInputs) -> V {
        V::from_xy(d.v_d, body[1])
    }
    fn position(&self, body: &[f64], d: &DriveInputs) -> V {
        V::from_xy(d.x_kin, body[0])
    }
    fn drive_force(&self, _: &[f64], _: &DriveInputs) -> f64 {
        f64::NAN
    }
    #[inline(always)]
    fn body_rate(&self, body: &[f64], f_f: V, _: &DriveInputs, out: &mut [f64]) {
        out[0] = body[1];
        out[1] = -f_f.y() * self.inv_m;
    }
    fn scale(&self, x_nom: f64, v_nom: f64, out: &mut [f64]) {
        out[0] = x_nom;
        out[1] = v_nom;
    }
    fn jacobian(&self, lj: &LawJacobian, jac: &mut Jac) {
        // state [s_x, s_y, y, v_y]; v_r depends on the body through v_y only.
        let (y, vy) = (V::DIM, V::DIM + 1);
        for i in 0..V::DIM {
            jac[i][vy] = lj.rate_v[i][1];
            jac[vy][i] = -lj.force_s[1][i] * self.inv_m;
        }
        jac[y][vy] = 1.0;
        jac[vy][vy] = -lj.force_v[1][1] * self.inv_m;
    }
}

/// Force drive `m·dv/dt = F_d·e_x − F_F`: body `[position (DIM), velocity (DIM)]`.
#[derive(Clone, Copy, Debug)]
pub struct Force {
    inv_m: f64,
}

impl<V: Vector> DriveKind<V> for Force {
    const N_BODY: usize = 2 * V::DIM;
    fn new(p: &Params) -> Self {
        Force { inv_m: 1.0 / p.m }
    }
    #[inline(always)]
    fn velocity(&self, body: &[f64], _: &DriveInputs) -> V {
        V::read(&body[V::DIM..])
    }
    fn position(&self, body: &[f64], _: &DriveInputs) -> V {
        V::read(body)
    }
    #[inline(always)]
    fn drive_force(&self, _: &[f64], d: &DriveInputs) -> f64 {
        d.f_d
    }
    #[inline(always)]
    fn body_rate(&self, body: &[f64], f_f: V, d: &DriveInputs, out: &mut [f64]) {
        body[V::DIM..]
            .iter()
            .zip(out.iter_mut())
            .for_each(|(v, o)| *o = *v);
        let acc = (V::from_xy(d.f_d, 0.0) - f_f) * self.inv_m;
        acc.write(&mut out[V::DIM..]);
    }
    fn scale(&self, x_nom: f64, v_nom: f64, out: &mut [f64]) {
        out[..V::DIM].fill(x_nom);
        out[V::DIM..].fill(v_nom);
    }
    fn jacobian(&self, lj: &LawJacobian, jac: &mut Jac) {
        body_jacobian::<V>(self.inv_m, lj, jac);
    }
}

/// Spring drive: `F_d = k_d·(x_d − x) + c_d·(v_d − v_x)`, `dx_d/dt = v_d`; body as [`Force`].
#[derive(Clone, Copy, Debug)]
pub struct Spring {
    inv_m: f64,
    k_d: f64,
    c_d: f64,
}

impl<V: Vector> DriveKind<V> for Spring {
    const N_BODY: usize = 2 * V::DIM;
    fn new(p: &Params) -> Self {
        Spring {
            inv_m: 1.0 / p.m,
            k_d: p.k_d,
            c_d: p.c_d,
        }
    }
    #[inline(always)]
    fn velocity(&self, body: &[f64], _: &DriveInputs) -> V {
        V::read(&body[V::DIM..])
    }
    fn position(&self, body: &[f64], _: &DriveInputs) -> V {
        V::read(body)
    }
    #[inline(always)]
    fn drive_force(&self, body: &[f64], d: &DriveInputs) -> f64 {
        self.k_d * (d.x_kin - body[0]) + self.c_d * (d.v_d - body[V::DIM])
    }
    #[inline(always)]
    fn body_rate(&self, body: &[f64], f_f: V, d: &DriveInputs, out: &mut [f64]) {
        body[V::DIM..]
            .iter()
            .zip(out.iter_mut())
            .for_each(|(v, o)| *o = *v);
        let f_d = <Self as DriveKind<V>>::drive_force(self, body, d);
        let acc = (V::from_xy(f_d, 0.0) - f_f) * self.inv_m;
        acc.write(&mut out[V::DIM..]);
    }
    fn scale(&self, x_nom: f64, v_nom: f64, out: &mut [f64]) {
        out[..V::DIM].fill(x_nom);
        out[V::DIM..].fill(v_nom);
    }
    fn jacobian(&self, lj: &LawJacobian, jac: &mut Jac) {
        body_jacobian::<V>(self.inv_m, lj, jac);
        // F_d = k_d·(x_d − x) + c_d·(v_d − v_x) acts on v_x.
        let (x, vx) = (V::DIM, 2 * V::DIM);
        jac[vx][x] -= self.k_d * self.inv_m;
        jac[vx][vx] -= self.c_d * self.inv_m;
    }
}

/// The right-hand side: everything the integrator needs, nothing it changes.
#[derive(Clone, Copy, Debug)]
pub struct Dynamics<V: Vector, L: FrictionLaw, D: DriveKind<V>> {
    law: L,
    drive: D,
    harmonic: Option<Harmonic>,
    /// Input tracks, indexed like [`InputId::ALL`].
    tracks: [InputTrack; 4],
    /// `x_kin` at the reference time of the `v_d` track.
    x_kin_ref: f64,
    f_c: f64,
    _v: std::marker::PhantomData<V>,
}

/// Kinematic and force quantities at one state.
#[derive(Clone, Copy, Debug)]
struct Eval<V> {
    s: V,
    v: V,
    vr: V,
    ds: V,
    f: V,
    drive: DriveInputs,
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>> Dynamics<V, L, D> {
    #[inline(always)]
    fn drive_inputs(&self, t: f64) -> DriveInputs {
        let vd = &self.tracks[1];
        DriveInputs {
            f_d: self.tracks[0].at(t),
            v_d: vd.at(t),
            x_kin: self.x_kin_ref + vd.integral(t),
        }
    }

    /// Support velocity: the harmonic source plus the input tracks, as enabled.
    #[inline(always)]
    fn support_velocity(&self, t: f64, input_support: bool) -> V {
        let mut vs = V::default();
        if let Some(h) = &self.harmonic {
            let (x, y) = h.velocity(t);
            vs = V::from_xy(x, y);
        }
        if input_support {
            vs = vs + V::from_xy(self.tracks[2].at(t), self.tracks[3].at(t));
        }
        vs
    }

    /// The relative velocity along x of a velocity drive from `t` on, for the closed-form path:
    /// the affine input tracks and the harmonic source's x component.
    fn forcing_x(&self, t: f64, input_support: bool) -> Forcing {
        let (vd, vsx) = (&self.tracks[1], &self.tracks[2]);
        let (mut b0, mut b1) = (vd.at(t), vd.slope);
        if input_support {
            b0 -= vsx.at(t);
            b1 -= vsx.slope;
        }
        let (amp, omega, theta0) = match &self.harmonic {
            Some(h) => (h.v_a() * h.dir.0, std::f64::consts::TAU * h.f, h.theta(t)),
            None => (0.0, 0.0, 0.0),
        };
        Forcing {
            b0,
            b1,
            amp,
            omega,
            theta0,
        }
    }

    /// Everything at `(t, y)`, given the support velocity `vs` at `t`.
    #[inline(always)]
    fn eval(&self, t: f64, y: &[f64], vs: V) -> Eval<V> {
        let s = V::read(y);
        let body = &y[V::DIM..];
        let drive = self.drive_inputs(t);
        let v = self.drive.velocity(body, &drive);
        let vr = v - vs;
        let ds = self.law.rate(s, vr);
        let f = self.law.force(s, vr, ds);
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
struct Relaxation1<'a, V: Vector, L: FrictionLaw, D: DriveKind<V>> {
    dynamics: &'a Dynamics<V, L, D>,
    input_support: bool,
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
                d: l.force_0.x(),
            },
            None => Sample::default(),
        }
    }
}

/// Number of support velocities a [`System`] remembers: the integrator evaluates the right-hand
/// side, its Jacobian, the switching functions and the quadrature at the same three stage times.
const SUPPORT_CACHE: usize = 4;

/// The system the integrator sees during one call: dynamics, the run-time support flag, and a
/// memo of the support velocity (one `cos` per distinct time instead of one per evaluation).
struct System<'a, V: Vector, L: FrictionLaw, D: DriveKind<V>> {
    dynamics: &'a Dynamics<V, L, D>,
    input_support: bool,
    scale: &'a [f64],
    force_scale: f64,
    switch_scale: [f64; MAX_SWITCH],
    cache: std::cell::Cell<([(f64, V); SUPPORT_CACHE], usize)>,
}

impl<'a, V: Vector, L: FrictionLaw, D: DriveKind<V>> System<'a, V, L, D> {
    fn new(
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
    fn support(&self, t: f64) -> V {
        let (mut slots, next) = self.cache.get();
        if let Some(&(_, v)) = slots.iter().find(|(ts, _)| *ts == t) {
            return v;
        }
        let v = self.dynamics.support_velocity(t, self.input_support);
        slots[next] = (t, v);
        self.cache.set((slots, (next + 1) % SUPPORT_CACHE));
        v
    }

    #[inline(always)]
    fn eval(&self, t: f64, y: &[f64]) -> Eval<V> {
        self.dynamics.eval(t, y, self.support(t))
    }

    /// `dy/dt` from an evaluation at `y`.
    #[inline(always)]
    fn rhs_at<const N: usize>(&self, e: &Eval<V>, y: &[f64]) -> SVector<f64, N> {
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
    fn jacobian_at<const N: usize>(&self, e: &Eval<V>) -> SMatrix<f64, N, N> {
        let lj = self.dynamics.law.jacobian(e.s, e.vr, e.ds);
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
        Some(self.jacobian_at(&self.eval(t, y.as_slice())))
    }

    /// One evaluation serves both.
    #[inline(always)]
    fn rhs_jacobian(
        &self,
        t: f64,
        y: &SVector<f64, N>,
    ) -> (SVector<f64, N>, Option<SMatrix<f64, N, N>>) {
        let e = self.eval(t, y.as_slice());
        (self.rhs_at(&e, y.as_slice()), Some(self.jacobian_at(&e)))
    }

    #[inline(always)]
    fn observe(&self, t: f64, y: &SVector<f64, N>) -> ([f64; MAX_SWITCH], f64) {
        let e = self.eval(t, y.as_slice());
        ([e.vr.x(), e.s.dot(e.vr)], e.f.x())
    }

    /// `F_Fx`, whose integral over each window is the mean friction force.
    #[inline(always)]
    fn quadrature(&self, t: f64, y: &SVector<f64, N>) -> f64 {
        self.eval(t, y.as_slice()).f.x()
    }

    fn quadrature_scale(&self) -> f64 {
        self.force_scale
    }

    fn switch_scale(&self) -> [f64; MAX_SWITCH] {
        self.switch_scale
    }

    fn project(&self, y: &mut SVector<f64, N>) {
        if let Some(bound) = self.dynamics.law.bound() {
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

/// Relative distance within which a communication point lies on a window boundary: far above
/// the rounding of importers' time arithmetic, far below any physical time scale.
const TIME_SNAP: f64 = 1e-12;

/// Relative distance within which a time is taken as a nearby short decimal: 256 ulps, above
/// the drift of importers' time arithmetic (`t += h`, `k·h`, integer nanoseconds) over
/// thousands of steps, and small enough that a time meant to be no short decimal (k/3) almost
/// never moves, and then by at most 256 ulps.
const DECIMAL_SNAP: f64 = 256.0 * f64::EPSILON;

/// The communication point an importer meant: a time within [`DECIMAL_SNAP`] of a decimal with
/// 12 significant digits is taken as that decimal, so that importers that accumulate time
/// differently step the FMU to bit-identical instants and get bit-identical results.
pub fn canonical_time(t: f64) -> f64 {
    if t == 0.0 || !t.is_finite() {
        return t;
    }
    let exponent = t.abs().log10().floor() as i32;
    let scale = 10f64.powi(11 - exponent);
    if !scale.is_finite() || scale == 0.0 {
        return t;
    }
    let c = (t * scale).round() / scale;
    if (c - t).abs() <= DECIMAL_SNAP * t.abs() {
        c
    } else {
        t
    }
}

/// Running mean of `F_Fx` over averaging windows of fixed length aligned on `origin`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Window {
    origin: f64,
    len: f64,
    /// Index of the window in progress.
    index: u64,
    /// ∫F_Fx dt since the start of the window in progress.
    acc: f64,
    /// Mean over the last completed window.
    last: Option<f64>,
}

impl Window {
    fn start(&self) -> f64 {
        self.origin + self.index as f64 * self.len
    }
    fn end(&self) -> f64 {
        self.origin + (self.index + 1) as f64 * self.len
    }
}

/// A contact with its integrator: implements [`Simulator`].
#[derive(Clone, Debug)]
pub struct Contact<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> {
    config: Config,
    params: Params,
    dynamics: Dynamics<V, L, D>,
    /// Natural magnitudes of the state components.
    scale: [f64; N],
    /// Natural magnitude of the friction force, for the error of its integral.
    force_scale: f64,
    /// Natural magnitudes of the switching functions `v_rx` and `s·v_r`.
    switch_scale: [f64; MAX_SWITCH],
    radau: Radau5<N>,
    /// Radau even where the closed form applies (tests and benchmarks of the fast path).
    radau_only: bool,
    /// The exponential integrator's proposed step (0: none yet).
    exp_h: f64,
    /// The integrator's scratch matrices, kept across communication steps.
    work: Workspace,
    window: Window,
}

/// Builds the contact with state dimension `N` (checked against the types).
pub fn boxed<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
    config: Config,
    params: Params,
    t_start: f64,
    tolerance: f64,
    path: Path,
) -> Box<dyn Simulator> {
    assert_eq!(N, V::DIM + D::N_BODY, "state dimension of {config:?}");
    let mut c = Contact::<V, L, D, N>::new(config, params, t_start, tolerance);
    c.radau_only = path == Path::Radau;
    Box::new(c)
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Contact<V, L, D, N> {
    fn new(config: Config, params: Params, t_start: f64, tolerance: f64) -> Self {
        let dynamics = Dynamics {
            law: L::new(&params),
            drive: D::new(&params),
            harmonic: config
                .harmonic
                .then(|| Harmonic::new(params.u0, params.f, params.angle, params.phase, t_start)),
            tracks: [InputTrack {
                t_ref: t_start,
                value: 0.0,
                slope: 0.0,
            }; 4],
            x_kin_ref: 0.0,
            f_c: params.f_c(),
            _v: std::marker::PhantomData,
        };
        let mut c = Contact {
            config,
            params,
            dynamics,
            scale: [0.0; N],
            force_scale: 0.0,
            switch_scale: [0.0; MAX_SWITCH],
            radau: Radau5::new(t_start, SVector::zeros(), tolerance),
            radau_only: false,
            exp_h: 0.0,
            work: Workspace::new(N),
            window: Window {
                origin: t_start,
                len: 0.0,
                index: 0,
                acc: 0.0,
                last: None,
            },
        };
        c.window.len = c.window_length();
        c.update_scale();
        c
    }

    fn window_length(&self) -> f64 {
        match &self.dynamics.harmonic {
            Some(h) if h.f > 0.0 => 1.0 / h.f,
            _ => self.params.t_avg,
        }
    }

    fn update_scale(&mut self) {
        let p = &self.params;
        let s_nom = self.dynamics.law.s_scale();
        let v_a = self.dynamics.harmonic.map_or(0.0, |h| h.v_a());
        let x_nom = s_nom.max(p.u0 * self.config.harmonic as u8 as f64);
        let v_nom = v_a.max(s_nom * (p.k_t / p.m).sqrt()).max(1e-9);
        self.scale[..V::DIM].fill(s_nom);
        self.force_scale = (p.k_t * s_nom).max(p.h_v * v_nom).max(1e-300);
        self.switch_scale = [v_nom, s_nom * v_nom];
        self.dynamics
            .drive
            .scale(x_nom, v_nom, &mut self.scale[V::DIM..]);
    }

    fn system(&self) -> System<'_, V, L, D> {
        System::new(
            &self.dynamics,
            self.config.input_support,
            &self.scale,
            self.force_scale,
            self.switch_scale,
        )
    }

    /// Longest step that cannot hide a pair of sign changes of `v_r` from the harmonic source.
    fn h_max(&self) -> f64 {
        match &self.dynamics.harmonic {
            Some(h) if h.f > 0.0 && h.u0 > 0.0 => 0.25 / h.f,
            _ => f64::INFINITY,
        }
    }

    fn eval_now(&self) -> Eval<V> {
        self.system().eval(self.radau.t, self.radau.y.as_slice())
    }

    fn track_index(&self, id: InputId) -> Result<usize, SimError> {
        if !id.present(&self.config) {
            return Err(SimError::NoSuchInput(id.name()));
        }
        Ok(InputId::ALL.iter().position(|&i| i == id).unwrap_or(0))
    }

    /// The closed-form path's relaxation, where this contact takes it: a longitudinal velocity
    /// drive (no body state) with a law that relaxes in the relative displacement (Dahl).
    fn exact_path(&self) -> Option<Relaxation> {
        if V::DIM == 1 && D::N_BODY == 0 && !self.radau_only {
            self.dynamics.law.relaxation()
        } else {
            None
        }
    }

    /// True when this contact takes the exponential integrator: a velocity drive with the
    /// lateral motion guided (no body state) and a law linear in `s`, where the closed form
    /// does not apply.
    fn exp_path(&self) -> bool {
        D::N_BODY == 0
            && !self.radau_only
            && self.exact_path().is_none()
            && self.dynamics.law.linear(V::from_xy(1.0, 0.0)).is_some()
    }

    /// Advances the exponential integrator to `t_target`, steps ending on every sign change of
    /// `v_rx` (a kink of `|v_r|` where `v_ry` vanishes too); returns `∫ a dt` (the decay) and
    /// the window's `∫F_Fx dt`.
    fn advance_exp(&mut self, t_target: f64, h_max: f64) -> Result<(f64, f64), SimError> {
        let t0 = self.radau.t;
        let forcing = self.dynamics.forcing_x(t0, self.config.input_support);
        let mut knots = [0.0f64; 8];
        let mut n = 0;
        exact::sign_changes(&forcing, t_target - t0, |r| {
            if n < knots.len() {
                knots[n] = t0 + r;
                n += 1;
            }
        });
        let sys = Relaxation1 {
            dynamics: &self.dynamics,
            input_support: self.config.input_support,
        };
        let mut ei = ExpIntegrator::new(self.radau.tolerance());
        ei.h = self.exp_h;
        let mut s = [0.0; 2];
        s[..V::DIM].copy_from_slice(&self.radau.y.as_slice()[..V::DIM]);
        let s_scale = self.scale[0];
        let mut integral = 0.0;
        let mut a = t0;
        for &b in knots[..n].iter().chain(std::iter::once(&t_target)) {
            if b > a {
                integral += ei
                    .integrate(&sys, a, b, &mut s, s_scale, self.force_scale, h_max)
                    .map_err(SimError::Solver)?;
                a = b;
            }
        }
        let mut y = self.radau.y;
        y.as_mut_slice()[..V::DIM].copy_from_slice(&s[..V::DIM]);
        OdeSystem::<N>::project(&self.system(), &mut y);
        self.radau.y = y;
        self.radau.t = t_target;
        self.radau.restart();
        self.exp_h = ei.h;
        let st = &mut self.radau.stats;
        st.steps += ei.steps;
        st.rejected += ei.rejected;
        st.rhs_evals += ei.evals;
        st.events += n as u64;
        Ok((ei.decay, integral))
    }

    /// Advances the closed-form path to `t_target`; returns `exp(−decay)`'s exponent and the
    /// window's `∫F_Fx dt` over the call.
    fn advance_exact(&mut self, relax: Relaxation, t_target: f64) -> (f64, f64) {
        let t0 = self.radau.t;
        let forcing = self.dynamics.forcing_x(t0, self.config.input_support);
        let a = exact::advance(
            &forcing,
            relax,
            self.radau.y[0],
            t_target - t0,
            self.radau.tolerance(),
        );
        self.radau.t = t_target;
        self.radau.y[0] = a.s;
        self.radau.restart();
        let st = &mut self.radau.stats;
        st.steps += a.segments;
        st.events += a.roots;
        st.rhs_evals += a.evals;
        (a.decay, relax.stiffness * a.integral_s)
    }

    /// True when no input has a derivative set: the forcing is then periodic in the window.
    fn inputs_held(&self) -> bool {
        self.dynamics.tracks.iter().all(|t| t.slope == 0.0)
    }

    /// True when the map of one window is affine in `s` with a scalar decay, `s ↦ exp(−L)·s +
    /// beta`, for held inputs: the deformation's rate is linear in `s` and nothing else is
    /// integrated (the closed form with `kappa = 1`, the exponential path).
    fn windows_affine(&self) -> bool {
        self.exact_path().is_some_and(|r| r.exponent == 1.0) || self.exp_path()
    }

    /// Skips `m` whole windows from the start of the current one in O(1), on a path where the
    /// map of a window is affine ([`Contact::windows_affine`]) and the inputs held, so that the
    /// forcing is periodic in the window: `m` maps compose in closed form. The first window is
    /// integrated to learn `L` and `beta`; the windows skipped leave no mean.
    fn skip_windows(&mut self, m: u64, h_max: f64) -> Result<(), SimError> {
        let s0 = V::read(self.radau.y.as_slice());
        let t_b = self.window.end();
        let (decay, integral) = match self.exact_path() {
            Some(relax) => self.advance_exact(relax, t_b),
            None => self.advance_exp(t_b, h_max)?,
        };
        let s1 = V::read(self.radau.y.as_slice());
        let k = (m - 1) as f64;
        let beta = s1 - s0 * (-decay).exp();
        // Σ_{j<k} exp(−j·L) = (1 − exp(−k·L))/(1 − exp(−L)), k when L = 0.
        let sum = if decay > 0.0 {
            (-k * decay).exp_m1() / (-decay).exp_m1()
        } else {
            k
        };
        let s = s1 * (-k * decay).exp() + beta * sum;
        self.window.last = Some(integral / self.window.len);
        self.window.acc = 0.0;
        self.window.index += m;
        self.radau.t = self.window.start();
        let mut y = self.radau.y;
        s.write(y.as_mut_slice());
        OdeSystem::<N>::project(&self.system(), &mut y);
        self.radau.y = y;
        self.radau.stats.steps += 1;
        Ok(())
    }

    /// Integrates to `t_target` (≤ the current window's end), accumulating `∫F_Fx dt`.
    fn integrate(&mut self, t_target: f64, h_max: f64) -> Result<(), SimError> {
        if let Some(relax) = self.exact_path() {
            let (_, integral) = self.advance_exact(relax, t_target);
            self.window.acc += integral;
            return Ok(());
        }
        if self.exp_path() {
            self.window.acc += self.advance_exp(t_target, h_max)?.1;
            return Ok(());
        }
        let dynamics = self.dynamics;
        let scale = self.scale;
        let sys = System::new(
            &dynamics,
            self.config.input_support,
            &scale,
            self.force_scale,
            self.switch_scale,
        );
        let mut acc = 0.0;
        self.radau
            .integrate_with(&mut self.work, &sys, t_target, h_max, |step: &Step<N>| {
                acc += step.quad
            })
            .map_err(SimError::Solver)?;
        self.window.acc += acc;
        Ok(())
    }

    fn f_mean(&self) -> f64 {
        if let Some(m) = self.window.last {
            return m;
        }
        let elapsed = self.radau.t - self.window.start();
        if elapsed > 0.0 {
            self.window.acc / elapsed
        } else {
            self.eval_now().f.x()
        }
    }

    /// Number of numbers in a snapshot.
    const SNAPSHOT_LEN: usize = 1 + 18 + 12 + 1 + 2 + 6 + Radau5::<N>::SAVED_LEN + 1;

    fn config_code(&self) -> f64 {
        let c = &self.config;
        (c.law as u8 as f64)
            + 4.0 * (c.motion as u8 as f64)
            + 8.0 * (c.drive as u8 as f64)
            + 32.0 * (c.lateral as u8 as f64)
            + 64.0 * (c.harmonic as u8 as f64)
            + 128.0 * (c.input_support as u8 as f64)
    }
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Simulator for Contact<V, L, D, N> {
    fn config(&self) -> Config {
        self.config
    }

    fn params(&self) -> &Params {
        &self.params
    }

    fn set_param(&mut self, id: ParamId, value: f64) -> Result<(), SimError> {
        if !id.tunable() {
            return Err(SimError::NotTunable(id.name()));
        }
        let mut params = self.params;
        id.set(&mut params, value)?;
        if params == self.params {
            return Ok(());
        }
        let t = self.radau.t;
        self.params = params;
        self.dynamics.law = L::new(&params);
        self.dynamics.drive = D::new(&params);
        self.dynamics.f_c = params.f_c();
        if let Some(h) = &mut self.dynamics.harmonic {
            h.rebase(t);
            if id == ParamId::Phase {
                h.theta_ref = value.rem_euclid(std::f64::consts::TAU);
            }
            h.u0 = params.u0;
            h.f = params.f;
            h.dir = (params.angle.cos(), params.angle.sin());
        }
        // A new source or load starts a new averaging window.
        self.window = Window {
            origin: t,
            len: 0.0,
            index: 0,
            acc: 0.0,
            last: None,
        };
        self.window.len = self.window_length();
        self.update_scale();
        let mut y = self.radau.y;
        OdeSystem::<N>::project(&self.system(), &mut y);
        self.radau.set_state(y);
        Ok(())
    }

    fn time(&self) -> f64 {
        self.radau.t
    }

    fn tolerance(&self) -> f64 {
        self.radau.tolerance()
    }

    fn set_input(&mut self, id: InputId, value: f64) -> Result<(), SimError> {
        let k = self.track_index(id)?;
        if !value.is_finite() {
            return Err(SimError::Input {
                name: id.name(),
                value,
            });
        }
        let t = self.radau.t;
        let track = &mut self.dynamics.tracks[k];
        if track.value.to_bits() == value.to_bits() && track.t_ref == t {
            return Ok(());
        }
        if id == InputId::VD {
            self.dynamics.x_kin_ref += track.integral(t);
        }
        track.t_ref = t;
        track.value = value;
        self.radau.restart();
        Ok(())
    }

    fn set_input_derivative(&mut self, id: InputId, value: f64) -> Result<(), SimError> {
        let k = self.track_index(id)?;
        if !value.is_finite() {
            return Err(SimError::Input {
                name: id.name(),
                value,
            });
        }
        let t = self.radau.t;
        let track = &mut self.dynamics.tracks[k];
        if id == InputId::VD {
            self.dynamics.x_kin_ref += track.integral(t);
        }
        track.value = track.at(t);
        track.t_ref = t;
        track.slope = value;
        self.radau.restart();
        Ok(())
    }

    fn inputs(&self) -> Inputs {
        let mut i = Inputs::default();
        for (k, id) in InputId::ALL.iter().enumerate() {
            *id.slot(&mut i) = self.dynamics.tracks[k].value;
        }
        i
    }

    fn step_to(&mut self, t_end: f64) -> Result<(), SimError> {
        let t0 = self.radau.t;
        if !(t_end.is_finite() && t_end > t0) {
            return Err(SimError::Time {
                now: t0,
                target: t_end,
            });
        }
        let t_end = match canonical_time(t_end) {
            c if c > t0 => c,
            _ => t_end,
        };
        let saved = (self.radau, self.window, self.exp_h);
        let h_max = self.h_max();
        let result = (|| {
            while self.radau.t < t_end {
                // Many whole windows ahead with the forcing periodic: skip all but the last
                // (whose mean is the output) in O(1).
                let whole = ((t_end - self.radau.t) / self.window.len).floor();
                if whole >= 3.0
                    && self.radau.t == self.window.start()
                    && self.inputs_held()
                    && self.windows_affine()
                {
                    self.skip_windows(whole as u64 - 1, h_max)?;
                    continue;
                }
                let mut t_b = self.window.end();
                if (t_b - t_end).abs() <= TIME_SNAP * t_end.abs() {
                    // A communication point on a window boundary completes the window,
                    // whichever side of it the importer's rounding put the point.
                    t_b = t_end;
                }
                let target = t_b.min(t_end);
                self.integrate(target, h_max)?;
                if target == t_b {
                    self.window.last = Some(self.window.acc / self.window.len);
                    self.window.acc = 0.0;
                    self.window.index += 1;
                }
            }
            Ok(())
        })();
        if let Err(e) = result {
            // Leave the simulator as it was before the call.
            (self.radau, self.window, self.exp_h) = saved;
            return Err(e);
        }
        // Input derivatives are valid for one step: hold the inputs from here on.
        let t = self.radau.t;
        for (k, track) in self.dynamics.tracks.iter_mut().enumerate() {
            if track.slope != 0.0 {
                if k == 1 {
                    self.dynamics.x_kin_ref += track.integral(t);
                    track.t_ref = t;
                }
                track.slope = 0.0;
                self.radau.restart();
            }
        }
        // Keep x_kin anchored near the current time for precision.
        let vd = &mut self.dynamics.tracks[1];
        self.dynamics.x_kin_ref += vd.integral(t);
        vd.t_ref = t;
        Ok(())
    }

    fn outputs(&self) -> Outputs {
        let e = self.eval_now();
        let body = &self.radau.y.as_slice()[V::DIM..];
        let pos = self.dynamics.drive.position(body, &e.drive);
        let f_mean = self.f_mean();
        let f_c = self.dynamics.f_c;
        let f_d = match self.config.drive {
            super::Drive::Velocity => e.f.x(),
            _ => self.dynamics.drive.drive_force(body, &e.drive),
        };
        Outputs {
            f_fx: e.f.x(),
            f_fy: e.f.y(),
            x: pos.x(),
            y: pos.y(),
            v_x: e.v.x(),
            v_y: e.v.y(),
            s_x: e.s.x(),
            s_y: e.s.y(),
            f_mean,
            // 1 − F_mean/F_C: the fraction by which the vibration lowers the mean friction.
            reduction: if f_c > 0.0 { 1.0 - f_mean / f_c } else { 0.0 },
            p_diss: self.dynamics.law.dissipation(e.s, e.vr, e.ds),
            f_d,
        }
    }

    fn stats(&self) -> StepStats {
        let s = self.radau.stats;
        StepStats {
            steps: s.steps,
            rejected: s.rejected,
            rhs_evals: s.rhs_evals,
            jacobians: s.jacobians,
            events: s.events,
        }
    }

    fn path(&self) -> Path {
        if self.exact_path().is_some() {
            Path::ClosedForm
        } else if self.exp_path() {
            Path::Exponential
        } else {
            Path::Radau
        }
    }

    fn snapshot(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(Self::SNAPSHOT_LEN);
        out.push(self.config_code());
        out.extend(ParamId::ALL.iter().map(|id| id.get(&self.params)));
        for t in &self.dynamics.tracks {
            out.extend_from_slice(&[t.t_ref, t.value, t.slope]);
        }
        out.push(self.dynamics.x_kin_ref);
        let h = self
            .dynamics
            .harmonic
            .unwrap_or(Harmonic::new(0.0, 0.0, 0.0, 0.0, 0.0));
        out.extend_from_slice(&[h.t_ref, h.theta_ref]);
        let w = &self.window;
        out.extend_from_slice(&[
            w.origin,
            w.len,
            w.index as f64,
            w.acc,
            w.last.unwrap_or(0.0),
            w.last.is_some() as u8 as f64,
        ]);
        self.radau.save(&mut out);
        out.push(self.exp_h);
        debug_assert_eq!(out.len(), Self::SNAPSHOT_LEN);
        out
    }

    fn restore(&mut self, state: &[f64]) -> Result<(), SimError> {
        if state.len() != Self::SNAPSHOT_LEN {
            return Err(SimError::BadSnapshot("wrong length"));
        }
        if state[0] != self.config_code() {
            return Err(SimError::BadSnapshot("taken from another scene"));
        }
        let mut params = Params::default();
        for (k, id) in ParamId::ALL.iter().enumerate() {
            id.set(&mut params, state[1 + k])
                .map_err(|_| SimError::BadSnapshot("parameter out of range"))?;
        }
        let mut rest = &state[19..];
        let mut tracks = [InputTrack::default(); 4];
        for t in tracks.iter_mut() {
            *t = InputTrack {
                t_ref: rest[0],
                value: rest[1],
                slope: rest[2],
            };
            rest = &rest[3..];
        }
        let x_kin_ref = rest[0];
        let (h_t_ref, h_theta_ref) = (rest[1], rest[2]);
        let w = &rest[3..9];
        let (integrator, exp_h) = rest[9..].split_at(rest.len() - 10);
        let radau =
            Radau5::<N>::load(integrator).ok_or(SimError::BadSnapshot("integrator state"))?;
        let mut c = Contact::<V, L, D, N>::new(self.config, params, radau.t, radau.tolerance());
        c.dynamics.tracks = tracks;
        c.dynamics.x_kin_ref = x_kin_ref;
        if let Some(h) = &mut c.dynamics.harmonic {
            h.t_ref = h_t_ref;
            h.theta_ref = h_theta_ref;
        }
        c.window = Window {
            origin: w[0],
            len: w[1],
            index: w[2] as u64,
            acc: w[3],
            last: (w[5] != 0.0).then_some(w[4]),
        };
        c.radau = radau;
        c.radau_only = self.radau_only;
        c.exp_h = exp_h[0];
        c.update_scale();
        *self = c;
        Ok(())
    }

    fn clone_box(&self) -> Box<dyn Simulator> {
        Box::new(self.clone())
    }

    fn ode(&self) -> Box<dyn Ode> {
        Box::new(ContactOde::<V, L, D, N> {
            dynamics: self.dynamics,
            input_support: self.config.input_support,
            y: self.radau.y.into(),
            scale: self.scale,
        })
    }
}

/// [`Ode`] view of a contact: its dynamics with the inputs frozen.
struct ContactOde<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> {
    dynamics: Dynamics<V, L, D>,
    input_support: bool,
    y: [f64; N],
    scale: [f64; N],
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> ContactOde<V, L, D, N> {
    fn eval(&self, t: f64, y: &[f64]) -> Eval<V> {
        let vs = self.dynamics.support_velocity(t, self.input_support);
        self.dynamics.eval(t, y, vs)
    }
    fn system(&self) -> System<'_, V, L, D> {
        System::new(
            &self.dynamics,
            self.input_support,
            &self.scale,
            1.0,
            [0.0; MAX_SWITCH],
        )
    }
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Ode for ContactOde<V, L, D, N> {
    fn dim(&self) -> usize {
        N
    }
    fn state(&self) -> Vec<f64> {
        self.y.to_vec()
    }
    fn scale(&self) -> Vec<f64> {
        self.scale.to_vec()
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let f = OdeSystem::<N>::rhs(&self.system(), t, &SVector::from_column_slice(y));
        dy.copy_from_slice(f.as_slice());
    }
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut [f64]) {
        let y = SVector::<f64, N>::from_column_slice(y);
        let j = OdeSystem::<N>::jacobian(&self.system(), t, &y).unwrap_or_else(SMatrix::zeros);
        for r in 0..N {
            for c in 0..N {
                jac[r * N + c] = j[(r, c)];
            }
        }
    }
    fn f_fx(&self, t: f64, y: &[f64]) -> f64 {
        self.eval(t, y).f.x()
    }
    fn v_rx(&self, t: f64, y: &[f64]) -> f64 {
        self.eval(t, y).vr.x()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Drive, Lateral, Law, Motion};
    use crate::physics::{Dahl, Dupont, LuGre, Planar};

    /// The closed-form Jacobian against central differences at states spread over the regimes
    /// of each law (pre-sliding, the Dupont transition, sliding near |s| = s_ss, both signs of
    /// v_r), for every law, motion and drive.
    fn check<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(c: Config, p: Params) {
        let mut contact = Contact::<V, L, D, N>::new(c, p, 0.0, 1e-6);
        contact.dynamics.tracks[0].value = 3.0; // F_d
        contact.dynamics.tracks[1].value = 1.2e-3; // v_d
        contact.dynamics.tracks[2].value = 2e-4; // v_sx
        contact.dynamics.tracks[3].value = -3e-4; // v_sy
        let sys = contact.system();
        let s_ss = p.f_c() / p.k_t;
        for (k, frac) in [0.1, 0.62, 0.8, 0.97, -0.7].into_iter().enumerate() {
            let t = 1.3e-4 * (k as f64 + 1.0);
            let mut y = SVector::<f64, N>::zeros();
            y[0] = frac * s_ss;
            if V::DIM == 2 {
                y[1] = 0.3 * frac * s_ss;
            }
            for i in V::DIM..N {
                // positions ~ µm, velocities ~ mm/s, with both signs
                y[i] = if i % 2 == 0 { 1e-6 } else { -2e-3 } * (1.0 + 0.1 * i as f64);
            }
            let jac = OdeSystem::<N>::jacobian(&sys, t, &y).unwrap();
            let scale = OdeSystem::<N>::scale(&sys);
            for j in 0..N {
                let h = 1e-7 * scale[j];
                let (mut yp, mut ym) = (y, y);
                yp[j] += h;
                ym[j] -= h;
                let fd = (OdeSystem::<N>::rhs(&sys, t, &yp) - OdeSystem::<N>::rhs(&sys, t, &ym))
                    / (2.0 * h);
                for i in 0..N {
                    let tol = 1e-5 * (fd[i].abs() + jac[(i, j)].abs()) + 1e-9 * scale_of(&jac, i);
                    assert!(
                        (jac[(i, j)] - fd[i]).abs() <= tol,
                        "{c:?} state {k}: J[{i}][{j}] = {} vs difference {}",
                        jac[(i, j)],
                        fd[i]
                    );
                }
            }
        }
    }

    fn scale_of<const N: usize>(jac: &SMatrix<f64, N, N>, row: usize) -> f64 {
        (0..N).map(|j| jac[(row, j)].abs()).fold(0.0, f64::max)
    }

    #[test]
    fn importers_time_arithmetic_maps_to_one_communication_point() {
        let h = 1e-4;
        let mut acc = 0.0;
        for k in 1..=3000u32 {
            acc += h; // ecos
            let nominal = k as f64 * h; // fmi-sim
            let fmpy = (k - 1) as f64 * h + (nominal - (k - 1) as f64 * h);
            let libcosim = (k as u64 * 100_000) as f64 / 1e9;
            let c = canonical_time(nominal);
            assert_eq!(canonical_time(acc), c, "t += h at step {k}");
            assert_eq!(canonical_time(fmpy), c);
            assert_eq!(canonical_time(libcosim), c);
            assert!((c - nominal).abs() <= 4.0 * f64::EPSILON * nominal);
        }
        // A time that is no short decimal stays exactly as it is.
        let third = 1.0 / 3.0;
        assert_eq!(canonical_time(third), third);
        assert_eq!(canonical_time(0.0), 0.0);
    }

    #[test]
    fn closed_form_jacobian_matches_finite_differences() {
        let mut p = Params {
            h_v: 20.0,
            ..Params::default()
        };
        for law in [Law::Dahl, Law::Dupont, Law::LuGre] {
            macro_rules! run {
                ($v:ty, $d:ty, $n:literal, $motion:expr, $drive:expr, $lateral:expr) => {{
                    let c = Config {
                        law,
                        motion: $motion,
                        drive: $drive,
                        lateral: $lateral,
                        harmonic: true,
                        input_support: true,
                    };
                    match law {
                        Law::Dahl => check::<$v, Dahl, $d, $n>(c, p),
                        Law::Dupont => check::<$v, Dupont, $d, $n>(c, p),
                        Law::LuGre => check::<$v, LuGre, $d, $n>(c, p),
                    }
                }};
            }
            use Motion::{Longitudinal as L1, Planar as P2};
            run!(f64, VelocityGuided, 1, L1, Drive::Velocity, Lateral::Guided);
            run!(f64, Force, 3, L1, Drive::Force, Lateral::Guided);
            run!(f64, Spring, 3, L1, Drive::Spring, Lateral::Guided);
            run!(
                Planar,
                VelocityGuided,
                2,
                P2,
                Drive::Velocity,
                Lateral::Guided
            );
            run!(Planar, VelocityFree, 4, P2, Drive::Velocity, Lateral::Free);
            run!(Planar, Force, 6, P2, Drive::Force, Lateral::Guided);
            run!(Planar, Spring, 6, P2, Drive::Spring, Lateral::Guided);
        }
        // Dahl with an exponent (longitudinal only).
        p.kappa = 2.0;
        let c = Config {
            law: Law::Dahl,
            motion: Motion::Longitudinal,
            drive: Drive::Force,
            lateral: Lateral::Guided,
            harmonic: true,
            input_support: true,
        };
        check::<f64, Dahl, Force, 3>(c, p);
    }
}
