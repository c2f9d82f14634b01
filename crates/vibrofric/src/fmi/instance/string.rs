//! A string scene's instance: its values by value reference (FMI 2.0: each element its own
//! value reference `b·1000000 + i`; FMI 3.0: an array's value reference reads and writes all of
//! its elements), input derivatives and the string's simulator
//! ([`crate::model::string::StringSimulator`]). The state machine, the experiment, stepping's
//! checks and saved states are the instance's own (`mod.rs`, `stepping.rs`, `saved_states.rs`).
//!
//! Every value of a set is checked (and named with its index, `m[3]`) before any is written.
//! The string's parameters, the shared law parameters among them, are fixed: set before
//! initialization ends.

use super::Instance;
use crate::description::scene::Scene;
use crate::fmi::refusal::{Answer, Refusal};
use crate::fmi::saved::StringSaved;
use crate::fmi::staging::Staged;
use crate::fmi::state::{Call, Interface, State};
use crate::fmi::status::Status;
use crate::model::string::{build_from_values, StringInput, StringSimulator};
use crate::model::{self, SimError};
use crate::table::{number, Role, StringValues, StringVar, ARRAY_STRIDE};

/// What a string scene's instance holds besides the single contact's staged values.
pub(super) struct StringPart {
    /// The string's parameters and inputs: staged before the simulator exists, its mirror
    /// afterwards.
    pub values: StringValues,
    /// Input derivatives set before the simulator exists (applied when it is built).
    pub derivs: Vec<(StringVar, usize, f64)>,
    pub sim: Option<Box<dyn StringSimulator>>,
}

impl StringPart {
    pub fn new(values: StringValues) -> StringPart {
        StringPart {
            values,
            derivs: vec![],
            sim: None,
        }
    }

    pub fn saved(&self) -> StringSaved {
        StringSaved {
            values: self.values.clone(),
            derivs: self
                .derivs
                .iter()
                .map(|&(v, i, d)| (v, i as u32, d))
                .collect(),
            sim: self.sim.as_ref().map(|s| s.save()),
        }
    }
}

/// One variable of a get or set: a shared law parameter (by its row), or elements of a string
/// variable (`from..to`).
#[derive(Clone, Copy)]
pub(super) enum Target {
    Shared(crate::table::ParamId),
    Time,
    Elements(StringVar, usize, usize),
}

/// The string input of element `i` of an input variable.
fn input_of(var: StringVar, i: usize) -> StringInput {
    StringInput::of(var, i).unwrap_or(StringInput::VBottom)
}

/// Model Exchange's local variables of a string now: the states, their derivatives, the event
/// indicators.
struct Locals {
    states: Vec<f64>,
    derivatives: Vec<f64>,
    indicators: Vec<f64>,
}

impl Locals {
    fn of(sim: &dyn StringSimulator) -> Locals {
        Locals {
            states: sim.exchange_states(),
            derivatives: sim.exchange_derivatives(),
            indicators: sim.event_indicators(),
        }
    }

    /// The values of a local variable of a string of `n` sections.
    fn values(&self, var: StringVar, n: usize) -> &[f64] {
        let from = var.state_index(n, 0).unwrap_or(0);
        let len = var.len(n);
        match var {
            StringVar::EventVrx => &self.indicators,
            _ if var.derivative_of().is_some() => &self.derivatives[from..from + len],
            _ => &self.states[from..from + len],
        }
    }
}

impl Instance {
    /// True for a string scene, whose FMI 3.0 variables are arrays.
    pub fn has_arrays(&self) -> bool {
        self.string.is_some()
    }

    fn part(&self) -> &StringPart {
        self.string.as_ref().expect("a string scene's instance")
    }

    /// The string's simulator built from the staged values, as leaving initialization builds
    /// it.
    pub(super) fn build_string_sim(&self) -> Result<Box<dyn StringSimulator>, SimError> {
        let part = self.part();
        let exchange = self.interface == Interface::ModelExchange;
        build(&self.scene, &self.st, &part.values, &part.derivs, exchange)
    }

