//! The numerical methods, knowing nothing of friction or of FMI:
//! - [`Radau5`]: an L-stable, stiffly accurate Radau IIA method of order 5 with error control,
//!   dense output, located switching events and exact landing on requested times, for any
//!   [`OdeSystem`];
//! - [`dopri`]: one step of Dormand–Prince 5(4) with its error estimate and continuous
//!   extension, for the smooth pieces of a moving body's motion;
//! - [`expint`]: exponential integration of a deformation relaxing toward a moving target at a
//!   scalar rate, explicit and of the same cost at any stiffness;
//! - [`quadrature`]: adaptive Gauss–Kronrod 7/15, for integrals of closed-form solutions;
//! - [`band`]: Radau IIA on systems of any size with banded Jacobians (a string of contacts).

// Numerical kernels index several arrays in lockstep (stages, Butcher rows, matrix entries);
// index loops say that more plainly than zipped iterators.
#![allow(clippy::needless_range_loop)]

pub mod band;
pub mod dopri;
pub mod expint;
mod lu;
pub mod quadrature;
mod radau;
mod system;

pub use radau::{Radau5, Workspace, B, C};
pub use system::{OdeSystem, Quad, SolverError, SolverStats, Step, MAX_DIM, MAX_QUAD, MAX_SWITCH};
