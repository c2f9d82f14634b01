//! The exporter's self-checks: each exported FMU, loaded through the importer crate, against the
//! core library run directly (Co-Simulation, the FMI 3.0 edition, Model Exchange).

use std::path::Path;

use vibrofric::description::variables::VarKind;
use vibrofric::description::{xml, Scene};
use vibrofric::model::{self, StateId};
use vibrofric_import::fmi3::Fmu3;
use vibrofric_import::{Fmu, Importer};

/// The FMI 3.0 edition through the importer's FMI 3.0 loader, on the steps of [`self_check`]:
/// its `F_mean` and `reduction` must equal the FMI 2.0 edition's bit for bit.
pub fn self_check_fmi3(fmu3_path: &Path, fmu2_path: &Path) -> Result<String, String> {
    let (t0, t1, _, step) = xml::DEFAULT_EXPERIMENT;
    let fmu2 = Fmu::load(fmu2_path).map_err(|e| e.to_string())?;
    let fmu3 = Fmu3::load(fmu3_path).map_err(|e| e.to_string())?;
    if fmu3.description.guid != fmu2.description.guid {
        return Err(format!(
            "instantiationToken {} is not the FMI 2.0 GUID {}",
            fmu3.description.guid, fmu2.description.guid
        ));
    }
    let outputs = ["F_mean", "reduction"].map(|n| fmu2.description.vr(n));
    let outputs: Vec<u32> = outputs.into_iter().flatten().collect();
    let rows2 = fmu2
        .simulate(t1 - t0, step, &[], &outputs)
        .map_err(|e| e.to_string())?;
    let rows3 = fmu3
        .simulate(t1 - t0, step, &[], &outputs)
        .map_err(|e| e.to_string())?;
    let same = rows2.len() == rows3.len()
        && rows2
            .iter()
            .flatten()
            .zip(rows3.iter().flatten())
            .all(|(a, b)| a.to_bits() == b.to_bits());
    if !same {
        return Err("F_mean or reduction differ from the FMI 2.0 edition's".into());
    }
    Ok(format!(
        "F_mean and reduction at all {} points equal to the FMI 2.0 edition's, bit for bit",
        rows3.len()
    ))
}

/// The core for a scene as the FMU starts it in its default experiment: its start values and
/// inputs, at `t0`, tolerance `tol`.
fn core_at(scene: &Scene, t0: f64, tol: f64) -> Result<Box<dyn model::Simulator>, String> {
    model::Setup::new(scene.config, scene.start)
        .inputs(scene.inputs)
        .start(t0)
        .tolerance(tol)
        .build()
        .map_err(|e| e.to_string())
}

