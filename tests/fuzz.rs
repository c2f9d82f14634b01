//! Seeded fuzzing of the C API and of the scene reader, with an invariant oracle.
//!
//! C API: random call sequences (in and out of order) on every standard scene's FMU, with values
//! from the edges of every range and beyond (NaN, ±inf, ±1e300, subnormals, 0, negatives),
//! unknown value references, wrong communication points, start times across the accepted range,
//! in-range values at the edges of floating point (subnormal forces and coefficients whose
//! products and quotients overflow), Model Exchange states far from any trajectory, calls of
//! the other interface, and serialized states that are corrupted (bit flips, truncation,
//! random bytes) or come from the other interface or FMI edition. The oracle, after every
//! call:
//! - the status is one the standard allows for a synchronous FMU (never fmi2Fatal or Pending);
//! - a call refused with fmi2Error or fmi2Discard changes no value the instance reports;
//! - fmi2GetReal never returns a non-finite value with fmi2OK, and after a call that was
//!   accepted it does not fail: every accepted value evaluates (Model Exchange may answer
//!   fmi2Discard for states set outside the model's domain);
//! - where fmi2GetReal is not allowed (Instantiated), a refused call leaves the staged values
//!   (read through a saved state) as they were;
//! - a state just saved restores (at any start time, after any step or fmi2SetTime);
//! - a function of the other interface, and a saved state of the other interface or of the
//!   other FMI edition, is refused with fmi2Error;
//! - fmi2Reset brings an instance back from fmi2Error;
//! - every call returns within `CALL_BOUND` (an oracle of the fuzzer, not a speed assertion).
//!
//! Scene reader: mutated standard scenes never panic; an accepted one exports a model
//! description that is well-formed XML.
//!
//! CI runs a bounded campaign (`VIBROFRIC_FUZZ_CALLS`, default 300 000 FMI 2.0 Co-Simulation
//! calls, `VIBROFRIC_FUZZ_CALLS_ME`, default 100 000 Model Exchange calls, and
//! `VIBROFRIC_FUZZ_CALLS3`, default 100 000 FMI 3.0 calls; about a minute); a long one (with
//! start times up to ±1e12 s: `VIBROFRIC_FUZZ_FAR_STARTS=1`; calls over 100 ms listed with
//! `VIBROFRIC_FUZZ_SLOW=1`):
//! `VIBROFRIC_FUZZ_CALLS=5000000 VIBROFRIC_FUZZ_SEED=7 cargo test --release --test fuzz -- --nocapture`

mod support;

use std::time::{Duration, Instant};

use support::fmu::*;
use support::scenes::*;
use vibrofric::description::scene::Scene;
use vibrofric::description::variables::VarKind;
use vibrofric::description::xml;
use vibrofric::fmi::saved;
use vibrofric::fmi::staging::Staged;
use vibrofric_import::Status;

/// xorshift64*: small, seeded, reproducible on every platform.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<T: Copy>(&mut self, v: &[T]) -> T {
        v[self.below(v.len())]
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

const CALL_BOUND: Duration = Duration::from_secs(10);

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Values at and beyond the edges of every range.
const EDGES: [f64; 22] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    1e-300,
    -1e-300,
    5e-324,
    1e300,
    -1e300,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    1e-12,
    1e12,
    1e13,
    1e7,
    1e-4,
    1e6,
    0.999,
    0.05,
    2e-7,
    1e3,
];

/// Values inside the ranges at the edges of floating point: subnormals, the smallest normal,
/// values whose products with others underflow and whose quotients overflow.
const TINY: [f64; 8] = [
    5e-324,
    1.5e-323,
    1e-310,
    1.5e-307,
    f64::MIN_POSITIVE,
    1e-300,
    1e-295,
    1e-290,
];

/// Start times across the range where importers start: half the sequences at 0, the rest at
/// the times where saved states used to fail (from 16384 s on) and anywhere up to ±1e7 s.
/// Beyond (setting up the experiment also tries 1e9 and 1e300) the absolute time's
/// resolution nears the vibration period and a step costs up to seconds: the long campaign
/// covers that with `VIBROFRIC_FUZZ_FAR_STARTS=1`.
fn start_time(rng: &mut Rng) -> f64 {
    let far = std::env::var("VIBROFRIC_FUZZ_FAR_STARTS").is_ok();
    match rng.below(16) {
        0..=7 => 0.0,
        8..=11 => rng.pick(&[16383.0, 16384.0, 1e5, 1e7, 12345.678, -5.0, 4.5 * 3600.0]),
        12..=14 => 10f64.powf(7.0 * rng.unit()),
        _ if far => 10f64.powf(7.0 + 5.0 * rng.unit()) * rng.pick(&[1.0, -1.0]),
        _ => -(10f64.powf(7.0 * rng.unit())),
    }
}

