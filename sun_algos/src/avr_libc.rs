//! f32 trigonometry from avr-libc's libm (feature `avr-libc-math`, 8-bit
//! AVR only).
//!
//! On avr-gcc `double` is 32 bits, so avr-libc's `sin`, `cos`, `tan`,
//! `asin`, `acos`, `atan`, `atan2`, `sqrt` and `floor` take and return an
//! IEEE single: exactly Rust's `f32` in the AVR C calling convention
//! (argument and result in r22–r25). They are hand-written assembler (the
//! `fplib` of avr-libc) and about 2.4× faster than [`crate::compact`] for `sin` on the
//! ATmega328P (1,779 against 4,202 cycles, simavr). The image must link
//! avr-libc's `libm.a` (avr-gcc as linker, `-lm`); the firmware images do
//! (see `.cargo/config.toml`).
//!
//! `sin_cos` is two calls: avr-libc has no `sincos`.

mod ffi {
    extern "C" {
        pub fn sin(x: f32) -> f32;
        pub fn cos(x: f32) -> f32;
        pub fn tan(x: f32) -> f32;
        pub fn asin(x: f32) -> f32;
        pub fn acos(x: f32) -> f32;
        pub fn atan(x: f32) -> f32;
        pub fn atan2(y: f32, x: f32) -> f32;
        pub fn sqrt(x: f32) -> f32;
        pub fn floor(x: f32) -> f32;
    }
}

// SAFETY (every call below): the avr-libc routine is a pure function of its
// argument(s) passed by value in registers; it reads no memory of ours and
// writes no global state besides possibly `errno` (never read here). Every
// f32 bit pattern, NaN and infinities included, is a valid input: out-of-
// domain arguments give NaN, not undefined behaviour.

/// Sine of `x` radians (avr-libc `sin`).
#[inline]
pub fn sin(x: f32) -> f32 {
    // SAFETY: see the module comment above.
    unsafe { ffi::sin(x) }
}

/// Cosine of `x` radians (avr-libc `cos`).
#[inline]
pub fn cos(x: f32) -> f32 {
    // SAFETY: see the module comment above.
    unsafe { ffi::cos(x) }
}

/// Sine and cosine of `x` radians (two avr-libc calls).
#[inline]
pub fn sin_cos(x: f32) -> (f32, f32) {
    (sin(x), cos(x))
}

/// Tangent of `x` radians (avr-libc `tan`).
#[inline]
pub fn tan(x: f32) -> f32 {
    // SAFETY: see the module comment above.
    unsafe { ffi::tan(x) }
}

/// Arcsine, radians (avr-libc `asin`; NaN outside `[−1, 1]`).
#[inline]
pub fn asin(x: f32) -> f32 {
    // SAFETY: see the module comment above.
    unsafe { ffi::asin(x) }
}

/// Arccosine, radians (avr-libc `acos`; NaN outside `[−1, 1]`).
#[inline]
pub fn acos(x: f32) -> f32 {
    // SAFETY: see the module comment above.
    unsafe { ffi::acos(x) }
}

/// Arctangent, radians (avr-libc `atan`).
#[inline]
pub fn atan(x: f32) -> f32 {
    // SAFETY: see the module comment above.
    unsafe { ffi::atan(x) }
}

/// Four-quadrant arctangent of `y/x`, radians (avr-libc `atan2`).
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    // SAFETY: see the module comment above.
    unsafe { ffi::atan2(y, x) }
}

/// Square root (avr-libc `sqrt`; NaN for negative input).
#[inline]
pub fn sqrt(x: f32) -> f32 {
    // SAFETY: see the module comment above.
    unsafe { ffi::sqrt(x) }
}

/// Largest integer not above `x` (avr-libc `floor`).
#[inline]
pub fn floor(x: f32) -> f32 {
    // SAFETY: see the module comment above.
    unsafe { ffi::floor(x) }
}
