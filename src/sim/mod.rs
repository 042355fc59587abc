//! Simulation: plant and sensor models for host runs and the QEMU image.

pub mod plant;
pub mod rng;
#[cfg(not(target_arch = "avr"))]
pub mod rtc;
pub mod sensors;
