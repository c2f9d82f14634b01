//! `vibrofric simulate`: a scene run by the core ([`vibrofric::model::Setup`]) directly, without the FMU layer,
//! printed as CSV. It is the independent reference the Python tests compare fmpy's runs of the
//! FMU with, and a quick way to look at a scene.
//!
//! ```text
//! vibrofric simulate SCENE.toml --step H --stop T [--start T0] [--tolerance TOL] [--set NAME=VALUE]...
//! ```
//!
//! The run is the one an FMI master such as fmpy makes with the FMU: the simulator is built at
//! `T0` from the scene's start values (overridden by `--set`, for parameters and inputs), with
//! every input of the scene set, and communication point `k` is `T0 + k·H`; each step goes from
//! the current point `t_k` to `t_k + (t_{k+1} − t_k)` and the last one ends at `T`. Output: a
//! header `time,<outputs of the scene>` and one row per communication point, numbers in
//! shortest round-trip form, so that a reader gets the core's values bit for bit.

use std::path::PathBuf;

use vibrofric::description::{xml, Scene};
use vibrofric::model::{self, InputId};
use vibrofric::table::ParamId;

/// What the command line asks for.
#[derive(Clone, Debug, PartialEq, clap::Args)]
pub struct Options {
    /// The scene file.
    pub scene: PathBuf,
    /// Communication step size H [s].
    #[arg(long, value_name = "H", value_parser = positive)]
    pub step: f64,
    /// Stop time T [s].
    #[arg(long, value_name = "T", value_parser = finite)]
    pub stop: f64,
    /// Start time T0 [s].
    #[arg(long, value_name = "T0", default_value_t = 0.0, value_parser = finite)]
    pub start: f64,
    /// Relative tolerance of the solver.
    #[arg(long, value_name = "TOL", default_value_t = xml::DEFAULT_EXPERIMENT.2)]
    pub tolerance: f64,
    /// Start value of a parameter or input (repeatable).
    #[arg(long, value_name = "NAME=VALUE", value_parser = assignment)]
    pub set: Vec<(String, f64)>,
}

fn finite(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err("must be finite".into()),
        Err(_) => Err("not a number".into()),
    }
}

fn positive(s: &str) -> Result<f64, String> {
    match finite(s)? {
        x if x > 0.0 => Ok(x),
        _ => Err("must be finite and > 0".into()),
    }
}

fn assignment(kv: &str) -> Result<(String, f64), String> {
    let (k, v) = kv.split_once('=').ok_or("must be NAME=VALUE")?;
    let x = v
        .parse::<f64>()
        .map_err(|_| format!("{v} is not a number"))?;
    Ok((k.to_string(), x))
}

/// Runs the scene text and returns the CSV.
pub fn simulate(scene: &Scene, o: &Options) -> Result<String, String> {
    let c = scene.config;
    let mut params = scene.start;
    let mut inputs = scene.inputs;
    for (name, v) in &o.set {
        if let Some(p) = ParamId::from_name(name) {
            p.set(&mut params, *v).map_err(|e| e.to_string())?;
        } else if let Some(i) = InputId::ALL.into_iter().find(|i| i.name() == name) {
            if !i.present(&c) {
                return Err(format!("--set {name}: this scene has no input {name}"));
            }
            *i.slot(&mut inputs) = *v;
        } else {
            return Err(format!("--set {name}: not a parameter or input name"));
        }
    }
    let sim = model::Setup::new(c, params)
        .inputs(inputs)
        .start(o.start)
        .tolerance(o.tolerance)
        .build();
    let mut sim = sim.map_err(|e| e.to_string())?;
    let mut out = String::from("time");
    for id in &scene.outputs {
        out.push(',');
        out.push_str(id.name());
    }
    out.push('\n');
    let row = |out: &mut String, t: f64, sim: &dyn model::Simulator| {
        let y = sim.outputs();
        out.push_str(&format!("{t:e}"));
        for id in &scene.outputs {
            out.push_str(&format!(",{:e}", id.get(&y)));
        }
        out.push('\n');
    };
    row(&mut out, o.start, sim.as_ref());
    let mut t = o.start;
    let mut k: u64 = 0;
    loop {
        // Python's math.isclose, as fmpy decides the last step.
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
        if t > o.stop || close(t, o.stop) {
            break;
        }
        let mut next = o.start + (k + 1) as f64 * o.step;
        if next > o.stop && !close(next, o.stop) {
            next = o.stop;
        }
        let h = next - t;
        sim.step_to(t + h).map_err(|e| format!("at t = {t}: {e}"))?;
        t = next;
        k += 1;
        row(&mut out, t, sim.as_ref());
    }
    Ok(out)
}

/// The whole command: read the scene, simulate.
pub fn run(o: &Options) -> Result<String, String> {
    if o.stop <= o.start {
        return Err(format!(
            "--stop = {}: must be > --start = {}",
            o.stop, o.start
        ));
    }
    let scene = Scene::load(&o.scene).map_err(|e| e.to_string())?;
    if let Some(n) = scene.sections() {
        return Err(format!(
            "{}: a string of {n} contacts; `simulate` runs a single contact: export the string and run its FMU",
            o.scene.display()
        ));
    }
    simulate(&scene, o)
}

#[cfg(test)]
mod tests {
    use super::*;

    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        o: Options,
    }

    fn parse(s: &str) -> Result<Options, String> {
        Cli::try_parse_from(std::iter::once("simulate").chain(s.split_whitespace()))
            .map(|c| c.o)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn parses_and_refuses_with_reasons() {
        let o = parse("s.toml --step 1e-3 --stop 0.01 --set F_d=2 --tolerance 1e-8").unwrap();
        assert_eq!(o.step, 1e-3);
        assert_eq!(o.tolerance, 1e-8);
        assert_eq!(o.set, vec![("F_d".to_string(), 2.0)]);
        assert!(parse("s.toml --stop 1").unwrap_err().contains("--step"));
        assert!(parse("s.toml --step 0 --stop 1")
            .unwrap_err()
            .contains("> 0"));
        assert!(parse("s.toml --step 1 --stop 1 --bogus")
            .unwrap_err()
            .contains("--bogus"));
        assert!(parse("s.toml --step 1 --stop 1 --set k_t")
            .unwrap_err()
            .contains("NAME=VALUE"));
    }

    #[test]
    fn rows_at_every_communication_point() {
        let text = "model_identifier = \"C\"\nlaw = \"dahl\"\nmotion = \"longitudinal\"\ndrive = \"force\"\nsupport = [\"harmonic\"]\n";
        let scene = Scene::parse(text, "c.toml").unwrap();
        let o = parse("c.toml --step 1e-3 --stop 2.5e-3 --set F_d=1").unwrap();
        let csv = simulate(&scene, &o).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert!(lines[0].starts_with("time,F_Fx"));
        assert_eq!(lines.len(), 1 + 4, "t = 0, 1, 2, 2.5 ms");
        assert!(lines[4].starts_with("2.5e-3,"));
        let bad = parse("c.toml --step 1e-3 --stop 1 --set k_t=-1").unwrap();
        assert!(simulate(&scene, &bad).unwrap_err().contains("k_t"));
    }
}
