//! QST QMC5883L three-axis magnetometer over I2C (our driver).
//!
//! Register map (QMC5883L datasheet, section 9):
//! `00h–05h` data X, Y, Z (LSB first, two's complement), `06h` status
//! (bit 0 DRDY, bit 1 OVL, bit 2 DOR), `09h` control 1 (`OSR[7:6]`, `RNG[5:4]`,
//! `ODR[3:2]`, `MODE[1:0]`), `0Ah` control 2 (SOFT_RST bit 7), `0Bh` SET/RESET
//! period (datasheet: write 0x01), `0Dh` chip ID (reads 0xFF).
//! Seven-bit address 0x0D. Sensitivity 12000 LSB/G (±2 G) or 3000 LSB/G (±8 G).

use embedded_hal::i2c::I2c;

use super::{Magnetometer, Vector3};

/// Fixed seven-bit I2C address.
///
/// ```
/// use drivers::compass::qmc5883l::ADDRESS;
///
/// assert_eq!(ADDRESS, 0x0D); // QMC5883L datasheet, I2C interface
/// ```
pub const ADDRESS: u8 = 0x0D;

const REG_DATA_X_LSB: u8 = 0x00;
const REG_STATUS: u8 = 0x06;
const REG_CONTROL1: u8 = 0x09;
const REG_CONTROL2: u8 = 0x0A;
const REG_SET_RESET_PERIOD: u8 = 0x0B;
const REG_CHIP_ID: u8 = 0x0D;

const CHIP_ID: u8 = 0xFF;
const SET_RESET_PERIOD: u8 = 0x01;
const SOFT_RESET: u8 = 0x80;
const STATUS_DRDY: u8 = 1 << 0;
const STATUS_OVL: u8 = 1 << 1;
const STATUS_DOR: u8 = 1 << 2;
const MODE_CONTINUOUS: u8 = 0b01;
const MODE_MASK: u8 = 0b11;

/// Driver errors.
///
/// ```
/// use drivers::compass::qmc5883l::{Config, Error, Qmc5883l};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // QMC5883L datasheet: the chip-ID register 0Dh reads 0xFF; a chip
/// // answering 0x00 there is not a QMC5883L.
/// let expectations = [Transaction::write_read(0x0D, vec![0x0D], vec![0x00])];
/// let mut i2c = Mock::new(&expectations);
/// let e = Qmc5883l::new(i2c.clone(), Config::default()).unwrap_err();
/// assert_eq!(e, Error::WrongChip(0x00));
/// assert_eq!(e.to_string(), "QMC5883L chip-ID register reads 0x00, expected 0xff");
/// i2c.done();
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error<E> {
    /// I2C bus error (NACK, arbitration loss, ...).
    Comm(E),
    /// The chip-ID register did not read 0xFF.
    WrongChip(u8),
    /// DRDY is clear: no new sample yet.
    NotReady,
    /// OVL is set: some axis is outside the selected range (data read and discarded).
    Overflow,
}

impl<E: core::fmt::Debug> core::fmt::Display for Error<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Comm(e) => write!(f, "QMC5883L I2C error: {e:?}"),
            Error::WrongChip(id) => write!(
                f,
                "QMC5883L chip-ID register reads {id:#04x}, expected 0xff"
            ),
            Error::NotReady => f.write_str("QMC5883L has no new sample yet"),
            Error::Overflow => f.write_str("QMC5883L axis outside the selected range"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for Error<E> {}

/// Output data rate (control 1, ODR bits 3:2).
///
/// ```
/// use drivers::compass::qmc5883l::{Config, DataRate, OverSampling, Range};
///
/// let config = Config { rate: DataRate::Hz50, range: Range::Gauss2, oversampling: OverSampling::X64 };
/// assert_ne!(config, Config::default());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DataRate {
    /// 10 Hz.
    Hz10 = 0b00,
    /// 50 Hz.
    Hz50 = 0b01,
    /// 100 Hz.
    Hz100 = 0b10,
    /// 200 Hz.
    Hz200 = 0b11,
}

/// Full-scale range (control 1, RNG bits 5:4).
///
/// ```
/// use drivers::compass::qmc5883l::{Config, DataRate, OverSampling, Range};
///
/// let config = Config { rate: DataRate::Hz50, range: Range::Gauss2, oversampling: OverSampling::X64 };
/// assert_ne!(config, Config::default());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Range {
    /// ±2 gauss, 12000 LSB/G.
    Gauss2 = 0b00,
    /// ±8 gauss, 3000 LSB/G.
    Gauss8 = 0b01,
}

