//! What the exporter writes beside an FMU's model description, from the same scene reader and
//! variable table the FMU's library reads: each FMU's documentation page with its picture
//! (`docs.rs`, `figure.rs`; a string of contacts' in `string_page.rs`) and the scene reference `docs/scenes.md` (`reference.rs`).
//!
//! A crate of its own so that none of it goes into the FMU's shared library: only the command
//! line's exporter and the tests use it. It reads the library's `description` and `table`
//! layers and nothing below them (`tests/layers.rs`).

pub mod docs;
pub mod figure;
pub mod reference;
pub mod string_page;
