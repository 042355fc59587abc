//! Simulation of a suntracker's world: the mount and its axes, the
//! attitude sensors, GPS and RTC streams, weather and operator scenarios,
//! and the sun-position workload of the speed benches. `no_std`: the host
//! tests and tools use it, and so does the QEMU board image, whose emulated
//! chip has no motors or sensors of its own.
#![no_std]
#![forbid(unsafe_code)]

#[cfg(not(target_arch = "avr"))]
pub mod gps;
pub mod plant;
pub mod rng;
#[cfg(not(target_arch = "avr"))]
pub mod rtc;
pub mod scenario;
pub mod sensors;
pub mod sun_workload;
