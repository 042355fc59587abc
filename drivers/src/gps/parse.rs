//! GGA and RMC contents, read field by field with integer arithmetic.
//!
//! Only the sentence type is looked at to classify a sentence; the talker
//! (GP, GN, GL, GA, BD, ...) is not restricted. Other sentence types (GSV,
//! GSA, VTG, TXT, ...) are [`Sentence::Other`]: valid, but of no use to the
//! fix.
//!
//! The fields are those of NMEA 0183 (v2.3 to v4.11; see e.g. u-blox, *NEO-6
//! Receiver Description including Protocol Specification*, §NMEA Messages,
//! GGA and RMC):
//!
//! ```text
//! $--GGA,hhmmss.ss,ddmm.mm,N,dddmm.mm,E,q,ss,h.h,a.a,M,g.g,M,age,stn*hh
//!        1         2       3 4        5 6 7  8   9   10 11 12 13  14
//! $--RMC,hhmmss.ss,A,ddmm.mm,N,dddmm.mm,E,s.s,c.c,ddmmyy,v.v,E,m,n*hh
//!        1         2 3       4 5        6 7   8   9      10  11 12 13
//! ```
//!
//! Numbers are read as decimal digits into an integer mantissa with a scale
//! (no text-to-float parsing, no `core::fmt`): a latitude `ddmm.mmmm` is kept
//! exactly, as `(dd·60 + mm)·10¹¹ + mmmm·10^(11−k)` 10⁻¹¹ arc-minutes
//! ([`Coordinate`], up to [`MINUTE_DECIMALS`] minute decimals), which each
//! float type rounds once; an altitude `a.aaa` is the `f32` nearest
//! `aaaa / 10^k`, rounded once from the integers (no `f64`). Integer
//! parts and counts are accumulated with checked arithmetic: one that
//! overflows is a [`ParseError`]; decimals past [`MINUTE_DECIMALS`],
//! [`ALTITUDE_DECIMALS`] or (for the time of day) the tenth are checked to be
//! digits and then dropped (they are below 2·10⁻¹³°, a nanometre, or the
//! rounding of a nanosecond).
//!
//! What each field must be, beyond its grammar, is what the `nmea` crate
//! (0.8), which this module replaced, required, so that the same sentences are
//! accepted and give the same values (see the tests, which compare both):
//! - GGA: fields 1..=12 present (13 and 14 may be missing); quality exactly
//!   one digit `0`..=`8`; altitude unit empty or `M`;
//! - RMC: fields 1..=11 present (the NMEA 2.3 mode and 4.1 navigational status
//!   may be missing, and are not read); status exactly `A`, `D` or `V`; a
//!   magnetic variation only with its `E`/`W`;
//! - time: leap second rejected; a fraction that rounds to the next second
//!   (ten or more nines) is rejected, except in second 59, where it is read as
//!   59.999 (as `chrono`, behind the `nmea` crate, represented it);
//! - satellites: any digit string that fits a `u32`, saturated to 255.
//!
//! A GGA or RMC is checked for possible content both while its fields are
//! read (the text of each, in the one pass over them) and after (the
//! values); an impossible one is a [`ParseError`] like an unreadable one. The rules
//! (ranges, minutes < 60, calendar dates, no leap second, no `nan`/`inf`) are
//! in the `plausible` module's documentation and in the README.

use sun_algos::Float;

use super::assembler::{check as check_framing, MAX_SENTENCE_LEN};
use super::coordinate::Coordinate;
use super::plausible::{gga_is_plausible, rmc_is_plausible, Kind};
use crate::time::{days_in_month, DateTime};

/// Fix quality, GGA field 6.
///
/// ```
/// use drivers::gps::{parse_sentence, FixQuality, Sentence};
///
/// // u-blox's GGA example with quality 2 (checksum 0x58 computed in Python).
/// let s = parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,2,08,1.01,499.6,M,48.0,M,,*58")?;
/// let Sentence::Gga(gga) = s else { unreachable!() };
/// assert_eq!(gga.quality, FixQuality::Dgps);
/// # Ok::<(), drivers::gps::ParseError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FixQuality {
    /// 0: no fix.
    #[default]
    Invalid,
    /// 1: autonomous GNSS fix.
    Gps,
    /// 2: differential GNSS fix.
    Dgps,
    /// 3: PPS fix.
    Pps,
    /// 4: RTK fixed.
    Rtk,
    /// 5: RTK float.
    FloatRtk,
    /// 6: dead reckoning.
    Estimated,
    /// 7: manual input.
    Manual,
    /// 8: simulation.
    Simulation,
}

impl FixQuality {
    /// The digit used in GGA field 6.
    ///
    /// ```
    /// use drivers::gps::FixQuality;
    ///
    /// // NMEA 0183 GGA quality indicator: 0 invalid, 1 GPS, 2 DGPS, 4 RTK
    /// // fixed, 5 RTK float, 6 estimated (dead reckoning).
    /// assert_eq!(FixQuality::Invalid.code(), 0);
    /// assert_eq!(FixQuality::Dgps.code(), 2);
    /// assert_eq!(FixQuality::Rtk.code(), 4);
    /// assert_eq!(FixQuality::Estimated.code(), 6);
    /// ```
    pub fn code(self) -> u8 {
        match self {
            FixQuality::Invalid => 0,
            FixQuality::Gps => 1,
            FixQuality::Dgps => 2,
            FixQuality::Pps => 3,
            FixQuality::Rtk => 4,
            FixQuality::FloatRtk => 5,
            FixQuality::Estimated => 6,
            FixQuality::Manual => 7,
            FixQuality::Simulation => 8,
        }
    }
}

/// Time of day in milliseconds, 0..86_400_000.
///
/// ```
/// use drivers::gps::{parse_sentence, Sentence, TimeOfDayMs};
///
/// let Sentence::Gga(gga) = parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B")? else { unreachable!() };
/// // 09:27:25.00 = (9·3600 + 27·60 + 25) s.
/// let expected: TimeOfDayMs = 34_045_000;
/// assert_eq!(gga.time_of_day_ms, Some(expected));
/// # Ok::<(), drivers::gps::ParseError>(())
/// ```
pub type TimeOfDayMs = u32;

