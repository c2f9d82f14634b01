//! The generated model descriptions: checked-in copies, per-scene variable lists, value
//! references, GUIDs and the consistency of `ModelStructure`.
//!
//! When a change to the table, the scenes or the writer is intended, regenerate the checked-in
//! copies with
//!
//! ```text
//! UPDATE_DESCRIPTIONS=1 cargo test --test model_description
//! ```
//!
//! (or `cargo run --release -- export --write-descriptions modelDescription/`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use quick_xml::events::Event;
use quick_xml::Reader;
use quick_xml::XmlVersion;

mod support;

use support::scenes::{scene, standard_scenes as scenes, standard_scenes_are_the_scene_folder};
use vibrofric::description::variables::VARIABLES;
use vibrofric::description::{xml, Scene};

const REGENERATE: &str = "regenerate with `UPDATE_DESCRIPTIONS=1 cargo test --test model_description` \
    (or `cargo run --release -- export --write-descriptions modelDescription/`) and review the diff";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The one list of standard scenes names every file of `scenes/`, and the default scene is
/// the one the documentation names.
#[test]
fn standard_scenes_exist() {
    standard_scenes_are_the_scene_folder();
    assert_eq!(
        scene("contact.toml").model_identifier,
        "VibratingContact",
        "the default scene"
    );
}

#[test]
fn checked_in_descriptions_match_the_generator() {
    let dir = root().join("modelDescription");
    let update = std::env::var_os("UPDATE_DESCRIPTIONS").is_some_and(|v| v != "0");
    let mut expected_files = vec![];
    let mut drift = vec![];
    for (file, s) in scenes() {
        let xml = xml::model_description(&s);
        let path = dir.join(format!("{}.xml", s.model_identifier));
        expected_files.push(path.file_name().unwrap().to_owned());
        if update {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&path, &xml).unwrap();
            continue;
        }
        match std::fs::read_to_string(&path) {
            Ok(checked_in) if checked_in == xml => {}
            Ok(_) => drift.push(format!(
                "{} differs from the description generated from scenes/{file}",
                path.display()
            )),
            Err(e) => drift.push(format!("{}: {e}", path.display())),
        }
    }
    // No stale copies of scenes that no longer exist.
    for e in std::fs::read_dir(&dir).unwrap() {
        let name = e.unwrap().file_name();
        if !expected_files.contains(&name) {
            if update {
                std::fs::remove_file(dir.join(&name)).unwrap();
            } else {
                drift.push(format!(
                    "modelDescription/{} has no scene in scenes/",
                    name.to_string_lossy()
                ));
            }
        }
    }
    assert!(drift.is_empty(), "{}\n{REGENERATE}", drift.join("\n"));
}

/// One `ScalarVariable` as read back from the XML.
#[derive(Debug, Clone)]
struct Var {
    name: String,
    vr: u32,
    causality: String,
    variability: String,
    initial: Option<String>,
    start: Option<f64>,
    unit: String,
    /// The 1-based index of the state a derivative belongs to.
    derivative: Option<usize>,
}

/// What the tests need of a parsed model description.
#[derive(Debug, Default)]
struct Parsed {
    root: BTreeMap<String, String>,
    cs: BTreeMap<String, String>,
    units: Vec<String>,
    vars: Vec<Var>,
    /// (index, dependencies) of Outputs and InitialUnknowns.
    outputs: Vec<(usize, Option<Vec<usize>>)>,
    initial: Vec<(usize, Option<Vec<usize>>)>,
    derivatives: Vec<(usize, Option<Vec<usize>>)>,
    me: BTreeMap<String, String>,
}

fn attrs(e: &quick_xml::events::BytesStart) -> BTreeMap<String, String> {
    e.attributes()
        .map(|a| {
            let a = a.expect("well-formed attribute");
            (
                a.key.as_ref().to_string(),
                a.normalized_value(XmlVersion::Implicit1_0)
                    .expect("valid escape")
                    .into_owned(),
            )
        })
        .collect()
}

