//! CPU time of a string of contacts against its number of sections: a drill string's sections
//! (10 m of 5-inch pipe, 267 kg, EA/L = 7.1e7 N/m, on the wall with 2.28 kN at mu = 0.3, LuGre
//! at k_t = 1e8 with F_S = 1.3·F_C), the top fed at 5 cm/s through a spring–dashpot, the bit a
//! spring–dashpot on the rock, an oscillation tool of 20 kN at 15 Hz at 3/4 of the length, in
//! communication steps of 1 ms at tolerance 1e-6, from rest.
//!
//! `cargo run --release --example string_bench [-- SECONDS [N,N,...] [TOL] [OPTION...]]`
//! with the options `normal-input` (the normal forces as held inputs, as in the `DrillString`
//! scene), `k_t=VALUE` (the contact stiffness, N/m, instead of the pipe's),
//! `law=dahl|dupont|lugre` (instead of LuGre), `support=HZ` (the wall vibrating along the
//! string with an amplitude of 1 µm at that frequency) and `tool-rate` (the tool's force with
//! its slope at each step's start as the input derivative, as `drill_string/coupling_bench.py`
//! gives it, instead of held) prints, per N: CPU time per simulated
//! second, per section and step, the string's steps, the sections' own steps (multirate), and
//! the weight on bit. An option it does not know stops it with its name.

use cpu_time::ThreadTime;
#[path = "../tests/support/configs.rs"]
mod configs;

use configs::drill_pipe;
use vibrofric::model::string::{build_string, StringConfig, StringInput};
use vibrofric::table::Law;

fn main() {
    let seconds: f64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1.0);
    let sizes: Vec<usize> = std::env::args()
        .nth(2)
        .map(|a| a.split(',').filter_map(|v| v.parse().ok()).collect())
        .unwrap_or_else(|| vec![1, 10, 20, 100, 1000]);
    let h = 1e-3;
    let tol: f64 = std::env::args()
        .nth(3)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1e-6);
    let options: Vec<String> = std::env::args().skip(4).collect();
    let option = |key: &str| {
        options
            .iter()
            .find_map(|a| a.strip_prefix(key)?.strip_prefix('=').map(str::to_owned))
    };
    if let Some(bad) = options.iter().find(|a| {
        *a != "normal-input"
            && *a != "tool-rate"
            && !["k_t=", "law=", "support="]
                .iter()
                .any(|p| a.starts_with(p))
    }) {
        panic!(
            "option {bad}: not normal-input, tool-rate, k_t=VALUE, law=dahl|dupont|lugre or support=HZ"
        );
    }
    let normal_input = options.iter().any(|a| a == "normal-input");
    let tool_rate = options.iter().any(|a| a == "tool-rate");
    let k_t: Option<f64> = option("k_t").map(|v| v.parse().expect("k_t=VALUE"));
    let support: Option<f64> = option("support").map(|v| v.parse().expect("support=HZ"));
    let law = match option("law").as_deref() {
        None | Some("lugre") => Law::LuGre,
        Some("dahl") => Law::Dahl,
        Some("dupont") => Law::Dupont,
        Some(other) => panic!("law={other}: not dahl, dupont or lugre"),
    };
    println!(
        "string of {law:?} sections (k_t {:e} N/m{}), tool 20 kN at 15 Hz, {seconds} s in steps of {h} s, tol {tol:e}",
        k_t.unwrap_or(drill_pipe(1).shared.k_t),
        support.map_or(String::new(), |f| format!(", the wall at 1 µm and {f} Hz"))
    );
    println!(
        "{:>6} {:>12} {:>14} {:>12} {:>10} {:>16} {:>12}",
        "N", "CPU s / s", "µs / sec·step", "steps / s", "rejected", "sec. steps / s", "WOB (N)"
    );
    for &n in &sizes {
        let mut p = drill_pipe(n);
        if let Some(k_t) = k_t {
            p.shared.k_t = k_t;
        }
        if let Some(f) = support {
            p.shared.u0 = 1e-6;
            p.shared.f = f;
        }
        let config = StringConfig {
            law,
            harmonic: support.is_some(),
            normal_input,
        };
        let mut sim = build_string(config, p, 0.0, tol).unwrap();
        sim.set_input(StringInput::VTop, 0.05).unwrap();
        let steps = (seconds / h).round() as usize;
        let tool = 3 * n / 4;
        let clock = ThreadTime::now();
        let mut wob = 0.0;
        for c in 0..steps {
            let t = c as f64 * h;
            let w = std::f64::consts::TAU * 15.0;
            sim.set_input(StringInput::Fd(tool), 2e4 * (w * t).sin())
                .unwrap();
            if tool_rate {
                sim.set_input_derivative(StringInput::Fd(tool), 2e4 * w * (w * t).cos())
                    .unwrap();
            }
            sim.step_to((c + 1) as f64 * h).unwrap();
            wob = sim.outputs().f_bottom_step;
        }
        let cpu = clock.elapsed().as_secs_f64();
        let st = sim.stats();
        println!(
            "{:>6} {:>12.4} {:>14.3} {:>12.0} {:>10} {:>16.0} {:>12.1}",
            n,
            cpu / seconds,
            cpu / (n as f64 * steps as f64) * 1e6,
            st.steps as f64 / seconds,
            st.rejected,
            sim.section_steps() as f64 / seconds,
            wob
        );
    }
}
