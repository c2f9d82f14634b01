use super::*;

const GOOD: &str = r#"
model_identifier = "PaperLongitudinal"
description = "test"
law = "dahl"
motion = "longitudinal"
drive = "velocity"
support = ["harmonic"]
outputs = ["reduction", "F_Fx", "F_mean"]
[start]
k_t = 2e8
v_d = 5e-4
"#;

fn err(text: &str) -> String {
    Scene::parse(text, "bad.toml").unwrap_err().to_string()
}

/// A valid planar scene with one line (`line`) added before `[start]`, and `start` lines.
fn planar(line: &str, start: &str) -> String {
    format!(
            "model_identifier = \"X\"\nlaw = \"dahl\"\nmotion = \"planar\"\ndrive = \"force\"\nsupport = [\"harmonic\"]\n{line}\n[start]\n{start}\n"
        )
}

fn longitudinal(line: &str, start: &str) -> String {
    format!(
            "model_identifier = \"X\"\nlaw = \"dahl\"\nmotion = \"longitudinal\"\ndrive = \"velocity\"\nsupport = [\"harmonic\"]\n{line}\n[start]\n{start}\n"
        )
}

#[test]
fn good_scene_reads() {
    let s = Scene::parse(GOOD, "good.toml").unwrap();
    assert_eq!(s.model_identifier, "PaperLongitudinal");
    assert_eq!(s.config.law, Law::Dahl);
    assert_eq!(s.config.motion, Motion::Longitudinal);
    assert_eq!(s.config.drive, Drive::Velocity);
    assert!(s.config.harmonic && !s.config.input_support);
    assert_eq!(
        s.outputs,
        vec![OutputId::FFx, OutputId::FMean, OutputId::Reduction]
    );
    assert_eq!(s.start.k_t, 2e8);
    assert_eq!(s.inputs.v_d, 5e-4);
    assert_eq!(s.source, GOOD);
    assert!(s.has_vr(201) && !s.has_vr(202) && !s.has_vr(203));
    assert!(s.has_vr(102) && !s.has_vr(101));
}

#[test]
fn defaults() {
    let s = Scene::parse(&planar("", ""), "x.toml").unwrap();
    assert_eq!(
        s.config,
        Config {
            input_support: false,
            normal_input: false,
            ..Config::default()
        }
    );
    assert_eq!(s.start, Params::default());
    assert_eq!(s.inputs, default_inputs());
    assert_eq!(s.description, summary(&s.config));
    // The default scene is force-driven: no F_d output (the spring's) and no reduction
    // (the velocity drive's).
    let all: Vec<_> = OutputId::ALL
        .into_iter()
        .filter(|o| ![OutputId::FDrive, OutputId::Reduction].contains(o))
        .collect();
    assert_eq!(s.outputs, all);
    let spring = Scene::parse(&planar("", "").replace("force", "spring"), "x.toml").unwrap();
    assert!(spring.outputs.contains(&OutputId::FDrive));
    // F_d is then the output vr 101.
    assert!(spring.has_vr(101));
}

#[test]
fn text_xml_cannot_hold_long_identifiers_and_long_values_are_refused_or_cut() {
    for c in ['\u{0}', '\u{1}', '\u{1F}', '\u{FFFE}', '\u{FFFF}'] {
        let text = planar("", "").replace(
            "law = ",
            &format!("description = \"a\\u{:04X}b\"\nlaw = ", c as u32),
        );
        let e = err(&text);
        assert!(
            e.contains("description") && e.contains(&format!("U+{:04X}", c as u32)),
            "{e}"
        );
    }
    let ok = planar("", "").replace("law = ", "description = \"tab\\there\"\nlaw = ");
    assert!(Scene::parse(&ok, "ok.toml").is_ok());
    let long = "M".repeat(250);
    let e = err(&planar("", "").replace(
        "model_identifier = \"X\"",
        &format!("model_identifier = \"{long}\""),
    ));
    assert!(e.contains("250 characters: at most 64"), "{e}");
    let huge = "x".repeat(10_000_000);
    let e = err(&planar("", "").replace("law = \"dahl\"", &format!("law = \"{huge}\"")));
    assert!(e.len() < 1000 && e.contains("bytes)"), "{} bytes", e.len());
}

