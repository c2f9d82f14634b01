//! The contact's equations as a plain ODE, for other integrators (the work–precision report's
//! peers) and for importers that integrate the state themselves.

use super::drive::DriveKind;
use nalgebra::{SMatrix, SVector};

use super::dynamics::{Dynamics, Eval, System};
use crate::physics::{FrictionLaw, Vector};
use crate::solver::{OdeSystem, MAX_SWITCH};

/// The contact's equations as a plain ODE `dy/dt = f(t, y)`, with the inputs held: what another
/// integrator (the report's peers, or a user's own solver) needs to solve the same problem.
/// The state is `[s | body]` as in the simulator; harmonic source and input tracks are
/// evaluated exactly as the simulator does.
pub trait Ode: Send + Sync {
    /// Number of state components.
    fn dim(&self) -> usize;
    /// The simulator's state when the view was taken.
    fn state(&self) -> Vec<f64>;
    /// Natural magnitude of each component (for absolute tolerances).
    fn scale(&self) -> Vec<f64>;
    /// `dy = f(t, y)`.
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]);
    /// `∂f/∂y` at `(t, y)`, row-major `dim × dim`, in closed form.
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut [f64]);
    /// Friction force `F_Fx` at `(t, y)`.
    fn f_fx(&self, t: f64, y: &[f64]) -> f64;
    /// `v_rx`, whose sign changes are the kinks of `f`.
    fn v_rx(&self, t: f64, y: &[f64]) -> f64;
}

/// [`Ode`] view of a contact: its dynamics with the inputs frozen.
pub(super) struct ContactOde<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> {
    pub(super) dynamics: Dynamics<V, L, D>,
    pub(super) input_support: bool,
    pub(super) y: [f64; N],
    pub(super) scale: [f64; N],
}

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> ContactOde<V, L, D, N> {
    pub(super) fn eval(&self, t: f64, y: &[f64]) -> Eval<V> {
        let vs = self.dynamics.support_velocity(t, self.input_support);
        self.dynamics.eval(t, y, vs)
    }
    pub(super) fn system(&self) -> System<'_, V, L, D> {
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
