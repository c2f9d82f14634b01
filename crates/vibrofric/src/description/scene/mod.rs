//! Scenes: the TOML file that says what an FMU contains (reference: `docs/scenes.md`, generated
//! from this reader and the variable table).
//!
//! A scene fixes the structural choices ([`Config`]), the outputs the FMU exposes and the start
//! values of its parameters and inputs. Reading one checks every key against its rule and reports
//! the first violation as `<file>:<line>: <key> = <value>: <rule>; valid: <list>`.
//!
//! Depends only on the variable table (`src/table`) and `description/variables.rs` (plus serde
//! and toml).

// A scene is read once per export or instantiation, and the error is the product the user reads:
// keep its fields plain rather than boxing them.
#![allow(clippy::result_large_err)]

mod context;
mod keys;
mod reader;
mod string;

use std::fmt;

use crate::description::variables::{VarKind, Variable, VARIABLES};
use crate::table::{Config, Drive, Inputs, Law, Motion, Normal, OutputId, Params, StringValues};
use crate::table::{ParamId, Support};

pub use keys::{is_c_identifier, shown, Key, KeyValues, KEYS, MAX_IDENTIFIER};
use reader::Reader;

/// A parsed and checked scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// C identifier: the FMU's `modelIdentifier`, file name and library name.
    pub model_identifier: String,
    /// Free text for the model description (a summary of the configuration when the scene has
    /// none).
    pub description: String,
    pub config: Config,
    /// The outputs the FMU exposes, in [`OutputId::ALL`] order. By default every output the
    /// configuration can have ([`OutputId::present`]), including `F_d` ([`OutputId::FDrive`]) in
    /// a spring drive.
    pub outputs: Vec<OutputId>,
    /// Parameter start values: [`Params::default`] with the scene's `[start]` overrides.
    pub start: Params,
    /// Input start values: the defaults of `docs/model.md` (`v_d` = 1e-3 m/s, the others 0) with the
    /// scene's `[start]` overrides. An FMU instance holds these inputs until the importer sets
    /// them; the model description's `start` attributes state them.
    pub inputs: Inputs,
    /// A string of contacts (`[string]`): its number of sections and the start values of its
    /// per-section, per-link and end variables (`start` then holds the law's shared
    /// parameters; `inputs` and `outputs` are unused).
    pub string: Option<StringValues>,
    /// The TOML text exactly as read (shipped in the FMU as `resources/scene.toml`).
    pub source: String,
}

/// Input start values when a scene does not set them (`docs/model.md`).
pub fn default_inputs() -> Inputs {
    Inputs {
        f_d: 0.0,
        v_d: 1e-3,
        v_sx: 0.0,
        v_sy: 0.0,
        f_n: Params::default().f_n,
    }
}

/// Why a scene was refused. `Display`: `<file>:<line>: <key> = <value>: <rule>; valid: <list>`
/// (the parts that do not apply are left out).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    /// File name (or other origin) of the scene text.
    pub file: String,
    /// 1-based line of the offending key or value, when the error has a place.
    pub line: Option<usize>,
    /// The key, as written in TOML (`start.k_t` for a key of the `[start]` table). Empty for a
    /// TOML syntax error.
    pub key: String,
    /// The offending value as written, when there is one.
    pub value: Option<String>,
    /// The rule that was broken.
    pub rule: String,
    /// What would be valid instead (empty when the rule says it all).
    pub valid: Vec<String>,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ": ")?;
        if !self.key.is_empty() {
            write!(f, "{}", self.key)?;
            if let Some(v) = &self.value {
                write!(f, " = {v}")?;
            }
            write!(f, ": ")?;
        }
        write!(f, "{}", self.rule)?;
        if !self.valid.is_empty() {
            write!(f, "; valid: {}", self.valid.join(", "))?;
        }
        Ok(())
    }
}

impl std::error::Error for SceneError {}

