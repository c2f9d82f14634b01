//! The ways a contact is advanced, each in a room of its own, and the one choice between them.
//!
//! ```text
//!                        contact.rs (step_to: windows, load events, the work limit)
//!                                  │ lends Shared + the state (Integrated: t, y, counts) + Kept
//!                                  ▼
//!                        paths/mod.rs: choose() ── the table of docs/model.md
//!        ┌──────────────┬──────────────┼───────────────┬──────────────────┐
//!        ▼              ▼              ▼               ▼                  ▼
//!   exact.rs     exponential.rs   explicit/     explicit_planar/     radau.rs
//!  closed form   (solver/expint)  (+ elastic)   (+ coulomb_limit)   (solver/radau)
//!                                      └──── stage_support.rs ──┘
//! ```
//!
//! Each path is a [`Path`]: whether it applies to the contact now, and how it advances the
//! contact to a time (no further than the averaging window's end), returning `∫F_F dt` over
//! the call. The paths see the contact through [`Shared`], what every path reads (the
//! configuration, the parameters, the dynamics, the scales, the window's length), and the
//! integrated state every path advances, an [`Integrated`] (time, state vector, work counters,
//! tolerance, work limit); what only one of them needs between calls is its part of [`Kept`]
//! (the Radau path's history included). They know nothing of the contact's windows,
//! step means, epoch or Model Exchange sides.
//!
//! Adding a path: a file here with a unit type implementing [`Path`] (its own kept fields, if
//! any, a field of [`Kept`]), one line in [`choose`], one arm in [`advance`], and a variant of
//! [`Integrator`] (`simulator.rs`) with its name.

mod attempts;
mod elastic;
mod exact;
mod explicit;
mod explicit_planar;
mod exponential;
mod integrated;
mod radau;
mod stage_support;

use std::sync::{Arc, OnceLock};

use nalgebra::SVector;

use super::drive::DriveKind;
use super::dynamics::{Dynamics, Eval, System};
use super::simulator::{Integrator, SimError};
use crate::physics::{ElastoPlastic, FrictionLaw, Vector};
use crate::solver::{Quad, Radau5, MAX_SWITCH};
use crate::table::{Config, InputId, Params};

pub(in crate::model) use integrated::Integrated;
pub(in crate::model) use radau::split as split_integrator;

/// What every path reads of the contact, lent for one call.
pub(in crate::model) struct Shared<'c, V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> {
    pub(in crate::model) config: Config,
    pub(in crate::model) params: &'c Params,
    pub(in crate::model) dynamics: &'c Dynamics<V, L, D>,
    /// Natural magnitudes of the state components.
    pub(in crate::model) scale: &'c [f64; N],
    /// Natural magnitude of the friction force, for the error of its integral.
    pub(in crate::model) force_scale: f64,
    /// Natural magnitudes of the switching functions `v_rx` and `s·v_r`.
    pub(in crate::model) switch_scale: [f64; MAX_SWITCH],
    /// The averaging window's length.
    pub(in crate::model) window_len: f64,
}

