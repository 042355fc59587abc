//! Modbus RTU master for function 0x03 (read holding registers) over an
//! RS-485 half-duplex transceiver.
//!
//! Framing (Modbus over Serial Line V1.02 and Modbus Application Protocol
//! V1.1b3): request `addr, 0x03, start_hi, start_lo, count_hi, count_lo,
//! crc_lo, crc_hi`; normal response `addr, 0x03, byte_count, data (big
//! endian registers)..., crc_lo, crc_hi`; exception response
//! `addr, 0x83, code, crc_lo, crc_hi`. The CRC is CRC-16/MODBUS (reflected
//! polynomial 0xA001, initial value 0xFFFF), sent low byte first.
//!
//! Timeout: byte level, by a polling budget on the caller's `DelayNs`:
//! before each `read`, `read_ready()` is polled every `poll_us` until a byte
//! is there or `timeout_us` have been spent waiting for that byte. This needs
//! `embedded_io::ReadReady` from the serial port (HALs implement it for their
//! UARTs); the budget counts only the delays, so it is a lower bound on the
//! wall-clock time.
//!
//! Direction: the transceiver's DE (and /RE) pin is driven high, the request
//! is written and `flush`ed (which must wait until the last stop bit has left
//! the UART, as `embedded_io::Write::flush` is documented to), then DE goes
//! low to listen.

use embedded_hal::delay::DelayNs;
use embedded_hal::digital::OutputPin;
use embedded_io::{Read, ReadReady, Write};

/// Function code: read holding registers.
const FN_READ_HOLDING: u8 = 0x03;
/// Set in the function code of an exception response.
const EXCEPTION_BIT: u8 = 0x80;
/// Largest register count this master reads at once (its receive buffer).
///
/// ```
/// # mod serial { include!("../doc_support/serial.rs"); }
/// # use serial::ScriptedSerial;
/// use drivers::tilt::modbus::{Error, ModbusMaster, Timeout, MAX_REGISTERS};
/// use embedded_hal_mock::eh1::delay::NoopDelay;
/// use embedded_hal_mock::eh1::digital::Mock as Pin;
///
/// // Refused before anything is sent: no DE change, no bytes written.
/// let mut bus = ModbusMaster::new(ScriptedSerial::new(&[], 64), Pin::new(&[]), NoopDelay::new(), Timeout::default());
/// let mut regs = [0u16; MAX_REGISTERS + 1];
/// assert_eq!(bus.read_holding_registers(0x11, 0, &mut regs), Err(Error::BadRequest));
/// let (serial, mut de, _) = bus.destroy();
/// assert!(serial.written().is_empty());
/// de.done();
/// ```
pub const MAX_REGISTERS: usize = 16;
/// Response header (address, function, byte count) plus CRC.
const RESPONSE_OVERHEAD: usize = 5;
const MAX_RESPONSE: usize = RESPONSE_OVERHEAD + 2 * MAX_REGISTERS;
/// Exception response length.
const EXCEPTION_LEN: usize = 5;

/// CRC-16/MODBUS of `data` (check value 0x4B37 for `b"123456789"`).
///
/// ```
/// use drivers::tilt::modbus::crc16_modbus;
///
/// // The check value of the CRC catalogue's CRC-16/MODBUS.
/// assert_eq!(crc16_modbus(b"123456789"), 0x4B37);
/// // Modbus Application Protocol example request 11 03 00 6B 00 03: the
/// // CRC is sent low byte first as 76 87.
/// assert_eq!(crc16_modbus(&[0x11, 0x03, 0x00, 0x6B, 0x00, 0x03]).to_le_bytes(), [0x76, 0x87]);
/// ```
pub fn crc16_modbus(data: &[u8]) -> u16 {
    data.iter().fold(0xFFFF, |crc, &b| {
        (0..8).fold(crc ^ u16::from(b), |c, _| {
            if c & 1 != 0 {
                (c >> 1) ^ 0xA001
            } else {
                c >> 1
            }
        })
    })
}

