//! A string of contacts: `N` sections in a line, each a body on its own contact, joined by
//! springs and dampers, the ends held to points the importer moves (a drill string's sections on
//! the borehole wall). A room of its own: its state is the whole string's, integrated together by
//! Radau IIA on the banded Jacobian of the chain ([`crate::solver::band`]), so that one call
//! advances every section and the stiff links and ends are resolved inside the step, at the
//! contact's tolerance, whatever the communication step. Each section's error is held to the
//! tolerance on its own; a section whose error fails in a step (a reversal, its contact damping
//! switching) is integrated again alone over that step with its neighbours on the string's
//! step, so that its transient costs its own short steps, not the whole string's; adjacent
//! sections that fail together are integrated again together.
//!
//! - `equations.rs`: the right-hand side, its banded Jacobian and the forces;
//! - `refine.rs`: a section integrated again alone;
//! - `run.rs`: adjacent sections integrated again together;
//! - `single.rs`: one section with free ends, which is the single contact and is simulated as
//!   it (bit for bit the scene without `[string]`);
//! - `exchange.rs`: the string for an importer's integrator (Model Exchange);
//! - `values.rs`: a string from the values of its variables, its inputs and outputs by
//!   variable;
//! - this file: parameters and their rules, inputs, stepping to communication points with the
//!   step means of the friction and end forces (the collocation quadrature of each accepted
//!   step), outputs.

mod equations;
mod exchange;
mod params;
mod refine;
mod run;
mod single;
mod values;

pub use equations::{Links, Section, StringInputs, StringModel, PER_SECTION};
pub use exchange::{state_name, InputDirection, StringExchange};
pub use params::{StringConfig, StringParams};
pub use values::build_from_values;

use crate::physics::{Dahl, Dupont, FrictionLaw, Harmonic, InputTrack, LuGre};
use crate::solver::band::{Accepted, BandRadau, BandSystem, BandWork};
use crate::solver::{SolverError, SolverStats, Workspace, B, C};
use crate::table::{number, InputId, Law};

use super::simulator::{SimError, StepStats, TOLERANCE_RANGE};
use super::time::{canonical_time, MAX_INPUT_RATE};

/// Most sections a string may have (declared with the string's variables).
pub use crate::table::MAX_SECTIONS;

/// An input of a string: per section (0-based index) or at an end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StringInput {
    /// `F_d[i]`: the external axial force on section `i`.
    Fd(usize),
    /// `v_sx[i]`: the support (wall) velocity under section `i`.
    Vsx(usize),
    /// `F_N[i]`: the normal force of section `i` (where it is an input).
    Fn(usize),
    /// The velocity of the point the top element holds.
    VTop,
    /// The velocity of the point the bottom element holds.
    VBottom,
}

impl StringInput {
    fn name(self) -> String {
        match self {
            StringInput::Fd(i) => format!("F_d[{}]", i + 1),
            StringInput::Vsx(i) => format!("v_sx[{}]", i + 1),
            StringInput::Fn(i) => format!("F_N[{}]", i + 1),
            StringInput::VTop => "v_top".into(),
            StringInput::VBottom => "v_bottom".into(),
        }
    }

    /// The single contact's input whose rule it follows.
    fn like(self) -> InputId {
        match self {
            StringInput::Fd(_) => InputId::FD,
            StringInput::Fn(_) => InputId::FN,
            _ => InputId::VSx,
        }
    }

    /// The value against the rule of the input it is like, named with its index.
    fn check(self, value: f64) -> Result<(), SimError> {
        let like = self.like();
        if like.rule().holds(value) {
            return Ok(());
        }
        Err(SimError::Inconsistent(format!(
            "{} = {}: {}",
            self.name(),
            number(value),
            like.rule().text(value, like.unit())
        )))
    }

    /// A time derivative: finite and at most [`MAX_INPUT_RATE`] in magnitude.
    fn check_derivative(self, value: f64) -> Result<(), SimError> {
        if value.is_finite() && value.abs() <= MAX_INPUT_RATE {
            return Ok(());
        }
        Err(SimError::Inconsistent(format!(
            "derivative of {} = {}: must be finite and at most {} in magnitude",
            self.name(),
            number(value),
            number(MAX_INPUT_RATE)
        )))
    }
}

