//! Independent truth for the tests: closed forms, exact solutions and reference integrations
//! written here, not in the library. Nothing in this file calls the code under test
//! ([`ExactDahl::new`] only reads parameter fields); the harness that drives the code under test
//! is in the sibling modules.
#![allow(dead_code, clippy::needless_range_loop)]

use std::f64::consts::PI;

/// Complete elliptic integral of the first kind `K(m)` in the parameter convention
/// (`m = k²`), by the arithmetic–geometric mean: `K(m) = pi / (2·AGM(1, sqrt(1 − m)))`.
pub fn ellip_k(m: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - m).sqrt());
    for _ in 0..60 {
        let (an, bn) = (0.5 * (a + b), (a * b).sqrt());
        a = an;
        b = bn;
        if (a - b).abs() <= 1e-16 * a {
            break;
        }
    }
    PI / (2.0 * a)
}

/// Coulomb limit of `F_mean/F_C`, longitudinal vibration, velocity drive (`docs/model.md`).
pub fn coulomb_longitudinal(psi: f64) -> f64 {
    if psi < 1.0 {
        2.0 / PI * psi.asin()
    } else {
        1.0
    }
}

/// Coulomb limit of `F_mean/F_C`, transverse vibration, lateral guided (`docs/model.md`).
pub fn coulomb_transverse(psi: f64) -> f64 {
    let q = 1.0 / psi;
    let q2 = q * q;
    2.0 / PI * ellip_k(q2 / (1.0 + q2)) / (1.0 + q2).sqrt()
}

/// Nodes and weights of the `n`-point Gauss–Legendre rule on `[-1, 1]`, computed here: each
/// node by Newton's iteration on the Legendre polynomial `P_n` (three-term recurrence) from
/// Tricomi's estimate, each weight `2 / ((1 − x²)·P_n'(x)²)`. No table is copied from anywhere.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    // P_n(x) and P_n'(x) by the recurrence (k+1)·P_{k+1} = (2k+1)·x·P_k − k·P_{k−1}.
    let legendre = |x: f64| {
        let (mut p0, mut p1) = (1.0, x);
        for k in 1..n {
            let p2 = ((2 * k + 1) as f64 * x * p1 - k as f64 * p0) / (k + 1) as f64;
            p0 = p1;
            p1 = p2;
        }
        (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
    };
    let (mut x, mut w) = (vec![0.0; n], vec![0.0; n]);
    for i in 0..n {
        let mut r = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre(r);
            let dr = p / dp;
            r -= dr;
            if dr.abs() <= 2.0 * f64::EPSILON {
                break;
            }
        }
        let (_, dp) = legendre(r);
        x[i] = r;
        w[i] = 2.0 / ((1.0 - r * r) * dp * dp);
    }
    (x, w)
}

/// Adaptive quadrature of `f` on `[a, b]` to absolute tolerance `tol`, independent of the
/// library's (a Gauss–Kronrod pair): the 12-point Gauss–Legendre rule of [`gauss_legendre`] on
/// an interval is compared with the same rule on its two halves; where they differ by more than
/// the tolerance, each half is refined in turn. It stops where the difference is down to the
/// integrand's own noise (500 ulp of `∫|f|`: the exact solutions below lose about that much
/// near the sign changes of the relative velocity) or after 30 halvings.
pub fn integrate(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let (x, w) = gauss_legendre(12);
    // (integral, integral of |f|) on [a, b].
    let rule = |a: f64, b: f64| {
        let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
        let (mut q, mut q_abs) = (0.0, 0.0);
        for (xi, wi) in x.iter().zip(&w) {
            let y = f(c + h * xi);
            q += wi * y;
            q_abs += wi * y.abs();
        }
        (q * h, q_abs * h.abs())
    };
    fn refine(
        rule: &dyn Fn(f64, f64) -> (f64, f64),
        a: f64,
        b: f64,
        whole: f64,
        tol: f64,
        depth: u32,
    ) -> f64 {
        let m = 0.5 * (a + b);
        let ((left, l_abs), (right, r_abs)) = (rule(a, m), rule(m, b));
        let halves = left + right;
        let e = (halves - whole).abs();
        if e <= tol || e <= 500.0 * f64::EPSILON * (l_abs + r_abs) || depth >= 30 {
            return halves;
        }
        refine(rule, a, m, left, 0.5 * tol, depth + 1)
            + refine(rule, m, b, right, 0.5 * tol, depth + 1)
    }
    let (whole, _) = rule(a, b);
    refine(&rule, a, b, whole, tol, 0)
}

