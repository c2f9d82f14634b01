//! One FMU instance, in safe Rust and in no particular FMI version.
//!
//! A version's C layer (`fmi2/ffi.rs`, `fmi3/ffi/`) turns C pointers into slices and strings
//! and runs each call through [`Instance::answer`] with a [`Call`]: the function's name, the
//! states its version's table allows it in and the interface it belongs to. `answer` checks
//! that once, at the entry; the function then validates all of its arguments and only then
//! changes the instance. A function that does not go through returns a [`Refusal`], which
//! `answer` turns into the log message (naming the function, the variable and the rule), the
//! change of state (`Error`, from which the instance can still be read, restored, reset or
//! freed) and the status, in one place.
//!
//! The functions are grouped as the standard groups them: `life_cycle.rs` (logging, experiment,
//! initialization, termination, reset), `values.rs` (get and set by value reference, input and
//! output derivatives), `stepping.rs` (Co-Simulation steps), `saved_states.rs` (save, restore,
//! serialize) and `model_exchange.rs` (time, continuous states, event indicators, events,
//! directional derivatives).
//!
//! Parameters and inputs set before initialization ends are staged in [`Staged`]; leaving
//! initialization builds the [`Simulator`] at the experiment's start time with the
//! experiment's tolerance (when defined; else the `DefaultExperiment`'s).

mod life_cycle;
mod model_exchange;
mod saved_states;
mod stepping;
mod string;
mod string_exchange;
mod values;

pub use model_exchange::EventInfo;

use super::log::Logger;
use super::refusal::{Answer, Refusal};
use super::staging::Staged;
use super::state::{Call, Interface, State};
use super::status::Status;
use crate::description::log::Category;
use crate::description::scene::Scene;
use crate::description::variables::{by_vr, VarKind, Variable};
use crate::description::xml;
use crate::model::{self, SimError, Simulator, StateId};

/// The FMU instance.
pub struct Instance {
    name: String,
    scene: Scene,
    guid: String,
    /// Co-Simulation or Model Exchange, as instantiated.
    interface: Interface,
    /// The scene's variables, sorted by value reference.
    vars: Vec<&'static Variable>,
    /// Model Exchange: the scene's continuous states, in the order of the state vector.
    states: Vec<StateId>,
    logger: Box<dyn Logger>,
    categories: [bool; 4],
    st: Staged,
    sim: Option<Box<dyn Simulator>>,
    /// A string scene's values and simulator (`string.rs`); `None` for a single contact.
    string: Option<string::StringPart>,
    /// Simulator built from the staged values to answer a get before the real one exists
    /// (without the rules between parameters, see `simulator_now`); dropped whenever a staged
    /// value changes.
    provisional: Option<Box<dyn Simulator>>,
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
        let scene = match Self::read_scene(token_arg, guid, dir, origin) {
            Ok(scene) => scene,
            Err(msg) => {
                let error = Category::StatusError.name();
                logger.log(Status::Error, error, &format!("{}: {msg}", call.name));
                return None;
            }
        };
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
            guid: xml::guid(&scene),
            string: scene.string.clone().map(string::StringPart::new),
            scene,
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

    /// The scene of the resources folder `dir`, checked against the token `guid`.
    fn read_scene(
        token_arg: &str,
        guid: Option<&str>,
        dir: &std::path::Path,
        origin: &str,
    ) -> Result<Scene, String> {
        let path = dir.join("scene.toml");
        let text = std::fs::read_to_string(&path)
            .map_err(|e| format!("cannot read {} (from {origin}): {e}", path.display()))?;
        let scene = Scene::parse(&text, &path.display().to_string())
            .map_err(|e| format!("resources/scene.toml is invalid: {e}"))?;
        let expected = xml::guid(&scene);
        match guid {
            Some(g) if g == expected => Ok(scene),
            Some(g) => Err(format!(
                "{token_arg} = \"{g}\" does not match this FMU's GUID \"{expected}\" (model {}): the modelDescription.xml and resources/scene.toml come from different FMUs",
                scene.model_identifier
            )),
            None => Err(format!(
                "{token_arg} = NULL: must be the guid of modelDescription.xml, \"{expected}\""
            )),
        }
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
        match self.string.as_ref().and_then(|p| p.sim.as_ref()) {
            Some(s) => s.time(),
            None => self.sim.as_ref().map_or(self.st.start_time, |s| s.time()),
        }
    }

