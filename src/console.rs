//! The configuration console every board image offers on its log serial
//! port: a line buffer, a parser of command lines into typed [`Command`]s,
//! the configuration commands themselves, and the reply lines.
//!
//! Everything here is `no_std`, allocation-free and free of `core::fmt`
//! (replies go through [`Sink`], numbers through [`Sink::fixed`] and
//! [`Sink::u32`]) and of core's float parsing (numbers are read by
//! [`Decimal::parse`]); nothing panics on any input.
//!
//! # The language
//!
//! One command a line; words are separated by spaces or tabs, command words
//! and keys are case-insensitive. Every reply line starts with `ok` or
//! `error`; a blank line gets no reply.
//!
//! | command | reply |
//! |---|---|
//! | `help` | one `ok …` line per line of [`HELP`] |
//! | `status` | `ok mode=<mode> utc=<YYYY-MM-DDTHH:MM:SSZ>\|none time=gps\|rtc\|none lat=<deg> lon=<deg> site=gps\|config c=<deg>\|none a=<deg>\|none faults=<name>,…\|none wind_hz=<Hz>\|none` ([`write_status`]) |
//! | `get` | `ok KEY=VALUE` for every key of the table below |
//! | `get KEY` | `ok KEY=VALUE` |
//! | `set KEY VALUE` or `set KEY=VALUE` | `ok KEY=VALUE` (the value as stored), or `error FIELD: REASON` |
//! | `set K1 V1 K2 V2 …` | all or nothing: `ok K1=V1 K2=V2 …`, or `error FIELD: REASON` |
//! | `set site.postal_code CC:CODE` | `ok site.lat_deg=<deg> site.lon_deg=<deg>`, or `error site.postal_code: …` |
//! | `save`, `load`, `defaults` | `ok save`, `ok load`, `ok defaults`, or `error save: …`, `error load: …` |
//! | `time set YYYY-MM-DDTHH:MM:SSZ` | `ok utc=…`, or `error time set: GPS time is in force` |
//! | `stow`, `resume`, `home`, `manual off`, `clear` | `ok stow`, `ok resume`, … |
//! | `jog c\|a DEG` | `ok jog` |
//! | `faults` | `ok fault=<name> attempts=<n>` per active fault, or `ok faults=none` |
//!
//! Malformed lines get `error unknown command`, `error unknown key`,
//! `error missing argument`, `error unexpected argument`,
//! `error KEY: not a number`, `error KEY: number too large`,
//! `error axis must be c or a`, `error time must be YYYY-MM-DDTHH:MM:SSZ`;
//! from the [`LineBuffer`]: `error line too long`, `error non-ASCII input`,
//! `error control character`.
//!
//! [`run_config`] carries out `help`, `get`, `set` and `defaults` on a
//! [`Config`] and answers them; the other commands act on the running
//! tracker, so the firmware carries them out and answers with the writers
//! of this module ([`write_status`], [`write_faults`], [`write_saved`],
//! [`write_loaded`], [`write_time_set`], [`write_time_refused`],
//! [`write_ok`] with [`Command::name`]). Refusing `time set` while GPS time
//! is trusted is the firmware's decision.
//!
//! # Keys
//!
//! Every field of [`Config`], named by [`Field::name`] (the dotted key with
//! its unit). A `set` is applied to a copy of the configuration, the copy
//! is checked by [`Config::validate`], and only a valid copy replaces the
//! configuration: a value out of range changes nothing and is answered
//! with the field and the reason the validation gives
//! ([`ConfigError`]: `error FIELD: REASON`). The ranges are those of
//! `src/config.rs` (the fields' doc comments and [`crate::config::ranges`]);
//! they are repeated here for the reader only.
//!
//! | key | unit | range (`src/config.rs`) |
//! |---|---|---|
//! | `site.lat_deg` | ° north | −90…90 |
//! | `site.lon_deg` | ° east | −180…180 |
//! | `site.elevation_m` | m | −500…10,000 |
//! | `site.postal_code` | `CC:CODE` | set only: a code of the built-in table ([`crate::site::postal`]) |
//! | `schedule.table_step_s` | s | 60…43,200, whole minutes dividing 86,400 |
//! | `schedule.hold_s` | s | 0…3,600 |
//! | `schedule.recheck_s` | s | 1…3,600 |
//! | `schedule.max_tick_gap_s` | s | 1…86,400 |
//! | `schedule.max_backward_s` | s | 0…86,400 |
//! | `axis.c.counts_per_motor_rev`, `axis.a.counts_per_motor_rev` | counts | 1…16,777,216 |
//! | `axis.c.microsteps`, `axis.a.microsteps` | per full step | 1…256 |
//! | `axis.c.gear_ratio`, `axis.a.gear_ratio` | motor rev per axis rev | 1…10,000 |
//! | `axis.c.counts_per_deg`, `axis.a.counts_per_deg` | counts/° | read only: counts × microsteps × gear / 360, must be 1…1,000,000 |
//! | `axis.c.min_deg`, `axis.a.min_deg` | ° | −360…360, below `max_deg` |
//! | `axis.c.max_deg`, `axis.a.max_deg` | ° | −360…360, above `min_deg` |
//! | `axis.c.home_deg`, `axis.a.home_deg` | ° | `min_deg` − 5 … `min_deg` + 10, at most `max_deg` |
//! | `axis.c.backlash_deg`, `axis.a.backlash_deg` | ° | 0…5 |
//! | `axis.c.max_speed_deg_s`, `axis.a.max_speed_deg_s` | °/s | 0.01…30 |
//! | `axis.c.deadband_deg`, `axis.a.deadband_deg` | ° | 0…5, below `safety.max_deviation_deg` |
//! | `wind.stow_hz` | Hz | 0.1…1,000 (the anemometer pulse rate that stows) |
//! | `wind.hold_s` | s | 0…600 |
//! | `wind.release_s` | s | 0…86,400 |
//! | `safety.max_deviation_deg` | ° | 0.1…45 |
//! | `safety.stall_timeout_s` | s | 1…600 |
//! | `safety.sensor_timeout_s` | s | 1…3,600 |
//! | `safety.max_retries` | count | 0…20 |
//! | `calibration.declination_deg` | ° east | −180…180 |
//! | `calibration.heading_offset_deg` | ° | −180…180 |
//! | `calibration.tilt_x_offset_deg` | ° | −45…45 |
//! | `calibration.tilt_y_offset_deg` | ° | −45…45 |
//! | `log.status_min` | min | 0…1,440 (0: no periodic `status` line) |
//!
//! Rules between fields (home switch near `min_deg`, deadband below the
//! largest deviation, the derived counts per degree) can need two fields
//! changed at once: `set axis.c.min_deg -360 axis.c.home_deg -360` sets
//! both or neither.
//!
//! Integer keys take whole numbers (`5` or `5.0`; `5.5` is `error KEY:
//! whole number expected`). A number is an optional sign, digits and an
//! optional fraction (`-12.375`); no exponent, no `nan` or `inf`. Values
//! are printed with as many decimals as an `f32` holds reliably (at most
//! six, trailing zeros dropped), so that a printed value typed back in
//! prints the same.
//!
//! `set site.postal_code DZ:16000` looks the code up in the built-in table
//! and sets latitude and longitude; a numeric code typed without its
//! leading zeros (`DZ:9000` for `DZ:09000`) is found too. The table has no
//! elevation: `site.elevation_m` is left as it is.
//!
//! # Use
//!
//! ```
//! use suntracker::config::Config;
//! use suntracker::console::{self, LineBuffer, Outcome};
//! use suntracker::log::Sink;
//!
//! struct Out([u8; 64], usize);
//! impl Sink for Out {
//!     fn put(&mut self, bytes: &[u8]) {
//!         for &b in bytes {
//!             if let Some(slot) = self.0.get_mut(self.1) {
//!                 *slot = b;
//!                 self.1 += 1;
//!             }
//!         }
//!     }
//! }
//!
//! let mut config = Config::default();
//! let mut line = LineBuffer::<{ console::LINE_LEN }>::new();
//! let mut out = Out([0; 64], 0);
//! for &byte in b"set wind.stow_hz 30\r\n" {
//!     match line.push(byte) {
//!         None => {}
//!         Some(Err(e)) => console::write_line_error(&mut out, e),
//!         Some(Ok(text)) => match console::parse(text) {
//!             Err(e) => console::write_parse_error(&mut out, &e),
//!             Ok(cmd) => match console::run_config(&mut out, &mut config, cmd) {
//!                 Outcome::Answered | Outcome::Changed => {}
//!                 // status, save, stow, …: the firmware's part.
//!                 Outcome::Pass(cmd) => console::write_ok(&mut out, cmd.name()),
//!             },
//!         },
//!     }
//! }
//! assert_eq!(&out.0[..out.1], b"ok wind.stow_hz=30\n");
//! assert_eq!(config.wind.threshold_hz, 30.0);
//! ```
//!
//! # Size
//!
//! The texts are `&'static str`s: the key names are [`Field::name`]'s and
//! the reasons [`Reason::text`](crate::config::Reason::text)'s, shared with
//! the configuration's validation errors. An 8-bit AVR keeps every linked
//! string, and the postal-code table, in RAM: about 3.5 KB for the whole
//! console, more than the ATmega2560 image has to spare, so an AVR image
//! needs these in program memory before it links the console. Numbers are
//! read without division or 64-bit multiplication; [`parse`],
//! [`run_config`] and the word comparison are kept out of line (inlined,
//! they made the AVR code 2 KB larger).