    /// What `vr` names in a string scene, and how many values it takes.
    pub(super) fn target(&self, time_vr: Option<u32>, vr: u32) -> Answer<Target> {
        if time_vr == Some(vr) {
            return Ok(Target::Time);
        }
        let c = &self.scene.config;
        let n = self.part().values.sections;
        let fmi3 = time_vr.is_some();
        let found = if fmi3 {
            StringVar::from_vr(vr).map(|v| (v, 0, v.len(n)))
        } else {
            StringVar::from_element_vr(vr).map(|(v, i)| (v, i, i + 1))
        };
        match found {
            Some((var, from, to)) if var.present(c, n) && to <= var.len(n) => {
                Ok(Target::Elements(var, from, to))
            }
            Some((var, from, _)) if var.present(c, n) => Err(Refusal::error(format!(
                "value reference {vr} names {} of a string of {n} sections, which has {} of them",
                var.element_name(from),
                var.len(n)
            ))),
            _ if vr >= ARRAY_STRIDE => Err(Refusal::error(format!(
                "unknown value reference {vr} (a string's arrays are numbered b*{ARRAY_STRIDE} in FMI 3.0, b*{ARRAY_STRIDE} + i in FMI 2.0)"
            ))),
            _ => match self.lookup(vr).map_err(Refusal::Error)?.kind {
                crate::description::variables::VarKind::Param(p) => Ok(Target::Shared(p)),
                _ => Err(Refusal::Internal(format!("vr {vr} in a string scene"))),
            },
        }
    }

    /// The number of values the variables of `vrs` hold.
    fn targets(&self, call: Call, vrs: &[u32], n_values: usize) -> Answer<Vec<Target>> {
        let targets = vrs
            .iter()
            .map(|&vr| self.target(call.words.time_vr, vr))
            .collect::<Answer<Vec<_>>>()?;
        let total: usize = targets
            .iter()
            .map(|t| match t {
                Target::Elements(_, from, to) => to - from,
                _ => 1,
            })
            .sum();
        if total != n_values {
            return Err(Refusal::error(format!(
                "nValues = {n_values}: the {} value references hold {total} values (an array's value reference holds all of its elements)",
                vrs.len()
            )));
        }
        Ok(targets)
    }

    /// Values of a string scene by value reference.
    pub(super) fn string_get(&mut self, call: Call, vrs: &[u32], values: &mut [f64]) -> Answer {
        let targets = self.targets(call, vrs, values.len())?;
        let c = self.scene.config;
        let asks = |role: Role| {
            targets
                .iter()
                .any(|t| matches!(t, Target::Elements(v, ..) if v.role(&c) == role))
        };
        let (asks_outputs, asks_locals) = (asks(Role::Output), asks(Role::Local));
        let outputs = if asks_outputs || asks_locals {
            let built;
            let sim = match &self.part().sim {
                Some(sim) => sim,
                None => {
                    built = self.build_string_sim().map_err(Refusal::error)?;
                    &built
                }
            };
            // Only what is asked for: the locals cost a right-hand side of the whole string.
            Some((
                asks_outputs.then(|| sim.outputs()),
                asks_locals.then(|| Locals::of(sim.as_ref())),
            ))
        } else {
            None
        };
        let time = self.time();
        let part = self.part();
        let mut k = 0;
        for t in &targets {
            match *t {
                Target::Time => {
                    values[k] = time;
                    k += 1;
                }
                Target::Shared(p) => {
                    values[k] = p.get(&self.st.params);
                    k += 1;
                }
                Target::Elements(var, from, to) => {
                    let src = match (var.role(&c), &outputs) {
                        (Role::Output, Some((Some(o), _))) => o.values(var),
                        (Role::Local, Some((_, Some(l)))) => l.values(var, part.values.sections),
                        _ => part.values.get(var),
                    };
                    values[k..k + to - from].copy_from_slice(&src[from..to]);
                    k += to - from;
                }
            }
        }
        if let Some(x) = values.iter().find(|x| !x.is_finite()) {
            return Err(Refusal::error(format!("a value evaluates to {x}: a parameter or input is beyond what the model can compute; restore a state with {}", call.words.set_state)));
        }
        Ok(Status::Ok)
    }

