//! Compact single-precision trigonometry (feature `compact-f32`).
//!
//! libm's `sinf`/`cosf` reduce their argument in `f64`; on 8-bit AVR that
//! pulls in software double arithmetic (over 10 KB of flash). These
//! routines use `f32` arithmetic only (plus integer operations):
//!
//! - **Range reduction** for `sin`/`cos`/`tan`: `k = round(x·2/π)`, then
//!   `r = ((x − k·C1) − k·C2) − k·C3` with π/2 split Cody–Waite style into
//!   `C1` (8 significant bits), `C2` (11 bits) and `C3` (rounded to `f32`):
//!   `k·C1` and `k·C2` are exact products and the first two subtractions
//!   are exact for `|k| < 2¹³`, i.e. **`|x| ≤ 12 867 rad` ([`REDUCTION_LIMIT`])**.
//!   There `r` is accurate to better than 2⁻³⁰ absolute. Beyond the limit
//!   the same formula is used but `k·C2` rounds, and the absolute error
//!   grows roughly in proportion to `|x|` (measured 1e-6 at 1e5 rad); non-finite
//!   inputs give NaN. The algorithms of this crate reduce every angle that
//!   grows with time before calling these, so their arguments stay below
//!   ~30 rad.
//! - **Kernels** on `|r| ≤ π/4`: the minimax polynomials of the Cephes
//!   library (S. L. Moshier, `sinf.c`/`cosf.c`: degree 7 for sine, 8 for
//!   cosine; `atanf.c`, `asinf.c`), Horner in `f32`.
//! - `atan`: `|x| > tan(3π/8)` → `π/2 − atan(1/x)`, `|x| > tan(π/8)` →
//!   `π/4 + atan((x − 1)/(x + 1))`, then the kernel. `atan2` takes the
//!   quadrant from the signs (IEEE special cases included). `asin`: the
//!   kernel below 0.5, `π/2 − 2·asin(√((1 − |x|)/2))` above; `acos` from
//!   the same pieces without cancellation near ±1.
//!
//! Accuracy (tests below, against libm's `f64` functions on dense grids):
//! `sin`, `cos` within 2 ulp on `|x| ≤ 2π` and within 2⁻²³ absolute (2 ulp
//! of 1) on `|x| ≤ 10⁴`; `tan` within 4 ulp on `|x| < 1.5`; `atan`, `atan2`,
//! `asin`, `acos` within 2–3 ulp (the tests print the measured figures).
//!
//! # Example
//!
//! ```
//! use sun_algos::compact;
//!
//! // Against the standard library's f64 functions on a grid of 0…2π: within
//! // 2 ulp of 1 (2⁻²²) — the bound stated above.
//! for i in 0..=1000 {
//!     let x = i as f32 * core::f32::consts::TAU / 1000.0;
//!     let (s, c) = compact::sin_cos(x);
//!     assert!((f64::from(s) - f64::from(x).sin()).abs() < 2.4e-7, "{x}");
//!     assert!((f64::from(c) - f64::from(x).cos()).abs() < 2.4e-7, "{x}");
//! }
//! ```

/// Largest `|x|` for which the sine/cosine reduction is exact (`|k| < 2¹³`).
///
/// ```
/// use sun_algos::compact::{sin, REDUCTION_LIMIT};
///
/// // Up to the limit the reduction is exact: sin agrees with the standard
/// // library's f64 sine of the same f32 argument to about 1e-7.
/// let x = REDUCTION_LIMIT;
/// assert!((f64::from(sin(x)) - f64::from(x).sin()).abs() < 2.4e-7);
/// ```
pub const REDUCTION_LIMIT: f32 = 12_867.0;

