//! The bad-input classes of the FMI 2.0 tests (`fmi_bad_input.rs`), replayed on the FMI 3.0 C
//! functions of the same library: NULL pointers with nonzero lengths, a NULL instance, unknown
//! value references and forbidden causality, calls out of order, non-finite and out-of-range
//! values, bad communication steps, corrupted serialized states, and the FMI 3.0 specifics
//! (`nValues` ≠ `nValueReferences`, event mode asked for, interfaces not offered). Oracle: the
//! status is `fmi3Error`, the log line names the function and the rule, and every value reads
//! as before.

mod support;

use std::ffi::{c_void, CString};
use std::os::raw::c_char;
use std::ptr;

use libloading::{Library, Symbol};
use support::fmu::*;
use support::scenes::*;
use vibrofric::description::xml;
use vibrofric_import::fmi3::types::*;
use vibrofric_import::fmi3::{log_message, Log};

const OK: i32 = 0;
const ERROR: i32 = 3;

/// One FMI 3.0 instance of a standard scene, with its log.
struct Fmu3 {
    lib: Library,
    inst: *mut c_void,
    log: Box<Log>,
    vrs: Vec<u32>,
    _dir: std::path::PathBuf,
}

impl Fmu3 {
    fn new(file: &str, tag: &str) -> Fmu3 {
        let dir = temp(tag);
        let scene = unpack(&dir, &scene_text(file));
        let lib = unsafe { Library::new(library()) }.unwrap();
        let log: Box<Log> = Box::default();
        let resources = CString::new(format!("{}/", dir.join("resources").display())).unwrap();
        let token = CString::new(xml::guid(&scene)).unwrap();
        let name = CString::new("fmi3-bad").unwrap();
        let inst = unsafe {
            let f: Symbol<fmi3InstantiateCoSimulationTYPE> =
                lib.get(b"fmi3InstantiateCoSimulation").unwrap();
            f(
                name.as_ptr(),
                token.as_ptr(),
                resources.as_ptr(),
                false,
                false,
                false,
                false,
                ptr::null(),
                0,
                &*log as *const Log as *mut c_void,
                Some(log_message),
                None,
            )
        };
        assert!(!inst.is_null(), "{:?}", log.lock().unwrap());
        Fmu3 {
            lib,
            inst,
            log,
            vrs: all_vrs(&scene),
            _dir: dir,
        }
    }

    fn f<T: Copy>(&self, name: &str) -> T {
        unsafe { *self.lib.get::<T>(name.as_bytes()).unwrap() }
    }

    fn last(&self) -> String {
        self.log.lock().unwrap().last().cloned().unwrap_or_default()
    }

    fn start(&self) {
        unsafe {
            assert_eq!(
                self.f::<fmi3EnterInitializationModeTYPE>("fmi3EnterInitializationMode")(
                    self.inst, false, 0.0, 0.0, false, 0.0
                ),
                OK
            );
            assert_eq!(
                self.f::<fmi3InstanceOnlyTYPE>("fmi3ExitInitializationMode")(self.inst),
                OK
            );
        }
    }

    fn step(&self, t: f64, h: f64) -> i32 {
        let (mut a, mut b, mut c, mut last) = (false, false, false, 0.0);
        unsafe {
            self.f::<fmi3DoStepTYPE>("fmi3DoStep")(
                self.inst, t, h, false, &mut a, &mut b, &mut c, &mut last,
            )
        }
    }

    fn values(&self) -> Vec<u64> {
        let mut v = vec![0.0; self.vrs.len()];
        let s = unsafe {
            self.f::<fmi3GetFloat64TYPE>("fmi3GetFloat64")(
                self.inst,
                self.vrs.as_ptr(),
                self.vrs.len(),
                v.as_mut_ptr(),
                v.len(),
            )
        };
        assert_eq!(s, OK, "{}", self.last());
        v.iter().map(|x| x.to_bits()).collect()
    }

    fn get_state(&self) -> *mut c_void {
        let mut s = ptr::null_mut();
        assert_eq!(
            unsafe { self.f::<fmi3GetFMUStateTYPE>("fmi3GetFMUState")(self.inst, &mut s) },
            OK
        );
        s
    }

    fn set_state(&self, s: *mut c_void) {
        assert_eq!(
            unsafe { self.f::<fmi3SetFMUStateTYPE>("fmi3SetFMUState")(self.inst, s) },
            OK,
            "{}",
            self.last()
        );
    }

