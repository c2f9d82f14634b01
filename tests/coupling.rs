//! What a host model integrates: the step means `F_Fx_step`, `F_Fy_step` (`∫F_F dt/h` over the
//! last communication step) against the window mean, against stepping the same time in short
//! steps, and against the body's momentum balance in the force drive.

mod support;

use support::scenes::{scene, start, STANDARD_SCENES};
use vibrofric::description::scene::Scene;
use vibrofric::model::{build, Drive, InputId, Setup};
use vibrofric::table::ParamId;

/// A communication step that is the averaging window integrates what `F_mean` integrates: the
/// two are the same number to rounding; over several windows in periodic steady state, the
/// step mean is the window mean.
#[test]
fn step_mean_over_whole_windows_is_the_window_mean() {
    let tol = 1e-8;
    for file in STANDARD_SCENES {
        let sc = scene(file);
        let p = sc.start;
        let window = if sc.config.harmonic {
            1.0 / p.f
        } else {
            p.t_avg
        };
        let mut sim = start(&sc, tol);
        let f_c = p.f_c();
        // Before any step the step means are the instantaneous force, like F_mean.
        let o = sim.outputs();
        assert_eq!((o.f_fx_step, o.f_fy_step), (o.f_fx, o.f_fy), "{file}");
        let mut t = 0.0;
        for k in 1..=60 {
            t = k as f64 * window;
            sim.step_to(t).unwrap();
        }
        let o = sim.outputs();
        assert!(
            (o.f_fx_step - o.f_mean).abs() <= 1e-12 * f_c.max(o.f_mean.abs()),
            "{file}: one window: F_Fx_step {} vs F_mean {}",
            o.f_fx_step,
            o.f_mean
        );
        // Periodic steady state: velocity drives (the body's own dynamics are slow in force and
        // spring drives), and the drill string, which sticks.
        if sc.config.drive == Drive::Velocity || !sc.config.harmonic {
            sim.step_to(t + 4.0 * window).unwrap();
            let o = sim.outputs();
            assert!(
                (o.f_fx_step - o.f_mean).abs() <= 20.0 * tol * f_c,
                "{file}: four windows: F_Fx_step {} vs F_mean {}",
                o.f_fx_step,
                o.f_mean
            );
        }
    }
}

/// One communication step over many vibration periods has the impulse of the same time stepped
/// period by period, on the paths that skip windows in O(1) (closed form, exponential) and on
/// Radau, from rest through the transient (a slow drive and a small amplitude: the deformation
/// forgets its start over tens of periods, so the windows skipped differ).
#[test]
fn one_long_step_has_the_impulse_of_many_short_ones() {
    let tol = 1e-9;
    for (file, periods) in [
        ("paper-longitudinal.toml", 2000u32),
        ("paper-transverse-guided.toml", 2000),
        ("paper-transverse.toml", 200),
    ] {
        let sc = scene(file);
        let mut p = sc.start;
        ParamId::U0.set(&mut p, 2e-9).unwrap();
        let mut sc = sc;
        sc.start = p;
        // 0.5 nm slid per period at 1 µm/s plus 8 nm of vibration: the deformation forgets its
        // start over tens of periods.
        sc.inputs.v_d = 1e-6;
        let period = 1.0 / p.f;
        let t_end = periods as f64 * period;
        let mut long = start(&sc, tol);
        long.step_to(t_end).unwrap();
        let lo = long.outputs();
        let mut short = start(&sc, tol);
        let (mut ix, mut iy) = (0.0, 0.0);
        let mut t0 = 0.0;
        for k in 1..=periods {
            let t1 = k as f64 * period;
            short.step_to(t1).unwrap();
            let o = short.outputs();
            ix += o.f_fx_step * (t1 - t0);
            iy += o.f_fy_step * (t1 - t0);
            t0 = t1;
        }
        let f_c = p.f_c();
        let (mx, my) = (ix / t_end, iy / t_end);
        assert!(
            (lo.f_fx_step - mx).abs() <= 10.0 * tol * f_c,
            "{file}: F_Fx_step {} vs {mx} ({:e})",
            lo.f_fx_step,
            (lo.f_fx_step - mx) / f_c
        );
        assert!(
            (lo.f_fy_step - my).abs() <= 10.0 * tol * f_c,
            "{file}: F_Fy_step {} vs {my}",
            lo.f_fy_step
        );
        eprintln!(
            "{file}: F_Fx_step {} ({:e}), F_Fy_step {} ({:e}), F_mean {}",
            lo.f_fx_step,
            (lo.f_fx_step - mx) / f_c,
            lo.f_fy_step,
            (lo.f_fy_step - my) / f_c,
            lo.f_mean
        );
        // The transient is in the impulse: it is not the steady-state mean.
        assert!(
            (lo.f_fx_step - lo.f_mean).abs() > 100.0 * tol * f_c,
            "{file}"
        );
    }
}