/// The outputs of a string at the current time.
#[derive(Clone, Debug, PartialEq)]
pub struct StringOutputs {
    pub x: Vec<f64>,
    pub v_x: Vec<f64>,
    pub s_x: Vec<f64>,
    pub f_fx: Vec<f64>,
    /// Mean of `F_Fx[i]` over the last communication step (exact integral over the step).
    pub f_fx_step: Vec<f64>,
    /// `N − 1` link forces, tension positive.
    pub f_link: Vec<f64>,
    pub f_top: f64,
    pub f_bottom: f64,
    pub f_top_step: f64,
    pub f_bottom_step: f64,
}

/// A string of contacts that can be stepped in time; a method that returns an error leaves it
/// as it was.
pub trait StringSimulator: StringExchange + Send {
    fn sections(&self) -> usize;
    fn time(&self) -> f64;
    fn tolerance(&self) -> f64;
    /// Sets an input from the current time on (its derivative back to 0).
    fn set_input(&mut self, input: StringInput, value: f64) -> Result<(), SimError>;
    /// The input's time derivative, for linear extrapolation over the next step only.
    fn set_input_derivative(&mut self, input: StringInput, value: f64) -> Result<(), SimError>;
    /// Sets several inputs as [`StringSimulator::set_input`] one after the other would, all or
    /// none.
    fn set_inputs(&mut self, values: &[(StringInput, f64)]) -> Result<(), SimError>;
    /// Sets several input derivatives as [`StringSimulator::set_input_derivative`] one after
    /// the other would, all or none.
    fn set_input_derivatives(&mut self, values: &[(StringInput, f64)]) -> Result<(), SimError>;
    /// Integrates exactly to `t_end`.
    fn step_to(&mut self, t_end: f64) -> Result<(), SimError>;
    fn outputs(&self) -> StringOutputs;
    /// The string's steps (`steps`, `rejected`), and every integrator's work (right-hand
    /// sides, Jacobians, located events).
    fn stats(&self) -> StepStats;
    /// The steps (accepted and rejected) of the sections integrated again (alone, or a run's
    /// steps once for the run).
    fn section_steps(&self) -> u64 {
        0
    }
    fn clone_box(&self) -> Box<dyn StringSimulator>;
    /// The string's complete state as numbers (the integrator's, the input tracks, the step
    /// means): [`StringSimulator::restore`] into a string built from the same configuration and
    /// parameters continues bit for bit.
    fn save(&self) -> Vec<f64>;
    /// Restores what [`StringSimulator::save`] wrote; an error leaves the string as it was.
    fn restore(&mut self, data: &[f64]) -> Result<(), SimError>;
    /// Puts the string at time `t` with the sections' states `y` (`[x, v, s]` per section),
    /// its input tracks as they are: a string that stands beside another simulator of the same
    /// sections (`single.rs`) and answers for it what only a string knows.
    fn place(&mut self, t: f64, y: &[f64]) -> Result<(), SimError>;
}

/// Builds a string at rest at the origin (zero deformation, zero inputs, the load inputs at the
/// parameters' `F_N`) at `t_start` with relative tolerance `tolerance`. A string of one section
/// with free ends (its four end elements 0) is the single contact, simulated as the single
/// contact (`single.rs`): bit for bit the scene without `[string]`.
pub fn build_string(
    config: StringConfig,
    params: StringParams,
    t_start: f64,
    tolerance: f64,
) -> Result<Box<dyn StringSimulator>, SimError> {
    params.validate(config.law)?;
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(SimError::Tolerance(tolerance));
    }
    if !t_start.is_finite() {
        return Err(SimError::Time {
            now: t_start,
            target: t_start,
        });
    }
    let tol = tolerance.clamp(TOLERANCE_RANGE.0, TOLERANCE_RANGE.1);
    if single::applies(&params) {
        let shadow = build_band(config, params.clone(), t_start, tol);
        return Ok(Box::new(single::Single::new(
            config, &params, t_start, tol, shadow,
        )?));
    }
    Ok(build_band(config, params, t_start, tol))
}

