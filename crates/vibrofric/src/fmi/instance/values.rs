//! Values by value reference: get and set, input derivatives (Co-Simulation) and output
//! derivatives. Every value of a set is checked before any is written.

use super::Instance;
use crate::description::log::Category;
use crate::description::variables::{by_vr, Causality, VarKind, Variability, Variable};
use crate::fmi::refusal::{Answer, Refusal};
use crate::fmi::staging::Assign;
use crate::fmi::state::{Call, Interface, State};
use crate::fmi::status::Status;
use crate::model::{self, OutputId, Outputs, Simulator, StateId};
use crate::table::{number, IndicatorId};

/// What a value reference names for an instance: the independent variable `time`, where the
/// version declares it as a variable (FMI 3.0), or one of the scene's variables.
#[derive(Clone, Copy)]
enum Named {
    Time,
    Var(&'static Variable),
}

impl Named {
    fn name(self) -> &'static str {
        match self {
            Named::Time => "time",
            Named::Var(v) => v.name(),
        }
    }
}

/// The simulator's values a get reads (zero where not asked for).
struct Evaluated {
    outputs: Outputs,
    states: [f64; StateId::COUNT],
    derivatives: [f64; StateId::COUNT],
    indicators: [f64; IndicatorId::ALL.len()],
}

/// Gets: what a value reference names and the values it reads.
impl Instance {
    /// What `vr` names in a get or set of this call's version.
    fn named(&self, call: Call, vr: u32) -> Answer<Named> {
        if call.words.time_vr == Some(vr) {
            return Ok(Named::Time);
        }
        self.lookup(vr).map(Named::Var).map_err(Refusal::Error)
    }

    /// Real values by value reference (`fmi2GetReal`, `fmi3GetFloat64`); `values` has the
    /// length of `vrs`. In `Error` (where the standard allows reads for debugging) a read does
    /// not fail on what it evaluates: the values as they stand, and where one cannot be
    /// evaluated (non-finite), the one of the scene's start values, with a warning naming it.
    pub fn get_values(&mut self, call: Call, vrs: &[u32], values: &mut [f64]) -> Answer {
        if self.string.is_some() {
            return self.string_get(call, vrs, values);
        }
        let named = vrs
            .iter()
            .map(|&vr| self.named(call, vr))
            .collect::<Answer<Vec<_>>>()?;
        if self.st.state == State::Error {
            return self.get_values_in_error(call, &named, values);
        }
        let now = self.evaluate(&named)?;
        self.fill(&named, &now, values);
        // OK never comes with a non-finite value (the ranges are chosen so that none arises;
        // this is the last guard).
        if let Some((n, x)) = named
            .iter()
            .zip(values.iter())
            .find(|(_, x)| !x.is_finite())
        {
            let (name, x) = (n.name(), *x);
            if self.interface == Interface::ModelExchange {
                if let Some(r) = self.out_of_domain(Some(format!("{name} evaluates to {x}"))) {
                    return Err(r);
                }
            }
            return Err(Refusal::error(format!("{name} evaluates to {x}: a parameter or input is beyond what the model can compute; restore a state with {}", call.words.set_state)));
        }
        Ok(Status::Ok)
    }

    /// [`Instance::get_values`] in `Error`: the values as they stand (Model Exchange's states
    /// wherever they were set); a value that is not finite, or all of them if none can be
    /// evaluated, replaced by the value at the scene's start values, with a warning that says
    /// which and why.
    fn get_values_in_error(&mut self, call: Call, named: &[Named], values: &mut [f64]) -> Answer {
        let config = self.scene.config;
        let (bad, why): (Vec<usize>, _) = match self.evaluate(named) {
            Ok(now) => {
                self.fill(named, &now, values);
                let bad = (0..named.len()).filter(|&k| !values[k].is_finite());
                (bad.collect(), None)
            }
            Err(Refusal::Internal(what)) => return Err(Refusal::Internal(what)),
            Err(Refusal::Error(why) | Refusal::Discard(why) | Refusal::StepFailed(why)) => {
                // Parameters, inputs and the time as set; nothing the simulator evaluates.
                self.fill(named, &Evaluated::none(), values);
                let bad = (0..named.len()).filter(|&k| match named[k] {
                    Named::Var(v) => {
                        v.output(&config).is_some()
                            || !matches!(v.kind, VarKind::Param(_) | VarKind::Input(_))
                    }
                    Named::Time => false,
                });
                (bad.collect(), Some(why))
            }
        };
        if bad.is_empty() {
            return Ok(Status::Ok);
        }
        let start = model::Setup::new(self.scene.config, self.scene.start)
            .inputs(self.scene.inputs)
            .start(self.st.start_time)
            .tolerance(self.st.tolerance())
            .build()
            .map_err(|e| Refusal::Internal(format!("the scene's start values: {e}")))?;
        let mut at_start = vec![0.0; named.len()];
        let now = evaluate_on(start.as_ref(), config, named);
        self.fill(named, &now, &mut at_start);
        let names: Vec<String> = bad
            .iter()
            .map(|&k| {
                values[k] = at_start[k];
                format!("{} = {}", named[k].name(), number(at_start[k]))
            })
            .collect();
        let why = why.unwrap_or_else(|| "not finite as they stand".into());
        let cause = self
            .error_cause
            .as_deref()
            .unwrap_or("a state restored in Error");
        self.log(
            Status::Warning,
            Category::StatusWarning,
            &format!(
                "{}: the instance is in Error (since {cause}); {why}: returned, for debugging, the values at the scene's start values: {} [instance \"{}\"]",
                call.name,
                names.join(", "),
                self.name
            ),
        );
        Ok(Status::Warning)
    }

