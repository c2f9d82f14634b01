//! One moving-body scene on its path, for profiles (valgrind) and accuracy checks: the counts
//! per vibration period (steps, those on the Coulomb limit, rejected attempts, right-hand
//! sides) and, with a reference file, the largest `F_Fx` and `F_Fy` errors at the 1 ms
//! communication points relative to `F_C`.
//!
//! cargo run --release --example planar_probe NAME TOL T [REF]   (in the environment,
//! `KT=<k_t>` replaces the scene's contact stiffness, `ANGLE=<rad>` its vibration's direction
//! in a planar scene, and `RADAU=1` takes Radau IIA whatever the path, for a reference; REF a
//! file of `F_Fx F_Fy` lines, one per 1 ms: compared against where it exists, written where
//! not)

#[path = "../tests/support/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use cpu_time::ProcessTime;
use vibrofric::model::Setup;
use vibrofric::table::Params;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = &args[1];
    let tol: f64 = args[2].parse().expect("TOL");
    let t_end: f64 = args[3].parse().expect("T in seconds");
    let reference = args.get(4);
    let (_, scene) = scenes::standard_scenes()
        .into_iter()
        .find(|(_, s)| s.model_identifier == *name)
        .expect("a standard scene");
    let env = |name: &str| std::env::var(name).ok().and_then(|v| v.parse::<f64>().ok());
    let mut p: Params = scene.start;
    if let Some(k_t) = env("KT") {
        p.k_t = k_t;
    }
    if let Some(angle) = env("ANGLE") {
        p.angle = angle;
    }
    let force_radau = env("RADAU").is_some_and(|r| r != 0.0);
    let n = (t_end / 1e-3).round() as usize;
    let start = ProcessTime::now();
    let mut sim = Setup::new(scene.config, p)
        .inputs(scene.inputs)
        .tolerance(tol)
        .force_radau(force_radau)
        .build()
        .unwrap();
    let mut f = Vec::with_capacity(n);
    for k in 1..=n {
        sim.step_to(k as f64 * 1e-3).unwrap();
        let o = sim.outputs();
        f.push((o.f_fx, o.f_fy));
    }
    let cpu = start.elapsed().as_secs_f64();
    let periods = t_end * p.f;
    let s = sim.stats();
    println!(
        "{name} k_t {:e} tol {tol:e} {:?}: {:.2} µs/period, steps {:.2} (limit {:.2}) rejected {:.2} evals {:.1} per period",
        p.k_t,
        sim.integrator(),
        cpu / periods * 1e6,
        s.steps as f64 / periods,
        s.limit_steps as f64 / periods,
        s.rejected as f64 / periods,
        s.rhs_evals as f64 / periods
    );
    if let Some(path) = reference {
        match std::fs::read_to_string(path) {
            Ok(text) => {
                let (mut ex, mut ey) = (0.0f64, 0.0f64);
                let (mut tx, mut ty) = (0, 0);
                for (k, (line, (fx, fy))) in text.lines().zip(&f).enumerate() {
                    let mut it = line.split_whitespace().map(|w| w.parse::<f64>().unwrap());
                    let (rx, ry) = (it.next().unwrap(), it.next().unwrap());
                    if (fx - rx).abs() > ex {
                        (ex, tx) = ((fx - rx).abs(), k + 1);
                    }
                    if (fy - ry).abs() > ey {
                        (ey, ty) = ((fy - ry).abs(), k + 1);
                    }
                }
                println!(
                    "  against {path}: F_Fx {:.3e} (at {tx} ms), F_Fy {:.3e} (at {ty} ms) of F_C",
                    ex / p.f_c(),
                    ey / p.f_c()
                );
            }
            Err(_) => {
                let text: String = f.iter().map(|(x, y)| format!("{x:e} {y:e}\n")).collect();
                std::fs::write(path, text).unwrap();
                println!("  reference written to {path}");
            }
        }
    }
}
