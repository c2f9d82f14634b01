//! The Model Exchange functions of an instance, in no particular FMI version: time, continuous
//! states and derivatives, event indicators, the event update and the directional derivatives.
//! The contact's side of them is `model/exchange.rs`.

use super::Instance;
use crate::description::variables::{Causality, VarKind};
use crate::fmi::refusal::{Answer, Refusal};
use crate::fmi::state::{Call, Interface, State};
use crate::fmi::status::Status;
use crate::model::{Inputs, OutputId, Simulator, StateId, StateVector};
use crate::table::number;

/// What `fmi2NewDiscreteStates` (`fmi3UpdateDiscreteStates`) reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EventInfo {
    pub values_of_continuous_states_changed: bool,
    pub next_event_time: Option<f64>,
}

impl Instance {
    /// Checks that the vector has one entry per continuous state.
    fn check_states_len(&self, arg: &str, n: usize) -> Answer<()> {
        if n != self.states.len() {
            return Err(Refusal::error(format!(
                "{arg} = {n}: this FMU has {} continuous states ({})",
                self.states.len(),
                self.state_names()
            )));
        }
        Ok(())
    }

    /// The continuous states now, `name = value`, for the messages of an out-of-domain
    /// evaluation.
    fn states_text(&self, sim: &dyn Simulator) -> String {
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
    pub(super) fn out_of_domain(&self, what: Option<String>) -> Option<Refusal> {
        let sim = self.sim.as_deref().or(self.provisional.as_deref())?;
        let why = match what {
            Some(w) => w,
            None => sim.out_of_domain()?,
        };
        Some(Refusal::discard(format!(
            "outside the model's domain at t = {}: {why}; the continuous states were {}; nothing changed: set states nearer the solution (a shorter integrator step) and evaluate again",
            self.time(),
            self.states_text(sim)
        )))
    }

    /// A value that evaluates non-finite: a discard where out of the domain, else an error.
    fn not_finite(&self, call: Call, what: String) -> Refusal {
        self.out_of_domain(Some(what.clone())).unwrap_or_else(|| {
            Refusal::error(format!(
                "{what}; restore a state with {}",
                call.words.set_state
            ))
        })
    }

    fn state_names(&self) -> String {
        self.states
            .iter()
            .map(|s| s.name())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// `fmi3GetNumberOfContinuousStates`.
    pub fn number_of_states(&self) -> usize {
        if self.string.is_some() {
            return self.string_number_of_states();
        }
        self.states.len()
    }

    /// `fmi3GetNumberOfEventIndicators`.
    pub fn number_of_event_indicators(&self) -> usize {
        if let Some(p) = &self.string {
            return p.values.sections;
        }
        self.scene().config.event_indicators()
    }

    /// The time of the continuous states (`fmi2SetTime`, `fmi3SetTime`).
    pub fn set_time(&mut self, t: f64) -> Answer {
        if self.string.is_some() {
            return self.string_set_time(t);
        }
        self.simulator("Model Exchange")?.set_time(t).map_err(|_| {
            Refusal::error(format!(
                "time = {}: must be finite and within {} averaging windows of the start time",
                number(t),
                number(crate::model::WINDOWS_MAX)
            ))
        })?;
        Ok(Status::Ok)
    }

    /// The continuous states (`fmi2SetContinuousStates`): every value is checked before any is
    /// written.
    pub fn set_continuous_states(&mut self, x: &[f64]) -> Answer {
        if self.string.is_some() {
            return self.string_set_states(x);
        }
        self.check_states_len("nx", x.len())?;
        let mut all = self.simulator("Model Exchange")?.states();
        for (id, value) in self.states.iter().zip(x) {
            all[id.index()] = *value;
        }
        self.simulator("Model Exchange")?
            .set_states(&all)
            .map_err(Refusal::error)?;
        Ok(Status::Ok)
    }

    /// Fills `out` with the present states' entries of a vector from the simulator.
    fn state_values(
        &mut self,
        call: Call,
        out: &mut [f64],
        evaluates: bool,
        of: impl Fn(&dyn Simulator) -> StateVector,
    ) -> Answer {
        self.check_states_len("nx", out.len())?;
        let values = of(self.simulator_now()?);
        if evaluates {
            if let Some(r) = self.out_of_domain(None) {
                return Err(r);
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
            return Err(self.not_finite(call, format!("{}: evaluates to {x}", id.name())));
        }
        Ok(Status::Ok)
    }

    /// `fmi2GetContinuousStates`.
    pub fn get_continuous_states(&mut self, call: Call, out: &mut [f64]) -> Answer {
        if self.string.is_some() {
            return self.string_get_states(call, out);
        }
        self.state_values(call, out, false, |s| s.states())
    }

    /// `fmi2GetDerivatives`.
    pub fn get_derivatives(&mut self, call: Call, out: &mut [f64]) -> Answer {
        if self.string.is_some() {
            return self.string_get_derivatives(call, out);
        }
        self.state_values(call, out, true, |s| s.derivatives())
    }

    /// `fmi2GetNominalsOfContinuousStates`.
    pub fn get_nominals(&mut self, call: Call, out: &mut [f64]) -> Answer {
        if self.string.is_some() {
            return self.string_get_nominals(call, out);
        }
        self.state_values(call, out, false, |s| s.nominals())
    }

    /// `fmi2GetEventIndicators`.
    pub fn get_event_indicators(&mut self, call: Call, out: &mut [f64]) -> Answer {
        if self.string.is_some() {
            return self.string_get_event_indicators(call, out);
        }
        let n = self.scene().config.event_indicators();
        if out.len() != n {
            return Err(Refusal::error(format!(
                "ni = {}: this FMU has {n} event indicators (numberOfEventIndicators)",
                out.len()
            )));
        }
        self.simulator_now()?.event_indicators(out);
        if let Some(r) = self.out_of_domain(None) {
            return Err(r);
        }
        if let Some(z) = out.iter().find(|z| !z.is_finite()) {
            return Err(self.not_finite(call, format!("an event indicator evaluates to {z}")));
        }
        Ok(Status::Ok)
    }

    /// Into event mode.
    pub fn enter_event_mode(&mut self, call: Call) -> Answer {
        self.st.state = State::EventMode;
        self.trace(|| format!("{}: t = {}", call.name, self.time()));
        Ok(Status::Ok)
    }

    /// The event update at the current time (`fmi2NewDiscreteStates`,
    /// `fmi3UpdateDiscreteStates`).
    pub fn update_events(&mut self, call: Call) -> Answer<EventInfo> {
        let info = if self.string.is_some() {
            self.string_update_events()?
        } else {
            let u = self.simulator("Model Exchange")?.update_events();
            EventInfo {
                values_of_continuous_states_changed: u.states_changed || self.st.states_changed,
                next_event_time: u.next_time,
            }
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
        Ok(info)
    }

    /// Into continuous-time mode.
    pub fn enter_continuous_time_mode(&mut self) -> Answer {
        self.st.state = State::ContinuousTimeMode;
        Ok(Status::Ok)
    }

    /// `dv_unknown = J·dv_known` with `J` the partial derivatives of the unknowns (derivatives,
    /// outputs) with respect to the knowns (states, inputs), in closed form. A Co-Simulation
    /// instance has none. A string's are by value reference of its version (`call`): FMI 3.0's
    /// arrays take one seed and give one sensitivity per element.
    pub fn get_directional_derivative(
        &mut self,
        call: Call,
        unknowns: &[u32],
        knowns: &[u32],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> Answer {
        if self.interface == Interface::CoSimulation {
            return Err(Refusal::error(
                "not supported in Co-Simulation (providesDirectionalDerivative = false there); instantiate the FMU for Model Exchange for the Jacobians",
            ));
        }
        if self.string.is_some() {
            return self
                .string_directional_derivative(call, unknowns, knowns, dv_known, dv_unknown);
        }
        if knowns.len() != dv_known.len() || unknowns.len() != dv_unknown.len() {
            return Err(Refusal::error(format!(
                "nSeed = {}, nSensitivity = {}: must equal nKnowns = {} and nUnknowns = {} (every variable is a scalar)",
                dv_known.len(),
                dv_unknown.len(),
                knowns.len(),
                unknowns.len()
            )));
        }
        let config = self.scene().config;
        let mut dx = [0.0; StateId::COUNT];
        let mut du = Inputs::default();
        for (&vr, &d) in knowns.iter().zip(dv_known) {
            let v = self
                .lookup(vr)
                .map_err(|msg| Refusal::error(format!("vKnown_ref: {msg}")))?;
            if !d.is_finite() {
                return Err(Refusal::error(format!(
                    "dvKnown for {} = {d}: must be finite",
                    v.name()
                )));
            }
            match (v.kind, v.causality(&config)) {
                (VarKind::State(x), _) => dx[x.index()] += d,
                (VarKind::Input(i), Causality::Input) => *i.slot(&mut du) += d,
                _ => {
                    return Err(Refusal::error(format!(
                        "vKnown_ref: {} (vr {vr}) is not a known: the knowns are the continuous states and the inputs",
                        v.name()
                    )))
                }
            }
        }
        let mut wanted = Vec::with_capacity(unknowns.len());
        for &vr in unknowns {
            let v = self
                .lookup(vr)
                .map_err(|msg| Refusal::error(format!("vUnknown_ref: {msg}")))?;
            match (v.kind, v.output(&config)) {
                (VarKind::Derivative(x), _) => wanted.push(Ok(x)),
                (_, Some(o)) => wanted.push(Err(o)),
                _ => {
                    return Err(Refusal::error(format!(
                        "vUnknown_ref: {} (vr {vr}) is not an unknown: the unknowns are the state derivatives and the outputs",
                        v.name()
                    )))
                }
            }
        }
        let (dder, dout) = self.simulator_now()?.tangent(&dx, &du);
        if let Some(r) = self.out_of_domain(None) {
            return Err(r);
        }
        for (w, out) in wanted.iter().zip(dv_unknown.iter_mut()) {
            *out = match w {
                Ok(x) => dder[x.index()],
                Err(o) => OutputId::get(*o, &dout),
            };
        }
        if dv_unknown.iter().any(|x| !x.is_finite()) {
            let what = "a directional derivative is not finite at this state".to_string();
            return Err(self
                .out_of_domain(Some(what.clone()))
                .unwrap_or(Refusal::Error(what)));
        }
        Ok(Status::Ok)
    }
}
