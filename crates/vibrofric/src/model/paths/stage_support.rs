//! The support velocity at the stage times of the explicit paths' Dormand–Prince steps
//! (`explicit/`, `explicit_planar/`): the harmonic source's by rotations of its phase, two
//! sines and cosines per attempt rather than a cosine at each of its five distinct stage
//! times; the input tracks' at each time.

use crate::model::drive::DriveKind;
use crate::model::dynamics::Dynamics;
use crate::physics::{trig, FrictionLaw, Harmonic, InputTrack, Vector};
use crate::solver::dopri::C;
use crate::table::InputId;
use std::f64::consts::TAU;
use std::marker::PhantomData;

/// The product of two rotations given as (cosine, sine).
#[inline(always)]
fn rot(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 * b.0 - a.1 * b.1, a.1 * b.0 + a.0 * b.1)
}

/// The rotations by the phase `omega·C[i]·h` over the stages of a step of length `h` ([`C`]),
/// from those over `h/10` and `h/9`, and the rotation over the whole step.
#[inline(always)]
fn stage_rotations(omega: f64, h: f64) -> ([(f64, f64); 7], (f64, f64)) {
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
    /// Its velocity amplitude along x, `v_a·cos(angle)`, and angular frequency (0 without
    /// one): the 1-D path reads them at every step.
    amp_x: f64,
    omega: f64,
    /// The phase's cosine and sine at the last attempt's start and end (at the start of the
    /// call before the first; the second's time NaN until then). An attempt from either
    /// carries the phase on by rotations; one from elsewhere (after steps that took the
    /// support otherwise) takes it afresh, so that the rotations' rounding adds up over at
    /// most the steps of one call.
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
            amp_x: h.map_or(0.0, |h| h.v_a() * h.dir.0),
            omega: h.map_or(0.0, |h| TAU * h.f),
            known: [(f64::NAN, (1.0, 0.0)); 2],
            tracks,
            dim: PhantomData,
        };
        support.known[0] = (t, support.phase(t));
        support
    }

    /// The harmonic source's phase at `t` as (cosine, sine): known, or afresh. Never inlined:
    /// inlined, rustc 1.95 (LLVM) has twice given the explicit path a wrong support velocity
    /// depending only on how other code happened to be inlined (RigLongitudinal at `k_t` =
    /// 1e12 at 115771 steps instead of 3209; after an unrelated change to the planar
    /// Coulomb limit, `tests/core_physics.rs`'s longitudinal force drive off its reference in
    /// sign). Out of line, the known phases are read from memory as a pair and both builds
    /// agree with their references. Inlined, the same source gives the reference's bits in a
    /// debug build, at opt-level 2, with the SLP vectorizer off and in one code-generation
    /// unit: a fault of the optimizer at opt-level 3, most likely the SLP vectorizer on the
    /// phase's rotations. (One unit would also allow the inlining, but costs the closed-form
    /// path about 7 % per vibration period.)
    #[inline(never)]
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
        if let Some(hm) = &self.harmonic {
            let phase = self.phase(t);
            let (rotations, whole) = stage_rotations(self.omega, h);
            let (v_a, dir) = (hm.v_a(), hm.dir);
            for (wi, r) in w.iter_mut().zip(rotations) {
                let c = rot(phase, r).0;
                // Along x alone as `now` takes it; in the plane as the source does.
                *wi = if V::DIM == 1 {
                    V::from_xy(self.amp_x * c, 0.0)
                } else {
                    let v = v_a * c;
                    V::from_xy(v * dir.0, v * dir.1)
                };
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
    use crate::model::drive::{Axial, Force};
    use crate::physics::{Dahl, Planar};
    use crate::table::{Config, Drive, Lateral, Law, Motion, Params};

    /// A planar Dahl contact under a force drive, its support vibrating at 2 kHz along the
    /// angle 0.7, with the support velocity inputs at `ramps` (value and slope along x and y).
    fn contact(u0: f64, ramps: [(f64, f64); 2]) -> Contact<Planar, Dahl, Force, 6> {
        let c = Config {
            law: Law::Dahl,
            motion: Motion::Planar,
            drive: Drive::Force,
            lateral: Lateral::Free,
            harmonic: true,
            input_support: true,
            normal_input: false,
        };
        let p = Params {
            f: 2000.0,
            angle: 0.7,
            u0,
            ..Params::default()
        };
        let mut contact = Contact::<Planar, Dahl, Force, 6>::new_local(c, p, 1e-6);
        for (id, (value, slope)) in [InputId::VSx, InputId::VSy].into_iter().zip(ramps) {
            let track = &mut contact.dynamics.tracks[id.index()];
            (track.value, track.slope) = (value, slope);
        }
        contact
    }

    /// Attempts from a known start (a rejected attempt's, an accepted one's end) and from one
    /// not known (afresh): `(h, how far the next start is, in steps)`.
    const ATTEMPTS: [(f64, f64); 5] = [
        (3e-5, 0.0),
        (1e-5, 1.0),
        (7e-5, 1.0),
        (2e-5, 1.5),
        (4e-5, 0.0),
    ];

    /// The harmonic source's velocity at the stage times by rotations agrees with its own (a
    /// cosine at each time) within the rounding of its phase `theta(t)` (about
    /// `2·pi·f·t·1e-16`, 3e-13 rad here), attempt after attempt; the input tracks' adds
    /// exactly what they are at each time; along x (one dimension) the velocity at a step's
    /// start is the first stage's, and the acceleration the source's own.
    #[test]
    fn stage_velocities_are_the_sources() {
        let harmonic = contact(2e-7, [(0.0, 0.0); 2]).dynamics;
        let v_a = harmonic.harmonic.unwrap().v_a();
        let mut support = StageSupport::<Planar>::new(&harmonic, true, 0.1);
        let mut t = 0.1;
        for (h, next) in ATTEMPTS {
            for (wi, ci) in support.stages(t, h).iter().zip(C) {
                let want = harmonic.support_velocity(t + ci * h, false);
                assert!((*wi - want).norm() <= 1e-12 * v_a, "t {t}, h {h}, c {ci}");
            }
            t += next * h;
        }
        // The tracks alone, the source still: exactly theirs.
        let tracks = contact(0.0, [(1e-3, 0.2), (-2e-3, -0.5)]).dynamics;
        let mut support = StageSupport::<Planar>::new(&tracks, true, 0.1);
        for (wi, ci) in support.stages(0.1, 3e-5).iter().zip(C) {
            let want = tracks.support_velocity(0.1 + ci * 3e-5, true);
            assert_eq!((wi.x(), wi.y()), (want.x(), want.y()));
        }
        // Along x, the same contact integrated in one dimension, tracks and source together.
        let both = contact(2e-7, [(1e-3, 0.2), (-2e-3, -0.5)]).dynamics;
        let Some(Axial::Force(drive)) = DriveKind::<Planar>::axial(&both.drive) else {
            panic!("a force drive has an axial form");
        };
        let line = both.with_drive::<f64, _>(drive);
        let mut support = StageSupport::<f64>::new(&line, true, 0.1);
        let h = 3e-5;
        let w = support.stages(0.1, h);
        let source = both.harmonic.unwrap();
        let track = both.tracks[InputId::VSx.index()];
        for (t, wi) in [(0.1, w[0]), (0.1 + h, w[6])] {
            let ((vx, _), (ax, _)) = source.velocity_acceleration(t);
            let (v, a) = (vx + track.at(t), ax + track.slope);
            assert_eq!(support.now(t), wi, "{t}");
            assert!((support.now(t) - v).abs() <= 1e-12 * v_a, "{t}");
            let acc = support.accel_now(t);
            assert!((acc - a).abs() <= 1e-12 * v_a * TAU_F, "{t}: {acc} vs {a}");
        }
    }

    /// `2·pi·f` at the test's 2 kHz.
    const TAU_F: f64 = std::f64::consts::TAU * 2000.0;
}
