//! From the two inclinometer axis angles to the mount's tilt α0, β0
//! (Choi et al., "Portable sun tracking system with tilt and magnetic
//! compensation", Section III.A, Expressions (4)–(7)). Pure math, `f32`.
//!
//! The paper's text as we have it lost the typeset equations, so they are
//! rebuilt here from its definitions, in the same frames and rotation order
//! as the tracker's `attitude` module and the compass heading
//! (`T = Rz(γ0)·Rx(α0)·Ry(β0)`, the paper's Expression (12)):
//! - the horizontal frame XYZ has Y to the south, X to the west, Z up;
//! - the mount is reached from level by α0 about x, then β0 about the new y,
//!   so its x and y axes in XYZ are the first two columns of Rx(α0)·Ry(β0)
//!   (γ0 about Z does not change their vertical components);
//! - the sensor outputs θx, θy ∈ [0, π] are the angles between the vertical Z
//!   and the mount's x and y axes (Expression (4): cos θ = Z · axis).
//!
//! The third row of Rx(α0)·Ry(β0) gives Expression (6):
//! ```text
//!   cos θx = −cos α0 · sin β0
//!   cos θy =  sin α0
//! ```
//! and solving it, Expression (7), with α0, β0 ∈ [−π/2, π/2]:
//! ```text
//!   α0 = asin(cos θy)
//!   β0 = asin(−cos θx / cos α0)
//! ```
//! The paper's Table IV, Case 1 (level): θx = θy = 90° gives α0 = β0 = 0.
//! Case 2 (α0 = 35.26°, β0 = 30°; the paper's text as we have it does not
//! keep its sensor outputs) corresponds, by hand, to cos θy = sin 35.26° =
//! 0.57729 (θy = 54.74°) and cos θx = −cos 35.26° · sin 30° = −0.40827
//! (θx = 114.096°); the test runs these backwards.
//!
//! Note: the extracted wording ("β0 about the Y-axis after α0 about the
//! X-axis of the horizontal coordinate system") could also be read as
//! rotations about the fixed axes, R = Ry(β0)·Rx(α0), for which Case 2 would
//! come from the rounder readings θx = 120°, θy = 60°. The moving-axes reading
//! is used because the rest of the project (attitude, compass) is built on it;
//! mixing the two would put α0/β0 into the wrong matrix.

use super::adxl345::Acceleration;
use crate::fmath;

/// How far |cos θx / cos α0| may exceed 1 (sensor noise) before the pair of
/// angles is refused rather than clamped.
const RATIO_TOLERANCE: f32 = 1e-3;
/// Below this |cos α0| the y axis is vertical and β0 is undefined.
const MIN_COS_ALPHA: f32 = 1e-4;

/// The mount's tilt from level.
///
/// ```
/// use drivers::tilt::{axis_angles, MountTilt};
///
/// let level = MountTilt { alpha0_deg: 0.0, beta0_deg: 0.0 };
/// assert_eq!(axis_angles(&level), (90.0, 90.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MountTilt {
    /// First rotation, about the x axis (west when level), degrees.
    pub alpha0_deg: f32,
    /// Second rotation, about the new y axis, degrees.
    pub beta0_deg: f32,
}

/// Why the axis angles do not describe a tilt.
///
/// ```
/// use drivers::tilt::{mount_tilt, MountTiltError};
///
/// assert_eq!(mount_tilt(190.0, 90.0), Err(MountTiltError::OutOfRange));
/// assert_eq!(mount_tilt(f32::NAN, 90.0), Err(MountTiltError::OutOfRange));
/// // Both axes 30° from vertical: cos²30° + cos²30° = 1.5 > 1.
/// assert_eq!(mount_tilt(30.0, 30.0), Err(MountTiltError::Inconsistent));
/// // The y axis vertical: β₀ undefined.
/// assert_eq!(mount_tilt(90.0, 0.0), Err(MountTiltError::Degenerate));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MountTiltError {
    /// An angle outside 0..=180° or not a number.
    OutOfRange,
    /// cos²θx + cos²θy > 1: no unit vector has these components.
    Inconsistent,
    /// The y axis is (nearly) vertical, so β0 is undefined.
    Degenerate,
}

