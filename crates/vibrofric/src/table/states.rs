//! The continuous states a Model Exchange importer integrates, each declared once: name, value
//! references of the state and of its derivative, units, the scenes that have it, and what its
//! derivative depends on (`ModelStructure/Derivatives`).
//!
//! The states are those the Co-Simulation solver integrates, `[s | body]`, plus the two it
//! computes in closed form there and an importer must integrate here: the position the inputs
//! impose (`x` under velocity drive, the spring's far end `x_d`), and `∫F_Fx dt` over the
//! averaging window in progress, from which `F_mean` follows at each window boundary (a time
//! event). Their derivatives:
//!
//! | state | derivative |
//! |---|---|
//! | `contact.s_x`, `contact.s_y` | the law's deformation rate at `v_r = v − v_s` |
//! | `body.x`, `body.y` | `v_x`, `v_y` (under velocity drive `body.x` is imposed: `v_d`) |
//! | `body.v_x`, `body.v_y` | `(F_d·e_x − F_F)/m` |
//! | `drive.x_d` | `v_d` |
//! | `window.F_int` | `F_Fx` |
//!
//! Each state is one row of the `states!` declaration below (`declare.rs` expands it).

use super::{Config, Drive, InputId, OutputId};

states! {
    Sx {
        name: "contact.s_x", unit: "m", display: Some("um"),
        description: "State: contact deformation along x",
        derivative_unit: "m/s",
        derivative_description: "Deformation rate along x (the friction law)",
        present: |_, _| true,
        derivative_knowns: |c| rate_knowns(c, 0),
    }
    Sy {
        name: "contact.s_y", unit: "m", display: Some("um"),
        description: "State: contact deformation along y",
        derivative_unit: "m/s",
        derivative_description: "Deformation rate along y (the friction law)",
        present: |c, _| c.planar(),
        derivative_knowns: |c| rate_knowns(c, 1),
    }
    X {
        name: "body.x", unit: "m", display: Some("um"),
        description: "State: body position along x (under velocity drive the integral of v_d)",
        derivative_unit: "m/s",
        derivative_description: "Body velocity along x",
        present: |_, _| true,
        derivative_knowns: |c| {
            if c.drive.imposes_velocity() {
                vec![Known::Input(InputId::VD)]
            } else {
                vec![Known::State(StateId::Vx)]
            }
        },
    }
    Y {
        name: "body.y", unit: "m", display: Some("um"),
        description: "State: body position along y",
        derivative_unit: "m/s",
        derivative_description: "Body velocity along y",
        present: |c, _| c.lateral_free(),
        derivative_knowns: |_| vec![Known::State(StateId::Vy)],
    }
    Vx {
        name: "body.v_x", unit: "m/s", display: Some("mm/s"),
        description: "State: body velocity along x",
        derivative_unit: "m/s2",
        derivative_description: "Body acceleration along x",
        present: |c, _| !c.drive.imposes_velocity(),
        derivative_knowns: |c| {
            let mut d = force_knowns(c, 0);
            match c.drive {
                Drive::Force => d.push(Known::Input(InputId::FD)),
                Drive::Velocity | Drive::Spring => d.extend([
                    Known::State(StateId::X),
                    Known::State(StateId::Vx),
                    Known::State(StateId::Xd),
                    Known::Input(InputId::VD),
                ]),
            }
            d
        },
    }
    Vy {
        name: "body.v_y", unit: "m/s", display: Some("mm/s"),
        description: "State: body velocity along y",
        derivative_unit: "m/s2",
        derivative_description: "Body acceleration along y",
        present: |c, _| c.lateral_free(),
        derivative_knowns: |c| force_knowns(c, 1),
    }
    Xd {
        name: "drive.x_d", unit: "m", display: Some("um"),
        description: "State: position of the spring's far end (the integral of v_d)",
        derivative_unit: "m/s",
        derivative_description: "Velocity of the spring's far end (v_d)",
        present: |c, _| c.drive.has_spring(),
        derivative_knowns: |_| vec![Known::Input(InputId::VD)],
    }
    Window {
        name: "window.F_int", unit: "N.s", display: None,
        description: "State: integral of F_Fx over the averaging window in progress (F_mean = F_int/window at its end)",
        derivative_unit: "N",
        derivative_description: "F_Fx, the integrand of the window's mean",
        present: |_, outputs| {
            outputs.contains(&OutputId::FMean) || outputs.contains(&OutputId::Reduction)
        },
        derivative_knowns: |c| force_knowns(c, 0),
    }
}

