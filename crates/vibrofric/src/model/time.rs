//! Times: the communication point an importer meant, and the limits on what one step may span.

/// Most averaging windows one communication step may span: their index stays exact in a
/// double and in the window count.
pub const WINDOWS_MAX: f64 = 4e15;

/// Largest magnitude of an input derivative, per second in the input's unit: far beyond any
/// physical rate, small enough that an input extrapolated over any step stays finite.
pub const MAX_INPUT_RATE: f64 = 1e12;

/// Relative distance within which a communication point lies on a window boundary: far above
/// the rounding of importers' time arithmetic, far below any physical time scale.
pub(super) const TIME_SNAP: f64 = 1e-12;

/// How close to a window boundary a communication point counts as on it: the importer's
/// rounding, relative to the time it counts in (`t_local`, counted from the start, and the
/// importer's `t_abs`), and never more than a quarter of the window (`len`), so that a point
/// snaps to one boundary only, however coarse the absolute time's resolution. Stepping and
/// the check of a restored state both use it, so that a state saved on a boundary restores
/// whatever the start time.
pub(super) fn boundary_snap(t_local: f64, t_abs: f64, len: f64) -> f64 {
    (TIME_SNAP * t_local.abs())
        .max(4.0 * f64::EPSILON * t_abs.abs())
        .min(0.25 * len)
}

/// Relative distance within which a time is taken as a nearby short decimal: 256 ulps, above
/// the drift of importers' time arithmetic (`t += h`, `k·h`, integer nanoseconds) over
/// thousands of steps, and small enough that a time meant to be no short decimal (k/3) almost
/// never moves, and then by at most 256 ulps.
pub(super) const DECIMAL_SNAP: f64 = 256.0 * f64::EPSILON;

/// The communication point an importer meant: a time within `DECIMAL_SNAP` of a decimal with
/// 12 significant digits is taken as that decimal, so that importers that accumulate time
/// differently step the FMU to bit-identical instants and get bit-identical results.
pub fn canonical_time(t: f64) -> f64 {
    if t == 0.0 || !t.is_finite() {
        return t;
    }
    let exponent = libm::log10(t.abs()).floor() as i32;
    let scale = 10f64.powi(11 - exponent);
    if !scale.is_finite() || scale == 0.0 {
        return t;
    }
    let c = (t * scale).round() / scale;
    if (c - t).abs() <= DECIMAL_SNAP * t.abs() {
        c
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn importers_time_arithmetic_maps_to_one_communication_point() {
        let h = 1e-4;
        let mut acc = 0.0;
        for k in 1..=3000u32 {
            acc += h; // ecos
            let nominal = k as f64 * h; // fmi-sim
            let fmpy = (k - 1) as f64 * h + (nominal - (k - 1) as f64 * h);
            let libcosim = (k as u64 * 100_000) as f64 / 1e9;
            let c = canonical_time(nominal);
            assert_eq!(canonical_time(acc), c, "t += h at step {k}");
            assert_eq!(canonical_time(fmpy), c);
            assert_eq!(canonical_time(libcosim), c);
            assert!((c - nominal).abs() <= 4.0 * f64::EPSILON * nominal);
        }
        // A time that is no short decimal stays exactly as it is.
        let third = 1.0 / 3.0;
        assert_eq!(canonical_time(third), third);
        assert_eq!(canonical_time(0.0), 0.0);
    }
}
