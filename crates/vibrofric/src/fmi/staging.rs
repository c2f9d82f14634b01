//! What an instance holds besides its simulator: the state machine's state, the values staged
//! before the simulator exists (its mirror afterwards) and the experiment's settings. A saved
//! state carries it whole.

use serde::{Deserialize, Serialize};

use super::state::State;
use crate::description::scene::Scene;
use crate::description::xml;
use crate::model::{InputId, Inputs};
use crate::table::{ParamId, Params};

/// Relative tolerance when the experiment defines none: the `DefaultExperiment`'s.
pub const DEFAULT_TOLERANCE: f64 = xml::DEFAULT_EXPERIMENT.2;

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Staged {
    pub state: State,
    /// Parameter values: staged before the simulator exists, its mirror afterwards.
    pub params: Params,
    /// Input values as last set (staged before the simulator exists).
    pub inputs: Inputs,
    /// First derivatives of inputs set before the simulator exists (applied when it is
    /// built), indexed like [`InputId::ALL`].
    pub derivs: [Option<f64>; InputId::ALL.len()],
    pub start_time: f64,
    /// The experiment's tolerance, when it defined one.
    pub tolerance: Option<f64>,
    pub stop_time: Option<f64>,
    /// Model Exchange: a continuous state changed in this event mode (a parameter set), to be
    /// reported by the next event update.
    pub states_changed: bool,
}

impl Staged {
    pub fn initial(scene: &Scene) -> Staged {
        Staged {
            state: State::Instantiated,
            params: scene.start,
            inputs: scene.inputs,
            derivs: [None; InputId::ALL.len()],
            start_time: xml::DEFAULT_EXPERIMENT.0,
            tolerance: None,
            stop_time: None,
            states_changed: false,
        }
    }

    pub fn tolerance(&self) -> f64 {
        self.tolerance.unwrap_or(DEFAULT_TOLERANCE)
    }
}

/// One validated assignment of a set call, applied once every value of the call is checked.
#[derive(Clone, Copy)]
pub(crate) enum Assign {
    Param(ParamId, f64),
    Input(InputId, f64),
}
