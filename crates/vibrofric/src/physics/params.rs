//! Quantities the physics derives from the parameters. The parameters themselves, with their
//! units, defaults and accepted ranges, are declared in `table/table.rs` and named from there
//! (`crate::table::Params`, `ParamId`).

use crate::table::Params;

impl Params {
    /// Coulomb force `F_C = mu·F_N`.
    pub fn f_c(&self) -> f64 {
        self.mu * self.f_n
    }

    /// LuGre's static force at the present load: `F_S` is given at the reference load and
    /// follows the Coulomb force, `F_S·(F_N/F_N_ref)·(mu/mu_ref)`, so that the law keeps its shape
    /// (`F_S/F_C`) at any load and friction coefficient. Exactly `F_S` at the reference load.
    /// Without a reference load (`F_N_ref` or `mu_ref` = 0) `F_S` is taken as it is.
    pub fn static_force(&self) -> f64 {
        if self.f_n_ref > 0.0 && self.mu_ref > 0.0 {
            self.f_s * (self.f_n / self.f_n_ref) * (self.mu / self.mu_ref)
        } else {
            self.f_s
        }
    }

    /// LuGre's contact damping ratio at the present load: `zeta_t` is given at the reference
    /// load and scales with the normal force, `zeta_t·F_N/F_N_ref` (damping by the asperities in
    /// contact). Exactly `zeta_t` at the reference load; `zeta_t` itself without one.
    pub fn damping_ratio(&self) -> f64 {
        if self.f_n_ref > 0.0 {
            self.zeta_t * (self.f_n / self.f_n_ref)
        } else {
            self.zeta_t
        }
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
