//! Every class of bad input of issue 3: each call returns the status the standard prescribes
//! with a log line naming the function, the variable and the rule; afterwards the variables
//! read as before, and both `fmi2SetFMUstate` with a state taken before the bad call and
//! `fmi2Reset` continue bit-for-bit like a run that never saw it.

#[macro_use]
mod support;

use std::ptr;

use support::fmu::*;
use support::scenes::*;
use vibrofric_import::{Fmu, Instance, Status};

const H: f64 = 1e-3;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// Bad call right after fmi2Instantiate.
    Instantiated,
    /// Bad call in initialization mode, after setting F_d.
    Init,
    /// Bad call after three communication steps.
    Stepping,
}

/// Brings an instance (new or reset) to the phase.
fn prepare(i: &mut Instance, phase: Phase) {
    if phase == Phase::Instantiated {
        return;
    }
    ok!(i, i.setup_experiment(Some(1e-6), 0.0, None));
    ok!(i, i.enter_initialization_mode());
    ok!(i, i.set_real(&[vr::F_D], &[3.0]));
    if phase == Phase::Stepping {
        ok!(i, i.exit_initialization_mode());
        let mut t = 0.0;
        for k in 0..3 {
            t = step(i, k, t, H);
        }
    }
}

/// Runs the rest of the standard experiment from the phase and returns every variable after
/// each step.
fn finish(i: &mut Instance, phase: Phase, vrs: &[u32]) -> Vec<Vec<u64>> {
    match phase {
        Phase::Instantiated => {
            prepare(i, Phase::Init);
            ok!(i, i.exit_initialization_mode());
            run(i, vrs, 0, 5, 0.0, H)
        }
        Phase::Init => {
            ok!(i, i.exit_initialization_mode());
            run(i, vrs, 0, 5, 0.0, H)
        }
        Phase::Stepping => run(i, vrs, 3, 8, 3.0 * H, H),
    }
}

type Bad = fn(&mut Instance) -> Status;

/// One bad call: what it is, the status it must return and the words its log line must hold.
struct Case {
    phase: Phase,
    what: &'static str,
    call: Bad,
    status: Status,
    words: &'static [&'static str],
}

fn case(
    phase: Phase,
    what: &'static str,
    status: Status,
    words: &'static [&'static str],
    call: Bad,
) -> Case {
    Case {
        phase,
        what,
        call,
        status,
        words,
    }
}

fn check(fmu: &Fmu, vrs: &[u32], c: &Case) {
    let reference = {
        let mut a = fmu.instantiate("reference").unwrap();
        prepare(&mut a, c.phase);
        finish(&mut a, c.phase, vrs)
    };
    let mut b = fmu.instantiate("bad").unwrap();
    prepare(&mut b, c.phase);
    let before = (c.phase != Phase::Instantiated).then(|| bits(&b.get_real(vrs).unwrap()));
    let saved = b.get_state().unwrap();
    b.take_messages();

    let status = (c.call)(&mut b);
    assert_eq!(status, c.status, "{}", c.what);
    let log = b.take_messages();
    let line = log
        .iter()
        .find(|r| r.status == c.status)
        .unwrap_or_else(|| panic!("{}: nothing logged with {status:?}: {log:?}", c.what));
    assert_eq!(line.category, "logStatusError", "{}", c.what);
    assert_eq!(line.format, "%s");
    for w in c.words {
        assert!(
            line.message.contains(w),
            "{}: \"{}\" lacks \"{w}\"",
            c.what,
            line.message
        );
    }

    // The bad value never touched the instance.
    if let Some(before) = before {
        let after = b.get_real(vrs).unwrap_or_else(|s| {
            panic!(
                "{}: fmi2GetReal after the bad call: {s:?} {}",
                c.what,
                b.last_message()
            )
        });
        assert_eq!(bits(&after), before, "{}: variables changed", c.what);
    }
    // A state taken before continues like the run that never saw the bad call.
    ok!(b, b.set_state(&saved));
    assert_eq!(
        finish(&mut b, c.phase, vrs),
        reference,
        "{}: after fmi2SetFMUstate",
        c.what
    );
    // So does fmi2Reset and the same experiment again.
    let mut b2 = fmu.instantiate("bad-reset").unwrap();
    prepare(&mut b2, c.phase);
    let _ = (c.call)(&mut b2);
    ok!(b2, b2.reset());
    prepare(&mut b2, c.phase);
    assert_eq!(
        finish(&mut b2, c.phase, vrs),
        reference,
        "{}: after fmi2Reset",
        c.what
    );
    ok!(b, b.free_state(saved));
}

