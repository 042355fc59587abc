//! Board layers: embedded-hal 1.0 / embedded-io implementations over a
//! chip's peripheral access crate, so that the `drivers` crate runs on it
//! unchanged.

#[cfg(target_arch = "avr")]
pub mod avr;
