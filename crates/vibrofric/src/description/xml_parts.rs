//! What both editions' model descriptions, and those of strings of contacts, write alike: the
//! XML helpers, the document's head (its root element, interfaces, units, unit types, log
//! categories and default experiment), a variable and the model structure, each in the
//! vocabulary of its edition. The callers (`xml.rs`, `xml3.rs`, `xml_string.rs`) say what to
//! write; these write it.

use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};
use quick_xml::Writer;

use crate::description::log::Category;

/// `DefaultExperiment` of every FMU: (startTime, stopTime, tolerance, stepSize).
pub const DEFAULT_EXPERIMENT: (f64, f64, f64, f64) = (0.0, 0.1, 1e-6, 1e-3);

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

pub fn joined<T: ToString>(idx: &[T]) -> String {
    idx.iter()
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

pub type W = Writer<Vec<u8>>;

/// A whole document written by `write` into memory (indented by 2), with a final newline.
pub fn document(write: impl FnOnce(&mut W) -> std::io::Result<()>) -> String {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    write(&mut w).expect("writing XML into memory cannot fail");
    let mut bytes = w.into_inner();
    bytes.push(b'\n');
    String::from_utf8(bytes).expect("quick-xml writes UTF-8 from UTF-8 input")
}

pub fn empty(w: &mut W, name: &str, attrs: &[(&str, &str)]) -> std::io::Result<()> {
    let mut e = BytesStart::new(name);
    for a in attrs {
        e.push_attribute(*a);
    }
    w.write_event(Event::Empty(e))
}

pub fn open(w: &mut W, name: &str, attrs: &[(&str, &str)]) -> std::io::Result<()> {
    let mut e = BytesStart::new(name);
    for a in attrs {
        e.push_attribute(*a);
    }
    w.write_event(Event::Start(e))
}

pub fn close(w: &mut W, name: &str) -> std::io::Result<()> {
    w.write_event(Event::End(BytesEnd::new(name)))
}

/// `UnitDefinitions`: every unit of `units` (those the scene's variables use), with its SI exponents and display
/// units (the same element in FMI 2.0 and 3.0).
pub fn write_units(w: &mut W, units: &[&str]) -> std::io::Result<()> {
    open(w, "UnitDefinitions", &[])?;
    for unit in UNIT_ORDER {
        if !units.contains(&unit) {
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
pub fn write_log_categories(w: &mut W) -> std::io::Result<()> {
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
pub fn write_default_experiment(w: &mut W) -> std::io::Result<()> {
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

/// The FMI edition a model description is written for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edition {
    Fmi2,
    Fmi3,
}

/// What a model description says before its variables.
pub struct Head<'a> {
    pub edition: Edition,
    pub model_identifier: &'a str,
    pub description: &'a str,
    /// The GUID (FMI 2.0) or instantiation token (FMI 3.0).
    pub token: &'a str,
    /// FMI 2.0's `numberOfEventIndicators`.
    pub event_indicators: usize,
    /// FMI 2.0 Co-Simulation's `canInterpolateInputs`.
    pub can_interpolate_inputs: bool,
    /// Co-Simulation's `maxOutputDerivativeOrder`.
    pub max_output_derivative_order: u32,
    /// The unit and display unit of each variable.
    pub units: Vec<(&'a str, Option<&'a str>)>,
}

/// The name of an FMI 3.0 `Float64Type`: the unit, with the display unit in parentheses.
pub fn type_name(unit: &str, display: Option<&str>) -> String {
    match display {
        Some(d) => format!("{unit} ({d})"),
        None => unit.to_string(),
    }
}

/// The XML declaration, the opening `fmiModelDescription`, the interfaces (Model Exchange and
/// Co-Simulation), `UnitDefinitions`, FMI 3.0's `TypeDefinitions` (a `Float64Type` per unit
/// and display unit, which the variables name as their declared type; the independent
/// variable's `s` first), `LogCategories` and `DefaultExperiment`.
pub fn write_head(w: &mut W, h: &Head) -> std::io::Result<()> {
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let tool = generation_tool();
    let indicators = h.event_indicators.to_string();
    let (version, token_name) = match h.edition {
        Edition::Fmi2 => ("2.0", "guid"),
        Edition::Fmi3 => ("3.0", "instantiationToken"),
    };
    let mut top = vec![
        ("fmiVersion", version),
        ("modelName", h.model_identifier),
        (token_name, h.token),
        ("description", h.description),
        ("generationTool", tool.as_str()),
        ("variableNamingConvention", "flat"),
    ];
    if h.edition == Edition::Fmi2 {
        top.push(("numberOfEventIndicators", &indicators));
    }
    open(w, "fmiModelDescription", &top)?;
    write_interfaces(w, h)?;
    let mut units: Vec<&str> = h.units.iter().map(|u| u.0).collect();
    let mut types: Vec<(&str, Option<&str>)> = vec![];
    if h.edition == Edition::Fmi3 {
        // The independent variable's.
        units.push("s");
        types.push(("s", None));
    }
    write_units(w, &units)?;
    if h.edition == Edition::Fmi3 {
        for t in &h.units {
            if !types.contains(t) {
                types.push(*t);
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
    write_default_experiment(w)
}

/// An element's attributes, (name, value) in order.
type Attributes<'a> = Vec<(&'a str, &'a str)>;

/// `ModelExchange` (with exact directional derivatives) and `CoSimulation`.
fn write_interfaces(w: &mut W, h: &Head) -> std::io::Result<()> {
    let id = h.model_identifier;
    let order = h.max_output_derivative_order.to_string();
    let interpolate = if h.can_interpolate_inputs {
        "true"
    } else {
        "false"
    };
    let (exchange, co_simulation): (Attributes, Attributes) = match h.edition {
        Edition::Fmi2 => (
            vec![
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
            vec![
                ("modelIdentifier", id),
                ("needsExecutionTool", "false"),
                ("canHandleVariableCommunicationStepSize", "true"),
                ("canInterpolateInputs", interpolate),
                ("maxOutputDerivativeOrder", &order),
                ("canRunAsynchronuously", "false"),
                ("canBeInstantiatedOnlyOncePerProcess", "false"),
                ("canNotUseMemoryManagementFunctions", "true"),
                ("canGetAndSetFMUstate", "true"),
                ("canSerializeFMUstate", "true"),
                ("providesDirectionalDerivative", "false"),
            ],
        ),
        Edition::Fmi3 => {
            // What both interfaces declare alike; Model Exchange alone has the derivatives.
            let common = |derivatives| {
                vec![
                    ("modelIdentifier", id),
                    ("needsExecutionTool", "false"),
                    ("canBeInstantiatedOnlyOncePerProcess", "false"),
                    ("canGetAndSetFMUState", "true"),
                    ("canSerializeFMUState", "true"),
                    ("providesDirectionalDerivatives", derivatives),
                    ("providesAdjointDerivatives", "false"),
                    ("providesPerElementDependencies", "false"),
                ]
            };
            let mut exchange = common("true");
            exchange.extend([
                // Nothing happens at the end of an integrator step: no step events.
                ("needsCompletedIntegratorStep", "false"),
                ("providesEvaluateDiscreteStates", "false"),
            ]);
            let mut co_simulation = common("false");
            co_simulation.extend([
                ("canHandleVariableCommunicationStepSize", "true"),
                ("maxOutputDerivativeOrder", &order),
                ("providesIntermediateUpdate", "false"),
                ("mightReturnEarlyFromDoStep", "false"),
                ("canReturnEarlyAfterIntermediateUpdate", "false"),
                ("hasEventMode", "false"),
                ("providesEvaluateDiscreteStates", "false"),
            ]);
            (exchange, co_simulation)
        }
    };
    empty(w, "ModelExchange", &exchange)?;
    empty(w, "CoSimulation", &co_simulation)
}

/// Value reference of FMI 3.0's independent variable `time`.
pub const TIME_VR: u32 = 0;

/// FMI 3.0's independent variable `time`, first in `ModelVariables`.
pub fn write_time(w: &mut W) -> std::io::Result<()> {
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
    )
}

/// One variable as a model description declares it.
pub struct Declared<'a> {
    pub name: &'a str,
    pub vr: u32,
    pub description: &'a str,
    pub causality: &'a str,
    pub variability: &'a str,
    pub initial: Option<&'a str>,
    pub unit: &'a str,
    pub display_unit: Option<&'a str>,
    /// The state it is the derivative of: its 1-based index (FMI 2.0) or value reference.
    pub derivative: Option<String>,
    /// Its start value, or FMI 3.0 array's start values separated by spaces.
    pub start: Option<String>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    /// An FMI 3.0 array's length.
    pub dimension: Option<usize>,
    /// Its 1-based index in `ModelVariables` (FMI 2.0 writes it as a comment).
    pub index: usize,
}

/// A variable: FMI 2.0 a `ScalarVariable` (its index as a comment before it) with its `Real`,
/// FMI 3.0 a `Float64` (with its `Dimension` where it is an array).
pub fn write_variable(w: &mut W, edition: Edition, d: &Declared) -> std::io::Result<()> {
    let vr = d.vr.to_string();
    let mut attrs: Vec<(&str, &str)> = vec![
        ("name", d.name),
        ("valueReference", &vr),
        ("description", d.description),
        ("causality", d.causality),
        ("variability", d.variability),
    ];
    if let Some(init) = d.initial {
        attrs.push(("initial", init));
    }
    let bounds: Vec<(&str, String)> = [("min", d.min), ("max", d.max)]
        .into_iter()
        .filter_map(|(n, x)| x.map(|x| (n, number(x))))
        .collect();
    match edition {
        Edition::Fmi2 => {
            let comment = format!(" index {} ", d.index);
            w.write_event(Event::Comment(BytesText::new(&comment)))?;
            open(w, "ScalarVariable", &attrs)?;
            let mut real: Vec<(&str, &str)> = vec![];
            if let Some(x) = &d.derivative {
                real.push(("derivative", x));
            }
            real.push(("unit", d.unit));
            if let Some(u) = d.display_unit {
                real.push(("displayUnit", u));
            }
            if let Some(x) = &d.start {
                real.push(("start", x));
            }
            real.extend(bounds.iter().map(|(n, x)| (*n, x.as_str())));
            empty(w, "Real", &real)?;
            close(w, "ScalarVariable")
        }
        Edition::Fmi3 => {
            let declared = type_name(d.unit, d.display_unit);
            attrs.push(("declaredType", &declared));
            if let Some(x) = &d.derivative {
                attrs.push(("derivative", x));
            }
            attrs.extend(bounds.iter().map(|(n, x)| (*n, x.as_str())));
            if let Some(x) = &d.start {
                attrs.push(("start", x));
            }
            match d.dimension {
                None => empty(w, "Float64", &attrs),
                Some(n) => {
                    open(w, "Float64", &attrs)?;
                    empty(w, "Dimension", &[("start", &n.to_string())])?;
                    close(w, "Float64")
                }
            }
        }
    }
}

/// An unknown of `ModelStructure`: its 1-based index (FMI 2.0) or value reference (FMI 3.0),
/// and the knowns it depends on, the same way, or `None` (no `dependencies` attribute: all).
pub struct Unknown {
    pub id: usize,
    pub dependencies: Option<Vec<usize>>,
}

/// What `ModelStructure` lists, each in its order.
pub struct Structure {
    pub outputs: Vec<Unknown>,
    pub derivatives: Vec<Unknown>,
    pub initial_unknowns: Vec<Unknown>,
    /// FMI 3.0 only (FMI 2.0 counts them in the root element).
    pub event_indicators: Vec<Unknown>,
}

/// `ModelStructure`: FMI 2.0 in the groups `Outputs`, `Derivatives`, `InitialUnknowns` of
/// `Unknown` elements by index; FMI 3.0 as `Output`, `ContinuousStateDerivative`,
/// `InitialUnknown` and `EventIndicator` elements by value reference. The dependencies are
/// written sorted.
pub fn write_structure(w: &mut W, edition: Edition, s: &Structure) -> std::io::Result<()> {
    open(w, "ModelStructure", &[])?;
    let lists = [
        ("Outputs", "Output", &s.outputs),
        ("Derivatives", "ContinuousStateDerivative", &s.derivatives),
        ("InitialUnknowns", "InitialUnknown", &s.initial_unknowns),
        ("", "EventIndicator", &s.event_indicators),
    ];
    for (group, tag, unknowns) in lists {
        let (tag, key) = match edition {
            Edition::Fmi2 if group.is_empty() => continue,
            Edition::Fmi2 => ("Unknown", "index"),
            Edition::Fmi3 => (tag, "valueReference"),
        };
        if edition == Edition::Fmi2 {
            open(w, group, &[])?;
        }
        for u in unknowns.iter() {
            let id = u.id.to_string();
            let mut attrs = vec![(key, id.as_str())];
            let deps = u.dependencies.as_ref().map(|d| {
                let mut d = d.clone();
                d.sort_unstable();
                joined(&d)
            });
            if let Some(d) = &deps {
                attrs.push(("dependencies", d));
            }
            empty(w, tag, &attrs)?;
        }
        if edition == Edition::Fmi2 {
            close(w, group)?;
        }
    }
    close(w, "ModelStructure")
}