/// Over-sampling ratio (control 1, OSR bits 7:6).
///
/// ```
/// use drivers::compass::qmc5883l::{Config, DataRate, OverSampling, Range};
///
/// let config = Config { rate: DataRate::Hz50, range: Range::Gauss2, oversampling: OverSampling::X64 };
/// assert_ne!(config, Config::default());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum OverSampling {
    /// 512.
    X512 = 0b00,
    /// 256.
    X256 = 0b01,
    /// 128.
    X128 = 0b10,
    /// 64.
    X64 = 0b11,
}

/// Measurement configuration.
///
/// ```
/// use drivers::compass::qmc5883l::{Config, DataRate, OverSampling, Qmc5883l, Range};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // QMC5883L datasheet, control 1 (09h): OSR[7:6] = 01 (256), RNG[5:4] = 00
/// // (±2 G), ODR[3:2] = 11 (200 Hz), MODE[1:0] = 01 (continuous): 0x4D.
/// let config = Config { rate: DataRate::Hz200, range: Range::Gauss2, oversampling: OverSampling::X256 };
/// let expectations = [
///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
///     Transaction::write(0x0D, vec![0x0B, 0x01]),
///     Transaction::write(0x0D, vec![0x09, 0x4D]),
/// ];
/// let compass = Qmc5883l::new(Mock::new(&expectations), config)?;
/// compass.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// Output data rate.
    pub rate: DataRate,
    /// Full-scale range.
    pub range: Range,
    /// Over-sampling ratio.
    pub oversampling: OverSampling,
}

impl Default for Config {
    /// 10 Hz, ±8 G, OSR 512: control 1 = 0x11.
    fn default() -> Self {
        Self {
            rate: DataRate::Hz10,
            range: Range::Gauss8,
            oversampling: OverSampling::X512,
        }
    }
}

impl Config {
    fn control1(&self) -> u8 {
        ((self.oversampling as u8) << 6)
            | ((self.range as u8) << 4)
            | ((self.rate as u8) << 2)
            | MODE_CONTINUOUS
    }

    fn lsb_per_gauss(&self) -> f32 {
        match self.range {
            Range::Gauss2 => 12_000.0,
            Range::Gauss8 => 3_000.0,
        }
    }
}

/// Raw status flags (register 06h).
///
/// ```
/// use drivers::compass::qmc5883l::{Config, Qmc5883l, Status};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // QMC5883L datasheet: chip ID 0Dh = 0xFF, SET/RESET period 0Bh ← 0x01,
/// // control 1 09h ← 0x11 (the default Config).
/// let init = [
///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
///     Transaction::write(0x0D, vec![0x0B, 0x01]),
///     Transaction::write(0x0D, vec![0x09, 0x11]),
/// ];
/// // Status 06h = 0x02: OVL only.
/// let mut expectations = init.to_vec();
/// expectations.push(Transaction::write_read(0x0D, vec![0x06], vec![0x02]));
/// let mut compass = Qmc5883l::new(Mock::new(&expectations), Config::default())?;
/// let expected = Status { data_ready: false, overflow: true, data_skipped: false };
/// assert_eq!(compass.status()?, expected);
/// compass.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status {
    /// DRDY: new data ready.
    pub data_ready: bool,
    /// OVL: a channel is out of range.
    pub overflow: bool,
    /// DOR: a sample was skipped because the data was not read in time.
    pub data_skipped: bool,
}

/// One raw sample in LSB.
///
/// ```
/// use drivers::compass::qmc5883l::RawField;
///
/// // At ±8 G (3000 LSB/G) a 0.5 G field along x reads 1500.
/// let raw = RawField { x: 1_500, y: 0, z: 0 };
/// assert_eq!(f32::from(raw.x) / 3_000.0, 0.5);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RawField {
    /// X.
    pub x: i16,
    /// Y.
    pub y: i16,
    /// Z.
    pub z: i16,
}

