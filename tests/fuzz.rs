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
//! - directed class 1: reads in Initialization Mode after in-range but inconsistent values
//!   (LuGre's `F_S` below the Coulomb force, `mu` and `F_N` anywhere in range) answer with
//!   finite values (Model Exchange: also the continuous states, nominals, event indicators and
//!   derivatives), leaving initialization refuses the inconsistency naming both forces, and the
//!   reads in Error after it answer too;
//! - directed class 2 (Co-Simulation): a state saved right after a step with a subnormal, zero
//!   or tiny input or tunable parameter, on every scene and so on every integrator path,
//!   restores into the same instance (also after a refused step) and, serialized, into a fresh
//!   one, and continues bit for bit;
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
use vibrofric::description::variables::{Causality, VarKind, Variability};
use vibrofric::description::xml;
use vibrofric::fmi::saved;
use vibrofric::fmi::staging::Staged;
use vibrofric::table::ParamId;
use vibrofric_import::fmi3::Fmu3;
use vibrofric_import::{CoSimulation, Fmu, Importer, Status};

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

/// An instance's staged values, read through a saved state: what a refused call must leave as
/// it was where reading values is not allowed.
fn staged<I: CoSimulation>(inst: &mut I) -> Option<Staged> {
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
    fn saved<I: CoSimulation>(mut i: I) -> Vec<u8> {
        let st = i.get_state().unwrap();
        let b = i.serialize_state(&st).unwrap();
        i.free_state(st);
        b
    }
    let bytes2 = |mut i: vibrofric_import::Instance| {
        i.enter_initialization_mode();
        i.exit_initialization_mode();
        saved(i)
    };
    let mut c3 = fmu3.instantiate("foreign").unwrap();
    c3.enter_initialization_mode(None, 0.0, None);
    c3.exit_initialization_mode();
    Foreign {
        cs2: bytes2(fmu.instantiate("foreign").unwrap()),
        me2: bytes2(fmu.instantiate_model_exchange("foreign").unwrap()),
        cs3: saved(c3),
    }
}

/// One call sequence of a campaign: the instance and what the operations act on.
struct Seq<'a, F: Importer + 'a> {
    fmu: &'a F,
    sc: &'a Scene,
    fr: &'a Foreign,
    inst: F::Instance<'a>,
    rng: Rng,
    /// The communication point the sequence is at.
    t: f64,
    vrs: Vec<u32>,
    /// Start values of `vrs` (1 where there is none).
    starts: Vec<f64>,
    states: Vec<State<'a, F>>,
    saved: Vec<Vec<u8>>,
}

type State<'a, F> = <<F as Importer>::Instance<'a> as CoSimulation>::State;

/// What a campaign drives: an edition and interface of every standard scene's FMU.
struct Campaign<'f, F: Importer + 'static> {
    fmus: &'f [(F, Scene, Foreign)],
    instantiate: for<'a> fn(&'a F, &str) -> Result<F::Instance<'a>, vibrofric_import::ImportError>,
    /// The instance name.
    name: &'static str,
    /// Brings a fresh instance (or one just reset) to stepping at `t0`.
    init: for<'a> fn(&mut F::Instance<'a>, f64),
    /// The operations drawn from, repeated to weigh them.
    ops: &'static [u8],
    /// The operations that change values even when refused (setting a saved state, reset).
    may_change: &'static [u8],
}

