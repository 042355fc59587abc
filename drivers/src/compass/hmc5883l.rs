//! Honeywell HMC5883L three-axis magnetometer over I2C (our driver).
//!
//! Register map (HMC5883L datasheet, Table 2): `00h` configuration A
//! (`MA[6:5]` samples averaged, `DO[4:2]` output rate, `MS[1:0]` bias), `01h`
//! configuration B (`GN[7:5]` gain), `02h` mode (`MD[1:0]`: 00 continuous,
//! 01 single, 1x idle), `03h–08h` data X, Z, Y (MSB first — note the order),
//! `09h` status (bit 0 RDY, bit 1 LOCK), `0Ah–0Ch` identification "H43".
//! Seven-bit address 0x1E. The chip has no overflow flag: an axis that over- or
//! underflows reads −4096 (0xF000), which [`Hmc5883l::read_raw`] reports as
//! [`Error::Overflow`].

use embedded_hal::i2c::I2c;

use super::{Magnetometer, Vector3};

/// Fixed seven-bit I2C address.
///
/// ```
/// use drivers::compass::hmc5883l::ADDRESS;
///
/// assert_eq!(ADDRESS, 0x1E); // HMC5883L datasheet, I2C interface
/// ```
pub const ADDRESS: u8 = 0x1E;

const REG_CONFIG_A: u8 = 0x00;
const REG_CONFIG_B: u8 = 0x01;
const REG_MODE: u8 = 0x02;
const REG_DATA_X_MSB: u8 = 0x03;
const REG_STATUS: u8 = 0x09;
const REG_ID_A: u8 = 0x0A;

const IDENTIFICATION: [u8; 3] = *b"H43";
const STATUS_RDY: u8 = 1 << 0;
const STATUS_LOCK: u8 = 1 << 1;
const MODE_CONTINUOUS: u8 = 0b00;
const MODE_IDLE: u8 = 0b11;
const OVERFLOW_VALUE: i16 = -4096;

/// Driver errors.
///
/// ```
/// use drivers::compass::hmc5883l::{Config, Error, Hmc5883l};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // HMC5883L datasheet: identification registers 0Ah..0Ch read "H43"; a
/// // QMC5883L clone, say, does not answer them so.
/// let expectations = [Transaction::write_read(0x1E, vec![0x0A], vec![0x00, 0x00, 0x00])];
/// let mut i2c = Mock::new(&expectations);
/// let e = Hmc5883l::new(i2c.clone(), Config::default()).unwrap_err();
/// assert_eq!(e, Error::WrongChip([0, 0, 0]));
/// i2c.done();
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error<E> {
    /// I2C bus error (NACK, arbitration loss, ...).
    Comm(E),
    /// Identification registers did not read "H43".
    WrongChip([u8; 3]),
    /// RDY is clear: no new sample yet.
    NotReady,
    /// An axis read −4096: outside the selected gain's range.
    Overflow,
}

impl<E: core::fmt::Debug> core::fmt::Display for Error<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Comm(e) => write!(f, "HMC5883L I2C error: {e:?}"),
            Error::WrongChip(id) => write!(
                f,
                "HMC5883L identification registers read {id:02x?}, expected \"H43\""
            ),
            Error::NotReady => f.write_str("HMC5883L has no new sample yet"),
            Error::Overflow => f.write_str("HMC5883L axis outside the selected gain's range"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for Error<E> {}

/// Samples averaged per output (configuration A, MA bits 6:5).
///
/// ```
/// use drivers::compass::hmc5883l::{Averaging, Config, DataRate, Gain};
///
/// // The datasheet's defaults: CRA 0x70 (8 samples, 15 Hz), CRB 0x20 (±1.3 Ga).
/// let defaults = Config { averaging: Averaging::X8, rate: DataRate::Hz15, gain: Gain::Ga1_3 };
/// assert_eq!(defaults, Config::default());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Averaging {
    /// 1 sample.
    X1 = 0b00,
    /// 2 samples.
    X2 = 0b01,
    /// 4 samples.
    X4 = 0b10,
    /// 8 samples.
    X8 = 0b11,
}

