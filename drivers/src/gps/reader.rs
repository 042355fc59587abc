//! Bytes to fixes: [`GpsDecoder`] (no I/O, feed it bytes from anywhere, e.g.
//! a UART interrupt's ring buffer) and [`GpsReader`], which pulls the bytes
//! from an `embedded_io::Read` serial port.
//!
//! The examples feed sentences from u-blox's *NEO-6 Receiver Description
//! including Protocol Specification* (GGA and RMC examples) and sentences of
//! the same form whose checksums were computed independently (Python: XOR of
//! the bytes between `$` and `*`).

use embedded_io::{ErrorKind, Read, ReadReady};

use super::assembler::{AssemblerStats, SentenceAssembler};
use super::fix::{FixFusion, GpsFix};
use super::parse::parse_sentence;
use crate::counter::count_up;

/// Size of the reader's receive chunk.
const READ_CHUNK: usize = 32;

/// Counters of the whole pipeline, as printed by the `gps_log` example.
///
/// ```
/// use drivers::gps::GpsDecoder;
///
/// // The u-blox GGA example with its last checksum digit changed (5B → 5C),
/// // then a line without `$`.
/// let mut gps = GpsDecoder::new(2_000);
/// for &b in b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5C\r\nnoise\r\n" {
///     gps.push(b, 0);
/// }
/// let stats = gps.stats();
/// assert_eq!((stats.sentences, stats.accepted), (2, 0));
/// assert_eq!((stats.rejected_checksum, stats.rejected_other), (1, 1));
/// assert_eq!(stats.framing.missing_start, 1);
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
///
/// ```
/// use drivers::gps::{FixQuality, GpsDecoder};
///
/// // GGA: the example of u-blox's NEO-6 protocol specification; RMC: the
/// // same epoch (checksum 0x54 computed independently in Python as the XOR
/// // of the bytes between `$` and `*`).
/// let nmea: &[u8] = b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n\
/// $GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54\r\n";
/// let mut gps = GpsDecoder::new(2_000);
/// // E.g. from a UART interrupt's ring buffer, with the time of arrival.
/// let fixes: Vec<_> = nmea.iter().filter_map(|&b| gps.push(b, 5_000)).collect();
/// assert_eq!(fixes.len(), 1);
/// assert_eq!(fixes[0].quality, FixQuality::Gps);
/// ```
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GpsDecoder {
    assembler: SentenceAssembler,
    fusion: FixFusion,
    parse_errors: u32,
}

impl GpsDecoder {
    /// A decoder whose fix goes stale `stale_after_ms` after the last epoch.
    ///
    /// ```
    /// use drivers::gps::{GpsDecoder, GpsFix};
    ///
    /// // `const`: it can live in a `static` (behind a critical-section mutex).
    /// const DECODER: GpsDecoder = GpsDecoder::new(2_000);
    /// let mut gps = DECODER;
    /// assert_eq!(gps.current(0), GpsFix::NONE);
    /// assert!(gps.is_stale(0));
    /// ```
    pub const fn new(stale_after_ms: u32) -> Self {
        Self {
            assembler: SentenceAssembler::new(),
            fusion: FixFusion::new(stale_after_ms),
            parse_errors: 0,
        }
    }

    /// Feeds one byte received at `now_ms`; returns a fix when an epoch completes.
    ///
    /// ```
    /// use drivers::gps::GpsDecoder;
    /// use drivers::time::DateTime;
    ///
    /// // GGA: the example of u-blox's NEO-6 protocol specification; RMC: the
    /// // same epoch (checksum 0x54 computed independently in Python as the XOR
    /// // of the bytes between `$` and `*`).
    /// let nmea: &[u8] = b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n\
    /// $GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54\r\n";
    /// let mut gps = GpsDecoder::new(2_000);
    /// let mut fix = None;
    /// for (i, &b) in nmea.iter().enumerate() {
    ///     // The epoch completes with the LF that ends its second sentence.
    ///     if let Some(f) = gps.push(b, 1_000) {
    ///         assert_eq!(i, nmea.len() - 1);
    ///         fix = Some(f);
    ///     }
    /// }
    /// let fix = fix.unwrap();
    /// // 47°17.11399' N, 8°33.91590' E, 499.6 m, 8 satellites, 2002-12-09.
    /// assert!((fix.latitude_deg.unwrap().deg::<f64>() - (47.0 + 17.11399 / 60.0)).abs() < 1e-12);
    /// assert!((fix.longitude_deg.unwrap().deg::<f64>() - (8.0 + 33.91590 / 60.0)).abs() < 1e-12);
    /// assert_eq!(fix.altitude_m, Some(499.6));
    /// assert_eq!(fix.satellites, Some(8));
    /// assert_eq!(fix.utc, Some(DateTime::new(2002, 12, 9, 9, 27, 25)?));
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub fn push(&mut self, byte: u8, now_ms: u32) -> Option<GpsFix> {
        self.push_completes(byte, now_ms)
            .then(|| self.fusion.last_fix())
    }

