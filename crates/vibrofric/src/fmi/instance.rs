//! One FMU instance and its FMI 2.0 Co-Simulation state machine, in safe Rust.
//!
//! `ffi.rs` turns C pointers into slices and strings and calls the methods here; every method
//! first checks that the call is allowed in the current state (the table of the standard, as the
//! Reference FMUs encode it), then validates all of its arguments, and only then changes the
//! instance. A call that fails logs a message naming the function, the variable and the rule,
//! leaves every value as it was, and moves the instance to the `Error` state of the standard,
//! from which it can still be read (`fmi2GetReal`), restored (`fmi2SetFMUstate`), reset
//! (`fmi2Reset`) or freed.
//!
//! Parameters and inputs set before `fmi2ExitInitializationMode` are staged in [`Params`] and
//! [`Inputs`]; leaving initialization builds the [`Simulator`] at the experiment's start time
//! with the tolerance of `fmi2SetupExperiment` (when defined; else the `DefaultExperiment`'s).

use std::fmt::Display;

use crate::description::scene::Scene;
use crate::description::variables::{by_vr, Causality, VarKind, Variability, Variable};
use crate::description::xml;
use crate::model::{self, InputId, Inputs, OutputId, Outputs, SimError, Simulator};
use crate::physics::{ParamId, Params};

/// `fmi2Status`, as the instance reports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
    Pending = 5,
}

impl Status {
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "fmi2OK",
            Status::Warning => "fmi2Warning",
            Status::Discard => "fmi2Discard",
            Status::Error => "fmi2Error",
            Status::Fatal => "fmi2Fatal",
            Status::Pending => "fmi2Pending",
        }
    }
}

/// `fmi2Type` value of Co-Simulation, the only interface this FMU implements.
pub const CO_SIMULATION: i32 = 1;

/// `fmi2StatusKind`.
pub mod status_kind {
    pub const DO_STEP_STATUS: i32 = 0;
    pub const PENDING_STATUS: i32 = 1;
    pub const LAST_SUCCESSFUL_TIME: i32 = 2;
    pub const TERMINATED: i32 = 3;

    pub fn name(kind: i32) -> String {
        match kind {
            DO_STEP_STATUS => "fmi2DoStepStatus".into(),
            PENDING_STATUS => "fmi2PendingStatus".into(),
            LAST_SUCCESSFUL_TIME => "fmi2LastSuccessfulTime".into(),
            TERMINATED => "fmi2Terminated".into(),
            k => format!("fmi2StatusKind {k} (unknown)"),
        }
    }
}

/// The states of the FMI 2.0 Co-Simulation state machine this FMU can be in. A synchronous
/// slave never is in `stepInProgress` or `stepCanceled`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmiState {
    Instantiated,
    InitializationMode,
    StepComplete,
    /// After `fmi2DoStep` returned `fmi2Discard` (the integrator could not reach the end of the
    /// step; the instance is still at the step's start).
    StepFailed,
    Terminated,
    Error,
    Fatal,
}

impl FmiState {
    const ALL: [FmiState; 7] = [
        FmiState::Instantiated,
        FmiState::InitializationMode,
        FmiState::StepComplete,
        FmiState::StepFailed,
        FmiState::Terminated,
        FmiState::Error,
        FmiState::Fatal,
    ];

    pub fn name(self) -> &'static str {
        match self {
            FmiState::Instantiated => "Instantiated",
            FmiState::InitializationMode => "InitializationMode",
            FmiState::StepComplete => "StepComplete",
            FmiState::StepFailed => "StepFailed",
            FmiState::Terminated => "Terminated",
            FmiState::Error => "Error",
            FmiState::Fatal => "Fatal",
        }
    }

    const fn bit(self) -> u32 {
        1 << self as u32
    }

    fn code(self) -> u8 {
        self as u8
    }

    fn from_code(c: u8) -> Option<FmiState> {
        FmiState::ALL.get(c as usize).copied()
    }
}

// Masks of the states in which each call is allowed (FMI 2.0, section 4.2.4).
const INSTANTIATED: u32 = FmiState::Instantiated.bit();
const INIT: u32 = FmiState::InitializationMode.bit();
const STEP_COMPLETE: u32 = FmiState::StepComplete.bit();
const STEP_FAILED: u32 = FmiState::StepFailed.bit();
const TERMINATED: u32 = FmiState::Terminated.bit();
const ERROR: u32 = FmiState::Error.bit();
/// Every state but `Fatal`.
const ANY: u32 = INSTANTIATED | INIT | STEP_COMPLETE | STEP_FAILED | TERMINATED | ERROR;
const MASK_GET: u32 = INIT | STEP_COMPLETE | STEP_FAILED | TERMINATED | ERROR;
const MASK_SET: u32 = INSTANTIATED | INIT | STEP_COMPLETE;
const MASK_STATUS: u32 = STEP_COMPLETE | STEP_FAILED | TERMINATED;
const MASK_OUTPUT_DERIVATIVES: u32 = STEP_COMPLETE | STEP_FAILED | TERMINATED | ERROR;

fn mask_names(mask: u32) -> String {
    FmiState::ALL
        .iter()
        .filter(|s| mask & s.bit() != 0)
        .map(|s| s.name())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Log categories of `modelDescription.xml` (`docs/using.md`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    Events = 0,
    StatusWarning = 1,
    StatusError = 2,
    All = 3,
}

impl Category {
    pub const ALL: [Category; 4] = [
        Category::Events,
        Category::StatusWarning,
        Category::StatusError,
        Category::All,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Category::Events => "logEvents",
            Category::StatusWarning => "logStatusWarning",
            Category::StatusError => "logStatusError",
            Category::All => "logAll",
        }
    }

    pub fn from_name(s: &str) -> Option<Category> {
        Category::ALL.into_iter().find(|c| c.name() == s)
    }
}