/// Force drive: `m·Δv = ∫(F_d·e_x − F_F) dt` over every step, held and ramped `F_d`, with the
/// vibration at 1 rad to x so that the body moves in y too.
#[test]
fn force_drive_momentum_balance_holds_over_every_step() {
    let tol = 1e-8;
    for file in [
        "contact.toml",
        "contact-lugre.toml",
        "contact-dupont.toml",
        "drill-string-axial.toml",
    ] {
        let mut sc = scene(file);
        if sc.config.harmonic {
            ParamId::Angle.set(&mut sc.start, 1.0).unwrap();
        }
        let p = sc.start;
        let mut sim = start(&sc, tol);
        let f_d0 = sc.inputs.f_d;
        let h = 7e-4;
        let mut worst: f64 = 0.0;
        for k in 0..60 {
            let (t0, t1) = (k as f64 * h, (k + 1) as f64 * h);
            let before = sim.outputs();
            // Ramp the drive through its derivative over the second half.
            let (f0, slope) = if k >= 30 {
                (f_d0 + 4.0 * (k - 30) as f64 * h / 0.01, 4.0 / 0.01)
            } else {
                (f_d0, 0.0)
            };
            sim.set_input(InputId::FD, f0).unwrap();
            if slope != 0.0 {
                sim.set_input_derivative(InputId::FD, slope).unwrap();
            }
            sim.step_to(t1).unwrap();
            let after = sim.outputs();
            let impulse_d = f0 * (t1 - t0) + 0.5 * slope * (t1 - t0).powi(2);
            let ex = p.m * (after.v_x - before.v_x) - (impulse_d - after.f_fx_step * (t1 - t0));
            let ey = p.m * (after.v_y - before.v_y) + after.f_fy_step * (t1 - t0);
            // In units of F_C·h: the step means' own tolerance.
            worst = worst.max(ex.abs().max(ey.abs()) / (p.f_c() * h));
        }
        eprintln!("{file}: momentum balance within {worst:e} F_C·h");
        assert!(
            worst <= 10.0 * tol,
            "{file}: momentum balance off by {worst:e} F_C·h"
        );
    }
}

/// A body free in y (the transverse scenes, on the planar explicit path, at the default and at
/// a stiff contact): `m·Δv_y = −∫F_Fy dt` over every step.
#[test]
fn lateral_momentum_balance_holds_over_every_step() {
    let tol = 1e-8;
    for file in ["paper-transverse.toml", "rig-transverse.toml"] {
        for k_t in [1e8, 1e12] {
            let mut sc = scene(file);
            sc.start.k_t = k_t;
            let p = sc.start;
            let mut sim = start(&sc, tol);
            let h = 7e-4;
            let mut worst: f64 = 0.0;
            for k in 0..60 {
                let before = sim.outputs();
                sim.step_to((k + 1) as f64 * h).unwrap();
                let after = sim.outputs();
                let ey = p.m * (after.v_y - before.v_y) + after.f_fy_step * h;
                worst = worst.max(ey.abs() / (p.f_c() * h));
            }
            eprintln!("{file} k_t {k_t:e}: lateral momentum balance within {worst:e} F_C·h");
            assert!(
                worst <= 10.0 * tol,
                "{file} k_t {k_t:e}: lateral momentum balance off by {worst:e} F_C·h"
            );
        }
    }
}

