//! Magnetometers and a chip-independent, tilt-compensated true heading.
//!
//! * [`qmc5883l`] and [`hmc5883l`]: I2C drivers (ours), register maps from the
//!   QST QMC5883L and Honeywell HMC5883L datasheets.
//! * [`calibration`]: hard- and soft-iron correction from a rotation sweep
//!   (per-axis min/max: offset = centre, scale = mean radius / axis radius).
//! * [`heading`]: tilt compensation from the mount tilts α₀, β₀ (roll and pitch) and the declination
//!   correction, seed *portable-tracker-tilt-magnetic-compensation* Expressions (8)–(11).
//! * [`wmm`]: a `no_std`, heap-free World Magnetic Model (WMM2025) giving the
//!   declination for a GPS position and date.
//!
//! Every chip driver implements [`Magnetometer`], so [`heading`] does not care
//! which chip is fitted.

pub mod calibration;
pub mod heading;
pub mod hmc5883l;
pub mod qmc5883l;
pub mod wmm;
#[rustfmt::skip]
mod wmm2025_coefficients;

/// A three-axis vector in the sensor frame. The unit is whatever the producer
/// says: gauss from [`Magnetometer::read_gauss`], raw counts elsewhere.
///
/// For [`heading`] the axes are the tracker's (seed *portable-tracker*): at the
/// home pose of a level mount x west, y south, z up.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vector3 {
    /// x component.
    pub x: f32,
    /// y component.
    pub y: f32,
    /// z component.
    pub z: f32,
}

impl Vector3 {
    /// Builds a vector from its components.
    pub const fn new(x: f32, y: f32, z: f32) -> Self {
        Self { x, y, z }
    }

    /// True when all three components are finite.
    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

/// A magnetometer that can deliver one field sample in gauss.
pub trait Magnetometer {
    /// The driver's error type.
    type Error;

    /// Reads one field sample, in gauss, sensor frame.
    fn read_gauss(&mut self) -> Result<Vector3, Self::Error>;

    /// True when `error` only says that no new sample is ready yet: the
    /// part measures at its output data rate (the QMC5883L at 10 Hz by
    /// default), and a reader faster than that is told so. Not a fault: the
    /// caller reads again later. False for every other error.
    fn is_not_ready(error: &Self::Error) -> bool {
        let _ = error;
        false
    }
}

/// Where the magnetic declination comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DeclinationSource {
    /// A fixed value from configuration, degrees, east positive.
    Fixed {
        /// Declination in degrees, east of true north positive.
        declination_deg: f32,
    },
    /// Computed by the World Magnetic Model for the site and date.
    Wmm2025,
}

impl DeclinationSource {
    /// The declination in degrees (east positive) for a site and date: the fixed
    /// value, or WMM2025 at the WGS-84 position (`height_km` above the ellipsoid)
    /// and decimal year (see [`wmm::decimal_year`]).
    pub fn declination_deg(
        &self,
        latitude_deg: f64,
        longitude_deg: f64,
        height_km: f64,
        decimal_year: f64,
    ) -> Result<f32, wmm::WmmError> {
        match *self {
            DeclinationSource::Fixed { declination_deg } if declination_deg.is_finite() => {
                Ok(declination_deg)
            }
            DeclinationSource::Fixed { .. } => Err(wmm::WmmError::NonFinite),
            DeclinationSource::Wmm2025 => wmm::WmmModel::wmm2025()
                .declination_deg(latitude_deg, longitude_deg, height_km, decimal_year)
                .map(|d| d as f32),
        }
    }
}
