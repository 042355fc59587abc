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
    #[inline]
    fn to_radians(self) -> Self {
        self * (Self::PI / Self::from_f64(180.0))
    }
    /// Radians to degrees.
    #[inline]
    fn to_degrees(self) -> Self {
        self * (Self::from_f64(180.0) / Self::PI)
    }
    /// Euclidean remainder: the result lies in `[0, m)` for `m > 0`.
    #[inline]
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
    #[inline]
    fn min(self, o: Self) -> Self {
        if o < self {
            o
        } else {
            self
        }
    }
    /// The larger of two values.
    #[inline]
    fn max(self, o: Self) -> Self {
        if o > self {
            o
        } else {
            self
        }
    }
    /// Clamps into `[lo, hi]`.
    #[inline]
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
    #[inline]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        backend32::sin_cos(self)
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
    pub use crate::compact::{acos, asin, atan, atan2, cos, sin, sin_cos, tan};
    pub use libm::{floorf as floor, sqrtf as sqrt};
}

/// The f32 trigonometry in use on 8-bit AVR with `avr-libc-math`: avr-libc's
/// assembler routines ([`crate::avr_libc`]).
#[cfg(all(target_arch = "avr", feature = "avr-libc-math"))]
mod backend32 {
    pub use crate::avr_libc::{acos, asin, atan, atan2, cos, floor, sin, sin_cos, sqrt, tan};
}
