//! Physics of the contact, with no knowledge of FMI or of the integrator: parameters, in-plane
//! vectors, friction laws and support motion.

mod law;
mod params;
mod support;
pub mod trig;
mod vector;

pub use law::{
    Dahl, Dupont, FrictionLaw, LawJacobian, Linear, LuGre, Mat2, Relaxation, NO_FRICTION_LENGTH,
};
// The parameters live in `table`; name them from there. Only fmi/ (staging.rs, instance.rs,
// model_exchange.rs, saved.rs) still reaches them through physics, its only arrows into
// physics: once those four imports read `crate::table`, delete this line.
#[doc(hidden)]
pub use crate::table::{ParamId, Params};
pub use support::{Harmonic, InputTrack};
pub use vector::{Planar, Vector};
