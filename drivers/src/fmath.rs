//! `f32` math for the drivers, through `sun_algos::Float`: on AVR that is
//! avr-libc's assembler routines (a `libm` `f32` sine there runs its kernel
//! in software `f64`, about ten times slower), elsewhere `libm`. One place,
//! so that every driver uses the same backend as the sun algorithms.

use sun_algos::Float;

/// Sine of radians.
#[inline]
pub(crate) fn sin(x: f32) -> f32 {
    Float::sin(x)
}

/// Cosine of radians.
#[inline]
pub(crate) fn cos(x: f32) -> f32 {
    Float::cos(x)
}

/// (sine, cosine) of radians.
#[inline]
pub(crate) fn sin_cos(x: f32) -> (f32, f32) {
    Float::sin_cos(x)
}

/// Arcsine, radians.
#[inline]
pub(crate) fn asin(x: f32) -> f32 {
    Float::asin(x)
}

/// Arccosine, radians.
#[inline]
pub(crate) fn acos(x: f32) -> f32 {
    Float::acos(x)
}

/// atan2(y, x), radians.
#[inline]
pub(crate) fn atan2(y: f32, x: f32) -> f32 {
    Float::atan2(y, x)
}

/// Square root.
#[inline]
pub(crate) fn sqrt(x: f32) -> f32 {
    Float::sqrt(x)
}

/// √(x² + y²) (the drivers' magnitudes, at most about 10⁵, square far
/// inside the `f32` range).
#[inline]
pub(crate) fn hypot(x: f32, y: f32) -> f32 {
    Float::sqrt(x * x + y * y)
}

/// Largest integer not above `x`.
#[inline]
pub(crate) fn floor(x: f32) -> f32 {
    Float::floor(x)
}