/// Output rate in continuous mode (configuration A, DO bits 4:2).
///
/// ```
/// use drivers::compass::hmc5883l::{Averaging, Config, DataRate, Gain};
///
/// // The datasheet's defaults: CRA 0x70 (8 samples, 15 Hz), CRB 0x20 (±1.3 Ga).
/// let defaults = Config { averaging: Averaging::X8, rate: DataRate::Hz15, gain: Gain::Ga1_3 };
/// assert_eq!(defaults, Config::default());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DataRate {
    /// 0.75 Hz.
    Hz0_75 = 0b000,
    /// 1.5 Hz.
    Hz1_5 = 0b001,
    /// 3 Hz.
    Hz3 = 0b010,
    /// 7.5 Hz.
    Hz7_5 = 0b011,
    /// 15 Hz (default).
    Hz15 = 0b100,
    /// 30 Hz.
    Hz30 = 0b101,
    /// 75 Hz.
    Hz75 = 0b110,
}

/// Gain (configuration B, GN bits 7:5), named by its range.
///
/// ```
/// use drivers::compass::hmc5883l::{Averaging, Config, DataRate, Gain};
///
/// // The datasheet's defaults: CRA 0x70 (8 samples, 15 Hz), CRB 0x20 (±1.3 Ga).
/// let defaults = Config { averaging: Averaging::X8, rate: DataRate::Hz15, gain: Gain::Ga1_3 };
/// assert_eq!(defaults, Config::default());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Gain {
    /// ±0.88 Ga, 1370 LSB/Ga.
    Ga0_88 = 0b000,
    /// ±1.3 Ga, 1090 LSB/Ga (default).
    Ga1_3 = 0b001,
    /// ±1.9 Ga, 820 LSB/Ga.
    Ga1_9 = 0b010,
    /// ±2.5 Ga, 660 LSB/Ga.
    Ga2_5 = 0b011,
    /// ±4.0 Ga, 440 LSB/Ga.
    Ga4_0 = 0b100,
    /// ±4.7 Ga, 390 LSB/Ga.
    Ga4_7 = 0b101,
    /// ±5.6 Ga, 330 LSB/Ga.
    Ga5_6 = 0b110,
    /// ±8.1 Ga, 230 LSB/Ga.
    Ga8_1 = 0b111,
}

impl Gain {
    fn lsb_per_gauss(self) -> f32 {
        match self {
            Gain::Ga0_88 => 1370.0,
            Gain::Ga1_3 => 1090.0,
            Gain::Ga1_9 => 820.0,
            Gain::Ga2_5 => 660.0,
            Gain::Ga4_0 => 440.0,
            Gain::Ga4_7 => 390.0,
            Gain::Ga5_6 => 330.0,
            Gain::Ga8_1 => 230.0,
        }
    }
}

/// Measurement configuration.
///
/// ```
/// use drivers::compass::hmc5883l::{Averaging, Config, DataRate, Gain, Hmc5883l};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // HMC5883L datasheet: CRA = MA 01 (2 samples), DO 110 (75 Hz) = 0x38;
/// // CRB = GN 111 (±8.1 Ga) = 0xE0.
/// let config = Config { averaging: Averaging::X2, rate: DataRate::Hz75, gain: Gain::Ga8_1 };
/// let expectations = [
///     Transaction::write_read(0x1E, vec![0x0A], vec![0x48, 0x34, 0x33]),
///     Transaction::write(0x1E, vec![0x00, 0x38]),
///     Transaction::write(0x1E, vec![0x01, 0xE0]),
///     Transaction::write(0x1E, vec![0x02, 0x00]),
/// ];
/// let compass = Hmc5883l::new(Mock::new(&expectations), config)?;
/// compass.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// Samples averaged.
    pub averaging: Averaging,
    /// Output rate.
    pub rate: DataRate,
    /// Gain.
    pub gain: Gain,
}

