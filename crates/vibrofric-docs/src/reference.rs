//! The scene reference `docs/scenes.md`, generated from the scene reader ([`Scene::parse`], its
//! keys and values) and the variable table ([`VARIABLES`]): every key and its values, every
//! parameter and input with default, unit and rule, and for each law × motion × drive which
//! parameters, inputs and outputs an FMU has. `tests/docs_reference.rs` fails when the checked-in
//! file differs from what this writes.
//!
//! The per-configuration tables are not derived from rules restated here: each row is a scene
//! text that the reader parses, and the variables listed are the ones that scene carries.

use std::fmt::Write as _;

use vibrofric::description::scene::{default_inputs, KeyValues, Scene, KEYS};
use vibrofric::description::variables::{Causality, VarKind, Variable, VARIABLES};
use vibrofric::description::xml;
use vibrofric::table::Params;
use vibrofric::table::{Config, Drive, Lateral, Law, Motion, Support};

fn code_list(words: &[&str]) -> String {
    words
        .iter()
        .map(|w| format!("`\"{w}\"`"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn names(vars: &[&Variable]) -> String {
    if vars.is_empty() {
        return "—".into();
    }
    vars.iter()
        .map(|v| format!("`{}`", v.name()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The accepted range (the configuration-independent one; a scene may narrow it, see the
/// per-scene tables and each FMU's model description).
fn rule_text(v: &Variable) -> String {
    let rule = match v.kind {
        VarKind::Param(p) => p.rule(),
        VarKind::Input(i) => i.rule(),
        _ => return String::new(),
    };
    format!("[{}, {}]", xml::number(rule.min), xml::number(rule.max))
}

fn default_text(v: &Variable) -> String {
    let p = Params::default();
    let i = default_inputs();
    match v.kind {
        VarKind::Param(id) => xml::number(id.get(&p)),
        VarKind::Input(id) => xml::number(id.get(&i)),
        _ => String::new(),
    }
}

/// A scene text with these choices (and no `outputs`, so every possible output).
pub fn scene_text(
    law: Law,
    motion: Motion,
    drive: Drive,
    lateral: Option<Lateral>,
    support: &[Support],
) -> String {
    let mut t = format!(
        "model_identifier = \"Reference\"\nlaw = \"{}\"\nmotion = \"{}\"\ndrive = \"{}\"\n",
        law.word(),
        motion.word(),
        drive.word()
    );
    if let Some(l) = lateral {
        t.push_str(&format!("lateral = \"{}\"\n", l.word()));
    }
    let s: Vec<String> = support
        .iter()
        .map(|s| format!("\"{}\"", s.word()))
        .collect();
    t.push_str(&format!("support = [{}]\n", s.join(", ")));
    t
}

fn parse(text: &str) -> Result<Scene, String> {
    Scene::parse(text, "reference.toml").map_err(|e| e.to_string())
}

/// Every law × motion × drive (× lateral for planar velocity drives), as the reader names them.
pub fn configurations() -> Vec<(Law, Motion, Drive, Option<Lateral>)> {
    let mut out = vec![];
    for law in Law::ALL {
        for motion in Motion::ALL {
            for drive in Drive::ALL {
                let c = Config {
                    law,
                    motion,
                    drive,
                    ..Config::default()
                };
                if c.has_lateral_choice() {
                    for l in Lateral::ALL {
                        out.push((law, motion, drive, Some(l)));
                    }
                } else {
                    out.push((law, motion, drive, None));
                }
            }
        }
    }
    out
}

/// The variables of a scene with this causality.
fn of(scene: &Scene, causality: Causality) -> Vec<&'static Variable> {
    scene
        .variables()
        .filter(|v| v.causality(&scene.config) == causality)
        .collect()
}

fn minus<'a>(a: &[&'a Variable], b: &[&'a Variable]) -> Vec<&'a Variable> {
    a.iter()
        .filter(|v| !b.iter().any(|w| w.vr == v.vr))
        .copied()
        .collect()
}

/// `docs/scenes.md`: `standard` is every standard scene as (file name, scene).
/// `docs/scenes.md`: `standard` is every standard scene as (file name, scene).
pub fn scenes_markdown(standard: &[(String, Scene)]) -> Result<String, String> {
    let configs = configurations();
    // Which choices a variable appears with: every configuration with every support motion.
    let all_supports: [&[Support]; 3] = [&[Support::Harmonic], &[Support::Input], &Support::ALL];
    let mut scenes_all: Vec<Scene> = vec![];
    for &(law, motion, drive, lateral) in &configs {
        for s in all_supports {
            scenes_all.push(parse(&scene_text(law, motion, drive, lateral, s))?);
        }
    }
    let mut m = String::new();
    intro(&mut m)?;
    keys_section(&mut m)?;
    parameters_section(&mut m, &scenes_all)?;
    outputs_section(&mut m, &scenes_all)?;
    combinations_section(&mut m, &configs)?;
    string_section(&mut m)?;
    standard_section(&mut m, standard)?;
    Ok(m)
}

/// The title, what a scene is, and an example.
fn intro(w: &mut String) -> Result<(), String> {
    writeln!(
        w,
        "# Scene reference\n\n\
         <!-- Generated from the scene reader (crates/vibrofric/src/description/scene/) and \
         the variable table (crates/vibrofric/src/table/table.rs) by \
         crates/vibrofric-docs/src/reference.rs. Do not edit: \
         regenerate with `UPDATE_DOCS=1 cargo test --test docs_reference`. -->\n\n\
         A scene is a TOML file that says what an FMU contains: the friction law, the motion, \
         the drive, the support motion, the outputs and the start values. `cargo run --release` \
         exports every `scenes/*.toml`; `cargo run --release -- export SCENE.toml... --out DIR` \
         exports the scenes given. The model and its parameters are explained in \
         [model.md](model.md); this page is the reference of the file format and of what each \
         combination of choices puts into an FMU.\n\n\
         An example (`scenes/paper-longitudinal.toml` is close to it):\n\n\
         ```toml\n\
         model_identifier = \"MyContact\"\n\
         description = \"Longitudinal vibration, velocity drive\"\n\
         law = \"dahl\"\n\
         motion = \"longitudinal\"\n\
         drive = \"velocity\"\n\
         support = [\"harmonic\"]\n\
         outputs = [\"F_Fx\", \"F_mean\", \"reduction\"]\n\
         \n\
         [start]\n\
         k_t = 1e9\n\
         u0 = 5e-7\n\
         v_d = 2e-3\n\
         ```\n"
    )
    .unwrap();
    Ok(())
}

/// The keys, and errors the reader gives.
fn keys_section(w: &mut String) -> Result<(), String> {
    writeln!(
        w,
        "## Keys\n\n| key | values | required / default | meaning |\n|---|---|---|---|"
    )
    .unwrap();
    for key in KEYS {
        let values = match key.values {
            KeyValues::Text(t) => t.to_string(),
            KeyValues::OneOf(words) => code_list(words),
            KeyValues::ArrayOf(words) => format!("array of {}", code_list(words)),
        };
        let (name, req, meaning) = (key.name, key.requirement, key.meaning);
        writeln!(w, "| `{name}` | {values} | {req} | {meaning} |").unwrap();
    }
    writeln!(
        w,
        "\nAny other key is an error. Every error names the file, the line, the key, the rule \
         it breaks and what would be valid, for example (messages from the reader itself):\n"
    )
    .unwrap();
    let base = scene_text(
        Law::Dahl,
        Motion::Longitudinal,
        Drive::Velocity,
        None,
        &[Support::Harmonic],
    );
    for bad in [
        format!("{base}colour = \"red\"\n"),
        base.replace("\"dahl\"", "\"coulomb\""),
        format!("{base}outputs = [\"F_Fx\", \"F_Fy\"]\n"),
        format!("{base}[start]\nk_t = -1e8\n"),
        format!("{base}[start]\nF_S = 20\n"),
    ] {
        match Scene::parse(&bad, "my-scene.toml") {
            Ok(_) => return Err(format!("the reader accepted a bad scene:\n{bad}")),
            Err(e) => writeln!(w, "    {e}").unwrap(),
        }
    }
    Ok(())
}

/// Every parameter and input, with the scenes that have it.
fn parameters_section(w: &mut String, scenes_all: &[Scene]) -> Result<(), String> {
    writeln!(
        w,
        "\n## Parameters and inputs (`[start]`)\n\n\
         Value references are the same in every FMU. Units are SI; the display unit is what an \
         importer may show. A start value out of its rule is refused when the scene is read; \
         the FMU refuses the same values in `fmi2SetReal` (with `fmi2Error` and a log message \
         naming the variable and the rule).\n\n\
         | name | value reference | unit | display unit | default | rule | in scenes with | description |\n\
         |---|---|---|---|---|---|---|---|"
    )
    .unwrap();
    for v in VARIABLES
        .iter()
        .filter(|v| matches!(v.kind, VarKind::Param(_) | VarKind::Input(_)))
    {
        let present = where_present(scenes_all, |s| s.has_vr(v.vr) && v.settable(&s.config))
            .map_err(|e| format!("{}: {e}", v.name()))?;
        writeln!(
            w,
            "| `{}` | {} | {} | {} | {} | {} | {} | {} |",
            v.name(),
            v.vr,
            v.unit,
            v.display_unit
                .map_or(String::new(), |d| d.replace("um", "µm")),
            default_text(v),
            rule_text(v),
            present,
            v.description
        )
        .unwrap();
    }
    Ok(())
}

/// Every output, with the scenes that have it.
fn outputs_section(w: &mut String, scenes_all: &[Scene]) -> Result<(), String> {
    writeln!(
        w,
        "\n## Outputs\n\n| name | value reference | unit | display unit | in scenes with | description |\n|---|---|---|---|---|---|"
    )
    .unwrap();
    for v in VARIABLES.iter() {
        let has = |s: &Scene| s.has_vr(v.vr) && v.causality(&s.config) == Causality::Output;
        if !scenes_all.iter().any(has) {
            continue;
        }
        let present = where_present(scenes_all, has).map_err(|e| format!("{}: {e}", v.name()))?;
        let description = if matches!(v.kind, VarKind::Input(_)) {
            "Spring-drive force on the body along x, `k_d·(x_d − x) + c_d·(v_d − v_x)` (an output in spring drive, the input of a force drive)"
        } else {
            v.description
        };
        writeln!(
            w,
            "| `{}` | {} | {} | {} | {} | {} |",
            v.name(),
            v.vr,
            v.unit,
            v.display_unit
                .map_or(String::new(), |d| d.replace("um", "µm")),
            present,
            description
        )
        .unwrap();
    }
    writeln!(
        w,
        "\nThe key `outputs` keeps a subset; leaving it out keeps every output the scene can have."
    )
    .unwrap();
    Ok(())
}

/// What each law × motion × drive has.
fn combinations_section(
    w: &mut String,
    configs: &[(Law, Motion, Drive, Option<Lateral>)],
) -> Result<(), String> {
    writeln!(
        w,
        "\n## What each combination has\n\n\
         For each law × motion × drive (and lateral motion, in planar scenes with velocity \
         drive): the parameters, inputs and outputs of its FMU with `support = [\"harmonic\"]`, \
         and what `\"input\"` support motion changes (with both, an FMU has the union). Each row \
         is a scene that the reader parsed.\n\n\
         | law | motion | drive | parameters | inputs | outputs | `\"input\"` instead of `\"harmonic\"` |\n\
         |---|---|---|---|---|---|---|"
    )
    .unwrap();
    for &(law, motion, drive, lateral) in configs {
        let h = parse(&scene_text(
            law,
            motion,
            drive,
            lateral,
            &[Support::Harmonic],
        ))?;
        let i = parse(&scene_text(law, motion, drive, lateral, &[Support::Input]))?;
        let both = parse(&scene_text(law, motion, drive, lateral, &Support::ALL))?;
        let (hp, hi, ho) = (
            of(&h, Causality::Parameter),
            of(&h, Causality::Input),
            of(&h, Causality::Output),
        );
        let (ip, ii) = (of(&i, Causality::Parameter), of(&i, Causality::Input));
        // The union claim of the heading: both = harmonic ∪ input.
        let union: Vec<u32> = {
            let mut u: Vec<u32> = h.variables().chain(i.variables()).map(|v| v.vr).collect();
            u.sort();
            u.dedup();
            u
        };
        let both_vrs: Vec<u32> = both.variables().map(|v| v.vr).collect();
        if union != both_vrs {
            return Err(format!(
                "{} {} {}: support = [harmonic, input] is not the union of the two",
                law.word(),
                motion.word(),
                drive.word()
            ));
        }
        let mut change = vec![];
        let lost = minus(&hp, &ip);
        if !lost.is_empty() {
            change.push(format!("no {}", names(&lost)));
        }
        let gained_inputs = minus(&ii, &hi);
        if !gained_inputs.is_empty() {
            change.push(format!("inputs {}", names(&gained_inputs)));
        }
        let drive_cell = match lateral {
            Some(l) => format!("{} (lateral `{}`)", drive.word(), l.word()),
            None => drive.word().to_string(),
        };
        writeln!(
            w,
            "| {} | {} | {} | {} | {} | {} | {} |",
            law.word(),
            motion.word(),
            drive_cell,
            names(&hp),
            names(&hi),
            names(&ho),
            change.join("; ")
        )
        .unwrap();
    }
    Ok(())
}

/// The standard scenes and the start values each sets.
/// The variables of a string of contacts (`[string]`), from their rows.
fn string_section(w: &mut String) -> Result<(), String> {
    use vibrofric::table::{Role, Shape, StringVar, ARRAY_STRIDE, MAX_SECTIONS};
    writeln!(
        w,
        "\n## Strings of contacts (`[string]`)\n\n\
         A scene with `[string]` and `sections = N` (1 to {MAX_SECTIONS}; only `motion = \"longitudinal\"` \
         and `drive = \"force\"`) holds N sections in one FMU (Model Exchange and Co-Simulation), each on its own \
         contact of the scene's law and support, joined by links and held at the ends. The law's \
         other parameters (`k_t`, `v_S`, `zeta_t`, ...) are shared by every section and take one \
         number in `[start]`; the variables below take one number for every element or a list of \
         one per element (N per section, N − 1 per link), e.g. `m = [267.0, 267.0, 300.0]`. A \
         string has no `outputs` key (it has every output below) and no `T_avg`, `F_mean`, \
         `reduction`, `P_diss`. Every parameter is fixed. Model Exchange's continuous states \
         are `x`, `v_x`, `s_x` and `x_top`, `x_bottom` (3N + 2), its event indicators \
         `event.v_rx` (one per section); the step means are the instantaneous forces there.\n\n\
         Value references: an array of base `b` is `b·{ARRAY_STRIDE}` in FMI 3.0 (one variable `x` with a \
         dimension of its length) and `b·{ARRAY_STRIDE} + i` for the scalar `x[i]` of FMI 2.0; a \
         variable of the string keeps them in every FMU. The standard scene is \
         `scenes/drill-string.toml`.\n\n\
         | name | per | causality | unit | value reference (FMI 3.0) | FMI 2.0 | accepted | default | description |\n\
         |---|---|---|---|---|---|---|---|---|"
    )
    .unwrap();
    for v in StringVar::ALL {
        let per = match v.shape() {
            Shape::Section => "section (N)",
            Shape::Link => "link (N − 1)",
            Shape::One => "string",
        };
        let causality = match v.role(&Config::default()) {
            Role::Param if v == StringVar::FN => "parameter (input with `normal = \"input\"`)",
            Role::Param => "parameter",
            Role::Input => "input",
            Role::Output => "output",
            Role::Local => "local (Model Exchange)",
        };
        let fmi2 = if v.shape() == Shape::One {
            v.vr().to_string()
        } else {
            format!(
                "`{}`: {} + i",
                v.element_name(0).replace("[1]", "[i]"),
                v.vr()
            )
        };
        let settable = v.settable(&Config::default()) || v == StringVar::FN;
        let (accepted, default) = if settable {
            let r = v.rule();
            let default = match v.contact_param() {
                Some(p) => format!(
                    "the scalar `{}` ({})",
                    p.name(),
                    xml::number(p.get(&Params::default()))
                ),
                None => "0".to_string(),
            };
            (
                format!("{} to {}", xml::number(r.min), xml::number(r.max)),
                default,
            )
        } else {
            ("—".into(), "—".into())
        };
        writeln!(
            w,
            "| `{}` | {per} | {causality} | {} | {} | {fmi2} | {accepted} | {default} | {} |",
            v.name(),
            v.unit(),
            v.vr(),
            v.description().replace('|', "\\|")
        )
        .unwrap();
    }
    Ok(())
}

fn standard_section(w: &mut String, standard: &[(String, Scene)]) -> Result<(), String> {
    writeln!(
        w,
        "\n## The standard scenes (`scenes/`)\n\n| file | FMU | configuration | variables | start values set by the scene |\n|---|---|---|---|---|"
    )
    .unwrap();
    for (file, s) in standard {
        let defaults = Params::default();
        let inputs = default_inputs();
        let mut changed = vec![];
        for v in s.variables() {
            let Some(x) = s.start_of(v) else { continue };
            let d = match v.kind {
                VarKind::Param(p) => p.get(&defaults),
                VarKind::Input(i) => i.get(&inputs),
                _ => continue,
            };
            if x.to_bits() != d.to_bits() {
                changed.push(format!("`{} = {}`", v.name(), xml::number(x)));
            }
        }
        writeln!(
            w,
            "| `{file}` | `{}` | {} | {} | {} |",
            s.model_identifier,
            vibrofric::description::scene::summary(&s.config),
            s.variables().count(),
            if changed.is_empty() {
                "—".into()
            } else {
                changed.join(", ")
            }
        )
        .unwrap();
    }
    Ok(())
}

/// The conditions a variable's presence is described by, in the words of the scene keys (a
/// condition per value of `law` and `drive` from their rows). The first whose set of scenes is
/// exactly the set that has the variable is used; a variable that none describes fails the
/// generation (add its condition here).
type Condition = (String, Box<dyn Fn(&Config) -> bool>);

fn conditions() -> Vec<Condition> {
    fn c(text: &str, f: impl Fn(&Config) -> bool + 'static) -> Condition {
        (text.to_string(), Box::new(f))
    }
    let key = |key: &str, word: &str| format!("{key} `\"{word}\"`");
    let mut out = vec![c("every scene", |_| true)];
    for law in Law::ALL {
        out.push(c(&key(Law::KEY.name, law.word()), move |c| c.law == law));
    }
    out.push(c(&key(Motion::KEY.name, Motion::Planar.word()), |c| {
        c.planar()
    }));
    out.push(c("law `\"dahl\"` and motion `\"longitudinal\"`", |c| {
        c.law == Law::Dahl && c.motion == Motion::Longitudinal
    }));
    for drive in Drive::ALL {
        out.push(c(&key(Drive::KEY.name, drive.word()), move |c| {
            c.drive == drive
        }));
    }
    out.extend([
        c("drive `\"velocity\"` or `\"spring\"`", |c| {
            !c.drive.force_input()
        }),
        c("support `\"harmonic\"`", |c| c.harmonic),
        c("support `\"harmonic\"` and motion `\"planar\"`", |c| {
            c.harmonic && c.planar()
        }),
        c("support `\"input\"`", |c| c.input_support),
        c("support `\"input\"` and motion `\"planar\"`", |c| {
            c.input_support && c.planar()
        }),
        c(
            "a moving body (drive `\"force\"` or `\"spring\"`, or `lateral = \"free\"`) or law `\"lugre\"` (its damping `h_t`)",
            |c| c.body_dynamic() || c.law.has_contact_damping(),
        ),
        c(
            "motion `\"planar\"`, except a velocity drive with `lateral = \"guided\"`",
            |c| c.lateral_free(),
        ),
        c("no scene", |_| false),
    ]);
    out
}

/// Where a variable appears: the [`conditions`] entry that matches `has` over `scenes` exactly.
fn where_present(scenes: &[Scene], has: impl Fn(&Scene) -> bool) -> Result<String, String> {
    conditions()
        .into_iter()
        .find(|(_, cond)| scenes.iter().all(|s| cond(&s.config) == has(s)))
        .map(|(text, _)| text)
        .ok_or_else(|| {
            "no condition in reference.rs conditions() describes the scenes that have this variable"
                .to_string()
        })
}
