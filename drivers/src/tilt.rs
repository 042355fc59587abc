//! Tilt sensors and the mount-tilt math.
//!
//! - [`WitInclinometer`]: WitMotion SINDT02-485-class two-axis inclinometer
//!   over RS-485 Modbus RTU ([`modbus`] is our own small master: function
//!   0x03, CRC-16/MODBUS, timeouts, exceptions, DE pin);
//! - [`Adxl345`]: accelerometer over I2C, the cheap alternative;
//! - [`mount_tilt`]: the seed portable-tracker's Expressions (6)–(7), from the
//!   two axis angles to the mount's α0, β0.

pub mod adxl345;
pub mod modbus;
mod mount;
pub mod witmotion;

pub use adxl345::{Acceleration, Adxl345};
pub use mount::{
    axis_angles, axis_angles_from_elevations, axis_angles_from_gravity,
    axis_angles_from_inclination, mount_tilt, MountTilt, MountTiltError,
};
pub use witmotion::WitInclinometer;

/// Roll (rotation about the sensor's X axis) and pitch (about its Y axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inclination {
    /// Roll, degrees.
    pub roll_deg: f32,
    /// Pitch, degrees.
    pub pitch_deg: f32,
}
