//! The contact core against truth it did not produce: Coulomb limits (`docs/model.md`), the exact
//! solution of longitudinal Dahl, reference Runge–Kutta integrations written here, invariants,
//! and the paper's qualitative claims.

// Varying one parameter of the defaults reads best as an assignment.
#![allow(clippy::field_reassign_with_default)]

mod support;

use std::f64::consts::FRAC_PI_2;

use support::reference::{coulomb_longitudinal, coulomb_transverse, rk4, ExactDahl};
use vibrofric::model::{build, Config, Drive, InputId, Lateral, Law, Motion, Outputs, Simulator};
use vibrofric::table::Params;

fn config(law: Law, motion: Motion, drive: Drive, lateral: Lateral) -> Config {
    Config {
        law,
        motion,
        drive,
        lateral,
        harmonic: true,
        input_support: false,
        normal_input: false,
    }
}

fn longitudinal_velocity(law: Law) -> Config {
    config(law, Motion::Longitudinal, Drive::Velocity, Lateral::Guided)
}

fn transverse_velocity(lateral: Lateral) -> Config {
    config(Law::Dahl, Motion::Planar, Drive::Velocity, lateral)
}

/// Velocity drive at `v_d`, `periods` vibration periods; returns the final outputs.
fn run_velocity(c: Config, p: Params, v_d: f64, periods: f64, tol: f64) -> Outputs {
    let mut sim = build(c, p, 0.0, tol).unwrap();
    sim.set_input(InputId::VD, v_d).unwrap();
    sim.step_to(periods / p.f).unwrap();
    sim.outputs()
}

fn transverse(p: &mut Params) {
    p.angle = FRAC_PI_2;
}

#[test]
fn coulomb_limits_are_reached_by_a_stiff_contact() {
    // u0·k_t/F_C = 2e-7·1e12/11 = 1.8e4 >= 1e4
    let mut p = Params::default();
    p.k_t = 1e12;
    assert!(p.u0 * p.k_t / p.f_c() >= 1e4);
    for psi in [0.25, 0.5, 0.8, 1.25, 2.0] {
        let long = run_velocity(
            longitudinal_velocity(Law::Dahl),
            p,
            psi * p.v_a(),
            20.0,
            1e-8,
        );
        let lim = coulomb_longitudinal(psi);
        // reduction = 1 − F_mean/F_C; the limits are F_mean/F_C.
        assert!(
            ((1.0 - long.reduction) - lim).abs() <= 1e-3 * lim,
            "longitudinal psi {psi}: {} vs {lim}",
            1.0 - long.reduction
        );
        let mut q = p;
        transverse(&mut q);
        let tr = run_velocity(
            transverse_velocity(Lateral::Guided),
            q,
            psi * q.v_a(),
            20.0,
            1e-8,
        );
        let lim = coulomb_transverse(psi);
        assert!(
            ((1.0 - tr.reduction) - lim).abs() <= 1e-3 * lim,
            "transverse psi {psi}: {} vs {lim}",
            1.0 - tr.reduction
        );
    }
}

#[test]
fn mean_force_approaches_coulomb_limit_monotonically_as_stiffness_grows() {
    for psi in [0.5, 0.8] {
        let mut prev_long = f64::INFINITY;
        let mut prev_tr = f64::INFINITY;
        for k_t in [1e9, 1e10, 1e11, 1e12] {
            let mut p = Params::default();
            p.k_t = k_t;
            let long = run_velocity(
                longitudinal_velocity(Law::Dahl),
                p,
                psi * p.v_a(),
                10.0,
                1e-9,
            );
            let e = ((1.0 - long.reduction) - coulomb_longitudinal(psi)).abs();
            assert!(
                e < prev_long,
                "longitudinal psi {psi} k_t {k_t}: {e} !< {prev_long}"
            );
            prev_long = e;
            transverse(&mut p);
            let tr = run_velocity(
                transverse_velocity(Lateral::Guided),
                p,
                psi * p.v_a(),
                10.0,
                1e-9,
            );
            let e = ((1.0 - tr.reduction) - coulomb_transverse(psi)).abs();
            assert!(
                e < prev_tr,
                "transverse psi {psi} k_t {k_t}: {e} !< {prev_tr}"
            );
            prev_tr = e;
        }
    }
}

