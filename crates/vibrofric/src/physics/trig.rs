//! Sine and cosine of a moderate argument (|x| ≤ 1e5), for the harmonic source; and
//! `exp(x) − 1` on a bounded range ([`expm1`]), for the explicit paths' relaxation and LuGre's
//! exponentials there.
//!
//! Two reasons not to call the platform's `libm`:
//! - speed: the support velocity is evaluated at every stage of every step, and glibc's `cos`
//!   spends half its time saving and restoring the rounding mode; this is about 3× cheaper;
//! - reproducibility: results are the same bits whichever C library the importer links
//!   (glibc, musl, the Microsoft CRT), so partners on other platforms see the same numbers.
//!
//! The method is fdlibm's (Sun Microsystems, 1993, freely distributable): Cody–Waite reduction
//! by π/2 with a two-part constant, then the minimax kernels `__kernel_sin` and `__kernel_cos`
//! on [−π/4, π/4], each within 1 ulp. The phase of the harmonic source lies in [0, 4π), far
//! inside the range where the two-part reduction is exact to a few ulps of the result.

// The constants are fdlibm's, digit for digit, so that they can be checked against it.
#![allow(clippy::excessive_precision)]

/// π/2 in three 33-bit parts with their tails (fdlibm's `pio2_1`, `pio2_1t`, ...).
const PIO2_1: f64 = 1.570_796_326_734_125_614_17e+00;
const PIO2_1T: f64 = 6.077_100_506_506_192_249_32e-11;
const PIO2_2: f64 = 6.077_100_506_303_965_976_60e-11;
const PIO2_2T: f64 = 2.022_266_248_795_950_631_54e-21;
const PIO2_3: f64 = 2.022_266_248_711_166_455_80e-21;
const PIO2_3T: f64 = 8.478_427_660_368_899_569_97e-32;
const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;

const S1: f64 = -1.666_666_666_666_663_243_48e-01;
const S2: f64 = 8.333_333_333_322_489_461_24e-03;
const S3: f64 = -1.984_126_982_985_794_931_34e-04;
const S4: f64 = 2.755_731_370_707_006_767_89e-06;
const S5: f64 = -2.505_076_025_340_686_341_95e-08;
const S6: f64 = 1.589_690_995_211_550_102_21e-10;

const C1: f64 = 4.166_666_666_666_660_190_37e-02;
const C2: f64 = -1.388_888_888_887_410_957_49e-03;
const C3: f64 = 2.480_158_728_947_672_941_78e-05;
const C4: f64 = -2.755_731_435_139_066_330_35e-07;
const C5: f64 = 2.087_572_321_298_174_827_90e-09;
const C6: f64 = -1.135_964_755_778_819_482_65e-11;

/// Largest argument for which the two-part reduction keeps full precision.
const MAX_ARG: f64 = 1e5;

/// `sin(x + y)` for |x| ≤ π/4, |y| ≪ ulp(x) (fdlibm `__kernel_sin`).
#[inline(always)]
fn kernel_sin(x: f64, y: f64) -> f64 {
    let z = x * x;
    let v = z * x;
    let r = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    x - ((z * (0.5 * y - v * r) - y) - v * S1)
}

/// `cos(x + y)` for |x| ≤ π/4 (fdlibm `__kernel_cos`, musl's refinement).
#[inline(always)]
fn kernel_cos(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let one_minus = 1.0 - hz;
    one_minus + (((1.0 - one_minus) - hz) + (z * r - x * y))
}

/// 1.5·2^52: adding and subtracting it rounds a number of magnitude below 2^51 to the nearest
/// integer (ties to even) in two additions, where `f64::round` is a library call on baseline
/// x86-64.
const TO_INT: f64 = 6_755_399_441_055_744.0;

#[inline(always)]
fn round(x: f64) -> f64 {
    round_bits(x).0
}

