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

use std::collections::BTreeMap;
use std::fmt;
use std::ops::Range;

use serde::Deserialize;
use toml::{Spanned, Value};

use crate::description::variables::{VarKind, Variable, VARIABLES};
use crate::table::{ChoiceKey, Config, Drive, InputId, Inputs, Lateral, Law, Motion, Normal};
use crate::table::{OutputId, ParamId, Params, Support};

/// A value as an error message shows it: at most 200 characters, then how long it was.
pub fn shown(s: &str) -> String {
    const MAX: usize = 200;
    match s.char_indices().nth(MAX) {
        None => s.to_string(),
        Some((cut, _)) => format!("{}… ({} bytes)", &s[..cut], s.len()),
    }
}

/// Longest model identifier: it names the FMU file, its library and the C symbols' prefix.
pub const MAX_IDENTIFIER: usize = 64;

/// What a top-level key takes, for the reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KeyValues {
    /// Described in words.
    Text(&'static str),
    /// One of these words.
    OneOf(&'static [&'static str]),
    /// A non-empty array of these words.
    ArrayOf(&'static [&'static str]),
}

/// A top-level key of a scene file: its name, what it takes, whether it is required (or its
/// default) and what it means.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Key {
    pub name: &'static str,
    pub values: KeyValues,
    pub requirement: &'static str,
    pub meaning: &'static str,
}

impl Key {
    const fn choice(k: ChoiceKey) -> Key {
        Key {
            name: k.name,
            values: KeyValues::OneOf(k.words),
            requirement: k.requirement,
            meaning: k.meaning,
        }
    }
}

/// The top-level keys of a scene file, in the order the documentation lists them; the choice
/// keys are the rows of `table/config.rs`.
pub const KEYS: [Key; 10] = [
    Key {
        name: "model_identifier",
        values: KeyValues::Text("string (C identifier)"),
        requirement: "required",
        meaning: "The FMU's model identifier: its file name `<model_identifier>.fmu` and the name of its shared library. A C identifier (a letter or `_`, then letters, digits or `_`; not a C keyword), different in every scene exported together.",
    },
    Key {
        name: "description",
        values: KeyValues::Text("string"),
        requirement: "default: a summary of law, motion, drive and support motion",
        meaning: "Free text, shown by importers and on the FMU's documentation page.",
    },
    Key::choice(Law::KEY),
    Key::choice(Motion::KEY),
    Key::choice(Drive::KEY),
    Key::choice(Lateral::KEY),
    Key {
        values: KeyValues::ArrayOf(Support::KEY.words),
        ..Key::choice(Support::KEY)
    },
    Key::choice(Normal::KEY),
    Key {
        name: "outputs",
        values: KeyValues::Text("array of output names"),
        requirement: "default: every output the scene can have",
        meaning: "The outputs the FMU exposes, a non-empty array of names (see the tables below for which a scene can have).",
    },
    Key {
        name: "start",
        values: KeyValues::Text("table: name = number"),
        requirement: "default: none",
        meaning: "A table of start values that override the defaults: any parameter or input of the scene (see the tables below), in SI units.",
    },
];

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

/// The second reading of a scene: the entries whose elements need their own place in the file.
#[derive(Deserialize, Default)]
struct Detail {
    #[serde(default)]
    support: Option<Vec<Spanned<Value>>>,
    #[serde(default)]
    outputs: Option<Vec<Spanned<Value>>>,
    #[serde(default)]
    start: Option<BTreeMap<Spanned<String>, Spanned<Value>>>,
}

/// Context for building errors that point into the text.
struct Ctx<'a> {
    text: &'a str,
    origin: &'a str,
}

impl Ctx<'_> {
    fn line(&self, span: &Range<usize>) -> usize {
        let end = span.start.min(self.text.len());
        self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    }

    /// The value as written (its TOML text on one line).
    /// A value as an error message shows it: as written, cut after 200 characters.
    fn shown(&self, v: &Spanned<Value>) -> String {
        let span = v.span();
        let s = match self.text.get(span) {
            Some(s) if !s.contains('\n') && !s.is_empty() => s.to_string(),
            _ => v.get_ref().to_string(),
        };
        shown(&s)
    }

    fn err(
        &self,
        span: Option<&Range<usize>>,
        key: impl Into<String>,
        value: Option<String>,
        rule: impl Into<String>,
        valid: Vec<String>,
    ) -> SceneError {
        SceneError {
            file: self.origin.to_string(),
            line: span.map(|s| self.line(s)),
            key: key.into(),
            value,
            rule: rule.into(),
            valid,
        }
    }

    fn toml_error(&self, e: toml::de::Error) -> SceneError {
        let line = e.span().map(|s| self.line(&s));
        SceneError {
            file: self.origin.to_string(),
            line,
            key: String::new(),
            value: None,
            rule: format!("invalid TOML: {}", e.message().trim()),
            valid: vec![],
        }
    }
}

