//! Quantities the physics derives from the parameters. The parameters themselves, with their
//! units, defaults and accepted ranges, are declared in `src/table/table.rs`.

pub use crate::table::{ParamError, ParamId, Params, Rule, Sign};

impl Params {
    /// Coulomb force `F_C = mu·F_N`.
    pub fn f_c(&self) -> f64 {
        self.mu * self.f_n
    }

    /// Angular frequency `omega = 2·pi·f`.
    pub fn omega(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.f
    }

    /// Velocity amplitude of the harmonic source `v_a = omega·u0`.
    pub fn v_a(&self) -> f64 {
        self.omega() * self.u0
    }
}
