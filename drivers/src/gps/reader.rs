//! Bytes to fixes: [`GpsDecoder`] (no I/O, feed it bytes from anywhere, e.g.
//! a UART interrupt's ring buffer) and [`GpsReader`], which pulls the bytes
//! from an `embedded_io::Read` serial port.

use embedded_io::{ErrorKind, Read, ReadReady};

use super::assembler::{AssemblerStats, SentenceAssembler};
use super::fix::{FixFusion, GpsFix};
use super::parse::parse_sentence;

/// Size of the reader's receive chunk.
const READ_CHUNK: usize = 32;

/// Counters of the whole pipeline, as printed by the `gps_log` example.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GpsStats {
    /// Lines seen (accepted + rejected).
    pub sentences: u32,
    /// Checksum correct and, for GGA/RMC, read by `parse_sentence`.
    pub accepted: u32,
    /// Checksum wrong.
    pub rejected_checksum: u32,
    /// Any other rejection (framing, overflow, non-ASCII, a GGA/RMC that is
    /// unparseable or has impossible content).
    pub rejected_other: u32,
    /// The part of `rejected_other` that framed well but failed to parse or
    /// had impossible content.
    pub parse_errors: u32,
    /// The assembler's detailed counters.
    pub framing: AssemblerStats,
}

/// Sentence assembly, parsing and fusion, fed one byte at a time.
#[derive(Debug, Clone)]
pub struct GpsDecoder {
    assembler: SentenceAssembler,
    fusion: FixFusion,
    parse_errors: u32,
}

impl GpsDecoder {
    /// A decoder whose fix goes stale `stale_after_ms` after the last epoch.
    pub const fn new(stale_after_ms: u64) -> Self {
        Self {
            assembler: SentenceAssembler::new(),
            fusion: FixFusion::new(stale_after_ms),
            parse_errors: 0,
        }
    }

    /// Feeds one byte received at `now_ms`; returns a fix when an epoch completes.
    pub fn push(&mut self, byte: u8, now_ms: u64) -> Option<GpsFix> {
        let sentence = match self.assembler.push(byte)? {
            Ok(text) => parse_sentence(text),
            Err(_) => return None,
        };
        match sentence {
            Ok(s) => self.fusion.update(&s, now_ms),
            Err(_) => {
                self.parse_errors = self.parse_errors.saturating_add(1);
                None
            }
        }
    }

    /// End of input: counts an unterminated line and gives out the last epoch.
    pub fn finish(&mut self) -> Option<GpsFix> {
        self.assembler.finish_stream();
        self.fusion.flush()
    }

    /// The latest fix, or [`GpsFix::NONE`] once stale.
    pub fn current(&self, now_ms: u64) -> GpsFix {
        self.fusion.current(now_ms)
    }

    /// Whether the fix is stale at `now_ms`.
    pub fn is_stale(&self, now_ms: u64) -> bool {
        self.fusion.is_stale(now_ms)
    }

    /// Counters so far.
    pub fn stats(&self) -> GpsStats {
        let framing = self.assembler.stats();
        GpsStats {
            sentences: framing.sentences(),
            accepted: framing.accepted.saturating_sub(self.parse_errors),
            rejected_checksum: framing.bad_checksum,
            rejected_other: framing.rejected_other().saturating_add(self.parse_errors),
            parse_errors: self.parse_errors,
            framing,
        }
    }
}

/// GPS reader errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Error<E> {
    /// The serial port failed.
    Comm(E),
    /// The serial port reported end of stream (`read` returned 0).
    EndOfStream,
}

impl<E: core::fmt::Debug> core::fmt::Display for Error<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Comm(e) => write!(f, "GPS serial port error: {e:?}"),
            Error::EndOfStream => f.write_str("GPS serial port reported end of stream"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for Error<E> {}

impl<E: embedded_io::Error> Error<E> {
    /// The `embedded-io` kind of a communication error.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Error::Comm(e) => e.kind(),
            Error::EndOfStream => ErrorKind::Other,
        }
    }
}

/// A GPS receiver on an `embedded_io::Read` serial port.
///
/// Why `embedded-io`: a GPS (and an RS-485 Modbus sensor) is a blocking byte
/// stream, which is exactly what `embedded_io::Read`/`Write` describe; HALs
/// implement them for their UARTs, `std` types implement them on the host, and
/// a mock is a few lines of code.
#[derive(Debug)]
pub struct GpsReader<R> {
    serial: R,
    decoder: GpsDecoder,
    buf: [u8; READ_CHUNK],
    start: usize,
    end: usize,
}

impl<R: Read> GpsReader<R> {
    /// A reader over `serial`; the fix goes stale `stale_after_ms` after the last epoch.
    pub fn new(serial: R, stale_after_ms: u64) -> Self {
        Self {
            serial,
            decoder: GpsDecoder::new(stale_after_ms),
            buf: [0; READ_CHUNK],
            start: 0,
            end: 0,
        }
    }

    /// Gives the serial port back.
    pub fn destroy(self) -> R {
        self.serial
    }

    /// Processes bytes until a fix completes. Calls `read` at most once
    /// (so it blocks at most as long as one `read` does); `Ok(None)` when the
    /// bytes read so far did not complete an epoch. At end of stream the last
    /// epoch is returned once, then [`Error::EndOfStream`].
    pub fn poll(&mut self, now_ms: u64) -> Result<Option<GpsFix>, Error<R::Error>> {
        if let Some(fix) = self.drain(now_ms) {
            return Ok(Some(fix));
        }
        let n = self.serial.read(&mut self.buf).map_err(Error::Comm)?;
        if n == 0 {
            return match self.decoder.finish() {
                Some(fix) => Ok(Some(fix)),
                None => Err(Error::EndOfStream),
            };
        }
        self.start = 0;
        self.end = n.min(READ_CHUNK);
        Ok(self.drain(now_ms))
    }

    /// Like [`GpsReader::poll`], but never blocks: when no byte is buffered
    /// and the port has none ready, returns `Ok(None)` without reading. For a
    /// main loop that also drives the motors.
    pub fn poll_if_ready(&mut self, now_ms: u64) -> Result<Option<GpsFix>, Error<R::Error>>
    where
        R: ReadReady,
    {
        if let Some(fix) = self.drain(now_ms) {
            return Ok(Some(fix));
        }
        if self.serial.read_ready().map_err(Error::Comm)? {
            self.poll(now_ms)
        } else {
            Ok(None)
        }
    }

    /// True when a byte is waiting: read but not yet decoded, or ready at
    /// the port. A main loop polls while this holds and stops when the port
    /// is drained, instead of calling [`GpsReader::poll_if_ready`] a fixed
    /// number of times.
    pub fn has_input(&mut self) -> Result<bool, Error<R::Error>>
    where
        R: ReadReady,
    {
        if self.start < self.end {
            return Ok(true);
        }
        self.serial.read_ready().map_err(Error::Comm)
    }

    fn drain(&mut self, now_ms: u64) -> Option<GpsFix> {
        while self.start < self.end {
            let byte = *self.buf.get(self.start)?;
            self.start += 1;
            if let Some(fix) = self.decoder.push(byte, now_ms) {
                return Some(fix);
            }
        }
        None
    }

    /// The latest fix, or [`GpsFix::NONE`] once stale.
    pub fn current(&self, now_ms: u64) -> GpsFix {
        self.decoder.current(now_ms)
    }

    /// Counters so far.
    pub fn stats(&self) -> GpsStats {
        self.decoder.stats()
    }
}
