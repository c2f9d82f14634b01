//! One FMU instance, in safe Rust and in no particular FMI version: its life cycle, the values
//! set before the simulator exists (`staging.rs`), get and set by value reference, stepping,
//! and saved states (`saved.rs`).
//!
//! A version's C layer (`fmi2/ffi.rs`) turns C pointers into slices and strings and calls the
//! methods here with a [`Call`]: the function's name and the states its table allows it in.
//! Every method first checks that the call is allowed in the current state, then validates all
//! of its arguments, and only then changes the instance. A call that fails logs a message
//! naming the function, the variable and the rule, leaves every value as it was, and moves the
//! instance to the `Error` state, from which it can still be read, restored, reset or freed.
//!
//! Parameters and inputs set before initialization ends are staged in [`Params`] and
//! [`Inputs`]; leaving initialization builds the [`Simulator`] at the experiment's start time
//! with the experiment's tolerance (when defined; else the `DefaultExperiment`'s).

use std::fmt::Display;

use super::log::Logger;
use super::saved::{self, FmuState};
use super::staging::{Assign, Staged};
use super::state::{Call, Interface, State};
use super::status::Status;
use crate::description::log::Category;
use crate::description::scene::Scene;
use crate::description::variables::{by_vr, Causality, VarKind, Variability, Variable};
use crate::description::xml;
use crate::model::{self, InputId, OutputId, Outputs, SimError, Simulator, StateId};
use crate::physics::ParamId;
use crate::table::number;
use crate::table::IndicatorId;

/// The FMU instance.
pub struct Instance {
    name: String,
    scene: Scene,
    guid: String,
    /// Co-Simulation or Model Exchange, as instantiated.
    pub(super) interface: Interface,
    /// The scene's variables, sorted by value reference.
    vars: Vec<&'static Variable>,
    /// Model Exchange: the scene's continuous states, in the order of the state vector.
    pub(super) states: Vec<StateId>,
    logger: Box<dyn Logger>,
    categories: [bool; 4],
    pub(super) st: Staged,
    pub(super) sim: Option<Box<dyn Simulator>>,
    /// Simulator built from the staged values to answer `fmi2GetReal` before the real one
    /// exists; dropped whenever a staged value changes.
    pub(super) provisional: Option<Box<dyn Simulator>>,
    /// The call that put the instance in `Error`, and why (cleared when it leaves `Error`).
    error_cause: Option<String>,
}

impl Instance {
    /// Why an instance name is refused, if it is (the C layers check it first).
    pub fn refuse_name(name: &str) -> Option<String> {
        name.is_empty().then(|| {
            "instanceName = \"\": must not be empty (importers and logs tell instances apart by it)"
                .to_string()
        })
    }

