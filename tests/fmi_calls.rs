//! The FMU driven through its C interface as an importer drives it: full call sequences, the
//! state machine, status queries, logging, instantiation, and results equal to the core.

#[macro_use]
mod support;

use support::fmu::*;
use support::scenes::*;
use vibrofric::description::variables::{Causality, VarKind};
use vibrofric::description::Scene;
use vibrofric::model::{self, InputId, Inputs, OutputId, Simulator};
use vibrofric::table::Params;
use vibrofric_import::{Functions, Importer, Status};

const H: f64 = 1e-3;

/// The core as the FMU drives it: built at `t0` with the staged parameters and every input the
/// scene has.
fn core(scene: &Scene, params: Params, inputs: Inputs, tol: f64) -> Box<dyn Simulator> {
    model::Setup::new(scene.config, params)
        .inputs(inputs)
        .tolerance(tol)
        .build()
        .unwrap()
}

/// Every variable of the scene, read from the core.
fn core_values(scene: &Scene, sim: &dyn Simulator, inputs: &Inputs) -> Vec<f64> {
    let o = sim.outputs();
    scene
        .variables()
        .map(|v| match (v.kind, v.causality(&scene.config)) {
            (VarKind::Param(p), _) => p.get(sim.params()),
            (VarKind::Input(i), Causality::Input) => i.get(inputs),
            (VarKind::Input(_), _) => OutputId::FDrive.get(&o),
            (VarKind::Output(id), _) => id.get(&o),
            (VarKind::State(x), _) => sim.states()[x.index()],
            (VarKind::Derivative(x), _) => sim.derivatives()[x.index()],
            (VarKind::Indicator(i), _) => {
                let mut z = [0.0; 3];
                sim.event_indicators(&mut z[..scene.config.event_indicators()]);
                z[i.index(&scene.config)]
            }
        })
        .collect()
}

#[test]
fn exports_every_common_and_cosimulation_function() {
    let fmu = load("contact.toml", "exports");
    assert_eq!(Functions::NAMES.len(), 34);
    assert_eq!(fmu.version(), "2.0");
    assert_eq!(fmu.types_platform(), "default");
    assert_eq!(fmu.description.model_identifier, "VibratingContact");
}

#[test]
fn full_call_sequence_equals_the_core_called_directly() {
    let fmu = load("contact.toml", "core");
    let scene = scene("contact.toml");
    let vrs = all_vrs(&scene);
    let mut i = started(&fmu, "fmu", &[]);
    let mut sim = core(&scene, scene.start, scene.inputs, 1e-6);
    let mut inputs = scene.inputs;
    assert_eq!(
        bits(&i.get_real(&vrs).unwrap()),
        bits(&core_values(&scene, sim.as_ref(), &inputs))
    );
    let mut t = 0.0;
    for k in 0..30 {
        // Every few steps the master also gives F_d's slope, as a master that interpolates.
        let slope = (k % 3 == 0).then(|| 100.0 * (k as f64).cos());
        ok!(i, i.set_real(&[vr::F_D], &[drive(k)]));
        sim.set_input(InputId::FD, drive(k)).unwrap();
        inputs.f_d = drive(k);
        if let Some(d) = slope {
            ok!(i, i.set_real_input_derivatives(&[vr::F_D], &[1], &[d]));
            sim.set_input_derivative(InputId::FD, d).unwrap();
        }
        ok!(i, i.do_step(t, H));
        sim.step_to(t + H).unwrap();
        t += H;
        assert_eq!(
            bits(&i.get_real(&vrs).unwrap()),
            bits(&core_values(&scene, sim.as_ref(), &inputs)),
            "step {k}"
        );
    }
    // The end of the last step: the instant the master meant (its t += H drifts by ulps).
    let (s, last) = i.get_real_status(2);
    assert_eq!((s, last), (Status::Ok, vibrofric::model::canonical_time(t)));
    assert!((last - t).abs() <= 1e-15);
    ok!(i, i.terminate());
    assert!(
        i.get_real(&vrs).is_ok(),
        "outputs can be read after fmi2Terminate"
    );
}

#[test]
fn tolerance_of_setup_experiment_reaches_the_integrator() {
    let fmu = load("contact.toml", "tolerance");
    let scene = scene("contact.toml");
    let vrs = all_vrs(&scene);
    for tol in [None, Some(1e-8), Some(1e-4)] {
        let mut i = fmu.instantiate("tol").unwrap();
        ok!(i, i.setup_experiment(tol, 0.0, None));
        ok!(i, i.enter_initialization_mode());
        ok!(i, i.exit_initialization_mode());
        let mut sim = core(&scene, scene.start, scene.inputs, tol.unwrap_or(1e-6));
        for k in 0..3 {
            ok!(i, i.do_step(k as f64 * H, H));
            sim.step_to(k as f64 * H + H).unwrap();
        }
        assert_eq!(
            bits(&i.get_real(&vrs).unwrap()),
            bits(&core_values(&scene, sim.as_ref(), &scene.inputs)),
            "tolerance {tol:?}"
        );
    }
}

