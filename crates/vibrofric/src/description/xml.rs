//! The FMI 2.0 `modelDescription.xml` of a scene (Model Exchange and Co-Simulation in one
//! document), written with quick-xml from the variable table
//! ([`crate::description::variables::VARIABLES`]) and nothing else.
//!
//! Depends only on the table and the scene (no solver, no FMI).
//!
//! Choices documented here because the standard leaves them open:
//! - `DefaultExperiment`: 0 to 0.1 s (200 periods of the default 2 kHz excitation), relative
//!   tolerance 1e-6, communication step 1e-3 s (two periods; the FMU resolves the periods inside a
//!   step itself).
//! - The GUID is the SHA-256 of this document written with an empty GUID, formatted as a UUID
//!   (version 8, "custom") in braces: it changes with anything the document says (scene,
//!   variables, start values, generator version) and with nothing else.

use std::io::Write;

use quick_xml::events::{BytesDecl, Event};
use quick_xml::Writer;
use sha2::{Digest, Sha256};

use crate::description::scene::Scene;
use crate::description::variables::{Causality, Initial, VarKind, Variable};
use crate::description::xml_parts::{close, empty, joined, open};
pub use crate::description::xml_parts::{
    generation_tool, number, DEFAULT_EXPERIMENT, DISPLAY_UNITS, W,
};
use crate::description::xml_parts::{write_default_experiment, write_log_categories, write_units};
use crate::description::xml_string::{self, Edition};

/// The FMI version written into `modelDescription.xml`.
pub const FMI_VERSION: &str = "2.0";

/// 1-based `ModelVariables` indices of the variables with these value references, sorted.
fn indices(vars: &[&Variable], vrs: &[u32]) -> Vec<usize> {
    let mut idx: Vec<usize> = vars
        .iter()
        .enumerate()
        .filter(|(_, v)| vrs.contains(&v.vr))
        .map(|(i, _)| i + 1)
        .collect();
    idx.sort_unstable();
    idx
}

/// The model description of a scene, with its content-derived GUID.
pub fn model_description(scene: &Scene) -> String {
    let g = guid(scene);
    write_document(scene, &g)
}

/// The GUID of a scene's model description: SHA-256 of the document written with an empty GUID,
/// as a version-8 UUID in braces.
pub fn guid(scene: &Scene) -> String {
    let doc = write_document(scene, "");
    let h = Sha256::digest(doc.as_bytes());
    let mut b = [0u8; 16];
    b.copy_from_slice(&h[..16]);
    b[6] = (b[6] & 0x0f) | 0x80; // version 8
    b[8] = (b[8] & 0x3f) | 0x80; // RFC 4122 variant
    let hex: String = b.iter().map(|x| format!("{x:02x}")).collect();
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}

fn write_document(scene: &Scene, guid: &str) -> String {
    if scene.string.is_some() {
        return xml_string::model_description(scene, Edition::Fmi2, guid);
    }
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    write_into(&mut w, scene, guid).expect("writing XML into memory cannot fail");
    let mut bytes = w.into_inner();
    bytes.write_all(b"\n").expect("in memory");
    String::from_utf8(bytes).expect("quick-xml writes UTF-8 from UTF-8 input")
}

fn write_into(w: &mut W, scene: &Scene, guid: &str) -> std::io::Result<()> {
    let c = &scene.config;
    let vars: Vec<&'static Variable> = scene.variables().collect();
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let tool = generation_tool();
    open(
        w,
        "fmiModelDescription",
        &[
            ("fmiVersion", FMI_VERSION),
            ("modelName", &scene.model_identifier),
            ("guid", guid),
            ("description", &scene.description),
            ("generationTool", &tool),
            ("variableNamingConvention", "flat"),
            ("numberOfEventIndicators", &c.event_indicators().to_string()),
        ],
    )?;

    empty(
        w,
        "ModelExchange",
        &[
            ("modelIdentifier", &scene.model_identifier),
            ("needsExecutionTool", "false"),
            // Nothing happens at the end of an integrator step: no step events.
            ("completedIntegratorStepNotNeeded", "true"),
            ("canBeInstantiatedOnlyOncePerProcess", "false"),
            ("canNotUseMemoryManagementFunctions", "true"),
            ("canGetAndSetFMUstate", "true"),
            ("canSerializeFMUstate", "true"),
            ("providesDirectionalDerivative", "true"),
        ],
    )?;
    let interpolate = vars.iter().any(|v| v.causality(c) == Causality::Input);
    empty(
        w,
        "CoSimulation",
        &[
            ("modelIdentifier", &scene.model_identifier),
            ("needsExecutionTool", "false"),
            ("canHandleVariableCommunicationStepSize", "true"),
            (
                "canInterpolateInputs",
                if interpolate { "true" } else { "false" },
            ),
            ("maxOutputDerivativeOrder", "1"),
            ("canRunAsynchronuously", "false"),
            ("canBeInstantiatedOnlyOncePerProcess", "false"),
            ("canNotUseMemoryManagementFunctions", "true"),
            ("canGetAndSetFMUstate", "true"),
            ("canSerializeFMUstate", "true"),
            ("providesDirectionalDerivative", "false"),
        ],
    )?;

    let units: Vec<&str> = vars.iter().map(|v| v.unit).collect();
    write_units(w, &units)?;
    write_log_categories(w)?;
    write_default_experiment(w)?;

    write_variables(w, scene, &vars)?;
    write_structure(w, scene, &vars)?;

    close(w, "fmiModelDescription")
}

