//! The variables of a string of contacts, each declared once: a per-section or per-link array
//! (`m[i]`, `k_s[i]`, `x[i]`, ...) or one value for the whole string (`k_top`, `F_bottom`, ...),
//! with its name, value reference, unit, rule, description and what it depends on. The law's
//! other parameters (`k_t`, `v_S`, `zeta_t`, ...) are the single contact's rows, shared by every
//! section ([`shared_params`]).
//!
//! Value references: an array variable has a base `b`; FMI 3.0 declares it as one variable of
//! value reference `b·1000000` with a dimension, FMI 2.0 as scalars `name[i]` of value
//! reference `b·1000000 + i` (`i` = 1 … its length, at most 100000). A scalar of the string has
//! its own small value reference (21–24, 105, 106, 221–224), next to the single contact's
//! (1–19, 101–104, 201–213, 301–503). A variable keeps its value references in every FMU: the
//! bases are the single contact's value references of the same quantity where there is one
//! (`m` 1, `F_N` 2, `mu` 3, `F_S` 7, `F_d` 101, `v_sx` 103, `F_Fx` 201, `x` 203, `v_x` 205,
//! `s_x` 207, `F_Fx_step` 212) and new ones otherwise (`k_s` 25, `c_s` 26, `F_link` 220).

use serde::{Deserialize, Serialize};

use super::rule::non_negative;
use super::{force_knowns, rate_knowns, velocity_knowns, Known, StateId};
use super::{Config, Dependency, Depends, InputId, ParamId, Rule};

/// Most sections a string may have.
pub const MAX_SECTIONS: usize = 100_000;

/// The factor between an array's base and its value reference.
pub const ARRAY_STRIDE: u32 = 1_000_000;

/// How many values a string variable has in a string of `n` sections.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// One per section (`n`).
    Section,
    /// One per link between neighbours (`n − 1`).
    Link,
    /// One for the whole string.
    One,
}

impl Shape {
    pub fn len(self, n: usize) -> usize {
        match self {
            Shape::Section => n,
            Shape::Link => n.saturating_sub(1),
            Shape::One => 1,
        }
    }

    pub fn is_array(self) -> bool {
        self != Shape::One
    }
}

/// A string variable's causality.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    Param,
    Input,
    Output,
    /// Model Exchange's continuous states of their own, their derivatives and the event
    /// indicators (causality local, computed by the FMU).
    Local,
}

/// The variables of a string scene besides the shared law parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum StringVar {
    M,
    FN,
    Mu,
    FS,
    KS,
    CS,
    KTop,
    CTop,
    KBottom,
    CBottom,
    FD,
    VSx,
    VTop,
    VBottom,
    FFx,
    X,
    Vx,
    Sx,
    FFxStep,
    FLink,
    FTop,
    FBottom,
    FTopStep,
    FBottomStep,
    XTop,
    XBottom,
    DerX,
    DerVx,
    DerSx,
    DerXTop,
    DerXBottom,
    EventVrx,
}

/// One declaration: name, base value reference, shape, causality (`F_N` is an input where the
/// normal force is one), unit, display unit, description.
struct Row {
    name: &'static str,
    base: u32,
    shape: Shape,
    role: Role,
    unit: &'static str,
    display: Option<&'static str>,
    description: &'static str,
}

const fn row(
    name: &'static str,
    base: u32,
    shape: Shape,
    role: Role,
    unit: &'static str,
    display: Option<&'static str>,
    description: &'static str,
) -> Row {
    Row {
        name,
        base,
        shape,
        role,
        unit,
        display,
        description,
    }
}

use Role::{Input as In, Local as Loc, Output as Out, Param as Par};
use Shape::{Link, One, Section};

