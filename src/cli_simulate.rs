//! `simulate`: a scene run by the core ([`crate::model::build`]) directly, without the FMU layer,
//! printed as CSV. It is the independent reference the Python tests compare fmpy's runs of the
//! FMU with, and a quick way to look at a scene.
//!
//! ```text
//! simulate SCENE.toml --step H --stop T [--start T0] [--tolerance TOL] [--set NAME=VALUE]...
//! ```
//!
//! The run is the one an FMI master such as fmpy makes with the FMU: the simulator is built at
//! `T0` from the scene's start values (overridden by `--set`, for parameters and inputs), with
//! every input of the scene set, and communication point `k` is `T0 + k·H`; each step goes from
//! the current point `t_k` to `t_k + (t_{k+1} − t_k)` and the last one ends at `T`. Output: a
//! header `time,<outputs of the scene>` and one row per communication point, numbers in
//! shortest round-trip form, so that a reader gets the core's values bit for bit.

use crate::description::scene::Scene;
use crate::model::{self, InputId};
use crate::physics::ParamId;

/// What the command line asks for.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    pub scene: String,
    pub step: f64,
    pub stop: f64,
    pub start: f64,
    pub tolerance: f64,
    pub set: Vec<(String, f64)>,
}

/// Usage text.
pub const USAGE: &str = "usage: simulate SCENE.toml --step H --stop T [--start T0] [--tolerance TOL] [--set NAME=VALUE]...";

fn number(flag: &str, v: Option<&String>) -> Result<f64, String> {
    let v = v.ok_or_else(|| format!("{flag} needs a value; {USAGE}"))?;
    v.parse::<f64>()
        .map_err(|_| format!("{flag} {v}: not a number; {USAGE}"))
}

/// Parses the arguments after the subcommand.
pub fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        scene: String::new(),
        step: f64::NAN,
        stop: f64::NAN,
        start: 0.0,
        tolerance: crate::description::xml::DEFAULT_EXPERIMENT.2,
        set: vec![],
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--step" => o.step = number(a, it.next())?,
            "--stop" => o.stop = number(a, it.next())?,
            "--start" => o.start = number(a, it.next())?,
            "--tolerance" => o.tolerance = number(a, it.next())?,
            "--set" => {
                let kv = it
                    .next()
                    .ok_or_else(|| format!("--set needs NAME=VALUE; {USAGE}"))?;
                let (k, v) = kv
                    .split_once('=')
                    .ok_or_else(|| format!("--set {kv}: must be NAME=VALUE"))?;
                let x = v
                    .parse::<f64>()
                    .map_err(|_| format!("--set {kv}: {v} is not a number"))?;
                o.set.push((k.to_string(), x));
            }
            s if s.starts_with("--") => return Err(format!("unknown option {s}; {USAGE}")),
            s if o.scene.is_empty() => o.scene = s.to_string(),
            s => return Err(format!("unexpected argument {s}; {USAGE}")),
        }
    }
    if o.scene.is_empty() {
        return Err(format!("no scene given; {USAGE}"));
    }
    if !(o.step.is_finite() && o.step > 0.0) {
        return Err(format!("--step = {}: must be finite and > 0", o.step));
    }
    if !(o.start.is_finite() && o.stop.is_finite() && o.stop > o.start) {
        return Err(format!(
            "--stop = {}: must be finite and > --start = {}",
            o.stop, o.start
        ));
    }
    Ok(o)
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
    let mut sim = model::build(c, params, o.start, o.tolerance).map_err(|e| e.to_string())?;
    for id in InputId::ALL {
        if id.present(&c) {
            sim.set_input(id, id.get(&inputs))
                .map_err(|e| e.to_string())?;
        }
    }
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

/// The whole command: parse, read the scene, simulate.
pub fn run(args: &[String]) -> Result<String, String> {
    let o = parse(args)?;
    let scene = Scene::load(std::path::Path::new(&o.scene)).map_err(|e| e.to_string())?;
    simulate(&scene, &o)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn parses_and_refuses_with_reasons() {
        let o = parse(&args(
            "s.toml --step 1e-3 --stop 0.01 --set F_d=2 --tolerance 1e-8",
        ))
        .unwrap();
        assert_eq!(o.step, 1e-3);
        assert_eq!(o.set, vec![("F_d".to_string(), 2.0)]);
        assert!(parse(&args("s.toml --stop 1"))
            .unwrap_err()
            .contains("--step"));
        assert!(parse(&args("s.toml --step 0 --stop 1"))
            .unwrap_err()
            .contains("> 0"));
        assert!(parse(&args("s.toml --step 1 --stop 1 --bogus"))
            .unwrap_err()
            .contains("--bogus"));
    }

    #[test]
    fn rows_at_every_communication_point() {
        let text = "model_identifier = \"C\"\nlaw = \"dahl\"\nmotion = \"longitudinal\"\ndrive = \"force\"\nsupport = [\"harmonic\"]\n";
        let scene = Scene::parse(text, "c.toml").unwrap();
        let o = parse(&args("c.toml --step 1e-3 --stop 2.5e-3 --set F_d=1")).unwrap();
        let csv = simulate(&scene, &o).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert!(lines[0].starts_with("time,F_Fx"));
        assert_eq!(lines.len(), 1 + 4, "t = 0, 1, 2, 2.5 ms");
        assert!(lines[4].starts_with("2.5e-3,"));
        let bad = parse(&args("c.toml --step 1e-3 --stop 1 --set k_t=-1")).unwrap();
        assert!(simulate(&scene, &bad).unwrap_err().contains("k_t"));
    }
}