impl<'c, V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Shared<'c, V, L, D, N> {
    /// The right-hand side of the contact's dynamics.
    pub(in crate::model) fn system(&self) -> System<'c, V, L, D> {
        self.system_on(self.dynamics, self.scale)
    }

    /// The right-hand side of `dynamics` (this contact's, or its drive on the x axis alone)
    /// with the contact's input support and error scales.
    pub(in crate::model) fn system_on<'a, W: Vector, E: DriveKind<W>>(
        &self,
        dynamics: &'a Dynamics<W, L, E>,
        scale: &'a [f64],
    ) -> System<'a, W, L, E> {
        System::new(
            dynamics,
            self.config.input_support,
            scale,
            self.force_scale,
            self.switch_scale,
        )
    }

    /// Everything at the state's time and vector.
    pub(in crate::model) fn eval_now(&self, r: &Integrated<N>) -> Eval<V> {
        self.system().eval(r.t, r.y.as_slice())
    }

    /// Whether the harmonic source shakes the support along x harder than the contact can
    /// hold the body to it: `m·u0·(2·pi·f)²·|cos angle|` at least twice the largest friction
    /// force `max(F_C, F_S)`, so that the body slides through most of every period and sticks
    /// at most during the passages of `v_r` through 0.
    fn vibration_unheld(&self) -> bool {
        let most = self.dynamics.law.envelope() * self.params.k_t;
        self.dynamics.harmonic.is_some_and(|h| {
            let w = std::f64::consts::TAU * h.f;
            self.params.m * h.u0 * w * w * h.dir.0.abs() >= 2.0 * most
        })
    }

    /// True when the motion of a force- or spring-driven body (state `[s, x, v]`, each of
    /// `V::DIM` components) stays on the x axis: a longitudinal contact, or a planar one with
    /// no lateral deformation, velocity or support motion now (nothing then pushes the body off
    /// the axis).
    fn on_x_axis(&self, y: &SVector<f64, N>) -> bool {
        if V::DIM == 1 {
            return true;
        }
        let y = y.as_slice();
        let lateral_support = self
            .dynamics
            .harmonic
            .is_some_and(|h| h.dir.1 != 0.0 && h.u0 != 0.0 && h.f != 0.0)
            || (self.config.input_support && {
                let t = &self.dynamics.tracks[InputId::VSy.index()];
                t.value != 0.0 || t.slope != 0.0
            });
        y[1] == 0.0 && y[2 * V::DIM + 1] == 0.0 && !lateral_support
    }

    /// Ends a call of a path at `t_target` with the state vector `y` (projected onto the
    /// equations' constraints): the state there, the integrator restarted.
    fn finish(&self, r: &mut Integrated<N>, t_target: f64, mut y: SVector<f64, N>) {
        crate::solver::OdeSystem::<N>::project(&self.system(), t_target, &mut y);
        r.y = y;
        r.t = t_target;
        r.restart();
    }
}

/// The one rule of the exponential and explicit paths' step proposal ([`Kept::propose`]), kept
/// by stepping and checked on restore (`snapshot.rs`): a length ≥ 0 (0: none yet, the path
/// chooses one), or +∞ where nothing bounds the next step (no vibration and a rate that
/// vanishes, a subnormal sliding velocity: a path then steps to its target, as with any
/// proposal beyond it). Anything else (NaN, a negative length) becomes 0. A restored state must
/// hold a proposal this leaves as it is, so that every proposal a path stores restores, and
/// only those.
pub(in crate::model) fn step_proposal(h: f64) -> f64 {
    if h >= 0.0 {
        h
    } else {
        0.0
    }
}

/// What the paths keep between calls, each its own part.
#[derive(Clone, Debug)]
pub(in crate::model) struct Kept<const N: usize> {
    /// Radau even where a faster path applies (tests and benchmarks of the fast paths).
    pub(in crate::model) force_radau: bool,
    /// The exponential or explicit paths' proposed step (0: none yet); one for all three, so
    /// that a contact moving from one to another keeps its step size.
    pub(in crate::model) h: f64,
    /// The explicit path's.
    pub(in crate::model) explicit: explicit::ExplicitKept,
    /// The Radau path's: its history and scratch matrices.
    pub(in crate::model) radau: radau::RadauKept<N>,
}

/// What a communication step that fails restores of [`Kept`] (the rest is scratch or cache).
#[derive(Clone, Copy, Debug)]
pub(in crate::model) struct Saved<const N: usize> {
    h: f64,
    direction: f64,
    radau: Radau5<N>,
}

impl<const N: usize> Kept<N> {
    /// Nothing kept yet, at tolerance `tol`.
    pub(in crate::model) fn new(tol: f64) -> Self {
        Kept {
            force_radau: false,
            h: 0.0,
            explicit: explicit::ExplicitKept {
                direction: 0.0,
                elastoplastic: OnceLock::new(),
            },
            radau: radau::RadauKept::new(tol),
        }
    }

    /// Stores the step proposal a path leaves for the next call, under [`step_proposal`]'s
    /// rule.
    pub(in crate::model) fn propose(&mut self, h: f64) {
        self.h = step_proposal(h);
    }

    pub(in crate::model) fn save(&self) -> Saved<N> {
        Saved {
            h: self.h,
            direction: self.explicit.direction,
            radau: self.radau.history(),
        }
    }

    pub(in crate::model) fn restore(&mut self, s: Saved<N>) {
        self.h = s.h;
        self.explicit.direction = s.direction;
        self.radau.set_history(s.radau);
    }

    /// The explicit path's branch (saved states).
    pub(in crate::model) fn direction(&self) -> f64 {
        self.explicit.direction
    }

