//! ADXL345 three-axis accelerometer over I2C, the cheap tilt sensor: at rest
//! it measures gravity, from which roll and pitch follow.
//!
//! Register facts from the Analog Devices ADXL345 datasheet (Rev. G):
//! I2C address 0x53 with ALT ADDRESS low, 0x1D with it high; DEVID (0x00)
//! reads 0xE5; BW_RATE (0x2C) rate code 0x0A = 100 Hz; POWER_CTL (0x2D) bit 3
//! Measure; DATA_FORMAT (0x31) bit 3 FULL_RES, bits 1:0 range (00 = ±2 g);
//! DATAX0..DATAZ1 (0x32..0x37) little-endian two's complement, read in one
//! multi-byte transfer; full resolution scale 3.9 mg/LSB (256 LSB/g typical).

use crate::fmath;
use embedded_hal::i2c::I2c;

use super::Inclination;

/// I2C address with ALT ADDRESS tied low.
///
/// ```
/// use drivers::tilt::adxl345::{Adxl345, ADDRESS_ALT_LOW};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // ADXL345 datasheet: 0x53 with ALT ADDRESS low; DEVID 0x00 reads 0xE5.
/// let expectations = [Transaction::write_read(0x53, vec![0x00], vec![0x00])];
/// let mut accel = Adxl345::new(Mock::new(&expectations), ADDRESS_ALT_LOW);
/// assert!(accel.init().is_err()); // DEVID 0x00: no ADXL345 there
/// accel.destroy().done();
/// ```
pub const ADDRESS_ALT_LOW: u8 = 0x53;
/// I2C address with ALT ADDRESS tied high.
///
/// ```
/// use drivers::tilt::adxl345::{Adxl345, ADDRESS_ALT_HIGH};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // ADXL345 datasheet: 0x1D with ALT ADDRESS high; data 0x32..0x37.
/// let expectations = [Transaction::write_read(0x1D, vec![0x32], vec![0; 6])];
/// let mut accel = Adxl345::new(Mock::new(&expectations), ADDRESS_ALT_HIGH);
/// assert_eq!(accel.read_raw()?, [0, 0, 0]);
/// accel.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
pub const ADDRESS_ALT_HIGH: u8 = 0x1D;

const REG_DEVID: u8 = 0x00;
const REG_BW_RATE: u8 = 0x2C;
const REG_POWER_CTL: u8 = 0x2D;
const REG_DATA_FORMAT: u8 = 0x31;
const REG_DATAX0: u8 = 0x32;

const DEVID: u8 = 0xE5;
const BW_RATE_100HZ: u8 = 0x0A;
const POWER_CTL_MEASURE: u8 = 0b0000_1000;
const DATA_FORMAT_FULL_RES_2G: u8 = 0b0000_1000;
/// g per LSB at full resolution (3.9 mg/LSB).
const G_PER_LSB: f32 = 0.0039;

/// ADXL345 errors.
///
/// ```
/// use drivers::tilt::adxl345::{Adxl345, Error, ADDRESS_ALT_LOW};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // ADXL345 datasheet: DEVID (0x00) reads 0xE5; 0x00 means another chip
/// // (or none) answered.
/// let expectations = [Transaction::write_read(0x53, vec![0x00], vec![0x00])];
/// let mut accel = Adxl345::new(Mock::new(&expectations), ADDRESS_ALT_LOW);
/// let e = accel.init().unwrap_err();
/// assert_eq!(e, Error::WrongDeviceId(0x00));
/// assert_eq!(e.to_string(), "ADXL345 DEVID reads 0x00, expected 0xe5");
/// accel.destroy().done();
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error<E> {
    /// I2C error (e.g. NACK).
    Comm(E),
    /// DEVID was not 0xE5: the value read.
    WrongDeviceId(u8),
    /// The acceleration is too small to tell which way is down.
    NoGravity,
}

