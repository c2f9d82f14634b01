//! A string of one section with free ends (`k_top = c_top = k_bottom = c_bottom = 0`): no
//! link, nothing at either end, so its equations are the single contact's (force drive,
//! longitudinal, the support's input velocity `v_sx[1]`). It is simulated by the single
//! contact's simulator ([`crate::model::Setup`]), so that it is the scene without `[string]`
//! bit for bit. The end parameters are fixed once the string is built (after initialization),
//! so the choice never changes during a run; a state restores into a string built from the
//! same parameters, hence of the same kind.

use super::exchange::{InputDirection, StringExchange};
use super::{StringConfig, StringInput, StringOutputs, StringParams, StringSimulator};
use crate::model::setup::Setup;
use crate::model::simulator::{SimError, Simulator, StepStats};
use crate::model::state::ContactState;
use crate::table::{Config, Drive, InputId, Inputs, Lateral, Motion};

/// First number of a saved state of this kind (the band integrator's saved states start with
/// the time, which is finite; this is a marker, not a time).
const MARK: f64 = -7.0e300;

/// Whether a string's parameters make it the single contact: one section, free ends.
pub(super) fn applies(p: &StringParams) -> bool {
    let l = &p.links;
    p.sections() == 1 && [l.k_top, l.c_top, l.k_bottom, l.c_bottom] == [0.0; 4]
}

/// The single contact as a string of one section.
pub(super) struct Single {
    sim: Box<dyn Simulator>,
    normal_input: bool,
    /// The same section as a string (never stepped, its input tracks the same): placed at the
    /// contact's state, it gives what only a string has, the Model Exchange variables that a
    /// Co-Simulation instance reads too (states, derivatives, event indicators, directional
    /// derivatives) and the ends' points `x_top`, `x_bottom`.
    shadow: Box<dyn StringSimulator>,
}

impl Clone for Single {
    fn clone(&self) -> Self {
        Single {
            sim: self.sim.clone_box(),
            normal_input: self.normal_input,
            shadow: self.shadow.clone_box(),
        }
    }
}

impl Single {
    /// The single contact of the string's law and support with section 1's parameters (its
    /// start load the reference load, as every section's), at rest, its load input at `F_N`.
    pub(super) fn new(
        config: StringConfig,
        params: &StringParams,
        t_start: f64,
        tolerance: f64,
        shadow: Box<dyn StringSimulator>,
    ) -> Result<Single, SimError> {
        let c = Config {
            law: config.law,
            motion: Motion::Longitudinal,
            drive: Drive::Force,
            lateral: Lateral::Guided,
            harmonic: config.harmonic,
            input_support: true,
            normal_input: config.normal_input,
        };
        let p = params.section(0);
        let inputs = Inputs {
            f_n: p.f_n,
            ..Inputs::default()
        };
        let sim = Setup::new(c, p)
            .inputs(inputs)
            .start(t_start)
            .tolerance(tolerance)
            .build()?;
        Ok(Single {
            sim,
            normal_input: config.normal_input,
            shadow,
        })
    }

    /// The contact's time and state `[x, v, s]`.
    fn state(&self) -> (f64, [f64; 3]) {
        let o = self.sim.outputs();
        (self.sim.time(), [o.x, o.v_x, o.s_x])
    }

    /// Sets an input on the shadow string (placed at the contact's state first) and, where
    /// the contact has it, on the contact; an error leaves both as they were.
    fn set_both(
        &mut self,
        input: StringInput,
        on_shadow: impl FnOnce(&mut dyn StringSimulator) -> Result<(), SimError>,
        on_contact: impl FnOnce(&mut dyn Simulator, InputId) -> Result<(), SimError>,
    ) -> Result<(), SimError> {
        let (t, y) = self.state();
        let mut shadow = self.shadow.clone_box();
        shadow.place(t, &y)?;
        on_shadow(shadow.as_mut())?;
        if let Some(id) = self.input(input)? {
            on_contact(self.sim.as_mut(), id)?;
        }
        self.shadow = shadow;
        Ok(())
    }

