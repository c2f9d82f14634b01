//! The equations of a string of contacts: `N` bodies in a line along x, section `i` on its own
//! contact of the scene's law, joined to section `i + 1` by a spring `k_s[i]` and a damper
//! `c_s[i]`, section 1 held by `k_top`, `c_top` to a point moving at `v_top`, section `N` by
//! `k_bottom`, `c_bottom` to a point moving at `v_bottom` (`docs/model.md`, "Strings of
//! contacts"):
//!
//! ```text
//! F_link[i] = k_s[i]·(x[i+1] − x[i]) + c_s[i]·(v[i+1] − v[i])            (tension positive)
//! F_top     = k_top·(x_top − x[1]) + c_top·(v_top − v[1])
//! F_bottom  = k_bottom·(x[N] − x_bottom) + c_bottom·(v[N] − v_bottom)
//! m[i]·dv[i]/dt = F_d[i] + F_link[i] − F_link[i−1] (+ F_top at 1, − F_bottom at N) − F_Fx[i]
//! ds[i]/dt = the law's rate at (s[i], v[i] − v_sx[i]),   F_Fx[i] = the law's force
//! ```
//!
//! The state is `[x_1, v_1, s_1, x_2, v_2, s_2, ...]`: each row couples a section only to its
//! neighbours, so the Jacobian is banded (4 sub-, 3 super-diagonals) and the stiff integrator's
//! work is linear in `N` ([`crate::solver::band`]).

use crate::physics::{FrictionLaw, Harmonic, InputTrack, LawJacobian};
use crate::solver::band::{Band, BandSystem};
use crate::table::Params;

use super::super::dynamics::loaded;

/// Components of the state per section.
pub const PER_SECTION: usize = 3;

/// The inputs of a string: one track per section for the drive force, the support velocity and
/// (where it is an input) the normal force; one for each end's moving point.
#[derive(Clone, Debug, PartialEq)]
pub struct StringInputs {
    pub f_d: Vec<InputTrack>,
    pub v_sx: Vec<InputTrack>,
    /// Empty where the normal force is a parameter.
    pub f_n: Vec<InputTrack>,
    pub v_top: InputTrack,
    pub v_bottom: InputTrack,
    /// The ends' points `x_top`, `x_bottom` at the tracks' reference times.
    pub x_top_ref: f64,
    pub x_bottom_ref: f64,
}

impl StringInputs {
    pub fn zero(n: usize, normal_input: bool, f_n: &[f64], t: f64) -> Self {
        let track = |value| InputTrack {
            t_ref: t,
            value,
            slope: 0.0,
        };
        StringInputs {
            f_d: vec![track(0.0); n],
            v_sx: vec![track(0.0); n],
            f_n: if normal_input {
                f_n.iter().map(|&v| track(v)).collect()
            } else {
                Vec::new()
            },
            v_top: track(0.0),
            v_bottom: track(0.0),
            x_top_ref: 0.0,
            x_bottom_ref: 0.0,
        }
    }

    /// The top point's position at `t`: the exact integral of its velocity.
    pub fn x_top(&self, t: f64) -> f64 {
        self.x_top_ref + self.v_top.integral(t)
    }

    pub fn x_bottom(&self, t: f64) -> f64 {
        self.x_bottom_ref + self.v_bottom.integral(t)
    }

    /// `∫ x_top dt` and `∫ x_bottom dt` from `t0` to `t1`, exactly (each point's position is
    /// quadratic in time between changes of its track).
    pub fn end_position_integrals(&self, t0: f64, t1: f64) -> (f64, f64) {
        let twice = |tr: &InputTrack, t: f64| {
            let d = t - tr.t_ref;
            d * d * (0.5 * tr.value + tr.slope * d / 6.0)
        };
        let h = t1 - t0;
        (
            self.x_top_ref * h + twice(&self.v_top, t1) - twice(&self.v_top, t0),
            self.x_bottom_ref * h + twice(&self.v_bottom, t1) - twice(&self.v_bottom, t0),
        )
    }
}

/// One section's contact: its law at its load (rebuilt from the load input where it is one) and
/// its mass.
#[derive(Clone, Copy, Debug)]
pub struct Section<L> {
    pub law: L,
    /// The section's parameters (its `m`, `mu`, `F_N`, `F_S` and the shared law parameters),
    /// with its own reference load, from which the law at an input load is scaled.
    pub params: Params,
    pub inv_m: f64,
}

