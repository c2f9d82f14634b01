//! What an ODE presents to the integrators ([`OdeSystem`]: right-hand side, scales, switching
//! functions, quadrature integrands, Jacobian) and what they report (accepted [`Step`]s, work
//! counters, errors).

use nalgebra::{SMatrix, SVector};

/// Most switching functions a system may have.
pub const MAX_SWITCH: usize = 2;
/// Most integrands a system hands to the step's quadrature.
pub const MAX_QUAD: usize = 2;
/// The integrands of a quadrature, or their integrals over a step.
pub type Quad = [f64; MAX_QUAD];

/// An ODE `dy/dt = f(t, y)` of fixed dimension `N` (at most [`MAX_DIM`]).
pub trait OdeSystem<const N: usize> {
    fn rhs(&self, t: f64, y: &SVector<f64, N>) -> SVector<f64, N>;
    /// Natural magnitude of each component: the absolute tolerance is `rtol·scale`.
    fn scale(&self) -> SVector<f64, N>;
    /// Number of switching functions in use (0 to [`MAX_SWITCH`]).
    fn n_switch(&self) -> usize {
        0
    }
    /// Functions whose sign changes mark kinks or jumps of `rhs`; only the first
    /// [`OdeSystem::n_switch`] entries are read.
    fn switch(&self, _t: f64, _y: &SVector<f64, N>) -> [f64; MAX_SWITCH] {
        [1.0; MAX_SWITCH]
    }
    /// Natural magnitude of each switching function. A sign change that stays within
    /// `rtol·scale` of zero is no event: the kink it marks is below the tolerance, and the
    /// error control steps over it (a stuck contact whose velocity hovers at 1e-19 m/s does
    /// not chatter). Zero (the default): every sign change is an event.
    fn switch_scale(&self) -> [f64; MAX_SWITCH] {
        [0.0; MAX_SWITCH]
    }
    /// Projects a state onto the invariant set of the exact flow (no-op by default).
    fn project(&self, _t: f64, _y: &mut SVector<f64, N>) {}
    /// The Jacobian `∂f/∂y` at `(t, y)`, if the system has it in closed form; otherwise the
    /// integrator uses forward differences.
    fn jacobian(&self, _t: f64, _y: &SVector<f64, N>) -> Option<SMatrix<f64, N, N>> {
        None
    }

    /// The switching functions and the quadrature's integrand together, for systems that
    /// share work between them.
    fn observe(&self, t: f64, y: &SVector<f64, N>) -> ([f64; MAX_SWITCH], Quad) {
        (self.switch(t, y), self.quadrature(t, y))
    }

    /// `f(t, y)` and the Jacobian together, for systems that share work between them.
    fn rhs_jacobian(
        &self,
        t: f64,
        y: &SVector<f64, N>,
    ) -> (SVector<f64, N>, Option<SMatrix<f64, N, N>>) {
        (self.rhs(t, y), self.jacobian(t, y))
    }
    /// Up to [`MAX_QUAD`] integrands `q(t, y)` whose integrals over each step the integrator
    /// returns in [`Step::quad`]: the first [`OdeSystem::quadrature_steers`] with their errors
    /// bounded like the state's, the others integrated alongside with the same formula.
    fn quadrature(&self, _t: f64, _y: &SVector<f64, N>) -> Quad {
        [0.0; MAX_QUAD]
    }
    /// `f(t, y)` and the integrands together, for systems that share work between them (the
    /// same numbers as [`OdeSystem::rhs`] and [`OdeSystem::quadrature`]).
    fn rhs_quadrature(&self, t: f64, y: &SVector<f64, N>) -> (SVector<f64, N>, Quad) {
        (self.rhs(t, y), self.quadrature(t, y))
    }
    /// Natural magnitude of every `q`: the error of each integral over a step of length `h` is
    /// kept below `rtol·scale·h`. Zero: no quadrature.
    fn quadrature_scale(&self) -> f64 {
        0.0
    }
    /// How many of the integrands (the first ones) take part in the step-size control. The
    /// others are integrated alongside by the same collocation formula, whose accuracy then
    /// follows the state's, and cost no steps (an output nobody may read should not make the
    /// state's integration more expensive).
    fn quadrature_steers(&self) -> usize {
        MAX_QUAD
    }
}

/// Largest state dimension.
pub const MAX_DIM: usize = 6;

/// Why the integrator stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SolverError {
    /// The step size fell below the resolution of the time axis.
    StepSizeTooSmall { t: f64, h: f64 },
    /// The right-hand side returned NaN or infinity.
    NonFinite { t: f64 },
    /// The caller's budget of steps ran out at `t` (`limit` steps).
    WorkLimit { t: f64, limit: f64 },
}

impl std::fmt::Display for SolverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SolverError::StepSizeTooSmall { t, h } => {
                write!(f, "integrator step size {h:e} too small at t = {t}")
            }
            SolverError::NonFinite { t } => {
                write!(f, "right-hand side not finite at t = {t}")
            }
            SolverError::WorkLimit { t, limit } => write!(
                f,
                "more than max_steps = {limit:e} integrator steps in this communication step, at t = {t} since its start: use shorter communication steps, or raise the parameter max_steps"
            ),
        }
    }
}

impl std::error::Error for SolverError {}

/// Work counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolverStats {
    pub steps: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
    pub jacobians: u64,
    pub events: u64,
    /// Steps of the planar explicit path taken on the Coulomb limit's slow manifold (the body
    /// alone; `model/coulomb_limit.rs`), counted in `steps` too.
    pub limit_steps: u64,
}

/// One accepted step, as handed to the caller: stage `i` lies at `t + C[i]·h`, and the
/// collocation quadrature of a function `g` over the step is `h·Σ B[i]·g(stage i)`.
pub struct Step<'a, const N: usize> {
    pub t: f64,
    pub h: f64,
    pub stages: &'a [SVector<f64, N>; 3],
    /// `∫ q dt` over the step (see [`OdeSystem::quadrature`]).
    pub quad: Quad,
}