/// Model Exchange through the exported FMU: the core steps the scene (its start values, the
/// default tolerance) to a time inside a later window; an instance for Model Exchange, set to
/// the same time and states, must give the core's derivatives and the Jacobian column of each
/// state bit for bit (the same code behind the C interface).
pub fn self_check_model_exchange(fmu_path: &Path, scene: &Scene) -> Result<String, String> {
    let (t0, _, tol, _) = xml::DEFAULT_EXPERIMENT;
    let t = t0 + 0.0123;
    let mut sim = core_at(scene, t0, tol)?;
    sim.step_to(t).map_err(|e| e.to_string())?;
    let states: Vec<StateId> = scene
        .variables()
        .filter_map(|v| match v.kind {
            VarKind::State(x) => Some(x),
            _ => None,
        })
        .collect();
    let (x, dx) = (sim.states(), sim.derivatives());
    let fmu = Fmu::load(fmu_path).map_err(|e| e.to_string())?;
    let mut inst = fmu
        .instantiate_model_exchange("self-check")
        .map_err(|e| e.to_string())?;
    let ok = |s: vibrofric_import::Status, what: &str, inst: &vibrofric_import::Instance| {
        if s == vibrofric_import::Status::Ok {
            Ok(())
        } else {
            Err(format!("{what}: {s:?} ({})", inst.last_message()))
        }
    };
    ok(inst.setup_experiment(Some(tol), t0, None), "setup", &inst)?;
    ok(inst.enter_initialization_mode(), "initialization", &inst)?;
    ok(inst.exit_initialization_mode(), "initialization", &inst)?;
    ok(inst.new_discrete_states().0, "event update", &inst)?;
    ok(inst.enter_continuous_time_mode(), "continuous time", &inst)?;
    ok(inst.set_time(t), "time", &inst)?;
    let values: Vec<f64> = states.iter().map(|s| x[s.index()]).collect();
    ok(inst.set_continuous_states(&values), "states", &inst)?;
    let got = inst
        .get_derivatives(states.len())
        .map_err(|s| format!("derivatives: {s:?} ({})", inst.last_message()))?;
    for (s, d) in states.iter().zip(&got) {
        if d.to_bits() != dx[s.index()].to_bits() {
            return Err(format!(
                "{} = {d} through the FMU but {} through the core",
                s.derivative_name(),
                dx[s.index()]
            ));
        }
    }
    let unknowns: Vec<u32> = states.iter().map(|s| s.derivative_vr()).collect();
    for known in &states {
        let mut dir = [0.0; StateId::COUNT];
        dir[known.index()] = 1.0;
        let (core, _) = sim.tangent(&dir, &model::Inputs::default());
        let column = inst
            .get_directional_derivative(&unknowns, &[known.vr()], &[1.0])
            .map_err(|s| format!("directional derivative: {s:?} ({})", inst.last_message()))?;
        for (s, d) in states.iter().zip(&column) {
            if d.to_bits() != core[s.index()].to_bits() {
                return Err(format!(
                    "d {} / d {} = {d} through the FMU but {} through the core",
                    s.derivative_name(),
                    known.name(),
                    core[s.index()]
                ));
            }
        }
    }
    Ok(format!(
        "the derivatives of its {} states and their Jacobian at t = {t} s equal to the core's, bit for bit",
        states.len()
    ))
}

/// A short simulation through the exported FMU: load the archive with the crate's importer
/// (unpacks it, loads `binaries/<platform>/<model_identifier>.so`, instantiates with the GUID of
/// its model description and its `resources/`), run the default experiment (0.1 s, communication
/// step 1e-3 s) with the scene's start values, and compare `F_mean` and `reduction` with the same
/// steps taken by the core library directly. Returns the line to print.
pub fn self_check(fmu_path: &Path, scene: &Scene) -> Result<String, String> {
    let (t0, t1, tol, step) = xml::DEFAULT_EXPERIMENT;
    let clock = std::time::Instant::now();
    let fmu = Fmu::load(fmu_path).map_err(|e| e.to_string())?;
    if fmu.description.guid != xml::guid(scene) {
        return Err(format!(
            "the archive's GUID {} is not the scene's {}",
            fmu.description.guid,
            xml::guid(scene)
        ));
    }
    let vr = |name: &str| {
        fmu.description
            .vr(name)
            .ok_or_else(|| format!("the FMU has no variable {name}"))
    };
    // `reduction` is an output of velocity-driven scenes only.
    let mut outputs = vec![vr("F_mean")?];
    outputs.extend(fmu.description.vr("reduction"));
    let rows = fmu
        .simulate(t1 - t0, step, &[], &outputs)
        .map_err(|e| e.to_string())?;
    let elapsed = clock.elapsed().as_secs_f64();
    let last = rows.last().ok_or("the simulation returned no rows")?;
    let (f_mean, reduction) = (last[1], last.get(2).copied());
    if !(f_mean.is_finite() && reduction.is_none_or(f64::is_finite)) {
        return Err(format!(
            "non-finite result: F_mean = {f_mean}, reduction = {reduction:?}"
        ));
    }
    let reduction = reduction.map_or(String::new(), |r| format!(", reduction = {r:.4}"));

    // The same communication points through the core (as `Importer::simulate` steps them).
    let mut sim = core_at(scene, t0, tol)?;
    let n = ((t1 - t0) / step).round().max(1.0) as u64;
    let mut t = t0;
    for k in 0..n {
        t = if k + 1 == n { t1 } else { t + step };
        sim.step_to(t).map_err(|e| e.to_string())?;
    }
    let core = sim.outputs();
    let diff = (f_mean - core.f_mean).abs();
    // Both run the same code with the same tolerance: anything beyond rounding is a fault.
    let scale = scene.start.f_c().max(f_mean.abs()).max(1e-12);
    if diff > 1e-9 * scale {
        return Err(format!(
            "F_mean = {f_mean} N through the FMU but {} N through the core",
            core.f_mean
        ));
    }
    let agreement = if diff == 0.0 {
        "identical to the core".to_string()
    } else {
        format!("core differs by {diff:.1e} N")
    };
    Ok(format!(
        "F_mean = {f_mean:.4} N{reduction} at t = {t1} s ({n} steps of {step} s through the FMU in {:.0} ms; {agreement})",
        elapsed * 1e3
    ))
}

