//! Bounded work and ranges: a communication step that would need more than `max_steps`
//! integrator steps stops at once with the instance as it was; a step over more windows than
//! can be counted likewise; values outside their accepted range are refused naming the rule;
//! tolerances are clamped to the range the integrators resolve.

mod support;

use support::scenes::{scene, standard_scenes, start, state_count, STANDARD_SCENES};
use vibrofric::model::{build, InputId, OutputId, SimError, TOLERANCE_RANGE};
use vibrofric::solver::SolverError;
use vibrofric::table::ParamId;

#[test]
fn a_step_beyond_max_steps_stops_and_changes_nothing() {
    let mut sc = scene("contact.toml");
    ParamId::MaxSteps.set(&mut sc.start, 1e4).unwrap();
    let mut sim = start(&sc, 1e-6);
    sim.step_to(1e-3).unwrap();
    let before = (sim.time(), sim.outputs());
    // 1e6 s of 2 kHz vibration on Radau: ~1e11 steps.
    match sim.step_to(1e6) {
        Err(SimError::Solver(SolverError::WorkLimit { limit, .. })) => assert_eq!(limit, 1e4),
        other => panic!("{other:?}"),
    }
    assert_eq!((sim.time(), sim.outputs()), before);
    let msg = sim.step_to(1e6).unwrap_err().to_string();
    assert!(
        msg.contains("max_steps = 1e4") && msg.contains("shorter communication steps"),
        "{msg}"
    );
    // And it goes on from where it was.
    sim.step_to(2e-3).unwrap();
    let o = sim.outputs();
    assert!(OutputId::ALL.iter().all(|id| id.get(&o).is_finite()));
}

#[test]
fn a_step_over_uncountably_many_windows_stops_at_once() {
    for file in [
        "contact.toml",
        "paper-longitudinal.toml",
        "paper-transverse-guided.toml",
    ] {
        let sc = scene(file);
        let mut sim = start(&sc, 1e-6);
        let before = (sim.time(), sim.outputs());
        for t in [1e300, 1e30] {
            assert!(
                matches!(
                    sim.step_to(t),
                    Err(SimError::Solver(SolverError::WorkLimit { .. }))
                ),
                "{file}: {t:e}"
            );
            assert_eq!((sim.time(), sim.outputs()), before, "{file}");
        }
    }
}

/// On the fast paths a step over 2e9 vibration periods (1e6 s) with held inputs is O(1) work.
#[test]
fn a_million_seconds_in_one_step_on_the_fast_paths() {
    for file in ["paper-longitudinal.toml", "paper-transverse-guided.toml"] {
        let sc = scene(file);
        let mut sim = start(&sc, 1e-6);
        sim.step_to(1e6).unwrap();
        let o = sim.outputs();
        assert!(
            OutputId::ALL.iter().all(|id| id.get(&o).is_finite()),
            "{file}"
        );
        assert!(
            sim.stats().steps < 10_000,
            "{file}: {} steps",
            sim.stats().steps
        );
    }
}

#[test]
fn values_outside_their_range_are_refused_with_the_rule() {
    let sc = scene("paper-longitudinal.toml");
    let mut sim = start(&sc, 1e-6);
    let e = sim.set_input(InputId::VD, 2e3).unwrap_err().to_string();
    assert_eq!(e, "v_d = 2000: must be in [-1000, 1000] m/s");
    let e = sim
        .set_input_derivative(InputId::VD, 1e300)
        .unwrap_err()
        .to_string();
    assert!(e.contains("derivative of v_d") && e.contains("1e12"), "{e}");
    let e = sim.set_param(ParamId::F, 1e8).unwrap_err().to_string();
    assert_eq!(e, "f = 1e8: must be in [0, 1e7] Hz");
    // A Dahl exponent of 0.2 is physics: the closed form takes it under velocity drive; under a
    // spring drive (Radau) the range starts at 0.5.
    let mut p = sc.start;
    ParamId::Kappa.set(&mut p, 0.2).unwrap();
    assert!(build(sc.config, p, 0.0, 1e-6).is_ok());
    let rig = scene("rig-longitudinal.toml");
    let e = build(rig.config, p, 0.0, 1e-6).err().unwrap().to_string();
    assert_eq!(e, "kappa = 0.2: must be in [0.5, 20]");
}

