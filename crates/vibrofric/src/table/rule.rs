//! What values a parameter or input accepts: a sign physics imposes and the closed range the FMU
//! accepts ([`Rule`]), and the error that names a broken one ([`ParamError`]).

/// What physics forbids outright.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sign {
    /// > 0
    Positive,
    /// >= 0
    NonNegative,
    /// any sign
    Any,
}

/// The physical range of a variable: its sign, and the closed interval `[min, max]` the FMU
/// accepts, wide enough for every real use (grams to tonnes, ultrasonic frequencies, contacts up
/// to 1e13 N/m) and narrow enough that the work per vibration period stays bounded. `min` and
/// `max` are the model description's attributes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rule {
    pub sign: Sign,
    pub min: f64,
    pub max: f64,
}

/// A rule for values `> 0` in `[min, max]`.
pub const fn positive(min: f64, max: f64) -> Rule {
    Rule {
        sign: Sign::Positive,
        min,
        max,
    }
}

/// A rule for values `>= 0` in `[min, max]`.
pub const fn non_negative(min: f64, max: f64) -> Rule {
    Rule {
        sign: Sign::NonNegative,
        min,
        max,
    }
}

/// A rule for values of any sign in `[min, max]`.
pub const fn any(min: f64, max: f64) -> Rule {
    Rule {
        sign: Sign::Any,
        min,
        max,
    }
}

impl Rule {
    pub fn holds(self, v: f64) -> bool {
        v.is_finite() && v >= self.min && v <= self.max
    }

    /// The rule broken by `v`, in words: the sign where that is what `v` breaks, else the
    /// range.
    pub fn text(self, v: f64, unit: &str) -> String {
        let unit = if unit == "1" {
            String::new()
        } else {
            format!(" {unit}")
        };
        let sign = match self.sign {
            Sign::Positive => "must be finite and > 0",
            Sign::NonNegative => "must be finite and >= 0",
            Sign::Any => "must be finite",
        };
        let broken_sign = !v.is_finite()
            || match self.sign {
                Sign::Positive => v <= 0.0,
                Sign::NonNegative => v < 0.0,
                Sign::Any => false,
            };
        if broken_sign {
            format!("{sign} (accepted: {:e} to {:e}{unit})", self.min, self.max)
        } else {
            format!("must be in [{:e}, {:e}]{unit}", self.min, self.max)
        }
    }

    /// Lower bound for the model description's `min` attribute.
    pub fn min(self) -> Option<f64> {
        Some(self.min)
    }

    /// Upper bound for the model description's `max` attribute.
    pub fn max(self) -> Option<f64> {
        Some(self.max)
    }
}

/// A parameter value that breaks its rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamError {
    pub name: &'static str,
    pub value: f64,
    pub rule: Rule,
    pub unit: &'static str,
}

impl ParamError {
    /// The rule the value breaks, in words.
    pub fn rule_text(&self) -> String {
        self.rule.text(self.value, self.unit)
    }
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} = {:e}: {}", self.name, self.value, self.rule_text())
    }
}

impl std::error::Error for ParamError {}