impl Default for Config {
    /// 8-sample average, 15 Hz, normal bias (CRA = 0x70), ±1.3 Ga (CRB = 0x20).
    fn default() -> Self {
        Self {
            averaging: Averaging::X8,
            rate: DataRate::Hz15,
            gain: Gain::Ga1_3,
        }
    }
}

/// Raw status flags (register 09h).
///
/// ```
/// use drivers::compass::hmc5883l::{Config, Hmc5883l, Status};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // HMC5883L datasheet: identification "H43", CRA ← 0x70, CRB ← 0x20,
/// // mode ← 0x00 (the default Config).
/// let init = [
///     Transaction::write_read(0x1E, vec![0x0A], vec![0x48, 0x34, 0x33]),
///     Transaction::write(0x1E, vec![0x00, 0x70]),
///     Transaction::write(0x1E, vec![0x01, 0x20]),
///     Transaction::write(0x1E, vec![0x02, 0x00]),
/// ];
/// // Status 09h = 0x01: RDY.
/// let mut expectations = init.to_vec();
/// expectations.push(Transaction::write_read(0x1E, vec![0x09], vec![0x01]));
/// let mut compass = Hmc5883l::new(Mock::new(&expectations), Config::default())?;
/// assert_eq!(compass.status()?, Status { ready: true, locked: false });
/// compass.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status {
    /// RDY: data written to all six data registers.
    pub ready: bool,
    /// LOCK: data registers locked until all six are read.
    pub locked: bool,
}

/// One raw sample in LSB.
///
/// ```
/// use drivers::compass::hmc5883l::RawField;
///
/// // At ±1.3 Ga (1090 LSB/Ga) a 0.5 Ga field along z reads 545.
/// let raw = RawField { x: 0, y: 0, z: 545 };
/// assert_eq!(f32::from(raw.z) / 1_090.0, 0.5);
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

/// HMC5883L device.
///
/// ```
/// use drivers::compass::hmc5883l::{Config, Hmc5883l};
/// use drivers::compass::{Magnetometer, Vector3};
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// // HMC5883L datasheet, Table 2: address 0x1E; identification 0Ah..0Ch
/// // reads "H43"; configuration A 00h ← 0x70 (8 samples, 15 Hz, normal),
/// // B 01h ← 0x20 (±1.3 Ga), mode 02h ← 0x00 (continuous): the default
/// // Config.
/// let init = [
///     Transaction::write_read(0x1E, vec![0x0A], vec![0x48, 0x34, 0x33]),
///     Transaction::write(0x1E, vec![0x00, 0x70]),
///     Transaction::write(0x1E, vec![0x01, 0x20]),
///     Transaction::write(0x1E, vec![0x02, 0x00]),
/// ];
/// // Status 09h = 0x01 (RDY), then data 03h..08h in the order X, Z, Y, MSB
/// // first: X = −545 (0xFDDF) = −0.5 Ga at 1090 LSB/Ga, Z = 0, Y = 1090.
/// let mut expectations = init.to_vec();
/// expectations.extend([
///     Transaction::write_read(0x1E, vec![0x09], vec![0x01]),
///     Transaction::write_read(0x1E, vec![0x03], vec![0xFD, 0xDF, 0x00, 0x00, 0x04, 0x42]),
/// ]);
/// let mut compass = Hmc5883l::new(Mock::new(&expectations), Config::default())?;
/// assert_eq!(compass.read_gauss()?, Vector3::new(-0.5, 1.0, 0.0));
/// compass.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Hmc5883l<I2C> {
    i2c: I2C,
    config: Config,
}

