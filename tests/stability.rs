//! The stiff and extreme-case stability matrix (issue 5) as tests: every row's outputs are
//! finite, the invariants of `docs/model.md` hold, and where the exact longitudinal Dahl solution
//! applies the mean friction force is within a bound proportional to the tolerance.

// Varying one parameter of the defaults reads best as an assignment.
#![allow(clippy::field_reassign_with_default)]

mod support;

use support::configs::{long_velocity, planar_force};
use support::reference::ExactDahl;
use vibrofric::model::{build, Config, Drive, InputId, Law, OutputId, Simulator};
use vibrofric::table::Params;

const TOL: f64 = 1e-6;

/// The driving input of a configuration: 8 N of force, or 1 mm/s of velocity.
fn drive_input(c: &Config) -> (InputId, f64) {
    if c.drive == Drive::Force {
        (InputId::FD, 8.0)
    } else {
        (InputId::VD, 1e-3)
    }
}

/// Steps `sim` with communication step `dt` to `n·dt`, asserting finite outputs and, for laws
/// with a bound, `|s| ≤ s_ss` and `P_diss ≥ 0` at every communication point.
fn step_checked(sim: &mut dyn Simulator, dt: f64, n: usize, bounded: bool) {
    let p = *sim.params();
    let s_ss = p.f_c() / p.k_t;
    let t0 = sim.time();
    for k in 1..=n {
        sim.step_to(t0 + k as f64 * dt).unwrap();
        let o = sim.outputs();
        for id in OutputId::ALL {
            assert!(
                id.get(&o).is_finite(),
                "non-finite {} at step {k}: {o:?}",
                id.name()
            );
        }
        if bounded {
            assert!(
                o.s_x.hypot(o.s_y) <= s_ss * (1.0 + 1e-12),
                "|s| > s_ss at step {k}"
            );
            assert!(o.p_diss >= 0.0, "P_diss < 0 at step {k}");
        }
    }
}

/// Longitudinal Dahl under velocity drive for `periods` periods in steps of `dt`, against the
/// exact solution.
fn exact_row(p: Params, v_d: f64, periods: usize, dt: f64) {
    let mut sim = build(long_velocity(Law::Dahl), p, 0.0, TOL).unwrap();
    sim.set_input(InputId::VD, v_d).unwrap();
    let t_end = periods as f64 / p.f;
    let n = (t_end / dt).round() as usize;
    step_checked(sim.as_mut(), t_end / n as f64, n, true);
    let exact = ExactDahl::new(&p, v_d).f_mean_after_periods(periods);
    let got = sim.outputs().f_mean;
    assert!(
        (got - exact).abs() <= TOL * p.f_c(),
        "k_t {} f {} u0 {} v_d {v_d}: F_mean {got} vs exact {exact}",
        p.k_t,
        p.f,
        p.u0
    );
}

#[test]
fn contact_stiffness_from_1e5_to_1e12() {
    for k_t in [1e5, 1e6, 1e8, 1e10, 1e12] {
        let mut p = Params::default();
        p.k_t = k_t;
        exact_row(p, 1e-3, 20, 1e-3);
        let mut sim = build(planar_force(Law::Dahl), p, 0.0, TOL).unwrap();
        sim.set_input(InputId::FD, 8.0).unwrap();
        step_checked(sim.as_mut(), 1e-3, 10, true);
    }
}

#[test]
fn frequency_up_to_ultrasonic() {
    for f in [50.0, 2000.0, 20000.0, 40000.0] {
        let mut p = Params::default();
        p.f = f;
        exact_row(p, 1e-3, 40, 1e-3);
    }
    // f = 0: the plain sliding force, for every law.
    for law in [Law::Dahl, Law::Dupont, Law::LuGre] {
        let mut p = Params::default();
        p.f = 0.0;
        let mut sim = build(long_velocity(law), p, 0.0, TOL).unwrap();
        sim.set_input(InputId::VD, 1e-3).unwrap();
        step_checked(sim.as_mut(), 1e-3, 10, law != Law::LuGre);
        let stribeck = p.f_c() + (p.f_s - p.f_c()) * (-(1e-3f64 / p.v_s).powi(2)).exp();
        let expect = if law == Law::LuGre { stribeck } else { p.f_c() };
        assert!(
            (sim.outputs().f_mean - expect).abs() < 1e-9 * expect,
            "{law:?}"
        );
    }
}

#[test]
fn amplitude_from_0_to_20_um() {
    for u0 in [2e-9, 2e-7, 2e-6, 2e-5] {
        let mut p = Params::default();
        p.u0 = u0;
        exact_row(p, 1e-3, 20, 1e-3);
    }
    let mut p = Params::default();
    p.u0 = 0.0;
    let mut sim = build(long_velocity(Law::Dahl), p, 0.0, TOL).unwrap();
    sim.set_input(InputId::VD, 1e-3).unwrap();
    step_checked(sim.as_mut(), 1e-3, 10, true);
    assert!(sim.outputs().reduction.abs() < 1e-12);
}

