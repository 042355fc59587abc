//! A GPS receiver model for simulations: one epoch of NMEA 0183 text
//! (`$GPRMC` then `$GPGGA`, CR LF after each) written into the caller's
//! buffer, with fault injection.
//!
//! Faults, all public fields of [`GpsReceiverModel`]:
//! - `fix = false`: no fix; RMC status `V` and GGA quality 0, with empty
//!   position fields (the time, and the RMC date, are still sent, as real
//!   receivers do once they know the time);
//! - `position_override`: the receiver reports this latitude/longitude
//!   instead of the site's, even an impossible one (91°, 200°): the degrees
//!   are written as digits whatever their count, e.g. `9100.0000,N` and
//!   `20000.0000,E`;
//! - `date_override`: the receiver reports this date with the (possibly
//!   stepped) time of day, as with the GPS week-number rollover bug;
//! - `time_offset_s`: the receiver's time is off by this many seconds.
//!
//! Positions are written as `ddmm.mmmm` / `dddmm.mmmm` (minutes to 1e-4,
//! i.e. better than 1e-6° after rounding). RMC carries a two-digit year:
//! `drivers::gps` reads 83..=99 as 19xx and the rest as 20xx.

use core::fmt::{self, Write};

use drivers::gps::nmea_checksum;
use sun_algos::UtcTime;

/// A buffer of this many bytes holds any epoch whose reported position has
/// fewer than 8 digits of degrees and whose altitude is below 1e9 m.
pub const EPOCH_BUF_LEN: usize = 192;

/// Units of 1e-4 arc minute in one degree.
const TEN_THOUSANDTH_MINUTES_PER_DEG: f64 = 600_000.0;
/// Units of 1e-4 arc minute in one arc minute.
const TEN_THOUSANDTH_MINUTES_PER_MIN: u64 = 10_000;

/// Why an epoch could not be written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GpsModelError {
    /// The caller's buffer is too small for the epoch's sentences.
    BufferTooSmall,
    /// The true time plus `time_offset_s` is outside the calendar.
    TimeOutOfRange,
    /// `date_override` is not a calendar date.
    InvalidDate,
    /// A reported latitude, longitude or altitude is NaN or infinite.
    NonFinite,
}

impl fmt::Display for GpsModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            GpsModelError::BufferTooSmall => "buffer too small for the GPS epoch",
            GpsModelError::TimeOutOfRange => "GPS time out of range",
            GpsModelError::InvalidDate => "GPS date override is not a calendar date",
            GpsModelError::NonFinite => "GPS position or altitude is not finite",
        })
    }
}

/// A simulated GPS receiver at a fixed site; see the module docs.
#[derive(Debug, Clone, PartialEq)]
pub struct GpsReceiverModel {
    /// True latitude of the site, degrees north positive.
    pub site_lat_deg: f64,
    /// True longitude of the site, degrees east positive.
    pub site_lon_deg: f64,
    /// True altitude of the site above mean sea level, metres.
    pub site_altitude_m: f64,
    /// Whether the receiver has a fix.
    pub fix: bool,
    /// Injected: the position reported instead of the site's, (latitude,
    /// longitude) in degrees; may be impossible.
    pub position_override: Option<(f64, f64)>,
    /// Injected: the date reported instead of the true one, (year, month,
    /// day), e.g. a week-rollover date.
    pub date_override: Option<(u16, u8, u8)>,
    /// Injected: the receiver's time minus the true time, seconds.
    pub time_offset_s: i64,
    /// Satellites used, reported in GGA with a fix.
    pub satellites: u8,
}

impl GpsReceiverModel {
    /// A receiver at the given site with a fix, 8 satellites and no faults.
    pub fn new(site_lat_deg: f64, site_lon_deg: f64, site_altitude_m: f64) -> Self {
        GpsReceiverModel {
            site_lat_deg,
            site_lon_deg,
            site_altitude_m,
            fix: true,
            position_override: None,
            date_override: None,
            time_offset_s: 0,
            satellites: 8,
        }
    }

    /// The position the receiver reports, degrees (override or site).
    pub fn reported_position_deg(&self) -> (f64, f64) {
        self.position_override
            .unwrap_or((self.site_lat_deg, self.site_lon_deg))
    }

