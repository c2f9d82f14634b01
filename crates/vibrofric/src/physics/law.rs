//! The friction laws of `docs/model.md`: Dahl, Dupont (elasto-plastic) and LuGre, each written once for
//! a longitudinal (`f64`) and a planar ([`Planar`](super::Planar)) contact.
//!
//! A law maps the deformation `s` and the relative velocity `v_r` to the deformation rate
//! `ds/dt`, and the three together to the friction force `F_F` (which resists the relative
//! motion) and the dissipated power `P_diss`.

use super::trig;
use super::Vector;
use crate::table::Params;

/// Smallest deformation scale used to normalise errors when the law has no friction at all.
const S_FLOOR: f64 = 1e-30;

/// The deformation `s_ss = F_C/k_t` at or below which the Coulomb force acts as none: its
/// inverse then stays below 1e290 /m, so that a relaxation rate `|v_r|/s_ss` is finite at any
/// relative velocity up to 1e18 m/s (with LuGre's floor of `g`, the same length).
pub const NO_FRICTION_LENGTH: f64 = 1e-290;

/// `1/s_ss`, or 0 (no friction) where `s_ss` is at most [`NO_FRICTION_LENGTH`]: a Coulomb
/// force that small (below 1e-288 N at the smallest stiffness) acts as none, exactly, instead
/// of turning the rates into infinities and NaN.
fn inverse_length(s_ss: f64) -> f64 {
    if s_ss > NO_FRICTION_LENGTH {
        1.0 / s_ss
    } else {
        0.0
    }
}

/// A 2×2 matrix over the in-plane components; a longitudinal contact uses `[0][0]` only.
pub type Mat2 = [[f64; 2]; 2];

/// Partial derivatives of the deformation rate and of the friction force with respect to the
/// deformation `s` and the relative velocity `v_r` (the force's through `ds/dt` included).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LawJacobian {
    pub rate_s: Mat2,
    pub rate_v: Mat2,
    pub force_s: Mat2,
    pub force_v: Mat2,
}

fn diag(a: f64) -> Mat2 {
    [[a, 0.0], [0.0, a]]
}

/// `a ⊗ b`
fn outer<V: Vector>(a: V, b: V) -> Mat2 {
    [
        [a.x() * b.x(), a.x() * b.y()],
        [a.y() * b.x(), a.y() * b.y()],
    ]
}

/// `a + k·b`
fn axpy(a: Mat2, k: f64, b: Mat2) -> Mat2 {
    [
        [a[0][0] + k * b[0][0], a[0][1] + k * b[0][1]],
        [a[1][0] + k * b[1][0], a[1][1] + k * b[1][1]],
    ]
}

/// Unit vector along `v`, zero for a zero vector. A subnormal `v` (a stuck contact's velocity
/// decays into them) is scaled up first, so that `1/|v|` cannot overflow.
fn unit<V: Vector>(v: V) -> V {
    unit_of(v, v.norm())
}

/// [`unit`](fn@unit) of `v` given its norm `n = v.norm()` (one square root where the caller
/// needs both), the same bits.
#[inline(always)]
fn unit_of<V: Vector>(v: V, n: f64) -> V {
    let (v, n) = if n < 1e-290 {
        let v = v * 1e300;
        (v, v.norm())
    } else {
        (v, n)
    };
    if n > 0.0 {
        v * (1.0 / n)
    } else {
        V::default()
    }
}

/// Force derivatives of a law whose force is `k_t·s`.
fn elastic(k_t: f64, rate_s: Mat2, rate_v: Mat2) -> LawJacobian {
    LawJacobian {
        rate_s,
        rate_v,
        force_s: diag(k_t),
        force_v: diag(0.0),
    }
}

/// A 1-D deformation that relaxes in the relative displacement alone (Dahl): with
/// `sigma = sgn(v_r)` and `w = 1 − sigma·s/length`, `dw = −|w|^exponent·sgn(w)·dX/length` where
/// `X = |x_r − x_r0|`, so that between sign changes of `v_r` the deformation is a closed-form
/// function of `X` ([`Relaxation::remaining`]), and `F_F = stiffness·s`. With `exponent = 1`
/// the rate is linear in `s` and the relaxation exponential.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Relaxation {
    pub length: f64,
    pub stiffness: f64,
    pub exponent: f64,
}