    /// Sets values of a string scene: every value checked first (named with its index), then
    /// written to a copy of the simulator, which replaces it only when all went through.
    pub(super) fn string_set(&mut self, call: Call, vrs: &[u32], values: &[f64]) -> Answer {
        let targets = self.targets(call, vrs, values.len())?;
        let c = self.scene.config;
        let state = self.st.state;
        let before_run = matches!(state, State::Instantiated | State::InitializationMode);
        let mut plan: Vec<(Target, usize, f64)> = vec![];
        let mut k = 0;
        for (t, &vr) in targets.iter().zip(vrs) {
            let fixed = |name: &str| {
                Refusal::error(format!(
                    "{name} (vr {vr}) is a parameter of a string (variability fixed): it can only be set before {}, not in state {}",
                    call.words.exit_initialization,
                    state.name()
                ))
            };
            match *t {
                Target::Time => {
                    return Err(Refusal::error(format!(
                        "time (vr {vr}) is the independent variable: it advances with {} and cannot be set",
                        call.words.do_step
                    )))
                }
                Target::Shared(p) => {
                    if !before_run {
                        return Err(fixed(p.name()));
                    }
                    p.check_in(values[k], &c)
                        .map_err(|e| Refusal::error(format!("{e} (vr {vr})")))?;
                    plan.push((*t, 0, values[k]));
                    k += 1;
                }
                Target::Elements(var, from, to) => {
                    let role = var.role(&c);
                    if role == Role::Local {
                        return Err(Refusal::error(format!(
                            "{} (vr {vr}) has causality local: a continuous state of Model Exchange (set by the integrator's SetContinuousStates), its derivative or an event indicator, computed by the FMU",
                            var.name()
                        )));
                    }
                    if role == Role::Output {
                        return Err(Refusal::error(format!(
                            "{} (vr {vr}) has causality output: it is computed by the FMU and cannot be set",
                            var.name()
                        )));
                    }
                    if role == Role::Param && !before_run {
                        return Err(fixed(var.name()));
                    }
                    let rule = var.rule();
                    for i in from..to {
                        let x = values[k];
                        if !rule.holds(x) {
                            return Err(Refusal::error(format!(
                                "{} = {}: {} (vr {})",
                                var.element_name(i),
                                number(x),
                                rule.text(x, var.unit()),
                                var.element_vr(i)
                            )));
                        }
                        plan.push((*t, i, x));
                        k += 1;
                    }
                }
            }
        }
        let part = self.string.as_mut().expect("a string scene's instance");
        if let Some(sim) = part.sim.as_mut() {
            let inputs: Vec<_> = plan
                .iter()
                .filter_map(|&(t, i, x)| match t {
                    Target::Elements(var, ..) => Some((input_of(var, i), x)),
                    _ => None,
                })
                .collect();
            sim.set_inputs(&inputs).map_err(Refusal::error)?;
        }
        for (t, i, x) in plan {
            match t {
                Target::Shared(p) => {
                    let _ = p.set(&mut self.st.params, x);
                }
                Target::Elements(var, ..) => part.values.get_mut(var)[i] = x,
                Target::Time => {}
            }
        }
        Ok(Status::Ok)
    }

    /// First derivatives of a string's inputs (`fmi2SetRealInputDerivatives`), for linear
    /// extrapolation over the next step.
    pub(super) fn string_set_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Answer {
        let c = self.scene.config;
        let mut plan = vec![];
        for ((&vr, &order), &d) in vrs.iter().zip(orders).zip(values) {
            let (var, i) = match self.target(None, vr)? {
                Target::Elements(var, i, _) if var.role(&c) == Role::Input => (var, i),
                _ => {
                    return Err(Refusal::error(format!(
                        "vr {vr}: only inputs have input derivatives"
                    )))
                }
            };
            let name = var.element_name(i);
            if order != 1 {
                return Err(Refusal::error(format!("order = {order} for {name} (vr {vr}): only first derivatives (order 1) are supported")));
            }
            if !(d.is_finite() && d.abs() <= model::MAX_INPUT_RATE) {
                return Err(Refusal::error(format!(
                    "derivative of {name} = {}: must be finite and at most {} {}/s in magnitude (vr {vr})",
                    number(d),
                    number(model::MAX_INPUT_RATE),
                    var.unit()
                )));
            }
            plan.push((var, i, d));
        }
        let part = self.string.as_mut().expect("a string scene's instance");
        match part.sim.as_mut() {
            Some(sim) => {
                let derivatives: Vec<_> = plan
                    .iter()
                    .map(|&(var, i, d)| (input_of(var, i), d))
                    .collect();
                sim.set_input_derivatives(&derivatives)
                    .map_err(Refusal::error)?;
            }
            None => part.derivs.extend(plan),
        }
        Ok(Status::Ok)
    }

