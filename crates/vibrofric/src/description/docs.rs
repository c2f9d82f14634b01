//! `documentation/index.html` of an FMU: what the scene is, the sign convention (a picture), its
//! variables with units, start values and ranges, the equations of its law, motion and drive,
//! how to choose the parameters, how to run it (fmpy), the platform it needs, and the scene text
//! itself. Plain HTML with no script, readable offline in any browser: a partner who receives
//! only the `.fmu` finds everything here.

use crate::description::figure::SIGN_CONVENTION_SVG;
use crate::description::scene::{drive_name, lateral_name, law_name, motion_name, summary, Scene};
use crate::description::variables::{Causality, VarKind, Variable};
use crate::description::xml::{self, DEFAULT_EXPERIMENT, DISPLAY_UNITS};
use crate::table::{Drive, InputId, Law, Motion};

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

fn range_html(v: &Variable, c: &crate::table::Config) -> String {
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
    let reduction = if c.drive == Drive::Velocity {
        " <code>reduction = 1 − F_mean/F_C</code>: the fraction by which the vibration lowers the mean friction of the body driven at <code>v_d</code> (0: no reduction, also where the Coulomb force is negligible, F_C/k_t ≤ 1e-290 m; 0.6: 60 % less friction)."
    } else {
        " This drive has no <code>reduction</code> output: the drive sets the friction a body meets while it sticks, so a mean friction below F_C is no reduction the vibration caused; compare <code>F_mean</code> with a run without the vibration (or use a velocity-driven scene)."
    };
    eq.push(format!("<code>F_mean</code>: exact mean of <code>F_Fx</code> over the most recently completed averaging window (Eq. 11), {window}; the mean since start until a first window completes.{reduction}"));
    eq.push("<code>P_diss = F_F·v_r − d(k_t·|s|²/2)/dt</code>: the power dissipated in the contact (never negative for Dahl and Dupont).".to_string());
    eq.push("<code>F_Fx_step</code>, <code>F_Fy_step</code>: the exact mean of each friction component over the last communication step, <code>∫F dt/h</code>: the impulse a host that integrates the body itself applies, without sampling a force that vibrates between its samples. First-order output derivatives (<code>fmi2GetRealOutputDerivatives</code>) are exact for <code>x</code>, <code>y</code>, <code>v_x</code>, <code>v_y</code>, <code>s_x</code>, <code>s_y</code> and the step means (as moving means over the last step).".to_string());
    if c.normal_input {
        eq.push("Normal force: <code>F_N</code> is an input (held, or extrapolated with its derivative); <code>F_C = mu·F_N(t)</code> and what follows from it change with it, and LuGre's <code>F_S</code> and <code>zeta_t</code> are given at the start value of <code>F_N</code> and scale with the load. A negative <code>F_N</code> is refused; below the tolerance times the start value the body has lifted off: no friction, no deformation, until the load returns.".to_string());
    }
    eq
}

/// One platform's library inside an FMU, for the platform section of its page.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Binary {
    /// The FMU's folders that hold it, of the page's edition: `linux64` (FMI 2.0),
    /// `x86_64-darwin` and `aarch64-darwin` (FMI 3.0), ...
    pub folders: Vec<&'static str>,
    /// The library's file extension (`so`, `dll`, `dylib`).
    pub file_ext: &'static str,
    /// The system it runs on, in words (`64-bit Windows (x86-64)`).
    pub os: &'static str,
    /// What the system must be (HTML): the oldest glibc, Windows or macOS version.
    pub requirement: String,
    /// The shared libraries it links, when known.
    pub libraries: Vec<String>,
}

