//! The FMU library's layers, read from its source: each layer imports only the layers below it
//! (`docs/architecture.md`), and no two files of one layer import each other, directly or
//! around a circle.
//!
//! A file's imports are the paths it names: `crate::<layer>` for layers, and `super::<file>` or
//! `crate::<layer>::<file>` for the files beside it (a re-export through the layer's `mod.rs` is
//! not a file's import). Test modules are left out: they may reach anywhere.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Each layer of `crates/vibrofric/src` and the layers it may import.
const LAYERS: [(&str, &[&str]); 6] = [
    ("table", &[]),
    ("physics", &["table"]),
    ("solver", &[]),
    ("model", &["table", "physics", "solver"]),
    ("description", &["table"]),
    ("fmi", &["table", "physics", "model", "description"]),
];

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/vibrofric/src")
}

/// The text of a source file without its `#[cfg(test)]` module and its comments.
fn code(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let text = match text.find("#[cfg(test)]\nmod tests") {
        Some(i) => &text[..i],
        None => &text[..],
    };
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The identifiers that follow `prefix` in `code`: `prefix name` and `prefix{a, b::c}` (first
/// segments only).
fn names_after(code: &str, prefix: &str) -> BTreeSet<String> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = BTreeSet::new();
    for (i, _) in code.match_indices(prefix) {
        let rest = &code[i + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let mut depth = 0;
            let mut item = String::new();
            for c in group.chars() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        out.insert(ident(item.trim()));
                        item.clear();
                        continue;
                    }
                    _ => {}
                }
                if depth == 0 {
                    item.push(c);
                }
            }
            out.insert(ident(item.trim()));
        } else {
            out.insert(ident(rest));
        }
    }
    out.remove("");
    out
}

/// The `.rs` files of a folder, recursively, as (module name relative to the layer, path).
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut v = vec![];
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            v.extend(files(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            v.push(p);
        }
    }
    v.sort();
    v
}

#[test]
fn each_layer_imports_only_layers_below_it() {
    let mut seen = vec![];
    for e in std::fs::read_dir(src()).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            seen.push(p.file_name().unwrap().to_string_lossy().into_owned());
        }
    }
    seen.sort();
    let mut declared: Vec<String> = LAYERS.iter().map(|(l, _)| l.to_string()).collect();
    declared.sort();
    assert_eq!(
        seen, declared,
        "a layer folder without a rule here (or the reverse)"
    );

    for (layer, allowed) in LAYERS {
        for file in files(&src().join(layer)) {
            for used in names_after(&code(&file), "crate::") {
                assert!(
                    used == layer || allowed.contains(&used.as_str()),
                    "{} imports crate::{used}; the {layer} layer may import only {allowed:?}",
                    file.display()
                );
            }
        }
    }
}

#[test]
fn no_two_files_of_a_layer_import_each_other() {
    for (layer, _) in LAYERS {
        let dir = src().join(layer);
        // Files directly in the layer's folder, by module name (`mod.rs` is the layer itself).
        let modules: BTreeMap<String, PathBuf> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.file_name().is_some_and(|n| n != "mod.rs"))
            .map(|p| {
                let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
                (stem, p)
            })
            .collect();
        let mut imports: BTreeMap<&str, BTreeSet<String>> = BTreeMap::new();
        for (name, path) in &modules {
            let sources = if path.is_dir() {
                files(path)
            } else {
                vec![path.clone()]
            };
            let mut used = BTreeSet::new();
            for f in sources {
                let c = code(&f);
                // A file inside a sub-folder reaches its siblings' siblings with `super::super::`;
                // at the layer's top level `super::` names a sibling.
                let depth = f.strip_prefix(&dir).unwrap().components().count();
                let up = "super::".repeat(depth.max(1));
                used.extend(names_after(&c, &up));
                used.extend(names_after(&c, &format!("crate::{layer}::")));
            }
            used.retain(|u| u != name && modules.contains_key(u));
            imports.insert(name, used);
        }
        // Depth-first search for a circle.
        fn visit<'a>(
            n: &'a str,
            imports: &'a BTreeMap<&str, BTreeSet<String>>,
            path: &mut Vec<&'a str>,
            done: &mut BTreeSet<&'a str>,
        ) -> Option<Vec<String>> {
            if let Some(i) = path.iter().position(|p| *p == n) {
                let mut circle: Vec<String> = path[i..].iter().map(|s| s.to_string()).collect();
                circle.push(n.to_string());
                return Some(circle);
            }
            if done.contains(n) {
                return None;
            }
            path.push(n);
            for m in imports.get(n).into_iter().flatten() {
                if let Some(c) = visit(m, imports, path, done) {
                    return Some(c);
                }
            }
            path.pop();
            done.insert(n);
            None
        }
        let mut done = BTreeSet::new();
        for n in imports.keys() {
            if let Some(circle) = visit(n, &imports, &mut vec![], &mut done) {
                panic!("{layer}: files import each other: {}", circle.join(" -> "));
            }
        }
    }
}

/// The export-time writers (documentation pages, `docs/scenes.md`) are a crate beside the FMU's
/// library, not in it, and read only its `description` and `table` layers: they sit above
/// `description` and nothing in the library reaches them.
#[test]
fn export_time_writers_stay_outside_the_library() {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/vibrofric-docs/src");
    let allowed = ["description", "table"];
    for file in files(&docs) {
        for used in names_after(&code(&file), "vibrofric::") {
            assert!(
                allowed.contains(&used.as_str()),
                "{} imports vibrofric::{used}; the export-time writers may read only {allowed:?}",
                file.display()
            );
        }
    }
    for file in files(&src()) {
        assert!(
            !code(&file).contains("vibrofric_docs"),
            "{} reaches the export-time writers",
            file.display()
        );
    }
    let manifest = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/vibrofric/Cargo.toml"),
    )
    .unwrap();
    assert!(!manifest.contains("vibrofric-docs"));
}