#[test]
fn initialization_mode_reads_outputs_consistent_with_the_staged_values() {
    // LuGre: F_F depends directly on the support velocity input.
    let fmu = load("contact-lugre.toml", "init-outputs");
    let scene = scene("contact-lugre.toml");
    let vrs = all_vrs(&scene);
    let mut i = fmu.instantiate("init").unwrap();
    ok!(i, i.enter_initialization_mode());
    let mut params = scene.start;
    let mut inputs = scene.inputs;
    ok!(i, i.set_real(&[vr::V_SX, vr::F_N], &[1e-3, 30.0]));
    inputs.v_sx = 1e-3;
    params.f_n = 30.0;
    let sim = core(&scene, params, inputs, 1e-6);
    let got = i.get_real(&vrs).unwrap();
    assert_eq!(
        bits(&got),
        bits(&core_values(&scene, sim.as_ref(), &inputs))
    );
    // Changing the staged input changes the outputs read in initialization mode.
    let f1 = i.get_real(&[vr::F_FX]).unwrap()[0];
    ok!(i, i.set_real(&[vr::V_SX], &[0.0]));
    inputs.v_sx = 0.0;
    let f0 = i.get_real(&[vr::F_FX]).unwrap()[0];
    assert_ne!(f0, f1, "F_Fx must feel v_sx at t0");
    let sim = core(&scene, params, inputs, 1e-6);
    assert_eq!(f0.to_bits(), sim.outputs().f_fx.to_bits());
    ok!(i, i.exit_initialization_mode());
}

#[test]
fn calls_out_of_order_return_error_naming_function_and_state() {
    let fmu = load("contact.toml", "order");
    type Call = fn(&mut vibrofric_import::Instance) -> Status;
    // (set-up calls, the call out of order, its name, the state it is made in)
    let cases: Vec<(usize, Call, &str, &str)> = vec![
        (0, |i| i.do_step(0.0, 1e-3), "fmi2DoStep", "Instantiated"),
        (
            0,
            |i| i.exit_initialization_mode(),
            "fmi2ExitInitializationMode",
            "Instantiated",
        ),
        (0, |i| i.terminate(), "fmi2Terminate", "Instantiated"),
        (
            0,
            |i| i.get_real(&[201]).err().unwrap_or(Status::Ok),
            "fmi2GetReal",
            "Instantiated",
        ),
        (
            1,
            |i| i.enter_initialization_mode(),
            "fmi2EnterInitializationMode",
            "InitializationMode",
        ),
        (
            1,
            |i| i.do_step(0.0, 1e-3),
            "fmi2DoStep",
            "InitializationMode",
        ),
        (
            1,
            |i| i.setup_experiment(None, 0.0, None),
            "fmi2SetupExperiment",
            "InitializationMode",
        ),
        (
            2,
            |i| i.setup_experiment(None, 0.0, None),
            "fmi2SetupExperiment",
            "StepComplete",
        ),
        (
            2,
            |i| i.enter_initialization_mode(),
            "fmi2EnterInitializationMode",
            "StepComplete",
        ),
        (
            2,
            |i| i.exit_initialization_mode(),
            "fmi2ExitInitializationMode",
            "StepComplete",
        ),
        (3, |i| i.do_step(0.0, 1e-3), "fmi2DoStep", "Terminated"),
        (
            3,
            |i| i.set_real(&[101], &[1.0]),
            "fmi2SetReal",
            "Terminated",
        ),
        (3, |i| i.terminate(), "fmi2Terminate", "Terminated"),
        (
            2,
            |i| unsafe { (i.functions().fmi2CancelStep)(i.raw()) }.into_status(),
            "fmi2CancelStep",
            "StepComplete",
        ),
        (
            0,
            |i| i.get_real_status(2).0,
            "fmi2GetRealStatus",
            "Instantiated",
        ),
    ];
    for (phase, call, name, state) in cases {
        let mut i = fmu.instantiate("order").unwrap();
        if phase >= 1 {
            ok!(i, i.enter_initialization_mode());
        }
        if phase >= 2 {
            ok!(i, i.exit_initialization_mode());
        }
        if phase >= 3 {
            ok!(i, i.terminate());
        }
        i.take_messages();
        assert_eq!(call(&mut i), Status::Error, "{name} in {state}");
        let log = i.take_messages();
        let line = log
            .iter()
            .find(|r| r.status == Status::Error)
            .unwrap_or_else(|| panic!("{name} in {state}: no error logged: {log:?}"));
        assert!(
            line.message.contains(name) && line.message.contains(state),
            "{name} in {state}: {}",
            line.message
        );
        assert_eq!(line.category, "logStatusError");
        // The standard's error state: the instance can still be reset and run.
        ok!(i, i.reset());
        ok!(i, i.enter_initialization_mode());
        ok!(i, i.exit_initialization_mode());
        ok!(i, i.do_step(0.0, 1e-3));
    }
}

trait IntoStatus {
    fn into_status(self) -> Status;
}

impl IntoStatus for i32 {
    fn into_status(self) -> Status {
        vibrofric_import::status(self)
    }
}

