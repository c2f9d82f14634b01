//! A stuck contact is a normal state: a force- or spring-driven body held inside the static
//! friction must never make a step fail, at any communication step, and must leave the stuck
//! phase when the drive exceeds what the contact holds. The truth here is the finest run (the
//! same problem stepped 5000× more often), the static force balance while stuck, and the
//! constant deceleration `(F_d − F_C)/m` of a LuGre body sliding well above the Stribeck velocity.

use std::path::Path;

use vibrofric::description::scene::Scene;
use vibrofric::model::{build, Config, Drive, InputId, Lateral, Law, Motion, Outputs};
use vibrofric::table::Params;

const TOL: f64 = 1e-6;
/// Communication steps of the issue: 1e-4 s (the reference) up to 0.5 s.
const STEPS: [f64; 4] = [1e-4, 1e-3, 1e-2, 0.5];

/// Runs `config` to `t_end` in communication steps `dt`, with the inputs `inputs(t)` set at the
/// start of each step; returns the outputs every 0.5 s. Every step must succeed.
fn run(
    config: Config,
    params: Params,
    dt: f64,
    t_end: f64,
    inputs: &dyn Fn(f64) -> Vec<(InputId, f64)>,
) -> Vec<Outputs> {
    let mut sim = build(config, params, 0.0, TOL).unwrap();
    let n = (t_end / dt).round() as usize;
    let per_sample = (0.5 / dt).round() as usize;
    let mut samples = vec![];
    for k in 0..n {
        for (id, v) in inputs(k as f64 * dt) {
            sim.set_input(id, v).unwrap();
        }
        let t = (k + 1) as f64 * dt;
        if let Err(e) = sim.step_to(t) {
            panic!("communication step {dt}: step to {t} failed: {e}");
        }
        if (k + 1) % per_sample == 0 {
            samples.push(sim.outputs());
        }
    }
    samples
}

/// Asserts that the run at every coarser communication step agrees with the finest one.
fn assert_coarse_agree(runs: &[Vec<Outputs>], scale_x: f64, scale_v: f64, f_c: f64) {
    let fine = &runs[0];
    for (r, dt) in runs.iter().zip(STEPS).skip(1) {
        for (k, (a, b)) in r.iter().zip(fine).enumerate() {
            let t = 0.5 * (k + 1) as f64;
            assert!(
                (a.x - b.x).abs() <= 10.0 * TOL * scale_x,
                "dt {dt}, t {t}: x {} vs {}",
                a.x,
                b.x
            );
            assert!(
                (a.v_x - b.v_x).abs() <= 10.0 * TOL * scale_v,
                "dt {dt}, t {t}: v_x {} vs {}",
                a.v_x,
                b.v_x
            );
            assert!(
                (a.f_fx - b.f_fx).abs() <= 10.0 * TOL * f_c,
                "dt {dt}, t {t}: F_Fx {} vs {}",
                a.f_fx,
                b.f_fx
            );
        }
    }
}

#[test]
fn drill_string_held_released_held_at_every_communication_step() {
    let scene = Scene::load(Path::new("scenes/drill-string-axial.toml")).unwrap();
    let p = scene.start;
    // A 10 m section of drill pipe (267 kg, F_C = 684 N, F_S = 889.2 N): held at 300 N, released
    // with 1200 N (above the static force) for 0.5 s, held again at 300 N.
    let (hold, push) = (300.0, 1200.0);
    let f_d = move |t: f64| match t {
        t if t < 0.5 - 1e-9 => hold,
        t if t < 1.0 - 1e-9 => push,
        _ => hold,
    };
    let inputs = |t: f64| vec![(InputId::FD, f_d(t))];
    let runs: Vec<_> = STEPS
        .iter()
        .map(|&dt| run(scene.config, p, dt, 3.0, &inputs))
        .collect();
    let fine = &runs[0];
    // Stuck: at rest, and the contact holds the drive exactly (k_t·s = F_d).
    for k in [0, 5] {
        let o = &fine[k];
        assert!(
            o.v_x.abs() < 1e-9,
            "t {}: v_x = {}",
            0.5 * (k + 1) as f64,
            o.v_x
        );
        assert!(
            (o.f_fx - hold).abs() < 1e-6 * hold / 5.0,
            "t {}: F_Fx = {}",
            0.5 * (k + 1) as f64,
            o.f_fx
        );
    }
    // Released: well above the Stribeck velocity the friction is F_C, so over the last 0.5 s
    // of the push the body gains (F_d − F_C)/m · 0.5 s (h_v = 0).
    let f_c = p.f_c();
    assert!(fine[1].v_x > 0.1, "released: v_x = {}", fine[1].v_x);
    let gain = (push - f_c) / p.m * 0.5;
    assert!(
        (fine[1].v_x - gain).abs() < 0.02 * gain,
        "v_x {} vs (F_d − F_C)/m·t = {gain}",
        fine[1].v_x
    );
    // Held again: it decelerates at (F_C − 300 N)/m and sticks.
    let decel = (f_c - hold) / p.m;
    assert!(
        (fine[2].v_x - (fine[1].v_x - decel * 0.5)).abs() < 1e-3 * fine[1].v_x,
        "v_x {} after 0.5 s at {hold} N",
        fine[2].v_x
    );
    assert!(fine[5].x > fine[1].x);
    assert_coarse_agree(&runs, fine[5].x, fine[1].v_x, f_c);
}