/// What a derivative or an output depends on among the knowns of Model Exchange.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Known {
    State(StateId),
    Input(InputId),
}

impl StateId {
    pub fn index(self) -> usize {
        self as usize
    }

    /// Value reference of the state (301–308) and of its derivative (401–408).
    pub fn vr(self) -> u32 {
        301 + self as u32
    }
    pub fn derivative_vr(self) -> u32 {
        401 + self as u32
    }

    /// The knowns the derivative depends on, in this configuration (the `dependencies` of
    /// `ModelStructure/Derivatives`): see the table of the module's documentation and, for the
    /// deformation rate and the force, [`force_knowns`] and [`rate_knowns`].
    pub fn derivative_dependencies(self, c: &Config, outputs: &[OutputId]) -> Vec<Known> {
        let mut d = self.derivative_knowns(c);
        d.retain(|k| match k {
            Known::State(s) => s.present(c, outputs),
            Known::Input(i) => i.present(c),
        });
        dedup(&mut d);
        d
    }
}

fn dedup(d: &mut Vec<Known>) {
    let mut out: Vec<Known> = vec![];
    for k in d.drain(..) {
        if !out.contains(&k) {
            out.push(k);
        }
    }
    *d = out;
}

/// The knowns the relative velocity `v_r = v − v_s` depends on: the body's velocity states, the
/// imposed `v_d`, the input support velocities.
pub fn velocity_knowns(c: &Config) -> Vec<Known> {
    let mut d = vec![];
    match c.drive {
        Drive::Velocity => {
            d.push(Known::Input(InputId::VD));
            if c.lateral_free() {
                d.push(Known::State(StateId::Vy));
            }
        }
        Drive::Force | Drive::Spring => {
            d.push(Known::State(StateId::Vx));
            if c.planar() {
                d.push(Known::State(StateId::Vy));
            }
        }
    }
    if c.input_support {
        d.push(Known::Input(InputId::VSx));
        if c.planar() {
            d.push(Known::Input(InputId::VSy));
        }
    }
    d
}

/// The knowns component `k` of the deformation rate depends on: its own deformation (both with
/// Dupont's planar weight `alpha(s, v_r)`), the relative velocity (all of it: the rate has
/// `|v_r|`), and the normal force where it is an input.
pub fn rate_knowns(c: &Config, k: usize) -> Vec<Known> {
    let own = [StateId::Sx, StateId::Sy][k];
    let mut d = vec![Known::State(own)];
    if c.planar() && c.law.has_breakaway() {
        d.push(Known::State([StateId::Sy, StateId::Sx][k]));
    }
    d.extend(velocity_knowns(c));
    if c.normal_input {
        d.push(Known::Input(InputId::FN));
    }
    d
}

/// The knowns component `k` of the friction force depends on: `k_t·s` for Dahl and Dupont;
/// LuGre adds `h_t(|v_r|)·ds/dt + h_v·v_r`, so the deformation rate's knowns.
pub fn force_knowns(c: &Config, k: usize) -> Vec<Known> {
    if c.law.force_has_rate() {
        rate_knowns(c, k)
    } else {
        vec![Known::State([StateId::Sx, StateId::Sy][k])]
    }
}

impl Config {
    /// Number of event indicators of Model Exchange: the sign of `v_rx` (the kink of `|v_r|`),
    /// in planar Dupont the direction test `s·v_r`, and with the normal force an input its
    /// lift-off threshold.
    pub fn event_indicators(&self) -> usize {
        IndicatorId::ALL.iter().filter(|i| i.present(self)).count()
    }
}