/// Builds a string for an importer's integrator (Model Exchange): as [`build_string`], but a
/// single free section too is the string's equations (its states are the string's).
pub fn build_string_exchange(
    config: StringConfig,
    params: StringParams,
    t_start: f64,
    tolerance: f64,
) -> Result<Box<dyn StringSimulator>, SimError> {
    let mut sim = build_string(config, params.clone(), t_start, tolerance)?;
    if single::applies(&params) {
        sim = build_band(config, params, t_start, sim.tolerance());
    }
    sim.set_exchange();
    Ok(sim)
}

/// The string on its band integrator, of its law.
fn build_band(
    config: StringConfig,
    params: StringParams,
    t_start: f64,
    tol: f64,
) -> Box<dyn StringSimulator> {
    match config.law {
        Law::Dahl => Box::new(StringSim::<Dahl>::new(config, params, t_start, tol)),
        Law::Dupont => Box::new(StringSim::<Dupont>::new(config, params, t_start, tol)),
        Law::LuGre => Box::new(StringSim::<LuGre>::new(config, params, t_start, tol)),
    }
}

/// The string simulator of one law.
#[derive(Clone, Debug)]
struct StringSim<L> {
    model: StringModel<L>,
    radau: BandRadau,
    work: BandWork,
    /// The integrals over the communication step in progress of `F_Fx[i]` (N of them), `F_top`
    /// and `F_bottom`.
    integrals: Vec<f64>,
    /// The means over the last completed communication step, laid out as `integrals`.
    means: Vec<f64>,
    /// Each component's natural scale (the error scale at rest), for the sections integrated
    /// again alone.
    nominal: Vec<f64>,
    /// The work of the sections integrated again, and their integrator's scratch space.
    refined: SolverStats,
    /// Each section's step its last refinement would have taken next (0: never refined):
    /// where the next starts.
    own_steps: Vec<f64>,
    work3: Workspace,
    /// Scratch: the string's error scale at a step's start.
    scratch: Vec<f64>,
    /// Model Exchange: the step means are the instantaneous forces.
    exchange: bool,
    /// Model Exchange: each section's side of its event indicator (0 before the first event).
    sides: Vec<f64>,
}

impl<L: FrictionLaw> StringSim<L> {
    fn new(config: StringConfig, params: StringParams, t: f64, tol: f64) -> Self {
        let n = params.sections();
        let sections = (0..n).map(|i| Section::new(params.section(i))).collect();
        let sh = &params.shared;
        let harmonic = config
            .harmonic
            .then(|| Harmonic::new(sh.u0, sh.f, 0.0, sh.phase, t));
        let model = StringModel::new(
            sections,
            params.links.clone(),
            harmonic,
            StringInputs::zero(n, config.normal_input, &params.f_n, t),
        );
        let mut radau = BandRadau::new(t, vec![0.0; PER_SECTION * n], tol);
        radau.step_limit = sh.max_steps as u64;
        let mut sim = StringSim {
            model,
            radau,
            work: BandWork::new(PER_SECTION * n, 4, 3),
            integrals: vec![0.0; n + 2],
            means: vec![0.0; n + 2],
            nominal: vec![0.0; PER_SECTION * n],
            refined: SolverStats::default(),
            own_steps: vec![0.0; n],
            work3: Workspace::new(PER_SECTION),
            scratch: vec![0.0; PER_SECTION * n],
            exchange: false,
            sides: vec![0.0; n],
        };
        let zero = vec![0.0; PER_SECTION * n];
        sim.model.error_scale(&zero, &mut sim.nominal);
        // Before the first step the step means are the instantaneous forces.
        sim.means = sim.instantaneous();
        sim
    }

