//! FMU state: get, set, free, serialise and deserialise. A state restored, in the same instance
//! or in a fresh one after serialisation, continues bit-for-bit like the original.

#[macro_use]
mod support;

use support::fmu::*;
use support::scenes::*;
use vibrofric::description::variables::{Causality, VarKind, Variability};
use vibrofric::description::Scene;
use vibrofric::fmi::saved;
use vibrofric::model::{ContactState, Law};
use vibrofric_import::Status;

const H: f64 = 1e-3;

#[test]
fn restored_states_continue_bit_for_bit() {
    let fmu = load("contact.toml", "state-restore");
    let vrs = all_vrs(&scene("contact.toml"));
    let mut a = started(&fmu, "a", &[(vr::K_T, 1.5e8)]);
    let straight = run(&mut a, &vrs, 0, 10, 0.0, H);

    let mut b = started(&fmu, "b", &[(vr::K_T, 1.5e8)]);
    assert_eq!(run(&mut b, &vrs, 0, 4, 0.0, H), straight[..4]);
    let t4 = 4.0 * H;
    let mut s = b.get_state().unwrap();
    let bytes = b.serialize_state(&s).unwrap();
    assert_eq!(
        run(&mut b, &vrs, 4, 10, t4, H),
        straight[4..],
        "taking a state changes nothing"
    );

    // Same instance, twice.
    for _ in 0..2 {
        ok!(b, b.set_state(&s));
        assert_eq!(run(&mut b, &vrs, 4, 10, t4, H), straight[4..]);
    }

    // A fresh instance, still in state Instantiated, from the bytes.
    let mut c = fmu.instantiate("c").unwrap();
    let sc = c.deserialize_state(&bytes).unwrap();
    ok!(c, c.set_state(&sc));
    assert_eq!(run(&mut c, &vrs, 4, 10, t4, H), straight[4..]);
    // Its own serialisation of the same state is the same bytes.
    assert_eq!(c.serialize_state(&sc).unwrap(), bytes);

    // An instance elsewhere in its own run, after fmi2Terminate.
    let mut d = started(&fmu, "d", &[]);
    run(&mut d, &vrs, 0, 2, 0.0, H);
    ok!(d, d.terminate());
    let sd = d.deserialize_state(&bytes).unwrap();
    ok!(d, d.set_state(&sd));
    assert_eq!(run(&mut d, &vrs, 4, 10, t4, H), straight[4..]);

    // fmi2GetFMUstate into an existing state reuses it.
    let before = s.raw();
    ok!(b, b.set_state(&s));
    run(&mut b, &vrs, 4, 6, t4, H);
    ok!(b, b.update_state(&mut s));
    assert_eq!(s.raw(), before);
    ok!(b, b.set_state(&s));
    assert_eq!(run(&mut b, &vrs, 6, 10, 6.0 * H, H), straight[6..]);

    for (inst, st) in [(&mut b, s), (&mut c, sc), (&mut d, sd)] {
        ok!(inst, inst.free_state(st));
    }
}

#[test]
fn states_keep_input_derivatives_tuned_parameters_and_the_averaging_window() {
    let fmu = load("contact.toml", "state-slopes");
    let vrs = all_vrs(&scene("contact.toml"));
    // Steps of 0.3 ms: the F_mean window (one 0.5 ms period) ends inside steps.
    let h = 3e-4;
    let prelude = |i: &mut vibrofric_import::Instance| {
        run(i, &vrs, 0, 3, 0.0, h);
        ok!(i, i.set_real(&[vr::U0, vr::F], &[3e-7, 1500.0]));
        ok!(
            i,
            i.set_real_input_derivatives(&[vr::F_D, vr::V_SX], &[1, 1], &[500.0, -0.2])
        );
    };
    let mut a = started(&fmu, "a", &[]);
    prelude(&mut a);
    let t3 = 3.0 * h;
    let straight = run(&mut a, &vrs, 3, 12, t3, h);

    let mut b = started(&fmu, "b", &[]);
    prelude(&mut b);
    let s = b.get_state().unwrap();
    let bytes = b.serialize_state(&s).unwrap();
    assert_eq!(run(&mut b, &vrs, 3, 12, t3, h), straight);
    ok!(b, b.set_state(&s));
    assert_eq!(run(&mut b, &vrs, 3, 12, t3, h), straight);

    let mut c = fmu.instantiate("c").unwrap();
    let sc = c.deserialize_state(&bytes).unwrap();
    ok!(c, c.set_state(&sc));
    assert_eq!(run(&mut c, &vrs, 3, 12, t3, h), straight);
}