/// [`round`]`(x)` and the bits of `x + 1.5·2^52`, whose low bits are that integer's, two's
/// complement (the unit in the last place of `1.5·2^52` is 1): where the integer itself is
/// needed, this is exact and takes no float-to-integer conversion, which Rust saturates with a
/// few compares and moves more.
#[inline(always)]
fn round_bits(x: f64) -> (f64, u64) {
    let shifted = x + TO_INT;
    (shifted - TO_INT, shifted.to_bits())
}

/// Fractional part `x − floor(x)` in [0, 1) for |x| < 2^51 (an exact operation).
#[inline(always)]
pub fn fract_floor(x: f64) -> f64 {
    if x.abs() >= 2_251_799_813_685_248.0 {
        return x - x.floor();
    }
    let mut n = round(x);
    if n > x {
        n -= 1.0;
    }
    x - n
}

fn exponent(x: f64) -> i32 {
    ((x.to_bits() >> 52) & 0x7ff) as i32
}

/// `x = n·π/2 + (hi + lo)` with |hi + lo| ≤ π/4 (approximately); returns `(n mod 4, hi, lo)`.
/// fdlibm's `__rem_pio2` for medium arguments: a second and third part of π/2 are subtracted
/// only when cancellation has eaten the first one's precision (x near a multiple of π/2).
#[inline(always)]
fn reduce(x: f64) -> (u32, f64, f64) {
    let (n, n_bits) = round_bits(x * INV_PIO2);
    let mut r = x - n * PIO2_1;
    let mut w = n * PIO2_1T;
    let mut hi = r - w;
    let e = exponent(x);
    if e - exponent(hi) > 16 {
        let t = r;
        w = n * PIO2_2;
        r = t - w;
        w = n * PIO2_2T - ((t - r) - w);
        hi = r - w;
        if e - exponent(hi) > 49 {
            let t = r;
            w = n * PIO2_3;
            r = t - w;
            w = n * PIO2_3T - ((t - r) - w);
            hi = r - w;
        }
    }
    let lo = (r - hi) - w;
    ((n_bits & 3) as u32, hi, lo)
}

/// Below this magnitude `sin(x) = x` and `cos(x) = 1` to the last bit.
const TINY: f64 = 7.450_580_596_923_828e-9; // 2^-27

/// `cos(x)`; within 1 ulp of the correctly rounded value for |x| ≤ 1e5, else `libm::cos`.
#[inline(always)]
pub fn cos(x: f64) -> f64 {
    if x.abs() > MAX_ARG || !x.is_finite() {
        return libm::cos(x);
    }
    if x.abs() < TINY {
        return 1.0;
    }
    let (q, hi, lo) = reduce(x);
    match q {
        0 => kernel_cos(hi, lo),
        1 => -kernel_sin(hi, lo),
        2 => -kernel_cos(hi, lo),
        _ => kernel_sin(hi, lo),
    }
}

/// `sin(x)`; within 1 ulp of the correctly rounded value for |x| ≤ 1e5, else `libm::sin`.
#[inline(always)]
pub fn sin(x: f64) -> f64 {
    if x.abs() > MAX_ARG || !x.is_finite() {
        return libm::sin(x);
    }
    if x.abs() < TINY {
        return x;
    }
    let (q, hi, lo) = reduce(x);
    match q {
        0 => kernel_sin(hi, lo),
        1 => kernel_cos(hi, lo),
        2 => -kernel_sin(hi, lo),
        _ => -kernel_cos(hi, lo),
    }
}

