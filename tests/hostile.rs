//! Bounded work and ranges: a communication step that would need more than `max_steps`
//! integrator steps stops at once with the instance as it was; a step over more windows than
//! can be counted likewise; values outside their accepted range are refused naming the rule;
//! tolerances are clamped to the range the integrators resolve.

#[allow(unused_macros)]
mod fmi_harness;

use std::path::Path as FsPath;

use vibrofric::description::scene::Scene;
use vibrofric::model::{build, InputId, OutputId, SimError, Simulator, TOLERANCE_RANGE};
use vibrofric::physics::ParamId;
use vibrofric::solver::SolverError;

fn scene(file: &str) -> Scene {
    Scene::load(FsPath::new("scenes").join(file).as_path()).unwrap()
}

fn start(sc: &Scene, tol: f64) -> Box<dyn Simulator> {
    let mut sim = build(sc.config, sc.start, 0.0, tol).unwrap();
    for id in InputId::ALL {
        if id.present(&sc.config) {
            sim.set_input(id, id.get(&sc.inputs)).unwrap();
        }
    }
    sim
}

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
    let fmu = fmi_harness::load("contact.toml", "instantiate-refusals");
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