/// The declarations, in the order of [`StringVar::ALL`].
const ROWS: [Row; 32] = [
    row("m", 1, Section, Par, "kg", None, "Mass of each section"),
    row("F_N", 2, Section, Par, "N", None, "Normal force pressing each section on its support (the wall)"),
    row("mu", 3, Section, Par, "1", None, "Coulomb friction coefficient of each section's contact"),
    row("F_S", 7, Section, Par, "N", None, "LuGre static friction force of each section, given at that section's own load (its start values of F_N and mu)"),
    row("k_s", 25, Link, Par, "N/m", None, "Stiffness of each link between neighbouring sections (EA/L of a pipe)"),
    row("c_s", 26, Link, Par, "N.s/m", None, "Damping of each link between neighbouring sections"),
    row("k_top", 21, One, Par, "N/m", None, "Stiffness of the top element holding section 1 (0: free end)"),
    row("c_top", 22, One, Par, "N.s/m", None, "Damping of the top element holding section 1 (0: free end)"),
    row("k_bottom", 23, One, Par, "N/m", None, "Stiffness of the bottom element holding section N (0: free end)"),
    row("c_bottom", 24, One, Par, "N.s/m", None, "Damping of the bottom element holding section N (0: free end)"),
    row("F_d", 101, Section, In, "N", None, "External axial force on each section (a push, a tool)"),
    row("v_sx", 103, Section, In, "m/s", Some("mm/s"), "Support (wall) velocity along x under each section"),
    row("v_top", 105, One, In, "m/s", Some("mm/s"), "Velocity of the point the top element holds (the fed top)"),
    row("v_bottom", 106, One, In, "m/s", Some("mm/s"), "Velocity of the point the bottom element holds (the rock advancing)"),
    row("F_Fx", 201, Section, Out, "N", None, "Friction force on each section along x"),
    row("x", 203, Section, Out, "m", Some("um"), "Position of each section along x"),
    row("v_x", 205, Section, Out, "m/s", Some("mm/s"), "Velocity of each section along x"),
    row("s_x", 207, Section, Out, "m", Some("um"), "Contact deformation of each section"),
    row("F_Fx_step", 212, Section, Out, "N", None, "Mean of each section's F_Fx over the last communication step (exact integral / step size)"),
    row("F_link", 220, Link, Out, "N", None, "Force in each link, tension positive: k_s*(x[i+1]-x[i]) + c_s*(v_x[i+1]-v_x[i])"),
    row("F_top", 221, One, Out, "N", None, "Force of the top element on section 1: k_top*(x_top-x[1]) + c_top*(v_top-v_x[1])"),
    row("F_bottom", 222, One, Out, "N", None, "Force of section N on what holds it (the weight on bit): k_bottom*(x[N]-x_bottom) + c_bottom*(v_x[N]-v_bottom)"),
    row("F_top_step", 223, One, Out, "N", None, "Mean of F_top over the last communication step (exact integral / step size)"),
    row("F_bottom_step", 224, One, Out, "N", None, "Mean of F_bottom over the last communication step (exact integral / step size)"),
    row("x_top", 309, One, Loc, "m", Some("um"), "State (Model Exchange): position of the point the top element holds, the integral of v_top"),
    row("x_bottom", 310, One, Loc, "m", Some("um"), "State (Model Exchange): position of the point the bottom element holds, the integral of v_bottom"),
    row("der(x)", 403, Section, Loc, "m/s", Some("mm/s"), "Velocity of each section (the derivative of the state x)"),
    row("der(v_x)", 405, Section, Loc, "m/s2", None, "Acceleration of each section (the derivative of the state v_x)"),
    row("der(s_x)", 401, Section, Loc, "m/s", Some("mm/s"), "Deformation rate of each section's contact (the friction law; the derivative of the state s_x)"),
    row("der(x_top)", 409, One, Loc, "m/s", Some("mm/s"), "Velocity of the point the top element holds (v_top)"),
    row("der(x_bottom)", 410, One, Loc, "m/s", Some("mm/s"), "Velocity of the point the bottom element holds (v_bottom)"),
    row("event.v_rx", 501, Section, Loc, "m/s", None, "Event indicator (Model Exchange): each section's v_rx = v_x - v_sx shifted by its hysteresis band (a sign change is a kink of |v_r|)"),
];

/// The rule of the links and end elements (finite, ≥ 0).
pub const LINK_RULE: Rule = non_negative(0.0, 1e13);

impl StringVar {
    pub const ALL: [StringVar; 32] = [
        StringVar::M,
        StringVar::FN,
        StringVar::Mu,
        StringVar::FS,
        StringVar::KS,
        StringVar::CS,
        StringVar::KTop,
        StringVar::CTop,
        StringVar::KBottom,
        StringVar::CBottom,
        StringVar::FD,
        StringVar::VSx,
        StringVar::VTop,
        StringVar::VBottom,
        StringVar::FFx,
        StringVar::X,
        StringVar::Vx,
        StringVar::Sx,
        StringVar::FFxStep,
        StringVar::FLink,
        StringVar::FTop,
        StringVar::FBottom,
        StringVar::FTopStep,
        StringVar::FBottomStep,
        StringVar::XTop,
        StringVar::XBottom,
        StringVar::DerX,
        StringVar::DerVx,
        StringVar::DerSx,
        StringVar::DerXTop,
        StringVar::DerXBottom,
        StringVar::EventVrx,
    ];

