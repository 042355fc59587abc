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

/// asin of `x` clamped to [−1, 1] (a NaN stays NaN), radians: for a sine
/// computed from readings, which rounding may put just outside.
// Out of line on the AVR: the clamp's two soft-float comparisons, written
// out at each caller, cost more than the call.
#[cfg_attr(target_arch = "avr", inline(never))]
pub(crate) fn asin_clamped(x: f32) -> f32 {
    asin(x.clamp(-1.0, 1.0))
}

/// acos of `x` clamped to [−1, 1] (a NaN stays NaN), in degrees.
// Out of line on the AVR, as `asin_clamped`.
#[cfg_attr(target_arch = "avr", inline(never))]
pub(crate) fn acos_deg_clamped(x: f32) -> f32 {
    acos(x.clamp(-1.0, 1.0)).to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamped_inverse_sines_take_the_end_values_outside_the_range() {
        // asin(1) = π/2, asin(−1) = −π/2, acos(−1) = 180°, acos(1) = 0°,
        // acos(½) = 60°, asin(½) = π/6.
        let pi = core::f32::consts::PI;
        assert_eq!(asin_clamped(1.000_01), pi / 2.0);
        assert_eq!(asin_clamped(-7.0), -pi / 2.0);
        assert!((asin_clamped(0.5) - pi / 6.0).abs() < 1e-6);
        assert_eq!(acos_deg_clamped(-1.5), 180.0);
        assert_eq!(acos_deg_clamped(3.0), 0.0);
        assert!((acos_deg_clamped(0.5) - 60.0).abs() < 1e-4);
        assert!(asin_clamped(f32::NAN).is_nan());
        assert!(acos_deg_clamped(f32::NAN).is_nan());
    }
}
