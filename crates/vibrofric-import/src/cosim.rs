//! What FMI 2.0 and FMI 3.0 Co-Simulation have in common, as two traits: [`Importer`] over a
//! loaded FMU ([`crate::Fmu`], [`crate::fmi3::Fmu3`]) and [`CoSimulation`] over one of its
//! instances. Code that drives an FMU the same way in both editions ([`Importer::simulate`],
//! the tests' fuzz campaigns) is written once against them; what only one edition has
//! (Model Exchange, input derivatives, the status queries) stays on the concrete types.

use std::path::Path;

use crate::{Description, ImportError, Status};

/// A loaded FMU of one FMI edition.
pub trait Importer: Sized {
    /// An instance, borrowing the FMU (whose library must outlive it).
    type Instance<'a>: CoSimulation
    where
        Self: 'a;

    /// Loads an unpacked FMU folder or a `.fmu` archive of this edition.
    fn load(path: &Path) -> Result<Self, ImportError>;

    /// What the importer read from `modelDescription.xml`.
    fn description(&self) -> &Description;

    /// A Co-Simulation instance with the FMU's token and resources.
    fn instantiate(&self, name: &str) -> Result<Self::Instance<'_>, ImportError>;

    /// Runs from 0 to `stop` in steps of `step` (the last one shortened to end on `stop`) with
    /// `inputs` (value reference, value) set in initialization mode, and returns rows
    /// `[t, outputs...]` of the value references `outputs`, at the start and after every step;
    /// then terminates. Both editions take the same points and steps, so that they compare.
    fn simulate(
        &self,
        stop: f64,
        step: f64,
        inputs: &[(u32, f64)],
        outputs: &[u32],
    ) -> Result<Vec<Vec<f64>>, ImportError> {
        let mut inst = self.instantiate("simulate")?;
        fn refused<I: CoSimulation>(inst: &I, s: Status, what: &str) -> ImportError {
            ImportError(format!(
                "{what} returned {}: {}",
                I::status_name(s),
                inst.last_message()
            ))
        }
        fn check<I: CoSimulation>(inst: &I, s: Status, what: &str) -> Result<(), ImportError> {
            if s <= Status::Warning {
                Ok(())
            } else {
                Err(refused(inst, s, what))
            }
        }
        fn names<I: CoSimulation>(_: &I) -> [&'static str; 6] {
            I::NAMES
        }
        let [enter, set, exit, get, do_step, terminate] = names(&inst);
        let s = inst.enter_initialization(None, 0.0, Some(stop));
        check(&inst, s, enter)?;
        let (vrs, vals): (Vec<u32>, Vec<f64>) = inputs.iter().copied().unzip();
        let s = inst.set_f64(&vrs, &vals);
        check(&inst, s, set)?;
        let s = inst.exit_initialization_mode();
        check(&inst, s, exit)?;
        let mut rows = Vec::new();
        let mut t = 0.0;
        let n = (stop / step).round().max(1.0) as u64;
        for k in 0..=n {
            let y = inst.get_f64(outputs).map_err(|s| refused(&inst, s, get))?;
            let mut row = vec![t];
            row.extend(y);
            rows.push(row);
            if k == n {
                break;
            }
            let h = if k + 1 == n { stop - t } else { step };
            let s = inst.do_step(t, h);
            check(&inst, s, do_step)?;
            t = if k + 1 == n { stop } else { t + h };
        }
        let s = inst.terminate();
        check(&inst, s, terminate)?;
        Ok(rows)
    }
}

/// One Co-Simulation instance of either edition; freed when dropped. Each call returns the
/// edition's status (FMI 2.0's and 3.0's codes are the same four plus fatal).
pub trait CoSimulation {
    /// A saved FMU state, to be freed with [`CoSimulation::free_state`].
    type State;

    /// The C names of the functions behind [`CoSimulation::enter_initialization`],
    /// [`CoSimulation::set_f64`], [`CoSimulation::exit_initialization_mode`],
    /// [`CoSimulation::get_f64`], [`CoSimulation::do_step`] and [`CoSimulation::terminate`],
    /// for messages.
    const NAMES: [&'static str; 6];

    /// The status as the edition's headers name it.
    fn status_name(s: Status) -> String;

    /// The text of the last message the instance logged, or "" when none.
    fn last_message(&self) -> String;

    /// Enters initialization mode with the experiment's tolerance, start and stop time (FMI
    /// 2.0: `fmi2SetupExperiment`, then `fmi2EnterInitializationMode` if that was accepted).
    fn enter_initialization(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Status;

    fn exit_initialization_mode(&mut self) -> Status;

    /// Sets `Float64` (FMI 2.0: `Real`) values; one value per reference.
    fn set_f64(&mut self, vrs: &[u32], values: &[f64]) -> Status;

    /// Reads `Float64` (FMI 2.0: `Real`) values; the status when refused.
    fn get_f64(&mut self, vrs: &[u32]) -> Result<Vec<f64>, Status>;

    /// One communication step from `current` by `step`.
    fn do_step(&mut self, current: f64, step: f64) -> Status;

    fn terminate(&mut self) -> Status;

    fn reset(&mut self) -> Status;

    /// Saves the FMU state into a new state.
    fn get_state(&mut self) -> Result<Self::State, Status>;

    fn set_state(&mut self, state: &Self::State) -> Status;

    fn free_state(&mut self, state: Self::State) -> Status;

    fn serialize_state(&mut self, state: &Self::State) -> Result<Vec<u8>, Status>;

    /// Deserializes into a new state.
    fn deserialize_state(&mut self, bytes: &[u8]) -> Result<Self::State, Status>;
}

impl Importer for crate::Fmu {
    type Instance<'a> = crate::Instance<'a>;

    fn load(path: &Path) -> Result<Self, ImportError> {
        crate::Fmu::load(path)
    }

    fn description(&self) -> &Description {
        &self.description
    }

    fn instantiate(&self, name: &str) -> Result<Self::Instance<'_>, ImportError> {
        crate::Fmu::instantiate(self, name)
    }
}

impl CoSimulation for crate::Instance<'_> {
    type State = crate::State;

