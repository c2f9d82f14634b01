//! The one variable table: names, value references, units, causality. The generated
//! `modelDescription.xml` and get/set by value reference both read it, and nothing else.
//!
//! Value references are fixed per variable and shared by every scene; a scene carries the subset
//! its configuration has (see [`Variable::present`]).

use crate::model::{param_present, Config, Drive, InputId, Inputs, Law, OutputId};
use crate::physics::{ParamId, Params};

/// What a variable is bound to in the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarKind {
    Param(ParamId),
    Input(InputId),
    Output(OutputId),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    Input,
    Output,
}

impl Causality {
    pub fn as_str(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::Input => "input",
            Causality::Output => "output",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    Fixed,
    Tunable,
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

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Initial {
    Exact,
    Calculated,
}

impl Initial {
    pub fn as_str(self) -> &'static str {
        match self {
            Initial::Exact => "exact",
            Initial::Calculated => "calculated",
        }
    }
}

/// One row of the table.
#[derive(Clone, Copy, Debug)]
pub struct Variable {
    pub vr: u32,
    pub kind: VarKind,
    pub description: &'static str,
    /// Unit name in `UnitDefinitions` (SI).
    pub unit: &'static str,
    /// Display unit for the importer's GUI, if any (µm, mm/s, deg).
    pub display_unit: Option<&'static str>,
}

impl Variable {
    pub fn name(&self) -> &'static str {
        match self.kind {
            VarKind::Param(p) => p.name(),
            VarKind::Input(i) => i.name(),
            VarKind::Output(o) => o.name(),
        }
    }

    /// `F_d` is the input of a force drive and the spring-damper force output of a spring drive;
    /// `F_N` is a parameter, or an input in scenes with `normal = "input"`.
    pub fn causality(&self, c: &Config) -> Causality {
        match self.kind {
            VarKind::Param(ParamId::FN) if c.normal_input => Causality::Input,
            VarKind::Param(_) => Causality::Parameter,
            VarKind::Input(InputId::FD) if c.drive == Drive::Spring => Causality::Output,
            VarKind::Input(_) => Causality::Input,
            VarKind::Output(_) => Causality::Output,
        }
    }

    pub fn variability(&self, c: &Config) -> Variability {
        match self.kind {
            VarKind::Param(ParamId::FN) if c.normal_input => Variability::Continuous,
            VarKind::Param(p) if p.tunable() => Variability::Tunable,
            VarKind::Param(_) => Variability::Fixed,
            _ => Variability::Continuous,
        }
    }

    /// `initial` attribute; `None` for inputs (which have no `initial`, only a `start`).
    pub fn initial(&self, c: &Config) -> Option<Initial> {
        match (self.kind, self.causality(c)) {
            (_, Causality::Input) => None,
            (VarKind::Param(_), _) => Some(Initial::Exact),
            _ => Some(Initial::Calculated),
        }
    }

    /// True when a scene with this configuration and these outputs carries the variable.
    pub fn present(&self, c: &Config, outputs: &[OutputId]) -> bool {
        match self.kind {
            VarKind::Param(p) => param_present(p, c),
            VarKind::Input(InputId::FD) if c.drive == Drive::Spring => {
                outputs.contains(&OutputId::FDrive)
            }
            VarKind::Input(i) => i.present(c),
            VarKind::Output(o) => o.present(c) && outputs.contains(&o),
        }
    }

    /// `start` attribute: the parameter's value, the input's start value (a scene's
    /// `Scene::inputs`), none for calculated outputs.
    pub fn start(&self, c: &Config, params: &Params, inputs: &Inputs) -> Option<f64> {
        match (self.kind, self.causality(c)) {
            (VarKind::Param(p), _) => Some(p.get(params)),
            (VarKind::Input(i), Causality::Input) => Some(i.get(inputs)),
            _ => None,
        }
    }

    /// Lower bound (`min`): the accepted range of parameters and inputs (outputs have none:
    /// LuGre, for one, is not passive in general).
    pub fn min(&self, c: &Config) -> Option<f64> {
        match self.kind {
            VarKind::Param(p) => crate::model::param_rule(p, c).min(),
            VarKind::Input(i) => i.rule().min(),
            VarKind::Output(_) => None,
        }
    }

    /// Upper bound (`max`) of the accepted range of parameters and inputs.
    pub fn max(&self, c: &Config) -> Option<f64> {
        match self.kind {
            VarKind::Param(p) => crate::model::param_rule(p, c).max(),
            VarKind::Input(i) => i.rule().max(),
            VarKind::Output(_) => None,
        }
    }