#[test]
fn a_state_taken_in_initialization_mode_and_the_state_machine_state() {
    let fmu = load("contact.toml", "state-init");
    let vrs = all_vrs(&scene("contact.toml"));
    let init = |i: &mut vibrofric_import::Instance| {
        ok!(i, i.setup_experiment(Some(1e-7), 0.0, None));
        ok!(i, i.enter_initialization_mode());
        ok!(
            i,
            i.set_real(&[vr::M, vr::F_D, vr::V_SY], &[4.0, 2.0, 1e-3])
        );
        ok!(i, i.set_real_input_derivatives(&[vr::V_SY], &[1], &[-1.0]));
    };
    let mut a = fmu.instantiate("a").unwrap();
    init(&mut a);
    ok!(a, a.exit_initialization_mode());
    let straight = run(&mut a, &vrs, 0, 5, 0.0, H);

    let mut b = fmu.instantiate("b").unwrap();
    init(&mut b);
    let s = b.get_state().unwrap();
    let bytes = b.serialize_state(&s).unwrap();
    let mut c = fmu.instantiate("c").unwrap();
    let sc = c.deserialize_state(&bytes).unwrap();
    ok!(c, c.set_state(&sc));
    // The state machine state came along: initialization mode.
    assert_eq!(c.enter_initialization_mode(), Status::Error);
    ok!(c, c.set_state(&sc));
    assert_eq!(c.get_real(&[vr::M]).unwrap(), vec![4.0]);
    ok!(c, c.exit_initialization_mode());
    assert_eq!(run(&mut c, &vrs, 0, 5, 0.0, H), straight);

    // A state of a terminated instance restores a terminated instance.
    ok!(a, a.terminate());
    let st = a.get_state().unwrap();
    let bytes = a.serialize_state(&st).unwrap();
    let mut d = fmu.instantiate("d").unwrap();
    let sd = d.deserialize_state(&bytes).unwrap();
    ok!(d, d.set_state(&sd));
    assert_eq!(d.do_step(5.0 * H, H), Status::Error);
    assert!(d.last_message().contains("Terminated"));
    ok!(d, d.set_state(&sd));
    assert_eq!(d.get_real(&vrs).unwrap(), a.get_real(&vrs).unwrap());
    assert_eq!(d.get_real_status(2), (Status::Ok, 5.0 * H));
}

#[test]
fn a_state_of_another_fmu_is_refused_naming_both_guids() {
    let dahl = load("contact.toml", "state-dahl");
    let lugre = load("contact-lugre.toml", "state-lugre");
    let mut a = started(&dahl, "a", &[]);
    ok!(a, a.do_step(0.0, H));
    let s = a.get_state().unwrap();
    let bytes = a.serialize_state(&s).unwrap();
    let mut b = started(&lugre, "b", &[]);
    ok!(b, b.do_step(0.0, H));
    let before = b.get_real(&all_vrs(&scene("contact-lugre.toml"))).unwrap();
    assert_eq!(b.deserialize_state(&bytes).err(), Some(Status::Error));
    let msg = b.last_message();
    assert!(
        msg.contains(&dahl.description.guid) && msg.contains(&lugre.description.guid),
        "{msg}"
    );
    assert_eq!(
        b.get_real(&all_vrs(&scene("contact-lugre.toml"))).unwrap(),
        before
    );
}

