//! A string of contacts at the edges of what its parameters and inputs allow: the stiffest
//! contacts (k_t = 1e12 on every law), stiff links and end elements, light sections, sections
//! without load, a call spanning 1000 s, a force of 1e9 N, the loosest and tightest
//! tolerances. Each must step without failing, keep every output finite, and keep the exact
//! momentum balance of the whole string: over each communication step the change of `Σ m·v`
//! equals the step means of the external forces (`F_d`, `F_top`, `F_bottom`, `F_Fx`) times
//! the step, whatever the law and the stiffness.

mod support;

use support::configs::drill_pipe as pipe;
use vibrofric::model::string::{build_string, StringConfig, StringInput, StringParams};
use vibrofric::table::Law;

const N: usize = 8;

/// The forces the host applies at time `t`: the feed at the top, a tool of 20 kN at 15 Hz on
/// section 6 (as `F_d`), and per section the normal force where it is an input.
struct Drive {
    tool: f64,
    loads: Option<fn(usize) -> f64>,
    extra: Option<(usize, f64)>,
}

/// Runs `steps` communication steps of `h` and returns the worst momentum imbalance as a
/// fraction of `Σ|external forces|·h` (at least `n·F_C·h`).
fn run(law: Law, p: StringParams, drive: Drive, tol: f64, h: f64, steps: usize) -> f64 {
    let n = p.sections();
    let config = StringConfig {
        law,
        harmonic: false,
        normal_input: drive.loads.is_some(),
    };
    let masses = p.m.clone();
    let mut sim = build_string(config, p, 0.0, tol).unwrap();
    sim.set_input(StringInput::VTop, 0.05).unwrap();
    if let Some(load) = drive.loads {
        for i in 0..n {
            sim.set_input(StringInput::Fn(i), load(i)).unwrap();
        }
    }
    let momentum = |v: &[f64]| -> f64 { v.iter().zip(&masses).map(|(v, m)| v * m).sum() };
    let mut p0 = momentum(&sim.outputs().v_x);
    let mut worst: f64 = 0.0;
    for c in 0..steps {
        let t = c as f64 * h;
        let f_tool = drive.tool * (std::f64::consts::TAU * 15.0 * t).sin();
        sim.set_input(StringInput::Fd(6 % n), f_tool).unwrap();
        let mut applied = f_tool;
        if let Some((i, f)) = drive.extra {
            sim.set_input(StringInput::Fd(i), f).unwrap();
            applied += f;
        }
        sim.step_to((c + 1) as f64 * h)
            .unwrap_or_else(|e| panic!("step {c}: {e}"));
        let o = sim.outputs();
        for v in
            o.x.iter()
                .chain(&o.v_x)
                .chain(&o.s_x)
                .chain(&o.f_fx)
                .chain(&o.f_fx_step)
                .chain(&o.f_link)
                .chain([&o.f_top, &o.f_bottom, &o.f_top_step, &o.f_bottom_step])
        {
            assert!(v.is_finite(), "step {c}: an output is {v}");
        }
        let friction: f64 = o.f_fx_step.iter().sum();
        let scale = (applied.abs()
            + o.f_top_step.abs()
            + o.f_bottom_step.abs()
            + o.f_fx_step.iter().map(|f| f.abs()).sum::<f64>())
        .max(n as f64 * 0.3 * 2280.0)
            * h;
        let p1 = momentum(&o.v_x);
        let impulse = (applied + o.f_top_step - o.f_bottom_step - friction) * h;
        worst = worst.max((p1 - p0 - impulse).abs() / scale);
        p0 = p1;
    }
    worst
}

fn tool() -> Drive {
    Drive {
        tool: 2e4,
        loads: None,
        extra: None,
    }
}

fn check(what: &str, imbalance: f64, tol: f64) {
    eprintln!("{what}: momentum balance off by {imbalance:.1e} of the impulses");
    assert!(imbalance < 10.0 * tol, "{what}: {imbalance:e}");
}

#[test]
fn the_stiffest_contacts_step_with_their_momentum_balanced() {
    for law in [Law::Dahl, Law::Dupont, Law::LuGre] {
        let mut p = pipe(N);
        p.shared.k_t = 1e12;
        let imbalance = run(law, p, tool(), 1e-6, 1e-3, 30);
        check(&format!("{law:?} at k_t 1e12"), imbalance, 1e-6);
    }
}