impl<F: Importer + 'static> Campaign<'_, F> {
    /// Runs sequences of 1 to 200 calls, each on a fresh instance of a random scene (most
    /// initialized at a random start time), until `budget` calls are made; `op` makes the call
    /// of an operation. After every call the oracle checks the invariants; after an error the
    /// instance is reset (the standard's way out) and may be initialized again. Returns the
    /// number of calls and the oracle.
    fn run(
        &self,
        budget: u64,
        mut rng: Rng,
        mut op: impl for<'a> FnMut(&mut Seq<'a, F>, u8) -> (Status, String),
    ) -> (u64, Oracle) {
        let mut calls = 0u64;
        let mut oracle = Oracle::default();
        while calls < budget {
            let (fmu, sc, fr) = &self.fmus[rng.below(self.fmus.len())];
            let vrs = all_vrs(sc);
            let starts: Vec<f64> = sc
                .variables()
                .map(|v| sc.start_of(v).unwrap_or(1.0))
                .collect();
            let mut inst = (self.instantiate)(fmu, self.name).unwrap();
            let mut t = 0.0;
            // Most sequences start from a properly initialized instance, so that the stepping
            // states are explored as much as the refusals.
            if rng.below(4) != 0 {
                t = start_time(&mut rng);
                (self.init)(&mut inst, t);
            }
            let mut c = Seq {
                fmu,
                sc,
                fr,
                inst,
                rng,
                t,
                vrs,
                starts,
                states: vec![],
                saved: vec![],
            };
            for _ in 0..c.rng.below(200) + 1 {
                calls += 1;
                let before = c.inst.get_f64(&c.vrs).ok();
                let staged_before = before.is_none().then(|| staged(&mut c.inst)).flatten();
                let op_k = c.rng.pick(self.ops);
                let started = Instant::now();
                let (status, what) = op(&mut c, op_k);
                let took = started.elapsed();
                let after = c.inst.get_f64(&c.vrs);
                let message = c.inst.last_message();
                let staged_after = staged_before
                    .is_some()
                    .then(|| staged(&mut c.inst))
                    .flatten();
                oracle.check(
                    sc,
                    &what,
                    // Discard: an evaluation outside the model's domain (Model Exchange).
                    (
                        status,
                        &[Status::Ok, Status::Warning, Status::Discard, Status::Error],
                    ),
                    took,
                    (&c.vrs, &before, &after),
                    (&staged_before, &staged_after),
                    self.may_change.contains(&op_k),
                    &message,
                );
                if status == Status::Error {
                    // The standard's way out of an error.
                    let s = c.inst.reset();
                    assert_eq!(
                        s,
                        Status::Ok,
                        "{}: reset after {what}: {}",
                        sc.model_identifier,
                        c.inst.last_message()
                    );
                    c.t = 0.0;
                    if c.rng.below(4) != 0 {
                        c.t = start_time(&mut c.rng);
                        (self.init)(&mut c.inst, c.t);
                    }
                }
            }
            for st in std::mem::take(&mut c.states) {
                c.inst.free_state(st);
            }
            rng = c.rng;
        }
        (calls, oracle)
    }
}

// The operations the campaigns share, written once for both editions.

/// Sets one variable to a value from the edges of its range and beyond, or an unknown value
/// reference (one of `unknown`).
fn set_value<F: Importer>(c: &mut Seq<F>, unknown: &[u32]) -> (Status, String) {
    let k = c.rng.below(c.vrs.len() + 1);
    let (vr, x) = if k == c.vrs.len() {
        (c.rng.pick(unknown), 1.0)
    } else {
        (c.vrs[k], value(&mut c.rng, c.starts[k]))
    };
    (c.inst.set_f64(&[vr], &[x]), format!("set vr {vr} = {x:e}"))
}

/// A step of one of the sizes `sizes`, from the current point or (one in eight) a wrong one.
fn do_step<F: Importer>(c: &mut Seq<F>, sizes: &[f64]) -> (Status, String) {
    let h = c.rng.pick(sizes);
    let current = if c.rng.below(8) == 0 { c.t + 1.0 } else { c.t };
    let s = c.inst.do_step(current, h);
    if s == Status::Ok {
        c.t = current + h;
    }
    (s, format!("do_step {current} {h:e}"))
}

/// Saves the state and sets it at once: a state just saved restores, whatever the time.
fn save_state<F: Importer>(c: &mut Seq<F>) -> (Status, String) {
    match c.inst.get_state() {
        Ok(st) => {
            let s = c.inst.set_state(&st);
            assert_eq!(
                s,
                Status::Ok,
                "{}: a state saved at t = {} does not restore: {}",
                c.sc.model_identifier,
                c.t,
                c.inst.last_message()
            );
            c.states.push(st);
            (Status::Ok, "get state".into())
        }
        Err(s) => (s, "get state".into()),
    }
}

/// Sets saved state `k`.
fn set_state<F: Importer>(c: &mut Seq<F>, k: usize) -> (Status, String) {
    (c.inst.set_state(&c.states[k]), "set state".into())
}

/// Serializes saved state `k`.
fn serialize<F: Importer>(c: &mut Seq<F>, k: usize) -> (Status, String) {
    match c.inst.serialize_state(&c.states[k]) {
        Ok(b) => {
            c.saved.push(b);
            (Status::Ok, "serialize".into())
        }
        Err(s) => (s, "serialize".into()),
    }
}

