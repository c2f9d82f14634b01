//! The model description of a string of contacts, in either edition, from the string's rows
//! ([`crate::table::StringVar`]) and the law's shared parameters:
//!
//! - FMI 2.0 writes each array as scalars `x[1]` … `x[N]` (value references `b·1000000 + i`);
//! - FMI 3.0 writes it as one variable `x` (value reference `b·1000000`) with
//!   `<Dimension start="N"/>` and its start values as a list.
//!
//! Every parameter of a string is fixed (set before initialization ends). A string offers
//! Model Exchange and Co-Simulation ([`write_interfaces`]): the continuous states are the
//! outputs `x`, `v_x`, `s_x` and the ends' points `x_top`, `x_bottom`, with derivatives
//! `der(x)`, ... and one event indicator per section (`event.v_rx`).

use std::io::Write;

use quick_xml::events::{BytesDecl, BytesStart, Event};
use quick_xml::Writer;

use crate::description::scene::Scene;
use crate::description::xml_parts::{close, empty, generation_tool, joined, number, open, W};
use crate::description::xml_parts::{write_default_experiment, write_log_categories, write_units};
use crate::table::{Config, Role, StringDependency, StringVar};

/// The FMI edition a model description is written for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edition {
    Fmi2,
    Fmi3,
}

/// One variable as the model description declares it: a scalar, an element of an array (FMI
/// 2.0) or a whole array (FMI 3.0, `dimension` its length).
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub name: String,
    pub vr: u32,
    pub description: &'static str,
    pub role: Role,
    pub unit: &'static str,
    pub display_unit: Option<&'static str>,
    /// Start values (one, or one per element of an FMI 3.0 array); none for outputs.
    pub start: Vec<f64>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub dimension: Option<usize>,
    /// The string variable and element (0-based) the row is, or `None` for a shared parameter.
    pub of: Option<(StringVar, usize)>,
    /// A derivative's state: its value reference (of the element in FMI 2.0, the array in 3.0).
    pub derivative_of: Option<u32>,
}

/// The rows of a string scene in `ModelVariables` order: the shared law parameters, then the
/// string's parameters, inputs and outputs in the order of [`StringVar::ALL`].
pub fn rows(scene: &Scene, edition: Edition) -> Vec<Row> {
    let c = &scene.config;
    let values = scene.string.as_ref().expect("a string scene");
    let n = values.sections;
    let mut rows: Vec<Row> = scene
        .variables()
        .map(|v| Row {
            name: v.name().to_string(),
            vr: v.vr,
            description: v.description,
            role: Role::Param,
            unit: v.unit,
            display_unit: v.display_unit,
            start: scene.start_of(v).into_iter().collect(),
            min: v.min(c),
            max: v.max(c),
            dimension: None,
            of: None,
            derivative_of: None,
        })
        .collect();
    for var in StringVar::ALL.into_iter().filter(|v| v.present(c, n)) {
        let role = var.role(c);
        let settable = var.settable(c);
        let row = |name: String,
                   vr: u32,
                   start: Vec<f64>,
                   dimension,
                   of: Option<(StringVar, usize)>| Row {
            name,
            vr,
            description: var.description(),
            role,
            unit: var.unit(),
            display_unit: var.display_unit(),
            start: if settable { start } else { vec![] },
            min: settable.then(|| var.rule().min()).flatten(),
            max: settable.then(|| var.rule().max()).flatten(),
            dimension,
            derivative_of: of.and_then(|(v, i)| v.derivative_of().map(|x| element(x, i, edition))),
            of,
        };
        let start = if settable { values.get(var) } else { &[][..] };
        match (edition, var.shape().is_array()) {
            (Edition::Fmi2, true) => rows.extend((0..var.len(n)).map(|i| {
                let s = start.get(i).copied().into_iter().collect();
                row(
                    var.element_name(i),
                    var.element_vr(i),
                    s,
                    None,
                    Some((var, i)),
                )
            })),
            (Edition::Fmi3, true) => rows.push(row(
                var.name().into(),
                var.vr(),
                start.to_vec(),
                Some(var.len(n)),
                Some((var, 0)),
            )),
            (_, false) => rows.push(row(
                var.name().into(),
                var.vr(),
                start.to_vec(),
                None,
                Some((var, 0)),
            )),
        }
    }
    rows
}

