//! Content checks on GGA and RMC sentences whose checksum is right.
//!
//! A checksum only shows that the bytes arrived as they were sent; a sentence
//! can still say something impossible (a receiver bug, a corrupted buffer
//! checksummed afterwards, a spoofer, a hand-written log). Two lines of
//! checks stand between such a sentence and a fix, each enough on its own
//! for the ranges below: the text of every field (rule 1), checked as
//! [`super::parse_sentence`] reads it, and the values read (rule 2), checked
//! after it in [`super::parse_sentence`] and again in [`super::FixFusion`]
//! (which also takes values built by hand), so no path turns such a sentence
//! into a fix.
//!
//! 1. The text of each field, by its NMEA 0183 meaning. These rules were
//!    written for the general floating-point parser of the `nmea` crate the
//!    reader replaced (which took `nan`, `inf`, exponents, signs and minutes
//!    of 60 or more in a latitude). The reader applies them in its one pass
//!    over the fields (`parse::read_field`: one routine per kind of field
//!    checks its text and reads it, so the grammar is written once);
//!    `reference::check_fields`, the same rules as a pass of their own, is kept in
//!    the tests as the reference the reader is compared with
//!    (`parse/differential.rs`):
//!    - UTC time `hhmmss[.s…]`: hour 0..=23, minute 0..=59, second 0..=59. A
//!      leap second (`60`) is rejected: [`crate::time::DateTime`] cannot
//!      represent it, and taking it as `59` or as the next
//!      `00` would give two epochs the same time. At most the one epoch stamped
//!      `23:59:60` is lost when a leap second is inserted (none has been since
//!      2016-12-31);
//!    - latitude `ddmm[.m…]` and longitude `dddmm[.m…]`: exactly 2 and 3 degree
//!      digits and 2 minute digits, minutes below 60, degrees at most 90 and
//!      180, no sign or exponent; hemisphere exactly `N`/`S` and `E`/`W`; the
//!      four fields all present or all empty;
//!    - date `ddmmyy`: a day that exists in that month (years `83`..`99` are
//!      1983..1999, the others 2000..2082, as the reader takes them);
//!    - counts (quality, satellites, station ID): digits only;
//!    - decimals (HDOP, altitude, geoid separation, age of differential data,
//!      speed, course, magnetic variation): digits with an optional fraction,
//!      a sign only on altitude and geoid separation;
//!    - any field at all, also past the ones listed: never a spelling of a
//!      non-finite number (`nan`, `inf`, `infinity`, any case, any sign).
//! 2. The parsed values ([`gga_is_plausible`], [`rmc_is_plausible`]):
//!    latitude within ±90°, longitude within ±180° (exact coordinates, always
//!    finite), altitude finite and within
//!    [`MIN_ALTITUDE_M`]..=[`MAX_ALTITUDE_M`], time of day below 24 h.

use super::coordinate::Coordinate;
use super::parse::{Gga, Rmc, TimeOfDayMs};

/// Lowest plausible antenna altitude above mean sea level (the Dead Sea shore
/// is at −430 m).
pub(crate) const MIN_ALTITUDE_M: f32 = -500.0;
/// Highest plausible antenna altitude above mean sea level (a tracker on a
/// balloon or aircraft is out of scope; Everest is 8,849 m).
pub(crate) const MAX_ALTITUDE_M: f32 = 20_000.0;
/// Milliseconds in a day.
const MS_PER_DAY: TimeOfDayMs = 86_400_000;

/// The sentence type a content check knows about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// Global positioning system fix data.
    Gga,
    /// Recommended minimum specific GNSS data.
    Rmc,
}

/// Rule 1 as a pass of its own over the fields, as it ran before the reader
/// took it over: the reference the reader is compared with in the tests.
#[cfg(test)]
pub(crate) mod reference {
    use super::super::fields::{before_ascii, split_ascii, split_once_ascii, split_sign};
    use super::Kind;
    use crate::time::days_in_month;