/// Deserializes and sets one of the serialized states (there is one), one in `kinds` with a
/// bit flipped, truncated, or (`kinds` = 4) 8 bytes overwritten at random.
fn corrupt<F: Importer>(c: &mut Seq<F>, kinds: usize) -> (Status, String) {
    let mut b = c.saved[c.rng.below(c.saved.len())].clone();
    match c.rng.below(kinds) {
        0 => {
            let i = c.rng.below(b.len());
            b[i] ^= 1 << c.rng.below(8);
        }
        1 => b.truncate(c.rng.below(b.len())),
        2 if kinds == 4 => {
            let from = c.rng.below(b.len());
            let rng = &mut c.rng;
            b.iter_mut()
                .skip(from)
                .take(8)
                .for_each(|x| *x = rng.next() as u8);
        }
        _ => {}
    }
    match c.inst.deserialize_state(&b) {
        Ok(st) => (c.inst.set_state(&st), "deserialize + set".into()),
        Err(s) => (s, "deserialize".into()),
    }
}

/// Deserializing a state of another interface or edition (`a` or `b`): refused with an
/// error, saying so.
fn refuse_foreign<F: Importer>(
    c: &mut Seq<F>,
    pick: impl Fn(&Foreign) -> [&Vec<u8>; 2],
) -> (Status, String) {
    let b = pick(c.fr)[c.rng.below(2)];
    let r = c
        .inst
        .deserialize_state(b)
        .map(|st| c.inst.free_state(st))
        .map(|_| ());
    let message = c.inst.last_message();
    let s = r.err().unwrap_or(Status::Ok);
    assert_eq!(
        s,
        Status::Error,
        "{}: a state of another interface or edition was accepted",
        c.sc.model_identifier
    );
    assert!(message.contains("restores only into"), "{message}");
    (s, "foreign state".into())
}

/// Terminates or resets, one in two each.
fn terminate_or_reset<F: Importer>(c: &mut Seq<F>) -> (Status, String) {
    if c.rng.below(2) == 0 {
        (c.inst.terminate(), "terminate".into())
    } else {
        c.t = 0.0;
        (c.inst.reset(), "reset".into())
    }
}

/// Reads every value.
fn get<F: Importer>(c: &mut Seq<F>) -> (Status, String) {
    (
        c.inst.get_f64(&c.vrs).map_or_else(|s| s, |_| Status::Ok),
        "get".into(),
    )
}

/// What the two directed classes ran and found: reads in Initialization Mode after in-range but
/// inconsistent values (LuGre's `F_S` below the Coulomb force, `mu` and `F_N` anywhere), and
/// states saved right after a step with a subnormal, zero or tiny input or parameter, restored
/// into the same instance and, serialized, into a fresh one.
#[derive(Default)]
struct Directed {
    /// Sequences into initialization with in-range values; of them, inconsistent ones.
    initializations: u64,
    inconsistent: u64,
    /// Reads (fmi2GetReal, and the continuous states, nominals and event indicators of Model
    /// Exchange) in Initialization Mode or in Error after it: made, and refused.
    reads: u64,
    read_failures: u64,
    /// States saved after such a step: how many, and how many did not restore or continue bit
    /// for bit.
    round_trips: u64,
    restore_failures: u64,
    first_failure: Option<String>,
}

impl Directed {
    fn fail(&mut self, what: String) {
        if self.first_failure.is_none() {
            self.first_failure = Some(what);
        }
    }

    fn read(&mut self, ok: bool, what: impl FnOnce() -> String) {
        self.reads += 1;
        if !ok {
            self.read_failures += 1;
            self.fail(what());
        }
    }

    fn summary(&self) -> String {
        format!(
            "{} initializations with in-range values ({} inconsistent): {} reads, {} refused; {} states saved after a step at subnormal or zero values, {} did not restore bit for bit{}",
            self.initializations,
            self.inconsistent,
            self.reads,
            self.read_failures,
            self.round_trips,
            self.restore_failures,
            self.first_failure
                .as_ref()
                .map_or(String::new(), |f| format!("; first: {f}"))
        )
    }

