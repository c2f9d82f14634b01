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

use sha2::{Digest, Sha256};

use crate::description::scene::Scene;
use crate::description::variables::{Causality, Initial, VarKind, Variable};
use crate::description::xml_parts::write_variable;
use crate::description::xml_parts::{close, document, open, write_head, write_structure};
pub use crate::description::xml_parts::{
    generation_tool, number, DEFAULT_EXPERIMENT, DISPLAY_UNITS, W,
};
use crate::description::xml_parts::{Declared, Edition, Head, Structure, Unknown};
use crate::description::xml_string;

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
    document(|w| write_into(w, scene, guid))
}

fn write_into(w: &mut W, scene: &Scene, guid: &str) -> std::io::Result<()> {
    let vars: Vec<&'static Variable> = scene.variables().collect();
    write_head(w, &head(scene, Edition::Fmi2, guid))?;
    open(w, "ModelVariables", &[])?;
    for (i, v) in vars.iter().enumerate() {
        // A derivative names its state by the state's 1-based index.
        let derivative = v
            .derivative_of()
            .and_then(|x| indices(&vars, &[x.vr()]).first().map(|i| i.to_string()));
        write_variable(w, Edition::Fmi2, &declared(scene, v, i + 1, derivative))?;
    }
    close(w, "ModelVariables")?;
    write_structure(w, Edition::Fmi2, &structure(scene, &vars))?;
    close(w, "fmiModelDescription")
}

/// A single contact's variable, the `index`-th, as the model description declares it.
pub(super) fn declared<'a>(
    scene: &Scene,
    v: &'a Variable,
    index: usize,
    derivative: Option<String>,
) -> Declared<'a> {
    let c = &scene.config;
    let initial = v.initial(c);
    let start = match initial {
        Some(Initial::Calculated) => None,
        _ => scene.start_of(v),
    };
    // The accepted range of what the importer sets (not of F_d as a spring drive's output).
    let settable = v.causality(c) != Causality::Output;
    Declared {
        name: v.name(),
        vr: v.vr,
        description: v.description,
        causality: v.causality(c).as_str(),
        variability: v.variability(c).as_str(),
        initial: initial.map(|i| i.as_str()),
        unit: v.unit,
        display_unit: v.display_unit,
        derivative,
        start: start.map(number),
        min: v.min(c).filter(|_| settable),
        max: v.max(c).filter(|_| settable),
        dimension: None,
        index,
    }
}

/// What a single contact's model description says before its variables, in `edition`.
pub(super) fn head<'a>(scene: &'a Scene, edition: Edition, token: &'a str) -> Head<'a> {
    let c = &scene.config;
    let vars = scene.variables();
    Head {
        edition,
        model_identifier: &scene.model_identifier,
        description: &scene.description,
        token,
        event_indicators: c.event_indicators(),
        // FMI 2.0 extrapolates the inputs with their derivatives.
        can_interpolate_inputs: scene
            .variables()
            .any(|v| v.causality(c) == Causality::Input),
        max_output_derivative_order: 1,
        units: vars.map(|v| (v.unit, v.display_unit)).collect(),
    }
}

/// `ModelStructure`: the outputs, the derivatives and the initial unknowns with their
/// dependencies, by 1-based index.
fn structure(scene: &Scene, vars: &[&'static Variable]) -> Structure {
    let c = &scene.config;
    let unknown = |(i, v): (usize, &&Variable)| Unknown {
        id: i + 1,
        dependencies: Some(indices(vars, &v.known_dependencies(c, &scene.outputs))),
    };
    let outputs: Vec<(usize, &&Variable)> = vars
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality(c) == Causality::Output)
        .collect();
    let mut initial_unknowns: Vec<Unknown> = outputs
        .iter()
        .filter(|(_, v)| v.initial(c) == Some(Initial::Calculated))
        .map(|(i, v)| {
            let vrs: Vec<u32> = v.initial_dependencies(c).iter().map(|d| d.vr()).collect();
            Unknown {
                id: i + 1,
                dependencies: Some(indices(vars, &vrs)),
            }
        })
        .collect();
    // The states start at 0 (the body at rest at the origin, undeformed); their derivatives
    // depend at the start on parameters and inputs (no `dependencies`: all of them).
    initial_unknowns.extend(vars.iter().enumerate().filter_map(|(i, v)| match v.kind {
        VarKind::State(_) => Some(Unknown {
            id: i + 1,
            dependencies: Some(vec![]),
        }),
        VarKind::Derivative(_) => Some(Unknown {
            id: i + 1,
            dependencies: None,
        }),
        _ => None,
    }));
    Structure {
        outputs: outputs.into_iter().map(unknown).collect(),
        // Model Exchange: the order of the derivatives is the order of the state vector.
        derivatives: vars
            .iter()
            .enumerate()
            .filter(|(_, v)| v.derivative_of().is_some())
            .map(unknown)
            .collect(),
        initial_unknowns,
        event_indicators: vec![],
    }
}