    /// Kept as in a saved state (`h`, `direction`, Radau's history) on `from`'s choice;
    /// `from`'s fitted shape too where it is the same law (`same_shape`).
    pub(in crate::model) fn load(&mut self, from: &Kept<N>, s: Saved<N>, same_shape: bool) {
        self.force_radau = from.force_radau;
        self.restore(s);
        if same_shape {
            self.explicit.elastoplastic = from.explicit.elastoplastic.clone();
        }
    }
}

impl<const N: usize> Saved<N> {
    pub(in crate::model) fn new(h: f64, direction: f64, radau: Radau5<N>) -> Self {
        Saved {
            h,
            direction,
            radau,
        }
    }
}

/// One way of advancing a contact.
trait Path<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> {
    /// Whether it applies to the contact now.
    fn applies(c: &Shared<'_, V, L, D, N>, r: &Integrated<N>, k: &Kept<N>) -> bool;
    /// Advances the contact's state `r` to `t_target` (no further than the averaging window's
    /// end): `∫F_F dt` over the call.
    fn advance(
        c: &Shared<'_, V, L, D, N>,
        r: &mut Integrated<N>,
        k: &mut Kept<N>,
        t_target: f64,
        h_max: f64,
    ) -> Result<Quad, SimError>;
}

/// The path the contact takes now, as `docs/model.md` ("How it is computed") lists them: the
/// first that applies.
pub(in crate::model) fn choose<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
    c: &Shared<'_, V, L, D, N>,
    r: &Integrated<N>,
    k: &Kept<N>,
) -> Integrator {
    use Integrator::*;
    if k.force_radau {
        Radau
    } else if exact::ClosedForm::applies(c, r, k) {
        ClosedForm
    } else if exponential::Exponential::applies(c, r, k) {
        Exponential
    } else if explicit::Explicit::applies(c, r, k) {
        Explicit
    } else if explicit_planar::ExplicitPlanar::applies(c, r, k) {
        ExplicitPlanar
    } else {
        Radau
    }
}

/// Advances the contact on `path` to `t_target`: `∫F_F dt` over the call.
pub(in crate::model) fn advance<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize>(
    path: Integrator,
    c: &Shared<'_, V, L, D, N>,
    r: &mut Integrated<N>,
    k: &mut Kept<N>,
    t_target: f64,
    h_max: f64,
) -> Result<Quad, SimError> {
    match path {
        Integrator::ClosedForm => exact::ClosedForm::advance(c, r, k, t_target, h_max),
        Integrator::Exponential => exponential::Exponential::advance(c, r, k, t_target, h_max),
        Integrator::Explicit => explicit::Explicit::advance(c, r, k, t_target, h_max),
        Integrator::ExplicitPlanar => {
            explicit_planar::ExplicitPlanar::advance(c, r, k, t_target, h_max)
        }
        Integrator::Radau => radau::Radau::advance(c, r, k, t_target, h_max),
    }
}

/// Advances a path whose map of a window is affine in `s` with a scalar decay (the closed form
/// with `kappa = 1`, the exponential path) to `t_target`: the decay `∫ a dt` and `∫F_F dt`.
/// None on any other path.
pub(in crate::model) fn advance_affine<
    V: Vector,
    L: FrictionLaw,
    D: DriveKind<V>,
    const N: usize,
>(
    c: &Shared<'_, V, L, D, N>,
    r: &mut Integrated<N>,
    k: &mut Kept<N>,
    t_target: f64,
    h_max: f64,
) -> Result<(f64, Quad), SimError> {
    match exact::relaxation(c, k) {
        Some(relax) => Ok(exact::advance_exact(c, r, relax, t_target)),
        None => exponential::advance_exp(c, r, k, t_target, h_max),
    }
}

/// True when the path now maps a window affinely in `s` with a scalar decay, `s ↦ exp(−L)·s +
/// beta`, for held inputs: the deformation's rate is linear in `s` and nothing else is
/// integrated (the closed form with `kappa = 1`, the exponential path).
pub(in crate::model) fn windows_affine<
    V: Vector,
    L: FrictionLaw,
    D: DriveKind<V>,
    const N: usize,
>(
    c: &Shared<'_, V, L, D, N>,
    r: &Integrated<N>,
    k: &Kept<N>,
) -> bool {
    exact::relaxation(c, k).is_some_and(|r| r.exponent == 1.0)
        || exponential::Exponential::applies(c, r, k)
}

/// Dupont's deformation along a branch for a breakaway ratio, fitted on first use.
type Shape = OnceLock<Option<Arc<ElastoPlastic>>>;