    fn assert_none_failed(&self) {
        assert_eq!(
            (self.read_failures, self.restore_failures),
            (0, 0),
            "{}",
            self.summary()
        );
        assert!(
            self.inconsistent > 0 && self.round_trips > 0,
            "{}",
            self.summary()
        );
    }
}

/// Directed class 1: from a reset instance into Initialization Mode at a random start time,
/// in-range values that are inconsistent where the law has a static force (`F_S` below the
/// Coulomb force at the scene's load, `mu` or `F_N` anywhere in range), then reads: they never
/// fail (`more_reads`: Model Exchange's state reads). Leaving initialization refuses the
/// inconsistent values naming `F_S` and `F_C`; the reads in Error after it answer too.
fn inconsistent_reads<F: Importer>(
    c: &mut Seq<F>,
    d: &mut Directed,
    mut more_reads: impl FnMut(&mut Seq<F>) -> Result<(), String>,
) -> (Status, String) {
    let sc = c.sc;
    let id = sc.model_identifier.clone();
    let what = "inconsistent values in initialization".to_string();
    let s = c.inst.reset();
    if s != Status::Ok {
        return (s, what);
    }
    c.t = start_time(&mut c.rng);
    let s = c.inst.enter_initialization(Some(1e-6), c.t, None);
    if s != Status::Ok {
        return (s, what);
    }
    let fs = ParamId::FS.vr();
    let has_fs = c.vrs.contains(&fs);
    let f_c = sc.start.reference_f_c();
    let mut sets = vec![];
    if c.rng.below(2) == 0 {
        let (p, start) = c.rng.pick(&[
            (ParamId::Mu.vr(), sc.start.mu),
            (ParamId::FN.vr(), sc.start.f_n),
        ]);
        if c.vrs.contains(&p) {
            sets.push((p, value(&mut c.rng, start)));
        }
    }
    let f_s = f_c * c.rng.pick(&[0.0, 5e-324, 1e-300, 0.5, 0.999_999, 1.0, 2.0]);
    if has_fs {
        sets.push((fs, f_s));
    }
    for &(vr, x) in &sets {
        let s = c.inst.set_f64(&[vr], &[x]);
        if s != Status::Ok {
            // Out of range: refused as it should be; not this class.
            return (s, format!("{what}: set vr {vr} = {x:e}"));
        }
    }
    let inverted = has_fs && f_s < f_c;
    d.initializations += 1;
    d.inconsistent += inverted as u64;
    let vrs = c.vrs.clone();
    let read = c.inst.get_f64(&vrs);
    let message = c.inst.last_message();
    d.read(
        matches!(&read, Ok(v) if v.iter().all(|x| x.is_finite())),
        || format!("{id}: get in Initialization Mode after {sets:?}: {read:?}: {message}"),
    );
    let more = more_reads(c);
    d.read(more.is_ok(), || {
        format!("{id}: in Initialization Mode after {sets:?}: {more:?}")
    });
    let exit = c.inst.exit_initialization_mode();
    let message = c.inst.last_message();
    if inverted {
        assert_eq!(
            exit,
            Status::Error,
            "{id}: F_S = {f_s:e} < F_C = {f_c} accepted"
        );
        assert!(
            message.contains("is below the Coulomb force F_C"),
            "{id}: {message}"
        );
    }
    // In Error (or stepping) the values read as they stand.
    let read = c.inst.get_f64(&vrs);
    let message = c.inst.last_message();
    d.read(
        matches!(&read, Ok(v) if v.iter().all(|x| x.is_finite())),
        || format!("{id}: get after leaving initialization ({exit:?}) after {sets:?}: {read:?}: {message}"),
    );
    (exit, what)
}