    /// Model Exchange's derivatives, in the order of the state vector `[x, v_x, s_x, x_top,
    /// x_bottom]` (each array's elements in order).
    pub const DERIVATIVES: [StringVar; 5] = [
        StringVar::DerX,
        StringVar::DerVx,
        StringVar::DerSx,
        StringVar::DerXTop,
        StringVar::DerXBottom,
    ];

    /// The state a derivative variable is the derivative of.
    pub fn derivative_of(self) -> Option<StringVar> {
        match self {
            StringVar::DerX => Some(StringVar::X),
            StringVar::DerVx => Some(StringVar::Vx),
            StringVar::DerSx => Some(StringVar::Sx),
            StringVar::DerXTop => Some(StringVar::XTop),
            StringVar::DerXBottom => Some(StringVar::XBottom),
            _ => None,
        }
    }

    /// Where element `i` of a state (or of its derivative) sits in the state vector of a
    /// string of `n` sections; `None` for a variable that is neither.
    pub fn state_index(self, n: usize, i: usize) -> Option<usize> {
        let state = self.derivative_of().unwrap_or(self);
        match state {
            StringVar::X => Some(i),
            StringVar::Vx => Some(n + i),
            StringVar::Sx => Some(2 * n + i),
            StringVar::XTop => Some(3 * n),
            StringVar::XBottom => Some(3 * n + 1),
            _ => None,
        }
    }

