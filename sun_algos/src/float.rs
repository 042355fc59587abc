//! The one math trait every algorithm is written against.
//!
//! All trigonometry of the crate goes through [`Float`], implemented for
//! `f32` and `f64`. The default backend is `libm`; with the `compact-f32`
//! feature `f32` uses the crate's own single-precision routines
//! (module `compact`, public with that feature) so AVR images carry no software double arithmetic.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// Floating-point type usable by the algorithms (`f32` or `f64`).
///
/// ```
/// use sun_algos::Float;
///
/// // One formula for f32 and f64: the hour angle of sunrise, cos ω = −tan φ tan δ
/// // (Duffie & Beckman eq. 1.6.10). At the equinox (δ = 0) it is 90° everywhere.
/// fn sunset_hour_angle_deg<T: Float>(latitude_deg: T, declination_deg: T) -> T {
///     let c = -(latitude_deg.to_radians().tan() * declination_deg.to_radians().tan());
///     c.clamp(-T::ONE, T::ONE).acos().to_degrees()
/// }
/// assert!((sunset_hour_angle_deg(52.0f64, 0.0) - 90.0).abs() < 1e-12);
/// assert!((sunset_hour_angle_deg(52.0f32, 0.0) - 90.0).abs() < 1e-5);
/// // At 52° N with δ = 23.44° (the June solstice): 2ω/15 = 16.4942 h of
/// // daylight, as pvlib 0.16.1's `sun_rise_set_transit_geometric` gives.
/// let w = sunset_hour_angle_deg(52.0f64, 23.44);
/// assert!((2.0 * w / 15.0 - 16.494_2).abs() < 1e-4);
/// // The exact values of sine, cosine and the 3-4-5 triangle.
/// assert!(((30.0f64).to_radians().sin() - 0.5).abs() < 1e-15);
/// assert!(((60.0f32).to_radians().cos() - 0.5).abs() < 1e-6);
/// assert_eq!(Float::sqrt(3.0f64 * 3.0 + 4.0 * 4.0), 5.0);
/// assert_eq!(Float::rem_euclid(-90.0f32, 360.0), 270.0);
/// ```
pub trait Float:
    Copy
    + Debug
    + Default
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
{
    /// 0
    const ZERO: Self;
    /// 1
    const ONE: Self;
    /// π
    const PI: Self;
    /// 2π
    const TAU: Self;
    /// π/2
    const FRAC_PI_2: Self;

    /// Converts an `f64` (used for constants; folds at compile time).
    fn from_f64(v: f64) -> Self;
    /// Converts an `i32` exactly when it fits the mantissa.
    fn from_i32(v: i32) -> Self;
    /// Converts a `u32`.
    fn from_u32(v: u32) -> Self;
    /// Widens to `f64` (host tools and tests).
    fn to_f64(self) -> f64;
    /// Converts an `f32` (configuration values; exact, and free for `f32`).
    fn from_f32(v: f32) -> Self;
    /// Narrows to `f32` (axis set-points; free for `f32`).
    fn to_f32(self) -> f32;
    /// The value nearest `num / den` (halves to even), rounded once from
    /// the integers themselves: exact decimal readings such as a GPS
    /// latitude `ddmm.mmmmm` (`f32` never goes through `f64`). `den = 0`
    /// gives ±∞, or NaN for `0 / 0`.
    ///
    /// ```
    /// use sun_algos::Float;
    ///
    /// // 47°17.11399' = 283 711 399 / 6 000 000° (u-blox's GGA example).
    /// let (num, den) = (283_711_399, 6_000_000);
    /// assert_eq!(f64::from_ratio(num, den), num as f64 / den as f64);
    /// assert_eq!(f32::from_ratio(num, den), 47.285_233_f32);
    /// // 2^24 + 1 is no f32: the halfway case goes to the even neighbour.
    /// assert_eq!(f32::from_ratio((1 << 24) + 1, 1), 16_777_216.0);
    /// assert_eq!(f32::from_ratio(-1, 0), f32::NEG_INFINITY);
    /// ```
    #[inline]
    fn from_ratio(num: i64, den: u64) -> Self {
        Self::from_f64(f64::from_ratio(num, den))
    }
    /// `self` as an integer times a power of two, exactly: `Some((m, e))`
    /// with `self = m · 2^e`; `None` for NaN and ±∞.
    ///
    /// ```
    /// use sun_algos::Float;
    ///
    /// let (m, e) = Float::to_mantissa_exp2(-0.375f32).unwrap();
    /// assert_eq!(m as f64 * 2f64.powi(e), -0.375);
    /// assert_eq!(Float::to_mantissa_exp2(f64::NAN), None);
    /// ```
    #[inline]
    fn to_mantissa_exp2(self) -> Option<(i64, i32)> {
        self.to_f64().to_mantissa_exp2()
    }

    /// `⌊x·100 + ½⌋` modulo 36 000 for `x = self`, exactly: a value in
    /// degrees rounded to whole centidegrees (halves up) and folded into
    /// one turn, `0..36 000`; 0 for NaN and ±∞. Computed from the value's
    /// own bits ([`Float::to_mantissa_exp2`]), never through a wider float.
    ///
    /// ```
    /// use sun_algos::Float;
    ///
    /// // 0.055 is 0.054999999701… in f32 (5.4999999701… cdeg) and
    /// // 0.055000000000000000277… in f64 (5.5000000000000000277… cdeg).
    /// assert_eq!(0.055f32.centi_round_mod_turn(), 5);
    /// assert_eq!(0.055f64.centi_round_mod_turn(), 6);
    /// // −0.125° is −12.5 cdeg: the half goes up, to −12 ≡ 35 988.
    /// assert_eq!((-0.125f32).centi_round_mod_turn(), 35_988);
    /// assert_eq!(720.0f64.centi_round_mod_turn(), 0);
    /// assert_eq!(f32::NAN.centi_round_mod_turn(), 0);
    /// ```
    fn centi_round_mod_turn(self) -> u32 {
        self.to_mantissa_exp2()
            .map_or(0, |(m, e)| centi_round_mod_turn_i64(m, e))
    }

    /// Sine of an angle in radians.
    fn sin(self) -> Self;
    /// Cosine of an angle in radians.
    fn cos(self) -> Self;
    /// Tangent of an angle in radians.
    fn tan(self) -> Self;
    /// Arcsine, radians.
    fn asin(self) -> Self;
    /// Arccosine, radians.
    fn acos(self) -> Self;
    /// Arctangent, radians.
    fn atan(self) -> Self;
    /// Four-quadrant arctangent of `self / x`, radians.
    fn atan2(self, x: Self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Largest integer not above `self`.
    fn floor(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// e^self
    fn exp(self) -> Self;
    /// Natural logarithm.
    fn ln(self) -> Self;
    /// `self` raised to `e`.
    fn powf(self, e: Self) -> Self;
    /// Neither NaN nor infinite.
    fn is_finite(self) -> bool;

    /// Sine and cosine together.
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        (self.sin(), self.cos())
    }
    /// Degrees to radians.
    // Out of line on the AVR, as `clamp`: a call takes its argument where
    // it is, the product loads the constant too.
    #[cfg_attr(not(target_arch = "avr"), inline)]
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn to_radians(self) -> Self {
        self * (Self::PI / Self::from_f64(180.0))
    }
    /// Radians to degrees.
    // Out of line on the AVR, as `clamp`: a call takes its argument where
    // it is, the product loads the constant too.
    #[cfg_attr(not(target_arch = "avr"), inline)]
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn to_degrees(self) -> Self {
        self * (Self::from_f64(180.0) / Self::PI)
    }
    /// Euclidean remainder: the result lies in `[0, m)` for `m > 0`.
    // Out of line on the AVR, as `clamp`.
    #[cfg_attr(not(target_arch = "avr"), inline)]
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn rem_euclid(self, m: Self) -> Self {
        let r = self - (self / m).floor() * m;
        // Rounding can land exactly on `m` for tiny negative inputs.
        if r >= m || r < Self::ZERO {
            Self::ZERO
        } else {
            r
        }
    }
    /// The smaller of two values.
    // Out of line on the AVR, as `clamp`.
    #[cfg_attr(not(target_arch = "avr"), inline)]
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn min(self, o: Self) -> Self {
        if o < self {
            o
        } else {
            self
        }
    }
    /// The larger of two values.
    // Out of line on the AVR, as `clamp`.
    #[cfg_attr(not(target_arch = "avr"), inline)]
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn max(self, o: Self) -> Self {
        if o > self {
            o
        } else {
            self
        }
    }
    /// Clamps into `[lo, hi]`.
    // Out of line on the AVR: the two soft-float comparisons and their
    // selects, written out at each caller, cost more than a call.
    #[cfg_attr(not(target_arch = "avr"), inline)]
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }
}