use crate::config::{Config, ConfigError, Field, Loaded, SaveError};
use crate::log::{Sink, SiteSource};
use crate::safety::{AxisId, Fault, FaultManager, Mode, MAX_ACTIVE};
use crate::site::key::MAX_CODE_LEN;
use crate::site::{lookup, PostalEntry, PostalError};
use crate::text::FlashStr;
use crate::time::datetime_from_utc;
use crate::time::TimeOrigin;
use drivers::rtc::Clock as RtcDriver;
use sun_algos::UtcTime;

/// A line length for [`LineBuffer`] that holds every command of the
/// language with room to spare (`set site.postal_code GB:SW1A 1AA` is 32
/// characters, `set site.lat_deg -33.8688 site.lon_deg 151.2093` 48).
pub const LINE_LEN: usize = 64;

/// The lines `help` prints, each after `ok `.
pub const HELP: &[FlashStr] = &[
    crate::flash_str!("status | faults | clear"),
    crate::flash_str!("get [KEY] | set KEY VALUE [KEY VALUE ...]"),
    crate::flash_str!("set site.postal_code CC:CODE"),
    crate::flash_str!("save | load | defaults"),
    crate::flash_str!("time set YYYY-MM-DDTHH:MM:SSZ"),
    crate::flash_str!("stow | resume | home | jog c|a DEG | manual off"),
];

/// A configuration key: a field of [`Config`] by its dotted name with unit
/// ([`Field::name`]).
pub type Key = Field;

/// The postal-code pseudo-key: `set` only, sets latitude and longitude.
pub const POSTAL_CODE_KEY: FlashStr = crate::flash_str!("site.postal_code");

// ---------------------------------------------------------------------------
// Line buffer

/// Why a line was refused before parsing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineError {
    /// More bytes than the buffer holds: `error line too long`.
    TooLong,
    /// A byte above 0x7F: `error non-ASCII input`.
    NonAscii,
    /// A control byte other than tab, CR, LF, backspace and DEL:
    /// `error control character`.
    Control,
}

impl LineError {
    /// The reply text after `error `.
    pub fn text(self) -> FlashStr {
        match self {
            LineError::TooLong => crate::flash_str!("line too long"),
            LineError::NonAscii => crate::flash_str!("non-ASCII input"),
            LineError::Control => crate::flash_str!("control character"),
        }
    }
}

/// Collects bytes into lines of at most `N` characters, one byte at a time,
/// in constant time per byte.
///
/// CR, LF and CR LF end a line (the LF of a CR LF pair is skipped); an
/// empty line yields nothing. Backspace (0x08) and DEL (0x7F) remove the
/// last character. A line longer than `N`, or with a byte above 0x7F or a
/// control byte (other than tab), is discarded up to its end of line and
/// then reported once as a [`LineError`]; the first problem is the one
/// reported. A flood of bytes without an end of line only keeps the
/// buffer in that state.
#[derive(Debug, Clone)]
pub struct LineBuffer<const N: usize> {
    buf: [u8; N],
    len: usize,
    error: Option<LineError>,
    after_cr: bool,
}

impl<const N: usize> Default for LineBuffer<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> LineBuffer<N> {
    /// An empty buffer.
    pub const fn new() -> Self {
        LineBuffer {
            buf: [0; N],
            len: 0,
            error: None,
            after_cr: false,
        }
    }

    /// Forgets the line being collected.
    pub fn clear(&mut self) {
        self.len = 0;
        self.error = None;
        self.after_cr = false;
    }

    /// Takes one byte; at the end of a non-empty line, the line (ASCII,
    /// without its end of line) or why it was refused.
    pub fn push(&mut self, byte: u8) -> Option<Result<&str, LineError>> {
        let after_cr = core::mem::replace(&mut self.after_cr, false);
        match byte {
            b'\n' if after_cr => None,
            b'\r' | b'\n' => {
                self.after_cr = byte == b'\r';
                self.finish()
            }
            0x08 | 0x7F => {
                if self.error.is_none() {
                    self.len = self.len.saturating_sub(1);
                }
                None
            }
            b'\t' | 0x20..=0x7E => {
                if self.error.is_none() {
                    match self.buf.get_mut(self.len) {
                        Some(slot) => {
                            *slot = byte;
                            self.len = self.len.saturating_add(1);
                        }
                        None => self.error = Some(LineError::TooLong),
                    }
                }
                None
            }
            0x80..=0xFF => {
                self.error.get_or_insert(LineError::NonAscii);
                None
            }
            _ => {
                self.error.get_or_insert(LineError::Control);
                None
            }
        }
    }

    fn finish(&mut self) -> Option<Result<&str, LineError>> {
        let len = core::mem::replace(&mut self.len, 0);
        if let Some(e) = self.error.take() {
            return Some(Err(e));
        }
        if len == 0 {
            return None;
        }
        let bytes = self.buf.get(..len)?;
        Some(crate::text::ascii_str(bytes).ok_or(LineError::NonAscii))
    }
}

// ---------------------------------------------------------------------------
// Numbers

/// Why a word is not a number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NumberError {
    /// Not `[+-]digits[.digits]`: `not a number`.
    Invalid,
    /// The whole part exceeds 4,294,967,295: `number too large`.
    TooLarge,
}

impl NumberError {
    /// The reply text.
    pub fn text(self) -> FlashStr {
        match self {
            NumberError::Invalid => crate::flash_str!("not a number"),
            NumberError::TooLarge => crate::flash_str!("number too large"),
        }
    }
}

/// Fraction digits kept at most (further ones only count for
/// [`Decimal::has_fraction`]): an `f32` resolves nothing finer in the
/// configuration's ranges.
const MAX_SCALE: u8 = 12;

/// A decimal number as typed: `±digits / 10^scale`, read without core's
/// float parsing (whose tables cost kilobytes on an AVR) and without
/// division.
///
/// Whole numbers up to 4,294,967,295 are exact. Fraction digits are kept
/// while the digits fit in a `u32` (at least nine significant digits,
/// beyond an `f32`'s seven) and at most twelve places; further ones only
/// count for [`Decimal::has_fraction`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Decimal {
    negative: bool,
    /// The whole part.
    whole: u32,
    /// The digits kept, whole part and fraction.
    digits: u32,
    /// Fraction digits in `digits`.
    scale: u8,
    /// A fraction digit other than zero was typed.
    fraction: bool,
}

/// `v × 10 + d` unless it exceeds `u32::MAX` (compared, not multiplied
/// in 64 bits: an 8-bit core has no cheap wide multiply).
fn times_ten_plus(v: u32, d: u32) -> Option<u32> {
    const MAX_DIV_10: u32 = u32::MAX / 10;
    const MAX_REM_10: u32 = u32::MAX % 10;
    if v > MAX_DIV_10 || (v == MAX_DIV_10 && d > MAX_REM_10) {
        None
    } else {
        Some(v.wrapping_mul(10).wrapping_add(d))
    }
}

