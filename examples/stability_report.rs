//! Writes `reports/stability.md`: the stiff and extreme-case matrix of issue 5 with, for each
//! row, finiteness, the invariants of `docs/model.md`, the error against the exact solution where it
//! applies, run time, steps and rejected steps. The same cases are asserted in
//! `tests/stability.rs`.
//!
//! cargo run --release --example stability_report

#[path = "../tests/support/configs.rs"]
mod configs;
#[path = "../tests/support/reference.rs"]
mod reference;

use std::fmt::Write as _;
use std::time::Instant;

use configs::{long_velocity, planar_force};
use reference::ExactDahl;
use vibrofric::model::{build, Config, InputId, Law, OutputId};
use vibrofric::table::Params;

const TOL: f64 = 1e-6;

struct Case {
    name: String,
    config: Config,
    params: Params,
    input: (InputId, f64),
    dt: f64,
    n: usize,
    /// Exact F_mean (longitudinal Dahl, velocity drive) after the run, if it applies.
    exact: Option<f64>,
}

/// Longitudinal Dahl at `v_d` over `periods` periods in steps of `dt`, with its exact truth.
fn exact_case(name: String, p: Params, v_d: f64, periods: usize, dt: f64) -> Case {
    let t_end = periods as f64 / p.f;
    let exact = ExactDahl::new(&p, v_d).f_mean_after_periods(periods);
    Case {
        name,
        config: long_velocity(Law::Dahl),
        params: p,
        input: (InputId::VD, v_d),
        dt: t_end / (t_end / dt).round(),
        n: (t_end / dt).round() as usize,
        exact: Some(exact),
    }
}

fn force_case(name: String, law: Law, p: Params) -> Case {
    Case {
        name,
        config: planar_force(law),
        params: p,
        input: (InputId::FD, 8.0),
        dt: 1e-3,
        n: 10,
        exact: None,
    }
}

fn with(f: impl FnOnce(&mut Params)) -> Params {
    let mut p = Params::default();
    f(&mut p);
    p
}

fn cases() -> Vec<Case> {
    let d = Params::default();
    let mut c = vec![];
    for k_t in [1e5, 1e6, 1e8, 1e10, 1e12] {
        let p = with(|p| p.k_t = k_t);
        c.push(exact_case(
            format!("k_t = {k_t:.0e} N/m, longitudinal velocity"),
            p,
            1e-3,
            20,
            1e-3,
        ));
        c.push(force_case(
            format!("k_t = {k_t:.0e} N/m, planar force"),
            Law::Dahl,
            p,
        ));
    }
    for f in [50.0, 2000.0, 20000.0, 40000.0] {
        c.push(exact_case(
            format!("f = {f} Hz"),
            with(|p| p.f = f),
            1e-3,
            40,
            1e-3,
        ));
    }
    c.push(force_case(
        "f = 0, planar force".into(),
        Law::Dahl,
        with(|p| p.f = 0.0),
    ));
    for u0 in [0.0, 2e-9, 2e-7, 2e-6, 2e-5] {
        let p = with(|p| p.u0 = u0);
        if u0 > 0.0 {
            c.push(exact_case(format!("u0 = {u0:.0e} m"), p, 1e-3, 20, 1e-3));
        } else {
            c.push(force_case("u0 = 0, planar force".into(), Law::Dahl, p));
        }
    }
    for v_d in [0.0, 1e-5, 1e-3, 0.1, 1.0] {
        c.push(exact_case(format!("v_d = {v_d} m/s"), d, v_d, 20, 1e-3));
    }
    for (label, psi) in [
        ("psi = 1 − 1e-9", 1.0 - 1e-9),
        ("psi = 1", 1.0),
        ("psi = 1 + 1e-9", 1.0 + 1e-9),
    ] {
        c.push(exact_case(label.into(), d, psi * d.v_a(), 20, 1e-3));
    }
    for m in [1e-3, 1e3] {
        c.push(force_case(
            format!("m = {m} kg, planar force"),
            Law::Dahl,
            with(|p| p.m = m),
        ));
    }
    c.push(force_case(
        "F_N = 0, planar force".into(),
        Law::Dahl,
        with(|p| p.f_n = 0.0),
    ));
    c.push(force_case(
        "mu = 0, planar force".into(),
        Law::Dahl,
        with(|p| p.mu = 0.0),
    ));
    c.push(force_case(
        "LuGre, zeta_t = 1, k_t = 1e10, planar force".into(),
        Law::LuGre,
        with(|p| p.k_t = 1e10),
    ));
    for r_ba in [0.0, 0.999] {
        c.push(force_case(
            format!("Dupont, r_ba = {r_ba}, planar force"),
            Law::Dupont,
            with(|p| p.r_ba = r_ba),
        ));
    }
    for law in [Law::Dahl, Law::Dupont, Law::LuGre] {
        for k_t in [1e8, 1e12] {
            // Held below the Coulomb force (Dupont within its breakaway), without vibration:
            // the body sticks (Dupont's rings on the contact).
            c.push(Case {
                input: (InputId::FD, 2.0),
                n: 1000,
                ..force_case(
                    format!("stuck: {law:?}, F_d = 2 N, u0 = 0, k_t = {k_t:.0e} N/m, 1 s"),
                    law,
                    with(|p| {
                        p.k_t = k_t;
                        p.u0 = 0.0
                    }),
                )
            });
        }
    }
    c.push(exact_case(
        "one step of 2000 periods".into(),
        d,
        1e-3,
        2000,
        1.0,
    ));
    c.push(exact_case(
        "communication steps of 1e-7 s".into(),
        d,
        1e-3,
        4,
        1e-7,
    ));
    c.push(exact_case(
        "1000 s at 2 kHz (2e6 periods), steps of 1 s".into(),
        d,
        1e-3,
        2_000_000,
        1.0,
    ));
    c
}

