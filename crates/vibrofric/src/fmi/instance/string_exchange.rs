//! The Model Exchange functions of a string scene's instance: the state vector `[x_1 … x_N,
//! v_1 … v_N, s_1 … s_N, x_top, x_bottom]`, its derivatives and nominals, an event indicator per
//! section, the event update and the directional derivatives by value reference (FMI 2.0: an
//! element each; FMI 3.0: an array's value reference takes all of its elements). The string's
//! side of them is `model/string/exchange.rs`.

use super::model_exchange::EventInfo;
use super::Instance;
use crate::fmi::refusal::{Answer, Refusal};
use crate::fmi::state::Call;
use crate::fmi::status::Status;
use crate::model::string::PER_SECTION;
use crate::model::string::{state_name, InputDirection, StringSimulator};
use crate::table::{number, Role, StringVar};

/// What the elements of a known or an unknown of a directional derivative are.
enum Slot {
    State(usize),
    Input(StringVar, usize),
    Output(StringVar, usize),
}

impl Instance {
    fn sections(&self) -> usize {
        self.string.as_ref().map_or(0, |p| p.values.sections)
    }

    /// `3N + 2` continuous states.
    pub(super) fn string_number_of_states(&self) -> usize {
        PER_SECTION * self.sections() + 2
    }

    fn string_sim(&mut self) -> Answer<&mut Box<dyn StringSimulator>> {
        self.string
            .as_mut()
            .and_then(|p| p.sim.as_mut())
            .ok_or_else(|| Refusal::Internal("no string simulator in Model Exchange".into()))
    }

    fn check_string_len(&self, arg: &str, len: usize, want: usize, what: &str) -> Answer<()> {
        if len != want {
            let n = self.sections();
            return Err(Refusal::error(format!(
                "{arg} = {len}: this FMU, a string of {n} sections, has {want} {what}"
            )));
        }
        Ok(())
    }

    /// A discard where the states are outside the model's domain.
    fn string_domain(&mut self) -> Answer<()> {
        let t = self.time();
        match self.string_sim()?.out_of_domain() {
            Some(why) => Err(Refusal::discard(format!(
                "outside the model's domain at t = {}: {why}; nothing changed: set states nearer the solution (a shorter integrator step) and evaluate again",
                number(t)
            ))),
            None => Ok(()),
        }
    }

    pub(super) fn string_set_time(&mut self, t: f64) -> Answer {
        self.string_sim()?
            .set_exchange_time(t)
            .map_err(|_| Refusal::error(format!("time = {}: must be finite", number(t))))?;
        Ok(Status::Ok)
    }

    pub(super) fn string_set_states(&mut self, x: &[f64]) -> Answer {
        let want = self.string_number_of_states();
        self.check_string_len("nx", x.len(), want, "continuous states")?;
        self.string_sim()?
            .set_exchange_states(x)
            .map_err(Refusal::error)?;
        Ok(Status::Ok)
    }

