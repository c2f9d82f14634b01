//! The support velocity at the stage times of the explicit paths' Dormand–Prince steps
//! (`explicit.rs`, `explicit_planar.rs`): the harmonic source's by rotations of its phase, two
//! sines and cosines per attempt rather than a cosine at each of its five distinct stage
//! times; the input tracks' at each time.

use super::drive::DriveKind;
use super::dynamics::Dynamics;
use crate::physics::{trig, FrictionLaw, Harmonic, InputTrack, Vector};
use crate::solver::dopri::C;
use crate::table::InputId;
use std::marker::PhantomData;

/// The product of two rotations given as (cosine, sine).
#[inline(always)]
pub(super) fn rot(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 * b.0 - a.1 * b.1, a.1 * b.0 + a.0 * b.1)
}

/// The rotations by the phase `omega·C[i]·h` over the stages of a step of length `h` ([`C`]),
/// from those over `h/10` and `h/9`, and the rotation over the whole step.
#[inline(always)]
pub(super) fn stage_rotations(omega: f64, h: f64) -> ([(f64, f64); 7], (f64, f64)) {
    let (s, c) = trig::sin_cos(0.1 * omega * h);
    let (s9, c9) = trig::sin_cos(omega * h / 9.0);
    let r1 = (c, s);
    let r2 = rot(r1, r1);
    let r3 = rot(r2, r1);
    let r4 = rot(r2, r2);
    let r8 = rot(r4, r4);
    let whole = rot(r8, r2);
    let r89 = rot(whole, (c9, -s9));
    ([(1.0, 0.0), r2, r3, r8, r89, whole, whole], whole)
}

/// The support velocity of one contact at the stage times of its explicit steps, in the
/// contact's `V::DIM` dimensions.
pub(super) struct StageSupport<V> {
    /// The harmonic source, if any.
    harmonic: Option<Harmonic>,
    /// Its velocity amplitude `v_a` (0 without one), that along x, its direction and its
    /// angular frequency.
    v_a: f64,
    amp_x: f64,
    dir: (f64, f64),
    omega: f64,
    /// The phase's cosine and sine at the last attempt's start and end (a time NaN until it
    /// is known). An attempt from either carries the phase on by rotations; one from
    /// elsewhere (after steps that took the support otherwise) takes it afresh, so that the
    /// rotations' rounding adds up over at most the steps of one call.
    known: [(f64, (f64, f64)); 2],
    /// The support velocity inputs along x and y, when they are enabled.
    tracks: Option<[InputTrack; 2]>,
    dim: PhantomData<V>,
}

impl<V: Vector> StageSupport<V> {
    /// The support of `dynamics` (with the velocity inputs where `input_support`), its phase
    /// known at `t`.
    pub(super) fn new<L: FrictionLaw, D: DriveKind<V>>(
        dynamics: &Dynamics<V, L, D>,
        input_support: bool,
        t: f64,
    ) -> Self {
        let tracks = input_support
            .then(|| [InputId::VSx, InputId::VSy].map(|id| dynamics.tracks[id.index()]));
        let h = dynamics.harmonic;
        let mut support = StageSupport {
            harmonic: h,
            v_a: h.map_or(0.0, |h| h.v_a()),
            amp_x: h.map_or(0.0, |h| h.v_a() * h.dir.0),
            dir: h.map_or((0.0, 0.0), |h| h.dir),
            omega: h.map_or(0.0, |h| std::f64::consts::TAU * h.f),
            known: [(f64::NAN, (1.0, 0.0)); 2],
            tracks,
            dim: PhantomData,
        };
        support.known[0] = (t, support.phase(t));
        support
    }

    /// The harmonic source's phase at `t` as (cosine, sine): known, or afresh.
    #[inline(always)]
    fn phase(&self, t: f64) -> (f64, f64) {
        let [(t0, p0), (t1, p1)] = self.known;
        if t == t0 {
            p0
        } else if t == t1 {
            p1
        } else if let Some(h) = &self.harmonic {
            let (sin, cos) = trig::sin_cos(h.theta(t));
            (cos, sin)
        } else {
            (1.0, 0.0)
        }
    }

    /// The input tracks' velocity at `t` (0 without them).
    #[inline(always)]
    fn tracks_at(&self, t: f64) -> V {
        self.tracks
            .map_or(V::default(), |[x, y]| V::from_xy(x.at(t), y.at(t)))
    }

    /// The support velocity at the stage times `t + C[i]·h` of a step from `t`; the phase
    /// then known at the step's start and end.
    #[inline(always)]
    pub(super) fn stages(&mut self, t: f64, h: f64) -> [V; 7] {
        let mut w = [V::default(); 7];
        if self.harmonic.is_some() {
            let phase = self.phase(t);
            let (rotations, whole) = stage_rotations(self.omega, h);
            for (wi, r) in w.iter_mut().zip(rotations) {
                let v = self.v_a * rot(phase, r).0;
                *wi = V::from_xy(v * self.dir.0, v * self.dir.1);
            }
            self.known = [(t, phase), (t + h, rot(phase, whole))];
        }
        if self.tracks.is_some() {
            for (wi, ci) in w.iter_mut().zip(C) {
                *wi = *wi + self.tracks_at(t + ci * h);
            }
        }
        w
    }

