//! Every parameter, input and output of every scene, each declared once: name, value reference,
//! unit and display unit, default, accepted range, variability, the scenes that have it, what it
//! depends on, and the description the model description and the documentation show.
//!
//! The declarations expand (`declare.rs`) into the structs the physics computes with
//! ([`Params`], [`Inputs`], [`Outputs`]) and the ids everything else reads them by
//! ([`ParamId`], [`InputId`], [`OutputId`]). The model description, get and set by value
//! reference, the rules, the scene reader and `docs/scenes.md` all read these ids; adding a
//! variable is one declaration here plus the physics that uses it.
//!
//! Value references are fixed per variable and shared by every scene. Two variables change
//! role with the scene and so have two declarations under one value reference: `F_N` (2) is a
//! parameter, or an input in scenes with `normal = "input"`; `F_d` (101) is the input of a force
//! drive and the spring-damper force output of a spring drive.

use super::rule::{any, non_negative, positive};
use super::{Config, Depends, Rule, Variability};

parameters! {
    M => m {
        name: "m", vr: 1, unit: "kg", display: None, default: 5.6,
        rule: positive(1e-4, 1e6), // 0.1 g to 1000 t
        variability: Fixed,
        present: |c| c.body_dynamic() || c.law.has_contact_damping(),
        description: "Body mass",
    }
    FN => f_n {
        name: "F_N", vr: 2, unit: "N", display: None, default: 55.0,
        rule: non_negative(0.0, 1e8),
        variability: Tunable,
        // In scenes with `normal = "input"` its variable is the input `F_N` below, which starts
        // at this parameter's value.
        present: |_| true,
        description: "Normal force pressing the body on the support",
    }
    Mu => mu {
        name: "mu", vr: 3, unit: "1", display: None, default: 0.2,
        rule: non_negative(0.0, 10.0),
        variability: Tunable,
        present: |_| true,
        description: "Coulomb friction coefficient (F_C = mu*F_N)",
    }
    KT => k_t {
        name: "k_t", vr: 4, unit: "N/m", display: None, default: 1e8,
        rule: positive(1e2, 1e13),
        variability: Fixed,
        present: |_| true,
        description: "Tangential contact stiffness",
    }
    Kappa => kappa {
        name: "kappa", vr: 5, unit: "1", display: None, default: 1.0,
        rule: positive(0.05, 20.0),
        // Below 0.5 the deformation reaches its bound at a finite distance; a force or spring
        // drive, which integrates the body and the deformation together, then takes millions
        // of steps per millisecond (the velocity drive takes the closed form for any exponent).
        narrowed: |c, rule| if !c.drive.imposes_velocity() { Rule { min: 0.5, ..rule } } else { rule },
        variability: Fixed,
        present: |c| c.law.has_exponent() && !c.planar(),
        description: "Dahl exponent (longitudinal Dahl only)",
    }
    RBa => r_ba {
        name: "r_ba", vr: 6, unit: "1", display: None, default: 0.5,
        rule: non_negative(0.0, 0.999),
        variability: Fixed,
        present: |c| c.law.has_breakaway(),
        description: "Dupont breakaway ratio s_ba/s_ss",
    }
    FS => f_s {
        name: "F_S", vr: 7, unit: "N", display: None, default: 14.3,
        rule: non_negative(0.0, 1e9),
        variability: Fixed,
        present: |c| c.law.has_static_force(),
        description: "LuGre static friction force at the scene's load (start values of F_N and mu); the law scales it with mu*F_N, keeping F_S/F_C; F_S < F_C there is refused",
    }
    VS => v_s {
        name: "v_S", vr: 8, unit: "m/s", display: Some("mm/s"), default: 1e-3,
        rule: positive(1e-9, 1e2),
        variability: Fixed,
        present: |c| c.law.has_static_force(),
        description: "Stribeck velocity",
    }
    ZetaT => zeta_t {
        name: "zeta_t", vr: 9, unit: "1", display: None, default: 1.0,
        rule: non_negative(0.0, 1e3),
        variability: Fixed,
        present: |c| c.law.has_static_force(),
        description: "LuGre contact damping ratio (Eq. 6) at the scene's load (start value of F_N); the law scales it with F_N",
    }
    HV => h_v {
        name: "h_v", vr: 10, unit: "N.s/m", display: None, default: 0.0,
        rule: non_negative(0.0, 1e9),
        variability: Fixed,
        present: |c| c.law.has_static_force(),
        description: "LuGre viscous coefficient",
    }
    VE => v_e {
        name: "v_e", vr: 11, unit: "m/s", display: Some("mm/s"), default: 1e-3,
        rule: positive(1e-9, 1e2),
        variability: Fixed,
        present: |c| c.law.has_static_force(),
        description: "LuGre damping decay velocity (Eq. 7)",
    }
    U0 => u0 {
        name: "u0", vr: 12, unit: "m", display: Some("um"), default: 2e-7,
        rule: non_negative(0.0, 0.01), // to 1 cm
        variability: Tunable,
        present: |c| c.harmonic,
        description: "Amplitude of the harmonic support motion",
    }
    F => f {
        name: "f", vr: 13, unit: "Hz", display: None, default: 2000.0,
        rule: non_negative(0.0, 1e7), // to 10 MHz
        variability: Tunable,
        present: |c| c.harmonic,
        description: "Frequency of the harmonic support motion",
    }
    Angle => angle {
        name: "angle", vr: 14, unit: "rad", display: Some("deg"), default: 0.0,
        rule: any(-1e4, 1e4),
        variability: Tunable,
        present: |c| c.harmonic && c.planar(),
        description: "Direction of the support vibration to x (0: longitudinal, pi/2: transverse)",
    }
    Phase => phase {
        name: "phase", vr: 15, unit: "rad", display: Some("deg"), default: 0.0,
        rule: any(-1e4, 1e4),
        variability: Tunable,
        present: |c| c.harmonic,
        description: "Phase of the harmonic support motion",
    }
    KD => k_d {
        name: "k_d", vr: 16, unit: "N/m", display: None, default: 1e5,
        rule: non_negative(0.0, 1e13),
        variability: Fixed,
        present: |c| c.drive.has_spring(),
        description: "Spring-drive stiffness",
    }
    CD => c_d {
        name: "c_d", vr: 17, unit: "N.s/m", display: None, default: 100.0,
        rule: non_negative(0.0, 1e9),
        variability: Fixed,
        present: |c| c.drive.has_spring(),
        description: "Spring-drive damping",
    }
    TAvg => t_avg {
        name: "T_avg", vr: 18, unit: "s", display: None, default: 1e-3,
        rule: positive(1e-9, 1e6),
        variability: Fixed,
        present: |_| true,
        description: "Averaging window of F_mean without harmonic source (or at f = 0)",
    }
    MaxSteps => max_steps {
        name: "max_steps", vr: 19, unit: "1", display: None, default: 1e6,
        rule: positive(1e2, 1e10),
        variability: Tunable,
        present: |_| true,
        description: "Most integrator steps in one communication step (like CVODE's mxstep): a step that needs more returns fmi2Discard; use shorter communication steps or raise it",
    }
}