    /// Writes the values of `named` into `values`: parameters and inputs as set, the time, and
    /// what `now` evaluated.
    fn fill(&self, named: &[Named], now: &Evaluated, values: &mut [f64]) {
        let (config, time) = (self.scene.config, self.time());
        for (n, out) in named.iter().zip(values.iter_mut()) {
            let Named::Var(v) = n else {
                *out = time;
                continue;
            };
            *out = match v.kind {
                VarKind::Param(p) => p.get(&self.st.params),
                VarKind::Input(i) if v.causality(&config) == Causality::Input => {
                    i.get(&self.st.inputs)
                }
                VarKind::Input(_) => OutputId::FDrive.get(&now.outputs),
                VarKind::Output(o) => o.get(&now.outputs),
                VarKind::State(x) => now.states[x.index()],
                VarKind::Derivative(x) => now.derivatives[x.index()],
                VarKind::Indicator(i) => now.indicators[i.index(&config)],
            };
        }
    }

    /// What a get of these variables reads from the simulator, and only that: outputs (one
    /// evaluation), and the states, derivatives and event indicators of Model Exchange when
    /// one of them is asked for. Model Exchange evaluates only inside the model's domain
    /// (except in `Error`, where the values are read as they stand, for debugging).
    fn evaluate(&mut self, named: &[Named]) -> Answer<Evaluated> {
        let config = self.scene.config;
        let asks = evaluates(config, named);
        if !asks.any() {
            return Ok(Evaluated::none());
        }
        self.simulator_now()?;
        let exchange = self.interface == Interface::ModelExchange;
        if exchange
            && self.st.state != State::Error
            && (asks.outputs || asks.derivatives || asks.indicators)
        {
            if let Some(r) = self.out_of_domain(None) {
                return Err(r);
            }
        }
        Ok(evaluate_on(self.simulator_now()?, config, named))
    }
}

/// Sets: values and input derivatives; the output derivatives a get reads.
impl Instance {
    /// Real values by value reference (`fmi2SetReal`, `fmi3SetFloat64`): every value is checked
    /// before any is written.
    pub fn set_values(&mut self, call: Call, vrs: &[u32], values: &[f64]) -> Answer {
        if self.string.is_some() {
            return self.string_set(call, vrs, values);
        }
        let plan = vrs
            .iter()
            .zip(values)
            .map(|(&vr, &value)| self.assignment(call, vr, value))
            .collect::<Answer<Vec<_>>>()?;
        // In Model Exchange the body lifts off or lands at the next event update, not here.
        let exchange = matches!(self.st.state, State::EventMode | State::ContinuousTimeMode);
        if let Some(sim) = self.sim.as_mut() {
            let apply = |sim: &mut dyn Simulator, a: Assign| match a {
                Assign::Param(p, x) => sim.set_param(p, x),
                Assign::Input(i, x) if exchange => sim.set_input_continuous(i, x),
                Assign::Input(i, x) => sim.set_input(i, x),
            };
            // One assignment leaves the simulator unchanged when it fails; several are applied
            // to a copy, so that a failure in the middle changes nothing either.
            if plan.len() == 1 {
                apply(sim.as_mut(), plan[0]).map_err(Refusal::error)?;
            } else {
                let mut next = sim.clone_box();
                plan.iter()
                    .try_for_each(|&a| apply(next.as_mut(), a))
                    .map_err(Refusal::error)?;
                *sim = next;
            }
        }
        for a in plan {
            match a {
                Assign::Param(p, x) => {
                    // A new parameter restarts the averaging window (F_int jumps to 0).
                    self.st.states_changed |= exchange;
                    // Checked above, cannot fail.
                    let _ = p.set(&mut self.st.params, x);
                }
                Assign::Input(i, x) => *i.slot(&mut self.st.inputs) = x,
            }
        }
        self.provisional = None;
        Ok(Status::Ok)
    }

