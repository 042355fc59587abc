//! Tilt-compensated magnetic and true heading.
//!
//! Seed *portable-tracker-tilt-magnetic-compensation*, section C "Geomagnetic
//! Sensor". The seed's sensor frame is tilted from the horizontal frame by a
//! rotation α₀ about the X axis followed by β₀ about the Y axis (its Expression (5)).
//! The extracted seed text names the equations but not their bodies, so they are
//! written out here for our axis convention (sensor x forward, y right, z down,
//! right-handed; α₀ = roll about x, β₀ = pitch about y, nose up positive):
//!
//! * Expression (8), sensor output in the horizontal frame:
//!   `H = R_Y(β₀) · R_X(α₀) · h`, i.e.
//!   `H_X = cos β₀·hx + sin β₀ sin α₀·hy + sin β₀ cos α₀·hz`,
//!   `H_Y = cos α₀·hy − sin α₀·hz`,
//!   `H_Z = −sin β₀·hx + cos β₀ sin α₀·hy + cos β₀ cos α₀·hz`.
//! * Expression (9): only `H_X`, `H_Y` are needed (above).
//! * Expression (10), rotation about magnetic north (heading of the x axis,
//!   clockwise seen from above): `δ₀ = atan2(−H_Y, H_X)`.
//! * Expression (11), about true north: `γ₀ = δ₀ + D`, D the declination
//!   (east positive), from configuration or [`super::wmm`].

use super::Vector3;

/// Why no heading could be computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeadingError {
    /// An input was NaN or infinite.
    NonFinite,
    /// The horizontal field is (numerically) zero: no direction can be found.
    NoHorizontalField,
}

/// The field in the horizontal frame, seed Expressions (8)–(9).
///
/// `field` in the sensor frame (any unit), `roll_rad` = α₀, `pitch_rad` = β₀.
pub fn horizontal_field(field: Vector3, roll_rad: f32, pitch_rad: f32) -> Vector3 {
    let (sa, ca) = libm::sincosf(roll_rad);
    let (sb, cb) = libm::sincosf(pitch_rad);
    Vector3 {
        x: cb * field.x + sb * sa * field.y + sb * ca * field.z,
        y: ca * field.y - sa * field.z,
        z: -sb * field.x + cb * sa * field.y + cb * ca * field.z,
    }
}

/// Magnetic heading δ₀ of the sensor x axis in degrees, 0..360, clockwise from
/// magnetic north, seed Expression (10) after tilt compensation (8)–(9).
pub fn magnetic_heading_deg(
    field: Vector3,
    roll_rad: f32,
    pitch_rad: f32,
) -> Result<f32, HeadingError> {
    if !field.is_finite() || !roll_rad.is_finite() || !pitch_rad.is_finite() {
        return Err(HeadingError::NonFinite);
    }
    let h = horizontal_field(field, roll_rad, pitch_rad);
    let norm = libm::hypotf(h.x, h.y);
    let total = libm::sqrtf(field.x * field.x + field.y * field.y + field.z * field.z);
    if norm <= 1e-6 * total || norm == 0.0 {
        return Err(HeadingError::NoHorizontalField);
    }
    Ok(wrap_deg(libm::atan2f(-h.y, h.x).to_degrees()))
}

/// True heading γ₀ in degrees, 0..360: seed Expression (11), `γ₀ = δ₀ + D`.
pub fn true_heading_deg(
    field: Vector3,
    roll_rad: f32,
    pitch_rad: f32,
    declination_deg: f32,
) -> Result<f32, HeadingError> {
    if !declination_deg.is_finite() {
        return Err(HeadingError::NonFinite);
    }
    magnetic_heading_deg(field, roll_rad, pitch_rad).map(|d| wrap_deg(d + declination_deg))
}

/// Wraps an angle into 0..360 degrees.
pub fn wrap_deg(angle_deg: f32) -> f32 {
    let w = angle_deg - 360.0 * libm::floorf(angle_deg / 360.0);
    if w >= 360.0 {
        0.0
    } else {
        w
    }
}