/// Exact solution of the longitudinal Dahl contact under velocity drive with the harmonic
/// source (phase 0), starting from `s = 0` at `t = 0`.
///
/// Dahl is rate-independent: between sign changes of `v_r = v_d − v_a·cos(omega·t)`, with
/// `sigma = sgn(v_r)`, `w = 1 − sigma·s/s_ss` obeys `dw/dD = −w^kappa/s_ss` in the distance
/// `D = |X(t) − X(t_k)|` slid since the sign change, `X(t) = v_d·t − u0·sin(omega·t)` the
/// relative displacement. So `w(t) = w(t_k)·exp(−D/s_ss)` for `kappa = 1`, and
/// `w^(1−kappa) = w(t_k)^(1−kappa) − (1 − kappa)·D/s_ss` otherwise (zero once that reaches
/// zero, for `kappa < 1`).
pub struct ExactDahl {
    pub v_d: f64,
    pub u0: f64,
    pub omega: f64,
    pub s_ss: f64,
    pub k_t: f64,
    pub kappa: f64,
}

impl ExactDahl {
    /// The exact solution for the contact parameters `p` driven at `v_d`, computed from the raw
    /// parameters (`omega = 2·pi·f`, `s_ss = mu·F_N/k_t`) rather than the library's derived ones.
    pub fn new(p: &vibrofric::table::Params, v_d: f64) -> Self {
        ExactDahl {
            v_d,
            u0: p.u0,
            omega: 2.0 * PI * p.f,
            s_ss: p.mu * p.f_n / p.k_t,
            k_t: p.k_t,
            kappa: p.kappa,
        }
    }

    fn v_rel(&self, t: f64) -> f64 {
        self.v_d - self.u0 * self.omega * (self.omega * t).cos()
    }

    /// Sign changes of `v_r` in `(a, b)`, sorted.
    fn roots(&self, a: f64, b: f64) -> Vec<f64> {
        let psi = self.v_d / (self.u0 * self.omega);
        if psi.is_nan() || psi.abs() >= 1.0 {
            return vec![];
        }
        let base = psi.acos(); // omega·t = ±base + 2·pi·n
        let period = 2.0 * PI / self.omega;
        let mut r = vec![];
        let n0 = (a / period).floor() as i64 - 1;
        let n1 = (b / period).ceil() as i64 + 1;
        for n in n0..=n1 {
            for th in [base, 2.0 * PI - base] {
                let t = (th + 2.0 * PI * n as f64) / self.omega;
                if t > a && t < b {
                    r.push(t);
                }
            }
        }
        r.sort_by(|x, y| x.partial_cmp(y).unwrap());
        r
    }

    /// `|X(t) − X(a)|` in product form: accurate to rounding of the difference itself, where
    /// subtracting two values of X would lose it in the boundary layer.
    fn dist(&self, a: f64, t: f64) -> f64 {
        (self.v_d * (t - a)
            - 2.0
                * self.u0
                * (0.5 * self.omega * (t + a)).cos()
                * (0.5 * self.omega * (t - a)).sin())
        .abs()
    }