impl Relaxation {
    /// `w` after a relative displacement of `phi` relaxation lengths, from `w0 ≥ 0`:
    /// `w = w0·exp(−phi)` for `exponent = 1`, else `w^u = w0^u − u·phi` with `u = 1 − exponent`,
    /// written as `w0·exp(ln(1 − r)/u)`, `r = u·phi/w0^u`, which tends to the exponential as
    /// `u → 0` without loss. For `exponent < 1`, `w` reaches 0 at finite `phi` and stays there.
    pub fn remaining(&self, w0: f64, phi: f64) -> f64 {
        let u = 1.0 - self.exponent;
        if u == 0.0 {
            return w0 * libm::exp(-phi);
        }
        if w0 <= 0.0 {
            return 0.0;
        }
        let r = u * phi * libm::exp(-u * libm::log(w0));
        if r >= 1.0 {
            0.0
        } else {
            w0 * libm::exp(libm::log1p(-r) / u)
        }
    }

    /// The `phi` at which `w` reaches 0 from `w0` (`exponent < 1` only; infinity otherwise).
    pub fn exhaustion(&self, w0: f64) -> f64 {
        let u = 1.0 - self.exponent;
        if u > 0.0 && w0 > 0.0 {
            libm::exp(u * libm::log(w0)) / u
        } else if u > 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    }
}

/// A rate linear in `s` with a scalar decay: `ds/dt = v_r − decay·s = decay·(target − s)`, and a
/// force affine in `s`: `F_F = force_s·s + force_0`, all at one relative velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Linear<V> {
    pub decay: f64,
    /// `v_r/decay`: where `s` relaxes to (zero where `v_r = 0`).
    pub target: V,
    pub force_s: f64,
    pub force_0: V,
}

/// A law's functions of the relative velocity alone (see [`FrictionLaw::velocity_terms`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VelocityTerms {
    /// The decay rate of [`FrictionLaw::linear`]: [`FrictionLaw::decay`].
    pub decay: f64,
    /// LuGre's contact damping `h_t(v_r)` (0 for the other laws).
    pub damping: f64,
}

/// LuGre's steady slide at one sliding velocity `v` on the x axis (see [`FrictionLaw::steady`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Steady {
    /// `g(v)`: the deformation a steady slide holds, `sign(v)·g` (Eq. 5 over `k_t`).
    pub g: f64,
    /// `dg/dv` (0 where `g` is floored).
    pub dg: f64,
    /// `k_t`.
    pub k_t: f64,
    /// The contact damping `h_t(v)`.
    pub damping: f64,
}