fn parse(xml: &str) -> Parsed {
    let mut r = Reader::from_str(xml);
    let mut p = Parsed::default();
    let mut section = String::new();
    let mut depth = 0usize;
    let mut current: Option<Var> = None;
    loop {
        let ev = r.read_event().expect("well-formed XML");
        let (e, empty) = match &ev {
            Event::Start(e) => (Some(e.clone()), false),
            Event::Empty(e) => (Some(e.clone()), true),
            Event::End(e) => {
                depth -= 1;
                let name = e.name().as_ref().to_string();
                if name == "ScalarVariable" {
                    p.vars.push(current.take().unwrap());
                }
                if name == "Outputs" || name == "InitialUnknowns" || name == "Derivatives" {
                    section.clear();
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let e = e.unwrap();
        let name = e.name().as_ref().to_string();
        let a = attrs(&e);
        match name.as_str() {
            "fmiModelDescription" => p.root = a,
            "CoSimulation" => p.cs = a,
            "ModelExchange" => p.me = a,
            "Unit" => p.units.push(a["name"].clone()),
            "ScalarVariable" => {
                current = Some(Var {
                    name: a["name"].clone(),
                    vr: a["valueReference"].parse().unwrap(),
                    causality: a["causality"].clone(),
                    variability: a["variability"].clone(),
                    initial: a.get("initial").cloned(),
                    start: None,
                    unit: String::new(),
                    derivative: None,
                })
            }
            "Real" => {
                let v = current.as_mut().expect("Real inside ScalarVariable");
                v.start = a.get("start").map(|s| s.parse().unwrap());
                v.unit = a["unit"].clone();
                v.derivative = a.get("derivative").map(|d| d.parse().unwrap());
            }
            "Outputs" | "InitialUnknowns" | "Derivatives" => section = name.clone(),
            "Unknown" => {
                let index = a["index"].parse().unwrap();
                let deps = a.get("dependencies").map(|d| {
                    d.split_whitespace()
                        .map(|i| i.parse().unwrap())
                        .collect::<Vec<usize>>()
                });
                match section.as_str() {
                    "Outputs" => p.outputs.push((index, deps)),
                    "InitialUnknowns" => p.initial.push((index, deps)),
                    "Derivatives" => p.derivatives.push((index, deps)),
                    s => panic!("Unknown outside Outputs/InitialUnknowns ({s})"),
                }
            }
            _ => {}
        }
        if !empty {
            depth += 1;
        }
    }
    assert_eq!(depth, 0, "unbalanced XML");
    p
}

#[test]
fn descriptions_are_well_formed_and_model_structure_is_consistent() {
    for (file, s) in scenes() {
        let p = parse(&xml::model_description(&s));
        assert_eq!(p.root["fmiVersion"], "2.0");
        assert_eq!(p.root["modelName"], s.model_identifier);
        assert_eq!(p.root["guid"], xml::guid(&s));
        assert_eq!(p.root["variableNamingConvention"], "flat");
        assert_eq!(p.cs["modelIdentifier"], s.model_identifier);
        for flag in [
            "canHandleVariableCommunicationStepSize",
            "canGetAndSetFMUstate",
            "canSerializeFMUstate",
            "canNotUseMemoryManagementFunctions",
        ] {
            assert_eq!(p.cs[flag], "true", "{file}: {flag}");
        }
        let has_input = p.vars.iter().any(|v| v.causality == "input");
        assert_eq!(p.cs["canInterpolateInputs"], has_input.to_string());

        // Units: every unit used is defined, and only those.
        for v in &p.vars {
            assert!(
                p.units.contains(&v.unit),
                "{file}: unit {} of {}",
                v.unit,
                v.name
            );
        }
        for u in &p.units {
            assert!(
                p.vars.iter().any(|v| &v.unit == u),
                "{file}: unused unit {u}"
            );
        }

        // Start values: parameters and inputs have one, calculated outputs none.
        for v in &p.vars {
            match v.causality.as_str() {
                "parameter" => {
                    assert_eq!(v.initial.as_deref(), Some("exact"));
                    assert!(v.start.is_some(), "{file}: {}", v.name);
                }
                "input" => {
                    assert_eq!(v.initial, None);
                    assert!(v.start.is_some(), "{file}: {}", v.name);
                    assert_eq!(v.variability, "continuous");
                }
                "output" | "local" => {
                    assert_eq!(v.initial.as_deref(), Some("calculated"));
                    assert_eq!(v.start, None, "{file}: {}", v.name);
                    assert_eq!(v.variability, "continuous");
                }
                c => panic!("{file}: causality {c}"),
            }
        }

        // Model Exchange: the states are the variables a derivative names; Derivatives lists
        // every derivative in index order; event indicators as the configuration has them.
        assert_eq!(p.me["modelIdentifier"], s.model_identifier);
        assert_eq!(p.me["providesDirectionalDerivative"], "true");
        assert_eq!(
            p.root["numberOfEventIndicators"],
            s.config.event_indicators().to_string()
        );
        let states: Vec<usize> = p.vars.iter().filter_map(|v| v.derivative).collect();
        let der_idx: Vec<usize> = p
            .vars
            .iter()
            .enumerate()
            .filter(|(_, v)| v.derivative.is_some())
            .map(|(i, _)| i + 1)
            .collect();
        let listed: Vec<usize> = p.derivatives.iter().map(|(i, _)| *i).collect();
        assert_eq!(listed, der_idx, "{file}: ModelStructure/Derivatives");
        assert!(!states.is_empty(), "{file}: no continuous states");
        for &x in &states {
            assert_eq!(p.vars[x - 1].causality, "local", "{file}: state {x}");
        }
        let known = |d: usize| p.vars[d - 1].causality == "input" || states.contains(&d);
        for (i, deps) in p.derivatives.iter().chain(&p.outputs) {
            let deps = deps
                .as_ref()
                .expect("Derivatives and Outputs state their dependencies");
            for &d in deps {
                assert!(
                    known(d),
                    "{file}: {} depends on {}, not an input or a state",
                    p.vars[i - 1].name,
                    p.vars[d - 1].name
                );
            }
        }

        // Outputs: exactly the output variables, sorted by index; dependencies on inputs and
        // states only.
        let out_idx: Vec<usize> = p
            .vars
            .iter()
            .enumerate()
            .filter(|(_, v)| v.causality == "output")
            .map(|(i, _)| i + 1)
            .collect();
        let listed: Vec<usize> = p.outputs.iter().map(|(i, _)| *i).collect();
        assert_eq!(listed, out_idx, "{file}: ModelStructure/Outputs");
        for (i, deps) in &p.outputs {
            let deps = deps.as_ref().expect("Outputs state their dependencies");
            assert!(
                deps.windows(2).all(|w| w[0] < w[1]),
                "{file}: {i}: {deps:?}"
            );
        }
        // InitialUnknowns: every calculated output, state and derivative (not the event
        // indicators, locals of their own); dependencies on
        // inputs and exact parameters.
        let init_idx: Vec<usize> = p.initial.iter().map(|(i, _)| *i).collect();
        let mut want = out_idx.clone();
        want.extend(
            p.vars
                .iter()
                .enumerate()
                .filter(|(i, v)| v.derivative.is_some() || states.contains(&(i + 1)))
                .map(|(i, _)| i + 1),
        );
        assert_eq!(init_idx, want, "{file}: ModelStructure/InitialUnknowns");
        for (i, deps) in &p.initial {
            if let Some(deps) = deps {
                assert!(
                    deps.windows(2).all(|w| w[0] < w[1]),
                    "{file}: {i}: {deps:?}"
                );
                for d in deps {
                    let v = &p.vars[d - 1];
                    assert!(
                        v.causality == "input" || v.initial.as_deref() == Some("exact"),
                        "{file}: initial unknown {} depends on {}",
                        p.vars[i - 1].name,
                        v.name
                    );
                }
            }
        }
    }
}

#[test]
fn each_scene_has_exactly_the_variables_spec_3_implies() {
    // Parameters, inputs and outputs (the states of Model Exchange below).
    let expect = |file: &str, want: &[&str]| {
        let p = parse(&xml::model_description(&scene(file)));
        let named: Vec<&str> = p
            .vars
            .iter()
            .filter(|v| v.causality != "local")
            .map(|v| v.name.as_str())
            .collect();
        assert_eq!(named, want, "scenes/{file}");
    };
    let states = |file: &str| -> Vec<String> {
        let p = parse(&xml::model_description(&scene(file)));
        let idx: Vec<usize> = p.vars.iter().filter_map(|v| v.derivative).collect();
        idx.iter().map(|i| p.vars[i - 1].name.clone()).collect()
    };
    // A planar force drive integrates deformation and body; a longitudinal velocity drive
    // only the deformation and the imposed position; both the window's integral.
    assert_eq!(
        states("contact.toml"),
        [
            "contact.s_x",
            "contact.s_y",
            "body.x",
            "body.y",
            "body.v_x",
            "body.v_y",
            "window.F_int"
        ]
    );
    assert_eq!(
        states("paper-longitudinal.toml"),
        ["contact.s_x", "body.x", "window.F_int"]
    );
    assert_eq!(
        states("rig-longitudinal.toml"),
        [
            "contact.s_x",
            "body.x",
            "body.v_x",
            "drive.x_d",
            "window.F_int"
        ]
    );
    let outputs_planar = [
        "F_Fx",
        "F_Fy",
        "x",
        "y",
        "v_x",
        "v_y",
        "s_x",
        "s_y",
        "F_mean",
        "reduction",
        "P_diss",
        "F_Fx_step",
        "F_Fy_step",
    ];
    let outputs_long = [
        "F_Fx",
        "x",
        "v_x",
        "s_x",
        "F_mean",
        "reduction",
        "P_diss",
        "F_Fx_step",
    ];
    let cat = |a: &[&'static str], b: &[&'static str]| -> Vec<&'static str> {
        a.iter().chain(b).copied().collect()
    };
    // `reduction` is the velocity drive's only: force and spring drives have none.
    let driven = |o: &[&'static str]| -> Vec<&'static str> {
        o.iter().copied().filter(|n| *n != "reduction").collect()
    };
    expect(
        "contact.toml",
        &cat(
            &[
                "m",
                "F_N",
                "mu",
                "k_t",
                "u0",
                "f",
                "angle",
                "phase",
                "T_avg",
                "max_steps",
                "F_d",
                "v_sx",
                "v_sy",
            ],
            &driven(&outputs_planar),
        ),
    );
    expect(
        "contact-lugre.toml",
        &cat(
            &[
                "m",
                "F_N",
                "mu",
                "k_t",
                "F_S",
                "v_S",
                "zeta_t",
                "h_v",
                "v_e",
                "u0",
                "f",
                "angle",
                "phase",
                "T_avg",
                "max_steps",
                "F_d",
                "v_sx",
                "v_sy",
            ],
            &driven(&outputs_planar),
        ),
    );
    expect(
        "contact-dupont.toml",
        &cat(
            &[
                "m",
                "F_N",
                "mu",
                "k_t",
                "r_ba",
                "u0",
                "f",
                "angle",
                "phase",
                "T_avg",
                "max_steps",
                "F_d",
                "v_sx",
                "v_sy",
            ],
            &driven(&outputs_planar),
        ),
    );
    // Velocity drive along x: no body mass, no F_d input; longitudinal Dahl has kappa.
    expect(
        "paper-longitudinal.toml",
        &cat(
            &[
                "F_N",
                "mu",
                "k_t",
                "kappa",
                "u0",
                "f",
                "phase",
                "T_avg",
                "max_steps",
                "v_d",
            ],
            &outputs_long,
        ),
    );
    // Lateral free: the body moves along y, so it has a mass.
    expect(
        "paper-transverse.toml",
        &cat(
            &[
                "m",
                "F_N",
                "mu",
                "k_t",
                "u0",
                "f",
                "angle",
                "phase",
                "T_avg",
                "max_steps",
                "v_d",
            ],
            &outputs_planar,
        ),
    );
    expect(
        "paper-transverse-guided.toml",
        &cat(
            &[
                "F_N",
                "mu",
                "k_t",
                "u0",
                "f",
                "angle",
                "phase",
                "T_avg",
                "max_steps",
                "v_d",
            ],
            &outputs_planar,
        ),
    );
    // Input support only: no harmonic parameters; longitudinal: no v_sy.
    expect(
        "drill-string-axial.toml",
        &cat(
            &[
                "m",
                "F_N",
                "mu",
                "k_t",
                "F_S",
                "v_S",
                "zeta_t",
                "h_v",
                "v_e",
                "T_avg",
                "max_steps",
                "F_d",
                "v_sx",
            ],
            &driven(&outputs_long),
        ),
    );
    // The normal force an input: the same variables, F_N now an input (same value reference).
    expect(
        "drill-string-contact.toml",
        &cat(
            &[
                "m",
                "F_N",
                "mu",
                "k_t",
                "F_S",
                "v_S",
                "zeta_t",
                "h_v",
                "v_e",
                "T_avg",
                "max_steps",
                "F_d",
                "v_sx",
            ],
            &driven(&outputs_long),
        ),
    );
    let p = parse(&xml::model_description(&scene("drill-string-contact.toml")));
    let f_n = p.vars.iter().find(|v| v.name == "F_N").unwrap();
    assert_eq!(
        (f_n.causality.as_str(), f_n.variability.as_str(), f_n.start),
        ("input", "continuous", Some(2280.0))
    );
    // Spring drive: k_d, c_d, v_d input, F_d output.
    expect(
        "rig-longitudinal.toml",
        &cat(
            &[
                "m",
                "F_N",
                "mu",
                "k_t",
                "kappa",
                "u0",
                "f",
                "phase",
                "k_d",
                "c_d",
                "T_avg",
                "max_steps",
                "F_d",
                "v_d",
            ],
            &driven(&outputs_long),
        ),
    );
    let rig = parse(&xml::model_description(&scene("rig-longitudinal.toml")));
    let f_d = rig.vars.iter().find(|v| v.name == "F_d").unwrap();
    assert_eq!((f_d.vr, f_d.causality.as_str()), (101, "output"));
}

#[test]
fn value_references_are_stable_across_scenes() {
    let mut seen: BTreeMap<String, u32> = BTreeMap::new();
    for (file, s) in scenes() {
        let p = parse(&xml::model_description(&s));
        for v in &p.vars {
            let table = VARIABLES.iter().find(|t| t.name() == v.name).unwrap();
            assert_eq!(v.vr, table.vr, "{file}: {}", v.name);
            if let Some(vr) = seen.insert(v.name.clone(), v.vr) {
                assert_eq!(vr, v.vr, "{file}: {}", v.name);
            }
            assert!(s.has_vr(v.vr));
        }
        // Value references of variables the scene leaves out are not in it.
        for t in VARIABLES.iter() {
            if !p.vars.iter().any(|v| v.vr == t.vr) {
                assert!(!s.has_vr(t.vr), "{file}: {}", t.name());
            }
        }
    }
}

#[test]
fn start_values_follow_the_scene() {
    let p = parse(&xml::model_description(&scene("paper-transverse.toml")));
    let start = |n: &str| p.vars.iter().find(|v| v.name == n).unwrap().start;
    assert_eq!(start("angle"), Some(std::f64::consts::FRAC_PI_2));
    assert_eq!(start("k_t"), Some(1e8));
    assert_eq!(start("v_d"), Some(1e-3), "the documented default of v_d");
    assert_eq!(start("F_Fx"), None);
}

#[test]
fn guids_differ_between_scenes_and_with_start_values() {
    let all = scenes();
    let guids: Vec<String> = all.iter().map(|(_, s)| xml::guid(s)).collect();
    for (i, a) in guids.iter().enumerate() {
        assert_eq!(a.len(), 38, "{a}");
        assert!(a.starts_with('{') && a.ends_with('}'));
        for b in &guids[i + 1..] {
            assert_ne!(a, b);
        }
    }
    // Same scene text, one start value changed (the scene already has a [start] table).
    let base = scene("contact.toml");
    let text = base.source.replace("[start]", "[start]\nk_t = 2e8");
    assert_ne!(text, base.source);
    let changed = Scene::parse(&text, "contact.toml").unwrap();
    assert_ne!(xml::guid(&base), xml::guid(&changed));
    // Deterministic.
    assert_eq!(xml::guid(&base), xml::guid(&scene("contact.toml")));
    // The GUID in the document is the one computed.
    assert!(xml::model_description(&base).contains(&xml::guid(&base)));
}

#[test]
fn initial_unknowns_of_lugre_depend_on_the_relative_velocity() {
    // LuGre at rest with zero deformation: F_F = (h_t + h_v)·v_r, v_r from v_d and the source.
    let s = scene("contact-lugre.toml");
    let p = parse(&xml::model_description(&s));
    let idx = |n: &str| p.vars.iter().position(|v| v.name == n).unwrap() + 1;
    let deps = |n: &str| -> Vec<&str> {
        let (_, d) = p.initial.iter().find(|(i, _)| *i == idx(n)).unwrap();
        d.as_ref()
            .unwrap()
            .iter()
            .map(|i| p.vars[i - 1].name.as_str())
            .collect()
    };
    let f = deps("F_Fx");
    for n in [
        "m", "k_t", "zeta_t", "v_e", "h_v", "u0", "f", "phase", "angle", "v_sx", "v_sy",
    ] {
        assert!(f.contains(&n), "F_Fx initial dependencies {f:?} lack {n}");
    }
    assert!(deps("x").is_empty());
    // Under the velocity drive reduction = 1 − F_mean/F_C depends on F_C (through mu).
    let pv = parse(&xml::model_description(&scene("paper-longitudinal.toml")));
    let r = pv.vars.iter().position(|v| v.name == "reduction").unwrap() + 1;
    let (_, rd) = pv.initial.iter().find(|(i, _)| *i == r).unwrap();
    assert!(rd
        .as_ref()
        .unwrap()
        .iter()
        .any(|i| pv.vars[i - 1].name == "mu"));
    // Dahl at rest: F_F = k_t·s = 0.
    let d = parse(&xml::model_description(&scene("contact.toml")));
    assert!(d.initial.iter().all(|(i, deps)| {
        let v = &d.vars[i - 1];
        v.name == "reduction" || v.derivative.is_some() || deps.as_ref().unwrap().is_empty()
    }));
}

#[test]
fn exporter_writes_a_complete_fmu() {
    let exe = env!("CARGO_BIN_EXE_vibrofric");
    let out = std::env::temp_dir().join(format!("vibrofric-export-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    // The host's library only (the cross builds are the test command's export, tests/all.sh).
    let run = std::process::Command::new(exe)
        .current_dir(root())
        .env("VIBROFRIC_PORTABLE", "0")
        .args([
            "export",
            "scenes/paper-longitudinal.toml",
            "--platforms",
            "linux64",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        stdout.contains("platforms in each FMU: FMI 3.0 linux64; FMI 2.0 linux64\n"),
        "{stdout}"
    );
    // The cdylib is built with the tests (the harness loads it too): its absence is a failure,
    // not a reason to skip.
    assert!(
        !stderr.contains("cannot find libvibrofric"),
        "the exporter found no cdylib next to {exe}: {stderr}"
    );
    assert!(run.status.success(), "{stderr}");
    let fmu = out.join("PaperLongitudinal.fmu");
    let mut zip = zip::ZipArchive::new(std::fs::File::open(&fmu).unwrap()).unwrap();
    let mut names: Vec<String> = zip.file_names().map(|n| n.unwrap().into_owned()).collect();
    names.sort();
    assert_eq!(
        names,
        [
            "binaries/linux64/PaperLongitudinal.so",
            "documentation/index.html",
            "modelDescription.xml",
            "resources/scene.toml",
        ]
    );
    let read = |zip: &mut zip::ZipArchive<std::fs::File>, n: &str| {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut zip.by_name(n).unwrap(), &mut s).unwrap();
        s
    };
    let s = scene("paper-longitudinal.toml");
    assert_eq!(
        read(&mut zip, "modelDescription.xml"),
        xml::model_description(&s)
    );
    assert_eq!(read(&mut zip, "resources/scene.toml"), s.source);
    let doc = read(&mut zip, "documentation/index.html");
    for needle in ["PaperLongitudinal", "kappa", "F_mean", "<table>", "Dahl"] {
        assert!(doc.contains(needle), "documentation lacks {needle}");
    }
    assert!(!doc.contains("<script"));
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn exporter_refuses_a_bad_scene_and_names_it() {
    let exe = env!("CARGO_BIN_EXE_vibrofric");
    let dir = std::env::temp_dir().join(format!("vibrofric-bad-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        "model_identifier = \"Bad\"\nlaw = \"dahl\"\nmotion = \"longitudinal\"\nsupport = [\"harmonic\"]\noutputs = [\"F_Fy\"]\n",
    )
    .unwrap();
    let run = std::process::Command::new(exe)
        .arg("export")
        .arg(&bad)
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    assert!(!run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr
            .contains("bad.toml:5: outputs = \"F_Fy\": not an output of a dahl longitudinal scene"),
        "{stderr}"
    );
    assert!(!dir.join("Bad.fmu").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn documentation_lists_every_variable() {
    for (file, s) in scenes() {
        let doc = vibrofric_docs::docs::index_html(&s);
        for v in s.variables() {
            assert!(
                doc.contains(&format!("<td><code>{}</code></td>", v.name())),
                "{file}: {}",
                v.name()
            );
        }
        assert!(doc.contains(&s.model_identifier));
        let _ = Path::new(&file);
    }
}

/// Values of every output of a scene, by value reference.
fn output_values(s: &Scene, o: &vibrofric::model::Outputs) -> Vec<(u32, f64)> {
    use vibrofric::description::variables::{Causality, VarKind};
    use vibrofric::model::OutputId;
    s.variables()
        .filter(|v| v.causality(&s.config) == Causality::Output)
        .map(|v| {
            let id = match v.kind {
                VarKind::Output(id) => id,
                _ => OutputId::FDrive, // F_d as the spring drive's output
            };
            (v.vr, id.get(o))
        })
        .collect()
}

/// Other values of a variable (those that break its rule are skipped).
fn perturbed(x: f64) -> [f64; 3] {
    [x * 0.5 + 1e-4, x * 1.5 + 0.3, 0.0]
}

#[test]
fn initial_unknown_dependencies_hold_in_the_core() {
    use vibrofric::description::variables::VarKind;
    use vibrofric::model::Setup;
    for (file, s) in scenes() {
        let at_start = |params: vibrofric::table::Params, inputs: vibrofric::model::Inputs| {
            let sim = Setup::new(s.config, params).inputs(inputs).build().unwrap();
            output_values(&s, &sim.outputs())
        };
        let base = at_start(s.start, s.inputs);
        for known in s.variables() {
            if !known.settable(&s.config) {
                continue;
            }
            for value in perturbed(s.start_of(known).unwrap()) {
                let (mut params, mut inputs) = (s.start, s.inputs);
                match known.kind {
                    VarKind::Param(p) => {
                        if p.set(&mut params, value).is_err() {
                            continue;
                        }
                    }
                    VarKind::Input(i) => *i.slot(&mut inputs) = value,
                    _ => unreachable!("only parameters and inputs are settable"),
                }
                // A LuGre static force below the Coulomb force is refused as a combination.
                let lugre = s.config.law == vibrofric::model::Law::LuGre;
                if lugre && params.static_force_inverted().is_some() {
                    continue;
                }
                let changed = at_start(params, inputs);
                for ((vr, a), (_, b)) in base.iter().zip(&changed) {
                    if a.to_bits() == b.to_bits() {
                        continue;
                    }
                    let out = VARIABLES.iter().find(|v| v.vr == *vr).unwrap();
                    let deps = out.initial_dependencies(&s.config);
                    assert!(
                        deps.iter().any(|d| d.vr() == known.vr),
                        "{file}: at the start {} changes ({a} -> {b}) with {} = {value}, but InitialUnknowns does not list {}",
                        out.name(),
                        known.name(),
                        known.name()
                    );
                }
            }
        }
    }
}

#[test]
fn output_dependencies_hold_in_the_core() {
    use vibrofric::description::variables::{Causality, VarKind};
    use vibrofric::model::{build, InputId};
    for (file, s) in scenes() {
        let mut sim = build(s.config, s.start, 0.0, 1e-6).unwrap();
        // Move away from the start: some deformation, some velocity.
        for i in InputId::ALL {
            if i.present(&s.config) {
                let v = match i {
                    InputId::FD => 3.0,
                    InputId::VD => 1e-3,
                    _ => 2e-4,
                };
                sim.set_input(i, v).unwrap();
            }
        }
        sim.step_to(2.3e-4).unwrap();
        let base = output_values(&s, &sim.outputs());
        for i in InputId::ALL {
            if !i.present(&s.config) {
                continue;
            }
            let mut other = sim.clone_box();
            other.set_input(i, i.get(&sim.inputs()) + 2.1e-3).unwrap();
            let changed = output_values(&s, &other.outputs());
            for ((vr, a), (_, b)) in base.iter().zip(&changed) {
                if a.to_bits() == b.to_bits() {
                    continue;
                }
                let out = VARIABLES.iter().find(|v| v.vr == *vr).unwrap();
                assert_eq!(out.causality(&s.config), Causality::Output);
                assert!(
                    out.input_dependencies(&s.config).contains(&i),
                    "{file}: {} changes at once with {} ({a} -> {b}) but ModelStructure/Outputs does not list it",
                    out.name(),
                    i.name()
                );
            }
        }
        // Model Exchange: an output that changes with a continuous state lists it.
        for v in s.variables() {
            let VarKind::State(x) = v.kind else { continue };
            let mut other = sim.clone_box();
            let mut states = other.states();
            states[x.index()] = states[x.index()] * 1.5 + 1e-8;
            other.set_states(&states).unwrap();
            let changed = output_values(&s, &other.outputs());
            for ((vr, a), (_, b)) in base.iter().zip(&changed) {
                if a.to_bits() == b.to_bits() || (a - b).abs() <= 1e-12 * a.abs() {
                    continue;
                }
                let out = VARIABLES.iter().find(|v| v.vr == *vr).unwrap();
                assert!(
                    out.known_dependencies(&s.config, &s.outputs).contains(&x.vr()),
                    "{file}: {} changes with the state {} ({a} -> {b}) but ModelStructure/Outputs does not list it",
                    out.name(),
                    x.name()
                );
            }
        }
    }
}