/// π/2 = C1 + C2 + C3: C1 has 8 significant bits (201/128).
const C1: f32 = 1.570_312_5;
/// Next 11 bits of π/2: 2029 × 2⁻²² (f32 bits 0x39FDA000).
const C2: f32 = f32::from_bits(0x39FD_A000); // 4.837513e-4
/// The rest of π/2, rounded to f32 (π/2 − C1 − C2 − C3 ≈ −1.7e−15).
const C3: f32 = f32::from_bits(0x33A2_2169); // 7.549790e-8

const FRAC_2_PI: f32 = core::f32::consts::FRAC_2_PI;
const FRAC_PI_2: f32 = core::f32::consts::FRAC_PI_2;
const FRAC_PI_4: f32 = core::f32::consts::FRAC_PI_4;
const PI: f32 = core::f32::consts::PI;
/// π − `PI` (the rounding error of the f32 π): π = `PI + PI_LO`.
const PI_LO: f32 = -8.742_278e-8;
/// π/2 − `FRAC_PI_2`: π/2 = `FRAC_PI_2 + FRAC_PI_2_LO`.
const FRAC_PI_2_LO: f32 = -4.371_139e-8;

/// Reduces `x` to `r` in about `[−π/4, π/4]` and the quadrant `k mod 4`.
#[inline]
fn reduce(x: f32) -> (f32, i32) {
    if x.abs() <= FRAC_PI_4 {
        return (x, 0);
    }
    let half = if x < 0.0 { -0.5 } else { 0.5 };
    // `as i32` saturates; finite inputs only reach here.
    let k = (x * FRAC_2_PI + half) as i32;
    let kf = k as f32;
    let r = ((x - kf * C1) - kf * C2) - kf * C3;
    (r, k & 3)
}

/// sin on `[−π/4, π/4]` (Cephes `sinf` polynomial).
#[inline]
fn sin_kernel(r: f32) -> f32 {
    let z = r * r;
    ((-1.951_529_6e-4 * z + 8.332_161e-3) * z - 1.666_665_5e-1) * z * r + r
}

/// cos on `[−π/4, π/4]` (Cephes `cosf` polynomial).
#[inline]
fn cos_kernel(r: f32) -> f32 {
    let z = r * r;
    ((2.443_315_7e-5 * z - 1.388_731_6e-3) * z + 4.166_664_6e-2) * z * z - 0.5 * z + 1.0
}

/// Sine of `x` radians (only the kernel the quadrant needs; the same
/// result as `sin_cos(x).0`).
///
/// ```
/// use sun_algos::compact::sin;
///
/// assert!((sin(core::f32::consts::FRAC_PI_6) - 0.5).abs() < 1e-7);
/// assert!((f64::from(sin(100.0)) - 100f64.sin()).abs() < 2.4e-7); // std's f64 sine
/// assert!(sin(f32::NAN).is_nan());
/// ```
pub fn sin(x: f32) -> f32 {
    if !x.is_finite() {
        return f32::NAN;
    }
    let (r, q) = reduce(x);
    sin_in_quadrant(r, q)
}

/// sin(r + q·π/2) from the kernels (`q` taken mod 4): the sine for the
/// quadrant `q`, the cosine for `q + 1`.
fn sin_in_quadrant(r: f32, q: i32) -> f32 {
    match q & 3 {
        0 => sin_kernel(r),
        1 => cos_kernel(r),
        2 => -sin_kernel(r),
        _ => -cos_kernel(r),
    }
}

/// Cosine of `x` radians (only the kernel the quadrant needs; the same
/// result as `sin_cos(x).1`).
///
/// ```
/// use sun_algos::compact::cos;
///
/// assert!((cos(core::f32::consts::FRAC_PI_3) - 0.5).abs() < 1e-7);
/// assert!((f64::from(cos(-7.5)) - (-7.5f64).cos()).abs() < 2.4e-7); // std's f64 cosine
/// ```
pub fn cos(x: f32) -> f32 {
    if !x.is_finite() {
        return f32::NAN;
    }
    let (r, q) = reduce(x);
    // cos(r + q·π/2) = sin(r + (q + 1)·π/2).
    sin_in_quadrant(r, q.wrapping_add(1))
}