/// One friction law with its constants precomputed from [`Params`].
pub trait FrictionLaw: Copy + Send + Sync + std::fmt::Debug + 'static {
    /// Whether the law has a discontinuity off `v_r = 0` in planar motion (Dupont's direction
    /// test `s·v_r = 0`): Radau IIA locates it; the planar explicit path leaves it to its error
    /// control.
    const PLANAR_SWITCH: bool;

    fn new(p: &Params) -> Self;
    /// `ds/dt`.
    fn rate<V: Vector>(&self, s: V, vr: V) -> V;
    /// The friction force `F_F`, given `ds/dt`.
    fn force<V: Vector>(&self, s: V, vr: V, ds: V) -> V;
    /// Power dissipated in the contact: `F_F·v_r` less the rate of change of `k_t·|s|²/2`.
    fn dissipation<V: Vector>(&self, s: V, vr: V, ds: V) -> f64;
    /// The bound `|s| ≤ s_ss` that the law keeps invariant, if it has one.
    fn bound(&self) -> Option<f64>;
    /// Natural magnitude of `s`, for error norms.
    fn s_scale(&self) -> f64;
    /// A bound on `|s|` that the law keeps invariant under constant parameters: the
    /// deformation that the largest friction force holds (`s_ss`; LuGre `max(F_C, F_S)/k_t`).
    /// Where the normal force falls, the contact slips back onto it.
    fn envelope(&self) -> f64;
    /// Partial derivatives at `(s, v_r)`, with `ds = rate(s, v_r)`.
    fn jacobian<V: Vector>(&self, s: V, vr: V, ds: V) -> LawJacobian;
    /// The law's relaxation in the relative displacement, where it has one (Dahl with friction;
    /// longitudinal contacts only for `kappa ≠ 1`).
    fn relaxation(&self) -> Option<Relaxation> {
        None
    }
    /// Dupont's elasto-plastic relaxation in the relative displacement, where the law has one
    /// (with friction): its length `s_ss`, stiffness `k_t` (`F_F = k_t·s`) and the breakaway
    /// ratio `r_ba`, whose shape [`crate::physics::ElastoPlastic`] gives the deformation
    /// along a branch.
    fn breakaway(&self) -> Option<(Relaxation, f64)> {
        None
    }
    /// The law's linear structure at `v_r`, where its rate is linear in `s` with a scalar decay
    /// (Dahl with `kappa = 1`, LuGre; not Dupont, whose weight depends on `s`).
    fn linear<V: Vector>(&self, _vr: V) -> Option<Linear<V>> {
        None
    }
    /// The decay rate of [`FrictionLaw::linear`] at `v_r` alone (0 where the law has no
    /// linear structure), without the force terms.
    fn decay<V: Vector>(&self, vr: V) -> f64 {
        self.linear(vr).map_or(0.0, |lin| lin.decay)
    }
    /// The law's functions of `v_r` alone, once for several deformations at that `v_r` (see
    /// [`FrictionLaw::rate_force_at`]).
    #[inline(always)]
    fn velocity_terms<V: Vector>(&self, vr: V) -> VelocityTerms {
        VelocityTerms {
            decay: self.decay(vr),
            damping: 0.0,
        }
    }
    /// `ds/dt` and the friction force at `(s, v_r)` given `terms = self.velocity_terms(v_r)`:
    /// the values of [`FrictionLaw::rate`] and [`FrictionLaw::force`] (to the last bit for
    /// Dahl; LuGre's to a few units in the last place of their terms, its exponential being
    /// [`trig::exp`]), without evaluating again what the terms already took (LuGre's `g(v_r)`
    /// and `h_t(v_r)`). The planar explicit path's right-hand side.
    #[inline(always)]
    fn rate_force_at<V: Vector>(&self, s: V, vr: V, terms: &VelocityTerms) -> (V, V) {
        let _ = terms;
        let ds = self.rate(s, vr);
        (ds, self.force(s, vr, ds))
    }
    /// The viscous coefficient `h_v` of a force term `h_v·v_r` (LuGre), 0 for laws without one:
    /// the only term of the force that does not scale with the normal load.
    fn viscous(&self) -> f64 {
        0.0
    }
    /// A steady slide at the velocity `v ≠ 0` along x of a law whose steady deformation is
    /// `g(v)` (LuGre with friction, even where `F_S = F_C` makes `g` constant; `None` for the
    /// other laws): the leading term of a stiff contact's slow manifold
    /// (`model/coulomb_limit.rs`). Its `g` comes from the same `k_t·g` bits as the relaxation
    /// rate of [`FrictionLaw::velocity_terms`].
    fn steady(&self, v: f64) -> Option<Steady> {
        let _ = v;
        None
    }
}

/// Dahl (`docs/model.md`, Eqs. 1, 3 with gamma = 1).
#[derive(Clone, Copy, Debug)]
pub struct Dahl {
    k_t: f64,
    s_ss: f64,
    inv_s_ss: f64,
    kappa: f64,
}

impl FrictionLaw for Dahl {
    const PLANAR_SWITCH: bool = false;

    fn new(p: &Params) -> Self {
        let s_ss = p.f_c() / p.k_t;
        Dahl {
            k_t: p.k_t,
            s_ss,
            inv_s_ss: inverse_length(s_ss),
            kappa: p.kappa,
        }
    }

    #[inline(always)]
    fn rate<V: Vector>(&self, s: V, vr: V) -> V {
        if self.inv_s_ss == 0.0 {
            return V::default(); // no friction: s stays at 0
        }
        if self.kappa == 1.0 {
            vr - s * (vr.norm() * self.inv_s_ss)
        } else {
            // Longitudinal only (`docs/model.md`): ds/dt = v_r·|w|^kappa·sgn(w), w = 1 − sgn(v_r)·s/s_ss.
            let (s, v) = (s.x(), vr.x());
            let w = 1.0 - v.signum() * s * self.inv_s_ss;
            V::from_xy(v * libm::pow(w.abs(), self.kappa) * w.signum(), 0.0)
        }
    }

    #[inline(always)]
    fn force<V: Vector>(&self, s: V, _vr: V, _ds: V) -> V {
        if self.inv_s_ss == 0.0 {
            return V::default(); // no friction, exactly
        }
        s * self.k_t
    }

    #[inline(always)]
    fn dissipation<V: Vector>(&self, s: V, vr: V, ds: V) -> f64 {
        if self.kappa == 1.0 {
            // k_t·|v_r|·|s|²/s_ss: non-negative by construction
            self.k_t * vr.norm() * s.dot(s) * self.inv_s_ss
        } else {
            // k_t·s·(v_r − ds/dt): both factors change sign together while |s| ≤ s_ss
            self.k_t * s.dot(vr - ds)
        }
    }

