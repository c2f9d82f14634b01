//! The scenes whose body moves, on the path each takes, in CPU time (this process's user and
//! system time from /proc/self/stat, in clock ticks: runs repeat until 0.5 s of it add up, so
//! that other work on a shared machine counts little):
//! per vibration period at tolerances 1e-6 and 1e-8 over `T` seconds in communication steps of
//! 1 ms, the largest `F_Fx` error at the communication points against Radau IIA at 1e-12, and
//! the cost at `k_t` = 1e12 against 1e8 (tolerance 1e-6, 0.1 s).
//!
//! cargo run --release --example explicit_bench [T [NAME]]   (T = 1 by default; only the
//! scene NAME)

use std::path::Path;

use vibrofric::description::scene::Scene;
use vibrofric::model::{build, build_on, Drive, InputId, Path as SolverPath};
use vibrofric::physics::Params;

/// CPU time of this process in seconds (Linux, 100 ticks per second); wall time elsewhere.
fn cpu() -> f64 {
    std::fs::read_to_string("/proc/self/stat")
        .ok()
        .and_then(|s| {
            // The fields after the command's closing parenthesis: utime and stime are the
            // 12th and 13th.
            let rest = &s[s.rfind(')')? + 2..];
            let f: Vec<f64> = rest
                .split_whitespace()
                .skip(11)
                .take(2)
                .filter_map(|x| x.parse().ok())
                .collect();
            (f.len() == 2).then(|| (f[0] + f[1]) * 0.01)
        })
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .unwrap()
                .as_secs_f64()
        })
}

/// Mean CPU time of at least `runs` runs to `t_end` (more until 0.5 s add up), the path,
/// `F_Fx` at every 1 ms and steps.
fn run(
    scene: &Scene,
    params: Params,
    tol: f64,
    t_end: f64,
    path: Option<SolverPath>,
    runs: usize,
) -> (f64, SolverPath, Vec<f64>, u64) {
    let mut out = (SolverPath::Radau, vec![], 0);
    let n = (t_end / 1e-3).round() as usize;
    let start = cpu();
    let mut done = 0;
    while done < runs.max(1) || (runs > 0 && cpu() - start < 0.5) {
        done += 1;
        let mut sim = match path {
            Some(p) => build_on(scene.config, params, 0.0, tol, p),
            None => build(scene.config, params, 0.0, tol),
        }
        .unwrap();
        for id in InputId::ALL {
            if id.present(&scene.config) {
                sim.set_input(id, id.get(&scene.inputs)).unwrap();
            }
        }
        let mut f = Vec::with_capacity(n);
        for k in 1..=n {
            sim.step_to(k as f64 * 1e-3).unwrap();
            f.push(sim.outputs().f_fx);
        }
        out = (sim.path(), f, sim.stats().steps);
    }
    ((cpu() - start) / done as f64, out.0, out.1, out.2)
}

fn main() {
    let t_end: f64 = std::env::args()
        .nth(1)
        .map_or(1.0, |a| a.parse().expect("T in seconds"));
    let only = std::env::args().nth(2).unwrap_or_default();
    println!("| scene | path | tol | µs/period | steps/period | max F_Fx error / F_C |");
    println!("|---|---|---|---|---|---|");
    let mut ratios = vec![];
    let mut files: Vec<_> = std::fs::read_dir("scenes")
        .expect("run from the repository root")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    for file in files {
        let scene = Scene::load(Path::new(&file)).unwrap();
        if scene.config.drive == Drive::Velocity
            || (!only.is_empty() && scene.model_identifier != only)
        {
            continue;
        }
        let p = scene.start;
        let period = if scene.config.harmonic {
            1.0 / p.f
        } else {
            5e-4
        };
        let periods = t_end / period;
        let (_, _, reference, _) = run(&scene, p, 1e-12, t_end, Some(SolverPath::Radau), 0);
        for tol in [1e-6, 1e-8] {
            let (t, path, f, steps) = run(&scene, p, tol, t_end, None, 1);
            let err = f
                .iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
                / p.f_c();
            println!(
                "| {} | {path:?} | {tol:.0e} | {:.2} | {:.1} | {err:.1e} |",
                scene.model_identifier,
                t / periods * 1e6,
                steps as f64 / periods
            );
        }
        let cost = |k_t: f64| {
            let q = Params { k_t, ..p };
            let mut sim = build(scene.config, q, 0.0, 1e-6).unwrap();
            for id in InputId::ALL {
                if id.present(&scene.config) {
                    sim.set_input(id, id.get(&scene.inputs)).unwrap();
                }
            }
            for k in 1..=100 {
                sim.step_to(k as f64 * 1e-3).unwrap();
            }
            let s = sim.stats();
            let per = 0.1 / period;
            eprintln!(
                "{} k_t {k_t:e}: steps {:.1} rejected {:.1} events {:.1} evals {:.1} per period",
                scene.model_identifier,
                s.steps as f64 / per,
                s.rejected as f64 / per,
                s.events as f64 / per,
                s.rhs_evals as f64 / per
            );
            run(&scene, q, 1e-6, 0.1, None, 1).0
        };
        ratios.push((scene.model_identifier.clone(), cost(1e12) / cost(1e8)));
    }
    println!("\n| scene | CPU time at k_t 1e12 / 1e8 (tol 1e-6, 0.1 s) |\n|---|---|");
    for (name, r) in ratios {
        println!("| {name} | {r:.2} |");
    }
}