/// A value for a variable that starts at `start`: an edge, a tiny in-range value, near the
/// start, far from it, or its negative.
fn value(rng: &mut Rng, start: f64) -> f64 {
    match rng.below(5) {
        4 => rng.pick(&TINY),
        0 => rng.pick(&EDGES),
        1 => start * (1.0 + 0.5 * (rng.unit() - 0.5)),
        2 => start * 10f64.powf(8.0 * (rng.unit() - 0.5)),
        _ => -start,
    }
}

/// Every value of an instance, or the status that refused to read them.
type Values = Result<Vec<f64>, Status>;

/// The oracle after every call of a campaign, and what it counts.
#[derive(Default)]
struct Oracle {
    slowest: (Duration, String),
    by_status: [u64; 4],
    /// Calls over 100 ms: how many, and their total time.
    slow: (u64, Duration),
}

impl Oracle {
    /// The call `what` returned `status`, one of those `allowed` (never fmi2Fatal or Pending),
    /// within `CALL_BOUND`; the values of `vrs` read after it are finite when read with OK, and
    /// a call refused with Error or Discard left them as they were `before`, unless it is one
    /// that changes values (`may_change`: setting a saved state, reset).
    #[allow(clippy::too_many_arguments)]
    fn check(
        &mut self,
        sc: &Scene,
        what: &str,
        (status, allowed): (Status, &[Status]),
        took: Duration,
        (vrs, before, after): (&[u32], &Option<Vec<f64>>, &Values),
        (staged_before, staged_after): (&Option<Staged>, &Option<Staged>),
        may_change: bool,
        message: &str,
    ) {
        let id = &sc.model_identifier;
        assert!(took < CALL_BOUND, "{id}: {what} took {took:?}");
        if took > self.slowest.0 {
            self.slowest = (took, format!("{id}: {what}"));
        }
        if took > Duration::from_millis(100) {
            self.slow = (self.slow.0 + 1, self.slow.1 + took);
            if std::env::var("VIBROFRIC_FUZZ_SLOW").is_ok() {
                println!("slow: {took:?} {id}: {what}");
            }
        }
        assert!(
            allowed.contains(&status),
            "{id}: {what} returned {status:?}: {message}"
        );
        self.by_status[(status as usize).min(3)] += 1;
        if let Ok(values) = after {
            if let Some(k) = values.iter().position(|x| !x.is_finite()) {
                panic!("{id}: after {what}, vr {} = {} with OK", vrs[k], values[k]);
            }
        }
        // Every accepted value evaluates: a call accepted where values were readable leaves
        // them readable.
        if status == Status::Ok && before.is_some() && !may_change {
            assert!(
                !matches!(after, Err(Status::Error)),
                "{id}: {what} was accepted, then reading the values failed: {message}"
            );
        }
        let refused = matches!(status, Status::Error | Status::Discard);
        if refused && !may_change {
            if let (Some(b), Ok(a)) = (before, after) {
                assert_eq!(
                    bits(b),
                    bits(a),
                    "{id}: {what} was refused but changed values"
                );
            }
            if let (Some(b), Some(a)) = (staged_before, staged_after) {
                assert_eq!(b, a, "{id}: {what} was refused but changed staged values");
            }
        }
    }

    fn summary(&self) -> String {
        let [ok, warning, discard, error] = self.by_status;
        format!(
            "{ok} OK, {warning} warning, {discard} discard, {error} error; slowest {:?} ({}); {} calls over 100 ms, {:?} in all",
            self.slowest.0, self.slowest.1, self.slow.0, self.slow.1
        )
    }
}

/// The staged values of a saved state, the state machine's state left out.
fn staged_of(bytes: Option<Vec<u8>>) -> Option<Staged> {
    let mut s = saved::decode(&bytes?).ok()?.staged;
    s.state = vibrofric::fmi::State::Instantiated;
    Some(s)
}

/// An FMI 2.0 instance's staged values, read through a saved state: what a refused call must
/// leave as it was where fmi2GetReal is not allowed.
fn staged2(inst: &mut vibrofric_import::Instance) -> Option<Staged> {
    let st = inst.get_state().ok()?;
    let bytes = inst.serialize_state(&st).ok();
    inst.free_state(st);
    staged_of(bytes)
}

/// The same for an FMI 3.0 instance.
fn staged3(inst: &mut vibrofric_import::fmi3::Instance3) -> Option<Staged> {
    let st = inst.get_state().ok()?;
    let bytes = inst.serialize_state(&st).ok();
    inst.free_state(st);
    staged_of(bytes)
}

/// Serialized states of the other interfaces and editions of a scene's FMU, each after
/// initialization: an FMI 2.0 Co-Simulation, an FMI 2.0 Model Exchange and an FMI 3.0
/// Co-Simulation instance's.
struct Foreign {
    cs2: Vec<u8>,
    me2: Vec<u8>,
    cs3: Vec<u8>,
}