fn raw(i: &Instance) -> (vibrofric_import::Functions, *mut std::ffi::c_void) {
    (*i.functions(), i.raw())
}

use Phase::{Init, Instantiated, Stepping};
use Status::Error;

#[test]
fn null_arrays_with_nonzero_length() {
    let fmu = load("contact.toml", "bad-null");
    let vrs = all_vrs(&scene("contact.toml"));
    let cases = [
        case(
            Stepping,
            "GetReal vr NULL",
            Error,
            &["fmi2GetReal", "vr = NULL"],
            |i| {
                let (f, c) = raw(i);
                let mut v = [0.0; 2];
                vibrofric_import::status(unsafe {
                    (f.fmi2GetReal)(c, ptr::null(), 2, v.as_mut_ptr())
                })
            },
        ),
        case(
            Stepping,
            "GetReal value NULL",
            Error,
            &["fmi2GetReal", "value = NULL"],
            |i| {
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe {
                    (f.fmi2GetReal)(c, [201].as_ptr(), 1, ptr::null_mut())
                })
            },
        ),
        case(
            Stepping,
            "SetReal value NULL",
            Error,
            &["fmi2SetReal", "value = NULL"],
            |i| {
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe {
                    (f.fmi2SetReal)(c, [101].as_ptr(), 1, ptr::null())
                })
            },
        ),
        case(
            Init,
            "SetReal vr NULL",
            Error,
            &["fmi2SetReal", "vr = NULL"],
            |i| {
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe {
                    (f.fmi2SetReal)(c, ptr::null(), 1, [1.0].as_ptr())
                })
            },
        ),
        case(
            Stepping,
            "SetRealInputDerivatives order NULL",
            Error,
            &["fmi2SetRealInputDerivatives", "order = NULL"],
            |i| {
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe {
                    (f.fmi2SetRealInputDerivatives)(
                        c,
                        [101].as_ptr(),
                        1,
                        ptr::null(),
                        [1.0].as_ptr(),
                    )
                })
            },
        ),
        case(
            Stepping,
            "GetFMUstate NULL",
            Error,
            &["fmi2GetFMUstate", "FMUstate = NULL"],
            |i| {
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe { (f.fmi2GetFMUstate)(c, ptr::null_mut()) })
            },
        ),
        case(
            Stepping,
            "SetFMUstate NULL",
            Error,
            &["fmi2SetFMUstate", "NULL"],
            |i| {
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe { (f.fmi2SetFMUstate)(c, ptr::null_mut()) })
            },
        ),
        case(
            Stepping,
            "SerializeFMUstate buffer NULL",
            Error,
            &["fmi2SerializeFMUstate", "serializedState = NULL"],
            |i| {
                let s = i.get_state().unwrap();
                let n = i.serialize_state(&s).unwrap().len();
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe {
                    (f.fmi2SerializeFMUstate)(c, s.raw(), ptr::null_mut(), n)
                })
            },
        ),
        case(
            Stepping,
            "SerializeFMUstate buffer too small",
            Error,
            &["fmi2SerializeFMUstate", "size = 8"],
            |i| {
                let s = i.get_state().unwrap();
                let (f, c) = raw(i);
                let mut buf = [0i8; 8];
                vibrofric_import::status(unsafe {
                    (f.fmi2SerializeFMUstate)(c, s.raw(), buf.as_mut_ptr() as *mut _, 8)
                })
            },
        ),
        case(
            Stepping,
            "DeSerializeFMUstate NULL",
            Error,
            &["fmi2DeSerializeFMUstate", "serializedState = NULL"],
            |i| {
                let (f, c) = raw(i);
                let mut p = ptr::null_mut();
                vibrofric_import::status(unsafe {
                    (f.fmi2DeSerializeFMUstate)(c, ptr::null(), 10, &mut p)
                })
            },
        ),
        case(
            Stepping,
            "SetDebugLogging categories NULL",
            Error,
            &["fmi2SetDebugLogging", "categories = NULL"],
            |i| {
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe { (f.fmi2SetDebugLogging)(c, 1, 2, ptr::null()) })
            },
        ),
        case(
            Stepping,
            "GetRealStatus value NULL",
            Error,
            &["fmi2GetRealStatus", "value = NULL"],
            |i| {
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe { (f.fmi2GetRealStatus)(c, 2, ptr::null_mut()) })
            },
        ),
    ];
    for c in &cases {
        check(&fmu, &vrs, c);
    }
}

