//! The running means the contact reports: `F_mean`, the mean of `F_Fx` over the last completed
//! averaging window (the vibration period, or `T_avg`), and the step means `F_Fx_step`,
//! `F_Fy_step` over the last communication step.

use crate::physics::Vector;
use crate::solver::{Quad, MAX_QUAD};

/// Running mean of `F_Fx` over averaging windows of fixed length aligned on `origin`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Window {
    pub(super) origin: f64,
    pub(super) len: f64,
    /// Index of the window in progress.
    pub(super) index: u64,
    /// ∫F_Fx dt since the start of the window in progress.
    pub(super) acc: f64,
    /// Mean over the last completed window.
    pub(super) last: Option<f64>,
}

impl Window {
    pub(super) fn start(&self) -> f64 {
        self.origin + self.index as f64 * self.len
    }
    pub(super) fn end(&self) -> f64 {
        self.origin + (self.index + 1) as f64 * self.len
    }
}

/// The friction force over communication steps: `∫F_F dt` over the step in progress, and the
/// means over the last one (the outputs `F_Fx_step`, `F_Fy_step`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct StepMean {
    pub(super) acc: Quad,
    /// `∫F_F dt/h` over the last completed step (none before the first).
    pub(super) last: Option<Quad>,
    /// Length of the last completed step.
    pub(super) h: f64,
    /// `F_F` at the start of the last completed step.
    pub(super) f_start: Quad,
}

impl StepMean {
    pub(super) const NONE: StepMean = StepMean {
        acc: [0.0; MAX_QUAD],
        last: None,
        h: 0.0,
        f_start: [0.0; MAX_QUAD],
    };
}

/// For `n` applications of the affine map `s ↦ e·s + beta` from `s_0`: `(c, d)` with
/// `Σ_{j<n} s_j = c·s_0 + d`, by binary powering (O(log n) operations, no cancellation
/// whatever `e` in `[0, 1]`).
pub(super) fn affine_sums<V: Vector>(e: f64, beta: V, n: u64) -> (f64, V) {
    // (a, b, c, d) of `k` maps: `s_k = a·s_0 + b`, `Σ_{j<k} s_j = c·s_0 + d`; `then(x, y)` is
    // `x`'s maps followed by `y`'s.
    type Maps<V> = (f64, V, f64, V);
    let then = |x: Maps<V>, y: Maps<V>| -> Maps<V> {
        (
            y.0 * x.0,
            x.1 * y.0 + y.1,
            x.2 + y.2 * x.0,
            x.3 + x.1 * y.2 + y.3,
        )
    };
    let mut result: Maps<V> = (1.0, V::default(), 0.0, V::default());
    let mut power: Maps<V> = (e, beta, 1.0, V::default());
    let mut n = n;
    while n > 0 {
        if n & 1 == 1 {
            result = then(result, power);
        }
        power = then(power, power);
        n >>= 1;
    }
    (result.2, result.3)
}
