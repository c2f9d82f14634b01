//! Adaptive Gauss–Kronrod (7/15) quadrature: the integral of a smooth function over an interval
//! with an error estimate, for the parts of a solution that are known in closed form but whose
//! integral is not (the mean friction force of a closed-form deformation).

/// Kronrod nodes on [−1, 1] (the non-negative half; odd indices are the Gauss nodes).
const XK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
/// Kronrod weights.
const WK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
/// Gauss weights of the 7-point rule (nodes `XK[1]`, `XK[3]`, `XK[5]`, `XK[7]`).
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// Deepest bisection: 2^-30 of the interval, far below any scale the callers resolve.
const MAX_DEPTH: u32 = 30;
/// Most panels of one call (30 000 evaluations): a bound on the work for integrands no
/// tolerance can be met on; past it, panels are no longer split and the estimate says so.
const MAX_PANELS: u32 = 2000;

/// An integral with its work.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Integral {
    /// The Kronrod value.
    pub value: f64,
    /// `|K15 − G7|` summed over the panels: the error of the 7-point rule, a generous bound
    /// on the error of the 15-point value.
    pub error: f64,
    /// Function evaluations.
    pub evals: u64,
}

impl std::ops::AddAssign for Integral {
    fn add_assign(&mut self, o: Integral) {
        self.value += o.value;
        self.error += o.error;
        self.evals += o.evals;
    }
}

/// The 15-point Kronrod value of `∫f` over `[a, b]` and its 7-point Gauss error.
pub fn kronrod15(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64) -> Integral {
    kronrod15_abs(f, a, b).0
}

/// [`kronrod15`] and the Kronrod value of `∫|f|`, the scale of the sum's rounding.
fn kronrod15_abs(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64) -> (Integral, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = f(c);
    let mut k = WK[7] * fc;
    let mut k_abs = WK[7] * fc.abs();
    let mut g = WG[3] * fc;
    for i in 0..7 {
        let (f1, f2) = (f(c - h * XK[i]), f(c + h * XK[i]));
        k += WK[i] * (f1 + f2);
        k_abs += WK[i] * (f1.abs() + f2.abs());
        if i % 2 == 1 {
            g += WG[i / 2] * (f1 + f2);
        }
    }
    let whole = Integral {
        value: k * h,
        error: ((k - g) * h).abs(),
        evals: 15,
    };
    (whole, k_abs * h.abs())
}

/// Relative rounding of a 15-term sum, below which an error estimate means nothing.
const ROUNDING: f64 = 50.0 * f64::EPSILON;

/// `∫f` over `[a, b]` to the absolute error `tol`, bisecting panels whose estimate exceeds
/// their share of it, down to the rounding of the panel's sum (a tolerance below it cannot be
/// met and would only multiply panels), `MAX_DEPTH` halvings or `MAX_PANELS` panels, where
/// the estimate is returned as it is.
/// Like every quadrature that samples, it cannot see a feature that falls between all nodes of
/// the first panel: the caller chooses `[a, b]` on the scale of the integrand.
pub fn adaptive(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64, tol: f64) -> Integral {
    fn rec(
        f: &mut impl FnMut(f64) -> f64,
        a: f64,
        b: f64,
        tol: f64,
        depth: u32,
        panels: &mut u32,
    ) -> Integral {
        let (whole, scale) = kronrod15_abs(f, a, b);
        *panels += 1;
        if whole.error <= tol.max(ROUNDING * scale)
            || depth >= MAX_DEPTH
            || *panels >= MAX_PANELS
            || !whole.value.is_finite()
        {
            return whole;
        }
        let m = 0.5 * (a + b);
        let mut r = rec(f, a, m, 0.5 * tol, depth + 1, panels);
        r += rec(f, m, b, 0.5 * tol, depth + 1, panels);
        r.evals += whole.evals;
        r
    }
    rec(f, a, b, tol, 0, &mut 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomials_up_to_degree_22_are_exact() {
        // K15 integrates degree 22 exactly, G7 degree 13.
        let i = kronrod15(&mut |x: f64| x.powi(22), 0.0, 1.0);
        assert!((i.value - 1.0 / 23.0).abs() < 1e-15);
        let i = kronrod15(&mut |x: f64| 3.0 * x * x - x, -1.0, 2.0);
        assert!((i.value - (9.0 - 1.5)).abs() < 1e-14);
        assert!(i.error < 1e-14);
    }

    #[test]
    fn an_impossible_tolerance_costs_only_the_rounding_floor() {
        // |x − 0.3| with tolerance 1e-300: the smooth panels stop at their rounding, only the
        // panels holding the kink go deep; the value is right to rounding.
        let i = adaptive(&mut |x: f64| (x - 0.3).abs(), 0.0, 1.0, 1e-300);
        assert!((i.value - (0.045 + 0.245)).abs() < 1e-13, "{}", i.value);
        assert!(i.evals < 15 * 200, "{} evaluations", i.evals);
    }

    #[test]
    fn boundary_layer_is_resolved_to_the_tolerance() {
        // ∫_0^L exp(−x/eps) dx = eps·(1 − exp(−L/eps)): a panel on the layer's own scale
        // (as the callers choose them) converges to the tolerance, with an honest estimate.
        let eps = 1e-6;
        for (len, tol) in [(2.0, 1e-8), (30.0, 1e-8), (30.0, 1e-12)] {
            let i = adaptive(&mut |x: f64| (-x / eps).exp(), 0.0, len * eps, tol * eps);
            let exact = eps * (-(-len).exp_m1());
            assert!((i.value - exact).abs() <= tol * eps, "{tol}: {}", i.value);
            assert!(i.error <= tol * eps);
            assert!((i.value - exact).abs() <= i.error.max(1e-15 * eps));
        }
    }
}