fn foreign(file: &str, tag: &str) -> Foreign {
    let fmu = load(file, &format!("fuzz-foreign-{tag}-{file}"));
    let fmu3 = load3(file, &format!("fuzz-foreign3-{tag}-{file}"));
    let bytes2 = |mut i: vibrofric_import::Instance| {
        i.enter_initialization_mode();
        i.exit_initialization_mode();
        let st = i.get_state().unwrap();
        let b = i.serialize_state(&st).unwrap();
        i.free_state(st);
        b
    };
    let mut c3 = fmu3.instantiate("foreign").unwrap();
    c3.enter_initialization_mode(None, 0.0, None);
    c3.exit_initialization_mode();
    let st = c3.get_state().unwrap();
    let cs3 = c3.serialize_state(&st).unwrap();
    c3.free_state(st);
    Foreign {
        cs2: bytes2(fmu.instantiate("foreign").unwrap()),
        me2: bytes2(fmu.instantiate_model_exchange("foreign").unwrap()),
        cs3,
    }
}

/// Deserializing a state of another interface or edition: refused with fmi2Error, saying so.
fn refuse_foreign(sc: &Scene, result: Result<(), Status>, message: &str) -> (Status, String) {
    let s = result.err().unwrap_or(Status::Ok);
    assert_eq!(
        s,
        Status::Error,
        "{}: a state of another interface or edition was accepted",
        sc.model_identifier
    );
    assert!(message.contains("restores only into"), "{message}");
    (s, "foreign state".into())
}