#[test]
fn free_state_accepts_null_and_states_survive_reset() {
    let fmu = load("contact.toml", "state-free");
    let vrs = all_vrs(&scene("contact.toml"));
    let mut a = started(&fmu, "a", &[]);
    let f = *a.functions();
    let mut p = std::ptr::null_mut();
    assert_eq!(unsafe { (f.fmi2FreeFMUstate)(a.raw(), &mut p) }, 0);
    run(&mut a, &vrs, 0, 2, 0.0, H);
    let s = a.get_state().unwrap();
    let straight = run(&mut a, &vrs, 2, 4, 2.0 * H, H);
    ok!(a, a.reset());
    ok!(a, a.set_state(&s));
    assert_eq!(run(&mut a, &vrs, 2, 4, 2.0 * H, H), straight);
    ok!(a, a.free_state(s));
}

/// `bytes` (a serialized state) with one field of the contact's state changed by `edit`,
/// written back in the FMU's own format (so that magic, version and checksum all pass).
fn crafted(bytes: &[u8], edit: impl Fn(&mut ContactState)) -> Vec<u8> {
    let mut state = saved::decode(bytes).unwrap();
    edit(state.sim.as_mut().unwrap());
    saved::encode(&state)
}

/// A serialized state is untrusted input: one whose checksum matches but whose fields are
/// inconsistent or out of range is refused naming the field, and the instance goes on as
/// before (it used to accept them and then return NaN, loop, or refuse every later call).
#[test]
fn crafted_states_are_refused_field_by_field() {
    let fmu = load("contact.toml", "state-crafted");
    let vrs = all_vrs(&scene("contact.toml"));
    let mut a = started(&fmu, "a", &[]);
    ok!(a, a.do_step(0.0, H));
    let s = a.get_state().unwrap();
    let bytes = a.serialize_state(&s).unwrap();
    type Edit = fn(&mut ContactState);
    let cases: [(Edit, &str); 10] = [
        (|s| s.params.f = 1e12, "parameter f = 1e12"),
        (
            |s| s.window.acc = f64::NEG_INFINITY,
            "window integral is -inf",
        ),
        (|s| s.window.len = 0.0, "window length = 0"),
        (
            |s| s.window.index = u64::MAX,
            "window index = 18446744073709551615",
        ),
        (|s| s.tracks[0].value = 5e9, "input F_d = 5000000000"),
        (
            |s| s.harmonic_theta_ref = 7.0,
            "harmonic phase reference = 7",
        ),
        (|s| s.config.law = Law::LuGre, "taken from another scene"),
        (
            |s| s.direction = 0.5,
            "branch of the explicit path 0.5: must be -1, 0 or 1",
        ),
        (
            |s| s.exp_h = f64::NAN,
            "step proposal of the explicit paths = NaN: must be a length >= 0",
        ),
        (
            |s| s.exp_h = -1e-3,
            "step proposal of the explicit paths = -0.001: must be a length >= 0",
        ),
    ];
    let mut b = started(&fmu, "b", &[]);
    ok!(b, b.do_step(0.0, H));
    let before = b.get_real(&vrs).unwrap();
    for (edit, field) in cases {
        assert_eq!(
            b.deserialize_state(&crafted(&bytes, edit)).err(),
            Some(Status::Error),
            "{field}"
        );
        let msg = b.last_message();
        assert!(msg.contains(field), "{field}: {msg}");
        assert_eq!(b.get_real(&vrs).unwrap(), before, "{field}");
    }
    // The untouched state still restores, also after all that.
    let sb = b.deserialize_state(&bytes).unwrap();
    ok!(b, b.set_state(&sb));
    ok!(b, b.do_step(H, H));
    // A step proposal of +inf (nothing bounds the step) is one a path stores: it restores and
    // continues as the proposal of the step's own length (a step to the target either way).
    let ones = |s: &mut ContactState| s.exp_h = f64::INFINITY;
    let sb = b.deserialize_state(&crafted(&bytes, ones)).unwrap();
    ok!(b, b.set_state(&sb));
    ok!(b, b.do_step(H, H));
}

