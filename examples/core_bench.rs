//! F_mean error against the exact solution and single-core run time of the paper-longitudinal
//! configuration (Dahl, velocity drive, defaults, 1 s = 2000 periods), on each path:
//! - closed form, one communication step of 1 s (windows skipped in O(1));
//! - closed form, stepped period by period (5e-4 s: every window integrated);
//! - Radau IIA alone, one step of 1 s (the general integrator the closed form replaces).
//!
//! cargo run --release --example core_bench

#[path = "../tests/support/configs.rs"]
mod configs;
#[path = "../tests/support/reference.rs"]
mod reference;

use std::time::Instant;
use vibrofric::model::{build_on, InputId, Integrator, Law, StepStats};
use vibrofric::table::Params;

/// Best of 5 runs: (F_mean, seconds, work).
fn run(params: Params, tol: f64, path: Integrator, step: f64) -> (f64, f64, StepStats) {
    let config = configs::long_velocity(Law::Dahl);
    let mut best = f64::INFINITY;
    let mut out = (0.0, Default::default());
    let n = (1.0 / step).round() as usize;
    for _ in 0..5 {
        let start = Instant::now();
        let mut sim = build_on(config, params, 0.0, tol, path == Integrator::Radau).unwrap();
        sim.set_input(InputId::VD, 1e-3).unwrap();
        for k in 1..=n {
            sim.step_to(k as f64 * step).unwrap();
        }
        best = best.min(start.elapsed().as_secs_f64());
        out = (sim.outputs().f_mean, sim.stats());
    }
    (out.0, best, out.1)
}

fn main() {
    let p = Params::default();
    let exact = reference::ExactDahl::new(&p, 1e-3).f_mean_after_periods(2000);
    println!(
        "exact F_mean = {exact:.15} N  (F_mean/F_C = {:.12})",
        exact / p.f_c()
    );
    let modes = [
        ("closed form, 1 step", Integrator::ClosedForm, 1.0),
        ("closed form, per period", Integrator::ClosedForm, 5e-4),
        ("Radau, 1 step", Integrator::Radau, 1.0),
    ];
    println!(
        "{:>24} {:>8} {:>12} {:>10} {:>8} {:>8} {:>8}",
        "path", "tol", "rel.err", "time[ms]", "steps", "events", "evals"
    );
    for (name, path, step) in modes {
        for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
            let (fm, t, st) = run(p, tol, path, step);
            println!(
                "{name:>24} {tol:>8.0e} {:>12.3e} {:>10.3} {:>8} {:>8} {:>8}",
                ((fm - exact) / exact).abs(),
                t * 1e3,
                st.steps,
                st.events,
                st.rhs_evals
            );
        }
    }
    for (name, path, step) in modes {
        for k_t in [1e8, 1e10, 1e12] {
            let mut q = p;
            q.k_t = k_t;
            let ex = reference::ExactDahl::new(&q, 1e-3).f_mean_after_periods(2000);
            let (fm, t, st) = run(q, 1e-6, path, step);
            println!(
                "{name}: k_t={k_t:.0e} tol=1e-6: rel.err {:.3e} time {:.3} ms steps {} events {}",
                ((fm - ex) / ex).abs(),
                t * 1e3,
                st.steps,
                st.events
            );
        }
    }
}