#[test]
fn unknown_key() {
    assert_eq!(
            err(&planar("colour = \"red\"", "")),
            "bad.toml:6: colour = \"red\": unknown key; valid: model_identifier, description, law, motion, drive, lateral, support, normal, outputs, start, string"
        );
}

#[test]
fn toml_syntax_error_names_the_line() {
    let e = err("model_identifier = \"X\"\nlaw = \n");
    assert!(e.starts_with("bad.toml:2: invalid TOML: "), "{e}");
}

#[test]
fn missing_required_key() {
    assert_eq!(
            err("model_identifier = \"X\"\nmotion = \"planar\"\nsupport = [\"input\"]\n"),
            "bad.toml: law: missing (required: the friction law); valid: \"dahl\", \"dupont\", \"lugre\""
        );
    assert!(err("law = \"dahl\"\n").starts_with("bad.toml: model_identifier: missing"));
    assert_eq!(
            err("model_identifier = \"X\"\nlaw = \"dahl\"\nmotion = \"planar\"\n"),
            "bad.toml: support: missing (required: the support motion, a non-empty array); valid: \"harmonic\", \"input\""
        );
}

#[test]
fn law_out_of_set() {
    assert_eq!(
        err(&planar("", "").replace("\"dahl\"", "\"coulomb\"")),
        "bad.toml:2: law = \"coulomb\": not a friction law; valid: \"dahl\", \"dupont\", \"lugre\""
    );
    assert_eq!(
            err(&planar("", "").replace("\"dahl\"", "3")),
            "bad.toml:2: law = 3: must be a string (not a friction law); valid: \"dahl\", \"dupont\", \"lugre\""
        );
}

#[test]
fn motion_out_of_set() {
    assert_eq!(
        err(&planar("", "").replace("\"planar\"", "\"spatial\"")),
        "bad.toml:3: motion = \"spatial\": not a motion; valid: \"longitudinal\", \"planar\""
    );
}

#[test]
fn drive_out_of_set() {
    assert_eq!(
        err(&planar("", "").replace("\"force\"", "\"torque\"")),
        "bad.toml:4: drive = \"torque\": not a drive; valid: \"force\", \"velocity\", \"spring\""
    );
}

#[test]
fn lateral_out_of_set() {
    let text = planar("lateral = \"loose\"", "").replace("\"force\"", "\"velocity\"");
    assert_eq!(
        err(&text),
        "bad.toml:6: lateral = \"loose\": not a lateral motion; valid: \"free\", \"guided\""
    );
}

#[test]
fn lateral_in_longitudinal_scene() {
    assert_eq!(
            err(&longitudinal("lateral = \"free\"", "")),
            "bad.toml:6: lateral = \"free\": only a planar velocity drive has a lateral choice (this scene is longitudinal, velocity drive); remove the key"
        );
}

#[test]
fn lateral_with_force_drive() {
    assert_eq!(
            err(&planar("lateral = \"guided\"", "")),
            "bad.toml:6: lateral = \"guided\": only a planar velocity drive has a lateral choice (this scene is planar, force drive); remove the key"
        );
}

#[test]
fn support_entries() {
    let base = planar("", "");
    assert_eq!(
            err(&base.replace("[\"harmonic\"]", "[]")),
            "bad.toml:5: support = []: must name at least one support motion; valid: \"harmonic\", \"input\""
        );
    assert_eq!(
        err(&base.replace("[\"harmonic\"]", "[\"harmonic\", \"random\"]")),
        "bad.toml:5: support = \"random\": not a support motion; valid: \"harmonic\", \"input\""
    );
    assert_eq!(
        err(&base.replace("[\"harmonic\"]", "[\n  \"input\",\n  \"input\",\n]")),
        "bad.toml:7: support = \"input\": listed twice; valid: \"harmonic\", \"input\""
    );
    assert_eq!(
        err(&base.replace("[\"harmonic\"]", "\"harmonic\"")),
        "bad.toml:5: support = \"harmonic\": must be an array of strings"
    );
}

