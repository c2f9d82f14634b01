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

use std::io::Write;

use quick_xml::events::{BytesDecl, Event};
use quick_xml::Writer;

use super::scene::Scene;
use super::variables::{Causality, Initial, VarKind, Variable};
use super::xml::guid;
use super::xml_parts::{close, empty, generation_tool, number, open, W};
use super::xml_parts::{write_default_experiment, write_log_categories, write_units};
use super::xml_string::{self, Edition};

/// The FMI version written into the FMI 3.0 model description.
pub const FMI3_VERSION: &str = "3.0";

/// Value reference of the independent variable `time`.
pub const TIME_VR: u32 = 0;

/// The FMI 3.0 model description of a scene.
pub fn model_description(scene: &Scene) -> String {
    if scene.string.is_some() {
        return xml_string::model_description(scene, Edition::Fmi3, &guid(scene));
    }
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    write_into(&mut w, scene, &guid(scene)).expect("writing XML into memory cannot fail");
    let mut bytes = w.into_inner();
    bytes.write_all(b"\n").expect("in memory");
    String::from_utf8(bytes).expect("quick-xml writes UTF-8 from UTF-8 input")
}

/// The name of the `Float64Type` of a unit and display unit: the unit, with the display unit in
/// parentheses.
fn type_name(unit: &str, display: Option<&str>) -> String {
    match display {
        Some(d) => format!("{unit} ({d})"),
        None => unit.to_string(),
    }
}