/// What a GGA sentence says.
///
/// ```
/// use drivers::gps::{parse_sentence, FixQuality, Gga, Sentence};
///
/// // u-blox NEO-6 protocol specification, GGA example.
/// let Sentence::Gga(gga) = parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B")? else { unreachable!() };
/// assert_eq!(gga.quality, FixQuality::Gps);
/// assert_eq!(gga.satellites, Some(8));
/// assert_eq!(gga.altitude_m, Some(499.6));
/// // 47°17.11399' N = 47 + 17.11399/60 degrees.
/// assert!((gga.latitude_deg.unwrap().deg::<f64>() - 47.285_233_166_666_67).abs() < 1e-12);
/// # Ok::<(), drivers::gps::ParseError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Gga {
    /// UTC time of day of the fix, if present.
    pub time_of_day_ms: Option<TimeOfDayMs>,
    /// Fix quality (field 6).
    pub quality: FixQuality,
    /// Latitude, degrees north positive.
    pub latitude_deg: Option<Coordinate>,
    /// Longitude, degrees east positive.
    pub longitude_deg: Option<Coordinate>,
    /// Altitude above mean sea level, metres.
    pub altitude_m: Option<f32>,
    /// Satellites used.
    pub satellites: Option<u8>,
}

/// What an RMC sentence says.
///
/// ```
/// use drivers::gps::{parse_sentence, Sentence};
/// use drivers::time::DateTime;
///
/// // u-blox NEO-6 protocol specification, RMC example: 2002-12-09 08:35:59,
/// // 47°17.11437' N, 8°33.91522' E.
/// let s = parse_sentence("$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A*57")?;
/// let Sentence::Rmc(rmc) = s else { unreachable!() };
/// assert!(rmc.valid);
/// assert_eq!(rmc.utc, Some(DateTime::new(2002, 12, 9, 8, 35, 59)?));
/// assert!((rmc.longitude_deg.unwrap().deg::<f64>() - (8.0 + 33.91522 / 60.0)).abs() < 1e-12);
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Rmc {
    /// UTC time of day, if present.
    pub time_of_day_ms: Option<TimeOfDayMs>,
    /// Date and time together, when both fields are present and valid.
    pub utc: Option<DateTime>,
    /// Status `A` (or `D`, differential) rather than `V`.
    pub valid: bool,
    /// Latitude, degrees north positive.
    pub latitude_deg: Option<Coordinate>,
    /// Longitude, degrees east positive.
    pub longitude_deg: Option<Coordinate>,
}

/// A checksum-verified sentence, classified.
///
/// ```
/// use drivers::gps::{parse_sentence, Sentence};
///
/// // A GSV (satellites in view; checksum 0x79 computed in Python): well
/// // framed but of no use to the fix.
/// assert_eq!(parse_sentence("$GPGSV,1,1,00*79")?, Sentence::Other);
/// assert!(matches!(parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B")?, Sentence::Gga(_)));
/// # Ok::<(), drivers::gps::ParseError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Sentence {
    /// GGA from any talker.
    Gga(Gga),
    /// RMC from any talker.
    Rmc(Rmc),
    /// Any other well-framed sentence (GSV, GSA, VTG, TXT, proprietary...).
    Other,
}

/// A GGA or RMC sentence that could not be read, or whose content is
/// impossible (see the module docs).
///
/// ```
/// use drivers::gps::{parse_sentence, ParseError};
///
/// // RMC with 30 February 2023 as its date (checksum 0x5C computed in
/// // Python): right checksum, impossible content.
/// let s = "$GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,300223,,,A*5C";
/// assert_eq!(parse_sentence(s), Err(ParseError));
/// assert_eq!(ParseError.to_string(), "unparsable or impossible GGA/RMC sentence");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ParseError;

impl core::fmt::Display for ParseError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("unparsable or impossible GGA/RMC sentence")
    }
}

impl core::error::Error for ParseError {}

/// Minute decimals of a latitude or longitude that are read; more are checked
/// to be digits and dropped (10⁻¹¹ minute is below 2·10⁻¹³°): a
/// [`Coordinate`]'s unit.
pub(crate) const MINUTE_DECIMALS: usize = 11;

/// Altitude decimals that are read (a nanometre); more are dropped.
pub(crate) const ALTITUDE_DECIMALS: usize = 9;

/// A UTC time of day as NMEA gives it, to the millisecond.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Hms {
    hour: u8,
    minute: u8,
    second: u8,
    millis: u16,
}

impl Hms {
    fn time_of_day_ms(self) -> TimeOfDayMs {
        let seconds =
            (u32::from(self.hour) * 60 + u32::from(self.minute)) * 60 + u32::from(self.second);
        seconds * 1000 + u32::from(self.millis)
    }
}

/// An RMC date `ddmmyy`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Ymd {
    year: u16,
    month: u8,
    day: u8,
}

fn to_datetime(date: Ymd, time: Hms) -> Option<DateTime> {
    DateTime::new(
        date.year,
        date.month,
        date.day,
        time.hour,
        time.minute,
        time.second,
    )
    .and_then(|dt| dt.with_millis(time.millis))
    .ok()
}

