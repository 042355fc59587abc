//! The mount the attitude sensors sit on, and the local geomagnetic field.
//!
//! Frames are the firmware's (`src/attitude.rs`, `drivers/src/tilt/mount.rs`,
//! `drivers/src/compass/heading.rs`, after Choi et al., portable tracker):
//! horizontal XYZ = (west, south, up); the tracker frame xyz is reached by
//! `T = Rz(γ0)·Rx(α0)·Ry(β0)`; the ADXL345 and the QMC5883L are mounted with
//! their axes along the tracker's x, y, z. A sensor therefore reads a world
//! vector `v` as `Tᵀ·v`: gravity's reaction (+1 g up) for the accelerometer,
//! the geomagnetic field for the magnetometer.
//!
//! Harness convention for `--tilt-deg X --heading-deg Y`: the mount is
//! tilted by α0 = X about its x axis, and its *facing* — the azimuth of the
//! tracker's −y axis, which is where the panel tips at γ = 0, α > 0 — is Y
//! degrees east of true north, so γ0 = −Y. "Level, facing north" is the
//! identity; through the firmware's drivers it reads θx = θy = 90° (the
//! angles between the vertical and the tracker's x, y axes) and a true
//! heading (azimuth of the tracker's +y axis) of 180°.

use drivers::compass::wmm::{decimal_year, WmmModel};
use suntracker::attitude::{MountAttitude, Vec3};

/// A mount attitude in the firmware's frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mount {
    /// The rotation from horizontal to tracker frame.
    pub attitude: MountAttitude<f64>,
}

impl Mount {
    /// Level, facing north: the identity.
    pub fn level() -> Self {
        Mount {
            attitude: MountAttitude::level(),
        }
    }

    /// Tilted by `tilt_deg` about the tracker's x axis, facing `heading_deg`
    /// (see the module doc).
    pub fn tilted(tilt_deg: f64, heading_deg: f64) -> Self {
        Mount {
            attitude: MountAttitude {
                alpha0_deg: tilt_deg,
                beta0_deg: 0.0,
                gamma0_deg: suntracker::attitude::wrap180(-heading_deg),
            },
        }
    }

    /// A world vector (XYZ) seen in the sensor (tracker) frame: `Tᵀ·v`.
    pub fn to_sensor(&self, v: &Vec3<f64>) -> Vec3<f64> {
        self.attitude.sun_in_tracker(v)
    }

    /// What an accelerometer at rest reads, in g.
    pub fn gravity_g(&self) -> Vec3<f64> {
        self.to_sensor(&[0.0, 0.0, 1.0])
    }
}

/// The local geomagnetic field in XYZ (west, south, up), gauss.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Field {
    /// West, south, up components, gauss.
    pub xyz_gauss: Vec3<f64>,
    /// Declination, degrees east.
    pub declination_deg: f64,
}

impl Field {
    /// WMM2025 (the repository's `drivers::compass::wmm`, coefficients from
    /// NOAA's WMM2025.COF) at a site and date.
    pub fn wmm2025(lat_deg: f64, lon_deg: f64, height_km: f64, ymd: (i32, u8, u8)) -> Self {
        let year = decimal_year(ymd.0, ymd.1, ymd.2, 43_200).unwrap_or(2026.5);
        let e = WmmModel::wmm2025()
            .field(lat_deg, lon_deg, height_km, year)
            .expect("WMM2025 in range");
        let k = 1e-5; // nT → gauss
        Field {
            xyz_gauss: [-e.east_nt * k, -e.north_nt * k, -e.down_nt * k],
            declination_deg: e.declination_deg,
        }
    }

    /// Kano (11.9683 N, 8.4261 E, 480 m) in mid-2026, WMM2025.
    pub fn kano_2026() -> Self {
        Self::wmm2025(11.9683, 8.4261, 0.48, (2026, 6, 21))
    }
}