#[test]
fn driving_velocity_from_0_to_1_and_at_the_threshold() {
    let p = Params::default();
    let v_a = p.v_a();
    for v_d in [0.0, 1e-5, 1e-3, 0.1, 1.0] {
        exact_row(p, v_d, 20, 1e-3);
    }
    // psi exactly 1 and 1 ± 1e-9.
    for psi in [1.0 - 1e-9, 1.0, 1.0 + 1e-9] {
        exact_row(p, psi * v_a, 20, 1e-3);
    }
}

#[test]
fn mass_from_1e_3_to_1e3_kg() {
    for m in [1e-3, 1.0, 1e3] {
        for law in [Law::Dahl, Law::Dupont] {
            let mut p = Params::default();
            p.m = m;
            let mut sim = build(planar_force(law), p, 0.0, TOL).unwrap();
            sim.set_input(InputId::FD, 8.0).unwrap();
            step_checked(sim.as_mut(), 1e-3, 10, true);
        }
    }
}

#[test]
fn zero_load_and_zero_friction_coefficient() {
    for (f_n, mu) in [(0.0, 0.2), (55.0, 0.0)] {
        for law in [Law::Dahl, Law::Dupont, Law::LuGre] {
            let mut p = Params::default();
            p.f_n = f_n;
            p.mu = mu;
            // LuGre's static force follows the load (F_S is given at 55 N, mu = 0.2): none here.
            assert_eq!(p.static_force(), 0.0);
            let mut sim = build(planar_force(law), p, 0.0, TOL).unwrap();
            sim.set_input(InputId::FD, 8.0).unwrap();
            step_checked(sim.as_mut(), 1e-3, 5, true);
            let o = sim.outputs();
            // No friction: the body accelerates freely under F_d.
            let t = sim.time();
            assert_eq!(o.f_fx, 0.0);
            assert!((o.v_x - 8.0 / p.m * t).abs() < 1e-9 * (8.0 / p.m * t));
        }
    }
}

#[test]
fn lugre_with_damping_ratio_1_at_k_t_1e10() {
    let mut p = Params::default();
    p.k_t = 1e10;
    p.zeta_t = 1.0;
    for c in [long_velocity(Law::LuGre), planar_force(Law::LuGre)] {
        let mut sim = build(c, p, 0.0, TOL).unwrap();
        let input = drive_input(&c);
        sim.set_input(input.0, input.1).unwrap();
        step_checked(sim.as_mut(), 1e-3, 10, false);
    }
    // Without vibration the force-driven body below the static force sticks: F_mean = F_d.
    p.u0 = 0.0;
    let mut sim = build(planar_force(Law::LuGre), p, 0.0, TOL).unwrap();
    sim.set_input(InputId::FD, 8.0).unwrap();
    step_checked(sim.as_mut(), 1e-3, 20, false);
    assert!(
        (sim.outputs().f_mean - 8.0).abs() < 1e-6 * 8.0,
        "{}",
        sim.outputs().f_mean
    );
}

#[test]
fn dupont_breakaway_ratio_0_and_0_999() {
    for r_ba in [0.0, 0.999] {
        let mut p = Params::default();
        p.r_ba = r_ba;
        for c in [long_velocity(Law::Dupont), planar_force(Law::Dupont)] {
            let mut sim = build(c, p, 0.0, TOL).unwrap();
            let input = drive_input(&c);
            sim.set_input(input.0, input.1).unwrap();
            step_checked(sim.as_mut(), 1e-3, 10, true);
        }
    }
}

#[test]
fn one_communication_step_spanning_2000_periods() {
    let p = Params::default();
    exact_row(p, 1e-3, 2000, 1.0);
    // The same run in 2000 steps gives the same mean force to the tolerance.
    let mut a = build(planar_force(Law::Dahl), p, 0.0, TOL).unwrap();
    let mut b = build(planar_force(Law::Dahl), p, 0.0, TOL).unwrap();
    a.set_input(InputId::FD, 8.0).unwrap();
    b.set_input(InputId::FD, 8.0).unwrap();
    step_checked(a.as_mut(), 1.0, 1, true);
    step_checked(b.as_mut(), 5e-4, 2000, true);
    let (fa, fb) = (a.outputs().f_mean, b.outputs().f_mean);
    assert!((fa - fb).abs() < 10.0 * TOL * p.f_c(), "{fa} vs {fb}");
}

#[test]
fn communication_steps_of_1e_7_s() {
    let p = Params::default();
    exact_row(p, 1e-3, 4, 1e-7);
}

#[test]
fn a_thousand_seconds_of_simulated_time() {
    // 20 Hz at the default velocity amplitude: 20 000 periods, with the phase at t = 1000 s
    // held to full precision.
    let mut p = Params::default();
    p.f = 20.0;
    p.u0 = Params::default().v_a() / p.omega();
    exact_row(p, 1e-3, 20_000, 10.0);
}
