//! What the explicit paths' loops of Dormand–Prince attempts share (`explicit/`,
//! `explicit_planar/steps.rs`): the work limit, the checks of an attempt's start and size,
//! its error made infinite where anything is not finite, and a rejected attempt's next size.

use crate::model::simulator::SimError;
use crate::solver::dopri::factor;
use crate::solver::{SolverError, SolverStats};

/// Fails at the work limit: `limit` attempts, accepted and rejected, in the counts `stats`.
#[inline(always)]
pub(super) fn within_limit(stats: &SolverStats, limit: u64, t: f64) -> Result<(), SimError> {
    if stats.steps + stats.rejected >= limit {
        return Err(SimError::Solver(SolverError::WorkLimit {
            t,
            limit: limit as f64,
        }));
    }
    Ok(())
}

/// Fails where the first stage `k1` of an attempt from `t` is not finite.
#[inline(always)]
pub(super) fn finite_start(k1: &[f64], t: f64) -> Result<(), SimError> {
    if !k1.iter().all(|z| z.is_finite()) {
        return Err(SimError::Solver(SolverError::NonFinite { t }));
    }
    Ok(())
}

/// Fails where an attempt of length `hh` from `t` that does not end the call (`last`) is
/// below the time's resolution there.
#[inline(always)]
pub(super) fn size_resolved(last: bool, hh: f64, t: f64) -> Result<(), SimError> {
    if !last && hh <= 16.0 * f64::EPSILON * t.abs().max(hh) {
        return Err(SimError::Solver(SolverError::StepSizeTooSmall { t, h: hh }));
    }
    Ok(())
}

/// An attempt's scaled error `err`, infinite where it or the end `u1` is not finite.
#[inline(always)]
pub(super) fn finite_error(err: f64, u1: &[f64]) -> f64 {
    if u1.iter().all(|z| z.is_finite()) && err.is_finite() {
        err
    } else {
        f64::INFINITY
    }
}

/// Counts a rejected attempt of length `hh` with the scaled error `err`: the size to try next.
#[inline(always)]
pub(super) fn rejected(stats: &mut SolverStats, hh: f64, err: f64) -> f64 {
    stats.rejected += 1;
    hh * factor(err).min(0.9)
}