impl<I2C: I2c> Hmc5883l<I2C> {
    /// Checks the identification registers, writes configuration A and B and
    /// selects continuous-measurement mode (the datasheet's three single writes).
    ///
    /// ```
    /// use drivers::compass::hmc5883l::{Config, Hmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // HMC5883L datasheet, Table 2: address 0x1E; identification 0Ah..0Ch
    /// // reads "H43"; configuration A 00h ← 0x70 (8 samples, 15 Hz, normal),
    /// // B 01h ← 0x20 (±1.3 Ga), mode 02h ← 0x00 (continuous): the default
    /// // Config.
    /// let init = [
    ///     Transaction::write_read(0x1E, vec![0x0A], vec![0x48, 0x34, 0x33]),
    ///     Transaction::write(0x1E, vec![0x00, 0x70]),
    ///     Transaction::write(0x1E, vec![0x01, 0x20]),
    ///     Transaction::write(0x1E, vec![0x02, 0x00]),
    /// ];
    /// let compass = Hmc5883l::new(Mock::new(&init), Config::default())?;
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn new(i2c: I2C, config: Config) -> Result<Self, Error<I2C::Error>> {
        let mut dev = Self { i2c, config };
        let mut id = [0u8; 3];
        dev.i2c
            .write_read(ADDRESS, &[REG_ID_A], &mut id)
            .map_err(Error::Comm)?;
        if id != IDENTIFICATION {
            return Err(Error::WrongChip(id));
        }
        let cra = ((config.averaging as u8) << 5) | ((config.rate as u8) << 2);
        dev.write_register(REG_CONFIG_A, cra)?;
        dev.write_register(REG_CONFIG_B, (config.gain as u8) << 5)?;
        dev.write_register(REG_MODE, MODE_CONTINUOUS)?;
        Ok(dev)
    }

    /// Gives the bus back.
    ///
    /// ```
    /// use drivers::compass::hmc5883l::{Config, Hmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // HMC5883L datasheet, Table 2: address 0x1E; identification 0Ah..0Ch
    /// // reads "H43"; configuration A 00h ← 0x70 (8 samples, 15 Hz, normal),
    /// // B 01h ← 0x20 (±1.3 Ga), mode 02h ← 0x00 (continuous): the default
    /// // Config.
    /// let init = [
    ///     Transaction::write_read(0x1E, vec![0x0A], vec![0x48, 0x34, 0x33]),
    ///     Transaction::write(0x1E, vec![0x00, 0x70]),
    ///     Transaction::write(0x1E, vec![0x01, 0x20]),
    ///     Transaction::write(0x1E, vec![0x02, 0x00]),
    /// ];
    /// let compass = Hmc5883l::new(Mock::new(&init), Config::default())?;
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
    /// use drivers::compass::hmc5883l::{Config, Gain, Hmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // HMC5883L datasheet, Table 2: address 0x1E; identification 0Ah..0Ch
    /// // reads "H43"; configuration A 00h ← 0x70 (8 samples, 15 Hz, normal),
    /// // B 01h ← 0x20 (±1.3 Ga), mode 02h ← 0x00 (continuous): the default
    /// // Config.
    /// let init = [
    ///     Transaction::write_read(0x1E, vec![0x0A], vec![0x48, 0x34, 0x33]),
    ///     Transaction::write(0x1E, vec![0x00, 0x70]),
    ///     Transaction::write(0x1E, vec![0x01, 0x20]),
    ///     Transaction::write(0x1E, vec![0x02, 0x00]),
    /// ];
    /// let compass = Hmc5883l::new(Mock::new(&init), Config::default())?;
    /// assert_eq!(compass.config().gain, Gain::Ga1_3);
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn config(&self) -> Config {
        self.config
    }