#[test]
fn longitudinal_dahl_matches_its_exact_solution() {
    for (k_t, v_d) in [(1e8, 1e-3), (1e8, 2e-3), (1e10, 1e-3)] {
        let mut p = Params::default();
        p.k_t = k_t;
        let exact = ExactDahl::new(&p, v_d);
        let truth = exact.f_mean_after_periods(100);
        for tol in [1e-6, 1e-9] {
            let out = run_velocity(longitudinal_velocity(Law::Dahl), p, v_d, 100.0, tol);
            let err = ((out.f_mean - truth) / truth).abs();
            assert!(
                err <= tol,
                "k_t {k_t} v_d {v_d} tol {tol}: F_mean error {err}"
            );
        }
    }
}

/// Dahl right-hand side written out here, independently of the library.
fn dahl_rate(s: f64, vr: f64, s_ss: f64) -> f64 {
    vr - vr.abs() * s / s_ss
}

/// Asserts that the reference integration converged (its two resolutions `r1`, `r2` agree to
/// 1e-7 of each component's scale) and that `got` matches it to 1e-5 of the scale.
fn assert_matches_converged_reference<const N: usize>(
    r1: &[f64; N],
    r2: &[f64; N],
    got: &[f64; N],
    scales: &[f64; N],
) {
    for i in 0..N {
        assert!(
            (r1[i] - r2[i]).abs() < 1e-7 * scales[i],
            "reference not converged in {i}"
        );
        assert!(
            (got[i] - r2[i]).abs() < 1e-5 * scales[i],
            "component {i}: {} vs reference {}",
            got[i],
            r2[i]
        );
    }
}

/// Runs a force drive at constant `F_d` to `t_end` at tolerance 1e-9.
fn run_force(c: Config, p: Params, f_d: f64, t_end: f64) -> Outputs {
    let mut sim = build(c, p, 0.0, 1e-9).unwrap();
    sim.set_input(InputId::FD, f_d).unwrap();
    sim.step_to(t_end).unwrap();
    sim.outputs()
}

#[test]
fn longitudinal_force_drive_matches_reference_runge_kutta() {
    let mut p = Params::default();
    p.u0 = 5e-7; // v_a = 6.3 mm/s: the body slips and sticks within a period
    let f_d = 5.0;
    let s_ss = p.f_c() / p.k_t;
    let (v_a, w, m, k_t) = (p.v_a(), p.omega(), p.m, p.k_t);
    let f = move |t: f64, y: &[f64; 3]| {
        let vr = y[2] - v_a * (w * t).cos();
        [dahl_rate(y[0], vr, s_ss), y[2], (f_d - k_t * y[0]) / m]
    };
    let t_end = 4e-3;
    let r1 = rk4(&f, 0.0, [0.0; 3], t_end, 400_000, &mut |_, _| {});
    let r2 = rk4(&f, 0.0, [0.0; 3], t_end, 800_000, &mut |_, _| {});
    let scales = [s_ss, 1e-6, v_a];
    let c = config(
        Law::Dahl,
        Motion::Longitudinal,
        Drive::Force,
        Lateral::Guided,
    );
    let o = run_force(c, p, f_d, t_end);
    assert_matches_converged_reference(&r1, &r2, &[o.s_x, o.x, o.v_x], &scales);
}

#[test]
fn planar_force_drive_matches_reference_runge_kutta() {
    let mut p = Params::default();
    p.angle = 0.6;
    p.u0 = 5e-7;
    let f_d = 6.0;
    let s_ss = p.f_c() / p.k_t;
    let (v_a, w, m, k_t) = (p.v_a(), p.omega(), p.m, p.k_t);
    let (ca, sa) = (p.angle.cos(), p.angle.sin());
    // y = [s_x, s_y, x, y, v_x, v_y]
    let f = move |t: f64, y: &[f64; 6]| {
        let vs = v_a * (w * t).cos();
        let (vrx, vry) = (y[4] - vs * ca, y[5] - vs * sa);
        let n = vrx.hypot(vry);
        [
            vrx - n * y[0] / s_ss,
            vry - n * y[1] / s_ss,
            y[4],
            y[5],
            (f_d - k_t * y[0]) / m,
            -k_t * y[1] / m,
        ]
    };
    let t_end = 3e-3;
    let r1 = rk4(&f, 0.0, [0.0; 6], t_end, 300_000, &mut |_, _| {});
    let r2 = rk4(&f, 0.0, [0.0; 6], t_end, 600_000, &mut |_, _| {});
    let scales = [s_ss, s_ss, 1e-6, 1e-6, v_a, v_a];
    let c = config(Law::Dahl, Motion::Planar, Drive::Force, Lateral::Guided);
    let o = run_force(c, p, f_d, t_end);
    let got = [o.s_x, o.s_y, o.x, o.y, o.v_x, o.v_y];
    assert_matches_converged_reference(&r1, &r2, &got, &scales);
}