#[test]
fn output_the_scene_cannot_have() {
    assert_eq!(
            err(&longitudinal("outputs = [\"F_Fx\", \"F_Fy\"]", "")),
            "bad.toml:6: outputs = \"F_Fy\": not an output of a dahl longitudinal scene with velocity drive; valid: \"F_Fx\", \"x\", \"v_x\", \"s_x\", \"F_mean\", \"reduction\", \"P_diss\", \"F_Fx_step\""
        );
    assert_eq!(
            err(&longitudinal("outputs = [\"F_Fx\", \"F_d\"]", "")),
            "bad.toml:6: outputs = \"F_d\": a dahl longitudinal scene with velocity drive has no F_d (an input in force drive, an output in spring drive; in velocity drive F_Fx is the driving force); valid: \"F_Fx\", \"x\", \"v_x\", \"s_x\", \"F_mean\", \"reduction\", \"P_diss\", \"F_Fx_step\""
        );
    assert!(err(&longitudinal("outputs = [\"F_Fx\", \"F_Fx\"]", ""))
        .starts_with("bad.toml:6: outputs = \"F_Fx\": listed twice; valid: "));
    assert!(err(&longitudinal("outputs = [\"force\"]", ""))
        .starts_with("bad.toml:6: outputs = \"force\": not an output of any scene; valid: "));
    assert!(err(&longitudinal("outputs = [\"k_t\"]", ""))
        .starts_with("bad.toml:6: outputs = \"k_t\": k_t is a parameter, not an output; valid: "));
    assert!(err(&longitudinal("outputs = []", "")).starts_with(
            "bad.toml:6: outputs = []: must name at least one output (leave the key out for all of them); valid: \"F_Fx\""
        ));
}

#[test]
fn input_asked_for_as_output() {
    assert!(err(&longitudinal("outputs = [\"v_sx\"]", "")).starts_with(
            "bad.toml:6: outputs = \"v_sx\": v_sx is an input of scenes with input support motion, never an output; valid: "
        ));
    let with_input = planar("outputs = [\"v_sx\"]", "").replace("[\"harmonic\"]", "[\"input\"]");
    assert!(err(&with_input).starts_with(
            "bad.toml:6: outputs = \"v_sx\": v_sx is an input of this dahl planar scene with force drive, not an output; valid: "
        ));
    assert!(err(&planar("outputs = [\"F_d\"]", "")).starts_with(
            "bad.toml:6: outputs = \"F_d\": F_d is an input of this dahl planar scene with force drive, not an output; valid: "
        ));
}

#[test]
fn start_value_out_of_range() {
    assert_eq!(
        err(&planar("", "k_t = -1e8")),
        "bad.toml:8: start.k_t = -1e8: must be finite and > 0 (accepted: 100 to 1e13 N/m)"
    );
    assert_eq!(
        err(&planar("", "mu = -0.1")),
        "bad.toml:8: start.mu = -0.1: must be finite and >= 0 (accepted: 0 to 10)"
    );
    assert_eq!(
        err(&planar("", "m = nan")),
        "bad.toml:8: start.m = nan: must be finite and > 0 (accepted: 1e-4 to 1e6 kg)"
    );
    assert_eq!(
        err(&planar("", "v_sx = inf").replace("[\"harmonic\"]", "[\"input\"]")),
        "bad.toml:8: start.v_sx = inf: must be finite (accepted: -1000 to 1000 m/s)"
    );
    assert_eq!(
        err(&planar("", "f = 1e8")),
        "bad.toml:8: start.f = 1e8: must be in [0, 1e7] Hz"
    );
    assert_eq!(
        err(&planar("", "m = \"heavy\"")),
        "bad.toml:8: start.m = \"heavy\": must be a number"
    );
    let dupont = planar("", "r_ba = 1").replace("dahl", "dupont");
    assert_eq!(
        err(&dupont),
        "bad.toml:8: start.r_ba = 1: must be in [0, 0.999]"
    );
}