    /// Along x: the harmonic source's velocity amplitude, its angular frequency and phase
    /// (cosine, sine) at `t`, and the input track's velocity and slope there: what
    /// `elastic.rs`'s closed form takes (one dimension).
    #[inline(always)]
    pub(super) fn along_x(&self, t: f64) -> (f64, f64, (f64, f64), f64, f64) {
        let (c0, c1) = self.tracks.map_or((0.0, 0.0), |[x, _]| (x.at(t), x.slope));
        (self.amp_x, self.omega, self.phase(t), c0, c1)
    }

    /// The support velocity along x at `t`.
    #[inline(always)]
    pub(super) fn now(&self, t: f64) -> f64 {
        let (amp, _, phase, c0, _) = self.along_x(t);
        amp * phase.0 + c0
    }

    /// The support acceleration along x at `t`.
    #[inline(always)]
    pub(super) fn accel_now(&self, t: f64) -> f64 {
        let (amp, omega, phase, _, c1) = self.along_x(t);
        -amp * omega * phase.1 + c1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::contact::Contact;
    use crate::model::drive::Force;
    use crate::physics::{Dahl, Planar};
    use crate::table::{Config, Drive, Lateral, Law, Motion, Params};

    fn config(motion: Motion) -> Config {
        Config {
            law: Law::Dahl,
            motion,
            drive: Drive::Force,
            lateral: Lateral::Free,
            harmonic: true,
            input_support: true,
            normal_input: false,
        }
    }

    /// Sets the support velocity inputs to ramps.
    fn ramps<V: Vector, D: DriveKind<V>>(dynamics: &mut Dynamics<V, Dahl, D>) {
        for (id, value, slope) in [(InputId::VSx, 1e-3, 0.2), (InputId::VSy, -2e-3, -0.5)] {
            let track = &mut dynamics.tracks[id.index()];
            (track.value, track.slope) = (value, slope);
        }
    }

    /// The stage velocities by rotations agree with the source's own velocity at each stage
    /// time (a cosine each) within rounding, attempt after attempt from a start known (a
    /// rejected attempt's, an accepted one's end) or not (afresh), with the input tracks
    /// added at each time; along x the velocity and acceleration at a step's start likewise.
    #[test]
    fn stage_velocities_are_the_sources() {
        let p = Params {
            f: 2000.0,
            angle: 0.7,
            ..Params::default()
        };
        let mut contact =
            Contact::<Planar, Dahl, Force, 6>::new_local(config(Motion::Planar), p, 1e-6);
        ramps(&mut contact.dynamics);
        let dynamics = contact.dynamics;
        let mut support = StageSupport::<Planar>::new(&dynamics, true, 0.1);
        let scale = dynamics.harmonic.unwrap().v_a() + 1e-3;
        let mut t = 0.1;
        // Rejected (the same start again), accepted twice, then a start not known.
        for (h, next) in [
            (3e-5, 0.0),
            (1e-5, 1.0),
            (7e-5, 1.0),
            (2e-5, 1.5),
            (4e-5, 0.0),
        ] {
            let w = support.stages(t, h);
            for (wi, ci) in w.iter().zip(C) {
                let want = dynamics.support_velocity(t + ci * h, true);
                assert!(
                    (*wi - want).norm() <= 1e-14 * (scale + want.norm()),
                    "t {t}, h {h}, c {ci}: {wi:?} vs {want:?}"
                );
            }
            t += next * h;
        }
        let q = Params { angle: 0.0, ..p };
        let mut line =
            Contact::<f64, Dahl, Force, 3>::new_local(config(Motion::Longitudinal), q, 1e-6);
        ramps(&mut line.dynamics);
        let dynamics = line.dynamics;
        let mut support = StageSupport::<f64>::new(&dynamics, true, 0.1);
        let h = 3e-5;
        support.stages(0.1, h);
        for t in [0.1, 0.1 + h] {
            let ((vx, _), (ax, _)) = dynamics.harmonic.unwrap().velocity_acceleration(t);
            let track = dynamics.tracks[InputId::VSx.index()];
            let (v, a) = (vx + track.at(t), ax + track.slope);
            assert!(
                (support.now(t) - v).abs() <= 1e-14 * (scale + v.abs()),
                "{t}"
            );
            // The rotated phase is within rounding of `theta(t)`, whose own rounding is
            // about `2·pi·f·t·1e-16` (3e-13 rad here).
            let acc = support.accel_now(t);
            assert!((acc - a).abs() <= 1e-12 * a.abs(), "{t}: {acc} vs {a}");
        }
    }
}