#[test]
fn tolerances_are_clamped_to_what_the_integrators_resolve() {
    let sc = scene("contact.toml");
    for (asked, used) in [
        (5e-324, TOLERANCE_RANGE.0),
        (1e-13, TOLERANCE_RANGE.0),
        (1e-6, 1e-6),
        (0.5, TOLERANCE_RANGE.1),
    ] {
        let mut sim = build(sc.config, sc.start, 0.0, asked).unwrap();
        assert_eq!(sim.tolerance(), used);
        sim.step_to(1e-3).unwrap();
    }
}

/// fmi2Instantiate refuses an empty instance name and a resource location whose byte 5 falls
/// inside a character (it panicked), each with a log line.
#[test]
fn instantiate_refuses_with_a_log_line() {
    let fmu = support::fmu::load("contact.toml", "instantiate-refusals");
    let guid = fmu.description.guid.clone();
    let uri = fmu.resource_uri();
    for (name, location, why) in [
        ("", uri.as_str(), "instanceName = \"\""),
        ("a", "fileé///x/", "must be a file: URI"),
    ] {
        let (inst, log) = fmu.instantiate_with(name, 1, Some(&guid), Some(location), false);
        assert!(inst.is_none(), "{why}");
        assert!(
            log.iter().any(|r| r.message.contains(why)),
            "{why}: {log:?}"
        );
    }
}

/// Every value inside a documented range evaluates to finite outputs, also at the edges of
/// floating point: a Coulomb force `mu·F_N` down to the smallest subnormal (where
/// `1 − F_mean/F_C` overflowed and fmi2GetReal failed), a tiny normal force input with a steep
/// derivative, and a relaxation rate `|v_r|/s_ss` that overflowed to a NaN derivative.
#[test]
fn accepted_values_at_the_edges_of_floating_point_evaluate() {
    use support::fmu::{all_vrs, load, started, vr};
    use vibrofric_import::Status;
    let cases: [(&str, &[(u32, f64)]); 12] = [
        ("drill-string-axial.toml", &[(vr::F_N, 1.5e-323)]),
        ("drill-string-axial.toml", &[(vr::F_N, 1e-310)]),
        ("drill-string-axial.toml", &[(vr::F_N, 1.5e-307)]),
        ("drill-string-axial.toml", &[(vr::MU, 5e-324)]),
        ("contact-lugre.toml", &[(vr::F_N, 5e-324)]),
        ("contact-lugre.toml", &[(vr::MU, 1e-300)]),
        ("contact.toml", &[(vr::MU, 1e-300), (vr::V_SY, -1000.0)]),
        (
            "contact-dupont.toml",
            &[(vr::MU, 1e-300), (vr::V_SY, -1000.0)],
        ),
        ("paper-longitudinal.toml", &[(vr::F_N, 5e-324)]),
        ("paper-longitudinal.toml", &[(vr::MU, 1e-295)]),
        ("paper-transverse.toml", &[(vr::MU, 1e-300)]),
        ("rig-transverse.toml", &[(vr::F_N, 1e-308)]),
    ];
    for (file, init) in cases {
        let sc = scene(file);
        let vrs = all_vrs(&sc);
        let fmu = load(file, &format!("edges-{file}"));
        let mut i = started(&fmu, "edges", init);
        for k in 0..3 {
            let t = k as f64 * 1e-3;
            assert_eq!(
                i.do_step(t, 1e-3),
                Status::Ok,
                "{file} {init:?}: {}",
                i.last_message()
            );
            let v = i.get_real(&vrs);
            assert!(v.is_ok(), "{file} {init:?}: {}", i.last_message());
            assert!(v.unwrap().iter().all(|x| x.is_finite()), "{file} {init:?}");
        }
        // Under the velocity drive a Coulomb force that acts as none has no reduction.
        if sc.has_vr(vr::REDUCTION) {
            assert_eq!(
                i.get_real(&[vr::REDUCTION]).unwrap(),
                [0.0],
                "{file} {init:?}"
            );
        }
    }
    // The normal force input 1e-308 N with a derivative of 1e6 N/s over a step.
    let file = "drill-string-contact.toml";
    let vrs = all_vrs(&scene(file));
    let fmu = load(file, "edges-input");
    let mut i = started(&fmu, "edges", &[]);
    assert_eq!(i.set_real(&[vr::F_N], &[1e-308]), Status::Ok);
    assert_eq!(
        i.set_real_input_derivatives(&[vr::F_N], &[1], &[1e6]),
        Status::Ok
    );
    assert_eq!(i.do_step(0.0, 1e-3), Status::Ok, "{}", i.last_message());
    let v = i.get_real(&vrs);
    assert!(v.is_ok(), "{}", i.last_message());
    assert!(v.unwrap().iter().all(|x| x.is_finite()));
}