    /// The shadow string placed at the contact's time and state.
    fn placed(&self) -> Box<dyn StringSimulator> {
        let mut s = self.shadow.clone_box();
        let (t, y) = self.state();
        // A contact's state is finite: placing it cannot fail.
        let _ = s.place(t, &y);
        s
    }

    /// The single contact's input, `None` for an end's velocity (which moves nothing: the ends
    /// are free).
    fn input(&self, input: StringInput) -> Result<Option<InputId>, SimError> {
        match input {
            StringInput::Fd(0) => Ok(Some(InputId::FD)),
            StringInput::Vsx(0) => Ok(Some(InputId::VSx)),
            StringInput::Fn(0) if self.normal_input => Ok(Some(InputId::FN)),
            StringInput::VTop | StringInput::VBottom => Ok(None),
            _ => Err(SimError::Inconsistent(format!(
                "{}: this string has no such input",
                input.name()
            ))),
        }
    }
}

/// A byte string as numbers, 4 bytes each (exact and finite), after the marker and the length.
fn pack(bytes: &[u8]) -> Vec<f64> {
    let mut out = vec![MARK, bytes.len() as f64];
    out.extend(bytes.chunks(4).map(|c| {
        let mut w = [0u8; 4];
        w[..c.len()].copy_from_slice(c);
        u32::from_le_bytes(w) as f64
    }));
    out
}

/// What [`pack`] wrote, or `None`.
/// The bytes packed at the start of `data`, and how many numbers they took.
fn unpack(data: &[f64]) -> Option<(Vec<u8>, usize)> {
    let (&mark, rest) = data.split_first()?;
    let (&len, words) = rest.split_first()?;
    if mark != MARK || len.fract() != 0.0 || !(0.0..=1e9).contains(&len) {
        return None;
    }
    let len = len as usize;
    let used = len.div_ceil(4);
    if words.len() < used {
        return None;
    }
    let words = &words[..used];
    let mut bytes = Vec::with_capacity(4 * words.len());
    for &w in words {
        if !(w.fract() == 0.0 && (0.0..=u32::MAX as f64).contains(&w)) {
            return None;
        }
        bytes.extend_from_slice(&(w as u32).to_le_bytes());
    }
    bytes.truncate(len);
    Some((bytes, 2 + used))
}

impl StringSimulator for Single {
    fn sections(&self) -> usize {
        1
    }

    fn time(&self) -> f64 {
        self.sim.time()
    }

    fn tolerance(&self) -> f64 {
        self.sim.tolerance()
    }

    fn set_input(&mut self, input: StringInput, value: f64) -> Result<(), SimError> {
        input.check(value)?;
        self.set_both(
            input,
            |s| s.set_input(input, value),
            |c, id| c.set_input(id, value),
        )
    }

    fn set_input_derivative(&mut self, input: StringInput, value: f64) -> Result<(), SimError> {
        input.check_derivative(value)?;
        self.set_both(
            input,
            |s| s.set_input_derivative(input, value),
            |c, id| c.set_input_derivative(id, value),
        )
    }

    fn set_inputs(&mut self, values: &[(StringInput, f64)]) -> Result<(), SimError> {
        let mut next = self.clone();
        for &(input, value) in values {
            next.set_input(input, value)?;
        }
        *self = next;
        Ok(())
    }

    fn set_input_derivatives(&mut self, values: &[(StringInput, f64)]) -> Result<(), SimError> {
        let mut next = self.clone();
        for &(input, value) in values {
            next.set_input_derivative(input, value)?;
        }
        *self = next;
        Ok(())
    }

    fn step_to(&mut self, t_end: f64) -> Result<(), SimError> {
        self.sim.step_to(t_end)
    }

