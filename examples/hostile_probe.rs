//! The slowest calls we can construct inside the accepted ranges: every standard scene, every
//! parameter and input at each end of its range, one communication step of 1 ms and one of 1 s;
//! prints what each returned and how long it took, slowest first.
//!
//! cargo run --release --example hostile_probe

#[path = "../tests/support/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use std::time::Instant;

use vibrofric::model::{InputId, OutputId, Setup};
use vibrofric::table::ParamId;

/// A case: its name, what it does to the parameters, and an input to set.
type Case = (
    String,
    Box<dyn Fn(&mut vibrofric::table::Params)>,
    Option<(InputId, f64)>,
);

fn main() {
    let mut rows = vec![];
    for (_, sc) in scenes::standard_scenes() {
        let mut cases: Vec<Case> = vec![];
        for id in ParamId::ALL {
            if !id.present(&sc.config) || id == ParamId::MaxSteps {
                continue;
            }
            for v in [id.rule().min, id.rule().max] {
                cases.push((
                    format!("{}={v:e}", id.name()),
                    Box::new(move |p| id.set(p, v).unwrap()),
                    None,
                ));
            }
        }
        for id in InputId::ALL {
            if id.present(&sc.config) {
                for v in [id.rule().min, id.rule().max] {
                    cases.push((
                        format!("{}={v:e}", id.name()),
                        Box::new(|_| {}),
                        Some((id, v)),
                    ));
                }
            }
        }
        for (name, set, input) in &cases {
            for h in [1e-3, 1.0] {
                let mut p = sc.start;
                set(&mut p);
                let mut sim = match Setup::new(sc.config, p).inputs(sc.inputs).build() {
                    Ok(s) => s,
                    Err(e) => {
                        rows.push((
                            0.0,
                            format!("{} {name} h={h}: build: {e}", sc.model_identifier),
                        ));
                        continue;
                    }
                };
                if let Some((id, v)) = input {
                    sim.set_input(*id, *v).unwrap();
                }
                let start = Instant::now();
                let r = sim.step_to(h);
                let dt = start.elapsed().as_secs_f64();
                let o = sim.outputs();
                let finite = OutputId::ALL.iter().all(|id| id.get(&o).is_finite());
                let what = match r {
                    Ok(()) => format!("ok, finite {finite}"),
                    Err(e) => format!("ERR {e}"),
                };
                rows.push((dt, format!("{} {name} h={h}: {what}", sc.model_identifier)));
            }
        }
    }
    rows.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap());
    let n = rows.len();
    let errs = rows.iter().filter(|r| r.1.contains("ERR")).count();
    println!("{n} calls, {errs} errors; slowest:");
    for (dt, r) in rows.iter().take(25) {
        println!("{:9.3} ms  {r}", dt * 1e3);
    }
    println!("errors:");
    for (_, r) in rows
        .iter()
        .filter(|r| r.1.contains("ERR") || r.1.contains("finite false"))
    {
        println!("  {r}");
    }
}
