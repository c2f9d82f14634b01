//! Integration of large systems with banded Jacobians (a chain of bodies, each coupled to its
//! neighbours only): band matrices and their LU factorisation (`lu.rs`), the Newton matrices of
//! a chain of bodies reduced to a tridiagonal system in the velocities (`chain.rs`), Radau IIA
//! of order 5 on them (`radau.rs`) and its Newton iteration continued on a few blocks alone
//! where only those have not converged (`local.rs`).

mod chain;
mod local;
mod lu;
mod radau;

pub use lu::{Band, BandLu};
pub use radau::{Accepted, BandRadau, BandSystem, BandWork};