#[test]
fn null_instance_returns_error_everywhere() {
    let fmu = load("contact.toml", "bad-null-instance");
    let f = fmu.functions;
    let c = ptr::null_mut();
    let mut v = [0.0];
    let mut st = ptr::null_mut();
    let mut n = 0usize;
    let mut i = 0;
    let mut r = 0.0;
    unsafe {
        let statuses = [
            (f.fmi2SetDebugLogging)(c, 1, 0, ptr::null()),
            (f.fmi2SetupExperiment)(c, 0, 0.0, 0.0, 0, 0.0),
            (f.fmi2EnterInitializationMode)(c),
            (f.fmi2ExitInitializationMode)(c),
            (f.fmi2Terminate)(c),
            (f.fmi2Reset)(c),
            (f.fmi2GetReal)(c, [201].as_ptr(), 1, v.as_mut_ptr()),
            (f.fmi2SetReal)(c, [101].as_ptr(), 1, v.as_ptr()),
            (f.fmi2GetInteger)(c, ptr::null(), 0, ptr::null_mut()),
            (f.fmi2SetInteger)(c, ptr::null(), 0, ptr::null()),
            (f.fmi2GetBoolean)(c, ptr::null(), 0, ptr::null_mut()),
            (f.fmi2SetBoolean)(c, ptr::null(), 0, ptr::null()),
            (f.fmi2GetString)(c, ptr::null(), 0, ptr::null_mut()),
            (f.fmi2SetString)(c, ptr::null(), 0, ptr::null()),
            (f.fmi2GetFMUstate)(c, &mut st),
            (f.fmi2SetFMUstate)(c, st),
            (f.fmi2FreeFMUstate)(c, &mut st),
            (f.fmi2SerializedFMUstateSize)(c, st, &mut n),
            (f.fmi2SerializeFMUstate)(c, st, ptr::null_mut(), 0),
            (f.fmi2DeSerializeFMUstate)(c, ptr::null(), 0, &mut st),
            (f.fmi2GetDirectionalDerivative)(
                c,
                ptr::null(),
                0,
                ptr::null(),
                0,
                ptr::null(),
                ptr::null_mut(),
            ),
            (f.fmi2SetRealInputDerivatives)(c, ptr::null(), 0, ptr::null(), ptr::null()),
            (f.fmi2GetRealOutputDerivatives)(c, ptr::null(), 0, ptr::null(), ptr::null_mut()),
            (f.fmi2DoStep)(c, 0.0, 1e-3, 0),
            (f.fmi2CancelStep)(c),
            (f.fmi2GetStatus)(c, 0, &mut i),
            (f.fmi2GetRealStatus)(c, 2, &mut r),
            (f.fmi2GetIntegerStatus)(c, 0, &mut i),
            (f.fmi2GetBooleanStatus)(c, 3, &mut i),
            (f.fmi2GetStringStatus)(c, 1, ptr::null_mut()),
        ];
        assert_eq!(
            statuses.len(),
            30,
            "every function that takes an instance, but free"
        );
        assert!(statuses.iter().all(|&s| s == 3), "{statuses:?}");
        assert!(st.is_null());
        (f.fmi2FreeInstance)(c);
    }
}