fn quoted(words: &[&str]) -> Vec<String> {
    words.iter().map(|w| format!("\"{w}\"")).collect()
}

/// A key whose value is one of the declared rows of `table/config.rs`.
trait Choice: Copy + 'static {
    const KEY: ChoiceKey;
    const DEFAULT: Option<Self>;
    fn from_word(word: &str) -> Option<Self>;
}

macro_rules! choice_keys {
    ($($t:ident),*) => {$(
        impl Choice for $t {
            const KEY: ChoiceKey = $t::KEY;
            const DEFAULT: Option<$t> = $t::DEFAULT;
            fn from_word(word: &str) -> Option<$t> {
                $t::from_word(word)
            }
        }
    )*};
}
choice_keys!(Law, Motion, Drive, Lateral, Support, Normal);

/// A string entry that must be one of the words of `T`'s rows (`key_span` is where an error
/// points).
fn word<T: Choice>(
    ctx: &Ctx,
    key_span: &Range<usize>,
    v: &Spanned<Value>,
) -> Result<T, SceneError> {
    let key = T::KEY;
    v.get_ref().as_str().and_then(T::from_word).ok_or_else(|| {
        let rule = if v.get_ref().is_str() {
            key.refusal.to_string()
        } else {
            format!("must be a string ({})", key.refusal)
        };
        ctx.err(
            Some(key_span),
            key.name,
            Some(ctx.shown(v)),
            rule,
            quoted(key.words),
        )
    })
}

/// True when `s` is a valid C identifier that is not a C keyword.
pub fn is_c_identifier(s: &str) -> bool {
    const KEYWORDS: [&str; 44] = [
        "auto",
        "break",
        "case",
        "char",
        "const",
        "continue",
        "default",
        "do",
        "double",
        "else",
        "enum",
        "extern",
        "float",
        "for",
        "goto",
        "if",
        "inline",
        "int",
        "long",
        "register",
        "restrict",
        "return",
        "short",
        "signed",
        "sizeof",
        "static",
        "struct",
        "switch",
        "typedef",
        "union",
        "unsigned",
        "void",
        "volatile",
        "while",
        "_Alignas",
        "_Alignof",
        "_Atomic",
        "_Bool",
        "_Complex",
        "_Generic",
        "_Imaginary",
        "_Noreturn",
        "_Static_assert",
        "_Thread_local",
    ];
    let mut chars = s.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
        _ => return false,
    }
    chars.all(|c| c.is_ascii_alphanumeric() || c == '_') && !KEYWORDS.contains(&s)
}

/// A scene's top-level table, read once, with the context its errors point into.
struct Reader<'a> {
    ctx: Ctx<'a>,
    top: BTreeMap<Spanned<String>, Spanned<Value>>,
}