    /// What a field must look like.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    enum Field {
        /// Checked by the reader in `parse.rs` (address, status, units) or not
        /// used; only the non-finite rule applies.
        Other,
        /// `hhmmss[.s…]`, UTC time of day.
        Time,
        /// `ddmm[.m…]`, latitude in degrees and minutes.
        Latitude,
        /// `N` or `S`.
        NorthSouth,
        /// `dddmm[.m…]`, longitude in degrees and minutes.
        Longitude,
        /// `E` or `W`, of the longitude.
        EastWest,
        /// `E` or `W`, of the magnetic variation.
        VariationSide,
        /// Digits only.
        Count,
        /// `x[.x…]` without a sign.
        Unsigned,
        /// `[+-]x[.x…]`.
        Signed,
        /// `ddmmyy`.
        Date,
    }

    /// GGA fields in NMEA 0183 order (index 0 is the address, e.g. `GPGGA`).
    const GGA_FIELDS: [Field; 15] = [
        Field::Other,      // address
        Field::Time,       // 1: UTC of position
        Field::Latitude,   // 2: latitude
        Field::NorthSouth, // 3: N/S
        Field::Longitude,  // 4: longitude
        Field::EastWest,   // 5: E/W
        Field::Count,      // 6: GPS quality indicator 0..8
        Field::Count,      // 7: number of satellites in use
        Field::Unsigned,   // 8: horizontal dilution of precision
        Field::Signed,     // 9: antenna altitude above/below mean sea level
        Field::Other,      // 10: units of altitude, M
        Field::Signed,     // 11: geoidal separation
        Field::Other,      // 12: units of separation, M
        Field::Unsigned,   // 13: age of differential GPS data, seconds
        Field::Count,      // 14: differential reference station ID
    ];

    /// RMC fields in NMEA 0183 order (index 0 is the address, e.g. `GPRMC`).
    const RMC_FIELDS: [Field; 14] = [
        Field::Other,         // address
        Field::Time,          // 1: UTC of position fix
        Field::Other,         // 2: status, A valid / V navigation receiver warning
        Field::Latitude,      // 3: latitude
        Field::NorthSouth,    // 4: N/S
        Field::Longitude,     // 5: longitude
        Field::EastWest,      // 6: E/W
        Field::Unsigned,      // 7: speed over ground, knots
        Field::Unsigned,      // 8: course over ground, degrees true
        Field::Date,          // 9: date ddmmyy
        Field::Unsigned,      // 10: magnetic variation, degrees
        Field::VariationSide, // 11: E/W of the variation
        Field::Other,         // 12: mode indicator (NMEA 2.3)
        Field::Other,         // 13: navigational status (NMEA 4.1)
    ];

    /// Checks the text of every field of a GGA or RMC (`$` through `*hh`, as the
    /// assembler gives it out). `false` when any field is impossible.
    pub(crate) fn check_fields(kind: Kind, sentence: &str) -> bool {
        let body = sentence.strip_prefix('$').unwrap_or(sentence);
        let body = before_ascii(body, b'*');
        let table: &[Field] = match kind {
            Kind::Gga => &GGA_FIELDS,
            Kind::Rmc => &RMC_FIELDS,
        };
        let mut position_fields = 0u8;
        let mut position_present = 0u8;
        for (index, text) in split_ascii(body, b',').enumerate() {
            if spells_non_finite(text) {
                return false;
            }
            let field = table.get(index).copied().unwrap_or(Field::Other);
            if matches!(
                field,
                Field::Latitude | Field::NorthSouth | Field::Longitude | Field::EastWest
            ) {
                position_fields = position_fields.saturating_add(1);
                if !text.is_empty() {
                    position_present = position_present.saturating_add(1);
                }
            }
            if !text.is_empty() && !field_ok(field, text) {
                return false;
            }
        }
        // Latitude, N/S, longitude and E/W come together or not at all.
        position_present == 0 || position_present == position_fields
    }

    fn field_ok(field: Field, text: &str) -> bool {
        match field {
            Field::Other => true,
            Field::Time => time_ok(text),
            Field::Latitude => angle_ok(text, 2, 90),
            Field::Longitude => angle_ok(text, 3, 180),
            Field::NorthSouth => text == "N" || text == "S",
            Field::EastWest | Field::VariationSide => text == "E" || text == "W",
            Field::Count => all_digits(text),
            Field::Unsigned => decimal_ok(text),
            Field::Signed => decimal_ok(split_sign(text).1),
            Field::Date => date_ok(text),
        }
    }

    /// `nan`, `inf`, `infinity` in any case, with or without a sign: what
    /// floating-point parsers take as non-finite.
    pub(super) fn spells_non_finite(text: &str) -> bool {
        let (_, unsigned) = split_sign(text);
        let prefix = unsigned.get(..3).unwrap_or(unsigned);
        prefix.eq_ignore_ascii_case("nan") || prefix.eq_ignore_ascii_case("inf")
    }

    fn all_digits(text: &str) -> bool {
        !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit())
    }

    /// `digits[.digits]`: no sign, no exponent, at least one digit each side of a
    /// decimal point that is present.
    pub(super) fn decimal_ok(text: &str) -> bool {
        match split_once_ascii(text, b'.') {
            Some((int, frac)) => all_digits(int) && all_digits(frac),
            None => all_digits(text),
        }
    }

    /// Value of two ASCII digits; `None` unless both are digits.
    fn two_digits(text: &str) -> Option<u16> {
        match text.as_bytes() {
            [a, b] if a.is_ascii_digit() && b.is_ascii_digit() => {
                Some(u16::from(a - b'0') * 10 + u16::from(b - b'0'))
            }
            _ => None,
        }
    }

    /// `hhmmss[.s…]` with hour < 24, minute < 60, second < 60 (no leap second).
    pub(super) fn time_ok(text: &str) -> bool {
        if !decimal_ok(text) {
            return false;
        }
        let int = before_ascii(text, b'.');
        let (Some(hour), Some(minute), Some(second)) = (
            int.get(0..2).and_then(two_digits),
            int.get(2..4).and_then(two_digits),
            int.get(4..6).and_then(two_digits),
        ) else {
            return false;
        };
        int.len() == 6 && hour < 24 && minute < 60 && second < 60
    }

    /// Degrees and minutes, `d…dmm[.m…]`, with exactly `degree_digits` degree
    /// digits, minutes < 60 and degrees ≤ `max_deg` (equal only with zero
    /// minutes, which the value check sees: 90°00.0' is fine, 90°00.1' is not).
    pub(super) fn angle_ok(text: &str, degree_digits: usize, max_deg: u16) -> bool {
        if !decimal_ok(text) {
            return false;
        }
        let int = before_ascii(text, b'.');
        if int.len() != degree_digits + 2 {
            return false;
        }
        let degrees = int
            .get(..degree_digits)
            .map(|d| {
                d.bytes()
                    .fold(0u16, |acc, b| acc * 10 + u16::from(b.wrapping_sub(b'0')))
            })
            .unwrap_or(u16::MAX);
        let minutes = int.get(degree_digits..).and_then(two_digits);
        degrees <= max_deg && minutes.is_some_and(|m| m < 60)
    }

    /// `ddmmyy` naming a day that exists.
    pub(super) fn date_ok(text: &str) -> bool {
        let (Some(day), Some(month), Some(yy)) = (
            text.get(0..2).and_then(two_digits),
            text.get(2..4).and_then(two_digits),
            text.get(4..6).and_then(two_digits),
        ) else {
            return false;
        };
        // The reader's two-digit year (NMEA 0183 appeared in 1983), as `parse_date`.
        let year = if yy >= 83 { 1900 + yy } else { 2000 + yy };
        let Ok(month) = u8::try_from(month) else {
            return false;
        };
        text.len() == 6 && day >= 1 && day <= u16::from(days_in_month(year, month))
    }
}

