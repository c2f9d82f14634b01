//! Where an instance's messages go. The C layer wraps the importer's logger callback in a
//! [`Logger`]; the categories are the model description's (`description/log.rs`).

use super::status::Status;

pub trait Logger {
    /// `category` is a [`Category`](crate::description::log::Category) name; `message` is
    /// plain text (no format directives are interpreted).
    fn log(&self, status: Status, category: &str, message: &str);
}

/// A logger that drops everything (the importer gave none).
pub struct NoLogger;

impl Logger for NoLogger {
    fn log(&self, _: Status, _: &str, _: &str) {}
}