impl core::fmt::Display for MountTiltError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            MountTiltError::OutOfRange => {
                f.write_str("axis angle outside 0..=180° or not a number")
            }
            MountTiltError::Inconsistent => {
                f.write_str("axis angles inconsistent: cos²θx + cos²θy > 1")
            }
            MountTiltError::Degenerate => f.write_str("y axis (nearly) vertical: β0 undefined"),
        }
    }
}

impl core::error::Error for MountTiltError {}

/// Expression (7): α0, β0 from the axis angles θx, θy (degrees from vertical).
///
/// ```
/// use drivers::tilt::mount_tilt;
///
/// // Choi et al., Table IV, Case 1: level, θx = θy = 90°.
/// let level = mount_tilt(90.0, 90.0)?;
/// assert!(level.alpha0_deg.abs() < 1e-4 && level.beta0_deg.abs() < 1e-4);
/// // Case 2, α₀ = 35.26°, β₀ = 30°: cos θy = sin 35.26°, cos θx =
/// // −cos 35.26° · sin 30° (Expression (6), by hand: θx = 114.096°, θy = 54.74°).
/// let t = mount_tilt(114.096, 54.74)?;
/// assert!((t.alpha0_deg - 35.26).abs() < 0.01 && (t.beta0_deg - 30.0).abs() < 0.01);
/// # Ok::<(), drivers::tilt::MountTiltError>(())
/// ```
pub fn mount_tilt(theta_x_deg: f32, theta_y_deg: f32) -> Result<MountTilt, MountTiltError> {
    let in_range = |t: f32| (0.0..=180.0).contains(&t);
    if !in_range(theta_x_deg) || !in_range(theta_y_deg) {
        return Err(MountTiltError::OutOfRange);
    }
    let cos_x = fmath::cos(theta_x_deg.to_radians());
    let cos_y = fmath::cos(theta_y_deg.to_radians());
    let alpha0 = fmath::asin_clamped(cos_y);
    let cos_alpha = fmath::cos(alpha0);
    if cos_alpha < MIN_COS_ALPHA {
        return Err(MountTiltError::Degenerate);
    }
    let ratio = -cos_x / cos_alpha;
    if ratio.abs() > 1.0 + RATIO_TOLERANCE {
        return Err(MountTiltError::Inconsistent);
    }
    let beta0 = fmath::asin_clamped(ratio);
    Ok(MountTilt {
        alpha0_deg: alpha0.to_degrees(),
        beta0_deg: beta0.to_degrees(),
    })
}

/// Expression (6): the axis angles θx, θy (degrees) a tilt produces.
///
/// ```
/// use drivers::tilt::{axis_angles, mount_tilt, MountTilt};
///
/// // Choi et al., Table IV, Case 2 forwards: θx = 114.096°, θy = 54.74° (by hand).
/// let (tx, ty) = axis_angles(&MountTilt { alpha0_deg: 35.26, beta0_deg: 30.0 });
/// assert!((tx - 114.096).abs() < 0.01 && (ty - 54.74).abs() < 0.01);
/// // And back.
/// let t = mount_tilt(tx, ty)?;
/// assert!((t.alpha0_deg - 35.26).abs() < 1e-3 && (t.beta0_deg - 30.0).abs() < 1e-3);
/// # Ok::<(), drivers::tilt::MountTiltError>(())
/// ```
pub fn axis_angles(tilt: &MountTilt) -> (f32, f32) {
    let a = tilt.alpha0_deg.to_radians();
    let b = tilt.beta0_deg.to_radians();
    let cos_x = -fmath::cos(a) * fmath::sin(b);
    let cos_y = fmath::sin(a);
    (
        fmath::acos_deg_clamped(cos_x),
        fmath::acos_deg_clamped(cos_y),
    )
}