    /// Runs `bad`, which must return `fmi3Error` with a log line containing every word of
    /// `says`, then restores `state` and checks that every value reads as before.
    fn refuses(
        &self,
        what: &str,
        says: &[&str],
        state: *mut c_void,
        before: &[u64],
        bad: impl FnOnce(&Fmu3) -> i32,
    ) {
        let s = bad(self);
        assert_eq!(s, ERROR, "{what}: status {s}, log {}", self.last());
        let msg = self.last();
        for w in says {
            assert!(msg.contains(w), "{what}: {w:?} not in {msg:?}");
        }
        self.set_state(state);
        assert_eq!(self.values(), before, "{what}: values changed");
    }
}

impl Drop for Fmu3 {
    fn drop(&mut self) {
        unsafe {
            let free: Symbol<fmi3FreeInstanceTYPE> = self.lib.get(b"fmi3FreeInstance").unwrap();
            free(self.inst);
        }
    }
}

#[test]
fn every_bad_input_class_of_fmi2_is_refused_by_fmi3_naming_the_rule() {
    let fmu = Fmu3::new("contact.toml", "fmi3-bad");
    fmu.start();
    assert_eq!(fmu.step(0.0, 1e-3), OK);
    let state = fmu.get_state();
    let before = fmu.values();
    let t = 1e-3;
    let (k_t, f_d, x) = (vr::K_T, vr::F_D, vr::X);
    let get: fmi3GetFloat64TYPE = fmu.f("fmi3GetFloat64");
    let set: fmi3SetFloat64TYPE = fmu.f("fmi3SetFloat64");
    let inst = fmu.inst;
    unsafe {
        // NULL arrays with nonzero lengths, and nValues ≠ nValueReferences.
        fmu.refuses(
            "get NULL vrs",
            &["fmi3GetFloat64", "valueReferences = NULL"],
            state,
            &before,
            |_| {
                let mut v = [0.0; 2];
                get(inst, ptr::null(), 2, v.as_mut_ptr(), 2)
            },
        );
        fmu.refuses(
            "set NULL values",
            &["fmi3SetFloat64", "values = NULL"],
            state,
            &before,
            |_| set(inst, [f_d].as_ptr(), 1, ptr::null(), 1),
        );
        fmu.refuses(
            "nValues",
            &["fmi3GetFloat64", "nValues = 2"],
            state,
            &before,
            |_| {
                let mut v = [0.0; 2];
                get(inst, [x].as_ptr(), 1, v.as_mut_ptr(), 2)
            },
        );
        // Unknown value reference, causality output, fixed parameter after initialization.
        fmu.refuses(
            "unknown vr",
            &["fmi3SetFloat64", "999"],
            state,
            &before,
            |_| set(inst, [999].as_ptr(), 1, [1.0].as_ptr(), 1),
        );
        fmu.refuses(
            "output set",
            &["fmi3SetFloat64", "causality output"],
            state,
            &before,
            |_| set(inst, [x].as_ptr(), 1, [1.0].as_ptr(), 1),
        );
        fmu.refuses(
            "fixed",
            &[
                "fmi3SetFloat64",
                "k_t",
                "fixed",
                "before fmi3ExitInitializationMode",
            ],
            state,
            &before,
            |_| set(inst, [k_t].as_ptr(), 1, [2e8].as_ptr(), 1),
        );
        // Non-finite and out-of-range values; the first value of a pair is not written either.
        fmu.refuses(
            "NaN input",
            &["fmi3SetFloat64", "F_d"],
            state,
            &before,
            |_| set(inst, [f_d].as_ptr(), 1, [f64::NAN].as_ptr(), 1),
        );
        fmu.refuses("pair", &["fmi3SetFloat64", "F_d"], state, &before, |_| {
            set(
                inst,
                [vr::U0, f_d].as_ptr(),
                2,
                [1e-7, f64::INFINITY].as_ptr(),
                2,
            )
        });
        fmu.refuses(
            "mu range",
            &["fmi3SetFloat64", "mu"],
            state,
            &before,
            |_| set(inst, [vr::MU].as_ptr(), 1, [-0.1].as_ptr(), 1),
        );
        // Bad communication steps.
        fmu.refuses(
            "wrong point",
            &["fmi3DoStep", "currentCommunicationPoint"],
            state,
            &before,
            |f| f.step(t + 1.0, 1e-3),
        );
        fmu.refuses(
            "zero step",
            &["fmi3DoStep", "communicationStepSize"],
            state,
            &before,
            |f| f.step(t, 0.0),
        );
        fmu.refuses(
            "NaN step",
            &["fmi3DoStep", "communicationStepSize"],
            state,
            &before,
            |f| f.step(t, f64::NAN),
        );
        // Calls out of order.
        fmu.refuses(
            "exit init twice",
            &["fmi3ExitInitializationMode", "not allowed in state"],
            state,
            &before,
            |f| f.f::<fmi3InstanceOnlyTYPE>("fmi3ExitInitializationMode")(inst),
        );
        // Types this FMU has none of, and what it does not offer.
        fmu.refuses("Int32", &["fmi3GetInt32", "Int32"], state, &before, |f| {
            let mut v = [0i32];
            f.f::<fmi3GetInt32TYPE>("fmi3GetInt32")(inst, [k_t].as_ptr(), 1, v.as_mut_ptr(), 1)
        });
        fmu.refuses(
            "event mode",
            &["fmi3EnterEventMode", "a function of Model Exchange"],
            state,
            &before,
            |f| f.f::<fmi3InstanceOnlyTYPE>("fmi3EnterEventMode")(inst),
        );
        // A corrupted serialized state: one bit flipped, or one byte short.
        let mut size = 0;
        assert_eq!(
            fmu.f::<fmi3SerializedFMUStateSizeTYPE>("fmi3SerializedFMUStateSize")(
                inst, state, &mut size
            ),
            OK
        );
        let mut bytes = vec![0u8; size];
        assert_eq!(
            fmu.f::<fmi3SerializeFMUStateTYPE>("fmi3SerializeFMUState")(
                inst,
                state,
                bytes.as_mut_ptr(),
                size
            ),
            OK
        );
        let deserialize: fmi3DeserializeFMUStateTYPE = fmu.f("fmi3DeserializeFMUState");
        let mut flipped = bytes.clone();
        flipped[40] ^= 1;
        fmu.refuses(
            "flipped bit",
            &["fmi3DeserializeFMUState", "checksum"],
            state,
            &before,
            |_| {
                let mut s = ptr::null_mut();
                deserialize(inst, flipped.as_ptr(), flipped.len(), &mut s)
            },
        );
        fmu.refuses(
            "short",
            &["fmi3DeserializeFMUState", "truncated"],
            state,
            &before,
            |_| {
                let mut s = ptr::null_mut();
                deserialize(inst, bytes.as_ptr(), bytes.len() - 1, &mut s)
            },
        );
        // And the untouched bytes restore and step on.
        let mut s = ptr::null_mut();
        assert_eq!(deserialize(inst, bytes.as_ptr(), bytes.len(), &mut s), OK);
        fmu.set_state(s);
        assert_eq!(fmu.step(t, 1e-3), OK, "{}", fmu.last());
    }
}