/// The case: PaperTransverse, no experiment set up, `u0` = 6.25e-7, `v_d` = 1e-308
/// (a subnormal sliding velocity), then `f` = -0 (no vibration): nothing bounds the planar
/// explicit path's step, whose proposal is +inf. The state saved after the first step restores
/// after a refused step (a target time not later than the current one), in the same instance
/// and serialized into a fresh one, and continues bit for bit; it used to be refused ("exponential
/// step is inf: every number must be finite").
#[test]
fn a_state_saved_with_an_unbounded_step_proposal_restores() {
    let file = "paper-transverse.toml";
    let fmu = load(file, "state-unbounded");
    let vrs = all_vrs(&scene(file));
    let mut a = fmu.instantiate("a").unwrap();
    ok!(a, a.enter_initialization_mode());
    ok!(a, a.set_real(&[vr::U0], &[6.25e-7]));
    ok!(a, a.set_real(&[vr::V_D], &[1e-308]));
    ok!(a, a.exit_initialization_mode());
    ok!(a, a.set_real(&[vr::F], &[-0.0]));
    ok!(a, a.do_step(0.0, 1e-3));
    let s = a.get_state().unwrap();
    let bytes = a.serialize_state(&s).unwrap();
    let proposal = saved::decode(&bytes).unwrap().sim.unwrap().exp_h;
    assert_eq!(proposal, f64::INFINITY, "the case this test is about");
    let continuation = |i: &mut vibrofric_import::Instance| {
        ok!(i, i.do_step(1e-3, 1e-3));
        bits(&i.get_real(&vrs).unwrap())
    };
    let straight = continuation(&mut a);
    assert_eq!(a.do_step(2e-3, 1e-300), Status::Error);
    ok!(a, a.set_state(&s));
    assert_eq!(continuation(&mut a), straight);
    let mut b = fmu.instantiate("b").unwrap();
    let sb = b.deserialize_state(&bytes).unwrap();
    ok!(b, b.set_state(&sb));
    assert_eq!(continuation(&mut b), straight);
}

/// Whether `x` is a value `vr` accepts in scene `sc`: a parameter in its range (and, `tuned`,
/// one that may change after initialization), or an input by its rule.
fn accepts(sc: &Scene, vr: u32, x: f64, tuned: bool) -> bool {
    let c = &sc.config;
    sc.variables().any(|v| {
        v.vr == vr
            && match v.kind {
                VarKind::Param(p) => {
                    p.check_in(x, c).is_ok() && (!tuned || v.variability(c) == Variability::Tunable)
                }
                VarKind::Input(i) => v.causality(c) == Causality::Input && i.rule().holds(x),
                _ => false,
            }
    })
}

