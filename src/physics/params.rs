//! Physical parameters of the contact (`docs/model.md`) and the rules that bound them.

/// Every parameter of every scene. A scene uses a subset; the others keep their defaults and
/// are never read by the arithmetic of that scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Body mass `m` [kg].
    pub m: f64,
    /// Normal force `F_N` [N].
    pub f_n: f64,
    /// Coulomb coefficient `mu` [1].
    pub mu: f64,
    /// Tangential contact stiffness `k_t` [N/m].
    pub k_t: f64,
    /// Dahl exponent `kappa` [1] (longitudinal Dahl only).
    pub kappa: f64,
    /// Dupont breakaway ratio `r_ba = s_ba/s_ss` [1].
    pub r_ba: f64,
    /// LuGre static force `F_S` [N].
    pub f_s: f64,
    /// Stribeck velocity `v_S` [m/s].
    pub v_s: f64,
    /// LuGre contact damping ratio `zeta_t` [1] (Eq. 6).
    pub zeta_t: f64,
    /// LuGre viscous coefficient `h_v` [N·s/m].
    pub h_v: f64,
    /// LuGre damping decay velocity `v_e` [m/s] (Eq. 7).
    pub v_e: f64,
    /// Harmonic amplitude `u0` [m].
    pub u0: f64,
    /// Harmonic frequency `f` [Hz].
    pub f: f64,
    /// Vibration direction to x, `angle` [rad].
    pub angle: f64,
    /// Harmonic phase [rad].
    pub phase: f64,
    /// Spring-drive stiffness `k_d` [N/m].
    pub k_d: f64,
    /// Spring-drive damping `c_d` [N·s/m].
    pub c_d: f64,
    /// Averaging window without harmonic source, `T_avg` [s].
    pub t_avg: f64,
    /// Most integrator steps in one communication step, `max_steps` [1] (like CVODE's
    /// `mxstep`): a step that needs more stops with an error that says what to do.
    pub max_steps: f64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            m: 5.6,
            f_n: 55.0,
            mu: 0.2,
            k_t: 1e8,
            kappa: 1.0,
            r_ba: 0.5,
            f_s: 14.3,
            v_s: 1e-3,
            zeta_t: 1.0,
            h_v: 0.0,
            v_e: 1e-3,
            u0: 2e-7,
            f: 2000.0,
            angle: 0.0,
            phase: 0.0,
            k_d: 1e5,
            c_d: 100.0,
            t_avg: 1e-3,
            max_steps: 1e6,
        }
    }
}

/// Identifies one parameter, for generic access by name (scenes, the variable table).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ParamId {
    M,
    FN,
    Mu,
    KT,
    Kappa,
    RBa,
    FS,
    VS,
    ZetaT,
    HV,
    VE,
    U0,
    F,
    Angle,
    Phase,
    KD,
    CD,
    TAvg,
    MaxSteps,
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

/// The physical range of a parameter: its sign, and the closed interval `[min, max]` the FMU
/// accepts, wide enough for every real use (grams to tonnes, ultrasonic frequencies, contacts up
/// to 1e13 N/m) and narrow enough that the work per vibration period stays bounded. `min` and
/// `max` are the model description's attributes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rule {
    pub sign: Sign,
    pub min: f64,
    pub max: f64,
}

impl Rule {
    const fn new(sign: Sign, min: f64, max: f64) -> Rule {
        Rule { sign, min, max }
    }

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

impl ParamId {
    pub const ALL: [ParamId; 19] = [
        ParamId::M,
        ParamId::FN,
        ParamId::Mu,
        ParamId::KT,
        ParamId::Kappa,
        ParamId::RBa,
        ParamId::FS,
        ParamId::VS,
        ParamId::ZetaT,
        ParamId::HV,
        ParamId::VE,
        ParamId::U0,
        ParamId::F,
        ParamId::Angle,
        ParamId::Phase,
        ParamId::KD,
        ParamId::CD,
        ParamId::TAvg,
        ParamId::MaxSteps,
    ];

