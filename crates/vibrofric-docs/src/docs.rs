//! `documentation/index.html` of an FMU: what the scene is, the sign convention (a picture), its
//! variables with units, start values and ranges, the equations of its law, motion and drive,
//! how to choose the parameters, how to run it (fmpy), the platform it needs, and the scene text
//! itself. Plain HTML with no script, readable offline in any browser: a partner who receives
//! only the `.fmu` finds everything here.

mod equations;

use crate::figure::sign_convention_svg;
use equations::equations;
use vibrofric::description::scene::{summary, Scene};
use vibrofric::description::variables::{Causality, VarKind, Variable};
use vibrofric::description::xml::{self, DEFAULT_EXPERIMENT, DISPLAY_UNITS};
use vibrofric::table::InputId;

/// The FMI standard a page speaks: the names of its calls, its identifier and its importer
/// classes. The two editions of a scene share variables, value references and results.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edition {
    Fmi2,
    Fmi3,
}

impl Edition {
    /// "2.0" or "3.0".
    pub fn version(self) -> &'static str {
        match self {
            Edition::Fmi2 => "2.0",
            Edition::Fmi3 => "3.0",
        }
    }

    /// The call that passes the tolerance and the start time.
    fn setup(self) -> &'static str {
        match self {
            Edition::Fmi2 => "<code>fmi2SetupExperiment</code>",
            Edition::Fmi3 => "<code>fmi3EnterInitializationMode</code>",
        }
    }

    /// The error status.
    fn error(self) -> &'static str {
        match self {
            Edition::Fmi2 => "<code>fmi2Error</code>",
            Edition::Fmi3 => "<code>fmi3Error</code>",
        }
    }

    /// The call that gives an input's time derivative (FMI 3.0 Co-Simulation has none).
    fn input_derivatives(self) -> Option<&'static str> {
        match self {
            Edition::Fmi2 => Some("<code>fmi2SetRealInputDerivatives</code>"),
            Edition::Fmi3 => None,
        }
    }

    fn output_derivatives(self) -> &'static str {
        match self {
            Edition::Fmi2 => "<code>fmi2GetRealOutputDerivatives</code>",
            Edition::Fmi3 => "<code>fmi3GetOutputDerivatives</code>",
        }
    }

    fn directional_derivative(self) -> &'static str {
        match self {
            Edition::Fmi2 => "<code>fmi2GetDirectionalDerivative</code>",
            Edition::Fmi3 => "<code>fmi3GetDirectionalDerivative</code>",
        }
    }

    /// How an input is carried over a communication step.
    fn input_hold(self) -> String {
        match self.input_derivatives() {
            Some(call) => {
                format!("held over a step, or extrapolated linearly when {call} gives a derivative")
            }
            None => "held over each communication step (FMI 3.0 has no input derivatives for \
                 Co-Simulation)"
                .to_string(),
        }
    }
}

/// A text shared by both editions (a variable's or log category's description) with the
/// edition's status names (`fmi2Discard` is `fmi3Discard` in FMI 3.0).
fn in_words_of(ed: Edition, text: &str) -> String {
    match ed {
        Edition::Fmi2 => text.to_string(),
        Edition::Fmi3 => text.replace("fmi2", "fmi3"),
    }
}

/// A number as Python reads it as a float (`2000.0`, `2e-7`, `0.001`).
fn py_float(x: f64) -> String {
    let s = xml::number(x);
    if s.contains(['.', 'e', 'i', 'N']) {
        s
    } else {
        format!("{s}.0")
    }
}

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