    fn row(self) -> &'static Row {
        &ROWS[self as usize]
    }

    pub fn index(self) -> usize {
        self as usize
    }

    pub fn name(self) -> &'static str {
        self.row().name
    }

    pub fn shape(self) -> Shape {
        self.row().shape
    }

    pub fn unit(self) -> &'static str {
        self.row().unit
    }

    pub fn display_unit(self) -> Option<&'static str> {
        self.row().display
    }

    pub fn description(self) -> &'static str {
        self.row().description
    }

    /// The causality in a scene of this configuration: `F_N` is an input where the normal force
    /// is one.
    pub fn role(self, c: &Config) -> Role {
        match self {
            StringVar::FN if c.normal_input => Role::Input,
            _ => self.row().role,
        }
    }

    /// Parameters of the string are fixed (set before initialization ends).
    pub fn settable(self, c: &Config) -> bool {
        matches!(self.role(c), Role::Param | Role::Input)
    }

    /// How many values it has in a string of `n` sections.
    pub fn len(self, n: usize) -> usize {
        self.shape().len(n)
    }

    /// True when a string scene of this configuration and `n` sections has it (the links'
    /// variables only from two sections on).
    pub fn present(self, c: &Config, n: usize) -> bool {
        let by_config = match self {
            StringVar::FS => c.law.has_static_force(),
            StringVar::VSx => c.input_support,
            _ => true,
        };
        by_config && self.len(n) > 0
    }

    /// The value reference of the variable: of a scalar, or of an array as FMI 3.0 declares it.
    pub fn vr(self) -> u32 {
        let r = self.row();
        if r.shape.is_array() {
            r.base * ARRAY_STRIDE
        } else {
            r.base
        }
    }

    /// The value reference of element `i` (0-based) as FMI 2.0 declares it: `x[i+1]`.
    pub fn element_vr(self, i: usize) -> u32 {
        if self.shape().is_array() {
            self.vr() + i as u32 + 1
        } else {
            self.vr()
        }
    }

    /// The FMI 2.0 name of element `i` (0-based): `x[1]` for the first.
    pub fn element_name(self, i: usize) -> String {
        if let (Some(x), true) = (self.derivative_of(), self.shape().is_array()) {
            format!("der({})", x.element_name(i))
        } else if self.shape().is_array() {
            format!("{}[{}]", self.name(), i + 1)
        } else {
            self.name().to_string()
        }
    }

    /// The variable and element (0-based) an FMI 2.0 value reference names, if any (the
    /// element may be beyond the string's length).
    pub fn from_element_vr(vr: u32) -> Option<(StringVar, usize)> {
        let (base, i) = (vr / ARRAY_STRIDE, vr % ARRAY_STRIDE);
        StringVar::ALL.into_iter().find_map(|v| {
            let r = v.row();
            match r.shape.is_array() {
                true if base == r.base && i >= 1 => Some((v, i as usize - 1)),
                false if vr == r.base => Some((v, 0)),
                _ => None,
            }
        })
    }

    /// The variable an FMI 3.0 value reference names, if any.
    pub fn from_vr(vr: u32) -> Option<StringVar> {
        StringVar::ALL.into_iter().find(|v| v.vr() == vr)
    }

    pub fn from_name(name: &str) -> Option<StringVar> {
        StringVar::ALL.into_iter().find(|v| v.name() == name)
    }

    /// The accepted range of a parameter or input: the single contact's variable's where there
    /// is one, the links' and ends' `[0, 1e13]` otherwise.
    pub fn rule(self) -> Rule {
        match self {
            StringVar::M => ParamId::M.rule(),
            StringVar::FN => ParamId::FN.rule(),
            StringVar::Mu => ParamId::Mu.rule(),
            StringVar::FS => ParamId::FS.rule(),
            StringVar::FD => InputId::FD.rule(),
            StringVar::VSx | StringVar::VTop | StringVar::VBottom => InputId::VSx.rule(),
            _ => LINK_RULE,
        }
    }

    /// The single contact's parameter whose value is this per-section parameter's default.
    pub fn contact_param(self) -> Option<ParamId> {
        match self {
            StringVar::M => Some(ParamId::M),
            StringVar::FN => Some(ParamId::FN),
            StringVar::Mu => Some(ParamId::Mu),
            StringVar::FS => Some(ParamId::FS),
            _ => None,
        }
    }

    /// The single contact's output kind of a per-section output (what it depends on).
    fn depends(self) -> Option<Depends> {
        match self {
            StringVar::FFx => Some(Depends::Force),
            StringVar::X => Some(Depends::State),
            StringVar::Vx => Some(Depends::BodyVelocity),
            StringVar::Sx => Some(Depends::Deformation),
            StringVar::FFxStep => Some(Depends::StepMean),
            _ => None,
        }
    }

    /// The inputs (variable, element) element `i` of an output depends on directly during the
    /// simulation: a section's own inputs as the single contact's output, the ends' moving
    /// points for the end forces (their dampers).
    pub fn direct_dependencies(self, c: &Config, i: usize) -> Vec<(StringVar, usize)> {
        match self {
            StringVar::FTop => vec![(StringVar::VTop, 0)],
            StringVar::FBottom => vec![(StringVar::VBottom, 0)],
            _ => self.depends().map_or(vec![], |d| {
                d.direct(c)
                    .into_iter()
                    .filter_map(|input| section_input(input, i))
                    .collect()
            }),
        }
    }

    /// The parameters and inputs (variable, element) element `i` of an output depends on at
    /// initialization (the string at rest at the origin, undeformed): a section's own as the
    /// single contact's output; the ends' dampers and moving points for the end forces.
    /// The shared law parameters are [`Dependency`]s of the single contact.
    pub fn initial_dependencies(self, c: &Config, i: usize) -> Vec<StringDependency> {
        match self {
            StringVar::FTop => vec![
                StringDependency::String(StringVar::CTop, 0),
                StringDependency::String(StringVar::VTop, 0),
            ],
            StringVar::FBottom => vec![
                StringDependency::String(StringVar::CBottom, 0),
                StringDependency::String(StringVar::VBottom, 0),
            ],
            _ => self.depends().map_or(vec![], |d| {
                d.initial(c)
                    .into_iter()
                    .filter_map(|dep| match dep {
                        Dependency::Param(p) => Some(match per_section(p) {
                            Some(v) => StringDependency::String(v, i),
                            None => StringDependency::Shared(p),
                        }),
                        Dependency::Input(input) => {
                            section_input(input, i).map(|(v, k)| StringDependency::String(v, k))
                        }
                    })
                    .collect()
            }),
        }
    }
}