    fn bound(&self) -> Option<f64> {
        Some(self.s_ss)
    }

    fn envelope(&self) -> f64 {
        self.s_ss
    }

    fn s_scale(&self) -> f64 {
        self.s_ss.max(S_FLOOR)
    }

    fn jacobian<V: Vector>(&self, s: V, vr: V, _ds: V) -> LawJacobian {
        if self.inv_s_ss == 0.0 {
            return LawJacobian::default(); // no friction: nothing depends on anything
        }
        if self.kappa == 1.0 {
            let rate_s = diag(-vr.norm() * self.inv_s_ss);
            let rate_v = axpy(diag(1.0), -self.inv_s_ss, outer(s, unit(vr)));
            elastic(self.k_t, rate_s, rate_v)
        } else {
            let (s, v) = (s.x(), vr.x());
            let w = 1.0 - v.signum() * s * self.inv_s_ss;
            // |w|^(kappa−1) is unbounded at w = 0 for kappa < 1; the floor keeps Newton finite.
            let d = -self.kappa
                * v.abs()
                * libm::pow(w.abs().max(1e-12), self.kappa - 1.0)
                * self.inv_s_ss;
            elastic(
                self.k_t,
                diag(d),
                diag(libm::pow(w.abs(), self.kappa) * w.signum()),
            )
        }
    }

    fn relaxation(&self) -> Option<Relaxation> {
        (self.inv_s_ss > 0.0).then_some(Relaxation {
            length: self.s_ss,
            stiffness: self.k_t,
            exponent: self.kappa,
        })
    }

    fn linear<V: Vector>(&self, vr: V) -> Option<Linear<V>> {
        (self.kappa == 1.0 && self.inv_s_ss > 0.0).then(|| {
            let n = vr.norm();
            Linear {
                decay: n * self.inv_s_ss,
                target: unit_of(vr, n) * self.s_ss,
                force_s: self.k_t,
                force_0: V::default(),
            }
        })
    }
}

/// Dupont elasto-plastic (`docs/model.md`; Dupont, Hayward, Armstrong, Altpeter, IEEE TAC 2002).
#[derive(Clone, Copy, Debug)]
pub struct Dupont {
    k_t: f64,
    s_ss: f64,
    s_ba: f64,
    r_ba: f64,
    inv_s_ss: f64,
}

impl Dupont {
    /// The elasto-plastic weight alpha(s, v_r) in [0, 1].
    #[inline(always)]
    pub fn alpha<V: Vector>(&self, s: V, vr: V) -> f64 {
        if s.dot(vr) <= 0.0 {
            return 0.0; // s and v_r point apart: purely elastic
        }
        let z = s.norm();
        if z <= self.s_ba {
            0.0
        } else if z >= self.s_ss {
            1.0
        } else {
            let mid = 0.5 * (self.s_ss + self.s_ba);
            0.5 * libm::sin(std::f64::consts::PI * (z - mid) / (self.s_ss - self.s_ba)) + 0.5
        }
    }
}

impl Dupont {
    /// Gradient of alpha with respect to `s` (zero outside the transition `s_ba < |s| < s_ss`).
    fn alpha_gradient<V: Vector>(&self, s: V, vr: V) -> V {
        let z = s.norm();
        if s.dot(vr) <= 0.0 || z <= self.s_ba || z >= self.s_ss {
            return V::default();
        }
        let width = self.s_ss - self.s_ba;
        let mid = 0.5 * (self.s_ss + self.s_ba);
        let d = 0.5 * std::f64::consts::PI / width
            * libm::cos(std::f64::consts::PI * (z - mid) / width);
        s * (d / z)
    }
}

impl FrictionLaw for Dupont {
    const PLANAR_SWITCH: bool = true;

    fn new(p: &Params) -> Self {
        let s_ss = p.f_c() / p.k_t;
        Dupont {
            k_t: p.k_t,
            s_ss,
            s_ba: p.r_ba * s_ss,
            r_ba: p.r_ba,
            inv_s_ss: inverse_length(s_ss),
        }
    }

    fn breakaway(&self) -> Option<(Relaxation, f64)> {
        let relax = Relaxation {
            length: self.s_ss,
            stiffness: self.k_t,
            exponent: 1.0,
        };
        (self.inv_s_ss > 0.0).then_some((relax, self.r_ba))
    }