    /// For `kappa < 1`, where in `(a, b)` the deformation from `s_a` reaches `±s_ss` (the
    /// kink where `w` reaches 0), by bisection on the monotone distance slid.
    fn exhausted(&self, a: f64, s_a: f64, b: f64) -> Option<f64> {
        if self.kappa >= 1.0 {
            return None;
        }
        let sigma = self.v_rel(0.5 * (a + b)).signum();
        let w_a = 1.0 - sigma * s_a / self.s_ss;
        let u = 1.0 - self.kappa;
        let d_star = w_a.max(0.0).powf(u) * self.s_ss / u;
        if self.dist(a, b) <= d_star {
            return None;
        }
        let (mut lo, mut hi) = (a, b);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if self.dist(a, mid) < d_star {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(hi)
    }

    /// Deformation at `t` given the deformation `s_a` at `a`, with no sign change of `v_r`
    /// inside `(a, t)`.
    fn s_piece(&self, a: f64, s_a: f64, t: f64) -> f64 {
        let mid = 0.5 * (a + t);
        let sigma = self.v_rel(mid).signum();
        let w_a = 1.0 - sigma * s_a / self.s_ss;
        let dx = self.dist(a, t);
        let w = if self.kappa == 1.0 {
            w_a * (-dx / self.s_ss).exp()
        } else {
            let u = 1.0 - self.kappa;
            let base = w_a.powf(u) - u * dx / self.s_ss;
            if base <= 0.0 {
                0.0
            } else {
                base.powf(1.0 / u)
            }
        };
        sigma * self.s_ss * (1.0 - w)
    }

    /// Deformation at `t1` and `∫ s dt` over `[t0, t1]` (0 when `quad_tol` is 0), from
    /// `s(t0) = s0`.
    pub fn advance(&self, t0: f64, s0: f64, t1: f64, quad_tol: f64) -> (f64, f64) {
        let mut knots = vec![t0];
        knots.extend(self.roots(t0, t1));
        knots.push(t1);
        let mut s = s0;
        let mut integral = 0.0;
        for w in knots.windows(2) {
            let (a, b) = (w[0], w[1]);
            let s_a = s;
            let f = |t: f64| self.s_piece(a, s_a, t);
            if quad_tol > 0.0 {
                // Split at the kink where w reaches 0 (kappa < 1), which the quadrature's
                // estimate would not see.
                integral += match self.exhausted(a, s_a, b) {
                    Some(k) => {
                        integrate(&f, a, k, 0.5 * quad_tol) + integrate(&f, k, b, 0.5 * quad_tol)
                    }
                    None => integrate(&f, a, b, quad_tol),
                };
            }
            s = self.s_piece(a, s_a, b);
        }
        (s, integral)
    }

    /// Exact mean friction force over the last of `n` whole periods after starting at `s = 0`
    /// at `t = 0`. The forcing is periodic, so every period is computed in local time
    /// `[0, 1/f]`, which keeps `ΔX/s_ss` free of the rounding of large phases; the truth's own
    /// relative error is about 1e-13.
    pub fn f_mean_after_periods(&self, n: usize) -> f64 {
        let period = 2.0 * PI / self.omega;
        let mut s = 0.0;
        for _ in 1..n {
            s = self.advance(0.0, s, period, 0.0).0;
        }
        let (_, integral) = self.advance(0.0, s, period, 1e-15 * self.s_ss * period);
        self.k_t * integral / period
    }
}

/// Classical fixed-step Runge–Kutta 4 on `dy/dt = f(t, y)`, `n` steps from `t0` to `t1`,
/// calling `observe(t, y)` after each step.
pub fn rk4<const N: usize>(
    f: &dyn Fn(f64, &[f64; N]) -> [f64; N],
    t0: f64,
    y0: [f64; N],
    t1: f64,
    n: usize,
    observe: &mut dyn FnMut(f64, &[f64; N]),
) -> [f64; N] {
    let h = (t1 - t0) / n as f64;
    let mut y = y0;
    let add = |y: &[f64; N], k: &[f64; N], c: f64| {
        let mut r = *y;
        for i in 0..N {
            r[i] += c * k[i];
        }
        r
    };
    for i in 0..n {
        let t = t0 + i as f64 * h;
        let k1 = f(t, &y);
        let k2 = f(t + 0.5 * h, &add(&y, &k1, 0.5 * h));
        let k3 = f(t + 0.5 * h, &add(&y, &k2, 0.5 * h));
        let k4 = f(t + h, &add(&y, &k3, h));
        for j in 0..N {
            y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
        }
        observe(t + h, &y);
    }
    y
}