/// One-line summary of a configuration, e.g. `Dahl law, planar motion, force drive, harmonic
/// and input support motion`.
pub fn summary(c: &Config) -> String {
    let mut s = format!(
        "{} friction, {} motion, {} drive",
        c.law.title(),
        c.motion.title(),
        c.drive.title()
    );
    if c.has_lateral_choice() {
        s.push_str(&format!(" (lateral {})", c.lateral.title()));
    }
    let support = match (c.harmonic, c.input_support) {
        (true, true) => "harmonic and input",
        (true, false) => "harmonic",
        (false, true) => "input",
        (false, false) => "no",
    };
    s.push_str(&format!(", {support} support motion"));
    s
}

impl Scene {
    /// Reads a scene from TOML text; `origin` (the file name) appears in error messages. The
    /// keys are checked in the order of [`KEYS`] (but `description`, last): the first error
    /// found is the one reported.
    pub fn parse(text: &str, origin: &str) -> Result<Scene, SceneError> {
        let r = Reader::new(text, origin)?;
        let model_identifier = r.model_identifier()?;
        let law = r.choice::<Law>()?;
        let motion = r.choice::<Motion>()?;
        let drive = r.choice::<Drive>()?;
        let lateral = r.lateral(motion, drive)?;
        let detail = r.detail()?;
        let support = r.support(detail.support)?;
        let config = Config {
            law,
            motion,
            drive,
            lateral,
            harmonic: support.contains(&Support::Harmonic),
            input_support: support.contains(&Support::Input),
            normal_input: match r.choice::<Normal>()? {
                Normal::Parameter => false,
                Normal::Input => true,
            },
        };
        let (outputs, start, inputs, string) = match r.string(detail.string, &config)? {
            Some(n) => {
                let (start, values) = r.string_start(detail.start, &config, n)?;
                (vec![], start, default_inputs(), Some(values))
            }
            None => {
                let outputs = r.outputs(detail.outputs, &config)?;
                let (start, inputs) = r.start(detail.start, &config, &outputs)?;
                (outputs, start, inputs, None)
            }
        };
        let description = r.description(&config)?;
        Ok(Scene {
            string,
            model_identifier,
            description,
            config,
            outputs,
            start,
            inputs,
            source: text.to_string(),
        })
    }

    /// Reads a scene file.
    pub fn load(path: &std::path::Path) -> Result<Scene, SceneError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError {
            file: origin.clone(),
            line: None,
            key: String::new(),
            value: None,
            rule: format!("cannot read the scene: {e}"),
            valid: vec![],
        })?;
        Scene::parse(&text, &origin)
    }

    /// The variables this scene carries, in table (`ModelVariables`) order; in a string scene
    /// the law's parameters its sections share (its own variables are
    /// [`crate::table::StringVar`]s).
    pub fn variables(&self) -> impl Iterator<Item = &'static Variable> + '_ {
        let shared: Vec<ParamId> = crate::table::shared_params(&self.config).collect();
        VARIABLES
            .iter()
            .filter(move |v| match (&self.string, v.kind) {
                (None, _) => v.present(&self.config, &self.outputs),
                (Some(_), VarKind::Param(p)) => shared.contains(&p),
                (Some(_), _) => false,
            })
            .map(move |v| v.in_scene(&self.config))
    }

    /// The number of sections of a string scene.
    pub fn sections(&self) -> Option<usize> {
        self.string.as_ref().map(|s| s.sections)
    }

    /// True when the scene carries the variable with this value reference.
    pub fn has_vr(&self, vr: u32) -> bool {
        self.variables().any(|v| v.vr == vr)
    }

    /// The `start` value of a variable in this scene (parameters and inputs; none for
    /// calculated outputs).
    pub fn start_of(&self, v: &Variable) -> Option<f64> {
        v.start(&self.config, &self.start, &self.inputs)
    }
}

#[cfg(test)]
mod tests;