/// Classifies and parses one sentence as returned by the assembler
/// (`$` through `*hh`, no CR LF).
///
/// The framing is checked again as the assembler checks it (at most
/// [`MAX_SENTENCE_LEN`] characters, `*hh` at the end, checksum right), so a
/// sentence given here by other means is held to the same rules.
///
/// ```
/// use drivers::gps::{parse_sentence, ParseError, Sentence};
///
/// // u-blox NEO-6 protocol specification, GGA example.
/// let Sentence::Gga(gga) = parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B")? else { unreachable!() };
/// assert_eq!(gga.time_of_day_ms, Some(34_045_000));
/// // The same sentence with a wrong checksum, and with a latitude of 91°
/// // (checksum right: 0x55, computed in Python).
/// assert_eq!(
///     parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5C"),
///     Err(ParseError)
/// );
/// assert_eq!(
///     parse_sentence("$GPGGA,092725.00,9100.00000,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*55"),
///     Err(ParseError)
/// );
/// # Ok::<(), ParseError>(())
/// ```
// Not inlined on the AVR: its fields would join the reader's stack frame,
// and a slot more than 63 bytes from the AVR's frame pointer costs six more
// instructions at every access.
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn parse_sentence(sentence: &str) -> Result<Sentence, ParseError> {
    // "$" + 2-character talker + 3-character type.
    let (kind, table, required): (_, &[Field], _) =
        match sentence.get(3..6).ok_or(ParseError)?.as_bytes() {
            b"GGA" => (Kind::Gga, &GGA_FIELDS, GGA_REQUIRED_FIELDS),
            b"RMC" => (Kind::Rmc, &RMC_FIELDS, RMC_REQUIRED_FIELDS),
            _ => return Ok(Sentence::Other),
        };
    let bytes = sentence.as_bytes();
    if bytes.len() > MAX_SENTENCE_LEN || check_framing(bytes).is_err() {
        return Err(ParseError);
    }
    // The framing check leaves `$`, the body, and `*hh` (no other `*`).
    let body = bytes
        .get(1..bytes.len().saturating_sub(3))
        .ok_or(ParseError)?;
    let mut reading = Reading::default();
    if read_fields(table, body, &mut reading) < required {
        return Err(ParseError);
    }
    reading.sentence(kind)
}

/// What a field of a GGA or RMC must be, and what is read from it; the
/// rules are those of the `plausible` module's documentation (rule 1) and of
/// the `nmea` crate (this module's documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Field {
    /// Not read: only the non-finite rule applies (units of separation,
    /// mode, navigational status, fields past the last one listed).
    Other,
    /// The address, talker and type: exactly 5 characters.
    Address,
    /// `hhmmss[.s…]`, UTC time of day.
    Time,
    /// `ddmm[.m…]`, at most 90°.
    Latitude,
    /// `N` or `S`.
    NorthSouth,
    /// `dddmm[.m…]`, at most 180°.
    Longitude,
    /// `E` or `W`, of the longitude.
    EastWest,
    /// GGA quality: exactly one digit `0`..=`8`, never empty.
    Quality,
    /// Digits fitting a `u32`, saturated to 255.
    Satellites,
    /// Digits only.
    Count,
    /// `x[.x…]` without a sign.
    Unsigned,
    /// `[+-]x[.x…]`.
    Signed,
    /// `[+-]x[.x…]` metres, the integer part fitting a `u32`.
    Altitude,
    /// Empty or `M`.
    AltitudeUnit,
    /// RMC status `A`, `D` or `V`, never empty.
    Status,
    /// `ddmmyy` naming a day that exists.
    Date,
    /// `x[.x…]` without a sign; when present, so is its side.
    Variation,
    /// `E` or `W`, of the magnetic variation.
    VariationSide,
}

/// GGA fields in NMEA 0183 order.
const GGA_FIELDS: [Field; 15] = [
    Field::Address,      // e.g. GPGGA
    Field::Time,         // 1: UTC of position
    Field::Latitude,     // 2: latitude
    Field::NorthSouth,   // 3: N/S
    Field::Longitude,    // 4: longitude
    Field::EastWest,     // 5: E/W
    Field::Quality,      // 6: GPS quality indicator 0..8
    Field::Satellites,   // 7: number of satellites in use
    Field::Unsigned,     // 8: horizontal dilution of precision
    Field::Altitude,     // 9: antenna altitude above/below mean sea level
    Field::AltitudeUnit, // 10: units of altitude, M
    Field::Signed,       // 11: geoidal separation
    Field::Other,        // 12: units of separation, M
    Field::Unsigned,     // 13: age of differential GPS data, seconds
    Field::Count,        // 14: differential reference station ID
];

/// Fields a GGA must have: the address and fields 1..=12.
const GGA_REQUIRED_FIELDS: usize = 13;

/// RMC fields in NMEA 0183 order.
const RMC_FIELDS: [Field; 14] = [
    Field::Address,       // e.g. GPRMC
    Field::Time,          // 1: UTC of position fix
    Field::Status,        // 2: status, A valid / V navigation receiver warning
    Field::Latitude,      // 3: latitude
    Field::NorthSouth,    // 4: N/S
    Field::Longitude,     // 5: longitude
    Field::EastWest,      // 6: E/W
    Field::Unsigned,      // 7: speed over ground, knots
    Field::Unsigned,      // 8: course over ground, degrees true
    Field::Date,          // 9: date ddmmyy
    Field::Variation,     // 10: magnetic variation, degrees
    Field::VariationSide, // 11: E/W of the variation
    Field::Other,         // 12: mode indicator (NMEA 2.3)
    Field::Other,         // 13: navigational status (NMEA 4.1)
];

/// Fields an RMC must have: the address and fields 1..=11.
const RMC_REQUIRED_FIELDS: usize = 12;

/// What the fields read so far say.
#[derive(Default)]
struct Reading {
    time: Option<Hms>,
    /// Latitude and longitude in 10⁻¹¹ arc-minutes, signed once their
    /// hemisphere is read.
    latitude: i64,
    longitude: i64,
    /// How many of the four position fields are present.
    position_fields: u8,
    quality: FixQuality,
    satellites: Option<u8>,
    altitude_m: Option<f32>,
    valid: bool,
    date: Option<Ymd>,
    variation: bool,
    variation_side: bool,
}

/// Reads every field of a GGA or RMC body (between `$` and `*`) in one
/// pass into `reading`, checking each by its [`Field`] rule. The number of
/// fields read, 0 when one breaks its rule.
// Out of line on the AVR, as `read_field` and `Reading::sentence`: each
// keeps a frame within the 63 bytes `ldd`/`std` reach (one function with
// the reading in its frame spent 232 B more on slots beyond).
#[cfg_attr(target_arch = "avr", inline(never))]
fn read_fields(table: &[Field], body: &[u8], reading: &mut Reading) -> usize {
    let mut count = 0;
    let mut rest = Some(body);
    while let Some(text) = rest {
        let (field_text, after) = split_at(text, b',');
        rest = after;
        let field = table.get(count).copied().unwrap_or(Field::Other);
        if read_field(field, field_text, reading).is_none() {
            return 0;
        }
        // At most MAX_SENTENCE_LEN fields: no overflow.
        count += 1;
    }
    count
}

