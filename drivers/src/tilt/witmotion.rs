//! WitMotion RS-485 inclinometers (SINDT02-485 class, the sensor named in
//! Li et al. 2022) over Modbus RTU.
//!
//! Register map assumed, from WitMotion's public "WIT standard Modbus
//! protocol" (the same map across their Modbus sensors): device address 0x50
//! by default; angle registers 0x3D Roll (about X), 0x3E Pitch (about Y),
//! 0x3F Yaw, each a signed 16-bit value with angle = raw / 32768 × 180°.
//! Roll and pitch are read together with one function-0x03 request of two
//! registers from 0x3D.

use embedded_hal::delay::DelayNs;
use embedded_hal::digital::OutputPin;
use embedded_io::{Read, ReadReady, Write};

use super::modbus::{Error, ModbusMaster, Timeout};
use super::Inclination;

/// WitMotion factory Modbus address.
///
/// ```
/// use drivers::tilt::modbus::read_holding_request;
/// use drivers::tilt::witmotion::DEFAULT_ADDRESS;
///
/// // The angle request of WitMotion's "WIT standard Modbus protocol":
/// // 50 03 00 3D 00 03 99 86 (roll, pitch and yaw).
/// let request = read_holding_request(DEFAULT_ADDRESS, 0x3D, 3);
/// assert_eq!(request, [0x50, 0x03, 0x00, 0x3D, 0x00, 0x03, 0x99, 0x86]);
/// ```
pub const DEFAULT_ADDRESS: u8 = 0x50;
const REG_ROLL: u16 = 0x3D;
/// Degrees per raw count: 180 / 32768.
const DEG_PER_COUNT: f32 = 180.0 / 32768.0;

/// Raw angle register to degrees.
///
/// ```
/// use drivers::tilt::witmotion::raw_to_deg;
///
/// // WitMotion: angle = raw (signed 16 bit) / 32768 × 180°.
/// assert_eq!(raw_to_deg(0x4000), 90.0);
/// assert_eq!(raw_to_deg(0xC000), -90.0);
/// assert_eq!(raw_to_deg(0x8000), -180.0);
/// ```
pub fn raw_to_deg(raw: u16) -> f32 {
    // The register holds a two's-complement i16.
    f32::from(raw as i16) * DEG_PER_COUNT
}

/// A WitMotion Modbus inclinometer.
///
/// ```
/// # mod serial { include!("../doc_support/serial.rs"); }
/// # use serial::ScriptedSerial;
/// use drivers::tilt::modbus::Timeout;
/// use drivers::tilt::witmotion::{WitInclinometer, DEFAULT_ADDRESS};
/// use embedded_hal_mock::eh1::delay::NoopDelay;
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
///
/// // WitMotion "WIT standard Modbus protocol": device 0x50, roll 0x3D and
/// // pitch 0x3E, angle = raw / 32768 × 180°. Request 50 03 00 3D 00 02 + CRC
/// // 58 46; response 50 03 04, roll 0x0E39 (20.0006°), pitch 0xF8E4
/// // (−9.9976°), CRC 2B 98 (CRCs by Python's crcmod, "modbus").
/// let response = [0x50, 0x03, 0x04, 0x0E, 0x39, 0xF8, 0xE4, 0x2B, 0x98];
/// // `ScriptedSerial` (hidden here: src/doc_support/serial.rs) replays the
/// // response and records the request. DE high to send, low to listen.
/// let mut de = Pin::new(&[T::set(State::High), T::set(State::Low)]);
/// let serial = ScriptedSerial::new(&response, 64);
/// let mut sensor =
///     WitInclinometer::new(serial, de.clone(), NoopDelay::new(), DEFAULT_ADDRESS, Timeout::default());
/// let angles = sensor.read()?;
/// assert!((angles.roll_deg - 20.0006).abs() < 1e-4);
/// assert!((angles.pitch_deg + 9.9976).abs() < 1e-4);
/// let (serial, _, _) = sensor.destroy();
/// assert_eq!(serial.written(), [0x50, 0x03, 0x00, 0x3D, 0x00, 0x02, 0x58, 0x46]);
/// de.done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct WitInclinometer<S, DE, D> {
    bus: ModbusMaster<S, DE, D>,
    address: u8,
}