impl<E: core::fmt::Debug> core::fmt::Display for Error<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Comm(e) => write!(f, "ADXL345 I2C error: {e:?}"),
            Error::WrongDeviceId(id) => write!(f, "ADXL345 DEVID reads {id:#04x}, expected 0xe5"),
            Error::NoGravity => f.write_str("acceleration too small to tell which way is down"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for Error<E> {}

/// Acceleration in units of g.
///
/// ```
/// use drivers::tilt::adxl345::{inclination_from_gravity, Acceleration};
///
/// let at_rest = Acceleration { x_g: 0.0, y_g: 0.0, z_g: 1.0 };
/// let level = inclination_from_gravity(&at_rest).unwrap();
/// assert_eq!((level.roll_deg, level.pitch_deg), (0.0, 0.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Acceleration {
    /// X axis, g.
    pub x_g: f32,
    /// Y axis, g.
    pub y_g: f32,
    /// Z axis, g.
    pub z_g: f32,
}

/// Roll about X and pitch about Y from gravity, for the X-Y-Z rotation
/// sequence (NXP application note AN3461, eqs. 25 and 26):
/// roll = atan2(y, z), pitch = atan2(-x, sqrt(y² + z²)).
/// `None` when |a| < 0.1 g (free fall: no direction to measure).
///
/// ```
/// use drivers::tilt::adxl345::{inclination_from_gravity, Acceleration};
///
/// // Gravity (0, sin 30°, cos 30°): rolled 30° about x (AN3461 eq. 25).
/// let a = Acceleration { x_g: 0.0, y_g: 0.5, z_g: 0.866_025_4 };
/// let i = inclination_from_gravity(&a).unwrap();
/// assert!((i.roll_deg - 30.0).abs() < 1e-4 && i.pitch_deg.abs() < 1e-4);
/// // (−sin 20°, 0, cos 20°): pitched 20° about y (eq. 26).
/// let a = Acceleration { x_g: -0.342_020_1, y_g: 0.0, z_g: 0.939_692_6 };
/// assert!((inclination_from_gravity(&a).unwrap().pitch_deg - 20.0).abs() < 1e-4);
/// // Free fall.
/// assert_eq!(inclination_from_gravity(&Acceleration { x_g: 0.0, y_g: 0.05, z_g: 0.0 }), None);
/// ```
pub fn inclination_from_gravity(a: &Acceleration) -> Option<Inclination> {
    let norm = fmath::sqrt(a.x_g * a.x_g + a.y_g * a.y_g + a.z_g * a.z_g);
    if norm.is_nan() || norm < 0.1 {
        return None;
    }
    let roll = fmath::atan2(a.y_g, a.z_g);
    let pitch = fmath::atan2(-a.x_g, fmath::sqrt(a.y_g * a.y_g + a.z_g * a.z_g));
    Some(Inclination {
        roll_deg: roll.to_degrees(),
        pitch_deg: pitch.to_degrees(),
    })
}

/// An ADXL345 on I2C.
///
/// ```
/// use drivers::tilt::adxl345::{Adxl345, ADDRESS_ALT_LOW};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // ADXL345 datasheet (Rev. G): DEVID 0x00 reads 0xE5; DATA_FORMAT 0x31
/// // ← 0x08 (FULL_RES, ±2 g); BW_RATE 0x2C ← 0x0A (100 Hz); POWER_CTL 0x2D
/// // ← 0x08 (Measure). Address 0x53 with ALT ADDRESS low.
/// let init = [
///     Transaction::write_read(0x53, vec![0x00], vec![0xE5]),
///     Transaction::write(0x53, vec![0x31, 0x08]),
///     Transaction::write(0x53, vec![0x2C, 0x0A]),
///     Transaction::write(0x53, vec![0x2D, 0x08]),
/// ];
/// // DATAX0..DATAZ1 (0x32..0x37), little-endian: x = 0, y = 0, z = 256
/// // (one g at the typical 256 LSB/g).
/// let mut expectations = init.to_vec();
/// expectations.push(Transaction::write_read(0x53, vec![0x32], vec![0x00, 0x00, 0x00, 0x00, 0x00, 0x01]));
/// let mut accel = Adxl345::new(Mock::new(&expectations), ADDRESS_ALT_LOW);
/// accel.init()?;
/// let level = accel.read_inclination()?;
/// assert_eq!((level.roll_deg, level.pitch_deg), (0.0, 0.0));
/// accel.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Adxl345<I2C> {
    i2c: I2C,
    address: u8,
}