    /// The variable name (the table of `docs/model.md`).
    pub fn name(self) -> &'static str {
        match self {
            ParamId::M => "m",
            ParamId::FN => "F_N",
            ParamId::Mu => "mu",
            ParamId::KT => "k_t",
            ParamId::Kappa => "kappa",
            ParamId::RBa => "r_ba",
            ParamId::FS => "F_S",
            ParamId::VS => "v_S",
            ParamId::ZetaT => "zeta_t",
            ParamId::HV => "h_v",
            ParamId::VE => "v_e",
            ParamId::U0 => "u0",
            ParamId::F => "f",
            ParamId::Angle => "angle",
            ParamId::Phase => "phase",
            ParamId::KD => "k_d",
            ParamId::CD => "c_d",
            ParamId::TAvg => "T_avg",
            ParamId::MaxSteps => "max_steps",
        }
    }

    pub fn from_name(name: &str) -> Option<ParamId> {
        ParamId::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The accepted range (see [`Rule`]).
    pub fn rule(self) -> Rule {
        use Sign::*;
        match self {
            ParamId::M => Rule::new(Positive, 1e-4, 1e6), // 0.1 g to 1000 t
            ParamId::FN => Rule::new(NonNegative, 0.0, 1e8),
            ParamId::Mu => Rule::new(NonNegative, 0.0, 10.0),
            ParamId::KT => Rule::new(Positive, 1e2, 1e13),
            ParamId::Kappa => Rule::new(Positive, 0.05, 20.0),
            ParamId::RBa => Rule::new(NonNegative, 0.0, 0.999),
            ParamId::FS => Rule::new(NonNegative, 0.0, 1e9),
            ParamId::VS | ParamId::VE => Rule::new(Positive, 1e-9, 1e2),
            ParamId::ZetaT => Rule::new(NonNegative, 0.0, 1e3),
            ParamId::HV | ParamId::CD => Rule::new(NonNegative, 0.0, 1e9),
            ParamId::U0 => Rule::new(NonNegative, 0.0, 0.01), // to 1 cm
            ParamId::F => Rule::new(NonNegative, 0.0, 1e7),   // to 10 MHz
            ParamId::Angle | ParamId::Phase => Rule::new(Any, -1e4, 1e4),
            ParamId::KD => Rule::new(NonNegative, 0.0, 1e13),
            ParamId::TAvg => Rule::new(Positive, 1e-9, 1e6),
            ParamId::MaxSteps => Rule::new(Positive, 1e2, 1e10),
        }
    }

    /// True when the parameter may change during the simulation (variability tunable): the
    /// vibration source, which test-rig protocols step, and the normal load.
    pub fn tunable(self) -> bool {
        matches!(
            self,
            ParamId::U0
                | ParamId::F
                | ParamId::Angle
                | ParamId::Phase
                | ParamId::FN
                | ParamId::Mu
                | ParamId::MaxSteps
        )
    }

    /// Unit of the parameter, as named in the model description's `UnitDefinitions`.
    pub fn unit(self) -> &'static str {
        match self {
            ParamId::M => "kg",
            ParamId::FN | ParamId::FS => "N",
            ParamId::Mu | ParamId::Kappa | ParamId::RBa | ParamId::ZetaT | ParamId::MaxSteps => "1",
            ParamId::KT | ParamId::KD => "N/m",
            ParamId::VS | ParamId::VE => "m/s",
            ParamId::HV | ParamId::CD => "N.s/m",
            ParamId::U0 => "m",
            ParamId::F => "Hz",
            ParamId::Angle | ParamId::Phase => "rad",
            ParamId::TAvg => "s",
        }
    }

