//! What a string is made of (its law, support and load inputs) and its parameters: the
//! shared law, the per-section arrays and the links, with the rules they must satisfy.

use crate::table::{number, Law, ParamId, Params, StringValues, StringVar, MAX_SECTIONS};

use super::equations::Links;
use super::SimError;

/// What a string is made of: the law, whether the support vibrates harmonically (the same
/// source under every section) and whether the normal forces are inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StringConfig {
    pub law: Law,
    pub harmonic: bool,
    pub normal_input: bool,
}

/// The parameters of a string. `shared` holds the law's parameters common to every section (and
/// the harmonic source's, the step budget); the per-section arrays override its `m`, `mu`,
/// `F_N` and `F_S`, each section's start load being its own reference load (so that `F_S[i]` is
/// given at section `i`'s load and `zeta_t` is the damping ratio of every section at its own).
#[derive(Clone, Debug, PartialEq)]
pub struct StringParams {
    pub shared: Params,
    pub m: Vec<f64>,
    pub mu: Vec<f64>,
    pub f_n: Vec<f64>,
    pub f_s: Vec<f64>,
    pub links: Links,
}

impl StringParams {
    /// `n` sections of the shared parameters' `m`, `mu`, `F_N`, `F_S`, links of stiffness
    /// `k_s` and damping `c_s`, free ends.
    pub fn uniform(n: usize, shared: Params, k_s: f64, c_s: f64) -> Self {
        StringParams {
            shared,
            m: vec![shared.m; n],
            mu: vec![shared.mu; n],
            f_n: vec![shared.f_n; n],
            f_s: vec![shared.f_s; n],
            links: Links {
                k_s: vec![k_s; n.saturating_sub(1)],
                c_s: vec![c_s; n.saturating_sub(1)],
                k_top: 0.0,
                c_top: 0.0,
                k_bottom: 0.0,
                c_bottom: 0.0,
            },
        }
    }

    /// A string's parameters from a scene's values: the law's shared parameters, each
    /// section's `m`, `mu`, `F_S` and the links and ends from `v`, and each section's load
    /// `f_n` (where the normal force is an input, the scene's start values: the load at which
    /// `F_S` and `zeta_t` are given).
    pub fn from_values(shared: Params, v: &StringValues, f_n: &[f64]) -> Self {
        StringParams {
            shared,
            m: v.get(StringVar::M).to_vec(),
            mu: v.get(StringVar::Mu).to_vec(),
            f_n: f_n.to_vec(),
            f_s: v.get(StringVar::FS).to_vec(),
            links: Links {
                k_s: v.get(StringVar::KS).to_vec(),
                c_s: v.get(StringVar::CS).to_vec(),
                k_top: v.one(StringVar::KTop),
                c_top: v.one(StringVar::CTop),
                k_bottom: v.one(StringVar::KBottom),
                c_bottom: v.one(StringVar::CBottom),
            },
        }
    }

    pub fn sections(&self) -> usize {
        self.m.len()
    }

    /// Section `i`'s parameters, with its start load as its reference load.
    pub fn section(&self, i: usize) -> Params {
        let mut p = self.shared;
        p.m = self.m[i];
        p.mu = self.mu[i];
        p.f_n = self.f_n[i];
        p.f_s = self.f_s[i];
        p.f_n_ref = p.f_n;
        p.mu_ref = p.mu;
        p
    }

    /// Every rule: the shared parameters' own, each section's `m`, `mu`, `F_N`, `F_S` by the
    /// scalar's rule (named with its index, 1-based), the links' and ends' (finite, ≥ 0), the
    /// array lengths, and LuGre's `F_S ≥ F_C` per section.
    pub fn validate(&self, law: Law) -> Result<(), SimError> {
        let n = self.sections();
        if n == 0 || n > MAX_SECTIONS {
            return Err(SimError::Inconsistent(format!(
                "sections = {n}: a string has 1 to {MAX_SECTIONS} sections"
            )));
        }
        for (name, len, want) in [
            ("mu", self.mu.len(), n),
            ("F_N", self.f_n.len(), n),
            ("F_S", self.f_s.len(), n),
            ("k_s", self.links.k_s.len(), n - 1),
            ("c_s", self.links.c_s.len(), n - 1),
        ] {
            if len != want {
                return Err(SimError::Inconsistent(format!(
                    "{name} has {len} values: a string of {n} sections needs {want}"
                )));
            }
        }
        self.shared.validate()?;
        for (id, values) in [
            (ParamId::M, &self.m),
            (ParamId::Mu, &self.mu),
            (ParamId::FN, &self.f_n),
            (ParamId::FS, &self.f_s),
        ] {
            for (i, &v) in values.iter().enumerate() {
                if !id.rule().holds(v) {
                    return Err(SimError::Inconsistent(format!(
                        "{}[{}] = {}: {}",
                        id.name(),
                        i + 1,
                        number(v),
                        id.rule().text(v, id.unit())
                    )));
                }
            }
        }
        let l = &self.links;
        let ends = [
            ("k_top", l.k_top),
            ("c_top", l.c_top),
            ("k_bottom", l.k_bottom),
            ("c_bottom", l.c_bottom),
        ];
        let named = |name: &str, i: usize| format!("{name}[{}]", i + 1);
        let links = (l.k_s.iter().enumerate().map(|(i, &v)| (named("k_s", i), v)))
            .chain(l.c_s.iter().enumerate().map(|(i, &v)| (named("c_s", i), v)));
        for (name, v) in ends
            .map(|(n, v)| (n.to_string(), v))
            .into_iter()
            .chain(links)
        {
            if !(v.is_finite() && (0.0..=1e13).contains(&v)) {
                return Err(SimError::Inconsistent(format!(
                    "{name} = {}: must be finite, >= 0 and <= 1e13",
                    number(v)
                )));
            }
        }
        if law.has_static_force() {
            for i in 0..n {
                let p = self.section(i);
                if p.static_force() < p.f_c() {
                    return Err(SimError::Inconsistent(format!(
                        "F_S[{}] = {} N is below the Coulomb force F_C = mu[{0}]·F_N[{0}] = {} N of its section: LuGre's static force must be at least F_C",
                        i + 1,
                        number(p.f_s),
                        number(p.f_c())
                    )));
                }
            }
        }
        Ok(())
    }
}
