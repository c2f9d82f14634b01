//! What values a parameter or input accepts: a sign physics imposes and the closed range the FMU
//! accepts ([`Rule`]), and the error that names a broken one ([`ParamError`]).

/// A number as a person writes it, in messages and in the model description: plain decimals
/// from 0.001 to below a million (`-1`, `-0.5`, `0`, `14.3`, `2000`), the shortest exponent form
/// outside (`2e-7`, `1e13`, `-3.5e-9`); each the shortest text that reads back as the same `f64`.
/// Non-finite values print as `NaN`, `inf`, `-inf`.
pub fn number(x: f64) -> String {
    let a = x.abs();
    if a.is_finite() && a != 0.0 && !(1e-3..1e6).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

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
            format!(
                "{sign} (accepted: {} to {}{unit})",
                number(self.min),
                number(self.max)
            )
        } else {
            format!(
                "must be in [{}, {}]{unit}",
                number(self.min),
                number(self.max)
            )
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
        write!(
            f,
            "{} = {}: {}",
            self.name,
            number(self.value),
            self.rule_text()
        )
    }
}

impl std::error::Error for ParamError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_as_a_person_writes_them_and_round_trip() {
        for (x, text) in [
            (-1.0, "-1"),
            (-0.5, "-0.5"),
            (0.0, "0"),
            (-0.0, "-0"),
            (2e-7, "2e-7"),
            (14.3, "14.3"),
            (0.001, "0.001"),
            (0.000999, "9.99e-4"),
            (999_999.0, "999999"),
            (1e6, "1e6"),
            (1e13, "1e13"),
            (-3.5e-9, "-3.5e-9"),
            (0.999, "0.999"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(number(x), text, "{x:e}");
            if x.is_finite() {
                assert_eq!(
                    text.parse::<f64>().unwrap().to_bits(),
                    x.to_bits(),
                    "{text}"
                );
            }
        }
        // The shortest text that reads back exactly, never a rounded one.
        let x = 0.1 + 0.2;
        assert_eq!(number(x), "0.30000000000000004");
    }

    #[test]
    fn errors_name_the_value_and_the_range_in_plain_numbers() {
        let e = ParamError {
            name: "k_t",
            value: -1.0,
            rule: positive(1e2, 1e13),
            unit: "N/m",
        };
        assert_eq!(
            e.to_string(),
            "k_t = -1: must be finite and > 0 (accepted: 100 to 1e13 N/m)"
        );
        let e = ParamError {
            name: "r_ba",
            value: 1.0,
            rule: non_negative(0.0, 0.999),
            unit: "1",
        };
        assert_eq!(e.to_string(), "r_ba = 1: must be in [0, 0.999]");
        let e = ParamError {
            name: "mu",
            value: -0.5,
            rule: non_negative(0.0, 10.0),
            unit: "1",
        };
        assert_eq!(
            e.to_string(),
            "mu = -0.5: must be finite and >= 0 (accepted: 0 to 10)"
        );
    }
}