inputs! {
    FD => f_d {
        name: "F_d", vr: 101, unit: "N", display: None,
        rule: any(-1e9, 1e9),
        present: |c| c.drive.force_input(),
        description: "Driving force along x",
    }
    VD => v_d {
        name: "v_d", vr: 102, unit: "m/s", display: Some("mm/s"),
        rule: any(-1e3, 1e3),
        present: |c| !c.drive.force_input(),
        description: "Driving velocity",
    }
    VSx => v_sx {
        name: "v_sx", vr: 103, unit: "m/s", display: Some("mm/s"),
        rule: any(-1e3, 1e3),
        present: |c| c.input_support,
        description: "Support velocity along x set by the importer",
    }
    VSy => v_sy {
        name: "v_sy", vr: 104, unit: "m/s", display: Some("mm/s"),
        rule: any(-1e3, 1e3),
        present: |c| c.input_support && c.planar(),
        description: "Support velocity along y set by the importer",
    }
    /// The parameter `F_N`'s variable where the normal force is an input (same range).
    FN => f_n {
        name: "F_N", vr: 2, unit: "N", display: None,
        rule: non_negative(0.0, 1e8),
        present: |c| c.normal_input,
        description: "Normal force pressing the body on the support",
    }
}

outputs! {
    FFx => f_fx {
        name: "F_Fx", vr: 201, unit: "N", display: None,
        present: |_| true, depends: Force,
        description: "Friction force along x (resists the relative motion; the support acts on the body with -F_F)",
    }
    FFy => f_fy {
        name: "F_Fy", vr: 202, unit: "N", display: None,
        present: |c| c.planar(), depends: Force,
        description: "Friction force along y",
    }
    X => x {
        name: "x", vr: 203, unit: "m", display: Some("um"),
        present: |_| true, depends: State,
        description: "Body position along x",
    }
    Y => y {
        name: "y", vr: 204, unit: "m", display: Some("um"),
        present: |c| c.planar(), depends: State,
        description: "Body position along y",
    }
    Vx => v_x {
        name: "v_x", vr: 205, unit: "m/s", display: Some("mm/s"),
        present: |_| true, depends: BodyVelocity,
        description: "Body velocity along x",
    }
    Vy => v_y {
        name: "v_y", vr: 206, unit: "m/s", display: Some("mm/s"),
        present: |c| c.planar(), depends: State,
        description: "Body velocity along y",
    }
    Sx => s_x {
        name: "s_x", vr: 207, unit: "m", display: Some("um"),
        present: |_| true, depends: Deformation,
        description: "Contact deformation along x",
    }
    Sy => s_y {
        name: "s_y", vr: 208, unit: "m", display: Some("um"),
        present: |c| c.planar(), depends: Deformation,
        description: "Contact deformation along y",
    }
    FMean => f_mean {
        name: "F_mean", vr: 209, unit: "N", display: None,
        present: |_| true, depends: Mean,
        description: "Mean of F_Fx over the last completed averaging window (exact integral)",
    }
    Reduction => reduction {
        name: "reduction", vr: 210, unit: "1", display: None,
        // Under force and spring drives a mean friction below F_C also comes from a body that
        // sticks (the friction then balances the drive): no reduction the vibration caused.
        present: |c| c.drive.imposes_velocity(), depends: Reduction,
        description: "Friction reduction 1 - F_mean/F_C under the velocity drive: the fraction by which the vibration lowers the mean friction (0: none, also when F_C = 0)",
    }
    PDiss => p_diss {
        name: "P_diss", vr: 211, unit: "W", display: None,
        present: |_| true, depends: Dissipation,
        description: "Power dissipated in the contact: F_F.v_r less the rate of the elastic energy",
    }
    /// The input `F_d`'s variable in spring drive: the spring-damper force (in velocity drive
    /// the model's driving force is `F_Fx`, not an output of its own).
    FDrive => f_d {
        name: "F_d", vr: 101, unit: "N", display: None,
        present: |c| c.drive.has_spring(), depends: DriveForce,
        description: "Driving force along x",
    }
    FFxStep => f_fx_step {
        name: "F_Fx_step", vr: 212, unit: "N", display: None,
        present: |_| true, depends: StepMean,
        description: "Mean of F_Fx over the last communication step (exact integral / step size): the impulse a host integrates without aliasing",
    }
    FFyStep => f_fy_step {
        name: "F_Fy_step", vr: 213, unit: "N", display: None,
        present: |c| c.planar(), depends: StepMean,
        description: "Mean of F_Fy over the last communication step (exact integral / step size)",
    }
}