#[test]
fn lugre_velocity_drive_matches_reference_runge_kutta() {
    let mut p = Params::default();
    p.h_v = 50.0;
    let v_d = 1e-3;
    let (v_a, w, k_t, f_c, f_s, v_s) = (p.v_a(), p.omega(), p.k_t, p.f_c(), p.f_s, p.v_s);
    let h_t0 = 2.0 * p.zeta_t * (p.m * p.k_t).sqrt();
    let (v_e, h_v) = (p.v_e, p.h_v);
    let lugre = move |t: f64, s: f64| {
        let vr = v_d - v_a * (w * t).cos();
        let g = (f_c + (f_s - f_c) * (-(vr / v_s).powi(2)).exp()) / k_t;
        let ds = vr - vr.abs() * s / g;
        let force = k_t * s + h_t0 * (-(vr / v_e).powi(2)).exp() * ds + h_v * vr;
        (ds, force)
    };
    // First period: s alone; second period: y = [s, ∫F dt].
    let period = 1.0 / p.f;
    let f1 = move |t: f64, y: &[f64; 1]| [lugre(t, y[0]).0];
    let f2 = move |t: f64, y: &[f64; 2]| {
        let (ds, force) = lugre(t, y[0]);
        [ds, force]
    };
    let run = |n: usize| {
        let s1 = rk4(&f1, 0.0, [0.0], period, n, &mut |_, _| {})[0];
        rk4(&f2, period, [s1, 0.0], 2.0 * period, n, &mut |_, _| {})
    };
    let (r1, r2) = (run(100_000), run(200_000));
    let f_mean_ref = r2[1] / period;
    let f_end_ref = lugre(2.0 * period, r2[0]).1;
    assert!(
        ((r1[1] - r2[1]) / period).abs() < 1e-8 * f_c,
        "reference not converged"
    );
    let out = run_velocity(longitudinal_velocity(Law::LuGre), p, v_d, 2.0, 1e-9);
    assert!(
        (out.f_mean - f_mean_ref).abs() < 1e-6 * f_c,
        "F_mean {} vs {f_mean_ref}",
        out.f_mean
    );
    assert!(
        (out.f_fx - f_end_ref).abs() < 1e-5 * f_c,
        "F_Fx {} vs {f_end_ref}",
        out.f_fx
    );
}

/// Steps a simulator with communication step `dt` and checks the invariants of `docs/model.md` at each point.
fn check_invariants(sim: &mut dyn Simulator, s_ss: f64, dt: f64, n: usize) {
    for k in 1..=n {
        sim.step_to(k as f64 * dt).unwrap();
        let o = sim.outputs();
        let s = o.s_x.hypot(o.s_y);
        assert!(
            s <= s_ss * (1.0 + 1e-12),
            "|s| = {s} > s_ss = {s_ss} at step {k}"
        );
        assert!(o.p_diss >= 0.0, "P_diss = {} < 0 at step {k}", o.p_diss);
        assert!(o.f_fx.is_finite() && o.x.is_finite() && o.f_mean.is_finite());
    }
}

#[test]
fn dahl_and_dupont_keep_their_invariants_at_coarse_tolerance() {
    for law in [Law::Dahl, Law::Dupont] {
        for r_ba in [0.0, 0.5, 0.999] {
            if law == Law::Dahl && r_ba != 0.5 {
                continue;
            }
            for (motion, drive) in [
                (Motion::Longitudinal, Drive::Velocity),
                (Motion::Longitudinal, Drive::Force),
                (Motion::Planar, Drive::Force),
                (Motion::Planar, Drive::Spring),
            ] {
                let mut p = Params::default();
                p.r_ba = r_ba;
                p.u0 = 1e-6;
                p.angle = 0.8;
                let c = config(law, motion, drive, Lateral::Guided);
                let mut sim = build(c, p, 0.0, 1e-3).unwrap();
                sim.set_input(
                    if drive == Drive::Force {
                        InputId::FD
                    } else {
                        InputId::VD
                    },
                    if drive == Drive::Force { 9.0 } else { 1e-3 },
                )
                .unwrap();
                check_invariants(sim.as_mut(), p.f_c() / p.k_t, 1e-4, 500);
            }
        }
    }
}