/// How to choose the parameters of this scene: the guidance a user needs before a first run,
/// as HTML list items.
pub fn guidance(scene: &Scene) -> Vec<String> {
    let c = &scene.config;
    let p = &scene.start;
    let mut g = vec![];
    let f_c = p.f_c();
    let s_ss = if p.k_t > 0.0 { f_c / p.k_t } else { f64::NAN };
    g.push(format!(
        "<code>k_t</code>: the tangential contact stiffness sets the pre-sliding displacement \
         <code>s_ss = F_C/k_t</code> (here {} µm), the elastic travel before the contact slides. \
         Choose it from a measured pre-sliding displacement (typically 0.1–10 µm for metal \
         contacts). What the vibration does depends on <code>psi = v_d/(2·pi·f·u0)</code> and on \
         <code>u0/s_ss = u0·k_t/F_C</code>: for <code>u0 ≫ s_ss</code> the contact acts as a \
         rigid Coulomb contact, for <code>u0 ≲ s_ss</code> the vibration is taken up elastically \
         and reduces little.",
        xml::number((s_ss * 1e6 * 1e4).round() / 1e4)
    ));
    if c.law == Law::LuGre {
        g.push(
            "<code>zeta_t</code> (LuGre): damping ratio of the contact's tangential mode, \
            <code>h_t = 2·zeta_t·sqrt(m·k_t)</code>. The default 1 (critical damping, the paper's \
            Eq. 6) adds <code>h_t·ds/dt</code> to <code>F_F</code>: under a fast vibration \
            <code>ds/dt</code> follows the support velocity and this viscous term makes \
            <code>F_Fx</code> swing beyond <code>F_S</code> within each period, although \
            <code>F_mean</code> stays right (in <code>contact-lugre.toml</code>, 2 kHz, 0.2 µm, \
            <code>F_d</code> = 8 N: <code>F_Fx</code> between −16.1 and 15.8 N at \
            <code>zeta_t</code> = 1, between 0.4 and 11.6 N at 0.1, <code>F_mean</code> = 8 N in \
            both). For a contact whose force should stay within <code>F_S</code>, take \
            <code>zeta_t</code> of 0.01–0.1, or a smaller <code>v_e</code>, which switches the \
            damping off once the contact slides (<code>v_e</code> = 1e-4 m/s at \
            <code>zeta_t</code> = 1: −0.7 to 11.8 N)."
                .to_string(),
        );
    }
    let window = if c.harmonic {
        "with the harmonic source on (<code>f</code> &gt; 0) the averaging window is its period \
         <code>1/f</code>; <code>T_avg</code> is used only when <code>f</code> = 0."
    } else {
        "this scene has no harmonic source: the averaging window is <code>T_avg</code>."
    };
    let input = if c.input_support {
        " When the support motion comes from the inputs <code>v_sx</code>/<code>v_sy</code>, the \
         FMU cannot know its period: <b>set <code>T_avg</code> to the period of the excitation</b> \
         (or a multiple of it). A window that is a fraction of the period gives an \
         <code>F_mean</code> that follows the excitation instead of its mean (with a 20 Hz \
         input and the default 1 ms, <code>F_mean</code> can even be negative)."
    } else {
        ""
    };
    g.push(format!(
        "<code>T_avg</code>: {window}{input} <code>F_mean</code> is updated at the end of each \
         window."
    ));
    g.push(
        "Tolerance (<code>fmi2SetupExperiment</code>, default 1e-6): the relative tolerance \
        of the internal integrator. The error of <code>F_mean</code> is of the order of \
        tolerance × <code>F_C</code> or smaller; 1e-4 suits system simulation, 1e-8 sweeps that \
        compare small differences of <code>F_mean</code>."
            .to_string(),
    );
    g.push(
        "Communication step: the FMU resolves every vibration period inside a step, so the \
        step follows what the importer needs, not the vibration. <code>F_mean</code> and \
        <code>reduction</code> change once per averaging window: a step of one or a few windows \
        shows them fully. To see the waveform of <code>F_Fx</code>, use a step of at most 1/20 of \
        the vibration period. When the FMU is coupled to a host model through its inputs, the \
        step must resolve the host's dynamics; passing input derivatives \
        (<code>fmi2SetRealInputDerivatives</code>) makes the inputs linear in time within a step."
            .to_string(),
    );
    g
}