/// Every saved state restores, bit for bit, at the edges of the accepted values: on every
/// standard scene, at start times from 0 to 1e7 s, with subnormal, zero and extreme in-range
/// inputs and parameters set in initialization and after it (`f` = 0 and -0, `u0` = 0 and
/// subnormal, `v_d` = 1e-308, subnormal forces and coefficients, the stiffest contact), a state
/// saved after each of two steps continues as the instance it was taken from over three more
/// steps (statuses and every value), restored into the same instance after a refused step and
/// serialized into a fresh one. The paths the steps take (from the model built with the same
/// values) are all five integrators.
#[test]
fn states_saved_at_the_edges_of_the_values_restore_bit_for_bit() {
    use vibrofric::model::{Integrator, Setup};
    type Sets = &'static [(u32, f64)];
    // (set in initialization, set after it)
    let variants: [(Sets, Sets); 11] = [
        (&[(vr::U0, 6.25e-7), (vr::V_D, 1e-308)], &[(vr::F, -0.0)]),
        (&[(vr::F, 0.0), (vr::U0, 0.0)], &[]),
        (
            &[(vr::U0, 5e-324), (vr::F_D, 5e-324), (vr::V_D, 5e-324)],
            &[],
        ),
        (&[(vr::V_SX, -1e-308), (vr::V_SY, 1e-308)], &[(vr::U0, 0.0)]),
        (&[(vr::MU, 5e-324)], &[(vr::F_D, 1e-300)]),
        (&[(vr::F_N, 1e-300)], &[(vr::V_D, 0.0)]),
        (&[(vr::V_D, 0.0), (vr::F_D, 0.0)], &[(vr::F, 0.0)]),
        (&[(vr::K_T, 1e12)], &[(vr::V_D, 1e-308)]),
        (&[(vr::K_T, 1e11), (vr::V_D, 2.0)], &[(vr::F_D, -1e-308)]),
        (&[(vr::M, 1e-6), (vr::F_D, 1e3)], &[]),
        (&[], &[(vr::U0, 1e-3), (vr::F, 1e4)]),
    ];
    let mut paths = std::collections::BTreeSet::new();
    let mut round_trips = 0;
    for (file, sc) in standard_scenes() {
        let fmu = load(file, &format!("state-edges-{file}"));
        let vrs = all_vrs(&sc);
        for (init, after) in variants {
            let init: Vec<_> = init
                .iter()
                .copied()
                .filter(|&(v, x)| accepts(&sc, v, x, false))
                .collect();
            let after: Vec<_> = after
                .iter()
                .copied()
                .filter(|&(v, x)| accepts(&sc, v, x, true))
                .collect();
            for t0 in [0.0, 16384.0, 1e5, 1e7] {
                let case = format!("{file} at {t0} s, {init:?} then {after:?}");
                let start = |name: &str| {
                    let mut i = fmu.instantiate(name).unwrap();
                    ok!(i, i.setup_experiment(Some(1e-6), t0, None));
                    ok!(i, i.enter_initialization_mode());
                    for &(v, x) in &init {
                        ok!(i, i.set_real(&[v], &[x]));
                    }
                    ok!(i, i.exit_initialization_mode());
                    for &(v, x) in &after {
                        ok!(i, i.set_real(&[v], &[x]));
                    }
                    i
                };
                // The same values in the model, for the paths the steps take.
                let mut params = sc.start;
                let mut inputs = sc.inputs;
                for &(v, x) in &init {
                    match sc.variables().find(|w| w.vr == v).unwrap().kind {
                        VarKind::Param(p) => p.set(&mut params, x).unwrap(),
                        VarKind::Input(i) => *i.slot(&mut inputs) = x,
                        _ => unreachable!(),
                    }
                }
                let mut sim = Setup::new(sc.config, params)
                    .inputs(inputs)
                    .start(t0)
                    .tolerance(1e-6)
                    .build()
                    .unwrap();
                for &(v, x) in &after {
                    match sc.variables().find(|w| w.vr == v).unwrap().kind {
                        VarKind::Param(p) => sim.set_param(p, x).unwrap(),
                        VarKind::Input(i) => sim.set_input(i, x).unwrap(),
                        _ => unreachable!(),
                    }
                }
                let steps: Vec<f64> = (1..=5).map(|k| t0 + k as f64 * H).collect();
                for &t in &steps {
                    paths.insert(format!("{:?}", sim.integrator()));
                    if sim.step_to(t).is_err() {
                        break;
                    }
                }
                let go = |i: &mut vibrofric_import::Instance, from: usize, to: usize| {
                    (from..to)
                        .map(|k| {
                            let t = if k == 0 { t0 } else { steps[k - 1] };
                            let s = i.do_step(t, steps[k] - t);
                            (s, i.get_real(&vrs).map(|v| bits(&v)))
                        })
                        .collect::<Vec<_>>()
                };
                let mut a = start("a");
                let straight = go(&mut a, 0, 5);
                for saved_after in [1, 2] {
                    if straight[..saved_after]
                        .iter()
                        .any(|(s, _)| *s != Status::Ok)
                    {
                        continue;
                    }
                    let mut b = start("b");
                    go(&mut b, 0, saved_after);
                    let st = b.get_state().unwrap();
                    let bytes = b.serialize_state(&st).unwrap();
                    let want = &straight[saved_after..];
                    assert_eq!(go(&mut b, saved_after, 5), want, "{case}: taking the state");
                    // A step too short to advance: refused, the instance in Error.
                    let t = steps[4];
                    assert_eq!(b.do_step(t, 1e-300), Status::Error, "{case}");
                    let s = b.set_state(&st);
                    assert_eq!(s, Status::Ok, "{case}: {}", b.last_message());
                    assert_eq!(go(&mut b, saved_after, 5), want, "{case}: same instance");
                    let mut c = fmu.instantiate("c").unwrap();
                    let sc2 = c.deserialize_state(&bytes);
                    let sc2 = sc2.unwrap_or_else(|_| panic!("{case}: {}", c.last_message()));
                    let s = c.set_state(&sc2);
                    assert_eq!(s, Status::Ok, "{case}: {}", c.last_message());
                    assert_eq!(go(&mut c, saved_after, 5), want, "{case}: fresh instance");
                    round_trips += 1;
                }
            }
        }
    }
    let all: Vec<String> = [
        Integrator::ClosedForm,
        Integrator::Exponential,
        Integrator::Explicit,
        Integrator::ExplicitPlanar,
        Integrator::Radau,
    ]
    .iter()
    .map(|p| format!("{p:?}"))
    .collect();
    let missing: Vec<_> = all.iter().filter(|p| !paths.contains(*p)).collect();
    assert!(
        missing.is_empty(),
        "paths not taken: {missing:?} (taken: {paths:?})"
    );
    assert!(round_trips > 500, "{round_trips} round trips");
    println!("{round_trips} states restored bit for bit; paths taken: {paths:?}");
}