    /// The checked assignment of `value` to the variable `vr` in the current state.
    fn assignment(&self, call: Call, vr: u32, value: f64) -> Answer<Assign> {
        let v = match self.named(call, vr)? {
            Named::Var(v) => v,
            Named::Time => {
                return Err(Refusal::error(format!(
                "time (vr {vr}) is the independent variable: it advances with {} and cannot be set",
                call.words.do_step
            )))
            }
        };
        let (state, config, name) = (self.st.state, self.scene.config, v.name());
        match (v.kind, v.causality(&config)) {
            (_, Causality::Output) => Err(Refusal::error(format!(
                "{name} (vr {vr}) has causality output: it is computed by the FMU and cannot be set"
            ))),
            (_, Causality::Local) => Err(Refusal::error(format!(
                "{name} (vr {vr}) is a continuous state or derivative (causality local): an importer sets states with {}",
                call.words.set_states
            ))),
            (VarKind::Param(p), _) if state == State::ContinuousTimeMode => Err(Refusal::error(format!(
                "{} (vr {vr}) is a parameter: in ContinuousTimeMode only inputs can be set; tunable parameters in EventMode",
                p.name()
            ))),
            (VarKind::Param(p), _) => {
                if v.variability(&config) == Variability::Fixed && state == State::StepComplete {
                    return Err(Refusal::error(format!(
                        "{name} (vr {vr}) is a parameter with variability fixed: it can only be set before {}, not in state {}",
                        call.words.exit_initialization,
                        state.name()
                    )));
                }
                p.check_in(value, &config)
                    .map_err(|e| Refusal::error(format!("{e} (vr {vr})")))?;
                Ok(Assign::Param(p, value))
            }
            (VarKind::Input(i), _) => {
                if !i.rule().holds(value) {
                    return Err(Refusal::error(format!(
                        "{name} = {value}: {} (vr {vr})",
                        i.rule().text(value, i.unit())
                    )));
                }
                Ok(Assign::Input(i, value))
            }
            _ => unreachable!("outputs and locals are refused above"),
        }
    }