#[test]
fn paper_claims_hold() {
    let p = Params::default();
    let v_a = p.v_a();
    // No longitudinal reduction while v_a <= v_d (Eqs. 12, 15).
    for psi in [1.0, 1.2, 2.0] {
        let o = run_velocity(longitudinal_velocity(Law::Dahl), p, psi * v_a, 40.0, 1e-8);
        assert!(
            o.reduction.abs() < 1e-6,
            "psi {psi}: reduction {}",
            o.reduction
        );
    }
    // Transverse reduction at any amplitude, growing with the amplitude.
    let mut prev = 0.0;
    for u0 in [2e-9, 2e-8, 2e-7, 2e-6] {
        let mut q = p;
        q.u0 = u0;
        transverse(&mut q);
        let o = run_velocity(transverse_velocity(Lateral::Free), q, 1e-3, 40.0, 1e-8);
        assert!(o.reduction > prev, "u0 {u0}: {} !> {prev}", o.reduction);
        prev = o.reduction;
    }
    assert!(prev > 0.0);
    // Above the threshold, longitudinal reduction exceeds transverse. Near the threshold this
    // needs a contact stiff against the amplitude: at the default u0·k_t/F_C = 1.8 and psi = 0.8
    // the elastic contact gives F_mean/F_C = 0.856 longitudinal against 0.761 transverse
    // (reduction 0.144 against 0.239).
    for (psi, k_t) in [(0.2, 1e8), (0.5, 1e8), (0.8, 1e10)] {
        let mut p = p;
        p.k_t = k_t;
        let long = run_velocity(longitudinal_velocity(Law::Dahl), p, psi * v_a, 40.0, 1e-8);
        let mut q = p;
        transverse(&mut q);
        let tr = run_velocity(transverse_velocity(Lateral::Free), q, psi * v_a, 40.0, 1e-8);
        assert!(
            long.reduction > tr.reduction,
            "psi {psi}: {} !> {}",
            long.reduction,
            tr.reduction
        );
    }
    // psi alone does not fix the reduction: same psi, different (u0, f).
    let mut a = p;
    a.u0 = 2e-7;
    a.f = 2000.0;
    let mut b = p;
    b.u0 = 8e-7;
    b.f = 500.0;
    assert!((a.v_a() - b.v_a()).abs() < 1e-15);
    let ra = run_velocity(longitudinal_velocity(Law::Dahl), a, 1e-3, 40.0, 1e-8).reduction;
    let rb = run_velocity(longitudinal_velocity(Law::Dahl), b, 1e-3, 40.0, 1e-8).reduction;
    assert!((ra - rb).abs() > 1e-2, "{ra} vs {rb}");
}

#[test]
fn zero_load_or_zero_friction_gives_zero_friction_without_nan() {
    for law in [Law::Dahl, Law::Dupont, Law::LuGre] {
        for (f_n, mu) in [(0.0, 0.2), (55.0, 0.0)] {
            let mut p = Params::default();
            p.f_n = f_n;
            p.mu = mu;
            // LuGre's static force follows the load (F_S is given at 55 N, mu = 0.2): none here.
            assert_eq!(p.static_force(), 0.0);
            for c in [
                longitudinal_velocity(law),
                config(law, Motion::Planar, Drive::Force, Lateral::Guided),
                config(law, Motion::Longitudinal, Drive::Spring, Lateral::Guided),
            ] {
                let mut sim = build(c, p, 0.0, 1e-6).unwrap();
                sim.set_input(
                    if c.drive == Drive::Force {
                        InputId::FD
                    } else {
                        InputId::VD
                    },
                    1e-3,
                )
                .unwrap();
                sim.step_to(5e-3).unwrap();
                let o = sim.outputs();
                assert_eq!(o.f_fx, 0.0, "{law:?} F_N {f_n} mu {mu}: {o:?}");
                assert_eq!(o.f_mean, 0.0);
                assert_eq!(o.reduction, 0.0);
                assert!(o.x.is_finite() && o.v_x.is_finite() && o.p_diss == 0.0);
            }
        }
    }
    // LuGre with a static force but no load stays finite: a contact given without a reference
    // load takes F_S as it is, 14.3 N against F_C = 0.
    let mut p = Params::default();
    p.f_n = 0.0;
    p.f_n_ref = 0.0;
    assert_eq!(p.static_force(), 14.3);
    let o = run_velocity(longitudinal_velocity(Law::LuGre), p, 1e-3, 10.0, 1e-6);
    assert!(o.f_fx.is_finite() && o.f_mean.is_finite());
}