/// Sine and cosine of `x` radians, sharing one reduction.
///
/// ```
/// use sun_algos::compact::{cos, sin, sin_cos};
///
/// // The same as sin and cos apart, from one reduction.
/// for x in [0.1f32, 1.0, 2.5, -4.0, 1000.0] {
///     assert_eq!(sin_cos(x), (sin(x), cos(x)));
/// }
/// let (s, c) = sin_cos(core::f32::consts::FRAC_PI_4);
/// assert!((s - core::f32::consts::FRAC_1_SQRT_2).abs() < 1e-7 && (c - s).abs() < 1e-7);
/// ```
pub fn sin_cos(x: f32) -> (f32, f32) {
    if !x.is_finite() {
        return (f32::NAN, f32::NAN);
    }
    let (r, q) = reduce(x);
    let (s, c) = (sin_kernel(r), cos_kernel(r));
    match q {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// Tangent of `x` radians.
///
/// ```
/// use sun_algos::compact::tan;
///
/// assert!((tan(core::f32::consts::FRAC_PI_4) - 1.0).abs() < 2e-7);
/// assert!((f64::from(tan(1.4)) - 1.4f64.tan()).abs() < 4e-6); // std's f64 tangent (≈ 5.8)
/// ```
pub fn tan(x: f32) -> f32 {
    if !x.is_finite() {
        return f32::NAN;
    }
    let (r, q) = reduce(x);
    let (s, c) = (sin_kernel(r), cos_kernel(r));
    if q & 1 == 0 {
        s / c
    } else {
        -c / s
    }
}

/// atan on `[−tan(π/8), tan(π/8)]` (Cephes `atanf` polynomial).
#[inline]
fn atan_kernel(x: f32) -> f32 {
    let z = x * x;
    (((8.053_744_5e-2 * z - 1.387_768_6e-1) * z + 1.997_771_1e-1) * z - 3.333_295e-1) * z * x + x
}

/// Arctangent, radians in `[−π/2, π/2]`.
///
/// ```
/// use sun_algos::compact::atan;
///
/// assert!((atan(1.0) - core::f32::consts::FRAC_PI_4).abs() < 1e-7);
/// assert!((f64::from(atan(1e6)) - 1e6f64.atan()).abs() < 2.4e-7); // π/2 − 1e-6
/// assert!((f64::from(atan(0.3)) - 0.3f64.atan()).abs() < 1e-7); // std's f64
/// ```
pub fn atan(x: f32) -> f32 {
    if x.is_nan() {
        return f32::NAN;
    }
    let a = x.abs();
    let y = if a > 2.414_213_6 {
        // π/2 − atan(1/a), with π/2 in two parts.
        (FRAC_PI_2 - atan_kernel(1.0 / a)) + FRAC_PI_2_LO
    } else if a > 0.414_213_57 {
        FRAC_PI_4 + atan_kernel((a - 1.0) / (a + 1.0))
    } else {
        atan_kernel(a)
    };
    if x < 0.0 {
        -y
    } else {
        y
    }
}

/// Four-quadrant arctangent of `y/x`, radians in `[−π, π]`.
///
/// ```
/// use sun_algos::compact::atan2;
/// use core::f32::consts::{FRAC_PI_2, PI};
///
/// // Every quadrant: 3π/4 for (1, −1), −π/2 straight down.
/// assert!((atan2(1.0, -1.0) - 3.0 * PI / 4.0).abs() < 3e-7);
/// assert!((atan2(-1.0, 0.0) + FRAC_PI_2).abs() < 1e-7);
/// assert!((f64::from(atan2(-0.2, -3.0)) - (-0.2f64).atan2(-3.0)).abs() < 3e-7); // std's f64
/// ```
pub fn atan2(y: f32, x: f32) -> f32 {
    if x.is_nan() || y.is_nan() {
        return f32::NAN;
    }
    let neg_y = y.is_sign_negative();
    let signed = |v: f32| if neg_y { -v } else { v };
    if y == 0.0 {
        // ±0 or ±π by the sign of x (IEEE 754 atan2).
        return if x.is_sign_negative() {
            signed(PI)
        } else {
            signed(0.0)
        };
    }
    if x == 0.0 {
        return signed(FRAC_PI_2);
    }
    if x.is_infinite() {
        return match (y.is_infinite(), x > 0.0) {
            (true, true) => signed(FRAC_PI_4),
            (true, false) => signed(3.0 * FRAC_PI_4),
            (false, true) => signed(0.0),
            (false, false) => signed(PI),
        };
    }
    if y.is_infinite() {
        return signed(FRAC_PI_2);
    }
    let t = atan((y / x).abs());
    let a = if x > 0.0 { t } else { (PI - t) + PI_LO };
    signed(a)
}

/// asin on `[0, 0.5]` (Cephes `asinf` polynomial).
#[inline]
fn asin_kernel(x: f32) -> f32 {
    let z = x * x;
    ((((4.216_32e-2 * z + 2.418_131e-2) * z + 4.547_002_6e-2) * z + 7.495_300_3e-2) * z
        + 1.666_675_2e-1)
        * z
        * x
        + x
}

/// Arcsine, radians in `[−π/2, π/2]`; NaN outside `[−1, 1]`.
///
/// ```
/// use sun_algos::compact::asin;
///
/// assert!((asin(0.5) - core::f32::consts::FRAC_PI_6).abs() < 1e-7);
/// assert!((f64::from(asin(0.99)) - 0.99f64.asin()).abs() < 3e-7); // std's f64
/// assert!(asin(1.5).is_nan());
/// ```
pub fn asin(x: f32) -> f32 {
    let a = x.abs();
    if a.is_nan() || a > 1.0 {
        return f32::NAN;
    }
    let y = if a > 0.5 {
        let s = sqrt(0.5 * (1.0 - a));
        (FRAC_PI_2 - 2.0 * asin_kernel(s)) + FRAC_PI_2_LO
    } else {
        asin_kernel(a)
    };
    if x < 0.0 {
        -y
    } else {
        y
    }
}

/// Square root, correctly rounded (IEEE 754-2008 §5.4.1 requires it of
/// every implementation, so the result is the same bits everywhere); NaN
/// below zero.
///
/// On a hard-float ARM target (ABI `eabihf`: every such core has a VFP
/// unit, and VFPv2 and later execute `VSQRT.F32`, Arm *Architecture
/// Reference Manual ARMv7-M*, A7.7.256) one instruction; elsewhere libm's
/// `sqrtf` (software, about 500 bytes of code and tables on a Cortex-M4F).
///
/// ```
/// use sun_algos::compact::sqrt;
///
/// assert_eq!(sqrt(2.25), 1.5);
/// // The f32 nearest √2 (0x3FB504F3), as std's correctly rounded f32 sqrt.
/// assert_eq!(sqrt(2.0).to_bits(), 0x3FB5_04F3);
/// assert!(sqrt(-1.0).is_nan());
/// ```
// Out of line on ARM: the value's moves to and from s0 beside the VSQRT
// make each inlined copy larger than a call (15 callers on the Black Pill).
#[cfg_attr(all(target_arch = "arm", target_abi = "eabihf"), inline(never))]
#[cfg_attr(not(all(target_arch = "arm", target_abi = "eabihf")), inline)]
pub fn sqrt(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        let root_bits: u32;
        // The value goes through a core register and s0, declared
        // clobbered: stable Rust offers the `sreg` operand class only with
        // the `vfp2` target feature, which is unstable to name.
        // SAFETY: VMOV and VSQRT.F32 touch no memory, no stack and no APSR
        // flag (VSQRT sets only FPSCR's cumulative exception bits, which
        // Rust does not model); s0 is declared clobbered.
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                "vmov s0, {x}",
                "vsqrt.f32 s0, s0",
                "vmov {root}, s0",
                x = in(reg) x.to_bits(),
                root = lateout(reg) root_bits,
                out("s0") _,
                options(pure, nomem, nostack, preserves_flags),
            );
        }
        f32::from_bits(root_bits)
    }
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
    {
        libm::sqrtf(x)
    }
}