#[test]
fn a_null_instance_returns_error_everywhere() {
    let fmu = Fmu3::new("contact.toml", "fmi3-null");
    let c = ptr::null_mut();
    let mut v = [0.0];
    let mut s = ptr::null_mut();
    let (mut a, mut b, mut e, mut last) = (false, false, false, 0.0);
    unsafe {
        let statuses = [
            fmu.f::<fmi3EnterInitializationModeTYPE>("fmi3EnterInitializationMode")(
                c, false, 0.0, 0.0, false, 0.0,
            ),
            fmu.f::<fmi3InstanceOnlyTYPE>("fmi3ExitInitializationMode")(c),
            fmu.f::<fmi3InstanceOnlyTYPE>("fmi3Terminate")(c),
            fmu.f::<fmi3InstanceOnlyTYPE>("fmi3Reset")(c),
            fmu.f::<fmi3GetFloat64TYPE>("fmi3GetFloat64")(c, [201].as_ptr(), 1, v.as_mut_ptr(), 1),
            fmu.f::<fmi3SetFloat64TYPE>("fmi3SetFloat64")(c, [101].as_ptr(), 1, v.as_ptr(), 1),
            fmu.f::<fmi3DoStepTYPE>("fmi3DoStep")(
                c, 0.0, 1e-3, false, &mut a, &mut b, &mut e, &mut last,
            ),
            fmu.f::<fmi3GetFMUStateTYPE>("fmi3GetFMUState")(c, &mut s),
            fmu.f::<fmi3InstanceOnlyTYPE>("fmi3EnterEventMode")(c),
        ];
        assert!(statuses.iter().all(|&s| s == ERROR), "{statuses:?}");
    }
}