fn main() {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Stability matrix\n\nGenerated by `cargo run --release --example stability_report` at tolerance {TOL:e}, \
         single thread. Defaults (`docs/model.md`) except the row's change; velocity rows at v_d = 1 mm/s, \
         force rows at F_d = 8 N with harmonic and input support (inputs 0). \"|s|/s_ss\": largest over \
         the communication points (Dahl and Dupont must stay ≤ 1; LuGre's bound is F_S/k_t). \
         \"error\": |F_mean − exact|/F_C against the exact solution of longitudinal Dahl (its own error \
         ~1e-13), where it applies. The same rows are asserted in `tests/stability.rs` (that file runs \
         1000 s at 20 Hz to keep CI short; the row here runs it at 2 kHz).\n"
    );
    let _ = writeln!(
        md,
        "| case | finite | max \\|s\\|/s_ss | min P_diss [W] | error / F_C | run time | steps | rejected |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
    for case in cases() {
        let p = case.params;
        let start = Instant::now();
        let mut sim = build(case.config, p, 0.0, TOL).unwrap();
        sim.set_input(case.input.0, case.input.1).unwrap();
        let s_ss = p.f_c() / p.k_t;
        let (mut finite, mut max_s, mut min_p) = (true, 0.0f64, f64::INFINITY);
        let mut failure = None;
        for k in 1..=case.n {
            if let Err(e) = sim.step_to(k as f64 * case.dt) {
                failure = Some(e.to_string());
                break;
            }
            let o = sim.outputs();
            finite &= OutputId::ALL.iter().all(|id| id.get(&o).is_finite());
            if s_ss > 0.0 {
                max_s = max_s.max(o.s_x.hypot(o.s_y) / s_ss);
            }
            min_p = min_p.min(o.p_diss);
        }
        let elapsed = start.elapsed().as_secs_f64();
        let st = sim.stats();
        let error = match (case.exact, &failure) {
            (_, Some(e)) => format!("FAILED: {e}"),
            (Some(x), None) => format!("{:.1e}", (sim.outputs().f_mean - x).abs() / p.f_c()),
            (None, None) => "–".into(),
        };
        let s_col = if s_ss > 0.0 {
            format!("{max_s:.9}")
        } else {
            "– (F_C = 0)".into()
        };
        let line = format!(
            "| {} | {} | {} | {:.2e} | {} | {:.1} ms | {} | {} |",
            case.name,
            if finite { "yes" } else { "NO" },
            s_col,
            min_p,
            error,
            elapsed * 1e3,
            st.steps,
            st.rejected
        );
        println!("{line}");
        let _ = writeln!(md, "{line}");
    }
    std::fs::create_dir_all("reports").unwrap();
    std::fs::write("reports/stability.md", md).unwrap();
    println!("wrote reports/stability.md");
}