#[test]
fn stiff_links_stiff_ends_and_light_sections_step() {
    let mut p = pipe(N);
    p.links.k_s.iter_mut().for_each(|k| *k = 1e12);
    check(
        "links 1e12",
        run(Law::LuGre, p, tool(), 1e-6, 1e-3, 10),
        1e-6,
    );
    let mut p = pipe(N);
    (p.links.k_top, p.links.k_bottom) = (1e13, 1e13);
    check(
        "ends 1e13",
        run(Law::LuGre, p, tool(), 1e-6, 1e-3, 10),
        1e-6,
    );
    let mut p = pipe(N);
    p.m.iter_mut().for_each(|m| *m = 1e-3);
    check(
        "sections of 1 g",
        run(Law::LuGre, p, tool(), 1e-6, 1e-3, 10),
        1e-6,
    );
}

/// Sections without load carry no friction: `F_Fx` is zero on them, exactly.
#[test]
fn sections_without_load_slide_without_friction() {
    let loads = |i: usize| if i.is_multiple_of(2) { 0.0 } else { 2280.0 };
    let drive = Drive {
        tool: 2e4,
        loads: Some(loads),
        extra: None,
    };
    check(
        "every other section unloaded",
        run(Law::LuGre, pipe(N), drive, 1e-6, 1e-3, 30),
        1e-6,
    );
    let mut sim = build_string(
        StringConfig {
            law: Law::LuGre,
            harmonic: false,
            normal_input: true,
        },
        pipe(N),
        0.0,
        1e-6,
    )
    .unwrap();
    for i in 0..N {
        sim.set_input(StringInput::Fn(i), loads(i)).unwrap();
    }
    sim.set_input(StringInput::Fd(2), 5e3).unwrap();
    sim.step_to(0.02).unwrap();
    let o = sim.outputs();
    for i in (0..N).step_by(2) {
        assert_eq!(o.f_fx[i], 0.0, "F_Fx[{}]", i + 1);
        assert_eq!(o.f_fx_step[i], 0.0, "F_Fx_step[{}]", i + 1);
    }
}

/// A string at rest with nothing driving it stays at rest through one call of 1000 s; fed at
/// the top, one call of 10 s ends where 10 calls of 1 s do (to the tolerance's order).
#[test]
fn long_calls_at_rest_and_fed() {
    let mut p = pipe(N);
    p.links.k_top = 0.0;
    p.links.c_top = 0.0;
    let config = StringConfig {
        law: Law::LuGre,
        harmonic: false,
        normal_input: false,
    };
    let mut sim = build_string(config, p, 0.0, 1e-6).unwrap();
    sim.step_to(1000.0).unwrap();
    let o = sim.outputs();
    assert!(o.x.iter().chain(&o.v_x).all(|&v| v == 0.0), "{o:?}");
    let fed = |calls: usize| {
        let mut sim = build_string(config, pipe(N), 0.0, 1e-6).unwrap();
        sim.set_input(StringInput::VTop, 0.05).unwrap();
        for c in 0..calls {
            sim.step_to(10.0 * (c + 1) as f64 / calls as f64).unwrap();
        }
        sim.outputs()
    };
    let (one, ten) = (fed(1), fed(10));
    for i in 0..N {
        // The top point has moved 0.5 m; positions agree to well within a micrometre.
        assert!((one.x[i] - ten.x[i]).abs() < 1e-6, "x[{}]", i + 1);
    }
}

#[test]
fn a_force_of_a_giganewton_and_the_tolerances_at_their_ends() {
    let drive = Drive {
        tool: 0.0,
        loads: None,
        extra: Some((3, 1e9)),
    };
    check(
        "1e9 N on section 4",
        run(Law::LuGre, pipe(N), drive, 1e-6, 1e-3, 10),
        1e-6,
    );
    check(
        "tolerance 1e-12",
        run(Law::LuGre, pipe(N), tool(), 1e-12, 1e-3, 3),
        1e-9,
    );
    check(
        "tolerance 1e-2",
        run(Law::LuGre, pipe(N), tool(), 1e-2, 1e-3, 30),
        1e-2,
    );
}