impl Reading {
    /// The sentence the fields read say, if possible: all of them read, the
    /// position all there or all missing, a variation with its side, and
    /// the values plausible.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn sentence(&self, kind: Kind) -> Result<Sentence, ParseError> {
        if self.variation && !self.variation_side {
            return Err(ParseError);
        }
        // Latitude, N/S, longitude and E/W come together or not at all.
        let (latitude_deg, longitude_deg) = match self.position_fields {
            0 => (None, None),
            4 => (
                Some(Coordinate::from_e11_min(self.latitude)),
                Some(Coordinate::from_e11_min(self.longitude)),
            ),
            _ => return Err(ParseError),
        };
        let time_of_day_ms = self.time.map(Hms::time_of_day_ms);
        let parsed = match kind {
            Kind::Gga => Sentence::Gga(Gga {
                time_of_day_ms,
                quality: self.quality,
                latitude_deg,
                longitude_deg,
                altitude_m: self.altitude_m,
                satellites: self.satellites,
            }),
            Kind::Rmc => Sentence::Rmc(Rmc {
                time_of_day_ms,
                utc: match (self.date, self.time) {
                    (Some(d), Some(t)) => to_datetime(d, t),
                    _ => None,
                },
                valid: self.valid,
                latitude_deg,
                longitude_deg,
            }),
        };
        if sentence_is_plausible(&parsed) {
            Ok(parsed)
        } else {
            Err(ParseError)
        }
    }
}

/// The text before the first `delim`, and the text after it (`None`
/// without one): one step of `split(delim)`, byte by byte (core's `str`
/// pattern code is large on the AVR).
fn split_at(text: &[u8], delim: u8) -> (&[u8], Option<&[u8]>) {
    match text.iter().position(|&b| b == delim) {
        // `at` < text.len(): both ranges are in bounds.
        Some(at) => (text.get(..at).unwrap_or(text), text.get(at + 1..)),
        None => (text, None),
    }
}

/// Checks one field by its rule and keeps what it says; `None` when the
/// field breaks the rule.
#[cfg_attr(target_arch = "avr", inline(never))]
fn read_field(field: Field, text: &[u8], reading: &mut Reading) -> Option<()> {
    if spells_non_finite(text) {
        return None;
    }
    if text.is_empty() {
        // Only the address, the quality and the status are never empty.
        return match field {
            Field::Address | Field::Quality | Field::Status => None,
            _ => Some(()),
        };
    }
    match field {
        Field::Other => {}
        Field::Address => {
            if text.len() != 5 {
                return None;
            }
        }
        Field::Time => reading.time = Some(parse_time(text)?),
        Field::Latitude => {
            reading.latitude = parse_angle(text, 2, 90)?;
            reading.position_fields += 1;
        }
        Field::NorthSouth => {
            match text {
                b"N" => {}
                b"S" => reading.latitude = -reading.latitude,
                _ => return None,
            }
            reading.position_fields += 1;
        }
        Field::Longitude => {
            reading.longitude = parse_angle(text, 3, 180)?;
            reading.position_fields += 1;
        }
        Field::EastWest => {
            match text {
                b"E" => {}
                b"W" => reading.longitude = -reading.longitude,
                _ => return None,
            }
            reading.position_fields += 1;
        }
        Field::Quality => reading.quality = parse_quality(text)?,
        Field::Satellites => {
            let count = digits_value(text)?;
            reading.satellites = Some(u8::try_from(count).unwrap_or(u8::MAX));
        }
        Field::Count => {
            if !text.iter().all(u8::is_ascii_digit) {
                return None;
            }
        }
        Field::Unsigned => {
            split_decimal(text)?;
        }
        Field::Signed => {
            split_decimal(split_sign(text).1)?;
        }
        Field::Altitude => reading.altitude_m = Some(parse_altitude(text)?),
        Field::AltitudeUnit => {
            if text != b"M" {
                return None;
            }
        }
        Field::Status => {
            reading.valid = match text {
                b"A" | b"D" => true,
                b"V" => false,
                _ => return None,
            }
        }
        Field::Date => reading.date = Some(parse_date(text)?),
        Field::Variation => {
            split_decimal(text)?;
            reading.variation = true;
        }
        Field::VariationSide => {
            if !matches!(text, b"E" | b"W") {
                return None;
            }
            reading.variation_side = true;
        }
    }
    Some(())
}

/// `nan`, `inf`, `infinity` in any case, with or without a sign: what
/// floating-point parsers take as non-finite (rule 1 of the `plausible`
/// module, for every field).
fn spells_non_finite(text: &[u8]) -> bool {
    let unsigned = split_sign(text).1;
    let prefix = unsigned.get(..3).unwrap_or(unsigned);
    prefix.eq_ignore_ascii_case(b"nan") || prefix.eq_ignore_ascii_case(b"inf")
}

/// `text` without one leading `-` or `+`, and whether that was a `-`.
fn split_sign(text: &[u8]) -> (bool, &[u8]) {
    match text.split_first() {
        Some((&sign @ (b'-' | b'+'), rest)) => (sign == b'-', rest),
        _ => (false, text),
    }
}

/// Splits `digits[.digits]` into its integer and fraction digits (the
/// fraction empty without a point). No sign, no exponent, at least one digit
/// each side of a point.
fn split_decimal(text: &[u8]) -> Option<(&[u8], &[u8])> {
    // One pass: digits, and at most one point (checked byte by byte; a
    // split and two digit scans were larger on the AVR).
    let mut point = None;
    for (at, &b) in text.iter().enumerate() {
        if b == b'.' && point.is_none() {
            point = Some(at);
        } else if !b.is_ascii_digit() {
            return None;
        }
    }
    let (int, frac) = match point {
        // `at` < text.len(): both ranges are in bounds.
        Some(at) => (text.get(..at)?, text.get(at + 1..)?),
        None => (text, &[][..]),
    };
    if int.is_empty() || (point.is_some() && frac.is_empty()) {
        return None;
    }
    Some((int, frac))
}