/// Axis angles θx, θy (degrees from vertical) from an accelerometer at rest
/// on the mount: it measures +1 g along the up direction, so its x and y
/// components are cos θx and cos θy times |a|. `None` below 0.1 g.
///
/// ```
/// use drivers::tilt::{axis_angles_from_gravity, Acceleration};
///
/// // Level: x and y horizontal.
/// let level = Acceleration { x_g: 0.0, y_g: 0.0, z_g: 1.0 };
/// assert_eq!(axis_angles_from_gravity(&level), Some((90.0, 90.0)));
/// // Up half along +x: x is 60° from vertical (cos 60° = 0.5).
/// let a = Acceleration { x_g: 0.5, y_g: 0.0, z_g: 0.866_025_4 };
/// let (tx, ty) = axis_angles_from_gravity(&a).unwrap();
/// assert!((tx - 60.0).abs() < 1e-4 && (ty - 90.0).abs() < 1e-4);
/// assert_eq!(axis_angles_from_gravity(&Acceleration { x_g: 0.0, y_g: 0.0, z_g: 0.01 }), None);
/// ```
pub fn axis_angles_from_gravity(a: &Acceleration) -> Option<(f32, f32)> {
    let norm = fmath::sqrt(a.x_g * a.x_g + a.y_g * a.y_g + a.z_g * a.z_g);
    if norm.is_nan() || norm < 0.1 {
        return None;
    }
    let angle = |c: f32| fmath::acos_deg_clamped(c / norm);
    Some((angle(a.x_g), angle(a.y_g)))
}

/// Axis angles from a two-axis inclinometer that reports each axis's
/// elevation above the horizontal: θ = 90° − elevation.
///
/// ```
/// use drivers::tilt::axis_angles_from_elevations;
///
/// assert_eq!(axis_angles_from_elevations(0.0, 0.0), (90.0, 90.0));
/// assert_eq!(axis_angles_from_elevations(-24.096, 35.26), (114.096, 54.74));
/// ```
pub fn axis_angles_from_elevations(x_elevation_deg: f32, y_elevation_deg: f32) -> (f32, f32) {
    (90.0 - x_elevation_deg, 90.0 - y_elevation_deg)
}

/// Axis angles θx, θy (degrees from vertical) from a roll/pitch pair in the
/// aerospace Z-Y-X Euler convention (roll about x, pitch about y), which is
/// what [`super::adxl345::inclination_from_gravity`] computes and what
/// WitMotion documents for its angle registers (assumed for the
/// SINDT02 class). In that convention the up direction seen in the sensor
/// frame is (−sin pitch, cos pitch · sin roll, cos pitch · cos roll), whose
/// x and y components are cos θx and cos θy.
///
/// ```
/// use drivers::tilt::{axis_angles_from_inclination, Inclination};
///
/// // Pitch 30°: up is (−sin 30°, 0, cos 30°) in the sensor frame, so
/// // θx = acos(−0.5) = 120°, θy = 90°.
/// let (tx, ty) = axis_angles_from_inclination(&Inclination { roll_deg: 0.0, pitch_deg: 30.0 });
/// assert!((tx - 120.0).abs() < 1e-4 && (ty - 90.0).abs() < 1e-4);
/// // Roll 30°: up is (0, sin 30°, cos 30°): θy = 60°.
/// let (tx, ty) = axis_angles_from_inclination(&Inclination { roll_deg: 30.0, pitch_deg: 0.0 });
/// assert!((tx - 90.0).abs() < 1e-4 && (ty - 60.0).abs() < 1e-4);
/// ```
pub fn axis_angles_from_inclination(incl: &super::Inclination) -> (f32, f32) {
    let roll = incl.roll_deg.to_radians();
    let pitch = incl.pitch_deg.to_radians();
    let cos_x = -fmath::sin(pitch);
    let cos_y = fmath::cos(pitch) * fmath::sin(roll);
    (
        fmath::acos_deg_clamped(cos_x),
        fmath::acos_deg_clamped(cos_y),
    )
}