#[test]
fn unknown_value_references_and_forbidden_causality() {
    let fmu = load("contact.toml", "bad-vr");
    let vrs = all_vrs(&scene("contact.toml"));
    let cases = [
        case(
            Stepping,
            "SetReal unknown vr",
            Error,
            &["fmi2SetReal", "unknown value reference 999"],
            |i| i.set_real(&[vr::F_D, 999], &[5.0, 1.0]),
        ),
        case(
            Init,
            "SetReal unknown vr in init",
            Error,
            &["fmi2SetReal", "unknown value reference 300"],
            |i| i.set_real(&[vr::K_T, 300], &[2e8, 1.0]),
        ),
        case(
            Stepping,
            "GetReal unknown vr",
            Error,
            &["fmi2GetReal", "unknown value reference 999"],
            |i| i.get_real(&[vr::F_FX, 999]).err().unwrap_or(Status::Ok),
        ),
        case(
            Stepping,
            "SetReal variable absent from the scene",
            Error,
            &["value reference 5", "kappa", "not a variable of this FMU"],
            |i| i.set_real(&[vr::KAPPA], &[2.0]),
        ),
        case(
            Stepping,
            "GetReal variable absent from the scene",
            Error,
            &["value reference 102", "v_d"],
            |i| i.get_real(&[vr::V_D]).err().unwrap_or(Status::Ok),
        ),
        case(
            Stepping,
            "SetReal output",
            Error,
            &["fmi2SetReal", "F_Fx", "causality output"],
            |i| i.set_real(&[vr::F_D, vr::F_FX], &[5.0, 1.0]),
        ),
        case(
            Init,
            "SetReal output in init",
            Error,
            &["x (vr 203)", "causality output"],
            |i| i.set_real(&[vr::X], &[1.0]),
        ),
        case(
            Stepping,
            "SetReal fixed parameter after init",
            Error,
            &["k_t", "variability fixed", "StepComplete"],
            |i| i.set_real(&[vr::K_T], &[2e8]),
        ),
        case(
            Stepping,
            "SetReal fixed mass after init",
            Error,
            &["m (vr 1)", "variability fixed"],
            |i| i.set_real(&[vr::F_N, vr::M], &[40.0, 6.0]),
        ),
        case(
            Stepping,
            "input derivative of a parameter",
            Error,
            &["fmi2SetRealInputDerivatives", "F_N", "causality parameter"],
            |i| i.set_real_input_derivatives(&[vr::F_N], &[1], &[1.0]),
        ),
        case(
            Stepping,
            "input derivative of order 2",
            Error,
            &["order = 2", "F_d", "order 1"],
            |i| i.set_real_input_derivatives(&[vr::F_D], &[2], &[1.0]),
        ),
        case(
            Stepping,
            "output derivative of an output without an exact one",
            Error,
            &[
                "fmi2GetRealOutputDerivatives",
                "F_Fx",
                "no exact time derivative",
            ],
            |i| {
                let (f, c) = raw(i);
                let mut v = [0.0];
                vibrofric_import::status(unsafe {
                    (f.fmi2GetRealOutputDerivatives)(
                        c,
                        [201].as_ptr(),
                        1,
                        [1].as_ptr(),
                        v.as_mut_ptr(),
                    )
                })
            },
        ),
        case(
            Stepping,
            "directional derivative",
            Error,
            &["fmi2GetDirectionalDerivative", "not supported"],
            |i| {
                let (f, c) = raw(i);
                let mut v = [0.0];
                vibrofric_import::status(unsafe {
                    (f.fmi2GetDirectionalDerivative)(
                        c,
                        [201].as_ptr(),
                        1,
                        [101].as_ptr(),
                        1,
                        [1.0].as_ptr(),
                        v.as_mut_ptr(),
                    )
                })
            },
        ),
        case(
            Stepping,
            "Integer access",
            Error,
            &["fmi2SetInteger", "no Integer variables"],
            |i| {
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe {
                    (f.fmi2SetInteger)(c, [1].as_ptr(), 1, [1].as_ptr())
                })
            },
        ),
    ];
    for c in &cases {
        check(&fmu, &vrs, c);
    }
}

