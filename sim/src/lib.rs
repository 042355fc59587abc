//! Simulation of a suntracker's world: the mount and its axes, the
//! attitude sensors, a continuous-rotation servo and its quadrature
//! encoder, DC gear motors on H-bridges with their Hall encoders and
//! current sense, linear actuators, GPS and RTC streams, weather and
//! operator scenarios, and the sun-position workload of the speed benches.
//! `no_std`: the host tests and tools use it, and so does the QEMU board
//! image, whose emulated chip has no motors or sensors of its own.
#![no_std]
#![forbid(unsafe_code)]

// Lists for the servo bench of the emulator harness (`servo::Fs5106r`,
// `encoder::QuadratureEncoder::edges_between`).
#[cfg(feature = "std")]
extern crate std;

// The DC axis of whole-tracker runs shares its motor through `Rc`.
#[cfg(feature = "std")]
pub mod dc_drive;
#[cfg(not(target_arch = "avr"))]
pub mod dc_motor;
#[cfg(not(target_arch = "avr"))]
pub mod encoder;
#[cfg(not(target_arch = "avr"))]
pub mod gps;
#[cfg(not(target_arch = "avr"))]
pub mod linear_actuator;
// The linear actuator's ports share it through `Rc`.
#[cfg(feature = "std")]
pub mod linear_drive;
pub mod plant;
pub mod rng;
#[cfg(not(target_arch = "avr"))]
pub mod rtc;
pub mod scenario;
pub mod sensors;
#[cfg(not(target_arch = "avr"))]
pub mod servo;
pub mod sun_workload;
