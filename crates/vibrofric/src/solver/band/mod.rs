//! Integration of large systems with banded Jacobians (a chain of bodies, each coupled to its
//! neighbours only): band matrices and their LU factorisation (`lu.rs`), the Newton matrices of
//! a chain of bodies reduced to a tridiagonal system in the velocities (`chain.rs`), and Radau
//! IIA of order 5 on them (`radau.rs`).

mod chain;
mod lu;
mod radau;

pub use lu::{Band, BandLu};
pub use radau::{Accepted, BandRadau, BandSystem, BandWork};
