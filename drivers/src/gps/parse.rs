//! GGA and RMC contents through the `nmea` crate (no default features, only
//! its `GGA` and `RMC` features, so it stays `no_std`).
//!
//! Only the sentence type is looked at here before handing the whole sentence
//! to `nmea::parse_str`; the talker (GP, GN, GL, GA, BD, ...) is not
//! restricted. Other sentence types (GSV, GSA, VTG, TXT, ...) are
//! [`Sentence::Other`]: valid, but of no use to the fix.
//!
//! A GGA or RMC is checked for possible content both before (the text of its
//! fields) and after (the values) `nmea` reads it; an impossible one is a
//! [`ParseError`] like an unreadable one. The rules (ranges, minutes < 60,
//! calendar dates, no leap second, no `nan`/`inf`) are in the `plausible`
//! module's documentation and in the README.

use chrono::{Datelike, Timelike};
use nmea::sentences::rmc::RmcStatusOfFix;
use nmea::sentences::FixType;
use nmea::ParseResult;

use super::plausible::{check_fields, gga_is_plausible, rmc_is_plausible, Kind};
use crate::time::DateTime;

/// Fix quality, GGA field 6.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
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

impl From<FixType> for FixQuality {
    fn from(f: FixType) -> Self {
        match f {
            FixType::Invalid => FixQuality::Invalid,
            FixType::Gps => FixQuality::Gps,
            FixType::DGps => FixQuality::Dgps,
            FixType::Pps => FixQuality::Pps,
            FixType::Rtk => FixQuality::Rtk,
            FixType::FloatRtk => FixQuality::FloatRtk,
            FixType::Estimated => FixQuality::Estimated,
            FixType::Manual => FixQuality::Manual,
            FixType::Simulation => FixQuality::Simulation,
        }
    }
}

/// Time of day in milliseconds, 0..86_400_000.
pub type TimeOfDayMs = u32;

/// What a GGA sentence says.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Gga {
    /// UTC time of day of the fix, if present.
    pub time_of_day_ms: Option<TimeOfDayMs>,
    /// Fix quality (field 6).
    pub quality: FixQuality,
    /// Latitude, degrees north positive.
    pub latitude_deg: Option<f64>,
    /// Longitude, degrees east positive.
    pub longitude_deg: Option<f64>,
    /// Altitude above mean sea level, metres.
    pub altitude_m: Option<f32>,
    /// Satellites used.
    pub satellites: Option<u8>,
}

/// What an RMC sentence says.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Rmc {
    /// UTC time of day, if present.
    pub time_of_day_ms: Option<TimeOfDayMs>,
    /// Date and time together, when both fields are present and valid.
    pub utc: Option<DateTime>,
    /// Status `A` (or `D`, differential) rather than `V`.
    pub valid: bool,
    /// Latitude, degrees north positive.
    pub latitude_deg: Option<f64>,
    /// Longitude, degrees east positive.
    pub longitude_deg: Option<f64>,
}

/// A checksum-verified sentence, classified.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sentence {
    /// GGA from any talker.
    Gga(Gga),
    /// RMC from any talker.
    Rmc(Rmc),
    /// Any other well-framed sentence (GSV, GSA, VTG, TXT, proprietary...).
    Other,
}

/// A GGA or RMC sentence the `nmea` crate could not parse, or whose content
/// is impossible (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ParseError;

impl core::fmt::Display for ParseError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("unparsable or impossible GGA/RMC sentence")
    }
}

impl core::error::Error for ParseError {}

fn time_of_day_ms(t: &chrono::NaiveTime) -> TimeOfDayMs {
    // chrono encodes a leap second as nanosecond >= 1e9; clamp into the second.
    let millis = (t.nanosecond() / 1_000_000).min(999);
    t.num_seconds_from_midnight() * 1000 + millis
}

fn to_datetime(date: &chrono::NaiveDate, time: &chrono::NaiveTime) -> Option<DateTime> {
    let year = u16::try_from(date.year()).ok()?;
    let month = u8::try_from(date.month()).ok()?;
    let day = u8::try_from(date.day()).ok()?;
    let hour = u8::try_from(time.hour()).ok()?;
    let minute = u8::try_from(time.minute()).ok()?;
    let second = u8::try_from(time.second()).ok()?;
    let millis = u16::try_from((time.nanosecond() / 1_000_000).min(999)).ok()?;
    DateTime::new(year, month, day, hour, minute, second)
        .and_then(|dt| dt.with_millis(millis))
        .ok()
}

/// Classifies and parses one sentence as returned by the assembler
/// (`$` through `*hh`, no CR LF).
pub fn parse_sentence(sentence: &str) -> Result<Sentence, ParseError> {
    // "$" + 2-character talker + 3-character type.
    let kind = match sentence.get(3..6).ok_or(ParseError)? {
        "GGA" => Kind::Gga,
        "RMC" => Kind::Rmc,
        _ => return Ok(Sentence::Other),
    };
    if !check_fields(kind, sentence) {
        return Err(ParseError);
    }
    let parsed = match nmea::parse_str(sentence) {
        Ok(ParseResult::GGA(g)) => Ok(Sentence::Gga(Gga {
            time_of_day_ms: g.fix_time.as_ref().map(time_of_day_ms),
            quality: g.fix_type.map(FixQuality::from).unwrap_or_default(),
            latitude_deg: g.latitude,
            longitude_deg: g.longitude,
            altitude_m: g.altitude,
            satellites: g.fix_satellites.map(|n| u8::try_from(n).unwrap_or(u8::MAX)),
        })),
        Ok(ParseResult::RMC(r)) => Ok(Sentence::Rmc(Rmc {
            time_of_day_ms: r.fix_time.as_ref().map(time_of_day_ms),
            utc: match (r.fix_date.as_ref(), r.fix_time.as_ref()) {
                (Some(d), Some(t)) => to_datetime(d, t),
                _ => None,
            },
            valid: matches!(
                r.status_of_fix,
                RmcStatusOfFix::Autonomous | RmcStatusOfFix::Differential
            ),
            latitude_deg: r.lat,
            longitude_deg: r.lon,
        })),
        _ => Err(ParseError),
    }?;
    if sentence_is_plausible(&parsed) {
        Ok(parsed)
    } else {
        Err(ParseError)
    }
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