impl Decimal {
    /// Reads `[+-]digits[.digits]`: at least one digit before a point and
    /// one after it; nothing else (no exponent, no `nan`, no `inf`, no
    /// spaces).
    pub fn parse(s: &str) -> Result<Decimal, NumberError> {
        let bytes = s.as_bytes();
        let (negative, rest) = match bytes.split_first() {
            Some((b'-', r)) => (true, r),
            Some((b'+', r)) => (false, r),
            _ => (false, bytes),
        };
        let mut d = Decimal {
            negative,
            whole: 0,
            digits: 0,
            scale: 0,
            fraction: false,
        };
        let (mut whole_digits, mut point, mut fraction_digits) = (false, false, false);
        for &b in rest {
            if b == b'.' && whole_digits && !point {
                point = true;
                continue;
            }
            if !b.is_ascii_digit() {
                return Err(NumberError::Invalid);
            }
            let digit = u32::from(b.wrapping_sub(b'0'));
            if point {
                fraction_digits = true;
                d.fraction |= digit != 0;
                if d.scale < MAX_SCALE {
                    if let Some(v) = times_ten_plus(d.digits, digit) {
                        d.digits = v;
                        d.scale = d.scale.saturating_add(1);
                    }
                }
            } else {
                whole_digits = true;
                d.whole = times_ten_plus(d.whole, digit).ok_or(NumberError::TooLarge)?;
                d.digits = d.whole;
            }
        }
        if !whole_digits || (point && !fraction_digits) {
            return Err(NumberError::Invalid);
        }
        if d.whole == 0 && !d.fraction {
            d.negative = false;
        }
        Ok(d)
    }

    /// A whole number.
    pub fn from_u32(value: u32) -> Decimal {
        Decimal {
            negative: false,
            whole: value,
            digits: value,
            scale: 0,
            fraction: false,
        }
    }

    /// The nearest `f32` (within one unit in the last place); always
    /// finite.
    pub fn to_f32(&self) -> f32 {
        let mut scale = 1.0f32;
        for _ in 0..self.scale {
            scale *= 10.0;
        }
        let v = self.digits as f32 / scale;
        if self.negative {
            -v
        } else {
            v
        }
    }

    /// True when the number has a fraction that is not zero.
    pub fn has_fraction(&self) -> bool {
        self.fraction
    }

    /// The number as a `u32`: `None` when it has a fraction or is negative.
    pub fn to_u32(&self) -> Option<u32> {
        let negative = self.negative && self.whole != 0;
        (!self.fraction && !negative).then_some(self.whole)
    }
}

/// Writes `value` with as many decimals as an `f32` holds reliably (at
/// most six, so that the scaled value stays below 2^21), trailing zeros
/// dropped: `25`, `0.05`, `11.9683`, `-179.1234`. A printed value read
/// back by [`Decimal::parse`] prints the same. `nan` for a value that is
/// not finite or above 4 × 10^9.
pub fn write_number(out: &mut dyn Sink, value: f32) {
    const LIMIT: f32 = 2_097_152.0;
    let magnitude = if value < 0.0 { -value } else { value };
    let mut decimals: u8 = 6;
    let mut scale = 1_000_000.0f32;
    while decimals > 0 && magnitude * scale >= LIMIT {
        decimals -= 1;
        scale /= 10.0;
    }
    // Below LIMIT (or zero decimals, where the count is not used): the
    // cast saturates and cannot fail.
    let mut units = (magnitude * scale + 0.5) as u32;
    while decimals > 0 && units.is_multiple_of(10) {
        units /= 10;
        decimals -= 1;
    }
    out.fixed(value, decimals);
}

// ---------------------------------------------------------------------------
// The key table

/// A key's value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A real number.
    F32(f32),
    /// A whole number (the `u8`, `u16` and `u32` fields).
    U32(u32),
}

/// Why a `set` changed nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SetError {
    /// The new configuration breaks a range or rule: the field and reason
    /// from [`Config::validate`] (usually the key that was set; for a rule
    /// between fields, the field the rule names):
    /// `error FIELD: REASON`.
    Invalid(ConfigError),
    /// A fraction for a whole-number key: `error KEY: whole number expected`.
    NotWhole(Key),
    /// A derived value (`axis.*.counts_per_deg`): `error KEY: read only`.
    ReadOnly(Key),
    /// A value the field cannot hold that the validation did not refuse
    /// either (no range allows it today): `error KEY: out of range`.
    OutOfRange(Key),
    /// The postal code gave no site: `error site.postal_code: …`.
    Postal(PostalError),
}

/// A whole number for a field of at most `max`, and whether it had to be
/// clipped: `NotWhole` for a fraction; `(max, true)` for a negative number
/// or one above `max`. No range of [`Config::validate`] includes its
/// type's maximum, so the validation then refuses the field with its own
/// reason.
fn whole(v: &Decimal, key: Key, max: u32) -> Result<(u32, bool), SetError> {
    if v.has_fraction() {
        return Err(SetError::NotWhole(key));
    }
    Ok(match v.to_u32() {
        Some(w) if w <= max => (w, false),
        _ => (max, true),
    })
}

/// Reads one field of the table.
macro_rules! key_read {
    (F32, $e:expr) => {
        Value::F32($e)
    };
    (Derived, $e:expr) => {
        Value::F32($e)
    };
    (U32, $e:expr) => {
        Value::U32($e)
    };
    (U16, $e:expr) => {
        Value::U32(u32::from($e))
    };
    (U8, $e:expr) => {
        Value::U32(u32::from($e))
    };
}

/// Where one field of the table lives, for writing.
macro_rules! key_slot {
    (F32, $e:expr) => {
        Slot::F32(&mut $e)
    };
    (Derived, $e:expr) => {
        Slot::Derived
    };
    (U32, $e:expr) => {
        Slot::U32(&mut $e)
    };
    (U16, $e:expr) => {
        Slot::U16(&mut $e)
    };
    (U8, $e:expr) => {
        Slot::U8(&mut $e)
    };
}

