//! Tilt-compensated magnetic and true heading, in the frames of seed
//! *portable-tracker-tilt-magnetic-compensation* (the same frames as the
//! tracker's `attitude` module).
//!
//! Frames. Horizontal XYZ: X west, Y south, Z up (seed Fig. 3). Tracker xyz:
//! fixed to the mounting, equal to XYZ at the home pose of a level mount whose
//! y axis points south. The mount is reached from XYZ by γ₀ about Z, then α₀
//! about the new x axis, then β₀ about the new y axis:
//! `T = R_Z(γ₀)·R_X(α₀)·R_Y(β₀)` maps tracker coordinates to horizontal ones
//! (seed Expression (12); α₀, β₀ from the inclinometer, Expression (7)). The
//! magnetometer is mounted with its axes along the tracker's x, y, z (the chip
//! axes may need a fixed swap/sign change to get there).
//!
//! The extracted seed text names the equations of section C but not their
//! bodies; for these frames they are:
//!
//! * Expression (8): the measured field with the tilt removed,
//!   `H′ = R_X(α₀)·R_Y(β₀)·h`, i.e.
//!   `H′x = cos β₀·hx + sin β₀·hz`,
//!   `H′y = sin α₀ sin β₀·hx + cos α₀·hy − sin α₀ cos β₀·hz`,
//!   `H′z = −cos α₀ sin β₀·hx + sin α₀·hy + cos α₀ cos β₀·hz`.
//! * Expression (9): the horizontal field points to magnetic north, which is
//!   −Y rotated by the declination D (east positive), so
//!   `H′x = −H·sin(γ₀ + D)`, `H′y = −H·cos(γ₀ + D)`.
//! * Expression (10): the rotation about magnetic north
//!   `δ₀ = atan2(−H′x, −H′y)` ( = γ₀ + D).
//! * Expression (11): the rotation about true north `γ₀ = δ₀ − D`.
//!
//! The azimuth (clockwise from true north) of the tracker's +y axis is
//! `180° − γ₀` ([`true_heading_deg`]), the input of `MountAttitude::from_sensors`.

use super::Vector3;
use crate::fmath;

/// Why no heading could be computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeadingError {
    /// An input was NaN or infinite.
    NonFinite,
    /// The horizontal field is (numerically) zero: no direction can be found.
    NoHorizontalField,
}

impl core::fmt::Display for HeadingError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            HeadingError::NonFinite => f.write_str("heading input NaN or infinite"),
            HeadingError::NoHorizontalField => f.write_str("horizontal field is zero: no heading"),
        }
    }
}

impl core::error::Error for HeadingError {}

/// The field with the tilt removed, seed Expression (8): `R_X(α₀)·R_Y(β₀)·h`.
pub fn detilt(field: Vector3, alpha0_rad: f32, beta0_rad: f32) -> Vector3 {
    let (sa, ca) = fmath::sin_cos(alpha0_rad);
    let (sb, cb) = fmath::sin_cos(beta0_rad);
    Vector3 {
        x: cb * field.x + sb * field.z,
        y: sa * sb * field.x + ca * field.y - sa * cb * field.z,
        z: -ca * sb * field.x + sa * field.y + ca * cb * field.z,
    }
}

/// δ₀, the mount's rotation about Z measured from magnetic north, degrees in
/// −180..180: seed Expressions (8)–(10).
pub fn magnetic_rotation_deg(
    field: Vector3,
    alpha0_rad: f32,
    beta0_rad: f32,
) -> Result<f32, HeadingError> {
    if !field.is_finite() || !alpha0_rad.is_finite() || !beta0_rad.is_finite() {
        return Err(HeadingError::NonFinite);
    }
    let h = detilt(field, alpha0_rad, beta0_rad);
    let horizontal = fmath::hypot(h.x, h.y);
    let total = fmath::sqrt(field.x * field.x + field.y * field.y + field.z * field.z);
    if horizontal == 0.0 || horizontal <= 1e-6 * total {
        return Err(HeadingError::NoHorizontalField);
    }
    Ok(fmath::atan2(-h.x, -h.y).to_degrees())
}

/// γ₀, the mount's rotation about Z from the true-north frame, degrees in
/// −180..180: seed Expression (11), `γ₀ = δ₀ − D` (D east positive).
pub fn gamma0_deg(
    field: Vector3,
    alpha0_rad: f32,
    beta0_rad: f32,
    declination_deg: f32,
) -> Result<f32, HeadingError> {
    if !declination_deg.is_finite() {
        return Err(HeadingError::NonFinite);
    }
    let delta0 = magnetic_rotation_deg(field, alpha0_rad, beta0_rad)?;
    Ok(wrap180_deg(delta0 - declination_deg))
}

/// Azimuth of the tracker's +y axis, degrees 0..360 clockwise from magnetic
/// north: `180° − δ₀`.
pub fn magnetic_heading_deg(
    field: Vector3,
    alpha0_rad: f32,
    beta0_rad: f32,
) -> Result<f32, HeadingError> {
    magnetic_rotation_deg(field, alpha0_rad, beta0_rad).map(|d| wrap360_deg(180.0 - d))
}

/// Azimuth of the tracker's +y axis, degrees 0..360 clockwise from true north:
/// `180° − γ₀` = magnetic heading + D.
pub fn true_heading_deg(
    field: Vector3,
    alpha0_rad: f32,
    beta0_rad: f32,
    declination_deg: f32,
) -> Result<f32, HeadingError> {
    gamma0_deg(field, alpha0_rad, beta0_rad, declination_deg).map(|g| wrap360_deg(180.0 - g))
}

/// Wraps an angle into 0..360 degrees.
pub fn wrap360_deg(angle_deg: f32) -> f32 {
    let w = angle_deg - 360.0 * fmath::floor(angle_deg / 360.0);
    if w >= 360.0 {
        0.0
    } else {
        w
    }
}

/// Wraps an angle into −180..180 degrees.
pub fn wrap180_deg(angle_deg: f32) -> f32 {
    let w = wrap360_deg(angle_deg);
    if w >= 180.0 {
        w - 360.0
    } else {
        w
    }
}
