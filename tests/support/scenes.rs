//! The standard scenes (`scenes/*.toml`) and the core built from one.

use std::path::Path;

use vibrofric::description::Scene;
use vibrofric::model::{Setup, Simulator};

/// The standard scenes, `scenes/*.toml`, in the order the fuzz campaigns draw from
/// ([`standard_scenes_are_the_scene_folder`] keeps it equal to the folder's contents).
pub const STANDARD_SCENES: [&str; 10] = [
    "contact.toml",
    "contact-lugre.toml",
    "contact-dupont.toml",
    "drill-string-axial.toml",
    "drill-string-contact.toml",
    "paper-longitudinal.toml",
    "paper-transverse.toml",
    "paper-transverse-guided.toml",
    "rig-longitudinal.toml",
    "rig-transverse.toml",
];

/// The standard scenes of strings of contacts (`[string]`): exported and self-checked with the
/// others, but with variables of their own (`tests/string_description.rs`,
/// `tests/python/test_string.py`), so not in [`STANDARD_SCENES`].
pub const STRING_SCENES: [&str; 1] = ["drill-string.toml"];

/// The text of `scenes/<file>`.
pub fn scene_text(file: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(file);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The scene `scenes/<file>`.
pub fn scene(file: &str) -> Scene {
    Scene::parse(&scene_text(file), file).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// Every standard scene with its file name.
pub fn standard_scenes() -> Vec<(&'static str, Scene)> {
    STANDARD_SCENES.iter().map(|f| (*f, scene(f))).collect()
}

/// The number of continuous states of the scene's Model Exchange interface.
pub fn state_count(sc: &Scene) -> usize {
    sc.variables()
        .filter(|v| matches!(v.kind, vibrofric::description::variables::VarKind::State(_)))
        .count()
}

/// The core for a scene at `t = 0`: its start values and every input it has, tolerance `tol`.
pub fn start(sc: &Scene, tol: f64) -> Box<dyn Simulator> {
    Setup::new(sc.config, sc.start)
        .inputs(sc.inputs)
        .tolerance(tol)
        .build()
        .unwrap()
}

/// [`STANDARD_SCENES`] names exactly the `.toml` files of `scenes/`.
pub fn standard_scenes_are_the_scene_folder() {
    let mut files: Vec<String> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".toml"))
            .collect();
    files.sort();
    let mut listed: Vec<String> = STANDARD_SCENES
        .iter()
        .chain(&STRING_SCENES)
        .map(|s| s.to_string())
        .collect();
    listed.sort();
    assert_eq!(files, listed, "scenes/ and STANDARD_SCENES differ");
}