/// The 8-byte request to read `count` holding registers from `start`.
///
/// ```
/// use drivers::tilt::modbus::read_holding_request;
///
/// // Modbus Application Protocol V1.1b3, section 6.3: read registers 108..=110
/// // (start 0x006B, count 3) from device 0x11; CRC 76 87.
/// assert_eq!(
///     read_holding_request(0x11, 0x006B, 3),
///     [0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87]
/// );
/// ```
pub fn read_holding_request(address: u8, start: u16, count: u16) -> [u8; 8] {
    let [s_hi, s_lo] = start.to_be_bytes();
    let [c_hi, c_lo] = count.to_be_bytes();
    let body = [address, FN_READ_HOLDING, s_hi, s_lo, c_hi, c_lo];
    let [crc_lo, crc_hi] = crc16_modbus(&body).to_le_bytes();
    [
        address,
        FN_READ_HOLDING,
        s_hi,
        s_lo,
        c_hi,
        c_lo,
        crc_lo,
        crc_hi,
    ]
}

/// A Modbus exception code returned by the device.
///
/// ```
/// use drivers::tilt::modbus::Exception;
///
/// // Modbus Application Protocol V1.1b3, section 7: exception codes.
/// assert_eq!(Exception::from(0x02), Exception::IllegalDataAddress);
/// assert_eq!(Exception::from(0x0B), Exception::Other(0x0B));
/// assert_eq!(Exception::IllegalDataAddress.to_string(), "illegal data address (0x02)");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Exception {
    /// 0x01.
    IllegalFunction,
    /// 0x02.
    IllegalDataAddress,
    /// 0x03.
    IllegalDataValue,
    /// 0x04.
    ServerDeviceFailure,
    /// 0x05.
    Acknowledge,
    /// 0x06.
    ServerDeviceBusy,
    /// Any other code.
    Other(u8),
}

impl Exception {
    /// The exception code as sent by the device.
    ///
    /// ```
    /// use drivers::tilt::modbus::Exception;
    ///
    /// assert_eq!(Exception::ServerDeviceBusy.code(), 0x06);
    /// assert_eq!(Exception::Other(0x0A).code(), 0x0A);
    /// for code in 0..=u8::MAX {
    ///     assert_eq!(Exception::from(code).code(), code);
    /// }
    /// ```
    pub fn code(self) -> u8 {
        match self {
            Exception::IllegalFunction => 0x01,
            Exception::IllegalDataAddress => 0x02,
            Exception::IllegalDataValue => 0x03,
            Exception::ServerDeviceFailure => 0x04,
            Exception::Acknowledge => 0x05,
            Exception::ServerDeviceBusy => 0x06,
            Exception::Other(c) => c,
        }
    }
}

/// The name the Modbus Application Protocol gives the code, and the code.
impl core::fmt::Display for Exception {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let name = match self {
            Exception::IllegalFunction => "illegal function",
            Exception::IllegalDataAddress => "illegal data address",
            Exception::IllegalDataValue => "illegal data value",
            Exception::ServerDeviceFailure => "server device failure",
            Exception::Acknowledge => "acknowledge",
            Exception::ServerDeviceBusy => "server device busy",
            Exception::Other(_) => "exception",
        };
        write!(f, "{name} ({:#04x})", self.code())
    }
}

impl core::error::Error for Exception {}

impl From<u8> for Exception {
    fn from(code: u8) -> Self {
        match code {
            0x01 => Exception::IllegalFunction,
            0x02 => Exception::IllegalDataAddress,
            0x03 => Exception::IllegalDataValue,
            0x04 => Exception::ServerDeviceFailure,
            0x05 => Exception::Acknowledge,
            0x06 => Exception::ServerDeviceBusy,
            c => Exception::Other(c),
        }
    }
}

/// Modbus errors. `E` is the serial port's error, `P` the DE pin's.
///
/// ```
/// # mod serial { include!("../doc_support/serial.rs"); }
/// # use serial::ScriptedSerial;
/// use drivers::tilt::modbus::{Error, ModbusMaster, Timeout};
/// use embedded_hal_mock::eh1::delay::NoopDelay;
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
///
/// // The Modbus spec's example response (11 03 06 02 2B 00 00 00 64, CRC
/// // C8 BA by crcmod) with the last CRC byte damaged.
/// let rx = [0x11, 0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64, 0xC8, 0xBB];
/// let mut de = Pin::new(&[T::set(State::High), T::set(State::Low)]);
/// let mut bus = ModbusMaster::new(ScriptedSerial::new(&rx, 64), de.clone(), NoopDelay::new(), Timeout::default());
/// let mut regs = [0u16; 3];
/// let e = bus.read_holding_registers(0x11, 0x006B, &mut regs).unwrap_err();
/// assert_eq!(e, Error::Crc);
/// assert_eq!(e.to_string(), "Modbus response CRC is wrong");
/// de.done();
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error<E, P> {
    /// Serial port error.
    Comm(E),
    /// Direction-enable pin error.
    Pin(P),
    /// No byte arrived within the timeout.
    Timeout,
    /// The serial port accepted no bytes (`write` returned 0).
    WriteZero,
    /// The response CRC is wrong.
    Crc,
    /// The device answered with an exception.
    Exception(Exception),
    /// Another address, function or byte count than asked for.
    UnexpectedResponse,
    /// More than [`MAX_REGISTERS`] (or zero) registers requested.
    BadRequest,
}

