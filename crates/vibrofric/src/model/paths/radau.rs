//! The general path: Radau IIA of order 5 (`solver/radau/`) on the whole state, with event
//! location at every sign change of the switching functions, for every contact no faster path
//! takes.

use super::{Kept, Path, Shared};
use crate::model::drive::DriveKind;
use crate::model::simulator::SimError;
use crate::physics::{FrictionLaw, Vector};
use crate::solver::{Quad, Radau5, Step, MAX_QUAD};

/// The Radau IIA path.
pub(super) struct Radau;

impl<V: Vector, L: FrictionLaw, D: DriveKind<V>, const N: usize> Path<V, L, D, N> for Radau {
    /// Always: the path of last resort.
    fn applies(_: &Shared<'_, V, L, D, N>, _: &Radau5<N>, _: &Kept) -> bool {
        true
    }

    fn advance(
        c: &Shared<'_, V, L, D, N>,
        r: &mut Radau5<N>,
        k: &mut Kept,
        t_target: f64,
        h_max: f64,
    ) -> Result<Quad, SimError> {
        let sys = c.system();
        let mut acc = [0.0; MAX_QUAD];
        r.integrate_with(&mut k.work, &sys, t_target, h_max, |step: &Step<N>| {
            acc[0] += step.quad[0];
            acc[1] += step.quad[1];
        })
        .map_err(SimError::Solver)?;
        Ok(acc)
    }
}
