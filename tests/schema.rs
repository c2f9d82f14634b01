//! The checked-in model descriptions read back with rust-fmi's `fmi-schema` (the FMI 2.0 schema
//! as Rust types, a parser that shares nothing with vibrofric's writer) and compared with the
//! variable table: every variable with its value reference, causality, variability, `initial`,
//! start value and description, and `ModelStructure` with the dependencies the table declares.
//! The FMI 3.0 descriptions likewise, with the schema's FMI 3.0 types.

use std::path::PathBuf;
use std::str::FromStr;

use fmi_schema::fmi2::{Causality as SchemaCausality, Fmi2ModelDescription, ScalarVariableElement};
use vibrofric::description::variables::{Causality, Initial, Variability};
use vibrofric::description::Scene;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every standard scene with its checked-in model description, parsed by the schema.
fn described_scenes() -> Vec<(Scene, Fmi2ModelDescription)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "the standard scenes are missing");
    files
        .iter()
        // A string of contacts has rows of its own (tests/string_description.rs).
        .map(|path| Scene::load(path).unwrap_or_else(|e| panic!("{e}")))
        .filter(|scene| scene.string.is_none())
        .map(|scene| {
            let xml_path = root()
                .join("modelDescription")
                .join(format!("{}.xml", scene.model_identifier));
            let xml = std::fs::read_to_string(&xml_path).unwrap();
            let md = Fmi2ModelDescription::from_str(&xml)
                .unwrap_or_else(|e| panic!("{}: {e:?}", xml_path.display()));
            (scene, md)
        })
        .collect()
}

#[test]
fn descriptions_are_fmi2_co_simulation_and_model_exchange_of_their_scene() {
    for (scene, md) in described_scenes() {
        assert_eq!(md.fmi_version, "2.0");
        assert_eq!(md.model_name, scene.model_identifier);
        let cs = md.co_simulation.as_ref().expect("a CoSimulation element");
        assert_eq!(cs.model_identifier, scene.model_identifier);
        let me = md.model_exchange.as_ref().expect("a ModelExchange element");
        assert_eq!(me.model_identifier, scene.model_identifier);
        assert_eq!(
            md.number_of_event_indicators,
            Some(scene.config.event_indicators() as u32)
        );
        assert_eq!(md.description.as_deref(), Some(scene.description.as_str()));
    }
}

#[test]
fn every_variable_is_the_table_row_of_its_scene() {
    for (scene, md) in described_scenes() {
        let c = &scene.config;
        let rows: Vec<_> = scene.variables().collect();
        let vars = &md.model_variables.variables;
        assert_eq!(vars.len(), rows.len(), "{}", scene.model_identifier);
        for (v, row) in vars.iter().zip(&rows) {
            let id = format!("{} {}", scene.model_identifier, row.name());
            assert_eq!(v.name, row.name(), "{id}");
            assert_eq!(v.value_reference, row.vr, "{id}");
            assert_eq!(v.description.as_deref(), Some(row.description), "{id}");
            let causality = match row.causality(c) {
                Causality::Parameter => SchemaCausality::Parameter,
                Causality::Input => SchemaCausality::Input,
                Causality::Output => SchemaCausality::Output,
                Causality::Local => SchemaCausality::Local,
            };
            assert_eq!(v.causality, causality, "{id}");
            let variability = v.variability.as_ref().map(|x| x.to_string());
            assert_eq!(
                variability.as_deref(),
                Some(row.variability(c).as_str()),
                "{id}"
            );
            let initial = v.initial.as_ref().map(|x| x.to_string());
            assert_eq!(
                initial.as_deref(),
                row.initial(c).map(Initial::as_str),
                "{id}"
            );
            let ScalarVariableElement::Real(real) = &v.elem else {
                panic!("{id}: every variable is Real");
            };
            let start = scene.start_of(row);
            assert_eq!(real.start, start, "{id}");
            if row.causality(c) == Causality::Input {
                assert_eq!(row.variability(c), Variability::Continuous, "{id}");
            }
        }
    }
}