    /// Reads the status register.
    ///
    /// ```
    /// use drivers::compass::hmc5883l::{Config, Hmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // HMC5883L datasheet, Table 2: address 0x1E; identification 0Ah..0Ch
    /// // reads "H43"; configuration A 00h ← 0x70 (8 samples, 15 Hz, normal),
    /// // B 01h ← 0x20 (±1.3 Ga), mode 02h ← 0x00 (continuous): the default
    /// // Config.
    /// let init = [
    ///     Transaction::write_read(0x1E, vec![0x0A], vec![0x48, 0x34, 0x33]),
    ///     Transaction::write(0x1E, vec![0x00, 0x70]),
    ///     Transaction::write(0x1E, vec![0x01, 0x20]),
    ///     Transaction::write(0x1E, vec![0x02, 0x00]),
    /// ];
    /// // Status 09h = 0x02: LOCK (bit 1) set, RDY (bit 0) clear.
    /// let mut expectations = init.to_vec();
    /// expectations.push(Transaction::write_read(0x1E, vec![0x09], vec![0x02]));
    /// let mut compass = Hmc5883l::new(Mock::new(&expectations), Config::default())?;
    /// let s = compass.status()?;
    /// assert!(s.locked && !s.ready);
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn status(&mut self) -> Result<Status, Error<I2C::Error>> {
        let mut b = [0u8];
        self.i2c
            .write_read(ADDRESS, &[REG_STATUS], &mut b)
            .map_err(Error::Comm)?;
        Ok(Status {
            ready: b[0] & STATUS_RDY != 0,
            locked: b[0] & STATUS_LOCK != 0,
        })
    }

    /// Reads one sample: status first; `NotReady` without RDY; otherwise the six
    /// data bytes X, Z, Y; `Overflow` if any axis reads −4096.
    ///
    /// ```
    /// use drivers::compass::hmc5883l::{Config, Error, Hmc5883l, RawField};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // HMC5883L datasheet, Table 2: address 0x1E; identification 0Ah..0Ch
    /// // reads "H43"; configuration A 00h ← 0x70 (8 samples, 15 Hz, normal),
    /// // B 01h ← 0x20 (±1.3 Ga), mode 02h ← 0x00 (continuous): the default
    /// // Config.
    /// let init = [
    ///     Transaction::write_read(0x1E, vec![0x0A], vec![0x48, 0x34, 0x33]),
    ///     Transaction::write(0x1E, vec![0x00, 0x70]),
    ///     Transaction::write(0x1E, vec![0x01, 0x20]),
    ///     Transaction::write(0x1E, vec![0x02, 0x00]),
    /// ];
    /// // Status 09h: 0x00 (not ready), then 0x01 with data 03h..08h = X, Z, Y
    /// // MSB first, then a Z of −4096 (0xF000), the datasheet's overflow value.
    /// let mut expectations = init.to_vec();
    /// expectations.extend([
    ///     Transaction::write_read(0x1E, vec![0x09], vec![0x00]),
    ///     Transaction::write_read(0x1E, vec![0x09], vec![0x01]),
    ///     Transaction::write_read(0x1E, vec![0x03], vec![0x00, 0x64, 0xFF, 0x38, 0x01, 0x2C]),
    ///     Transaction::write_read(0x1E, vec![0x09], vec![0x01]),
    ///     Transaction::write_read(0x1E, vec![0x03], vec![0x00, 0x64, 0xF0, 0x00, 0x01, 0x2C]),
    /// ]);
    /// let mut compass = Hmc5883l::new(Mock::new(&expectations), Config::default())?;
    /// assert_eq!(compass.read_raw(), Err(Error::NotReady));
    /// assert_eq!(compass.read_raw()?, RawField { x: 100, y: 300, z: -200 });
    /// assert_eq!(compass.read_raw(), Err(Error::Overflow));
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn read_raw(&mut self) -> Result<RawField, Error<I2C::Error>> {
        if !self.status()?.ready {
            return Err(Error::NotReady);
        }
        let mut b = [0u8; 6];
        self.i2c
            .write_read(ADDRESS, &[REG_DATA_X_MSB], &mut b)
            .map_err(Error::Comm)?;
        let raw = RawField {
            x: i16::from_be_bytes([b[0], b[1]]),
            z: i16::from_be_bytes([b[2], b[3]]),
            y: i16::from_be_bytes([b[4], b[5]]),
        };
        if raw.x == OVERFLOW_VALUE || raw.y == OVERFLOW_VALUE || raw.z == OVERFLOW_VALUE {
            return Err(Error::Overflow);
        }
        Ok(raw)
    }