/// `reduction` is an output of the velocity drive only: under force and spring drives a stuck
/// body with no vibration would read `1 − F_d/F_C` (0.975 on the default scene), a reduction
/// the vibration did not cause.
#[test]
fn reduction_is_offered_only_under_the_velocity_drive() {
    use vibrofric::table::{Drive, OutputId};
    for (file, sc) in standard_scenes() {
        assert_eq!(
            sc.outputs.contains(&OutputId::Reduction),
            sc.config.drive == Drive::Velocity,
            "{file}"
        );
    }
    let fmu = support::fmu::load("contact.toml", "no-reduction");
    let mut i = support::fmu::started(&fmu, "r", &[(support::fmu::vr::U0, 0.0)]);
    assert!(i.get_real(&[support::fmu::vr::REDUCTION]).is_err());
    assert!(
        i.last_message().contains("is not a variable of this FMU"),
        "{}",
        i.last_message()
    );
}

/// Model Exchange: states set far from any trajectory (a deformation far beyond what the law
/// holds) are outside the model's domain: the evaluations answer fmi2Discard naming the states,
/// nothing changes, and the instance goes on (set time, other states, terminate). They used to
/// answer fmi2Error ("P_diss evaluates to inf"), after which fmi2SetTime and fmi2Terminate were
/// refused, or evaluate absurd values with fmi2OK.
#[test]
fn model_exchange_states_far_from_any_trajectory_are_discarded() {
    use support::fmu::{all_vrs, bits, load, vr};
    use vibrofric_import::Status;
    for file in STANDARD_SCENES {
        let sc = scene(file);
        let vrs = all_vrs(&sc);
        let (nx, ni) = (state_count(&sc), sc.config.event_indicators());
        let fmu = load(file, &format!("domain-{file}"));
        let mut i = fmu.instantiate_model_exchange("domain").unwrap();
        assert_eq!(i.enter_initialization_mode(), Status::Ok);
        assert_eq!(i.exit_initialization_mode(), Status::Ok);
        assert_eq!(i.new_discrete_states().0, Status::Ok);
        assert_eq!(i.enter_continuous_time_mode(), Status::Ok);
        let good = i.get_derivatives(nx).unwrap();
        let outputs = i.get_real(&vrs).unwrap();
        let mut states = vec![0.0; nx];
        let f = fmu.model_exchange.unwrap();
        assert_eq!(
            unsafe { (f.fmi2GetContinuousStates)(i.raw(), states.as_mut_ptr(), nx) },
            0
        );
        // The first state is the deformation s_x: 1 m, where the law holds about 1e-7 m.
        let mut far = states.clone();
        far[0] = 1.0;
        assert_eq!(i.set_continuous_states(&far), Status::Ok);
        assert_eq!(i.get_derivatives(nx).err(), Some(Status::Discard), "{file}");
        let msg = i.last_message();
        assert!(
            msg.contains("outside the model's domain") && msg.contains("contact.s_x = 1,"),
            "{file}: {msg}"
        );
        assert_eq!(
            i.get_event_indicators(ni).err(),
            Some(Status::Discard),
            "{file}"
        );
        assert_eq!(
            i.get_real(&[vr::F_FX]).err(),
            Some(Status::Discard),
            "{file}"
        );
        // Parameters and inputs still read; the instance goes on.
        assert!(i.get_real(&[vr::MU]).is_ok());
        assert_eq!(i.set_time(1e-4), Status::Ok, "{file}: {}", i.last_message());
        assert_eq!(i.set_time(0.0), Status::Ok);
        // Back on the trajectory, the same evaluations as before the excursion.
        assert_eq!(i.set_continuous_states(&states), Status::Ok);
        assert_eq!(bits(&i.get_derivatives(nx).unwrap()), bits(&good), "{file}");
        assert_eq!(bits(&i.get_real(&vrs).unwrap()), bits(&outputs), "{file}");
        assert_eq!(i.terminate(), Status::Ok, "{file}: {}", i.last_message());
    }
}

