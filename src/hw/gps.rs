//! The GPS receiver as the main loop sees it: drain what the UART has, keep
//! the latest fix, never block.

use drivers::gps::{Error, GpsFix, GpsReader, GpsStats};
use embedded_io::{Read, ReadReady};
use sun_algos::Float;

use crate::site::filter::{SiteFilter, SiteFilterConfig};

/// Most reads per [`GpsPort::service`] call, so that a receiver that never
/// stops talking cannot hold the loop (each read is one UART chunk).
const MAX_READS_PER_SERVICE: u8 = 64;

/// The GPS input a board gives the loop ([`crate::firmware::Firmware::new`]):
/// any serial port with a receiver on it (`embedded_io::{Read, ReadReady}`),
/// or [`NoGps`].
pub trait GpsInput<T> {
    /// What the loop keeps of the input.
    type Part: GpsState<T>;
    /// The loop's part over this input: its fix goes stale `stale_after_ms`
    /// after the last epoch, `filter` decides which positions become the
    /// site.
    fn into_part(self, stale_after_ms: u32, filter: SiteFilterConfig) -> Self::Part;
}

/// A receiver's part of the loop, as the loop reads it.
pub trait GpsState<T> {
    /// Drains the port (bounded) and keeps the current fix; false when the
    /// port reported an error (an overrun, a framing error).
    fn service(&mut self, now_ms: u32) -> bool;
    /// The fix and the loop's state about it; `None` without a receiver
    /// (a constant of each image, so that the code using it folds away).
    fn track(&self) -> Option<&GpsTrack<T>>;
    /// The same, to update.
    fn track_mut(&mut self) -> Option<&mut GpsTrack<T>>;
}

/// The loop's state about the GPS receiver's fix.
#[derive(Debug)]
pub struct GpsTrack<T> {
    /// The current fix ([`GpsFix::NONE`] before any and once stale).
    pub fix: GpsFix,
    /// Monotonic ms of the last tick with trusted GPS time.
    pub last_time_ms: Option<u32>,
    /// Which GPS positions become the site.
    pub site_filter: SiteFilter<T>,
}

/// A receiver on a serial port and the loop's state about it.
#[derive(Debug)]
pub struct GpsPart<T, R> {
    port: GpsPort<R>,
    track: GpsTrack<T>,
}

impl<T: Float, R: Read + ReadReady> GpsInput<T> for R {
    type Part = GpsPart<T, R>;
    fn into_part(self, stale_after_ms: u32, filter: SiteFilterConfig) -> GpsPart<T, R> {
        GpsPart {
            port: GpsPort::new(self, stale_after_ms),
            track: GpsTrack {
                fix: GpsFix::NONE,
                last_time_ms: None,
                site_filter: SiteFilter::new(filter),
            },
        }
    }
}

impl<T, R: Read + ReadReady> GpsState<T> for GpsPart<T, R> {
    // Out of line on the Cortex-M images (the port's own service is on the
    // AVR): inlined into the loop's pass it cost the Black Pill 112 B.
    #[cfg_attr(not(target_arch = "avr"), inline(never))]
    fn service(&mut self, now_ms: u32) -> bool {
        match self.port.service(now_ms) {
            Ok(fix) => {
                self.track.fix = fix;
                true
            }
            Err(_) => false,
        }
    }
    #[inline]
    fn track(&self) -> Option<&GpsTrack<T>> {
        Some(&self.track)
    }
    #[inline]
    fn track_mut(&mut self) -> Option<&mut GpsTrack<T>> {
        Some(&mut self.track)
    }
}

/// The GPS input of a board without a receiver. Its part of the loop has
/// no size and no fix: the loop's GPS parts (the sentence reader, the fix,
/// the time keeper's GPS rules, the filter of GPS positions) are left out
/// of the image and its RAM by type, as an attitude sensor of type
/// `Infallible`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NoGps;

impl<T> GpsInput<T> for NoGps {
    type Part = NoGps;
    fn into_part(self, _stale_after_ms: u32, _filter: SiteFilterConfig) -> NoGps {
        self
    }
}

impl<T> GpsState<T> for NoGps {
    #[inline]
    fn service(&mut self, _now_ms: u32) -> bool {
        true
    }
    #[inline]
    fn track(&self) -> Option<&GpsTrack<T>> {
        None
    }
    #[inline]
    fn track_mut(&mut self) -> Option<&mut GpsTrack<T>> {
        None
    }
}

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
    fn a_board_without_a_receiver_holds_nothing_and_has_no_fix() {
        let mut part: NoGps =
            <NoGps as GpsInput<f32>>::into_part(NoGps, 3_000, SiteFilterConfig::default());
        assert_eq!(core::mem::size_of_val(&part), 0);
        assert!(GpsState::<f32>::service(&mut part, 0));
        assert!(GpsState::<f32>::track(&part).is_none());
        assert!(GpsState::<f32>::track_mut(&mut part).is_none());
    }

    #[test]
    fn a_serial_port_is_a_receiver_with_no_fix_before_its_first_epoch() {
        let port = CountingPort::new(b"", 8);
        let mut part = GpsInput::<f32>::into_part(port, 3_000, SiteFilterConfig::default());
        assert!(part.service(0));
        let track = part.track().expect("a receiver");
        assert_eq!(track.fix, GpsFix::NONE);
        assert_eq!(track.last_time_ms, None);
        assert!(!track.site_filter.unstable());
    }

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