/// Directed class 2: on a stepping instance, an input or tunable parameter set to a subnormal,
/// zero or tiny value, one step, and the state saved at once; the straight continuation (one
/// step) against the same instance restored (after, one time in two, a step too short to
/// advance, refused with fmi2Error) and against a fresh instance from the serialized bytes:
/// the same statuses and the same values, bit for bit.
fn subnormal_round_trip<'a, F: Importer>(c: &mut Seq<'a, F>, d: &mut Directed) -> (Status, String) {
    let sc = c.sc;
    let config = sc.config;
    let id = sc.model_identifier.clone();
    let settable: Vec<u32> = sc
        .variables()
        .filter(|v| {
            v.causality(&config) == Causality::Input
                || (matches!(v.kind, VarKind::Param(_))
                    && v.variability(&config) == Variability::Tunable)
        })
        .map(|v| v.vr)
        .collect();
    if settable.is_empty() {
        return get(c);
    }
    let vr = c.rng.pick(&settable);
    let x = c.rng.pick(&[
        0.0,
        -0.0,
        5e-324,
        -5e-324,
        1e-308,
        -1e-308,
        f64::MIN_POSITIVE,
        1e-300,
        6.25e-7,
    ]);
    let what = format!("subnormal round trip: vr {vr} = {x:e}");
    let s = c.inst.set_f64(&[vr], &[x]);
    if s != Status::Ok {
        return (s, what);
    }
    let h = c.rng.pick(&[1e-3, 1e-4, 2.5e-3, 1e-6]);
    let s = c.inst.do_step(c.t, h);
    if s != Status::Ok {
        return (s, format!("{what}, step {h:e}"));
    }
    c.t += h;
    let Ok(st) = c.inst.get_state() else {
        d.fail(format!("{id}: get state after {what}"));
        d.restore_failures += 1;
        return (Status::Error, what);
    };
    let bytes = c.inst.serialize_state(&st).unwrap();
    d.round_trips += 1;
    let h2 = c.rng.pick(&[1e-3, 1e-4, 2.5e-3]);
    let t = c.t;
    let vrs = c.vrs.clone();
    let continuation = |i: &mut F::Instance<'a>| {
        let s = i.do_step(t, h2);
        (s, i.get_f64(&vrs).map(|v| bits(&v)))
    };
    let straight = continuation(&mut c.inst);
    if c.rng.below(2) == 0 {
        // A step too short to advance the time: refused (Error).
        c.inst.do_step(t + h2, 1e-300);
    }
    let restored = c.inst.set_state(&st);
    let again = (restored == Status::Ok).then(|| continuation(&mut c.inst));
    if again.as_ref() != Some(&straight) {
        d.restore_failures += 1;
        let message = c.inst.last_message();
        d.fail(format!(
            "{id}: at t = {t}, after {what} and a step of {h:e}, the state restored ({restored:?}: {message}) continues {again:?} instead of {straight:?}"
        ));
    }
    let mut fresh = <F as Importer>::instantiate(c.fmu, "fresh").unwrap();
    let from_bytes = fresh.deserialize_state(&bytes).ok().and_then(|sf| {
        let s = fresh.set_state(&sf);
        fresh.free_state(sf);
        (s == Status::Ok).then(|| continuation(&mut fresh))
    });
    if from_bytes.as_ref() != Some(&straight) {
        d.restore_failures += 1;
        let message = fresh.last_message();
        d.fail(format!(
            "{id}: at t = {t}, after {what} and a step of {h:e}, the state serialized into a fresh instance ({message}) continues {from_bytes:?} instead of {straight:?}"
        ));
    }
    c.inst.free_state(st);
    if restored != Status::Ok {
        // Still in Error: the campaign resets.
        return (Status::Error, what);
    }
    if straight.0 == Status::Ok {
        c.t = t + h2;
    }
    (straight.0, what)
}