#[test]
fn model_structure_lists_the_declared_dependencies() {
    for (scene, md) in described_scenes() {
        let c = &scene.config;
        let vars = &md.model_variables.variables;
        let vr_at = |index: u32| vars[index as usize - 1].value_reference;
        let outputs: Vec<u32> = vars
            .iter()
            .enumerate()
            .filter(|(_, v)| v.causality == SchemaCausality::Output)
            .map(|(i, _)| i as u32 + 1)
            .collect();
        let listed: Vec<u32> = md
            .model_structure
            .outputs
            .unknowns
            .iter()
            .map(|u| u.index)
            .collect();
        assert_eq!(listed, outputs, "{}", scene.model_identifier);
        // Model Exchange: every derivative, in the order of the states.
        let derivatives: Vec<u32> = scene
            .variables()
            .filter(|r| r.derivative_of().is_some())
            .map(|r| r.vr)
            .collect();
        let listed: Vec<u32> = md
            .model_structure
            .derivatives
            .unknowns
            .iter()
            .map(|u| vr_at(u.index))
            .collect();
        assert_eq!(listed, derivatives, "{}", scene.model_identifier);
        // Outputs and derivatives depend on the declared knowns: inputs and states.
        let structure = &md.model_structure;
        for u in structure
            .outputs
            .unknowns
            .iter()
            .chain(&structure.derivatives.unknowns)
        {
            let row = scene.variables().find(|r| r.vr == vr_at(u.index)).unwrap();
            let mut declared = row.known_dependencies(c, &scene.outputs);
            let mut written: Vec<u32> = u.dependencies.iter().map(|&i| vr_at(i)).collect();
            declared.sort_unstable();
            written.sort_unstable();
            assert_eq!(
                written,
                declared,
                "{} {}",
                scene.model_identifier,
                row.name()
            );
            for &d in &u.dependencies {
                assert!(matches!(
                    vars[d as usize - 1].causality,
                    SchemaCausality::Input | SchemaCausality::Local
                ));
            }
        }
        for u in &md.model_structure.initial_unknowns.unknowns {
            let row = scene.variables().find(|r| r.vr == vr_at(u.index)).unwrap();
            if row.derivative_of().is_some() {
                continue; // no dependencies attribute: all knowns
            }
            let mut declared: Vec<u32> =
                row.initial_dependencies(c).iter().map(|d| d.vr()).collect();
            let mut written: Vec<u32> = u.dependencies.iter().map(|&i| vr_at(i)).collect();
            declared.sort_unstable();
            written.sort_unstable();
            assert_eq!(
                written,
                declared,
                "{} {}",
                scene.model_identifier,
                row.name()
            );
            for &d in &u.dependencies {
                let dep = &vars[d as usize - 1];
                assert!(
                    matches!(
                        dep.causality,
                        SchemaCausality::Input | SchemaCausality::Parameter
                    ),
                    "{} {}: depends on {}",
                    scene.model_identifier,
                    row.name(),
                    dep.name
                );
            }
        }
    }
}

/// The FMI 3.0 description of every standard scene, generated and read back with `fmi-schema`'s
/// FMI 3.0 types: the same rows as FMI 2.0 (plus the independent `time`), the instantiation
/// token is the FMI 2.0 GUID, units come from declared types, and `ModelStructure` lists the
/// table's dependencies by value reference.
#[test]
fn fmi3_descriptions_are_the_table_rows_too() {
    use fmi_schema::fmi3::{
        AbstractVariableTrait, Causality as C3, Fmi3ModelDescription, InitializableVariableTrait,
        VariableDependency,
    };
    use vibrofric::description::{xml, xml3};
    for (scene, _) in described_scenes() {
        let c = &scene.config;
        let text = xml3::model_description(&scene);
        let md: Fmi3ModelDescription = fmi_schema::deserialize(&text)
            .unwrap_or_else(|e| panic!("{}: {e:?}", scene.model_identifier));
        let id = &scene.model_identifier;
        assert_eq!(md.fmi_version, "3.0");
        assert_eq!(md.instantiation_token, xml::guid(&scene));
        assert_eq!(md.co_simulation.as_ref().unwrap().model_identifier, *id);
        let vars = md.model_variables.float64();
        assert_eq!(vars.len(), scene.variables().count() + 1, "{id}");
        assert_eq!(
            (vars[0].name(), vars[0].causality()),
            ("time", C3::Independent)
        );
        for (v, row) in vars[1..].iter().zip(scene.variables()) {
            assert_eq!(v.name(), row.name(), "{id}");
            assert_eq!(v.value_reference(), row.vr, "{id}");
            let causality = match row.causality(c) {
                Causality::Parameter => C3::Parameter,
                Causality::Input => C3::Input,
                Causality::Output => C3::Output,
                Causality::Local => C3::Local,
            };
            assert_eq!(v.causality(), causality, "{id} {}", row.name());
            let start = v.start().and_then(|s| s.first().copied());
            let expected = match row.initial(c) {
                Some(Initial::Calculated) => None,
                _ => scene.start_of(row),
            };
            assert_eq!(start, expected, "{id} {}", row.name());
            let unit = v.declared_type.as_deref().unwrap();
            assert!(unit.starts_with(row.unit), "{id} {}: {unit}", row.name());
        }
        for u in &md.model_structure.unknowns {
            let (unknown, declared): (_, Vec<u32>) = match u {
                VariableDependency::Output(u) => {
                    let row = scene
                        .variables()
                        .find(|r| r.vr == u.value_reference)
                        .unwrap();
                    (u, row.known_dependencies(c, &scene.outputs))
                }
                VariableDependency::ContinuousStateDerivative(u) => {
                    let row = scene
                        .variables()
                        .find(|r| r.vr == u.value_reference)
                        .unwrap();
                    (u, row.known_dependencies(c, &scene.outputs))
                }
                VariableDependency::InitialUnknown(u) => {
                    let row = scene
                        .variables()
                        .find(|r| r.vr == u.value_reference)
                        .unwrap();
                    if row.derivative_of().is_some() {
                        continue;
                    }
                    (
                        u,
                        row.initial_dependencies(c).iter().map(|d| d.vr()).collect(),
                    )
                }
                VariableDependency::EventIndicator(u) => {
                    let row = scene
                        .variables()
                        .find(|r| r.vr == u.value_reference)
                        .unwrap();
                    (u, row.known_dependencies(c, &scene.outputs))
                }
                other => panic!("{id}: unexpected {other:?}"),
            };
            let mut written: Vec<u32> =
                unknown.dependencies.as_ref().map_or(vec![], |d| d.to_vec());
            let mut declared = declared;
            written.sort_unstable();
            declared.sort_unstable();
            assert_eq!(written, declared, "{id} vr {}", unknown.value_reference);
        }
    }
}
