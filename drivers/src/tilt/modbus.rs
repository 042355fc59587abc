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
pub const MAX_REGISTERS: usize = 16;
/// Response header (address, function, byte count) plus CRC.
const RESPONSE_OVERHEAD: usize = 5;
const MAX_RESPONSE: usize = RESPONSE_OVERHEAD + 2 * MAX_REGISTERS;
/// Exception response length.
const EXCEPTION_LEN: usize = 5;

/// CRC-16/MODBUS of `data` (check value 0x4B37 for `b"123456789"`).
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
    pub fn new(serial: S, de: DE, delay: D, timeout: Timeout) -> Self {
        Self {
            serial,
            de,
            delay,
            timeout,
        }
    }

    /// Gives the serial port, DE pin and delay back.
    pub fn destroy(self) -> (S, DE, D) {
        (self.serial, self.de, self.delay)
    }

    /// Reads `out.len()` holding registers from `start` on device `address`.
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
