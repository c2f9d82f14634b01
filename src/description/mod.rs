//! What an FMU declares: the variable table, scenes, and the generated `modelDescription.xml`.
//! Knows the model's identifiers, nothing of the integrator or of C.

pub mod docs;
pub mod figure;
pub mod reference;
pub mod scene;
pub mod variables;
pub mod xml;

/// The model descriptions `build.rs` generated from `scenes/*.toml` at build time, with the same
/// code as [`xml::model_description`].
pub mod generated {
    include!(concat!(env!("OUT_DIR"), "/model_descriptions.rs"));
}

pub use scene::{Scene, SceneError};
