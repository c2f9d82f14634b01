//! A string from the values of its variables, as an FMU instance and `vibrofric simulate` hold
//! them ([`StringValues`]: per section, per link, at the ends), and the values of its inputs
//! and outputs by variable.

use super::{build_string, build_string_exchange, StringConfig, StringInput, StringOutputs};
use super::{StringParams, StringSimulator};
use crate::model::SimError;
use crate::table::{Config, Params, Role, StringValues, StringVar};

impl StringInput {
    /// The input of element `i` (0-based) of a string variable, if it is an input.
    pub fn of(var: StringVar, i: usize) -> Option<StringInput> {
        match var {
            StringVar::FD => Some(StringInput::Fd(i)),
            StringVar::VSx => Some(StringInput::Vsx(i)),
            StringVar::FN => Some(StringInput::Fn(i)),
            StringVar::VTop => Some(StringInput::VTop),
            StringVar::VBottom => Some(StringInput::VBottom),
            _ => None,
        }
    }
}

impl StringOutputs {
    /// The values of an output variable (one for a scalar; none for a variable that is no
    /// output).
    pub fn values(&self, var: StringVar) -> &[f64] {
        match var {
            StringVar::FFx => &self.f_fx,
            StringVar::X => &self.x,
            StringVar::Vx => &self.v_x,
            StringVar::Sx => &self.s_x,
            StringVar::FFxStep => &self.f_fx_step,
            StringVar::FLink => &self.f_link,
            StringVar::FTop => std::slice::from_ref(&self.f_top),
            StringVar::FBottom => std::slice::from_ref(&self.f_bottom),
            StringVar::FTopStep => std::slice::from_ref(&self.f_top_step),
            StringVar::FBottomStep => std::slice::from_ref(&self.f_bottom_step),
            _ => &[],
        }
    }
}

/// A string of configuration `c` (for Model Exchange where `exchange`) at `t_start` with
/// relative tolerance `tolerance`, from the law's shared parameters and the values of its
/// variables `v`: the parameters, then the inputs as set. Each section's reference load (at
/// which `F_S` and `zeta_t` are given) is its `F_N` in `v`, or, where the normal force is an
/// input, in the scene's start values `start`.
pub fn build_from_values(
    c: &Config,
    shared: Params,
    v: &StringValues,
    start: &StringValues,
    (t_start, tolerance): (f64, f64),
    exchange: bool,
) -> Result<Box<dyn StringSimulator>, SimError> {
    let f_n = match c.normal_input {
        true => start.get(StringVar::FN),
        false => v.get(StringVar::FN),
    };
    let params = StringParams::from_values(shared, v, f_n);
    let config = StringConfig {
        law: c.law,
        harmonic: c.harmonic,
        normal_input: c.normal_input,
    };
    let mut sim = if exchange {
        build_string_exchange(config, params, t_start, tolerance)?
    } else {
        build_string(config, params, t_start, tolerance)?
    };
    let n = v.sections;
    for var in StringVar::ALL {
        if !(var.present(c, n) && var.role(c) == Role::Input) {
            continue;
        }
        for (i, &x) in v.get(var).iter().enumerate() {
            // The simulator starts with its inputs at 0 and the load inputs at F_N.
            let at_start = if var == StringVar::FN { f_n[i] } else { 0.0 };
            if let (true, Some(input)) = (x != at_start, StringInput::of(var, i)) {
                sim.set_input(input, x)?;
            }
        }
    }
    Ok(sim)
}