#[test]
fn start_key_the_scene_does_not_have() {
    let e = err(&planar("", "F_S = 20"));
    assert!(
            e.starts_with("bad.toml:8: start.F_S = 20: F_S is not a parameter of a dahl planar scene with force drive; valid: m, F_N, mu, k_t, u0, f, angle, phase, T_avg, max_steps, F_d"),
            "{e}"
        );
    let e = err(&planar("", "kappa = 2"));
    assert!(
            e.starts_with("bad.toml:8: start.kappa = 2: kappa is not a parameter of a dahl planar scene with force drive; valid: "),
            "{e}"
        );
    assert!(err(&longitudinal("", "F_d = 1")).starts_with(
            "bad.toml:8: start.F_d = 1: F_d is not an input of a dahl longitudinal scene with velocity drive; valid: "
        ));
    assert!(err(&longitudinal("", "v_sx = 1e-3")).starts_with(
            "bad.toml:8: start.v_sx = 1e-3: v_sx is an input only with input support motion (support = [\"input\"]); valid: "
        ));
    assert!(err(&longitudinal("", "F_Fx = 1")).starts_with(
        "bad.toml:8: start.F_Fx = 1: F_Fx is an output; outputs have no start value; valid: "
    ));
    let spring = planar("", "F_d = 1").replace("\"force\"", "\"spring\"");
    assert!(err(&spring).starts_with(
            "bad.toml:8: start.F_d = 1: F_d is an output of this dahl planar scene with spring drive; outputs have no start value; valid: "
        ));
    assert!(err(&planar("", "stiffness = 1")).starts_with(
        "bad.toml:8: start.stiffness = 1: not a parameter or input of any scene; valid: "
    ));
}

#[test]
fn model_identifier_not_a_c_identifier() {
    for bad in ["\"2fast\"", "\"Vibrating-Contact\"", "\"\"", "\"int\"", "7"] {
        let text = planar("", "").replace("\"X\"", bad);
        assert_eq!(
                err(&text),
                format!("bad.toml:1: model_identifier = {bad}: must be a C identifier (a letter or _, then letters, digits or _; not a C keyword)")
            );
    }
    assert!(is_c_identifier("_Vibrating_Contact2"));
}

#[test]
fn wrong_container_types() {
    assert_eq!(
        err(&planar("outputs = \"F_Fx\"", "")),
        "bad.toml:6: outputs = \"F_Fx\": must be an array of strings"
    );
    assert_eq!(
        err(&planar("", "").replace("[start]\n", "start = 3\n")),
        "bad.toml:7: start = 3: must be a table"
    );
    assert_eq!(
        err(&planar("description = 5", "")),
        "bad.toml:6: description = 5: must be a string"
    );
}

/// A LuGre string scene of `sections` with `start` lines.
fn string_scene(sections: &str, start: &str) -> String {
    format!(
        "model_identifier = \"S\"\nlaw = \"lugre\"\nmotion = \"longitudinal\"\ndrive = \"force\"\nnormal = \"input\"\nsupport = [\"input\"]\n[string]\n{sections}\n[start]\n{start}\n"
    )
}