/// How long the self-check of a string of contacts simulates: its integrator costs seconds of
/// CPU per simulated second at a hundred sections, so a short push.
const STRING_CHECK: (f64, f64) = (0.02, 1e-3);

/// A string of contacts through its exported FMUs: both editions pushed at the top (`v_top` =
/// 0.5 m/s) for 20 ms in steps of 1 ms, `F_top_step` and `F_bottom_step` at every point equal,
/// bit for bit, to each other's and to the core's string run directly.
pub fn self_check_string(fmu2: &Path, fmu3: &Path, scene: &Scene) -> Result<String, String> {
    use vibrofric::model::string::{build_string, StringConfig, StringInput, StringParams};
    use vibrofric::table::StringVar;
    let (t1, step) = STRING_CHECK;
    let tol = xml::DEFAULT_EXPERIMENT.2;
    let values = scene.string.as_ref().ok_or("not a string scene")?;
    let v_top = 0.5;
    let inputs = [(StringVar::VTop.vr(), v_top)];
    let outputs = [StringVar::FTopStep.vr(), StringVar::FBottomStep.vr()];
    let clock = std::time::Instant::now();
    let f2 = Fmu::load(fmu2).map_err(|e| e.to_string())?;
    let rows2 = f2
        .simulate(t1, step, &inputs, &outputs)
        .map_err(|e| e.to_string())?;
    let elapsed = clock.elapsed().as_secs_f64();
    let f3 = Fmu3::load(fmu3).map_err(|e| e.to_string())?;
    let rows3 = f3
        .simulate(t1, step, &inputs, &outputs)
        .map_err(|e| e.to_string())?;
    let c = &scene.config;
    let config = StringConfig {
        law: c.law,
        harmonic: c.harmonic,
        normal_input: c.normal_input,
    };
    let params = StringParams::from_values(scene.start, values, values.get(StringVar::FN));
    let mut sim = build_string(config, params, 0.0, tol).map_err(|e| e.to_string())?;
    sim.set_input(StringInput::VTop, v_top)
        .map_err(|e| e.to_string())?;
    let mut core = vec![];
    let n = (t1 / step).round() as u64;
    let mut t = 0.0;
    for k in 0..=n {
        let o = sim.outputs();
        core.push(vec![t, o.f_top_step, o.f_bottom_step]);
        if k == n {
            break;
        }
        t = if k + 1 == n { t1 } else { t + step };
        sim.step_to(t).map_err(|e| e.to_string())?;
    }
    let same = |a: &[Vec<f64>], b: &[Vec<f64>]| {
        a.len() == b.len()
            && a.iter()
                .flatten()
                .zip(b.iter().flatten())
                .all(|(x, y)| x.to_bits() == y.to_bits())
    };
    if !same(&rows2, &core) {
        return Err("F_top_step or F_bottom_step differ from the core's".into());
    }
    if !same(&rows3, &rows2) {
        return Err("the FMI 3.0 edition differs from the FMI 2.0 edition".into());
    }
    let last = rows2.last().ok_or("no rows")?;
    Ok(format!(
        "{} sections pushed at the top at {v_top} m/s: F_top_step = {:.1} N, F_bottom_step = {:.4} N at t = {t1} s ({n} steps of {step} s through the FMU in {:.0} ms); the FMI 3.0 edition and the core identical at all {} points",
        values.sections,
        last[1],
        last[2],
        elapsed * 1e3,
        rows2.len()
    ))
}
