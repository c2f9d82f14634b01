//! Seeded fuzzing of the C API and of the scene reader, with an invariant oracle.
//!
//! C API: random call sequences (in and out of order) on every standard scene's FMU, with values
//! from the edges of every range and beyond (NaN, ±inf, ±1e300, subnormals, 0, negatives),
//! unknown value references, wrong communication points, and serialized states that are
//! corrupted (bit flips, truncation, random bytes). The oracle, after every call:
//! - the status is one the standard allows for a synchronous FMU (never fmi2Fatal or Pending);
//! - a call refused with fmi2Error or fmi2Discard changes no value the instance reports;
//! - fmi2GetReal never returns a non-finite value with fmi2OK;
//! - fmi2Reset brings an instance back from fmi2Error;
//! - every call returns within `CALL_BOUND` (an oracle of the fuzzer, not a speed assertion).
//!
//! Scene reader: mutated standard scenes never panic; an accepted one exports a model
//! description that is well-formed XML.
//!
//! CI runs a bounded campaign (`VIBROFRIC_FUZZ_CALLS`, default 300 000 FMI 2.0 Co-Simulation
//! calls, `VIBROFRIC_FUZZ_CALLS_ME`, default 100 000 Model Exchange calls, and
//! `VIBROFRIC_FUZZ_CALLS3`, default 100 000 FMI 3.0 calls; about a minute); a long one:
//! `VIBROFRIC_FUZZ_CALLS=5000000 VIBROFRIC_FUZZ_SEED=7 cargo test --release --test fuzz -- --nocapture`

#[allow(unused_macros)]
mod fmi_harness;

use std::time::{Duration, Instant};

use fmi_harness::*;
use vibrofric::description::scene::Scene;
use vibrofric::description::variables::VarKind;
use vibrofric::description::xml;
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

/// The standard scenes.
const FILES: [&str; 10] = [
    "contact.toml",
    "contact-lugre.toml",
    "contact-dupont.toml",
    "drill-string-axial.toml",
    "drill-string-contact.toml",
    "paper-longitudinal.toml",
    "paper-transverse.toml",
    "paper-transverse-guided.toml",
    "rig-longitudinal.toml",
    "rig-transverse.toml",
];

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