impl Float for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const PI: Self = core::f64::consts::PI;
    const TAU: Self = core::f64::consts::TAU;
    const FRAC_PI_2: Self = core::f64::consts::FRAC_PI_2;

    #[inline]
    fn from_f64(v: f64) -> Self {
        v
    }
    #[inline]
    fn from_i32(v: i32) -> Self {
        v as f64
    }
    #[inline]
    fn from_u32(v: u32) -> Self {
        v as f64
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline]
    fn from_f32(v: f32) -> Self {
        f64::from(v)
    }
    #[inline]
    fn to_f32(self) -> f32 {
        self as f32
    }
    fn from_ratio(num: i64, den: u64) -> Self {
        f64::from_bits(ratio_bits(num, den, F64_FORMAT))
    }
    fn to_mantissa_exp2(self) -> Option<(i64, i32)> {
        mantissa_exp2(self.to_bits(), F64_FORMAT)
    }
    #[inline]
    fn sin(self) -> Self {
        libm::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        libm::cos(self)
    }
    #[inline]
    fn tan(self) -> Self {
        libm::tan(self)
    }
    #[inline]
    fn asin(self) -> Self {
        libm::asin(self)
    }
    #[inline]
    fn acos(self) -> Self {
        libm::acos(self)
    }
    #[inline]
    fn atan(self) -> Self {
        libm::atan(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        libm::atan2(self, x)
    }
    #[inline]
    fn sqrt(self) -> Self {
        libm::sqrt(self)
    }
    #[inline]
    fn floor(self) -> Self {
        libm::floor(self)
    }
    #[inline]
    fn abs(self) -> Self {
        libm::fabs(self)
    }
    #[inline]
    fn exp(self) -> Self {
        libm::exp(self)
    }
    #[inline]
    fn ln(self) -> Self {
        libm::log(self)
    }
    #[inline]
    fn powf(self, e: Self) -> Self {
        libm::pow(self, e)
    }
    #[inline]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        libm::sincos(self)
    }
}