    /// Inputs whose current value the output depends on directly (the `dependencies` of
    /// `ModelStructure/Outputs`), in this configuration.
    pub fn input_dependencies(&self, c: &Config) -> Vec<InputId> {
        let support = |v: &mut Vec<InputId>| {
            if c.input_support {
                v.push(InputId::VSx);
                if c.planar() {
                    v.push(InputId::VSy);
                }
            }
        };
        // The body velocity is the input v_d under velocity drive, a state otherwise.
        let velocity_input = c.drive == Drive::Velocity;
        let mut deps = vec![];
        let out = match self.kind {
            VarKind::Output(o) => o,
            VarKind::Input(InputId::FD) if c.drive == Drive::Spring => OutputId::FDrive,
            _ => return deps,
        };
        match out {
            // F_F = k_t·s for Dahl and Dupont; LuGre adds terms in v_r.
            OutputId::FFx | OutputId::FFy | OutputId::FMean | OutputId::Reduction
                if c.law == Law::LuGre =>
            {
                if velocity_input {
                    deps.push(InputId::VD);
                }
                support(&mut deps);
            }
            OutputId::PDiss => {
                if velocity_input {
                    deps.push(InputId::VD);
                }
                support(&mut deps);
            }
            OutputId::Vx if velocity_input => deps.push(InputId::VD),
            OutputId::FDrive => deps.push(InputId::VD),
            _ => {}
        }
        // A normal force input acts at once on the force (a lower load makes the contact slip
        // back onto its envelope; LuGre's g), on the deformation, on the dissipation and on
        // the reduction (through F_C).
        if c.normal_input {
            let direct = matches!(
                out,
                OutputId::FFx
                    | OutputId::FFy
                    | OutputId::Sx
                    | OutputId::Sy
                    | OutputId::PDiss
                    | OutputId::Reduction
            );
            if direct {
                deps.push(InputId::FN);
            }
        }
        deps
    }
}

const fn row(
    vr: u32,
    kind: VarKind,
    unit: &'static str,
    display_unit: Option<&'static str>,
    description: &'static str,
) -> Variable {
    Variable {
        vr,
        kind,
        description,
        unit,
        display_unit,
    }
}

const fn param(
    vr: u32,
    p: ParamId,
    unit: &'static str,
    display: Option<&'static str>,
    description: &'static str,
) -> Variable {
    row(vr, VarKind::Param(p), unit, display, description)
}

const fn input(
    vr: u32,
    i: InputId,
    unit: &'static str,
    display: Option<&'static str>,
    description: &'static str,
) -> Variable {
    row(vr, VarKind::Input(i), unit, display, description)
}

const fn output(
    vr: u32,
    o: OutputId,
    unit: &'static str,
    display: Option<&'static str>,
    description: &'static str,
) -> Variable {
    row(vr, VarKind::Output(o), unit, display, description)
}

const UM: Option<&str> = Some("um");
const MMS: Option<&str> = Some("mm/s");
const DEG: Option<&str> = Some("deg");