/// The value references an output row depends on directly during the simulation (FMI 3.0:
/// the whole arrays), sorted and once each.
pub fn direct_dependencies(c: &Config, row: &Row, edition: Edition) -> Vec<u32> {
    let Some((var, i)) = row.of else {
        return vec![];
    };
    let mut vrs: Vec<u32> = var
        .direct_dependencies(c, i)
        .into_iter()
        .map(|(v, k)| element(v, k, edition))
        .collect();
    if edition == Edition::Fmi3 {
        // An array depends on what any of its elements depends on.
        if let Some(n) = row.dimension {
            vrs = (0..n)
                .flat_map(|i| var.direct_dependencies(c, i))
                .map(|(v, k)| element(v, k, edition))
                .collect();
        }
    }
    vrs.sort_unstable();
    vrs.dedup();
    vrs
}

/// The value references an output row depends on at initialization, sorted and once each.
pub fn initial_dependencies(c: &Config, row: &Row, edition: Edition) -> Vec<u32> {
    let Some((var, i)) = row.of else {
        return vec![];
    };
    let elements = match (edition, row.dimension) {
        (Edition::Fmi3, Some(n)) => (0..n).collect(),
        _ => vec![i],
    };
    let mut vrs: Vec<u32> = elements
        .into_iter()
        .flat_map(|i| var.initial_dependencies(c, i))
        .map(|d| match d {
            StringDependency::Shared(p) => p.vr(),
            StringDependency::String(v, k) => element(v, k, edition),
        })
        .collect();
    vrs.sort_unstable();
    vrs.dedup();
    vrs
}

/// The knowns of Model Exchange (states and inputs) a row of a string of `n` sections depends
/// on ([`StringVar::exchange_dependencies`]; FMI 3.0: the whole arrays, what any element
/// depends on), with an output's direct dependencies of Co-Simulation, sorted and once each.
pub fn known_dependencies(c: &Config, n: usize, row: &Row, edition: Edition) -> Vec<u32> {
    let Some((var, i)) = row.of else {
        return vec![];
    };
    let elements: Vec<usize> = match (edition, row.dimension) {
        (Edition::Fmi3, Some(len)) => (0..len).collect(),
        _ => vec![i],
    };
    let mut vrs: Vec<u32> = elements
        .into_iter()
        .flat_map(|i| var.exchange_dependencies(c, n, i))
        .map(|(v, k)| element(v, k, edition))
        .collect();
    if var.role(c) == Role::Output {
        vrs.extend(direct_dependencies(c, row, edition));
    }
    vrs.sort_unstable();
    vrs.dedup();
    vrs
}

fn element(v: StringVar, k: usize, edition: Edition) -> u32 {
    match edition {
        Edition::Fmi2 => v.element_vr(k),
        Edition::Fmi3 => v.vr(),
    }
}

fn causality(role: Role) -> &'static str {
    match role {
        Role::Param => "parameter",
        Role::Input => "input",
        Role::Output => "output",
        Role::Local => "local",
    }
}

/// The model description of a string scene in `edition`, with this GUID (FMI 2.0) or
/// instantiation token (FMI 3.0).
pub fn model_description(scene: &Scene, edition: Edition, token: &str) -> String {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    write_into(&mut w, scene, edition, token).expect("writing XML into memory cannot fail");
    let mut bytes = w.into_inner();
    bytes.write_all(b"\n").expect("in memory");
    String::from_utf8(bytes).expect("quick-xml writes UTF-8 from UTF-8 input")
}