#[test]
fn c_api_call_sequences_keep_the_invariants() {
    let budget = env_u64("VIBROFRIC_FUZZ_CALLS", 300_000);
    let seed = env_u64("VIBROFRIC_FUZZ_SEED", 1);
    let fmus: Vec<_> = STANDARD_SCENES
        .iter()
        .map(|f| (load(f, &format!("fuzz-{f}")), scene(f), foreign(f, "cs")))
        .collect();
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let mut calls = 0u64;
    let mut oracle = Oracle::default();
    while calls < budget {
        let (fmu, sc, fr) = &fmus[rng.below(fmus.len())];
        let vrs = all_vrs(sc);
        let starts: Vec<f64> = sc
            .variables()
            .map(|v| sc.start_of(v).unwrap_or(1.0))
            .collect();
        let mut inst = fmu.instantiate("fuzz").unwrap();
        let mut t = 0.0;
        // Most sequences start from a properly initialized instance, so that the stepping
        // states are explored as much as the refusals.
        let init = |inst: &mut vibrofric_import::Instance, t0: f64| {
            inst.setup_experiment(Some(1e-6), t0, None);
            inst.enter_initialization_mode();
            inst.exit_initialization_mode();
        };
        if rng.below(4) != 0 {
            t = start_time(&mut rng);
            init(&mut inst, t);
        }
        let mut states = vec![];
        let mut saved: Vec<Vec<u8>> = vec![];
        for _ in 0..rng.below(200) + 1 {
            calls += 1;
            let before = inst.get_real(&vrs).ok();
            let staged_before = before.is_none().then(|| staged2(&mut inst)).flatten();
            // do_step and set_real most often.
            let op = rng.pick(&[
                0, 1, 2, 3, 4, 5, 6, 7, 7, 8, 8, 9, 9, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17,
            ]);
            let started = Instant::now();
            let (status, what) = match op {
                0 => {
                    let tol =
                        rng.pick(&[Some(1e-6), Some(5e-324), Some(1.0), None, Some(f64::NAN)]);
                    let t0 = match rng.below(2) {
                        0 => rng.pick(&[0.0, 1e9, -5.0, f64::NAN, 1e300]),
                        _ => start_time(&mut rng),
                    };
                    t = t0;
                    (
                        inst.setup_experiment(tol, t0, None),
                        format!("setup {tol:?} {t0}"),
                    )
                }
                1 => (inst.enter_initialization_mode(), "enter init".into()),
                2 => (inst.exit_initialization_mode(), "exit init".into()),
                3..=5 => {
                    let k = rng.below(vrs.len() + 1);
                    let (vr, x) = if k == vrs.len() {
                        (rng.pick(&[0u32, 99, 300, u32::MAX]), 1.0)
                    } else {
                        (vrs[k], value(&mut rng, starts[k]))
                    };
                    (inst.set_real(&[vr], &[x]), format!("set vr {vr} = {x:e}"))
                }
                6 => {
                    let k = rng.below(vrs.len());
                    let d = value(&mut rng, 1.0);
                    (
                        inst.set_real_input_derivatives(&[vrs[k]], &[rng.pick(&[1, 2, 0])], &[d]),
                        format!("derivative vr {} = {d:e}", vrs[k]),
                    )
                }
                7..=9 => {
                    let h = rng.pick(&[
                        1e-3,
                        1e-4,
                        1e-2,
                        1e-6,
                        0.0,
                        -1e-3,
                        f64::NAN,
                        2.0f64.powi(-10),
                        5e-4,
                        1.5e-3,
                        2.5e-3,
                    ]);
                    let current = if rng.below(8) == 0 { t + 1.0 } else { t };
                    let s = inst.do_step(current, h);
                    if s == Status::Ok {
                        t = current + h;
                    }
                    (s, format!("do_step {current} {h:e}"))
                }
                10 => (
                    inst.get_real_status(rng.pick(&[2, 0, 7])).0,
                    "real status".into(),
                ),
                11 => match inst.get_state() {
                    Ok(st) => {
                        // A state just saved restores, whatever the time.
                        let s = inst.set_state(&st);
                        assert_eq!(
                            s,
                            Status::Ok,
                            "{}: a state saved at t = {t} does not restore: {}",
                            sc.model_identifier,
                            inst.last_message()
                        );
                        states.push(st);
                        (Status::Ok, "get state".into())
                    }
                    Err(s) => (s, "get state".into()),
                },
                12 if !states.is_empty() => {
                    let k = rng.below(states.len());
                    (inst.set_state(&states[k]), "set state".into())
                }
                16 => {
                    // A function of Model Exchange on a Co-Simulation instance.
                    let f = fmu.model_exchange.unwrap();
                    let c = inst.raw();
                    let mut x = [0.0; 16];
                    let (code, name) = unsafe {
                        match rng.below(6) {
                            0 => ((f.fmi2GetContinuousStates)(c, x.as_mut_ptr(), 1), "states"),
                            1 => ((f.fmi2GetDerivatives)(c, x.as_mut_ptr(), 1), "derivatives"),
                            2 => (
                                (f.fmi2GetEventIndicators)(c, x.as_mut_ptr(), 1),
                                "indicators",
                            ),
                            3 => (
                                (f.fmi2GetNominalsOfContinuousStates)(c, x.as_mut_ptr(), 1),
                                "nominals",
                            ),
                            4 => ((f.fmi2SetTime)(c, t), "set time"),
                            _ => ((f.fmi2EnterEventMode)(c), "event mode"),
                        }
                    };
                    let s = vibrofric_import::status(code);
                    assert_eq!(
                        s,
                        Status::Error,
                        "{}: Model Exchange's {name} on Co-Simulation",
                        sc.model_identifier
                    );
                    (s, format!("Model Exchange {name}"))
                }
                17 => {
                    let b = if rng.below(2) == 0 { &fr.me2 } else { &fr.cs3 };
                    let r = inst
                        .deserialize_state(b)
                        .map(|st| inst.free_state(st))
                        .map(|_| ());
                    let m = inst.last_message();
                    refuse_foreign(sc, r, &m)
                }
                13 if !states.is_empty() => {
                    let k = rng.below(states.len());
                    match inst.serialize_state(&states[k]) {
                        Ok(b) => {
                            saved.push(b);
                            (Status::Ok, "serialize".into())
                        }
                        Err(s) => (s, "serialize".into()),
                    }
                }
                14 if !saved.is_empty() => {
                    let mut b = saved[rng.below(saved.len())].clone();
                    match rng.below(4) {
                        0 => {
                            let i = rng.below(b.len());
                            b[i] ^= 1 << rng.below(8);
                        }
                        1 => b.truncate(rng.below(b.len())),
                        2 => {
                            let from = rng.below(b.len());
                            b.iter_mut()
                                .skip(from)
                                .take(8)
                                .for_each(|x| *x = rng.next() as u8);
                        }
                        _ => {}
                    }
                    match inst.deserialize_state(&b) {
                        Ok(st) => {
                            let s = inst.set_state(&st);
                            (s, "deserialize + set".into())
                        }
                        Err(s) => (s, "deserialize".into()),
                    }
                }
                15 => {
                    if rng.below(2) == 0 {
                        (inst.terminate(), "terminate".into())
                    } else {
                        t = 0.0;
                        (inst.reset(), "reset".into())
                    }
                }
                _ => (
                    inst.get_real(&vrs).map_or_else(|s| s, |_| Status::Ok),
                    "get".into(),
                ),
            };
            let took = started.elapsed();
            let after = inst.get_real(&vrs);
            let message = inst.last_message();
            let staged_after = staged_before
                .is_some()
                .then(|| staged2(&mut inst))
                .flatten();
            oracle.check(
                sc,
                &what,
                (
                    status,
                    &[Status::Ok, Status::Warning, Status::Discard, Status::Error],
                ),
                took,
                (&vrs, &before, &after),
                (&staged_before, &staged_after),
                matches!(op, 12 | 14 | 15),
                &message,
            );
            if status == Status::Error {
                // The standard's way out of an error.
                let s = inst.reset();
                assert_eq!(
                    s,
                    Status::Ok,
                    "{}: reset after {what}: {}",
                    sc.model_identifier,
                    inst.last_message()
                );
                t = 0.0;
                if rng.below(4) != 0 {
                    t = start_time(&mut rng);
                    init(&mut inst, t);
                }
            }
        }
        for st in states {
            inst.free_state(st);
        }
    }
    println!("{calls} calls (seed {seed}): {}", oracle.summary());
}