    /// `F_Fx[i]`, `F_top`, `F_bottom` now.
    fn instantaneous(&self) -> Vec<f64> {
        let (t, y) = (self.radau.t, &self.radau.y);
        let n = self.model.n();
        let mut out: Vec<f64> = (0..n)
            .map(|i| {
                self.model
                    .contact(i, t, y[PER_SECTION * i + 1], y[PER_SECTION * i + 2])
                    .1
            })
            .collect();
        let ends = self.model.ends(t, y);
        out.push(ends.top);
        out.push(ends.bottom);
        out
    }

    fn track(&mut self, input: StringInput) -> Result<&mut InputTrack, SimError> {
        let n = self.model.n();
        let missing =
            || SimError::Inconsistent(format!("{}: this string has no such input", input.name()));
        let inputs = &mut self.model.inputs;
        match input {
            StringInput::Fd(i) if i < n => Ok(&mut inputs.f_d[i]),
            StringInput::Vsx(i) if i < n => Ok(&mut inputs.v_sx[i]),
            StringInput::Fn(i) => inputs.f_n.get_mut(i).ok_or_else(missing),
            StringInput::VTop => Ok(&mut inputs.v_top),
            StringInput::VBottom => Ok(&mut inputs.v_bottom),
            _ => Err(missing()),
        }
    }

    /// Re-anchors one input's track at the current time (its value and slope there), keeping
    /// an end's position exact.
    fn anchor(&mut self, input: StringInput) -> Result<&mut InputTrack, SimError> {
        let t = self.radau.t;
        let inp = &mut self.model.inputs;
        match input {
            StringInput::VTop => inp.x_top_ref = inp.x_top(t),
            StringInput::VBottom => inp.x_bottom_ref = inp.x_bottom(t),
            _ => {}
        }
        let tr = self.track(input)?;
        tr.value = tr.at(t);
        tr.t_ref = t;
        Ok(tr)
    }

    /// Re-anchors every track at the current time, keeping the ends' positions exact.
    fn anchor_tracks(&mut self) {
        let t = self.radau.t;
        let inp = &mut self.model.inputs;
        inp.x_top_ref = inp.x_top(t);
        inp.x_bottom_ref = inp.x_bottom(t);
        for tr in inp
            .f_d
            .iter_mut()
            .chain(inp.v_sx.iter_mut())
            .chain(inp.f_n.iter_mut())
            .chain([&mut inp.v_top, &mut inp.v_bottom])
        {
            tr.hold_from(t);
        }
    }
}