impl Float for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const PI: Self = core::f32::consts::PI;
    const TAU: Self = core::f32::consts::TAU;
    const FRAC_PI_2: Self = core::f32::consts::FRAC_PI_2;

    #[inline]
    fn from_f64(v: f64) -> Self {
        v as f32
    }
    #[inline]
    fn from_i32(v: i32) -> Self {
        v as f32
    }
    #[inline]
    fn from_u32(v: u32) -> Self {
        v as f32
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline]
    fn from_f32(v: f32) -> Self {
        v
    }
    #[inline]
    fn to_f32(self) -> f32 {
        self
    }
    fn from_ratio(num: i64, den: u64) -> Self {
        // The bits of an f32 fill the low half of the u64.
        f32::from_bits(ratio_bits(num, den, F32_FORMAT) as u32)
    }
    fn to_mantissa_exp2(self) -> Option<(i64, i32)> {
        mantissa_exp2(u64::from(self.to_bits()), F32_FORMAT)
    }
    // In 32-bit integers: an f32's significand times 100 stays below 2^31
    // (the 64-bit path took about 1 KB more on the AVR).
    fn centi_round_mod_turn(self) -> u32 {
        let bits = self.to_bits();
        let field = (bits >> 23) & 0xff;
        if field == 0xff {
            return 0;
        }
        let fraction = bits & 0x7f_ffff;
        // Subnormals (field 0) have no hidden bit and the exponent of field 1.
        let (m, field) = if field == 0 {
            (fraction, 1)
        } else {
            (fraction | 1 << 23, field)
        };
        // field ≤ 254: e in −149..=104.
        let e = field as i32 - 150;
        // m < 2^24: m·100 < 2^31.
        let y = (m * 100) as i32;
        let y = if bits >> 31 != 0 { -y } else { y };
        const TURN: i32 = CENTI_TURN as i32;
        if e >= 0 {
            // A whole number y·2^e: doubled e times modulo the turn.
            (0..e).fold(y.rem_euclid(TURN) as u32, |r, _| r * 2 % CENTI_TURN)
        } else if e < -31 {
            // |y·2^e| < 2^31·2^−32: ⌊y·2^e + ½⌋ = 0.
            0
        } else {
            // ⌊y/2^s + ½⌋ = ⌊(⌊y/2^(s−1)⌋ + 1) / 2⌋ for s = −e (arithmetic
            // shifts round towards −∞; |y >> (s−1)| ≤ 2^30, no overflow).
            let s = e.unsigned_abs();
            (((y >> (s - 1)) + 1) >> 1).rem_euclid(TURN) as u32
        }
    }
    #[inline]
    fn sin(self) -> Self {
        backend32::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        backend32::cos(self)
    }
    #[inline]
    fn tan(self) -> Self {
        backend32::tan(self)
    }
    #[inline]
    fn asin(self) -> Self {
        backend32::asin(self)
    }
    #[inline]
    fn acos(self) -> Self {
        backend32::acos(self)
    }
    #[inline]
    fn atan(self) -> Self {
        backend32::atan(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        backend32::atan2(self, x)
    }
    #[inline]
    fn sqrt(self) -> Self {
        backend32::sqrt(self)
    }
    #[inline]
    fn floor(self) -> Self {
        backend32::floor(self)
    }
    #[inline]
    fn abs(self) -> Self {
        libm::fabsf(self)
    }
    #[inline]
    fn exp(self) -> Self {
        libm::expf(self)
    }
    #[inline]
    fn ln(self) -> Self {
        libm::logf(self)
    }
    #[inline]
    fn powf(self, e: Self) -> Self {
        libm::powf(self, e)
    }
    // Out of line on the AVR, as `clamp`.
    #[cfg_attr(not(target_arch = "avr"), inline)]
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        backend32::sin_cos(self)
    }
}

