//! Saved states: save, restore, and the bytes of a state (`saved.rs` is their format). A state
//! restores only into an instance of the FMU, the standard's edition and the interface that
//! saved it, and continues exactly as the instance it was taken from.

use super::Instance;
use crate::fmi::refusal::{Answer, Refusal};
use crate::fmi::saved::{self, FmuState};
use crate::fmi::state::{Call, Interface};
use crate::fmi::status::Status;
use crate::model::{self, Simulator};

impl Instance {
    /// The instance's state now (`fmi2GetFMUstate`, `fmi3GetFMUState`).
    pub fn save_state(&self, call: Call) -> FmuState {
        let s = FmuState {
            guid: self.guid.clone(),
            interface: self.interface,
            edition: call.words.edition.to_string(),
            staged: self.st,
            sim: self.sim.as_ref().map(|s| s.snapshot()),
            string: self.string.as_ref().map(|p| p.saved()),
        };
        self.event(|| {
            format!(
                "{}: saved state {} at t = {}",
                call.name,
                self.st.state.name(),
                self.time()
            )
        });
        s
    }

    /// Builds the simulator a state holds; nothing is changed.
    fn simulator_of(&self, call: Call, s: &FmuState) -> Answer<Option<Box<dyn Simulator>>> {
        if s.guid != self.guid {
            return Err(Refusal::error(format!(
                "the state belongs to the FMU with GUID {}, this instance is {}",
                s.guid, self.guid
            )));
        }
        if s.interface != self.interface || s.edition != call.words.edition {
            return Err(Refusal::error(format!(
                "the state was saved by an {} {} instance and this instance is {} {}: a state restores only into an instance of the interface and edition that saved it (their state machines differ)",
                s.edition,
                s.interface.name(),
                call.words.edition,
                self.interface.name()
            )));
        }
        let Some(snap) = &s.sim else {
            return Ok(None);
        };
        let mut sim = model::Setup::new(self.scene.config, s.staged.params)
            .start(s.staged.start_time)
            .tolerance(s.staged.tolerance())
            .build()
            .map_err(Refusal::error)?;
        match s.interface {
            Interface::CoSimulation => sim.restore(snap),
            Interface::ModelExchange => sim.restore_exchange(snap),
        }
        .map_err(Refusal::error)?;
        Ok(Some(sim))
    }

    /// Restores a saved state (`fmi2SetFMUstate`, `fmi3SetFMUState`).
    pub fn restore_state(&mut self, call: Call, s: &FmuState) -> Answer {
        let sim = self.simulator_of(call, s)?;
        self.string = self.string_part_of(s)?;
        self.sim = sim;
        self.st = s.staged;
        self.provisional = None;
        self.error_cause = None;
        self.event(|| {
            format!(
                "{}: restored state {} at t = {}",
                call.name,
                self.st.state.name(),
                self.time()
            )
        });
        Ok(Status::Ok)
    }

    /// The string's part of a state, checked and built (`None` for a single contact).
    fn string_part_of(&self, s: &FmuState) -> Answer<Option<super::string::StringPart>> {
        match (&self.string, &s.string) {
            (None, None) => Ok(None),
            (Some(_), Some(saved)) => self.string_of(&s.staged, saved).map(Some),
            _ => Err(Refusal::error(
                "the state and this instance disagree on being a string of contacts",
            )),
        }
    }

    /// The bytes of a state.
    pub fn serialize_state(&self, s: &FmuState) -> Vec<u8> {
        saved::encode(s)
    }

    /// A state from its bytes: everything checked, including that the simulator restores.
    pub fn deserialize_state(&self, call: Call, bytes: &[u8]) -> Answer<FmuState> {
        let s = saved::decode(bytes).map_err(Refusal::error)?;
        self.simulator_of(call, &s)?;
        self.string_part_of(&s)?;
        Ok(s)
    }
}
