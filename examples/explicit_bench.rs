//! The scenes whose body moves (force and spring drives, velocity drives with the lateral
//! motion free), on the path each takes, in CPU time (this process's, with
//! runs repeated until 0.5 s of it add up, so that other work on a shared machine counts
//! little):
//! per vibration period at tolerances 1e-6 and 1e-8 over `T` seconds in communication steps of
//! 1 ms, the largest `F_Fx` error at the communication points against Radau IIA at 1e-12, and
//! the cost at `k_t` = 1e12 against 1e8 (tolerance 1e-6, over the first 0.1 s from rest and
//! over the next 0.1 s).
//!
//! cargo run --release --example explicit_bench [T [NAME]]   (T = 1 by default; only the
//! scene NAME; with `KT=<k_t>` in the environment the table's rows at that stiffness)

#[path = "../tests/support/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use cpu_time::ProcessTime;
use vibrofric::description::scene::Scene;
use vibrofric::model::{Drive, Integrator, Lateral, Setup};
use vibrofric::table::Params;

/// CPU time of this process in seconds.
fn cpu() -> f64 {
    ProcessTime::now().as_duration().as_secs_f64()
}

/// Mean CPU time of at least `runs` runs to `t_end` (more until 0.5 s add up), the path,
/// `F_Fx` at every 1 ms and steps.
fn run(
    scene: &Scene,
    params: Params,
    tol: f64,
    t_end: f64,
    path: Option<Integrator>,
    runs: usize,
) -> (f64, Integrator, Vec<f64>, u64) {
    let mut out = (Integrator::Radau, vec![], 0);
    let n = (t_end / 1e-3).round() as usize;
    let start = cpu();
    let mut done = 0;
    while done < runs.max(1) || (runs > 0 && cpu() - start < 0.5) {
        done += 1;
        let setup = Setup::new(scene.config, params)
            .inputs(scene.inputs)
            .tolerance(tol);
        let mut sim = match path {
            Some(p) => setup.force_radau(p == Integrator::Radau),
            None => setup,
        }
        .build()
        .unwrap();
        let mut f = Vec::with_capacity(n);
        for k in 1..=n {
            sim.step_to(k as f64 * 1e-3).unwrap();
            f.push(sim.outputs().f_fx);
        }
        out = (sim.integrator(), f, sim.stats().steps);
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
    for (_, scene) in scenes::standard_scenes() {
        // The velocity drives whose body moves: the lateral motion free.
        if (scene.config.drive == Drive::Velocity && scene.config.lateral != Lateral::Free)
            || (!only.is_empty() && scene.model_identifier != only)
        {
            continue;
        }
        // `KT=1e12` in the environment: the table's rows at that contact stiffness.
        let p = match std::env::var("KT").ok().and_then(|v| v.parse().ok()) {
            Some(k_t) => Params { k_t, ..scene.start },
            None => scene.start,
        };
        let period = if scene.config.harmonic {
            1.0 / p.f
        } else {
            5e-4
        };
        let periods = t_end / period;
        let (_, _, reference, _) = run(&scene, p, 1e-12, t_end, Some(Integrator::Radau), 0);
        for tol in [1e-6, 1e-8] {
            let (t, path, f, steps) = run(&scene, p, tol, t_end, None, 1);
            let err = f
                .iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
                / p.f_c();
            println!(
                "| {} | {path:?} | {tol:.0e} | {:.2} | {:.1} | {err:.3e} |",
                scene.model_identifier,
                t / periods * 1e6,
                steps as f64 / periods
            );
        }
        let cost = |k_t: f64| {
            let q = Params { k_t, ..p };
            let mut sim = Setup::new(scene.config, q)
                .inputs(scene.inputs)
                .build()
                .unwrap();
            for k in 1..=100 {
                sim.step_to(k as f64 * 1e-3).unwrap();
            }
            let s = sim.stats();
            let per = 0.1 / period;
            eprintln!(
                "{} k_t {k_t:e}: steps {:.1} ({:.1} on the Coulomb limit) rejected {:.1} events {:.1} evals {:.1} per period",
                scene.model_identifier,
                s.steps as f64 / per,
                s.limit_steps as f64 / per,
                s.rejected as f64 / per,
                s.events as f64 / per,
                s.rhs_evals as f64 / per
            );
            // The next 0.1 s, once the start's transient (a body set moving from rest) has had
            // 0.1 s to settle: from copies of the simulator at 0.1 s.
            let (before, start) = (sim.stats(), cpu());
            let mut done = 0;
            let mut after = before;
            while done < 1 || cpu() - start < 0.5 {
                done += 1;
                let mut copy = sim.clone_box();
                for k in 101..=200 {
                    copy.step_to(k as f64 * 1e-3).unwrap();
                }
                after = copy.stats();
            }
            let settled = (cpu() - start) / done as f64;
            eprintln!(
                "{} k_t {k_t:e}, 0.1 to 0.2 s: steps {:.1} ({:.1} on the Coulomb limit) rejected {:.1} evals {:.1} per period",
                scene.model_identifier,
                (after.steps - before.steps) as f64 / per,
                (after.limit_steps - before.limit_steps) as f64 / per,
                (after.rejected - before.rejected) as f64 / per,
                (after.rhs_evals - before.rhs_evals) as f64 / per
            );
            (run(&scene, q, 1e-6, 0.1, None, 1).0, settled)
        };
        let (stiff, soft) = (cost(1e12), cost(1e8));
        ratios.push((
            scene.model_identifier.clone(),
            stiff.0 / soft.0,
            stiff.1 / soft.1,
        ));
    }
    println!(
        "\n| scene | CPU time at k_t 1e12 / 1e8 (tol 1e-6, 0 to 0.1 s) | the same, 0.1 to 0.2 s |\n|---|---|---|"
    );
    for (name, r, settled) in ratios {
        println!("| {name} | {r:.2} | {settled:.2} |");
    }
}