    fn outputs(&self) -> StringOutputs {
        let o = self.sim.outputs();
        StringOutputs {
            x: vec![o.x],
            v_x: vec![o.v_x],
            s_x: vec![o.s_x],
            f_fx: vec![o.f_fx],
            f_fx_step: vec![o.f_fx_step],
            f_link: vec![],
            // Free ends hold nothing.
            f_top: 0.0,
            f_bottom: 0.0,
            f_top_step: 0.0,
            f_bottom_step: 0.0,
        }
    }

    fn stats(&self) -> StepStats {
        self.sim.stats()
    }

    fn clone_box(&self) -> Box<dyn StringSimulator> {
        Box::new(self.clone())
    }

    fn save(&self) -> Vec<f64> {
        // A struct of numbers, options and vectors always serializes.
        let mut out = pack(&postcard::to_allocvec(&self.sim.snapshot()).unwrap_or_default());
        out.extend(self.shadow.save());
        out
    }

    fn restore(&mut self, data: &[f64]) -> Result<(), SimError> {
        let bad = |why: &str| SimError::Inconsistent(format!("the saved string state {why}"));
        let (bytes, used) =
            unpack(data).ok_or_else(|| bad("is not one of a single free section"))?;
        let state: ContactState =
            postcard::from_bytes(&bytes).map_err(|e| bad(&format!("does not read: {e}")))?;
        let mut shadow = self.shadow.clone_box();
        shadow.restore(&data[used..])?;
        // The contact checks every field; on error nothing changes.
        self.sim.restore(&state)?;
        self.shadow = shadow;
        Ok(())
    }

    fn place(&mut self, _t: f64, _y: &[f64]) -> Result<(), SimError> {
        Err(SimError::Inconsistent(
            "a single free section simulated as the single contact is not placed".into(),
        ))
    }
}

/// What only a string knows, from the shadow string at the contact's state. A single free
/// section is built for Co-Simulation only (Model Exchange builds the string's equations,
/// [`super::build_string_exchange`]): the calls that set Model Exchange's states, time or
/// events refuse.
impl StringExchange for Single {
    fn set_exchange(&mut self) {}

    fn exchange_states(&self) -> Vec<f64> {
        self.placed().exchange_states()
    }

    fn set_exchange_states(&mut self, _x: &[f64]) -> Result<(), SimError> {
        Err(co_simulation_only())
    }

    fn set_exchange_time(&mut self, _t: f64) -> Result<(), SimError> {
        Err(co_simulation_only())
    }

    fn exchange_derivatives(&self) -> Vec<f64> {
        self.placed().exchange_derivatives()
    }

    fn exchange_nominals(&self) -> Vec<f64> {
        self.shadow.exchange_nominals()
    }

    fn event_indicators(&self) -> Vec<f64> {
        self.placed().event_indicators()
    }

    fn update_events(&mut self) {}

    fn out_of_domain(&self) -> Option<String> {
        None
    }

    fn tangent(&self, dx: &[f64], du: &InputDirection) -> (Vec<f64>, StringOutputs) {
        self.placed().tangent(dx, du)
    }
}

fn co_simulation_only() -> SimError {
    SimError::Inconsistent(
        "a single free section in Co-Simulation has no Model Exchange states to set".into(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_bytes_read_back_and_damaged_ones_are_refused() {
        for n in [0usize, 1, 3, 4, 5, 257] {
            let bytes: Vec<u8> = (0..n).map(|k| (k * 37 % 256) as u8).collect();
            let data = pack(&bytes);
            assert!(data.iter().all(|x| x.is_finite()));
            assert_eq!(unpack(&data), Some((bytes, data.len())));
        }
        let data = pack(&[1, 2, 3, 4, 5]);
        assert_eq!(unpack(&data[..2]), None);
        let mut bad = data.clone();
        bad[0] = 0.0;
        assert_eq!(unpack(&bad), None);
        let mut bad = data.clone();
        bad[2] = 0.5;
        assert_eq!(unpack(&bad), None);
        let mut bad = data;
        bad[1] = 9.0;
        assert_eq!(unpack(&bad), None);
    }
}
