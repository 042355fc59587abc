//! Tilt sensors and the mount-tilt math.
//!
//! - [`WitInclinometer`]: WitMotion SINDT02-485-class two-axis inclinometer
//!   over RS-485 Modbus RTU ([`modbus`] is our own small master: function
//!   0x03, CRC-16/MODBUS, timeouts, exceptions, DE pin);
//! - [`Adxl345`]: accelerometer over I2C, the cheap alternative;
//! - [`mount_tilt`]: Expressions (6)–(7) of Choi et al., "Portable sun
//!   tracking system with tilt and magnetic compensation", from the two axis
//!   angles to the mount's α0, β0.

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
///
/// ```
/// use drivers::tilt::{axis_angles_from_inclination, mount_tilt, Inclination};
///
/// // Level sensor: both axes horizontal, 90° from the vertical.
/// let level = Inclination { roll_deg: 0.0, pitch_deg: 0.0 };
/// let (theta_x, theta_y) = axis_angles_from_inclination(&level);
/// let tilt = mount_tilt(theta_x, theta_y)?;
/// assert!(tilt.alpha0_deg.abs() < 1e-4 && tilt.beta0_deg.abs() < 1e-4);
/// # Ok::<(), drivers::tilt::MountTiltError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Inclination {
    /// Roll, degrees.
    pub roll_deg: f32,
    /// Pitch, degrees.
    pub pitch_deg: f32,
}
