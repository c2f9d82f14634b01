//! Identifiers of the inputs, outputs and parameters a configuration has. Depends only on
//! `config.rs` and `physics/params.rs`, so that `build.rs` can include it.

use crate::model::{Config, Drive, Law, Motion};

/// The importer's inputs at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inputs {
    /// Driving force `F_d` [N] (force drive).
    pub f_d: f64,
    /// Driving velocity `v_d` [m/s] (velocity and spring drives).
    pub v_d: f64,
    /// Support velocity along x, `v_sx` [m/s] (input support motion).
    pub v_sx: f64,
    /// Support velocity along y, `v_sy` [m/s] (input support motion, planar).
    pub v_sy: f64,
    /// Normal force `F_N` [N] (scenes with `normal = "input"`).
    pub f_n: f64,
}

/// Identifies one input, for generic access.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum InputId {
    FD,
    VD,
    VSx,
    VSy,
    /// The normal force, in scenes where it is an input (its variable is the parameter `F_N`'s).
    FN,
}

impl InputId {
    pub const ALL: [InputId; 5] = [
        InputId::FD,
        InputId::VD,
        InputId::VSx,
        InputId::VSy,
        InputId::FN,
    ];

    pub fn name(self) -> &'static str {
        match self {
            InputId::FD => "F_d",
            InputId::VD => "v_d",
            InputId::VSx => "v_sx",
            InputId::VSy => "v_sy",
            InputId::FN => "F_N",
        }
    }

    pub fn get(self, i: &Inputs) -> f64 {
        match self {
            InputId::FD => i.f_d,
            InputId::VD => i.v_d,
            InputId::VSx => i.v_sx,
            InputId::VSy => i.v_sy,
            InputId::FN => i.f_n,
        }
    }

    pub fn slot(self, i: &mut Inputs) -> &mut f64 {
        match self {
            InputId::FD => &mut i.f_d,
            InputId::VD => &mut i.v_d,
            InputId::VSx => &mut i.v_sx,
            InputId::VSy => &mut i.v_sy,
            InputId::FN => &mut i.f_n,
        }
    }

    /// The accepted range of the input's value: wide for every real use, finite everywhere
    /// (the normal force that of the parameter `F_N`).
    pub fn rule(self) -> crate::physics::Rule {
        use crate::physics::{ParamId, Rule, Sign};
        match self {
            InputId::FD => Rule {
                sign: Sign::Any,
                min: -1e9,
                max: 1e9,
            },
            InputId::VD | InputId::VSx | InputId::VSy => Rule {
                sign: Sign::Any,
                min: -1e3,
                max: 1e3,
            },
            InputId::FN => ParamId::FN.rule(),
        }
    }

    /// Unit of the input.
    pub fn unit(self) -> &'static str {
        match self {
            InputId::FD | InputId::FN => "N",
            InputId::VD | InputId::VSx | InputId::VSy => "m/s",
        }
    }

    /// True when a scene with this configuration has the input.
    pub fn present(self, c: &Config) -> bool {
        match self {
            InputId::FD => c.drive == Drive::Force,
            InputId::VD => c.drive != Drive::Force,
            InputId::VSx => c.input_support,
            InputId::VSy => c.input_support && c.planar(),
            InputId::FN => c.normal_input,
        }
    }
}

/// Everything the contact reports at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Outputs {
    /// Friction force `F_F` [N] (resists the relative motion; the support acts on the body with `−F_F`).
    pub f_fx: f64,
    pub f_fy: f64,
    /// Body position [m].
    pub x: f64,
    pub y: f64,
    /// Body velocity [m/s].
    pub v_x: f64,
    pub v_y: f64,
    /// Contact deformation [m].
    pub s_x: f64,
    pub s_y: f64,
    /// Mean of `F_Fx` over the most recently completed averaging window [N].
    pub f_mean: f64,
    /// `1 − F_mean/F_C`: the fraction by which the vibration lowers the mean friction force
    /// (0: no reduction, also when `F_C` = 0; 1: no mean friction left).
    pub reduction: f64,
    /// Power dissipated in the contact [W].
    pub p_diss: f64,
    /// Mean of `F_Fx` and `F_Fy` over the last communication step, `∫F dt/h` [N]: what a host
    /// integrates without aliasing (the instantaneous force before the first step).
    pub f_fx_step: f64,
    pub f_fy_step: f64,
    /// Driving force [N]: the input in force drive, the spring-damper force in spring drive, and
    /// the instantaneous force needed to impose `v_d` (= `F_Fx`) in velocity drive.
    pub f_d: f64,
}

