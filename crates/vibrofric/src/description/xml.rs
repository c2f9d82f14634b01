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

use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, Event};
use quick_xml::Writer;
use sha2::{Digest, Sha256};

use crate::description::log::Category;
use crate::description::scene::Scene;
use crate::description::variables::{Causality, Initial, VarKind, Variable};

/// `DefaultExperiment` of every FMU: (startTime, stopTime, tolerance, stepSize).
pub const DEFAULT_EXPERIMENT: (f64, f64, f64, f64) = (0.0, 0.1, 1e-6, 1e-3);

/// The FMI version written into `modelDescription.xml`.
pub const FMI_VERSION: &str = "2.0";

/// `generationTool` attribute.
pub fn generation_tool() -> String {
    format!("vibrofric {}", env!("CARGO_PKG_VERSION"))
}

/// SI exponents of a unit: (kg, m, s, rad).
fn base_unit(unit: &str) -> Option<[i32; 4]> {
    Some(match unit {
        "kg" => [1, 0, 0, 0],
        "m" => [0, 1, 0, 0],
        "s" => [0, 0, 1, 0],
        "rad" => [0, 0, 0, 1],
        "m/s" => [0, 1, -1, 0],
        "N" => [1, 1, -2, 0],
        "N/m" => [1, 0, -2, 0],
        "N.s/m" => [1, 0, -1, 0],
        "N.s" => [1, 1, -1, 0],
        "m/s2" => [0, 1, -2, 0],
        "m2/s" => [0, 2, -1, 0],
        "Hz" => [0, 0, -1, 0],
        "W" => [1, 2, -3, 0],
        "1" => [0, 0, 0, 0],
        _ => return None,
    })
}

/// Display units: (unit, display unit, factor), `display = factor·value`.
pub const DISPLAY_UNITS: [(&str, &str, f64); 3] = [
    ("m", "um", 1e6),
    ("m/s", "mm/s", 1e3),
    ("rad", "deg", 57.29577951308232),
];

/// Order of `UnitDefinitions`.
const UNIT_ORDER: [&str; 14] = [
    "1", "kg", "m", "m/s", "m/s2", "m2/s", "N", "N.s", "N/m", "N.s/m", "W", "Hz", "s", "rad",
];

/// A number as the model description writes it: shortest round-trip form, with an exponent for
/// very small or large magnitudes.
pub fn number(x: f64) -> String {
    crate::table::number(x)
}

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

pub(super) fn joined<T: ToString>(idx: &[T]) -> String {
    idx.iter()
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(" ")
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

pub(super) type W = Writer<Vec<u8>>;

pub(super) fn empty(w: &mut W, name: &str, attrs: &[(&str, &str)]) -> std::io::Result<()> {
    let mut e = BytesStart::new(name);
    for a in attrs {
        e.push_attribute(*a);
    }
    w.write_event(Event::Empty(e))
}

pub(super) fn open(w: &mut W, name: &str, attrs: &[(&str, &str)]) -> std::io::Result<()> {
    let mut e = BytesStart::new(name);
    for a in attrs {
        e.push_attribute(*a);
    }
    w.write_event(Event::Start(e))
}

pub(super) fn close(w: &mut W, name: &str) -> std::io::Result<()> {
    w.write_event(Event::End(BytesEnd::new(name)))
}

fn write_document(scene: &Scene, guid: &str) -> String {
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

    write_units(w, &vars)?;
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

/// `UnitDefinitions`: every unit a variable of the scene uses, with its SI exponents and display
/// units (the same element in FMI 2.0 and 3.0).
pub(super) fn write_units(w: &mut W, vars: &[&Variable]) -> std::io::Result<()> {
    open(w, "UnitDefinitions", &[])?;
    for unit in UNIT_ORDER {
        if !vars.iter().any(|v| v.unit == unit) {
            continue;
        }
        let exps = base_unit(unit).expect("every unit of the table has SI exponents");
        open(w, "Unit", &[("name", unit)])?;
        let strs: Vec<(&str, String)> = ["kg", "m", "s", "rad"]
            .iter()
            .zip(exps)
            .filter(|(_, e)| *e != 0)
            .map(|(n, e)| (*n, e.to_string()))
            .collect();
        let attrs: Vec<(&str, &str)> = strs.iter().map(|(n, e)| (*n, e.as_str())).collect();
        empty(w, "BaseUnit", &attrs)?;
        for (u, d, factor) in DISPLAY_UNITS {
            if u == unit {
                empty(
                    w,
                    "DisplayUnit",
                    &[("name", d), ("factor", &number(factor))],
                )?;
            }
        }
        close(w, "Unit")?;
    }
    close(w, "UnitDefinitions")?;
    Ok(())
}

/// `LogCategories` (the same element in FMI 2.0 and 3.0).
pub(super) fn write_log_categories(w: &mut W) -> std::io::Result<()> {
    open(w, "LogCategories", &[])?;
    for c in Category::ALL {
        let (name, description) = (c.name(), c.description());
        empty(
            w,
            "Category",
            &[("name", name), ("description", description)],
        )?;
    }
    close(w, "LogCategories")?;
    Ok(())
}

/// `DefaultExperiment` (the same element in FMI 2.0 and 3.0).
pub(super) fn write_default_experiment(w: &mut W) -> std::io::Result<()> {
    let (t0, t1, tol, step) = DEFAULT_EXPERIMENT;
    empty(
        w,
        "DefaultExperiment",
        &[
            ("startTime", &number(t0)),
            ("stopTime", &number(t1)),
            ("tolerance", &number(tol)),
            ("stepSize", &number(step)),
        ],
    )?;
    Ok(())
}
