//! Support motion and importer inputs as functions of time.

use std::f64::consts::TAU;

/// The built-in harmonic source `u = u0·sin(theta(t))` along the direction `angle` to x
/// (`docs/model.md`, Eqs. 13–14), with `theta(t) = theta_ref + 2·pi·f·(t − t_ref)`.
///
/// When `f` or `phase` is retuned during a run, the reference moves to that instant so that the
/// support position stays continuous.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Harmonic {
    pub u0: f64,
    pub f: f64,
    /// Unit direction (cos angle, sin angle).
    pub dir: (f64, f64),
    pub t_ref: f64,
    /// Phase at `t_ref`, in [0, 2·pi).
    pub theta_ref: f64,
}

impl Harmonic {
    pub fn new(u0: f64, f: f64, angle: f64, phase: f64, t_start: f64) -> Self {
        Harmonic {
            u0,
            f,
            dir: (libm::cos(angle), libm::sin(angle)),
            t_ref: t_start,
            theta_ref: phase.rem_euclid(TAU),
        }
    }

    /// Phase at time `t`; the number of whole cycles is removed before multiplying by 2·pi so
    /// that long runs keep full precision.
    #[inline(always)]
    pub fn theta(&self, t: f64) -> f64 {
        self.theta_ref + TAU * super::trig::fract_floor(self.f * (t - self.t_ref))
    }

    /// Velocity amplitude `v_a = 2·pi·f·u0`.
    #[inline(always)]
    pub fn v_a(&self) -> f64 {
        TAU * self.f * self.u0
    }

    /// Support velocity (x, y) at `t`.
    #[inline(always)]
    pub fn velocity(&self, t: f64) -> (f64, f64) {
        let v = self.v_a() * super::trig::cos(self.theta(t));
        (v * self.dir.0, v * self.dir.1)
    }

    /// Support velocity and acceleration (x, y) at `t` from one argument reduction: the
    /// velocity of [`Harmonic::velocity`] to the last bit, and its derivative.
    #[inline(always)]
    pub fn velocity_acceleration(&self, t: f64) -> ((f64, f64), (f64, f64)) {
        let (s, c) = super::trig::sin_cos(self.theta(t));
        let v = self.v_a() * c;
        let a = -self.v_a() * TAU * self.f * s;
        (
            (v * self.dir.0, v * self.dir.1),
            (a * self.dir.0, a * self.dir.1),
        )
    }

    /// Support displacement along its direction at `t`.
    pub fn displacement(&self, t: f64) -> f64 {
        self.u0 * super::trig::sin(self.theta(t))
    }

    /// Period `1/f`, or `None` when `f = 0`.
    pub fn period(&self) -> Option<f64> {
        (self.f > 0.0).then(|| 1.0 / self.f)
    }

    /// Moves the phase reference to `t` (before retuning `f` or the amplitude).
    pub fn rebase(&mut self, t: f64) {
        self.theta_ref = self.theta(t).rem_euclid(TAU);
        self.t_ref = t;
    }
}

/// An importer input over one communication step: `u(t) = value + slope·(t − t_ref)`
/// (held when `slope` = 0, extrapolated after `fmi2SetRealInputDerivatives`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct InputTrack {
    pub t_ref: f64,
    pub value: f64,
    pub slope: f64,
}

impl InputTrack {
    #[inline(always)]
    pub fn at(&self, t: f64) -> f64 {
        self.value + self.slope * (t - self.t_ref)
    }

    /// Exact integral of the input from `t_ref` to `t`.
    #[inline(always)]
    pub fn integral(&self, t: f64) -> f64 {
        let d = t - self.t_ref;
        d * (self.value + 0.5 * self.slope * d)
    }

    /// Re-anchors the track at `t`, keeping its value there and dropping the slope.
    pub fn hold_from(&mut self, t: f64) {
        self.value = self.at(t);
        self.slope = 0.0;
        self.t_ref = t;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_velocity_is_derivative_of_displacement() {
        let h = Harmonic::new(2e-7, 2000.0, 0.3, 0.7, 0.0);
        let t = 0.123_456;
        let dt = 1e-9;
        let num = (h.displacement(t + dt) - h.displacement(t - dt)) / (2.0 * dt);
        let (vx, vy) = h.velocity(t);
        let v = vx * 0.3f64.cos() + vy * 0.3f64.sin();
        // central difference: phase rounding at f·t ~ 250 limits it to ~1e-8 relative
        assert!((num - v).abs() < 1e-7 * h.v_a(), "{num} {v}");
    }

    #[test]
    fn rebase_keeps_phase_continuous() {
        let mut h = Harmonic::new(1e-6, 1234.5, 0.0, 0.0, 0.0);
        let t = 10.000_37;
        let before = h.displacement(t);
        h.rebase(t);
        h.f = 3000.0;
        let theta_new = h.theta(t);
        assert!((h.u0 * theta_new.sin() - before).abs() < 1e-15);
    }

    #[test]
    fn input_track_integral() {
        let u = InputTrack {
            t_ref: 1.0,
            value: 2.0,
            slope: 3.0,
        };
        assert_eq!(u.at(2.0), 5.0);
        assert_eq!(u.integral(3.0), 2.0 * 2.0 + 1.5 * 4.0);
    }
}