/// The same campaign on the FMI 3.0 functions of the same library: random sequences of
/// initialization, `Float64` sets (edge values, unknown value references), steps (bad sizes,
/// wrong points), FMU states (corrupted serialized bytes), terminate and reset, with the same
/// oracle. Budget `VIBROFRIC_FUZZ_CALLS3` (default 100 000).
#[test]
fn fmi3_call_sequences_keep_the_invariants() {
    let budget = env_u64("VIBROFRIC_FUZZ_CALLS3", 100_000);
    let seed = env_u64("VIBROFRIC_FUZZ_SEED", 1);
    let fmus: Vec<_> = STANDARD_SCENES
        .iter()
        .map(|f| (load3(f, &format!("fuzz3-{f}")), scene(f), foreign(f, "3")))
        .collect();
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 3 | 1);
    let mut calls = 0u64;
    let mut oracle = Oracle::default();
    while calls < budget {
        let (fmu, sc, fr) = &fmus[rng.below(fmus.len())];
        let vrs = all_vrs(sc);
        let starts: Vec<f64> = sc
            .variables()
            .map(|v| sc.start_of(v).unwrap_or(1.0))
            .collect();
        let mut inst = fmu.instantiate("fuzz3").unwrap();
        let init = |inst: &mut vibrofric_import::fmi3::Instance3, t0: f64| {
            inst.enter_initialization_mode(Some(1e-6), t0, None);
            inst.exit_initialization_mode();
        };
        let mut t = 0.0;
        if rng.below(4) != 0 {
            t = start_time(&mut rng);
            init(&mut inst, t);
        }
        let (mut states, mut saved) = (vec![], vec![]);
        for _ in 0..rng.below(200) + 1 {
            calls += 1;
            let before = inst.get_f64(&vrs).ok();
            let staged_before = before.is_none().then(|| staged3(&mut inst)).flatten();
            let op = rng.pick(&[0, 1, 2, 2, 3, 3, 3, 4, 5, 6, 7, 8, 2, 3, 9]);
            let started = Instant::now();
            let (status, what) = match op {
                0 => {
                    let tol = rng.pick(&[Some(1e-6), Some(5e-324), None, Some(f64::NAN)]);
                    let t0 = match rng.below(2) {
                        0 => rng.pick(&[0.0, 1e9, f64::NAN]),
                        _ => start_time(&mut rng),
                    };
                    t = t0;
                    (
                        inst.enter_initialization_mode(tol, t0, None),
                        format!("enter init {tol:?} {t0}"),
                    )
                }
                1 => (inst.exit_initialization_mode(), "exit init".into()),
                2 => {
                    let k = rng.below(vrs.len() + 1);
                    let (vr, x) = if k == vrs.len() {
                        (rng.pick(&[0u32, 99, 300, u32::MAX]), 1.0)
                    } else {
                        (vrs[k], value(&mut rng, starts[k]))
                    };
                    (inst.set_f64(&[vr], &[x]), format!("set vr {vr} = {x:e}"))
                }
                3 => {
                    let h = rng.pick(&[1e-3, 1e-4, 1e-2, 0.0, -1e-3, f64::NAN, 5e-4, 2.5e-3]);
                    let current = if rng.below(8) == 0 { t + 1.0 } else { t };
                    let (s, _) = inst.do_step(current, h);
                    if s == Status::Ok {
                        t = current + h;
                    }
                    (s, format!("do_step {current} {h:e}"))
                }
                4 => match inst.get_state() {
                    Ok(st) => {
                        let s = inst.set_state(&st);
                        assert_eq!(
                            s,
                            Status::Ok,
                            "{}: a state saved at t = {t} does not restore: {}",
                            sc.model_identifier,
                            inst.last_message()
                        );
                        states.push(st);
                        (Status::Ok, "get state".into())
                    }
                    Err(s) => (s, "get state".into()),
                },
                5 if !states.is_empty() => {
                    let k = rng.below(states.len());
                    match rng.below(2) {
                        0 => (inst.set_state(&states[k]), "set state".into()),
                        _ => match inst.serialize_state(&states[k]) {
                            Ok(b) => {
                                saved.push(b);
                                (Status::Ok, "serialize".into())
                            }
                            Err(s) => (s, "serialize".into()),
                        },
                    }
                }
                6 if !saved.is_empty() => {
                    let mut b: Vec<u8> = saved[rng.below(saved.len())].clone();
                    match rng.below(3) {
                        0 => {
                            let i = rng.below(b.len());
                            b[i] ^= 1 << rng.below(8);
                        }
                        1 => b.truncate(rng.below(b.len())),
                        _ => {}
                    }
                    match inst.deserialize_state(&b) {
                        Ok(st) => (inst.set_state(&st), "deserialize + set".into()),
                        Err(s) => (s, "deserialize".into()),
                    }
                }
                7 => (inst.terminate(), "terminate".into()),
                9 => {
                    let b = if rng.below(2) == 0 { &fr.cs2 } else { &fr.me2 };
                    let r = inst
                        .deserialize_state(b)
                        .map(|st| inst.free_state(st))
                        .map(|_| ());
                    let m = inst.last_message();
                    refuse_foreign(sc, r, &m)
                }
                8 => {
                    t = 0.0;
                    (inst.reset(), "reset".into())
                }
                _ => (
                    inst.get_f64(&vrs).map_or_else(|s| s, |_| Status::Ok),
                    "get".into(),
                ),
            };
            let took = started.elapsed();
            let after = inst.get_f64(&vrs);
            let message = inst.last_message();
            let staged_after = staged_before
                .is_some()
                .then(|| staged3(&mut inst))
                .flatten();
            oracle.check(
                sc,
                &what,
                (
                    status,
                    &[Status::Ok, Status::Warning, Status::Discard, Status::Error],
                ),
                took,
                (&vrs, &before, &after),
                (&staged_before, &staged_after),
                matches!(op, 5 | 6 | 8),
                &message,
            );
            if status == Status::Error {
                let s = inst.reset();
                assert_eq!(
                    s,
                    Status::Ok,
                    "{}: reset after {what}: {}",
                    sc.model_identifier,
                    inst.last_message()
                );
                t = 0.0;
                if rng.below(4) != 0 {
                    t = start_time(&mut rng);
                    init(&mut inst, t);
                }
            }
        }
        for st in states {
            inst.free_state(st);
        }
    }
    println!("FMI 3.0: {calls} calls (seed {seed}): {}", oracle.summary());
}

