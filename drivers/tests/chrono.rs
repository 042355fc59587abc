//! The `chrono` feature's conversions, against chrono's own calendar.
//!
//! chrono keeps its own proleptic Gregorian arithmetic (year flags and
//! 400-year cycle tables), independent of the suntracker-time formulas
//! behind `drivers::time::DateTime`, so every instant below is made by chrono
//! from a Unix millisecond count and then compared field by field and count
//! by count with what our type makes of it.
#![cfg(feature = "chrono")]

use chrono::{
    DateTime as ChronoDateTime, Datelike, FixedOffset, NaiveDate, NaiveDateTime, NaiveTime,
    TimeZone, Timelike, Utc,
};
use drivers::time::{DateTime, DateTimeError, MAX_YEAR, MIN_YEAR};

/// chrono's UTC instant `ms` milliseconds after the Unix epoch.
fn chrono_at(ms: i64) -> ChronoDateTime<Utc> {
    ChronoDateTime::<Utc>::from_timestamp_millis(ms).expect("inside chrono's range")
}

/// Checks one instant both ways: fields, counts, and back to chrono.
fn check(c: ChronoDateTime<Utc>) {
    let ours = DateTime::try_from(c).unwrap_or_else(|e| panic!("{c}: {e}"));
    assert_eq!(i32::from(ours.year()), c.year(), "{c}");
    assert_eq!(u32::from(ours.month()), c.month(), "{c}");
    assert_eq!(u32::from(ours.day()), c.day(), "{c}");
    assert_eq!(u32::from(ours.hour()), c.hour(), "{c}");
    assert_eq!(u32::from(ours.minute()), c.minute(), "{c}");
    assert_eq!(u32::from(ours.second()), c.second(), "{c}");
    assert_eq!(u32::from(ours.millis()), c.timestamp_subsec_millis(), "{c}");
    assert_eq!(ours.unix_millis(), c.timestamp_millis(), "{c}");
    assert_eq!(ours.unix_seconds(), c.timestamp(), "{c}");
    // Sunday = 1 in our numbering, chrono counts from Sunday = 0.
    assert_eq!(
        u32::from(ours.weekday_from_sunday()),
        c.weekday().num_days_from_sunday() + 1,
        "{c}"
    );
    assert_eq!(ChronoDateTime::<Utc>::from(ours), c, "{c}");
    assert_eq!(NaiveDateTime::from(ours), c.naive_utc(), "{c}");
    assert_eq!(DateTime::try_from(c.naive_utc()), Ok(ours), "{c}");
}

/// Unix milliseconds of 0001-01-01T00:00:00Z and 9999-12-31T23:59:59.999Z
/// (Python: `datetime(1, 1, 1, tzinfo=timezone.utc).timestamp()` and
/// `datetime(9999, 12, 31, 23, 59, 59, 999000, tzinfo=timezone.utc).timestamp()`).
const FIRST_MS: i64 = -62_135_596_800_000;
const LAST_MS: i64 = 253_402_300_799_999;

#[test]
fn range_ends_are_those_of_python_and_chrono() {
    assert_eq!(
        DateTime::new(MIN_YEAR, 1, 1, 0, 0, 0)
            .unwrap()
            .unix_millis(),
        FIRST_MS
    );
    let last = DateTime::new(MAX_YEAR, 12, 31, 23, 59, 59)
        .unwrap()
        .with_millis(999)
        .unwrap();
    assert_eq!(last.unix_millis(), LAST_MS);
    check(chrono_at(FIRST_MS));
    check(chrono_at(LAST_MS));
    // One millisecond outside, on either side.
    assert_eq!(
        DateTime::try_from(chrono_at(FIRST_MS - 1)),
        Err(DateTimeError::Year)
    );
    assert_eq!(
        DateTime::try_from(chrono_at(LAST_MS + 1)),
        Err(DateTimeError::Year)
    );
}

#[test]
fn agrees_with_chrono_on_two_hundred_thousand_instants() {
    // A fixed 64-bit LCG (Knuth's MMIX constants) spread over the whole range.
    let span = u64::try_from(LAST_MS - FIRST_MS + 1).unwrap();
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    for _ in 0..200_000 {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let offset = i64::try_from((state >> 11) % span).unwrap();
        check(chrono_at(FIRST_MS + offset));
    }
}

#[test]
fn every_day_of_four_centuries_at_both_ends_of_the_day() {
    // 1900-01-01 to 2300-01-01: the century rules (1900, 2100, 2200 common,
    // 2000 leap) and every February 29th in between.
    let start = NaiveDate::from_ymd_opt(1900, 1, 1).unwrap();
    let end = NaiveDate::from_ymd_opt(2300, 1, 1).unwrap();
    let mut day = start;
    while day < end {
        let midnight = day.and_hms_opt(0, 0, 0).unwrap().and_utc();
        check(midnight);
        check(day.and_hms_milli_opt(23, 59, 59, 999).unwrap().and_utc());
        day = day.succ_opt().unwrap();
    }
}

