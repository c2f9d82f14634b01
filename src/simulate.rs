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
//!
//! A string scene (`[string]`) runs the string of its FMU: its outputs as columns, an array as
//! `x[1]` … `x[N]` (the FMI 2.0 names, in the model description's order); `--set` takes a
//! string variable's every element (`F_d=…`), one element (`F_d[3]=…`) or a shared law
//! parameter (`k_t=…`).

use std::path::PathBuf;

use vibrofric::description::{xml, Scene};
use vibrofric::model::{self, InputId};
use vibrofric::table::{shared_params, Config, ParamId, Params, Role, StringValues, StringVar};

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
    let header: Vec<String> = scene.outputs.iter().map(|id| id.name().into()).collect();
    communicate(o, &header, sim.as_mut(), |sim| {
        let y = sim.outputs();
        scene.outputs.iter().map(|id| id.get(&y)).collect()
    })
}

/// Runs a string scene and returns the CSV: a column per element of each output in the
/// order of the FMI 2.0 model description (`x[1]` … `x[N]`, `F_top`, ...).
pub fn simulate_string(scene: &Scene, o: &Options) -> Result<String, String> {
    let c = scene.config;
    let start = scene.string.as_ref().ok_or("not a string scene")?;
    let n = start.sections;
    let (mut shared, mut values) = (scene.start, start.clone());
    for (name, v) in &o.set {
        set_string(&c, (&mut shared, &mut values), name, *v)?;
    }
    let time = (o.start, o.tolerance);
    let mut sim = model::string::build_from_values(&c, shared, &values, start, time, false)
        .map_err(|e| e.to_string())?;
    let outputs: Vec<StringVar> = StringVar::ALL
        .into_iter()
        .filter(|v| v.present(&c, n) && v.role(&c) == Role::Output)
        .collect();
    let header: Vec<String> = outputs
        .iter()
        .flat_map(|v| (0..v.len(n)).map(|i| v.element_name(i)))
        .collect();
    communicate(o, &header, sim.as_mut(), |sim| {
        let y = sim.outputs();
        outputs.iter().flat_map(|v| y.values(*v).to_vec()).collect()
    })
}

/// `--set NAME=VALUE` on a string: every element of a string variable (`F_d`), one element
/// (`F_d[3]`, 1-based), or a shared law parameter (`k_t`).
fn set_string(
    c: &Config,
    (shared, values): (&mut Params, &mut StringValues),
    name: &str,
    v: f64,
) -> Result<(), String> {
    let (base, element) = match name.strip_suffix(']').and_then(|s| s.split_once('[')) {
        Some((base, i)) => {
            let i = i.parse::<usize>().ok().filter(|&i| i >= 1);
            let i = i.ok_or(format!("--set {name}: an element is counted from 1"))?;
            (base, Some(i))
        }
        None => (name, None),
    };
    let n = values.sections;
    let var = StringVar::from_name(base).filter(|var| var.present(c, n) && var.settable(c));
    match (var, element) {
        (Some(var), None) => values.get_mut(var).fill(v),
        (Some(var), Some(i)) => match values.get_mut(var).get_mut(i - 1) {
            Some(x) => *x = v,
            None => {
                let len = var.len(n);
                return Err(format!("--set {name}: {base} has {len} elements"));
            }
        },
        (None, None) => match ParamId::from_name(name) {
            Some(p) if shared_params(c).any(|q| q == p) => {
                p.set(shared, v).map_err(|e| e.to_string())?
            }
            _ => {
                return Err(format!(
                    "--set {name}: not a parameter or input of this string"
                ))
            }
        },
        (None, Some(_)) => {
            return Err(format!(
                "--set {name}: {base} is not a parameter or input of this string"
            ))
        }
    }
    Ok(())
}

/// A simulator an FMI master steps: a single contact's or a string's.
trait Stepped {
    fn advance(&mut self, t: f64) -> Result<(), String>;
}

impl Stepped for dyn model::Simulator {
    fn advance(&mut self, t: f64) -> Result<(), String> {
        self.step_to(t).map_err(|e| e.to_string())
    }
}

impl Stepped for dyn model::string::StringSimulator {
    fn advance(&mut self, t: f64) -> Result<(), String> {
        self.step_to(t).map_err(|e| e.to_string())
    }
}

/// The run of an FMI master over the communication points of `o`: a CSV header `time` and
/// `header`, and a row of `outputs` at the start and after each step to the next point.
fn communicate<S: Stepped + ?Sized>(
    o: &Options,
    header: &[String],
    sim: &mut S,
    outputs: impl Fn(&S) -> Vec<f64>,
) -> Result<String, String> {
    let mut out = String::from("time");
    for name in header {
        out.push(',');
        out.push_str(name);
    }
    out.push('\n');
    let row = |out: &mut String, t: f64, sim: &S| {
        out.push_str(&format!("{t:e}"));
        for y in outputs(sim) {
            out.push_str(&format!(",{y:e}"));
        }
        out.push('\n');
    };
    row(&mut out, o.start, sim);
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
        sim.advance(t + h).map_err(|e| format!("at t = {t}: {e}"))?;
        t = next;
        k += 1;
        row(&mut out, t, sim);
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
    match scene.string {
        Some(_) => simulate_string(&scene, o),
        None => simulate(&scene, o),
    }
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

    #[test]
    fn a_string_runs_with_a_column_per_element_and_sets_elements() {
        let text = "model_identifier = \"S\"\nlaw = \"dahl\"\nmotion = \"longitudinal\"\ndrive = \"force\"\nsupport = [\"input\"]\n[string]\nsections = 3\n[start]\nk_s = 1e5\nk_top = 1e4\n";
        let scene = Scene::parse(text, "s.toml").unwrap();
        let o = parse("s.toml --step 1e-3 --stop 2e-3 --set F_d[2]=8 --set k_t=2e8").unwrap();
        let csv = simulate_string(&scene, &o).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        let header: Vec<&str> = lines[0].split(',').collect();
        assert_eq!(
            &header[..5],
            ["time", "F_Fx[1]", "F_Fx[2]", "F_Fx[3]", "x[1]"]
        );
        assert!(header.contains(&"F_link[2]") && !header.contains(&"F_link[3]"));
        assert_eq!(header.last(), Some(&"F_bottom_step"));
        assert_eq!(lines.len(), 1 + 3, "t = 0, 1, 2 ms");
        // Only section 2 is pushed: it leads, its neighbours follow through the links.
        let last: Vec<f64> = lines[3].split(',').map(|x| x.parse().unwrap()).collect();
        let x = |i: usize| last[header.iter().position(|h| *h == format!("x[{i}]")).unwrap()];
        assert!(x(2) > x(1) && x(2) > x(3) && x(1) > 0.0, "{lines:?}");
        for (set, words) in [
            ("F_d[4]=1", "F_d has 3 elements"),
            ("F_d[0]=1", "counted from 1"),
            ("x=1", "not a parameter or input"),
            ("T_avg=1", "not a parameter or input"),
            ("m[2]=-1", "m[2] = -1"),
        ] {
            let o = parse(&format!("s.toml --step 1e-3 --stop 2e-3 --set {set}")).unwrap();
            let e = simulate_string(&scene, &o).unwrap_err();
            assert!(e.contains(words), "{set}: {e}");
        }
    }
}