    const NAMES: [&'static str; 6] = [
        "fmi2SetupExperiment/fmi2EnterInitializationMode",
        "fmi2SetReal",
        "fmi2ExitInitializationMode",
        "fmi2GetReal",
        "fmi2DoStep",
        "fmi2Terminate",
    ];

    fn status_name(s: Status) -> String {
        vibrofric::fmi::fmi2::status_name(s).to_string()
    }

    fn last_message(&self) -> String {
        crate::Instance::last_message(self)
    }

    fn enter_initialization(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Status {
        let s = self.setup_experiment(tolerance, start, stop);
        if s > Status::Warning {
            return s;
        }
        self.enter_initialization_mode()
    }

    fn exit_initialization_mode(&mut self) -> Status {
        crate::Instance::exit_initialization_mode(self)
    }

    fn set_f64(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        self.set_real(vrs, values)
    }

    fn get_f64(&mut self, vrs: &[u32]) -> Result<Vec<f64>, Status> {
        self.get_real(vrs)
    }

    fn do_step(&mut self, current: f64, step: f64) -> Status {
        crate::Instance::do_step(self, current, step)
    }

    fn terminate(&mut self) -> Status {
        crate::Instance::terminate(self)
    }

    fn reset(&mut self) -> Status {
        crate::Instance::reset(self)
    }

    fn get_state(&mut self) -> Result<Self::State, Status> {
        crate::Instance::get_state(self)
    }

    fn set_state(&mut self, state: &Self::State) -> Status {
        crate::Instance::set_state(self, state)
    }

    fn free_state(&mut self, state: Self::State) -> Status {
        crate::Instance::free_state(self, state)
    }

    fn serialize_state(&mut self, state: &Self::State) -> Result<Vec<u8>, Status> {
        crate::Instance::serialize_state(self, state)
    }

    fn deserialize_state(&mut self, bytes: &[u8]) -> Result<Self::State, Status> {
        crate::Instance::deserialize_state(self, bytes)
    }
}

impl Importer for crate::fmi3::Fmu3 {
    type Instance<'a> = crate::fmi3::Instance3<'a>;

    fn load(path: &Path) -> Result<Self, ImportError> {
        crate::fmi3::Fmu3::load(path)
    }

    fn description(&self) -> &Description {
        &self.description
    }

    fn instantiate(&self, name: &str) -> Result<Self::Instance<'_>, ImportError> {
        crate::fmi3::Fmu3::instantiate(self, name)
    }
}

impl CoSimulation for crate::fmi3::Instance3<'_> {
    type State = crate::fmi3::State3;

    const NAMES: [&'static str; 6] = [
        "fmi3EnterInitializationMode",
        "fmi3SetFloat64",
        "fmi3ExitInitializationMode",
        "fmi3GetFloat64",
        "fmi3DoStep",
        "fmi3Terminate",
    ];

    fn status_name(s: Status) -> String {
        format!("{s:?}")
    }

    fn last_message(&self) -> String {
        crate::fmi3::Instance3::last_message(self)
    }

    fn enter_initialization(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Status {
        self.enter_initialization_mode(tolerance, start, stop)
    }

    fn exit_initialization_mode(&mut self) -> Status {
        crate::fmi3::Instance3::exit_initialization_mode(self)
    }

    fn set_f64(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        crate::fmi3::Instance3::set_f64(self, vrs, values)
    }

    fn get_f64(&mut self, vrs: &[u32]) -> Result<Vec<f64>, Status> {
        crate::fmi3::Instance3::get_f64(self, vrs)
    }

    fn do_step(&mut self, current: f64, step: f64) -> Status {
        crate::fmi3::Instance3::do_step(self, current, step).0
    }

    fn terminate(&mut self) -> Status {
        crate::fmi3::Instance3::terminate(self)
    }

    fn reset(&mut self) -> Status {
        crate::fmi3::Instance3::reset(self)
    }

    fn get_state(&mut self) -> Result<Self::State, Status> {
        crate::fmi3::Instance3::get_state(self)
    }

    fn set_state(&mut self, state: &Self::State) -> Status {
        crate::fmi3::Instance3::set_state(self, state)
    }

    fn free_state(&mut self, state: Self::State) -> Status {
        crate::fmi3::Instance3::free_state(self, state)
    }

    fn serialize_state(&mut self, state: &Self::State) -> Result<Vec<u8>, Status> {
        crate::fmi3::Instance3::serialize_state(self, state)
    }

    fn deserialize_state(&mut self, bytes: &[u8]) -> Result<Self::State, Status> {
        crate::fmi3::Instance3::deserialize_state(self, bytes)
    }
}