/// Takes an accepted step of the string: integrates again alone the sections whose own error
/// failed (`refine.rs`), their neighbours on the step, and adds the step's integrals of every
/// section's friction and of the end forces (the collocation quadrature of the step, the
/// sections' own integrals where they were integrated again).
#[allow(clippy::too_many_arguments)]
fn accept_step<L: FrictionLaw>(
    model: &StringModel<L>,
    step: Accepted<'_>,
    integrals: &mut [f64],
    nominal: &[f64],
    scratch: &mut [f64],
    tol: f64,
    work3: &mut Workspace,
    stats: &mut SolverStats,
    own_steps: &mut [f64],
) -> Result<(), SolverError> {
    let n = model.n();
    let (t, h) = (step.t, step.h);
    // The sections integrated again, alone or in runs, against the string's step; then (after
    // the step's integrals) their new states and the links' impulses made to agree
    // (`refine::reflux`; a run's inner links agree by themselves).
    let mut refined: Vec<(usize, refine::Refined)> = Vec::with_capacity(step.refine.len());
    if !step.refine.is_empty() {
        model.error_scale(step.y0, scratch);
    }
    // Runs of sections side by side whose errors failed: together where one of them is far
    // off (`run.rs`: integrated alone against its trajectory of the step, its neighbours
    // would be as far off), else each alone.
    let mut at = 0;
    while at < step.refine.len() {
        let first = step.refine[at];
        let mut len = 1;
        while step.refine.get(at + len) == Some(&(first + len)) {
            len += 1;
        }
        if !step.far[at..at + len].contains(&true) {
            len = 1;
        }
        at += len;
        let from = refined.len();
        if len == 1 {
            let x_scale = scratch[PER_SECTION * first];
            let r = refine::refine(
                model,
                first,
                t,
                step.t1,
                step.y0,
                step.stages,
                nominal,
                x_scale,
                tol,
                own_steps[first],
                work3,
            )?;
            refined.push((first, r));
        } else {
            let run = run::refine_run(
                model,
                (first, len),
                t,
                step.t1,
                step.y0,
                step.stages,
                (nominal, scratch),
                tol,
                own_steps,
            )?;
            refined.extend((first..).zip(run));
        }
        for (i, r) in &refined[from..] {
            own_steps[*i] = r.next_step;
            stats.steps += r.stats.steps;
            stats.rejected += r.stats.rejected;
            stats.rhs_evals += r.stats.rhs_evals;
            stats.jacobians += r.stats.jacobians;
            stats.events += r.stats.events;
        }
    }
    // The integrals on the stages Newton solved, before `reflux` corrects the last one.
    let stages = &*step.stages;
    let ends: [_; 3] = std::array::from_fn(|k| model.ends(t + C[k] * h, &stages[k]));
    let mut next = refined.iter().peekable();
    for (i, integral) in integrals[..n].iter_mut().enumerate() {
        if let Some((_, r)) = next.next_if(|(j, _)| *j == i) {
            *integral += r.friction;
            continue;
        }
        let (kv, ks) = (PER_SECTION * i + 1, PER_SECTION * i + 2);
        if model.law(i, t).envelope() == 0.0 {
            // No dry friction at the step's start (no load): the quadrature itself, which is
            // exactly 0 where the law has no viscous term either.
            for (k, y) in stages.iter().enumerate() {
                *integral += B[k] * h * model.contact(i, t + C[k] * h, y[kv], y[ks]).1;
            }
            continue;
        }
        // The friction's impulse is what pushed the section less its change of momentum: Radau
        // IIA's last stage is the step's end, `v(t + h) − v(t) = h·Σ B[k]·dv/dt(stage k)`, so
        // this is the collocation quadrature of the friction itself (to the Newton iteration's
        // residual), without the law's evaluations at the stages again.
        let mut push = 0.0;
        for (k, (y, ends)) in stages.iter().zip(&ends).enumerate() {
            push += B[k] * h * model.pushing(i, t + C[k] * h, y, ends);
        }
        *integral += push - (stages[2][kv] - step.y0[kv]) * model.sections[i].params.m;
    }
    // The end forces: by the collocation quadrature, or from the position integral and the
    // displacement of an end section integrated again (the ends' points in closed form).
    let own = |i: usize| refined.iter().find(|o| o.0 == i).map(|o| &o.1);
    let (l, inp) = (&model.links, &model.inputs);
    let last = PER_SECTION * (n - 1);
    let (x_top_int, x_bottom_int) = inp.end_position_integrals(t, step.t1);
    integrals[n] += match own(0) {
        Some(r) => {
            l.k_top * (x_top_int - r.position)
                + l.c_top * ((inp.x_top(step.t1) - inp.x_top(t)) - (r.y[0] - step.y0[0]))
        }
        None => (0..3).map(|k| B[k] * h * ends[k].top).sum(),
    };
    integrals[n + 1] += match own(n - 1) {
        Some(r) => {
            l.k_bottom * (r.position - x_bottom_int)
                + l.c_bottom
                    * ((r.y[0] - step.y0[last]) - (inp.x_bottom(step.t1) - inp.x_bottom(t)))
        }
        None => (0..3).map(|k| B[k] * h * ends[k].bottom).sum(),
    };
    if !refined.is_empty() {
        refine::reflux(model, h, step.y0, step.stages, &refined);
    }
    Ok(())
}

impl<L: FrictionLaw> StringSimulator for StringSim<L> {
    fn sections(&self) -> usize {
        self.model.n()
    }

    fn time(&self) -> f64 {
        self.radau.t
    }

    fn tolerance(&self) -> f64 {
        self.radau.tolerance()
    }

    fn set_input(&mut self, input: StringInput, value: f64) -> Result<(), SimError> {
        self.set_inputs(&[(input, value)])
    }

