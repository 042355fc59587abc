//! Sine and cosine of an angle given in turns or degrees, in `f64`: the
//! Earth periodic terms (Table A4.2), whose angles C τ the crate already
//! holds in turns (see [`super::split`]), and the nutation's fundamental
//! arguments (eq. 15–19), which are polynomials in degrees.
//!
//! Reduction: `k = round(4 t)` and `r = t − k/4` in `[−1/8, 1/8]` turn. The
//! subtraction is exact (`k/4` is a multiple of `ulp(t)` for `|t| < 2⁴⁹`), so
//! unlike `sin(2π · t)` through radians — where the product `2π t` rounds at
//! the magnitude of the whole angle, up to 9·10⁻¹⁶ absolute at 13 rad — the
//! only roundings are `y = 2π r` (half an ulp of `|y| ≤ π/4`) and the
//! kernel's. The quarter turn `k mod 4` then swaps and negates the pair
//! without a branch.
//!
//! Kernels: the polynomials of fdlibm's `__kernel_sin` and `__kernel_cos`
//! (Sun Microsystems, 1993, "Permission to use, copy, modify, and distribute
//! this software is freely granted, provided that this notice is
//! preserved"; the same as the `libm` crate uses), valid on `|y| ≤ π/4`
//! with errors below one ulp. Measured against a double-double reference
//! in the tests below.

// The kernel coefficients as fdlibm prints them (more digits than an f64
// holds; each rounds to the f64 fdlibm uses).
#![allow(clippy::excessive_precision)]

/// sin kernel coefficients (fdlibm `k_sin.c`).
const S1: f64 = -1.666_666_666_666_663_243_48e-01;
const S2: f64 = 8.333_333_333_322_489_461_24e-03;
const S3: f64 = -1.984_126_982_985_794_931_34e-04;
const S4: f64 = 2.755_731_370_707_006_767_89e-06;
const S5: f64 = -2.505_076_025_340_686_341_95e-08;
const S6: f64 = 1.589_690_995_211_550_102_21e-10;

/// cos kernel coefficients (fdlibm `k_cos.c`).
const C1: f64 = 4.166_666_666_666_660_190_37e-02;
const C2: f64 = -1.388_888_888_887_410_957_49e-03;
const C3: f64 = 2.480_158_728_947_672_941_78e-05;
const C4: f64 = -2.755_731_435_139_066_330_35e-07;
const C5: f64 = 2.087_572_321_298_174_827_90e-09;
const C6: f64 = -1.135_964_755_778_819_482_65e-11;

/// Signs of (sin, cos) after `k mod 4` quarter turns, applied to the pair
/// `(sin y, cos y)` swapped when `k` is odd: sin(y + k·π/2) is sin y, cos y,
/// −sin y, −cos y and cos(y + k·π/2) is cos y, −sin y, −cos y, sin y.
const SIGN_SIN: [f64; 4] = [1.0, 1.0, -1.0, -1.0];
const SIGN_COS: [f64; 4] = [1.0, -1.0, -1.0, 1.0];

/// 1.5 · 2⁵²: for `|x| < 2⁵¹`, `x + ROUND` lands in `[2⁵², 2⁵³)` where the
/// spacing is 1, so the addition rounds `x` to an integer (ties to even)
/// and the low bits of the sum's significand are that integer modulo 4
/// (2⁵¹ + k ≡ k mod 4). No float-to-integer conversion, no branch.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// `x` rounded to an integer `k` (as `f64`) and `k mod 4`, for `|x| < 2⁵¹`
/// (non-finite `x` gives a non-finite `k`).
#[inline(always)]
fn round_quarter(x: f64) -> (f64, usize) {
    let b = x + ROUND;
    (b - ROUND, (b.to_bits() & 3) as usize)
}

/// `(sin y, cos y)` for `|y| ≤ π/4` (a little beyond is harmless), then
/// turned by `q` quarter turns: `(sin(y + qπ/2), cos(y + qπ/2))`, `q < 4`.
#[inline(always)]
fn kernel(y: f64, q: usize) -> (f64, f64) {
    let z = y * y;
    let w = z * z;
    // fdlibm __kernel_sin(y, 0, 0).
    let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let sin_y = y + z * y * (S1 + z * r);
    // fdlibm __kernel_cos(y, 0).
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let one_minus_hz = 1.0 - hz;
    let cos_y = one_minus_hz + (((1.0 - one_minus_hz) - hz) + z * r);
    // Quarter turns: masked indices, in range by construction.
    let q = q & 3;
    let pair = [sin_y, cos_y];
    let odd = q & 1;
    (pair[odd] * SIGN_SIN[q], pair[odd ^ 1] * SIGN_COS[q])
}

/// `(sin 2πt, cos 2πt)` for `t` in turns, `|t| < 2⁴⁹`; for the Earth
/// periodic terms `t` stays within a few turns.
#[inline]
pub(crate) fn sin_cos_turns(t: f64) -> (f64, f64) {
    // k = round(4t); t − k/4 is exact (see the module docs).
    let (k, q) = round_quarter(t * 4.0);
    kernel((t - k * 0.25) * core::f64::consts::TAU, q)
}

