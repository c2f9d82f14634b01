//! The variables as a model description lists them: one row per value reference, made from the
//! declarations of `table/table.rs`, with the causality, variability, `initial`, start
//! value and bounds each has in a scene. The generated `modelDescription.xml` and get/set by
//! value reference both read these rows.
//!
//! A scene carries the subset of rows its configuration has (see [`Variable::present`]), each
//! with its final kind ([`Variable::in_scene`]): `F_N` (vr 2) is the parameter's row in most
//! scenes and the input's row with `normal = "input"`, so that nothing after the scene is read
//! translates between the two. `F_d` (vr 101) is the input of a force drive and the
//! spring-damper force output of a spring drive.

use std::sync::LazyLock;

pub use crate::table::Variability;
use crate::table::{
    Config, Dependency, IndicatorId, InputId, Inputs, Known, OutputId, ParamId, Params, StateId,
};

/// What a variable is bound to in the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarKind {
    Param(ParamId),
    Input(InputId),
    Output(OutputId),
    /// A continuous state of Model Exchange (a local variable).
    State(StateId),
    /// The derivative of a continuous state (a local variable).
    Derivative(StateId),
    /// An event indicator of Model Exchange (a local variable).
    Indicator(IndicatorId),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    Input,
    Output,
    Local,
}

impl Causality {
    pub fn as_str(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
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
    /// The row of a declared variable.
    fn of(kind: VarKind) -> Variable {
        let (vr, unit, display_unit, description) = match kind {
            VarKind::Param(p) => (p.vr(), p.unit(), p.display_unit(), p.description()),
            VarKind::Input(i) => (i.vr(), i.unit(), i.display_unit(), i.description()),
            VarKind::Output(o) => (o.vr(), o.unit(), o.display_unit(), o.description()),
            VarKind::State(x) => (x.vr(), x.unit(), x.display_unit(), x.description()),
            VarKind::Derivative(x) => (
                x.derivative_vr(),
                x.derivative_unit(),
                None,
                x.derivative_description(),
            ),
            VarKind::Indicator(i) => (i.vr(), i.unit(), None, i.description()),
        };
        Variable {
            vr,
            kind,
            description,
            unit,
            display_unit,
        }
    }

    pub fn name(&self) -> &'static str {
        match self.kind {
            VarKind::Param(p) => p.name(),
            VarKind::Input(i) => i.name(),
            VarKind::Output(o) => o.name(),
            VarKind::State(x) => x.name(),
            VarKind::Derivative(x) => x.derivative_name(),
            VarKind::Indicator(i) => i.name(),
        }
    }