#[test]
fn status_queries_of_a_synchronous_slave() {
    let fmu = load("contact.toml", "status");
    let mut i = started(&fmu, "status", &[]);
    ok!(i, i.do_step(0.0, 2e-3));
    assert_eq!(i.get_real_status(2), (Status::Ok, 2e-3)); // fmi2LastSuccessfulTime
    assert_eq!(i.get_boolean_status(3), (Status::Ok, false)); // fmi2Terminated
    let f = *i.functions();
    let c = i.raw();
    unsafe {
        let mut st = 0;
        assert_eq!(
            (f.fmi2GetStatus)(c, 0, &mut st),
            2,
            "fmi2DoStepStatus: discard"
        );
        let mut n = 0;
        assert_eq!((f.fmi2GetIntegerStatus)(c, 0, &mut n), 2);
        let mut s = std::ptr::null();
        assert_eq!(
            (f.fmi2GetStringStatus)(c, 1, &mut s),
            2,
            "fmi2PendingStatus: discard"
        );
        let mut r = 0.0;
        assert_eq!((f.fmi2GetRealStatus)(c, 0, &mut r), 2);
        let mut b = 0;
        assert_eq!((f.fmi2GetBooleanStatus)(c, 2, &mut b), 2);
    }
    let log = i.take_messages();
    assert!(
        log.iter()
            .any(|r| r.status == Status::Discard && r.message.contains("fmi2Pending")),
        "{log:?}"
    );
    // fmi2Discard leaves the instance running.
    ok!(i, i.do_step(2e-3, 1e-3));
    ok!(i, i.terminate());
    assert_eq!(i.get_real_status(2), (Status::Ok, 3e-3));
}

#[test]
fn integer_boolean_and_string_access_has_no_variables() {
    let fmu = load("contact.toml", "types");
    let f = fmu.functions;
    let mut i = started(&fmu, "types", &[]);
    let c = i.raw();
    let vrs = [4u32];
    let mut iv = [0i32];
    let mut sv = [std::ptr::null::<std::os::raw::c_char>()];
    unsafe {
        assert_eq!((f.fmi2GetInteger)(c, vrs.as_ptr(), 0, iv.as_mut_ptr()), 0);
        assert_eq!((f.fmi2SetInteger)(c, vrs.as_ptr(), 0, iv.as_ptr()), 0);
        assert_eq!((f.fmi2GetBoolean)(c, vrs.as_ptr(), 0, iv.as_mut_ptr()), 0);
        assert_eq!((f.fmi2SetBoolean)(c, vrs.as_ptr(), 0, iv.as_ptr()), 0);
        assert_eq!((f.fmi2GetString)(c, vrs.as_ptr(), 0, sv.as_mut_ptr()), 0);
        assert_eq!((f.fmi2SetString)(c, vrs.as_ptr(), 0, sv.as_ptr()), 0);
    }
    type Probe = fn(&Functions, *mut std::ffi::c_void) -> i32;
    let probes: [(&str, Probe); 6] = [
        ("fmi2GetInteger", |f, c| unsafe {
            (f.fmi2GetInteger)(c, [4u32].as_ptr(), 1, [0].as_mut_ptr())
        }),
        ("fmi2SetInteger", |f, c| unsafe {
            (f.fmi2SetInteger)(c, [4u32].as_ptr(), 1, [0].as_ptr())
        }),
        ("fmi2GetBoolean", |f, c| unsafe {
            (f.fmi2GetBoolean)(c, [4u32].as_ptr(), 1, [0].as_mut_ptr())
        }),
        ("fmi2SetBoolean", |f, c| unsafe {
            (f.fmi2SetBoolean)(c, [4u32].as_ptr(), 1, [0].as_ptr())
        }),
        ("fmi2GetString", |f, c| unsafe {
            (f.fmi2GetString)(c, [4u32].as_ptr(), 1, [std::ptr::null()].as_mut_ptr())
        }),
        ("fmi2SetString", |f, c| unsafe {
            (f.fmi2SetString)(c, [4u32].as_ptr(), 1, [c"x".as_ptr()].as_ptr())
        }),
    ];
    for (name, probe) in probes {
        ok!(i, i.reset());
        ok!(i, i.enter_initialization_mode());
        i.take_messages();
        assert_eq!(probe(&f, i.raw()), 3, "{name}");
        let msg = i.last_message();
        assert!(
            msg.contains(name) && msg.contains("value reference 4") && msg.contains("k_t"),
            "{msg}"
        );
    }
}