#[test]
fn mutated_scenes_never_panic_and_accepted_ones_export_well_formed_xml() {
    let budget = env_u64("VIBROFRIC_FUZZ_SCENES", 4_000);
    let seed = env_u64("VIBROFRIC_FUZZ_SEED", 1);
    let mut rng = Rng(seed.wrapping_mul(0xd1b5_4a32_d192_ed03) | 1);
    let texts: Vec<String> = STANDARD_SCENES.iter().map(|f| scene_text(f)).collect();
    const INSERTS: [&str; 12] = [
        "\u{0}",
        "\u{1f}",
        "\u{fffe}",
        "\"",
        "\n",
        "[start]\n",
        "= 1e999",
        "é",
        "\\u0000",
        "[[x]]\n",
        "nan",
        "9999999999999999999999",
    ];
    let (mut accepted, mut refused) = (0, 0);
    for _ in 0..budget {
        let mut b = texts[rng.below(texts.len())].clone().into_bytes();
        for _ in 0..rng.below(4) + 1 {
            let i = rng.below(b.len() + 1);
            match rng.below(3) {
                0 if i < b.len() => b[i] = rng.next() as u8,
                1 => {
                    let ins = rng.pick(&INSERTS).as_bytes().to_vec();
                    b.splice(i..i, ins);
                }
                _ => b.truncate(i),
            }
        }
        let text = String::from_utf8_lossy(&b).into_owned();
        match std::panic::catch_unwind(|| Scene::parse(&text, "fuzz.toml").map_err(Box::new)) {
            Err(_) => panic!("the scene reader panicked on:\n{text}"),
            Ok(Err(e)) => {
                refused += 1;
                assert!(
                    !e.key.is_empty() || e.to_string().contains("fuzz.toml"),
                    "{e}"
                );
            }
            Ok(Ok(sc)) => {
                accepted += 1;
                let md = xml::model_description(&sc);
                let mut reader = quick_xml::Reader::from_str(&md);
                loop {
                    match reader.read_event() {
                        Ok(quick_xml::events::Event::Eof) => break,
                        Ok(_) => {}
                        Err(e) => panic!("ill-formed XML ({e}) from:\n{text}"),
                    }
                }
            }
        }
    }
    println!("{budget} mutated scenes: {accepted} accepted, {refused} refused with an error");
}