/// A state saved after a step from a late start time restores, in the same instance and
/// serialized into a fresh one, and continues bit for bit. The step ends on a window boundary
/// that the start time's rounding puts a few ulps of the absolute time off it; the check of
/// the restored state used to compare that time with a slack relative to the time since the
/// start and refused it (from start time 16384 s on).
#[test]
fn a_state_saved_at_a_late_start_time_restores_and_continues() {
    for file in STANDARD_SCENES {
        let fmu = load(file, &format!("state-late-{file}"));
        let vrs = all_vrs(&scene(file));
        for start in [16383.0, 16384.0, 1e5, 1e7] {
            for h in [5e-4, 1.5e-3, 2.5e-3, 1e-2] {
                let what = format!("{file}: start {start}, step {h}");
                let mut a = fmu.instantiate("a").unwrap();
                ok!(a, a.setup_experiment(Some(1e-6), start, None));
                ok!(a, a.enter_initialization_mode());
                ok!(a, a.exit_initialization_mode());
                ok!(a, a.do_step(start, h));
                let s = a.get_state().unwrap();
                assert_eq!(a.set_state(&s), Status::Ok, "{what}: {}", a.last_message());
                let bytes = a.serialize_state(&s).unwrap();
                let mut b = fmu.instantiate("b").unwrap();
                let sb = b.deserialize_state(&bytes);
                assert!(sb.is_ok(), "{what}: {}", b.last_message());
                ok!(b, b.set_state(&sb.unwrap()));
                ok!(a, a.do_step(start + h, h));
                ok!(b, b.do_step(start + h, h));
                assert_eq!(
                    bits(&a.get_real(&vrs).unwrap()),
                    bits(&b.get_real(&vrs).unwrap()),
                    "{what}"
                );
                a.free_state(s);
            }
        }
    }
}

/// Model Exchange: the importer sets the time anywhere (beyond the averaging window in
/// progress, before its start); a state saved there restores, also serialized into a fresh
/// instance, and evaluates as the original. It used to be refused as "outside the averaging
/// window".
#[test]
fn a_model_exchange_state_saved_after_set_time_anywhere_restores() {
    let file = "contact.toml";
    let fmu = load(file, "state-me-time");
    let sc = scene(file);
    let vrs = all_vrs(&sc);
    let nx = state_count(&sc);
    // The window is the vibration period, 5e-4 s.
    for t in [6e-4, 2.2e-3, -1e-4, 3e3] {
        let mut a = fmu.instantiate_model_exchange("a").unwrap();
        ok!(a, a.setup_experiment(Some(1e-6), 0.0, None));
        ok!(a, a.enter_initialization_mode());
        ok!(a, a.exit_initialization_mode());
        ok!(a, a.new_discrete_states().0);
        ok!(a, a.enter_continuous_time_mode());
        ok!(a, a.set_time(t));
        let s = a.get_state().unwrap();
        assert_eq!(a.set_state(&s), Status::Ok, "t = {t}: {}", a.last_message());
        let bytes = a.serialize_state(&s).unwrap();
        let mut b = fmu.instantiate_model_exchange("b").unwrap();
        let sb = b.deserialize_state(&bytes);
        assert!(sb.is_ok(), "t = {t}: {}", b.last_message());
        ok!(b, b.set_state(&sb.unwrap()));
        assert_eq!(
            bits(&a.get_derivatives(nx).unwrap()),
            bits(&b.get_derivatives(nx).unwrap()),
            "t = {t}"
        );
        assert_eq!(
            bits(&a.get_real(&vrs).unwrap()),
            bits(&b.get_real(&vrs).unwrap()),
            "t = {t}"
        );
        a.free_state(s);
    }
}

