//! Issue-2 measurements: F_mean error against the exact solution and single-core run time of
//! the paper-longitudinal configuration (Dahl, velocity drive, defaults, 1 s).
//!
//! cargo run --release --example core_bench

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Instant;
use vibrofric::model::{build, Law};
use vibrofric::physics::Params;

fn run(params: Params, tol: f64) -> (f64, f64, vibrofric::model::StepStats) {
    let config = common::configs::long_velocity(Law::Dahl);
    let mut best = f64::INFINITY;
    let mut out = (0.0, Default::default());
    for _ in 0..5 {
        let start = Instant::now();
        let mut sim = build(config, params, 0.0, tol).unwrap();
        sim.set_input(vibrofric::model::InputId::VD, 1e-3).unwrap();
        sim.step_to(1.0).unwrap();
        let el = start.elapsed().as_secs_f64();
        best = best.min(el);
        out = (sim.outputs().f_mean, sim.stats());
    }
    (out.0, best, out.1)
}

fn main() {
    let p = Params::default();
    let exact = common::ExactDahl::new(&p, 1e-3).f_mean_after_periods(2000);
    println!(
        "exact F_mean = {exact:.15} N  (F_mean/F_C = {:.12})",
        exact / p.f_c()
    );
    println!(
        "{:>8} {:>12} {:>10} {:>8} {:>8} {:>8} {:>8}",
        "tol", "rel.err", "time[ms]", "steps", "rejct", "events", "jacs"
    );
    for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let (fm, t, st) = run(p, tol);
        println!(
            "{tol:>8.0e} {:>12.3e} {:>10.3} {:>8} {:>8} {:>8} {:>8}",
            ((fm - exact) / exact).abs(),
            t * 1e3,
            st.steps,
            st.rejected,
            st.events,
            st.jacobians
        );
    }
    for k_t in [1e8, 1e10, 1e12] {
        let mut q = p;
        q.k_t = k_t;
        let ex = common::ExactDahl::new(&q, 1e-3).f_mean_after_periods(2000);
        let (fm, t, st) = run(q, 1e-6);
        println!(
            "k_t={k_t:.0e} tol=1e-6: rel.err {:.3e} time {:.3} ms steps {} rejected {} events {}",
            ((fm - ex) / ex).abs(),
            t * 1e3,
            st.steps,
            st.rejected,
            st.events
        );
    }
}