#[test]
fn logging_honours_categories_with_percent_s_and_the_importer_environment() {
    let fmu = load("contact.toml", "logging");
    // Debug logging off: life-cycle events are not logged, errors are.
    let mut i = started(&fmu, "quiet", &[]);
    ok!(i, i.do_step(0.0, 1e-3));
    assert!(i.take_messages().is_empty());
    assert_eq!(i.set_real(&[999], &[1.0]), Status::Error);
    let log = i.take_messages();
    assert_eq!(log.len(), 1, "{log:?}");
    assert_eq!(log[0].category, "logStatusError");
    assert_eq!(log[0].format, "%s");
    assert_eq!(log[0].instance, "quiet");

    // On at instantiation: every category.
    let (i, log) = fmu.instantiate_with(
        "loud",
        1,
        Some(&fmu.description.guid),
        Some(&fmu.resource_uri()),
        true,
    );
    let mut i = i.unwrap();
    assert!(log
        .iter()
        .any(|r| r.category == "logEvents" && r.message.contains("fmi2Instantiate")));
    ok!(i, i.enter_initialization_mode());
    ok!(i, i.exit_initialization_mode());
    ok!(i, i.do_step(0.0, 1e-3));
    let log = i.take_messages();
    assert!(log.iter().any(|r| r.category == "logEvents"), "{log:?}");
    assert!(
        log.iter()
            .any(|r| r.category == "logAll" && r.message.contains("fmi2DoStep")),
        "{log:?}"
    );
    assert!(log
        .iter()
        .all(|r| r.format == "%s" && !r.category.is_empty() && r.instance == "loud"));

    // Only logEvents.
    ok!(i, i.set_debug_logging(false, &[]));
    ok!(i, i.set_debug_logging(true, &["logEvents"]));
    i.take_messages();
    ok!(i, i.do_step(1e-3, 1e-3));
    assert!(
        i.take_messages().is_empty(),
        "no per-step trace without logAll"
    );
    ok!(i, i.terminate());
    assert!(i.take_messages().iter().any(|r| r.category == "logEvents"));

    // An unknown category is an error naming it and the valid ones.
    assert_eq!(
        i.set_debug_logging(true, &["logEvents", "logEverything"]),
        Status::Error
    );
    let msg = i.last_message();
    assert!(
        msg.contains("logEverything") && msg.contains("logStatusWarning"),
        "{msg}"
    );

    // A '%' in a message reaches the importer literally.
    let (none, log) =
        fmu.instantiate_with("pct", 1, Some("{%s%n%d}"), Some(&fmu.resource_uri()), false);
    assert!(none.is_none());
    assert!(
        log[0].message.contains("{%s%n%d}") && log[0].format == "%s",
        "{log:?}"
    );
}

#[test]
fn every_local_resource_location_is_accepted() {
    let dir = temp("resources dir %");
    unpack(&dir, &scene_text("contact.toml"));
    let fmu = vibrofric_import::Fmu::load(&dir).unwrap();
    let res = dir.join("resources");
    // The folder as a URI path: /tmp/x/resources on Unix, /C:/users/x/resources on Windows.
    let p = res.display().to_string().replace('\\', "/");
    let p = if p.starts_with('/') {
        p
    } else {
        format!("/{p}")
    };
    let enc = p.replace('%', "%25").replace(' ', "%20");
    let mut uris = vec![
        format!("file://{enc}/"),
        format!("file://{enc}"),
        format!("file:{enc}/"),
        format!("file://localhost{enc}/"),
        fmu.resource_uri(),
    ];
    if cfg!(windows) {
        // A drive letter: percent-encoded, in its old `C|` spelling, and straight after file:.
        let colon = enc.replacen(':', "%3A", 1);
        uris.push(format!("file://{colon}/"));
        uris.push(format!("file://{}/", enc.replacen(':', "|", 1)));
        uris.push(format!("file:{}/", &enc[1..]));
    } else {
        // An empty authority followed by a doubled slash (file:////tmp/x/).
        uris.push(format!("file:///{enc}/"));
        uris.push(format!("file:///{enc}"));
    }
    for uri in uris {
        let (i, log) =
            fmu.instantiate_with("res", 1, Some(&fmu.description.guid), Some(&uri), false);
        assert!(i.is_some(), "{uri}: {log:?}");
    }
}

#[test]
fn instantiate_refuses_bad_arguments_with_a_log_line() {
    let fmu = load("contact.toml", "refuse");
    let guid = fmu.description.guid.clone();
    let res = fmu.resource_uri();
    let empty = temp("refuse-empty");
    let empty_uri = vibrofric_import::file_uri(&empty) + "/";
    // (what, fmuType, fmuGUID, fmuResourceLocation, words of the log line)
    type Case<'a> = (&'a str, i32, Option<&'a str>, Option<&'a str>, Vec<&'a str>);
    let cases: Vec<Case> = vec![
        (
            "null resources",
            1,
            Some(&guid),
            None,
            vec!["fmuResourceLocation = NULL"],
        ),
        (
            "http",
            1,
            Some(&guid),
            Some("http://example.org/r/"),
            vec!["file: URI"],
        ),
        (
            "remote host",
            1,
            Some(&guid),
            Some("file://server/r/"),
            vec!["server"],
        ),
        (
            "no scene",
            1,
            Some(&guid),
            Some(&empty_uri),
            vec!["scene.toml"],
        ),
        (
            "wrong guid",
            1,
            Some("{0000}"),
            Some(&res),
            vec!["{0000}", guid.as_str()],
        ),
        (
            "null guid",
            1,
            None,
            Some(&res),
            vec!["fmuGUID = NULL", guid.as_str()],
        ),
        (
            "unknown interface",
            2,
            Some(&guid),
            Some(&res),
            vec![
                "fmuType = 2",
                "fmi2ModelExchange (0)",
                "fmi2CoSimulation (1)",
            ],
        ),
    ];
    for (what, ty, g, r, words) in cases {
        let (i, log) = fmu.instantiate_with("bad", ty, g, r, false);
        assert!(i.is_none(), "{what}");
        assert_eq!(log.len(), 1, "{what}: {log:?}");
        assert_eq!(log[0].status, Status::Error);
        assert_eq!(log[0].category, "logStatusError");
        for w in words {
            assert!(
                log[0].message.contains(w),
                "{what}: {} lacks {w}",
                log[0].message
            );
        }
    }
    // An invalid scene in resources/.
    let bad = temp("refuse-scene");
    std::fs::write(
        bad.join("scene.toml"),
        "model_identifier = \"X\"\nlaw = \"coulomb\"\n",
    )
    .unwrap();
    let (i, log) = fmu.instantiate_with(
        "bad",
        1,
        Some(&guid),
        Some(&vibrofric_import::file_uri(&bad)),
        false,
    );
    assert!(i.is_none());
    assert!(
        log[0].message.contains("law") && log[0].message.contains("coulomb"),
        "{log:?}"
    );
}

