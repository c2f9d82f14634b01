//! Run time per simulated vibration period of every standard scene, and of pairs of
//! configurations that differ in one choice only, to show what leaving things out saves.
//! Single thread; the median of repeated runs of 0.1 s (200 periods at 2 kHz) at tolerance 1e-6.
//! Then, for the scenes whose body moves: the largest `F_Fx` error at the communication points
//! against a tolerance-1e-10 run, and the cost at `k_t` = 1e12 against 1e8; and the default
//! contact (VibratingContact) over 1 s at tolerances 1e-4 … 1e-10 against a 1e-12 run.
//!
//! cargo run --release --example scene_bench

#[path = "../tests/support/configs.rs"]
mod configs;
#[path = "../tests/support/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use std::time::Instant;

use vibrofric::model::{Config, Drive, Inputs, Integrator, Law, Motion, Setup, StepStats};
use vibrofric::table::Params;

const RUNS: usize = 9;
const T_END: f64 = 0.1;
/// Nominal period for scenes without a harmonic source (the default 2 kHz).
const NOMINAL_PERIOD: f64 = 5e-4;

/// Median wall time of a run to `T_END` with communication step 1e-3 s, and its work counters.
fn time_run(config: Config, params: Params, inputs: Inputs) -> (f64, StepStats, Integrator) {
    let (t, stats, path, _) = timed(config, params, inputs, 1e-6, T_END, RUNS);
    (t, stats, path)
}

/// Median wall time of `runs` runs to `t_end` at tolerance `tol` in communication steps of
/// 1 ms, the work counters, the path and `F_Fx` at every communication point.
fn timed(
    config: Config,
    params: Params,
    inputs: Inputs,
    tol: f64,
    t_end: f64,
    runs: usize,
) -> (f64, StepStats, Integrator, Vec<f64>) {
    let mut times = Vec::with_capacity(runs);
    let mut stats = StepStats::default();
    let mut path = Integrator::Radau;
    let mut f_fx = vec![];
    let n = (t_end / 1e-3).round() as usize;
    for _ in 0..runs {
        f_fx.clear();
        let start = Instant::now();
        let mut sim = Setup::new(config, params)
            .inputs(inputs)
            .tolerance(tol)
            .build()
            .unwrap();
        for k in 1..=n {
            sim.step_to(k as f64 * 1e-3).unwrap();
            f_fx.push(sim.outputs().f_fx);
        }
        times.push(start.elapsed().as_secs_f64());
        stats = sim.stats();
        path = sim.integrator();
    }
    times.sort_by(|a, b| a.partial_cmp(b).unwrap());
    (times[runs / 2], stats, path, f_fx)
}

/// The largest difference of two series, relative to `scale`.
fn max_err(a: &[f64], b: &[f64], scale: f64) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / scale)
        .fold(0.0, f64::max)
}

fn row(name: &str, config: Config, params: Params, inputs: Inputs) -> f64 {
    let period = if config.harmonic && params.f > 0.0 {
        1.0 / params.f
    } else {
        NOMINAL_PERIOD
    };
    let periods = T_END / period;
    let (t, s, path) = time_run(config, params, inputs);
    let per = t / periods * 1e6;
    println!(
        "| {name} | {path:?} | {per:.2} | {:.1} | {:.1} |",
        s.steps as f64 / periods,
        s.rhs_evals as f64 / periods
    );
    per
}