impl<L: FrictionLaw> Section<L> {
    /// The section of parameters `p` (its own reference load).
    pub fn new(p: Params) -> Self {
        Section {
            law: L::new(&p),
            params: p,
            inv_m: 1.0 / p.m,
        }
    }
}

/// The ends and links.
#[derive(Clone, Debug, PartialEq)]
pub struct Links {
    /// `k_s[i]`, `c_s[i]` of the link between sections `i` and `i + 1` (N − 1 of each).
    pub k_s: Vec<f64>,
    pub c_s: Vec<f64>,
    pub k_top: f64,
    pub c_top: f64,
    pub k_bottom: f64,
    pub c_bottom: f64,
}

/// The right-hand side of the string: everything the integrator needs, nothing it changes.
/// The sections, links and harmonic support are fixed once built ([`StringModel::new`]: the
/// error scale's constants are taken from them there); the inputs change.
#[derive(Clone, Debug)]
pub struct StringModel<L> {
    pub(crate) sections: Vec<Section<L>>,
    pub(crate) links: Links,
    pub(crate) harmonic: Option<Harmonic>,
    pub inputs: StringInputs,
    /// Per section where the load is an input: the law at a load it held, with that load, so
    /// that a held load input does not rebuild its law at every evaluation
    /// ([`StringModel::hold_loads`]); a load that differs builds its own.
    pub held: Vec<(f64, L)>,
    /// Per section, what its error scale takes from the parameters alone
    /// ([`BandSystem::error_scale`]), built with the model.
    scale_base: Vec<ScaleBase>,
}

/// What a section's error scale takes from its parameters, the links' and the harmonic
/// support's: its position's floor, its velocity's and deformation's natural scales, the
/// stiffer of the springs that hold it and its Coulomb force.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ScaleBase {
    x: f64,
    v: f64,
    s: f64,
    k_spring: f64,
    f_c: f64,
}

/// The forces at one state: friction per section and the two ends (links are computed where
/// needed).
pub struct Forces {
    pub top: f64,
    pub bottom: f64,
}

impl<L: FrictionLaw> StringModel<L> {
    /// The string of `sections` joined by `links`, on the harmonic support `harmonic` (if
    /// any), with the input tracks `inputs`.
    pub fn new(
        sections: Vec<Section<L>>,
        links: Links,
        harmonic: Option<Harmonic>,
        inputs: StringInputs,
    ) -> Self {
        let u0 = harmonic.map_or(0.0, |h| h.u0);
        let v_a = harmonic.map_or(0.0, |h| h.v_a());
        let n = sections.len();
        let scale_base = sections
            .iter()
            .enumerate()
            .map(|(i, sec)| {
                let left = if i == 0 {
                    links.k_top
                } else {
                    links.k_s[i - 1]
                };
                let right = if i + 1 < n {
                    links.k_s[i]
                } else {
                    links.k_bottom
                };
                let s_nom = sec.law.s_scale();
                let v_nom = v_a
                    .max(s_nom * (sec.params.k_t / sec.params.m).sqrt())
                    .max(1e-9);
                let omega = ((sec.params.k_t + left + right) * sec.inv_m).sqrt();
                ScaleBase {
                    x: s_nom.max(u0).max(v_nom / omega),
                    v: v_nom,
                    s: s_nom,
                    k_spring: left.max(right),
                    f_c: sec.params.f_c(),
                }
            })
            .collect();
        StringModel {
            sections,
            links,
            harmonic,
            inputs,
            held: Vec::new(),
            scale_base,
        }
    }

    pub fn n(&self) -> usize {
        self.sections.len()
    }

    /// The law of section `i` at time `t` (at its load input where the load is one).
    #[inline(always)]
    pub fn law(&self, i: usize, t: f64) -> L {
        match self.inputs.f_n.get(i) {
            Some(track) => {
                let f_n = track.at(t).max(0.0);
                match self.held.get(i) {
                    Some(&(held, law)) if held == f_n => law,
                    _ => L::new(&loaded(&self.sections[i].params, f_n)),
                }
            }
            None => self.sections[i].law,
        }
    }