/// The interfaces a string scene offers: Model Exchange (with exact directional derivatives
/// from the string's banded Jacobian) and Co-Simulation.
fn write_interfaces(w: &mut W, scene: &Scene, edition: Edition) -> std::io::Result<()> {
    let id = scene.model_identifier.as_str();
    let exchange: Vec<(&str, &str)> = match edition {
        Edition::Fmi2 => vec![
            ("modelIdentifier", id),
            ("needsExecutionTool", "false"),
            // Nothing happens at the end of an integrator step: no step events.
            ("completedIntegratorStepNotNeeded", "true"),
            ("canBeInstantiatedOnlyOncePerProcess", "false"),
            ("canNotUseMemoryManagementFunctions", "true"),
            ("canGetAndSetFMUstate", "true"),
            ("canSerializeFMUstate", "true"),
            ("providesDirectionalDerivative", "true"),
        ],
        Edition::Fmi3 => vec![
            ("modelIdentifier", id),
            ("needsExecutionTool", "false"),
            ("canBeInstantiatedOnlyOncePerProcess", "false"),
            ("canGetAndSetFMUState", "true"),
            ("canSerializeFMUState", "true"),
            ("providesDirectionalDerivatives", "true"),
            ("providesAdjointDerivatives", "false"),
            ("providesPerElementDependencies", "false"),
            ("needsCompletedIntegratorStep", "false"),
            ("providesEvaluateDiscreteStates", "false"),
        ],
    };
    empty(w, "ModelExchange", &exchange)?;
    let attrs: Vec<(&str, &str)> = match edition {
        Edition::Fmi2 => vec![
            ("modelIdentifier", id),
            ("needsExecutionTool", "false"),
            ("canHandleVariableCommunicationStepSize", "true"),
            ("canInterpolateInputs", "true"),
            ("maxOutputDerivativeOrder", "0"),
            ("canRunAsynchronuously", "false"),
            ("canBeInstantiatedOnlyOncePerProcess", "false"),
            ("canNotUseMemoryManagementFunctions", "true"),
            ("canGetAndSetFMUstate", "true"),
            ("canSerializeFMUstate", "true"),
            ("providesDirectionalDerivative", "false"),
        ],
        Edition::Fmi3 => vec![
            ("modelIdentifier", id),
            ("needsExecutionTool", "false"),
            ("canBeInstantiatedOnlyOncePerProcess", "false"),
            ("canGetAndSetFMUState", "true"),
            ("canSerializeFMUState", "true"),
            ("providesDirectionalDerivatives", "false"),
            ("providesAdjointDerivatives", "false"),
            ("providesPerElementDependencies", "false"),
            ("canHandleVariableCommunicationStepSize", "true"),
            ("maxOutputDerivativeOrder", "0"),
            ("providesIntermediateUpdate", "false"),
            ("mightReturnEarlyFromDoStep", "false"),
            ("canReturnEarlyAfterIntermediateUpdate", "false"),
            ("hasEventMode", "false"),
            ("providesEvaluateDiscreteStates", "false"),
        ],
    };
    empty(w, "CoSimulation", &attrs)
}

/// The name of an FMI 3.0 `Float64Type`: the unit, with the display unit in parentheses.
fn type_name(unit: &str, display: Option<&str>) -> String {
    match display {
        Some(d) => format!("{unit} ({d})"),
        None => unit.to_string(),
    }
}