#[test]
fn instantiation_refuses_a_wrong_token_event_mode_and_no_resources() {
    let dir = temp("fmi3-inst");
    let scene = unpack(&dir, &scene_text("contact.toml"));
    let lib = unsafe { Library::new(library()) }.unwrap();
    let f: fmi3InstantiateCoSimulationTYPE =
        unsafe { *lib.get(b"fmi3InstantiateCoSimulation").unwrap() };
    let resources = CString::new(format!("{}/", dir.join("resources").display())).unwrap();
    let good = CString::new(xml::guid(&scene)).unwrap();
    let bad = CString::new("{not-this-fmu}").unwrap();
    let name = CString::new("i").unwrap();
    let log: Box<Log> = Box::default();
    let env = &*log as *const Log as *mut c_void;
    let make = |token: &CString, res: *const c_char, event_mode: bool| unsafe {
        f(
            name.as_ptr(),
            token.as_ptr(),
            res,
            false,
            false,
            event_mode,
            false,
            ptr::null(),
            0,
            env,
            Some(log_message),
            None,
        )
    };
    for (token, res, event, says) in [
        (
            &bad,
            resources.as_ptr(),
            false,
            "instantiationToken = \"{not-this-fmu}\"",
        ),
        (&good, resources.as_ptr(), true, "eventModeUsed = true"),
        (&good, ptr::null(), false, "resourcePath = NULL"),
    ] {
        assert!(make(token, res, event).is_null());
        let msg = log.lock().unwrap().last().cloned().unwrap();
        assert!(
            msg.starts_with("fmi3InstantiateCoSimulation: ") && msg.contains(says),
            "{msg}"
        );
    }
    let inst = make(&good, resources.as_ptr(), false);
    assert!(!inst.is_null());
    unsafe {
        let free: fmi3FreeInstanceTYPE = *lib.get(b"fmi3FreeInstance").unwrap();
        free(inst);
    }
}

/// FMI 3.0's reads never apply a rule of leaving initialization either: on every LuGre scene,
/// at start times 0 and 1e7 s, `F_S` below the Coulomb force at the scene's load is accepted,
/// fmi3GetFloat64 reads every value in Initialization Mode with fmi3OK, bit for bit the values
/// at `F_S = F_C` (the deformation is 0 at the start: no static force enters), and reads them
/// again in Error after fmi3ExitInitializationMode refused the rule naming both forces.
#[test]
fn fmi3_reads_in_initialization_do_not_apply_the_static_force_rule() {
    use vibrofric::table::ParamId;
    use vibrofric_import::{CoSimulation, Status};
    let fs = ParamId::FS.vr();
    let mut cases = 0;
    for (file, sc) in standard_scenes() {
        let vrs = all_vrs(&sc);
        let Some(k) = vrs.iter().position(|&v| v == fs) else {
            continue;
        };
        let fmu = load3(file, &format!("fmi3-inconsistent-{file}"));
        let f_c = sc.start.reference_f_c();
        for t0 in [0.0, 1e7] {
            let init = |f_s: f64| {
                let mut i = fmu.instantiate("reads").unwrap();
                assert_eq!(i.enter_initialization(None, t0, None), Status::Ok);
                assert_eq!(i.set_f64(&[fs], &[f_s]), Status::Ok);
                i
            };
            let mut want = bits(&init(f_c).get_f64(&vrs).unwrap());
            for f_s in [0.0, 5e-324, f_c * 0.5, f_c * (1.0 - f64::EPSILON)] {
                let case = format!("{file} at {t0} s, F_S = {f_s:e}");
                let mut i = init(f_s);
                want[k] = f_s.to_bits();
                let read = i.get_f64(&vrs);
                let msg = i.last_message();
                assert_eq!(read.map(|v| bits(&v)), Ok(want.clone()), "{case}: {msg}");
                assert_eq!(i.exit_initialization_mode(), Status::Error, "{case}");
                let msg = i.last_message();
                assert!(
                    msg.contains("fmi3ExitInitializationMode: F_S = ")
                        && msg.contains("N is below the Coulomb force F_C = mu·F_N = "),
                    "{case}: {msg}"
                );
                let read = i.get_f64(&vrs);
                let msg = i.last_message();
                assert_eq!(
                    read.map(|v| bits(&v)),
                    Ok(want.clone()),
                    "{case}: in Error: {msg}"
                );
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 3 * 2 * 4, "three LuGre scenes");
}