/// Value of a digit string (digits only, may be empty: 0); `None` on a
/// non-digit or when it does not fit a `u32` (every integer field does; on
/// an 8-bit core checked 64-bit arithmetic costs several times more code).
fn digits_value(text: &[u8]) -> Option<u32> {
    // acc · 10 + digit fits a u32 when acc < ⌊u32::MAX / 10⌋, or equals it
    // and digit ≤ u32::MAX mod 10: tested before, not by a checked
    // multiply (a 64-bit product on the AVR, two library calls).
    const LIMIT: u32 = u32::MAX / 10;
    let mut acc: u32 = 0;
    for &b in text {
        let digit = u32::from(b.wrapping_sub(b'0'));
        if digit > 9 || acc > LIMIT || (acc == LIMIT && digit > u32::MAX % 10) {
            return None;
        }
        acc = acc * 10 + digit;
    }
    Some(acc)
}

/// Value of the two digits at `at`; `None` unless both are there and digits.
fn two_digits(text: &[u8], at: usize) -> Option<u8> {
    let tens = text.get(at)?.wrapping_sub(b'0');
    let ones = text.get(at.checked_add(1)?)?.wrapping_sub(b'0');
    // Each at most 9 once checked: at most 99.
    (tens <= 9 && ones <= 9).then(|| tens * 10 + ones)
}

/// `acc` followed by the first `places` digits of `digits` (zeros past its
/// end): `acc · 10^places + value(digits[..k]) · 10^(places − k)`. The one
/// place of 64-bit arithmetic of the reader (an exact latitude, longitude
/// or altitude mantissa needs more than 32 bits), out of line so that the
/// AVR has it once. `digits` must be ASCII digits; the callers keep the
/// result below 2⁶³ (at most 4.3·10⁹ · 10⁹).
#[cfg_attr(target_arch = "avr", inline(never))]
fn append_digits(acc: u64, digits: &[u8], places: usize) -> u64 {
    (0..places).fold(acc, |value, i| {
        let digit = digits.get(i).map_or(0, |b| b.wrapping_sub(b'0'));
        value * 10 + u64::from(digit)
    })
}

/// `hhmmss[.s…]`: hour < 24, minute < 60, second < 60.
fn parse_time(text: &[u8]) -> Option<Hms> {
    let (int, frac) = split_decimal(text)?;
    if int.len() != 6 {
        return None;
    }
    let (hour, minute, second) = (
        two_digits(int, 0)?,
        two_digits(int, 2)?,
        two_digits(int, 4)?,
    );
    if hour >= 24 || minute >= 60 || second >= 60 {
        return None;
    }
    // The fraction to the nanosecond (below 10⁹: fits a u32), rounded half
    // up on the tenth digit.
    let mut nanos = u32::try_from(append_digits(0, frac, 9)).ok()?;
    if frac.get(9).is_some_and(|d| *d >= b'5') {
        nanos += 1;
    }
    let millis = if nanos < 1_000_000_000 {
        nanos / 1_000_000
    } else if second == 59 {
        // Rounded up into the next second: chrono (behind the old parser)
        // took that as the leap second 59.999…; only there is it accepted.
        999
    } else {
        return None;
    };
    Some(Hms {
        hour,
        minute,
        second,
        millis: u16::try_from(millis).ok()?,
    })
}

/// Degrees and minutes `d…dmm[.m…]` with exactly `degree_digits` degree
/// digits, at most `max_deg` degrees and minutes below 60, in 10⁻¹¹
/// arc-minutes (exact: at most 999·60·10¹¹ < 2⁶³). Beyond `max_deg` with
/// minutes is left to the value check (90°00.0' is a latitude, 90°00.1' is
/// not).
fn parse_angle(text: &[u8], degree_digits: usize, max_deg: u32) -> Option<i64> {
    let (int, frac) = split_decimal(text)?;
    if int.len() != degree_digits + 2 {
        return None;
    }
    let degrees = digits_value(int.get(..degree_digits)?)?;
    let minutes = u32::from(two_digits(int, degree_digits)?);
    if degrees > max_deg || minutes >= 60 {
        return None;
    }
    // Whole minutes ≤ 999·60 + 59, then [`MINUTE_DECIMALS`] decimals.
    let e11_min = append_digits(u64::from(degrees * 60 + minutes), frac, MINUTE_DECIMALS);
    i64::try_from(e11_min).ok()
}

/// `[+-]digits[.digits]`, metres.
fn parse_altitude(text: &[u8]) -> Option<f32> {
    let (negative, unsigned) = split_sign(text);
    let (int, frac) = split_decimal(unsigned)?;
    let places = frac.len().min(ALTITUDE_DECIMALS);
    // An integer part beyond u32 is far outside the plausible range; below
    // it, int · 10⁹ + decimals < 4.3·10¹⁸ < 2⁶³.
    let mantissa = append_digits(u64::from(digits_value(int)?), frac, places);
    let scale = append_digits(1, &[], places);
    // The f32 nearest mantissa / scale, rounded once from the integers.
    let value = f32::from_ratio(i64::try_from(mantissa).ok()?, scale);
    Some(if negative { -value } else { value })
}

/// GGA field 6: exactly one digit 0..=8.
fn parse_quality(text: &[u8]) -> Option<FixQuality> {
    let [digit] = text else {
        return None;
    };
    // By the digit's value, not by string compares: one range check.
    Some(match digit.wrapping_sub(b'0') {
        0 => FixQuality::Invalid,
        1 => FixQuality::Gps,
        2 => FixQuality::Dgps,
        3 => FixQuality::Pps,
        4 => FixQuality::Rtk,
        5 => FixQuality::FloatRtk,
        6 => FixQuality::Estimated,
        7 => FixQuality::Manual,
        8 => FixQuality::Simulation,
        _ => return None,
    })
}

/// `ddmmyy` naming a day that exists; years 83..=99 are 1983..=1999 (NMEA 0183
/// appeared in 1983), the others 2000..=2082.
fn parse_date(text: &[u8]) -> Option<Ymd> {
    if text.len() != 6 {
        return None;
    }
    let (day, month, yy) = (
        two_digits(text, 0)?,
        two_digits(text, 2)?,
        two_digits(text, 4)?,
    );
    let year = if yy >= 83 {
        1900 + u16::from(yy)
    } else {
        2000 + u16::from(yy)
    };
    if !(1..=12).contains(&month) || day == 0 || day > days_in_month(year, month) {
        return None;
    }
    Some(Ymd { year, month, day })
}