    /// A vector of the states' length from the string (`what` of each state); `evaluates`
    /// checks the domain first.
    fn string_vector(
        &mut self,
        call: Call,
        out: &mut [f64],
        (evaluates, what): (bool, &str),
        of: impl Fn(&dyn StringSimulator) -> Vec<f64>,
    ) -> Answer {
        let want = self.string_number_of_states();
        self.check_string_len("nx", out.len(), want, "continuous states")?;
        if evaluates {
            self.string_domain()?;
        }
        let n = self.sections();
        let values = of(self.string_sim()?.as_ref());
        out.copy_from_slice(&values);
        if let Some((k, x)) = out.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(Refusal::error(format!(
                "{what}{} evaluates to {x}; restore a state with {}",
                state_name(n, k),
                call.words.set_state
            )));
        }
        Ok(Status::Ok)
    }

    pub(super) fn string_get_states(&mut self, call: Call, out: &mut [f64]) -> Answer {
        self.string_vector(call, out, (false, ""), |s| s.exchange_states())
    }

    pub(super) fn string_get_derivatives(&mut self, call: Call, out: &mut [f64]) -> Answer {
        self.string_vector(call, out, (true, "the derivative of "), |s| {
            s.exchange_derivatives()
        })
    }

    pub(super) fn string_get_nominals(&mut self, call: Call, out: &mut [f64]) -> Answer {
        self.string_vector(call, out, (false, "the nominal of "), |s| {
            s.exchange_nominals()
        })
    }

    pub(super) fn string_get_event_indicators(&mut self, call: Call, out: &mut [f64]) -> Answer {
        let n = self.sections();
        self.check_string_len("ni", out.len(), n, "event indicators (one per section)")?;
        self.string_domain()?;
        out.copy_from_slice(&self.string_sim()?.event_indicators());
        if let Some(z) = out.iter().find(|z| !z.is_finite()) {
            return Err(Refusal::error(format!(
                "an event indicator evaluates to {z}; restore a state with {}",
                call.words.set_state
            )));
        }
        Ok(Status::Ok)
    }

    pub(super) fn string_update_events(&mut self) -> Answer<EventInfo> {
        self.string_sim()?.update_events();
        let info = EventInfo {
            values_of_continuous_states_changed: self.st.states_changed,
            next_event_time: None,
        };
        self.st.states_changed = false;
        Ok(info)
    }

    /// What the elements `from..to` of the variable of `vr` are to a directional derivative.
    fn slots(&self, call: Call, vr: u32, known: bool) -> Answer<Vec<Slot>> {
        let (arg, what) = match known {
            true => (
                "vKnown_ref",
                "not a known: the knowns are the continuous states and the inputs",
            ),
            false => (
                "vUnknown_ref",
                "not an unknown: the unknowns are the state derivatives and the outputs",
            ),
        };
        let n = self.sections();
        let c = self.scene.config;
        let (var, from, to) = match self.target(call.words.time_vr, vr)? {
            super::string::Target::Elements(var, from, to) => (var, from, to),
            _ => return Err(Refusal::error(format!("{arg}: vr {vr} is {what}"))),
        };
        (from..to)
            .map(|i| {
                let state = var.state_index(n, i);
                match (known, var.role(&c), var.derivative_of(), state) {
                    (true, _, None, Some(k)) => Ok(Slot::State(k)),
                    (true, Role::Input, ..) => Ok(Slot::Input(var, i)),
                    (false, _, Some(_), Some(k)) => Ok(Slot::State(k)),
                    (false, Role::Output, ..) => Ok(Slot::Output(var, i)),
                    _ => Err(Refusal::error(format!(
                        "{arg}: {} (vr {vr}) is {what}",
                        var.element_name(i)
                    ))),
                }
            })
            .collect()
    }

    /// `dv_unknown = J·dv_known` of a string, exact: the string's banded Jacobian with the ends
    /// and inputs ([`crate::model::string::StringExchange::tangent`]).
    pub(super) fn string_directional_derivative(
        &mut self,
        call: Call,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Answer {
        let n = self.sections();
        let c = self.scene.config;
        let mut dx = vec![0.0; self.string_number_of_states()];
        let mut du = InputDirection::zero(n, c.normal_input);
        let known: Vec<Slot> = knowns
            .iter()
            .map(|&vr| self.slots(call, vr, true))
            .collect::<Answer<Vec<_>>>()?
            .into_iter()
            .flatten()
            .collect();
        let unknown: Vec<Slot> = unknowns
            .iter()
            .map(|&vr| self.slots(call, vr, false))
            .collect::<Answer<Vec<_>>>()?
            .into_iter()
            .flatten()
            .collect();
        if known.len() != seed.len() || unknown.len() != sensitivity.len() {
            return Err(Refusal::error(format!(
                "{} seeds and {} sensitivities given: the knowns hold {} values and the unknowns {} (an array's value reference holds all of its elements)",
                seed.len(),
                sensitivity.len(),
                known.len(),
                unknown.len()
            )));
        }
        for (slot, &d) in known.iter().zip(seed) {
            if !d.is_finite() {
                return Err(Refusal::error(format!("a seed = {d}: must be finite")));
            }
            match *slot {
                Slot::State(k) => dx[k] += d,
                Slot::Input(StringVar::FD, i) => du.f_d[i] += d,
                Slot::Input(StringVar::VSx, i) => du.v_sx[i] += d,
                Slot::Input(StringVar::FN, i) => du.f_n[i] += d,
                Slot::Input(StringVar::VTop, _) => du.v_top += d,
                Slot::Input(..) => du.v_bottom += d,
                Slot::Output(..) => {}
            }
        }
        self.string_domain()?;
        let (dder, dout) = self.string_sim()?.tangent(&dx, &du);
        for (slot, out) in unknown.iter().zip(sensitivity.iter_mut()) {
            *out = match *slot {
                Slot::State(k) => dder[k],
                Slot::Output(var, i) => dout.values(var)[i],
                Slot::Input(..) => 0.0,
            };
        }
        if sensitivity.iter().any(|x| !x.is_finite()) {
            return Err(Refusal::error(
                "a directional derivative is not finite at this state",
            ));
        }
        Ok(Status::Ok)
    }
}