    /// Idle mode (MD = 11): lowest supply current.
    ///
    /// ```
    /// use drivers::compass::hmc5883l::{Config, Hmc5883l};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // HMC5883L datasheet, Table 2: address 0x1E; identification 0Ah..0Ch
    /// // reads "H43"; configuration A 00h ← 0x70 (8 samples, 15 Hz, normal),
    /// // B 01h ← 0x20 (±1.3 Ga), mode 02h ← 0x00 (continuous): the default
    /// // Config.
    /// let init = [
    ///     Transaction::write_read(0x1E, vec![0x0A], vec![0x48, 0x34, 0x33]),
    ///     Transaction::write(0x1E, vec![0x00, 0x70]),
    ///     Transaction::write(0x1E, vec![0x01, 0x20]),
    ///     Transaction::write(0x1E, vec![0x02, 0x00]),
    /// ];
    /// // Mode register 02h ← 0x03 (MD = 11, idle).
    /// let mut expectations = init.to_vec();
    /// expectations.push(Transaction::write(0x1E, vec![0x02, 0x03]));
    /// let mut compass = Hmc5883l::new(Mock::new(&expectations), Config::default())?;
    /// compass.idle()?;
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn idle(&mut self) -> Result<(), Error<I2C::Error>> {
        self.write_register(REG_MODE, MODE_IDLE)
    }

    fn write_register(&mut self, reg: u8, value: u8) -> Result<(), Error<I2C::Error>> {
        self.i2c.write(ADDRESS, &[reg, value]).map_err(Error::Comm)
    }
}

impl<I2C: I2c> Magnetometer for Hmc5883l<I2C> {
    type Error = Error<I2C::Error>;

    /// [`Hmc5883l::read_raw`] divided by the gain's sensitivity (datasheet
    /// Table 9, e.g. 1090 LSB/Ga at ±1.3 Ga).
    ///
    /// ```
    /// use drivers::compass::hmc5883l::{Averaging, Config, DataRate, Gain, Hmc5883l};
    /// use drivers::compass::{Magnetometer, Vector3};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // HMC5883L datasheet: ±4.0 Ga is GN = 100 (CRB 0x80), 440 LSB/Ga; a
    /// // Y of 220 (0x00DC) is 0.5 Ga.
    /// let config = Config { averaging: Averaging::X8, rate: DataRate::Hz15, gain: Gain::Ga4_0 };
    /// let expectations = [
    ///     Transaction::write_read(0x1E, vec![0x0A], vec![0x48, 0x34, 0x33]),
    ///     Transaction::write(0x1E, vec![0x00, 0x70]),
    ///     Transaction::write(0x1E, vec![0x01, 0x80]),
    ///     Transaction::write(0x1E, vec![0x02, 0x00]),
    ///     Transaction::write_read(0x1E, vec![0x09], vec![0x01]),
    ///     Transaction::write_read(0x1E, vec![0x03], vec![0x00, 0x00, 0x00, 0x00, 0x00, 0xDC]),
    /// ];
    /// let mut compass = Hmc5883l::new(Mock::new(&expectations), config)?;
    /// assert_eq!(compass.read_gauss()?, Vector3::new(0.0, 0.5, 0.0));
    /// compass.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn read_gauss(&mut self) -> Result<Vector3, Self::Error> {
        let raw = self.read_raw()?;
        let k = self.config.gain.lsb_per_gauss();
        Ok(Vector3::new(
            f32::from(raw.x) / k,
            f32::from(raw.y) / k,
            f32::from(raw.z) / k,
        ))
    }

    /// `true` for [`Error::NotReady`] (RDY clear) only.
    ///
    /// ```
    /// use drivers::compass::hmc5883l::{Error, Hmc5883l};
    /// use drivers::compass::Magnetometer;
    /// use embedded_hal::i2c::ErrorKind;
    /// use embedded_hal_mock::eh1::i2c::Mock;
    ///
    /// assert!(Hmc5883l::<Mock>::is_not_ready(&Error::NotReady));
    /// assert!(!Hmc5883l::<Mock>::is_not_ready(&Error::WrongChip(*b"H44")));
    /// ```
    fn is_not_ready(error: &Self::Error) -> bool {
        matches!(error, Error::NotReady)
    }
}