/// `(sin x, cos x)` for `x` in degrees, `|x| < 2⁵²`: `k = round(x/90)` and
/// `x − 90k` is exact (`90k` is an integer, a multiple of `ulp(x) ≤ 1`), so
/// a large angle such as a nutation argument at 2·10⁷° (year 6000) loses
/// nothing before the single rounding of `(x − 90k)·π/180`.
#[inline]
pub(crate) fn sin_cos_deg(x: f64) -> (f64, f64) {
    let (k, q) = round_quarter(x * (1.0 / 90.0));
    kernel((x - k * 90.0) * (core::f64::consts::PI / 180.0), q)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dekker's exact product: `a · b = p + e`.
    fn two_prod(a: f64, b: f64) -> (f64, f64) {
        let split = |x: f64| {
            let c = 134_217_729.0 * x; // 2²⁷ + 1
            let hi = c - (c - x);
            (hi, x - hi)
        };
        let p = a * b;
        let (ah, al) = split(a);
        let (bh, bl) = split(b);
        (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
    }

    /// 2π − `TAU` (the rounding of `f64` 2π).
    const TAU_LO: f64 = 2.449_293_598_294_706_4e-16;

    /// An independent reference: 2πt as a double-double (hi, lo) through
    /// Dekker's product, then sin(hi + lo) ≈ sin hi + lo cos hi with libm.
    fn reference(t: f64) -> (f64, f64) {
        let (hi, e) = two_prod(t, core::f64::consts::TAU);
        let lo = e + t * TAU_LO;
        let (s, c) = libm::sincos(hi);
        (s + lo * c, c - lo * s)
    }

    #[test]
    fn matches_a_double_double_reference() {
        // Dense grid over the turns the Earth terms produce, plus the
        // quarter-turn boundaries and their neighbours.
        let mut worst: f64 = 0.0;
        let mut check = |t: f64| {
            let (s, c) = sin_cos_turns(t);
            let (rs, rc) = reference(t);
            worst = worst.max((s - rs).abs()).max((c - rc).abs());
        };
        let n = 400_000;
        for i in 0..=n {
            check(-1.5 + 5.0 * f64::from(i) / f64::from(n) + 1e-9 * f64::from(i % 7));
        }
        for k in -12..=24 {
            let t = f64::from(k) / 8.0;
            for d in [-3e-16, -1e-16, 0.0, 1e-16, 3e-16, 1e-9, -1e-9] {
                check(t + d);
            }
        }
        // One ulp of 1 is 2.2e-16: both the reference (libm near hi, plus
        // the lo correction) and the kernels round a little.
        assert!(worst <= 2.3e-16, "worst absolute error {worst:e}");
    }

    #[test]
    fn degrees_match_a_double_double_reference() {
        // Reference: x° = x · (π/180) as a double-double, reduced by the
        // multiple of 2π nearest it in double-double too (exact for the
        // integer turn counts used here), then sin/cos as above.
        let deg = core::f64::consts::PI / 180.0;
        // π/180 − `deg`.
        let deg_lo = 2.163_813_816_219_386e-19;
        let mut worst: f64 = 0.0;
        for i in 0..200_000 {
            let turns = (i % 1000) as f64 - 500.0;
            let x = turns * 360.0 + (f64::from(i) * 0.001_234_567).rem_euclid(360.0) - 180.0;
            let (s, c) = sin_cos_deg(x);
            // x − 360·turns is exact; the reference works on that remainder.
            let rem = x - turns * 360.0;
            let (hi, e) = two_prod(rem, deg);
            let lo = e + rem * deg_lo;
            let (rs, rc) = libm::sincos(hi);
            let (rs, rc) = (rs + lo * rc, rc - lo * rs);
            worst = worst.max((s - rs).abs()).max((c - rc).abs());
        }
        assert!(worst <= 2.3e-16, "worst absolute error {worst:e}");
        // Large arguments: 2·10⁷° is 55 555 turns and 200°.
        let (s, c) = sin_cos_deg(20_000_000.0);
        let (rs, rc) = sin_cos_deg(200.0);
        assert_eq!((s, c), (rs, rc));
    }

    #[test]
    fn coefficients_are_fdlibms() {
        // The hexadecimal words fdlibm prints beside each coefficient.
        let want: [(f64, u64); 12] = [
            (S1, 0xBFC5_5555_5555_5549),
            (S2, 0x3F81_1111_1110_F8A6),
            (S3, 0xBF2A_01A0_19C1_61D5),
            (S4, 0x3EC7_1DE3_57B1_FE7D),
            (S5, 0xBE5A_E5E6_8A2B_9CEB),
            (S6, 0x3DE5_D93A_5ACF_D57C),
            (C1, 0x3FA5_5555_5555_554C),
            (C2, 0xBF56_C16C_16C1_5177),
            (C3, 0x3EFA_01A0_19CB_1590),
            (C4, 0xBE92_7E4F_809C_52AD),
            (C5, 0x3E21_EE9E_BDB4_B1C4),
            (C6, 0xBDA8_FAE9_BE88_38D4),
        ];
        for (c, bits) in want {
            assert_eq!(c.to_bits(), bits, "{c:e}");
        }
    }

    #[test]
    fn quarter_turns_are_exact() {
        assert_eq!(sin_cos_turns(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_turns(0.25), (1.0, 0.0));
        assert_eq!(sin_cos_turns(0.5), (0.0, -1.0));
        assert_eq!(sin_cos_turns(-0.25), (-1.0, 0.0));
        assert_eq!(sin_cos_turns(3.75), (-1.0, 0.0));
        assert_eq!(sin_cos_deg(90.0), (1.0, 0.0));
        assert_eq!(sin_cos_deg(-270.0), (1.0, 0.0));
        assert_eq!(sin_cos_deg(180.0), (0.0, -1.0));
    }
}