/// A field to write.
enum Slot<'a> {
    F32(&'a mut f32),
    U32(&'a mut u32),
    U16(&'a mut u16),
    U8(&'a mut u8),
    /// Computed from other fields (read only).
    Derived,
}

/// The key table: each key once, with its kind and where it lives in the
/// configuration. The matches are exhaustive over [`Field`]: a field added
/// to the configuration's keys must be added here.
macro_rules! key_table {
    ($c:ident; $( $field:ident $kind:ident $place:expr; )*) => {
        /// Every key, in the order of the configuration's layout (`get`
        /// lists them in this order). `site.postal_code` is not a field and
        /// not in the table.
        pub const KEYS: &[Key] = &[$(Field::$field,)*];

        /// The value of `key` in `config`.
        pub fn get(config: &Config, key: Key) -> Value {
            let $c = config;
            match key {
                $(Field::$field => key_read!($kind, $place),)*
            }
        }

        /// The field of `key`, to write.
        fn slot($c: &mut Config, key: Key) -> Slot<'_> {
            match key {
                $(Field::$field => key_slot!($kind, $place),)*
            }
        }
    };
}

key_table! { c;
    SiteLatDeg F32 c.site.latitude_deg;
    SiteLonDeg F32 c.site.longitude_deg;
    SiteElevationM F32 c.site.elevation_m;
    ScheduleTableStepS U32 c.schedule.table_step_s;
    ScheduleHoldS U32 c.schedule.hold_s;
    ScheduleRecheckS U32 c.schedule.recheck_s;
    ScheduleMaxTickGapS U32 c.schedule.max_tick_gap_s;
    ScheduleMaxBackwardS U32 c.schedule.max_backward_s;
    AxisCCountsPerMotorRev U32 c.axes[0].counts_per_motor_rev;
    AxisCMicrosteps U16 c.axes[0].microsteps;
    AxisCGearRatio F32 c.axes[0].gear_ratio;
    AxisCCountsPerDeg Derived c.axes[0].counts_per_deg();
    AxisCMinDeg F32 c.axes[0].min_deg;
    AxisCMaxDeg F32 c.axes[0].max_deg;
    AxisCHomeDeg F32 c.axes[0].home_deg;
    AxisCBacklashDeg F32 c.axes[0].backlash_deg;
    AxisCMaxSpeedDegS F32 c.axes[0].max_speed_deg_s;
    AxisCDeadbandDeg F32 c.axes[0].deadband_deg;
    AxisACountsPerMotorRev U32 c.axes[1].counts_per_motor_rev;
    AxisAMicrosteps U16 c.axes[1].microsteps;
    AxisAGearRatio F32 c.axes[1].gear_ratio;
    AxisACountsPerDeg Derived c.axes[1].counts_per_deg();
    AxisAMinDeg F32 c.axes[1].min_deg;
    AxisAMaxDeg F32 c.axes[1].max_deg;
    AxisAHomeDeg F32 c.axes[1].home_deg;
    AxisABacklashDeg F32 c.axes[1].backlash_deg;
    AxisAMaxSpeedDegS F32 c.axes[1].max_speed_deg_s;
    AxisADeadbandDeg F32 c.axes[1].deadband_deg;
    WindStowHz F32 c.wind.threshold_hz;
    WindHoldS U32 c.wind.hold_s;
    WindReleaseS U32 c.wind.release_s;
    SafetyMaxDeviationDeg F32 c.safety.max_deviation_deg;
    SafetyStallTimeoutS U32 c.safety.stall_timeout_s;
    SafetySensorTimeoutS U32 c.safety.sensor_timeout_s;
    SafetyMaxRetries U8 c.safety.max_retries;
    CalibrationDeclinationDeg F32 c.calibration.declination_deg;
    CalibrationHeadingOffsetDeg F32 c.calibration.heading_offset_deg;
    CalibrationTiltXOffsetDeg F32 c.calibration.tilt_x_offset_deg;
    CalibrationTiltYOffsetDeg F32 c.calibration.tilt_y_offset_deg;
    LogStatusMin U16 c.log.status_every_min;
}

/// The key named `name` (ASCII case-insensitive).
pub fn key_from_name(name: &str) -> Option<Key> {
    key_in(KEYS, name)
}

/// The key of `keys` named `name` (ASCII case-insensitive).
fn key_in(keys: &[Key], name: &str) -> Option<Key> {
    keys.iter().copied().find(|k| same_word(name, k.name()))
}

/// Stores `v` in `key` of `c`, unchecked; `Ok(true)` when it had to be
/// clipped to the field's type.
fn store(c: &mut Config, key: Key, v: &Decimal) -> Result<bool, SetError> {
    match slot(c, key) {
        Slot::F32(f) => {
            *f = v.to_f32();
            Ok(false)
        }
        Slot::U32(f) => {
            let (w, clipped) = whole(v, key, u32::MAX)?;
            *f = w;
            Ok(clipped)
        }
        Slot::U16(f) => {
            let (w, clipped) = whole(v, key, u32::from(u16::MAX))?;
            *f = u16::try_from(w).unwrap_or(u16::MAX);
            Ok(clipped)
        }
        Slot::U8(f) => {
            let (w, clipped) = whole(v, key, u32::from(u8::MAX))?;
            *f = u8::try_from(w).unwrap_or(u8::MAX);
            Ok(clipped)
        }
        Slot::Derived => Err(SetError::ReadOnly(key)),
    }
}

/// True for a key `set` refuses (`axis.*.counts_per_deg`, derived).
pub fn is_read_only(key: Key) -> bool {
    matches!(key, Field::AxisCCountsPerDeg | Field::AxisACountsPerDeg)
}

/// Sets `key` to `value` in a copy of `config`, validates the copy with
/// [`Config::validate`] and only then stores it; on error `config` is
/// unchanged.
pub fn apply_set(config: &mut Config, key: Key, value: Decimal) -> Result<(), SetError> {
    let mut copy = *config;
    let clipped = store(&mut copy, key, &value)?;
    commit(config, copy, clipped.then_some(key))
}

/// Sets every pair of `set` in a copy of `config`, validates the copy once
/// and only then stores it: all or nothing.
pub fn apply_assignments(config: &mut Config, set: &Assignments<'_>) -> Result<(), SetError> {
    let mut copy = *config;
    let mut clipped = None;
    for (key, value) in set.iter() {
        if store(&mut copy, key, &value)? {
            clipped = Some(key);
        }
    }
    commit(config, copy, clipped)
}

/// Stores `copy` if it is valid and no value had to be clipped to its
/// field's type (`clipped` names such a key).
fn commit(config: &mut Config, copy: Config, clipped: Option<Key>) -> Result<(), SetError> {
    copy.validate().map_err(SetError::Invalid)?;
    if let Some(key) = clipped {
        return Err(SetError::OutOfRange(key));
    }
    *config = copy;
    Ok(())
}

/// Looks `text` (`CC:CODE`, e.g. `DZ:16000`) up in the postal-code table
/// and sets the site's latitude and longitude from it (the elevation stays:
/// the table has none), validated as [`apply_set`] does.
///
/// A numeric code not in the table is tried again with leading zeros, up
/// to the longest code the table stores, so that `DZ:9000` finds
/// `DZ:09000`.
pub fn apply_postal_code(config: &mut Config, text: &str) -> Result<PostalEntry, SetError> {
    let entry = find_postal(text).map_err(SetError::Postal)?;
    let mut copy = *config;
    copy.site.latitude_deg = entry.latitude_deg::<f32>();
    copy.site.longitude_deg = entry.longitude_deg::<f32>();
    copy.validate().map_err(SetError::Invalid)?;
    *config = copy;
    Ok(entry)
}

/// The table entry of `CC:CODE`, with leading zeros added to a numeric
/// code that is not found as typed.
pub fn find_postal(text: &str) -> Result<PostalEntry, PostalError> {
    let (country, code) = split_at_byte(text, b':').ok_or(PostalError::BadFormat)?;
    let (country, code) = (trim_blank(country), trim_blank(code));
    let first = lookup(country, code);
    if first != Err(PostalError::UnknownPostalCode) || !code.bytes().all(|b| b.is_ascii_digit()) {
        return first;
    }
    let mut buf = [b'0'; MAX_CODE_LEN];
    let mut total = code.len();
    // One more leading zero each time, up to the longest code stored.
    while total < MAX_CODE_LEN {
        total = total.saturating_add(1);
        buf.fill(b'0');
        let zeros = total.saturating_sub(code.len());
        for (d, s) in buf.iter_mut().skip(zeros).zip(code.bytes()) {
            *d = s;
        }
        if let Some(padded) = buf.get(..total).and_then(crate::text::ascii_str) {
            if let found @ Ok(_) = lookup(country, padded) {
                return found;
            }
        }
    }
    first
}

// ---------------------------------------------------------------------------
// Commands

/// Several `KEY VALUE` (or `KEY=VALUE`) pairs of one `set`, checked by
/// [`parse`]: every key known, every value a number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Assignments<'a> {
    text: &'a str,
    /// The keys the line was parsed against.
    keys: &'a [Key],
}

impl<'a> Assignments<'a> {
    /// The pairs, in the order typed.
    pub fn iter(&self) -> impl Iterator<Item = (Key, Decimal)> + 'a {
        let (mut rest, keys) = (self.text, self.keys);
        core::iter::from_fn(move || loop {
            let (key, value, tail) = next_pair(rest).ok()??;
            rest = tail;
            if let (Some(k), Ok(v)) = (key_in(keys, key), Decimal::parse(value)) {
                return Some((k, v));
            }
        })
    }
}

