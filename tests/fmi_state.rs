//! FMU state: get, set, free, serialise and deserialise. A state restored, in the same instance
//! or in a fresh one after serialisation, continues bit-for-bit like the original.

#[macro_use]
mod fmi_harness;

use fmi_harness::*;
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
    let cases: [(Edit, &str); 8] = [
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
}
