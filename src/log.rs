//! The one log format every image speaks, written without `core::fmt`.
//!
//! `core::fmt` with floats costs several kilobytes of flash on an 8-bit AVR
//! and carries panic paths; [`Sink`] writes integers and fixed-point
//! decimals byte by byte into a UART, semihosting or a test buffer, never
//! panics and never allocates. The line shapes, one per event, so that a
//! person or a script can follow any tracker:
//!
//! ```text
//! boot suntracker <version> board=<name>
//! time source=gps|rtc utc=YYYY-MM-DDTHH:MM:SSZ
//! site source=gps|config lat=<deg, 4 decimals> lon=<deg, 4 decimals>
//! setpoint utc=YYYY-MM-DDTHH:MM:SSZ zenith=<deg, 3 decimals> azimuth=<deg, 3 decimals> c=<deg, 2 decimals> a=<deg, 2 decimals>
//! mode <name>
//! fault <name> raised|cleared
//! gps rejected_epochs=<n>
//! ```
//!
//! Mode and fault names are [`Mode::name`] and [`Fault::name`], as in the
//! simulator's trace.

use crate::safety::{Fault, FaultManager, Mode, MAX_ACTIVE};
use crate::text::FlashStr;
use crate::time::TimeOrigin;
use sun_algos::UtcTime;

/// Where formatted text goes: a UART, semihosting, or a buffer in tests.
pub trait Sink {
    /// Writes all of `bytes`.
    fn put(&mut self, bytes: &[u8]);

    /// Writes one byte (from a register: a one-byte text is a constant the
    /// AVR copies into RAM at reset).
    fn byte(&mut self, byte: u8) {
        self.put(&[byte]);
    }

    /// Writes a string.
    fn text(&mut self, s: &str) {
        self.put(s.as_bytes());
    }

    /// Writes a constant text kept in flash on AVR ([`FlashStr`]).
    fn flash(&mut self, s: FlashStr) {
        s.for_each_chunk(|t| self.text(t));
    }

    /// Writes an unsigned integer in decimal.
    fn u32(&mut self, value: u32) {
        let mut digits = [0u8; 10];
        let mut n = value;
        let mut len = 0;
        for slot in digits.iter_mut().rev() {
            *slot = b'0' + (n % 10) as u8;
            n /= 10;
            len += 1;
            if n == 0 {
                break;
            }
        }
        let start = digits.len() - len;
        if let Some(used) = digits.get(start..) {
            self.put(used);
        }
    }

    /// Writes a signed integer in decimal.
    fn i32(&mut self, value: i32) {
        if value < 0 {
            self.byte(b'-');
        }
        self.u32(value.unsigned_abs());
    }

    /// Writes an unsigned integer padded with zeros to `width` digits.
    fn u32_padded(&mut self, value: u32, width: u8) {
        let mut limit: u32 = 10;
        for _ in 1..width {
            if value < limit {
                self.byte(b'0');
            }
            limit = limit.saturating_mul(10);
        }
        self.u32(value);
    }

    /// Writes `value` rounded to `decimals` places (at most 6); `nan` for a
    /// value that is not finite or too large for the fixed-point range.
    fn fixed(&mut self, value: f32, decimals: u8) {
        // In program memory on the AVR (as a constant it took 28 B of RAM).
        crate::progmem! {
            static POW10: [u32; 7] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];
        }
        let decimals = decimals.min(6);
        let scale = POW10.get(usize::from(decimals)).unwrap_or(1);
        let magnitude = if value < 0.0 { -value } else { value };
        let scaled = magnitude * scale as f32 + 0.5;
        // Also rejects NaN.
        if !scaled.is_finite() || scaled >= 4.0e9 {
            self.put(b"nan");
            return;
        }
        let units = scaled as u32;
        if value < 0.0 && units != 0 {
            self.byte(b'-');
        }
        // `scale` is never zero; checked division keeps panics out anyway.
        self.u32(units.checked_div(scale).unwrap_or(0));
        if decimals > 0 {
            self.byte(b'.');
            self.u32_padded(units.checked_rem(scale).unwrap_or(0), decimals);
        }
    }

    /// Writes a UTC instant as `YYYY-MM-DDTHH:MM:SSZ`.
    fn utc(&mut self, t: &UtcTime) {
        let (y, mo, d) = t.ymd();
        let (h, mi, s, _) = t.hms_milli();
        self.i32(y);
        self.byte(b'-');
        self.u32_padded(u32::from(mo), 2);
        self.byte(b'-');
        self.u32_padded(u32::from(d), 2);
        self.byte(b'T');
        self.u32_padded(u32::from(h), 2);
        self.byte(b':');
        self.u32_padded(u32::from(mi), 2);
        self.byte(b':');
        self.u32_padded(u32::from(s), 2);
        self.byte(b'Z');
    }
}

/// Where the site in use came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SiteSource {
    /// The GPS position.
    Gps,
    /// The stored configuration (or a postal code entered into it).
    Config,
}

/// `boot suntracker <version> board=<name>`
pub fn boot(out: &mut dyn Sink, board: &str) {
    out.flash(crate::flash_str!("boot "));
    out.flash(crate::flash_str!(crate::BANNER));
    out.flash(crate::flash_str!(" board="));
    out.text(board);
    out.flash(crate::flash_str!("\n"));
}

