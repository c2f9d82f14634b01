//! The equations of a scene's configuration on its documentation page: the law, the motion, the
//! drive and the inputs, in the page's edition's words.

use super::Edition;
use vibrofric::description::scene::Scene;
use vibrofric::description::xml;
use vibrofric::table::{Drive, Law};

/// The equations of the scene's configuration, as HTML list items.
pub(super) fn equations(scene: &Scene, ed: Edition) -> Vec<String> {
    let c = &scene.config;
    let planar = c.planar();
    let mut eq = vec![];
    eq.push(
        "Coulomb force <code>F_C = mu·F_N</code>; relative velocity <code>v_r = v − v_s</code> (body velocity less support velocity).".to_string(),
    );
    if planar {
        eq.push("Planar motion: <code>s</code>, <code>v_r</code> and <code>F_F</code> are vectors in the sliding plane; <code>|v_r|</code> is the Euclidean norm and every equation holds component-wise with it (the isotropic generalisation, equal to the paper's scalar equations when all motion is along x).".to_string());
    } else {
        eq.push("Longitudinal motion: every quantity is a scalar along x.".to_string());
    }
    match c.law {
        Law::Dahl => {
            eq.push("Dahl law (Eqs. 1, 3 with gamma = 1): <code>F_F = k_t·s</code>, <code>s_ss = F_C/k_t</code>.".to_string());
            if planar {
                eq.push("<code>ds/dt = v_r − |v_r|·s/s_ss</code>; <code>|s| ≤ s_ss</code> holds for all time.".to_string());
            } else {
                eq.push("<code>ds/dt = v_r·|1 − sgn(v_r)·s/s_ss|^kappa · sgn(1 − sgn(v_r)·s/s_ss)</code> (kappa = 1: <code>ds/dt = v_r − |v_r|·s/s_ss</code>).".to_string());
            }
        }
        Law::Dupont => {
            eq.push("Dupont elasto-plastic law (Eq. 3 with gamma = alpha): <code>F_F = k_t·s</code>, <code>ds/dt = v_r − alpha(s, v_r)·|v_r|·s/s_ss</code>, <code>s_ss = F_C/k_t</code>, breakaway <code>s_ba = r_ba·s_ss</code>.".to_string());
            let apart = if planar {
                "<code>s·v_r ≤ 0</code>"
            } else {
                "<code>sgn(s) ≠ sgn(v_r)</code>"
            };
            eq.push(format!("<code>alpha = 0</code> when {apart}; otherwise 0 for <code>|s| ≤ s_ba</code>, <code>1/2·sin(pi·(|s| − (s_ss + s_ba)/2)/(s_ss − s_ba)) + 1/2</code> for <code>s_ba &lt; |s| &lt; s_ss</code>, 1 for <code>|s| ≥ s_ss</code>."));
        }
        Law::LuGre => {
            eq.push("LuGre law (Eqs. 2, 4–7): <code>F_F = k_t·s + h_t(v_r)·ds/dt + h_v·v_r</code>, <code>ds/dt = v_r − |v_r|·s/g(v_r)</code>.".to_string());
            eq.push("<code>g(v_r) = (F_C + (F_S − F_C)·exp(−(|v_r|/v_S)²))/k_t</code>, <code>h_t(v_r) = 2·zeta_t·sqrt(m·k_t)·exp(−(|v_r|/v_e)²)</code>.".to_string());
            let p = &scene.start;
            if p.reference_f_c() > 0.0 {
                eq.push(format!(
                "The static force follows the load: <code>F_S</code> and <code>zeta_t</code> are given at this scene's load (<code>F_N</code> = {} N, <code>mu</code> = {}: <code>F_C</code> = {} N, <code>F_S/F_C</code> = {}); at any other <code>F_N</code> or <code>mu</code> the law uses the static force <code>F_S·(F_N/{})·(mu/{})</code>, which keeps <code>F_S/F_C</code>, and the damping ratio <code>zeta_t·F_N/{}</code>. A static force below the Coulomb force at this load (<code>F_S</code> &lt; {} N) would invert the Stribeck curve and is refused.",
                xml::number(p.f_n_ref),
                xml::number(p.mu_ref),
                xml::number(p.reference_f_c()),
                xml::number((p.f_s / p.reference_f_c() * 1e4).round() / 1e4),
                xml::number(p.f_n_ref),
                xml::number(p.mu_ref),
                xml::number(p.f_n_ref),
                xml::number(p.reference_f_c()),
            ));
            } else {
                eq.push("This scene starts without load (<code>F_C</code> = 0): <code>F_S</code> and <code>zeta_t</code> are taken as they are, at every load.".to_string());
            }
        }
    }
    eq.push("The support acts on the body with <code>−F_F</code>.".to_string());
    match c.drive {
        Drive::Force => {
            eq.push("Force drive (Eqs. 8, 9): <code>m·dv_x/dt = F_d − F_Fx</code>, <code>dx/dt = v_x</code>.".to_string());
            if planar {
                eq.push(
                    "Lateral (Eq. 10): <code>m·dv_y/dt = −F_Fy</code>, <code>dy/dt = v_y</code>."
                        .to_string(),
                );
            }
        }
        Drive::Velocity => {
            eq.push("Velocity drive: <code>v_x = v_d</code> is imposed, <code>x = ∫v_d dt</code>; <code>F_Fx</code> is the instantaneous driving force.".to_string());
            if planar {
                eq.push(format!(
                    "Lateral motion {}: {}.",
                    c.lateral.word(),
                    if c.lateral_free() {
                        "<code>m·dv_y/dt = −F_Fy</code> (Eq. 10)"
                    } else {
                        "<code>v_y = 0</code>, <code>y = 0</code>"
                    }
                ));
            }
        }
        Drive::Spring => {
            eq.push("Spring drive (test rig): <code>F_d = k_d·(x_d − x) + c_d·(v_d − v_x)</code>, <code>dx_d/dt = v_d</code>, <code>m·dv_x/dt = F_d − F_Fx</code>; <code>F_d</code> is an output.".to_string());
            if planar {
                eq.push("Lateral (Eq. 10): <code>m·dv_y/dt = −F_Fy</code>.".to_string());
            }
        }
    }
    if c.harmonic {
        let dir = if planar {
            "along the direction at <code>angle</code> to x: <code>v_s = u0·omega·cos(omega·t + phase)·(cos angle, sin angle)</code>"
        } else {
            "along x: <code>v_s = u0·omega·cos(omega·t + phase)</code>"
        };
        eq.push(format!("Harmonic support motion (Eqs. 13, 14): <code>u = u0·sin(omega·t + phase)</code>, <code>omega = 2·pi·f</code>, {dir}. The FMU resolves every vibration period inside a communication step."));
    }
    if c.input_support {
        let which = if planar {
            "<code>v_sx</code>, <code>v_sy</code>"
        } else {
            "<code>v_sx</code>"
        };
        let sum = if c.harmonic {
            ", added to the harmonic motion"
        } else {
            ""
        };
        eq.push(format!(
            "Input support motion: {which} set by the importer{sum}; {}.",
            ed.input_hold()
        ));
    }
    let window = if c.harmonic {
        "the excitation period <code>1/f</code> (<code>T_avg</code> when f = 0)"
    } else {
        "<code>T_avg</code>"
    };
    let reduction = if c.drive.imposes_velocity() {
        " <code>reduction = 1 − F_mean/F_C</code>: the fraction by which the vibration lowers the mean friction of the body driven at <code>v_d</code> (0: no reduction, also where the Coulomb force is negligible, F_C/k_t ≤ 1e-290 m; 0.6: 60 % less friction)."
    } else {
        " This drive has no <code>reduction</code> output: the drive sets the friction a body meets while it sticks, so a mean friction below F_C is no reduction the vibration caused; compare <code>F_mean</code> with a run without the vibration (or use a velocity-driven scene)."
    };
    eq.push(format!("<code>F_mean</code>: exact mean of <code>F_Fx</code> over the most recently completed averaging window (Eq. 11), {window}; the mean since start until a first window completes.{reduction}"));
    eq.push("<code>P_diss = F_F·v_r − d(k_t·|s|²/2)/dt</code>: the power dissipated in the contact (never negative for Dahl and Dupont).".to_string());
    eq.push(format!("<code>F_Fx_step</code>, <code>F_Fy_step</code>: the exact mean of each friction component over the last communication step, <code>∫F dt/h</code>: the impulse a host that integrates the body itself applies, without sampling a force that vibrates between its samples. First-order output derivatives ({}) are exact for <code>x</code>, <code>y</code>, <code>v_x</code>, <code>v_y</code>, <code>s_x</code>, <code>s_y</code> and the step means (as moving means over the last step).", ed.output_derivatives()));
    if c.normal_input {
        eq.push(format!("Normal force: <code>F_N</code> is an input ({}); <code>F_C = mu·F_N(t)</code> and what follows from it change with it, and LuGre's <code>F_S</code> and <code>zeta_t</code> are given at the start value of <code>F_N</code> and follow the load as a parameter <code>F_N</code> makes them (a held input gives the numbers of the same scene with that <code>F_N</code> as a parameter). A negative <code>F_N</code> is refused; below the tolerance times the start value the body has lifted off: no friction, no deformation, until the load returns.", ed.input_hold()));
    }
    eq
}