/// QMC5883L device.
///
/// ```
/// use drivers::compass::qmc5883l::{Config, Qmc5883l};
/// use drivers::compass::{Magnetometer, Vector3};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // QMC5883L datasheet, section 9: address 0x0D; chip ID 0Dh reads 0xFF;
/// // SET/RESET period 0Bh ← 0x01; control 1 09h ← 0x11 (OSR 512, ±8 G,
/// // 10 Hz, continuous: the default Config).
/// let init = [
///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
///     Transaction::write(0x0D, vec![0x0B, 0x01]),
///     Transaction::write(0x0D, vec![0x09, 0x11]),
/// ];
/// // Status 06h = 0x01 (DRDY), then data 00h..05h, LSB first: X = 3000
/// // (0x0BB8) = 1 G and Y = −1500 (0xFA24) = −0.5 G at 3000 LSB/G.
/// let mut expectations = init.to_vec();
/// expectations.extend([
///     Transaction::write_read(0x0D, vec![0x06], vec![0x01]),
///     Transaction::write_read(0x0D, vec![0x00], vec![0xB8, 0x0B, 0x24, 0xFA, 0x00, 0x00]),
/// ]);
/// let mut compass = Qmc5883l::new(Mock::new(&expectations), Config::default())?;
/// assert_eq!(compass.read_gauss()?, Vector3::new(1.0, -0.5, 0.0));
/// compass.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Qmc5883l<I2C> {
    i2c: I2C,
    config: Config,
}

impl<I2C: I2c> Qmc5883l<I2C> {
    /// Checks the chip ID, writes the SET/RESET period and starts continuous
    /// measurement with `config`.
    ///
    /// ```
    /// use drivers::compass::qmc5883l::{Config, Qmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // QMC5883L datasheet, section 9: address 0x0D; chip ID 0Dh reads 0xFF;
    /// // SET/RESET period 0Bh ← 0x01; control 1 09h ← 0x11 (OSR 512, ±8 G,
    /// // 10 Hz, continuous: the default Config).
    /// let init = [
    ///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
    ///     Transaction::write(0x0D, vec![0x0B, 0x01]),
    ///     Transaction::write(0x0D, vec![0x09, 0x11]),
    /// ];
    /// let compass = Qmc5883l::new(Mock::new(&init), Config::default())?;
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn new(i2c: I2C, config: Config) -> Result<Self, Error<I2C::Error>> {
        let mut dev = Self { i2c, config };
        let mut id = [0u8];
        dev.i2c
            .write_read(ADDRESS, &[REG_CHIP_ID], &mut id)
            .map_err(Error::Comm)?;
        if id[0] != CHIP_ID {
            return Err(Error::WrongChip(id[0]));
        }
        dev.write_register(REG_SET_RESET_PERIOD, SET_RESET_PERIOD)?;
        dev.write_register(REG_CONTROL1, config.control1())?;
        Ok(dev)
    }

    /// Gives the bus back.
    ///
    /// ```
    /// use drivers::compass::qmc5883l::{Config, Qmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // QMC5883L datasheet, section 9: address 0x0D; chip ID 0Dh reads 0xFF;
    /// // SET/RESET period 0Bh ← 0x01; control 1 09h ← 0x11 (OSR 512, ±8 G,
    /// // 10 Hz, continuous: the default Config).
    /// let init = [
    ///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
    ///     Transaction::write(0x0D, vec![0x0B, 0x01]),
    ///     Transaction::write(0x0D, vec![0x09, 0x11]),
    /// ];
    /// let compass = Qmc5883l::new(Mock::new(&init), Config::default())?;
    /// let mut i2c = compass.destroy();
    /// i2c.done(); // the bus is free for another device
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn destroy(self) -> I2C {
        self.i2c
    }

    /// Current configuration.
    ///
    /// ```
    /// use drivers::compass::qmc5883l::{Config, Qmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // QMC5883L datasheet, section 9: address 0x0D; chip ID 0Dh reads 0xFF;
    /// // SET/RESET period 0Bh ← 0x01; control 1 09h ← 0x11 (OSR 512, ±8 G,
    /// // 10 Hz, continuous: the default Config).
    /// let init = [
    ///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
    ///     Transaction::write(0x0D, vec![0x0B, 0x01]),
    ///     Transaction::write(0x0D, vec![0x09, 0x11]),
    /// ];
    /// let compass = Qmc5883l::new(Mock::new(&init), Config::default())?;
    /// assert_eq!(compass.config(), Config::default());
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn config(&self) -> Config {
        self.config
    }

