//! Dupont's elastic part in closed form: a body held by a force drive on a contact whose
//! deformation stays within the breakaway (`|s| ≤ s_ba`, where `alpha = 0`) is a linear
//! oscillator on the contact stiffness, `ds/dt = v_r`, `m·dv/dt = F_d(t) − k_t·s`, forced by
//! the drive (held or ramped) and the support's motion (harmonic and ramped input). A stuck
//! body rings on the contact at `Ω = sqrt(k_t/m)` without loss, which an explicit method follows
//! at about three steps per `1/Ω` (a million steps per second at `k_t` = 1e12); here a step of
//! any length costs a few sines and cosines.
//!
//! In the relative displacement `ξ` since the step's start, `τ` the time since then:
//! `ξ'' + Ω²·ξ = (d0 + d1·τ − k_t·s0)/m − c1 + a·ω·sin(θ0 + ω·τ)`, with the drive force
//! `d0 + d1·τ`, the support velocity `a·cos(θ0 + ω·τ) + c0 + c1·τ`. Its solution is the sum of
//! `P(τ) = (d0 + d1·τ − k_t·s0 − m·c1)/k_t`, `H(τ) = B·sin(θ0 + ω·τ)` with
//! `B = a·ω/(Ω² − ω²)`, and `C·cos(Ωτ) + D·sin(Ωτ)` from `ξ(0) = 0`, `ξ'(0) = v_r0`. The step
//! is taken only where the deformation provably stays elastic over it:
//! `max|s0 + P| + |B| + sqrt(C² + D²) < s_ba`; elsewhere (or near resonance, `Ω ≈ ω`, where `B`
//! grows without bound) the explicit method takes over.

/// The forcing of the elastic oscillator over a step, from its start.
#[derive(Clone, Copy, Debug)]
pub(super) struct Forcing {
    /// Drive force at the start and its rate.
    pub d0: f64,
    pub d1: f64,
    /// The harmonic source's velocity amplitude along x, its angular frequency and the
    /// cosine and sine of its phase at the start.
    pub amp: f64,
    pub omega: f64,
    pub phase: (f64, f64),
    /// The input support velocity at the start and its rate.
    pub c0: f64,
    pub c1: f64,
}

/// The end of an elastic step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ElasticEnd {
    pub s: f64,
    pub x: f64,
    pub v: f64,
    /// `∫F_Fx dt` over the step.
    pub impulse: f64,
    /// The relative velocity at the end.
    pub v_r: f64,
}

/// The body and deformation after `h` from `(s0, x0, v0)`, if the deformation stays within
/// `s_ba` (a margin of a millionth inside it) over the whole step; `None` otherwise.
#[allow(clippy::too_many_arguments)]
pub(super) fn elastic_step(
    s0: f64,
    x0: f64,
    v0: f64,
    h: f64,
    k_t: f64,
    m: f64,
    s_ba: f64,
    f: &Forcing,
) -> Option<ElasticEnd> {
    let big = (k_t / m).sqrt();
    let (cos0, sin0) = f.phase;
    let b = if f.amp == 0.0 {
        0.0
    } else {
        f.amp * f.omega / (big * big - f.omega * f.omega)
    };
    let p = |tau: f64| (f.d0 + f.d1 * tau - k_t * s0 - m * f.c1) / k_t;
    let vs0 = f.amp * cos0 + f.c0;
    let c = -p(0.0) - b * sin0;
    let d = ((v0 - vs0) - f.d1 / k_t - b * f.omega * cos0) / big;
    let reach = (s0 + p(0.0)).abs().max((s0 + p(h)).abs()) + b.abs() + libm::hypot(c, d);
    // (NaN, from a resonance or an infinite stiffness, is no certificate.)
    let certified = reach < s_ba * (1.0 - 1e-6) && big.is_finite();
    if !certified {
        return None;
    }
    let (sin_w, cos_w) = (libm::sin(f.omega * h), libm::cos(f.omega * h));
    let (sin_1, cos_1) = (sin0 * cos_w + cos0 * sin_w, cos0 * cos_w - sin0 * sin_w);
    let (sin_b, cos_b) = (libm::sin(big * h), libm::cos(big * h));
    let xi = p(h) + b * sin_1 + c * cos_b + d * sin_b;
    let dxi = f.d1 / k_t + b * f.omega * cos_1 - c * big * sin_b + d * big * cos_b;
    let vs1 = f.amp * cos_1 + f.c0 + f.c1 * h;
    // ∫v_s: the harmonic part a/ω·(sin θ1 − sin θ0) (a·cos θ0·h as ω → 0), the input's.
    let harmonic_path = if f.amp == 0.0 {
        0.0
    } else if f.omega * h < 1e-8 {
        f.amp * cos0 * h
    } else {
        f.amp / f.omega * (sin_1 - sin0)
    };
    let support_path = harmonic_path + f.c0 * h + 0.5 * f.c1 * h * h;
    // ∫k_t·(s0 + ξ): k_t·(s0·h + ∫P) is the drive's impulse less m times the input's change
    // of velocity; the harmonic and the ringing parts in closed form.
    let harmonic_int = if f.amp == 0.0 {
        0.0
    } else {
        b / f.omega * (cos0 - cos_1)
    };
    let ring_int = (c * sin_b + d * (1.0 - cos_b)) / big;
    let impulse = (f.d0 - m * f.c1) * h + 0.5 * f.d1 * h * h + k_t * (harmonic_int + ring_int);
    Some(ElasticEnd {
        s: s0 + xi,
        x: x0 + xi + support_path,
        v: dxi + vs1,
        impulse,
        v_r: dxi,
    })
}

