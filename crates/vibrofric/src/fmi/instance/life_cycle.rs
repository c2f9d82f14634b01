//! The life cycle of an instance: logging, the experiment, initialization, termination,
//! reset and freeing.

use super::Instance;
use crate::description::log::Category;
use crate::fmi::refusal::{Answer, Refusal};
use crate::fmi::staging::Staged;
use crate::fmi::state::{Call, Interface, State};
use crate::fmi::status::Status;
use crate::model::{self, InputId};
use crate::table::number;

impl Instance {
    /// Logging on or off per category (`fmi2SetDebugLogging`, `fmi3SetDebugLogging`). An empty
    /// category list applies to every category.
    pub fn set_logging(&mut self, call: Call, on: bool, categories: &[&str]) -> Answer {
        let mut wanted = Vec::with_capacity(categories.len());
        for c in categories {
            match Category::from_name(c) {
                Some(c) => wanted.push(c),
                None => {
                    let valid: Vec<_> = Category::ALL.iter().map(|c| c.name()).collect();
                    return Err(Refusal::error(format!(
                        "unknown log category \"{c}\"; valid: {}",
                        valid.join(", ")
                    )));
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
        let f = call.name;
        self.event(|| format!("{f}: loggingOn = {on}, categories {categories:?}"));
        Ok(Status::Ok)
    }

    /// The experiment: tolerance, start and stop time (`fmi2SetupExperiment`, the arguments of
    /// `fmi3EnterInitializationMode`). A tolerance outside the integrators' range is clamped,
    /// with a warning.
    pub fn set_experiment(
        &mut self,
        call: Call,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Answer {
        let f = call.name;
        if let Some(tol) = tolerance {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(Refusal::error(format!(
                    "tolerance = {tol}: must be finite and > 0 (or toleranceDefined = {})",
                    call.words.false_
                )));
            }
        }
        if !start_time.is_finite() {
            return Err(Refusal::error(format!(
                "startTime = {start_time}: must be finite"
            )));
        }
        if let Some(stop) = stop_time {
            if !(stop.is_finite() && stop >= start_time) {
                return Err(Refusal::error(format!(
                    "stopTime = {stop}: must be finite and >= startTime = {start_time}"
                )));
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
                return Ok(Status::Warning);
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
        Ok(Status::Ok)
    }

    /// Into initialization mode.
    pub fn enter_initialization(&mut self, call: Call) -> Answer {
        self.st.state = State::InitializationMode;
        self.event(|| call.name.to_string());
        Ok(Status::Ok)
    }

    /// The experiment and into initialization mode in one call (`fmi3EnterInitializationMode`):
    /// the experiment's warning, if any, is the status.
    pub fn enter_initialization_with(
        &mut self,
        call: Call,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Answer {
        let experiment = self.set_experiment(call, tolerance, start_time, stop_time)?;
        Ok(self.enter_initialization(call)?.max(experiment))
    }

    /// Out of initialization mode: builds the simulator from the staged values.
    pub fn exit_initialization(&mut self, call: Call) -> Answer {
        if self.string.is_some() {
            let sim = self.build_string_sim().map_err(Refusal::error)?;
            if let Some(part) = self.string.as_mut() {
                part.sim = Some(sim);
                part.derivs.clear();
            }
        } else {
            let sim = self.build_sim().map_err(Refusal::error)?;
            self.sim = Some(sim);
        }
        self.provisional = None;
        self.st.derivs = [None; InputId::ALL.len()];
        self.st.state = match self.interface {
            Interface::CoSimulation => State::StepComplete,
            Interface::ModelExchange => State::EventMode,
        };
        self.event(|| {
            format!(
                "{}: simulator built at t = {} with tolerance {}",
                call.name,
                self.st.start_time,
                self.st.tolerance()
            )
        });
        Ok(Status::Ok)
    }

    pub fn terminate(&mut self, call: Call) -> Answer {
        self.st.state = State::Terminated;
        self.event(|| format!("{}: at t = {}", call.name, self.time()));
        Ok(Status::Ok)
    }

    /// Back to `Instantiated` with the scene's start values.
    pub fn reset(&mut self, call: Call) -> Answer {
        self.st = Staged::initial(&self.scene);
        self.sim = None;
        self.string = self
            .scene
            .string
            .clone()
            .map(super::string::StringPart::new);
        self.provisional = None;
        self.error_cause = None;
        self.event(|| format!("{}: start values restored", call.name));
        Ok(Status::Ok)
    }

    /// Freeing: logs it (the C layer then drops the instance).
    pub fn free(&self, call: Call) {
        self.event(|| call.name.to_string());
    }
}
