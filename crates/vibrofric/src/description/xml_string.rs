//! The model description of a string of contacts, in either edition, from the string's rows
//! ([`crate::table::StringVar`]) and the law's shared parameters:
//!
//! - FMI 2.0 writes each array as scalars `x[1]` … `x[N]` (value references `b·1000000 + i`);
//! - FMI 3.0 writes it as one variable `x` (value reference `b·1000000`) with
//!   `<Dimension start="N"/>` and its start values as a list.
//!
//! Every parameter of a string is fixed (set before initialization ends). A string offers
//! Model Exchange and Co-Simulation: the continuous states are the
//! outputs `x`, `v_x`, `s_x` and the ends' points `x_top`, `x_bottom`, with derivatives
//! `der(x)`, ... and one event indicator per section (`event.v_rx`).

use crate::description::scene::Scene;
use crate::description::xml_parts::{close, number, open, write_head, write_structure};
use crate::description::xml_parts::{document, Unknown, W};
use crate::description::xml_parts::{write_time, write_variable, Declared, Head, Structure};
use crate::table::{Config, Role, StringDependency, StringVar};

pub use crate::description::xml_parts::Edition;

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
    document(|w| write_into(w, scene, edition, token))
}

fn write_into(w: &mut W, scene: &Scene, edition: Edition, token: &str) -> std::io::Result<()> {
    let c = &scene.config;
    let rows = rows(scene, edition);
    let head = Head {
        edition,
        model_identifier: &scene.model_identifier,
        description: &scene.description,
        token,
        event_indicators: StringVar::EventVrx.len(values_of(scene).sections),
        can_interpolate_inputs: true,
        max_output_derivative_order: 0,
        units: rows.iter().map(|r| (r.unit, r.display_unit)).collect(),
    };
    write_head(w, &head)?;
    open(w, "ModelVariables", &[])?;
    if edition == Edition::Fmi3 {
        write_time(w)?;
    }
    for (k, r) in rows.iter().enumerate() {
        // A derivative names its state: FMI 2.0 by its 1-based index, FMI 3.0 by value
        // reference.
        let derivative = r.derivative_of.map(|vr| match edition {
            Edition::Fmi2 => (index_of(&rows, vr)).to_string(),
            Edition::Fmi3 => vr.to_string(),
        });
        write_variable(w, edition, &declared(r, k + 1, derivative))?;
    }
    close(w, "ModelVariables")?;
    write_structure(
        w,
        edition,
        &structure(c, values_of(scene).sections, &rows, edition),
    )?;
    close(w, "fmiModelDescription")
}

/// The 1-based index of the row of value reference `vr`.
fn index_of(rows: &[Row], vr: u32) -> usize {
    rows.iter().position(|r| r.vr == vr).map_or(0, |k| k + 1)
}

fn values_of(scene: &Scene) -> &crate::table::StringValues {
    scene.string.as_ref().expect("a string scene")
}

/// A row as the model description declares it: every parameter fixed, every output and local
/// calculated.
fn declared(r: &Row, index: usize, derivative: Option<String>) -> Declared<'_> {
    let start = r
        .start
        .iter()
        .map(|&x| number(x))
        .collect::<Vec<_>>()
        .join(" ");
    Declared {
        name: &r.name,
        vr: r.vr,
        description: r.description,
        causality: causality(r.role),
        variability: match r.role {
            Role::Param => "fixed",
            _ => "continuous",
        },
        initial: match r.role {
            Role::Param => Some("exact"),
            Role::Output | Role::Local => Some("calculated"),
            Role::Input => None,
        },
        unit: r.unit,
        display_unit: r.display_unit,
        derivative,
        start: (!r.start.is_empty()).then_some(start),
        min: r.min,
        max: r.max,
        dimension: r.dimension,
        index,
    }
}

/// `ModelStructure` of a string of `n` sections: FMI 2.0 names variables by their 1-based
/// index, FMI 3.0 by value reference.
fn structure(c: &Config, n: usize, rows: &[Row], edition: Edition) -> Structure {
    let refs = |vrs: Vec<u32>| -> Vec<usize> {
        match edition {
            Edition::Fmi3 => vrs.into_iter().map(|vr| vr as usize).collect(),
            Edition::Fmi2 => vrs.iter().map(|&vr| index_of(rows, vr)).collect(),
        }
    };
    let id = |k: usize, r: &Row| match edition {
        Edition::Fmi2 => k + 1,
        Edition::Fmi3 => r.vr as usize,
    };
    let known = |(k, r): (usize, &Row)| Unknown {
        id: id(k, r),
        dependencies: Some(refs(known_dependencies(c, n, r, edition))),
    };
    let rows = || rows.iter().enumerate();
    Structure {
        outputs: rows()
            .filter(|(_, r)| r.role == Role::Output)
            .map(known)
            .collect(),
        // Model Exchange: the order of the derivatives is the order of the state vector.
        derivatives: rows()
            .filter(|(_, r)| r.derivative_of.is_some())
            .map(known)
            .collect(),
        // The outputs at initialization; the ends' points start at 0 (no dependencies), the
        // derivatives depend on every parameter and input (no `dependencies`). In index order.
        initial_unknowns: rows()
            .filter_map(|(k, r)| {
                let var = r.of.map(|o| o.0);
                let dependencies = if r.role == Role::Output {
                    Some(refs(initial_dependencies(c, r, edition)))
                } else if matches!(var, Some(StringVar::XTop | StringVar::XBottom)) {
                    Some(vec![])
                } else if r.derivative_of.is_some() {
                    None
                } else {
                    return None;
                };
                Some(Unknown {
                    id: id(k, r),
                    dependencies,
                })
            })
            .collect(),
        event_indicators: rows()
            .filter(|(_, r)| r.of.map(|o| o.0) == Some(StringVar::EventVrx))
            .map(known)
            .collect(),
    }
}
