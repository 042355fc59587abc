//! A Modbus RTU client (master) of Read Holding Registers (function code
//! 03) on a serial line, for `monitor --modbus`.
//!
//! Modbus over Serial Line Specification and Implementation Guide V1.02
//! (modbus.org, 2006): the RTU frame is the server address, the PDU and the
//! CRC-16 low byte first (§2.5.1; the CRC is the `suntracker-modbus`
//! crate's, §6.2.2), and frames are kept apart by a silence of at least 3.5
//! characters (§2.5.1.1: 1,750 µs above 19,200 baud). Modbus Application
//! Protocol Specification V1.1b3 (modbus.org, 2012): the 03 request
//! (start, quantity 1 to 125) and its reply (byte count, registers high
//! byte first) (§6.3), and the exception reply (function code + 0x80, one
//! exception code) with the codes' names (§7).
//!
//! The reply is framed by its length, which its first bytes give (an
//! exception reply is 5 bytes, a 03 reply 5 + its byte count), within the
//! reply time-out: a request is written, then bytes are read until the
//! reply is whole or the time runs out. A reply that is not whole in time is
//! a [`Error::Timeout`], one whose CRC is wrong a [`Error::Crc`], an
//! exception reply an [`Error::Exception`]; after any of them the bytes
//! still on the line are dropped before the next request, so that a late
//! reply is not read as the next one's.

use std::fmt;
use std::io::{ErrorKind, Read, Write};
use std::time::{Duration, Instant};

use suntracker_modbus::crc::crc16;
use suntracker_modbus::pdu::{FC_READ_HOLDING, MAX_READ_REGISTERS};
use suntracker_modbus::rtu::{RtuTiming, MAX_FRAME_BYTES};

/// The name of Modbus exception code `code` (Application Protocol V1.1b3,
/// §7), or `None` for a code the specification does not define.
pub fn exception_name(code: u8) -> Option<&'static str> {
    Some(match code {
        0x01 => "illegal function",
        0x02 => "illegal data address",
        0x03 => "illegal data value",
        0x04 => "server device failure",
        0x05 => "acknowledge",
        0x06 => "server device busy",
        0x08 => "memory parity error",
        0x0A => "gateway path unavailable",
        0x0B => "gateway target device failed to respond",
        _ => return None,
    })
}

/// Why a request got no usable reply.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Error {
    /// No whole reply within the reply time-out; `got` bytes of one came.
    Timeout { got: usize },
    /// The reply's CRC does not match its bytes.
    Crc { received: u16, computed: u16 },
    /// The server answered the request with an exception.
    Exception { function: u8, code: u8 },
    /// A whole reply with a good CRC that does not answer the request
    /// (another address or function code, a wrong byte count).
    Unexpected(String),
    /// The port failed.
    Io(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Timeout { got: 0 } => write!(f, "time-out: no reply"),
            Error::Timeout { got } => write!(f, "time-out: {got} bytes of a reply, not all"),
            Error::Crc { received, computed } => write!(
                f,
                "CRC error: the reply carries {received:04X}, its bytes give {computed:04X}"
            ),
            Error::Exception { function, code } => write!(
                f,
                "exception {code:02X} ({}) to function {function:02X}",
                exception_name(*code).unwrap_or("not a code of the specification")
            ),
            Error::Unexpected(what) => write!(f, "unexpected reply: {what}"),
            Error::Io(e) => write!(f, "port: {e}"),
        }
    }
}

/// The RTU frame of a read of `count` holding registers from `start` at
/// server `address`, its CRC appended.
pub fn read_request(address: u8, start: u16, count: u16) -> [u8; 8] {
    let [sh, sl] = start.to_be_bytes();
    let [ch, cl] = count.to_be_bytes();
    let body = [address, FC_READ_HOLDING, sh, sl, ch, cl];
    let [lo, hi] = crc16(&body).to_le_bytes();
    [address, FC_READ_HOLDING, sh, sl, ch, cl, lo, hi]
}

/// How long the whole reply is, from its first bytes; `None` until they
/// have come.
fn reply_len(bytes: &[u8]) -> Option<usize> {
    match bytes {
        [_, function, ..] if function & 0x80 != 0 => Some(5),
        [_, _, byte_count, ..] => Some(5 + usize::from(*byte_count)),
        _ => None,
    }
}

/// The registers of a whole reply `frame` (CRC included) to a read of
/// `count` registers at `address`.
pub fn parse_read_reply(frame: &[u8], address: u8, count: u16) -> Result<Vec<u16>, Error> {
    let Some((body, crc)) = frame.split_last_chunk::<2>() else {
        return Err(Error::Timeout { got: frame.len() });
    };
    let received = u16::from_le_bytes(*crc);
    let computed = crc16(body);
    if received != computed {
        return Err(Error::Crc { received, computed });
    }
    match body {
        [a, ..] if *a != address => Err(Error::Unexpected(format!(
            "from address {a}, not {address}"
        ))),
        [_, f, code] if *f == FC_READ_HOLDING | 0x80 => Err(Error::Exception {
            function: FC_READ_HOLDING,
            code: *code,
        }),
        [_, f, n, data @ ..] if *f == FC_READ_HOLDING => {
            if usize::from(*n) != data.len() || data.len() != usize::from(count) * 2 {
                return Err(Error::Unexpected(format!(
                    "{} data bytes for {count} registers",
                    data.len()
                )));
            }
            Ok(data
                .chunks_exact(2)
                .map(|p| u16::from_be_bytes([p[0], p[1]]))
                .collect())
        }
        [_, f, ..] => Err(Error::Unexpected(format!("function code {f:02X}"))),
        _ => Err(Error::Unexpected(format!("{} bytes", body.len()))),
    }
}

