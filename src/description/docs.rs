//! `documentation/index.html` of an FMU: what the scene is, its variables with units, start values
//! and ranges, the equations of its law, motion and drive, and the scene text itself. Plain HTML
//! with no script, readable offline in any browser.

use crate::description::scene::{drive_name, lateral_name, law_name, motion_name, summary, Scene};
use crate::description::variables::{Causality, Variable};
use crate::description::xml::{self, DEFAULT_EXPERIMENT, DISPLAY_UNITS};
use crate::model::{Drive, Law, Motion};

/// Escapes text for HTML element content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

fn display_unit_html(v: &Variable) -> String {
    match v.display_unit {
        Some("um") => "µm".into(),
        Some(d) => escape(d),
        None => String::new(),
    }
}

/// The start value in SI and, where the variable has one, in its display unit.
fn start_html(scene: &Scene, v: &Variable) -> String {
    let Some(x) = scene.start_of(v) else {
        return "(calculated)".into();
    };
    let mut s = xml::number(x);
    if let Some(d) = v.display_unit {
        if let Some((_, _, factor)) = DISPLAY_UNITS
            .iter()
            .find(|(u, du, _)| *u == v.unit && *du == d)
        {
            let shown = display_unit_html(v);
            // 12 significant digits hide the rounding of the conversion (2e-7 m = 0.2 µm).
            let shown_value: f64 = format!("{:.11e}", x * factor).parse().unwrap_or(x * factor);
            s.push_str(&format!(" ({} {shown})", xml::number(shown_value)));
        }
    }
    s
}

fn range_html(v: &Variable, c: &crate::model::Config) -> String {
    if v.causality(c) == Causality::Output {
        return String::new();
    }
    match (v.min(c), v.max(c)) {
        (Some(a), Some(b)) => format!("[{}, {}]", xml::number(a), xml::number(b)),
        (Some(a), None) => format!("≥ {}", xml::number(a)),
        (None, Some(b)) => format!("≤ {}", xml::number(b)),
        (None, None) => String::new(),
    }
}

/// The equations of the scene's configuration, as HTML list items.
fn equations(scene: &Scene) -> Vec<String> {
    let c = &scene.config;
    let planar = c.motion == Motion::Planar;
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
                    lateral_name(c.lateral),
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
        eq.push(format!("Input support motion: {which} set by the importer{sum}; held over a step, or extrapolated linearly when <code>fmi2SetRealInputDerivatives</code> gives a derivative."));
    }
    let window = if c.harmonic {
        "the excitation period <code>1/f</code> (<code>T_avg</code> when f = 0)"
    } else {
        "<code>T_avg</code>"
    };
    eq.push(format!("<code>F_mean</code>: exact mean of <code>F_Fx</code> over the most recently completed averaging window (Eq. 11), {window}; the mean since start until a first window completes. <code>reduction = F_mean/F_C</code> (1 when F_C = 0)."));
    eq.push("<code>P_diss = F_F·v_r − d(k_t·|s|²/2)/dt</code>: the power dissipated in the contact (never negative for Dahl and Dupont).".to_string());
    eq.push("<code>F_Fx_step</code>, <code>F_Fy_step</code>: the exact mean of each friction component over the last communication step, <code>∫F dt/h</code>: the impulse a host that integrates the body itself applies, without sampling a force that vibrates between its samples. First-order output derivatives (<code>fmi2GetRealOutputDerivatives</code>) are exact for <code>x</code>, <code>y</code>, <code>v_x</code>, <code>v_y</code>, <code>s_x</code>, <code>s_y</code> and the step means (as moving means over the last step).".to_string());
    if c.normal_input {
        eq.push("Normal force: <code>F_N</code> is an input (held, or extrapolated with its derivative); <code>F_C = mu·F_N(t)</code> and what follows from it change with it, and LuGre's <code>F_S</code> and <code>zeta_t</code> are given at the start value of <code>F_N</code> and scale with the load. A negative <code>F_N</code> is refused; below the tolerance times the start value the body has lifted off: no friction, no deformation, until the load returns.".to_string());
    }
    eq
}