impl<'a> Reader<'a> {
    /// The first reading: TOML syntax, then every key known.
    fn new(text: &'a str, origin: &'a str) -> Result<Reader<'a>, SceneError> {
        let ctx = Ctx { text, origin };
        let top = toml::from_str(text).map_err(|e| ctx.toml_error(e))?;
        let r = Reader { ctx, top };
        r.unknown_keys()?;
        Ok(r)
    }

    /// Unknown keys, in file order so that the first one written is the one reported.
    fn unknown_keys(&self) -> Result<(), SceneError> {
        let mut entries: Vec<_> = self.top.iter().collect();
        entries.sort_by_key(|(k, _)| k.span().start);
        match entries
            .into_iter()
            .find(|(k, _)| !KEYS.iter().any(|key| key.name == k.get_ref().as_str()))
        {
            None => Ok(()),
            Some((k, v)) => Err(self.ctx.err(
                Some(&k.span()),
                k.get_ref().as_str(),
                Some(self.ctx.shown(v)),
                "unknown key",
                KEYS.iter().map(|key| key.name.to_string()).collect(),
            )),
        }
    }

    /// The key's place and its value.
    fn get(&self, key: &str) -> Option<(Range<usize>, Spanned<Value>)> {
        self.top
            .get_key_value(key)
            .map(|(k, v)| (k.span(), v.clone()))
    }

    /// A required key left out (the error has no line).
    fn missing(&self, key: &str, rule: String, valid: Vec<String>) -> SceneError {
        SceneError {
            file: self.ctx.origin.to_string(),
            line: None,
            key: key.to_string(),
            value: None,
            rule,
            valid,
        }
    }

    /// An error on the key's entry, showing its value.
    fn refuse(&self, key: &str, rule: impl Into<String>) -> SceneError {
        let (ks, v) = self.get(key).expect("refusing a key that is present");
        self.ctx
            .err(Some(&ks), key, Some(self.ctx.shown(&v)), rule, vec![])
    }

    fn model_identifier(&self) -> Result<String, SceneError> {
        let key = "model_identifier";
        let Some((_, v)) = self.get(key) else {
            let rule = "missing (required: the FMU's model identifier, a C identifier)";
            return Err(self.missing(key, rule.into(), vec![]));
        };
        match v.get_ref().as_str() {
            Some(s) if s.len() > MAX_IDENTIFIER => Err(self.refuse(
                key,
                format!(
                    "{} characters: at most {MAX_IDENTIFIER} (it names the FMU file and its library)",
                    s.len()
                ),
            )),
            Some(s) if is_c_identifier(s) => Ok(s.to_string()),
            _ => Err(self.refuse(
                key,
                "must be a C identifier (a letter or _, then letters, digits or _; not a C keyword)",
            )),
        }
    }

    /// A choice key: its value, or its default, or the error of a required key left out.
    fn choice<T: Choice>(&self) -> Result<T, SceneError> {
        let key = T::KEY;
        match self.get(key.name) {
            Some((ks, v)) => word::<T>(&self.ctx, &ks, &v),
            None => T::DEFAULT.ok_or_else(|| {
                let what = key.missing.unwrap_or(key.meaning);
                let rule = format!("missing (required: {what})");
                self.missing(key.name, rule, quoted(key.words))
            }),
        }
    }

    /// `lateral`, which only a planar velocity drive may have.
    fn lateral(&self, motion: Motion, drive: Drive) -> Result<Lateral, SceneError> {
        let lateral = self.choice::<Lateral>()?;
        let planar_velocity = Config {
            motion,
            drive,
            ..Config::default()
        }
        .has_lateral_choice();
        if self.get(Lateral::KEY.name).is_some() && !planar_velocity {
            return Err(self.refuse(
                Lateral::KEY.name,
                format!(
                    "only a planar velocity drive has a lateral choice (this scene is {}, {} drive); remove the key",
                    motion.word(),
                    drive.word()
                ),
            ));
        }
        Ok(lateral)
    }

    /// The second, typed reading of the entries whose elements need their own line. The first
    /// reading proved the file is TOML; check the container types before.
    fn detail(&self) -> Result<Detail, SceneError> {
        for (key, is_ok, what) in [
            (
                Support::KEY.name,
                Value::is_array as fn(&Value) -> bool,
                "an array of strings",
            ),
            ("outputs", Value::is_array, "an array of strings"),
            ("start", Value::is_table, "a table"),
        ] {
            if let Some((_, v)) = self.get(key) {
                if !is_ok(v.get_ref()) {
                    return Err(self.refuse(key, format!("must be {what}")));
                }
            }
        }
        toml::from_str(self.ctx.text).map_err(|e| self.ctx.toml_error(e))
    }

    /// `support`: a non-empty array of distinct support motions.
    fn support(&self, list: Option<Vec<Spanned<Value>>>) -> Result<Vec<Support>, SceneError> {
        let key = Support::KEY;
        let (span, list) = match (self.get(key.name), list) {
            (Some((ks, _)), Some(list)) => (ks, list),
            _ => {
                let rule = format!("missing (required: {})", key.missing.unwrap_or_default());
                return Err(self.missing(key.name, rule, quoted(key.words)));
            }
        };
        if list.is_empty() {
            return Err(self.ctx.err(
                Some(&span),
                key.name,
                Some("[]".into()),
                "must name at least one support motion",
                quoted(key.words),
            ));
        }
        let mut chosen = vec![];
        for item in &list {
            let s = word::<Support>(&self.ctx, &item.span(), item)?;
            if chosen.contains(&s) {
                return Err(self.ctx.err(
                    Some(&item.span()),
                    key.name,
                    Some(self.ctx.shown(item)),
                    "listed twice",
                    quoted(key.words),
                ));
            }
            chosen.push(s);
        }
        Ok(chosen)
    }

    /// `outputs`: a non-empty array of distinct outputs the configuration has; every one when
    /// the key is left out.
    fn outputs(
        &self,
        list: Option<Vec<Spanned<Value>>>,
        config: &Config,
    ) -> Result<Vec<OutputId>, SceneError> {
        let possible: Vec<OutputId> = OutputId::ALL
            .into_iter()
            .filter(|o| o.present(config))
            .collect();
        let Some(list) = list else {
            return Ok(possible);
        };
        let possible_names = || -> Vec<String> {
            possible
                .iter()
                .map(|o| format!("\"{}\"", o.name()))
                .collect()
        };
        if list.is_empty() {
            let span = self.get("outputs").map(|(ks, _)| ks);
            return Err(self.ctx.err(
                span.as_ref(),
                "outputs",
                Some("[]".into()),
                "must name at least one output (leave the key out for all of them)",
                possible_names(),
            ));
        }
        let mut chosen: Vec<OutputId> = vec![];
        for item in &list {
            let refuse = |rule: String| {
                let shown = Some(self.ctx.shown(item));
                let span = item.span();
                self.ctx
                    .err(Some(&span), "outputs", shown, rule, possible_names())
            };
            let Some(name) = item.get_ref().as_str() else {
                return Err(refuse("must be a string (an output name)".into()));
            };
            let Some(&o) = possible.iter().find(|o| o.name() == name) else {
                return Err(refuse(output_refusal(name, config)));
            };
            if chosen.contains(&o) {
                return Err(refuse("listed twice".into()));
            }
            chosen.push(o);
        }
        Ok(OutputId::ALL
            .into_iter()
            .filter(|o| chosen.contains(o))
            .collect())
    }

    /// `[start]`: start values of the parameters and inputs this scene can set, each checked
    /// against its rule; then the reference load and, for a law with a static force, its
    /// consistency with it.
    fn start(
        &self,
        table: Option<BTreeMap<Spanned<String>, Spanned<Value>>>,
        config: &Config,
        outputs: &[OutputId],
    ) -> Result<(Params, Inputs), SceneError> {
        let mut start = Params::default();
        let mut inputs = default_inputs();
        let settable: Vec<&'static Variable> = VARIABLES
            .iter()
            .filter(|v| v.present(config, outputs) && v.settable(config))
            .collect();
        let settable_names = || settable.iter().map(|v| v.name().to_string()).collect();
        let mut entries: Vec<_> = table.unwrap_or_default().into_iter().collect();
        entries.sort_by_key(|(k, _)| k.span().start);
        for (k, v) in &entries {
            let name = k.get_ref().as_str();
            let key = format!("start.{name}");
            let span = k.span();
            let refuse = |rule: String, valid: Vec<String>| {
                self.ctx.err(
                    Some(&span),
                    key.clone(),
                    Some(self.ctx.shown(v)),
                    rule,
                    valid,
                )
            };
            let Some(var) = VARIABLES.iter().find(|var| var.name() == name) else {
                let rule = "not a parameter or input of any scene";
                return Err(refuse(rule.into(), settable_names()));
            };
            if !settable.iter().any(|s| s.vr == var.vr) {
                return Err(refuse(start_refusal(var, config), settable_names()));
            }
            let value = match v.get_ref() {
                Value::Float(x) => *x,
                Value::Integer(i) => *i as f64,
                _ => return Err(refuse("must be a number".into(), vec![])),
            };
            match var.kind {
                VarKind::Param(p) => p
                    .check_in(value, config)
                    .and_then(|_| p.set(&mut start, value))
                    .map_err(|e| refuse(e.rule_text(), vec![]))?,
                VarKind::Input(i) => {
                    if !i.rule().holds(value) {
                        return Err(refuse(i.rule().text(value, i.unit()), vec![]));
                    }
                    *i.slot(&mut inputs) = value;
                }
                _ => unreachable!("only parameters and inputs are settable"),
            }
        }

        // An input F_N starts at the value its variable states.
        inputs.f_n = start.f_n;
        // The scene's load is the one at which a static force (LuGre's F_S and zeta_t) is
        // given; a static force below the Coulomb force there inverts the law.
        start.set_reference();
        if config.law.has_static_force() {
            if let Some(why) = start.static_force_inverted() {
                let at = entries
                    .iter()
                    .find(|(k, _)| ["F_S", "F_N", "mu"].contains(&k.get_ref().as_str()))
                    .map(|(k, _)| k.span());
                let shown = Some(crate::table::number(start.f_s));
                return Err(self.ctx.err(at.as_ref(), "start.F_S", shown, why, vec![]));
            }
        }
        Ok((start, inputs))
    }

    /// `description`: free text an XML 1.0 document can hold; the configuration's summary when
    /// left out.
    fn description(&self, config: &Config) -> Result<String, SceneError> {
        let key = "description";
        let Some((_, v)) = self.get(key) else {
            return Ok(summary(config));
        };
        let Some(s) = v.get_ref().as_str() else {
            return Err(self.refuse(key, "must be a string"));
        };
        // XML 1.0 cannot hold these, not even escaped.
        match s.chars().find(|&c| {
            (c < ' ' && !matches!(c, '\t' | '\n' | '\r')) || matches!(c, '\u{FFFE}' | '\u{FFFF}')
        }) {
            Some(c) => Err(self.refuse(
                key,
                format!("holds the character U+{:04X}, which XML 1.0 cannot hold (only tab, line feed and carriage return below U+0020)", c as u32),
            )),
            None => Ok(s.to_string()),
        }
    }
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
        let outputs = r.outputs(detail.outputs, &config)?;
        let (start, inputs) = r.start(detail.start, &config, &outputs)?;
        let description = r.description(&config)?;
        Ok(Scene {
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

    /// The variables this scene carries, in table (`ModelVariables`) order.
    pub fn variables(&self) -> impl Iterator<Item = &'static Variable> + '_ {
        VARIABLES
            .iter()
            .filter(move |v| v.present(&self.config, &self.outputs))
            .map(move |v| v.in_scene(&self.config))
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

/// How an error names the configuration: `dahl longitudinal scene with velocity drive`.
fn what(c: &Config) -> String {
    format!(
        "{} {} scene with {} drive",
        c.law.word(),
        c.motion.word(),
        c.drive.word()
    )
}

/// Why an output name is not available in this configuration.
fn output_refusal(name: &str, c: &Config) -> String {
    let what = what(c);
    if let Some(i) = InputId::ALL.into_iter().find(|i| i.name() == name) {
        return if i.present(c) {
            format!("{name} is an input of this {what}, not an output")
        } else if name == "F_d" {
            format!(
                "a {what} has no F_d (an input in force drive, an output in spring drive; in velocity drive F_Fx is the driving force)"
            )
        } else {
            format!("{name} is an input of scenes with input support motion, never an output")
        };
    }
    if OutputId::ALL.iter().any(|o| o.name() == name) {
        return format!("not an output of a {what}");
    }
    if ParamId::from_name(name).is_some() {
        return format!("{name} is a parameter, not an output");
    }
    "not an output of any scene".to_string()
}

/// Why a `[start]` key is refused (the variable exists in some scene, not settable in this one).
fn start_refusal(var: &Variable, c: &Config) -> String {
    let what = what(c);
    let name = var.name();
    match var.kind {
        VarKind::Param(p) if !p.present(c) => {
            format!("{name} is not a parameter of a {what}")
        }
        VarKind::Input(i) if i.present(c) || (i == InputId::FD && c.drive.has_spring()) => {
            format!("{name} is an output of this {what}; outputs have no start value")
        }
        VarKind::Input(InputId::VSx | InputId::VSy) if !c.input_support => {
            format!("{name} is an input only with input support motion (support = [\"input\"])")
        }
        VarKind::Input(_) => format!("{name} is not an input of a {what}"),
        VarKind::State(_) | VarKind::Derivative(_) => format!(
            "{name} is a continuous state of Model Exchange (or its derivative); the body starts at rest at the origin, undeformed"
        ),
        _ => format!("{name} is an output; outputs have no start value"),
    }
}

#[cfg(test)]
mod tests {
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
            "bad.toml:6: colour = \"red\": unknown key; valid: model_identifier, description, law, motion, drive, lateral, support, normal, outputs, start"
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
        assert!(err(&longitudinal("outputs = [\"k_t\"]", "")).starts_with(
            "bad.toml:6: outputs = \"k_t\": k_t is a parameter, not an output; valid: "
        ));
        assert!(err(&longitudinal("outputs = []", "")).starts_with(
            "bad.toml:6: outputs = []: must name at least one output (leave the key out for all of them); valid: \"F_Fx\""
        ));
    }

    #[test]
    fn input_asked_for_as_output() {
        assert!(err(&longitudinal("outputs = [\"v_sx\"]", "")).starts_with(
            "bad.toml:6: outputs = \"v_sx\": v_sx is an input of scenes with input support motion, never an output; valid: "
        ));
        let with_input =
            planar("outputs = [\"v_sx\"]", "").replace("[\"harmonic\"]", "[\"input\"]");
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
}