#[test]
fn without_vibration_the_plain_sliding_force_remains() {
    let v_d = 1e-3;
    for (u0, f) in [(0.0, 2000.0), (2e-7, 0.0)] {
        let mut p = Params::default();
        p.u0 = u0;
        p.f = f;
        // Dahl: F = F_C·(1 − exp(−v_d·t/s_ss)), fully developed after 1 ms (v_d·t/s_ss = 9e3).
        let mut sim = build(longitudinal_velocity(Law::Dahl), p, 0.0, 1e-8).unwrap();
        sim.set_input(InputId::VD, v_d).unwrap();
        sim.step_to(5e-3).unwrap();
        let o = sim.outputs();
        assert!((o.f_fx - p.f_c()).abs() < 1e-12 * p.f_c());
        assert!(o.reduction.abs() < 1e-9, "u0 {u0} f {f}: {}", o.reduction);
        // LuGre: the Stribeck curve plus the viscous term.
        p.h_v = 30.0;
        let mut sim = build(longitudinal_velocity(Law::LuGre), p, 0.0, 1e-8).unwrap();
        sim.set_input(InputId::VD, v_d).unwrap();
        sim.step_to(5e-3).unwrap();
        let expect = p.f_c() + (p.f_s - p.f_c()) * (-(v_d / p.v_s).powi(2)).exp() + p.h_v * v_d;
        let o = sim.outputs();
        assert!(
            (o.f_fx - expect).abs() < 1e-9 * expect,
            "{} vs {expect}",
            o.f_fx
        );
        assert!((o.f_mean - expect).abs() < 1e-9 * expect);
    }
}

#[test]
fn spring_drive_settles_to_the_coulomb_force_without_vibration() {
    let mut p = Params::default();
    p.u0 = 0.0;
    let c = config(
        Law::Dahl,
        Motion::Longitudinal,
        Drive::Spring,
        Lateral::Guided,
    );
    let mut sim = build(c, p, 0.0, 1e-8).unwrap();
    sim.set_input(InputId::VD, 1e-3).unwrap();
    // The spring-mass transient decays at (c_d/2m + Dahl damping) ≥ 8.9 1/s.
    sim.step_to(4.0).unwrap();
    let o = sim.outputs();
    // Steady sliding at v_d: the spring carries F_C, the damper nothing.
    assert!((o.f_d - p.f_c()).abs() < 1e-6 * p.f_c(), "F_d = {}", o.f_d);
    assert!((o.v_x - 1e-3).abs() < 1e-9);
}

#[test]
fn snapshot_restore_continues_bit_for_bit_in_a_fresh_simulator() {
    for c in [
        longitudinal_velocity(Law::Dupont),
        config(Law::LuGre, Motion::Planar, Drive::Force, Lateral::Guided),
        transverse_velocity(Lateral::Free),
        // The explicit path (its branch and step are saved), longitudinal and planar.
        config(
            Law::Dahl,
            Motion::Longitudinal,
            Drive::Spring,
            Lateral::Guided,
        ),
        config(Law::Dahl, Motion::Planar, Drive::Force, Lateral::Guided),
    ] {
        let p = Params::default();
        let mut a = build(c, p, 0.0, 1e-6).unwrap();
        a.set_input(
            if c.drive == Drive::Force {
                InputId::FD
            } else {
                InputId::VD
            },
            4.0e-3,
        )
        .unwrap();
        a.step_to(1.3e-3).unwrap();
        let snap = a.snapshot();
        let mut b = build(c, p, 0.0, 1e-6).unwrap();
        b.restore(&snap).unwrap();
        for k in 1..=5 {
            let t = 1.3e-3 + k as f64 * 7e-4;
            a.step_to(t).unwrap();
            b.step_to(t).unwrap();
            let (oa, ob) = (a.outputs(), b.outputs());
            assert_eq!(format!("{oa:?}"), format!("{ob:?}"));
            assert_eq!(oa.f_fx.to_bits(), ob.f_fx.to_bits());
        }
        // A snapshot of another configuration is refused and changes nothing.
        let other = build(longitudinal_velocity(Law::Dahl), p, 0.0, 1e-6).unwrap();
        let before = b.outputs();
        assert!(b.restore(&other.snapshot()).is_err());
        assert_eq!(format!("{before:?}"), format!("{:?}", b.outputs()));
    }
}