fn joined(vrs: &[u32]) -> String {
    let mut v = vrs.to_vec();
    v.sort_unstable();
    v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

fn write_into(w: &mut W, scene: &Scene, token: &str) -> std::io::Result<()> {
    let vars: Vec<&'static Variable> = scene.variables().collect();
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let tool = generation_tool();
    open(
        w,
        "fmiModelDescription",
        &[
            ("fmiVersion", FMI3_VERSION),
            ("modelName", &scene.model_identifier),
            ("instantiationToken", token),
            ("description", &scene.description),
            ("generationTool", &tool),
            ("variableNamingConvention", "flat"),
        ],
    )?;
    empty(
        w,
        "ModelExchange",
        &[
            ("modelIdentifier", &scene.model_identifier),
            ("needsExecutionTool", "false"),
            ("canBeInstantiatedOnlyOncePerProcess", "false"),
            ("canGetAndSetFMUState", "true"),
            ("canSerializeFMUState", "true"),
            ("providesDirectionalDerivatives", "true"),
            ("providesAdjointDerivatives", "false"),
            ("providesPerElementDependencies", "false"),
            // Nothing happens at the end of an integrator step: no step events.
            ("needsCompletedIntegratorStep", "false"),
            ("providesEvaluateDiscreteStates", "false"),
        ],
    )?;
    empty(
        w,
        "CoSimulation",
        &[
            ("modelIdentifier", &scene.model_identifier),
            ("needsExecutionTool", "false"),
            ("canBeInstantiatedOnlyOncePerProcess", "false"),
            ("canGetAndSetFMUState", "true"),
            ("canSerializeFMUState", "true"),
            ("providesDirectionalDerivatives", "false"),
            ("providesAdjointDerivatives", "false"),
            ("providesPerElementDependencies", "false"),
            ("canHandleVariableCommunicationStepSize", "true"),
            ("maxOutputDerivativeOrder", "1"),
            ("providesIntermediateUpdate", "false"),
            ("mightReturnEarlyFromDoStep", "false"),
            ("canReturnEarlyAfterIntermediateUpdate", "false"),
            ("hasEventMode", "false"),
            ("providesEvaluateDiscreteStates", "false"),
        ],
    )?;
    let units: Vec<&str> = vars.iter().map(|v| v.unit).collect();
    write_units(w, &units)?;
    // Units as types: a Float64Type per (unit, display unit) the variables use, which they
    // name as their declaredType (FMI 3.0 allows the unit on the variable too, but importers
    // built on rust-fmi's schema, such as fmi-sim, read it only from a type).
    let mut types: Vec<(&str, Option<&str>)> = vec![("s", None)];
    for v in &vars {
        let t = (v.unit, v.display_unit);
        if !types.contains(&t) {
            types.push(t);
        }
    }
    open(w, "TypeDefinitions", &[])?;
    for (unit, display) in &types {
        let name = type_name(unit, *display);
        let mut attrs = vec![("name", name.as_str()), ("unit", *unit)];
        if let Some(d) = display {
            attrs.push(("displayUnit", d));
        }
        empty(w, "Float64Type", &attrs)?;
    }
    close(w, "TypeDefinitions")?;
    write_log_categories(w)?;
    write_default_experiment(w)?;

    write_variables(w, scene, &vars)?;
    write_structure(w, scene, &vars)?;
    close(w, "fmiModelDescription")
}

/// `ModelVariables`: `time`, then the scene's variables with their types, ranges and starts.
fn write_variables(w: &mut W, scene: &Scene, vars: &[&'static Variable]) -> std::io::Result<()> {
    let c = &scene.config;
    open(w, "ModelVariables", &[])?;
    empty(
        w,
        "Float64",
        &[
            ("name", "time"),
            ("valueReference", &TIME_VR.to_string()),
            ("description", "Simulation time"),
            ("causality", "independent"),
            ("variability", "continuous"),
            ("declaredType", "s"),
        ],
    )?;
    for v in vars {
        let vr = v.vr.to_string();
        let mut attrs: Vec<(&str, String)> = vec![
            ("name", v.name().into()),
            ("valueReference", vr),
            ("description", v.description.into()),
            ("causality", v.causality(c).as_str().into()),
            ("variability", v.variability(c).as_str().into()),
        ];
        let initial = v.initial(c);
        if let Some(init) = initial {
            attrs.push(("initial", init.as_str().into()));
        }
        attrs.push(("declaredType", type_name(v.unit, v.display_unit)));
        // A derivative names its state by value reference.
        if let Some(x) = v.derivative_of() {
            attrs.push(("derivative", x.vr().to_string()));
        }
        if v.causality(c) != Causality::Output {
            for (n, x) in [("min", v.min(c)), ("max", v.max(c))] {
                if let Some(x) = x {
                    attrs.push((n, number(x)));
                }
            }
        }
        let start = match initial {
            Some(Initial::Calculated) => None,
            _ => scene.start_of(v),
        };
        if let Some(x) = start {
            attrs.push(("start", number(x)));
        }
        let refs: Vec<(&str, &str)> = attrs.iter().map(|(n, x)| (*n, x.as_str())).collect();
        empty(w, "Float64", &refs)?;
    }
    close(w, "ModelVariables")?;
    Ok(())
}

/// `ModelStructure`: the outputs, the derivatives, the initial unknowns and the event
/// indicators with their dependencies.
fn write_structure(w: &mut W, scene: &Scene, vars: &[&'static Variable]) -> std::io::Result<()> {
    let c = &scene.config;
    open(w, "ModelStructure", &[])?;
    let outputs: Vec<&&Variable> = vars
        .iter()
        .filter(|v| v.causality(c) == Causality::Output)
        .collect();
    for v in &outputs {
        let deps = v.known_dependencies(c, &scene.outputs);
        let vr = v.vr.to_string();
        empty(
            w,
            "Output",
            &[("valueReference", &vr), ("dependencies", &joined(&deps))],
        )?;
    }
    // The order of the derivatives is the order of the state vector.
    for v in vars.iter().filter(|v| v.derivative_of().is_some()) {
        let deps = v.known_dependencies(c, &scene.outputs);
        let vr = v.vr.to_string();
        empty(
            w,
            "ContinuousStateDerivative",
            &[("valueReference", &vr), ("dependencies", &joined(&deps))],
        )?;
    }
    for v in &outputs {
        if v.initial(c) != Some(Initial::Calculated) {
            continue;
        }
        let deps: Vec<u32> = v.initial_dependencies(c).iter().map(|d| d.vr()).collect();
        let vr = v.vr.to_string();
        empty(
            w,
            "InitialUnknown",
            &[("valueReference", &vr), ("dependencies", &joined(&deps))],
        )?;
    }
    // The states start at 0; their derivatives depend at the start on parameters and inputs.
    for v in vars {
        let vr = v.vr.to_string();
        match v.kind {
            VarKind::State(_) => empty(
                w,
                "InitialUnknown",
                &[("valueReference", &vr), ("dependencies", "")],
            )?,
            VarKind::Derivative(_) => empty(w, "InitialUnknown", &[("valueReference", &vr)])?,
            _ => {}
        }
    }
    // The event indicators of Model Exchange, in the order of the indicator vector.
    for v in vars
        .iter()
        .filter(|v| matches!(v.kind, VarKind::Indicator(_)))
    {
        let deps = v.known_dependencies(c, &scene.outputs);
        let vr = v.vr.to_string();
        empty(
            w,
            "EventIndicator",
            &[("valueReference", &vr), ("dependencies", &joined(&deps))],
        )?;
    }
    close(w, "ModelStructure")?;
    Ok(())
}