/// Whether a GGA's or RMC's values are possible: finite, latitude within ±90°,
/// longitude within ±180°, altitude within −500..=20,000 m, time of day below
/// 24 h. [`Sentence::Other`] is always plausible.
pub(crate) fn sentence_is_plausible(sentence: &Sentence) -> bool {
    match sentence {
        Sentence::Gga(g) => gga_is_plausible(g),
        Sentence::Rmc(r) => rmc_is_plausible(r),
        Sentence::Other => true,
    }
}

#[cfg(test)]
mod differential;

#[cfg(test)]
mod tests {
    extern crate std;

    use std::format;
    use std::string::String;

    use super::super::assembler::nmea_checksum;
    use super::*;

    fn frame(body: &str) -> String {
        format!("${body}*{:02X}", nmea_checksum(body.as_bytes()))
    }

    fn gga(fields: &str) -> Result<Gga, ParseError> {
        match parse_sentence(&frame(&format!("GPGGA,{fields}")))? {
            Sentence::Gga(g) => Ok(g),
            other => panic!("{other:?}"),
        }
    }

    fn rmc(fields: &str) -> Result<Rmc, ParseError> {
        match parse_sentence(&frame(&format!("GNRMC,{fields}")))? {
            Sentence::Rmc(r) => Ok(r),
            other => panic!("{other:?}"),
        }
    }

    /// A GGA with this latitude and longitude (and their hemispheres).
    fn position(lat: &str, ns: &str, lon: &str, ew: &str) -> Result<(f64, f64), ParseError> {
        let g = gga(&format!(
            "120000,{lat},{ns},{lon},{ew},1,08,0.9,10.0,M,0.0,M,,"
        ))?;
        Ok((
            g.latitude_deg.unwrap().deg(),
            g.longitude_deg.unwrap().deg(),
        ))
    }

    #[test]
    fn full_gga() {
        let g = gga("033745.25,5650.82344,N,03548.9778,W,2,07,1.8,-101.2,M,14.7,M,,0000").unwrap();
        assert_eq!(
            g.time_of_day_ms,
            Some(((3 * 60 + 37) * 60 + 45) * 1000 + 250)
        );
        assert_eq!(g.quality, FixQuality::Dgps);
        assert_eq!(g.satellites, Some(7));
        assert_eq!(g.altitude_m, Some(-101.2));
        assert_eq!(
            g.latitude_deg.map(|c| c.deg::<f64>()),
            Some(56.0 + 50.82344 / 60.0)
        );
        assert_eq!(
            g.longitude_deg.map(|c| c.deg::<f64>()),
            Some(-(35.0 + 48.9778 / 60.0))
        );
    }

    #[test]
    fn full_rmc() {
        let r = rmc("225446.33,D,4916.45,S,12311.12,E,000.5,054.7,191194,020.3,E,D,V").unwrap();
        assert!(r.valid);
        assert_eq!(
            r.time_of_day_ms,
            Some(((22 * 60 + 54) * 60 + 46) * 1000 + 330)
        );
        let utc = DateTime::new(1994, 11, 19, 22, 54, 46)
            .unwrap()
            .with_millis(330)
            .unwrap();
        assert_eq!(r.utc, Some(utc));
        assert_eq!(
            r.latitude_deg.map(|c| c.deg::<f64>()),
            Some(-(49.0 + 16.45 / 60.0))
        );
        assert_eq!(
            r.longitude_deg.map(|c| c.deg::<f64>()),
            Some(123.0 + 11.12 / 60.0)
        );
        // NMEA 2.0 (no mode) and 2.3 (mode, no navigational status) lengths.
        assert!(rmc("225446,A,4916.45,N,12311.12,W,0.5,54.7,191194,,").is_ok());
        assert!(rmc("225446,V,,,,,,,191194,,,N").is_ok_and(|r| !r.valid));
    }

    #[test]
    fn talkers_are_not_restricted() {
        for talker in ["GP", "GN", "GL", "GA", "BD", "GB", "QZ"] {
            let s = frame(&format!(
                "{talker}GGA,120000,3734.002,N,12658.998,E,1,08,,,,,,,"
            ));
            assert!(matches!(parse_sentence(&s), Ok(Sentence::Gga(_))), "{s}");
        }
        for other in [
            "GPGSV,1,1,00",
            "GPVTG,,T,,M,,N,,K,N",
            "PUBX,00",
            "GPTXT,01,01,02,ANT",
        ] {
            assert_eq!(
                parse_sentence(&frame(other)),
                Ok(Sentence::Other),
                "{other}"
            );
        }
        // The address is 2 + 3 characters.
        assert_eq!(
            parse_sentence(&frame("GPGGAX,120000,,,,,0,,,,,,,,")),
            Err(ParseError)
        );
    }

    #[test]
    fn framing_is_checked_again() {
        let good = frame("GPGGA,120000,,,,,0,00,,,,,,,");
        assert!(parse_sentence(&good).is_ok());
        let body = "GPGGA,120000,,,,,0,00,,,,,,,";
        let bad_sum = format!("${body}*{:02X}", nmea_checksum(body.as_bytes()) ^ 1);
        assert_eq!(parse_sentence(&bad_sum), Err(ParseError));
        assert_eq!(parse_sentence(&format!("{good}\r\n")), Err(ParseError));
        assert_eq!(
            parse_sentence("$GPGGA,120000,,,,,0,00,,,,,,,"),
            Err(ParseError)
        );
        let long = frame(&format!("GPGGA,120000,,,,,0,00,,,,,,,{}", "0".repeat(60)));
        assert_eq!(parse_sentence(&long), Err(ParseError));
    }

