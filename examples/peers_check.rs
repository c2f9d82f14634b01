//! Smoke test of the Rust peer integrators (`examples/report/peers.rs`): every peer on the
//! paper-longitudinal case (Dahl, velocity drive, harmonic support) for 0.02 s at tol 1e-6,
//! beside vibrofric's own simulator.
//!
//! `cargo run --release --example peers_check [-- TOL [T_END [K_T]]]`
//! Prints each peer's `F_mean` against vibrofric's at tolerance 1e-10, and its largest `F_Fx`
//! difference over the samples, relative to `F_C`.

#[path = "report/peers.rs"]
mod peers;

#[path = "../tests/support/configs.rs"]
mod configs;

use cpu_time::ThreadTime;
use peers::RustPeer;
use vibrofric::model::{build, InputId, Law};
use vibrofric::table::Params;

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
    let clock = ThreadTime::now();
    let n_samples = (t_end / sample_dt).round() as usize + 1;
    let mut samples = vec![sim.outputs().f_fx];
    for k in 1..n_samples {
        sim.step_to((k as f64 * sample_dt).min(t_end))
            .expect("vibrofric step_to");
        samples.push(sim.outputs().f_fx);
    }
    let reference = sim.outputs().f_mean;
    println!(
        "{:<32} {:>22} {:>10} {:>9} {:>10} {:>10}",
        "integrator", "F_mean [N]", "rel. diff", "cpu [s]", "steps", "F_Fx/F_C"
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
        let ffx = r
            .samples
            .iter()
            .zip(&samples)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
            / f_scale;
        if std::env::var_os("PEERS_CHECK_WORST").is_some() {
            let mut errs: Vec<(f64, usize)> = r
                .samples
                .iter()
                .zip(&samples)
                .enumerate()
                .map(|(k, (a, b))| ((a - b).abs(), k))
                .collect();
            errs.sort_by(|a, b| b.0.total_cmp(&a.0));
            for &(e, k) in errs.iter().take(5) {
                println!(
                    "  worst: t = {:.6e}: peer {:.6e}, vibrofric {:.6e} ({e:.1e})",
                    k as f64 * sample_dt,
                    r.samples[k],
                    samples[k]
                );
            }
        }
        match &r.status {
            Ok(()) => println!(
                "{:<32} {:>22.15e} {:>10.2e} {:>9.4} {:>10} {:>10.1e}  ({} samples of {n_samples}, {} reversals)",
                peer.name(),
                r.f_mean,
                (r.f_mean - reference).abs() / reference.abs(),
                r.cpu_s,
                r.steps,
                ffx,
                r.samples.len(),
                r.reversals,
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