    /// Builds, for each load input that is held (no slope), the law at its value once: what
    /// [`StringModel::law`] then returns for it, the same numbers as built at every evaluation.
    pub fn hold_loads(&mut self) {
        let n = self.n();
        self.held.resize(
            self.inputs.f_n.len().min(n),
            (f64::NAN, self.sections[0].law),
        );
        for (i, track) in self.inputs.f_n.iter().enumerate() {
            let f_n = track.value.max(0.0);
            if track.slope == 0.0 && self.held[i].0 != f_n {
                self.held[i] = (f_n, L::new(&loaded(&self.sections[i].params, f_n)));
            }
        }
    }

    /// The support velocity under section `i` at `t`.
    #[inline(always)]
    pub fn support(&self, i: usize, t: f64) -> f64 {
        self.inputs.v_sx[i].at(t) + self.harmonic_velocity(t)
    }

    /// The harmonic source's velocity at `t` (0 without one), the same under every section.
    #[inline(always)]
    fn harmonic_velocity(&self, t: f64) -> f64 {
        self.harmonic.map_or(0.0, |h| h.velocity(t).0)
    }

    /// `(ds/dt, F_Fx)` of section `i` at `t` with velocity `v` and deformation `s`.
    #[inline(always)]
    pub fn contact(&self, i: usize, t: f64, v: f64, s: f64) -> (f64, f64) {
        self.contact_over(i, t, self.support(i, t), v, s)
    }

    /// [`StringModel::contact`] over a support moving at `w`.
    #[inline(always)]
    fn contact_over(&self, i: usize, t: f64, w: f64, v: f64, s: f64) -> (f64, f64) {
        let law = self.law(i, t);
        let vr = v - w;
        // One exponential where the law's two velocities are equal (LuGre's default).
        law.rate_force_at(s, vr, &law.velocity_terms(vr))
    }

    /// Section `i`'s law at `t`, its relative velocity `v_r`, deformation rate and the law's
    /// partial derivatives there (velocity `v`, deformation `s`).
    #[inline(always)]
    pub fn partials(&self, i: usize, t: f64, v: f64, s: f64) -> (L, f64, f64, LawJacobian) {
        let law = self.law(i, t);
        let vr = v - self.support(i, t);
        let ds = law.rate(s, vr);
        let lj = law.jacobian(s, vr, ds);
        (law, vr, ds, lj)
    }

    /// Section `i`'s rates `[dx/dt, dv/dt, ds/dt]` at `t` from its state `y`: its section
    /// data, drive force track and support velocity `w`, the forces of the links on either
    /// side `(F_link[i − 1], F_link[i])` (0 where there is none) and the end forces (those
    /// acting on it). What [`BandSystem::rhs`] and [`BandSystem::rhs_block`] both evaluate.
    #[inline(always)]
    fn section_rates(
        &self,
        i: usize,
        t: f64,
        (sec, f_d, w): (&Section<L>, &InputTrack, f64),
        y: &[f64; PER_SECTION],
        (left, right): (f64, f64),
        ends: &Forces,
    ) -> [f64; PER_SECTION] {
        let [_, v, s] = *y;
        let (ds, f) = self.contact_over(i, t, w, v, s);
        let force = self.with_ends(i, f_d.at(t) + right - left - f, ends);
        [v, force * sec.inv_m, ds]
    }

    /// `force` on section `i` with the end elements' forces `ends` that act on it added.
    #[inline(always)]
    fn with_ends(&self, i: usize, mut force: f64, ends: &Forces) -> f64 {
        if i == 0 {
            force += ends.top;
        }
        if i + 1 == self.n() {
            force -= ends.bottom;
        }
        force
    }

    /// The force on section `i` at `t` in the state `y` of the whole string other than its
    /// friction: its drive force, the links on either side and the end elements `ends` (those
    /// acting on it); [`StringModel::section_rates`]'s `m·dv/dt + F_Fx`.
    #[inline(always)]
    pub fn pushing(&self, i: usize, t: f64, y: &[f64], ends: &Forces) -> f64 {
        let mut force = self.inputs.f_d[i].at(t);
        if i > 0 {
            force -= self.link(i - 1, y);
        }
        if i + 1 < self.n() {
            force += self.link(i, y);
        }
        self.with_ends(i, force, ends)
    }

    /// The force in link `i` (between sections `i` and `i + 1`, 0-based), tension positive.
    #[inline(always)]
    pub fn link(&self, i: usize, y: &[f64]) -> f64 {
        let (a, b) = (PER_SECTION * i, PER_SECTION * (i + 1));
        self.link_between(i, &y[a..b], &y[b..])
    }