/// `(sin x, cos x)` with one argument reduction: the same bits as [`sin`] and [`cos`].
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() > MAX_ARG || !x.is_finite() {
        return libm::sincos(x);
    }
    if x.abs() < TINY {
        return (x, 1.0);
    }
    let (q, hi, lo) = reduce(x);
    let (s, c) = (kernel_sin(hi, lo), kernel_cos(hi, lo));
    match q {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// `exp(x) − 1` for `x` in [−39, 50], to about 2 units in the last place (relative): the
/// explicit paths' elementary function (and LuGre's Stribeck and damping exponentials there),
/// cheaper than `libm::expm1` (no special cases,
/// no division). `x = k·ln 2 + r` with `|r| ≤ ln 2 / 2` (Cody–Waite), `exp(r) − 1` by its
/// Taylor series to `r^13/13!` (truncation below 1e-17 relative), then
/// `2^k·(1 + p) − 1 = (2^k − 1) + 2^k·p`, exact for `k = 0`. Plain arithmetic: the same bits
/// on every platform.
#[inline(always)]
pub fn expm1(x: f64) -> f64 {
    let (scale, p) = exp_kernel(x);
    (scale - 1.0) + scale * p
}

/// `exp(x)` for `x ≤ 50`, to about 2 units in the last place (relative), by the method of
/// [`expm1`]: `2^k·(1 + p) = 2^k + 2^k·p`; 0 below −700, where it is below 1e-304.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    if x < -700.0 {
        return 0.0;
    }
    let (scale, p) = exp_kernel(x);
    scale + scale * p
}