impl<I2C: I2c> Adxl345<I2C> {
    /// Wraps the bus; no bus traffic until [`Adxl345::init`].
    ///
    /// ```
    /// use drivers::tilt::adxl345::{Adxl345, ADDRESS_ALT_LOW};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // No transactions expected.
    /// let accel = Adxl345::new(Mock::new(&[]), ADDRESS_ALT_LOW);
    /// accel.destroy().done();
    /// ```
    pub fn new(i2c: I2C, address: u8) -> Self {
        Self { i2c, address }
    }

    /// Gives the bus back.
    ///
    /// ```
    /// use drivers::tilt::adxl345::{Adxl345, ADDRESS_ALT_LOW};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // ADXL345 datasheet (Rev. G): DEVID 0x00 reads 0xE5; DATA_FORMAT 0x31
    /// // ← 0x08 (FULL_RES, ±2 g); BW_RATE 0x2C ← 0x0A (100 Hz); POWER_CTL 0x2D
    /// // ← 0x08 (Measure). Address 0x53 with ALT ADDRESS low.
    /// let init = [
    ///     Transaction::write_read(0x53, vec![0x00], vec![0xE5]),
    ///     Transaction::write(0x53, vec![0x31, 0x08]),
    ///     Transaction::write(0x53, vec![0x2C, 0x0A]),
    ///     Transaction::write(0x53, vec![0x2D, 0x08]),
    /// ];
    /// let mut accel = Adxl345::new(Mock::new(&init), ADDRESS_ALT_LOW);
    /// accel.init()?;
    /// let mut i2c = accel.destroy();
    /// i2c.done(); // the bus is free for another device
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn destroy(self) -> I2C {
        self.i2c
    }

