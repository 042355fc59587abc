//! Tilt-compensated magnetic and true heading, in the frames of Choi et al.,
//! "Portable sun tracking system with tilt and magnetic compensation" (the
//! same frames as the tracker's `attitude` module).
//!
//! Frames. Horizontal XYZ: X west, Y south, Z up (the paper's Fig. 3).
//! Tracker xyz: fixed to the mounting, equal to XYZ at the home pose of a
//! level mount whose y axis points south. The mount is reached from XYZ by γ₀
//! about Z, then α₀ about the new x axis, then β₀ about the new y axis:
//! `T = R_Z(γ₀)·R_X(α₀)·R_Y(β₀)` maps tracker coordinates to horizontal ones
//! (the paper's Expression (12); α₀, β₀ from the inclinometer, Expression
//! (7)). The magnetometer is mounted with its axes along the tracker's x, y, z
//! (the chip axes may need a fixed swap/sign change to get there).
//!
//! The paper's text as we have it names the equations of section C but not
//! their bodies; for these frames they are:
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
///
/// ```
/// use drivers::compass::heading::{magnetic_heading_deg, HeadingError};
/// use drivers::compass::Vector3;
///
/// // A field straight down (at a magnetic pole): no horizontal direction.
/// let down = Vector3::new(0.0, 0.0, -0.6);
/// assert_eq!(magnetic_heading_deg(down, 0.0, 0.0), Err(HeadingError::NoHorizontalField));
/// assert_eq!(
///     magnetic_heading_deg(down, f32::NAN, 0.0),
///     Err(HeadingError::NonFinite)
/// );
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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

/// The field with the tilt removed, Choi et al., Expression (8):
/// `R_X(α₀)·R_Y(β₀)·h`.
///
/// ```
/// use drivers::compass::heading::detilt;
/// use drivers::compass::Vector3;
///
/// // The reading of a magnetometer on a mount turned γ₀ = 30° about Z and
/// // tilted α₀ = 10°, β₀ = −15°, in a field of 0.2 G horizontal, 0.45 G down
/// // and a declination of 3° E: Tᵀ·F with T = R_Z(γ₀)·R_X(α₀)·R_Y(β₀),
/// // computed independently with numpy.
/// let h = Vector3::new(-0.212_376_78, -0.243_327_54, -0.371_736_21);
/// let (alpha0, beta0) = (10f32.to_radians(), (-15f32).to_radians());
/// let level = detilt(h, alpha0, beta0);
/// // R_X(α₀)·R_Y(β₀)·h by numpy: (−0.108 927 81, −0.167 734 11, −0.45), the
/// // field as a level sensor turned by γ₀ would see it.
/// assert!((level.x + 0.108_927_81).abs() < 1e-6);
/// assert!((level.y + 0.167_734_11).abs() < 1e-6);
/// assert!((level.z + 0.45).abs() < 1e-6);
/// ```
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
/// −180..180: Choi et al., Expressions (8)–(10).
///
/// ```
/// use drivers::compass::heading::magnetic_rotation_deg;
/// use drivers::compass::Vector3;
///
/// // The reading of a magnetometer on a mount turned γ₀ = 30° about Z and
/// // tilted α₀ = 10°, β₀ = −15°, in a field of 0.2 G horizontal, 0.45 G down
/// // and a declination of 3° E: Tᵀ·F with T = R_Z(γ₀)·R_X(α₀)·R_Y(β₀),
/// // computed independently with numpy.
/// let h = Vector3::new(-0.212_376_78, -0.243_327_54, -0.371_736_21);
/// let (alpha0, beta0) = (10f32.to_radians(), (-15f32).to_radians());
/// // δ₀ = γ₀ + D = 33°.
/// let delta0 = magnetic_rotation_deg(h, alpha0, beta0)?;
/// assert!((delta0 - 33.0).abs() < 1e-3);
/// // Level, with the field along +x: x points to magnetic north, δ₀ = −90°.
/// let d = magnetic_rotation_deg(Vector3::new(0.2, 0.0, -0.4), 0.0, 0.0)?;
/// assert!((d + 90.0).abs() < 1e-4);
/// # Ok::<(), drivers::compass::heading::HeadingError>(())
/// ```
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
/// −180..180: Choi et al., Expression (11), `γ₀ = δ₀ − D` (D east positive).
///
/// ```
/// use drivers::compass::heading::gamma0_deg;
/// use drivers::compass::Vector3;
///
/// // The reading of a magnetometer on a mount turned γ₀ = 30° about Z and
/// // tilted α₀ = 10°, β₀ = −15°, in a field of 0.2 G horizontal, 0.45 G down
/// // and a declination of 3° E: Tᵀ·F with T = R_Z(γ₀)·R_X(α₀)·R_Y(β₀),
/// // computed independently with numpy.
/// let h = Vector3::new(-0.212_376_78, -0.243_327_54, -0.371_736_21);
/// let (alpha0, beta0) = (10f32.to_radians(), (-15f32).to_radians());
/// let gamma0 = gamma0_deg(h, alpha0, beta0, 3.0)?;
/// assert!((gamma0 - 30.0).abs() < 1e-3); // the rotation the reading was made with
/// # Ok::<(), drivers::compass::heading::HeadingError>(())
/// ```
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
///
/// ```
/// use drivers::compass::heading::magnetic_heading_deg;
/// use drivers::compass::Vector3;
///
/// // Level, at the home pose: the field (pointing north and down) is along
/// // −y, so +y points south, azimuth 180°.
/// let home = magnetic_heading_deg(Vector3::new(0.0, -0.2, -0.4), 0.0, 0.0)?;
/// assert!((home - 180.0).abs() < 1e-4);
/// // The field along +x: x points north, so +y points west, 270°.
/// let west = magnetic_heading_deg(Vector3::new(0.2, 0.0, -0.4), 0.0, 0.0)?;
/// assert!((west - 270.0).abs() < 1e-4);
/// # Ok::<(), drivers::compass::heading::HeadingError>(())
/// ```
pub fn magnetic_heading_deg(
    field: Vector3,
    alpha0_rad: f32,
    beta0_rad: f32,
) -> Result<f32, HeadingError> {
    magnetic_rotation_deg(field, alpha0_rad, beta0_rad).map(|d| wrap360_deg(180.0 - d))
}