#[test]
fn instance_names_of_any_length_a_null_logger_and_null_callbacks() {
    let fmu = load("contact.toml", "names");
    let long = "n".repeat(100_000);
    let (i, _) = fmu.instantiate_with(
        &long,
        1,
        Some(&fmu.description.guid),
        Some(&fmu.resource_uri()),
        false,
    );
    let mut i = i.unwrap();
    assert_eq!(i.set_real(&[998], &[0.0]), Status::Error);
    assert_eq!(i.take_messages()[0].instance, long);
    drop(i);

    let f = fmu.functions;
    let guid = std::ffi::CString::new(fmu.description.guid.clone()).unwrap();
    let res = std::ffi::CString::new(fmu.resource_uri()).unwrap();
    let callbacks = vibrofric::fmi::fmi2::types::fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    unsafe {
        let c = (f.fmi2Instantiate)(
            c"nolog".as_ptr(),
            1,
            guid.as_ptr(),
            res.as_ptr(),
            &callbacks,
            0,
            1,
        );
        assert!(!c.is_null(), "a NULL logger is allowed");
        assert_eq!((f.fmi2DoStep)(c, 0.0, 1.0, 0), 3, "errors without a logger");
        assert_eq!((f.fmi2Reset)(c), 0);
        (f.fmi2FreeInstance)(c);
        let c = (f.fmi2Instantiate)(
            c"nocb".as_ptr(),
            1,
            guid.as_ptr(),
            res.as_ptr(),
            std::ptr::null(),
            0,
            1,
        );
        assert!(c.is_null(), "NULL callback functions");
        let c = (f.fmi2Instantiate)(
            std::ptr::null(),
            1,
            guid.as_ptr(),
            res.as_ptr(),
            &callbacks,
            0,
            1,
        );
        assert!(c.is_null(), "NULL instance name");
        (f.fmi2FreeInstance)(std::ptr::null_mut());
    }
}

#[test]
fn do_step_accepts_a_master_rounded_communication_point_and_honours_stop_time() {
    let fmu = load("contact.toml", "rounding");
    let mut i = fmu.instantiate("round").unwrap();
    ok!(i, i.setup_experiment(None, 0.0, Some(0.01)));
    ok!(i, i.enter_initialization_mode());
    ok!(i, i.exit_initialization_mode());
    // A master that sums 0.1 ms ten times has 0.0009999999999999998 ≠ 1e-3.
    let mut t = 0.0;
    for _ in 0..10 {
        ok!(i, i.do_step(t, 1e-4));
        t += 1e-4;
    }
    assert_ne!(t, 1e-3);
    ok!(i, i.do_step(1e-3, 4e-3));
    assert_eq!(
        i.get_real_status(2).1,
        5e-3,
        "steps to currentCommunicationPoint + h"
    );
    ok!(i, i.do_step(5e-3, 5e-3));
    assert_eq!(i.do_step(1e-2, 1e-3), Status::Error);
    assert!(
        i.last_message().contains("stopTime"),
        "{}",
        i.last_message()
    );
}

#[test]
fn normal_force_zero_is_valid() {
    let fmu = load("contact.toml", "fn0");
    let mut i = started(&fmu, "fn0", &[(vr::F_N, 0.0), (vr::MU, 0.0)]);
    let mut t = 0.0;
    for k in 0..5 {
        t = step(&mut i, k, t, H);
    }
    let y = i.get_real(&[vr::F_FX, vr::X, vr::V_X]).unwrap();
    assert!(y.iter().all(|v| v.is_finite()), "{y:?}");
    assert_eq!(y[0], 0.0, "no friction");
    // F_N is tunable: friction comes back during the run.
    ok!(i, i.set_real(&[vr::F_N, vr::MU], &[55.0, 0.2]));
    let _ = step(&mut i, 5, t, H);
    // Under the velocity drive, no Coulomb force means no reduction: 0.
    let fmu = load("paper-longitudinal.toml", "fn0-velocity");
    let mut i = started(&fmu, "fn0", &[(vr::F_N, 0.0)]);
    ok!(i, i.do_step(0.0, H));
    assert_eq!(
        i.get_real(&[vr::F_FX, vr::F_MEAN, vr::REDUCTION]).unwrap(),
        [0.0, 0.0, 0.0]
    );
}

