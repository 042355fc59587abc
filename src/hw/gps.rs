//! The GPS receiver as the main loop sees it: drain what the UART has, keep
//! the latest fix, never block.

use drivers::gps::{Error, GpsFix, GpsReader, GpsStats};
use embedded_io::{Read, ReadReady};

/// Most reads per [`GpsPort::service`] call, so that a receiver that never
/// stops talking cannot hold the loop (each read is one UART chunk).
const MAX_READS_PER_SERVICE: u8 = 64;

/// A GPS receiver on a serial port, polled from the main loop.
#[derive(Debug)]
pub struct GpsPort<R> {
    reader: GpsReader<R>,
    fixes: u32,
}

impl<R: Read + ReadReady> GpsPort<R> {
    /// A port whose fix goes stale `stale_after_ms` after the last epoch.
    pub fn new(serial: R, stale_after_ms: u32) -> Self {
        GpsPort {
            reader: GpsReader::new(serial, stale_after_ms),
            fixes: 0,
        }
    }

    /// Reads what the port has ready (bounded) and returns the current fix
    /// ([`GpsFix::NONE`] once stale). `now_ms` is a monotonic millisecond
    /// count of the board.
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn service(&mut self, now_ms: u32) -> Result<GpsFix, Error<R::Error>> {
        // A `None` only says that the bytes so far did not finish an epoch;
        // the loop ends as soon as the port is drained: when it is empty
        // the call costs one `read_ready` (a pass of the loop on the
        // ATmega2560 spent its whole millisecond here while it polled 64
        // times whatever the port held).
        for _ in 0..MAX_READS_PER_SERVICE {
            if !self.reader.has_input()? {
                break;
            }
            if self.reader.poll_if_ready(now_ms)?.is_some() {
                drivers::counter::count_up(&mut self.fixes);
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

#[cfg(test)]
mod tests {
    use super::*;
    use core::convert::Infallible;

    /// A port that hands out `data` in chunks of at most `chunk` bytes and
    /// counts the calls made to it.
    struct CountingPort {
        data: &'static [u8],
        chunk: usize,
        ready_calls: u32,
        read_calls: u32,
    }

    impl CountingPort {
        fn new(data: &'static [u8], chunk: usize) -> Self {
            CountingPort {
                data,
                chunk,
                ready_calls: 0,
                read_calls: 0,
            }
        }
    }

    impl embedded_io::ErrorType for CountingPort {
        type Error = Infallible;
    }

    impl Read for CountingPort {
        fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
            self.read_calls += 1;
            let n = self.data.len().min(buf.len()).min(self.chunk);
            let (head, rest) = self.data.split_at(n);
            buf[..n].copy_from_slice(head);
            self.data = rest;
            Ok(n)
        }
    }

    impl ReadReady for CountingPort {
        fn read_ready(&mut self) -> Result<bool, Infallible> {
            self.ready_calls += 1;
            Ok(!self.data.is_empty())
        }
    }

    const RMC: &[u8] = b"$GPRMC,120000.00,A,1158.098,N,00825.566,E,0.0,0.0,210626,,,A*6C\r\n";

    #[test]
    fn an_empty_port_costs_one_ready_check_and_no_read() {
        let port = CountingPort::new(b"", 8);
        let mut gps = GpsPort::new(port, 3_000);
        gps.service(0).unwrap();
        let port = gps.destroy();
        assert_eq!((port.ready_calls, port.read_calls), (1, 0));
    }

    #[test]
    fn a_service_reads_until_the_port_is_drained_then_stops() {
        // 67 bytes in chunks of 8: nine reads, then the empty port is
        // seen once and the loop ends (not 64 passes).
        let port = CountingPort::new(RMC, 8);
        let mut gps = GpsPort::new(port, 3_000);
        gps.service(0).unwrap();
        let port = gps.destroy();
        let reads = RMC.len().div_ceil(8) as u32;
        assert_eq!(port.read_calls, reads);
        assert!(port.data.is_empty());
        assert!(
            port.ready_calls <= 2 * reads + 1,
            "{} ready checks",
            port.ready_calls
        );
    }
}
