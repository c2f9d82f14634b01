//! What both editions' model descriptions, and those of strings of contacts, write alike: the
//! XML helpers, units, log categories and the default experiment.

use quick_xml::events::{BytesEnd, BytesStart, Event};
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