fn main() {
    println!("Standard scenes (tolerance 1e-6, communication step 1 ms, median of {RUNS} runs of 0.1 s)\n");
    println!("| scene | path | µs per period | steps per period | rhs evaluations per period |");
    println!("|---|---|---|---|---|");
    for (_, scene) in scenes::standard_scenes() {
        row(
            &scene.model_identifier,
            scene.config,
            scene.start,
            scene.inputs,
        );
    }

    println!("\nScenes whose body moves (tolerance 1e-6, 0.1 s): F_Fx error against a tolerance-1e-10 run on the same path, and the cost at k_t = 1e12 against 1e8\n");
    println!("| scene | path | µs per period | steps per period | max F_Fx error / F_C | µs per period at k_t 1e12 | 1e12 / 1e8 |");
    println!("|---|---|---|---|---|---|---|");
    for (_, scene) in scenes::standard_scenes() {
        if scene.config.drive == Drive::Velocity {
            continue;
        }
        let (c, start, inputs) = (scene.config, scene.start, scene.inputs);
        let periods = T_END * start.f;
        let (t, st, path, f) = timed(c, start, inputs, 1e-6, T_END, RUNS);
        let (_, _, _, reference) = timed(c, start, inputs, 1e-10, T_END, 1);
        let stiff = Params { k_t: 1e12, ..start };
        let (t12, _, _, _) = timed(c, stiff, inputs, 1e-6, T_END, RUNS);
        println!(
            "| {} | {path:?} | {:.2} | {:.1} | {:.1e} | {:.2} | {:.2} |",
            scene.model_identifier,
            t / periods * 1e6,
            st.steps as f64 / periods,
            max_err(&f, &reference, start.f_c()),
            t12 / periods * 1e6,
            t12 / t
        );
    }

    println!("\nVibratingContact, 1 s at 2 kHz, F_Fx at every 1 ms against tolerance 1e-12 (explicit path) or Radau at its tolerance\n");
    println!("| path | tolerance | µs per period | steps per period | max F_Fx error / F_C |");
    println!("|---|---|---|---|---|");
    let scene = scenes::scene("contact.toml");
    let (c, start, inputs) = (scene.config, scene.start, scene.inputs);
    let (_, _, _, reference) = timed(c, start, inputs, 1e-12, 1.0, 1);
    let periods = start.f;
    for tol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-10] {
        let (t, st, path, f) = timed(c, start, inputs, tol, 1.0, 3);
        println!(
            "| {path:?} | {tol:.0e} | {:.2} | {:.1} | {:.1e} |",
            t / periods * 1e6,
            st.steps as f64 / periods,
            max_err(&f, &reference, start.f_c())
        );
    }

    println!("\nWhat leaving things out saves: pairs that differ in one choice (velocity v_d = 1 mm/s or force F_d = 8 N, defaults otherwise)\n");
    println!(
        "| configuration | path | µs per period | steps per period | rhs evaluations per period |"
    );
    println!("|---|---|---|---|---|");
    let base = configs::long_velocity(Law::Dahl);
    let p = Params::default();
    let vel = Inputs {
        v_d: 1e-3,
        ..Inputs::default()
    };
    let force = Inputs {
        f_d: 8.0,
        ..Inputs::default()
    };
    let a = row("Dahl, longitudinal, velocity", base, p, vel);
    let b = row(
        "Dahl, planar (angle 0: same motion), velocity guided",
        Config {
            motion: Motion::Planar,
            ..base
        },
        p,
        vel,
    );
    println!("| planar / longitudinal | | {:.2}× | | |", b / a);
    let c = row(
        "Dahl, longitudinal, force",
        Config {
            drive: Drive::Force,
            ..base
        },
        p,
        force,
    );
    println!("| force / velocity drive | | {:.2}× | | |", c / a);
    let d = row(
        "LuGre, longitudinal, velocity",
        Config {
            law: Law::LuGre,
            ..base
        },
        p,
        vel,
    );
    println!("| LuGre / Dahl | | {:.2}× | | |", d / a);
    let e = row(
        "Dahl, planar, force, harmonic + input support",
        Config {
            motion: Motion::Planar,
            drive: Drive::Force,
            input_support: true,
            normal_input: false,
            ..base
        },
        p,
        force,
    );
    println!(
        "| default contact / paper-longitudinal | | {:.2}× | | |",
        e / a
    );
}