    fn set_input_derivative(&mut self, input: StringInput, value: f64) -> Result<(), SimError> {
        self.set_input_derivatives(&[(input, value)])
    }

    /// Checked all first, then set in place: no copy of the string (a hundred sections' copy
    /// cost more than their step). As the single contact: each input alone re-anchored at the
    /// current time, its derivative kept; a value it already has there changes nothing.
    fn set_inputs(&mut self, values: &[(StringInput, f64)]) -> Result<(), SimError> {
        for &(input, value) in values {
            input.check(value)?;
            self.track(input)?;
        }
        let t = self.radau.t;
        for &(input, value) in values {
            let tr = self.track(input)?;
            if tr.value.to_bits() == value.to_bits() && tr.t_ref == t {
                continue;
            }
            self.anchor(input)?.value = value;
            self.radau.restart();
        }
        Ok(())
    }

    fn set_input_derivatives(&mut self, values: &[(StringInput, f64)]) -> Result<(), SimError> {
        for &(input, value) in values {
            input.check_derivative(value)?;
            self.track(input)?;
        }
        for &(input, value) in values {
            self.anchor(input)?.slope = value;
            self.radau.restart();
        }
        Ok(())
    }

    fn step_to(&mut self, t_end: f64) -> Result<(), SimError> {
        let t0 = self.radau.t;
        // The communication point the importer meant, as the single contact takes it: masters
        // that reach k·h by other arithmetic (t += h, integer nanoseconds) step to the same
        // instants and get the same numbers, bit for bit.
        let t_end = match canonical_time(t_end) {
            c if c > t0 => c,
            _ => t_end,
        };
        if !(t_end.is_finite() && t_end > t0) {
            return Err(SimError::Time {
                now: t0,
                target: t_end,
            });
        }
        let saved = (self.radau.clone(), self.refined, self.own_steps.clone());
        self.model.hold_loads();
        let model = &self.model;
        let integrals = &mut self.integrals;
        integrals.fill(0.0);
        let (nominal, work3, refined) = (&self.nominal, &mut self.work3, &mut self.refined);
        let own_steps = &mut self.own_steps;
        let scratch = &mut self.scratch;
        let tol = self.radau.tolerance();
        let result = self.radau.integrate(model, &mut self.work, t_end, |step| {
            accept_step(
                model, step, integrals, nominal, scratch, tol, work3, refined, own_steps,
            )
        });
        if let Err(e) = result {
            (self.radau, self.refined, self.own_steps) = saved;
            return Err(SimError::Solver(e));
        }
        let span = t_end - t0;
        for (m, i) in self.means.iter_mut().zip(&self.integrals) {
            *m = i / span;
        }
        // Input derivatives hold for one step: the inputs are held from here on.
        let sloped = {
            let inp = &self.model.inputs;
            inp.f_d
                .iter()
                .chain(&inp.v_sx)
                .chain(&inp.f_n)
                .chain([&inp.v_top, &inp.v_bottom])
                .any(|tr| tr.slope != 0.0)
        };
        self.anchor_tracks();
        if sloped {
            self.radau.restart();
        }
        Ok(())
    }

    fn outputs(&self) -> StringOutputs {
        let n = self.model.n();
        let y = &self.radau.y;
        let now = self.instantaneous();
        let means = if self.exchange { &now } else { &self.means };
        StringOutputs {
            x: (0..n).map(|i| y[PER_SECTION * i]).collect(),
            v_x: (0..n).map(|i| y[PER_SECTION * i + 1]).collect(),
            s_x: (0..n).map(|i| y[PER_SECTION * i + 2]).collect(),
            f_fx: now[..n].to_vec(),
            f_fx_step: means[..n].to_vec(),
            f_link: (0..n.saturating_sub(1))
                .map(|i| self.model.link(i, y))
                .collect(),
            f_top: now[n],
            f_bottom: now[n + 1],
            f_top_step: means[n],
            f_bottom_step: means[n + 1],
        }
    }

    fn stats(&self) -> StepStats {
        let mut s: StepStats = self.radau.stats.into();
        s.rhs_evals += self.refined.rhs_evals;
        s.jacobians += self.refined.jacobians;
        s.events += self.refined.events;
        s
    }

