//! The bottom layer: what a contact is made of and what it exposes, with no physics, no solver
//! and no FMI.
//!
//! - `config.rs`: the structural choices of a scene ([`Config`]: law, motion, drive, sources);
//! - `table.rs`: every parameter, input and output declared once (expanded by `declare.rs`
//!   into [`Params`], [`Inputs`], [`Outputs`] and their ids);
//! - `rule.rs`: the accepted ranges ([`Rule`]) and the error naming a broken one;
//! - `dependencies.rs`: what each kind of output depends on ([`Depends`]);
//! - `states.rs`: the continuous states of Model Exchange ([`StateId`]) and what their
//!   derivatives depend on;
//! - `string.rs`: the variables of a string of contacts ([`StringVar`]), their value
//!   references and values ([`StringValues`]).

#[macro_use]
mod declare;
mod config;
mod dependencies;
mod rule;
mod states;
mod string;
#[allow(clippy::module_inception)]
mod table;

pub use config::{ChoiceKey, Config, Drive, Lateral, Law, Motion, Normal, Support};
pub use dependencies::{Dependency, Depends};
pub use rule::{number, ParamError, Rule, Sign};
pub use states::{force_knowns, rate_knowns, velocity_knowns, IndicatorId, Known, StateId};
pub use string::{
    shared_params, Role, Shape, StringDependency, StringValues, StringVar, ARRAY_STRIDE, LINK_RULE,
    MAX_SECTIONS,
};
pub use table::{InputId, Inputs, OutputId, Outputs, ParamId, Params};

/// Whether a variable may change during the simulation (the model description's
/// `variability`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    /// Set before initialization only.
    Fixed,
    /// A parameter that may change between communication steps.
    Tunable,
    /// Inputs and outputs.
    Continuous,
}

impl Variability {
    pub fn as_str(self) -> &'static str {
        match self {
            Variability::Fixed => "fixed",
            Variability::Tunable => "tunable",
            Variability::Continuous => "continuous",
        }
    }
}

impl ParamId {
    pub fn from_name(name: &str) -> Option<ParamId> {
        ParamId::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Sets the parameter if the value obeys its rule; otherwise leaves `p` untouched.
    pub fn set(self, p: &mut Params, value: f64) -> Result<(), ParamError> {
        self.check(value)?;
        *self.slot(p) = value;
        Ok(())
    }

    /// Checks a value against the parameter's rule in every scene.
    pub fn check(self, value: f64) -> Result<(), ParamError> {
        self.error_unless(self.rule(), value)
    }

    /// Checks a value against the parameter's rule in a scene with this configuration.
    pub fn check_in(self, value: f64, c: &Config) -> Result<(), ParamError> {
        self.error_unless(self.rule_in(c), value)
    }

    fn error_unless(self, rule: Rule, value: f64) -> Result<(), ParamError> {
        if rule.holds(value) {
            Ok(())
        } else {
            Err(ParamError {
                name: self.name(),
                value,
                rule,
                unit: self.unit(),
            })
        }
    }
}

impl Params {
    /// Makes the present load (`F_N`, `mu`) the reference load: the one at which LuGre's static
    /// force `F_S` and contact damping ratio `zeta_t` are given. A scene calls it once its start
    /// values are read; at any other load they scale with it (`Params::static_force`,
    /// `Params::damping_ratio`).
    pub fn set_reference(&mut self) {
        self.f_n_ref = self.f_n;
        self.mu_ref = self.mu;
    }

    /// The Coulomb force of the reference load, `mu_ref·F_N_ref`: the load at which `F_S` and
    /// `zeta_t` are given (a scene's start values of `mu` and `F_N`).
    pub fn reference_f_c(&self) -> f64 {
        self.mu_ref * self.f_n_ref
    }

    /// The combination of parameters a LuGre contact refuses: a static force below the Coulomb
    /// force at the reference load (`F_S < F_C`) would turn the Stribeck curve upside down
    /// (friction rising with speed). The text names both; `None` when consistent.
    pub fn static_force_inverted(&self) -> Option<String> {
        let f_c = self.reference_f_c();
        (self.f_s < f_c).then(|| {
            format!(
                "F_S = {} N is below the Coulomb force F_C = mu·F_N = {} N (mu = {}, F_N = {} N, \
                 the load at which F_S is given): LuGre's static force must be at least F_C, \
                 else the Stribeck curve is inverted (friction rising with speed); F_S scales \
                 with mu·F_N, keeping F_S/F_C",
                number(self.f_s),
                number(f_c),
                number(self.mu_ref),
                number(self.f_n_ref)
            )
        })
    }

    /// Checks every parameter against its rule.
    pub fn validate(&self) -> Result<(), ParamError> {
        for id in ParamId::ALL {
            id.check(id.get(self))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_obey_rules() {
        Params::default().validate().unwrap();
    }

    #[test]
    fn names_round_trip_and_bad_values_leave_params_untouched() {
        for id in ParamId::ALL {
            assert_eq!(ParamId::from_name(id.name()), Some(id));
        }
        let mut p = Params::default();
        let err = ParamId::KT.set(&mut p, 0.0).unwrap_err();
        assert_eq!(err.name, "k_t");
        assert_eq!(
            err.to_string(),
            "k_t = 0: must be finite and > 0 (accepted: 100 to 1e13 N/m)"
        );
        assert_eq!(p, Params::default());
        assert!(ParamId::RBa.set(&mut p, 1.0).is_err());
        assert!(ParamId::Mu.set(&mut p, f64::NAN).is_err());
        assert!(ParamId::FN.set(&mut p, 0.0).is_ok());
    }

    #[test]
    fn ids_index_their_lists() {
        for (k, id) in InputId::ALL.into_iter().enumerate() {
            assert_eq!(id.index(), k);
        }
    }
}