/// The same campaign on Model Exchange (FMI 2.0): random sequences of initialization, sets,
/// event updates, mode changes, times (edges, far beyond, backwards), continuous states (edge
/// values, wrong sizes), derivatives, event indicators, directional derivatives (unknown and
/// forbidden value references), FMU states (corrupted serialized bytes), terminate and reset,
/// with the same oracle. Budget `VIBROFRIC_FUZZ_CALLS_ME` (default 100 000).
#[test]
fn model_exchange_call_sequences_keep_the_invariants() {
    let budget = env_u64("VIBROFRIC_FUZZ_CALLS_ME", 100_000);
    let seed = env_u64("VIBROFRIC_FUZZ_SEED", 1);
    let fmus: Vec<_> = STANDARD_SCENES
        .iter()
        .map(|f| (load(f, &format!("fuzz-me-{f}")), scene(f), foreign(f, "me")))
        .collect();
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 3);
    let mut calls = 0u64;
    let mut oracle = Oracle::default();
    while calls < budget {
        let (fmu, sc, fr) = &fmus[rng.below(fmus.len())];
        let vrs = all_vrs(sc);
        let starts: Vec<f64> = sc
            .variables()
            .map(|v| sc.start_of(v).unwrap_or(1.0))
            .collect();
        let nx = sc
            .variables()
            .filter(|v| matches!(v.kind, VarKind::State(_)))
            .count();
        let ni = sc.config.event_indicators();
        let mut inst = fmu.instantiate_model_exchange("fuzz-me").unwrap();
        let mut t = 0.0;
        let init = |inst: &mut vibrofric_import::Instance, t0: f64| {
            inst.setup_experiment(Some(1e-6), t0, None);
            inst.enter_initialization_mode();
            inst.exit_initialization_mode();
            inst.new_discrete_states();
            inst.enter_continuous_time_mode();
        };
        if rng.below(4) != 0 {
            t = start_time(&mut rng);
            init(&mut inst, t);
        }
        let mut states = vec![];
        let mut saved: Vec<Vec<u8>> = vec![];
        for _ in 0..rng.below(200) + 1 {
            calls += 1;
            let before = inst.get_real(&vrs).ok();
            let staged_before = before.is_none().then(|| staged2(&mut inst)).flatten();
            let op = rng.pick(&[
                0, 1, 2, 3, 4, 5, 6, 6, 7, 7, 8, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17,
            ]);
            let started = Instant::now();
            let (status, what) = match op {
                0 => {
                    let t0 = match rng.below(2) {
                        0 => rng.pick(&[0.0, 1e9, -5.0, f64::NAN, 1e300]),
                        _ => start_time(&mut rng),
                    };
                    t = t0;
                    (
                        inst.setup_experiment(Some(1e-6), t0, None),
                        format!("setup {t0}"),
                    )
                }
                1 => (inst.enter_initialization_mode(), "enter init".into()),
                2 => (inst.exit_initialization_mode(), "exit init".into()),
                3 => {
                    let k = rng.below(vrs.len() + 1);
                    let (vr, x) = if k == vrs.len() {
                        (rng.pick(&[0u32, 99, 301, 401, 501, u32::MAX]), 1.0)
                    } else {
                        (vrs[k], value(&mut rng, starts[k]))
                    };
                    (inst.set_real(&[vr], &[x]), format!("set vr {vr} = {x:e}"))
                }
                4 => (inst.new_discrete_states().0, "event update".into()),
                5 => match rng.below(3) {
                    0 => (inst.enter_continuous_time_mode(), "continuous time".into()),
                    1 => (inst.enter_event_mode(), "event mode".into()),
                    _ => (inst.completed_integrator_step(), "completed step".into()),
                },
                6 => {
                    let far = 5e-4 * 10f64.powf(4.0 * rng.unit());
                    let next = rng.pick(&[
                        t + 1e-5,
                        t + 2.5e-4,
                        t + 1e-3,
                        t - 1e-4,
                        // Anywhere within or beyond the window in progress, before it.
                        t + far,
                        t - far,
                        1e300,
                        -1e300,
                        f64::NAN,
                        f64::INFINITY,
                    ]);
                    let s = inst.set_time(next);
                    if s == Status::Ok {
                        t = next;
                    }
                    (s, format!("set time {next:e}"))
                }
                7 => {
                    let n = if rng.below(10) == 0 { nx + 1 } else { nx };
                    // Near the trajectory, at the edges, or far from any trajectory.
                    let x: Vec<f64> = (0..n)
                        .map(|_| match rng.below(4) {
                            0 => rng.pick(&EDGES),
                            1 => 10f64.powf(-8.0 + 10.0 * rng.unit()) * rng.pick(&[1.0, -1.0]),
                            _ => 1e-7 * (rng.unit() - 0.5),
                        })
                        .collect();
                    (inst.set_continuous_states(&x), format!("set states {x:?}"))
                }
                8 => {
                    let n = if rng.below(10) == 0 { nx + 1 } else { nx };
                    match inst.get_derivatives(n) {
                        Ok(d) => {
                            assert!(
                                d.iter().all(|x| x.is_finite()),
                                "{}: derivatives {d:?} with fmi2OK",
                                sc.model_identifier
                            );
                            (Status::Ok, "derivatives".into())
                        }
                        Err(s) => (s, "derivatives".into()),
                    }
                }
                9 => {
                    let n = if rng.below(10) == 0 { ni + 1 } else { ni };
                    match inst.get_event_indicators(n) {
                        Ok(z) => {
                            assert!(
                                z.iter().all(|x| x.is_finite()),
                                "{}: event indicators {z:?} with fmi2OK",
                                sc.model_identifier
                            );
                            (Status::Ok, "event indicators".into())
                        }
                        Err(s) => (s, "event indicators".into()),
                    }
                }
                10 => {
                    let pick = |rng: &mut Rng| {
                        if rng.below(6) == 0 {
                            rng.pick(&[0u32, 99, u32::MAX])
                        } else {
                            vrs[rng.below(vrs.len())]
                        }
                    };
                    let (u, k) = (pick(&mut rng), pick(&mut rng));
                    let seed = value(&mut rng, 1.0);
                    match inst.get_directional_derivative(&[u], &[k], &[seed]) {
                        Ok(d) => {
                            assert!(
                                d[0].is_finite(),
                                "{}: d {u}/d {k} = {}",
                                sc.model_identifier,
                                d[0]
                            );
                            (Status::Ok, format!("directional {u} {k}"))
                        }
                        Err(s) => (s, format!("directional {u} {k}")),
                    }
                }
                11 => match inst.get_state() {
                    Ok(st) => {
                        let s = inst.set_state(&st);
                        assert_eq!(
                            s,
                            Status::Ok,
                            "{}: a state saved at t = {t} does not restore: {}",
                            sc.model_identifier,
                            inst.last_message()
                        );
                        states.push(st);
                        (Status::Ok, "get state".into())
                    }
                    Err(s) => (s, "get state".into()),
                },
                12 if !states.is_empty() => {
                    let k = rng.below(states.len());
                    (inst.set_state(&states[k]), "set state".into())
                }
                13 if !states.is_empty() => {
                    let k = rng.below(states.len());
                    match inst.serialize_state(&states[k]) {
                        Ok(b) => {
                            saved.push(b);
                            (Status::Ok, "serialize".into())
                        }
                        Err(s) => (s, "serialize".into()),
                    }
                }
                14 if !saved.is_empty() => {
                    let mut b = saved[rng.below(saved.len())].clone();
                    match rng.below(3) {
                        0 => {
                            let i = rng.below(b.len());
                            b[i] ^= 1 << rng.below(8);
                        }
                        1 => b.truncate(rng.below(b.len())),
                        _ => {}
                    }
                    match inst.deserialize_state(&b) {
                        Ok(st) => (inst.set_state(&st), "deserialize + set".into()),
                        Err(s) => (s, "deserialize".into()),
                    }
                }
                15 => {
                    if rng.below(2) == 0 {
                        (inst.terminate(), "terminate".into())
                    } else {
                        t = 0.0;
                        (inst.reset(), "reset".into())
                    }
                }
                16 => {
                    // A function of Co-Simulation on a Model Exchange instance.
                    let (s, name) = match rng.below(5) {
                        0 => (inst.do_step(t, 1e-3), "do_step"),
                        1 => (
                            inst.set_real_input_derivatives(
                                &[vrs[rng.below(vrs.len())]],
                                &[1],
                                &[1.0],
                            ),
                            "input derivative",
                        ),
                        2 => (inst.get_real_status(2).0, "real status"),
                        3 => (inst.get_boolean_status(3).0, "boolean status"),
                        _ => (
                            vibrofric_import::status(unsafe {
                                (fmu.functions.fmi2CancelStep)(inst.raw())
                            }),
                            "cancel step",
                        ),
                    };
                    assert_eq!(
                        s,
                        Status::Error,
                        "{}: Co-Simulation's {name} on Model Exchange",
                        sc.model_identifier
                    );
                    (s, format!("Co-Simulation {name}"))
                }
                17 => {
                    let b = if rng.below(2) == 0 { &fr.cs2 } else { &fr.cs3 };
                    let r = inst
                        .deserialize_state(b)
                        .map(|st| inst.free_state(st))
                        .map(|_| ());
                    let m = inst.last_message();
                    refuse_foreign(sc, r, &m)
                }
                _ => (
                    inst.get_real(&vrs).map_or_else(|s| s, |_| Status::Ok),
                    "get".into(),
                ),
            };
            let took = started.elapsed();
            let after = inst.get_real(&vrs);
            let message = inst.last_message();
            let staged_after = staged_before
                .is_some()
                .then(|| staged2(&mut inst))
                .flatten();
            oracle.check(
                sc,
                &what,
                // Discard: an evaluation outside the model's domain.
                (
                    status,
                    &[Status::Ok, Status::Warning, Status::Discard, Status::Error],
                ),
                took,
                (&vrs, &before, &after),
                (&staged_before, &staged_after),
                matches!(op, 12 | 14 | 15),
                &message,
            );
            if status == Status::Error {
                let s = inst.reset();
                assert_eq!(
                    s,
                    Status::Ok,
                    "{}: reset after {what}: {}",
                    sc.model_identifier,
                    inst.last_message()
                );
                t = 0.0;
                if rng.below(4) != 0 {
                    t = start_time(&mut rng);
                    init(&mut inst, t);
                }
            }
        }
        for st in states {
            inst.free_state(st);
        }
    }
    println!(
        "Model Exchange: {calls} calls (seed {seed}): {}",
        oracle.summary()
    );
}