/// A Python (fmpy) snippet that runs this FMU.
pub fn usage_snippet(scene: &Scene) -> String {
    let c = &scene.config;
    let id = &scene.model_identifier;
    let outputs: Vec<&str> = scene
        .variables()
        .filter(|v| v.causality(c) == Causality::Output)
        .map(|v| v.name())
        .filter(|n| ["F_Fx", "F_mean", "reduction"].contains(n))
        .collect();
    let mut start = vec![];
    if c.harmonic {
        start.push("\"u0\": 0.5e-6".to_string());
    }
    if c.input_support && !c.harmonic {
        start.push("\"T_avg\": 0.05".to_string());
    }
    let input_present = |i: InputId| {
        scene
            .variables()
            .any(|v| v.kind == VarKind::Input(i) && v.causality(c) == Causality::Input)
    };
    if input_present(InputId::VD) {
        start.push("\"v_d\": 2e-3".to_string());
    }
    if input_present(InputId::FD) {
        start.push("\"F_d\": 8.0".to_string());
    }
    let mut py = String::new();
    py.push_str("# pip install fmpy\nfrom fmpy import simulate_fmu\n\n");
    py.push_str(&format!(
        "res = simulate_fmu(\n    \"{id}.fmu\",\n    stop_time=0.1,\n    output_interval=1e-3,  # the communication step of a co-simulation\n    relative_tolerance=1e-6,\n    start_values={{{}}},\n    output={:?},\n)\n",
        start.join(", "),
        outputs
    ));
    py.push_str(&format!(
        "print(res[\"time\"][-1], res[\"{}\"][-1])\n",
        outputs.first().copied().unwrap_or("time")
    ));
    if input_present(InputId::VSx) {
        py.push_str("\n# A co-simulation loop: the importer sets the support velocity v_sx before every\n# step, with its derivative, so that the FMU extrapolates it linearly within the step.\nimport math\nimport shutil\n\nfrom fmpy import extract, read_model_description\nfrom fmpy.fmi2 import FMU2Slave\n\n");
        py.push_str(&format!(
            "md = read_model_description(\"{id}.fmu\")\nvr = {{v.name: v.valueReference for v in md.modelVariables}}\nunzipdir = extract(\"{id}.fmu\")\nfmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,\n                modelIdentifier=md.coSimulation.modelIdentifier, instanceName=\"contact\")\n"
        ));
        py.push_str("fmu.instantiate()\nfmu.setupExperiment(tolerance=1e-6, startTime=0.0)\nf_ex, amplitude = 20.0, 0.05  # the excitation: 20 Hz, 50 mm/s\n");
        if c.harmonic {
            py.push_str("# F_mean averages over the built-in vibration's period 1/f (T_avg only when f = 0)\n");
        } else {
            py.push_str("fmu.setReal([vr[\"T_avg\"]], [1.0 / f_ex])  # F_mean over one period of the excitation\n");
        }
        py.push_str("fmu.enterInitializationMode()\nfmu.exitInitializationMode()\nh, w = 1e-3, 2 * math.pi * f_ex\n");
        py.push_str("for k in range(500):\n    t = k * h\n    fmu.setReal([vr[\"v_sx\"]], [amplitude * math.sin(w * t)])\n    fmu.setRealInputDerivatives([vr[\"v_sx\"]], [1], [amplitude * w * math.cos(w * t)])\n    fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)\n");
        py.push_str("print(\"F_mean =\", fmu.getReal([vr[\"F_mean\"]])[0])\nfmu.terminate()\nfmu.freeInstance()\nshutil.rmtree(unzipdir)\n");
    }
    py
}

/// The platform section: the library of each platform inside the FMU and what it needs.
fn platform_html(scene: &Scene, binaries: &[Binary]) -> String {
    let id = escape(&scene.model_identifier);
    let mut h = String::from("<h2>Platform requirements</h2>\n<ul>\n");
    for b in binaries {
        let files = b
            .folders
            .iter()
            .map(|f| format!("<code>binaries/{f}/{id}.{}</code>", b.file_ext))
            .collect::<Vec<_>>()
            .join(", ");
        let libraries = if b.libraries.is_empty() {
            "only system libraries".to_string()
        } else {
            let names = b
                .libraries
                .iter()
                .map(|l| format!("<code>{}</code>", escape(l)))
                .collect::<Vec<_>>()
                .join(", ");
            format!("only {names}")
        };
        h.push_str(&format!(
            "<li>{files}: {}, {}. It links {libraries}: no other run-time, no Python, no licence server.</li>\n",
            b.os, b.requirement
        ));
    }
    h.push_str("<li>Any FMI 2.0 importer, for Co-Simulation (fmpy, OMSimulator, libcosim, ecos, Simulink's FMU Import block, Dymola, fmi-sim and others) or Model Exchange (the importer's own integrator: fmpy's CVode, Dymola, OpenModelica, Simulink, OMSimulator). The FMI 3.0 edition of the same scene offers both as well.</li>\n");
    let all = ["linux64", "win64", "darwin64"];
    let shipped = |p: &str| {
        binaries.iter().any(|b| {
            b.folders.iter().any(|f| {
                *f == p
                    || (p == "linux64" && f.ends_with("-linux"))
                    || (p == "win64" && f.ends_with("-windows"))
                    || (p == "darwin64" && f.ends_with("-darwin"))
            })
        })
    };
    let absent: Vec<String> = all
        .iter()
        .filter(|p| !shipped(p))
        .map(|p| format!("<code>{p}</code>"))
        .collect();
    if !absent.is_empty() {
        h.push_str(&format!(
            "<li>Not in this FMU: {}. The exporter builds every platform on Linux where its cross toolchain is installed; export the scene again there.</li>\n",
            absent.join(", ")
        ));
    }
    h.push_str("</ul>\n");
    h
}