    #[inline(always)]
    fn rate<V: Vector>(&self, s: V, vr: V) -> V {
        if self.inv_s_ss == 0.0 {
            return V::default();
        }
        vr - s * (self.alpha(s, vr) * vr.norm() * self.inv_s_ss)
    }

    #[inline(always)]
    fn force<V: Vector>(&self, s: V, _vr: V, _ds: V) -> V {
        if self.inv_s_ss == 0.0 {
            return V::default(); // no friction, exactly
        }
        s * self.k_t
    }

    #[inline(always)]
    fn dissipation<V: Vector>(&self, s: V, vr: V, _ds: V) -> f64 {
        self.k_t * self.alpha(s, vr) * vr.norm() * s.dot(s) * self.inv_s_ss
    }

    fn bound(&self) -> Option<f64> {
        Some(self.s_ss)
    }

    fn envelope(&self) -> f64 {
        self.s_ss
    }

    fn s_scale(&self) -> f64 {
        self.s_ss.max(S_FLOOR)
    }

    fn jacobian<V: Vector>(&self, s: V, vr: V, _ds: V) -> LawJacobian {
        if self.inv_s_ss == 0.0 {
            return LawJacobian::default(); // no friction: nothing depends on anything
        }
        let r = vr.norm();
        let alpha = self.alpha(s, vr);
        let k = r * self.inv_s_ss;
        let rate_s = axpy(diag(-alpha * k), -k, outer(s, self.alpha_gradient(s, vr)));
        let rate_v = axpy(diag(1.0), -alpha * self.inv_s_ss, outer(s, unit(vr)));
        elastic(self.k_t, rate_s, rate_v)
    }
}

/// Lowest `g(v_r)` relative to its largest value (see [`LuGre::g`]): a friction force of a
/// millionth of the largest is none for any tolerance the integrators resolve.
const G_FLOOR: f64 = 1e-6;

/// LuGre (`docs/model.md`, Eqs. 2, 4–7).
#[derive(Clone, Copy, Debug)]
pub struct LuGre {
    k_t: f64,
    f_c: f64,
    f_s: f64,
    inv_v_s2: f64,
    h_t0: f64,
    inv_v_e2: f64,
    h_v: f64,
}

impl LuGre {
    /// `g(v_r)` of Eq. 5, floored at [`G_FLOOR`] of its largest value (and above 0), so that a
    /// static force far below the Coulomb force (`F_S` = 0), or a Coulomb force far below the
    /// static one at high sliding speed (`F_N` or `mu` = 0 with `F_S` > 0), does not make the
    /// relaxation rate `|v_r|/g` unbounded.
    #[inline(always)]
    fn g(&self, vr2: f64) -> f64 {
        self.g_of(libm::exp(-vr2 * self.inv_v_s2))
    }

    /// `g` from `exp(−v_r²/v_S²)`.
    #[inline(always)]
    fn g_of(&self, stribeck: f64) -> f64 {
        self.steady_force(stribeck).0 / self.k_t
    }

    /// `k_t·g` (the force of a steady slide) from `exp(−v_r²/v_S²)`, floored as [`LuGre::g`],
    /// and whether it is on the floor.
    #[inline(always)]
    fn steady_force(&self, stribeck: f64) -> (f64, bool) {
        let raw = self.f_c + (self.f_s - self.f_c) * stribeck;
        let kg = raw
            .max(G_FLOOR * self.f_c.max(self.f_s))
            .max(1e-290 * self.k_t);
        (kg, kg > raw)
    }

    /// The Stribeck and damping exponentials `exp(−v_r²/v_S²)` and `exp(−v_r²/v_e²)` at
    /// `v_r² = vr2`, by the plain-arithmetic [`trig::exp`] (one where the two velocities are
    /// equal, the default): the explicit paths' (see [`LuGre::velocity_terms`]).
    #[inline(always)]
    fn exponentials(&self, vr2: f64) -> (f64, f64) {
        let stribeck = trig::exp(-vr2 * self.inv_v_s2);
        let damping = if self.inv_v_e2 == self.inv_v_s2 {
            stribeck
        } else {
            trig::exp(-vr2 * self.inv_v_e2)
        };
        (stribeck, damping)
    }
}

impl FrictionLaw for LuGre {
    const PLANAR_SWITCH: bool = false;