/// Where the instance's messages go: the importer's logger callback, wrapped by `ffi.rs`.
pub trait Logger {
    /// `category` is one of [`Category::name`]; `message` is plain text (no format directives
    /// are interpreted).
    fn log(&self, status: Status, category: &str, message: &str);
}

/// A logger that drops everything (the importer gave none).
pub struct NoLogger;

impl Logger for NoLogger {
    fn log(&self, _: Status, _: &str, _: &str) {}
}

/// Relative tolerance when `fmi2SetupExperiment` defines none: the `DefaultExperiment`'s.
pub const DEFAULT_TOLERANCE: f64 = xml::DEFAULT_EXPERIMENT.2;

/// Everything about an instance that is not the simulator: what an FMU state saves besides
/// [`Simulator::snapshot`].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Staged {
    state: FmiState,
    /// Parameter values: staged before the simulator exists, its mirror afterwards.
    params: Params,
    /// Input values as last set (staged before the simulator exists).
    inputs: Inputs,
    /// First derivatives of inputs set before the simulator exists (applied when it is built).
    derivs: [Option<f64>; InputId::ALL.len()],
    start_time: f64,
    /// Tolerance of `fmi2SetupExperiment`, when it defined one.
    tolerance: Option<f64>,
    stop_time: Option<f64>,
}

impl Staged {
    fn initial(scene: &Scene) -> Staged {
        Staged {
            state: FmiState::Instantiated,
            params: scene.start,
            inputs: scene.inputs,
            derivs: [None; InputId::ALL.len()],
            start_time: xml::DEFAULT_EXPERIMENT.0,
            tolerance: None,
            stop_time: None,
        }
    }

    fn tolerance(&self) -> f64 {
        self.tolerance.unwrap_or(DEFAULT_TOLERANCE)
    }
}

/// A saved FMU state (`fmi2FMUstate`): the state machine's state, the staged values and the
/// simulator's complete state. Restoring it, also into another instance of the same FMU or
/// after serialisation, continues bit-for-bit.
#[derive(Clone, Debug, PartialEq)]
pub struct FmuState {
    guid: String,
    staged: Staged,
    sim: Option<Vec<f64>>,
}

/// The FMU instance.
pub struct Instance {
    name: String,
    scene: Scene,
    guid: String,
    /// The scene's variables, sorted by value reference.
    vars: Vec<&'static Variable>,
    logger: Box<dyn Logger>,
    categories: [bool; 4],
    st: Staged,
    sim: Option<Box<dyn Simulator>>,
    /// Simulator built from the staged values to answer `fmi2GetReal` before the real one
    /// exists; dropped whenever a staged value changes.
    provisional: Option<Box<dyn Simulator>>,
}

/// One validated assignment of `fmi2SetReal`.
#[derive(Clone, Copy)]
enum Assign {
    Param(ParamId, f64),
    Input(InputId, f64),
}