    // ---- the entry of every call -------------------------------------------------------------

    /// Runs one call of the C interface: checks that the call may be made by this instance (a
    /// function of its interface, or one common to both) in its current state, then runs
    /// `body`, and turns a refusal from either into log, state and status.
    pub fn answer(&mut self, call: Call, body: impl FnOnce(&mut Instance) -> Answer) -> Status {
        match self.allow(call).and_then(|()| body(self)) {
            Ok(status) => status,
            Err(refusal) => self.refuse(call, refusal),
        }
    }

    /// Whether `call` is allowed now; the refusal says why not.
    fn allow(&self, call: Call) -> Answer<()> {
        if let Some(only) = call.only {
            if only != self.interface {
                return Err(Refusal::Error(format!(
                    "a function of {} only, and this instance was instantiated for {}: an instance answers only the functions of its own interface ({}); illegal call sequence",
                    only.name(),
                    self.interface.name(),
                    call.words.edition
                )));
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
        Err(Refusal::Error(format!(
            "not allowed in state {} (allowed in: {}); illegal call sequence{cause}",
            state.name(),
            call.allowed.names()
        )))
    }

    /// The one place a refusal becomes a log message (`f: msg [instance "name"]`), a change of
    /// state and a status. An error remembers which call put the instance in `Error`, for the
    /// messages of the calls refused afterwards.
    fn refuse(&mut self, call: Call, refusal: Refusal) -> Status {
        let f = call.name;
        let (status, msg) = match refusal {
            Refusal::Error(msg) => (Status::Error, msg),
            Refusal::Discard(msg) => (Status::Discard, msg),
            Refusal::StepFailed(msg) => {
                self.st.state = State::StepFailed;
                (Status::Discard, msg)
            }
            Refusal::Internal(what) => {
                self.provisional = None;
                let words = call.words;
                let msg = format!(
                    "internal error ({what}); call {} or {} to continue",
                    words.reset, words.set_state
                );
                (Status::Error, msg)
            }
        };
        self.log(
            status,
            Category::StatusError,
            &format!("{f}: {msg} [instance \"{}\"]", self.name),
        );
        if status == Status::Error && !matches!(self.st.state, State::Fatal | State::Error) {
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
        status
    }

    /// Called by the C layer after it caught a panic: the instance may be half-updated, so it
    /// only remains to be reset, restored or freed.
    pub fn internal_error(&mut self, call: Call, what: &str) -> Status {
        self.refuse(call, Refusal::Internal(what.to_string()))
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

    // ---- what every group of functions uses --------------------------------------------------

    /// The simulator built from the staged values, as leaving initialization builds it.
    fn setup(&self) -> model::Setup {
        model::Setup::new(self.scene.config, self.st.params)
            .inputs(self.st.inputs)
            .derivatives(self.st.derivs)
            .start(self.st.start_time)
            .tolerance(self.st.tolerance())
    }

    /// The simulator built from the staged values, checked as leaving initialization checks
    /// them.
    fn build_sim(&self) -> Result<Box<dyn Simulator>, SimError> {
        self.setup().build()
    }

    /// The variable with this value reference, or why there is none in this scene.
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

    /// The simulator, or before it exists one built from the staged values. That one reads
    /// values only: the rules between parameters (LuGre's `F_S` ≥ `F_C`) belong to leaving
    /// initialization, which refuses them, and not to a read (values set in any order).
    fn simulator_now(&mut self) -> Answer<&dyn Simulator> {
        if self.sim.is_none() && self.provisional.is_none() {
            let sim = self.setup().provisional().build();
            self.provisional = Some(sim.map_err(Refusal::error)?);
        }
        match self.sim.as_deref().or(self.provisional.as_deref()) {
            Some(sim) => Ok(sim),
            None => unreachable!("built above"),
        }
    }

    /// The simulator, which exists once initialization is over.
    fn simulator(&mut self, when: &str) -> Answer<&mut Box<dyn Simulator>> {
        self.sim
            .as_mut()
            .ok_or_else(|| Refusal::Internal(format!("no simulator in {when}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi::fmi2::co_simulation;
    use crate::fmi::fmi2::types::{fmi2DoStepStatus, fmi2LastSuccessfulTime};
    use crate::fmi::fmi2::Function as Fn;
    use crate::fmi::saved::{decode, encode};

    /// Runs one call as the C layer does: through [`Instance::answer`].
    fn run(i: &mut Instance, f: Fn, body: impl FnOnce(&mut Instance, Call) -> Answer) -> Status {
        let call = f.call();
        i.answer(call, |i| body(i, call))
    }
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
        assert_eq!(
            run(&mut i, Fn::DoStep, |i, c| i.step(c, 0.0, 1e-3)),
            Status::Error
        );
        assert_eq!(i.state(), State::Error);
        assert!(log.borrow().last().unwrap().2.contains("fmi2DoStep"));
        assert!(log.borrow().last().unwrap().2.contains("Instantiated"));
        assert_eq!(run(&mut i, Fn::Reset, |i, c| i.reset(c)), Status::Ok);
        assert_eq!(
            run(&mut i, Fn::SetupExperiment, |i, c| i.set_experiment(
                c,
                Some(1e-7),
                0.0,
                Some(1.0)
            )),
            Status::Ok
        );
        assert_eq!(
            run(&mut i, Fn::EnterInitializationMode, |i, c| i
                .enter_initialization(c)),
            Status::Ok
        );
        assert_eq!(
            run(&mut i, Fn::SetReal, |i, c| i.set_values(c, &[101], &[2.0])),
            Status::Ok
        );
        let mut v = [0.0; 2];
        assert_eq!(
            run(&mut i, Fn::GetReal, |i, c| i.get_values(
                c,
                &[101, 201],
                &mut v
            )),
            Status::Ok
        );
        assert_eq!(v[0], 2.0);
        assert_eq!(
            run(&mut i, Fn::ExitInitializationMode, |i, c| i
                .exit_initialization(c)),
            Status::Ok
        );
        assert_eq!(
            run(&mut i, Fn::DoStep, |i, c| i.step(c, 0.0, 1e-3)),
            Status::Ok
        );
        assert_eq!(
            run(&mut i, Fn::DoStep, |i, c| i.step(c, 1e-3, 1e-3)),
            Status::Ok
        );
        assert_eq!(i.time(), 2e-3);
        assert_eq!(
            co_simulation::get_real_status(&i, fmi2LastSuccessfulTime),
            Ok(2e-3)
        );
        assert_eq!(
            run(&mut i, Fn::GetStatus, |_, _| co_simulation::get_status(
                fmi2DoStepStatus
            )),
            Status::Discard
        );
        assert_eq!(i.state(), State::StepComplete);
        assert_eq!(
            run(&mut i, Fn::Terminate, |i, c| i.terminate(c)),
            Status::Ok
        );
        assert_eq!(
            run(&mut i, Fn::GetReal, |i, c| i.get_values(
                c,
                &[203],
                &mut v[..1]
            )),
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
            run(&mut i, Fn::SetReal, |i, c| i.set_values(
                c,
                &[2, 4],
                &[10.0, 0.0]
            )),
            Status::Error
        );
        assert!(log.borrow().last().unwrap().2.contains("k_t"));
        assert_eq!(i.st.params, before.params);
        assert_eq!(i.state(), State::Error);
        assert_eq!(
            run(&mut i, Fn::SetReal, |i, c| i.set_values(c, &[2], &[1.0])),
            Status::Error,
            "not allowed in Error"
        );
        assert!(log.borrow().last().unwrap().2.contains("state Error"));
        assert_eq!(run(&mut i, Fn::Reset, |i, c| i.reset(c)), Status::Ok);
        assert_eq!(
            run(&mut i, Fn::SetReal, |i, c| i.set_values(c, &[999], &[1.0])),
            Status::Error
        );
        assert!(log.borrow().last().unwrap().2.contains("999"));
        assert_eq!(i.st.params, before.params);
    }

    #[test]
    fn serialisation_round_trips_and_detects_corruption() {
        let dir = tmp("ser");
        let (mut i, _) = instance(&dir);
        run(&mut i, Fn::EnterInitializationMode, |i, c| {
            i.enter_initialization(c)
        });
        run(&mut i, Fn::ExitInitializationMode, |i, c| {
            i.exit_initialization(c)
        });
        run(&mut i, Fn::DoStep, |i, c| i.step(c, 0.0, 1e-3));
        let s = i.save_state(Fn::GetFMUstate.call());
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