#[test]
fn lugre_stick_slip_through_a_soft_spring_at_every_communication_step() {
    let config = Config {
        law: Law::LuGre,
        motion: Motion::Longitudinal,
        drive: Drive::Spring,
        lateral: Lateral::Guided,
        harmonic: false,
        input_support: true,
        normal_input: false,
    };
    let p = Params {
        k_d: 2e3,
        c_d: 0.0,
        ..Params::default()
    };
    // The far end moves at 2 mm/s: the spring force rises at 4 N/s until the contact slips.
    let inputs = |_: f64| vec![(InputId::VD, 2e-3)];
    let runs: Vec<_> = STEPS
        .iter()
        .map(|&dt| run(config, p, dt, 15.0, &inputs))
        .collect();
    let fine = &runs[0];
    // Stick–slip: some samples stuck, and the body slides faster than the far end in the slips.
    let stuck = fine.iter().filter(|o| o.v_x.abs() < 1e-5).count();
    assert!(stuck >= 10, "{stuck} of {} samples stuck", fine.len());
    // While stuck (at rest, not accelerating) the friction balances the spring: F_Fx = F_d.
    for o in fine.iter().filter(|o| o.v_x.abs() < 1e-7) {
        assert!(
            (o.f_fx - o.f_d).abs() < 1e-3,
            "stuck: F_Fx {} vs F_d {}",
            o.f_fx,
            o.f_d
        );
        assert!(o.f_fx <= p.f_s * 1.0001, "stuck above F_S: {}", o.f_fx);
    }
    let x_end = fine.last().unwrap().x;
    assert!(x_end > 0.02, "the body followed the spring: x = {x_end}");
    assert_coarse_agree(&runs, x_end, 2e-3, p.f_c());
}

/// The explicit path (a body on a Dahl contact, no damping in the contact): held at 5 N from
/// rest, pushed with 20 N, held again, at every communication step, against Radau at 1e-10.
/// While stuck the body oscillates on the contact's stiffness (Dahl has no viscous term; only
/// the hysteresis damps it), so the force balance holds to the oscillation's amplitude.
#[test]
fn dahl_body_on_the_explicit_path_held_released_held_at_every_communication_step() {
    use vibrofric::model::{build_on, Integrator};
    let config = Config {
        law: Law::Dahl,
        motion: Motion::Longitudinal,
        drive: Drive::Force,
        lateral: Lateral::Guided,
        harmonic: false,
        input_support: true,
        normal_input: false,
    };
    let p = Params::default();
    let f_d = |t: f64| match t {
        t if t < 0.5 - 1e-9 => 5.0,
        t if t < 1.0 - 1e-9 => 20.0,
        _ => 5.0,
    };
    let inputs = |t: f64| vec![(InputId::FD, f_d(t))];
    assert_eq!(
        build(config, p, 0.0, TOL).unwrap().integrator(),
        Integrator::Explicit
    );
    let runs: Vec<_> = STEPS
        .iter()
        .map(|&dt| run(config, p, dt, 3.0, &inputs))
        .collect();
    let fine = &runs[0];
    let f_c = p.f_c();
    // Stuck from rest: the friction holds the drive up to the contact oscillation.
    assert!(fine[0].v_x.abs() < 1e-5, "v_x = {}", fine[0].v_x);
    assert!(
        (fine[0].f_fx - 5.0).abs() < 0.01 * f_c,
        "F_Fx = {}",
        fine[0].f_fx
    );
    // Sliding: the Dahl force is F_C exactly, so the body gains (F_d − F_C)/m · 0.5 s.
    let gain = (20.0 - f_c) / p.m * 0.5;
    assert!(
        (fine[1].v_x - gain).abs() < 1e-3 * gain,
        "v_x {}",
        fine[1].v_x
    );
    // Stuck again after decelerating at (F_C − 5)/m.
    for o in &fine[4..] {
        assert!(o.v_x.abs() < 1e-5, "v_x = {}", o.v_x);
        assert!((o.f_fx - 5.0).abs() < 0.01 * f_c, "F_Fx = {}", o.f_fx);
    }
    // Every communication step gives the same motion. The phase of the undamped stuck
    // oscillation (about 670 Hz) drifts by the tolerance per cycle, so the force sampled at an
    // instant is compared to the oscillation's amplitude only.
    for (r, dt) in runs.iter().zip(STEPS).skip(1) {
        for (k, (a, b)) in r.iter().zip(fine).enumerate() {
            let t = 0.5 * (k + 1) as f64;
            assert!(
                (a.x - b.x).abs() <= 10.0 * TOL * fine[5].x,
                "dt {dt}, t {t}: x {} vs {}",
                a.x,
                b.x
            );
            assert!(
                (a.v_x - b.v_x).abs() <= 10.0 * TOL * fine[1].v_x,
                "dt {dt}, t {t}: v_x {} vs {}",
                a.v_x,
                b.v_x
            );
            assert!(
                (a.f_fx - b.f_fx).abs() <= 0.01 * f_c,
                "dt {dt}, t {t}: F_Fx"
            );
        }
    }
    // The same run on Radau at a tight tolerance.
    let mut radau = build_on(config, p, 0.0, 1e-10, true).unwrap();
    let mut reference = vec![];
    for k in 0..6 {
        radau.set_input(InputId::FD, f_d(k as f64 * 0.5)).unwrap();
        radau.step_to((k + 1) as f64 * 0.5).unwrap();
        reference.push(radau.outputs());
    }
    for (k, (a, b)) in fine.iter().zip(&reference).enumerate() {
        assert!(
            // While stuck, up to the oscillation's amplitude (1 % of F_C on the stiffness).
            (a.x - b.x).abs() <= 10.0 * TOL * b.x.abs() + 0.01 * f_c / p.k_t,
            "t {}: x {} vs Radau {}",
            0.5 * (k + 1) as f64,
            a.x,
            b.x
        );
    }
}
