//! Magnetometers and a chip-independent, tilt-compensated true heading.
//!
//! * [`qmc5883l`] and [`hmc5883l`]: I2C drivers (ours), register maps from the
//!   QST QMC5883L and Honeywell HMC5883L datasheets.
//! * [`calibration`]: hard- and soft-iron correction from a rotation sweep
//!   (per-axis min/max: offset = centre, scale = mean radius / axis radius).
//! * [`heading`]: tilt compensation from the mount tilts α₀, β₀ (roll and pitch) and the declination
//!   correction, Expressions (8)–(11) of Choi et al., "Portable sun tracking
//!   system with tilt and magnetic compensation".
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
/// For [`heading`] the axes are the tracker's (as in Choi et al.): at the
/// home pose of a level mount x west, y south, z up.
///
/// ```
/// use drivers::compass::Vector3;
///
/// let v = Vector3 { x: 0.1, ..Vector3::default() };
/// assert_eq!(v, Vector3::new(0.1, 0.0, 0.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    ///
    /// ```
    /// use drivers::compass::Vector3;
    ///
    /// const NORTH_LEVEL: Vector3 = Vector3::new(0.0, -0.2, -0.4);
    /// assert_eq!(NORTH_LEVEL.y, -0.2);
    /// ```
    pub const fn new(x: f32, y: f32, z: f32) -> Self {
        Self { x, y, z }
    }

    /// True when all three components are finite.
    ///
    /// ```
    /// use drivers::compass::Vector3;
    ///
    /// assert!(Vector3::new(0.1, 0.2, 0.3).is_finite());
    /// assert!(!Vector3::new(0.1, f32::NAN, 0.3).is_finite());
    /// assert!(!Vector3::new(f32::INFINITY, 0.0, 0.0).is_finite());
    /// ```
    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

/// A magnetometer that can deliver one field sample in gauss.
///
/// Heading code written against the trait runs with either chip:
///
/// ```
/// use drivers::compass::{heading, qmc5883l, Magnetometer};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// /// Magnetic heading of a level sensor, `None` while no sample is ready.
/// fn level_heading<M: Magnetometer>(m: &mut M) -> Result<Option<f32>, M::Error> {
///     match m.read_gauss() {
///         Ok(field) => Ok(heading::magnetic_heading_deg(field, 0.0, 0.0).ok()),
///         Err(e) if M::is_not_ready(&e) => Ok(None),
///         Err(e) => Err(e),
///     }
/// }
///
/// // QMC5883L datasheet: address 0x0D, chip ID 0Dh = 0xFF, SET/RESET
/// // period 0Bh = 0x01, control 1 09h = 0x11 (continuous, 10 Hz, ±8 G, OSR
/// // 512); status 06h bit 0 = DRDY; data 00h..05h, X/Y/Z LSB first, 3000 LSB/G.
/// // Y = −600 (0xFDA8) is −0.2 G: the horizontal field, which points to
/// // magnetic north, lies along −y, so +y points south: heading 180°.
/// let expectations = [
///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
///     Transaction::write(0x0D, vec![0x0B, 0x01]),
///     Transaction::write(0x0D, vec![0x09, 0x11]),
///     Transaction::write_read(0x0D, vec![0x06], vec![0x00]),
///     Transaction::write_read(0x0D, vec![0x06], vec![0x01]),
///     Transaction::write_read(0x0D, vec![0x00], vec![0x00, 0x00, 0xA8, 0xFD, 0x00, 0x00]),
/// ];
/// let mut compass = qmc5883l::Qmc5883l::new(Mock::new(&expectations), Default::default())?;
/// assert_eq!(level_heading(&mut compass)?, None); // DRDY clear
/// let h = level_heading(&mut compass)?.unwrap();
/// assert!((h - 180.0).abs() < 1e-4);
/// compass.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
pub trait Magnetometer {
    /// The driver's error type.
    type Error;

    /// Reads one field sample, in gauss, sensor frame.
    ///
    /// ```
    /// use drivers::compass::{hmc5883l, Magnetometer, Vector3};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // HMC5883L datasheet: address 0x1E, identification 0Ah..0Ch "H43",
    /// // configuration A 00h = 0x70, B 01h = 0x20 (±1.3 Ga, 1090 LSB/Ga),
    /// // mode 02h = 0x00; status 09h bit 0 = RDY; data 03h..08h in the order
    /// // X, Z, Y, MSB first. X = 1090 (0x0442) is 1 Ga.
    /// let expectations = [
    ///     Transaction::write_read(0x1E, vec![0x0A], vec![b'H', b'4', b'3']),
    ///     Transaction::write(0x1E, vec![0x00, 0x70]),
    ///     Transaction::write(0x1E, vec![0x01, 0x20]),
    ///     Transaction::write(0x1E, vec![0x02, 0x00]),
    ///     Transaction::write_read(0x1E, vec![0x09], vec![0x01]),
    ///     Transaction::write_read(0x1E, vec![0x03], vec![0x04, 0x42, 0x00, 0x00, 0x00, 0x00]),
    /// ];
    /// let mut compass = hmc5883l::Hmc5883l::new(Mock::new(&expectations), Default::default())?;
    /// assert_eq!(compass.read_gauss()?, Vector3::new(1.0, 0.0, 0.0));
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn read_gauss(&mut self) -> Result<Vector3, Self::Error>;

    /// True when `error` only says that no new sample is ready yet: the
    /// part measures at its output data rate (the QMC5883L at 10 Hz by
    /// default), and a reader faster than that is told so. Not a fault: the
    /// caller reads again later. False for every other error.
    ///
    /// ```
    /// use drivers::compass::{qmc5883l, Magnetometer};
    /// use embedded_hal::i2c::ErrorKind;
    ///
    /// type Chip = qmc5883l::Qmc5883l<embedded_hal_mock::eh1::i2c::Mock>;
    /// assert!(Chip::is_not_ready(&qmc5883l::Error::NotReady));
    /// assert!(!Chip::is_not_ready(&qmc5883l::Error::Overflow));
    /// assert!(!Chip::is_not_ready(&qmc5883l::Error::Comm(ErrorKind::Other)));
    /// ```
    fn is_not_ready(error: &Self::Error) -> bool {
        let _ = error;
        false
    }
}

/// Where the magnetic declination comes from.
///
/// ```
/// use drivers::compass::DeclinationSource;
///
/// let config = DeclinationSource::Fixed { declination_deg: 2.5 };
/// assert_eq!(config.declination_deg(47.0, 8.0, 0.5, 2026.0), Ok(2.5));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    ///
    /// ```
    /// use drivers::compass::{wmm::WmmError, DeclinationSource};
    ///
    /// // NOAA's WMM2025 test values: 2025.0, 0 km, 80° N, 0° E: D = 1.28°.
    /// let d = DeclinationSource::Wmm2025.declination_deg(80.0, 0.0, 0.0, 2025.0)?;
    /// assert!((d - 1.28).abs() < 0.005);
    /// // A configured value must be a number.
    /// let bad = DeclinationSource::Fixed { declination_deg: f32::NAN };
    /// assert_eq!(bad.declination_deg(80.0, 0.0, 0.0, 2025.0), Err(WmmError::NonFinite));
    /// // Outside the model's life span 2025.0..=2030.0.
    /// assert_eq!(
    ///     DeclinationSource::Wmm2025.declination_deg(80.0, 0.0, 0.0, 2031.0),
    ///     Err(WmmError::DateOutsideModel)
    /// );
    /// # Ok::<(), WmmError>(())
    /// ```
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
