//! The band Radau integrator's saved state: every field a continuation needs, as numbers.

use super::BandRadau;

impl BandRadau {
    /// Appends the integrator's complete state (all but the step limit) to `out`: loaded by
    /// [`BandRadau::load`], it continues bit for bit.
    pub fn save(&self, out: &mut Vec<f64>) {
        out.extend_from_slice(&[self.t, self.tol, self.y.len() as f64]);
        out.extend(self.y.iter());
        out.extend_from_slice(&[
            self.h,
            self.h_old,
            self.h_acc,
            self.err_acc,
            self.faccon,
            self.first as u8 as f64,
            self.n_accept as f64,
            self.stats.steps as f64,
            self.stats.rejected as f64,
            self.stats.rhs_evals as f64,
            self.stats.jacobians as f64,
            self.stats.events as f64,
        ]);
        out.extend(self.cont.iter());
    }

    /// The number of numbers [`BandRadau::save`] writes for `n` unknowns.
    pub fn saved_len(n: usize) -> usize {
        3 + n + 12 + 3 * n
    }

    /// An integrator of `n` unknowns from what [`BandRadau::save`] wrote (`None` when the
    /// numbers do not describe one: wrong length or size, a tolerance out of range).
    pub fn load(data: &[f64], n: usize, step_limit: u64) -> Option<Self> {
        if data.len() != Self::saved_len(n) || data[2] != n as f64 {
            return None;
        }
        let (t, tol) = (data[0], data[1]);
        if !(t.is_finite() && tol.is_finite() && tol > 0.0) {
            return None;
        }
        let mut r = BandRadau::new(t, data[3..3 + n].to_vec(), tol);
        let rest = &data[3 + n..];
        let count = |x: f64| (x.is_finite() && x >= 0.0).then_some(x as u64);
        r.h = rest[0];
        r.h_old = rest[1];
        r.h_acc = rest[2];
        r.err_acc = rest[3];
        r.faccon = rest[4];
        r.first = rest[5] != 0.0;
        r.n_accept = count(rest[6])?;
        r.stats.steps = count(rest[7])?;
        r.stats.rejected = count(rest[8])?;
        r.stats.rhs_evals = count(rest[9])?;
        r.stats.jacobians = count(rest[10])?;
        r.stats.events = count(rest[11])?;
        r.cont = rest[12..].to_vec();
        r.step_limit = step_limit;
        Some(r)
    }
}
