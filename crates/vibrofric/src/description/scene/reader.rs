//! The scene reader: each top-level key read and checked against its rule.

#![allow(clippy::result_large_err)]

use std::collections::BTreeMap;
use std::ops::Range;

use toml::{Spanned, Value};

use super::context::{output_refusal, quoted, start_refusal, word, Choice, Ctx, Detail};
use super::keys::{is_c_identifier, KEYS, MAX_IDENTIFIER};
use super::{default_inputs, summary, SceneError};
use crate::description::variables::{VarKind, Variable, VARIABLES};
use crate::table::{Config, Drive, Inputs, Lateral, Motion, OutputId, Params, Support};

/// A scene's top-level table, read once, with the context its errors point into.
pub(super) struct Reader<'a> {
    pub(super) ctx: Ctx<'a>,
    top: BTreeMap<Spanned<String>, Spanned<Value>>,
}

impl<'a> Reader<'a> {
    /// The first reading: TOML syntax, then every key known.
    pub fn new(text: &'a str, origin: &'a str) -> Result<Reader<'a>, SceneError> {
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
    pub(super) fn get(&self, key: &str) -> Option<(Range<usize>, Spanned<Value>)> {
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
    pub(super) fn refuse(&self, key: &str, rule: impl Into<String>) -> SceneError {
        let (ks, v) = self.get(key).expect("refusing a key that is present");
        self.ctx
            .err(Some(&ks), key, Some(self.ctx.shown(&v)), rule, vec![])
    }

    pub fn model_identifier(&self) -> Result<String, SceneError> {
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
    pub fn choice<T: Choice>(&self) -> Result<T, SceneError> {
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
    pub fn lateral(&self, motion: Motion, drive: Drive) -> Result<Lateral, SceneError> {
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
    pub fn detail(&self) -> Result<Detail, SceneError> {
        for (key, is_ok, what) in [
            (
                Support::KEY.name,
                Value::is_array as fn(&Value) -> bool,
                "an array of strings",
            ),
            ("outputs", Value::is_array, "an array of strings"),
            ("start", Value::is_table, "a table"),
            ("string", Value::is_table, "a table (sections = N)"),
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
    pub fn support(&self, list: Option<Vec<Spanned<Value>>>) -> Result<Vec<Support>, SceneError> {
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
    pub fn outputs(
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
    pub fn start(
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
    pub fn description(&self, config: &Config) -> Result<String, SceneError> {
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