    fn new(p: &Params) -> Self {
        // As Dahl's and Dupont's: a contact whose largest deformation, max(F_C, F_S)/k_t, is at
        // most NO_FRICTION_LENGTH (a subnormal load, F_S scaling with it) has no dry friction;
        // its relaxation rate |v_r|/g would be beyond any integrator.
        let (f_c, f_s) = (p.f_c(), p.static_force());
        let (f_c, f_s) = if f_c.max(f_s) / p.k_t > NO_FRICTION_LENGTH {
            (f_c, f_s)
        } else {
            (0.0, 0.0)
        };
        LuGre {
            k_t: p.k_t,
            f_c,
            f_s,
            inv_v_s2: 1.0 / (p.v_s * p.v_s),
            h_t0: 2.0 * p.damping_ratio() * (p.m * p.k_t).sqrt(),
            inv_v_e2: 1.0 / (p.v_e * p.v_e),
            h_v: p.h_v,
        }
    }

    #[inline(always)]
    fn rate<V: Vector>(&self, s: V, vr: V) -> V {
        if self.f_c == 0.0 && self.f_s == 0.0 {
            return V::default();
        }
        let vr2 = vr.dot(vr);
        vr - s * (vr2.sqrt() / self.g(vr2))
    }

    #[inline(always)]
    fn force<V: Vector>(&self, s: V, vr: V, ds: V) -> V {
        if self.f_c == 0.0 && self.f_s == 0.0 {
            return vr * self.h_v; // no dry friction: the viscous term alone
        }
        let h_t = self.h_t0 * libm::exp(-vr.dot(vr) * self.inv_v_e2);
        s * self.k_t + ds * h_t + vr * self.h_v
    }

    #[inline(always)]
    fn dissipation<V: Vector>(&self, s: V, vr: V, ds: V) -> f64 {
        self.force(s, vr, ds).dot(vr) - self.k_t * s.dot(ds)
    }

    fn viscous(&self) -> f64 {
        self.h_v
    }

    fn bound(&self) -> Option<f64> {
        None
    }

    fn envelope(&self) -> f64 {
        self.f_c.max(self.f_s) / self.k_t
    }

    fn s_scale(&self) -> f64 {
        (self.f_c.max(self.f_s) / self.k_t).max(S_FLOOR)
    }

    fn jacobian<V: Vector>(&self, s: V, vr: V, ds: V) -> LawJacobian {
        let r2 = vr.dot(vr);
        let r = r2.sqrt();
        let h_t = self.h_t0 * libm::exp(-r2 * self.inv_v_e2);
        let grad_h_t = vr * (-2.0 * self.inv_v_e2 * h_t);
        if self.f_c == 0.0 && self.f_s == 0.0 {
            return LawJacobian {
                force_v: diag(self.h_v),
                ..LawJacobian::default()
            };
        }
        let (rate_s, rate_v) = {
            let ex = libm::exp(-r2 * self.inv_v_s2);
            // The floor of `g` (see `LuGre::g`): flat below it.
            let (kg, floored) = self.steady_force(ex);
            let g = kg / self.k_t;
            let grad_g = if floored {
                V::default()
            } else {
                vr * ((self.f_s - self.f_c) * ex * (-2.0 * self.inv_v_s2) / self.k_t)
            };
            // ∇(|v_r|/g) = e/g − |v_r|·∇g/g²
            let grad_q = unit(vr) * (1.0 / g) - grad_g * (r / (g * g));
            (diag(-r / g), axpy(diag(1.0), -1.0, outer(s, grad_q)))
        };
        LawJacobian {
            rate_s,
            rate_v,
            force_s: axpy(diag(self.k_t), h_t, rate_s),
            force_v: axpy(axpy(diag(self.h_v), h_t, rate_v), 1.0, outer(ds, grad_h_t)),
        }
    }

    fn decay<V: Vector>(&self, vr: V) -> f64 {
        if self.f_c == 0.0 && self.f_s == 0.0 {
            return 0.0;
        }
        let vr2 = vr.dot(vr);
        vr2.sqrt() / self.g(vr2)
    }

    /// One exponential where the Stribeck and damping velocities are equal (the default), by
    /// the plain-arithmetic [`trig::exp`] (a fifth of the explicit path's time went to
    /// `libm::exp`), and one division: `|v_r|/g = k_t·|v_r|/(k_t·g)`.
    #[inline(always)]
    fn velocity_terms<V: Vector>(&self, vr: V) -> VelocityTerms {
        if self.f_c == 0.0 && self.f_s == 0.0 {
            return VelocityTerms::default();
        }
        let vr2 = vr.dot(vr);
        let (stribeck, damping) = self.exponentials(vr2);
        let (kg, _) = self.steady_force(stribeck);
        VelocityTerms {
            decay: vr2.sqrt() * self.k_t / kg,
            damping: self.h_t0 * damping,
        }
    }

