//! The GPS receiver as the main loop sees it: drain what the UART has, keep
//! the latest fix, never block.

use drivers::gps::{Error, GpsFix, GpsReader, GpsStats};
use embedded_io::{Read, ReadReady};

/// Most reads per [`GpsPort::service`] call, so that a receiver that never
/// stops talking cannot hold the loop (each read is one UART chunk).
const MAX_READS_PER_SERVICE: u32 = 64;

/// A GPS receiver on a serial port, polled from the main loop.
#[derive(Debug)]
pub struct GpsPort<R> {
    reader: GpsReader<R>,
    fixes: u32,
}

impl<R: Read + ReadReady> GpsPort<R> {
    /// A port whose fix goes stale `stale_after_ms` after the last epoch.
    pub fn new(serial: R, stale_after_ms: u64) -> Self {
        GpsPort {
            reader: GpsReader::new(serial, stale_after_ms),
            fixes: 0,
        }
    }

    /// Reads what the port has ready (bounded) and returns the current fix
    /// ([`GpsFix::NONE`] once stale). `now_ms` is a monotonic millisecond
    /// count of the board.
    pub fn service(&mut self, now_ms: u64) -> Result<GpsFix, Error<R::Error>> {
        // A `None` only says that the bytes so far did not finish an epoch;
        // when the port is empty the call costs one `read_ready`.
        for _ in 0..MAX_READS_PER_SERVICE {
            if self.reader.poll_if_ready(now_ms)?.is_some() {
                self.fixes = self.fixes.saturating_add(1);
            }
        }
        Ok(self.reader.current(now_ms))
    }

    /// Epochs decoded so far.
    pub fn fixes(&self) -> u32 {
        self.fixes
    }

    /// The decoder's counters.
    pub fn stats(&self) -> GpsStats {
        self.reader.stats()
    }

    /// Gives the port back.
    pub fn destroy(self) -> R {
        self.reader.destroy()
    }
}