/// An IEEE 754 binary format: significand bits (the hidden one counted)
/// and exponent field width.
#[derive(Clone, Copy)]
struct Format {
    digits: u32,
    exponent_bits: u32,
}

const F32_FORMAT: Format = Format {
    digits: 24,
    exponent_bits: 8,
};
const F64_FORMAT: Format = Format {
    digits: 53,
    exponent_bits: 11,
};

impl Format {
    /// Exponent bias: 127 (f32), 1023 (f64).
    const fn bias(self) -> i32 {
        (1 << (self.exponent_bits - 1)) - 1
    }
    /// Bit position of the sign: 31 (f32), 63 (f64).
    const fn sign_shift(self) -> u32 {
        self.digits - 1 + self.exponent_bits
    }
}

/// The bits of the value nearest `num / den` in `format` (see
/// [`Float::from_ratio`]).
///
/// Restoring division (Knuth, *TAOCP* vol. 2, §4.3.1) on the operands
/// shifted up to their top bit, one quotient bit per step: `digits + 1`
/// bits, the last being the rounding bit, and the remainder's non-zero-ness
/// as the sticky bit (IEEE 754 round to nearest, ties to even). Any `i64`
/// over any `u64` lies within 2^±64, a normal number of both formats, so
/// no subnormal or overflowing result arises.
fn ratio_bits(num: i64, den: u64, format: Format) -> u64 {
    let sign = u64::from(num < 0) << format.sign_shift();
    let n = num.unsigned_abs();
    let all_ones_exponent = ((1u64 << format.exponent_bits) - 1) << (format.digits - 1);
    if den == 0 {
        // ±∞, or a quiet NaN for 0 / 0.
        let quiet = if n == 0 { 1 << (format.digits - 2) } else { 0 };
        return sign | all_ones_exponent | quiet;
    }
    if n == 0 {
        return 0;
    }
    // n / den = (r / d) · 2^e with r, d in [2^63, 2^64), shifted up a bit
    // at a time: on an 8-bit core a 64-bit leading-zero count and shift by
    // a variable amount take some 1.5 KB, this loop a few dozen bytes.
    let (mut r, mut d, mut e) = (n, den, 0i32);
    while r >> 63 == 0 {
        r <<= 1;
        e -= 1;
    }
    while d >> 63 == 0 {
        d <<= 1;
        e += 1;
    }
    // The remainder has a 65th bit, `carry`, once doubled.
    let mut carry = false;
    if r < d {
        // r ≥ 2^63, so 2r ≥ 2^64 > d: now r / d lies in [1, 2).
        carry = true;
        r <<= 1;
        e -= 1;
    }
    let mut q: u64 = 0;
    for _ in 0..=format.digits {
        q <<= 1;
        if carry || r >= d {
            // With the carry the true remainder is 2^64 + r; the wrapped
            // difference is exact, below d.
            r = r.wrapping_sub(d);
            q |= 1;
        }
        carry = r >> 63 != 0;
        r <<= 1;
    }
    // q = ⌊(n / den) · 2^(digits − e)⌋ in [2^digits, 2^(digits + 1)).
    let sticky = carry || r != 0;
    let mut m = q >> 1;
    if q & 1 != 0 && (sticky || m & 1 != 0) {
        m += 1;
        if m >> format.digits != 0 {
            // Rounded up to the next power of two.
            m >>= 1;
            e += 1;
        }
    }
    // m in [2^(digits − 1), 2^digits): the hidden bit is dropped.
    let hidden = 1u64 << (format.digits - 1);
    let biased = (e + format.bias()) as u64;
    sign | (biased << (format.digits - 1)) | (m & (hidden - 1))
}