#[test]
fn string_scene_reads_scalars_and_lists() {
    use crate::table::StringVar as V;
    let s = Scene::parse(
        &string_scene(
            "sections = 3",
            "m = [1.0, 2, 3]\nk_s = [10.0, 20.0]\nc_s = 5\nF_N = 100\nmu = 0.3\nF_S = 39\nk_t = 2e8\nk_bottom = 1e7\nF_d = [0, 0, 7]",
        ),
        "s.toml",
    )
    .unwrap();
    let v = s.string.as_ref().unwrap();
    assert_eq!(s.sections(), Some(3));
    assert_eq!(v.get(V::M), &[1.0, 2.0, 3.0]);
    assert_eq!(v.get(V::KS), &[10.0, 20.0]);
    assert_eq!(v.get(V::CS), &[5.0, 5.0]);
    assert_eq!(v.get(V::FN), &[100.0; 3]);
    assert_eq!(v.get(V::FS), &[39.0; 3]);
    assert_eq!(v.get(V::FD), &[0.0, 0.0, 7.0]);
    assert_eq!(v.get(V::KBottom), &[1e7]);
    assert_eq!(v.get(V::KTop), &[0.0]);
    assert_eq!(s.start.k_t, 2e8);
    assert!(s.outputs.is_empty());
    // The scene's own rows are the shared law parameters only.
    let names: Vec<_> = s.variables().map(|v| v.name()).collect();
    assert_eq!(
        names,
        ["k_t", "v_S", "zeta_t", "h_v", "v_e", "max_steps"],
        "{names:?}"
    );
    // One section: no links.
    let one = Scene::parse(&string_scene("sections = 1", "F_S = 14.3"), "s.toml").unwrap();
    assert!(one.string.unwrap().get(V::KS).is_empty());
}

#[test]
fn string_scene_errors_name_the_key_and_the_rule() {
    let planar = string_scene("sections = 2", "").replace("longitudinal", "planar");
    assert_eq!(
        err(&planar),
        "bad.toml:7: string: a string of contacts needs motion = \"longitudinal\" and drive = \"force\" (this scene is planar, force drive)"
    );
    let velocity = string_scene("sections = 2", "")
        .replace("\"force\"", "\"velocity\"")
        .replace("normal = \"input\"\n", "");
    assert!(err(&velocity).contains("needs motion = \"longitudinal\" and drive = \"force\" (this scene is longitudinal, velocity drive)"), "{}", err(&velocity));
    for (sections, want) in [
        (
            "sections = 0",
            "string.sections = 0: must be a whole number of sections from 1 to 100000",
        ),
        (
            "sections = 100001",
            "string.sections = 100001: must be a whole number",
        ),
        (
            "sections = 2.5",
            "string.sections = 2.5: must be a whole number",
        ),
        (
            "count = 2",
            "string.count = 2: unknown key; valid: sections",
        ),
    ] {
        let e = err(&string_scene(sections, ""));
        assert!(e.contains(want), "{e}");
    }
    assert!(err(&string_scene("", "")).contains("string.sections"));
    for (start, want) in [
        ("m = [1, 2]", "start.m = [1, 2]: a list of 2 values: must be a number or one per section (3)"),
        ("k_s = [1, 2, 3]", "start.k_s = [1, 2, 3]: a list of 3 values: must be a number or one per link (2 for 3 sections)"),
        ("m = [1, -2, 3]", "start.m[2] = -2: "),
        ("m = [1, \"a\", 3]", "start.m[2] = [1, \"a\", 3]: must be a number"),
        ("k_top = [1, 2]", "start.k_top = [1, 2]: must be a number"),
        ("k_t = [1e8, 1e8, 1e8]", "start.k_t = [1e8, 1e8, 1e8]: must be a number (a parameter shared by every section)"),
        ("T_avg = 1", "start.T_avg = 1: T_avg is not a parameter or input of this string scene"),
        ("F_Fx = 1", "start.F_Fx = 1: F_Fx is an output"),
        ("F_link = 1", "start.F_link = 1: F_link is not a parameter or input of this string scene"),
        ("zzz = 1", "start.zzz = 1: not a parameter or input of any scene"),
        ("F_N = [55, 55, 200]", "start.F_S[3] = 14.3: section 3: F_S = 14.3 N is below the Coulomb force"),
        ("c_s = -1", "start.c_s = -1: "),
    ] {
        let e = err(&string_scene("sections = 3", start));
        assert!(e.contains(want), "{start}: {e}");
    }
    let outputs =
        string_scene("sections = 2", "").replace("[string]", "outputs = [\"x\"]\n[string]");
    assert!(err(&outputs).contains("outputs = [\"x\"]: a string scene exposes every output of its sections: remove the key"), "{}", err(&outputs));
}