/// The documentation page of a scene's FMU.
pub fn index_html(scene: &Scene) -> String {
    let c = &scene.config;
    let id = escape(&scene.model_identifier);
    let mut h = String::new();
    h.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    h.push_str(&format!("<title>{id}: vibrofric FMU</title>\n"));
    h.push_str("<style>body{font-family:sans-serif;max-width:60em;margin:2em auto;padding:0 1em;line-height:1.4}table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:.2em .5em;text-align:left;vertical-align:top}code,pre{background:#f4f4f4}pre{padding:.5em;overflow-x:auto}</style>\n");
    h.push_str("</head>\n<body>\n");
    h.push_str(&format!(
        "<h1>{id}</h1>\n<p>{}</p>\n",
        escape(&scene.description)
    ));
    h.push_str(&format!(
        "<p>FMI 2.0 Co-Simulation FMU generated by {} (GUID <code>{}</code>). {}.</p>\n",
        escape(&xml::generation_tool()),
        escape(&xml::guid(scene)),
        escape(&summary(c))
    ));
    h.push_str(&format!(
        "<p>Scene: law <code>{}</code>, motion <code>{}</code>, drive <code>{}</code>{}, support motion {}.</p>\n",
        law_name(c.law),
        motion_name(c.motion),
        drive_name(c.drive),
        if c.planar() && c.drive == Drive::Velocity {
            format!(", lateral <code>{}</code>", lateral_name(c.lateral))
        } else {
            String::new()
        },
        match (c.harmonic, c.input_support) {
            (true, true) => "harmonic and input",
            (true, false) => "harmonic",
            _ => "input",
        }
    ));
    h.push_str("<p>The model is the friction contact of a body sliding on a support that vibrates in the sliding plane, after Leus and Gutowski, “Friction force reduction efficiency in sliding motion under tangential vibrations of elastic support”, Acta Mechanica et Automatica, 2024 (equation numbers are the paper's).</p>\n");

    h.push_str("<h2>Equations</h2>\n<ul>\n");
    for e in equations(scene) {
        h.push_str(&format!("<li>{e}</li>\n"));
    }
    h.push_str("</ul>\n");

    h.push_str("<h2>Variables</h2>\n");
    h.push_str("<p>Values are in SI units; the display unit is what importers may show.</p>\n");
    h.push_str("<table>\n<tr><th>name</th><th>value reference</th><th>causality</th><th>variability</th><th>unit</th><th>display unit</th><th>start</th><th>range</th><th>description</th></tr>\n");
    for v in scene.variables() {
        let causality = v.causality(c);
        h.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape(v.name()),
            v.vr,
            causality.as_str(),
            v.variability(c).as_str(),
            escape(v.unit),
            display_unit_html(v),
            if causality == Causality::Output { "(calculated)".into() } else { start_html(scene, v) },
            range_html(v, c),
            escape(v.description)
        ));
    }
    h.push_str("</table>\n");
    h.push_str("<p>Parameters with variability <code>tunable</code> may change between communication steps; the harmonic source stays continuous in phase. Parameters out of their physical range are refused with <code>fmi2Error</code> and a log message naming the rule.</p>\n");

    let (t0, t1, tol, step) = DEFAULT_EXPERIMENT;
    h.push_str(&format!(
        "<h2>Default experiment</h2>\n<p>From {} s to {} s, relative tolerance {}, communication step {} s. The internal solver integrates exactly to every communication point and uses the tolerance given to <code>fmi2SetupExperiment</code> when it is defined.</p>\n",
        xml::number(t0),
        xml::number(t1),
        xml::number(tol),
        xml::number(step)
    ));
    h.push_str("<h2>Logging</h2>\n<ul>\n");
    for (name, d) in xml::LOG_CATEGORIES {
        h.push_str(&format!("<li><code>{name}</code>: {}</li>\n", escape(d)));
    }
    h.push_str("</ul>\n");

    h.push_str("<h2>Scene</h2>\n<p>The scene this FMU was exported from (also in <code>resources/scene.toml</code>):</p>\n");
    h.push_str(&format!("<pre>{}</pre>\n", escape(&scene.source)));
    h.push_str("</body>\n</html>\n");
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn page_shows_display_values_and_escapes_the_scene() {
        let text = "# <b> & \"quotes\"\nmodel_identifier = \"T\"\nlaw = \"dupont\"\nmotion = \"planar\"\ndrive = \"velocity\"\nlateral = \"free\"\nsupport = [\"harmonic\"]\n[start]\nangle = 1.5707963267948966\n";
        let scene = Scene::parse(text, "t.toml").unwrap();
        let html = index_html(&scene);
        assert!(html.contains("2e-7 (0.2 µm)"), "{html}");
        assert!(html.contains("1.5707963267948966 (90 deg)"));
        assert!(html.contains("0.001 (1 mm/s)"), "v_d start");
        assert!(html.contains("# &lt;b&gt; &amp; &quot;quotes&quot;"));
        assert!(!html.contains("<b>"));
        assert!(html.contains("Dupont elasto-plastic law"));
        assert!(html.contains("<code>s·v_r ≤ 0</code>"));
        assert!(html.contains("Lateral motion free"));
        assert!(!html.contains("<script"));
    }
}