/// A command line, parsed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command<'a> {
    /// `help`.
    Help,
    /// `status`.
    Status,
    /// `get`: every key.
    GetAll,
    /// `get KEY`.
    Get(Key),
    /// `set KEY VALUE` (the value not yet checked against the range).
    Set(Key, Decimal),
    /// `set K1 V1 K2 V2 …`: all or nothing.
    SetMany(Assignments<'a>),
    /// `set site.postal_code CC:CODE`: the text after the key, trimmed.
    SetPostalCode(&'a str),
    /// `save`.
    Save,
    /// `load`.
    Load,
    /// `defaults`.
    Defaults,
    /// `time set YYYY-MM-DDTHH:MM:SSZ`.
    TimeSet(UtcTime),
    /// `stow`.
    Stow,
    /// `resume`.
    Resume,
    /// `home`.
    Home,
    /// `jog c|a DEG`: move an axis by DEG degrees (the firmware keeps it
    /// inside its limits).
    Jog(AxisId, f32),
    /// `manual off`.
    ManualOff,
    /// `faults`.
    Faults,
    /// `clear`.
    Clear,
}

impl Command<'_> {
    /// The command's words, for its `ok` reply (`stow`, `manual off`,
    /// `time set`, …).
    pub fn name(&self) -> FlashStr {
        match self {
            Command::Help => crate::flash_str!("help"),
            Command::Status => crate::flash_str!("status"),
            Command::GetAll | Command::Get(_) => crate::flash_str!("get"),
            Command::Set(..) | Command::SetMany(_) | Command::SetPostalCode(_) => {
                crate::flash_str!("set")
            }
            Command::Save => crate::flash_str!("save"),
            Command::Load => crate::flash_str!("load"),
            Command::Defaults => crate::flash_str!("defaults"),
            Command::TimeSet(_) => crate::flash_str!("time set"),
            Command::Stow => crate::flash_str!("stow"),
            Command::Resume => crate::flash_str!("resume"),
            Command::Home => crate::flash_str!("home"),
            Command::Jog(..) => crate::flash_str!("jog"),
            Command::ManualOff => crate::flash_str!("manual off"),
            Command::Faults => crate::flash_str!("faults"),
            Command::Clear => crate::flash_str!("clear"),
        }
    }
}

/// Why a line is not a command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParseError {
    /// Nothing but blanks: no reply.
    Empty,
    /// `error unknown command`.
    UnknownCommand,
    /// `error unknown key`.
    UnknownKey,
    /// `error missing argument`.
    MissingArgument,
    /// `error unexpected argument`.
    UnexpectedArgument,
    /// `error KEY: not a number` or `… number too large`.
    BadValue(Key, NumberError),
    /// `error not a number` or `error number too large` (`jog`).
    BadNumber(NumberError),
    /// `error axis must be c or a`.
    BadAxis,
    /// `error time must be YYYY-MM-DDTHH:MM:SSZ` (also for a date that
    /// does not exist).
    BadTime,
    /// `get site.postal_code`: `error site.postal_code: set only`.
    SetOnly,
}

fn is_blank_byte(b: u8) -> bool {
    b == b' ' || b == b'\t'
}

/// `s` without leading spaces and tabs.
fn trim_start_blank(s: &str) -> &str {
    let start = s.bytes().position(|c| !is_blank_byte(c)).unwrap_or(s.len());
    s.get(start..).unwrap_or("")
}

/// `s` without leading and trailing spaces and tabs (byte loops: `trim`
/// links a Unicode table).
fn trim_blank(s: &str) -> &str {
    let s = trim_start_blank(s);
    let end = s
        .bytes()
        .rposition(|c| !is_blank_byte(c))
        .map_or(0, |i| i.saturating_add(1));
    s.get(..end).unwrap_or("")
}

/// Splits off the first word: (word, rest); the word is empty when `s` is
/// blank.
fn word(s: &str) -> (&str, &str) {
    let s = trim_start_blank(s);
    let end = s.bytes().position(is_blank_byte).unwrap_or(s.len());
    (s.get(..end).unwrap_or(""), s.get(end..).unwrap_or(""))
}

/// Splits `s` at the first `sep` (an ASCII byte).
fn split_at_byte(s: &str, sep: u8) -> Option<(&str, &str)> {
    let i = s.bytes().position(|c| c == sep)?;
    Some((s.get(..i)?, s.get(i.saturating_add(1)..)?))
}

fn is_blank(s: &str) -> bool {
    s.bytes().all(is_blank_byte)
}

fn no_more(rest: &str) -> Result<(), ParseError> {
    if is_blank(rest) {
        Ok(())
    } else {
        Err(ParseError::UnexpectedArgument)
    }
}

/// The next `KEY VALUE` or `KEY=VALUE` pair: (key, value, rest), `None` at
/// the end.
fn next_pair(s: &str) -> Result<Option<(&str, &str, &str)>, ParseError> {
    let (first, rest) = word(s);
    if first.is_empty() {
        return Ok(None);
    }
    let (key, value, rest) = match split_at_byte(first, b'=') {
        Some((k, v)) => (k, v, rest),
        None => {
            let (v, rest) = word(rest);
            (first, v, rest)
        }
    };
    if key.is_empty() || value.is_empty() {
        return Err(ParseError::MissingArgument);
    }
    Ok(Some((key, value, rest)))
}

/// `s` without a leading `prefix` (ASCII case-insensitive).
fn strip_prefix_ignore_case(s: &str, prefix: FlashStr) -> Option<&str> {
    s.get(..prefix.len())
        .filter(|p| same_word(p, prefix))
        .and_then(|_| s.get(prefix.len()..))
}

/// Parses `set`'s arguments against `keys`.
fn parse_set<'a>(args: &'a str, keys: &'a [Key]) -> Result<Command<'a>, ParseError> {
    let trimmed = trim_start_blank(args);
    if let Some(after) = strip_prefix_ignore_case(trimmed, POSTAL_CODE_KEY) {
        let value = after.strip_prefix('=').or_else(|| {
            after
                .bytes()
                .next()
                .is_none_or(is_blank_byte)
                .then_some(after)
        });
        if let Some(value) = value {
            let value = trim_blank(value);
            if value.is_empty() {
                return Err(ParseError::MissingArgument);
            }
            return Ok(Command::SetPostalCode(value));
        }
    }
    let mut rest = args;
    let mut count = 0u8;
    let mut single = None;
    while let Some((key, value, tail)) = next_pair(rest)? {
        if same_word(key, POSTAL_CODE_KEY) {
            return Err(ParseError::UnexpectedArgument);
        }
        let k = key_in(keys, key).ok_or(ParseError::UnknownKey)?;
        let v = Decimal::parse(value).map_err(|e| ParseError::BadValue(k, e))?;
        single = Some((k, v));
        count = count.saturating_add(1);
        rest = tail;
    }
    match single {
        None => Err(ParseError::MissingArgument),
        Some((k, v)) if count == 1 => Ok(Command::Set(k, v)),
        Some(_) => Ok(Command::SetMany(Assignments { text: args, keys })),
    }
}

/// `YYYY-MM-DDTHH:MM:SSZ` exactly (`T` and `Z` in either case).
pub fn parse_utc(s: &str) -> Option<UtcTime> {
    // `0` stands for a digit; the other bytes end a field.
    const TEMPLATE: &[u8; 20] = b"0000-00-00T00:00:00Z";
    let b = s.as_bytes();
    if b.len() != TEMPLATE.len() {
        return None;
    }
    // Year, month, day, hour, minute, second: at most 9999.
    let mut fields = [0u16; 6];
    let mut field = 0usize;
    for (&c, &t) in b.iter().zip(TEMPLATE.iter()) {
        if t == b'0' {
            if !c.is_ascii_digit() {
                return None;
            }
            let f = fields.get_mut(field)?;
            *f = f
                .wrapping_mul(10)
                .wrapping_add(u16::from(c.wrapping_sub(b'0')));
        } else if c.eq_ignore_ascii_case(&t) {
            field = field.saturating_add(1);
        } else {
            return None;
        }
    }
    let [year, month, day, hour, minute, second] = fields;
    let small = |v: u16| u8::try_from(v).ok();
    UtcTime::from_ymd_hms(
        i32::from(year),
        small(month)?,
        small(day)?,
        small(hour)?,
        small(minute)?,
        small(second)?,
    )
    .ok()
}

/// The first word of a command line.
#[derive(Clone, Copy)]
enum Verb {
    Help,
    Status,
    Get,
    Set,
    Save,
    Load,
    Defaults,
    Time,
    Stow,
    Resume,
    Home,
    Jog,
    Manual,
    Faults,
    Clear,
}