    /// The stiffness and damping that hold section `i` to its neighbours and end elements
    /// (its Jacobian's, in the string and where it is integrated again alone).
    pub(super) fn holding(&self, i: usize) -> (f64, f64) {
        let (l, n) = (&self.links, self.n());
        let (mut k_sum, mut c_sum) = (0.0, 0.0);
        if i > 0 {
            k_sum += l.k_s[i - 1];
            c_sum += l.c_s[i - 1];
        }
        if i + 1 < n {
            k_sum += l.k_s[i];
            c_sum += l.c_s[i];
        }
        if i == 0 {
            k_sum += l.k_top;
            c_sum += l.c_top;
        }
        if i + 1 == n {
            k_sum += l.k_bottom;
            c_sum += l.c_bottom;
        }
        (k_sum, c_sum)
    }

    /// `∂(dx/dt, dv/dt, ds/dt)/∂(x, v, s)` of section `i` at `t` with velocity `v` and
    /// deformation `s`, its neighbours held: the diagonal block of the string's Jacobian.
    fn own_block(&self, i: usize, t: f64, v: f64, s: f64) -> [[f64; PER_SECTION]; PER_SECTION] {
        let (_, _, _, lj) = self.partials(i, t, v, s);
        let inv_m = self.sections[i].inv_m;
        let (k_sum, c_sum) = self.holding(i);
        [
            [0.0, 1.0, 0.0],
            [
                -k_sum * inv_m,
                -(c_sum + lj.force_v[0][0]) * inv_m,
                -lj.force_s[0][0] * inv_m,
            ],
            [0.0, lj.rate_v[0][0], lj.rate_s[0][0]],
        ]
    }

    /// Section `i`'s rows of a Jacobian (its state `yi` at `t`), at rows and columns from `k`
    /// on: its own block, and its links' columns where the section before it and the one after
    /// it are unknowns of the same system (`left`, `right`; the string's, or a run's in
    /// `run.rs`).
    pub(super) fn section_jacobian(
        &self,
        i: usize,
        t: f64,
        yi: &[f64],
        k: usize,
        (left, right): (bool, bool),
        jac: &mut Band<f64>,
    ) {
        let l = &self.links;
        let inv_m = self.sections[i].inv_m;
        if left {
            jac.set(k + 1, k - PER_SECTION, l.k_s[i - 1] * inv_m);
            jac.set(k + 1, k - PER_SECTION + 1, l.c_s[i - 1] * inv_m);
        }
        if right {
            jac.set(k + 1, k + PER_SECTION, l.k_s[i] * inv_m);
            jac.set(k + 1, k + PER_SECTION + 1, l.c_s[i] * inv_m);
        }
        let own = self.own_block(i, t, yi[1], yi[2]);
        for (r, row) in own.iter().enumerate() {
            for (c, &v) in row.iter().enumerate() {
                jac.set(k + r, k + c, v);
            }
        }
    }

    /// The force in link `i` from the states `[x, v, ...]` of the sections it joins.
    #[inline(always)]
    fn link_between(&self, i: usize, a: &[f64], b: &[f64]) -> f64 {
        self.links.k_s[i] * (b[0] - a[0]) + self.links.c_s[i] * (b[1] - a[1])
    }

    /// The end forces at `t`: `F_top` on section 1, `F_bottom` of section N on its holder.
    #[inline(always)]
    pub fn ends(&self, t: f64, y: &[f64]) -> Forces {
        let last = PER_SECTION * (self.n() - 1);
        Forces {
            top: self.top_force(t, y[0], y[1]),
            bottom: self.bottom_force(t, y[last], y[last + 1]),
        }
    }

    /// `F_top` at `t` with the first section at position `x`, velocity `v`.
    #[inline(always)]
    pub fn top_force(&self, t: f64, x: f64, v: f64) -> f64 {
        let (l, inp) = (&self.links, &self.inputs);
        l.k_top * (inp.x_top(t) - x) + l.c_top * (inp.v_top.at(t) - v)
    }

    /// `F_bottom` at `t` with the last section at position `x`, velocity `v`.
    #[inline(always)]
    pub fn bottom_force(&self, t: f64, x: f64, v: f64) -> f64 {
        let (l, inp) = (&self.links, &self.inputs);
        l.k_bottom * (x - inp.x_bottom(t)) + l.c_bottom * (v - inp.v_bottom.at(t))
    }
}