impl OutputId {
    /// The states the output depends on in Model Exchange (with [`super::Depends::direct`]'s
    /// inputs, the `dependencies` of `ModelStructure/Outputs`). `F_mean` is `F_int` over the
    /// time elapsed in the first window (`F_Fx` at its very start), a constant after it; the
    /// step means are `F_F` (an importer's integrator has no communication steps).
    pub fn state_dependencies(self, c: &Config, outputs: &[OutputId]) -> Vec<StateId> {
        let mut d: Vec<Known> = match self {
            OutputId::FFx | OutputId::FFxStep => force_knowns(c, 0),
            OutputId::FFy | OutputId::FFyStep => force_knowns(c, 1),
            OutputId::X => vec![Known::State(StateId::X)],
            OutputId::Y => vec![Known::State(StateId::Y)],
            OutputId::Vx => vec![Known::State(StateId::Vx)],
            OutputId::Vy => vec![Known::State(StateId::Vy)],
            OutputId::Sx => vec![Known::State(StateId::Sx)],
            OutputId::Sy => vec![Known::State(StateId::Sy)],
            OutputId::FMean | OutputId::Reduction => {
                let mut d = vec![Known::State(StateId::Window)];
                d.extend(force_knowns(c, 0));
                d
            }
            OutputId::PDiss => {
                let mut d = vec![];
                for k in 0..1 + c.planar() as usize {
                    d.extend(force_knowns(c, k));
                    d.extend(rate_knowns(c, k));
                }
                d
            }
            OutputId::FDrive => [StateId::Xd, StateId::X, StateId::Vx]
                .map(Known::State)
                .to_vec(),
        };
        dedup(&mut d);
        let mut states: Vec<StateId> = d
            .into_iter()
            .filter_map(|k| match k {
                Known::State(s) if s.present(c, outputs) => Some(s),
                _ => None,
            })
            .collect();
        states.sort_by_key(|s| s.index());
        states
    }
}

// The switching functions the Co-Simulation solver locates, with its hysteresis band, and the
// lift-off threshold of a normal force input.
indicators! {
    /// `v_rx + side·band`: the kink of `|v_r|`.
    Slip {
        name: "event.v_rx", unit: "m/s",
        description: "Event indicator: v_rx shifted by its hysteresis band (a sign change is a kink of |v_r|)",
        present: |_| true,
        knowns: velocity_knowns,
    }
    /// `s·v_r + side·band`: Dupont's planar direction test.
    Direction {
        name: "event.s_dot_v_r", unit: "m2/s",
        description: "Event indicator: s.v_r shifted by its hysteresis band (Dupont's direction test)",
        present: |c| c.planar() && c.law.has_breakaway(),
        knowns: |c| {
            let mut d = vec![Known::State(StateId::Sx), Known::State(StateId::Sy)];
            d.extend(velocity_knowns(c));
            d
        },
    }
    /// `F_N − F_lift`: the body leaves the support or lands.
    LiftOff {
        name: "event.F_N_lift", unit: "N",
        description: "Event indicator: F_N less the lift-off load (the body leaves the support or lands)",
        present: |c| c.normal_input,
        knowns: |_| vec![Known::Input(InputId::FN)],
    }
}

impl IndicatorId {
    /// Value references 501–503.
    pub fn vr(self) -> u32 {
        501 + self as u32
    }

    /// The knowns the indicator depends on: the relative velocity's (and the deformation for
    /// the direction test), the normal force input for the lift-off.
    pub fn dependencies(self, c: &Config, outputs: &[OutputId]) -> Vec<Known> {
        let mut d = self.knowns(c);
        d.retain(|k| match k {
            Known::State(s) => s.present(c, outputs),
            Known::Input(i) => i.present(c),
        });
        d
    }

    /// Position in the vector of event indicators of this configuration.
    pub fn index(self, c: &Config) -> usize {
        IndicatorId::ALL
            .iter()
            .take_while(|i| **i != self)
            .filter(|i| i.present(c))
            .count()
    }
}