impl<E: core::fmt::Debug, P: core::fmt::Debug> core::fmt::Display for Error<E, P> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Comm(e) => write!(f, "Modbus serial port error: {e:?}"),
            Error::Pin(p) => write!(f, "Modbus direction-enable pin error: {p:?}"),
            Error::Timeout => f.write_str("Modbus response timed out"),
            Error::WriteZero => f.write_str("serial port accepted no bytes"),
            Error::Crc => f.write_str("Modbus response CRC is wrong"),
            Error::Exception(x) => write!(f, "Modbus exception from the device: {x:?}"),
            Error::UnexpectedResponse => {
                f.write_str("unexpected address, function or byte count in the Modbus response")
            }
            Error::BadRequest => write!(f, "register count zero or above {MAX_REGISTERS}"),
        }
    }
}

impl<E: core::fmt::Debug, P: core::fmt::Debug> core::error::Error for Error<E, P> {}

/// Timeout settings, in microseconds of the delay provider.
///
/// ```
/// # mod serial { include!("../doc_support/serial.rs"); }
/// # use serial::ScriptedSerial;
/// use drivers::tilt::modbus::{Error, ModbusMaster, Timeout};
/// use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
///
/// // A silent device: the port is polled every 100 µs until 300 µs have
/// // been spent waiting for the first byte, exactly three delays.
/// let timeout = Timeout { timeout_us: 300, poll_us: 100 };
/// let mut delay = CheckedDelay::new(&[D::delay_us(100), D::delay_us(100), D::delay_us(100)]);
/// let mut de = Pin::new(&[T::set(State::High), T::set(State::Low)]);
/// let mut bus = ModbusMaster::new(ScriptedSerial::new(&[], 64), de.clone(), delay.clone(), timeout);
/// let mut regs = [0u16; 1];
/// assert_eq!(bus.read_holding_registers(0x11, 0, &mut regs), Err(Error::Timeout));
/// delay.done();
/// de.done();
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Timeout {
    /// Longest wait for any one byte of the response (the first one includes
    /// the device's processing time).
    pub timeout_us: u32,
    /// Polling interval.
    pub poll_us: u32,
}

impl Default for Timeout {
    /// 100 ms per byte, polled every 100 µs.
    fn default() -> Self {
        Self {
            timeout_us: 100_000,
            poll_us: 100,
        }
    }
}

/// A Modbus RTU master on an RS-485 port.
///
/// ```
/// # mod serial { include!("../doc_support/serial.rs"); }
/// # use serial::ScriptedSerial;
/// use drivers::tilt::modbus::{ModbusMaster, Timeout};
/// use embedded_hal_mock::eh1::delay::NoopDelay;
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
///
/// // Modbus Application Protocol V1.1b3, section 6.3: device 0x11, read
/// // registers 108..=110 (start 0x006B, count 3); response 11 03 06 and
/// // the values 0x022B (555), 0x0000, 0x0064 (100); CRCs 76 87 and C8 BA
/// // (the latter by Python's crcmod, "modbus").
/// let response = [0x11, 0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64, 0xC8, 0xBA];
/// // `ScriptedSerial` (hidden here: src/doc_support/serial.rs) replays the
/// // response and records the request; the DE pin goes high to send and
/// // low to listen.
/// let mut de = Pin::new(&[T::set(State::High), T::set(State::Low)]);
/// let serial = ScriptedSerial::new(&response, 4);
/// let mut bus = ModbusMaster::new(serial, de.clone(), NoopDelay::new(), Timeout::default());
/// let mut regs = [0u16; 3];
/// bus.read_holding_registers(0x11, 0x006B, &mut regs)?;
/// assert_eq!(regs, [555, 0, 100]);
/// let (serial, _, _) = bus.destroy();
/// assert_eq!(serial.written(), [0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87]);
/// assert_eq!(serial.flushes(), 1); // the request left the UART before DE went low
/// de.done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct ModbusMaster<S, DE, D> {
    serial: S,
    de: DE,
    delay: D,
    timeout: Timeout,
}