fn latitude_ok(lat: Option<Coordinate>) -> bool {
    lat.is_none_or(|v| v.within_deg(90))
}

fn longitude_ok(lon: Option<Coordinate>) -> bool {
    lon.is_none_or(|v| v.within_deg(180))
}

fn time_of_day_ok(ms: Option<TimeOfDayMs>) -> bool {
    ms.is_none_or(|t| t < MS_PER_DAY)
}

/// Whether a GGA's values are possible (see the module docs); also guards
/// values built by hand and given straight to [`super::FixFusion`].
pub(crate) fn gga_is_plausible(g: &Gga) -> bool {
    latitude_ok(g.latitude_deg)
        && longitude_ok(g.longitude_deg)
        && g.latitude_deg.is_some() == g.longitude_deg.is_some()
        && g.altitude_m
            .is_none_or(|a| a.is_finite() && (MIN_ALTITUDE_M..=MAX_ALTITUDE_M).contains(&a))
        && time_of_day_ok(g.time_of_day_ms)
}

/// Whether an RMC's values are possible (see the module docs).
pub(crate) fn rmc_is_plausible(r: &Rmc) -> bool {
    latitude_ok(r.latitude_deg)
        && longitude_ok(r.longitude_deg)
        && r.latitude_deg.is_some() == r.longitude_deg.is_some()
        && time_of_day_ok(r.time_of_day_ms)
}

#[cfg(test)]
mod tests {
    use super::reference::*;

    #[test]
    fn field_grammar() {
        assert!(time_ok("235959.99") && time_ok("000000") && !time_ok("235960"));
        assert!(!time_ok("240000") && !time_ok("006000") && !time_ok("0315.5"));
        assert!(angle_ok("9000.000", 2, 90) && !angle_ok("9100.000", 2, 90));
        assert!(angle_ok("3759.999", 2, 90) && !angle_ok("3760.000", 2, 90));
        assert!(!angle_ok("37-4.003", 2, 90) && !angle_ok("37.34e2", 2, 90));
        assert!(!angle_ok("+3734.0", 2, 90) && !angle_ok("373.4", 2, 90));
        assert!(angle_ok("18000.0", 3, 180) && !angle_ok("20000.0", 3, 180));
        assert!(date_ok("290224") && !date_ok("290223") && !date_ok("310624"));
        assert!(!date_ok("000624") && !date_ok("151324") && !date_ok("150024"));
        assert!(date_ok("311299") && !date_ok("3112999"));
        for s in ["nan", "NaN", "-inf", "+Infinity", "INF"] {
            assert!(spells_non_finite(s), "{s}");
        }
        assert!(!spells_non_finite("N") && !spells_non_finite("12.5"));
        assert!(decimal_ok("0.5") && !decimal_ok(".5") && !decimal_ok("5.") && !decimal_ok("1e5"));
    }
}
