//! Generates the `modelDescription.xml` of every scene in `scenes/` into
//! `$OUT_DIR/model_descriptions/<model_identifier>.xml`, and `$OUT_DIR/model_descriptions.rs`
//! listing them for the library (`vibrofric::description::generated`).
//!
//! The generator is the library's own: the variable table, the scene reader and the XML writer
//! are included here by path, with modules mirroring the crate's so that their `crate::physics`,
//! `crate::model` and `crate::description` paths resolve. A scene that does not read fails the
//! build with the reader's message.

#![allow(dead_code)]

#[path = "src/model/config.rs"]
mod config;
#[path = "src/model/ids.rs"]
mod ids;
#[path = "src/physics/params.rs"]
mod params;
#[path = "src/description/scene.rs"]
mod scene;
#[path = "src/description/variables.rs"]
mod variables;
#[path = "src/description/xml.rs"]
mod xml;

mod physics {
    pub use crate::params::*;
}
mod model {
    pub use crate::config::*;
    pub use crate::ids::*;
}
mod description {
    pub(crate) use crate::{scene, variables};
}

use std::fmt::Write as _;
use std::path::PathBuf;

fn main() {
    for f in [
        "scenes",
        "src/physics/params.rs",
        "src/model/config.rs",
        "src/model/ids.rs",
        "src/description/variables.rs",
        "src/description/scene.rs",
        "src/description/xml.rs",
        "build.rs",
    ] {
        println!("cargo:rerun-if-changed={f}");
    }

    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let dir = out.join("model_descriptions");
    std::fs::create_dir_all(&dir).expect("create OUT_DIR/model_descriptions");

    let mut files: Vec<PathBuf> = std::fs::read_dir("scenes")
        .expect("read scenes/")
        .map(|e| e.expect("read scenes/").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();

    let mut list = String::from(
        "/// Every standard scene as built: (scene file name, model identifier, model description).\n\
         pub static GENERATED: &[(&str, &str, &str)] = &[\n",
    );
    let mut seen: Vec<(String, String)> = vec![];
    for path in &files {
        let s = match scene::Scene::load(path) {
            Ok(s) => s,
            Err(e) => panic!("{e}"),
        };
        let file = path
            .file_name()
            .expect("a scene file has a name")
            .to_string_lossy()
            .into_owned();
        if let Some((other, _)) = seen.iter().find(|(_, id)| *id == s.model_identifier) {
            panic!(
                "{}: model_identifier = \"{}\": already used by scenes/{other}; every scene needs its own",
                path.display(),
                s.model_identifier
            );
        }
        seen.push((file.clone(), s.model_identifier.clone()));
        let xml_path = dir.join(format!("{}.xml", s.model_identifier));
        std::fs::write(&xml_path, xml::model_description(&s)).expect("write model description");
        writeln!(
            list,
            "    ({file:?}, {:?}, include_str!(concat!(env!(\"OUT_DIR\"), \"/model_descriptions/{}.xml\"))),",
            s.model_identifier, s.model_identifier
        )
        .expect("write to String");
    }
    list.push_str("];\n");
    std::fs::write(out.join("model_descriptions.rs"), list).expect("write model_descriptions.rs");
}