impl StringVar {
    /// The knowns of Model Exchange (states and inputs, as variable and element) element `i`
    /// of a derivative, an output or an event indicator depends on, in a string of `n`
    /// sections, sorted and once each: a section's velocity and deformation rate and its
    /// friction force as the single contact's ([`rate_knowns`], [`force_knowns`]); its
    /// acceleration also on its neighbours' positions and velocities (the links), its own drive
    /// force, and at the ends on the ends' points and their velocities. The step means are the
    /// instantaneous forces in Model Exchange (an importer's integrator has no communication
    /// steps).
    pub fn exchange_dependencies(self, c: &Config, n: usize, i: usize) -> Vec<(StringVar, usize)> {
        use StringVar as S;
        let section = |ks: Vec<Known>| -> Vec<(StringVar, usize)> {
            ks.into_iter()
                .filter_map(|k| match k {
                    Known::State(StateId::Sx) => Some((S::Sx, i)),
                    Known::State(StateId::Vx) => Some((S::Vx, i)),
                    Known::State(StateId::X) => Some((S::X, i)),
                    Known::Input(input) => section_input(input, i),
                    Known::State(_) => None,
                })
                .collect()
        };
        let mut d = match self {
            S::DerX => vec![(S::Vx, i)],
            S::DerVx => {
                let mut d = section(force_knowns(c, 0));
                d.extend([(S::X, i), (S::Vx, i), (S::FD, i)]);
                if i > 0 {
                    d.extend([(S::X, i - 1), (S::Vx, i - 1)]);
                }
                if i + 1 < n {
                    d.extend([(S::X, i + 1), (S::Vx, i + 1)]);
                }
                if i == 0 {
                    d.extend([(S::XTop, 0), (S::VTop, 0)]);
                }
                if i + 1 == n {
                    d.extend([(S::XBottom, 0), (S::VBottom, 0)]);
                }
                d
            }
            S::DerSx => section(rate_knowns(c, 0)),
            S::DerXTop => vec![(S::VTop, 0)],
            S::DerXBottom => vec![(S::VBottom, 0)],
            S::EventVrx => section(velocity_knowns(c)),
            S::FFx | S::FFxStep => section(force_knowns(c, 0)),
            S::X | S::Vx | S::Sx => vec![(self, i)],
            S::FLink => vec![(S::X, i), (S::X, i + 1), (S::Vx, i), (S::Vx, i + 1)],
            S::FTop | S::FTopStep => vec![(S::XTop, 0), (S::X, 0), (S::Vx, 0), (S::VTop, 0)],
            S::FBottom | S::FBottomStep => vec![
                (S::XBottom, 0),
                (S::X, n - 1),
                (S::Vx, n - 1),
                (S::VBottom, 0),
            ],
            _ => vec![],
        };
        d.retain(|(v, _)| v.present(c, n));
        d.sort_unstable();
        d.dedup();
        d
    }
}

/// A variable an output of a string depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StringDependency {
    /// A shared law parameter (the single contact's row).
    Shared(ParamId),
    /// An element of a string variable.
    String(StringVar, usize),
}

/// The per-section parameter that replaces a single contact's parameter, if it is one.
fn per_section(p: ParamId) -> Option<StringVar> {
    StringVar::ALL
        .into_iter()
        .find(|v| v.contact_param() == Some(p))
}

/// A section's input of the single contact's input.
fn section_input(input: InputId, i: usize) -> Option<(StringVar, usize)> {
    match input {
        InputId::FD => Some((StringVar::FD, i)),
        InputId::VSx => Some((StringVar::VSx, i)),
        InputId::FN => Some((StringVar::FN, i)),
        _ => None,
    }
}

/// The single contact's parameters a string shares between its sections: those of its
/// configuration but the per-section ones and the averaging window (a string has no `F_mean`).
pub fn shared_params(c: &Config) -> impl Iterator<Item = ParamId> + '_ {
    ParamId::ALL
        .into_iter()
        .filter(move |p| p.present(c) && per_section(*p).is_none() && *p != ParamId::TAvg)
}

/// The values of a string's parameters and inputs, one vector per variable in the order of
/// [`StringVar::ALL`] (a scalar as a vector of one; outputs empty).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StringValues {
    pub sections: usize,
    values: Vec<Vec<f64>>,
}

impl StringValues {
    /// `n` sections with the per-section parameters at `m`, `F_N`, `mu`, `F_S`, the links and
    /// ends at 0 (free ends), the inputs at 0 but `F_N` (an input where the normal force is
    /// one) at the parameter's value.
    pub fn new(n: usize, m: f64, f_n: f64, mu: f64, f_s: f64) -> StringValues {
        let values = StringVar::ALL
            .into_iter()
            .map(|v| {
                let x = match v {
                    StringVar::M => m,
                    StringVar::FN => f_n,
                    StringVar::Mu => mu,
                    StringVar::FS => f_s,
                    _ => 0.0,
                };
                match v.row().role {
                    Role::Output | Role::Local => vec![],
                    _ => vec![x; v.len(n)],
                }
            })
            .collect();
        StringValues {
            sections: n,
            values,
        }
    }

    pub fn get(&self, v: StringVar) -> &[f64] {
        &self.values[v.index()]
    }

    pub fn get_mut(&mut self, v: StringVar) -> &mut [f64] {
        &mut self.values[v.index()]
    }

    /// The one value of a scalar (or the first element).
    pub fn one(&self, v: StringVar) -> f64 {
        self.values[v.index()].first().copied().unwrap_or(0.0)
    }
}