    /// Writes the epoch at true UTC `true_now` (`$GPRMC` and `$GPGGA`, each
    /// ending in CR LF) to the start of `buf`; returns the number of bytes
    /// written. [`EPOCH_BUF_LEN`] bytes are enough for any plausible state.
    pub fn epoch(&self, true_now: UtcTime, buf: &mut [u8]) -> Result<usize, GpsModelError> {
        let now = true_now
            .add_seconds(self.time_offset_s)
            .map_err(|_| GpsModelError::TimeOutOfRange)?;
        let (hour, minute, second, millis) = now.hms_milli();
        let (year, month, day) = match self.date_override {
            Some((y, m, d)) => {
                let valid = (1..=12).contains(&m)
                    && d >= 1
                    && d <= sun_algos::time::days_in_month(i32::from(y), m);
                if !valid {
                    return Err(GpsModelError::InvalidDate);
                }
                (i32::from(y), m, d)
            }
            None => now.ymd(),
        };
        let (lat_deg, lon_deg) = self.reported_position_deg();
        if self.fix
            && !(lat_deg.is_finite() && lon_deg.is_finite() && self.site_altitude_m.is_finite())
        {
            return Err(GpsModelError::NonFinite);
        }
        let time = Hms {
            hour,
            minute,
            second,
            centis: millis / 10,
        };
        let mut w = SliceWriter { buf, len: 0 };
        w.sentence(|w| {
            write!(w, "GPRMC,{time},")?;
            if self.fix {
                w.write_str("A,")?;
                write_angle(w, lat_deg, 2, 'N', 'S')?;
                w.write_char(',')?;
                write_angle(w, lon_deg, 3, 'E', 'W')?;
                w.write_str(",0.0,,")?;
            } else {
                w.write_str("V,,,,,,,")?;
            }
            let yy = year.rem_euclid(100);
            write!(w, "{day:02}{month:02}{yy:02},,,")?;
            w.write_char(if self.fix { 'A' } else { 'N' })
        })?;
        w.sentence(|w| {
            write!(w, "GPGGA,{time},")?;
            if self.fix {
                write_angle(w, lat_deg, 2, 'N', 'S')?;
                w.write_char(',')?;
                write_angle(w, lon_deg, 3, 'E', 'W')?;
                write!(
                    w,
                    ",1,{:02},0.9,{:.1},M,0.0,M,,",
                    self.satellites, self.site_altitude_m
                )
            } else {
                w.write_str(",,,,0,00,99.99,,,,,,")
            }
        })?;
        Ok(w.len)
    }
}

/// NMEA time of day, `hhmmss.ss`.
#[derive(Debug, Clone, Copy)]
struct Hms {
    hour: u8,
    minute: u8,
    second: u8,
    centis: u16,
}

impl fmt::Display for Hms {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:02}{:02}{:02}.{:02}",
            self.hour, self.minute, self.second, self.centis
        )
    }
}

/// Writes `|value_deg|` as degrees (at least `deg_width` digits) and minutes
/// to 1e-4, then the hemisphere letter: `positive` for ≥ 0, else `negative`.
/// Rounding carries into the degrees (59.99999' → next degree). Values too
/// large for a `u64` of 1e-4 minutes saturate.
fn write_angle<W: Write>(
    w: &mut W,
    value_deg: f64,
    deg_width: usize,
    positive: char,
    negative: char,
) -> fmt::Result {
    let hemisphere = if value_deg < 0.0 { negative } else { positive };
    // Float-to-int `as` saturates (and maps NaN to 0): no overflow.
    let units = libm::round(libm::fabs(value_deg) * TEN_THOUSANDTH_MINUTES_PER_DEG) as u64;
    let per_deg = TEN_THOUSANDTH_MINUTES_PER_MIN * 60;
    let degrees = units / per_deg;
    let minute_units = units % per_deg;
    write!(
        w,
        "{degrees:0deg_width$}{:02}.{:04},{hemisphere}",
        minute_units / TEN_THOUSANDTH_MINUTES_PER_MIN,
        minute_units % TEN_THOUSANDTH_MINUTES_PER_MIN,
    )
}

/// A `fmt::Write` into a byte slice that fails instead of truncating.
struct SliceWriter<'a> {
    buf: &'a mut [u8],
    len: usize,
}

impl SliceWriter<'_> {
    /// Writes `$`, the body from `body`, `*hh` and CR LF.
    fn sentence(
        &mut self,
        body: impl FnOnce(&mut Self) -> fmt::Result,
    ) -> Result<(), GpsModelError> {
        let too_small = |_| GpsModelError::BufferTooSmall;
        self.write_char('$').map_err(too_small)?;
        let body_start = self.len;
        body(self).map_err(too_small)?;
        let checksum = self
            .buf
            .get(body_start..self.len)
            .map(nmea_checksum)
            .unwrap_or(0);
        write!(self, "*{checksum:02X}\r\n").map_err(too_small)
    }
}

impl Write for SliceWriter<'_> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let end = self.len.checked_add(s.len()).ok_or(fmt::Error)?;
        let dest = self.buf.get_mut(self.len..end).ok_or(fmt::Error)?;
        dest.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}