    /// [`GpsDecoder::push`] saying only whether an epoch completed (its fix
    /// is then `self.fusion.last_fix()`), so that no `Option<GpsFix>` is
    /// copied per byte.
    // Out of line on the AVR: one copy of the byte path, its own frame.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn push_completes(&mut self, byte: u8, now_ms: u32) -> bool {
        let sentence = match self.assembler.push(byte) {
            Some(Ok(text)) => parse_sentence(text),
            _ => return false,
        };
        match sentence {
            Ok(s) => self.fusion.update_completes(&s, now_ms),
            Err(_) => {
                count_up(&mut self.parse_errors);
                false
            }
        }
    }

    /// End of input: counts an unterminated line and gives out the last epoch.
    ///
    /// ```
    /// use drivers::gps::GpsDecoder;
    ///
    /// // Only the GGA of an epoch (u-blox's example), then a cut-off line:
    /// // the epoch may still get its RMC, so nothing is given out yet.
    /// let mut gps = GpsDecoder::new(2_000);
    /// let log = b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n$GPRMC,0927";
    /// assert!(log.iter().all(|&b| gps.push(b, 0).is_none()));
    /// let fix = gps.finish().unwrap();
    /// assert!(fix.has_position());
    /// assert_eq!(fix.utc, None); // GGA has no date
    /// assert_eq!(gps.stats().framing.partial, 1);
    /// assert_eq!(gps.finish(), None); // given out once
    /// ```
    pub fn finish(&mut self) -> Option<GpsFix> {
        self.assembler.finish_stream();
        self.fusion.flush()
    }

    /// The latest fix, or [`GpsFix::NONE`] once stale (a stale fix is then forgotten).
    ///
    /// ```
    /// use drivers::gps::{GpsDecoder, GpsFix};
    ///
    /// // GGA: the example of u-blox's NEO-6 protocol specification; RMC: the
    /// // same epoch (checksum 0x54 computed independently in Python as the XOR
    /// // of the bytes between `$` and `*`).
    /// let nmea: &[u8] = b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n\
    /// $GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54\r\n";
    /// let mut gps = GpsDecoder::new(2_000);
    /// nmea.iter().for_each(|&b| drop(gps.push(b, 10_000)));
    /// assert!(gps.current(12_000).has_position()); // 2 s later: still fresh
    /// assert_eq!(gps.current(12_001), GpsFix::NONE); // stale
    /// ```
    pub fn current(&mut self, now_ms: u32) -> GpsFix {
        self.fusion.current(now_ms)
    }

    /// Whether the fix is stale at `now_ms`.
    ///
    /// ```
    /// use drivers::gps::GpsDecoder;
    ///
    /// // GGA: the example of u-blox's NEO-6 protocol specification; RMC: the
    /// // same epoch (checksum 0x54 computed independently in Python as the XOR
    /// // of the bytes between `$` and `*`).
    /// let nmea: &[u8] = b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n\
    /// $GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54\r\n";
    /// let mut gps = GpsDecoder::new(2_000);
    /// assert!(gps.is_stale(0)); // nothing heard yet
    /// nmea.iter().for_each(|&b| drop(gps.push(b, 10_000)));
    /// assert!(!gps.is_stale(12_000));
    /// assert!(gps.is_stale(12_001));
    /// ```
    pub fn is_stale(&self, now_ms: u32) -> bool {
        self.fusion.is_stale(now_ms)
    }

    /// Counters so far.
    ///
    /// ```
    /// use drivers::gps::GpsDecoder;
    ///
    /// // Right checksum (0x55, computed in Python), impossible content: a
    /// // latitude of 91°. Counted as a parse error, not as a checksum error.
    /// let mut gps = GpsDecoder::new(2_000);
    /// for &b in b"$GPGGA,092725.00,9100.00000,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*55\r\n" {
    ///     gps.push(b, 0);
    /// }
    /// let stats = gps.stats();
    /// assert_eq!((stats.accepted, stats.parse_errors, stats.rejected_other), (0, 1, 1));
    /// assert_eq!(stats.rejected_checksum, 0);
    /// ```
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
///
/// ```
/// use drivers::gps::{Error, GpsReader};
///
/// let mut gps = GpsReader::new(&b""[..], 2_000);
/// assert_eq!(gps.poll(0), Err(Error::EndOfStream));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    ///
    /// ```
    /// use drivers::gps::Error;
    /// use embedded_io::ErrorKind;
    ///
    /// let e: Error<ErrorKind> = Error::Comm(ErrorKind::TimedOut);
    /// assert_eq!(e.kind(), ErrorKind::TimedOut);
    /// assert_eq!(Error::<ErrorKind>::EndOfStream.kind(), ErrorKind::Other);
    /// ```
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
///
/// ```
/// use drivers::gps::{FixQuality, GpsReader};
///
/// // GGA: the example of u-blox's NEO-6 protocol specification; RMC: the
/// // same epoch (checksum 0x54 computed independently in Python as the XOR
/// // of the bytes between `$` and `*`).
/// let nmea: &[u8] = b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n\
/// $GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54\r\n";
/// // Any `embedded_io::Read` will do; a byte slice stands in for the UART.
/// let mut gps = GpsReader::new(nmea, 2_000);
/// let fix = loop {
///     if let Some(fix) = gps.poll(1_000)? {
///         break fix;
///     }
/// };
/// assert_eq!(fix.quality, FixQuality::Gps);
/// # Ok::<(), drivers::gps::Error<core::convert::Infallible>>(())
/// ```
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
    ///
    /// ```
    /// use drivers::gps::{GpsFix, GpsReader};
    ///
    /// let mut gps = GpsReader::new(&b"$GPGSV,1,1,00*79\r\n"[..], 2_000);
    /// assert_eq!(gps.current(0), GpsFix::NONE); // nothing read yet
    /// assert_eq!(gps.stats().sentences, 0);
    /// ```
    pub fn new(serial: R, stale_after_ms: u32) -> Self {
        Self {
            serial,
            decoder: GpsDecoder::new(stale_after_ms),
            buf: [0; READ_CHUNK],
            start: 0,
            end: 0,
        }
    }

    /// Gives the serial port back.
    ///
    /// ```
    /// use drivers::gps::GpsReader;
    ///
    /// // A GSV with no satellites (checksum 0x79 computed in Python), then
    /// // bytes the reader has not taken yet: one `poll` reads at most 32.
    /// let serial: &[u8] = b"$GPGSV,1,1,00*79\r\n$GPGSV,1,1,00*79\r\n$GPGSV,1,1,00*79\r\n";
    /// let mut gps = GpsReader::new(serial, 2_000);
    /// assert_eq!(gps.poll(0), Ok(None));
    /// let rest: &[u8] = gps.destroy();
    /// assert_eq!(rest.len(), serial.len() - 32);
    /// ```
    pub fn destroy(self) -> R {
        self.serial
    }

    /// Processes bytes until a fix completes. Calls `read` at most once
    /// (so it blocks at most as long as one `read` does); `Ok(None)` when the
    /// bytes read so far did not complete an epoch. At end of stream the last
    /// epoch is returned once, then [`Error::EndOfStream`].
    ///
    /// ```
    /// use drivers::gps::{Error, GpsReader};
    /// use drivers::time::DateTime;
    ///
    /// // The u-blox RMC example alone: its epoch is given out at the end
    /// // of the stream, as no GGA of the same second followed.
    /// let nmea: &[u8] = b"$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A*57\r\n";
    /// let mut gps = GpsReader::new(nmea, 2_000);
    /// let mut fixes = Vec::new();
    /// loop {
    ///     match gps.poll(0) {
    ///         Ok(Some(fix)) => fixes.push(fix),
    ///         Ok(None) => {}
    ///         Err(Error::EndOfStream) => break,
    ///         Err(Error::Comm(e)) => match e {}, // a byte slice cannot fail
    ///     }
    /// }
    /// assert_eq!(fixes.len(), 1);
    /// assert_eq!(fixes[0].utc, Some(DateTime::new(2002, 12, 9, 8, 35, 59)?));
    /// assert!((fixes[0].latitude_deg.unwrap().deg::<f64>() - (47.0 + 17.11437 / 60.0)).abs() < 1e-12);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub fn poll(&mut self, now_ms: u32) -> Result<Option<GpsFix>, Error<R::Error>> {
        if self.drain(now_ms) {
            return Ok(Some(self.decoder.fusion.last_fix()));
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
        Ok(self.drain(now_ms).then(|| self.decoder.fusion.last_fix()))
    }

    /// Like [`GpsReader::poll`], but never blocks: when no byte is buffered
    /// and the port has none ready, returns `Ok(None)` without reading. For a
    /// main loop that also drives the motors.
    ///
    /// ```
    /// # mod serial { include!("../doc_support/serial.rs"); }
    /// # use serial::ScriptedSerial;
    /// use drivers::gps::GpsReader;
    ///
    /// // GGA: the example of u-blox's NEO-6 protocol specification; RMC: the
    /// // same epoch (checksum 0x54 computed independently in Python as the XOR
    /// // of the bytes between `$` and `*`).
    /// let nmea: &[u8] = b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n\
    /// $GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54\r\n";
    /// // `ScriptedSerial` (hidden here: src/doc_support/serial.rs) replays
    /// // the bytes, 8 per `read`, and says when none are left.
    /// let mut gps = GpsReader::new(ScriptedSerial::new(nmea, 8), 2_000);
    /// let mut fixes = 0;
    /// for _ in 0..100 {
    ///     // Never blocks: once the port is drained this returns Ok(None).
    ///     if gps.poll_if_ready(0)?.is_some() {
    ///         fixes += 1;
    ///     }
    /// }
    /// assert_eq!(fixes, 1);
    /// assert_eq!(gps.destroy().remaining(), 0);
    /// # Ok::<(), drivers::gps::Error<core::convert::Infallible>>(())
    /// ```
    pub fn poll_if_ready(&mut self, now_ms: u32) -> Result<Option<GpsFix>, Error<R::Error>>
    where
        R: ReadReady,
    {
        if self.drain(now_ms) {
            return Ok(Some(self.decoder.fusion.last_fix()));
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
    ///
    /// ```
    /// # mod serial { include!("../doc_support/serial.rs"); }
    /// # use serial::ScriptedSerial;
    /// use drivers::gps::GpsReader;
    ///
    /// // GGA: the example of u-blox's NEO-6 protocol specification; RMC: the
    /// // same epoch (checksum 0x54 computed independently in Python as the XOR
    /// // of the bytes between `$` and `*`).
    /// let nmea: &[u8] = b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n\
    /// $GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54\r\n";
    /// // `ScriptedSerial` (hidden here: src/doc_support/serial.rs) replays
    /// // the bytes, 16 per `read`.
    /// let mut gps = GpsReader::new(ScriptedSerial::new(nmea, 16), 2_000);
    /// let mut polls = 0;
    /// let mut fix = None;
    /// while gps.has_input()? {
    ///     fix = gps.poll_if_ready(0)?.or(fix);
    ///     polls += 1;
    /// }
    /// assert!(fix.is_some());
    /// assert_eq!(polls, nmea.len().div_ceil(16)); // one read each, then drained
    /// # Ok::<(), drivers::gps::Error<core::convert::Infallible>>(())
    /// ```
    pub fn has_input(&mut self) -> Result<bool, Error<R::Error>>
    where
        R: ReadReady,
    {
        if self.start < self.end {
            return Ok(true);
        }
        self.serial.read_ready().map_err(Error::Comm)
    }

    /// Decodes the buffered bytes until an epoch completes (its fix is then
    /// `self.decoder.fusion.last_fix()`); whether one did.
    fn drain(&mut self, now_ms: u32) -> bool {
        while let Some(&byte) = self.buf.get(self.start).filter(|_| self.start < self.end) {
            self.start += 1;
            if self.decoder.push_completes(byte, now_ms) {
                return true;
            }
        }
        false
    }

    /// The latest fix, or [`GpsFix::NONE`] once stale (a stale fix is then forgotten).
    ///
    /// ```
    /// use drivers::gps::{GpsFix, GpsReader};
    ///
    /// // GGA: the example of u-blox's NEO-6 protocol specification; RMC: the
    /// // same epoch (checksum 0x54 computed independently in Python as the XOR
    /// // of the bytes between `$` and `*`).
    /// let nmea: &[u8] = b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n\
    /// $GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54\r\n";
    /// let mut gps = GpsReader::new(nmea, 1_000);
    /// while gps.poll(60_000)?.is_none() {}
    /// assert!(gps.current(61_000).has_position());
    /// assert_eq!(gps.current(61_001), GpsFix::NONE);
    /// # Ok::<(), drivers::gps::Error<core::convert::Infallible>>(())
    /// ```
    pub fn current(&mut self, now_ms: u32) -> GpsFix {
        self.decoder.current(now_ms)
    }

    /// Counters so far.
    ///
    /// ```
    /// use drivers::gps::GpsReader;
    ///
    /// // GGA: the example of u-blox's NEO-6 protocol specification; RMC: the
    /// // same epoch (checksum 0x54 computed independently in Python as the XOR
    /// // of the bytes between `$` and `*`).
    /// let nmea: &[u8] = b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\r\n\
    /// $GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54\r\n";
    /// let mut gps = GpsReader::new(nmea, 2_000);
    /// while gps.poll(0)?.is_none() {}
    /// let stats = gps.stats();
    /// assert_eq!((stats.sentences, stats.accepted, stats.rejected_checksum), (2, 2, 0));
    /// # Ok::<(), drivers::gps::Error<core::convert::Infallible>>(())
    /// ```
    pub fn stats(&self) -> GpsStats {
        self.decoder.stats()
    }
}