/// `(y(t + δ) − y(t))/δ` extrapolated to δ → 0 (Richardson on δ and δ/2): O(δ²).
fn richardson(at: impl Fn(f64) -> f64, y0: f64, delta: f64) -> f64 {
    let d1 = (at(delta) - y0) / delta;
    let d2 = (at(0.5 * delta) - y0) / (0.5 * delta);
    2.0 * d2 - d1
}

/// The output derivatives against finite differences of the outputs over small steps: the body's
/// position and velocity, the deformation, and the step means as moving means over the step.
#[test]
fn output_derivatives_match_finite_differences() {
    use vibrofric::model::OutputId;
    let tol = 1e-12;
    let h = 1e-3;
    // 0.37 ms after a step: away from the instants where v_r changes sign.
    let t = 10.0 * h + 3.7e-4;
    let delta = 2e-7;
    for file in STANDARD_SCENES {
        let sc = scene(file);
        let c = sc.config;
        let base = |t0: f64| {
            let mut sim = start(&sc, tol);
            if t0 > 0.0 {
                sim.step_to(t0).unwrap();
            }
            for k in 1..=10 {
                sim.step_to(t0 + k as f64 * h).unwrap();
            }
            sim
        };
        let mut sim = start(&sc, tol);
        sim.step_to(3.7e-4).unwrap();
        for k in 1..=10 {
            sim.step_to(3.7e-4 + k as f64 * h).unwrap();
        }
        let now = sim.outputs();
        for id in [
            OutputId::X,
            OutputId::Y,
            OutputId::Vx,
            OutputId::Vy,
            OutputId::Sx,
            OutputId::Sy,
        ] {
            if !id.present(&c) {
                continue;
            }
            let d = sim.output_derivative(id).unwrap();
            let at = |dt: f64| {
                let mut s = sim.clone_box();
                s.step_to(t + dt).unwrap();
                id.get(&s.outputs())
            };
            let fd = richardson(at, id.get(&now), delta);
            // Natural magnitudes: velocities for positions and deformations (whose rate is
            // v_r less the relaxation), F_C/m for velocities.
            let p = &sc.start;
            let speed = now.v_x.abs() + std::f64::consts::TAU * p.f * p.u0 + 1e-3;
            let natural = match id {
                OutputId::Vx | OutputId::Vy => p.f_c() / p.m,
                _ => speed,
            };
            let scale = d.abs().max(fd.abs()).max(natural);
            assert!(
                (d - fd).abs() <= 1e-5 * scale,
                "{file}: d{}/dt = {d:e}, finite differences {fd:e}",
                id.name()
            );
        }
        // Step means: the moving mean over the last step's length h, shifted by δ.
        for id in [OutputId::FFxStep, OutputId::FFyStep] {
            if !id.present(&c) {
                continue;
            }
            let d = sim.output_derivative(id).unwrap();
            let at = |dt: f64| {
                let mut s = base(3.7e-4 - h + dt);
                s.step_to(t + dt).unwrap();
                id.get(&s.outputs())
            };
            let fd = richardson(at, id.get(&now), delta);
            let f_c = sc.start.f_c();
            // The truncation of the differences, and the integrals' own error (tol·F_C) over δ.
            assert!(
                (d - fd).abs() <= 1e-4 * d.abs().max(fd.abs()) + 100.0 * tol * f_c / delta,
                "{file}: d{}/dt = {d:e}, finite differences {fd:e}",
                id.name()
            );
        }
        // Forces and window means have none.
        assert_eq!(sim.output_derivative(OutputId::FFx), None, "{file}");
        assert_eq!(sim.output_derivative(OutputId::FMean), None, "{file}");
    }
}

/// The scene's contact with the normal force an input (`normal = "input"`).
fn with_normal_input(mut sc: Scene) -> Scene {
    sc.config.normal_input = true;
    sc.inputs.f_n = sc.start.f_n;
    sc
}

