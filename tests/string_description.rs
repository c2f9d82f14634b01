//! The model descriptions of a string of contacts: FMI 2.0 declares each array as scalars
//! `x[1]` … `x[N]`, FMI 3.0 as one variable `x` with a `Dimension`; value references are those
//! of `docs/architecture.md` (`b·1000000 + i`), unique and the same in every string; the
//! `ModelStructure` dependencies follow the equations of a section (its own inputs and
//! parameters, the law's shared ones, the ends' dampers and moving points).

use std::collections::{BTreeMap, BTreeSet};

use quick_xml::events::Event;
use quick_xml::{Reader, XmlVersion};

use vibrofric::description::{xml, xml3, Scene};

/// One element of the document: its tag, its attributes, and the tag of its parent.
#[derive(Debug, Clone)]
struct Element {
    tag: String,
    parent: String,
    attrs: BTreeMap<String, String>,
}

fn elements(doc: &str) -> Vec<Element> {
    let mut r = Reader::from_str(doc);
    let mut stack: Vec<String> = vec![];
    let mut out = vec![];
    loop {
        let (e, empty) = match r.read_event().expect("well-formed XML") {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                stack.pop();
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let tag = e.name().as_ref().to_string();
        let attrs = e
            .attributes()
            .map(|a| {
                let a = a.unwrap();
                let v = a.normalized_value(XmlVersion::Implicit1_0).unwrap();
                (a.key.as_ref().to_string(), v.into_owned())
            })
            .collect();
        out.push(Element {
            tag: tag.clone(),
            parent: stack.last().cloned().unwrap_or_default(),
            attrs,
        });
        if !empty {
            stack.push(tag);
        }
    }
    out
}

fn string_scene(sections: usize, start: &str) -> Scene {
    let text = format!(
        "model_identifier = \"S\"\nlaw = \"lugre\"\nmotion = \"longitudinal\"\ndrive = \"force\"\nnormal = \"input\"\nsupport = [\"input\"]\n[string]\nsections = {sections}\n[start]\nF_N = 2280\nmu = 0.3\nF_S = 889.2\n{start}\n"
    );
    Scene::parse(&text, "s.toml").unwrap()
}

/// The FMI 2.0 variables: name -> (1-based index, attributes of ScalarVariable).
fn fmi2_variables(els: &[Element]) -> BTreeMap<String, (usize, BTreeMap<String, String>)> {
    els.iter()
        .filter(|e| e.tag == "ScalarVariable")
        .enumerate()
        .map(|(k, e)| (e.attrs["name"].clone(), (k + 1, e.attrs.clone())))
        .collect()
}

/// The unknowns of a `ModelStructure` list: index -> dependencies (none where the attribute is
/// absent: a derivative at the start depends on everything).
fn unknowns(els: &[Element], list: &str) -> BTreeMap<usize, BTreeSet<usize>> {
    els.iter()
        .filter(|e| e.tag == "Unknown" && e.parent == list)
        .map(|e| {
            let deps = e
                .attrs
                .get("dependencies")
                .map_or("", |d| d.as_str())
                .split_whitespace()
                .map(|d| d.parse().unwrap())
                .collect();
            (e.attrs["index"].parse().unwrap(), deps)
        })
        .collect()
}

#[test]
fn fmi2_writes_arrays_as_scalars_with_stable_unique_value_references() {
    let s = string_scene(3, "m = [1.0, 2.0, 3.0]\nk_s = 7.1e7\nc_top = 1e4");
    let doc = xml::model_description(&s);
    let els = elements(&doc);
    assert!(els.iter().any(|e| e.tag == "CoSimulation"));
    assert!(
        els.iter().any(|e| e.tag == "ModelExchange"),
        "a string offers Model Exchange"
    );
    let vars = fmi2_variables(&els);
    let vr = |name: &str| -> u32 { vars[name].1["valueReference"].parse().unwrap() };
    for (name, base) in [
        ("x", 203),
        ("v_x", 205),
        ("s_x", 207),
        ("F_Fx", 201),
        ("F_Fx_step", 212),
        ("m", 1),
        ("mu", 3),
        ("F_N", 2),
        ("F_S", 7),
        ("F_d", 101),
        ("v_sx", 103),
    ] {
        for i in 1..=3u32 {
            assert_eq!(
                vr(&format!("{name}[{i}]")),
                base * 1_000_000 + i,
                "{name}[{i}]"
            );
        }
        assert!(!vars.contains_key(&format!("{name}[4]")) && !vars.contains_key(name));
    }
    for (name, base) in [("k_s", 25), ("c_s", 26), ("F_link", 220)] {
        for i in 1..=2u32 {
            assert_eq!(vr(&format!("{name}[{i}]")), base * 1_000_000 + i);
        }
        assert!(!vars.contains_key(&format!("{name}[3]")));
    }
    for (name, v) in [
        ("k_top", 21),
        ("c_top", 22),
        ("k_bottom", 23),
        ("c_bottom", 24),
        ("v_top", 105),
        ("v_bottom", 106),
        ("F_top", 221),
        ("F_bottom", 222),
        ("F_top_step", 223),
        ("F_bottom_step", 224),
        ("k_t", 4),
        ("zeta_t", 9),
    ] {
        assert_eq!(vr(name), v, "{name}");
    }
    // Every value reference once; no single-contact variable a string replaces.
    let vrs: BTreeSet<u32> = vars.keys().map(|n| vr(n)).collect();
    assert_eq!(vrs.len(), vars.len());
    for gone in ["T_avg", "F_mean", "reduction", "P_diss"] {
        assert!(!vars.contains_key(gone), "{gone}");
    }
    // Start values per element; causalities.
    let attr = |name: &str, a: &str| vars[name].1.get(a).cloned();
    let real = |name: &str| -> BTreeMap<String, String> {
        // The Real element follows its ScalarVariable.
        let k = els
            .iter()
            .position(|e| e.tag == "ScalarVariable" && e.attrs["name"] == name)
            .unwrap();
        els[k + 1].attrs.clone()
    };
    assert_eq!(real("m[2]")["start"], "2");
    assert_eq!(real("k_s[1]")["start"], "7.1e7");
    assert_eq!(real("F_N[3]")["start"], "2280");
    assert_eq!(real("x[1]")["unit"], "m");
    assert_eq!(real("x[1]").get("start"), None);
    assert_eq!(attr("F_N[1]", "causality").as_deref(), Some("input"));
    assert_eq!(attr("m[1]", "causality").as_deref(), Some("parameter"));
    assert_eq!(attr("F_link[2]", "causality").as_deref(), Some("output"));
    // The same variable has the same value reference in a longer string.
    let s5 = string_scene(5, "");
    let vars5 = fmi2_variables(&elements(&xml::model_description(&s5)));
    for name in ["x[3]", "F_link[2]", "k_t", "v_top", "F_bottom_step"] {
        assert_eq!(
            vars5[name].1["valueReference"],
            vars[name].1["valueReference"]
        );
    }
    assert_ne!(xml::guid(&s), xml::guid(&s5));
}

#[test]
fn fmi2_model_structure_follows_each_section() {
    let s = string_scene(3, "");
    let els = elements(&xml::model_description(&s));
    let vars = fmi2_variables(&els);
    let idx = |n: &str| vars[n].0;
    let outputs = unknowns(&els, "Outputs");
    let initial = unknowns(&els, "InitialUnknowns");
    let set = |names: &[&str]| -> BTreeSet<usize> { names.iter().map(|n| idx(n)).collect() };
    let all_outputs: BTreeSet<usize> = vars
        .values()
        .filter(|(_, a)| a["causality"] == "output")
        .map(|(k, _)| *k)
        .collect();
    assert_eq!(
        outputs.keys().copied().collect::<BTreeSet<_>>(),
        all_outputs
    );
    // At the start: the outputs, the ends' points (Model Exchange's states of their own) and
    // every derivative.
    let derivatives = unknowns(&els, "Derivatives");
    let mut starting = all_outputs.clone();
    starting.extend(set(&["x_top", "x_bottom"]));
    starting.extend(derivatives.keys().copied());
    assert_eq!(initial.keys().copied().collect::<BTreeSet<_>>(), starting);
    // LuGre's force has terms in the relative velocity and scales with the load: a section's
    // friction depends on its own deformation, velocity, wall velocity and normal force,
    // nobody else's (Model Exchange's knowns: states and inputs).
    let f_fx2 = set(&["s_x[2]", "v_x[2]", "v_sx[2]", "F_N[2]"]);
    assert_eq!(outputs[&idx("F_Fx[2]")], f_fx2);
    assert_eq!(outputs[&idx("s_x[3]")], set(&["s_x[3]", "F_N[3]"]));
    for state in ["x[1]", "v_x[2]"] {
        assert_eq!(outputs[&idx(state)], set(&[state]), "{state}");
    }
    assert_eq!(
        outputs[&idx("F_link[1]")],
        set(&["x[1]", "x[2]", "v_x[1]", "v_x[2]"])
    );
    assert_eq!(
        outputs[&idx("F_Fx_step[1]")],
        set(&["s_x[1]", "v_x[1]", "v_sx[1]", "F_N[1]"])
    );
    let top = set(&["x_top", "x[1]", "v_x[1]", "v_top"]);
    assert_eq!(outputs[&idx("F_top")], top);
    assert_eq!(outputs[&idx("F_top_step")], top);
    assert_eq!(
        outputs[&idx("F_bottom")],
        set(&["x_bottom", "x[3]", "v_x[3]", "v_bottom"])
    );
    // The derivatives, in the order of the state vector [x, v_x, s_x, x_top, x_bottom], each
    // naming its state; a section's acceleration depends on its neighbours and its own inputs
    // (banded), the first and last on the ends.
    let order: Vec<String> = els
        .iter()
        .filter(|e| e.tag == "Unknown" && e.parent == "Derivatives")
        .map(|e| {
            let k: usize = e.attrs["index"].parse().unwrap();
            vars.iter().find(|(_, v)| v.0 == k).unwrap().0.clone()
        })
        .collect();
    let mut want: Vec<String> = vec![];
    for v in ["x", "v_x", "s_x"] {
        want.extend((1..=3).map(|i| format!("der({v}[{i}])")));
    }
    want.extend(["der(x_top)".into(), "der(x_bottom)".into()]);
    assert_eq!(order, want);
    let reals: Vec<&Element> = els.iter().filter(|e| e.tag == "Real").collect();
    assert_eq!(
        reals[idx("der(v_x[2])") - 1].attrs["derivative"],
        idx("v_x[2]").to_string()
    );
    assert_eq!(
        derivatives[&idx("der(v_x[2])")],
        set(&[
            "x[1]", "x[2]", "x[3]", "v_x[1]", "v_x[2]", "v_x[3]", "s_x[2]", "F_d[2]", "v_sx[2]",
            "F_N[2]"
        ])
    );
    assert!(derivatives[&idx("der(v_x[1])")].is_superset(&set(&["x_top", "v_top"])));
    assert!(derivatives[&idx("der(v_x[3])")].is_superset(&set(&["x_bottom", "v_bottom"])));
    assert_eq!(derivatives[&idx("der(x[2])")], set(&["v_x[2]"]));
    assert_eq!(derivatives[&idx("der(s_x[2])")], f_fx2);
    assert_eq!(derivatives[&idx("der(x_top)")], set(&["v_top"]));
    // At the start (at rest, undeformed) the friction is LuGre's damping of the relative
    // velocity: the section's own m, F_N, mu, F_S, wall velocity and the shared law.
    assert_eq!(
        initial[&idx("F_Fx[2]")],
        set(&["m[2]", "F_N[2]", "mu[2]", "F_S[2]", "k_t", "zeta_t", "h_v", "v_e", "v_sx[2]"])
    );
    assert_eq!(initial[&idx("F_Fx_step[1]")], initial[&idx("F_Fx[1]")]);
    assert_eq!(initial[&idx("F_top")], set(&["c_top", "v_top"]));
    assert!(initial[&idx("x[3]")].is_empty() && initial[&idx("F_link[2]")].is_empty());
}

#[test]
fn fmi3_writes_one_array_variable_with_its_dimension() {
    let s = string_scene(4, "m = [1.0, 2.0, 3.0, 4.0]");
    let els = elements(&xml3::model_description(&s));
    assert!(els.iter().any(|e| e.tag == "ModelExchange"));
    let vars: BTreeMap<String, (usize, BTreeMap<String, String>)> = els
        .iter()
        .enumerate()
        .filter(|(_, e)| e.tag == "Float64" && e.parent == "ModelVariables")
        .map(|(k, e)| (e.attrs["name"].clone(), (k, e.attrs.clone())))
        .collect();
    let dimension = |name: &str| -> Option<String> {
        let k = vars[name].0;
        let next = els.get(k + 1)?;
        (next.tag == "Dimension" && next.parent == "Float64").then(|| next.attrs["start"].clone())
    };
    for (name, vr, n) in [
        ("x", 203_000_000, "4"),
        ("F_Fx", 201_000_000, "4"),
        ("F_link", 220_000_000, "3"),
        ("k_s", 25_000_000, "3"),
        ("m", 1_000_000, "4"),
        ("v_sx", 103_000_000, "4"),
    ] {
        assert_eq!(vars[name].1["valueReference"], vr.to_string(), "{name}");
        assert_eq!(dimension(name).as_deref(), Some(n), "{name}");
    }
    for scalar in ["k_t", "k_top", "v_top", "F_bottom", "time"] {
        assert_eq!(dimension(scalar), None, "{scalar}");
    }
    assert_eq!(vars["m"].1["start"], "1 2 3 4");
    assert_eq!(vars["F_N"].1["start"], "2280 2280 2280 2280");
    assert!(!vars.contains_key("x[1]"));
    let vrs: BTreeSet<&String> = vars.values().map(|(_, a)| &a["valueReference"]).collect();
    assert_eq!(vrs.len(), vars.len());
    let deps = |tag: &str, vr: u32| -> String {
        els.iter()
            .find(|e| e.tag == tag && e.attrs["valueReference"] == vr.to_string())
            .unwrap()
            .attrs["dependencies"]
            .clone()
    };
    // Model Exchange's knowns, whole arrays: states and inputs.
    assert_eq!(
        deps("Output", 201_000_000),
        "2000000 103000000 205000000 207000000"
    );
    assert_eq!(deps("Output", 203_000_000), "203000000");
    assert_eq!(deps("Output", 221), "105 309 203000000 205000000");
    assert_eq!(
        deps("ContinuousStateDerivative", 405_000_000),
        "105 106 309 310 2000000 101000000 103000000 203000000 205000000 207000000"
    );
    assert_eq!(deps("EventIndicator", 501_000_000), "103000000 205000000");
    assert_eq!(vars["der(x)"].1["derivative"], "203000000");
    assert_eq!(dimension("der(v_x)").as_deref(), Some("4"));
    let order: Vec<&String> = els
        .iter()
        .filter(|e| e.tag == "ContinuousStateDerivative")
        .map(|e| &e.attrs["valueReference"])
        .collect();
    assert_eq!(order, ["403000000", "405000000", "401000000", "409", "410"]);
    assert_eq!(
        deps("InitialUnknown", 201_000_000),
        "4 9 10 11 1000000 2000000 3000000 7000000 103000000"
    );
}
