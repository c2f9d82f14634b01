//! CPU time per vibration period of one standard scene at one setting, for comparing two
//! builds of the library run after each other (the minimum of REPS runs, so that a loaded
//! machine biases it least), with the path it takes and its steps.
//!
//! `cargo run --release --example period_bench -- FILE TOL KT T REPS`: the scene `scenes/FILE`,
//! tolerance TOL, contact stiffness KT (0 keeps the scene's), T seconds in communication steps
//! of 1 ms. REPS 0 builds the simulator only (to subtract the start-up's instructions when
//! counting them with valgrind).

#[path = "../tests/support/scenes.rs"]
#[allow(dead_code)]
mod scenes;

use cpu_time::ProcessTime;
use vibrofric::model::Setup;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let file = &a[1];
    let tol: f64 = a[2].parse().unwrap();
    let kt: f64 = a[3].parse().unwrap();
    let t_end: f64 = a[4].parse().unwrap();
    let reps: usize = a[5].parse().unwrap();
    let scene = scenes::scene(file);
    let mut p = scene.start;
    if kt > 0.0 {
        p.k_t = kt;
    }
    let period = if scene.config.harmonic {
        1.0 / p.f
    } else {
        5e-4
    };
    let n = (t_end / 1e-3).round() as usize;
    let mut best = f64::INFINITY;
    let mut info = String::new();
    let mut sum = 0.0;
    let build = || {
        Setup::new(scene.config, p)
            .inputs(scene.inputs)
            .tolerance(tol)
            .build()
            .unwrap()
    };
    if reps == 0 {
        println!("built {:?}", build().integrator());
        return;
    }
    for _ in 0..reps {
        let start = ProcessTime::now();
        let mut sim = build();
        for k in 1..=n {
            sim.step_to(k as f64 * 1e-3).unwrap();
            sum += sim.outputs().f_fx;
        }
        let c = start.elapsed().as_secs_f64();
        best = best.min(c);
        info = format!("{:?} steps {}", sim.integrator(), sim.stats().steps);
    }
    println!(
        "{file} tol {tol:e} kt {kt:e}: {:.4} us/period min of {reps}; {info} ({sum:e})",
        best / (t_end / period) * 1e6
    );
}