#[test]
fn reset_restarts_from_the_scene_start_values() {
    let fmu = load("contact.toml", "reset");
    let scene = scene("contact.toml");
    let vrs = all_vrs(&scene);
    let mut i = started(&fmu, "reset", &[(vr::K_T, 2e8), (vr::F_D, 3.0)]);
    let first = run(&mut i, &vrs, 0, 5, 0.0, H);
    ok!(i, i.reset());
    ok!(i, i.enter_initialization_mode());
    let start = i.get_real(&[vr::K_T, vr::F_D]).unwrap();
    assert_eq!(start, vec![scene.start.k_t, scene.inputs.f_d]);
    ok!(i, i.set_real(&[vr::K_T, vr::F_D], &[2e8, 3.0]));
    ok!(i, i.exit_initialization_mode());
    assert_eq!(run(&mut i, &vrs, 0, 5, 0.0, H), first);
}

#[test]
fn the_importer_loads_a_packed_fmu_archive_and_removes_its_unpacked_copy() {
    use std::io::Write;
    let dir = temp("archive-src");
    let scene = unpack(&dir, &scene_text("contact.toml"));
    let fmu_file = temp("archive").join("VibratingContact.fmu");
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&fmu_file).unwrap());
    let opts = zip::write::SimpleFileOptions::default();
    let so = format!(
        "binaries/{}/{}.{}",
        vibrofric_import::platform().0,
        scene.model_identifier,
        vibrofric_import::platform().1
    );
    for (name, path) in [
        ("modelDescription.xml", dir.join("modelDescription.xml")),
        ("resources/scene.toml", dir.join("resources/scene.toml")),
        (so.as_str(), library()),
    ] {
        zip.start_file(name, opts).unwrap();
        zip.write_all(&std::fs::read(path).unwrap()).unwrap();
    }
    zip.finish().unwrap();

    let fmu = vibrofric_import::Fmu::load(&fmu_file).unwrap();
    let unpacked = fmu.dir.clone();
    assert!(unpacked.join("resources/scene.toml").is_file());
    let rows = fmu
        .simulate(0.01, 1e-3, &[(vr::F_D, 2.0)], &[vr::X, vr::F_MEAN])
        .unwrap();
    assert_eq!(rows.len(), 11);
    assert_eq!(rows[10][0], 0.01);
    assert!(rows[10][1] > 0.0, "pushed by F_d: x = {}", rows[10][1]);
    drop(fmu);
    assert!(!unpacked.exists(), "temporary folder removed");
}

#[test]
fn spring_drive_reports_f_d_as_an_output_equal_to_the_core() {
    let fmu = load("rig-longitudinal.toml", "spring");
    let scene = scene("rig-longitudinal.toml");
    let vrs = all_vrs(&scene);
    assert!(vrs.contains(&vr::F_D) && vrs.contains(&vr::V_D));
    let mut i = started(&fmu, "rig", &[]);
    let mut sim = core(&scene, scene.start, scene.inputs, 1e-6);
    let mut inputs = scene.inputs;
    let mut t = 0.0;
    for k in 0..10 {
        let v_d = 1e-3 * (1.0 + 0.1 * k as f64);
        ok!(i, i.set_real(&[vr::V_D], &[v_d]));
        sim.set_input(InputId::VD, v_d).unwrap();
        inputs.v_d = v_d;
        ok!(i, i.do_step(t, H));
        sim.step_to(t + H).unwrap();
        t += H;
        assert_eq!(
            bits(&i.get_real(&vrs).unwrap()),
            bits(&core_values(&scene, sim.as_ref(), &inputs)),
            "step {k}"
        );
    }
    let f_d = i.get_real(&[vr::F_D]).unwrap()[0];
    assert!(f_d != 0.0, "the spring pulls: F_d = {f_d}");
    assert_eq!(i.set_real(&[vr::F_D], &[1.0]), Status::Error);
    let msg = i.last_message();
    assert!(
        msg.contains("F_d (vr 101)") && msg.contains("causality output"),
        "{msg}"
    );
}