fn write_into(w: &mut W, scene: &Scene, edition: Edition, token: &str) -> std::io::Result<()> {
    let c = &scene.config;
    let rows = rows(scene, edition);
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let tool = generation_tool();
    let (version, token_name) = match edition {
        Edition::Fmi2 => ("2.0", "guid"),
        Edition::Fmi3 => ("3.0", "instantiationToken"),
    };
    let mut top = vec![
        ("fmiVersion", version),
        ("modelName", scene.model_identifier.as_str()),
        (token_name, token),
        ("description", scene.description.as_str()),
        ("generationTool", tool.as_str()),
        ("variableNamingConvention", "flat"),
    ];
    let indicators = StringVar::EventVrx
        .len(values_of(scene).sections)
        .to_string();
    if edition == Edition::Fmi2 {
        top.push(("numberOfEventIndicators", &indicators));
    }
    open(w, "fmiModelDescription", &top)?;
    write_interfaces(w, scene, edition)?;
    let mut units: Vec<&str> = rows.iter().map(|r| r.unit).collect();
    if edition == Edition::Fmi3 {
        // The independent variable's.
        units.push("s");
    }
    write_units(w, &units)?;
    if edition == Edition::Fmi3 {
        let mut types: Vec<(&str, Option<&str>)> = vec![("s", None)];
        for r in &rows {
            if !types.contains(&(r.unit, r.display_unit)) {
                types.push((r.unit, r.display_unit));
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
    }
    write_log_categories(w)?;
    write_default_experiment(w)?;
    open(w, "ModelVariables", &[])?;
    if edition == Edition::Fmi3 {
        empty(
            w,
            "Float64",
            &[
                ("name", "time"),
                ("valueReference", "0"),
                ("description", "Simulation time"),
                ("causality", "independent"),
                ("variability", "continuous"),
                ("declaredType", "s"),
            ],
        )?;
    }
    for (k, r) in rows.iter().enumerate() {
        // A derivative names its state: FMI 2.0 by its 1-based index, FMI 3.0 by value
        // reference.
        let derivative = r.derivative_of.map(|vr| match edition {
            Edition::Fmi2 => (index_of(&rows, vr)).to_string(),
            Edition::Fmi3 => vr.to_string(),
        });
        write_variable(w, r, edition, k + 1, derivative)?;
    }
    close(w, "ModelVariables")?;
    write_structure(w, c, values_of(scene).sections, &rows, edition)?;
    close(w, "fmiModelDescription")
}

/// The 1-based index of the row of value reference `vr`.
fn index_of(rows: &[Row], vr: u32) -> usize {
    rows.iter().position(|r| r.vr == vr).map_or(0, |k| k + 1)
}

fn values_of(scene: &Scene) -> &crate::table::StringValues {
    scene.string.as_ref().expect("a string scene")
}

fn write_variable(
    w: &mut W,
    r: &Row,
    edition: Edition,
    index: usize,
    derivative: Option<String>,
) -> std::io::Result<()> {
    let vr = r.vr.to_string();
    let variability = match r.role {
        Role::Param => "fixed",
        _ => "continuous",
    };
    let mut attrs: Vec<(&str, String)> = vec![
        ("name", r.name.clone()),
        ("valueReference", vr),
        ("description", r.description.into()),
        ("causality", causality(r.role).into()),
        ("variability", variability.into()),
    ];
    match r.role {
        Role::Param => attrs.push(("initial", "exact".into())),
        Role::Output | Role::Local => attrs.push(("initial", "calculated".into())),
        Role::Input => {}
    }
    let start = r
        .start
        .iter()
        .map(|&x| number(x))
        .collect::<Vec<_>>()
        .join(" ");
    let bounds: Vec<(&str, String)> = [("min", r.min), ("max", r.max)]
        .into_iter()
        .filter_map(|(n, x)| x.map(|x| (n, number(x))))
        .collect();
    match edition {
        Edition::Fmi2 => {
            w.write_event(Event::Comment(quick_xml::events::BytesText::new(&format!(
                " index {index} "
            ))))?;
            let refs: Vec<(&str, &str)> = attrs.iter().map(|(n, x)| (*n, x.as_str())).collect();
            open(w, "ScalarVariable", &refs)?;
            let mut real: Vec<(&str, &str)> = vec![];
            if let Some(d) = &derivative {
                real.push(("derivative", d));
            }
            real.push(("unit", r.unit));
            if let Some(d) = r.display_unit {
                real.push(("displayUnit", d));
            }
            if !r.start.is_empty() {
                real.push(("start", &start));
            }
            real.extend(bounds.iter().map(|(n, x)| (*n, x.as_str())));
            empty(w, "Real", &real)?;
            close(w, "ScalarVariable")
        }
        Edition::Fmi3 => {
            attrs.push(("declaredType", type_name(r.unit, r.display_unit)));
            if let Some(d) = derivative {
                attrs.push(("derivative", d));
            }
            attrs.extend(bounds);
            if !r.start.is_empty() {
                attrs.push(("start", start));
            }
            let mut e = BytesStart::new("Float64");
            for (n, x) in &attrs {
                e.push_attribute((*n, x.as_str()));
            }
            match r.dimension {
                None => w.write_event(Event::Empty(e)),
                Some(n) => {
                    w.write_event(Event::Start(e))?;
                    empty(w, "Dimension", &[("start", &n.to_string())])?;
                    close(w, "Float64")
                }
            }
        }
    }
}

fn write_structure(
    w: &mut W,
    c: &Config,
    n: usize,
    rows: &[Row],
    edition: Edition,
) -> std::io::Result<()> {
    // FMI 2.0 names variables by their 1-based index, FMI 3.0 by value reference.
    let refs = |vrs: Vec<u32>| -> String {
        match edition {
            Edition::Fmi3 => joined(&vrs),
            Edition::Fmi2 => {
                let mut idx: Vec<usize> = vrs.iter().map(|&vr| index_of(rows, vr)).collect();
                idx.sort_unstable();
                joined(&idx)
            }
        }
    };
    open(w, "ModelStructure", &[])?;
    let (out_tag, der_tag, init_tag, key) = match edition {
        Edition::Fmi2 => ("Unknown", "Unknown", "Unknown", "index"),
        Edition::Fmi3 => (
            "Output",
            "ContinuousStateDerivative",
            "InitialUnknown",
            "valueReference",
        ),
    };
    let id = |k: usize, r: &Row| match edition {
        Edition::Fmi2 => (k + 1).to_string(),
        Edition::Fmi3 => r.vr.to_string(),
    };
    let group = |w: &mut W, name: &str, start: bool| -> std::io::Result<()> {
        match (edition, start) {
            (Edition::Fmi3, _) => Ok(()),
            (Edition::Fmi2, true) => open(w, name, &[]),
            (Edition::Fmi2, false) => close(w, name),
        }
    };
    group(w, "Outputs", true)?;
    for (k, r) in rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.role == Role::Output)
    {
        let deps = refs(known_dependencies(c, n, r, edition));
        empty(w, out_tag, &[(key, &id(k, r)), ("dependencies", &deps)])?;
    }
    group(w, "Outputs", false)?;
    // Model Exchange: the order of the derivatives is the order of the state vector.
    group(w, "Derivatives", true)?;
    for (k, r) in rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.derivative_of.is_some())
    {
        let deps = refs(known_dependencies(c, n, r, edition));
        empty(w, der_tag, &[(key, &id(k, r)), ("dependencies", &deps)])?;
    }
    group(w, "Derivatives", false)?;
    // The outputs at initialization; the ends' points start at 0 (no dependencies), the
    // derivatives depend on every parameter and input (no `dependencies`). In index order.
    group(w, "InitialUnknowns", true)?;
    for (k, r) in rows.iter().enumerate() {
        let var = r.of.map(|o| o.0);
        if r.role == Role::Output {
            let deps = refs(initial_dependencies(c, r, edition));
            empty(w, init_tag, &[(key, &id(k, r)), ("dependencies", &deps)])?;
        } else if matches!(var, Some(StringVar::XTop | StringVar::XBottom)) {
            empty(w, init_tag, &[(key, &id(k, r)), ("dependencies", "")])?;
        } else if r.derivative_of.is_some() {
            empty(w, init_tag, &[(key, &id(k, r))])?;
        }
    }
    group(w, "InitialUnknowns", false)?;
    if edition == Edition::Fmi3 {
        for r in rows
            .iter()
            .filter(|r| r.of.map(|o| o.0) == Some(StringVar::EventVrx))
        {
            let deps = refs(known_dependencies(c, n, r, edition));
            empty(
                w,
                "EventIndicator",
                &[
                    ("valueReference", &r.vr.to_string()),
                    ("dependencies", &deps),
                ],
            )?;
        }
    }
    close(w, "ModelStructure")
}