/// `ModelVariables`: each `ScalarVariable` with its index as a comment, its `Real` with unit,
/// range and start.
fn write_variables(w: &mut W, scene: &Scene, vars: &[&'static Variable]) -> std::io::Result<()> {
    let c = &scene.config;
    open(w, "ModelVariables", &[])?;
    for (i, v) in vars.iter().enumerate() {
        w.write_event(Event::Comment(quick_xml::events::BytesText::new(&format!(
            " index {} ",
            i + 1
        ))))?;
        let vr = v.vr.to_string();
        let mut attrs: Vec<(&str, &str)> = vec![
            ("name", v.name()),
            ("valueReference", &vr),
            ("description", v.description),
            ("causality", v.causality(c).as_str()),
            ("variability", v.variability(c).as_str()),
        ];
        let initial = v.initial(c);
        if let Some(init) = initial {
            attrs.push(("initial", init.as_str()));
        }
        open(w, "ScalarVariable", &attrs)?;
        let start = match initial {
            Some(Initial::Calculated) => None,
            _ => scene.start_of(v),
        };
        // The accepted range of what the importer sets (not of F_d as a spring drive's output).
        let settable = v.causality(c) != Causality::Output;
        let (min, max) = if settable {
            (v.min(c), v.max(c))
        } else {
            (None, None)
        };
        let nums: Vec<(&str, String)> = [("start", start), ("min", min), ("max", max)]
            .into_iter()
            .filter_map(|(n, x)| x.map(|x| (n, number(x))))
            .collect();
        let mut real: Vec<(&str, &str)> = vec![("unit", v.unit)];
        if let Some(d) = v.display_unit {
            real.push(("displayUnit", d));
        }
        real.extend(nums.iter().map(|(n, x)| (*n, x.as_str())));
        // A derivative names its state by the state's 1-based index.
        let state_index = v
            .derivative_of()
            .and_then(|x| indices(vars, &[x.vr()]).first().map(|i| i.to_string()));
        if let Some(i) = &state_index {
            real.insert(0, ("derivative", i.as_str()));
        }
        empty(w, "Real", &real)?;
        close(w, "ScalarVariable")?;
    }
    close(w, "ModelVariables")?;
    Ok(())
}

/// `ModelStructure`: the outputs, the derivatives and the initial unknowns with their
/// dependencies, by 1-based index.
fn write_structure(w: &mut W, scene: &Scene, vars: &[&'static Variable]) -> std::io::Result<()> {
    let c = &scene.config;
    open(w, "ModelStructure", &[])?;
    let outputs: Vec<(usize, &&Variable)> = vars
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality(c) == Causality::Output)
        .map(|(i, v)| (i + 1, v))
        .collect();
    open(w, "Outputs", &[])?;
    for (index, v) in &outputs {
        let vrs = v.known_dependencies(c, &scene.outputs);
        let deps = joined(&indices(vars, &vrs));
        let index = index.to_string();
        empty(w, "Unknown", &[("index", &index), ("dependencies", &deps)])?;
    }
    close(w, "Outputs")?;
    // Model Exchange: the order of the derivatives is the order of the state vector.
    let derivatives: Vec<(usize, &&Variable)> = vars
        .iter()
        .enumerate()
        .filter(|(_, v)| v.derivative_of().is_some())
        .map(|(i, v)| (i + 1, v))
        .collect();
    open(w, "Derivatives", &[])?;
    for (index, v) in &derivatives {
        let vrs = v.known_dependencies(c, &scene.outputs);
        let deps = joined(&indices(vars, &vrs));
        let index = index.to_string();
        empty(w, "Unknown", &[("index", &index), ("dependencies", &deps)])?;
    }
    close(w, "Derivatives")?;
    open(w, "InitialUnknowns", &[])?;
    for (index, v) in &outputs {
        if v.initial(c) != Some(Initial::Calculated) {
            continue;
        }
        let vrs: Vec<u32> = v.initial_dependencies(c).iter().map(|d| d.vr()).collect();
        let deps = joined(&indices(vars, &vrs));
        let index = index.to_string();
        empty(w, "Unknown", &[("index", &index), ("dependencies", &deps)])?;
    }
    // The states start at 0 (the body at rest at the origin, undeformed); their derivatives
    // depend at the start on parameters and inputs (no `dependencies`: all of them).
    for (i, v) in vars.iter().enumerate() {
        let index = (i + 1).to_string();
        match v.kind {
            VarKind::State(_) => empty(w, "Unknown", &[("index", &index), ("dependencies", "")])?,
            VarKind::Derivative(_) => empty(w, "Unknown", &[("index", &index)])?,
            _ => {}
        }
    }
    close(w, "InitialUnknowns")?;
    close(w, "ModelStructure")?;
    Ok(())
}