    #[inline(always)]
    fn rate_force_at<V: Vector>(&self, s: V, vr: V, terms: &VelocityTerms) -> (V, V) {
        if self.f_c == 0.0 && self.f_s == 0.0 {
            return (V::default(), vr * self.h_v);
        }
        // As `rate` and `force`, with `|v_r|/g(v_r)` and `h_t(v_r)` from the terms.
        let ds = vr - s * terms.decay;
        (ds, s * self.k_t + ds * terms.damping + vr * self.h_v)
    }

    /// `g = (F_C + (F_S − F_C)·e)/k_t`, `e = exp(−v²/v_S²)`, `dg/dv = −2·v·(F_S − F_C)·e/(k_t·v_S²)`,
    /// with the exponentials of [`LuGre::velocity_terms`].
    #[inline(always)]
    fn steady(&self, v: f64) -> Option<Steady> {
        if self.f_c == 0.0 && self.f_s == 0.0 {
            return None;
        }
        let (stribeck, damping) = self.exponentials(v * v);
        let (kg, floored) = self.steady_force(stribeck);
        let dg = if floored {
            0.0
        } else {
            -2.0 * v * self.inv_v_s2 * (self.f_s - self.f_c) * stribeck / self.k_t
        };
        Some(Steady {
            g: kg / self.k_t,
            dg,
            k_t: self.k_t,
            damping: self.h_t0 * damping,
        })
    }

