//! The generated parts of the user's guide (`docs/`) against the code they describe, and the
//! guide's links.
//!
//! - `docs/scenes.md` is written by `vibrofric_docs::reference` from the scene reader and
//!   the variable table; `docs/sign-convention.svg` is the picture every FMU's documentation
//!   page shows. A change to the code that changes either fails here until the checked-in copy
//!   is regenerated with
//!
//!   ```text
//!   UPDATE_DOCS=1 cargo test --test docs_reference
//!   ```
//!
//!   and the diff reviewed.
//! - Every relative link in `README.md` and `docs/*.md` points to a file of the repository.

mod support;

use std::path::{Path, PathBuf};

use vibrofric::description::Scene;
use vibrofric_docs::docs;
use vibrofric_docs::figure::{sign_convention_svg, SIGN_CONVENTION_SVG};
use vibrofric_docs::reference::{self, configurations, scene_text};

const REGENERATE: &str =
    "regenerate with `UPDATE_DOCS=1 cargo test --test docs_reference` and review the diff";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The standard scenes in file-name order, the order `docs/scenes.md` lists them.
fn standard_scenes() -> Vec<(String, Scene)> {
    let mut v: Vec<(String, Scene)> = support::scenes::standard_scenes()
        .into_iter()
        .map(|(f, s)| (f.to_string(), s))
        .collect();
    v.sort_by(|a, b| a.0.cmp(&b.0));
    v
}

/// Compares (or, with UPDATE_DOCS=1, writes) one generated file.
fn check(path: &Path, generated: &str) -> Option<String> {
    if std::env::var_os("UPDATE_DOCS").is_some_and(|v| v != "0") {
        std::fs::write(path, generated).unwrap();
        return None;
    }
    match std::fs::read_to_string(path) {
        Ok(s) if s == generated => None,
        Ok(s) => {
            let line = s
                .lines()
                .zip(generated.lines())
                .position(|(a, b)| a != b)
                .map_or(s.lines().count().min(generated.lines().count()), |i| i)
                + 1;
            Some(format!(
                "{} differs from the generator (first at line {line})",
                path.display()
            ))
        }
        Err(e) => Some(format!("{}: {e}", path.display())),
    }
}

#[test]
fn checked_in_reference_matches_the_generator() {
    let md = reference::scenes_markdown(&standard_scenes()).unwrap_or_else(|e| panic!("{e}"));
    let drift: Vec<String> = [
        check(&root().join("docs/scenes.md"), &md),
        check(
            &root().join("docs/sign-convention.svg"),
            SIGN_CONVENTION_SVG,
        ),
    ]
    .into_iter()
    .flatten()
    .collect();
    assert!(drift.is_empty(), "{}\n{REGENERATE}", drift.join("\n"));
}

/// The reference's per-configuration rows are what the reader makes of each scene text: spot
/// checks against facts stated independently of the generator.
#[test]
fn reference_rows_agree_with_the_reader() {
    let md = reference::scenes_markdown(&standard_scenes()).unwrap();
    // 3 laws × (3 longitudinal drives + planar force, velocity free, velocity guided, spring).
    assert_eq!(configurations().len(), 21);
    let row = |start: &str| {
        md.lines()
            .find(|l| l.starts_with(start))
            .unwrap_or_else(|| panic!("no row {start}"))
            .to_string()
    };
    // Longitudinal Dahl under velocity drive: kappa, no m, no y quantities, v_d input.
    let r = row("| dahl | longitudinal | velocity |");
    assert!(r.contains("`kappa`") && !r.contains("`m`") && !r.contains("`F_Fy`"));
    assert!(r.contains("| `v_d` |"), "{r}");
    // LuGre always has m (its damping h_t = 2·zeta_t·sqrt(m·k_t)).
    let r = row("| lugre | longitudinal | velocity |");
    assert!(r.contains("`m`") && r.contains("`zeta_t`") && !r.contains("`kappa`"));
    // Spring drive: F_d is an output, v_d the input.
    let r = row("| dupont | planar | spring |");
    assert!(r.contains("`r_ba`") && r.contains("`k_d`") && r.contains("`F_d`"));
    // Planar input support adds v_sx and v_sy and drops the harmonic parameters.
    let r = row("| dahl | planar | force |");
    assert!(
        r.ends_with("no `u0`, `f`, `angle`, `phase`; inputs `v_sx`, `v_sy` |"),
        "{r}"
    );
    // Every row's scene text is one the reader accepts.
    for (law, motion, drive, lateral) in configurations() {
        Scene::parse(
            &scene_text(
                law,
                motion,
                drive,
                lateral,
                &[vibrofric::table::Support::Harmonic],
            ),
            "x",
        )
        .unwrap();
    }
    // The errors quoted are the reader's.
    assert!(md.contains("my-scene.toml:6: colour = \"red\": unknown key; valid: model_identifier"));
    assert!(md.contains("start.k_t = -1e8: must be finite and > 0"));
}