impl<S, DE, D> WitInclinometer<S, DE, D>
where
    S: Read + Write + ReadReady,
    DE: OutputPin,
    D: DelayNs,
{
    /// The sensor at Modbus `address` (usually [`DEFAULT_ADDRESS`]).
    ///
    /// ```
    /// # mod serial { include!("../doc_support/serial.rs"); }
    /// # use serial::ScriptedSerial;
    /// use drivers::tilt::modbus::Timeout;
    /// use drivers::tilt::witmotion::{WitInclinometer, DEFAULT_ADDRESS};
    /// use embedded_hal_mock::eh1::delay::NoopDelay;
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// // No bus traffic until the first read.
    /// let mut de = Pin::new(&[]);
    /// let sensor = WitInclinometer::new(
    ///     ScriptedSerial::new(&[], 64),
    ///     de.clone(),
    ///     NoopDelay::new(),
    ///     DEFAULT_ADDRESS,
    ///     Timeout::default(),
    /// );
    /// let (serial, _, _) = sensor.destroy();
    /// assert!(serial.written().is_empty());
    /// de.done();
    /// ```
    pub fn new(serial: S, de: DE, delay: D, address: u8, timeout: Timeout) -> Self {
        Self {
            bus: ModbusMaster::new(serial, de, delay, timeout),
            address,
        }
    }

    /// Gives the serial port, DE pin and delay back.
    ///
    /// ```
    /// # mod serial { include!("../doc_support/serial.rs"); }
    /// # use serial::ScriptedSerial;
    /// use drivers::tilt::modbus::Timeout;
    /// use drivers::tilt::witmotion::{WitInclinometer, DEFAULT_ADDRESS};
    /// use embedded_hal_mock::eh1::delay::NoopDelay;
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// let sensor = WitInclinometer::new(
    ///     ScriptedSerial::new(&[], 64),
    ///     Pin::new(&[]),
    ///     NoopDelay::new(),
    ///     DEFAULT_ADDRESS,
    ///     Timeout::default(),
    /// );
    /// let (serial, mut de, _delay) = sensor.destroy();
    /// assert_eq!(serial.flushes(), 0);
    /// de.done();
    /// ```
    pub fn destroy(self) -> (S, DE, D) {
        self.bus.destroy()
    }

    /// Reads roll (about X) and pitch (about Y) in degrees.
    ///
    /// ```
    /// # mod serial { include!("../doc_support/serial.rs"); }
    /// # use serial::ScriptedSerial;
    /// use drivers::tilt::modbus::Timeout;
    /// use drivers::tilt::witmotion::{WitInclinometer, DEFAULT_ADDRESS};
    /// use embedded_hal_mock::eh1::delay::NoopDelay;
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// use drivers::tilt::modbus::{Error, Exception};
    ///
    /// // WitMotion "WIT standard Modbus protocol": device 0x50, roll 0x3D and
    /// // pitch 0x3E, angle = raw / 32768 × 180°. Request 50 03 00 3D 00 02 + CRC
    /// // 58 46; response 50 03 04, roll 0x0E39 (20.0006°), pitch 0xF8E4
    /// // (−9.9976°), CRC 2B 98 (CRCs by Python's crcmod, "modbus").
    /// let response = [0x50, 0x03, 0x04, 0x0E, 0x39, 0xF8, 0xE4, 0x2B, 0x98];
    /// // Then an exception response 50 83 02 (illegal data address), CRC
    /// // 91 20 by crcmod.
    /// let mut rx = response.to_vec();
    /// rx.extend([0x50, 0x83, 0x02, 0x91, 0x20]);
    /// let de_tx = [T::set(State::High), T::set(State::Low)];
    /// let mut de = Pin::new(&[de_tx.clone(), de_tx].concat());
    /// let mut sensor = WitInclinometer::new(
    ///     ScriptedSerial::new(&rx, 64),
    ///     de.clone(),
    ///     NoopDelay::new(),
    ///     DEFAULT_ADDRESS,
    ///     Timeout::default(),
    /// );
    /// assert!((sensor.read()?.roll_deg - 20.0006).abs() < 1e-4);
    /// assert_eq!(sensor.read(), Err(Error::Exception(Exception::IllegalDataAddress)));
    /// de.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn read(&mut self) -> Result<Inclination, Error<S::Error, DE::Error>> {
        let mut regs = [0u16; 2];
        self.bus
            .read_holding_registers(self.address, REG_ROLL, &mut regs)?;
        let [roll, pitch] = regs;
        Ok(Inclination {
            roll_deg: raw_to_deg(roll),
            pitch_deg: raw_to_deg(pitch),
        })
    }
}
