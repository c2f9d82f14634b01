//! What a contact is made of: the choices a scene makes (`docs/scenes.md`), each key and its
//! values declared once as rows ([`choices!`](super::declare)), and the facts that differ
//! between the values as exhaustive `match`es, so that a new value does not compile until every
//! fact is stated for it.

/// A scene key whose value is one of a declared set of words (`law`, `motion`, ...).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChoiceKey {
    /// The key as a scene writes it.
    pub name: &'static str,
    /// Required, or its default, as the reference states it.
    pub requirement: &'static str,
    /// What a missing required key lacks (`None`: the key has a default).
    pub missing: Option<&'static str>,
    /// What the key means, for the reference.
    pub meaning: &'static str,
    /// The rule a value outside the set breaks.
    pub refusal: &'static str,
    /// The accepted values, as written.
    pub words: &'static [&'static str],
}

choices! {
    /// Friction law of the contact zone.
    Law {
        key: "law",
        requirement: "required",
        missing: "the friction law",
        meaning: "The friction law of the contact.",
        refusal: "not a friction law",
        values: {
            Dahl => "dahl", "Dahl";
            Dupont => "dupont", "Dupont elasto-plastic";
            LuGre => "lugre", "LuGre";
        }
    }
}

choices! {
    /// Kinematics of the contact: 1-D along x, or the full sliding plane.
    Motion {
        key: "motion",
        requirement: "required",
        missing: "the kinematics of the contact",
        meaning: "`longitudinal`: every quantity is a scalar along x. `planar`: deformation, velocities and friction force are vectors in the sliding plane (x, y).",
        refusal: "not a motion",
        values: {
            Longitudinal => "longitudinal", "longitudinal";
            Planar => "planar", "planar";
        }
    }
}

choices! {
    /// How the body is moved.
    Drive {
        key: "drive",
        requirement: "default: `\"force\"`",
        default: Force,
        meaning: "How the body is driven along x: `force` (input `F_d`, the body's motion is integrated), `velocity` (input `v_d` imposed; `F_Fx` is then the driving force), `spring` (a spring `k_d` and damper `c_d` whose far end moves at the input `v_d`; `F_d` is an output).",
        refusal: "not a drive",
        values: {
            /// `F_d` input, body dynamics.
            Force => "force", "force";
            /// `v_x = v_d` imposed.
            Velocity => "velocity", "velocity";
            /// Spring `k_d` and damper `c_d` whose far end moves at `v_d`.
            Spring => "spring", "spring";
        }
    }
}

choices! {
    /// Lateral motion of a planar velocity drive.
    Lateral {
        key: "lateral",
        requirement: "default: `\"guided\"`; only in planar scenes with velocity drive",
        default: Guided,
        meaning: "Lateral motion of a velocity-driven body: `free` (`m·dv_y/dt = −F_Fy`) or `guided` (`v_y = 0`).",
        refusal: "not a lateral motion",
        values: {
            /// `m·dv_y/dt = −F_Fy`
            Free => "free", "free";
            /// `v_y = 0`
            Guided => "guided", "guided";
        }
    }
}

choices! {
    /// A source of support motion; a scene lists one or both ([`Config::harmonic`],
    /// [`Config::input_support`]).
    Support {
        key: "support",
        requirement: "required, a non-empty array",
        missing: "the support motion, a non-empty array",
        meaning: "The support motion: `harmonic` (built in: `u0`, `f`, `phase`, and `angle` in planar scenes), `input` (support velocities `v_sx`, `v_sy` set by the importer), or both (summed).",
        refusal: "not a support motion",
        values: {
            /// The built-in harmonic motion.
            Harmonic => "harmonic", "harmonic";
            /// Support velocities set by the importer.
            Input => "input", "input";
        }
    }
}

choices! {
    /// What the normal force `F_N` is ([`Config::normal_input`]).
    Normal {
        key: "normal",
        requirement: "default: `\"parameter\"`",
        default: Parameter,
        meaning: "The normal force `F_N`: a tunable `parameter`, or a continuous `input` from the host (held or extrapolated with its input derivative; `F_C = mu·F_N(t)` and what follows from it change with it; LuGre's `F_S` and `zeta_t` are given at `F_N`'s start value and follow the load as with a parameter `F_N`; a negative `F_N` is refused, and below the tolerance times the start value the body has lifted off: no friction, no deformation). Its value reference is 2 in either case.",
        refusal: "not a kind of normal force",
        values: {
            /// A tunable parameter.
            Parameter => "parameter", "parameter";
            /// A continuous input.
            Input => "input", "input";
        }
    }
}