/// `(2^k, exp(r) − 1)` with `x = k·ln 2 + r`, `|r| ≤ ln 2 / 2`, for `x` in [−700, 50].
#[inline(always)]
fn exp_kernel(x: f64) -> (f64, f64) {
    // ln 2 in two parts (fdlibm's): k·LN2_HI is exact for |k| < 2^11.
    const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
    const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
    let (k, k_bits) = round_bits(x * std::f64::consts::LOG2_E);
    let r = (x - k * LN2_HI) - k * LN2_LO;
    let (r2, c) = (r * r, |n: f64| 1.0 / n);
    let r4 = r2 * r2;
    let a = c(2.0) + c(6.0) * r;
    let b = (c(24.0) + c(120.0) * r) + r2 * (c(720.0) + c(5040.0) * r);
    let d = (c(40320.0) + c(362_880.0) * r)
        + r2 * (c(3_628_800.0) + c(39_916_800.0) * r)
        + r4 * (c(479_001_600.0) + c(6_227_020_800.0) * r);
    let p = r + r2 * a + r4 * b + (r4 * r4) * d;
    // `2^k`: the biased exponent `k + 1023` (in [13, 1096]) from the low bits of `k`'s, which
    // are all the shift keeps.
    let scale = f64::from_bits(k_bits.wrapping_add(1023) << 52);
    (scale, p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The low bits of `x + 1.5·2^52` are the rounded integer's (two's complement) over the
    /// whole range the reduction and the exponential use them in.
    #[test]
    fn round_bits_carry_the_integer() {
        let mut x = -1.1e6;
        while x < 1.1e6 {
            for y in [x, x * 1e-3, x * 1e-6] {
                let (n, bits) = round_bits(y);
                let exact = n as i64;
                assert_eq!(n, (y + TO_INT) - TO_INT, "{y}");
                assert_eq!(bits & 0xfff, (exact as u64) & 0xfff, "{y}");
                let k = round_bits(y * 1e-3).1;
                if (-1010..=73).contains(&(round(y * 1e-3) as i64)) {
                    let two_k = f64::from_bits(k.wrapping_add(1023) << 52);
                    assert_eq!(two_k, libm::exp2(round(y * 1e-3)), "{y}");
                }
            }
            x += 0.37;
        }
    }

    #[test]
    fn sin_cos_is_sin_and_cos_bit_for_bit() {
        for k in 0..20_000 {
            let x = -30.0 + 60.0 * k as f64 / 20_000.0 + 1e-9 * k as f64;
            let (s, c) = sin_cos(x);
            assert_eq!(s.to_bits(), sin(x).to_bits(), "sin {x}");
            assert_eq!(c.to_bits(), cos(x).to_bits(), "cos {x}");
        }
        assert_eq!(sin_cos(1e-10), (sin(1e-10), cos(1e-10)));
    }

    /// Distance in units in the last place, with an absolute floor of one ulp of 1e-16
    /// where the result itself is near zero.
    fn ulps(a: f64, b: f64) -> f64 {
        (a - b).abs() / (f64::EPSILON * b.abs().max(1e-16))
    }

    /// An independent reference, so that the tests check these functions and not the host's
    /// C library (which differs between platforms): sine and cosine in double-double arithmetic
    /// (about 32 digits), reduced by a triple-double π/2 and summed as Taylor series.
    mod reference {
        /// A double-double number hi + lo, |lo| ≤ ulp(hi)/2.
        #[derive(Clone, Copy)]
        pub struct Dd(pub f64, pub f64);

        fn two_sum(a: f64, b: f64) -> Dd {
            let s = a + b;
            let v = s - a;
            Dd(s, (a - (s - v)) + (b - v))
        }

        /// Veltkamp's split of a double into two 26-bit halves.
        fn split(a: f64) -> (f64, f64) {
            let t = 134_217_729.0 * a; // 2^27 + 1
            let hi = t - (t - a);
            (hi, a - hi)
        }

        /// Dekker's exact product, without `mul_add`: on targets without a hardware FMA that
        /// is a C library call, and mingw's is not exact.
        fn two_prod(a: f64, b: f64) -> Dd {
            let p = a * b;
            let ((ah, al), (bh, bl)) = (split(a), split(b));
            Dd(p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
        }

        fn add(a: Dd, b: Dd) -> Dd {
            let s = two_sum(a.0, b.0);
            let t = two_sum(s.1 + a.1 + b.1, 0.0);
            let r = two_sum(s.0, t.0);
            Dd(r.0, r.1 + t.1)
        }

        fn mul(a: Dd, b: Dd) -> Dd {
            let p = two_prod(a.0, b.0);
            two_sum(p.0, p.1 + a.0 * b.1 + a.1 * b.0)
        }

        fn div(a: Dd, n: f64) -> Dd {
            let q = a.0 / n;
            let r = add(a, Dd(-two_prod(q, n).0, -two_prod(q, n).1));
            two_sum(q, r.0 / n)
        }

        /// π/2 as three doubles.
        const PIO2: [f64; 3] = [
            std::f64::consts::FRAC_PI_2,
            6.123_233_995_736_766e-17,
            -1.497_384_904_859_169_8e-33,
        ];

        /// (sin x, cos x), each to about 1e-30 relative.
        pub fn sin_cos(x: f64) -> (f64, f64) {
            let k = (x / PIO2[0]).round();
            let mut r = Dd(x, 0.0);
            for c in PIO2 {
                let p = two_prod(k, c);
                r = add(r, Dd(-p.0, -p.1));
            }
            let r2 = mul(r, r);
            let (mut s, mut c) = (r, Dd(1.0, 0.0));
            let (mut ts, mut tc) = (r, Dd(1.0, 0.0));
            for n in 1..30 {
                let n = n as f64;
                ts = div(mul(ts, r2), -(2.0 * n) * (2.0 * n + 1.0));
                tc = div(mul(tc, r2), -(2.0 * n - 1.0) * (2.0 * n));
                s = add(s, ts);
                c = add(c, tc);
            }
            let (s, c) = (s.0 + s.1, c.0 + c.1);
            match (k as i64).rem_euclid(4) {
                0 => (s, c),
                1 => (c, -s),
                2 => (-s, -c),
                _ => (-c, s),
            }
        }
    }

    #[test]
    fn the_reference_is_exact_where_the_truth_is_known() {
        let (s, c) = reference::sin_cos(0.5);
        // sin 0.5 and cos 0.5 rounded to double (from their 35-digit decimal expansions).
        assert_eq!(s, 0.479_425_538_604_203_000_273_287_935_215_571_4);
        assert_eq!(c, 0.877_582_561_890_372_716_116_281_582_603_829_7);
        let (s, c) = reference::sin_cos(std::f64::consts::FRAC_PI_6);
        assert!((s - 0.5).abs() <= f64::EPSILON / 2.0, "{s}");
        assert!((c - 0.75f64.sqrt()).abs() <= f64::EPSILON, "{c}");
        // cos of the double nearest π/2 is the remainder π/2 − x: 6.123233995736766e-17.
        let (_, c) = reference::sin_cos(std::f64::consts::FRAC_PI_2);
        assert_eq!(c, 6.123_233_995_736_766e-17);
    }

    #[test]
    fn agrees_with_an_independent_reference_to_an_ulp() {
        // Dense over the phase range the harmonic source uses, and sparse beyond it.
        let mut worst: f64 = 0.0;
        let mut check = |x: f64| {
            let (s, c) = reference::sin_cos(x);
            worst = worst.max(ulps(cos(x), c)).max(ulps(sin(x), s));
        };
        let n = 400_000;
        for i in 0..=n {
            check(-0.5 + 13.5 * i as f64 / n as f64);
        }
        // Up to the largest argument these functions reduce themselves (1e5; beyond it they
        // defer to the libm crate's).
        for i in 0..20_000 {
            check(-1e5 + 10.0 * i as f64 + 0.123);
        }
        // fdlibm's bound: below one ulp of the correctly rounded result.
        assert!(worst <= 1.0, "worst {worst} ulps");
    }

    #[test]
    fn exact_at_special_points() {
        assert_eq!(cos(0.0), 1.0);
        assert_eq!(sin(0.0), 0.0);
        assert_eq!(sin(-0.0).to_bits(), (-0.0f64).to_bits());
        assert!((cos(std::f64::consts::FRAC_PI_2) - 6.123_233_995_736_766e-17).abs() < 1e-31);
        assert!(cos(f64::NAN).is_nan());
        assert_eq!(cos(1e300), libm::cos(1e300));
    }

    /// Near a multiple of π/2 the result is tiny and its relative accuracy rests on the
    /// reduction: compare with the reference, whose reduction carries π/2 to 160 bits.
    #[test]
    fn accurate_near_zeros() {
        for k in 1..9 {
            let x = k as f64 * std::f64::consts::FRAC_PI_2;
            let (c, s) = (cos(x), sin(x));
            let (sl, cl) = reference::sin_cos(x);
            assert!(
                (c - cl).abs() <= 1e-31 + 2.0 * f64::EPSILON * cl.abs(),
                "cos({k}·π/2)"
            );
            assert!(
                (s - sl).abs() <= 1e-31 + 2.0 * f64::EPSILON * sl.abs(),
                "sin({k}·π/2)"
            );
        }
    }

    /// The fast expm1 against libm's over its range, near 0 and at the ends.
    #[test]
    fn expm1_is_libm_s_to_a_few_units_in_the_last_place() {
        let mut worst: f64 = 0.0;
        let mut check = |x: f64| {
            let (a, b) = (super::expm1(x), libm::expm1(x));
            worst = worst.max(((a - b) / b.abs()).abs() / f64::EPSILON);
        };
        for i in 0..=200_000 {
            check(-39.0 + 89.0 * i as f64 / 200_000.0 + 1e-9);
            check((i as f64 - 100_000.0) * 1e-7 + 1e-15);
        }
        for x in [-39.0, 50.0, 1e-300, -1e-20, 0.5 * std::f64::consts::LN_2] {
            check(x);
        }
        assert!(worst < 4.0, "{worst} ulp");
        assert_eq!(super::expm1(0.0).to_bits(), 0.0f64.to_bits());
    }

    /// The fast exp against libm's over its range, and 0 below it.
    #[test]
    fn exp_is_libm_s_to_a_few_units_in_the_last_place() {
        let mut worst: f64 = 0.0;
        for i in 0..=400_000 {
            let x = -700.0 + 750.0 * i as f64 / 400_000.0 + 1e-9;
            let (a, b) = (super::exp(x), libm::exp(x));
            worst = worst.max(((a - b) / b).abs() / f64::EPSILON);
        }
        assert!(worst < 4.0, "{worst} ulp");
        assert_eq!(super::exp(0.0), 1.0);
        assert_eq!(super::exp(-700.1), 0.0);
        assert_eq!(super::exp(-1e300), 0.0);
    }
}
