//! Smoke test of the Rust peer integrators (`examples/report/peers.rs`): every peer on the
//! paper-longitudinal case (Dahl, velocity drive, harmonic support) for 0.02 s at tol 1e-6,
//! beside vibrofric's own simulator.
//!
//! `cargo run --release --example peers_check [-- TOL [T_END [K_T]]]`

#[path = "report/peers.rs"]
mod peers;

#[path = "../tests/support/configs.rs"]
mod configs;

use peers::RustPeer;
use std::time::Instant;
use vibrofric::model::{build, InputId, Law};
use vibrofric::physics::Params;

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("numeric arguments: TOL T_END K_T"))
        .collect();
    let tol = args.first().copied().unwrap_or(1e-6);
    let t_end = args.get(1).copied().unwrap_or(0.02);
    let mut params = Params::default();
    if let Some(&k_t) = args.get(2) {
        params.k_t = k_t;
    }
    let cfg = configs::long_velocity(Law::Dahl);
    let period = 1.0 / params.f;
    let sample_dt = period / 20.0;
    let f_scale = params.mu * params.f_n;

    let mut sim = build(cfg, params, 0.0, 1e-10).expect("build");
    sim.set_input(InputId::VD, 1e-3).expect("v_d");
    let ode = sim.ode();
    let clock = Instant::now();
    sim.step_to(t_end).expect("vibrofric step_to");
    let reference = sim.outputs().f_mean;
    println!(
        "{:<32} {:>22} {:>10} {:>9} {:>10}",
        "integrator", "F_mean [N]", "rel. diff", "time [s]", "steps"
    );
    println!(
        "{:<32} {:>22.15e} {:>10} {:>9.4} {:>10}",
        "vibrofric (tol 1e-10)",
        reference,
        "",
        clock.elapsed().as_secs_f64(),
        sim.stats().steps
    );
    for peer in RustPeer::ALL {
        if params.k_t > 1e9 && !peer.stiff_capable() {
            continue;
        }
        let r = peers::run(peer, &*ode, t_end, sample_dt, period, f_scale, tol, 20.0);
        let n_expected = (t_end / sample_dt).round() as usize + 1;
        match &r.status {
            Ok(()) => println!(
                "{:<32} {:>22.15e} {:>10.2e} {:>9.4} {:>10}  ({} samples of {n_expected})",
                peer.name(),
                r.f_mean,
                (r.f_mean - reference).abs() / reference.abs(),
                r.cpu_s,
                r.steps,
                r.samples.len(),
            ),
            Err(e) => println!(
                "{:<32} failed after {:.4} s, {} steps: {e}",
                peer.name(),
                r.cpu_s,
                r.steps
            ),
        }
    }
}