    /// Reads the status register.
    ///
    /// ```
    /// use drivers::compass::qmc5883l::{Config, Qmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // QMC5883L datasheet, section 9: address 0x0D; chip ID 0Dh reads 0xFF;
    /// // SET/RESET period 0Bh ← 0x01; control 1 09h ← 0x11 (OSR 512, ±8 G,
    /// // 10 Hz, continuous: the default Config).
    /// let init = [
    ///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
    ///     Transaction::write(0x0D, vec![0x0B, 0x01]),
    ///     Transaction::write(0x0D, vec![0x09, 0x11]),
    /// ];
    /// // Status 06h = 0x05: DRDY (bit 0) and DOR (bit 2, a sample skipped).
    /// let mut expectations = init.to_vec();
    /// expectations.push(Transaction::write_read(0x0D, vec![0x06], vec![0x05]));
    /// let mut compass = Qmc5883l::new(Mock::new(&expectations), Config::default())?;
    /// let s = compass.status()?;
    /// assert!(s.data_ready && s.data_skipped && !s.overflow);
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn status(&mut self) -> Result<Status, Error<I2C::Error>> {
        let s = self.read_register(REG_STATUS)?;
        Ok(Status {
            data_ready: s & STATUS_DRDY != 0,
            overflow: s & STATUS_OVL != 0,
            data_skipped: s & STATUS_DOR != 0,
        })
    }

    /// Reads one sample: status first; `NotReady` without DRDY; otherwise the six
    /// data bytes (which clears DRDY), then `Overflow` if OVL was set.
    ///
    /// ```
    /// use drivers::compass::qmc5883l::{Config, Error, Qmc5883l, RawField};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // QMC5883L datasheet, section 9: address 0x0D; chip ID 0Dh reads 0xFF;
    /// // SET/RESET period 0Bh ← 0x01; control 1 09h ← 0x11 (OSR 512, ±8 G,
    /// // 10 Hz, continuous: the default Config).
    /// let init = [
    ///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
    ///     Transaction::write(0x0D, vec![0x0B, 0x01]),
    ///     Transaction::write(0x0D, vec![0x09, 0x11]),
    /// ];
    /// // Status 06h: 0x00 (no DRDY), then 0x01 with data 00h..05h LSB first,
    /// // then 0x03 (DRDY and OVL): the data is read and discarded.
    /// let mut expectations = init.to_vec();
    /// expectations.extend([
    ///     Transaction::write_read(0x0D, vec![0x06], vec![0x00]),
    ///     Transaction::write_read(0x0D, vec![0x06], vec![0x01]),
    ///     Transaction::write_read(0x0D, vec![0x00], vec![0x10, 0x00, 0xF0, 0xFF, 0x00, 0x80]),
    ///     Transaction::write_read(0x0D, vec![0x06], vec![0x03]),
    ///     Transaction::write_read(0x0D, vec![0x00], vec![0xFF, 0x7F, 0x00, 0x00, 0x00, 0x00]),
    /// ]);
    /// let mut compass = Qmc5883l::new(Mock::new(&expectations), Config::default())?;
    /// assert_eq!(compass.read_raw(), Err(Error::NotReady));
    /// assert_eq!(compass.read_raw()?, RawField { x: 16, y: -16, z: -32_768 });
    /// assert_eq!(compass.read_raw(), Err(Error::Overflow));
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn read_raw(&mut self) -> Result<RawField, Error<I2C::Error>> {
        let status = self.status()?;
        if !status.data_ready {
            return Err(Error::NotReady);
        }
        let mut b = [0u8; 6];
        self.i2c
            .write_read(ADDRESS, &[REG_DATA_X_LSB], &mut b)
            .map_err(Error::Comm)?;
        if status.overflow {
            return Err(Error::Overflow);
        }
        Ok(RawField {
            x: i16::from_le_bytes([b[0], b[1]]),
            y: i16::from_le_bytes([b[2], b[3]]),
            z: i16::from_le_bytes([b[4], b[5]]),
        })
    }

    /// Puts the chip in standby (MODE = 00), keeping the other settings.
    ///
    /// ```
    /// use drivers::compass::qmc5883l::{Config, Qmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // QMC5883L datasheet, section 9: address 0x0D; chip ID 0Dh reads 0xFF;
    /// // SET/RESET period 0Bh ← 0x01; control 1 09h ← 0x11 (OSR 512, ±8 G,
    /// // 10 Hz, continuous: the default Config).
    /// let init = [
    ///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
    ///     Transaction::write(0x0D, vec![0x0B, 0x01]),
    ///     Transaction::write(0x0D, vec![0x09, 0x11]),
    /// ];
    /// // Control 1 with MODE[1:0] = 00: 0x11 becomes 0x10.
    /// let mut expectations = init.to_vec();
    /// expectations.push(Transaction::write(0x0D, vec![0x09, 0x10]));
    /// let mut compass = Qmc5883l::new(Mock::new(&expectations), Config::default())?;
    /// compass.standby()?;
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn standby(&mut self) -> Result<(), Error<I2C::Error>> {
        self.write_register(REG_CONTROL1, self.config.control1() & !MODE_MASK)
    }