/// `time source=gps|rtc utc=…`, when the time is first trusted or its
/// source changes.
pub fn time(out: &mut dyn Sink, source: TimeOrigin, utc: &UtcTime) {
    out.flash(match source {
        TimeOrigin::Gps => crate::flash_str!("time source=gps utc="),
        TimeOrigin::Rtc => crate::flash_str!("time source=rtc utc="),
    });
    out.utc(utc);
    out.flash(crate::flash_str!("\n"));
}

/// `gps rejected_epochs=N`, when the GPS time faults (`gps_time_implausible`,
/// `gps_time_unstable`) have cleared: the epochs refused while they were
/// raised. A receiver that sends bad epochs for an hour raises its fault
/// once and is summed up here, not logged epoch by epoch.
pub fn gps_rejected(out: &mut dyn Sink, epochs: u32) {
    out.flash(crate::flash_str!("gps rejected_epochs="));
    out.u32(epochs);
    out.flash(crate::flash_str!("\n"));
}

/// `site source=gps|config lat=… lon=…`, when the site is taken or changes.
pub fn site(out: &mut dyn Sink, source: SiteSource, lat_deg: f32, lon_deg: f32) {
    out.flash(match source {
        SiteSource::Gps => crate::flash_str!("site source=gps lat="),
        SiteSource::Config => crate::flash_str!("site source=config lat="),
    });
    out.fixed(lat_deg, 4);
    out.flash(crate::flash_str!(" lon="));
    out.fixed(lon_deg, 4);
    out.flash(crate::flash_str!("\n"));
}

/// `setpoint utc=… zenith=… azimuth=… c=… a=…`: the sun's topocentric
/// zenith and azimuth (east of north) for that instant and the commanded
/// axis pose.
pub fn setpoint(
    out: &mut dyn Sink,
    utc: &UtcTime,
    zenith_deg: f32,
    azimuth_deg: f32,
    c_deg: f32,
    a_deg: f32,
) {
    setpoint_fields(out, utc, zenith_deg, azimuth_deg, c_deg, a_deg);
    out.flash(crate::flash_str!("\n"));
}

/// [`setpoint`] with the panel voltage read with it appended:
/// `setpoint utc=… zenith=… azimuth=… c=… a=… panel_mv=<int>` (Chowdhury et
/// al. 2019 read the panel voltage on the ADC; see [`crate::panel`]).
pub fn setpoint_with_panel(
    out: &mut dyn Sink,
    utc: &UtcTime,
    zenith_deg: f32,
    azimuth_deg: f32,
    c_deg: f32,
    a_deg: f32,
    panel_mv: u32,
) {
    setpoint_fields(out, utc, zenith_deg, azimuth_deg, c_deg, a_deg);
    out.flash(crate::flash_str!(" panel_mv="));
    out.u32(panel_mv);
    out.flash(crate::flash_str!("\n"));
}

fn setpoint_fields(
    out: &mut dyn Sink,
    utc: &UtcTime,
    zenith_deg: f32,
    azimuth_deg: f32,
    c_deg: f32,
    a_deg: f32,
) {
    out.flash(crate::flash_str!("setpoint utc="));
    out.utc(utc);
    out.flash(crate::flash_str!(" zenith="));
    out.fixed(zenith_deg, 3);
    out.flash(crate::flash_str!(" azimuth="));
    out.fixed(azimuth_deg, 3);
    out.flash(crate::flash_str!(" c="));
    out.fixed(c_deg, 2);
    out.flash(crate::flash_str!(" a="));
    out.fixed(a_deg, 2);
}

/// `mode <name>`, on each mode change.
pub fn mode(out: &mut dyn Sink, mode: Mode) {
    out.flash(crate::flash_str!("mode "));
    out.flash(mode.name());
    out.flash(crate::flash_str!("\n"));
}

/// `fault <name> raised|cleared`.
pub fn fault(out: &mut dyn Sink, fault: Fault, raised: bool) {
    out.flash(crate::flash_str!("fault "));
    out.flash(fault.name());
    out.flash(if raised {
        crate::flash_str!(" raised\n")
    } else {
        crate::flash_str!(" cleared\n")
    });
}

/// Remembers the active faults and the mode between ticks and logs what
/// changed: `fault … raised|cleared` and `mode …` lines.
#[derive(Debug, Clone, Default)]
pub struct ChangeLog {
    faults: [Option<Fault>; MAX_ACTIVE],
    mode: Option<Mode>,
}

impl ChangeLog {
    /// Nothing logged yet. Out of line on the AVR: built in place in the
    /// firmware (2.4 KB), each of its `None`s was a store with an address
    /// computation of its own (44 B more on the ATmega2560).
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn new() -> Self {
        Self::default()
    }

    /// Logs the faults cleared and raised since the last call (cleared
    /// first), then the mode if it changed.
    pub fn update(&mut self, out: &mut dyn Sink, faults: &FaultManager, mode: Mode) {
        for old in self.faults.iter().flatten() {
            if !faults.is_active(*old) {
                fault(out, *old, false);
            }
        }
        for a in faults.active() {
            if !self.faults.iter().flatten().any(|f| *f == a.fault) {
                fault(out, a.fault, true);
            }
        }
        let mut now = [None; MAX_ACTIVE];
        for (slot, a) in now.iter_mut().zip(faults.active()) {
            *slot = Some(a.fault);
        }
        self.faults = now;
        if self.mode != Some(mode) {
            self::mode(out, mode);
            self.mode = Some(mode);
        }
    }
}