/// A saved state carries the interface and the standard's edition of the instance that saved
/// it and restores only into the same: a Co-Simulation state in a Model Exchange instance (and
/// the converse), or an FMI 2.0 state in an FMI 3.0 instance, is refused naming both, and the
/// instance is unchanged. A Model Exchange instance used to accept a Co-Simulation state and
/// then run fmi2DoStep.
#[test]
fn a_state_restores_only_into_its_interface_and_edition() {
    let file = "contact.toml";
    let fmu = load(file, "state-interface");
    let vrs = all_vrs(&scene(file));
    let mut cs = started(&fmu, "cs", &[]);
    ok!(cs, cs.do_step(0.0, H));
    let s_cs = cs.get_state().unwrap();
    let b_cs = cs.serialize_state(&s_cs).unwrap();

    let mut me = fmu.instantiate_model_exchange("me").unwrap();
    ok!(me, me.setup_experiment(Some(1e-6), 0.0, None));
    ok!(me, me.enter_initialization_mode());
    ok!(me, me.exit_initialization_mode());
    let before = me.get_real(&vrs).unwrap();
    let s_me = me.get_state().unwrap();
    let b_me = me.serialize_state(&s_me).unwrap();
    assert_eq!(me.deserialize_state(&b_cs).err(), Some(Status::Error));
    let msg = me.last_message();
    assert!(
        msg.contains("saved by an FMI 2.0 Co-Simulation instance")
            && msg.contains("this instance is FMI 2.0 Model Exchange"),
        "{msg}"
    );
    assert_eq!(me.get_real(&vrs).unwrap(), before);
    // The same pointer handed across, without serialization.
    assert_eq!(me.set_state(&s_cs), Status::Error);
    assert!(me
        .last_message()
        .contains("saved by an FMI 2.0 Co-Simulation instance"));
    // The instance is in Error: no fmi2DoStep in Model Exchange, whatever state it holds.
    assert_eq!(me.do_step(H, H), Status::Error);
    ok!(me, me.reset());

    assert_eq!(cs.deserialize_state(&b_me).err(), Some(Status::Error));
    assert!(cs
        .last_message()
        .contains("saved by an FMI 2.0 Model Exchange instance"));
    ok!(cs, cs.reset());

    // FMI 2.0 bytes into the FMI 3.0 library of the same scene (same instantiation token).
    let fmu3 = load3(file, "state-interface-3");
    let mut c3 = fmu3.instantiate("c3").unwrap();
    assert_eq!(c3.deserialize_state(&b_cs).err(), Some(Status::Error));
    let msg = c3.last_message();
    assert!(
        msg.contains("saved by an FMI 2.0 Co-Simulation instance")
            && msg.contains("this instance is FMI 3.0 Co-Simulation"),
        "{msg}"
    );
    // And the converse: FMI 3.0 bytes into FMI 2.0.
    assert_eq!(c3.reset(), Status::Ok);
    assert_eq!(
        c3.enter_initialization_mode(Some(1e-6), 0.0, None),
        Status::Ok
    );
    assert_eq!(c3.exit_initialization_mode(), Status::Ok);
    let s3 = c3.get_state().unwrap();
    let b3 = c3.serialize_state(&s3).unwrap();
    assert_eq!(cs.deserialize_state(&b3).err(), Some(Status::Error));
    assert!(cs
        .last_message()
        .contains("saved by an FMI 3.0 Co-Simulation instance"));
    c3.free_state(s3);
    cs.free_state(s_cs);
    me.free_state(s_me);
}