    /// First derivatives of inputs (`fmi2SetRealInputDerivatives`), used to extrapolate them
    /// linearly over the next step.
    pub fn set_input_derivatives(&mut self, vrs: &[u32], orders: &[i32], values: &[f64]) -> Answer {
        if self.string.is_some() {
            return self.string_set_input_derivatives(vrs, orders, values);
        }
        let config = self.scene.config;
        let mut plan = Vec::with_capacity(vrs.len());
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let v = self.lookup(vr).map_err(Refusal::Error)?;
            let name = v.name();
            let id = match (v.kind, v.causality(&config)) {
                (VarKind::Input(i), Causality::Input) => i,
                (_, c) => {
                    return Err(Refusal::error(format!(
                        "{name} (vr {vr}) has causality {}: only inputs have input derivatives",
                        c.as_str()
                    )))
                }
            };
            if order != 1 {
                return Err(Refusal::error(format!("order = {order} for {name} (vr {vr}): only first derivatives (order 1) are supported")));
            }
            if !(value.is_finite() && value.abs() <= model::MAX_INPUT_RATE) {
                return Err(Refusal::error(format!(
                    "derivative of {name} = {}: must be finite and at most {} {}/s in magnitude (vr {vr})",
                    number(value),
                    number(model::MAX_INPUT_RATE),
                    id.unit()
                )));
            }
            plan.push((id, value));
        }
        match self.sim.as_mut() {
            Some(sim) => {
                if plan.len() == 1 {
                    sim.set_input_derivative(plan[0].0, plan[0].1)
                        .map_err(Refusal::error)?;
                } else {
                    let mut next = sim.clone_box();
                    plan.iter()
                        .try_for_each(|&(i, d)| next.set_input_derivative(i, d))
                        .map_err(Refusal::error)?;
                    *sim = next;
                }
            }
            None => {
                for (id, d) in plan {
                    self.st.derivs[id.index()] = Some(d);
                }
                self.provisional = None;
            }
        }
        Ok(Status::Ok)
    }

    /// First derivatives (`maxOutputDerivativeOrder` = 1) of the outputs that have an exact one
    /// (see `Simulator::output_derivative`; `fmi2GetRealOutputDerivatives`,
    /// `fmi3GetOutputDerivatives`); every value is checked before any is written.
    pub fn get_output_derivatives(
        &mut self,
        call: Call,
        vrs: &[u32],
        orders: &[i32],
        values: &mut [f64],
    ) -> Answer {
        if self.string.is_some() && !vrs.is_empty() {
            return Err(Refusal::error(
                "a string of contacts provides no output derivatives (maxOutputDerivativeOrder = 0)",
            ));
        }
        let config = self.scene.config;
        let mut found = Vec::with_capacity(vrs.len());
        for (&vr, &order) in vrs.iter().zip(orders) {
            let v = self.lookup(vr).map_err(Refusal::Error)?;
            let name = v.name();
            let id = match (v.output(&config), v.causality(&config)) {
                (Some(o), _) => o,
                (None, c) => {
                    return Err(Refusal::error(format!(
                        "{name} (vr {vr}) has causality {}: only outputs have output derivatives",
                        c.as_str()
                    )))
                }
            };
            if order != 1 {
                return Err(Refusal::error(format!("order = {order} for {name} (vr {vr}): only first derivatives (order 1) are provided (maxOutputDerivativeOrder = 1)")));
            }
            let Some(sim) = self.sim.as_ref() else {
                return Err(Refusal::error(format!(
                    "no simulation state: call {} first",
                    call.words.exit_initialization
                )));
            };
            match sim.output_derivative(id) {
                Some(d) if d.is_finite() => found.push(d),
                Some(d) => {
                    return Err(Refusal::error(format!(
                        "the derivative of {name} (vr {vr}) is {d}"
                    )))
                }
                None => {
                    return Err(Refusal::error(format!("{name} (vr {vr}) has no exact time derivative; derivatives are provided for x, y, v_x, v_y, s_x, s_y, and for F_Fx_step, F_Fy_step after the first {}", call.words.do_step)))
                }
            }
        }
        values[..found.len()].copy_from_slice(&found);
        Ok(Status::Ok)
    }

    /// The getters and setters of the types this FMU has no variables of (`fmi2GetInteger`,
    /// `fmi3SetBoolean`, ...): any value reference is an error, an empty call does nothing.
    pub fn no_variables_of_type(&mut self, type_name: &str, vrs: &[u32]) -> Answer {
        match vrs.first() {
            None => Ok(Status::Ok),
            Some(&vr) => {
                let what = match by_vr(vr) {
                    Some(v) => format!("value reference {vr} ({}) is a Real variable", v.name()),
                    None => format!("unknown value reference {vr}"),
                };
                Err(Refusal::error(format!(
                    "{what}; this FMU has no {type_name} variables"
                )))
            }
        }
    }
}

/// Which of the simulator's values a get asks for.
struct Asks {
    outputs: bool,
    states: bool,
    derivatives: bool,
    indicators: bool,
}

impl Asks {
    fn any(&self) -> bool {
        self.outputs || self.states || self.derivatives || self.indicators
    }
}

fn evaluates(config: crate::table::Config, named: &[Named]) -> Asks {
    let asks = |kind: fn(&VarKind) -> bool| {
        named
            .iter()
            .any(|n| matches!(n, Named::Var(v) if kind(&v.kind)))
    };
    Asks {
        outputs: named
            .iter()
            .any(|n| matches!(n, Named::Var(v) if v.output(&config).is_some())),
        states: asks(|k| matches!(k, VarKind::State(_))),
        derivatives: asks(|k| matches!(k, VarKind::Derivative(_))),
        indicators: asks(|k| matches!(k, VarKind::Indicator(_))),
    }
}

impl Evaluated {
    fn none() -> Evaluated {
        Evaluated {
            outputs: Outputs::default(),
            states: [0.0; StateId::COUNT],
            derivatives: [0.0; StateId::COUNT],
            indicators: [0.0; IndicatorId::ALL.len()],
        }
    }
}

/// The values of `sim` a get of `named` reads (zero where not asked for).
fn evaluate_on(sim: &dyn Simulator, config: crate::table::Config, named: &[Named]) -> Evaluated {
    let asks = evaluates(config, named);
    let mut now = Evaluated::none();
    if asks.outputs {
        now.outputs = sim.outputs();
    }
    if asks.states {
        now.states = sim.states();
    }
    if asks.derivatives {
        now.derivatives = sim.derivatives();
    }
    if asks.indicators {
        sim.event_indicators(&mut now.indicators[..config.event_indicators()]);
    }
    now
}