#[test]
fn leap_days_and_year_ends() {
    for (y, m, d) in [
        (1600, 2, 29),
        (2000, 2, 29),
        (2024, 2, 29),
        (2400, 2, 29),
        (4, 2, 29),
        (9996, 2, 29),
        (1999, 12, 31),
        (2000, 1, 1),
        (2099, 12, 31),
        (2100, 1, 1),
        (1, 1, 1),
        (9999, 12, 31),
    ] {
        let date = NaiveDate::from_ymd_opt(y, m, d).unwrap();
        for (h, mi, s, ms) in [(0, 0, 0, 0), (12, 34, 56, 789), (23, 59, 59, 999)] {
            check(date.and_hms_milli_opt(h, mi, s, ms).unwrap().and_utc());
        }
    }
    // The day after a leap day and after a non-leap February.
    let t = DateTime::try_from(
        NaiveDate::from_ymd_opt(2100, 2, 28)
            .unwrap()
            .and_hms_opt(23, 59, 59)
            .unwrap(),
    )
    .unwrap();
    let next = DateTime::from_unix_seconds(t.unix_seconds() + 1).unwrap();
    assert_eq!((next.month(), next.day()), (3, 1));
    // 29 February of a common year is no date in either calendar.
    assert_eq!(NaiveDate::from_ymd_opt(1900, 2, 29), None);
    assert_eq!(DateTime::new(1900, 2, 29, 0, 0, 0), Err(DateTimeError::Day));
}

#[test]
fn years_outside_the_range_are_errors() {
    for y in [0, -1, -4713, 10_000, 10_001, 262_142, -262_143] {
        let naive = NaiveDate::from_ymd_opt(y, 6, 15)
            .unwrap()
            .and_hms_opt(12, 0, 0)
            .unwrap();
        assert_eq!(
            DateTime::try_from(naive),
            Err(DateTimeError::Year),
            "year {y}"
        );
        assert_eq!(
            DateTime::try_from(naive.and_utc()),
            Err(DateTimeError::Year),
            "year {y}"
        );
    }
    assert_eq!(
        DateTime::try_from(NaiveDateTime::MIN),
        Err(DateTimeError::Year)
    );
    assert_eq!(
        DateTime::try_from(NaiveDateTime::MAX),
        Err(DateTimeError::Year)
    );
}

#[test]
fn leap_second_nanoseconds_are_an_error() {
    let day = NaiveDate::from_ymd_opt(2016, 12, 31).unwrap();
    // chrono keeps 23:59:60.x as second 59 with 1e9 + x ns.
    for nanos in [1_000_000_000, 1_000_000_001, 1_500_000_000, 1_999_999_999] {
        let t = NaiveTime::from_hms_nano_opt(23, 59, 59, nanos).unwrap();
        assert_eq!(
            DateTime::try_from(day.and_time(t)),
            Err(DateTimeError::Second),
            "{nanos} ns"
        );
        assert_eq!(
            DateTime::try_from(day.and_time(t).and_utc()),
            Err(DateTimeError::Second),
            "{nanos} ns"
        );
    }
    // The nanosecond before the leap second is fine.
    let t = NaiveTime::from_hms_nano_opt(23, 59, 59, 999_999_999).unwrap();
    let ours = DateTime::try_from(day.and_time(t)).unwrap();
    assert_eq!((ours.second(), ours.millis()), (59, 999));
}

#[test]
fn nanoseconds_below_the_millisecond_are_truncated() {
    let day = NaiveDate::from_ymd_opt(2024, 3, 10).unwrap();
    for (nanos, millis) in [
        (0, 0),
        (999_999, 0),
        (1_000_000, 1),
        (123_456_789, 123),
        (999_999_999, 999),
    ] {
        let t = day.and_hms_nano_opt(12, 0, 0, nanos).unwrap();
        assert_eq!(DateTime::try_from(t).unwrap().millis(), millis, "{nanos}");
    }
}

#[test]
fn other_time_zones_are_taken_at_their_utc_instant() {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let span = u64::try_from(LAST_MS - FIRST_MS + 1 - 2 * 86_400_000).unwrap();
    for offset_s in [
        -12 * 3600,
        -(9 * 3600 + 30 * 60),
        0,
        5 * 3600 + 45 * 60,
        14 * 3600,
    ] {
        let tz = FixedOffset::east_opt(offset_s).unwrap();
        for _ in 0..10_000 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let ms = FIRST_MS + 86_400_000 + i64::try_from((state >> 11) % span).unwrap();
            let utc = chrono_at(ms);
            let local = tz.from_utc_datetime(&utc.naive_utc());
            assert_eq!(
                DateTime::try_from(local),
                DateTime::try_from(utc),
                "{local}"
            );
        }
    }
    // A local date in year 10 000 can still be a UTC instant in 9999 ...
    let east = FixedOffset::east_opt(3600).unwrap();
    let local = east.with_ymd_and_hms(10_000, 1, 1, 0, 30, 0).unwrap();
    assert_eq!(
        DateTime::try_from(local),
        DateTime::new(9999, 12, 31, 23, 30, 0)
    );
    // ... and a local date in year 1 one in year 0, which is refused.
    let west = FixedOffset::west_opt(3600).unwrap();
    let local = east.with_ymd_and_hms(1, 1, 1, 0, 30, 0).unwrap();
    assert_eq!(DateTime::try_from(local), Err(DateTimeError::Year));
    let local = west.with_ymd_and_hms(1, 1, 1, 0, 30, 0).unwrap();
    assert_eq!(DateTime::try_from(local), DateTime::new(1, 1, 1, 1, 30, 0));
}

#[test]
fn into_chrono_utc_matches_chronos_timestamp() {
    // Independent of our field accessors: chrono builds the instant from the
    // Unix count alone.
    for t in [
        DateTime::new(1970, 1, 1, 0, 0, 0).unwrap(),
        DateTime::new(2009, 2, 13, 23, 31, 30).unwrap(),
        DateTime::new(2038, 1, 19, 3, 14, 8).unwrap(),
        DateTime::new(1969, 12, 31, 23, 59, 59)
            .unwrap()
            .with_millis(1)
            .unwrap(),
    ] {
        let c: ChronoDateTime<Utc> = t.into();
        assert_eq!(c, Utc.timestamp_millis_opt(t.unix_millis()).unwrap());
    }
}