/// Longitudinal velocity drive of a law given by its rate and force, against RK4 over two
/// periods: F_mean over the second period and F_Fx at the end.
fn check_velocity_drive_against_rk4(
    law: Law,
    p: Params,
    v_d: f64,
    rate: impl Fn(f64, f64) -> f64 + Copy,
    force: impl Fn(f64) -> f64 + Copy,
) {
    let (v_a, w) = (p.v_a(), p.omega());
    let vr = move |t: f64| v_d - v_a * (w * t).cos();
    let period = 1.0 / p.f;
    let f1 = move |t: f64, y: &[f64; 1]| [rate(y[0], vr(t))];
    let f2 = move |t: f64, y: &[f64; 2]| [rate(y[0], vr(t)), force(y[0])];
    let run = |n: usize| {
        let s1 = rk4(&f1, 0.0, [0.0], period, n, &mut |_, _| {})[0];
        rk4(&f2, period, [s1, 0.0], 2.0 * period, n, &mut |_, _| {})
    };
    let (r1, r2) = (run(100_000), run(200_000));
    let f_c = p.f_c();
    assert!(
        ((r1[1] - r2[1]) / period).abs() < 1e-8 * f_c,
        "reference not converged"
    );
    let out = run_velocity(longitudinal_velocity(law), p, v_d, 2.0, 1e-9);
    let f_mean_ref = r2[1] / period;
    assert!(
        (out.f_mean - f_mean_ref).abs() < 1e-6 * f_c,
        "{law:?}: F_mean {} vs {f_mean_ref}",
        out.f_mean
    );
    assert!(
        (out.f_fx - force(r2[0])).abs() < 1e-5 * f_c,
        "{law:?}: F_Fx {} vs {}",
        out.f_fx,
        force(r2[0])
    );
}

#[test]
fn dahl_with_exponent_matches_reference_runge_kutta() {
    for kappa in [0.5, 2.0] {
        let mut p = Params::default();
        p.kappa = kappa;
        let (s_ss, k_t) = (p.f_c() / p.k_t, p.k_t);
        // ds/dt = v_r·|w|^kappa·sgn(w), w = 1 − sgn(v_r)·s/s_ss (`docs/model.md`)
        let rate = move |s: f64, vr: f64| {
            let w = 1.0 - vr.signum() * s / s_ss;
            vr * w.abs().powf(kappa) * w.signum()
        };
        check_velocity_drive_against_rk4(Law::Dahl, p, 1e-3, rate, move |s| k_t * s);
    }
}

/// The exponents the literature uses, down to 0.1 where `w` reaches 0 in finite displacement
/// (the deformation then sits at `±s_ss`, a kink), against the exact solution over 400
/// periods, at tolerances 1e-6 and 1e-9.
#[test]
fn dahl_with_exponents_matches_its_exact_solution() {
    for kappa in [0.1, 0.2, 0.5, 2.0] {
        let mut p = Params::default();
        p.kappa = kappa;
        let exact = ExactDahl::new(&p, 1e-3);
        let f_mean = exact.f_mean_after_periods(400);
        for tol in [1e-6, 1e-9] {
            let out = run_velocity(longitudinal_velocity(Law::Dahl), p, 1e-3, 400.0, tol);
            assert!(
                (out.f_mean - f_mean).abs() <= tol * p.f_c(),
                "kappa {kappa}, tol {tol}: F_mean {} vs {f_mean}",
                out.f_mean
            );
        }
    }
}