impl<S, DE, D> ModbusMaster<S, DE, D>
where
    S: Read + Write + ReadReady,
    DE: OutputPin,
    D: DelayNs,
{
    /// A master on `serial`, with `de` as the transceiver's driver enable.
    ///
    /// ```
    /// # mod serial { include!("../doc_support/serial.rs"); }
    /// # use serial::ScriptedSerial;
    /// use drivers::tilt::modbus::{ModbusMaster, Timeout};
    /// use embedded_hal_mock::eh1::delay::NoopDelay;
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// // No bus traffic and no pin change until the first request.
    /// let bus = ModbusMaster::new(ScriptedSerial::new(&[], 64), Pin::new(&[]), NoopDelay::new(), Timeout::default());
    /// let (serial, mut de, _) = bus.destroy();
    /// assert!(serial.written().is_empty());
    /// de.done();
    /// ```
    pub fn new(serial: S, de: DE, delay: D, timeout: Timeout) -> Self {
        Self {
            serial,
            de,
            delay,
            timeout,
        }
    }

    /// Gives the serial port, DE pin and delay back.
    ///
    /// ```
    /// # mod serial { include!("../doc_support/serial.rs"); }
    /// # use serial::ScriptedSerial;
    /// use drivers::tilt::modbus::{ModbusMaster, Timeout};
    /// use embedded_hal_mock::eh1::delay::NoopDelay;
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// // Modbus Application Protocol V1.1b3, section 6.3: device 0x11, read
    /// // registers 108..=110 (start 0x006B, count 3); response 11 03 06 and
    /// // the values 0x022B (555), 0x0000, 0x0064 (100); CRCs 76 87 and C8 BA
    /// // (the latter by Python's crcmod, "modbus").
    /// let response = [0x11, 0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64, 0xC8, 0xBA];
    /// let de = Pin::new(&[T::set(State::High), T::set(State::Low)]);
    /// let mut bus = ModbusMaster::new(ScriptedSerial::new(&response, 64), de, NoopDelay::new(), Timeout::default());
    /// let mut regs = [0u16; 3];
    /// bus.read_holding_registers(0x11, 0x006B, &mut regs)?;
    /// let (serial, mut de, _delay) = bus.destroy();
    /// assert_eq!(serial.remaining(), 0); // the whole response was taken
    /// de.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn destroy(self) -> (S, DE, D) {
        (self.serial, self.de, self.delay)
    }

    /// Reads `out.len()` holding registers from `start` on device `address`.
    ///
    /// ```
    /// # mod serial { include!("../doc_support/serial.rs"); }
    /// # use serial::ScriptedSerial;
    /// use drivers::tilt::modbus::{ModbusMaster, Timeout};
    /// use embedded_hal_mock::eh1::delay::NoopDelay;
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// use drivers::tilt::modbus::{Error, Exception};
    ///
    /// // Modbus Application Protocol V1.1b3, section 6.3: device 0x11, read
    /// // registers 108..=110 (start 0x006B, count 3); response 11 03 06 and
    /// // the values 0x022B (555), 0x0000, 0x0064 (100); CRCs 76 87 and C8 BA
    /// // (the latter by Python's crcmod, "modbus").
    /// let response = [0x11, 0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64, 0xC8, 0xBA];
    /// // Then the exception response 11 83 02 (illegal data address), CRC
    /// // C1 34 (crcmod), to a second request.
    /// let mut rx = response.to_vec();
    /// rx.extend([0x11, 0x83, 0x02, 0xC1, 0x34]);
    /// let de_tx = [T::set(State::High), T::set(State::Low)];
    /// let mut de = Pin::new(&[de_tx.clone(), de_tx].concat());
    /// // One byte per read: the response arrives in pieces.
    /// let mut bus = ModbusMaster::new(ScriptedSerial::new(&rx, 1), de.clone(), NoopDelay::new(), Timeout::default());
    /// let mut regs = [0u16; 3];
    /// bus.read_holding_registers(0x11, 0x006B, &mut regs)?;
    /// assert_eq!(regs, [555, 0, 100]);
    /// assert_eq!(
    ///     bus.read_holding_registers(0x11, 0x006B, &mut regs),
    ///     Err(Error::Exception(Exception::IllegalDataAddress))
    /// );
    /// let (serial, _, _) = bus.destroy();
    /// let request = [0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87];
    /// assert_eq!(serial.written(), [request, request].concat());
    /// de.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn read_holding_registers(
        &mut self,
        address: u8,
        start: u16,
        out: &mut [u16],
    ) -> Result<(), Error<S::Error, DE::Error>> {
        let count = out.len();
        if count == 0 || count > MAX_REGISTERS {
            return Err(Error::BadRequest);
        }
        // count <= MAX_REGISTERS fits in u16.
        let request = read_holding_request(address, start, count as u16);
        self.transmit(&request)?;

        let expected = RESPONSE_OVERHEAD + 2 * count;
        let mut buf = [0u8; MAX_RESPONSE];
        let mut target = expected;
        let mut n = 0;
        while n < target {
            self.wait_for_byte()?;
            let free = buf.get_mut(n..target).ok_or(Error::UnexpectedResponse)?;
            let k = self.serial.read(free).map_err(Error::Comm)?;
            n = n.saturating_add(k).min(target);
            if n >= 2 && buf.get(1) == Some(&(FN_READ_HOLDING | EXCEPTION_BIT)) {
                target = EXCEPTION_LEN;
                n = n.min(target);
            }
        }
        let frame = buf.get(..n).ok_or(Error::UnexpectedResponse)?;
        let data = check_response(frame, address, count)?;
        for (reg, pair) in out.iter_mut().zip(data.chunks_exact(2)) {
            if let [hi, lo] = *pair {
                *reg = u16::from_be_bytes([hi, lo]);
            }
        }
        Ok(())
    }

    fn transmit(&mut self, frame: &[u8]) -> Result<(), Error<S::Error, DE::Error>> {
        self.de.set_high().map_err(Error::Pin)?;
        let sent = self.write_all(frame);
        // Always hand the bus back, but report the first error.
        let released = self.de.set_low().map_err(Error::Pin);
        sent.and(released)
    }

    fn write_all(&mut self, mut frame: &[u8]) -> Result<(), Error<S::Error, DE::Error>> {
        while !frame.is_empty() {
            let n = self.serial.write(frame).map_err(Error::Comm)?;
            if n == 0 {
                return Err(Error::WriteZero);
            }
            frame = frame.get(n..).unwrap_or(&[]);
        }
        self.serial.flush().map_err(Error::Comm)
    }

    fn wait_for_byte(&mut self) -> Result<(), Error<S::Error, DE::Error>> {
        let mut waited_us: u32 = 0;
        while !self.serial.read_ready().map_err(Error::Comm)? {
            if waited_us >= self.timeout.timeout_us {
                return Err(Error::Timeout);
            }
            self.delay.delay_us(self.timeout.poll_us);
            waited_us = waited_us.saturating_add(self.timeout.poll_us.max(1));
        }
        Ok(())
    }
}

/// Checks a complete response frame; returns the register data bytes.
fn check_response<E, P>(frame: &[u8], address: u8, count: usize) -> Result<&[u8], Error<E, P>> {
    let split = frame
        .len()
        .checked_sub(2)
        .ok_or(Error::UnexpectedResponse)?;
    let (body, crc) = frame.split_at(split);
    let received = match crc {
        [lo, hi] => u16::from_le_bytes([*lo, *hi]),
        _ => return Err(Error::UnexpectedResponse),
    };
    if crc16_modbus(body) != received {
        return Err(Error::Crc);
    }
    match body {
        [a, ..] if *a != address => Err(Error::UnexpectedResponse),
        [_, f, code] if *f == FN_READ_HOLDING | EXCEPTION_BIT => {
            Err(Error::Exception(Exception::from(*code)))
        }
        [_, FN_READ_HOLDING, byte_count, data @ ..]
            if usize::from(*byte_count) == 2 * count && data.len() == 2 * count =>
        {
            Ok(data)
        }
        _ => Err(Error::UnexpectedResponse),
    }
}