    /// Instantiation: reads `<resources>/scene.toml` and checks the token (the FMI 2.0 GUID,
    /// FMI 3.0's instantiation token) against the scene's. The C layer has resolved the
    /// resources folder; `origin` says where it came from and `token_arg` names the token
    /// argument, for the messages. On failure the reason is logged and `None` returned.
    #[allow(clippy::too_many_arguments)]
    pub fn instantiate(
        call: Call,
        interface: Interface,
        name: &str,
        token_arg: &str,
        guid: Option<&str>,
        dir: &std::path::Path,
        origin: &str,
        logger: Box<dyn Logger>,
        logging_on: bool,
    ) -> Option<Instance> {
        let fail = |msg: String| {
            logger.log(
                Status::Error,
                Category::StatusError.name(),
                &format!("{}: {msg}", call.name),
            );
        };
        let path = dir.join("scene.toml");
        let scene = match std::fs::read_to_string(&path) {
            Ok(text) => match Scene::parse(&text, &path.display().to_string()) {
                Ok(s) => s,
                Err(e) => {
                    fail(format!("resources/scene.toml is invalid: {e}"));
                    return None;
                }
            },
            Err(e) => {
                fail(format!(
                    "cannot read {} (from {origin}): {e}",
                    path.display()
                ));
                return None;
            }
        };
        let expected = xml::guid(&scene);
        match guid {
            Some(g) if g == expected => {}
            Some(g) => {
                fail(format!(
                    "{token_arg} = \"{g}\" does not match this FMU's GUID \"{expected}\" (model {}): the modelDescription.xml and resources/scene.toml come from different FMUs",
                    scene.model_identifier
                ));
                return None;
            }
            None => {
                fail(format!(
                    "{token_arg} = NULL: must be the guid of modelDescription.xml, \"{expected}\""
                ));
                return None;
            }
        }
        let mut vars: Vec<&'static Variable> = scene.variables().collect();
        vars.sort_by_key(|v| v.vr);
        let states = scene
            .variables()
            .filter_map(|v| match v.kind {
                VarKind::State(x) => Some(x),
                _ => None,
            })
            .collect();
        let inst = Instance {
            name: name.to_string(),
            interface,
            states,
            st: Staged::initial(&scene),
            scene,
            guid: expected,
            vars,
            logger,
            categories: [logging_on; 4],
            sim: None,
            provisional: None,
            error_cause: None,
        };
        inst.event(|| {
            format!(
                "{}: instance \"{}\" of {} ({}), resources {}",
                call.name,
                inst.name,
                inst.scene.model_identifier,
                inst.guid,
                dir.display()
            )
        });
        Some(inst)
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn guid(&self) -> &str {
        &self.guid
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    pub fn state(&self) -> State {
        self.st.state
    }

    /// The instance's time: the simulator's, or the start time before it exists.
    pub fn time(&self) -> f64 {
        self.sim.as_ref().map_or(self.st.start_time, |s| s.time())
    }

    // ---- logging -----------------------------------------------------------------------------

    fn enabled(&self, c: Category) -> bool {
        self.categories[c as usize] || self.categories[Category::All as usize]
    }

    /// Logs a status message: errors and discards always reach the importer, other messages
    /// only when their category is enabled.
    pub(super) fn log(&self, status: Status, c: Category, msg: &str) {
        if status >= Status::Discard || self.enabled(c) {
            self.logger.log(status, c.name(), msg);
        }
    }

    /// A `logEvents` message, formatted only when that category is enabled.
    pub(super) fn event(&self, msg: impl FnOnce() -> String) {
        if self.enabled(Category::Events) {
            self.logger.log(Status::Ok, Category::Events.name(), &msg());
        }
    }

    /// A `logAll` trace, formatted only when that category is enabled.
    pub(super) fn trace(&self, msg: impl FnOnce() -> String) {
        if self.categories[Category::All as usize] {
            self.logger.log(Status::Ok, Category::All.name(), &msg());
        }
    }

    /// Logs `f: msg` as an error and enters the `Error` state, remembering which call put
    /// the instance there (for the messages of the calls refused afterwards).
    pub(super) fn fail(&mut self, f: &str, msg: impl Display) -> Status {
        let msg = msg.to_string();
        self.log(
            Status::Error,
            Category::StatusError,
            &format!("{f}: {msg} [instance \"{}\"]", self.name),
        );
        if !matches!(self.st.state, State::Fatal | State::Error) {
            // The first clause of the message says what went wrong; the rest is advice.
            let what: String = msg
                .split("; ")
                .next()
                .unwrap_or("")
                .chars()
                .take(200)
                .collect();
            self.error_cause = Some(format!(
                "{f} in state {} (\"{what}\")",
                self.st.state.name()
            ));
            self.st.state = State::Error;
        }
        Status::Error
    }

    /// Logs `f: msg` as a discard; the state does not change.
    pub(crate) fn discard(&self, f: &str, msg: impl Display) -> Status {
        self.log(
            Status::Discard,
            Category::StatusError,
            &format!("{f}: {msg} [instance \"{}\"]", self.name),
        );
        Status::Discard
    }

    /// Checks that `call` may be made by this instance (a function of its interface, or one
    /// common to both) and in its current state.
    pub(crate) fn allow(&mut self, call: Call) -> Result<(), Status> {
        if let Some(only) = call.only {
            if only != self.interface {
                return Err(self.fail(
                    call.name,
                    format!(
                        "a function of {} only, and this instance was instantiated for {}: an instance answers only the functions of its own interface ({}); illegal call sequence",
                        only.name(),
                        self.interface.name(),
                        call.words.edition
                    ),
                ));
            }
        }
        if call.allowed.contains(self.st.state) {
            return Ok(());
        }
        let state = self.st.state;
        let cause = match (state, &self.error_cause) {
            (State::Error, Some(cause)) => format!(
                "; the instance entered Error at {cause}; {} recovers it (or {} with a state saved before)",
                call.words.reset, call.words.set_state
            ),
            (State::Error, None) => format!(
                "; the state was restored in Error; {} recovers it (or {} with a state saved before the error)",
                call.words.reset, call.words.set_state
            ),
            _ => String::new(),
        };
        Err(self.fail(
            call.name,
            format!(
                "not allowed in state {} (allowed in: {}); illegal call sequence{cause}",
                state.name(),
                call.allowed.names()
            ),
        ))
    }

    /// Logs an error for a call whose arguments the C layer found invalid (a NULL pointer).
    pub fn invalid_argument(&mut self, f: &str, msg: impl Display) -> Status {
        self.fail(f, msg)
    }

    /// Called by the C layer after it caught a panic: the instance may be half-updated, so it
    /// only remains to be reset, restored or freed.
    pub fn internal_error(&mut self, call: Call, what: &str) -> Status {
        self.provisional = None;
        let (f, words) = (call.name, call.words);
        self.fail(
            f,
            format!(
                "internal error ({what}); call {} or {} to continue",
                words.reset, words.set_state
            ),
        )
    }

    // ---- life cycle --------------------------------------------------------------------------

    /// `fmi2SetDebugLogging`. An empty category list applies to every category.
    pub fn set_debug_logging(&mut self, call: Call, on: bool, categories: &[&str]) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        let mut wanted = Vec::with_capacity(categories.len());
        for c in categories {
            match Category::from_name(c) {
                Some(c) => wanted.push(c),
                None => {
                    let valid: Vec<_> = Category::ALL.iter().map(|c| c.name()).collect();
                    return self.fail(
                        f,
                        format!("unknown log category \"{c}\"; valid: {}", valid.join(", ")),
                    );
                }
            }
        }
        if wanted.is_empty() {
            self.categories = [on; 4];
        } else {
            for c in wanted {
                self.categories[c as usize] = on;
            }
        }
        self.event(|| format!("{f}: loggingOn = {on}, categories {categories:?}"));
        Status::Ok
    }

    /// `fmi2SetupExperiment`.
    pub fn setup_experiment(
        &mut self,
        call: Call,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        if let Some(tol) = tolerance {
            if !(tol.is_finite() && tol > 0.0) {
                return self.fail(
                    f,
                    format!(
                        "tolerance = {tol}: must be finite and > 0 (or toleranceDefined = {})",
                        call.words.false_
                    ),
                );
            }
        }
        if !start_time.is_finite() {
            return self.fail(f, format!("startTime = {start_time}: must be finite"));
        }
        if let Some(stop) = stop_time {
            if !(stop.is_finite() && stop >= start_time) {
                return self.fail(
                    f,
                    format!("stopTime = {stop}: must be finite and >= startTime = {start_time}"),
                );
            }
        }
        let (lo, hi) = model::TOLERANCE_RANGE;
        let clamped = tolerance.map(|t| t.clamp(lo, hi));
        self.st.tolerance = clamped;
        self.st.start_time = start_time;
        self.st.stop_time = stop_time;
        self.provisional = None;
        if let (Some(asked), Some(used)) = (tolerance, clamped) {
            if asked != used {
                self.log(
                    Status::Warning,
                    Category::StatusWarning,
                    &format!(
                        "{f}: tolerance = {} is outside [{}, {}], the range the integrators resolve: using {} [instance \"{}\"]",
                        number(asked),
                        number(lo),
                        number(hi),
                        number(used),
                        self.name
                    ),
                );
                return Status::Warning;
            }
        }
        self.event(|| {
            format!(
                "{f}: tolerance {} ({}), startTime {start_time}, stopTime {}",
                self.st.tolerance(),
                if tolerance.is_some() {
                    "defined"
                } else {
                    "DefaultExperiment"
                },
                stop_time.map_or("undefined".to_string(), |s| s.to_string())
            )
        });
        Status::Ok
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization_mode(&mut self, call: Call) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        self.st.state = State::InitializationMode;
        self.event(|| f.to_string());
        Status::Ok
    }

    /// `fmi2ExitInitializationMode`: builds the simulator from the staged values.
    pub fn exit_initialization_mode(&mut self, call: Call) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        match self.build_sim() {
            Ok(sim) => {
                self.sim = Some(sim);
                self.provisional = None;
                self.st.derivs = [None; InputId::ALL.len()];
                self.st.state = match self.interface {
                    Interface::CoSimulation => State::StepComplete,
                    Interface::ModelExchange => State::EventMode,
                };
                self.event(|| {
                    format!(
                        "{f}: simulator built at t = {} with tolerance {}",
                        self.st.start_time,
                        self.st.tolerance()
                    )
                });
                Status::Ok
            }
            Err(e) => self.fail(f, e),
        }
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self, call: Call) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        self.st.state = State::Terminated;
        self.event(|| format!("{f}: at t = {}", self.time()));
        Status::Ok
    }

    /// `fmi2Reset`: back to `Instantiated` with the scene's start values.
    pub fn reset(&mut self, call: Call) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        self.st = Staged::initial(&self.scene);
        self.sim = None;
        self.provisional = None;
        self.error_cause = None;
        self.event(|| format!("{f}: start values restored"));
        Status::Ok
    }

    /// Freeing: logs it (the C layer then drops the instance).
    pub fn free(&self, call: Call) {
        self.event(|| call.name.to_string());
    }

    pub(super) fn build_sim(&self) -> Result<Box<dyn Simulator>, SimError> {
        let c = self.scene.config;
        let mut sim = model::build(c, self.st.params, self.st.start_time, self.st.tolerance())?;
        for id in InputId::ALL {
            if id.present(&c) {
                sim.set_input(id, id.get(&self.st.inputs))?;
            }
        }
        for (k, id) in InputId::ALL.into_iter().enumerate() {
            if let Some(d) = self.st.derivs[k] {
                sim.set_input_derivative(id, d)?;
            }
        }
        Ok(sim)
    }

    // ---- variables ---------------------------------------------------------------------------

    pub(super) fn lookup(&self, vr: u32) -> Result<&'static Variable, String> {
        if let Ok(k) = self.vars.binary_search_by_key(&vr, |v| v.vr) {
            return Ok(self.vars[k]);
        }
        Err(match by_vr(vr) {
            Some(v) => format!(
                "value reference {vr} ({}) is not a variable of this FMU ({}: {})",
                v.name(),
                self.scene.model_identifier,
                crate::description::scene::summary(&self.scene.config)
            ),
            None => format!("unknown value reference {vr}"),
        })
    }

    /// The simulator, or before it exists one built from the staged values.
    pub(super) fn simulator_now(&mut self) -> Result<&dyn Simulator, SimError> {
        if self.sim.is_none() && self.provisional.is_none() {
            self.provisional = Some(self.build_sim()?);
        }
        match self.sim.as_deref().or(self.provisional.as_deref()) {
            Some(sim) => Ok(sim),
            None => unreachable!("built above"),
        }
    }

    /// `fmi2GetReal`. `values` has the length of `vrs`.
    pub fn get_real(&mut self, call: Call, vrs: &[u32], values: &mut [f64]) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        let mut vars = Vec::with_capacity(vrs.len());
        for &vr in vrs {
            match self.lookup(vr) {
                Ok(v) => vars.push(v),
                Err(msg) => return self.fail(f, msg),
            }
        }
        // Only what the call reads is computed: outputs (one evaluation), and the states,
        // derivatives and event indicators of Model Exchange when one of them is asked for.
        let config = self.scene.config;
        let asks = |kind: fn(&VarKind) -> bool| vars.iter().any(|v| kind(&v.kind));
        let need_outputs = vars.iter().any(|v| v.output(&config).is_some());
        let need_states = asks(|k| matches!(k, VarKind::State(_)));
        let need_derivatives = asks(|k| matches!(k, VarKind::Derivative(_)));
        let need_indicators = asks(|k| matches!(k, VarKind::Indicator(_)));
        let mut outputs = Outputs::default();
        let (mut states, mut derivatives) = ([0.0; StateId::COUNT], [0.0; StateId::COUNT]);
        let mut indicators = [0.0; IndicatorId::ALL.len()];
        let exchange = self.interface == Interface::ModelExchange;
        if need_outputs || need_states || need_derivatives || need_indicators {
            if let Err(e) = self.simulator_now() {
                return self.fail(f, e);
            }
            if exchange && (need_outputs || need_derivatives || need_indicators) {
                if let Some(s) = self.out_of_domain(call, None) {
                    return s;
                }
            }
            let sim = match self.simulator_now() {
                Ok(sim) => sim,
                Err(e) => return self.fail(f, e),
            };
            if need_outputs {
                outputs = sim.outputs();
            }
            if need_states {
                states = sim.states();
            }
            if need_derivatives {
                derivatives = sim.derivatives();
            }
            if need_indicators {
                sim.event_indicators(&mut indicators[..config.event_indicators()]);
            }
        }
        for (v, out) in vars.iter().zip(values.iter_mut()) {
            *out = match v.kind {
                VarKind::Param(ParamId::FN) if self.scene.config.normal_input => self.st.inputs.f_n,
                VarKind::Param(p) => p.get(&self.st.params),
                VarKind::Input(i) if v.causality(&self.scene.config) == Causality::Input => {
                    i.get(&self.st.inputs)
                }
                VarKind::Input(_) => OutputId::FDrive.get(&outputs),
                VarKind::Output(o) => o.get(&outputs),
                VarKind::State(x) => states[x.index()],
                VarKind::Derivative(x) => derivatives[x.index()],
                VarKind::Indicator(i) => indicators[i.index(&self.scene.config)],
            };
        }
        // fmi2OK never comes with a non-finite value (the ranges are chosen so that none
        // arises; this is the last guard).
        if let Some((v, x)) = vars.iter().zip(values.iter()).find(|(_, x)| !x.is_finite()) {
            let (name, x) = (v.name(), *x);
            if exchange {
                if let Some(s) = self.out_of_domain(call, Some(format!("{name} evaluates to {x}")))
                {
                    return s;
                }
            }
            return self.fail(f, format!("{name} evaluates to {x}: a parameter or input is beyond what the model can compute; restore a state with {}", call.words.set_state));
        }
        Status::Ok
    }

    /// `fmi2SetReal`: every value is checked before any is written.
    pub fn set_real(&mut self, call: Call, vrs: &[u32], values: &[f64]) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        let state = self.st.state;
        let config = self.scene.config;
        let mut plan = Vec::with_capacity(vrs.len());
        for (&vr, &value) in vrs.iter().zip(values) {
            let v = match self.lookup(vr) {
                Ok(v) => v,
                Err(msg) => return self.fail(f, msg),
            };
            let name = v.name();
            match (v.kind, v.causality(&config)) {
                (_, Causality::Output) => {
                    return self.fail(
                        f,
                        format!("{name} (vr {vr}) has causality output: it is computed by the FMU and cannot be set"),
                    )
                }
                (_, Causality::Local) => {
                    return self.fail(
                        f,
                        format!("{name} (vr {vr}) is a continuous state or derivative (causality local): an importer sets states with {}", call.words.set_states),
                    )
                }
                (VarKind::Param(p), Causality::Parameter) if state == State::ContinuousTimeMode => {
                    return self.fail(
                        f,
                        format!("{} (vr {vr}) is a parameter: in ContinuousTimeMode only inputs can be set; tunable parameters in EventMode", p.name()),
                    )
                }
                (VarKind::Param(ParamId::FN), Causality::Input) => {
                    let rule = InputId::FN.rule();
                    if !rule.holds(value) {
                        return self.fail(
                            f,
                            format!("F_N = {value}: {} (vr {vr}; a contact cannot pull, 0: the body has lifted off)", rule.text(value, "N")),
                        );
                    }
                    plan.push(Assign::Input(InputId::FN, value));
                }
                (VarKind::Param(p), _) => {
                    if v.variability(&config) == Variability::Fixed && state == State::StepComplete {
                        return self.fail(
                            f,
                            format!(
                                "{name} (vr {vr}) is a parameter with variability fixed: it can only be set before {}, not in state {}",
                                call.words.exit_initialization,
                                state.name()
                            ),
                        );
                    }
                    if let Err(e) = p.check_in(value, &config) {
                        return self.fail(f, format!("{e} (vr {vr})"));
                    }
                    plan.push(Assign::Param(p, value));
                }
                (VarKind::Input(i), _) => {
                    if !i.rule().holds(value) {
                        return self.fail(
                            f,
                            format!("{name} = {value}: {} (vr {vr})", i.rule().text(value, i.unit())),
                        );
                    }
                    plan.push(Assign::Input(i, value));
                }
                _ => unreachable!("outputs and locals are refused above"),
            }
        }
        // In Model Exchange the body lifts off or lands at the next event update, not here.
        let exchange = matches!(state, State::EventMode | State::ContinuousTimeMode);
        if let Some(sim) = self.sim.as_mut() {
            let apply = |sim: &mut dyn Simulator, a: Assign| match a {
                Assign::Param(p, x) => sim.set_param(p, x),
                Assign::Input(i, x) if exchange => sim.set_input_continuous(i, x),
                Assign::Input(i, x) => sim.set_input(i, x),
            };
            // One assignment leaves the simulator unchanged when it fails; several are applied
            // to a copy, so that a failure in the middle changes nothing either.
            let result = if plan.len() == 1 {
                apply(sim.as_mut(), plan[0])
            } else {
                let mut next = sim.clone_box();
                plan.iter()
                    .try_for_each(|&a| apply(next.as_mut(), a))
                    .map(|_| *sim = next)
            };
            if let Err(e) = result {
                return self.fail(f, e);
            }
        }
        for a in plan {
            match a {
                Assign::Param(p, x) => {
                    // A new parameter restarts the averaging window (F_int jumps to 0).
                    self.st.states_changed |= exchange;
                    // Checked above, cannot fail.
                    let _ = p.set(&mut self.st.params, x);
                }
                Assign::Input(i, x) => *i.slot(&mut self.st.inputs) = x,
            }
        }
        self.provisional = None;
        Status::Ok
    }

    /// `fmi2SetRealInputDerivatives`: first derivatives of inputs, used to extrapolate them
    /// linearly over the next step.
    pub fn set_real_input_derivatives(
        &mut self,
        call: Call,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        let config = self.scene.config;
        let mut plan = Vec::with_capacity(vrs.len());
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let v = match self.lookup(vr) {
                Ok(v) => v,
                Err(msg) => return self.fail(f, msg),
            };
            let name = v.name();
            let id = match (v.kind, v.causality(&config)) {
                (VarKind::Input(i), Causality::Input) => i,
                (VarKind::Param(ParamId::FN), Causality::Input) => InputId::FN,
                (_, c) => {
                    return self.fail(
                        f,
                        format!(
                            "{name} (vr {vr}) has causality {}: only inputs have input derivatives",
                            c.as_str()
                        ),
                    )
                }
            };
            if order != 1 {
                return self.fail(
                    f,
                    format!("order = {order} for {name} (vr {vr}): only first derivatives (order 1) are supported"),
                );
            }
            if !(value.is_finite() && value.abs() <= model::MAX_INPUT_RATE) {
                return self.fail(
                    f,
                    format!(
                        "derivative of {name} = {}: must be finite and at most {} {}/s in magnitude (vr {vr})",
                        number(value),
                        number(model::MAX_INPUT_RATE),
                        id.unit()
                    ),
                );
            }
            plan.push((id, value));
        }
        match self.sim.as_mut() {
            Some(sim) => {
                let result = if plan.len() == 1 {
                    sim.set_input_derivative(plan[0].0, plan[0].1)
                } else {
                    let mut next = sim.clone_box();
                    plan.iter()
                        .try_for_each(|&(i, d)| next.set_input_derivative(i, d))
                        .map(|_| *sim = next)
                };
                if let Err(e) = result {
                    return self.fail(f, e);
                }
            }
            None => {
                for (id, d) in plan {
                    self.st.derivs[id.index()] = Some(d);
                }
                self.provisional = None;
            }
        }
        Status::Ok
    }

    /// `fmi2GetRealOutputDerivatives`: first derivatives (`maxOutputDerivativeOrder` = 1) of the
    /// outputs that have an exact one (see `Simulator::output_derivative`); every value is
    /// checked before any is written.
    pub fn get_real_output_derivatives(
        &mut self,
        call: Call,
        vrs: &[u32],
        orders: &[i32],
        values: &mut [f64],
    ) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        let config = self.scene.config;
        let mut found = Vec::with_capacity(vrs.len());
        for (&vr, &order) in vrs.iter().zip(orders) {
            let v = match self.lookup(vr) {
                Ok(v) => v,
                Err(msg) => return self.fail(f, msg),
            };
            let name = v.name();
            let id = match (v.kind, v.causality(&config)) {
                (VarKind::Output(o), _) => o,
                (VarKind::Input(InputId::FD), Causality::Output) => OutputId::FDrive,
                (_, c) => {
                    return self.fail(
                        f,
                        format!(
                        "{name} (vr {vr}) has causality {}: only outputs have output derivatives",
                        c.as_str()
                    ),
                    )
                }
            };
            if order != 1 {
                return self.fail(
                    f,
                    format!("order = {order} for {name} (vr {vr}): only first derivatives (order 1) are provided (maxOutputDerivativeOrder = 1)"),
                );
            }
            let Some(sim) = self.sim.as_ref() else {
                return self.fail(
                    f,
                    format!(
                        "no simulation state: call {} first",
                        call.words.exit_initialization
                    ),
                );
            };
            match sim.output_derivative(id) {
                Some(d) if d.is_finite() => found.push(d),
                Some(d) => {
                    return self.fail(f, format!("the derivative of {name} (vr {vr}) is {d}"))
                }
                None => {
                    return self.fail(
                        f,
                        format!("{name} (vr {vr}) has no exact time derivative; derivatives are provided for x, y, v_x, v_y, s_x, s_y, and for F_Fx_step, F_Fy_step after the first {}", call.words.do_step),
                    )
                }
            }
        }
        values[..found.len()].copy_from_slice(&found);
        Status::Ok
    }

    /// Directional derivatives of a Co-Simulation instance: not provided.
    pub fn no_directional_derivative(&mut self, call: Call) -> Status {
        let f = call.name;
        self.fail(
            f,
            "not supported in Co-Simulation (providesDirectionalDerivative = false there); instantiate the FMU for Model Exchange for the Jacobians",
        )
    }

    /// A function of an interface or mode this FMU does not offer: an error saying why.
    pub fn unsupported(&mut self, call: Call, why: &str) -> Status {
        if let Err(s) = self.allow(call) {
            return s;
        }
        self.fail(call.name, format!("not supported: {why}"))
    }

    /// `fmi2GetInteger`, `fmi2SetInteger`, `fmi2GetBoolean`, ...: this FMU has only Real
    /// variables, so any value reference is an error and an empty call does nothing.
    pub fn no_variables_of_type(&mut self, call: Call, type_name: &str, vrs: &[u32]) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        match vrs.first() {
            None => Status::Ok,
            Some(&vr) => {
                let what = match by_vr(vr) {
                    Some(v) => format!("value reference {vr} ({}) is a Real variable", v.name()),
                    None => format!("unknown value reference {vr}"),
                };
                self.fail(f, format!("{what}; this FMU has no {type_name} variables"))
            }
        }
    }

    // ---- stepping ----------------------------------------------------------------------------

    /// `fmi2DoStep`: integrates exactly to `current + step`.
    pub fn do_step(&mut self, call: Call, current: f64, step: f64) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        let t = self.time();
        if !current.is_finite() {
            return self.fail(
                f,
                format!("currentCommunicationPoint = {current}: must be finite"),
            );
        }
        if !(step.is_finite() && step > 0.0) {
            return self.fail(
                f,
                format!("communicationStepSize = {step}: must be finite and > 0"),
            );
        }
        // Masters accumulate time with rounding: allow a relative 1e-9.
        if (current - t).abs() > 1e-9 * t.abs().max(1.0) {
            return self.fail(
                f,
                format!(
                    "currentCommunicationPoint = {current} is not the instance's time {t}: a step starts where the previous one ended"
                ),
            );
        }
        let target = current + step;
        if let Some(stop) = self.st.stop_time {
            if target > stop + 1e-9 * stop.abs().max(1.0) {
                return self.fail(
                    f,
                    format!(
                        "currentCommunicationPoint + communicationStepSize = {target} is past stopTime = {stop} of {}", call.words.setup_experiment
                    ),
                );
            }
        }
        let Some(sim) = self.sim.as_mut() else {
            return self.internal_error(call, "no simulator in state StepComplete");
        };
        match sim.step_to(target) {
            Ok(()) => {
                self.trace(|| format!("{f}: t = {current} -> {target}"));
                Status::Ok
            }
            Err(SimError::Solver(e)) => {
                self.st.state = State::StepFailed;
                self.discard(
                    f,
                    format!(
                        "the integrator could not reach t = {target} from t = {t} ({e}); the instance stays at t = {t} ({}); restore a state with {} to retry with a shorter step", call.words.last_successful_time, call.words.set_state
                    ),
                )
            }
            Err(e) => self.fail(f, e),
        }
    }

    /// `fmi2CancelStep`: steps are synchronous, so there is never one to cancel.
    pub fn cancel_step(&mut self, call: Call) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        let state = self.st.state;
        self.fail(
            f,
            format!(
                "only allowed while fmi2DoStep is pending; this FMU completes every step before fmi2DoStep returns (state {}); illegal call sequence",
                state.name()
            ),
        )
    }

    // ---- FMU state ---------------------------------------------------------------------------

    /// Checks that an FMU-state function may be called now (all states but `Fatal`).
    pub fn allow_call(&mut self, call: Call) -> Status {
        match self.allow(call) {
            Ok(()) => Status::Ok,
            Err(s) => s,
        }
    }

    /// `fmi2GetFMUstate`.
    pub fn get_fmu_state(&mut self, call: Call) -> Result<FmuState, Status> {
        let f = call.name;
        self.allow(call)?;
        let s = FmuState {
            guid: self.guid.clone(),
            interface: self.interface,
            edition: call.words.edition.to_string(),
            staged: self.st,
            sim: self.sim.as_ref().map(|s| s.snapshot()),
        };
        self.event(|| {
            format!(
                "{f}: saved state {} at t = {}",
                self.st.state.name(),
                self.time()
            )
        });
        Ok(s)
    }

    /// Builds the simulator a state holds; nothing is changed. A state restores only into an
    /// instance of the FMU, the standard's edition and the interface that saved it.
    fn simulator_of(&self, call: Call, s: &FmuState) -> Result<Option<Box<dyn Simulator>>, String> {
        if s.guid != self.guid {
            return Err(format!(
                "the state belongs to the FMU with GUID {}, this instance is {}",
                s.guid, self.guid
            ));
        }
        if s.interface != self.interface || s.edition != call.words.edition {
            return Err(format!(
                "the state was saved by an {} {} instance and this instance is {} {}: a state restores only into an instance of the interface and edition that saved it (their state machines differ)",
                s.edition,
                s.interface.name(),
                call.words.edition,
                self.interface.name()
            ));
        }
        match &s.sim {
            None => Ok(None),
            Some(snap) => {
                let mut sim = model::build(
                    self.scene.config,
                    s.staged.params,
                    s.staged.start_time,
                    s.staged.tolerance(),
                )
                .map_err(|e| e.to_string())?;
                match s.interface {
                    Interface::CoSimulation => sim.restore(snap),
                    Interface::ModelExchange => sim.restore_exchange(snap),
                }
                .map_err(|e| e.to_string())?;
                Ok(Some(sim))
            }
        }
    }

    /// `fmi2SetFMUstate`: the instance continues exactly as the one the state was taken from.
    pub fn set_fmu_state(&mut self, call: Call, s: &FmuState) -> Status {
        let f = call.name;
        if let Err(st) = self.allow(call) {
            return st;
        }
        match self.simulator_of(call, s) {
            Ok(sim) => {
                self.st = s.staged;
                self.sim = sim;
                self.provisional = None;
                self.error_cause = None;
                self.event(|| {
                    format!(
                        "{f}: restored state {} at t = {}",
                        self.st.state.name(),
                        self.time()
                    )
                });
                Status::Ok
            }
            Err(e) => self.fail(f, e),
        }
    }

    /// `fmi2SerializedFMUstateSize` and `fmi2SerializeFMUstate`: the bytes of a state.
    pub fn serialize_fmu_state(&mut self, call: Call, s: &FmuState) -> Result<Vec<u8>, Status> {
        self.allow(call)?;
        Ok(saved::encode(s))
    }

    /// `fmi2DeSerializeFMUstate`: checks everything, including that the simulator restores.
    pub fn deserialize_fmu_state(&mut self, call: Call, bytes: &[u8]) -> Result<FmuState, Status> {
        let f = call.name;
        self.allow(call)?;
        let s = match saved::decode(bytes) {
            Ok(s) => s,
            Err(e) => return Err(self.fail(f, e)),
        };
        if let Err(e) = self.simulator_of(call, &s) {
            return Err(self.fail(f, e));
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi::fmi2::co_simulation;
    use crate::fmi::fmi2::types::{fmi2DoStepStatus, fmi2LastSuccessfulTime};
    use crate::fmi::fmi2::Function as Fn;
    use crate::fmi::saved::{decode, encode};
    use std::cell::RefCell;
    use std::rc::Rc;

    type Log = Rc<RefCell<Vec<(Status, String, String)>>>;

    struct Collect(Log);

    impl crate::fmi::Logger for Collect {
        fn log(&self, status: Status, category: &str, message: &str) {
            self.0
                .borrow_mut()
                .push((status, category.to_string(), message.to_string()));
        }
    }

    const SCENE: &str = r#"
model_identifier = "VibratingContact"
law = "dahl"
motion = "planar"
drive = "force"
support = ["harmonic", "input"]
"#;

    fn instance(dir: &std::path::Path) -> (Instance, Log) {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
        let scene = Scene::parse(SCENE, "scene.toml").unwrap();
        let log: Log = Default::default();
        let inst = Instance::instantiate(
            Fn::Instantiate.call(),
            crate::fmi::Interface::CoSimulation,
            "unit",
            "fmuGUID",
            Some(&xml::guid(&scene)),
            dir,
            "a test folder",
            Box::new(Collect(log.clone())),
            false,
        )
        .unwrap();
        (inst, log)
    }

    fn tmp(name: &str) -> std::path::PathBuf {
        std::env::temp_dir().join(format!("vibrofric-unit-{}-{name}", std::process::id()))
    }

    #[test]
    fn call_sequence_and_state_machine() {
        let dir = tmp("seq");
        let (mut i, log) = instance(&dir);
        assert_eq!(i.state(), State::Instantiated);
        assert_eq!(i.do_step(Fn::DoStep.call(), 0.0, 1e-3), Status::Error);
        assert_eq!(i.state(), State::Error);
        assert!(log.borrow().last().unwrap().2.contains("fmi2DoStep"));
        assert!(log.borrow().last().unwrap().2.contains("Instantiated"));
        assert_eq!(i.reset(Fn::Reset.call()), Status::Ok);
        assert_eq!(
            i.setup_experiment(Fn::SetupExperiment.call(), Some(1e-7), 0.0, Some(1.0)),
            Status::Ok
        );
        assert_eq!(
            i.enter_initialization_mode(Fn::EnterInitializationMode.call()),
            Status::Ok
        );
        assert_eq!(i.set_real(Fn::SetReal.call(), &[101], &[2.0]), Status::Ok);
        let mut v = [0.0; 2];
        assert_eq!(
            i.get_real(Fn::GetReal.call(), &[101, 201], &mut v),
            Status::Ok
        );
        assert_eq!(v[0], 2.0);
        assert_eq!(
            i.exit_initialization_mode(Fn::ExitInitializationMode.call()),
            Status::Ok
        );
        assert_eq!(i.do_step(Fn::DoStep.call(), 0.0, 1e-3), Status::Ok);
        assert_eq!(i.do_step(Fn::DoStep.call(), 1e-3, 1e-3), Status::Ok);
        assert_eq!(i.time(), 2e-3);
        assert_eq!(
            co_simulation::get_real_status(
                &mut i,
                Fn::GetRealStatus.call(),
                fmi2LastSuccessfulTime
            ),
            (Status::Ok, 2e-3)
        );
        assert_eq!(
            co_simulation::get_status(&mut i, Fn::GetStatus.call(), fmi2DoStepStatus),
            Status::Discard
        );
        assert_eq!(i.state(), State::StepComplete);
        assert_eq!(i.terminate(Fn::Terminate.call()), Status::Ok);
        assert_eq!(
            i.get_real(Fn::GetReal.call(), &[203], &mut v[..1]),
            Status::Ok
        );
        assert!(v[0] > 0.0, "pushed by F_d = 2 N, x = {}", v[0]);
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn bad_values_change_nothing() {
        let dir = tmp("bad");
        let (mut i, log) = instance(&dir);
        let before = i.st;
        assert_eq!(
            i.set_real(Fn::SetReal.call(), &[2, 4], &[10.0, 0.0]),
            Status::Error
        );
        assert!(log.borrow().last().unwrap().2.contains("k_t"));
        assert_eq!(i.st.params, before.params);
        assert_eq!(i.state(), State::Error);
        assert_eq!(
            i.set_real(Fn::SetReal.call(), &[2], &[1.0]),
            Status::Error,
            "not allowed in Error"
        );
        assert!(log.borrow().last().unwrap().2.contains("state Error"));
        assert_eq!(i.reset(Fn::Reset.call()), Status::Ok);
        assert_eq!(
            i.set_real(Fn::SetReal.call(), &[999], &[1.0]),
            Status::Error
        );
        assert!(log.borrow().last().unwrap().2.contains("999"));
        assert_eq!(i.st.params, before.params);
    }

    #[test]
    fn serialisation_round_trips_and_detects_corruption() {
        let dir = tmp("ser");
        let (mut i, _) = instance(&dir);
        i.enter_initialization_mode(Fn::EnterInitializationMode.call());
        i.exit_initialization_mode(Fn::ExitInitializationMode.call());
        i.do_step(Fn::DoStep.call(), 0.0, 1e-3);
        let s = i.get_fmu_state(Fn::GetFMUstate.call()).unwrap();
        let b = encode(&s);
        assert_eq!(decode(&b).unwrap(), s);
        let mut padded = b.clone();
        padded.extend_from_slice(&[0; 7]);
        assert_eq!(decode(&padded).unwrap(), s);
        let mut bad = b.clone();
        bad[40] ^= 1;
        assert!(decode(&bad).is_err());
        assert!(decode(&b[..b.len() - 1]).is_err());
    }
}
