//! Simulation: plant and sensor models for host runs and the QEMU image.

#[cfg(not(target_arch = "avr"))]
pub mod gps;
pub mod plant;
pub mod rng;
#[cfg(not(target_arch = "avr"))]
pub mod rtc;
pub mod scenario;
pub mod sensors;