    /// Checks DEVID, then sets full resolution ±2 g, 100 Hz, and measurement mode.
    ///
    /// ```
    /// use drivers::tilt::adxl345::{Adxl345, ADDRESS_ALT_LOW};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // ADXL345 datasheet (Rev. G): DEVID 0x00 reads 0xE5; DATA_FORMAT 0x31
    /// // ← 0x08 (FULL_RES, ±2 g); BW_RATE 0x2C ← 0x0A (100 Hz); POWER_CTL 0x2D
    /// // ← 0x08 (Measure). Address 0x53 with ALT ADDRESS low.
    /// let init = [
    ///     Transaction::write_read(0x53, vec![0x00], vec![0xE5]),
    ///     Transaction::write(0x53, vec![0x31, 0x08]),
    ///     Transaction::write(0x53, vec![0x2C, 0x0A]),
    ///     Transaction::write(0x53, vec![0x2D, 0x08]),
    /// ];
    /// let mut accel = Adxl345::new(Mock::new(&init), ADDRESS_ALT_LOW);
    /// accel.init()?;
    /// accel.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn init(&mut self) -> Result<(), Error<I2C::Error>> {
        let mut id = [0];
        self.i2c
            .write_read(self.address, &[REG_DEVID], &mut id)
            .map_err(Error::Comm)?;
        if id[0] != DEVID {
            return Err(Error::WrongDeviceId(id[0]));
        }
        for (reg, value) in [
            (REG_DATA_FORMAT, DATA_FORMAT_FULL_RES_2G),
            (REG_BW_RATE, BW_RATE_100HZ),
            (REG_POWER_CTL, POWER_CTL_MEASURE),
        ] {
            self.i2c
                .write(self.address, &[reg, value])
                .map_err(Error::Comm)?;
        }
        Ok(())
    }

    /// Raw X, Y, Z counts.
    ///
    /// ```
    /// use drivers::tilt::adxl345::{Adxl345, ADDRESS_ALT_LOW};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // ADXL345 datasheet: one multi-byte read of DATAX0..DATAZ1 from 0x32,
    /// // little-endian two's complement: x = −256 (0xFF00), y = 18, z = 255.
    /// let expectations = [Transaction::write_read(
    ///     0x53,
    ///     vec![0x32],
    ///     vec![0x00, 0xFF, 0x12, 0x00, 0xFF, 0x00],
    /// )];
    /// let mut accel = Adxl345::new(Mock::new(&expectations), ADDRESS_ALT_LOW);
    /// assert_eq!(accel.read_raw()?, [-256, 18, 255]);
    /// accel.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn read_raw(&mut self) -> Result<[i16; 3], Error<I2C::Error>> {
        let mut d = [0u8; 6];
        self.i2c
            .write_read(self.address, &[REG_DATAX0], &mut d)
            .map_err(Error::Comm)?;
        let [x0, x1, y0, y1, z0, z1] = d;
        Ok([
            i16::from_le_bytes([x0, x1]),
            i16::from_le_bytes([y0, y1]),
            i16::from_le_bytes([z0, z1]),
        ])
    }

    /// Acceleration in g (full-resolution scale).
    ///
    /// ```
    /// use drivers::tilt::adxl345::{Adxl345, ADDRESS_ALT_LOW};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // ADXL345 datasheet: full resolution, 3.9 mg/LSB; z = 256 (0x0100)
    /// // is 0.9984 g, x = −128 (0xFF80) is −0.4992 g.
    /// let expectations = [Transaction::write_read(
    ///     0x53,
    ///     vec![0x32],
    ///     vec![0x80, 0xFF, 0x00, 0x00, 0x00, 0x01],
    /// )];
    /// let mut accel = Adxl345::new(Mock::new(&expectations), ADDRESS_ALT_LOW);
    /// let a = accel.read_acceleration()?;
    /// assert!((a.z_g - 0.9984).abs() < 1e-6 && (a.x_g + 0.4992).abs() < 1e-6);
    /// accel.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn read_acceleration(&mut self) -> Result<Acceleration, Error<I2C::Error>> {
        let [x, y, z] = self.read_raw()?;
        Ok(Acceleration {
            x_g: f32::from(x) * G_PER_LSB,
            y_g: f32::from(y) * G_PER_LSB,
            z_g: f32::from(z) * G_PER_LSB,
        })
    }

    /// Roll and pitch in degrees from one acceleration sample.
    ///
    /// ```
    /// use drivers::tilt::adxl345::{Adxl345, Error, ADDRESS_ALT_LOW};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // ADXL345 datasheet: data 0x32..0x37. y = z = 181 (0x00B5): rolled
    /// // 45° about x. Then all zero: free fall, no direction to measure.
    /// let expectations = [
    ///     Transaction::write_read(0x53, vec![0x32], vec![0x00, 0x00, 0xB5, 0x00, 0xB5, 0x00]),
    ///     Transaction::write_read(0x53, vec![0x32], vec![0x00; 6]),
    /// ];
    /// let mut accel = Adxl345::new(Mock::new(&expectations), ADDRESS_ALT_LOW);
    /// let i = accel.read_inclination()?;
    /// assert!((i.roll_deg - 45.0).abs() < 1e-4 && i.pitch_deg.abs() < 1e-4);
    /// assert_eq!(accel.read_inclination(), Err(Error::NoGravity));
    /// accel.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn read_inclination(&mut self) -> Result<Inclination, Error<I2C::Error>> {
        let a = self.read_acceleration()?;
        inclination_from_gravity(&a).ok_or(Error::NoGravity)
    }
}