#[test]
fn calls_out_of_order() {
    let fmu = load("contact.toml", "bad-order");
    let vrs = all_vrs(&scene("contact.toml"));
    let cases = [
        case(
            Instantiated,
            "DoStep before initialization",
            Error,
            &["fmi2DoStep", "Instantiated"],
            |i| i.do_step(0.0, H),
        ),
        case(
            Instantiated,
            "ExitInitializationMode first",
            Error,
            &["fmi2ExitInitializationMode", "Instantiated"],
            |i| i.exit_initialization_mode(),
        ),
        case(
            Init,
            "SetupExperiment in initialization",
            Error,
            &["fmi2SetupExperiment", "InitializationMode"],
            |i| i.setup_experiment(None, 0.0, None),
        ),
        case(
            Init,
            "DoStep in initialization",
            Error,
            &["fmi2DoStep", "InitializationMode"],
            |i| i.do_step(0.0, H),
        ),
        case(
            Stepping,
            "EnterInitializationMode again",
            Error,
            &["fmi2EnterInitializationMode", "StepComplete"],
            |i| i.enter_initialization_mode(),
        ),
        case(
            Stepping,
            "SetupExperiment while stepping",
            Error,
            &["fmi2SetupExperiment", "StepComplete"],
            |i| i.setup_experiment(Some(1e-8), 0.0, None),
        ),
        case(
            Stepping,
            "CancelStep without a pending step",
            Error,
            &["fmi2CancelStep", "StepComplete"],
            |i| {
                let (f, c) = raw(i);
                vibrofric_import::status(unsafe { (f.fmi2CancelStep)(c) })
            },
        ),
    ];
    for c in &cases {
        check(&fmu, &vrs, c);
    }
}

#[test]
fn nan_and_infinite_inputs_and_parameters() {
    let fmu = load("contact.toml", "bad-nan");
    let vrs = all_vrs(&scene("contact.toml"));
    let cases = [
        case(
            Stepping,
            "NaN input among good ones",
            Error,
            &["fmi2SetReal", "v_sx = NaN", "finite"],
            |i| i.set_real(&[vr::F_D, vr::V_SX], &[7.0, f64::NAN]),
        ),
        case(
            Stepping,
            "infinite input",
            Error,
            &["F_d = inf", "finite"],
            |i| i.set_real(&[vr::F_D], &[f64::INFINITY]),
        ),
        case(
            Init,
            "-infinite input in init",
            Error,
            &["v_sy = -inf"],
            |i| i.set_real(&[vr::V_SY], &[f64::NEG_INFINITY]),
        ),
        case(
            Stepping,
            "NaN tunable parameter",
            Error,
            &["mu = NaN", "must be finite"],
            |i| i.set_real(&[vr::MU], &[f64::NAN]),
        ),
        case(
            Stepping,
            "infinite amplitude",
            Error,
            &["u0 = inf", "must be finite"],
            |i| i.set_real(&[vr::U0], &[f64::INFINITY]),
        ),
        case(
            Init,
            "NaN stiffness in init",
            Error,
            &["k_t = NaN", "> 0"],
            |i| i.set_real(&[vr::K_T], &[f64::NAN]),
        ),
        case(
            Init,
            "infinite frequency in init",
            Error,
            &["f = inf"],
            |i| i.set_real(&[vr::F], &[f64::INFINITY]),
        ),
        case(
            Stepping,
            "NaN input derivative",
            Error,
            &["derivative of F_d = NaN"],
            |i| i.set_real_input_derivatives(&[vr::F_D], &[1], &[f64::NAN]),
        ),
        case(
            Instantiated,
            "NaN tolerance",
            Error,
            &["fmi2SetupExperiment", "tolerance = NaN"],
            |i| i.setup_experiment(Some(f64::NAN), 0.0, None),
        ),
        case(
            Instantiated,
            "negative tolerance",
            Error,
            &["tolerance = -0.001", "> 0"],
            |i| i.setup_experiment(Some(-1e-3), 0.0, None),
        ),
        case(
            Instantiated,
            "infinite start time",
            Error,
            &["startTime = inf"],
            |i| i.setup_experiment(None, f64::INFINITY, None),
        ),
        case(
            Instantiated,
            "stop before start",
            Error,
            &["stopTime = -1", ">= startTime"],
            |i| i.setup_experiment(None, 0.0, Some(-1.0)),
        ),
    ];
    for c in &cases {
        check(&fmu, &vrs, c);
    }
}