#[test]
fn every_standard_scene_through_the_fmu_equals_the_core() {
    for file in STANDARD_SCENES {
        let what = format!("{file} through the FMU");
        within(60, &what, move || {
            let fmu = load(file, &format!("scene-{file}"));
            let scene = scene(file);
            let vrs = all_vrs(&scene);
            let mut i = started(&fmu, file, &[]);
            let mut sim = core(&scene, scene.start, scene.inputs, 1e-6);
            let mut inputs = scene.inputs;
            let mut t = 0.0;
            for k in 0..6 {
                let x = k as f64;
                for (id, value) in [
                    (InputId::FD, drive(k)),
                    (InputId::VD, 1e-3 * (1.0 + 0.2 * x.sin())),
                    (InputId::VSx, 1e-4 * x.cos()),
                    (InputId::VSy, 5e-5 * x.sin()),
                ] {
                    if id.present(&scene.config) {
                        let vr = match id {
                            InputId::FD => vr::F_D,
                            InputId::VD => vr::V_D,
                            InputId::VSx => vr::V_SX,
                            InputId::VSy => vr::V_SY,
                            InputId::FN => vr::F_N,
                        };
                        ok!(i, i.set_real(&[vr], &[value]));
                        sim.set_input(id, value).unwrap();
                        *id.slot(&mut inputs) = value;
                    }
                }
                ok!(i, i.do_step(t, H));
                sim.step_to(t + H).unwrap();
                t += H;
                assert_eq!(
                    bits(&i.get_real(&vrs).unwrap()),
                    bits(&core_values(&scene, sim.as_ref(), &inputs)),
                    "{file}, step {k}"
                );
            }
        });
    }
}

/// Each instance answers only its own interface's functions (FMI 2.0 sections 3.2.3 and
/// 4.2.4): on a Model Exchange instance the Co-Simulation functions (input and output
/// derivatives, steps, status queries) answer fmi2Error saying so, in every state; on a
/// Co-Simulation instance the Model Exchange functions likewise. A Model Exchange instance used
/// to accept input derivatives (one on `F_N` zeroed the deformation in continuous-time mode,
/// with no event), output derivatives and fmi2GetRealStatus, and answered fmi2GetStatus with
/// fmi2Discard; a Co-Simulation instance read continuous states, derivatives, event indicators
/// and nominals.
#[test]
fn each_interface_answers_only_its_own_functions() {
    let file = "drill-string-contact.toml";
    let fmu = load(file, "interfaces");
    let f = fmu.functions;
    let me_f = fmu.model_exchange.expect("Model Exchange functions");
    type Raw = Box<dyn Fn(vibrofric::fmi::fmi2::types::fmi2Component) -> i32>;
    let cs_only: Vec<(&str, Raw)> = vec![
        (
            "fmi2SetRealInputDerivatives",
            Box::new(move |c| unsafe { (f.fmi2SetRealInputDerivatives)(c, &vr::F_N, 1, &1, &1e6) }),
        ),
        (
            "fmi2GetRealOutputDerivatives",
            Box::new(move |c| unsafe {
                let mut d = 0.0;
                (f.fmi2GetRealOutputDerivatives)(c, &vr::X, 1, &1, &mut d)
            }),
        ),
        (
            "fmi2DoStep",
            Box::new(move |c| unsafe { (f.fmi2DoStep)(c, 0.0, 1e-3, 1) }),
        ),
        (
            "fmi2CancelStep",
            Box::new(move |c| unsafe { (f.fmi2CancelStep)(c) }),
        ),
        (
            "fmi2GetStatus",
            Box::new(move |c| unsafe {
                let mut s = 0;
                (f.fmi2GetStatus)(c, 0, &mut s)
            }),
        ),
        (
            "fmi2GetRealStatus",
            Box::new(move |c| unsafe {
                let mut r = 0.0;
                (f.fmi2GetRealStatus)(c, 2, &mut r)
            }),
        ),
        (
            "fmi2GetBooleanStatus",
            Box::new(move |c| unsafe {
                let mut b = 0;
                (f.fmi2GetBooleanStatus)(c, 3, &mut b)
            }),
        ),
    ];
    let sc = scene(file);
    let nx = sc
        .variables()
        .filter(|v| matches!(v.kind, VarKind::State(_)))
        .count();
    let ni = sc.config.event_indicators();
    let me_only: Vec<(&str, Raw)> = vec![
        (
            "fmi2GetContinuousStates",
            Box::new(move |c| unsafe {
                let mut x = vec![0.0; nx];
                (me_f.fmi2GetContinuousStates)(c, x.as_mut_ptr(), nx)
            }),
        ),
        (
            "fmi2GetDerivatives",
            Box::new(move |c| unsafe {
                let mut x = vec![0.0; nx];
                (me_f.fmi2GetDerivatives)(c, x.as_mut_ptr(), nx)
            }),
        ),
        (
            "fmi2GetEventIndicators",
            Box::new(move |c| unsafe {
                let mut z = vec![0.0; ni];
                (me_f.fmi2GetEventIndicators)(c, z.as_mut_ptr(), ni)
            }),
        ),
        (
            "fmi2GetNominalsOfContinuousStates",
            Box::new(move |c| unsafe {
                let mut x = vec![0.0; nx];
                (me_f.fmi2GetNominalsOfContinuousStates)(c, x.as_mut_ptr(), nx)
            }),
        ),
        (
            "fmi2SetTime",
            Box::new(move |c| unsafe { (me_f.fmi2SetTime)(c, 1e-3) }),
        ),
        (
            "fmi2EnterEventMode",
            Box::new(move |c| unsafe { (me_f.fmi2EnterEventMode)(c) }),
        ),
    ];
    // Model Exchange instances in Instantiated, InitializationMode, EventMode,
    // ContinuousTimeMode and Terminated; Co-Simulation instances in Instantiated,
    // InitializationMode, StepComplete and Terminated.
    for phase in 0..5 {
        for (name, call) in &cs_only {
            let mut i = fmu.instantiate_model_exchange("me").unwrap();
            let vrs = all_vrs(&sc);
            if phase >= 1 {
                ok!(i, i.enter_initialization_mode());
            }
            if phase >= 2 {
                ok!(i, i.exit_initialization_mode());
            }
            if phase >= 3 {
                ok!(i, i.new_discrete_states().0);
                ok!(i, i.enter_continuous_time_mode());
            }
            if phase >= 4 {
                ok!(i, i.terminate());
            }
            let before = i.get_real(&vrs).ok();
            i.take_messages();
            let s = vibrofric_import::status(call(i.raw()));
            assert_eq!(s, Status::Error, "{name} on Model Exchange, phase {phase}");
            let msg = i.last_message();
            assert!(
                msg.contains(name)
                    && msg.contains("a function of Co-Simulation only")
                    && msg.contains("instantiated for Model Exchange"),
                "{msg}"
            );
            if let Some(b) = before {
                assert_eq!(bits(&i.get_real(&vrs).unwrap()), bits(&b), "{name}");
            }
        }
        for (name, call) in &me_only {
            let mut i = fmu.instantiate("cs").unwrap();
            if phase >= 1 {
                ok!(i, i.enter_initialization_mode());
            }
            if phase >= 2 {
                ok!(i, i.exit_initialization_mode());
            }
            if phase >= 3 {
                ok!(i, i.do_step(0.0, 1e-3));
            }
            if phase >= 4 {
                ok!(i, i.terminate());
            }
            let s = vibrofric_import::status(call(i.raw()));
            assert_eq!(s, Status::Error, "{name} on Co-Simulation, phase {phase}");
            let msg = i.last_message();
            assert!(
                msg.contains(name)
                    && msg.contains("a function of Model Exchange only")
                    && msg.contains("instantiated for Co-Simulation"),
                "{msg}"
            );
        }
    }
    // The Model Exchange instance of DrillStringContact with F_N = 0 keeps its deformation in
    // continuous-time mode: no input derivative reaches it.
    let mut i = fmu.instantiate_model_exchange("me").unwrap();
    ok!(i, i.enter_initialization_mode());
    ok!(i, i.exit_initialization_mode());
    ok!(i, i.new_discrete_states().0);
    ok!(i, i.enter_continuous_time_mode());
    let mut x = vec![0.0; nx];
    x[0] = 1e-8;
    ok!(i, i.set_continuous_states(&x));
    ok!(i, i.set_real(&[vr::F_N], &[0.0]));
    assert_eq!(
        i.set_real_input_derivatives(&[vr::F_N], &[1], &[1e6]),
        Status::Error
    );
    ok!(i, i.reset());
}