    /// The row this variable has in a scene with this configuration: the input `F_N` in scenes
    /// with `normal = "input"` (it shares the parameter's value reference, name, unit, range and
    /// description), the row itself otherwise. A scene's rows ([`Scene::variables`]) are these.
    ///
    /// [`Scene::variables`]: crate::description::scene::Scene::variables
    pub fn in_scene(&'static self, c: &Config) -> &'static Variable {
        match self.kind {
            VarKind::Param(ParamId::FN) if c.normal_input => &INPUT_F_N,
            _ => self,
        }
    }

    /// `F_d` is the input of a force drive and the spring-damper force output of a spring
    /// drive.
    pub fn causality(&self, c: &Config) -> Causality {
        match self.kind {
            VarKind::Param(_) => Causality::Parameter,
            VarKind::Input(InputId::FD) if c.drive.has_spring() => Causality::Output,
            VarKind::Input(_) => Causality::Input,
            VarKind::Output(_) => Causality::Output,
            VarKind::State(_) | VarKind::Derivative(_) | VarKind::Indicator(_) => Causality::Local,
        }
    }

    /// The variability, the same in every scene (a scene's rows have their final kind; the
    /// configuration is taken for symmetry with [`Variable::causality`]).
    pub fn variability(&self, _c: &Config) -> Variability {
        match self.kind {
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
            VarKind::Param(p) => p.present(c),
            VarKind::Input(InputId::FD) if c.drive.has_spring() => {
                outputs.contains(&OutputId::FDrive)
            }
            VarKind::Input(i) => i.present(c),
            VarKind::Output(o) => o.present(c) && outputs.contains(&o),
            VarKind::State(x) | VarKind::Derivative(x) => x.present(c, outputs),
            VarKind::Indicator(i) => i.present(c),
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
            VarKind::Param(p) => p.rule_in(c).min(),
            VarKind::Input(i) => i.rule().min(),
            _ => None,
        }
    }

    /// Upper bound (`max`) of the accepted range of parameters and inputs.
    pub fn max(&self, c: &Config) -> Option<f64> {
        match self.kind {
            VarKind::Param(p) => p.rule_in(c).max(),
            VarKind::Input(i) => i.rule().max(),
            _ => None,
        }
    }

    /// True when an importer may set the variable (parameters and inputs).
    pub fn settable(&self, c: &Config) -> bool {
        matches!(self.causality(c), Causality::Parameter | Causality::Input)
    }

    /// The state whose derivative this row is, if it is one.
    pub fn derivative_of(&self) -> Option<StateId> {
        match self.kind {
            VarKind::Derivative(x) => Some(x),
            _ => None,
        }
    }

    /// The output this row is in this configuration, if it is one.
    pub fn output(&self, c: &Config) -> Option<OutputId> {
        match self.kind {
            VarKind::Output(o) => Some(o),
            VarKind::Input(InputId::FD) if c.drive.has_spring() => Some(OutputId::FDrive),
            _ => None,
        }
    }

    /// Inputs whose current value the output depends on directly (the `dependencies` of
    /// `ModelStructure/Outputs`), in this configuration.
    pub fn input_dependencies(&self, c: &Config) -> Vec<InputId> {
        self.output(c).map_or(vec![], |o| o.depends().direct(c))
    }

    /// Value references of the knowns (inputs, continuous states) an output, a state
    /// derivative or an event indicator depends on during the simulation: the `dependencies`
    /// of `ModelStructure/Outputs`, `Derivatives` (FMI 3.0: `ContinuousStateDerivative`) and
    /// FMI 3.0's `EventIndicator`.
    pub fn known_dependencies(&self, c: &Config, outputs: &[OutputId]) -> Vec<u32> {
        let knowns = match self.kind {
            VarKind::Derivative(x) => Some(x.derivative_dependencies(c, outputs)),
            VarKind::Indicator(i) => Some(i.dependencies(c, outputs)),
            _ => None,
        };
        if let Some(knowns) = knowns {
            return knowns
                .into_iter()
                .map(|k| match k {
                    Known::State(s) => s.vr(),
                    Known::Input(i) => i.vr(),
                })
                .collect();
        }
        let Some(o) = self.output(c) else {
            return vec![];
        };
        let mut vrs: Vec<u32> = o.depends().direct(c).iter().map(|i| i.vr()).collect();
        vrs.extend(o.state_dependencies(c, outputs).iter().map(|s| s.vr()));
        vrs
    }

    /// Parameters and inputs the output depends on at initialization (the `dependencies` of
    /// `ModelStructure/InitialUnknowns`), in this configuration.
    pub fn initial_dependencies(&self, c: &Config) -> Vec<Dependency> {
        self.output(c).map_or(vec![], |o| o.depends().initial(c))
    }
}

/// Every variable of every scene, in `ModelVariables` order (by value reference): every
/// declared parameter, input and output, each value reference once (the input `F_N` and the
/// output `F_d` share the rows of the parameter `F_N` and the input `F_d`).
pub static VARIABLES: LazyLock<Vec<Variable>> = LazyLock::new(|| {
    let kinds = ParamId::ALL
        .into_iter()
        .map(VarKind::Param)
        .chain(InputId::ALL.into_iter().map(VarKind::Input))
        .chain(OutputId::ALL.into_iter().map(VarKind::Output))
        .chain(StateId::ALL.into_iter().map(VarKind::State))
        .chain(StateId::ALL.into_iter().map(VarKind::Derivative))
        .chain(IndicatorId::ALL.into_iter().map(VarKind::Indicator));
    let mut rows: Vec<Variable> = vec![];
    for kind in kinds {
        let row = Variable::of(kind);
        if !rows.iter().any(|r| r.vr == row.vr) {
            rows.push(row);
        }
    }
    rows.sort_by_key(|r| r.vr);
    rows
});

/// The row of the input `F_N`, which scenes with `normal = "input"` carry under the parameter's
/// value reference (see [`Variable::in_scene`]).
static INPUT_F_N: LazyLock<Variable> = LazyLock::new(|| Variable::of(VarKind::Input(InputId::FN)));

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
    use crate::table::Law;

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
            motion: crate::table::Motion::Longitudinal,
            drive: crate::table::Drive::Velocity,
            lateral: crate::table::Lateral::Guided,
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
