//! The model's view of the variable table (`src/table`): the inputs it reads, the outputs it
//! reports, and the accepted range of a parameter in a configuration.

use crate::table::{Config, ParamError, ParamId, Rule};
pub use crate::table::{InputId, Inputs, OutputId, Outputs};

/// The accepted range of a parameter in this configuration.
pub fn param_rule(id: ParamId, c: &Config) -> Rule {
    id.rule_in(c)
}

/// Checks a parameter value against [`param_rule`].
pub fn check_param(id: ParamId, value: f64, c: &Config) -> Result<(), ParamError> {
    id.check_in(value, c)
}

/// True when a scene with this configuration uses the parameter.
pub fn param_present(id: ParamId, c: &Config) -> bool {
    id.present(c)
}