    #[test]
    fn latitude_and_longitude() {
        let (lat, lon) = position("3734.00200", "N", "12658.99800", "E").unwrap();
        assert_eq!(lat, 37.0 + 34.002 / 60.0);
        assert_eq!(lon, 126.0 + 58.998 / 60.0);
        // Integers only, and the limits: 90° and 180° exactly, minutes 59.9999.
        assert_eq!(
            position("3734", "S", "12658", "W").unwrap(),
            (-(37.0 + 34.0 / 60.0), -(126.0 + 58.0 / 60.0))
        );
        assert_eq!(
            position("9000.0000", "N", "18000.0000", "W").unwrap(),
            (90.0, -180.0)
        );
        assert_eq!(
            position("0000.0000", "S", "00000.0", "E").unwrap(),
            (0.0, 0.0)
        );
        let (lat, lon) = position("8959.9999", "N", "17959.9999", "E").unwrap();
        assert_eq!(lat, 89.0 + 59.9999 / 60.0);
        assert_eq!(lon, 179.0 + 59.9999 / 60.0);
        // Eleven minute decimals are read, more are dropped.
        let (lat, _) = position("1234.56789012345678", "N", "00000.0", "E").unwrap();
        assert_eq!(lat, 12.0 + 34.56789012345 / 60.0);
        // Beyond the poles and the antimeridian, minutes of 60, wrong widths.
        for (lat, lon) in [
            ("9000.0001", "00000.0"),
            ("9100.0", "00000.0"),
            ("0000.0", "18000.0001"),
            ("0000.0", "18100.0"),
            ("3760.0000", "00000.0"),
            ("0000.0", "00060.0"),
            ("373.4", "00000.0"),
            ("03734.0", "00000.0"),
            ("0000.0", "0000.0"),
            ("0000.0", "000000.0"),
        ] {
            assert_eq!(position(lat, "N", lon, "E"), Err(ParseError), "{lat} {lon}");
        }
    }

    #[test]
    fn malformed_numbers_are_errors() {
        for lat in [
            "37a4.0", "3734.0a", "+3734.0", "-3734.0", "3734.", ".3734", "37.34e2", "3734..0",
            "3734.0.0", "nan", "inf", " 3734.0",
        ] {
            assert_eq!(position(lat, "N", "00000.0", "E"), Err(ParseError), "{lat}");
        }
        for alt in [
            "1e3", "12.", ".5", "--1", "+-1", "1.2.3", "nan", "-inf", "12 ", "0x10",
        ] {
            let g = gga(&format!("120000,,,,,0,00,,{alt},M,,,,"));
            assert_eq!(g, Err(ParseError), "{alt}");
        }
        for sats in [
            "+8",
            "-1",
            "8.0",
            "0x8",
            "4294967296",
            "99999999999999999999999",
        ] {
            assert_eq!(
                gga(&format!("120000,,,,,0,{sats},,,,,,,")),
                Err(ParseError),
                "{sats}"
            );
        }
    }

    #[test]
    fn hemispheres_exactly_as_before() {
        // The old parser (nmea's one_of("NS")/one_of("EW"), and check_fields
        // before it) took only capitals; so does this one.
        for (ns, ew) in [
            ("n", "E"),
            ("N", "e"),
            ("s", "W"),
            ("S", "w"),
            ("X", "E"),
            ("N", "Q"),
            ("NN", "E"),
        ] {
            assert_eq!(
                position("3734.0", ns, "12658.0", ew),
                Err(ParseError),
                "{ns} {ew}"
            );
        }
    }

    #[test]
    fn empty_fields() {
        // No fix: the four position fields empty, and everything optional empty.
        let g = gga(",,,,,0,,,,,,,,").unwrap();
        assert_eq!(g, Gga::default());
        let r = rmc(",V,,,,,,,,,,N").unwrap();
        assert_eq!(r, Rmc::default());
        // Some of the four position fields only: error.
        for fields in ["3734.0,N,,", ",,12658.0,E", "3734.0,N,12658.0,", ",N,,"] {
            assert_eq!(
                gga(&format!("120000,{fields},1,08,,,,,,,")),
                Err(ParseError),
                "{fields}"
            );
        }
        // A date without a time, or a time without a date: no date-time.
        let r = rmc("120000,A,,,,,,,,,").unwrap();
        assert_eq!((r.time_of_day_ms, r.utc), (Some(43_200_000), None));
        let r = rmc(",A,,,,,,,150624,,").unwrap();
        assert_eq!((r.time_of_day_ms, r.utc), (None, None));
    }

    #[test]
    fn required_fields_and_letters() {
        // Quality exactly one digit 0..=8 (it is not optional).
        for q in ["", "9", "10", "01", "A"] {
            assert_eq!(
                gga(&format!("120000,,,,,{q},00,,,,,,,")),
                Err(ParseError),
                "{q}"
            );
        }
        for (q, quality) in [
            ("0", FixQuality::Invalid),
            ("4", FixQuality::Rtk),
            ("8", FixQuality::Simulation),
        ] {
            assert_eq!(
                gga(&format!("120000,,,,,{q},00,,,,,,,")).unwrap().quality,
                quality
            );
        }
        // Altitude unit empty or M; GGA up to field 12, RMC up to field 11.
        assert_eq!(gga("120000,,,,,1,08,,12.0,F,,,,"), Err(ParseError));
        assert!(gga("120000,,,,,1,08,,12.0,M,,").is_ok());
        assert_eq!(gga("120000,,,,,1,08,,12.0,M,"), Err(ParseError));
        assert!(rmc("120000,A,,,,,,,150624,,").is_ok());
        assert_eq!(rmc("120000,A,,,,,,,150624,"), Err(ParseError));
        // RMC status A, D or V; a magnetic variation needs its side.
        for status in ["", "a", "X", "AV"] {
            assert_eq!(
                rmc(&format!("120000,{status},,,,,,,150624,,")),
                Err(ParseError),
                "{status}"
            );
        }
        assert!(rmc("120000,A,,,,,,,150624,3.1,W").is_ok());
        assert_eq!(rmc("120000,A,,,,,,,150624,3.1,"), Err(ParseError));
        assert!(rmc("120000,A,,,,,,,150624,,W").is_ok());
    }

    #[test]
    fn satellites_saturate() {
        let sats = |s: &str| gga(&format!("120000,,,,,1,{s},,,,,,,")).unwrap().satellites;
        assert_eq!(sats(""), None);
        assert_eq!(sats("00"), Some(0));
        assert_eq!(sats("255"), Some(255));
        assert_eq!(sats("256"), Some(255));
        assert_eq!(sats("4294967295"), Some(255));
        assert_eq!(sats("0000000000000000000012"), Some(12));
    }