/// The facts that set the laws apart, each an exhaustive `match`: a new law is stated in each.
impl Law {
    /// The force has a part proportional to the deformation rate and the relative velocity
    /// (LuGre's `h_t·ds/dt + h_v·v_r`), so it depends on the velocity directly; the others are
    /// `k_t·s`.
    pub const fn force_has_rate(self) -> bool {
        match self {
            Law::Dahl | Law::Dupont => false,
            Law::LuGre => true,
        }
    }

    /// The law has a static force and a Stribeck curve (`F_S`, `v_S`, ...), given at the
    /// reference load, and refuses a static force below the Coulomb force.
    pub const fn has_static_force(self) -> bool {
        match self {
            Law::Dahl | Law::Dupont => false,
            Law::LuGre => true,
        }
    }

    /// The contact has a damping ratio (LuGre's `zeta_t`, of the critical damping
    /// `2·sqrt(m·k_t)`), so the law needs the mass `m` even when the body has no dynamics.
    pub const fn has_contact_damping(self) -> bool {
        match self {
            Law::Dahl | Law::Dupont => false,
            Law::LuGre => true,
        }
    }

    /// The law has a breakaway deformation (Dupont's `r_ba`): in planar motion its weight
    /// `alpha(s, v_r)` couples the two components and has a direction test `s·v_r` (an event).
    pub const fn has_breakaway(self) -> bool {
        match self {
            Law::Dahl | Law::LuGre => false,
            Law::Dupont => true,
        }
    }

    /// The law has a shape exponent (Dahl's `kappa`, in longitudinal motion).
    pub const fn has_exponent(self) -> bool {
        match self {
            Law::Dupont | Law::LuGre => false,
            Law::Dahl => true,
        }
    }
}

/// The facts that set the drives apart.
impl Drive {
    /// The body's velocity along x is the input `v_d` (no dynamics along x).
    pub const fn imposes_velocity(self) -> bool {
        match self {
            Drive::Force | Drive::Spring => false,
            Drive::Velocity => true,
        }
    }

    /// The force on the body is the input `F_d`.
    pub const fn force_input(self) -> bool {
        match self {
            Drive::Velocity | Drive::Spring => false,
            Drive::Force => true,
        }
    }

    /// A spring `k_d` and damper `c_d` drive the body; its far end `x_d` moves at `v_d`.
    pub const fn has_spring(self) -> bool {
        match self {
            Drive::Force | Drive::Velocity => false,
            Drive::Spring => true,
        }
    }
}

/// The structural choices of one contact. Parameter values are not part of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct Config {
    pub law: Law,
    pub motion: Motion,
    pub drive: Drive,
    /// Only meaningful for `Motion::Planar` with `Drive::Velocity`; `Guided` otherwise.
    pub lateral: Lateral,
    /// Built-in harmonic support motion.
    pub harmonic: bool,
    /// Support velocities `v_sx`, `v_sy` set by the importer.
    pub input_support: bool,
    /// The normal force `F_N` is a continuous input (else a tunable parameter).
    pub normal_input: bool,
}

impl Default for Config {
    /// The default scene: Dahl, planar, force drive, harmonic and input support motion.
    fn default() -> Self {
        Config {
            law: Law::Dahl,
            motion: Motion::Planar,
            drive: Drive::Force,
            lateral: Lateral::Guided,
            harmonic: true,
            input_support: true,
            normal_input: false,
        }
    }
}

impl Config {
    pub fn planar(&self) -> bool {
        match self.motion {
            Motion::Longitudinal => false,
            Motion::Planar => true,
        }
    }

    /// True when the scene has a lateral choice: a planar velocity drive.
    pub fn has_lateral_choice(&self) -> bool {
        self.planar() && self.drive.imposes_velocity()
    }

    /// True when the lateral motion `y`, `v_y` is a dynamic state.
    pub fn lateral_free(&self) -> bool {
        self.planar()
            && match self.drive {
                Drive::Velocity => match self.lateral {
                    Lateral::Free => true,
                    Lateral::Guided => false,
                },
                Drive::Force | Drive::Spring => true,
            }
    }

    /// True when the body has dynamics (and so needs the mass `m`).
    pub fn body_dynamic(&self) -> bool {
        !self.drive.imposes_velocity() || self.lateral_free()
    }

    /// Whether the scene lists this support motion.
    pub fn has_support(&self, s: Support) -> bool {
        match s {
            Support::Harmonic => self.harmonic,
            Support::Input => self.input_support,
        }
    }

    /// The normal force's kind.
    pub fn normal(&self) -> Normal {
        if self.normal_input {
            Normal::Input
        } else {
            Normal::Parameter
        }
    }
}