impl<L: FrictionLaw> BandSystem for StringModel<L> {
    fn dim(&self) -> usize {
        PER_SECTION * self.n()
    }

    fn bands(&self) -> (usize, usize) {
        // v_i depends on x_{i−1} (4 columns left) and v_{i+1} (3 columns right).
        (4, 3)
    }

    /// As [`StringModel::contact`] and [`StringModel::link`] section by section, on the
    /// sections' chunks of the state (no bounds checks), the support's harmonic part once.
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.n();
        let ends = self.ends(t, y);
        let harmonic = self.harmonic_velocity(t);
        let (ys, _) = y[..PER_SECTION * n].as_chunks::<PER_SECTION>();
        let (dys, _) = dy[..PER_SECTION * n].as_chunks_mut::<PER_SECTION>();
        let inp = &self.inputs;
        let mut left = 0.0; // F_link[i − 1]
        let sections = self.sections.iter().zip(&inp.f_d).zip(&inp.v_sx);
        for (i, ((((sec, f_d), v_sx), yi), dyi)) in sections.zip(ys).zip(dys).enumerate() {
            let right = match ys.get(i + 1) {
                Some(next) => self.link_between(i, yi, next),
                None => 0.0,
            };
            let w = v_sx.at(t) + harmonic;
            *dyi = self.section_rates(i, t, (sec, f_d, w), yi, (left, right), &ends);
            left = right;
        }
    }

    /// Section `k`'s rows of [`Self::rhs`], through the same [`StringModel::section_rates`]
    /// (the same bits).
    fn rhs_block(&self, t: f64, y: &[f64], k: usize, out: &mut [f64]) {
        let n = self.n();
        let (ys, _) = y[..PER_SECTION * n].as_chunks::<PER_SECTION>();
        let yk = &ys[k];
        let left = match k.checked_sub(1) {
            Some(j) => self.link_between(j, &ys[j], yk),
            None => 0.0,
        };
        let right = match ys.get(k + 1) {
            Some(next) => self.link_between(k, yk, next),
            None => 0.0,
        };
        // Only the ends acting on this section.
        let last = PER_SECTION * (n - 1);
        let ends = Forces {
            top: if k == 0 {
                self.top_force(t, y[0], y[1])
            } else {
                0.0
            },
            bottom: if k + 1 == n {
                self.bottom_force(t, y[last], y[last + 1])
            } else {
                0.0
            },
        };
        let (sec, f_d) = (&self.sections[k], &self.inputs.f_d[k]);
        let rates = self.section_rates(
            k,
            t,
            (sec, f_d, self.support(k, t)),
            yk,
            (left, right),
            &ends,
        );
        out[..PER_SECTION].copy_from_slice(&rates);
    }

    /// An eighth of the sections (none below 8): an iteration of one section alone costs about
    /// a hundredth of the string's, so a few of them pay where the rest has converged.
    fn max_local(&self) -> usize {
        self.n() / 8
    }

    fn jacobian(&self, t: f64, y: &[f64], jac: &mut Band<f64>) {
        let n = self.n();
        for i in 0..n {
            let k = PER_SECTION * i;
            self.section_jacobian(i, t, &y[k..k + PER_SECTION], k, (i > 0, i + 1 < n), jac);
        }
    }

    /// Section `k`'s own rows and columns of [`Self::jacobian`], through the same
    /// [`StringModel::own_block`].
    fn jacobian_block(&self, t: f64, y: &[f64], k: usize, out: &mut [f64]) -> bool {
        let at = PER_SECTION * k;
        let own = self.own_block(k, t, y[at + 1], y[at + 2]);
        for (o, v) in out.iter_mut().zip(own.as_flattened()) {
            *o = *v;
        }
        true
    }

    /// The velocity and the deformation to their natural scales plus their magnitudes; a
    /// position to what moves the forces of the springs that hold the section (its links and
    /// end elements) by the section's Coulomb force plus their magnitude (a position matters
    /// only through the springs it stretches: the links feel differences of positions, not the
    /// distance travelled), and at least to the deformation scale and what the velocity's
    /// scale is in position over the section's fastest time constant `sqrt(m/k)` (`k` the
    /// contact's and links' stiffness together).
    fn error_scale(&self, y: &[f64], out: &mut [f64]) {
        let n = self.n();
        let ends = self.ends(self.inputs.v_top.t_ref, y);
        // |force| of the spring on each side of the section.
        let mut left = ends.top.abs();
        for (i, b) in self.scale_base.iter().enumerate() {
            let k = PER_SECTION * i;
            let right = if i + 1 < n {
                self.link(i, y).abs()
            } else {
                ends.bottom.abs()
            };
            let mut x_scale = b.x;
            if b.k_spring > 0.0 {
                x_scale = x_scale.max((b.f_c + left.max(right)) / b.k_spring);
            }
            out[k] = x_scale;
            out[k + 1] = b.v + y[k + 1].abs();
            out[k + 2] = b.s + y[k + 2].abs();
            left = right;
        }
    }

    /// A section (position, velocity, deformation) is a block: where its own error fails in a
    /// step it is integrated again alone (`refine.rs`).
    fn block(&self) -> usize {
        PER_SECTION
    }

    /// A quarter of the sections, at least one.
    fn max_refined(&self) -> usize {
        (self.n() / 4).max(1)
    }

    /// Each section is `[x, v, s]`: its position moves at its velocity, its deformation's rate
    /// is its own contact's, its velocity feels its neighbours through the links.
    fn chain(&self) -> bool {
        true
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::model::string::StringParams;
    use crate::physics::{Dahl, Dupont, LuGre};

    /// Numbers in [−1, 1), the same every run (a linear congruential generator).
    struct Numbers(u64);

    impl Numbers {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// A string of `n` sections of different masses and loads, both ends held by moving
    /// points, every input a track with a slope; where the load is an input, sections 0, 3,
    /// 6, ... hold theirs (the law built once), the others ramp (built at each evaluation), one
    /// of them below 0 (no load).
    pub(in crate::model::string) fn model<L: FrictionLaw>(
        n: usize,
        harmonic: bool,
        normal_input: bool,
    ) -> StringModel<L> {
        let mut r = Numbers(n as u64 + 7);
        let shared = Params {
            h_v: 20.0,
            ..Params::default()
        };
        let mut p = StringParams::uniform(n, shared, 1e5, 10.0);
        for i in 0..n {
            p.m[i] *= 1.0 + 0.5 * r.next();
            p.f_n[i] *= 1.0 + 0.5 * r.next();
        }
        p.links.k_top = 2e4;
        p.links.c_top = 5.0;
        p.links.k_bottom = 3e4;
        p.links.c_bottom = 7.0;
        let sections = (0..n).map(|i| Section::new(p.section(i))).collect();
        let t0 = 0.01;
        let mut inputs = StringInputs::zero(n, normal_input, &p.f_n, t0);
        let mut ramp = |tr: &mut InputTrack, value: f64, slope: f64| {
            tr.value = value * (1.0 + 0.3 * r.next());
            tr.slope = slope * r.next();
        };
        for i in 0..n {
            ramp(&mut inputs.f_d[i], 3.0, 100.0);
            ramp(&mut inputs.v_sx[i], 2e-4, 0.1);
            if normal_input {
                let hold = i % 3 == 0;
                ramp(&mut inputs.f_n[i], p.f_n[i], if hold { 0.0 } else { 1e4 });
            }
        }
        if normal_input && n > 1 {
            inputs.f_n[1].value = -1.0;
        }
        ramp(&mut inputs.v_top, 1.2e-3, 0.5);
        ramp(&mut inputs.v_bottom, -0.5e-3, 0.5);
        inputs.x_top_ref = 2e-6;
        inputs.x_bottom_ref = -1e-6;
        let mut m = StringModel::new(
            sections,
            p.links.clone(),
            harmonic.then(|| Harmonic::new(2e-6, 150.0, 0.0, 0.3, t0)),
            inputs,
        );
        m.hold_loads();
        m
    }

    /// Every law, with and without the harmonic support and the load as input, strings of 1,
    /// 2, 3 and 7 sections, states from sticking to sliding either way: each section's rows
    /// of `rhs_block` are those of `rhs`, bit for bit.
    fn rows_are_the_rhs<L: FrictionLaw>() {
        for n in [1, 2, 3, 7] {
            for harmonic in [false, true] {
                for normal_input in [false, true] {
                    let m = model::<L>(n, harmonic, normal_input);
                    let mut r = Numbers(99);
                    let mut y = vec![0.0; PER_SECTION * n];
                    let (mut dy, mut rows) = (vec![0.0; y.len()], [0.0; PER_SECTION]);
                    for trial in 0..20 {
                        let t = 0.01 + 1e-4 * trial as f64;
                        for (i, yi) in y.chunks_mut(PER_SECTION).enumerate() {
                            let s_ss = m.sections[i].params.f_c() / m.sections[i].params.k_t;
                            yi[0] = 1e-5 * r.next();
                            yi[1] = 5e-3 * r.next();
                            yi[2] = 1.2 * s_ss * r.next();
                        }
                        m.rhs(t, &y, &mut dy);
                        for k in 0..n {
                            m.rhs_block(t, &y, k, &mut rows);
                            let at = PER_SECTION * k;
                            for (j, (a, b)) in rows.iter().zip(&dy[at..]).enumerate() {
                                assert_eq!(
                                    a.to_bits(),
                                    b.to_bits(),
                                    "n {n} harmonic {harmonic} load input {normal_input} \
                                     section {k} row {j}: {a} against {b}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// Each section's `jacobian_block` against central differences of its `rhs_block` (every
    /// law, with and without the harmonic support and the load as input, sliding either way),
    /// and equal to the diagonal block of the string's band Jacobian bit for bit.
    fn blocks_are_the_derivatives<L: FrictionLaw>() {
        for n in [1, 3, 7] {
            for harmonic in [false, true] {
                for normal_input in [false, true] {
                    let m = model::<L>(n, harmonic, normal_input);
                    let mut r = Numbers(5);
                    let mut y = vec![0.0; PER_SECTION * n];
                    let mut band = Band::zeros(y.len(), 4, 3);
                    for trial in 0..10 {
                        let t = 0.01 + 1e-4 * trial as f64;
                        let mut scales = vec![[0.0; PER_SECTION]; n];
                        for (i, yi) in y.chunks_mut(PER_SECTION).enumerate() {
                            let s_ss = m.sections[i].params.f_c() / m.sections[i].params.k_t;
                            // Away from a reversal, where the rates are smooth.
                            let v = 5e-3 * r.next();
                            yi[0] = 1e-5 * r.next();
                            yi[1] = v + 2e-3 * v.signum();
                            yi[2] = 0.8 * s_ss * r.next();
                            scales[i] = [1e-5, 5e-3, s_ss];
                        }
                        band.clear();
                        m.jacobian(t, &y, &mut band);
                        for (k, scale) in scales.iter().enumerate() {
                            let mut block = [0.0; PER_SECTION * PER_SECTION];
                            assert!(m.jacobian_block(t, &y, k, &mut block));
                            let at = PER_SECTION * k;
                            for (e, j) in block.iter().enumerate() {
                                let (row, col) = (e / PER_SECTION, e % PER_SECTION);
                                let b = band.get(at + row, at + col);
                                assert_eq!(j.to_bits(), b.to_bits(), "section {k} ({row}, {col})");
                            }
                            for col in 0..PER_SECTION {
                                let d = 1e-6 * scale[col];
                                let (mut up, mut down) = (y.clone(), y.clone());
                                up[at + col] += d;
                                down[at + col] -= d;
                                let (mut fu, mut fd) = ([0.0; PER_SECTION], [0.0; PER_SECTION]);
                                m.rhs_block(t, &up, k, &mut fu);
                                m.rhs_block(t, &down, k, &mut fd);
                                for row in 0..PER_SECTION {
                                    let fdiff = (fu[row] - fd[row]) / (2.0 * d);
                                    let j = block[row * PER_SECTION + col];
                                    // Against the row's largest term, each column on its scale.
                                    let size = (0..PER_SECTION)
                                        .map(|c| {
                                            (block[row * PER_SECTION + c] * scales[k][c]).abs()
                                        })
                                        .fold(0.0, f64::max);
                                    assert!(
                                        ((j - fdiff) * scales[k][col]).abs()
                                            <= 1e-6 * size + 1e-300,
                                        "n {n} harmonic {harmonic} load input {normal_input} \
                                         section {k} ({row}, {col}): {j} against {fdiff}"
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn a_sections_block_of_the_jacobian_is_its_derivative() {
        blocks_are_the_derivatives::<Dahl>();
        blocks_are_the_derivatives::<Dupont>();
        blocks_are_the_derivatives::<LuGre>();
    }

    #[test]
    fn a_section_alone_has_the_rows_of_the_whole_string() {
        rows_are_the_rhs::<Dahl>();
        rows_are_the_rhs::<Dupont>();
        rows_are_the_rhs::<LuGre>();
    }
}