fn range_html(v: &Variable, c: &vibrofric::table::Config) -> String {
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
/// as HTML list items (FMI 2.0 names).
pub fn guidance(scene: &Scene) -> Vec<String> {
    guidance_for(scene, Edition::Fmi2)
}

/// [`guidance`] in the words of an edition.
pub fn guidance_for(scene: &Scene, ed: Edition) -> Vec<String> {
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
    if c.law.has_contact_damping() {
        let excitation = if c.harmonic {
            "under a fast vibration"
        } else {
            "under a fast excitation through <code>v_sx</code>"
        };
        g.push(format!(
            "<code>zeta_t</code> (LuGre): damping ratio of the contact's tangential mode, \
            <code>h_t = 2·zeta_t·sqrt(m·k_t)</code> (here {zeta}, <code>h_t</code> = {h_t} N·s/m \
            at rest). The default 1 (critical damping, the paper's Eq. 6) adds \
            <code>h_t·ds/dt</code> to <code>F_F</code>: {excitation} <code>ds/dt</code> follows \
            the support velocity and this viscous term makes <code>F_Fx</code> swing beyond \
            <code>F_S</code> within each period, although <code>F_mean</code> stays right. For a \
            contact whose force should stay within <code>F_S</code>, take <code>zeta_t</code> of \
            0.01–0.1, or a smaller <code>v_e</code>, which switches the damping off once the \
            contact slides. How far <code>F_Fx</code> swings in this FMU at its start values, at \
            <code>zeta_t</code> = 0.1 and at <code>v_e</code> = 1e-4 m/s: the second snippet \
            under <i>Running it</i> measures it (it prints the range of <code>F_Fx</code> and \
            <code>F_mean</code> for each).",
            zeta = xml::number(p.zeta_t),
            h_t = xml::number((2.0 * p.zeta_t * (p.m * p.k_t).sqrt()).round()),
        ));
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
    g.push(format!(
        "Tolerance ({}, default 1e-6): the relative tolerance \
        of the internal integrator. The error of <code>F_mean</code> is of the order of \
        tolerance × <code>F_C</code> or smaller; 1e-4 suits system simulation, 1e-8 sweeps that \
        compare small differences of <code>F_mean</code>.",
        ed.setup()
    ));
    let hold = match ed.input_derivatives() {
        Some(call) => format!(
            "passing input derivatives ({call}) makes the inputs linear in time within a step"
        ),
        None => "FMI 3.0 holds the inputs over each step (the FMI 2.0 edition of this scene \
                 also takes their derivatives)"
            .to_string(),
    };
    let period = if c.harmonic && p.f > 0.0 {
        format!(
            " (here {} s, one period of the {} Hz vibration)",
            xml::number(1.0 / p.f),
            xml::number(p.f)
        )
    } else {
        format!(" (here <code>T_avg</code> = {} s)", xml::number(p.t_avg))
    };
    g.push(format!(
        "Communication step: the FMU resolves every vibration period inside a step, so the \
        step follows what the importer needs, not the vibration. <code>F_mean</code> and \
        <code>reduction</code> change once per averaging window: a step of one or a few windows{period} \
        shows them fully. To see the waveform of <code>F_Fx</code>, use a step of at most 1/20 of \
        the vibration period. When the FMU is coupled to a host model through its inputs, the \
        step must resolve the host's dynamics; {hold}."
    ));
    g
}

/// The communication step of the page's snippets: one vibration period with the harmonic source
/// on, else one averaging window `T_avg`; and the words that say which.
fn snippet_step(scene: &Scene) -> (f64, &'static str) {
    let p = &scene.start;
    if scene.config.harmonic && p.f > 0.0 {
        (1.0 / p.f, "one vibration period, 1/f")
    } else {
        (p.t_avg, "one averaging window, T_avg")
    }
}

/// The scene's own start values that the snippets pass, as a template to change: its inputs
/// (but the support velocities) and the harmonic source's amplitude and frequency.
fn snippet_start(scene: &Scene) -> Vec<String> {
    let c = &scene.config;
    scene
        .variables()
        .filter(|v| {
            let input = v.causality(c) == Causality::Input
                && !matches!(v.kind, VarKind::Input(InputId::VSx | InputId::VSy));
            input || (c.harmonic && matches!(v.name(), "u0" | "f"))
        })
        .filter_map(|v| {
            scene
                .start_of(v)
                .map(|x| format!("\"{}\": {}", v.name(), py_float(x)))
        })
        .collect()
}

/// The outputs the snippets print.
fn snippet_outputs(scene: &Scene) -> Vec<&'static str> {
    let c = &scene.config;
    scene
        .variables()
        .filter(|v| v.causality(c) == Causality::Output)
        .map(|v| v.name())
        .filter(|n| ["F_Fx", "F_mean", "reduction"].contains(n))
        .collect()
}

/// A Python (fmpy) snippet that runs this FMU (FMI 2.0).
pub fn usage_snippet(scene: &Scene) -> String {
    usage_snippet_for(scene, Edition::Fmi2)
}

/// A Python (fmpy) snippet that runs this FMU, in the calls of an edition: `simulate_fmu` with
/// the scene's start values and a step that fits its vibration, and with input support motion a
/// co-simulation loop that sets the support velocity before every step.
pub fn usage_snippet_for(scene: &Scene, ed: Edition) -> String {
    let c = &scene.config;
    let id = &scene.model_identifier;
    let outputs = snippet_outputs(scene);
    let (step, which) = snippet_step(scene);
    let mut py = String::new();
    py.push_str("# pip install fmpy\nfrom fmpy import simulate_fmu\n\n");
    py.push_str(&format!(
        "res = simulate_fmu(\n    \"{id}.fmu\",\n    stop_time=0.1,\n    output_interval={},  # the communication step: {which}\n    relative_tolerance=1e-6,\n    start_values={{{}}},  # this scene's start values\n    output={:?},\n)\n",
        xml::number(step),
        snippet_start(scene).join(", "),
        outputs
    ));
    for o in &outputs {
        py.push_str(&format!("print(\"{o} =\", res[\"{o}\"][-1])\n"));
    }
    if !c.input_support {
        return py;
    }
    py.push_str(
        "\n# A co-simulation loop: the importer sets the support velocity v_sx before every step",
    );
    match ed {
        Edition::Fmi2 => py.push_str(
            ",\n# with its derivative, so that the FMU extrapolates it linearly within the step.\n",
        ),
        Edition::Fmi3 => py.push_str(
            ";\n# FMI 3.0 holds it over the step: the value at the step's middle is the best constant.\n",
        ),
    }
    py.push_str("import math\nimport shutil\n\nfrom fmpy import extract, read_model_description\n");
    let (slave, token, set, get, setup) = match ed {
        Edition::Fmi2 => (
            "from fmpy.fmi2 import FMU2Slave",
            "md.guid",
            "setReal",
            "getReal",
            "fmu.setupExperiment(tolerance=1e-6, startTime=0.0)\n",
        ),
        Edition::Fmi3 => (
            "from fmpy.fmi3 import FMU3Slave",
            "md.instantiationToken",
            "setFloat64",
            "getFloat64",
            "",
        ),
    };
    let class = &slave[slave.len() - 9..];
    py.push_str(&format!("{slave}\n\n"));
    py.push_str(&format!(
        "md = read_model_description(\"{id}.fmu\")\nvr = {{v.name: v.valueReference for v in md.modelVariables}}\nunzipdir = extract(\"{id}.fmu\")\nfmu = {class}(guid={token}, unzipDirectory=unzipdir,\n                modelIdentifier=md.coSimulation.modelIdentifier, instanceName=\"contact\")\n"
    ));
    py.push_str(&format!(
        "fmu.instantiate()\n{setup}f_ex, amplitude = 20.0, 0.05  # the excitation: 20 Hz, 50 mm/s\n"
    ));
    if c.harmonic {
        py.push_str(
            "# F_mean averages over the built-in vibration's period 1/f (T_avg only when f = 0)\n",
        );
    } else {
        py.push_str(&format!(
            "fmu.{set}([vr[\"T_avg\"]], [1.0 / f_ex])  # F_mean over one period of the excitation\n"
        ));
    }
    match ed {
        Edition::Fmi2 => py.push_str("fmu.enterInitializationMode()\n"),
        Edition::Fmi3 => {
            py.push_str("fmu.enterInitializationMode(tolerance=1e-6, startTime=0.0)\n")
        }
    }
    py.push_str("fmu.exitInitializationMode()\nh, w = 1e-3, 2 * math.pi * f_ex\nfor k in range(500):\n    t = k * h\n");
    match ed {
        Edition::Fmi2 => py.push_str("    fmu.setReal([vr[\"v_sx\"]], [amplitude * math.sin(w * t)])\n    fmu.setRealInputDerivatives([vr[\"v_sx\"]], [1], [amplitude * w * math.cos(w * t)])\n"),
        Edition::Fmi3 => py.push_str("    fmu.setFloat64([vr[\"v_sx\"]], [amplitude * math.sin(w * (t + h / 2))])\n"),
    }
    py.push_str("    fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)\n");
    py.push_str(&format!(
        "print(\"F_mean =\", fmu.{get}([vr[\"F_mean\"]])[0])\nfmu.terminate()\nfmu.freeInstance()\nshutil.rmtree(unzipdir)\n"
    ));
    py
}

/// A snippet that measures how far LuGre's `F_Fx` swings within the vibration periods at the
/// scene's start values, at `zeta_t` = 0.1 and at `v_e` = 1e-4 m/s (the page's guidance points
/// to it). Without a harmonic source it imposes the co-simulation loop's excitation through
/// `v_sx`.
pub fn swing_snippet(scene: &Scene) -> String {
    let id = &scene.model_identifier;
    let p = &scene.start;
    let mut py = String::new();
    let cases = "cases = {\"start values\": {}, \"zeta_t = 0.1\": {\"zeta_t\": 0.1}, \"v_e = 1e-4 m/s\": {\"v_e\": 1e-4}}\n";
    if scene.config.harmonic && p.f > 0.0 {
        let period = 1.0 / p.f;
        py.push_str("from fmpy import simulate_fmu\n\n# F_Fx sampled 40 times per vibration period over 20 periods; the last 10 are kept.\n");
        py.push_str(cases);
        py.push_str(&format!(
            "for label, values in cases.items():\n    r = simulate_fmu(\"{id}.fmu\", stop_time={}, output_interval={},\n                     start_values=values, output=[\"F_Fx\", \"F_mean\"])\n",
            xml::number(20.0 * period),
            xml::number(period / 40.0)
        ));
    } else {
        py.push_str("import numpy as np\nfrom fmpy import simulate_fmu\n\n# The loop's excitation, 20 Hz and 50 mm/s, as an input signal; F_Fx sampled every\n# 0.1 ms over 10 periods, the last 5 kept; F_mean over one period of the excitation.\n");
        py.push_str("t = np.linspace(0.0, 0.5, 5001)\nsignal = np.array(list(zip(t, 0.05 * np.sin(2 * np.pi * 20.0 * t))),\n                  dtype=[(\"time\", float), (\"v_sx\", float)])\n");
        py.push_str(cases);
        py.push_str(&format!(
            "for label, values in cases.items():\n    r = simulate_fmu(\"{id}.fmu\", stop_time=0.5, output_interval=1e-4, input=signal,\n                     start_values={{\"T_avg\": 0.05, **values}}, output=[\"F_Fx\", \"F_mean\"])\n"
        ));
    }
    py.push_str("    late = r[\"F_Fx\"][len(r) // 2:]\n    print(f\"{label}: F_Fx from {late.min():.1f} to {late.max():.1f} N, F_mean = {r['F_mean'][-1]:.2f} N\")\n");
    py
}

/// A Model Exchange run through fmpy's own integrator.
fn model_exchange_snippet(scene: &Scene) -> String {
    let (step, _) = snippet_step(scene);
    let p = &scene.start;
    let stop = if scene.config.harmonic && p.f > 0.0 {
        20.0 / p.f
    } else {
        0.1
    };
    let out = snippet_outputs(scene);
    let first = out.first().copied().unwrap_or("F_Fx");
    format!(
        "from fmpy import simulate_fmu\n\nresult = simulate_fmu(\n    \"{}.fmu\",\n    fmi_type=\"ModelExchange\",  # fmpy's CVode integrates the FMU's states\n    relative_tolerance=1e-8,\n    stop_time={},\n    output_interval={},\n)\nprint(\"{first} =\", result[\"{first}\"][-1])\n",
        scene.model_identifier,
        xml::number(stop),
        xml::number(step)
    )
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
    // FMI 3.0's folders are `<arch>-<os>`, FMI 2.0's `linux64`, `win64`, `darwin64`.
    let fmi3 = binaries
        .iter()
        .any(|b| b.folders.iter().any(|f| f.contains('-')));
    h.push_str(if fmi3 {
        "<li>Any FMI 3.0 importer, for Co-Simulation (fmpy, fmi-sim, Dymola, Simulink and others) or Model Exchange (the importer's own integrator). The FMI 2.0 edition of the same scene offers both as well, for FMI 2.0 importers.</li>\n"
    } else {
        "<li>Any FMI 2.0 importer, for Co-Simulation (fmpy, OMSimulator, libcosim, ecos, Simulink's FMU Import block, Dymola, fmi-sim and others) or Model Exchange (the importer's own integrator: fmpy's CVode, Dymola, OpenModelica, Simulink, OMSimulator). The FMI 3.0 edition of the same scene offers both as well.</li>\n"
    });
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
fn model_exchange_html(scene: &Scene, ed: Edition) -> String {
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
    let instantiate = match ed {
        Edition::Fmi2 => "<code>fmi2Instantiate</code> with <code>fmi2ModelExchange</code>",
        Edition::Fmi3 => "<code>fmi3InstantiateModelExchange</code>",
    };
    format!(
        "<h2>Model Exchange</h2>\n<p>This FMU offers Model Exchange as well as Co-Simulation. Instantiated for Model Exchange ({instantiate}), it hands its continuous states to the importer's integrator: {states}, with their derivatives <code>der(...)</code>, the same equations the Co-Simulation solver integrates. Event indicators {indicators} change sign at the kinks of the friction law, shifted by a band of the tolerance so that a stuck contact hovering at <code>v_r = 0</code> gives no train of events; time events end the averaging windows of <code>F_mean</code>. Directional derivatives ({}) are exact (closed form). Without communication steps, <code>F_Fx_step</code> and <code>F_Fy_step</code> equal <code>F_Fx</code> and <code>F_Fy</code>. With fmpy:</p>\n<pre class=\"python\">{}</pre>\n",
        ed.directional_derivative(),
        escape(&model_exchange_snippet(scene))
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

/// The documentation page of the FMI 3.0 edition of a scene's FMU that ships `binaries`: the
/// FMI 2.0 page's content in FMI 3.0's calls, with FMI 3.0 snippets.
pub fn index_html_fmi3(scene: &Scene, binaries: &[Binary]) -> String {
    page(scene, binaries, Edition::Fmi3)
}

/// The documentation page of the FMI 2.0 edition of a scene's FMU that ships `binaries`.
pub fn index_html_for(scene: &Scene, binaries: &[Binary]) -> String {
    page(scene, binaries, Edition::Fmi2)
}

/// The documentation page of one edition of a scene's FMU.
fn page(scene: &Scene, binaries: &[Binary], ed: Edition) -> String {
    if scene.string.is_some() {
        return crate::string_page::page(scene, ed);
    }
    let c = &scene.config;
    let id = escape(&scene.model_identifier);
    let v = ed.version();
    let mut h = String::new();
    h.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    h.push_str(&format!("<title>{id}: vibrofric FMU (FMI {v})</title>\n"));
    h.push_str("<style>body{font-family:sans-serif;max-width:60em;margin:2em auto;padding:0 1em;line-height:1.4}table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:.2em .5em;text-align:left;vertical-align:top}code,pre{background:#f4f4f4}pre{padding:.5em;overflow-x:auto}</style>\n");
    h.push_str("</head>\n<body>\n");
    h.push_str(&format!(
        "<h1>{id}</h1>\n<p>{}</p>\n",
        escape(&scene.description)
    ));
    let token = match ed {
        Edition::Fmi2 => "GUID",
        Edition::Fmi3 => "instantiation token",
    };
    h.push_str(&format!(
        "<p>FMI {v} FMU for Co-Simulation and Model Exchange, generated by {} ({token} <code>{}</code>). {}.</p>\n",
        escape(&xml::generation_tool()),
        escape(&xml::guid(scene)),
        escape(&summary(c))
    ));
    let other = match ed {
        Edition::Fmi2 => "<p>The FMI 3.0 edition of this scene has the same variables, value references and results for FMI 3.0 importers.</p>\n",
        Edition::Fmi3 => "<p>The FMI 2.0 edition of this scene has the same variables, value references and results (its GUID is this instantiation token) for FMI 2.0 importers; it also takes input derivatives.</p>\n",
    };
    h.push_str(other);
    h.push_str(&crate::string_page::load_warning_html(scene));
    h.push_str(&format!(
        "<p>Scene: law <code>{}</code>, motion <code>{}</code>, drive <code>{}</code>{}, support motion {}.</p>\n",
        c.law.word(),
        c.motion.word(),
        c.drive.word(),
        if c.has_lateral_choice() {
            format!(", lateral <code>{}</code>", c.lateral.word())
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
    h.push_str(&sign_convention_svg(c.planar()));
    h.push_str("<p><code>F_F</code> is the friction force in the paper's convention: it resists the relative velocity <code>v_r = v − v_s</code>, and the support acts on the body with <code>−F_F</code>. While the body slides towards +x relative to the support, <code>F_Fx</code> &gt; 0; under a velocity drive <code>F_Fx</code> is the force that keeps the body at <code>v_d</code>.</p>\n");

    h.push_str("<h2>Equations</h2>\n<ul>\n");
    for e in equations(scene, ed) {
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
            escape(&in_words_of(ed, v.description))
        ));
    }
    h.push_str("</table>\n");
    h.push_str(&format!("<p>Parameters with variability <code>tunable</code> may change between communication steps; the harmonic source stays continuous in phase. Parameters out of their physical range are refused with {} and a log message naming the rule.</p>\n", ed.error()));

    let (t0, t1, tol, step) = DEFAULT_EXPERIMENT;
    h.push_str(&format!(
        "<h2>Default experiment</h2>\n<p>From {} s to {} s, relative tolerance {}, communication step {} s. The internal solver integrates exactly to every communication point and uses the tolerance given to {} when it is defined.</p>\n",
        xml::number(t0),
        xml::number(t1),
        xml::number(tol),
        xml::number(step),
        ed.setup()
    ));
    h.push_str("<h2>Choosing the parameters</h2>\n<ul>\n");
    for g in guidance_for(scene, ed) {
        h.push_str(&format!("<li>{g}</li>\n"));
    }
    h.push_str("</ul>\n");

    let (step, _) = snippet_step(scene);
    h.push_str(&format!("<h2>Running it</h2>\n<p>With <a href=\"https://github.com/CATIA-Systems/FMPy\">fmpy</a> (<code>pip install fmpy</code>), which reads FMI {v} FMUs like this one. For Co-Simulation the communication step is fmpy's <code>output_interval</code> (<code>--output-interval</code> on fmpy's command line); <code>step_size</code> is for Model Exchange only. The snippets use this scene's start values and a step of {}; the file is this FMU, <code>{id}.fmu</code>.</p>\n", escape(snippet_step(scene).1)));
    h.push_str(&format!(
        "<pre class=\"python\">{}</pre>\n",
        escape(&usage_snippet_for(scene, ed))
    ));
    if c.law.has_contact_damping() {
        h.push_str("<p>How far <code>F_Fx</code> swings within the periods (see <code>zeta_t</code> above):</p>\n");
        h.push_str(&format!(
            "<pre class=\"python\">{}</pre>\n",
            escape(&swing_snippet(scene))
        ));
    }
    h.push_str(&format!(
        "<p>From the command line: <code class=\"shell\">fmpy simulate {id}.fmu --output-interval {} --stop-time 0.1</code>. The variable table above gives every name and value reference; value references are the same in every vibrofric FMU.</p>\n",
        xml::number(step)
    ));
    h.push_str(&model_exchange_html(scene, ed));
    h.push_str(&platform_html(scene, binaries));

    h.push_str("<h2>Logging</h2>\n<ul>\n");
    for c in vibrofric::description::log::Category::ALL {
        let (name, d) = (c.name(), c.description());
        let d = in_words_of(ed, d);
        h.push_str(&format!("<li><code>{name}</code>: {}</li>\n", escape(&d)));
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