#[test]
fn bad_communication_steps() {
    let fmu = load("contact.toml", "bad-step");
    let vrs = all_vrs(&scene("contact.toml"));
    let cases = [
        case(
            Stepping,
            "zero step",
            Error,
            &["fmi2DoStep", "communicationStepSize = 0", "> 0"],
            |i| i.do_step(3.0 * H, 0.0),
        ),
        case(
            Stepping,
            "negative step",
            Error,
            &["communicationStepSize = -0.001"],
            |i| i.do_step(3.0 * H, -H),
        ),
        case(
            Stepping,
            "NaN step",
            Error,
            &["communicationStepSize = NaN"],
            |i| i.do_step(3.0 * H, f64::NAN),
        ),
        case(
            Stepping,
            "infinite step",
            Error,
            &["communicationStepSize = inf"],
            |i| i.do_step(3.0 * H, f64::INFINITY),
        ),
        case(
            Stepping,
            "communication point ahead",
            Error,
            &["currentCommunicationPoint = 0.004", "instance's time 0.003"],
            |i| i.do_step(4.0 * H, H),
        ),
        case(
            Stepping,
            "communication point behind",
            Error,
            &["currentCommunicationPoint = 0", "instance's time"],
            |i| i.do_step(0.0, H),
        ),
        case(
            Stepping,
            "NaN communication point",
            Error,
            &["currentCommunicationPoint = NaN"],
            |i| i.do_step(f64::NAN, H),
        ),
    ];
    for c in &cases {
        check(&fmu, &vrs, c);
    }
}

#[test]
fn parameters_out_of_their_physical_range() {
    let fmu = load("contact.toml", "bad-range");
    let vrs = all_vrs(&scene("contact.toml"));
    let cases = [
        case(
            Init,
            "zero mass",
            Error,
            &["fmi2SetReal", "m = 0", "must be finite and > 0", "vr 1"],
            |i| i.set_real(&[vr::M], &[0.0]),
        ),
        case(Init, "negative mass", Error, &["m = -1"], |i| {
            i.set_real(&[vr::M], &[-1.0])
        }),
        case(Init, "zero stiffness", Error, &["k_t = 0", "> 0"], |i| {
            i.set_real(&[vr::F_N, vr::K_T], &[10.0, 0.0])
        }),
        case(Init, "negative stiffness", Error, &["k_t = -1e8"], |i| {
            i.set_real(&[vr::K_T], &[-1e8])
        }),
        case(
            Init,
            "negative frequency",
            Error,
            &["f = -1", ">= 0"],
            |i| i.set_real(&[vr::F], &[-1.0]),
        ),
        case(
            Stepping,
            "negative friction coefficient",
            Error,
            &["mu = -0.1", ">= 0"],
            |i| i.set_real(&[vr::MU], &[-0.1]),
        ),
        case(
            Stepping,
            "negative normal force",
            Error,
            &["F_N = -1", ">= 0"],
            |i| i.set_real(&[vr::F_N], &[-1.0]),
        ),
        case(
            Stepping,
            "negative amplitude",
            Error,
            &["u0 = -1e-7", ">= 0"],
            |i| i.set_real(&[vr::U0], &[-1e-7]),
        ),
        case(
            Stepping,
            "negative frequency while stepping",
            Error,
            &["f = -2000"],
            |i| i.set_real(&[vr::F_D, vr::F], &[1.0, -2000.0]),
        ),
    ];
    for c in &cases {
        check(&fmu, &vrs, c);
    }
}

#[test]
fn dupont_breakaway_ratio_outside_zero_one() {
    // Bounded in time: a stalling integrator fails the test instead of hanging the run.
    within(120, "Dupont r_ba cases", || {
        let fmu = load("contact-dupont.toml", "bad-rba");
        let vrs = all_vrs(&scene("contact-dupont.toml"));
        let cases = [
            case(
                Init,
                "r_ba = 1",
                Error,
                &["r_ba = 1", "must be in [0, 0.999]"],
                |i| i.set_real(&[vr::R_BA], &[1.0]),
            ),
            case(
                Init,
                "r_ba < 0",
                Error,
                &[
                    "r_ba = -0.1",
                    "must be finite and >= 0 (accepted: 0 to 0.999)",
                ],
                |i| i.set_real(&[vr::R_BA], &[-0.1]),
            ),
            case(
                Stepping,
                "r_ba after init",
                Error,
                &["r_ba", "variability fixed"],
                |i| i.set_real(&[vr::R_BA], &[0.3]),
            ),
        ];
        for c in &cases {
            check(&fmu, &vrs, c);
        }
        // Both ends of [0, 1) are allowed.
        for r_ba in [0.0, 0.999] {
            let mut i = started(&fmu, "rba", &[(vr::R_BA, r_ba)]);
            let mut t = 0.0;
            for k in 0..3 {
                t = step(&mut i, k, t, H);
            }
        }
    });
}