crate::progmem! {
    /// The command words (in program memory on AVR, the table's pointers
    /// and lengths too; read one entry at a time).
    static VERBS: [(FlashStr, Verb); 15] = [
        (crate::flash_str!("help"), Verb::Help),
        (crate::flash_str!("status"), Verb::Status),
        (crate::flash_str!("get"), Verb::Get),
        (crate::flash_str!("set"), Verb::Set),
        (crate::flash_str!("save"), Verb::Save),
        (crate::flash_str!("load"), Verb::Load),
        (crate::flash_str!("defaults"), Verb::Defaults),
        (crate::flash_str!("time"), Verb::Time),
        (crate::flash_str!("stow"), Verb::Stow),
        (crate::flash_str!("resume"), Verb::Resume),
        (crate::flash_str!("home"), Verb::Home),
        (crate::flash_str!("jog"), Verb::Jog),
        (crate::flash_str!("manual"), Verb::Manual),
        (crate::flash_str!("faults"), Verb::Faults),
        (crate::flash_str!("clear"), Verb::Clear),
    ];
}

/// ASCII case-insensitive equality (one copy, not inlined at every use).
#[inline(never)]
fn same_word(a: &str, b: FlashStr) -> bool {
    b.eq_ignore_ascii_case(a)
}

/// Parses one command line (see the module docs for the language).
pub fn parse(line: &str) -> Result<Command<'_>, ParseError> {
    parse_in(line, KEYS)
}

/// Parses one command line whose keys are those of `keys`: the language of
/// [`parse`] on a board that offers a part of the configuration (the
/// Arduino Uno's settings); any other key is `error unknown key`.
#[inline(never)]
pub fn parse_in<'a>(line: &'a str, keys: &'a [Key]) -> Result<Command<'a>, ParseError> {
    let (cmd, rest) = word(line);
    if cmd.is_empty() {
        return Err(ParseError::Empty);
    }
    let Some(verb) = VERBS
        .iter()
        .find(|(w, _)| same_word(cmd, *w))
        .map(|(_, v)| v)
    else {
        return Err(ParseError::UnknownCommand);
    };
    let (arg, after) = word(rest);
    let alone = |c: Command<'static>| {
        if arg.is_empty() {
            Ok(c)
        } else {
            Err(ParseError::UnexpectedArgument)
        }
    };
    match verb {
        Verb::Help => alone(Command::Help),
        Verb::Status => alone(Command::Status),
        Verb::Save => alone(Command::Save),
        Verb::Load => alone(Command::Load),
        Verb::Defaults => alone(Command::Defaults),
        Verb::Stow => alone(Command::Stow),
        Verb::Resume => alone(Command::Resume),
        Verb::Home => alone(Command::Home),
        Verb::Faults => alone(Command::Faults),
        Verb::Clear => alone(Command::Clear),
        Verb::Get => {
            if arg.is_empty() {
                return Ok(Command::GetAll);
            }
            no_more(after)?;
            if same_word(arg, POSTAL_CODE_KEY) {
                return Err(ParseError::SetOnly);
            }
            key_in(keys, arg)
                .map(Command::Get)
                .ok_or(ParseError::UnknownKey)
        }
        Verb::Set => parse_set(rest, keys),
        Verb::Time => {
            if !same_word(arg, crate::flash_str!("set")) {
                return Err(ParseError::UnknownCommand);
            }
            let (t, after) = word(after);
            if t.is_empty() {
                return Err(ParseError::MissingArgument);
            }
            no_more(after)?;
            parse_utc(t)
                .map(Command::TimeSet)
                .ok_or(ParseError::BadTime)
        }
        Verb::Manual => {
            if !same_word(arg, crate::flash_str!("off")) {
                return Err(ParseError::UnknownCommand);
            }
            no_more(after).map(|()| Command::ManualOff)
        }
        Verb::Jog => {
            let (deg, after) = word(after);
            if deg.is_empty() {
                return Err(ParseError::MissingArgument);
            }
            no_more(after)?;
            let axis = if same_word(arg, crate::flash_str!("c")) {
                AxisId::C
            } else if same_word(arg, crate::flash_str!("a")) {
                AxisId::A
            } else {
                return Err(ParseError::BadAxis);
            };
            let deg = Decimal::parse(deg).map_err(ParseError::BadNumber)?;
            Ok(Command::Jog(axis, deg.to_f32()))
        }
    }
}

// ---------------------------------------------------------------------------
// Carrying out the configuration commands

/// What [`run_config`] did with a command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome<'a> {
    /// Answered; the configuration is unchanged.
    Answered,
    /// Answered; the configuration changed (the firmware puts it into
    /// effect; `save` stores it).
    Changed,
    /// Not a configuration command: the firmware carries it out and
    /// answers.
    Pass(Command<'a>),
}

/// Carries out and answers `help`, `get`, `set` and `defaults` on
/// `config`; passes every other command back.
#[inline(never)]
pub fn run_config<'a>(out: &mut dyn Sink, config: &mut Config, cmd: Command<'a>) -> Outcome<'a> {
    let changed = |ok: bool| {
        if ok {
            Outcome::Changed
        } else {
            Outcome::Answered
        }
    };
    match cmd {
        Command::Help => {
            write_help(out);
            Outcome::Answered
        }
        Command::GetAll => {
            for k in KEYS {
                format_get(out, config, *k);
            }
            Outcome::Answered
        }
        Command::Get(k) => {
            format_get(out, config, k);
            Outcome::Answered
        }
        Command::Set(k, v) => {
            let r = apply_set(config, k, v);
            match r {
                Ok(()) => format_get(out, config, k),
                Err(e) => write_set_error(out, &e),
            }
            changed(r.is_ok())
        }
        Command::SetMany(a) => {
            let r = apply_assignments(config, &a);
            match r {
                Ok(()) => {
                    out.flash(crate::flash_str!("ok"));
                    for (k, _) in a.iter() {
                        out.flash(crate::flash_str!(" "));
                        write_key_value(out, config, k);
                    }
                    out.flash(crate::flash_str!("\n"));
                }
                Err(e) => write_set_error(out, &e),
            }
            changed(r.is_ok())
        }
        Command::SetPostalCode(text) => {
            let r = apply_postal_code(config, text);
            match r {
                Ok(_) => {
                    out.flash(crate::flash_str!("ok "));
                    write_key_value(out, config, Field::SiteLatDeg);
                    out.flash(crate::flash_str!(" "));
                    write_key_value(out, config, Field::SiteLonDeg);
                    out.flash(crate::flash_str!("\n"));
                }
                Err(e) => write_set_error(out, &e),
            }
            changed(r.is_ok())
        }
        Command::Defaults => {
            *config = Config::default();
            write_ok(out, crate::flash_str!("defaults"));
            Outcome::Changed
        }
        other => Outcome::Pass(other),
    }
}

// ---------------------------------------------------------------------------
// Replies

/// `ok WHAT` (`ok` alone for an empty `what`).
pub fn write_ok(out: &mut dyn Sink, what: FlashStr) {
    out.flash(crate::flash_str!("ok"));
    if !what.is_empty() {
        out.flash(crate::flash_str!(" "));
        out.flash(what);
    }
    out.flash(crate::flash_str!("\n"));
}

/// `error WHAT`.
pub fn write_error(out: &mut dyn Sink, what: FlashStr) {
    out.flash(crate::flash_str!("error "));
    out.flash(what);
    out.flash(crate::flash_str!("\n"));
}

/// `ok LINE` for every line of [`HELP`].
pub fn write_help(out: &mut dyn Sink) {
    for line in HELP {
        write_ok(out, *line);
    }
}

/// `KEY=VALUE`, without `ok` or end of line.
pub fn write_key_value(out: &mut dyn Sink, config: &Config, key: Key) {
    out.flash(key.name());
    out.flash(crate::flash_str!("="));
    match get(config, key) {
        Value::F32(v) => write_number(out, v),
        Value::U32(v) => out.u32(v),
    }
}