/// An input `F_N` held at the parameter's value is the parameter: every standard scene over 50
/// steps of 1 ms (the velocity drives then leave their fast paths for Radau).
#[test]
fn normal_force_input_held_equals_the_parameter() {
    let tol = 1e-9;
    for file in STANDARD_SCENES {
        let sc = scene(file);
        let f_c = sc.start.f_c();
        let s_ss = f_c / sc.start.k_t;
        let mut a = start(&sc, tol);
        let mut b = start(&with_normal_input(sc.clone()), tol);
        let mut worst: f64 = 0.0;
        for k in 1..=50 {
            a.step_to(k as f64 * 1e-3).unwrap();
            b.step_to(k as f64 * 1e-3).unwrap();
            let (oa, ob) = (a.outputs(), b.outputs());
            for id in [
                OutputId::FFx,
                OutputId::FFy,
                OutputId::FMean,
                OutputId::FFxStep,
            ] {
                worst = worst.max((id.get(&oa) - id.get(&ob)).abs() / f_c);
            }
            worst = worst.max((oa.s_x - ob.s_x).abs() / s_ss);
        }
        eprintln!("{file}: F_N input held against the parameter: {worst:e}");
        assert!(worst <= 20.0 * tol, "{file}: {worst:e}");
    }
}

use vibrofric::model::{Config, Lateral, Law, Motion, OutputId};

/// Steady sliding at `v` under a normal force falling linearly, `F_N = a + b·t`, given through
/// input derivatives: `ds/dt = v·(1 − s/s_ss(t))` with `s_ss = mu·F_N/k_t` has the closed form
/// `s = v·a/(b·(c + 1))·(r − r^(−c))`, `r = F_N(t)/a`, `c = v·k_t/(mu·b)`. (The relaxation lags
/// the falling load: `s` ends 0.1 % above `s_ss`, as the law says.)
#[test]
fn normal_force_ramp_matches_the_exact_solution() {
    let config = Config {
        law: Law::Dahl,
        motion: Motion::Longitudinal,
        drive: Drive::Velocity,
        lateral: Lateral::Guided,
        harmonic: false,
        input_support: true,
        normal_input: true,
    };
    let p = vibrofric::table::Params::default();
    let (a, b, v) = (55.0, -500.0, 1e-3);
    let c = v * p.k_t / (p.mu * b);
    let exact = |t: f64| {
        let r = (a + b * t) / a;
        v * a / (b * (c + 1.0)) * (r - (-c * r.ln()).exp())
    };
    for tol in [1e-6, 1e-9] {
        let mut sim = build(config, p, 0.0, tol).unwrap();
        sim.set_input(InputId::VD, v).unwrap();
        let mut worst: f64 = 0.0;
        for k in 0..100 {
            let t = k as f64 * 1e-3;
            sim.set_input(InputId::FN, a + b * t).unwrap();
            sim.set_input_derivative(InputId::FN, b).unwrap();
            sim.step_to(t + 1e-3).unwrap();
            let o = sim.outputs();
            let s_ss = p.mu * (a + b * (t + 1e-3)) / p.k_t;
            worst = worst.max((o.s_x - exact(t + 1e-3)).abs() / s_ss);
        }
        eprintln!("tol {tol:e}: s against the exact solution within {worst:e} s_ss");
        assert!(worst <= 20.0 * tol, "tol {tol:e}: {worst:e}");
    }
}

/// The body lifts off (the load ramps to 0 inside a step, then stays 0) and lands again: every
/// step succeeds, every output is finite, `|s| ≤ s_ss(t)` where the law keeps it (Dahl and
/// Dupont under a held or rising load), no friction and no deformation while off (the body then
/// accelerates at exactly `F_d/m`), friction again after landing.
#[test]
fn lift_off_and_touch_down() {
    for tol in [1e-6, 1e-8, 1e-10] {
        lift_off_and_touch_down_at(tol);
    }
}