    fn linear<V: Vector>(&self, vr: V) -> Option<Linear<V>> {
        if self.f_c == 0.0 && self.f_s == 0.0 {
            return None;
        }
        let vr2 = vr.dot(vr);
        let g = self.g(vr2);
        let decay = vr2.sqrt() / g;
        let h_t = self.h_t0 * libm::exp(-vr2 * self.inv_v_e2);
        Some(Linear {
            decay,
            target: unit(vr) * g,
            force_s: self.k_t - h_t * decay,
            force_0: vr * (h_t + self.h_v),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::Planar;

    #[test]
    fn dahl_kappa_one_matches_general_formula() {
        let p = Params::default();
        let d = Dahl::new(&p);
        let mut p3 = p;
        p3.kappa = 1.0 + 1e-15; // forces the general branch
        let d3 = Dahl::new(&p3);
        for &(s, v) in &[(3e-8, 1e-3), (-5e-8, 2e-3), (1e-7, -1e-4), (0.0, 1e-3)] {
            let a = d.rate(s, v);
            let b = d3.rate(s, v);
            assert!((a - b).abs() <= 1e-12 * v.abs(), "{a} {b}");
        }
    }

    #[test]
    fn dupont_uses_magnitude_and_direction_test() {
        let p = Params::default();
        let d = Dupont::new(&p);
        let s_ss = p.f_c() / p.k_t;
        // negative s moving in the negative direction slides exactly like positive s forwards
        let s = -0.9 * s_ss;
        assert!((d.alpha(s, -1e-3) - d.alpha(-s, 1e-3)).abs() < 1e-15);
        assert!(d.alpha(s, -1e-3) > 0.5);
        // pointing apart: purely elastic
        assert_eq!(d.alpha(s, 1e-3), 0.0);
        // the transition is 1/2 at the midpoint between s_ba and s_ss
        let mid = 0.5 * (s_ss + 0.5 * s_ss);
        assert!((d.alpha(mid, 1.0) - 0.5).abs() < 1e-12);
        // planar: same magnitudes in any direction
        let sp = Planar {
            x: 0.0,
            y: 0.9 * s_ss,
        };
        let vp = Planar { x: 0.0, y: 1e-3 };
        assert!((d.alpha(sp, vp) - d.alpha(0.9 * s_ss, 1e-3)).abs() < 1e-15);
    }

    #[test]
    fn relaxation_solves_the_dahl_rate_in_the_displacement() {
        // dw/dX = −w^kappa/s_ss: the closed form against a fine Runge–Kutta in X.
        let p = Params::default();
        for kappa in [0.1, 0.5, 1.0 - 1e-12, 1.0, 2.0, 3.0] {
            let relax = Relaxation {
                length: 1.0,
                stiffness: 1.0,
                exponent: kappa,
            };
            let f = |w: f64| -w.max(0.0).powf(kappa);
            for w0 in [0.0, 0.3, 1.0, 1.9] {
                let (mut w, n, end) = (w0, 200_000, 3.0);
                let h = end / n as f64;
                for _ in 0..n {
                    let k1 = f(w);
                    let k2 = f(w + 0.5 * h * k1);
                    let k3 = f(w + 0.5 * h * k2);
                    let k4 = f(w + h * k3);
                    w = (w + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)).max(0.0);
                }
                let closed = relax.remaining(w0, end);
                assert!(
                    (closed - w).abs() < 1e-9,
                    "kappa {kappa}, w0 {w0}: {closed} vs {w}"
                );
                if kappa <= 0.5 && w0 > 0.0 {
                    let at = relax.exhaustion(w0);
                    assert!(relax.remaining(w0, 0.999_999 * at) > 0.0);
                    assert_eq!(relax.remaining(w0, at * 1.000_001), 0.0);
                }
            }
        }
        let _ = p;
    }

    #[test]
    fn linear_structure_reproduces_rate_and_force() {
        let p = Params {
            h_v: 20.0,
            ..Params::default()
        };
        fn check<L: FrictionLaw>(law: L, s_ss: f64) {
            for (k, &(sx, sy, vx, vy)) in [
                (0.3, -0.2, 1e-3, 2e-4),
                (-0.9, 0.1, -4e-4, 0.0),
                (0.5, 0.5, 1e-6, -3e-3),
                (0.2, 0.0, 0.0, 0.0),
            ]
            .iter()
            .enumerate()
            {
                let (s, vr) = (
                    Planar {
                        x: sx * s_ss,
                        y: sy * s_ss,
                    },
                    Planar { x: vx, y: vy },
                );
                let lin = law.linear(vr).unwrap();
                assert_eq!(law.decay(vr), lin.decay, "{k}");
                let ds = law.rate(s, vr);
                let rate = (lin.target - s) * lin.decay;
                let f = law.force(s, vr, ds);
                let f_lin = s * lin.force_s + lin.force_0;
                for (a, b) in [(ds.x, rate.x), (ds.y, rate.y)] {
                    assert!(
                        (a - b).abs() <= 1e-12 * (vx.abs() + vy.abs() + 1e-9),
                        "{k}: {a} {b}"
                    );
                }
                for (a, b) in [(f.x, f_lin.x), (f.y, f_lin.y)] {
                    assert!((a - b).abs() <= 1e-12 * (f.norm() + 1.0), "{k}: {a} {b}");
                }
                // The rate and force from the velocity terms are the law's own, to a few units
                // in the last place of their terms (LuGre's exponential is `trig::exp`).
                let terms = law.velocity_terms(vr);
                let decay = law.decay(vr);
                assert!(
                    (terms.decay - decay).abs() <= 4.0 * f64::EPSILON * decay,
                    "{k}: {} {decay}",
                    terms.decay
                );
                let (ds2, f2) = law.rate_force_at(s, vr, &terms);
                let rate_terms = vr.norm() + s.norm() * decay;
                for (a, b) in [(ds.x, ds2.x), (ds.y, ds2.y)] {
                    assert!((a - b).abs() <= 1e-14 * rate_terms, "{k}: {a} {b}");
                }
                for (a, b) in [(f.x, f2.x), (f.y, f2.y)] {
                    assert!((a - b).abs() <= 1e-14 * (f.norm() + 1.0), "{k}: {a} {b}");
                }
            }
        }
        let s_ss = p.f_c() / p.k_t;
        check(Dahl::new(&p), s_ss);
        check(LuGre::new(&p), s_ss);
        // A damping velocity apart from the Stribeck velocity: two exponentials.
        check(LuGre::new(&Params { v_e: 3e-4, ..p }), s_ss);
        assert!(Dupont::new(&p).linear(1e-3).is_none());
    }

    #[test]
    fn lugre_steady_state_is_stribeck_curve() {
        let p = Params::default();
        let l = LuGre::new(&p);
        for &v in &[1e-4, 1e-3, 1e-2] {
            let g = l.g(v * v);
            let s = g; // ds/dt = 0 at s = g·sgn(v)
            assert!(l.rate(s, v).abs() < 1e-18);
            let f = l.force(s, v, 0.0);
            let stribeck = p.f_c() + (p.f_s - p.f_c()) * (-(v / p.v_s).powi(2)).exp();
            assert!((f - stribeck).abs() < 1e-12 * stribeck);
        }
    }
}