#[test]
fn c_api_call_sequences_keep_the_invariants() {
    let budget = env_u64("VIBROFRIC_FUZZ_CALLS", 300_000);
    let seed = env_u64("VIBROFRIC_FUZZ_SEED", 1);
    let fmus: Vec<_> = STANDARD_SCENES
        .iter()
        .map(|f| (load(f, &format!("fuzz-{f}")), scene(f), foreign(f, "cs")))
        .collect();
    let campaign = Campaign {
        fmus: &fmus,
        instantiate: Fmu::instantiate,
        name: "fuzz",
        init: |inst, t0| {
            inst.setup_experiment(Some(1e-6), t0, None);
            inst.enter_initialization_mode();
            inst.exit_initialization_mode();
        },
        // do_step and set_real most often.
        ops: &[
            0, 1, 2, 3, 4, 5, 6, 7, 7, 8, 8, 9, 9, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19,
        ],
        may_change: &[12, 14, 15, 18, 19],
    };
    let rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let mut directed = Directed::default();
    let (calls, oracle) = campaign.run(budget, rng, |c, op| match op {
        18 => inconsistent_reads(c, &mut directed, |_| Ok(())),
        19 => subnormal_round_trip(c, &mut directed),
        0 => {
            let tol = c
                .rng
                .pick(&[Some(1e-6), Some(5e-324), Some(1.0), None, Some(f64::NAN)]);
            let t0 = match c.rng.below(2) {
                0 => c.rng.pick(&[0.0, 1e9, -5.0, f64::NAN, 1e300]),
                _ => start_time(&mut c.rng),
            };
            c.t = t0;
            (
                c.inst.setup_experiment(tol, t0, None),
                format!("setup {tol:?} {t0}"),
            )
        }
        1 => (c.inst.enter_initialization_mode(), "enter init".into()),
        2 => (c.inst.exit_initialization_mode(), "exit init".into()),
        3..=5 => set_value(c, &[0, 99, 300, u32::MAX]),
        6 => {
            let k = c.rng.below(c.vrs.len());
            let d = value(&mut c.rng, 1.0);
            let order = c.rng.pick(&[1, 2, 0]);
            (
                c.inst
                    .set_real_input_derivatives(&[c.vrs[k]], &[order], &[d]),
                format!("derivative vr {} = {d:e}", c.vrs[k]),
            )
        }
        7..=9 => do_step(
            c,
            &[
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
            ],
        ),
        10 => (
            c.inst.get_real_status(c.rng.pick(&[2, 0, 7])).0,
            "real status".into(),
        ),
        11 => save_state(c),
        12 if !c.states.is_empty() => {
            let k = c.rng.below(c.states.len());
            set_state(c, k)
        }
        16 => {
            // A function of Model Exchange on a Co-Simulation instance.
            let f = c.fmu.model_exchange.unwrap();
            let raw = c.inst.raw();
            let mut x = [0.0; 16];
            let (code, name) = unsafe {
                match c.rng.below(6) {
                    0 => (
                        (f.fmi2GetContinuousStates)(raw, x.as_mut_ptr(), 1),
                        "states",
                    ),
                    1 => (
                        (f.fmi2GetDerivatives)(raw, x.as_mut_ptr(), 1),
                        "derivatives",
                    ),
                    2 => (
                        (f.fmi2GetEventIndicators)(raw, x.as_mut_ptr(), 1),
                        "indicators",
                    ),
                    3 => (
                        (f.fmi2GetNominalsOfContinuousStates)(raw, x.as_mut_ptr(), 1),
                        "nominals",
                    ),
                    4 => ((f.fmi2SetTime)(raw, c.t), "set time"),
                    _ => ((f.fmi2EnterEventMode)(raw), "event mode"),
                }
            };
            let s = vibrofric_import::status(code);
            assert_eq!(
                s,
                Status::Error,
                "{}: Model Exchange's {name} on Co-Simulation",
                c.sc.model_identifier
            );
            (s, format!("Model Exchange {name}"))
        }
        17 => refuse_foreign(c, |f| [&f.me2, &f.cs3]),
        13 if !c.states.is_empty() => {
            let k = c.rng.below(c.states.len());
            serialize(c, k)
        }
        14 if !c.saved.is_empty() => corrupt(c, 4),
        15 => terminate_or_reset(c),
        _ => get(c),
    });
    println!("{calls} calls (seed {seed}): {}", oracle.summary());
    println!("directed: {}", directed.summary());
    directed.assert_none_failed();
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
    let campaign = Campaign {
        fmus: &fmus,
        instantiate: Fmu3::instantiate,
        name: "fuzz3",
        init: |inst, t0| {
            inst.enter_initialization_mode(Some(1e-6), t0, None);
            inst.exit_initialization_mode();
        },
        ops: &[0, 1, 2, 2, 3, 3, 3, 4, 5, 6, 7, 8, 2, 3, 9, 10, 11],
        may_change: &[5, 6, 8, 10, 11],
    };
    let rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 3 | 1);
    let mut directed = Directed::default();
    let (calls, oracle) = campaign.run(budget, rng, |c, op| match op {
        10 => inconsistent_reads(c, &mut directed, |_| Ok(())),
        11 => subnormal_round_trip(c, &mut directed),
        0 => {
            let tol = c
                .rng
                .pick(&[Some(1e-6), Some(5e-324), None, Some(f64::NAN)]);
            let t0 = match c.rng.below(2) {
                0 => c.rng.pick(&[0.0, 1e9, f64::NAN]),
                _ => start_time(&mut c.rng),
            };
            c.t = t0;
            (
                c.inst.enter_initialization_mode(tol, t0, None),
                format!("enter init {tol:?} {t0}"),
            )
        }
        1 => (c.inst.exit_initialization_mode(), "exit init".into()),
        2 => set_value(c, &[0, 99, 300, u32::MAX]),
        3 => do_step(c, &[1e-3, 1e-4, 1e-2, 0.0, -1e-3, f64::NAN, 5e-4, 2.5e-3]),
        4 => save_state(c),
        5 if !c.states.is_empty() => {
            let k = c.rng.below(c.states.len());
            match c.rng.below(2) {
                0 => set_state(c, k),
                _ => serialize(c, k),
            }
        }
        6 if !c.saved.is_empty() => corrupt(c, 3),
        7 => (c.inst.terminate(), "terminate".into()),
        9 => refuse_foreign(c, |f| [&f.cs2, &f.me2]),
        8 => {
            c.t = 0.0;
            (c.inst.reset(), "reset".into())
        }
        _ => get(c),
    });
    println!("FMI 3.0: {calls} calls (seed {seed}): {}", oracle.summary());
    println!("FMI 3.0 directed: {}", directed.summary());
    directed.assert_none_failed();
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
    let campaign = Campaign {
        fmus: &fmus,
        instantiate: Fmu::instantiate_model_exchange,
        name: "fuzz-me",
        init: |inst, t0| {
            inst.setup_experiment(Some(1e-6), t0, None);
            inst.enter_initialization_mode();
            inst.exit_initialization_mode();
            inst.new_discrete_states();
            inst.enter_continuous_time_mode();
        },
        ops: &[
            0, 1, 2, 3, 4, 5, 6, 6, 7, 7, 8, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18,
        ],
        may_change: &[12, 14, 15, 18],
    };
    let rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 3);
    let mut directed = Directed::default();
    let (calls, oracle) = campaign.run(budget, rng, |c, op| {
        let nx = state_count(c.sc);
        let ni = c.sc.config.event_indicators();
        let sc = c.sc;
        let id = &sc.model_identifier;
        match op {
            18 => inconsistent_reads(c, &mut directed, |c| {
                // The continuous states, their nominals, the event indicators and the
                // derivatives.
                let f = c.fmu.model_exchange.unwrap();
                let raw = c.inst.raw();
                let mut x = vec![0.0; nx];
                for (name, code) in unsafe {
                    [
                        (
                            "states",
                            (f.fmi2GetContinuousStates)(raw, x.as_mut_ptr(), nx),
                        ),
                        (
                            "nominals",
                            (f.fmi2GetNominalsOfContinuousStates)(raw, x.as_mut_ptr(), nx),
                        ),
                    ]
                } {
                    let s = vibrofric_import::status(code);
                    if s != Status::Ok {
                        return Err(format!("{name}: {s:?}: {}", c.inst.last_message()));
                    }
                }
                let z = c.inst.get_event_indicators(ni);
                let dx = c.inst.get_derivatives(nx);
                match (z, dx) {
                    (Ok(z), Ok(dx)) if z.iter().chain(&dx).all(|v| v.is_finite()) => Ok(()),
                    other => Err(format!("{other:?}: {}", c.inst.last_message())),
                }
            }),
            0 => {
                let t0 = match c.rng.below(2) {
                    0 => c.rng.pick(&[0.0, 1e9, -5.0, f64::NAN, 1e300]),
                    _ => start_time(&mut c.rng),
                };
                c.t = t0;
                (
                    c.inst.setup_experiment(Some(1e-6), t0, None),
                    format!("setup {t0}"),
                )
            }
            1 => (c.inst.enter_initialization_mode(), "enter init".into()),
            2 => (c.inst.exit_initialization_mode(), "exit init".into()),
            3 => set_value(c, &[0, 99, 301, 401, 501, u32::MAX]),
            4 => (c.inst.new_discrete_states().0, "event update".into()),
            5 => match c.rng.below(3) {
                0 => (
                    c.inst.enter_continuous_time_mode(),
                    "continuous time".into(),
                ),
                1 => (c.inst.enter_event_mode(), "event mode".into()),
                _ => (c.inst.completed_integrator_step(), "completed step".into()),
            },
            6 => {
                let t = c.t;
                let far = 5e-4 * 10f64.powf(4.0 * c.rng.unit());
                let next = c.rng.pick(&[
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
                let s = c.inst.set_time(next);
                if s == Status::Ok {
                    c.t = next;
                }
                (s, format!("set time {next:e}"))
            }
            7 => {
                let n = if c.rng.below(10) == 0 { nx + 1 } else { nx };
                // Near the trajectory, at the edges, or far from any trajectory.
                let x: Vec<f64> = (0..n)
                    .map(|_| match c.rng.below(4) {
                        0 => c.rng.pick(&EDGES),
                        1 => 10f64.powf(-8.0 + 10.0 * c.rng.unit()) * c.rng.pick(&[1.0, -1.0]),
                        _ => 1e-7 * (c.rng.unit() - 0.5),
                    })
                    .collect();
                (
                    c.inst.set_continuous_states(&x),
                    format!("set states {x:?}"),
                )
            }
            8 => {
                let n = if c.rng.below(10) == 0 { nx + 1 } else { nx };
                match c.inst.get_derivatives(n) {
                    Ok(d) => {
                        assert!(
                            d.iter().all(|x| x.is_finite()),
                            "{id}: derivatives {d:?} with fmi2OK",
                        );
                        (Status::Ok, "derivatives".into())
                    }
                    Err(s) => (s, "derivatives".into()),
                }
            }
            9 => {
                let n = if c.rng.below(10) == 0 { ni + 1 } else { ni };
                match c.inst.get_event_indicators(n) {
                    Ok(z) => {
                        assert!(
                            z.iter().all(|x| x.is_finite()),
                            "{id}: event indicators {z:?} with fmi2OK",
                        );
                        (Status::Ok, "event indicators".into())
                    }
                    Err(s) => (s, "event indicators".into()),
                }
            }
            10 => {
                let pick = |rng: &mut Rng, vrs: &[u32]| {
                    if rng.below(6) == 0 {
                        rng.pick(&[0u32, 99, u32::MAX])
                    } else {
                        vrs[rng.below(vrs.len())]
                    }
                };
                let (u, k) = (pick(&mut c.rng, &c.vrs), pick(&mut c.rng, &c.vrs));
                let seed = value(&mut c.rng, 1.0);
                match c.inst.get_directional_derivative(&[u], &[k], &[seed]) {
                    Ok(d) => {
                        assert!(d[0].is_finite(), "{id}: d {u}/d {k} = {}", d[0]);
                        (Status::Ok, format!("directional {u} {k}"))
                    }
                    Err(s) => (s, format!("directional {u} {k}")),
                }
            }
            11 => save_state(c),
            12 if !c.states.is_empty() => {
                let k = c.rng.below(c.states.len());
                set_state(c, k)
            }
            13 if !c.states.is_empty() => {
                let k = c.rng.below(c.states.len());
                serialize(c, k)
            }
            14 if !c.saved.is_empty() => corrupt(c, 3),
            15 => terminate_or_reset(c),
            16 => {
                // A function of Co-Simulation on a Model Exchange instance.
                let (s, name) = match c.rng.below(5) {
                    0 => (c.inst.do_step(c.t, 1e-3), "do_step"),
                    1 => {
                        let vr = c.vrs[c.rng.below(c.vrs.len())];
                        (
                            c.inst.set_real_input_derivatives(&[vr], &[1], &[1.0]),
                            "input derivative",
                        )
                    }
                    2 => (c.inst.get_real_status(2).0, "real status"),
                    3 => (c.inst.get_boolean_status(3).0, "boolean status"),
                    _ => (
                        vibrofric_import::status(unsafe {
                            (c.fmu.functions.fmi2CancelStep)(c.inst.raw())
                        }),
                        "cancel step",
                    ),
                };
                assert_eq!(
                    s,
                    Status::Error,
                    "{id}: Co-Simulation's {name} on Model Exchange",
                );
                (s, format!("Co-Simulation {name}"))
            }
            17 => refuse_foreign(c, |f| [&f.cs2, &f.cs3]),
            _ => get(c),
        }
    });
    println!(
        "Model Exchange: {calls} calls (seed {seed}): {}",
        oracle.summary()
    );
    println!("Model Exchange directed: {}", directed.summary());
    assert_eq!(directed.read_failures, 0, "{}", directed.summary());
    assert!(directed.inconsistent > 0, "{}", directed.summary());
}