/// `(m, e)` with `value = m · 2^e` from the bits of a value in `format`;
/// `None` for NaN and ±∞.
fn mantissa_exp2(bits: u64, format: Format) -> Option<(i64, i32)> {
    let fraction_bits = format.digits - 1;
    let field_mask = (1u64 << format.exponent_bits) - 1;
    let field = (bits >> fraction_bits) & field_mask;
    if field == field_mask {
        return None;
    }
    let fraction = bits & ((1u64 << fraction_bits) - 1);
    // Subnormals (field 0) have no hidden bit and the exponent of field 1.
    let (m, field) = if field == 0 {
        (fraction, 1)
    } else {
        (fraction | 1 << fraction_bits, field)
    };
    let e = field as i32 - format.bias() - fraction_bits as i32;
    // m < 2^53.
    let m = m as i64;
    Some(if bits >> format.sign_shift() & 1 != 0 {
        (-m, e)
    } else {
        (m, e)
    })
}

/// Centidegrees in a turn.
const CENTI_TURN: u32 = 36_000;

/// `⌊x·100 + ½⌋` modulo [`CENTI_TURN`] (in `0..36 000`) for `x = m·2^e`, in
/// integer arithmetic, exactly (`|m| < 2^53`, as a float's significand).
fn centi_round_mod_turn_i64(m: i64, e: i32) -> u32 {
    // 32-bit steps (no 64-bit division linked on an 8-bit part).
    let turn_rem = |v: i64| crate::time::div_rem_euclid_i64(v, CENTI_TURN).map_or(0, |(_, r)| r);
    // |m| < 2^53: below 2^60.
    let y = m * 100;
    if e >= 0 {
        // A whole number y·2^e: doubled e times modulo the turn.
        (0..e).fold(turn_rem(y), |r, _| r * 2 % CENTI_TURN)
    } else if e < -62 {
        // |y·2^e| < 2^−2: rounds to 0.
        0
    } else {
        // ⌊(y + 2^(s−1)) / 2^s⌋ for s = −e, the shift rounding towards −∞
        // (no overflow: |y| + 2^61 < 2^63).
        let s = e.unsigned_abs();
        turn_rem((y + (1 << (s - 1))) >> s)
    }
}

