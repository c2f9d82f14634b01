//! What each output depends on, by kind of output ([`Depends`], named in each output's
//! declaration): the inputs it depends on directly (`ModelStructure/Outputs`) and the
//! parameters and inputs it depends on at initialization (`ModelStructure/InitialUnknowns`).
//!
//! Derived from the equations of `docs/model.md`. At the start time the deformation is zero, the
//! body rests at the origin and the spring's far end is at `x_d = 0`, so:
//! - `s`, `x`, `y`, `v_y` are 0: no dependency; `v_x` is `v_d` in velocity drive, else 0.
//! - Dahl and Dupont: `F_F = k_t·s = 0`, `P_diss = 0`: no dependency.
//! - LuGre: `ds/dt = v_r` (0 when `F_C = F_S = 0`), so `F_F = (h_t(|v_r|) + h_v)·v_r` with
//!   `h_t = 2·zeta_t·sqrt(m·k_t)·exp(−|v_r|²/v_e²)`; `v_r = v − v_s` depends on `v_d` (velocity
//!   drive), the harmonic source (`u0`, `f`, `phase`, `angle`) and the input support velocities.
//!   `P_diss = F_F·v_r` has the same dependencies.
//! - `F_mean` and the step means = `F_F` at the start; `reduction = 1 − F_mean/F_C` adds `F_N`,
//!   `mu`.
//! - Spring drive: `F_d = c_d·v_d`.
//!
//! During the simulation, LuGre's force has terms in `v_r`, so it depends directly on the
//! inputs that set the relative velocity; Dahl's and Dupont's is `k_t·s`, a state. The
//! dissipation `F_F·v_r` depends on them under every law. A normal force input acts at once on
//! the force (a lower load makes the contact slip back onto its envelope; LuGre's `g`), the
//! deformation, the dissipation and the reduction (through `F_C`).

use super::{Config, InputId, ParamId};

/// The kinds of output, by what they depend on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Depends {
    /// The friction force `F_F`.
    Force,
    /// `F_mean`, the mean over the last completed window.
    Mean,
    /// The means over the last communication step: nothing now, the friction at the start.
    StepMean,
    /// `reduction = 1 − F_mean/F_C`.
    Reduction,
    /// `P_diss`.
    Dissipation,
    /// The deformation `s`.
    Deformation,
    /// A state of the body that starts at 0 (`x`, `y`, `v_y`).
    State,
    /// `v_x`: the input `v_d` in velocity drive, a state otherwise.
    BodyVelocity,
    /// The spring-damper force `F_d = k_d·(x_d − x) + c_d·(v_d − v_x)`.
    DriveForce,
}

/// A variable an output depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dependency {
    Param(ParamId),
    Input(InputId),
}

impl Dependency {
    /// The value reference of the variable.
    pub fn vr(self) -> u32 {
        match self {
            Dependency::Param(p) => p.vr(),
            Dependency::Input(i) => i.vr(),
        }
    }
}

/// The inputs that set the relative velocity `v_r` (beside the harmonic source).
fn velocity_inputs(c: &Config) -> Vec<InputId> {
    let mut d = vec![];
    if c.drive.imposes_velocity() {
        d.push(InputId::VD);
    }
    if c.input_support {
        d.push(InputId::VSx);
        if c.planar() {
            d.push(InputId::VSy);
        }
    }
    d
}

impl Depends {
    /// The inputs whose current value the output depends on directly, in this configuration.
    pub fn direct(self, c: &Config) -> Vec<InputId> {
        let rate = c.law.force_has_rate();
        let mut deps = match self {
            Depends::Force | Depends::Mean | Depends::Reduction if rate => velocity_inputs(c),
            Depends::Dissipation => velocity_inputs(c),
            Depends::BodyVelocity if c.drive.imposes_velocity() => vec![InputId::VD],
            Depends::DriveForce => vec![InputId::VD],
            _ => vec![],
        };
        let load = matches!(
            self,
            Depends::Force | Depends::Deformation | Depends::Dissipation | Depends::Reduction
        );
        if c.normal_input && load {
            deps.push(InputId::FN);
        }
        deps
    }

    /// The parameters and inputs the output depends on at initialization.
    pub fn initial(self, c: &Config) -> Vec<Dependency> {
        let friction = || {
            if !c.law.force_has_rate() {
                return vec![];
            }
            let mut d: Vec<Dependency> = [
                ParamId::M,
                ParamId::FN,
                ParamId::Mu,
                ParamId::KT,
                ParamId::FS,
                ParamId::ZetaT,
                ParamId::HV,
                ParamId::VE,
            ]
            .map(Dependency::Param)
            .to_vec();
            if c.harmonic {
                d.extend([ParamId::U0, ParamId::F, ParamId::Phase].map(Dependency::Param));
                if c.planar() {
                    d.push(Dependency::Param(ParamId::Angle));
                }
            }
            d.extend(velocity_inputs(c).into_iter().map(Dependency::Input));
            d
        };
        match self {
            Depends::Force | Depends::Mean | Depends::StepMean | Depends::Dissipation => friction(),
            Depends::Reduction => {
                let mut d = friction();
                for p in [ParamId::FN, ParamId::Mu].map(Dependency::Param) {
                    if !d.contains(&p) {
                        d.push(p);
                    }
                }
                d
            }
            Depends::BodyVelocity if c.drive.imposes_velocity() => {
                vec![Dependency::Input(InputId::VD)]
            }
            Depends::DriveForce => vec![
                Dependency::Param(ParamId::CD),
                Dependency::Input(InputId::VD),
            ],
            _ => vec![],
        }
    }
}