/// Azimuth of the tracker's +y axis, degrees 0..360 clockwise from true north:
/// `180° − γ₀` = magnetic heading + D.
///
/// ```
/// use drivers::compass::heading::true_heading_deg;
/// use drivers::compass::Vector3;
///
/// // The reading of a magnetometer on a mount turned γ₀ = 30° about Z and
/// // tilted α₀ = 10°, β₀ = −15°, in a field of 0.2 G horizontal, 0.45 G down
/// // and a declination of 3° E: Tᵀ·F with T = R_Z(γ₀)·R_X(α₀)·R_Y(β₀),
/// // computed independently with numpy.
/// let h = Vector3::new(-0.212_376_78, -0.243_327_54, -0.371_736_21);
/// let (alpha0, beta0) = (10f32.to_radians(), (-15f32).to_radians());
/// let azimuth = true_heading_deg(h, alpha0, beta0, 3.0)?;
/// assert!((azimuth - 150.0).abs() < 1e-3); // 180° − γ₀
/// # Ok::<(), drivers::compass::heading::HeadingError>(())
/// ```
pub fn true_heading_deg(
    field: Vector3,
    alpha0_rad: f32,
    beta0_rad: f32,
    declination_deg: f32,
) -> Result<f32, HeadingError> {
    gamma0_deg(field, alpha0_rad, beta0_rad, declination_deg).map(|g| wrap360_deg(180.0 - g))
}

/// Wraps an angle into 0..360 degrees.
///
/// ```
/// use drivers::compass::heading::wrap360_deg;
///
/// assert_eq!(wrap360_deg(-90.0), 270.0);
/// assert_eq!(wrap360_deg(720.0), 0.0);
/// assert_eq!(wrap360_deg(359.5), 359.5);
/// ```
pub fn wrap360_deg(angle_deg: f32) -> f32 {
    let w = angle_deg - 360.0 * fmath::floor(angle_deg / 360.0);
    if w >= 360.0 {
        0.0
    } else {
        w
    }
}

/// Wraps an angle into −180..180 degrees.
///
/// ```
/// use drivers::compass::heading::wrap180_deg;
///
/// assert_eq!(wrap180_deg(270.0), -90.0);
/// assert_eq!(wrap180_deg(180.0), -180.0);
/// assert_eq!(wrap180_deg(-190.0), 170.0);
/// ```
pub fn wrap180_deg(angle_deg: f32) -> f32 {
    let w = wrap360_deg(angle_deg);
    if w >= 180.0 {
        w - 360.0
    } else {
        w
    }
}