#[test]
fn corrupted_serialized_state() {
    let fmu = load("contact.toml", "bad-bytes");
    let vrs = all_vrs(&scene("contact.toml"));
    let cases = [
        case(
            Stepping,
            "flipped byte",
            Error,
            &["fmi2DeSerializeFMUstate", "checksum"],
            |i| {
                let s = i.get_state().unwrap();
                let mut b = i.serialize_state(&s).unwrap();
                let n = b.len() / 2;
                b[n] ^= 0x10;
                i.deserialize_state(&b).err().unwrap_or(Status::Ok)
            },
        ),
        case(
            Stepping,
            "truncated",
            Error,
            &["fmi2DeSerializeFMUstate", "truncated"],
            |i| {
                let s = i.get_state().unwrap();
                let b = i.serialize_state(&s).unwrap();
                i.deserialize_state(&b[..b.len() - 9])
                    .err()
                    .unwrap_or(Status::Ok)
            },
        ),
        case(
            Stepping,
            "not a state",
            Error,
            &["fmi2DeSerializeFMUstate", "magic"],
            |i| {
                i.deserialize_state(b"GIF89a and more bytes")
                    .err()
                    .unwrap_or(Status::Ok)
            },
        ),
    ];
    for c in &cases {
        check(&fmu, &vrs, c);
    }
}

/// Every read of a Model Exchange instance (`fmi2GetReal` of every variable, the continuous
/// states, their nominals, the event indicators and the derivatives), as bits, or the first
/// read that did not answer fmi2OK with its message.
fn every_read(fmu: &Fmu, i: &mut Instance, vrs: &[u32], nx: usize, ni: usize) -> Vec<u64> {
    let mut out = bits(
        &i.get_real(vrs)
            .unwrap_or_else(|s| panic!("{s:?}: {}", i.last_message())),
    );
    let f = fmu.model_exchange.unwrap();
    for get in [
        f.fmi2GetContinuousStates,
        f.fmi2GetNominalsOfContinuousStates,
    ] {
        let mut x = vec![0.0; nx];
        let code = unsafe { get(i.raw(), x.as_mut_ptr(), nx) };
        let s = vibrofric_import::status(code);
        assert_eq!(s, Status::Ok, "{}", i.last_message());
        out.extend(bits(&x));
    }
    let z = i.get_event_indicators(ni);
    out.extend(bits(
        &z.unwrap_or_else(|s| panic!("{s:?}: {}", i.last_message())),
    ));
    let dx = i.get_derivatives(nx);
    out.extend(bits(
        &dx.unwrap_or_else(|s| panic!("{s:?}: {}", i.last_message())),
    ));
    out
}

