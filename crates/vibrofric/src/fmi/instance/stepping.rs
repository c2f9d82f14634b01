//! Co-Simulation's steps: the instance integrates exactly to the end of each communication
//! step, synchronously.

use super::Instance;
use crate::fmi::refusal::{Answer, Refusal};
use crate::fmi::state::Call;
use crate::fmi::status::Status;
use crate::model::SimError;

impl Instance {
    /// One communication step (`fmi2DoStep`, `fmi3DoStep`): integrates exactly to
    /// `current + step`. When the integrator cannot get there, the instance stays at the
    /// step's start in `StepFailed` and the status is a discard.
    pub fn step(&mut self, call: Call, current: f64, step: f64) -> Answer {
        let t = self.time();
        if !current.is_finite() {
            return Err(Refusal::error(format!(
                "currentCommunicationPoint = {current}: must be finite"
            )));
        }
        if !(step.is_finite() && step > 0.0) {
            return Err(Refusal::error(format!(
                "communicationStepSize = {step}: must be finite and > 0"
            )));
        }
        // Masters accumulate time with rounding: allow a relative 1e-9.
        if (current - t).abs() > 1e-9 * t.abs().max(1.0) {
            return Err(Refusal::error(format!(
                "currentCommunicationPoint = {current} is not the instance's time {t}: a step starts where the previous one ended"
            )));
        }
        let target = current + step;
        if let Some(stop) = self.st.stop_time {
            if target > stop + 1e-9 * stop.abs().max(1.0) {
                return Err(Refusal::error(format!(
                    "currentCommunicationPoint + communicationStepSize = {target} is past stopTime = {stop} of {}",
                    call.words.setup_experiment
                )));
            }
        }
        let stepped = match self.string.as_mut().and_then(|p| p.sim.as_mut()) {
            Some(sim) => sim.step_to(target),
            None => self.simulator("state StepComplete")?.step_to(target),
        };
        match stepped {
            Ok(()) => {
                self.trace(|| format!("{}: t = {current} -> {target}", call.name));
                Ok(Status::Ok)
            }
            Err(SimError::Solver(e)) => Err(Refusal::StepFailed(format!(
                "the integrator could not reach t = {target} from t = {t} ({e}); the instance stays at t = {t} ({}); restore a state with {} to retry with a shorter step",
                call.words.last_successful_time, call.words.set_state
            ))),
            Err(e) => Err(Refusal::error(e)),
        }
    }

    /// `fmi2CancelStep`: steps are synchronous, so there is never one to cancel.
    pub fn cancel_step(&mut self) -> Answer {
        Err(Refusal::error(format!(
            "only allowed while fmi2DoStep is pending; this FMU completes every step before fmi2DoStep returns (state {}); illegal call sequence",
            self.st.state.name()
        )))
    }
}