    pub fn get(self, p: &Params) -> f64 {
        match self {
            ParamId::M => p.m,
            ParamId::FN => p.f_n,
            ParamId::Mu => p.mu,
            ParamId::KT => p.k_t,
            ParamId::Kappa => p.kappa,
            ParamId::RBa => p.r_ba,
            ParamId::FS => p.f_s,
            ParamId::VS => p.v_s,
            ParamId::ZetaT => p.zeta_t,
            ParamId::HV => p.h_v,
            ParamId::VE => p.v_e,
            ParamId::U0 => p.u0,
            ParamId::F => p.f,
            ParamId::Angle => p.angle,
            ParamId::Phase => p.phase,
            ParamId::KD => p.k_d,
            ParamId::CD => p.c_d,
            ParamId::TAvg => p.t_avg,
            ParamId::MaxSteps => p.max_steps,
        }
    }

    fn slot(self, p: &mut Params) -> &mut f64 {
        match self {
            ParamId::M => &mut p.m,
            ParamId::FN => &mut p.f_n,
            ParamId::Mu => &mut p.mu,
            ParamId::KT => &mut p.k_t,
            ParamId::Kappa => &mut p.kappa,
            ParamId::RBa => &mut p.r_ba,
            ParamId::FS => &mut p.f_s,
            ParamId::VS => &mut p.v_s,
            ParamId::ZetaT => &mut p.zeta_t,
            ParamId::HV => &mut p.h_v,
            ParamId::VE => &mut p.v_e,
            ParamId::U0 => &mut p.u0,
            ParamId::F => &mut p.f,
            ParamId::Angle => &mut p.angle,
            ParamId::Phase => &mut p.phase,
            ParamId::KD => &mut p.k_d,
            ParamId::CD => &mut p.c_d,
            ParamId::TAvg => &mut p.t_avg,
            ParamId::MaxSteps => &mut p.max_steps,
        }
    }

    /// Sets the parameter if the value obeys its rule; otherwise leaves `p` untouched.
    pub fn set(self, p: &mut Params, value: f64) -> Result<(), ParamError> {
        self.check(value)?;
        *self.slot(p) = value;
        Ok(())
    }

    pub fn check(self, value: f64) -> Result<(), ParamError> {
        let rule = self.rule();
        if rule.holds(value) {
            Ok(())
        } else {
            Err(ParamError {
                name: self.name(),
                value,
                rule,
            })
        }
    }
}

/// A parameter value that breaks its physical rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamError {
    pub name: &'static str,
    pub value: f64,
    pub rule: Rule,
}

impl ParamError {
    /// The rule the value breaks, in words.
    pub fn rule_text(&self) -> String {
        let unit = ParamId::from_name(self.name).map_or("1", |p| p.unit());
        self.rule.text(self.value, unit)
    }
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} = {:e}: {}", self.name, self.value, self.rule_text())
    }
}

impl std::error::Error for ParamError {}

impl Params {
    /// Checks every parameter against its rule.
    pub fn validate(&self) -> Result<(), ParamError> {
        for id in ParamId::ALL {
            id.check(id.get(self))?;
        }
        Ok(())
    }

    /// Coulomb force `F_C = mu·F_N`.
    pub fn f_c(&self) -> f64 {
        self.mu * self.f_n
    }

    /// Angular frequency `omega = 2·pi·f`.
    pub fn omega(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.f
    }

    /// Velocity amplitude of the harmonic source `v_a = omega·u0`.
    pub fn v_a(&self) -> f64 {
        self.omega() * self.u0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_obey_rules() {
        Params::default().validate().unwrap();
    }

    #[test]
    fn names_round_trip_and_bad_values_leave_params_untouched() {
        for id in ParamId::ALL {
            assert_eq!(ParamId::from_name(id.name()), Some(id));
        }
        let mut p = Params::default();
        let err = ParamId::KT.set(&mut p, 0.0).unwrap_err();
        assert_eq!(err.name, "k_t");
        assert_eq!(p, Params::default());
        assert!(ParamId::RBa.set(&mut p, 1.0).is_err());
        assert!(ParamId::Mu.set(&mut p, f64::NAN).is_err());
        assert!(ParamId::FN.set(&mut p, 0.0).is_ok());
    }
}
