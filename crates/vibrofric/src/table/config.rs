//! What a contact is made of: the choices a scene makes (`docs/scenes.md`).

/// Friction law of the contact zone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Law {
    Dahl,
    Dupont,
    LuGre,
}

/// Kinematics of the contact: 1-D along x, or the full sliding plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Motion {
    Longitudinal,
    Planar,
}

/// How the body is moved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Drive {
    /// `F_d` input, body dynamics.
    Force,
    /// `v_x = v_d` imposed.
    Velocity,
    /// Spring `k_d` and damper `c_d` whose far end moves at `v_d`.
    Spring,
}

/// Lateral motion of a planar velocity drive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Lateral {
    /// `m·dv_y/dt = −F_Fy`
    Free,
    /// `v_y = 0`
    Guided,
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
        self.motion == Motion::Planar
    }

    /// True when the lateral motion `y`, `v_y` is a dynamic state.
    pub fn lateral_free(&self) -> bool {
        self.planar()
            && match self.drive {
                Drive::Velocity => self.lateral == Lateral::Free,
                Drive::Force | Drive::Spring => true,
            }
    }

    /// True when the body has dynamics (and so needs the mass `m`).
    pub fn body_dynamic(&self) -> bool {
        self.drive != Drive::Velocity || self.lateral_free()
    }
}