#[test]
fn dupont_matches_reference_runge_kutta() {
    for r_ba in [0.0, 0.5, 0.9] {
        let mut p = Params::default();
        p.r_ba = r_ba;
        let (s_ss, k_t) = (p.f_c() / p.k_t, p.k_t);
        let s_ba = r_ba * s_ss;
        // Dupont, Hayward, Armstrong, Altpeter (2002), written out with |s| and the direction test.
        let rate = move |s: f64, vr: f64| {
            let alpha = if s * vr <= 0.0 || s.abs() <= s_ba {
                0.0
            } else if s.abs() >= s_ss {
                1.0
            } else {
                0.5 * (std::f64::consts::PI * (s.abs() - 0.5 * (s_ss + s_ba)) / (s_ss - s_ba)).sin()
                    + 0.5
            };
            vr - alpha * vr.abs() * s / s_ss
        };
        check_velocity_drive_against_rk4(Law::Dupont, p, 1e-3, rate, move |s| k_t * s);
    }
}

/// Planar Dupont contact under force drive (the contact-dupont scene): `F_Fx` on a 0.1 ms grid
/// through several reversals, against a reference Runge–Kutta integration written out here,
/// at tight tolerances. A Newton iteration stopped on a stale contraction estimate once left
/// a 6e-5 error in one reversal at tolerance 1e-10 while 1e-9 and 1e-12 were right.
#[test]
fn planar_dupont_force_drive_follows_reference_at_tight_tolerances() {
    let p = Params::default();
    let f_d = 8.0;
    let s_ss = p.f_c() / p.k_t;
    let s_ba = p.r_ba * s_ss;
    let (v_a, w, m, k_t) = (p.v_a(), p.omega(), p.m, p.k_t);
    // Dupont, Hayward, Armstrong, Altpeter (2002): alpha from |s|, zero when s and v_r point
    // apart; the planar form with the Euclidean norm (`docs/model.md`).
    let alpha = move |s: [f64; 2], vr: [f64; 2]| {
        let z = s[0].hypot(s[1]);
        if s[0] * vr[0] + s[1] * vr[1] <= 0.0 || z <= s_ba {
            0.0
        } else if z >= s_ss {
            1.0
        } else {
            0.5 * (std::f64::consts::PI * (z - 0.5 * (s_ss + s_ba)) / (s_ss - s_ba)).sin() + 0.5
        }
    };
    // y = [s_x, s_y, x, y, v_x, v_y]
    let f = move |t: f64, y: &[f64; 6]| {
        let vr = [y[4] - v_a * (w * t).cos(), y[5]];
        let s = [y[0], y[1]];
        let a = alpha(s, vr) * vr[0].hypot(vr[1]) / s_ss;
        [
            vr[0] - a * s[0],
            vr[1] - a * s[1],
            y[4],
            y[5],
            (f_d - k_t * y[0]) / m,
            -k_t * y[1] / m,
        ]
    };
    let n_samples = 60; // to 6 ms: 12 periods, 24 reversals
    let reference = |steps_per_sample: usize| {
        let mut out = vec![];
        let mut y = [0.0; 6];
        for k in 0..n_samples {
            let (t0, t1) = (k as f64 * 1e-4, (k + 1) as f64 * 1e-4);
            y = rk4(&f, t0, y, t1, steps_per_sample, &mut |_, _| {});
            out.push(k_t * y[0]);
        }
        out
    };
    let (r1, r2) = (reference(20_000), reference(40_000));
    let f_c = p.f_c();
    let ref_err = r1
        .iter()
        .zip(&r2)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(ref_err < 1e-9 * f_c, "reference not converged: {ref_err:e}");
    let c = config(Law::Dupont, Motion::Planar, Drive::Force, Lateral::Guided);
    for tol in [1e-8, 1e-9, 1e-10, 1e-11, 1e-12] {
        let mut sim = build(c, p, 0.0, tol).unwrap();
        sim.set_input(InputId::FD, f_d).unwrap();
        let mut worst: f64 = 0.0;
        for (k, r) in r2.iter().enumerate() {
            sim.step_to((k + 1) as f64 * 1e-4).unwrap();
            worst = worst.max((sim.outputs().f_fx - r).abs());
        }
        // A reversal amplifies small shifts in time: allow 100× the tolerance, plus the
        // reference's own error (measured: 3.6, 16, 54, 24 and 22 × tol from 1e-8 to 1e-12;
        // the stale-contraction bug gave 6500 to 5.8e5 × tol).
        assert!(
            worst <= 100.0 * tol * f_c + 10.0 * ref_err,
            "tol {tol:e}: max F_Fx error {:e}·F_C",
            worst / f_c
        );
    }
}