/// The client on one serial line.
pub struct Client {
    port: Box<dyn serialport::SerialPort>,
    /// The server's address, 1 to 247.
    pub address: u8,
    /// How long after its request a reply must be whole.
    pub reply_timeout: Duration,
    /// The silence between frames (3.5 characters).
    silence: Duration,
    /// When the line was last busy (a byte sent or read).
    last_busy: Instant,
}

impl Client {
    /// A client of server `address` on `port`, at `baud` (for the silence
    /// between frames).
    pub fn new(
        port: Box<dyn serialport::SerialPort>,
        address: u8,
        baud: u32,
        reply_timeout: Duration,
    ) -> Self {
        let t35_us = RtuTiming::from_baud_us(baud).t35_ticks;
        Self {
            port,
            address,
            reply_timeout,
            silence: Duration::from_micros(u64::from(t35_us)),
            last_busy: Instant::now(),
        }
    }

    /// Reads `count` holding registers (1 to 125) from `start`.
    pub fn read_holding(&mut self, start: u16, count: u16) -> Result<Vec<u16>, Error> {
        if !(1..=MAX_READ_REGISTERS).contains(&count) {
            return Err(Error::Unexpected(format!(
                "a read of {count} registers (1 to {MAX_READ_REGISTERS})"
            )));
        }
        let result = self.exchange(start, count);
        if result.is_err() {
            // A late or broken reply must not be read as the next one's.
            self.discard();
        }
        result
    }

    fn exchange(&mut self, start: u16, count: u16) -> Result<Vec<u16>, Error> {
        let io = |e: std::io::Error| Error::Io(e.to_string());
        // The silence after the last frame on the line.
        let quiet = self.last_busy + self.silence;
        if let Some(wait) = quiet.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        // Bytes nobody asked for (noise, a reply given up on) go first.
        let _ = self.port.clear(serialport::ClearBuffer::Input);
        let request = read_request(self.address, start, count);
        self.port.write_all(&request).map_err(io)?;
        self.port.flush().map_err(io)?;
        self.last_busy = Instant::now();
        let deadline = self.last_busy + self.reply_timeout;
        let mut frame: Vec<u8> = Vec::with_capacity(MAX_FRAME_BYTES);
        let mut chunk = [0_u8; MAX_FRAME_BYTES];
        loop {
            if let Some(len) = reply_len(&frame) {
                if frame.len() >= len {
                    frame.truncate(len);
                    return parse_read_reply(&frame, self.address, count);
                }
            }
            let now = Instant::now();
            if now >= deadline {
                return Err(Error::Timeout { got: frame.len() });
            }
            // Read no more than the reply still needs.
            let want = reply_len(&frame)
                .unwrap_or(3)
                .saturating_sub(frame.len())
                .clamp(1, chunk.len());
            let _ = self.port.set_timeout((deadline - now).min(READ_POLL));
            match self.port.read(&mut chunk[..want]) {
                Ok(0) => return Err(Error::Io("the port closed".into())),
                Ok(n) => {
                    frame.extend_from_slice(&chunk[..n]);
                    self.last_busy = Instant::now();
                }
                Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::WouldBlock) => {}
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) => return Err(io(e)),
            }
        }
    }

    /// Drops what is on the line until it has been silent for 3.5
    /// characters (at least [`READ_POLL`]).
    fn discard(&mut self) {
        let _ = self.port.set_timeout(self.silence.max(READ_POLL));
        let mut chunk = [0_u8; MAX_FRAME_BYTES];
        let end = Instant::now() + DISCARD_MAX;
        while Instant::now() < end {
            match self.port.read(&mut chunk) {
                Ok(n) if n > 0 => self.last_busy = Instant::now(),
                _ => break,
            }
        }
    }
}

/// How long one read of the port waits for bytes.
const READ_POLL: Duration = Duration::from_millis(20);
/// The longest the line is drained after a failed request.
const DISCARD_MAX: Duration = Duration::from_secs(1);

/// Opens `path` for Modbus RTU: 8 data bits, `parity`, one stop bit, two
/// without parity (§2.5.1: 11 bits a character).
pub fn open(
    path: &str,
    baud: u32,
    parity: serialport::Parity,
) -> Result<Box<dyn serialport::SerialPort>, String> {
    let stop = if parity == serialport::Parity::None {
        serialport::StopBits::Two
    } else {
        serialport::StopBits::One
    };
    serialport::new(path, baud)
        .data_bits(serialport::DataBits::Eight)
        .parity(parity)
        .stop_bits(stop)
        .flow_control(serialport::FlowControl::None)
        .timeout(READ_POLL)
        .open()
        .map_err(|e| format!("--modbus {path}: {e}"))
}