    /// The string's part a saved state holds, its simulator built from the state's values;
    /// nothing is changed.
    pub(super) fn string_of(&self, staged: &Staged, s: &StringSaved) -> Answer<StringPart> {
        let n = self.part().values.sections;
        if s.values.sections != n {
            return Err(Refusal::error(format!(
                "the state holds a string of {} sections, this FMU's has {n}",
                s.values.sections
            )));
        }
        let c = &self.scene.config;
        for var in StringVar::ALL.into_iter().filter(|v| v.settable(c)) {
            let values = s.values.get(var);
            if values.len() != var.len(n) && !(var.len(n) == 0 && values.is_empty()) {
                return Err(Refusal::error(format!(
                    "the state's {} has {} values",
                    var.name(),
                    values.len()
                )));
            }
            if let Some((i, x)) = values
                .iter()
                .enumerate()
                .find(|(_, x)| !var.rule().holds(**x))
            {
                return Err(Refusal::error(format!(
                    "the state's {} = {}: {}",
                    var.element_name(i),
                    number(*x),
                    var.rule().text(*x, var.unit())
                )));
            }
        }
        let derivs: Vec<(StringVar, usize, f64)> = s
            .derivs
            .iter()
            .map(|&(v, i, d)| (v, i as usize, d))
            .collect();
        let sim = match &s.sim {
            None => None,
            Some(data) => {
                let exchange = self.interface == Interface::ModelExchange;
                let mut sim = build(&self.scene, staged, &s.values, &derivs, exchange)
                    .map_err(Refusal::error)?;
                sim.restore(data).map_err(Refusal::error)?;
                Some(sim)
            }
        };
        Ok(StringPart {
            values: s.values.clone(),
            derivs,
            sim,
        })
    }
}

