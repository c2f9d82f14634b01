//! How the body is moved: the drives (force `F_d`, imposed velocity `v_d` with the lateral
//! motion guided or free, a spring-damper whose far end moves at `v_d`), each with its body
//! equations and their Jacobian (`docs/model.md`, Eqs. 8–10).

// Jacobian assembly indexes rows and columns of several matrices in lockstep.
#![allow(clippy::needless_range_loop)]

use crate::physics::{LawJacobian, Vector};
use crate::solver::MAX_DIM;
use crate::table::Params;

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
    /// Body acceleration under the friction force `f_f`, with `a_d = dv_d/dt` (the input
    /// derivative of `v_d`, zero when held).
    fn acceleration(&self, body: &[f64], f_f: V, d: &DriveInputs, a_d: f64) -> V;
    /// Natural magnitudes of the body states (positions, then velocities).
    fn scale(&self, x_nom: f64, v_nom: f64, out: &mut [f64]);
    /// Fills the Jacobian's body rows, and the deformation rows' columns of the body velocity,
    /// from the law's partial derivatives. Rows and columns index the whole state, the
    /// deformation first; every other entry is left as it is (zero).
    fn jacobian(&self, lj: &LawJacobian, jac: &mut Jac);
    /// The same drive on a body that moves along x only, where it has one with body
    /// `[x, v_x]` (force and spring drives): the planar explicit path integrates a planar
    /// motion that stays on the x axis in one dimension.
    fn axial(&self) -> Option<Axial> {
        None
    }
}

/// A force or spring drive in one dimension (see [`DriveKind::axial`]).
#[derive(Clone, Copy, Debug)]
pub enum Axial {
    Force(Force),
    Spring(Spring),
}

/// The Jacobian of the largest state, indexed `[row][column]`.
pub type Jac = [[f64; MAX_DIM]; MAX_DIM];

/// Jacobian entries of a body `[position (DIM), velocity (DIM)]` pushed by `F_d·e_x − F_F`.
pub(super) fn body_jacobian<V: Vector>(inv_m: f64, lj: &LawJacobian, jac: &mut Jac) {
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
    fn acceleration(&self, _: &[f64], _: V, _: &DriveInputs, a_d: f64) -> V {
        V::from_xy(a_d, 0.0)
    }
    fn scale(&self, _: f64, _: f64, _: &mut [f64]) {}
    fn jacobian(&self, _: &LawJacobian, _: &mut Jac) {}
}

/// Velocity drive in x with free lateral motion `m·dv_y/dt = −F_Fy` (planar only): body `[y, v_y]`.
#[derive(Clone, Copy, Debug)]
pub struct VelocityFree {
    pub(super) inv_m: f64,
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
    fn acceleration(&self, _: &[f64], f_f: V, _: &DriveInputs, a_d: f64) -> V {
        V::from_xy(a_d, -f_f.y() * self.inv_m)
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
    pub(super) inv_m: f64,
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
    fn acceleration(&self, _: &[f64], f_f: V, d: &DriveInputs, _: f64) -> V {
        (V::from_xy(d.f_d, 0.0) - f_f) * self.inv_m
    }
    fn scale(&self, x_nom: f64, v_nom: f64, out: &mut [f64]) {
        out[..V::DIM].fill(x_nom);
        out[V::DIM..].fill(v_nom);
    }
    fn jacobian(&self, lj: &LawJacobian, jac: &mut Jac) {
        body_jacobian::<V>(self.inv_m, lj, jac);
    }
    fn axial(&self) -> Option<Axial> {
        Some(Axial::Force(*self))
    }
}

/// Spring drive: `F_d = k_d·(x_d − x) + c_d·(v_d − v_x)`, `dx_d/dt = v_d`; body as [`Force`].
#[derive(Clone, Copy, Debug)]
pub struct Spring {
    pub(super) inv_m: f64,
    pub(super) k_d: f64,
    pub(super) c_d: f64,
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
    fn acceleration(&self, body: &[f64], f_f: V, d: &DriveInputs, _: f64) -> V {
        let f_d = <Self as DriveKind<V>>::drive_force(self, body, d);
        (V::from_xy(f_d, 0.0) - f_f) * self.inv_m
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
    fn axial(&self) -> Option<Axial> {
        Some(Axial::Spring(*self))
    }
}