/// Reads never apply a rule of leaving initialization (they used to refuse every read while
/// `F_S < F_C`, and in Initialization Mode that put the instance in Error). On every LuGre
/// scene, Co-Simulation and Model Exchange, at start times 0 and 1e7 s: `F_S` below the
/// Coulomb force at the scene's load (0, subnormal, just below) is accepted; in Initialization
/// Mode every value reads with fmi2OK and is bit for bit the one at `F_S = F_C`, the lowest
/// static force accepted (at the start the deformation is 0: `F_F = (h_t + h_v)·v_r` and
/// `ds/dt = v_r` need no static force, and the deformation's nominal is `max(F_C, F_S)/k_t`
/// either way); fmi2ExitInitializationMode refuses with the rule, naming both forces; in Error
/// the values read as they stood, with fmi2OK.
#[test]
fn reads_in_initialization_do_not_apply_the_static_force_rule() {
    use vibrofric::table::ParamId;
    let fs = ParamId::FS.vr();
    let mut cases = 0;
    for (file, sc) in standard_scenes() {
        if !all_vrs(&sc).contains(&fs) {
            continue;
        }
        let fmu = load(file, &format!("inconsistent-reads-{file}"));
        let vrs = all_vrs(&sc);
        let (nx, ni) = (state_count(&sc), sc.config.event_indicators());
        let f_c = sc.start.reference_f_c();
        let k = vrs.iter().position(|&v| v == fs).unwrap();
        for me in [false, true] {
            for t0 in [0.0, 1e7] {
                let init = |name: &str, f_s: f64| {
                    let mut i = if me {
                        fmu.instantiate_model_exchange(name).unwrap()
                    } else {
                        fmu.instantiate(name).unwrap()
                    };
                    ok!(i, i.setup_experiment(None, t0, None));
                    ok!(i, i.enter_initialization_mode());
                    ok!(i, i.set_real(&[fs], &[f_s]));
                    i
                };
                let read = |i: &mut Instance| {
                    if me {
                        every_read(&fmu, i, &vrs, nx, ni)
                    } else {
                        let v = i.get_real(&vrs);
                        bits(&v.unwrap_or_else(|s| panic!("{s:?}: {}", i.last_message())))
                    }
                };
                let mut at_f_c = init("consistent", f_c);
                let mut want = read(&mut at_f_c);
                ok!(at_f_c, at_f_c.exit_initialization_mode());
                for f_s in [0.0, 5e-324, f_c * 0.5, f_c * (1.0 - f64::EPSILON)] {
                    let case = format!("{file} (Model Exchange {me}) at {t0} s, F_S = {f_s:e}");
                    let mut i = init("inconsistent", f_s);
                    want[k] = f_s.to_bits();
                    assert_eq!(read(&mut i), want, "{case}: in Initialization Mode");
                    assert_eq!(i.exit_initialization_mode(), Status::Error, "{case}");
                    let msg = i.last_message();
                    assert!(
                        msg.contains("fmi2ExitInitializationMode: F_S = ")
                            && msg.contains("N is below the Coulomb force F_C = mu·F_N = "),
                        "{case}: {msg}"
                    );
                    assert_eq!(read(&mut i), want, "{case}: in Error");
                    cases += 1;
                }
            }
        }
    }
    assert_eq!(cases, 3 * 2 * 2 * 4, "three LuGre scenes");
}

/// In Error, fmi2GetReal answers for debugging: Model Exchange states set far from any
/// trajectory (a deformation of 1e307 m, refused for evaluation with fmi2Discard), then an
/// error (a NaN parameter): the values read as they stand (the deformation output is the
/// state set), and those that are not finite there (the friction force `k_t·s`) are the values
/// at the scene's start values, with fmi2Warning naming them (in the log category
/// logStatusWarning).
#[test]
fn reads_in_error_answer_as_the_values_stand_or_at_the_start_values() {
    let file = "contact.toml";
    let sc = scene(file);
    let fmu = load(file, "reads-in-error");
    let vrs = all_vrs(&sc);
    let at_start = {
        let mut i = fmu.instantiate_model_exchange("start").unwrap();
        ok!(i, i.enter_initialization_mode());
        i.get_real(&vrs).unwrap()
    };
    let mut i = fmu.instantiate_model_exchange("far").unwrap();
    ok!(i, i.set_debug_logging(true, &["logStatusWarning"]));
    ok!(i, i.enter_initialization_mode());
    ok!(i, i.exit_initialization_mode());
    ok!(i, i.new_discrete_states().0);
    ok!(i, i.enter_continuous_time_mode());
    let mut x = vec![0.0; state_count(&sc)];
    x[0] = 1e307;
    ok!(i, i.set_continuous_states(&x));
    assert_eq!(i.get_real(&vrs).err(), Some(Status::Discard));
    assert_eq!(i.set_real(&[vr::M], &[f64::NAN]), Status::Error);
    let f = *i.functions();
    let mut values = vec![0.0; vrs.len()];
    let status = vibrofric_import::status(unsafe {
        (f.fmi2GetReal)(i.raw(), vrs.as_ptr(), vrs.len(), values.as_mut_ptr())
    });
    assert_eq!(status, Status::Warning, "{}", i.last_message());
    let msg = i.last_message();
    assert!(msg.contains("the instance is in Error"), "{msg}");
    let s_x = vrs.iter().position(|&v| v == vr::S_X).unwrap();
    let f_fx = vrs.iter().position(|&v| v == vr::F_FX).unwrap();
    assert_eq!(values[s_x], 1e307, "as it stands");
    assert_eq!(values[f_fx].to_bits(), at_start[f_fx].to_bits(), "{msg}");
    assert!(msg.contains("F_Fx = "), "{msg}");
    assert!(values.iter().all(|x| x.is_finite()), "{values:?}");
}
