//! The scene reader's part for a string of contacts: the `[string]` table and the `[start]`
//! values of a string scene (a number for every section, or a list of one per section or
//! link).

#![allow(clippy::result_large_err)]

use std::collections::BTreeMap;

use toml::{Spanned, Value};

use super::reader::Reader;
use super::SceneError;
use crate::description::variables::{VarKind, VARIABLES};
use crate::table::{number, shared_params, Config, Drive, Motion, Params, Shape, StringValues};
use crate::table::{StringVar, MAX_SECTIONS};

type Table = BTreeMap<Spanned<String>, Spanned<Value>>;

impl Reader<'_> {
    /// `[string]`: `sections = N`, only with longitudinal motion and force drive; `None` for a
    /// single contact.
    pub fn string(&self, table: Option<Table>, c: &Config) -> Result<Option<usize>, SceneError> {
        let Some(table) = table else {
            return Ok(None);
        };
        if c.motion != Motion::Longitudinal || c.drive != Drive::Force {
            let (span, _) = self.get("string").expect("the table is there");
            let rule = format!(
                "a string of contacts needs motion = \"longitudinal\" and drive = \"force\" (this scene is {}, {} drive)",
                c.motion.word(),
                c.drive.word()
            );
            return Err(self.ctx.err(Some(&span), "string", None, rule, vec![]));
        }
        if self.get("outputs").is_some() {
            return Err(self.refuse(
                "outputs",
                "a string scene exposes every output of its sections: remove the key",
            ));
        }
        let mut entries: Vec<_> = table.into_iter().collect();
        entries.sort_by_key(|(k, _)| k.span().start);
        let mut sections = None;
        for (k, v) in &entries {
            let name = k.get_ref().as_str();
            let span = k.span();
            let key = format!("string.{name}");
            let shown = Some(self.ctx.shown(v));
            if name != "sections" {
                let valid = vec!["sections".to_string()];
                return Err(self.ctx.err(Some(&span), key, shown, "unknown key", valid));
            }
            match v.get_ref() {
                Value::Integer(n) if (1..=MAX_SECTIONS as i64).contains(n) => {
                    sections = Some(*n as usize)
                }
                _ => {
                    let rule =
                        format!("must be a whole number of sections from 1 to {MAX_SECTIONS}");
                    return Err(self.ctx.err(Some(&span), key, shown, rule, vec![]));
                }
            }
        }
        match sections {
            Some(n) => Ok(Some(n)),
            None => {
                let (span, _) = self.get("string").expect("the table is there");
                Err(self.ctx.err(
                    Some(&span),
                    "string.sections",
                    None,
                    format!("missing (required: the number of sections, 1 to {MAX_SECTIONS})"),
                    vec![],
                ))
            }
        }
    }

    /// `[start]` of a string scene: the shared law parameters (one number each) and the string's
    /// parameters and inputs (a number for every element, or a list of one per element), each
    /// element checked against its rule; then LuGre's `F_S[i] ≥ F_C` at each section's load.
    pub fn string_start(
        &self,
        table: Option<Table>,
        c: &Config,
        n: usize,
    ) -> Result<(Params, StringValues), SceneError> {
        let mut shared = Params::default();
        let strings: Vec<StringVar> = StringVar::ALL
            .into_iter()
            .filter(|v| v.present(c, n) && v.settable(c))
            .collect();
        let shared_ids: Vec<_> = shared_params(c).collect();
        let valid = || -> Vec<String> {
            shared_ids
                .iter()
                .map(|p| p.name().to_string())
                .chain(strings.iter().map(|v| v.name().to_string()))
                .collect()
        };
        let mut entries: Vec<_> = table.unwrap_or_default().into_iter().collect();
        entries.sort_by_key(|(k, _)| k.span().start);
        // The per-section parameters' scalars first set the defaults of every section.
        let mut lists: Vec<(StringVar, &Spanned<String>, &Spanned<Value>)> = vec![];
        for (k, v) in &entries {
            let name = k.get_ref().as_str();
            let span = k.span();
            let refuse = |key: String, rule: String, valid: Vec<String>| {
                self.ctx
                    .err(Some(&span), key, Some(self.ctx.shown(v)), rule, valid)
            };
            let key = format!("start.{name}");
            if let Some(var) = strings.iter().copied().find(|s| s.name() == name) {
                if let (Some(p), Some(x)) = (var.contact_param(), as_number(v.get_ref())) {
                    // Checked per element below; the shared row keeps a valid value.
                    let _ = p.set(&mut shared, x);
                }
                lists.push((var, k, v));
                continue;
            }
            let Some(p) = shared_ids.iter().copied().find(|p| p.name() == name) else {
                let rule = match VARIABLES.iter().find(|r| r.name() == name) {
                    Some(r) if matches!(r.kind, VarKind::Param(_) | VarKind::Input(_)) => {
                        format!("{name} is not a parameter or input of this string scene")
                    }
                    Some(_) => format!("{name} is an output; outputs have no start value"),
                    None if StringVar::from_name(name).is_some() => {
                        format!("{name} is not a parameter or input of this string scene")
                    }
                    None => "not a parameter or input of any scene".to_string(),
                };
                return Err(refuse(key, rule, valid()));
            };
            let Some(x) = as_number(v.get_ref()) else {
                let rule = "must be a number (a parameter shared by every section)".to_string();
                return Err(refuse(key, rule, vec![]));
            };
            p.check_in(x, c)
                .and_then(|_| p.set(&mut shared, x))
                .map_err(|e| refuse(key, e.rule_text(), vec![]))?;
        }
        let mut values = StringValues::new(n, shared.m, shared.f_n, shared.mu, shared.f_s);
        for (var, k, v) in lists {
            self.fill(&mut values, var, k, v, n)?;
        }
        shared.set_reference();
        if c.law.has_static_force() {
            self.static_forces(&entries, &values, &shared)?;
        }
        Ok((shared, values))
    }

    /// The values of one string variable from `[start]`: a number for every element or a list
    /// of exactly one per element.
    fn fill(
        &self,
        values: &mut StringValues,
        var: StringVar,
        k: &Spanned<String>,
        v: &Spanned<Value>,
        n: usize,
    ) -> Result<(), SceneError> {
        let name = var.name();
        let len = var.len(n);
        let span = k.span();
        let shown = Some(self.ctx.shown(v));
        let per = match var.shape() {
            Shape::Section => format!("one per section ({len})"),
            Shape::Link => format!("one per link ({len} for {n} sections)"),
            Shape::One => "one number".to_string(),
        };
        // The error of the value as a whole, breaking `rule`.
        let whole = |rule: String| {
            let key = format!("start.{name}");
            self.ctx.err(Some(&span), key, shown.clone(), rule, vec![])
        };
        let items: Vec<(String, f64)> = match v.get_ref() {
            Value::Array(list) if var.shape().is_array() => {
                if list.len() != len {
                    let rule =
                        format!("a list of {} values: must be a number or {per}", list.len());
                    return Err(whole(rule));
                }
                let mut items = vec![];
                for (i, x) in list.iter().enumerate() {
                    let key = format!("start.{name}[{}]", i + 1);
                    let Some(x) = as_number(x) else {
                        let rule = "must be a number".to_string();
                        return Err(self.ctx.err(Some(&span), key, shown.clone(), rule, vec![]));
                    };
                    items.push((key, x));
                }
                items
            }
            other => match as_number(other) {
                Some(x) => vec![(format!("start.{name}"), x); len],
                None => {
                    let rule = format!("must be a number or {per}");
                    let rule = if var.shape().is_array() {
                        rule
                    } else {
                        "must be a number".into()
                    };
                    return Err(whole(rule));
                }
            },
        };
        let rule = var.rule();
        for (key, x) in &items {
            if !rule.holds(*x) {
                let shown = Some(number(*x));
                let text = rule.text(*x, var.unit());
                return Err(self.ctx.err(Some(&span), key.clone(), shown, text, vec![]));
            }
        }
        for (slot, (_, x)) in values.get_mut(var).iter_mut().zip(items) {
            *slot = x;
        }
        Ok(())
    }

    /// LuGre's static force of each section at its own load: `F_S[i] ≥ mu[i]·F_N[i]`.
    fn static_forces(
        &self,
        entries: &[(Spanned<String>, Spanned<Value>)],
        values: &StringValues,
        shared: &Params,
    ) -> Result<(), SceneError> {
        for i in 0..values.sections {
            let mut p = *shared;
            p.m = values.get(StringVar::M)[i];
            p.f_n = values.get(StringVar::FN)[i];
            p.mu = values.get(StringVar::Mu)[i];
            p.f_s = values.get(StringVar::FS)[i];
            p.set_reference();
            if let Some(why) = p.static_force_inverted() {
                let at = entries
                    .iter()
                    .find(|(k, _)| ["F_S", "F_N", "mu"].contains(&k.get_ref().as_str()))
                    .map(|(k, _)| k.span());
                let key = format!("start.F_S[{}]", i + 1);
                let shown = Some(number(p.f_s));
                let why = format!("section {}: {why}", i + 1);
                return Err(self.ctx.err(at.as_ref(), key, shown, why, vec![]));
            }
        }
        Ok(())
    }
}

fn as_number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(x) => Some(*x),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}
