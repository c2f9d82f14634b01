//! The exponential path (PaperTransverseGuided: velocity drive along x, support vibrating across
//! it, body guided) in CPU time: per vibration period at each tolerance, in communication steps
//! of `H` (1e-4 s by default: the work–precision report's sample spacing), with the largest
//! `F_Fx` error at the communication points (over `F_C`) and the relative `F_mean` error at the
//! end, both against Radau IIA at tolerance 1e-12 on the same grid (an independent integrator).
//! Runs are repeated until 0.3 s of CPU time add up (the thread's time, so that other work on a
//! shared machine counts little).
//!
//! cargo run --release --example guided_bench [H [T [K_T [TOL]]]]   (H = 1e-4 s, T = 0.1 s,
//! K_T = the scene's contact stiffness, TOL: only this tolerance)

#[path = "../tests/support/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use cpu_time::ThreadTime;
use vibrofric::model::{canonical_time, Integrator, Setup};
use vibrofric::table::Params;

/// `F_Fx` at every communication point, `F_mean` at the end, accepted and rejected steps,
/// integrator, CPU seconds per run.
fn run(
    scene: &vibrofric::description::Scene,
    params: Params,
    tol: f64,
    h: f64,
    t_end: f64,
    path: Option<Integrator>,
) -> (Vec<f64>, f64, (u64, u64), Integrator, f64) {
    let n = (t_end / h).round() as usize;
    let start = ThreadTime::now();
    let mut done = 0;
    loop {
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
            sim.step_to(canonical_time(k as f64 * h)).unwrap();
            f.push(sim.outputs().f_fx);
        }
        let secs = start.elapsed().as_secs_f64();
        if path.is_some() || secs >= 0.3 {
            let out = sim.outputs();
            return (
                f,
                out.f_mean,
                (sim.stats().steps, sim.stats().rejected),
                sim.integrator(),
                secs / done as f64,
            );
        }
    }
}

fn main() {
    let arg = |i: usize, default: f64| {
        std::env::args()
            .nth(i)
            .map_or(default, |a| a.parse().expect("a number"))
    };
    let h = arg(1, 1e-4);
    let t_end = arg(2, 0.1);
    let scene = scenes::scene("paper-transverse-guided.toml");
    let mut params = scene.start;
    params.k_t = arg(3, params.k_t);
    let period = 1.0 / params.f;
    let periods = t_end / period;
    let f_c = params.f_c();
    let (f_ref, mean_ref, ..) = run(&scene, params, 1e-12, h, t_end, Some(Integrator::Radau));
    println!(
        "PaperTransverseGuided, k_t = {:.0e}, {t_end} s = {periods} periods, communication step \
         {h:e} s; reference Radau IIA at 1e-12",
        params.k_t
    );
    println!(
        "| tol | path | µs/period | steps/period | rejected/period | F_mean rel. error | \
         max F_Fx error / F_C |"
    );
    println!("|---|---|---|---|---|---|---|");
    let tols = match std::env::args().nth(4) {
        Some(t) => vec![t.parse().expect("a tolerance")],
        None => vec![1e-3, 1e-4, 1e-6, 1e-8, 1e-10],
    };
    for tol in tols {
        let (f, mean, (steps, rejected), path, secs) = run(&scene, params, tol, h, t_end, None);
        let e_ffx = f
            .iter()
            .zip(&f_ref)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
            / f_c;
        println!(
            "| {tol:.0e} | {path:?} | {:.2} | {:.2} | {:.2} | {:.1e} | {:.1e} |",
            secs / periods * 1e6,
            steps as f64 / periods,
            rejected as f64 / periods,
            ((mean - mean_ref) / mean_ref).abs(),
            e_ffx
        );
    }
}