/// Arccosine, radians in `[0, π]`; NaN outside `[−1, 1]`.
///
/// ```
/// use sun_algos::compact::acos;
///
/// assert!((acos(0.5) - core::f32::consts::FRAC_PI_3).abs() < 1e-7);
/// // Near π an f32 ulp is 2.4e-7: within 3 ulp of std's f64.
/// assert!((f64::from(acos(-0.999)) - (-0.999f64).acos()).abs() < 7.2e-7);
/// assert!(acos(-1.5).is_nan());
/// ```
pub fn acos(x: f32) -> f32 {
    let a = x.abs();
    if a.is_nan() || a > 1.0 {
        return f32::NAN;
    }
    if a <= 0.5 {
        return (FRAC_PI_2 - asin_kernel(x)) + FRAC_PI_2_LO;
    }
    let s = sqrt(0.5 * (1.0 - a));
    let t = 2.0 * asin_kernel(s);
    if x > 0.0 {
        t
    } else {
        (PI - t) + PI_LO
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    /// One unit in the last place of an f32 near `v` (f64 math on the host).
    fn ulp(v: f64) -> f64 {
        let a = (v.abs() as f32).max(f32::MIN_POSITIVE);
        let bits = a.to_bits();
        f64::from(f32::from_bits(bits + 1)) - f64::from(f32::from_bits(bits))
    }

    /// Max error in ulps of the exact result over `n` points of `[lo, hi]`.
    fn max_ulp(f: fn(f32) -> f32, exact: fn(f64) -> f64, lo: f32, hi: f32, n: u32) -> f64 {
        let mut worst = 0.0f64;
        for i in 0..=n {
            let x = lo + (hi - lo) * (i as f32 / n as f32);
            let e = exact(f64::from(x));
            let d = (f64::from(f(x)) - e).abs() / ulp(e);
            worst = worst.max(d);
        }
        worst
    }

    /// Max absolute error over `n` points of `[lo, hi]`.
    fn max_abs(f: fn(f32) -> f32, exact: fn(f64) -> f64, lo: f32, hi: f32, n: u32) -> f64 {
        let mut worst = 0.0f64;
        for i in 0..=n {
            let x = lo + (hi - lo) * (i as f32 / n as f32);
            worst = worst.max((f64::from(f(x)) - exact(f64::from(x))).abs());
        }
        worst
    }

    #[test]
    fn sin_cos_within_two_ulp_on_a_turn() {
        let s = max_ulp(sin, libm::sin, -6.3, 6.3, 400_000);
        let c = max_ulp(cos, libm::cos, -6.3, 6.3, 400_000);
        std::println!("|x| <= 6.3: sin {s} ulp, cos {c} ulp");
        assert!(s <= 2.0 && c <= 2.0, "sin {s} cos {c} ulp");
        // Every f32 in [0, π/4] near zero: relative accuracy kept.
        let s = max_ulp(sin, libm::sin, 1e-6, 1e-2, 100_000);
        assert!(s <= 2.0, "{s}");
    }

    #[test]
    fn sin_cos_large_arguments_up_to_the_limit() {
        let s = max_abs(sin, libm::sin, -1e4, 1e4, 2_000_000);
        let c = max_abs(cos, libm::cos, -1e4, 1e4, 2_000_000);
        let lim = 2f64.powi(-23);
        std::println!("|x| <= 1e4: sin {s:e}, cos {c:e} absolute");
        assert!(s <= lim && c <= lim, "sin {s} cos {c}");
        let s = max_abs(sin, libm::sin, 1e4, REDUCTION_LIMIT, 200_000);
        assert!(s <= lim, "{s}");
        // Beyond the limit: documented growth (about 2e-7 at 1e5 rad).
        let s = max_abs(sin, libm::sin, 9e4, 1e5, 200_000);
        std::println!("9e4 <= x <= 1e5: sin {s:e} absolute");
        assert!(s < 2e-6, "{s}");
    }

    #[test]
    fn sin_cos_agrees_with_sin_and_cos() {
        for i in 0..10_000 {
            let x = -50.0 + i as f32 * 0.01;
            assert_eq!(sin_cos(x), (sin(x), cos(x)));
        }
    }

    #[test]
    fn tan_within_four_ulp() {
        let t = max_ulp(tan, libm::tan, -1.5, 1.5, 400_000);
        std::println!("tan |x| <= 1.5: {t} ulp");
        assert!(t <= 4.0, "{t}");
        // Relative error stays small near the poles (|x| up to 1.57).
        let t = max_ulp(tan, libm::tan, 1.5, FRAC_PI_2 - 1e-4, 20_000);
        assert!(t <= 4.0, "{t}");
    }

    #[test]
    fn atan_asin_acos_within_a_few_ulp() {
        let a = max_ulp(atan, libm::atan, -20.0, 20.0, 400_000);
        assert!(a <= 2.0, "atan {a}");
        let a = max_ulp(atan, libm::atan, 20.0, 1e6, 100_000);
        assert!(a <= 2.0, "atan far {a}");
        let s = max_ulp(asin, libm::asin, -1.0, 1.0, 400_000);
        assert!(s <= 3.0, "asin {s}");
        let c = max_ulp(acos, libm::acos, -1.0, 1.0, 400_000);
        std::println!("atan {a} ulp, asin {s} ulp, acos {c} ulp");
        assert!(c <= 3.0, "acos {c}");
    }

    #[test]
    fn atan2_all_quadrants() {
        let mut worst = 0.0f64;
        for i in 0..720 {
            let ang = (i as f64 + 0.37) * core::f64::consts::PI / 360.0 - core::f64::consts::PI;
            for r in [1e-3f64, 0.7, 1.0, 3e4] {
                let (y, x) = ((r * ang.sin()) as f32, (r * ang.cos()) as f32);
                let e = libm::atan2(f64::from(y), f64::from(x));
                worst = worst.max((f64::from(atan2(y, x)) - e).abs() / ulp(e));
            }
        }
        std::println!("atan2 {worst} ulp");
        assert!(worst <= 3.0, "{worst}");
    }

    #[test]
    fn special_values_follow_ieee() {
        let inf = f32::INFINITY;
        for (y, x) in [
            (0.0, 1.0),
            (-0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (inf, inf),
            (-inf, inf),
            (inf, -inf),
            (-inf, -inf),
            (1.0, inf),
            (1.0, -inf),
            (-1.0, -inf),
            (inf, 1.0),
            (0.0, 0.0),
            (0.0, -0.0),
        ] {
            let ours = atan2(y, x);
            let libm = libm::atan2f(y, x);
            assert!(
                (ours - libm).abs() <= 2.4e-7 && ours.is_sign_negative() == libm.is_sign_negative(),
                "atan2({y}, {x}) = {ours}, libm {libm}"
            );
        }
        assert!(atan2(f32::NAN, 1.0).is_nan());
        assert!(sin(inf).is_nan() && cos(f32::NAN).is_nan() && tan(-inf).is_nan());
        assert!(asin(1.0001).is_nan() && acos(-1.5).is_nan());
        assert_eq!(asin(1.0), FRAC_PI_2);
        assert_eq!(acos(1.0), 0.0);
        assert!((acos(-1.0) - PI).abs() <= 1e-7);
        assert_eq!(atan(inf), FRAC_PI_2);
        assert_eq!(sin(0.0), 0.0);
        assert_eq!(cos(0.0), 1.0);
    }
}
