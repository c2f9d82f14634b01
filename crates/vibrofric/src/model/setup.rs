//! The one way from a scene's values to a running simulator: [`Setup`].

use super::build::{build_inconsistent, consistent};
use super::simulator::{SimError, Simulator};
use crate::table::Params;
use crate::table::{Config, InputId, Inputs};

/// Everything a simulator starts from: the configuration, the parameters, the inputs (each one
/// the configuration has is set), the start time, the relative tolerance, optionally the input
/// derivatives and whether to force the general integrator. The FMU instance, the command line, the tests and the
/// examples all build their simulators through it, so that they start alike.
///
/// ```
/// use vibrofric::model::{Config, Inputs, Setup};
/// use vibrofric::table::Params;
/// let sim = Setup::new(Config::default(), Params::default())
///     .inputs(Inputs::default())
///     .tolerance(1e-8)
///     .build()
///     .unwrap();
/// assert_eq!(sim.time(), 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    pub config: Config,
    pub params: Params,
    /// The inputs to set, `None` to leave them all at zero.
    pub inputs: Option<Inputs>,
    /// The first time derivative of each input ([`InputId::index`]), set after the inputs.
    pub derivatives: [Option<f64>; InputId::ALL.len()],
    pub t_start: f64,
    pub tolerance: f64,
    /// Radau IIA at every step (the reference of the tests and benchmarks of the fast paths),
    /// else the fastest path that applies ([`super::build_on`]).
    pub force_radau: bool,
    /// Whether the rules between parameters ([`super::consistent`]) are applied: not to a
    /// simulator that only reads values at parameters still being set ([`Setup::provisional`]).
    pub consistent: bool,
}

impl Setup {
    /// Starts at `t = 0` with relative tolerance 1e-6, no inputs set, the fastest path.
    pub fn new(config: Config, params: Params) -> Setup {
        Setup {
            config,
            params,
            inputs: None,
            derivatives: [None; InputId::ALL.len()],
            t_start: 0.0,
            tolerance: 1e-6,
            force_radau: false,
            consistent: true,
        }
    }

    /// Sets each input the configuration has to its value in `inputs`.
    pub fn inputs(self, inputs: Inputs) -> Setup {
        Setup {
            inputs: Some(inputs),
            ..self
        }
    }

    /// Sets the input derivatives given (indexed by [`InputId::index`]).
    pub fn derivatives(self, derivatives: [Option<f64>; InputId::ALL.len()]) -> Setup {
        Setup {
            derivatives,
            ..self
        }
    }

    /// Starts at `t_start`.
    pub fn start(self, t_start: f64) -> Setup {
        Setup { t_start, ..self }
    }

    /// Relative tolerance of the integrator (clamped to [`super::TOLERANCE_RANGE`]).
    pub fn tolerance(self, tolerance: f64) -> Setup {
        Setup { tolerance, ..self }
    }

    /// Whether to take Radau IIA at every step even where a faster path applies (see
    /// [`super::build_on`]).
    pub fn force_radau(self, force_radau: bool) -> Setup {
        Setup {
            force_radau,
            ..self
        }
    }

    /// Without the rules between parameters ([`super::consistent`]): a simulator that reads
    /// the values at parameters still being set (an FMU's reads before initialization ends,
    /// which leaving initialization checks). Each parameter still obeys its own range.
    pub fn provisional(self) -> Setup {
        Setup {
            consistent: false,
            ..self
        }
    }

    /// The simulator: [`super::build_on`] (without [`super::consistent`] when
    /// [`Setup::provisional`]), then each input the configuration has, then the derivatives
    /// given. The first refusal is returned.
    pub fn build(&self) -> Result<Box<dyn Simulator>, SimError> {
        let c = self.config;
        if self.consistent {
            consistent(c, &self.params)?;
        }
        let mut sim = build_inconsistent(
            c,
            self.params,
            self.t_start,
            self.tolerance,
            self.force_radau,
        )?;
        if let Some(inputs) = &self.inputs {
            for id in InputId::ALL {
                if id.present(&c) {
                    sim.set_input(id, id.get(inputs))?;
                }
            }
        }
        for id in InputId::ALL {
            if let Some(d) = self.derivatives[id.index()] {
                sim.set_input_derivative(id, d)?;
            }
        }
        Ok(sim)
    }
}