/// `ok KEY=VALUE`: the reply to `get KEY` and to a successful `set`.
pub fn format_get(out: &mut dyn Sink, config: &Config, key: Key) {
    out.flash(crate::flash_str!("ok "));
    write_key_value(out, config, key);
    out.flash(crate::flash_str!("\n"));
}

/// The reply to a line the [`LineBuffer`] refused: `error line too long`, …
pub fn write_line_error(out: &mut dyn Sink, e: LineError) {
    write_error(out, e.text());
}

/// The reply to a line [`parse`] refused; nothing for a blank line.
pub fn write_parse_error(out: &mut dyn Sink, e: &ParseError) {
    let text = match e {
        ParseError::Empty => return,
        ParseError::UnknownCommand => crate::flash_str!("unknown command"),
        ParseError::UnknownKey => crate::flash_str!("unknown key"),
        ParseError::MissingArgument => crate::flash_str!("missing argument"),
        ParseError::UnexpectedArgument => crate::flash_str!("unexpected argument"),
        ParseError::BadValue(k, n) => {
            out.flash(crate::flash_str!("error "));
            out.flash(k.name());
            out.flash(crate::flash_str!(": "));
            out.flash(n.text());
            out.flash(crate::flash_str!("\n"));
            return;
        }
        ParseError::BadNumber(n) => n.text(),
        ParseError::BadAxis => crate::flash_str!("axis must be c or a"),
        ParseError::BadTime => crate::flash_str!("time must be YYYY-MM-DDTHH:MM:SSZ"),
        ParseError::SetOnly => crate::flash_str!("site.postal_code: set only"),
    };
    write_error(out, text);
}

/// The reply text of a postal-code error (after `site.postal_code: `).
pub fn postal_error_text(e: PostalError) -> FlashStr {
    match e {
        PostalError::BadCountry => crate::flash_str!("country must be two letters"),
        PostalError::BadPostalCode => {
            crate::flash_str!("postal code must be 1-10 of 0-9, A-Z, space, -")
        }
        PostalError::BadFormat => crate::flash_str!("expected CC:CODE, e.g. DZ:16000"),
        PostalError::UnknownPostalCode => crate::flash_str!("not in the table"),
    }
}

/// The reply to a refused `set`: `error FIELD: REASON`, `error KEY: whole
/// number expected`, `error KEY: read only`, `error KEY: out of range`,
/// `error site.postal_code: …`.
pub fn write_set_error(out: &mut dyn Sink, e: &SetError) {
    out.flash(crate::flash_str!("error "));
    let (name, reason) = match *e {
        SetError::Invalid(ConfigError { field, reason }) => (field.name(), reason.text()),
        SetError::NotWhole(k) => (k.name(), crate::flash_str!("whole number expected")),
        SetError::ReadOnly(k) => (k.name(), crate::flash_str!("read only")),
        SetError::OutOfRange(k) => (k.name(), crate::flash_str!("out of range")),
        SetError::Postal(p) => (POSTAL_CODE_KEY, postal_error_text(p)),
    };
    out.flash(name);
    out.flash(crate::flash_str!(": "));
    out.flash(reason);
    out.flash(crate::flash_str!("\n"));
}

/// A plain snapshot of what `status` reports, filled by the firmware.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StatusView {
    /// The mode in force.
    pub mode: Mode,
    /// The UTC time and its source, `None` while no time is trusted.
    pub time: Option<(UtcTime, TimeOrigin)>,
    /// Latitude of the site in use, degrees north.
    pub lat_deg: f32,
    /// Longitude of the site in use, degrees east.
    pub lon_deg: f32,
    /// Where the site came from.
    pub site_source: SiteSource,
    /// C-axis angle, degrees (`None`: not known, e.g. before homing).
    pub c_deg: Option<f32>,
    /// A-axis angle, degrees (`None`: not known).
    pub a_deg: Option<f32>,
    /// The active faults ([`StatusView::faults_of`]).
    pub faults: [Option<Fault>; MAX_ACTIVE],
    /// The anemometer's pulse rate, Hz (`None`: no anemometer or no
    /// reading).
    pub wind_hz: Option<f32>,
}

impl StatusView {
    /// The active faults of `m`, for [`StatusView::faults`].
    pub fn faults_of(m: &FaultManager) -> [Option<Fault>; MAX_ACTIVE] {
        let mut f = [None; MAX_ACTIVE];
        for (slot, a) in f.iter_mut().zip(m.active()) {
            *slot = Some(a.fault);
        }
        f
    }
}

fn write_opt_number(out: &mut dyn Sink, v: Option<f32>, decimals: u8) {
    match v {
        Some(v) => out.fixed(v, decimals),
        None => out.flash(crate::flash_str!("none")),
    }
}

/// The reply to `status`, one line:
/// `ok mode=tracking utc=2026-03-20T12:00:00Z time=gps lat=11.9683
/// lon=8.4261 site=config c=12.50 a=-30.25 faults=none wind_hz=3.20`
/// (latitude and longitude with 4 decimals, angles and wind with 2, as the
/// log; `none` for what is unknown; faults by [`Fault::name`], separated
/// by commas).
pub fn write_status(out: &mut dyn Sink, s: &StatusView) {
    out.flash(crate::flash_str!("ok "));
    write_status_fields(out, s);
}

/// The fields of `status` from `mode=` to the end of the line (the
/// periodic log line is `status ` and these fields).
pub fn write_status_fields(out: &mut dyn Sink, s: &StatusView) {
    out.flash(crate::flash_str!("mode="));
    out.flash(s.mode.name());
    match &s.time {
        Some((t, source)) => {
            out.flash(crate::flash_str!(" utc="));
            out.utc(t);
            out.flash(match source {
                TimeOrigin::Gps => crate::flash_str!(" time=gps"),
                TimeOrigin::Rtc => crate::flash_str!(" time=rtc"),
            });
        }
        None => out.flash(crate::flash_str!(" utc=none time=none")),
    }
    out.flash(crate::flash_str!(" lat="));
    out.fixed(s.lat_deg, 4);
    out.flash(crate::flash_str!(" lon="));
    out.fixed(s.lon_deg, 4);
    out.flash(match s.site_source {
        SiteSource::Gps => crate::flash_str!(" site=gps"),
        SiteSource::Config => crate::flash_str!(" site=config"),
    });
    out.flash(crate::flash_str!(" c="));
    write_opt_number(out, s.c_deg, 2);
    out.flash(crate::flash_str!(" a="));
    write_opt_number(out, s.a_deg, 2);
    out.flash(crate::flash_str!(" faults="));
    let mut any = false;
    for f in s.faults.iter().flatten() {
        if any {
            out.flash(crate::flash_str!(","));
        }
        out.flash(f.name());
        any = true;
    }
    if !any {
        out.flash(crate::flash_str!("none"));
    }
    out.flash(crate::flash_str!(" wind_hz="));
    write_opt_number(out, s.wind_hz, 2);
    out.flash(crate::flash_str!("\n"));
}

/// The reply to `faults`: `ok fault=<name> attempts=<n>` per active fault,
/// or `ok faults=none`.
pub fn write_faults(out: &mut dyn Sink, m: &FaultManager) {
    let mut any = false;
    for a in m.active() {
        out.flash(crate::flash_str!("ok fault="));
        out.flash(a.fault.name());
        out.flash(crate::flash_str!(" attempts="));
        out.u32(a.attempts);
        out.flash(crate::flash_str!("\n"));
        any = true;
    }
    if !any {
        write_ok(out, crate::flash_str!("faults=none"));
    }
}

/// The reply to `time set` once the clock is set: `ok utc=…`.
pub fn write_time_set(out: &mut dyn Sink, t: &UtcTime) {
    out.flash(crate::flash_str!("ok utc="));
    out.utc(t);
    out.flash(crate::flash_str!("\n"));
}

/// The reply to `time set` while GPS time is trusted:
/// `error time set: GPS time is in force`.
pub fn write_time_refused(out: &mut dyn Sink) {
    write_error(out, crate::flash_str!("time set: GPS time is in force"));
}