#[cfg(test)]
mod tests {
    use super::{elastic_step, Forcing};

    /// The closed form against a classical Runge–Kutta integration of the same oscillator
    /// (`ds/dt = v − v_s`, `m·dv/dt = F_d − k_t·s`, `dx/dt = v`, `dI/dt = k_t·s`) with a million
    /// steps, with and without the harmonic source and the ramps.
    #[test]
    fn elastic_step_is_the_oscillator_s_solution() {
        let (k_t, m, s_ba) = (1e8, 1.0, 8e-8);
        for (amp, c1, d1) in [(0.0, 0.0, 0.0), (2e-5, 0.0, 0.0), (2e-5, 3e-3, 50.0)] {
            let f = Forcing {
                d0: 2.0,
                d1,
                amp,
                omega: std::f64::consts::TAU * 2000.0,
                phase: (libm::cos(0.3), libm::sin(0.3)),
                c0: 1e-5,
                c1,
            };
            let (s0, x0, v0, h) = (1e-8, 0.0, 1e-4, 2e-3);
            let end = elastic_step(s0, x0, v0, h, k_t, m, s_ba, &f).expect("elastic");
            let vs = |t: f64| f.amp * libm::cos(0.3 + f.omega * t) + f.c0 + f.c1 * t;
            let rate = |t: f64, y: [f64; 4]| {
                [
                    y[2] - vs(t),
                    y[2],
                    (f.d0 + f.d1 * t - k_t * y[0]) / m,
                    k_t * y[0],
                ]
            };
            let n = 1_000_000;
            let dt = h / n as f64;
            let mut y = [s0, x0, v0, 0.0];
            for i in 0..n {
                let t = i as f64 * dt;
                let add =
                    |y: [f64; 4], k: [f64; 4], a: f64| std::array::from_fn(|j| y[j] + a * k[j]);
                let k1 = rate(t, y);
                let k2 = rate(t + 0.5 * dt, add(y, k1, 0.5 * dt));
                let k3 = rate(t + 0.5 * dt, add(y, k2, 0.5 * dt));
                let k4 = rate(t + dt, add(y, k3, dt));
                y = std::array::from_fn(|j| {
                    y[j] + dt / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])
                });
            }
            let what = format!("amp {amp}, c1 {c1}, d1 {d1}");
            assert!(
                (end.s - y[0]).abs() < 1e-10 * s_ba,
                "{what}: s {} vs {}",
                end.s,
                y[0]
            );
            assert!(
                (end.x - y[1]).abs() < 1e-15,
                "{what}: x {} vs {}",
                end.x,
                y[1]
            );
            assert!(
                (end.v - y[2]).abs() < 1e-11,
                "{what}: v {} vs {}",
                end.v,
                y[2]
            );
            assert!(
                (end.impulse - y[3]).abs() < 1e-12,
                "{what}: ∫F {} vs {}",
                end.impulse,
                y[3]
            );
            assert!((end.v_r - (y[2] - vs(h))).abs() < 1e-11, "{what}: v_r");
        }
    }

    /// A deformation that would reach the breakaway, or a resonant source, is no elastic step.
    #[test]
    fn refuses_what_it_cannot_certify() {
        let f = Forcing {
            d0: 8.0,
            d1: 0.0,
            amp: 0.0,
            omega: 0.0,
            phase: (1.0, 0.0),
            c0: 0.0,
            c1: 0.0,
        };
        // A held force of 8 N from rest: s rings between 0 and 16/k_t, beyond s_ba = 5e-8.
        assert!(elastic_step(0.0, 0.0, 0.0, 1e-3, 1e8, 1.0, 5e-8, &f).is_none());
        // Started at its equilibrium it stays there.
        let end = elastic_step(8e-8, 0.0, 0.0, 1e-3, 1e8, 1.0, 9e-8, &f).unwrap();
        assert!((end.s - 8e-8).abs() < 1e-22 && end.v.abs() < 1e-18);
        let resonant = Forcing {
            amp: 1e-3,
            omega: 1e4,
            ..f
        };
        assert!(elastic_step(8e-8, 0.0, 0.0, 1e-3, 1e8, 1.0, 9e-8, &resonant).is_none());
    }
}