fn lift_off_and_touch_down_at(tol: f64) {
    for file in [
        "contact.toml",
        "contact-dupont.toml",
        "contact-lugre.toml",
        "drill-string-axial.toml",
    ] {
        let sc = with_normal_input(scene(file));
        let p = sc.start;
        let mut sim = start(&sc, tol);
        let h = 1e-3;
        let f_n0 = p.f_n;
        // 0-10 ms: full load; 10-14.5 ms: down to 0 (reached inside the step to 15 ms);
        // 15-25 ms: off; 25-35 ms: back up; 35-60 ms: full load.
        let load = |t: f64| -> (f64, f64) {
            if t < 0.010 {
                (f_n0, 0.0)
            } else if t < 0.015 {
                let slope = -f_n0 / 0.0045;
                ((f_n0 + slope * (t - 0.010)).max(0.0), slope)
            } else if t < 0.025 {
                (0.0, 0.0)
            } else if t < 0.035 {
                (f_n0 * (t - 0.025) / 0.010, f_n0 / 0.010)
            } else {
                (f_n0, 0.0)
            }
        };
        let mut landed_force: f64 = 0.0;
        for k in 0..60 {
            let t = k as f64 * h;
            let (f_n, slope) = load(t + 1e-12);
            sim.set_input(InputId::FN, f_n).unwrap();
            if slope != 0.0 {
                sim.set_input_derivative(InputId::FN, slope).unwrap();
            }
            let before = sim.outputs();
            sim.step_to(t + h)
                .unwrap_or_else(|e| panic!("{file}: step to {}: {e}", t + h));
            let o = sim.outputs();
            for id in OutputId::ALL {
                assert!(id.get(&o).is_finite(), "{file}: {} at {}", id.name(), t + h);
            }
            // The load the contact ended the step with (the ramp clamped at 0).
            let f_n_end = (f_n + slope * h).max(0.0);
            if sc.config.law != Law::LuGre && slope >= 0.0 {
                let s_ss = p.mu * f_n_end / p.k_t;
                let s = (o.s_x * o.s_x + o.s_y * o.s_y).sqrt();
                // To the tolerance: with the load an input, the bound is the law's, not a
                // projection's.
                assert!(
                    s <= s_ss * (1.0 + 10.0 * tol),
                    "{file}: |s| {s} > s_ss {s_ss} at {}",
                    t + h
                );
            }
            if (0.015..0.025).contains(&t) {
                assert_eq!(
                    (o.f_fx, o.f_fy),
                    (0.0, 0.0),
                    "{file}: friction while off at {t}"
                );
                let s_ref = p.f_c() / p.k_t;
                assert!(
                    o.s_x.abs().max(o.s_y.abs()) <= 1e-15 * s_ref,
                    "{file}: deformation ({}, {}) while off at {t}",
                    o.s_x,
                    o.s_y
                );
                let dv = o.v_x - before.v_x;
                let free = sc.inputs.f_d * h / p.m;
                assert!(
                    (dv - free).abs() <= 1e-12 * free.abs().max(1e-12),
                    "{file}: dv {dv} vs F_d·h/m {free}"
                );
            }
            if t >= 0.05 {
                landed_force = landed_force.max(o.f_fx.abs());
            }
        }
        assert!(
            landed_force > 0.1 * p.f_c(),
            "{file}: no friction after landing"
        );
    }
}

/// The contact counts time from its start: started at 1e6 s or 1e9 s (where a double resolves
/// 1.2e-7 s, a quarter of a thousandth of a vibration period) it computes what it computes when
/// started at 0, bit for bit, on communication points the importer can represent exactly.
#[test]
fn large_start_times_keep_full_accuracy() {
    let tol = 1e-8;
    for file in STANDARD_SCENES {
        let sc = scene(file);
        let run = |t0: f64| {
            let mut sim = Setup::new(sc.config, sc.start)
                .inputs(sc.inputs)
                .start(t0)
                .tolerance(tol)
                .build()
                .unwrap();
            for k in 1..=100 {
                sim.step_to(t0 + k as f64 / 1024.0).unwrap();
            }
            assert_eq!(sim.time(), t0 + 100.0 / 1024.0);
            sim.outputs()
        };
        let reference = run(0.0);
        for t0 in [1e6, 1e9] {
            assert_eq!(run(t0), reference, "{file}: started at {t0:e}");
        }
    }
}
