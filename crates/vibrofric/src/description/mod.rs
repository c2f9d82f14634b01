//! What an FMU declares: the variable table, scenes, and the generated `modelDescription.xml`.
//! Knows the model's identifiers, nothing of the integrator or of C.

pub mod log;
pub mod scene;
pub mod variables;
pub mod xml;
pub mod xml3;

pub use scene::{Scene, SceneError};