    #[test]
    fn altitudes() {
        let alt = |a: &str| gga(&format!("120000,,,,,1,08,,{a},M,,,,")).map(|g| g.altitude_m);
        assert_eq!(alt(""), Ok(None));
        assert_eq!(alt("38.5"), Ok(Some(38.5)));
        assert_eq!(alt("+38.7"), Ok(Some(38.7)));
        assert_eq!(alt("-500"), Ok(Some(-500.0)));
        assert_eq!(alt("20000.0"), Ok(Some(20_000.0)));
        assert_eq!(alt("-0.0"), Ok(Some(-0.0)));
        // Out of range (the value check), overflowing digits (the reader).
        assert_eq!(alt("-500.1"), Err(ParseError));
        assert_eq!(alt("20000.01"), Err(ParseError));
        assert_eq!(alt("99999999999999999999"), Err(ParseError));
        // Nine decimals are read, more are dropped.
        assert_eq!(alt("1.0000000001"), Ok(Some(1.0)));
    }

    #[test]
    fn altitudes_are_correctly_rounded() {
        // Every altitude of the plausible range to the decimetre, and strides
        // of those to the centimetre and millimetre, equal str::parse::<f32>,
        // which the old parser used.
        for (decimals, step) in [(1u32, 1usize), (2, 7), (3, 71)] {
            let scale = 10i64.pow(decimals);
            for m in (-500 * scale..=20_000 * scale).step_by(step) {
                let text = format!(
                    "{}{}.{:0width$}",
                    if m < 0 { "-" } else { "" },
                    m.abs() / scale,
                    m.abs() % scale,
                    width = decimals as usize
                );
                assert_eq!(
                    parse_altitude(text.as_bytes()),
                    Some(text.parse::<f32>().unwrap()),
                    "{text}"
                );
            }
        }
    }

    #[test]
    fn times() {
        let ms = |t: &str| gga(&format!("{t},,,,,0,,,,,,,,")).map(|g| g.time_of_day_ms);
        assert_eq!(ms(""), Ok(None));
        assert_eq!(ms("000000"), Ok(Some(0)));
        assert_eq!(ms("235959.999"), Ok(Some(86_399_999)));
        assert_eq!(ms("123456.7"), Ok(Some(45_296_700)));
        assert_eq!(ms("123456.9999"), Ok(Some(45_296_999)));
        // Rounded to the nanosecond, as the old parser did: into the next second
        // only with ten nines, an error except in second 59 (read as 59.999).
        assert_eq!(ms("123456.999999999"), Ok(Some(45_296_999)));
        assert_eq!(ms("123456.9999999995"), Err(ParseError));
        assert_eq!(ms("123459.9999999995"), Ok(Some(45_299_999)));
        for bad in [
            "240000", "236000", "235960", "235961", "12345", "1234567", "123456.", "12:34:56",
            "+23456", "1234a6",
        ] {
            assert_eq!(ms(bad), Err(ParseError), "{bad}");
        }
    }

    #[test]
    fn dates() {
        let utc = |d: &str| rmc(&format!("120000,A,,,,,,,{d},,")).map(|r| r.utc);
        let day = |y, m, d| Some(DateTime::new(y, m, d, 12, 0, 0).unwrap());
        assert_eq!(utc("150624"), Ok(day(2024, 6, 15)));
        assert_eq!(utc("290224"), Ok(day(2024, 2, 29)));
        assert_eq!(utc("010183"), Ok(day(1983, 1, 1)));
        assert_eq!(utc("311299"), Ok(day(1999, 12, 31)));
        assert_eq!(utc("311282"), Ok(day(2082, 12, 31)));
        assert_eq!(utc(""), Ok(None));
        for bad in [
            "290223", "300224", "310624", "000624", "150024", "151324", "15062", "1506244",
            "15o624",
        ] {
            assert_eq!(utc(bad), Err(ParseError), "{bad}");
        }
    }

    #[test]
    fn digit_helpers() {
        assert_eq!(digits_value(b""), Some(0));
        assert_eq!(digits_value(b"4294967295"), Some(u32::MAX));
        assert_eq!(digits_value(b"4294967296"), None);
        assert_eq!(digits_value(b"1a"), None);
        assert_eq!(two_digits(b"1234", 2), Some(34));
        assert_eq!(
            (two_digits(b"123", 2), two_digits(b"1x34", 0)),
            (None, None)
        );
        // 11 decimals read, zeros appended, digits past them not read.
        assert_eq!(append_digits(0, b"99999999999", 11), 99_999_999_999);
        assert_eq!(append_digits(0, b"0000000000159", 11), 1);
        assert_eq!(append_digits(0, b"", 11), 0);
        assert_eq!(append_digits(59_999, b"5", 11), 5_999_950_000_000_000);
        assert_eq!(
            (append_digits(1, b"", 0), append_digits(1, b"", 11)),
            (1, 100_000_000_000)
        );
        assert_eq!(split_decimal(b"12.50"), Some((&b"12"[..], &b"50"[..])));
        assert_eq!(split_decimal(b"12"), Some((&b"12"[..], &b""[..])));
        for bad in ["", ".", "1.", ".1", "1..2", "-1", "1e2", "١٢"] {
            assert_eq!(split_decimal(bad.as_bytes()), None, "{bad}");
        }
        assert_eq!(split_at(b"a,b,c", b','), (&b"a"[..], Some(&b"b,c"[..])));
        assert_eq!(split_at(b"abc", b','), (&b"abc"[..], None));
        assert_eq!(split_at(b",", b','), (&b""[..], Some(&b""[..])));
        assert_eq!(split_sign(b"-1.5"), (true, &b"1.5"[..]));
        assert_eq!(split_sign(b"+-2"), (false, &b"-2"[..]));
        assert_eq!(split_sign(b"3"), (false, &b"3"[..]));
        for s in ["nan", "NaN", "-inf", "+Infinity", "INF", "nAn1"] {
            assert!(spells_non_finite(s.as_bytes()), "{s}");
        }
        for s in ["N", "12.5", "", "-", "na", "in", "−inf"] {
            assert!(!spells_non_finite(s.as_bytes()), "{s}");
        }
    }
}