/// Identifies one output, for generic access.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OutputId {
    FFx,
    FFy,
    X,
    Y,
    Vx,
    Vy,
    Sx,
    Sy,
    FMean,
    Reduction,
    PDiss,
    /// `F_d` as an output: only in spring drive (in force drive `F_d` is the input).
    FDrive,
    FFxStep,
    FFyStep,
}

impl OutputId {
    pub const ALL: [OutputId; 14] = [
        OutputId::FFx,
        OutputId::FFy,
        OutputId::X,
        OutputId::Y,
        OutputId::Vx,
        OutputId::Vy,
        OutputId::Sx,
        OutputId::Sy,
        OutputId::FMean,
        OutputId::Reduction,
        OutputId::PDiss,
        OutputId::FDrive,
        OutputId::FFxStep,
        OutputId::FFyStep,
    ];

    pub fn name(self) -> &'static str {
        match self {
            OutputId::FFx => "F_Fx",
            OutputId::FFy => "F_Fy",
            OutputId::X => "x",
            OutputId::Y => "y",
            OutputId::Vx => "v_x",
            OutputId::Vy => "v_y",
            OutputId::Sx => "s_x",
            OutputId::Sy => "s_y",
            OutputId::FMean => "F_mean",
            OutputId::Reduction => "reduction",
            OutputId::PDiss => "P_diss",
            OutputId::FDrive => "F_d",
            OutputId::FFxStep => "F_Fx_step",
            OutputId::FFyStep => "F_Fy_step",
        }
    }

    pub fn get(self, o: &Outputs) -> f64 {
        match self {
            OutputId::FFx => o.f_fx,
            OutputId::FFy => o.f_fy,
            OutputId::X => o.x,
            OutputId::Y => o.y,
            OutputId::Vx => o.v_x,
            OutputId::Vy => o.v_y,
            OutputId::Sx => o.s_x,
            OutputId::Sy => o.s_y,
            OutputId::FMean => o.f_mean,
            OutputId::Reduction => o.reduction,
            OutputId::PDiss => o.p_diss,
            OutputId::FDrive => o.f_d,
            OutputId::FFxStep => o.f_fx_step,
            OutputId::FFyStep => o.f_fy_step,
        }
    }

    /// True when a scene with this configuration can have the output.
    pub fn present(self, c: &Config) -> bool {
        match self {
            OutputId::FFy | OutputId::Y | OutputId::Vy | OutputId::Sy | OutputId::FFyStep => {
                c.planar()
            }
            OutputId::FDrive => c.drive == Drive::Spring,
            _ => true,
        }
    }
}

/// The accepted range of a parameter in this configuration: its physical rule, narrowed where
/// the configuration's integrator needs it to keep the work per vibration period bounded. A
/// Dahl exponent below 0.5 under a force or spring drive makes the body and the deformation,
/// integrated together, take millions of steps per millisecond where the deformation reaches
/// its bound at a finite distance (the velocity drive takes the closed form for any exponent).
pub fn param_rule(id: crate::physics::ParamId, c: &Config) -> crate::physics::Rule {
    let rule = id.rule();
    if id == crate::physics::ParamId::Kappa && c.drive != Drive::Velocity {
        crate::physics::Rule { min: 0.5, ..rule }
    } else {
        rule
    }
}

/// Checks a parameter value against [`param_rule`].
pub fn check_param(
    id: crate::physics::ParamId,
    value: f64,
    c: &Config,
) -> Result<(), crate::physics::ParamError> {
    let rule = param_rule(id, c);
    if rule.holds(value) {
        Ok(())
    } else {
        Err(crate::physics::ParamError {
            name: id.name(),
            value,
            rule,
        })
    }
}

/// True when a scene with this configuration uses the parameter.
pub fn param_present(id: crate::physics::ParamId, c: &Config) -> bool {
    use crate::physics::ParamId as P;
    match id {
        P::M => c.body_dynamic() || c.law == Law::LuGre,
        P::FN | P::Mu | P::KT | P::TAvg | P::MaxSteps => true,
        P::Kappa => c.law == Law::Dahl && c.motion == Motion::Longitudinal,
        P::RBa => c.law == Law::Dupont,
        P::FS | P::VS | P::ZetaT | P::HV | P::VE => c.law == Law::LuGre,
        P::U0 | P::F | P::Phase => c.harmonic,
        P::Angle => c.harmonic && c.planar(),
        P::KD | P::CD => c.drive == Drive::Spring,
    }
}
