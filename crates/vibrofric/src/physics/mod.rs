//! Physics of the contact, with no knowledge of FMI or of the integrator: parameters, in-plane
//! vectors, friction laws and support motion.

mod chebyshev;
mod elastoplastic;
mod law;
mod params;
mod support;
pub mod trig;
mod vector;

pub use elastoplastic::{BranchStart, ElastoPlastic};
pub use law::{
    Dahl, Dupont, FrictionLaw, LawJacobian, Linear, LuGre, Mat2, Relaxation, Steady, VelocityTerms,
    NO_FRICTION_LENGTH,
};
pub use support::{Harmonic, InputTrack};
pub use vector::{Planar, Vector};
