//! The Model Exchange functions of an instance, in no particular FMI version: time, continuous
//! states and derivatives, event indicators, the event update and the directional derivatives.
//! The contact's side of them is `model/exchange.rs`; each version's C layer turns pointers into
//! slices and calls these with a [`Call`].

use super::instance::Instance;
use super::state::{Call, Interface, State};
use super::status::Status;
use crate::description::variables::{Causality, VarKind};
use crate::model::{Inputs, OutputId, StateId, StateVector};
use crate::physics::ParamId;
use crate::table::number;

/// What `fmi2NewDiscreteStates` (`fmi3UpdateDiscreteStates`) reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EventInfo {
    pub values_of_continuous_states_changed: bool,
    pub next_event_time: Option<f64>,
}

impl Instance {
    /// Checks the call's state and that the vector has one entry per continuous state.
    fn check_states_len(&mut self, call: Call, arg: &str, n: usize) -> Result<(), Status> {
        self.allow(call)?;
        if n != self.states.len() {
            return Err(self.fail(
                call.name,
                format!(
                    "{arg} = {n}: this FMU has {} continuous states ({})",
                    self.states.len(),
                    self.state_names()
                ),
            ));
        }
        Ok(())
    }

    /// The continuous states now, `name = value`, for the messages of an out-of-domain
    /// evaluation.
    fn states_text(&self, sim: &dyn crate::model::Simulator) -> String {
        let x = sim.states();
        self.states
            .iter()
            .map(|id| format!("{} = {}", id.name(), number(x[id.index()])))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Model Exchange: an evaluation outside the model's domain (states far from any
    /// trajectory, or a value that evaluates non-finite) is a discard, so that the importer's
    /// integrator can retry with a shorter step; the instance stays in its state. `what`
    /// names what is out of domain; `None` checks the states' domain.
    pub(super) fn out_of_domain(&mut self, call: Call, what: Option<String>) -> Option<Status> {
        let (why, states) = {
            let sim = self.sim.as_deref().or(self.provisional.as_deref())?;
            let why = match what {
                Some(w) => w,
                None => sim.out_of_domain()?,
            };
            (why, self.states_text(sim))
        };
        Some(self.discard(
            call.name,
            format!(
                "outside the model's domain at t = {}: {why}; the continuous states were {states}; nothing changed: set states nearer the solution (a shorter integrator step) and evaluate again",
                self.time()
            ),
        ))
    }

    fn state_names(&self) -> String {
        self.states
            .iter()
            .map(|s| s.name())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// `fmi3GetNumberOfContinuousStates`.
    pub fn number_of_states(&mut self, call: Call) -> Result<usize, Status> {
        self.allow(call)?;
        Ok(self.states.len())
    }

    /// `fmi3GetNumberOfEventIndicators`.
    pub fn number_of_event_indicators(&mut self, call: Call) -> Result<usize, Status> {
        self.allow(call)?;
        Ok(self.scene().config.event_indicators())
    }

    /// `fmi2SetTime`.
    pub fn set_time(&mut self, call: Call, t: f64) -> Status {
        if let Err(s) = self.allow(call) {
            return s;
        }
        let Some(sim) = self.sim.as_mut() else {
            return self.internal_error(call, "no simulator in Model Exchange");
        };
        match sim.set_time(t) {
            Ok(()) => Status::Ok,
            Err(_) => self.fail(
                call.name,
                format!(
                    "time = {}: must be finite and within {} averaging windows of the start time",
                    number(t),
                    number(crate::model::WINDOWS_MAX)
                ),
            ),
        }
    }

    /// `fmi2SetContinuousStates`: every value is checked before any is written.
    pub fn set_continuous_states(&mut self, call: Call, x: &[f64]) -> Status {
        if let Err(s) = self.check_states_len(call, "nx", x.len()) {
            return s;
        }
        let Some(sim) = self.sim.as_mut() else {
            return self.internal_error(call, "no simulator in Model Exchange");
        };
        let mut all = sim.states();
        for (id, value) in self.states.iter().zip(x) {
            all[id.index()] = *value;
        }
        match sim.set_states(&all) {
            Ok(()) => Status::Ok,
            Err(e) => self.fail(call.name, e),
        }
    }

    /// Fills `out` with the present states' entries of a vector from the simulator.
    fn state_values(
        &mut self,
        call: Call,
        arg: &str,
        out: &mut [f64],
        evaluates: bool,
        of: impl Fn(&dyn crate::model::Simulator) -> StateVector,
    ) -> Status {
        if let Err(s) = self.check_states_len(call, arg, out.len()) {
            return s;
        }
        let values = match self.simulator_now() {
            Ok(sim) => of(sim),
            Err(e) => return self.fail(call.name, e),
        };
        if evaluates {
            if let Some(s) = self.out_of_domain(call, None) {
                return s;
            }
        }
        for (id, o) in self.states.iter().zip(out.iter_mut()) {
            *o = values[id.index()];
        }
        if let Some((id, x)) = self
            .states
            .iter()
            .zip(out.iter())
            .find(|(_, x)| !x.is_finite())
        {
            let (name, x) = (id.name(), *x);
            let what = format!("{name}: evaluates to {x}");
            if let Some(s) = self.out_of_domain(call, Some(what.clone())) {
                return s;
            }
            return self.fail(
                call.name,
                format!("{what}; restore a state with {}", call.words.set_state),
            );
        }
        Status::Ok
    }

    /// `fmi2GetContinuousStates`.
    pub fn get_continuous_states(&mut self, call: Call, out: &mut [f64]) -> Status {
        self.state_values(call, "nx", out, false, |s| s.states())
    }

    /// `fmi2GetDerivatives`.
    pub fn get_derivatives(&mut self, call: Call, out: &mut [f64]) -> Status {
        self.state_values(call, "nx", out, true, |s| s.derivatives())
    }

    /// `fmi2GetNominalsOfContinuousStates`.
    pub fn get_nominals(&mut self, call: Call, out: &mut [f64]) -> Status {
        self.state_values(call, "nx", out, false, |s| s.nominals())
    }

    /// `fmi2GetEventIndicators`.
    pub fn get_event_indicators(&mut self, call: Call, out: &mut [f64]) -> Status {
        if let Err(s) = self.allow(call) {
            return s;
        }
        let n = self.scene().config.event_indicators();
        if out.len() != n {
            return self.fail(
                call.name,
                format!(
                    "ni = {}: this FMU has {n} event indicators (numberOfEventIndicators)",
                    out.len()
                ),
            );
        }
        match self.simulator_now() {
            Ok(sim) => sim.event_indicators(out),
            Err(e) => return self.fail(call.name, e),
        }
        if let Some(s) = self.out_of_domain(call, None) {
            return s;
        }
        if let Some(z) = out.iter().find(|z| !z.is_finite()) {
            let what = format!("an event indicator evaluates to {z}");
            if let Some(s) = self.out_of_domain(call, Some(what)) {
                return s;
            }
            return self.fail(
                call.name,
                format!(
                    "an event indicator evaluates to {z}; restore a state with {}",
                    call.words.set_state
                ),
            );
        }
        Status::Ok
    }

    /// `fmi2EnterEventMode`.
    pub fn enter_event_mode(&mut self, call: Call) -> Status {
        if let Err(s) = self.allow(call) {
            return s;
        }
        self.st.state = State::EventMode;
        self.trace(|| format!("{}: t = {}", call.name, self.time()));
        Status::Ok
    }

    /// `fmi2NewDiscreteStates`: the event update at the current time.
    pub fn new_discrete_states(&mut self, call: Call) -> (Status, EventInfo) {
        if let Err(s) = self.allow(call) {
            return (s, EventInfo::default());
        }
        let Some(sim) = self.sim.as_mut() else {
            return (
                self.internal_error(call, "no simulator in Model Exchange"),
                EventInfo::default(),
            );
        };
        let u = sim.update_events();
        let info = EventInfo {
            values_of_continuous_states_changed: u.states_changed || self.st.states_changed,
            next_event_time: u.next_time,
        };
        self.st.states_changed = false;
        self.event(|| {
            format!(
                "{}: t = {}, states changed {}, next time event {:?}",
                call.name,
                self.time(),
                info.values_of_continuous_states_changed,
                info.next_event_time
            )
        });
        (Status::Ok, info)
    }

    /// `fmi2EnterContinuousTimeMode`.
    pub fn enter_continuous_time_mode(&mut self, call: Call) -> Status {
        if let Err(s) = self.allow(call) {
            return s;
        }
        self.st.state = State::ContinuousTimeMode;
        Status::Ok
    }

    /// `fmi2CompletedIntegratorStep`: nothing to do (no step events); never asks for an event
    /// or to terminate.
    pub fn completed_integrator_step(&mut self, call: Call) -> Status {
        match self.allow(call) {
            Ok(()) => Status::Ok,
            Err(s) => s,
        }
    }

    /// `fmi2GetDirectionalDerivative`: `dv_unknown = J·dv_known` with `J` the partial
    /// derivatives of the unknowns (derivatives, outputs) with respect to the knowns (states,
    /// inputs), in closed form.
    pub fn get_directional_derivative(
        &mut self,
        call: Call,
        unknowns: &[u32],
        knowns: &[u32],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> Status {
        let f = call.name;
        if let Err(s) = self.allow(call) {
            return s;
        }
        if self.interface == Interface::CoSimulation {
            return self.no_directional_derivative(call);
        }
        let config = self.scene().config;
        let mut dx = [0.0; StateId::COUNT];
        let mut du = Inputs::default();
        for (&vr, &d) in knowns.iter().zip(dv_known) {
            let v = match self.lookup(vr) {
                Ok(v) => v,
                Err(msg) => return self.fail(f, format!("vKnown_ref: {msg}")),
            };
            if !d.is_finite() {
                return self.fail(f, format!("dvKnown for {} = {d}: must be finite", v.name()));
            }
            match (v.kind, v.causality(&config)) {
                (VarKind::State(x), _) => dx[x.index()] += d,
                (VarKind::Input(i), Causality::Input) => *i.slot(&mut du) += d,
                (VarKind::Param(ParamId::FN), Causality::Input) => du.f_n += d,
                _ => {
                    return self.fail(
                        f,
                        format!(
                            "vKnown_ref: {} (vr {vr}) is not a known: the knowns are the continuous states and the inputs",
                            v.name()
                        ),
                    )
                }
            }
        }
        let mut wanted = Vec::with_capacity(unknowns.len());
        for &vr in unknowns {
            let v = match self.lookup(vr) {
                Ok(v) => v,
                Err(msg) => return self.fail(f, format!("vUnknown_ref: {msg}")),
            };
            match (v.kind, v.output(&config)) {
                (VarKind::Derivative(x), _) => wanted.push(Ok(x)),
                (_, Some(o)) => wanted.push(Err(o)),
                _ => {
                    return self.fail(
                        f,
                        format!(
                            "vUnknown_ref: {} (vr {vr}) is not an unknown: the unknowns are the state derivatives and the outputs",
                            v.name()
                        ),
                    )
                }
            }
        }
        let (dder, dout) = match self.simulator_now() {
            Ok(sim) => sim.tangent(&dx, &du),
            Err(e) => return self.fail(f, e),
        };
        if let Some(s) = self.out_of_domain(call, None) {
            return s;
        }
        for (w, out) in wanted.iter().zip(dv_unknown.iter_mut()) {
            *out = match w {
                Ok(x) => dder[x.index()],
                Err(o) => OutputId::get(*o, &dout),
            };
        }
        if dv_unknown.iter().any(|x| !x.is_finite()) {
            let what = "a directional derivative is not finite at this state".to_string();
            if let Some(s) = self.out_of_domain(call, Some(what)) {
                return s;
            }
            return self.fail(
                f,
                "a directional derivative is not finite at this state".to_string(),
            );
        }
        Status::Ok
    }
}
