//! The FMI 3.0 `modelDescription.xml` of a scene (Model Exchange and Co-Simulation), from the
//! same rows as the FMI 2.0 one ([`super::xml`]): the same variables, value references, units,
//! ranges, start values and dependencies, written in FMI 3.0's vocabulary.
//!
//! Differences from FMI 2.0, each required by the standard:
//! - variables are `Float64` elements with their type attributes inline;
//! - an independent variable `time` (value reference 0) is declared;
//! - `ModelStructure` names variables by value reference, not by index, and lists the event
//!   indicators (local variables in both editions);
//! - FMI 3.0 Co-Simulation has no input derivatives: inputs are held over a step;
//! - the `instantiationToken` is the FMI 2.0 GUID of the same scene: one scene, one token, and
//!   the instance checks the same string whichever version instantiates it.
//!
//! Planar quantities stay scalars (`F_Fx`, `F_Fy`, ...), not arrays: every importer that takes
//! FMI 3.0 also takes scalars, the value references and names stay those of FMI 2.0, and a host
//! model connects the same signals either way.

use super::scene::Scene;
use super::variables::{Causality, Initial, VarKind, Variable};
use super::xml::{declared, guid, head};
use super::xml_parts::{close, document, open, write_head, write_structure, write_time};
use super::xml_parts::{write_variable, Edition, Structure, Unknown, W};
use super::xml_string;

/// The FMI version written into the FMI 3.0 model description.
pub const FMI3_VERSION: &str = "3.0";

/// Value reference of the independent variable `time`.
pub use super::xml_parts::TIME_VR;

/// The FMI 3.0 model description of a scene.
pub fn model_description(scene: &Scene) -> String {
    if scene.string.is_some() {
        return xml_string::model_description(scene, Edition::Fmi3, &guid(scene));
    }
    document(|w| write_into(w, scene, &guid(scene)))
}

fn write_into(w: &mut W, scene: &Scene, token: &str) -> std::io::Result<()> {
    let vars: Vec<&'static Variable> = scene.variables().collect();
    write_head(w, &head(scene, Edition::Fmi3, token))?;
    open(w, "ModelVariables", &[])?;
    write_time(w)?;
    for (i, v) in vars.iter().enumerate() {
        // A derivative names its state by value reference.
        let derivative = v.derivative_of().map(|x| x.vr().to_string());
        write_variable(w, Edition::Fmi3, &declared(scene, v, i + 1, derivative))?;
    }
    close(w, "ModelVariables")?;
    write_structure(w, Edition::Fmi3, &structure(scene, &vars))?;
    close(w, "fmiModelDescription")
}

/// `ModelStructure`: the outputs, the derivatives, the initial unknowns and the event
/// indicators with their dependencies, by value reference.
fn structure(scene: &Scene, vars: &[&'static Variable]) -> Structure {
    let c = &scene.config;
    let vrs = |vrs: Vec<u32>| Some(vrs.into_iter().map(|x| x as usize).collect());
    let unknown = |v: &&&Variable| Unknown {
        id: v.vr as usize,
        dependencies: vrs(v.known_dependencies(c, &scene.outputs)),
    };
    let outputs: Vec<&&Variable> = vars
        .iter()
        .filter(|v| v.causality(c) == Causality::Output)
        .collect();
    let mut initial_unknowns: Vec<Unknown> = outputs
        .iter()
        .filter(|v| v.initial(c) == Some(Initial::Calculated))
        .map(|v| Unknown {
            id: v.vr as usize,
            dependencies: vrs(v.initial_dependencies(c).iter().map(|d| d.vr()).collect()),
        })
        .collect();
    // The states start at 0; their derivatives depend at the start on parameters and inputs.
    initial_unknowns.extend(vars.iter().filter_map(|v| match v.kind {
        VarKind::State(_) => Some(Unknown {
            id: v.vr as usize,
            dependencies: Some(vec![]),
        }),
        VarKind::Derivative(_) => Some(Unknown {
            id: v.vr as usize,
            dependencies: None,
        }),
        _ => None,
    }));
    Structure {
        outputs: outputs.iter().map(unknown).collect(),
        // The order of the derivatives is the order of the state vector.
        derivatives: vars
            .iter()
            .filter(|v| v.derivative_of().is_some())
            .collect::<Vec<_>>()
            .iter()
            .map(unknown)
            .collect(),
        initial_unknowns,
        // The event indicators of Model Exchange, in the order of the indicator vector.
        event_indicators: vars
            .iter()
            .filter(|v| matches!(v.kind, VarKind::Indicator(_)))
            .collect::<Vec<_>>()
            .iter()
            .map(unknown)
            .collect(),
    }
}