    /// Soft reset (control 2 bit 7); call [`Qmc5883l::new`] again afterwards.
    ///
    /// ```
    /// use drivers::compass::qmc5883l::{Config, Qmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // QMC5883L datasheet, section 9: address 0x0D; chip ID 0Dh reads 0xFF;
    /// // SET/RESET period 0Bh ← 0x01; control 1 09h ← 0x11 (OSR 512, ±8 G,
    /// // 10 Hz, continuous: the default Config).
    /// let init = [
    ///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
    ///     Transaction::write(0x0D, vec![0x0B, 0x01]),
    ///     Transaction::write(0x0D, vec![0x09, 0x11]),
    /// ];
    /// // Control 2 (0Ah) ← 0x80: SOFT_RST.
    /// let mut expectations = init.to_vec();
    /// expectations.push(Transaction::write(0x0D, vec![0x0A, 0x80]));
    /// let mut compass = Qmc5883l::new(Mock::new(&expectations), Config::default())?;
    /// compass.soft_reset()?;
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn soft_reset(&mut self) -> Result<(), Error<I2C::Error>> {
        self.write_register(REG_CONTROL2, SOFT_RESET)
    }

    fn write_register(&mut self, reg: u8, value: u8) -> Result<(), Error<I2C::Error>> {
        self.i2c.write(ADDRESS, &[reg, value]).map_err(Error::Comm)
    }

    fn read_register(&mut self, reg: u8) -> Result<u8, Error<I2C::Error>> {
        let mut b = [0u8];
        self.i2c
            .write_read(ADDRESS, &[reg], &mut b)
            .map_err(Error::Comm)?;
        Ok(b[0])
    }
}

impl<I2C: I2c> Magnetometer for Qmc5883l<I2C> {
    type Error = Error<I2C::Error>;

    /// [`Qmc5883l::read_raw`] divided by the range's sensitivity (12000
    /// LSB/G at ±2 G, 3000 LSB/G at ±8 G).
    ///
    /// ```
    /// use drivers::compass::qmc5883l::{Config, DataRate, OverSampling, Qmc5883l, Range};
    /// use drivers::compass::{Magnetometer, Vector3};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // QMC5883L datasheet: ±2 G is RNG = 00, control 1 = 0x01; at 12000
    /// // LSB/G, Z = −6000 (0xE890, LSB first) is −0.5 G.
    /// let config = Config { rate: DataRate::Hz10, range: Range::Gauss2, oversampling: OverSampling::X512 };
    /// let expectations = [
    ///     Transaction::write_read(0x0D, vec![0x0D], vec![0xFF]),
    ///     Transaction::write(0x0D, vec![0x0B, 0x01]),
    ///     Transaction::write(0x0D, vec![0x09, 0x01]),
    ///     Transaction::write_read(0x0D, vec![0x06], vec![0x01]),
    ///     Transaction::write_read(0x0D, vec![0x00], vec![0x00, 0x00, 0x00, 0x00, 0x90, 0xE8]),
    /// ];
    /// let mut compass = Qmc5883l::new(Mock::new(&expectations), config)?;
    /// assert_eq!(compass.read_gauss()?, Vector3::new(0.0, 0.0, -0.5));
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn read_gauss(&mut self) -> Result<Vector3, Self::Error> {
        let raw = self.read_raw()?;
        let k = self.config.lsb_per_gauss();
        Ok(Vector3::new(
            f32::from(raw.x) / k,
            f32::from(raw.y) / k,
            f32::from(raw.z) / k,
        ))
    }

    /// `true` for [`Error::NotReady`] (DRDY clear) only.
    ///
    /// ```
    /// use drivers::compass::qmc5883l::{Error, Qmc5883l};
    /// use drivers::compass::Magnetometer;
    /// use embedded_hal::i2c::ErrorKind;
    /// use embedded_hal_mock::eh1::i2c::Mock;
    ///
    /// assert!(Qmc5883l::<Mock>::is_not_ready(&Error::NotReady));
    /// assert!(!Qmc5883l::<Mock>::is_not_ready(&Error::Comm(ErrorKind::Bus)));
    /// ```
    fn is_not_ready(error: &Self::Error) -> bool {
        matches!(error, Error::NotReady)
    }
}
