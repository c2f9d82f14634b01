//! What an FMU declares: its scene, the rows of its variables, and the generated
//! `modelDescription.xml` (FMI 2.0 and 3.0). Knows the model's identifiers, nothing of the
//! integrator or of C. The documentation pages and `docs/scenes.md` are written at export time by
//! the `vibrofric-docs` crate, from these.

pub mod log;
pub mod scene;
pub mod variables;
pub mod xml;
pub mod xml3;
mod xml_parts;
pub mod xml_string;

pub use scene::{Scene, SceneError};