/// Every FMU page carries the picture (a longitudinal one without the planar top view), the
/// usage snippets in its own edition's calls with a step that fits the scene's vibration, and
/// the platform section; both editions say they offer Model Exchange.
#[test]
fn fmu_pages_carry_the_picture_usage_and_platform() {
    let linux = docs::Binary {
        folders: vec!["linux64"],
        file_ext: "so",
        os: "x86-64 Linux",
        requirement: "glibc 2.17 or newer".into(),
        libraries: vec!["libc.so.6".into(), "libm.so.6".into()],
    };
    let windows = docs::Binary {
        folders: vec!["win64"],
        file_ext: "dll",
        os: "64-bit Windows (x86-64)",
        requirement: "Windows 10 or later".into(),
        libraries: vec!["KERNEL32.dll".into()],
    };
    for (file, s) in standard_scenes() {
        let html = docs::index_html_for(&s, &[linux.clone(), windows.clone()]);
        let html3 = docs::index_html_fmi3(&s, &[linux.clone(), windows.clone()]);
        let planar = s.config.planar();
        let step = if s.config.harmonic {
            1.0 / s.start.f
        } else {
            s.start.t_avg
        };
        let step = format!(
            "output_interval={}",
            vibrofric::description::xml::number(step)
        );
        for (page, v) in [(&html, "2.0"), (&html3, "3.0")] {
            assert!(page.contains(&sign_convention_svg(planar)), "{file}");
            assert_eq!(page.contains("Top view"), planar, "{file}");
            assert!(page.contains(&step), "{file}: {step}");
            assert!(
                page.contains(&format!(
                    "<p>FMI {v} FMU for Co-Simulation and Model Exchange, generated by"
                )),
                "{file}"
            );
            assert!(
                page.contains("fmi_type=&quot;ModelExchange&quot;"),
                "{file}"
            );
            assert!(page.contains("<code>T_avg</code>"), "{file}");
            if s.config.law.has_contact_damping() {
                assert!(page.contains("<code>zeta_t</code> (LuGre)"), "{file}");
                assert!(page.contains("The static force follows the load"), "{file}");
            }
            if s.config.input_support {
                assert!(
                    page.contains("set <code>T_avg</code> to the period of the excitation"),
                    "{file}"
                );
            }
        }
        assert!(html.contains(SIGN_CONVENTION_SVG) == planar, "{file}");
        assert!(html.contains("glibc 2.17 or newer"), "{file}");
        assert!(
            html.contains("It links only <code>libc.so.6</code>, <code>libm.so.6</code>:"),
            "{file}"
        );
        let id = &s.model_identifier;
        assert!(
            html.contains(&format!(
                "<code>binaries/win64/{id}.dll</code>: 64-bit Windows"
            )),
            "{file}"
        );
        assert!(
            html.contains("Not in this FMU: <code>darwin64</code>."),
            "{file}"
        );
        assert!(html.contains("Any FMI 2.0 importer"), "{file}");
        // The FMI 3.0 edition's page names its own folders and importers.
        let linux3 = docs::Binary {
            folders: vec!["x86_64-linux"],
            ..linux.clone()
        };
        let html3 = docs::index_html_fmi3(&s, &[linux3]);
        assert!(
            html3.contains(&format!("<code>binaries/x86_64-linux/{id}.so</code>")),
            "{file}"
        );
        assert!(html3.contains("Any FMI 3.0 importer"), "{file}");
        assert!(!html3.contains("binaries/linux64/"), "{file}");
        let linux_only = docs::index_html_for(&s, std::slice::from_ref(&linux));
        assert!(
            linux_only.contains("Not in this FMU: <code>win64</code>, <code>darwin64</code>."),
            "{file}"
        );
        if s.config.input_support {
            assert!(html.contains("setRealInputDerivatives"), "{file}");
            assert!(
                html.contains("FMU2Slave") && !html.contains("FMU3Slave"),
                "{file}"
            );
            assert!(
                html3.contains("FMU3Slave") && !html3.contains("FMU2Slave"),
                "{file}"
            );
        }
        // The FMI 3.0 page names FMI 3.0's calls only.
        assert!(!html3.contains("fmi2"), "{file}");
        assert!(html3.contains("fmi3EnterInitializationMode"), "{file}");
    }
}

/// Relative links `](path)` and `](path#anchor)` in markdown.
fn links(text: &str) -> Vec<String> {
    let mut out = vec![];
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        rest = &rest[i + 2..];
        if let Some(j) = rest.find(')') {
            let target = &rest[..j];
            if !target.contains("://") && !target.starts_with('#') && !target.starts_with("mailto:")
            {
                out.push(target.split('#').next().unwrap().to_string());
            }
        }
    }
    out
}

#[test]
fn guide_links_resolve() {
    let mut pages = vec![root().join("README.md")];
    for e in std::fs::read_dir(root().join("docs")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "md") {
            pages.push(p);
        }
    }
    let mut broken = vec![];
    for page in &pages {
        let text = std::fs::read_to_string(page).unwrap();
        for l in links(&text) {
            let target = page.parent().unwrap().join(&l);
            if !target.exists() {
                broken.push(format!("{}: {l}", page.display()));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
    // The README links the guide.
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    assert!(readme.contains("](docs/README.md)"));
}