/// What an importer that integrates the FMU itself (Model Exchange) gets.
fn model_exchange_html(scene: &Scene) -> String {
    let names = |kind: fn(&VarKind) -> bool| {
        scene
            .variables()
            .filter(|v| kind(&v.kind))
            .map(|v| format!("<code>{}</code>", escape(v.name())))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let states = names(|k| matches!(k, VarKind::State(_)));
    let indicators = names(|k| matches!(k, VarKind::Indicator(_)));
    format!(
        "<h2>Model Exchange</h2>\n<p>Instantiated for Model Exchange (FMI 2.0 or 3.0), the FMU hands its continuous states to the importer's integrator: {states}, with their derivatives <code>der(...)</code>, the same equations the Co-Simulation solver integrates. Event indicators {indicators} change sign at the kinks of the friction law, shifted by a band of the tolerance so that a stuck contact hovering at <code>v_r = 0</code> gives no train of events; time events end the averaging windows of <code>F_mean</code>. Directional derivatives are exact (closed form). Without communication steps, <code>F_Fx_step</code> and <code>F_Fy_step</code> equal <code>F_Fx</code> and <code>F_Fy</code>.</p>\n<pre>{}</pre>\n",
        escape(&format!(
            "from fmpy import simulate_fmu\nresult = simulate_fmu('{}.fmu', fmi_type='ModelExchange',\n                      relative_tolerance=1e-8, stop_time=0.1)",
            scene.model_identifier
        ))
    )
}

/// The documentation page of a scene's FMU, for a binary whose requirements are not known (the
/// exporter uses [`index_html_for`]).
pub fn index_html(scene: &Scene) -> String {
    index_html_for(
        scene,
        &[Binary {
            folders: vec!["linux64"],
            file_ext: "so",
            os: "x86-64 Linux",
            requirement:
                "glibc: the exporter prints the version the library needs when it writes the FMU"
                    .into(),
            libraries: vec![],
        }],
    )
}

/// The documentation page of the FMI 3.0 edition of a scene's FMU: the FMI 2.0 page, whose
/// calls map one to one onto FMI 3.0's, with that mapping said up front.
pub fn index_html_fmi3(scene: &Scene, binaries: &[Binary]) -> String {
    let page = index_html_for(scene, binaries);
    page.replacen(
        "<p>FMI 2.0 Co-Simulation FMU generated by",
        "<p><b>FMI 3.0 edition.</b> The same FMU as the FMI 2.0 one of this scene (same variables, \
         value references and results, instantiation token = the FMI 2.0 GUID), for FMI 3.0 \
         importers. Where this page names an FMI 2.0 function, FMI 3.0 has: \
         <code>fmi3InstantiateCoSimulation</code> (without event mode), \
         <code>fmi3EnterInitializationMode</code> (tolerance, start and stop time; \
         <code>fmi2SetupExperiment</code>), <code>fmi3GetFloat64</code>/<code>fmi3SetFloat64</code> \
         (<code>fmi2GetReal</code>/<code>fmi2SetReal</code>), <code>fmi3GetOutputDerivatives</code>, \
         <code>fmi3DoStep</code>, <code>fmi3GetFMUState</code> and the rest of the state functions. \
         Input derivatives have no FMI 3.0 call: inputs are held over a step.</p>\n<p>Generated as an \
         FMI 2.0 Co-Simulation FMU by",
        1,
    )
}

/// The documentation page of a scene's FMU that ships `binaries`.
pub fn index_html_for(scene: &Scene, binaries: &[Binary]) -> String {
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

    h.push_str("<h2>Sign convention</h2>\n");
    h.push_str(SIGN_CONVENTION_SVG);
    h.push_str("<p><code>F_F</code> is the friction force in the paper's convention: it resists the relative velocity <code>v_r = v − v_s</code>, and the support acts on the body with <code>−F_F</code>. While the body slides towards +x relative to the support, <code>F_Fx</code> &gt; 0; under a velocity drive <code>F_Fx</code> is the force that keeps the body at <code>v_d</code>.</p>\n");

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
            if matches!(causality, Causality::Output | Causality::Local) { "(calculated)".into() } else { start_html(scene, v) },
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
    h.push_str("<h2>Choosing the parameters</h2>\n<ul>\n");
    for g in guidance(scene) {
        h.push_str(&format!("<li>{g}</li>\n"));
    }
    h.push_str("</ul>\n");

    h.push_str("<h2>Running it</h2>\n<p>With <a href=\"https://github.com/CATIA-Systems/FMPy\">fmpy</a> (<code>pip install fmpy</code>). For a Co-Simulation FMU the communication step is fmpy's <code>output_interval</code> (<code>--output-interval</code> on fmpy's command line); <code>step_size</code> is for Model Exchange only.</p>\n");
    h.push_str(&format!("<pre>{}</pre>\n", escape(&usage_snippet(scene))));
    h.push_str(&format!(
        "<p>From the command line: <code>fmpy simulate {}.fmu --output-interval 1e-3 --stop-time 0.1</code>. The variable table above gives every name and value reference; value references are the same in every vibrofric FMU.</p>\n",
        escape(&scene.model_identifier)
    ));
    h.push_str(&model_exchange_html(scene));
    h.push_str(&platform_html(scene, binaries));

    h.push_str("<h2>Logging</h2>\n<ul>\n");
    for c in crate::description::log::Category::ALL {
        let (name, d) = (c.name(), c.description());
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
