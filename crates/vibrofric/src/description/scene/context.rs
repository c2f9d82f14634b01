//! What the scene reader's errors point into (the text, its lines) and how they name keys,
//! choices and configurations.

#![allow(clippy::result_large_err)]

use std::collections::BTreeMap;
use std::ops::Range;

use serde::Deserialize;
use toml::{Spanned, Value};

use super::keys::shown;
use super::SceneError;
use crate::description::variables::{VarKind, Variable};
use crate::table::{ChoiceKey, Config, Drive, InputId, Lateral, Law, Motion, Normal};
use crate::table::{OutputId, ParamId, Support};

/// The second reading of a scene: the entries whose elements need their own place in the file.
#[derive(Deserialize, Default)]
pub(super) struct Detail {
    #[serde(default)]
    pub support: Option<Vec<Spanned<Value>>>,
    #[serde(default)]
    pub outputs: Option<Vec<Spanned<Value>>>,
    #[serde(default)]
    pub start: Option<BTreeMap<Spanned<String>, Spanned<Value>>>,
    #[serde(default)]
    pub string: Option<BTreeMap<Spanned<String>, Spanned<Value>>>,
}

/// Context for building errors that point into the text.
pub(super) struct Ctx<'a> {
    pub text: &'a str,
    pub origin: &'a str,
}

impl Ctx<'_> {
    pub fn line(&self, span: &Range<usize>) -> usize {
        let end = span.start.min(self.text.len());
        self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    }

    /// The value as written (its TOML text on one line).
    /// A value as an error message shows it: as written, cut after 200 characters.
    pub fn shown(&self, v: &Spanned<Value>) -> String {
        let span = v.span();
        let s = match self.text.get(span) {
            Some(s) if !s.contains('\n') && !s.is_empty() => s.to_string(),
            _ => v.get_ref().to_string(),
        };
        shown(&s)
    }

    pub fn err(
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

    pub fn toml_error(&self, e: toml::de::Error) -> SceneError {
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

pub(super) fn quoted(words: &[&str]) -> Vec<String> {
    words.iter().map(|w| format!("\"{w}\"")).collect()
}

/// A key whose value is one of the declared rows of `table/config.rs`.
pub(super) trait Choice: Copy + 'static {
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
pub(super) fn word<T: Choice>(
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

/// How an error names the configuration: `dahl longitudinal scene with velocity drive`.
pub(super) fn what(c: &Config) -> String {
    format!(
        "{} {} scene with {} drive",
        c.law.word(),
        c.motion.word(),
        c.drive.word()
    )
}

/// Why an output name is not available in this configuration.
pub(super) fn output_refusal(name: &str, c: &Config) -> String {
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
pub(super) fn start_refusal(var: &Variable, c: &Config) -> String {
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