/// An importer's unstable integrator (forward Euler with a 1 ms step, fmusim's default, on a
/// contact whose relaxation takes microseconds) runs off every trajectory: the FMU answers
/// fmi2Discard within a few steps, naming the states, instead of evaluating ever larger
/// values with fmi2OK (`P_diss` off by 1e63) or failing with fmi2Error.
#[test]
fn an_unstable_importer_integration_is_discarded_within_a_few_steps() {
    use support::fmu::{load, vr};
    use vibrofric_import::Status;
    for file in [
        "paper-longitudinal.toml",
        "paper-transverse-guided.toml",
        "contact.toml",
    ] {
        let sc = scene(file);
        let nx = state_count(&sc);
        let fmu = load(file, &format!("euler-{file}"));
        let mut i = fmu.instantiate_model_exchange("euler").unwrap();
        assert_eq!(i.setup_experiment(None, 0.0, None), Status::Ok);
        assert_eq!(i.enter_initialization_mode(), Status::Ok);
        assert_eq!(i.exit_initialization_mode(), Status::Ok);
        assert_eq!(i.new_discrete_states().0, Status::Ok);
        assert_eq!(i.enter_continuous_time_mode(), Status::Ok);
        let f = fmu.model_exchange.unwrap();
        let mut x = vec![0.0; nx];
        assert_eq!(
            unsafe { (f.fmi2GetContinuousStates)(i.raw(), x.as_mut_ptr(), nx) },
            0
        );
        let (h, mut t) = (1e-3, 0.0);
        let mut discarded = None;
        for k in 0..1000 {
            let dx = match i.get_derivatives(nx) {
                Ok(dx) => dx,
                Err(s) => {
                    assert_eq!(s, Status::Discard, "{file}: {}", i.last_message());
                    discarded = Some(k);
                    break;
                }
            };
            match i.get_real(&[vr::F_FX]) {
                // The friction force stays within what the law's bound allows times the
                // domain's margin.
                Ok(v) => assert!(
                    v[0].abs() <= 1e3 * 1e3,
                    "{file}: F_Fx = {} at step {k}",
                    v[0]
                ),
                Err(s) => assert_eq!(s, Status::Discard),
            }
            for (xk, dk) in x.iter_mut().zip(&dx) {
                *xk += h * dk;
            }
            t += h;
            assert_eq!(i.set_time(t), Status::Ok);
            assert_eq!(i.set_continuous_states(&x), Status::Ok);
            assert_eq!(i.completed_integrator_step(), Status::Ok);
        }
        let k = discarded.unwrap_or_else(|| panic!("{file}: no discard in 1000 Euler steps"));
        assert!(k <= 20, "{file}: discarded only at step {k}");
        assert!(i.last_message().contains("s_x = "), "{}", i.last_message());
        // The instance is still usable: the time moves on, it terminates.
        assert_eq!(i.set_time(t + h), Status::Ok);
        assert_eq!(i.terminate(), Status::Ok, "{}", i.last_message());
    }
}