/// Every variable of every scene, in `ModelVariables` order.
pub static VARIABLES: [Variable; 36] = [
    param(1, ParamId::M, "kg", None, "Body mass"),
    param(2, ParamId::FN, "N", None, "Normal force pressing the body on the support"),
    param(3, ParamId::Mu, "1", None, "Coulomb friction coefficient (F_C = mu*F_N)"),
    param(4, ParamId::KT, "N/m", None, "Tangential contact stiffness"),
    param(5, ParamId::Kappa, "1", None, "Dahl exponent (longitudinal Dahl only)"),
    param(6, ParamId::RBa, "1", None, "Dupont breakaway ratio s_ba/s_ss"),
    param(7, ParamId::FS, "N", None, "LuGre static friction force"),
    param(8, ParamId::VS, "m/s", MMS, "Stribeck velocity"),
    param(9, ParamId::ZetaT, "1", None, "LuGre contact damping ratio (Eq. 6)"),
    param(10, ParamId::HV, "N.s/m", None, "LuGre viscous coefficient"),
    param(11, ParamId::VE, "m/s", MMS, "LuGre damping decay velocity (Eq. 7)"),
    param(12, ParamId::U0, "m", UM, "Amplitude of the harmonic support motion"),
    param(13, ParamId::F, "Hz", None, "Frequency of the harmonic support motion"),
    param(14, ParamId::Angle, "rad", DEG, "Direction of the support vibration to x (0: longitudinal, pi/2: transverse)"),
    param(15, ParamId::Phase, "rad", DEG, "Phase of the harmonic support motion"),
    param(16, ParamId::KD, "N/m", None, "Spring-drive stiffness"),
    param(17, ParamId::CD, "N.s/m", None, "Spring-drive damping"),
    param(18, ParamId::TAvg, "s", None, "Averaging window of F_mean without harmonic source (or at f = 0)"),
    param(19, ParamId::MaxSteps, "1", None, "Most integrator steps in one communication step (like CVODE's mxstep): a step that needs more returns fmi2Discard; use shorter communication steps or raise it"),
    input(101, InputId::FD, "N", None, "Driving force along x"),
    input(102, InputId::VD, "m/s", MMS, "Driving velocity"),
    input(103, InputId::VSx, "m/s", MMS, "Support velocity along x set by the importer"),
    input(104, InputId::VSy, "m/s", MMS, "Support velocity along y set by the importer"),
    output(201, OutputId::FFx, "N", None, "Friction force along x (resists the relative motion; the support acts on the body with -F_F)"),
    output(202, OutputId::FFy, "N", None, "Friction force along y"),
    output(203, OutputId::X, "m", UM, "Body position along x"),
    output(204, OutputId::Y, "m", UM, "Body position along y"),
    output(205, OutputId::Vx, "m/s", MMS, "Body velocity along x"),
    output(206, OutputId::Vy, "m/s", MMS, "Body velocity along y"),
    output(207, OutputId::Sx, "m", UM, "Contact deformation along x"),
    output(208, OutputId::Sy, "m", UM, "Contact deformation along y"),
    output(209, OutputId::FMean, "N", None, "Mean of F_Fx over the last completed averaging window (exact integral)"),
    output(210, OutputId::Reduction, "1", None, "Friction reduction 1 - F_mean/F_C: the fraction by which the vibration lowers the mean friction (0: none, also when F_C = 0)"),
    output(211, OutputId::PDiss, "W", None, "Power dissipated in the contact: F_F.v_r less the rate of the elastic energy"),
    output(212, OutputId::FFxStep, "N", None, "Mean of F_Fx over the last communication step (exact integral / step size): the impulse a host integrates without aliasing"),
    output(213, OutputId::FFyStep, "N", None, "Mean of F_Fy over the last communication step (exact integral / step size)"),
];

/// The row with this value reference.
pub fn by_vr(vr: u32) -> Option<&'static Variable> {
    VARIABLES.iter().find(|v| v.vr == vr)
}

/// The row with this name.
pub fn by_name(name: &str) -> Option<&'static Variable> {
    VARIABLES.iter().find(|v| v.name() == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_references_and_names_are_unique() {
        for (i, a) in VARIABLES.iter().enumerate() {
            for b in &VARIABLES[i + 1..] {
                assert_ne!(a.vr, b.vr);
                assert_ne!(a.name(), b.name());
            }
        }
        assert_eq!(by_vr(201).unwrap().name(), "F_Fx");
        assert_eq!(by_name("k_t").unwrap().vr, 4);
    }

    #[test]
    fn longitudinal_dahl_velocity_scene_leaves_out_what_it_does_not_need() {
        let c = Config {
            law: Law::Dahl,
            motion: crate::model::Motion::Longitudinal,
            drive: Drive::Velocity,
            lateral: crate::model::Lateral::Guided,
            harmonic: true,
            input_support: false,
            normal_input: false,
        };
        let outs: Vec<OutputId> = OutputId::ALL.to_vec();
        let names: Vec<&str> = VARIABLES
            .iter()
            .filter(|v| v.present(&c, &outs))
            .map(|v| v.name())
            .collect();
        for absent in [
            "y", "v_y", "s_y", "F_Fy", "v_sy", "v_sx", "F_S", "r_ba", "m", "angle", "F_d", "k_d",
        ] {
            assert!(!names.contains(&absent), "{absent} in {names:?}");
        }
        for present in [
            "F_Fx",
            "x",
            "kappa",
            "u0",
            "f",
            "v_d",
            "F_mean",
            "reduction",
            "P_diss",
        ] {
            assert!(names.contains(&present), "{present} missing from {names:?}");
        }
    }
}