/// A value for a variable that starts at `start`: an edge, near the start, far from it, or
/// its negative.
fn value(rng: &mut Rng, start: f64) -> f64 {
    match rng.below(4) {
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
}

impl Oracle {
    /// The call `what` returned `status`, one of those `allowed` (never fmi2Fatal or Pending),
    /// within `CALL_BOUND`; the values of `vrs` read after it are finite when read with OK, and
    /// a call refused with Error or Discard left them as they were `before`, unless it is one
    /// that changes values (`may_change`: setting a saved state, reset).
    fn check(
        &mut self,
        sc: &Scene,
        what: &str,
        (status, allowed): (Status, &[Status]),
        took: Duration,
        (vrs, before, after): (&[u32], &Option<Vec<f64>>, &Values),
        may_change: bool,
    ) {
        let id = &sc.model_identifier;
        assert!(took < CALL_BOUND, "{id}: {what} took {took:?}");
        if took > self.slowest.0 {
            self.slowest = (took, format!("{id}: {what}"));
        }
        assert!(
            allowed.contains(&status),
            "{id}: {what} returned {status:?}"
        );
        self.by_status[(status as usize).min(3)] += 1;
        if let Ok(values) = after {
            if let Some(k) = values.iter().position(|x| !x.is_finite()) {
                panic!("{id}: after {what}, vr {} = {} with OK", vrs[k], values[k]);
            }
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
        }
    }

    fn summary(&self) -> String {
        let [ok, warning, discard, error] = self.by_status;
        format!(
            "{ok} OK, {warning} warning, {discard} discard, {error} error; slowest {:?} ({})",
            self.slowest.0, self.slowest.1
        )
    }
}

#[test]
fn c_api_call_sequences_keep_the_invariants() {
    let budget = env_u64("VIBROFRIC_FUZZ_CALLS", 300_000);
    let seed = env_u64("VIBROFRIC_FUZZ_SEED", 1);
    let fmus: Vec<_> = FILES
        .iter()
        .map(|f| (load(f, &format!("fuzz-{f}")), scene(f)))
        .collect();
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let mut calls = 0u64;
    let mut oracle = Oracle::default();
    while calls < budget {
        let (fmu, sc) = &fmus[rng.below(fmus.len())];
        let vrs = all_vrs(sc);
        let starts: Vec<f64> = sc
            .variables()
            .map(|v| sc.start_of(v).unwrap_or(1.0))
            .collect();
        let mut inst = fmu.instantiate("fuzz").unwrap();
        let mut t = 0.0;
        // Most sequences start from a properly initialized instance, so that the stepping
        // states are explored as much as the refusals.
        let init = |inst: &mut vibrofric_import::Instance| {
            inst.setup_experiment(Some(1e-6), 0.0, None);
            inst.enter_initialization_mode();
            inst.exit_initialization_mode();
        };
        if rng.below(4) != 0 {
            init(&mut inst);
        }
        let mut states = vec![];
        let mut saved: Vec<Vec<u8>> = vec![];
        for _ in 0..rng.below(200) + 1 {
            calls += 1;
            let before = inst.get_real(&vrs).ok();
            // do_step and set_real most often.
            let op = rng.pick(&[
                0, 1, 2, 3, 4, 5, 6, 7, 7, 8, 8, 9, 9, 7, 8, 9, 10, 11, 12, 13, 14, 15,
            ]);
            let started = Instant::now();
            let (status, what) = match op {
                0 => {
                    let tol =
                        rng.pick(&[Some(1e-6), Some(5e-324), Some(1.0), None, Some(f64::NAN)]);
                    let t0 = rng.pick(&[0.0, 1e9, -5.0, f64::NAN, 1e300]);
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
            let after = inst.get_real(&vrs);
            oracle.check(
                sc,
                &what,
                (
                    status,
                    &[Status::Ok, Status::Warning, Status::Discard, Status::Error],
                ),
                started.elapsed(),
                (&vrs, &before, &after),
                matches!(op, 12 | 14 | 15),
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
                    init(&mut inst);
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
    let fmus: Vec<_> = FILES
        .iter()
        .map(|f| (load3(f, &format!("fuzz3-{f}")), scene(f)))
        .collect();
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 3 | 1);
    let mut calls = 0u64;
    let mut oracle = Oracle::default();
    while calls < budget {
        let (fmu, sc) = &fmus[rng.below(fmus.len())];
        let vrs = all_vrs(sc);
        let starts: Vec<f64> = sc
            .variables()
            .map(|v| sc.start_of(v).unwrap_or(1.0))
            .collect();
        let mut inst = fmu.instantiate("fuzz3").unwrap();
        let init = |inst: &mut vibrofric_import::fmi3::Instance3| {
            inst.enter_initialization_mode(Some(1e-6), 0.0, None);
            inst.exit_initialization_mode();
        };
        if rng.below(4) != 0 {
            init(&mut inst);
        }
        let mut t = 0.0;
        let (mut states, mut saved) = (vec![], vec![]);
        for _ in 0..rng.below(200) + 1 {
            calls += 1;
            let before = inst.get_f64(&vrs).ok();
            let op = rng.pick(&[0, 1, 2, 2, 3, 3, 3, 4, 5, 6, 7, 8, 2, 3]);
            let started = Instant::now();
            let (status, what) = match op {
                0 => {
                    let tol = rng.pick(&[Some(1e-6), Some(5e-324), None, Some(f64::NAN)]);
                    let t0 = rng.pick(&[0.0, 1e9, f64::NAN]);
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
                    let h = rng.pick(&[1e-3, 1e-4, 1e-2, 0.0, -1e-3, f64::NAN]);
                    let current = if rng.below(8) == 0 { t + 1.0 } else { t };
                    let (s, _) = inst.do_step(current, h);
                    if s == Status::Ok {
                        t = current + h;
                    }
                    (s, format!("do_step {current} {h:e}"))
                }
                4 => match inst.get_state() {
                    Ok(st) => {
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
                8 => {
                    t = 0.0;
                    (inst.reset(), "reset".into())
                }
                _ => (
                    inst.get_f64(&vrs).map_or_else(|s| s, |_| Status::Ok),
                    "get".into(),
                ),
            };
            let after = inst.get_f64(&vrs);
            oracle.check(
                sc,
                &what,
                (
                    status,
                    &[Status::Ok, Status::Warning, Status::Discard, Status::Error],
                ),
                started.elapsed(),
                (&vrs, &before, &after),
                matches!(op, 5 | 6 | 8),
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
                    init(&mut inst);
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
    let texts: Vec<String> = std::fs::read_dir("scenes")
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
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
    let fmus: Vec<_> = FILES
        .iter()
        .map(|f| (load(f, &format!("fuzz-me-{f}")), scene(f)))
        .collect();
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 3);
    let mut calls = 0u64;
    let mut oracle = Oracle::default();
    while calls < budget {
        let (fmu, sc) = &fmus[rng.below(fmus.len())];
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
        let init = |inst: &mut vibrofric_import::Instance| {
            inst.setup_experiment(Some(1e-6), 0.0, None);
            inst.enter_initialization_mode();
            inst.exit_initialization_mode();
            inst.new_discrete_states();
            inst.enter_continuous_time_mode();
        };
        if rng.below(4) != 0 {
            init(&mut inst);
        }
        let mut states = vec![];
        let mut saved: Vec<Vec<u8>> = vec![];
        for _ in 0..rng.below(200) + 1 {
            calls += 1;
            let before = inst.get_real(&vrs).ok();
            let op = rng.pick(&[
                0, 1, 2, 3, 4, 5, 6, 6, 7, 7, 8, 8, 9, 10, 11, 12, 13, 14, 15,
            ]);
            let started = Instant::now();
            let (status, what) = match op {
                0 => {
                    let t0 = rng.pick(&[0.0, 1e9, -5.0, f64::NAN, 1e300]);
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
                    let next = rng.pick(&[
                        t + 1e-5,
                        t + 2.5e-4,
                        t + 1e-3,
                        t - 1e-4,
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
                    let x: Vec<f64> = (0..n)
                        .map(|_| match rng.below(3) {
                            0 => rng.pick(&EDGES),
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
                _ => (
                    inst.get_real(&vrs).map_or_else(|s| s, |_| Status::Ok),
                    "get".into(),
                ),
            };
            let after = inst.get_real(&vrs);
            oracle.check(
                sc,
                &what,
                (status, &[Status::Ok, Status::Warning, Status::Error]),
                started.elapsed(),
                (&vrs, &before, &after),
                matches!(op, 12 | 14 | 15),
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
                    init(&mut inst);
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
