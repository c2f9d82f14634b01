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
}

/// Identifies one input, for generic access.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum InputId {
    FD,
    VD,
    VSx,
    VSy,
}

impl InputId {
    pub const ALL: [InputId; 4] = [InputId::FD, InputId::VD, InputId::VSx, InputId::VSy];

    pub fn name(self) -> &'static str {
        match self {
            InputId::FD => "F_d",
            InputId::VD => "v_d",
            InputId::VSx => "v_sx",
            InputId::VSy => "v_sy",
        }
    }

    pub fn get(self, i: &Inputs) -> f64 {
        match self {
            InputId::FD => i.f_d,
            InputId::VD => i.v_d,
            InputId::VSx => i.v_sx,
            InputId::VSy => i.v_sy,
        }
    }

    pub fn slot(self, i: &mut Inputs) -> &mut f64 {
        match self {
            InputId::FD => &mut i.f_d,
            InputId::VD => &mut i.v_d,
            InputId::VSx => &mut i.v_sx,
            InputId::VSy => &mut i.v_sy,
        }
    }

    /// True when a scene with this configuration has the input.
    pub fn present(self, c: &Config) -> bool {
        match self {
            InputId::FD => c.drive == Drive::Force,
            InputId::VD => c.drive != Drive::Force,
            InputId::VSx => c.input_support,
            InputId::VSy => c.input_support && c.planar(),
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
}

impl OutputId {
    pub const ALL: [OutputId; 12] = [
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
        }
    }

    /// True when a scene with this configuration can have the output.
    pub fn present(self, c: &Config) -> bool {
        match self {
            OutputId::FFy | OutputId::Y | OutputId::Vy | OutputId::Sy => c.planar(),
            OutputId::FDrive => c.drive == Drive::Spring,
            _ => true,
        }
    }
}

/// True when a scene with this configuration uses the parameter.
pub fn param_present(id: crate::physics::ParamId, c: &Config) -> bool {
    use crate::physics::ParamId as P;
    match id {
        P::M => c.body_dynamic() || c.law == Law::LuGre,
        P::FN | P::Mu | P::KT | P::TAvg => true,
        P::Kappa => c.law == Law::Dahl && c.motion == Motion::Longitudinal,
        P::RBa => c.law == Law::Dupont,
        P::FS | P::VS | P::ZetaT | P::HV | P::VE => c.law == Law::LuGre,
        P::U0 | P::F | P::Phase => c.harmonic,
        P::Angle => c.harmonic && c.planar(),
        P::KD | P::CD => c.drive == Drive::Spring,
    }
}