/// The f32 trigonometry in use: libm by default.
#[cfg(not(feature = "compact-f32"))]
mod backend32 {
    pub use libm::{acosf as acos, asinf as asin, atan2f as atan2, atanf as atan, cosf as cos};
    pub use libm::{floorf as floor, sinf as sin, sqrtf as sqrt, tanf as tan};
    #[inline]
    pub fn sin_cos(x: f32) -> (f32, f32) {
        libm::sincosf(x)
    }
}

/// The f32 trigonometry in use: the crate's compact single-precision routines
/// (with `compact-f32`, or `avr-libc-math` off AVR).
#[cfg(all(
    feature = "compact-f32",
    not(all(target_arch = "avr", feature = "avr-libc-math"))
))]
mod backend32 {
    pub use crate::compact::{acos, asin, atan, atan2, cos, sin, sin_cos, sqrt, tan};
    pub use libm::floorf as floor;
}

/// The f32 trigonometry in use on 8-bit AVR with `avr-libc-math`: avr-libc's
/// assembler routines ([`crate::avr_libc`]).
#[cfg(all(target_arch = "avr", feature = "avr-libc-math"))]
mod backend32 {
    pub use crate::avr_libc::{acos, asin, atan, atan2, cos, floor, sin, sin_cos, sqrt, tan};
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xorshift64 (Marsaglia 2003).
    fn xorshift(state: &mut u64) -> u64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        *state
    }

    /// Whether `x` is the nearest value of its format to `n / d` (`n`, `d`
    /// in 1..2^60), ties to even, decided in exact integer arithmetic: with
    /// `x = m · 2^−k`, `m` of `digits` bits, compare `n·2^k − m·d` with half
    /// the spacing of the neighbours, `d/2` (`d/4` below a power of two),
    /// all times 4 (and times 2^−k when k < 0). Every term stays below
    /// 2^116 (n·2^k ≈ m·d < 2^113).
    fn is_nearest(n: u64, d: u64, x: f64, digits: u32) -> bool {
        let (m, e) = x.to_mantissa_exp2().unwrap();
        let (m, n, d) = (m as i128, n as i128, d as i128);
        // Normalise m to `digits` bits so that its neighbours are m ± 1.
        // (An f32 widened to f64 has zeros below its 24 bits.)
        let shift = digits as i32 - (128 - m.leading_zeros() as i32);
        let m = if shift >= 0 { m << shift } else { m >> -shift };
        assert_eq!(m.leading_zeros(), 128 - digits);
        let k = shift - e;
        let (target, d) = if k >= 0 { (n << k, d) } else { (n, d << -k) };
        let err = 4 * (target - m * d);
        let half_up = 2 * d;
        let half_down = if m == 1 << (digits - 1) { d } else { half_up };
        let even = m & 1 == 0;
        if err >= 0 {
            err < half_up || (err == half_up && even)
        } else {
            -err < half_down || (-err == half_down && even)
        }
    }

    #[test]
    fn from_ratio_is_correctly_rounded() {
        let mut state = 0x9e37_79b9_7f4a_7c15;
        for i in 0..300_000u32 {
            let n = xorshift(&mut state) >> (4 + xorshift(&mut state) % 60);
            let d = xorshift(&mut state) >> (4 + xorshift(&mut state) % 60);
            // Every fourth: a GPS reading over its 60·10^k.
            let (n, d) = if i % 4 == 0 {
                (n >> 10, 60 * 10u64.pow(i % 12))
            } else {
                (n, d)
            };
            if n == 0 || d == 0 {
                continue;
            }
            let x32 = f32::from_ratio(n as i64, d);
            assert!(is_nearest(n, d, f64::from(x32), 24), "{n} / {d}: {x32}");
            assert_eq!(f32::from_ratio(-(n as i64), d), -x32);
            let x64 = f64::from_ratio(n as i64, d);
            assert!(is_nearest(n, d, x64, 53), "{n} / {d}: {x64}");
            if n < 1 << 53 && d < 1 << 53 {
                // Both exact in an f64: its division rounds once as well.
                assert_eq!(x64, n as f64 / d as f64);
            }
        }
    }

    #[test]
    fn from_ratio_at_halfway_and_the_ends() {
        // 2^24 + 1 and 2^24 + 3 lie halfway between f32s: to the even one.
        assert_eq!(f32::from_ratio((1 << 24) + 1, 1), 16_777_216.0);
        assert_eq!(f32::from_ratio((1 << 24) + 3, 1), 16_777_220.0);
        assert_eq!(f32::from_ratio((1 << 25) - 1, 2), 16_777_216.0);
        assert_eq!(f64::from_ratio(i64::MIN, 1), -(2f64.powi(63)));
        assert_eq!(f32::from_ratio(1, u64::MAX), 2f32.powi(-64));
        assert_eq!(f32::from_ratio(i64::MAX, 1), 2f32.powi(63));
        assert_eq!(f32::from_ratio(0, 7), 0.0);
        assert_eq!(f64::from_ratio(3, 0), f64::INFINITY);
        assert!(f32::from_ratio(0, 0).is_nan() && f64::from_ratio(0, 0).is_nan());
    }

    /// `⌊x·100 + ½⌋ mod 36 000` in f64, independently of the integer
    /// paths. For a finite f32 x, x·100 has at most 31 significant bits and
    /// is exact in f64; adding ½ is exact too unless |x·100| < 2^−22, where
    /// the rounded sum stays inside (0, 1) and the floor is 0 either way;
    /// at and above 2^53 the value is whole and the floor keeps it; f64's
    /// remainder is exact.
    fn centi_reference(x: f32) -> u32 {
        if !x.is_finite() {
            return 0;
        }
        let v = (f64::from(x) * 100.0 + 0.5).floor();
        v.rem_euclid(36_000.0) as u32
    }

    #[test]
    fn centi_round_mod_turn_of_f32_matches_f64_over_the_bit_patterns() {
        // Every 1021st bit pattern (all exponents and signs, both ends of
        // each binade's significands), then every value near the halves
        // and the ends of the range where the rounding turns.
        let strided = (0..=u32::MAX / 1021).map(|i| f32::from_bits(i * 1021));
        let near_halves = (-72_000i32..72_000).flat_map(|k| {
            let half = (k as f32 + 0.5) / 100.0;
            (-3i32..=3).map(move |d| f32::from_bits(half.to_bits().wrapping_add_signed(d)))
        });
        let specials = [
            0.0f32,
            -0.0,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
        ];
        for x in strided.chain(near_halves).chain(specials) {
            assert_eq!(
                x.centi_round_mod_turn(),
                centi_reference(x),
                "{x:e} ({:#x})",
                x.to_bits()
            );
            // The generic 64-bit path (f64's) agrees on the same values.
            assert_eq!(
                f64::from(x).centi_round_mod_turn(),
                centi_reference(x),
                "{x:e} as f64"
            );
        }
    }

    #[test]
    fn mantissa_exp2_is_exact() {
        for x in [
            0.0f32,
            -0.0,
            1.0,
            -1.5,
            0.1,
            359.99,
            f32::MAX,
            f32::MIN_POSITIVE,
            1e-45,
        ] {
            let (m, e) = x.to_mantissa_exp2().unwrap();
            assert_eq!(m as f64 * 2f64.powi(e), f64::from(x), "{x}");
        }
        for x in [0.1f64, -123.456, f64::MAX, f64::MIN_POSITIVE, 5e-324] {
            let (m, e) = x.to_mantissa_exp2().unwrap();
            // Split the power so that neither factor over- or underflows.
            assert_eq!(m as f64 * 2f64.powi(e / 2) * 2f64.powi(e - e / 2), x, "{x}");
        }
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            assert_eq!(x.to_mantissa_exp2(), None);
        }
        assert_eq!(f64::NEG_INFINITY.to_mantissa_exp2(), None);
    }
}