/// A string's simulator (for Model Exchange where `exchange`) from its scene, the staged shared
/// parameters, start time and tolerance, and its values ([`build_from_values`]: each section's
/// load at the scene's `F_N` where the normal force is an input), then the input derivatives.
fn build(
    scene: &Scene,
    st: &Staged,
    v: &StringValues,
    derivs: &[(StringVar, usize, f64)],
    exchange: bool,
) -> Result<Box<dyn StringSimulator>, SimError> {
    let start = scene.string.as_ref().unwrap_or(v);
    let time = (st.start_time, st.tolerance());
    let mut sim = build_from_values(&scene.config, st.params, v, start, time, exchange)?;
    for &(var, i, d) in derivs {
        sim.set_input_derivative(input_of(var, i), d)?;
    }
    Ok(sim)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::xml;
    use crate::fmi::fmi2::Function as F2;
    use crate::fmi::fmi3::Function as F3;
    use crate::fmi::Interface;
    use std::sync::{Arc, Mutex};

    type Log = Arc<Mutex<Vec<String>>>;
    struct Collect(Log);
    impl crate::fmi::Logger for Collect {
        fn log(&self, _: Status, _: &str, message: &str) {
            self.0.lock().unwrap().push(message.to_string());
        }
    }

    const SCENE: &str = "model_identifier = \"S\"\nlaw = \"dahl\"\nmotion = \"longitudinal\"\ndrive = \"force\"\nsupport = [\"input\"]\n[string]\nsections = 3\n[start]\nm = [1.0, 2.0, 3.0]\nk_s = 1e5\n";

    fn instance(tag: &str, call: Call) -> (Instance, Log) {
        let dir =
            std::env::temp_dir().join(format!("vibrofric-string-{}-{tag}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
        let scene = Scene::parse(SCENE, "scene.toml").unwrap();
        let log: Log = Default::default();
        let i = Instance::instantiate(
            call,
            Interface::CoSimulation,
            "unit",
            "token",
            Some(&xml::guid(&scene)),
            &dir,
            "a test folder",
            Box::new(Collect(log.clone())),
            false,
        )
        .unwrap();
        let _ = std::fs::remove_dir_all(dir);
        (i, log)
    }

    fn last(log: &Log) -> String {
        log.lock().unwrap().last().cloned().unwrap_or_default()
    }

    #[test]
    fn fmi2_elements_are_checked_named_and_fixed_after_initialization() {
        let (mut i, log) = instance("fmi2", F2::Instantiate.call());
        let run = |i: &mut Instance, f: F2, body: &mut dyn FnMut(&mut Instance, Call) -> Answer| {
            let c = f.call();
            i.answer(c, |i| body(i, c))
        };
        // Reset, then through initialization with the values as they are.
        let reset_and_initialize = |i: &mut Instance| {
            run(i, F2::Reset, &mut |i, c| i.reset(c));
            run(i, F2::EnterInitializationMode, &mut |i, c| {
                i.enter_initialization(c)
            });
            run(i, F2::ExitInitializationMode, &mut |i, c| {
                i.exit_initialization(c)
            });
        };
        // m[2] = -1 refused, m[1] of the same call not written.
        let s = run(&mut i, F2::SetReal, &mut |i, c| {
            i.set_values(c, &[1_000_001, 1_000_002], &[5.0, -1.0])
        });
        assert_eq!(s, Status::Error);
        assert!(last(&log).contains("m[2] = -1"), "{}", last(&log));
        run(&mut i, F2::Reset, &mut |i, c| i.reset(c));
        run(&mut i, F2::EnterInitializationMode, &mut |i, c| {
            i.enter_initialization(c)
        });
        let mut v = [0.0; 3];
        assert_eq!(
            run(&mut i, F2::GetReal, &mut |i, c| i.get_values(
                c,
                &[1_000_001, 1_000_002, 1_000_003],
                &mut v
            )),
            Status::Ok
        );
        assert_eq!(v, [1.0, 2.0, 3.0]);
        // x[4] of a string of 3.
        let mut one = [0.0];
        assert_eq!(
            run(&mut i, F2::GetReal, &mut |i, c| i.get_values(
                c,
                &[203_000_004],
                &mut one
            )),
            Status::Error
        );
        assert!(
            last(&log).contains("x[4]") && last(&log).contains("3 of them"),
            "{}",
            last(&log)
        );
        reset_and_initialize(&mut i);
        assert_eq!(
            run(&mut i, F2::SetReal, &mut |i, c| i.set_values(
                c,
                &[1_000_001],
                &[5.0]
            )),
            Status::Error
        );
        assert!(last(&log).contains("variability fixed"), "{}", last(&log));
        reset_and_initialize(&mut i);
        // Pushed at section 3 for a step: it moves, F_d[3] reads back.
        assert_eq!(
            run(&mut i, F2::SetReal, &mut |i, c| i.set_values(
                c,
                &[101_000_003],
                &[10.0]
            )),
            Status::Ok
        );
        assert_eq!(
            run(&mut i, F2::DoStep, &mut |i, c| i.step(c, 0.0, 1e-3)),
            Status::Ok
        );
        let mut got = [0.0; 2];
        run(&mut i, F2::GetReal, &mut |i, c| {
            i.get_values(c, &[203_000_003, 101_000_003], &mut got)
        });
        assert!(got[0] > 0.0 && got[1] == 10.0, "{got:?}");
    }

    #[test]
    fn fmi3_arrays_take_all_their_elements() {
        let (mut i, log) = instance("fmi3", F3::InstantiateCoSimulation.call());
        let c = F3::EnterInitializationMode.call();
        i.answer(c, |i| i.enter_initialization(c));
        let c = F3::GetFloat64.call();
        let mut v = [0.0; 4];
        // m (3) and k_s (2) hold 5 values, not 4.
        assert_eq!(
            i.answer(c, |i| i.get_values(c, &[1_000_000, 25_000_000], &mut v)),
            Status::Error
        );
        assert!(last(&log).contains("hold 5 values"), "{}", last(&log));
        let c = F3::Reset.call();
        i.answer(c, |i| i.reset(c));
        let c = F3::EnterInitializationMode.call();
        i.answer(c, |i| i.enter_initialization(c));
        let c = F3::GetFloat64.call();
        let mut v = [0.0; 5];
        assert_eq!(
            i.answer(c, |i| i.get_values(c, &[1_000_000, 25_000_000], &mut v)),
            Status::Ok
        );
        assert_eq!(v, [1.0, 2.0, 3.0, 1e5, 1e5]);
        let c = F3::SetFloat64.call();
        assert_eq!(
            i.answer(c, |i| i.set_values(c, &[3_000_000], &[0.1, 0.2, -0.3])),
            Status::Error
        );
        assert!(last(&log).contains("mu[3] = -0.3"), "{}", last(&log));
    }
}