impl Instance {
    /// `fmi2Instantiate`: reads `<resource location>/scene.toml`, checks the GUID. On failure the
    /// reason is logged and `None` returned.
    pub fn instantiate(
        name: &str,
        fmu_type: i32,
        guid: Option<&str>,
        resource_location: Option<&str>,
        logger: Box<dyn Logger>,
        logging_on: bool,
    ) -> Option<Instance> {
        let fail = |msg: String| {
            logger.log(
                Status::Error,
                Category::StatusError.name(),
                &format!("fmi2Instantiate: {msg}"),
            );
        };
        if name.is_empty() {
            fail("instanceName = \"\": must not be empty (importers and logs tell instances apart by it)".into());
            return None;
        }
        if fmu_type != CO_SIMULATION {
            fail(format!(
                "fmuType = {fmu_type}: this FMU implements only fmi2CoSimulation ({CO_SIMULATION})"
            ));
            return None;
        }
        let Some(location) = resource_location else {
            fail("fmuResourceLocation = NULL: must be the file: URI of the FMU's resources folder, e.g. file:///path/to/fmu/resources/".into());
            return None;
        };
        let dir = match super::uri::resource_dir(location) {
            Ok(d) => d,
            Err(e) => {
                fail(e);
                return None;
            }
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
                    "cannot read {} (from fmuResourceLocation = \"{location}\"): {e}",
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
                    "fmuGUID = \"{g}\" does not match this FMU's GUID \"{expected}\" (model {}): the modelDescription.xml and resources/scene.toml come from different FMUs",
                    scene.model_identifier
                ));
                return None;
            }
            None => {
                fail(format!(
                    "fmuGUID = NULL: must be the guid of modelDescription.xml, \"{expected}\""
                ));
                return None;
            }
        }
        let mut vars: Vec<&'static Variable> = scene.variables().collect();
        vars.sort_by_key(|v| v.vr);
        let inst = Instance {
            name: name.to_string(),
            st: Staged::initial(&scene),
            scene,
            guid: expected,
            vars,
            logger,
            categories: [logging_on; 4],
            sim: None,
            provisional: None,
        };
        inst.event(|| {
            format!(
                "fmi2Instantiate: instance \"{}\" of {} ({}), resources {}",
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

    pub fn state(&self) -> FmiState {
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
    fn log(&self, status: Status, c: Category, msg: &str) {
        if status >= Status::Discard || self.enabled(c) {
            self.logger.log(status, c.name(), msg);
        }
    }

    /// A `logEvents` message, formatted only when that category is enabled.
    fn event(&self, msg: impl FnOnce() -> String) {
        if self.enabled(Category::Events) {
            self.logger.log(Status::Ok, Category::Events.name(), &msg());
        }
    }

    /// A `logAll` trace, formatted only when that category is enabled.
    fn trace(&self, msg: impl FnOnce() -> String) {
        if self.categories[Category::All as usize] {
            self.logger.log(Status::Ok, Category::All.name(), &msg());
        }
    }

    /// Logs `f: msg` as an error and enters the `Error` state.
    fn fail(&mut self, f: &str, msg: impl Display) -> Status {
        self.log(
            Status::Error,
            Category::StatusError,
            &format!("{f}: {msg} [instance \"{}\"]", self.name),
        );
        if self.st.state != FmiState::Fatal {
            self.st.state = FmiState::Error;
        }
        Status::Error
    }

    /// Logs `f: msg` as a discard; the state does not change.
    fn discard(&self, f: &str, msg: impl Display) -> Status {
        self.log(
            Status::Discard,
            Category::StatusError,
            &format!("{f}: {msg} [instance \"{}\"]", self.name),
        );
        Status::Discard
    }

    /// Checks that `f` may be called in the current state.
    fn allow(&mut self, f: &str, mask: u32) -> Result<(), Status> {
        if self.st.state.bit() & mask != 0 {
            return Ok(());
        }
        let state = self.st.state;
        Err(self.fail(
            f,
            format!(
                "not allowed in state {} (allowed in: {}); illegal call sequence",
                state.name(),
                mask_names(mask)
            ),
        ))
    }

    /// Logs an error for a call whose arguments the C layer found invalid (a NULL pointer).
    pub fn invalid_argument(&mut self, f: &str, msg: impl Display) -> Status {
        self.fail(f, msg)
    }

    /// Called by the C layer after it caught a panic: the instance may be half-updated, so it
    /// only remains to be reset, restored or freed.
    pub fn internal_error(&mut self, f: &str, what: &str) -> Status {
        self.provisional = None;
        self.fail(
            f,
            format!("internal error ({what}); call fmi2Reset or fmi2SetFMUstate to continue"),
        )
    }

    // ---- life cycle --------------------------------------------------------------------------

    /// `fmi2SetDebugLogging`. An empty category list applies to every category.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> Status {
        const F: &str = "fmi2SetDebugLogging";
        if let Err(s) = self.allow(F, ANY) {
            return s;
        }
        let mut wanted = Vec::with_capacity(categories.len());
        for c in categories {
            match Category::from_name(c) {
                Some(c) => wanted.push(c),
                None => {
                    let valid: Vec<_> = Category::ALL.iter().map(|c| c.name()).collect();
                    return self.fail(
                        F,
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
        self.event(|| format!("{F}: loggingOn = {on}, categories {categories:?}"));
        Status::Ok
    }

    /// `fmi2SetupExperiment`.
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Status {
        const F: &str = "fmi2SetupExperiment";
        if let Err(s) = self.allow(F, INSTANTIATED) {
            return s;
        }
        if let Some(tol) = tolerance {
            if !(tol.is_finite() && tol > 0.0) {
                return self.fail(
                    F,
                    format!("tolerance = {tol}: must be finite and > 0 (or toleranceDefined = fmi2False)"),
                );
            }
        }
        if !start_time.is_finite() {
            return self.fail(F, format!("startTime = {start_time}: must be finite"));
        }
        if let Some(stop) = stop_time {
            if !(stop.is_finite() && stop >= start_time) {
                return self.fail(
                    F,
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
                        "{F}: tolerance = {asked:e} is outside [{lo:e}, {hi:e}], the range the integrators resolve: using {used:e} [instance \"{}\"]",
                        self.name
                    ),
                );
                return Status::Warning;
            }
        }
        self.event(|| {
            format!(
                "{F}: tolerance {} ({}), startTime {start_time}, stopTime {}",
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
    pub fn enter_initialization_mode(&mut self) -> Status {
        const F: &str = "fmi2EnterInitializationMode";
        if let Err(s) = self.allow(F, INSTANTIATED) {
            return s;
        }
        self.st.state = FmiState::InitializationMode;
        self.event(|| F.to_string());
        Status::Ok
    }

    /// `fmi2ExitInitializationMode`: builds the simulator from the staged values.
    pub fn exit_initialization_mode(&mut self) -> Status {
        const F: &str = "fmi2ExitInitializationMode";
        if let Err(s) = self.allow(F, INIT) {
            return s;
        }
        match self.build_sim() {
            Ok(sim) => {
                self.sim = Some(sim);
                self.provisional = None;
                self.st.derivs = [None; InputId::ALL.len()];
                self.st.state = FmiState::StepComplete;
                self.event(|| {
                    format!(
                        "{F}: simulator built at t = {} with tolerance {}",
                        self.st.start_time,
                        self.st.tolerance()
                    )
                });
                Status::Ok
            }
            Err(e) => self.fail(F, e),
        }
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> Status {
        const F: &str = "fmi2Terminate";
        if let Err(s) = self.allow(F, STEP_COMPLETE | STEP_FAILED) {
            return s;
        }
        self.st.state = FmiState::Terminated;
        self.event(|| format!("{F}: at t = {}", self.time()));
        Status::Ok
    }

    /// `fmi2Reset`: back to `Instantiated` with the scene's start values.
    pub fn reset(&mut self) -> Status {
        const F: &str = "fmi2Reset";
        if let Err(s) = self.allow(F, ANY) {
            return s;
        }
        self.st = Staged::initial(&self.scene);
        self.sim = None;
        self.provisional = None;
        self.event(|| format!("{F}: start values restored"));
        Status::Ok
    }

    /// `fmi2FreeInstance` (the C layer then drops the instance).
    pub fn free(&self) {
        self.event(|| "fmi2FreeInstance".to_string());
    }

    fn build_sim(&self) -> Result<Box<dyn Simulator>, SimError> {
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

    fn lookup(&self, vr: u32) -> Result<&'static Variable, String> {
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

    fn outputs_now(&mut self) -> Result<Outputs, SimError> {
        if let Some(sim) = &self.sim {
            return Ok(sim.outputs());
        }
        if self.provisional.is_none() {
            self.provisional = Some(self.build_sim()?);
        }
        Ok(self
            .provisional
            .as_ref()
            .map(|s| s.outputs())
            .unwrap_or_default())
    }

    /// `fmi2GetReal`. `values` has the length of `vrs`.
    pub fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Status {
        const F: &str = "fmi2GetReal";
        if let Err(s) = self.allow(F, MASK_GET) {
            return s;
        }
        let mut vars = Vec::with_capacity(vrs.len());
        let mut need_outputs = false;
        for &vr in vrs {
            match self.lookup(vr) {
                Ok(v) => {
                    need_outputs |= v.causality(&self.scene.config) == Causality::Output;
                    vars.push(v);
                }
                Err(msg) => return self.fail(F, msg),
            }
        }
        let outputs = if need_outputs {
            match self.outputs_now() {
                Ok(o) => o,
                Err(e) => return self.fail(F, e),
            }
        } else {
            Outputs::default()
        };
        for (v, out) in vars.iter().zip(values.iter_mut()) {
            *out = match v.kind {
                VarKind::Param(ParamId::FN) if self.scene.config.normal_input => self.st.inputs.f_n,
                VarKind::Param(p) => p.get(&self.st.params),
                VarKind::Input(i) if v.causality(&self.scene.config) == Causality::Input => {
                    i.get(&self.st.inputs)
                }
                VarKind::Input(_) => OutputId::FDrive.get(&outputs),
                VarKind::Output(o) => o.get(&outputs),
            };
        }
        // fmi2OK never comes with a non-finite value (the ranges are chosen so that none
        // arises; this is the last guard).
        if let Some((v, x)) = vars.iter().zip(values.iter()).find(|(_, x)| !x.is_finite()) {
            let (name, x) = (v.name(), *x);
            return self.fail(F, format!("{name} evaluates to {x}: a parameter or input is beyond what the model can compute; restore a state with fmi2SetFMUstate"));
        }
        Status::Ok
    }

    /// `fmi2SetReal`: every value is checked before any is written.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        const F: &str = "fmi2SetReal";
        if let Err(s) = self.allow(F, MASK_SET) {
            return s;
        }
        let state = self.st.state;
        let config = self.scene.config;
        let mut plan = Vec::with_capacity(vrs.len());
        for (&vr, &value) in vrs.iter().zip(values) {
            let v = match self.lookup(vr) {
                Ok(v) => v,
                Err(msg) => return self.fail(F, msg),
            };
            let name = v.name();
            match (v.kind, v.causality(&config)) {
                (_, Causality::Output) => {
                    return self.fail(
                        F,
                        format!("{name} (vr {vr}) has causality output: it is computed by the FMU and cannot be set"),
                    )
                }
                (VarKind::Param(ParamId::FN), Causality::Input) => {
                    let rule = InputId::FN.rule();
                    if !rule.holds(value) {
                        return self.fail(
                            F,
                            format!("F_N = {value}: {} (vr {vr}; a contact cannot pull, 0: the body has lifted off)", rule.text(value, "N")),
                        );
                    }
                    plan.push(Assign::Input(InputId::FN, value));
                }
                (VarKind::Param(p), _) => {
                    if v.variability(&config) == Variability::Fixed && state == FmiState::StepComplete {
                        return self.fail(
                            F,
                            format!(
                                "{name} (vr {vr}) is a parameter with variability fixed: it can only be set before fmi2ExitInitializationMode, not in state {}",
                                state.name()
                            ),
                        );
                    }
                    if let Err(e) = model::check_param(p, value, &config) {
                        return self.fail(F, format!("{e} (vr {vr})"));
                    }
                    plan.push(Assign::Param(p, value));
                }
                (VarKind::Input(i), _) => {
                    if !i.rule().holds(value) {
                        return self.fail(
                            F,
                            format!("{name} = {value}: {} (vr {vr})", i.rule().text(value, i.unit())),
                        );
                    }
                    plan.push(Assign::Input(i, value));
                }
                (VarKind::Output(_), _) => unreachable!("outputs have causality output"),
            }
        }
        if let Some(sim) = self.sim.as_mut() {
            let apply = |sim: &mut dyn Simulator, a: Assign| match a {
                Assign::Param(p, x) => sim.set_param(p, x),
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
                return self.fail(F, e);
            }
        }
        for a in plan {
            match a {
                Assign::Param(p, x) => {
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
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Status {
        const F: &str = "fmi2SetRealInputDerivatives";
        if let Err(s) = self.allow(F, MASK_SET) {
            return s;
        }
        let config = self.scene.config;
        let mut plan = Vec::with_capacity(vrs.len());
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let v = match self.lookup(vr) {
                Ok(v) => v,
                Err(msg) => return self.fail(F, msg),
            };
            let name = v.name();
            let id = match (v.kind, v.causality(&config)) {
                (VarKind::Input(i), Causality::Input) => i,
                (VarKind::Param(ParamId::FN), Causality::Input) => InputId::FN,
                (_, c) => {
                    return self.fail(
                        F,
                        format!(
                            "{name} (vr {vr}) has causality {}: only inputs have input derivatives",
                            c.as_str()
                        ),
                    )
                }
            };
            if order != 1 {
                return self.fail(
                    F,
                    format!("order = {order} for {name} (vr {vr}): only first derivatives (order 1) are supported"),
                );
            }
            if !(value.is_finite() && value.abs() <= model::MAX_INPUT_RATE) {
                return self.fail(
                    F,
                    format!(
                        "derivative of {name} = {value}: must be finite and at most {:e} {}/s in magnitude (vr {vr})",
                        model::MAX_INPUT_RATE,
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
                    return self.fail(F, e);
                }
            }
            None => {
                for (id, d) in plan {
                    let k = InputId::ALL.iter().position(|&i| i == id).unwrap_or(0);
                    self.st.derivs[k] = Some(d);
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
        vrs: &[u32],
        orders: &[i32],
        values: &mut [f64],
    ) -> Status {
        const F: &str = "fmi2GetRealOutputDerivatives";
        if let Err(s) = self.allow(F, MASK_OUTPUT_DERIVATIVES) {
            return s;
        }
        let config = self.scene.config;
        let mut found = Vec::with_capacity(vrs.len());
        for (&vr, &order) in vrs.iter().zip(orders) {
            let v = match self.lookup(vr) {
                Ok(v) => v,
                Err(msg) => return self.fail(F, msg),
            };
            let name = v.name();
            let id = match (v.kind, v.causality(&config)) {
                (VarKind::Output(o), _) => o,
                (VarKind::Input(InputId::FD), Causality::Output) => OutputId::FDrive,
                (_, c) => {
                    return self.fail(
                        F,
                        format!(
                        "{name} (vr {vr}) has causality {}: only outputs have output derivatives",
                        c.as_str()
                    ),
                    )
                }
            };
            if order != 1 {
                return self.fail(
                    F,
                    format!("order = {order} for {name} (vr {vr}): only first derivatives (order 1) are provided (maxOutputDerivativeOrder = 1)"),
                );
            }
            let Some(sim) = self.sim.as_ref() else {
                return self.fail(
                    F,
                    "no simulation state: call fmi2ExitInitializationMode first",
                );
            };
            match sim.output_derivative(id) {
                Some(d) if d.is_finite() => found.push(d),
                Some(d) => {
                    return self.fail(F, format!("the derivative of {name} (vr {vr}) is {d}"))
                }
                None => {
                    return self.fail(
                        F,
                        format!("{name} (vr {vr}) has no exact time derivative; derivatives are provided for x, y, v_x, v_y, s_x, s_y, and for F_Fx_step, F_Fy_step after the first fmi2DoStep"),
                    )
                }
            }
        }
        values[..found.len()].copy_from_slice(&found);
        Status::Ok
    }

    /// `fmi2GetDirectionalDerivative`: not supported.
    pub fn get_directional_derivative(&mut self) -> Status {
        const F: &str = "fmi2GetDirectionalDerivative";
        self.fail(
            F,
            "not supported: this FMU provides no directional derivatives (providesDirectionalDerivative = false)",
        )
    }

    /// `fmi2GetInteger`, `fmi2SetInteger`, `fmi2GetBoolean`, ...: this FMU has only Real
    /// variables, so any value reference is an error and an empty call does nothing.
    pub fn no_variables_of_type(&mut self, f: &str, type_name: &str, vrs: &[u32]) -> Status {
        let mask = if f.starts_with("fmi2Get") {
            MASK_GET
        } else {
            MASK_SET
        };
        if let Err(s) = self.allow(f, mask) {
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
    pub fn do_step(&mut self, current: f64, step: f64) -> Status {
        const F: &str = "fmi2DoStep";
        if let Err(s) = self.allow(F, STEP_COMPLETE) {
            return s;
        }
        let t = self.time();
        if !current.is_finite() {
            return self.fail(
                F,
                format!("currentCommunicationPoint = {current}: must be finite"),
            );
        }
        if !(step.is_finite() && step > 0.0) {
            return self.fail(
                F,
                format!("communicationStepSize = {step}: must be finite and > 0"),
            );
        }
        // Masters accumulate time with rounding: allow a relative 1e-9.
        if (current - t).abs() > 1e-9 * t.abs().max(1.0) {
            return self.fail(
                F,
                format!(
                    "currentCommunicationPoint = {current} is not the instance's time {t}: a step starts where the previous one ended"
                ),
            );
        }
        let target = current + step;
        if let Some(stop) = self.st.stop_time {
            if target > stop + 1e-9 * stop.abs().max(1.0) {
                return self.fail(
                    F,
                    format!(
                        "currentCommunicationPoint + communicationStepSize = {target} is past stopTime = {stop} of fmi2SetupExperiment"
                    ),
                );
            }
        }
        let Some(sim) = self.sim.as_mut() else {
            return self.internal_error(F, "no simulator in state StepComplete");
        };
        match sim.step_to(target) {
            Ok(()) => {
                self.trace(|| format!("{F}: t = {current} -> {target}"));
                Status::Ok
            }
            Err(SimError::Solver(e)) => {
                self.st.state = FmiState::StepFailed;
                self.discard(
                    F,
                    format!(
                        "the integrator could not reach t = {target} from t = {t} ({e}); the instance stays at t = {t} (fmi2LastSuccessfulTime); restore a state with fmi2SetFMUstate to retry with a shorter step"
                    ),
                )
            }
            Err(e) => self.fail(F, e),
        }
    }

    /// `fmi2CancelStep`: steps are synchronous, so there is never one to cancel.
    pub fn cancel_step(&mut self) -> Status {
        const F: &str = "fmi2CancelStep";
        let state = self.st.state;
        self.fail(
            F,
            format!(
                "only allowed while fmi2DoStep is pending; this FMU completes every step before fmi2DoStep returns (state {}); illegal call sequence",
                state.name()
            ),
        )
    }

    fn status_query(&mut self, f: &str, kind: i32, what: &str) -> Status {
        if let Err(s) = self.allow(f, MASK_STATUS) {
            return s;
        }
        let why = match kind {
            status_kind::DO_STEP_STATUS | status_kind::PENDING_STATUS => {
                "can be asked only after fmi2DoStep returned fmi2Pending; this FMU completes every step synchronously".to_string()
            }
            status_kind::LAST_SUCCESSFUL_TIME => "is a Real status: use fmi2GetRealStatus".into(),
            status_kind::TERMINATED => "is a Boolean status: use fmi2GetBooleanStatus".into(),
            _ => "is not a status kind of FMI 2.0".into(),
        };
        self.discard(f, format!("{} {why} ({what})", status_kind::name(kind)))
    }

    /// `fmi2GetStatus`: never available (no asynchronous steps); `fmi2Discard`.
    pub fn get_status(&mut self, kind: i32) -> Status {
        self.status_query("fmi2GetStatus", kind, "fmi2Status")
    }

    /// `fmi2GetRealStatus`: `fmi2LastSuccessfulTime` is the instance's time.
    pub fn get_real_status(&mut self, kind: i32) -> (Status, f64) {
        const F: &str = "fmi2GetRealStatus";
        if kind == status_kind::LAST_SUCCESSFUL_TIME {
            if let Err(s) = self.allow(F, MASK_STATUS) {
                return (s, 0.0);
            }
            return (Status::Ok, self.time());
        }
        (self.status_query(F, kind, "fmi2Real"), 0.0)
    }

    /// `fmi2GetIntegerStatus`: FMI 2.0 defines no Integer status; `fmi2Discard`.
    pub fn get_integer_status(&mut self, kind: i32) -> Status {
        self.status_query("fmi2GetIntegerStatus", kind, "fmi2Integer")
    }

    /// `fmi2GetBooleanStatus`: `fmi2Terminated` is false (the slave never asks to stop).
    pub fn get_boolean_status(&mut self, kind: i32) -> (Status, bool) {
        const F: &str = "fmi2GetBooleanStatus";
        if kind == status_kind::TERMINATED {
            if let Err(s) = self.allow(F, MASK_STATUS) {
                return (s, false);
            }
            return (Status::Ok, false);
        }
        (self.status_query(F, kind, "fmi2Boolean"), false)
    }

    /// `fmi2GetStringStatus`: no pending step, so no status string; `fmi2Discard`.
    pub fn get_string_status(&mut self, kind: i32) -> Status {
        self.status_query("fmi2GetStringStatus", kind, "fmi2String")
    }

    // ---- FMU state ---------------------------------------------------------------------------

    /// Checks that an FMU-state function may be called now (all states but `Fatal`).
    pub fn allow_state_call(&mut self, f: &str) -> Status {
        match self.allow(f, ANY) {
            Ok(()) => Status::Ok,
            Err(s) => s,
        }
    }

    /// `fmi2GetFMUstate`.
    pub fn get_fmu_state(&mut self) -> Result<FmuState, Status> {
        const F: &str = "fmi2GetFMUstate";
        self.allow(F, ANY)?;
        let s = FmuState {
            guid: self.guid.clone(),
            staged: self.st,
            sim: self.sim.as_ref().map(|s| s.snapshot()),
        };
        self.event(|| {
            format!(
                "{F}: saved state {} at t = {}",
                self.st.state.name(),
                self.time()
            )
        });
        Ok(s)
    }

    /// Builds the simulator a state holds; nothing is changed.
    fn simulator_of(&self, s: &FmuState) -> Result<Option<Box<dyn Simulator>>, String> {
        if s.guid != self.guid {
            return Err(format!(
                "the state belongs to the FMU with GUID {}, this instance is {}",
                s.guid, self.guid
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
                sim.restore(snap).map_err(|e| e.to_string())?;
                Ok(Some(sim))
            }
        }
    }

    /// `fmi2SetFMUstate`: the instance continues exactly as the one the state was taken from.
    pub fn set_fmu_state(&mut self, s: &FmuState) -> Status {
        const F: &str = "fmi2SetFMUstate";
        if let Err(st) = self.allow(F, ANY) {
            return st;
        }
        match self.simulator_of(s) {
            Ok(sim) => {
                self.st = s.staged;
                self.sim = sim;
                self.provisional = None;
                self.event(|| {
                    format!(
                        "{F}: restored state {} at t = {}",
                        self.st.state.name(),
                        self.time()
                    )
                });
                Status::Ok
            }
            Err(e) => self.fail(F, e),
        }
    }

    /// `fmi2SerializedFMUstateSize` and `fmi2SerializeFMUstate`: the bytes of a state.
    pub fn serialize_fmu_state(&mut self, f: &str, s: &FmuState) -> Result<Vec<u8>, Status> {
        self.allow(f, ANY)?;
        Ok(serialize(s))
    }

    /// `fmi2DeSerializeFMUstate`: checks everything, including that the simulator restores.
    pub fn deserialize_fmu_state(&mut self, bytes: &[u8]) -> Result<FmuState, Status> {
        const F: &str = "fmi2DeSerializeFMUstate";
        self.allow(F, ANY)?;
        let s = match deserialize(bytes) {
            Ok(s) => s,
            Err(e) => return Err(self.fail(F, e)),
        };
        if let Err(e) = self.simulator_of(&s) {
            return Err(self.fail(F, e));
        }
        Ok(s)
    }
}

// ---- serialisation -------------------------------------------------------------------------

const MAGIC: &[u8; 16] = b"vibrofric-state\0";
const FORMAT_VERSION: u32 = 3;

/// FNV-1a, 64 bit: detects a corrupted or truncated byte string.
fn checksum(b: &[u8]) -> u64 {
    b.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &x| {
        (h ^ x as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Layout (little-endian): magic, format version (u32), GUID (u32 length + UTF-8), state
/// machine state (u8), 18 parameters, 4 inputs, 4 × (flag u8, derivative), start time,
/// (flag, tolerance), (flag, stop time), (flag, u32 count, simulator snapshot), FNV-1a checksum
/// of everything before it (u64). Numbers are `f64` bit patterns, so a round trip is exact.
pub fn serialize(s: &FmuState) -> Vec<u8> {
    let mut b = Vec::with_capacity(512);
    b.extend_from_slice(MAGIC);
    b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    b.extend_from_slice(&(s.guid.len() as u32).to_le_bytes());
    b.extend_from_slice(s.guid.as_bytes());
    let st = &s.staged;
    b.push(st.state.code());
    let f = |b: &mut Vec<u8>, x: f64| b.extend_from_slice(&x.to_bits().to_le_bytes());
    for id in ParamId::ALL {
        f(&mut b, id.get(&st.params));
    }
    for id in InputId::ALL {
        f(&mut b, id.get(&st.inputs));
    }
    let opt = |b: &mut Vec<u8>, x: Option<f64>| {
        b.push(x.is_some() as u8);
        f(b, x.unwrap_or(0.0));
    };
    for d in st.derivs {
        opt(&mut b, d);
    }
    f(&mut b, st.start_time);
    opt(&mut b, st.tolerance);
    opt(&mut b, st.stop_time);
    match &s.sim {
        None => b.push(0),
        Some(v) => {
            b.push(1);
            b.extend_from_slice(&(v.len() as u32).to_le_bytes());
            for &x in v {
                f(&mut b, x);
            }
        }
    }
    let sum = checksum(&b);
    b.extend_from_slice(&sum.to_le_bytes());
    b
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.b.len());
        let end = end.ok_or_else(|| {
            format!(
                "serialized state truncated at byte {} of {}",
                self.at,
                self.b.len()
            )
        })?;
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, String> {
        let mut a = [0; 4];
        a.copy_from_slice(self.take(4)?);
        Ok(u32::from_le_bytes(a))
    }
    fn u64(&mut self) -> Result<u64, String> {
        let mut a = [0; 8];
        a.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(a))
    }
    fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(self.u64()?))
    }
    fn flag(&mut self) -> Result<bool, String> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            x => Err(format!("bad flag {x} at byte {}", self.at - 1)),
        }
    }
    fn opt(&mut self) -> Result<Option<f64>, String> {
        let present = self.flag()?;
        let x = self.f64()?;
        Ok(present.then_some(x))
    }
}

/// Reads what [`serialize`] wrote. Trailing zero bytes (a buffer larger than needed) are
/// accepted.
pub fn deserialize(bytes: &[u8]) -> Result<FmuState, String> {
    let mut r = Reader { b: bytes, at: 0 };
    if r.take(MAGIC.len()).ok() != Some(&MAGIC[..]) {
        return Err("not a serialized vibrofric FMU state (bad magic)".into());
    }
    let version = r.u32()?;
    if version != FORMAT_VERSION {
        return Err(format!(
            "serialized state has format version {version}, this FMU reads version {FORMAT_VERSION}"
        ));
    }
    let n = r.u32()? as usize;
    let guid = String::from_utf8(r.take(n)?.to_vec()).map_err(|_| "GUID is not UTF-8")?;
    let code = r.u8()?;
    let state = FmiState::from_code(code).ok_or(format!("bad state machine state {code}"))?;
    let mut params = Params::default();
    for id in ParamId::ALL {
        id.set(&mut params, r.f64()?)
            .map_err(|e| format!("serialized parameter {e}"))?;
    }
    let mut inputs = Inputs::default();
    for id in InputId::ALL {
        let x = r.f64()?;
        if !id.rule().holds(x) {
            return Err(format!(
                "serialized input {} = {x}: {}",
                id.name(),
                id.rule().text(x, id.unit())
            ));
        }
        *id.slot(&mut inputs) = x;
    }
    let mut derivs = [None; InputId::ALL.len()];
    for d in derivs.iter_mut() {
        *d = r.opt()?;
    }
    let start_time = r.f64()?;
    let tolerance = r.opt()?;
    let stop_time = r.opt()?;
    let sim = if r.flag()? {
        let n = r.u32()? as usize;
        if n > bytes.len() / 8 {
            return Err(format!(
                "simulator snapshot of {n} numbers exceeds the state's size"
            ));
        }
        let mut v = Vec::with_capacity(n);
        for _ in 0..n {
            v.push(r.f64()?);
        }
        Some(v)
    } else {
        None
    };
    let end = r.at;
    let sum = r.u64()?;
    if sum != checksum(&bytes[..end]) {
        return Err("checksum mismatch: the serialized state is corrupted".into());
    }
    if bytes[r.at..].iter().any(|&x| x != 0) {
        return Err(format!(
            "{} unexpected bytes after the serialized state",
            bytes.len() - r.at
        ));
    }
    // Untrusted input: every field checked as the calls that set it check it.
    for (id, d) in InputId::ALL.iter().zip(derivs) {
        if let Some(d) = d {
            if !(d.is_finite() && d.abs() <= model::MAX_INPUT_RATE) {
                return Err(format!(
                    "serialized derivative of {} = {d}: must be finite and at most {:e} in magnitude",
                    id.name(),
                    model::MAX_INPUT_RATE
                ));
            }
        }
    }
    if !start_time.is_finite() {
        return Err(format!(
            "serialized startTime = {start_time}: must be finite"
        ));
    }
    if let Some(t) = tolerance {
        let (lo, hi) = model::TOLERANCE_RANGE;
        if !(lo..=hi).contains(&t) {
            return Err(format!(
                "serialized tolerance = {t}: must be in [{lo:e}, {hi:e}]"
            ));
        }
    }
    if let Some(t) = stop_time {
        if !(t.is_finite() && t >= start_time) {
            return Err(format!(
                "serialized stopTime = {t}: must be finite and >= startTime = {start_time}"
            ));
        }
    }
    use FmiState as S;
    match (state, sim.is_some()) {
        (S::Fatal, _) => {
            return Err("serialized state machine state Fatal cannot be restored".into())
        }
        (S::StepComplete | S::StepFailed | S::Terminated, false) => {
            return Err(format!(
                "serialized state machine state {} has no simulator state",
                state.name()
            ))
        }
        (S::Instantiated | S::InitializationMode, true) => {
            return Err(format!(
                "serialized state machine state {} cannot carry a simulator state",
                state.name()
            ))
        }
        _ => {}
    }
    Ok(FmuState {
        guid,
        staged: Staged {
            state,
            params,
            inputs,
            derivs,
            start_time,
            tolerance,
            stop_time,
        },
        sim,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;
    use std::rc::Rc;

    type Log = Rc<RefCell<Vec<(Status, String, String)>>>;

    struct Collect(Log);

    impl Logger for Collect {
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
        let uri = format!("file://{}", dir.display());
        let inst = Instance::instantiate(
            "unit",
            CO_SIMULATION,
            Some(&xml::guid(&scene)),
            Some(&uri),
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
        assert_eq!(i.state(), FmiState::Instantiated);
        assert_eq!(i.do_step(0.0, 1e-3), Status::Error);
        assert_eq!(i.state(), FmiState::Error);
        assert!(log.borrow().last().unwrap().2.contains("fmi2DoStep"));
        assert!(log.borrow().last().unwrap().2.contains("Instantiated"));
        assert_eq!(i.reset(), Status::Ok);
        assert_eq!(i.setup_experiment(Some(1e-7), 0.0, Some(1.0)), Status::Ok);
        assert_eq!(i.enter_initialization_mode(), Status::Ok);
        assert_eq!(i.set_real(&[101], &[2.0]), Status::Ok);
        let mut v = [0.0; 2];
        assert_eq!(i.get_real(&[101, 201], &mut v), Status::Ok);
        assert_eq!(v[0], 2.0);
        assert_eq!(i.exit_initialization_mode(), Status::Ok);
        assert_eq!(i.do_step(0.0, 1e-3), Status::Ok);
        assert_eq!(i.do_step(1e-3, 1e-3), Status::Ok);
        assert_eq!(i.time(), 2e-3);
        assert_eq!(
            i.get_real_status(status_kind::LAST_SUCCESSFUL_TIME),
            (Status::Ok, 2e-3)
        );
        assert_eq!(i.get_status(status_kind::DO_STEP_STATUS), Status::Discard);
        assert_eq!(i.state(), FmiState::StepComplete);
        assert_eq!(i.terminate(), Status::Ok);
        assert_eq!(i.get_real(&[203], &mut v[..1]), Status::Ok);
        assert!(v[0] > 0.0, "pushed by F_d = 2 N, x = {}", v[0]);
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn bad_values_change_nothing() {
        let dir = tmp("bad");
        let (mut i, log) = instance(&dir);
        let before = i.st;
        assert_eq!(i.set_real(&[2, 4], &[10.0, 0.0]), Status::Error);
        assert!(log.borrow().last().unwrap().2.contains("k_t"));
        assert_eq!(i.st.params, before.params);
        assert_eq!(i.state(), FmiState::Error);
        assert_eq!(
            i.set_real(&[2], &[1.0]),
            Status::Error,
            "not allowed in Error"
        );
        assert!(log.borrow().last().unwrap().2.contains("state Error"));
        assert_eq!(i.reset(), Status::Ok);
        assert_eq!(i.set_real(&[999], &[1.0]), Status::Error);
        assert!(log.borrow().last().unwrap().2.contains("999"));
        assert_eq!(i.st.params, before.params);
    }

    #[test]
    fn serialisation_round_trips_and_detects_corruption() {
        let dir = tmp("ser");
        let (mut i, _) = instance(&dir);
        i.enter_initialization_mode();
        i.exit_initialization_mode();
        i.do_step(0.0, 1e-3);
        let s = i.get_fmu_state().unwrap();
        let b = serialize(&s);
        assert_eq!(deserialize(&b).unwrap(), s);
        let mut padded = b.clone();
        padded.extend_from_slice(&[0; 7]);
        assert_eq!(deserialize(&padded).unwrap(), s);
        let mut bad = b.clone();
        bad[40] ^= 1;
        assert!(deserialize(&bad).is_err());
        assert!(deserialize(&b[..b.len() - 1]).is_err());
    }
}