/// After a refused call, the calls refused in state Error say which call put the instance
/// there and why, and that fmi2Reset (or restoring a saved state) recovers; it does.
#[test]
fn refusals_in_error_name_the_call_that_caused_it_and_the_way_out() {
    let fmu = load("contact.toml", "error-cause");
    let mut i = started(&fmu, "cause", &[]);
    assert_eq!(i.set_real(&[vr::K_T], &[-1.0]), Status::Error);
    assert_eq!(i.do_step(0.0, H), Status::Error);
    let msg = i.last_message();
    assert!(
        msg.contains("not allowed in state Error")
            && msg.contains("entered Error at fmi2SetReal in state StepComplete")
            && msg.contains("k_t")
            && msg.contains("fmi2Reset recovers it"),
        "{msg}"
    );
    // The first cause stays, however many calls are refused after it.
    assert_eq!(i.exit_initialization_mode(), Status::Error);
    assert!(i.last_message().contains("at fmi2SetReal"));
    ok!(i, i.reset());
    ok!(i, i.enter_initialization_mode());
    ok!(i, i.exit_initialization_mode());
    ok!(i, i.do_step(0.0, H));
    // After the reset, a new error names its own cause.
    assert_eq!(i.do_step(5.0, H), Status::Error);
    assert_eq!(i.do_step(H, H), Status::Error);
    assert!(
        i.last_message()
            .contains("entered Error at fmi2DoStep in state StepComplete"),
        "{}",
        i.last_message()
    );
    // FMI 3.0 names its own reset.
    let fmu3 = load3("contact.toml", "error-cause-3");
    let mut c = fmu3.instantiate("cause3").unwrap();
    assert_eq!(c.exit_initialization_mode(), Status::Error);
    assert_eq!(c.exit_initialization_mode(), Status::Error);
    let msg = c.last_message();
    assert!(
        msg.contains("entered Error at fmi3ExitInitializationMode in state Instantiated")
            && msg.contains("fmi3Reset recovers it"),
        "{msg}"
    );
    assert_eq!(c.reset(), Status::Ok);
}