/// Sets `rtc` to `t` (the console's `time set` once the firmware has
/// allowed it): `OutOfRange` for an instant the RTC's calendar cannot
/// hold, `RtcFailed` when the chip did not take it.
pub fn set_rtc_time<R: RtcDriver>(rtc: &mut R, t: &UtcTime) -> Result<(), TimeSetError> {
    let d = datetime_from_utc(t).map_err(|_| TimeSetError::OutOfRange)?;
    rtc.set_datetime(&d).map_err(|_| TimeSetError::RtcFailed)
}

/// The reply to a refused `time set`: `error time set: GPS time is in
/// force`, `… the RTC did not answer`, `… outside the RTC's range`.
pub fn write_time_error(out: &mut dyn Sink, e: TimeSetError) {
    match e {
        TimeSetError::GpsInForce => write_time_refused(out),
        TimeSetError::RtcFailed => {
            write_error(out, crate::flash_str!("time set: the RTC did not answer"))
        }
        TimeSetError::OutOfRange => {
            write_error(out, crate::flash_str!("time set: outside the RTC's range"))
        }
    }
}

/// The reply to `save`: `ok save`, or `error save: config invalid`,
/// `… storage too small`, `… storage failed`.
pub fn write_saved<E>(out: &mut dyn Sink, r: &Result<(), SaveError<E>>) {
    match r {
        Ok(()) => write_ok(out, crate::flash_str!("save")),
        Err(SaveError::Invalid) => write_error(out, crate::flash_str!("save: config invalid")),
        Err(SaveError::TooSmall) => write_error(out, crate::flash_str!("save: storage too small")),
        Err(SaveError::Storage(_)) => write_error(out, crate::flash_str!("save: storage failed")),
    }
}

/// The reply to `load`: `ok load` when a stored copy was good, else
/// `error load: no valid stored config` (the firmware then keeps the
/// configuration in force; `defaults` gives the defaults).
pub fn write_loaded<R>(out: &mut dyn Sink, l: &Loaded<R>) {
    if l.defaults {
        write_error(out, crate::flash_str!("load: no valid stored config"));
    } else {
        write_ok(out, crate::flash_str!("load"));
    }
}

// ---------------------------------------------------------------------------
// Carrying out commands on a running tracker

/// Why `time set` was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeSetError {
    /// GPS time is trusted: `error time set: GPS time is in force`.
    GpsInForce,
    /// The RTC did not take it: `error time set: the RTC did not answer`.
    RtcFailed,
    /// Outside what the RTC holds: `error time set: outside the RTC's range`.
    OutOfRange,
}

/// The result of a `jog`: the manual pose now commanded, and whether the
/// soft limits cut the move short.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jogged {
    /// C-axis angle commanded, degrees.
    pub c_deg: f32,
    /// A-axis angle commanded, degrees.
    pub a_deg: f32,
    /// The move was held at a soft limit.
    pub limited: bool,
}

/// What a board's tracker lets the console do besides editing the
/// configuration: [`execute`] answers every command through it, so every
/// board speaks the same language with the same replies.
pub trait Operator {
    /// Where replies go (the log port).
    fn out(&mut self) -> &mut dyn Sink;
    /// The configuration in force.
    fn config(&self) -> Config;
    /// The board's own configuration, which `defaults` restores (its
    /// mechanics, not [`Config::default`]'s generic ones).
    fn defaults(&self) -> Config;
    /// Puts a changed (valid) configuration into effect; false when the
    /// tracker refused it (then nothing changed).
    fn apply(&mut self, config: Config) -> bool;
    /// What `status` reports.
    fn status(&self) -> StatusView;
    /// Writes the `faults` reply ([`write_faults`] or the same shape).
    fn write_faults(&mut self);
    /// Starts storing `config`: `None` when the board has no storage; the
    /// reply to a started save comes when it ends (the caller polls it).
    fn begin_save(&mut self, config: &Config) -> Option<Result<(), SaveError<()>>>;
    /// Reads the stored configuration: `None` when the board has no
    /// storage.
    fn load(&mut self) -> Option<Loaded>;
    /// Sets the RTC.
    fn set_time(&mut self, t: &UtcTime) -> Result<(), TimeSetError>;
    /// An operator's stow (true) or its release (false).
    fn stow(&mut self, on: bool);
    /// Homes both axes again; false on a board without home switches.
    fn home(&mut self) -> bool;
    /// Manual mode: moves `axis` by `deg`, within the soft limits.
    fn jog(&mut self, axis: AxisId, deg: f32) -> Jogged;
    /// Leaves manual mode.
    fn manual_off(&mut self);
    /// The operator's reset of a safe stop: faults cleared.
    fn clear(&mut self);
}

/// What [`execute`] left for the caller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Executed {
    /// Answered (or a blank line).
    Done,
    /// A save was started: poll it and answer with [`write_saved`] when it
    /// ends.
    SaveStarted,
}

/// Parses `line`, carries it out through `op` and answers on
/// [`Operator::out`]. Not inlined: a command's temporaries (a copy of the
/// configuration, the status view) are on the stack only while it runs.
#[inline(never)]
pub fn execute(op: &mut dyn Operator, line: &str) -> Executed {
    let cmd = match parse(line) {
        Ok(c) => c,
        Err(ParseError::Empty) => return Executed::Done,
        Err(e) => {
            write_parse_error(op.out(), &e);
            return Executed::Done;
        }
    };
    let mut config = op.config();
    if cmd == Command::Defaults {
        if op.apply(op.defaults()) {
            write_ok(op.out(), cmd.name());
        } else {
            write_error(
                op.out(),
                crate::flash_str!("config refused by the tracker: not in effect"),
            );
        }
        return Executed::Done;
    }
    let cmd = match run_config(op.out(), &mut config, cmd) {
        Outcome::Answered => return Executed::Done,
        Outcome::Changed => {
            if !op.apply(config) {
                write_error(
                    op.out(),
                    crate::flash_str!("config refused by the tracker: not in effect"),
                );
            }
            return Executed::Done;
        }
        Outcome::Pass(cmd) => cmd,
    };
    match cmd {
        Command::Status => {
            let view = op.status();
            write_status(op.out(), &view);
        }
        Command::Faults => op.write_faults(),
        Command::Save => match op.begin_save(&config) {
            Some(Ok(())) => return Executed::SaveStarted,
            Some(Err(e)) => write_saved(op.out(), &Err(e)),
            None => write_error(
                op.out(),
                crate::flash_str!("save: no storage on this board"),
            ),
        },
        Command::Load => match op.load() {
            Some(loaded) => {
                write_loaded(op.out(), &loaded);
                if !loaded.defaults && !op.apply(loaded.config) {
                    write_error(
                        op.out(),
                        crate::flash_str!("config refused by the tracker: not in effect"),
                    );
                }
            }
            None => write_error(
                op.out(),
                crate::flash_str!("load: no storage on this board"),
            ),
        },
        Command::TimeSet(t) => match op.set_time(&t) {
            Ok(()) => write_time_set(op.out(), &t),
            Err(e) => write_time_error(op.out(), e),
        },
        Command::Stow | Command::Resume => {
            op.stow(matches!(cmd, Command::Stow));
            write_ok(op.out(), cmd.name());
        }
        Command::Home => {
            if op.home() {
                write_ok(op.out(), cmd.name());
            } else {
                write_error(
                    op.out(),
                    crate::flash_str!("home: no home switches on this board"),
                );
            }
        }
        Command::ManualOff => {
            op.manual_off();
            write_ok(op.out(), cmd.name());
        }
        Command::Clear => {
            op.clear();
            write_ok(op.out(), cmd.name());
        }
        Command::Jog(axis, deg) => {
            let j = op.jog(axis, deg);
            let out = op.out();
            out.flash(crate::flash_str!("ok jog c="));
            out.fixed(j.c_deg, 2);
            out.flash(crate::flash_str!(" a="));
            out.fixed(j.a_deg, 2);
            out.flash(if j.limited {
                crate::flash_str!(" limited\n")
            } else {
                crate::flash_str!("\n")
            });
        }
        // Carried out by `run_config`.
        Command::Help
        | Command::GetAll
        | Command::Get(_)
        | Command::Set(..)
        | Command::SetMany(_)
        | Command::SetPostalCode(_)
        | Command::Defaults => {}
    }
    Executed::Done
}