    fn section_steps(&self) -> u64 {
        self.refined.steps + self.refined.rejected
    }

    fn clone_box(&self) -> Box<dyn StringSimulator> {
        Box::new(self.clone())
    }

    fn save(&self) -> Vec<f64> {
        let mut out = vec![];
        self.radau.save(&mut out);
        let inp = &self.model.inputs;
        for tr in inp
            .f_d
            .iter()
            .chain(&inp.v_sx)
            .chain(&inp.f_n)
            .chain([&inp.v_top, &inp.v_bottom])
        {
            out.extend_from_slice(&[tr.t_ref, tr.value, tr.slope]);
        }
        out.extend_from_slice(&[inp.x_top_ref, inp.x_bottom_ref]);
        out.extend(self.integrals.iter().chain(&self.means).chain(&self.sides));
        out.extend(&self.own_steps);
        out
    }

    fn restore(&mut self, data: &[f64]) -> Result<(), SimError> {
        let bad = |why: &str| SimError::Inconsistent(format!("the saved string state {why}"));
        let n = self.model.n();
        let dim = PER_SECTION * n;
        let radau_len = BandRadau::saved_len(dim);
        let tracks = 2 * n + self.model.inputs.f_n.len() + 2;
        // Saved before the sections' own steps were kept: without them (each refinement then
        // starts afresh).
        let before_own = radau_len + 3 * tracks + 2 + 2 * (n + 2) + n;
        if data.len() != before_own && data.len() != before_own + n {
            return Err(bad("has the wrong length for this string"));
        }
        if data.iter().any(|x| !x.is_finite()) {
            return Err(bad("holds a number that is not finite"));
        }
        let radau = BandRadau::load(&data[..radau_len], dim, self.radau.step_limit)
            .ok_or_else(|| bad("does not describe this string's integrator"))?;
        let mut inputs = self.model.inputs.clone();
        let mut it = data[radau_len..].chunks(3);
        for tr in inputs
            .f_d
            .iter_mut()
            .chain(inputs.v_sx.iter_mut())
            .chain(inputs.f_n.iter_mut())
            .chain([&mut inputs.v_top, &mut inputs.v_bottom])
        {
            let c = it.next().ok_or_else(|| bad("is truncated"))?;
            *tr = InputTrack {
                t_ref: c[0],
                value: c[1],
                slope: c[2],
            };
        }
        let rest = &data[radau_len + 3 * tracks..];
        inputs.x_top_ref = rest[0];
        inputs.x_bottom_ref = rest[1];
        let sides = &rest[2 + 2 * (n + 2)..2 + 2 * (n + 2) + n];
        let own_steps = &rest[2 + 2 * (n + 2) + n..];
        if own_steps.iter().any(|h| *h < 0.0) {
            return Err(bad("holds a section's own step that is negative"));
        }
        if sides.iter().any(|x| ![-1.0, 0.0, 1.0].contains(x)) {
            return Err(bad(
                "holds an event indicator's side that is not -1, 0 or 1",
            ));
        }
        self.sides = sides.to_vec();
        self.own_steps = if own_steps.is_empty() {
            vec![0.0; n]
        } else {
            own_steps.to_vec()
        };
        self.integrals = rest[2..2 + n + 2].to_vec();
        self.means = rest[2 + n + 2..2 + 2 * (n + 2)].to_vec();
        self.model.inputs = inputs;
        self.radau = radau;
        Ok(())
    }

    fn place(&mut self, t: f64, y: &[f64]) -> Result<(), SimError> {
        if y.len() != self.radau.y.len() || !t.is_finite() || y.iter().any(|v| !v.is_finite()) {
            return Err(SimError::Inconsistent(format!(
                "a string of {} sections placed at t = {} with {} finite states",
                self.model.n(),
                number(t),
                y.iter().filter(|v| v.is_finite()).count()
            )));
        }
        self.radau.t = t;
        self.radau.y.copy_from_slice(y);
        self.radau.restart();
        Ok(())
    }
}
