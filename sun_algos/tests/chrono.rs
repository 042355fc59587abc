//! The `chrono` feature: chrono's date-times into `UtcTime` (and back),
//! checked against chrono's own arithmetic (`timestamp_millis`,
//! `signed_duration_since`, its calendar fields) on many instants, leap
//! days, year boundaries, out-of-range years, sub-millisecond nanoseconds
//! and leap seconds (nanoseconds ≥ 10⁹).
#![cfg(feature = "chrono")]

use chrono::{
    DateTime, Datelike, FixedOffset, NaiveDate, NaiveDateTime, NaiveTime, TimeDelta, Timelike, Utc,
};
use sun_algos::time::{MAX_YEAR, MIN_YEAR};
use sun_algos::{Error, UtcTime};

/// Milliseconds since 1970-01-01T00:00:00 of a `UtcTime`.
fn unix_ms(t: &UtcTime) -> i64 {
    t.unix_seconds() * 1000 + i64::from(t.ms_of_day() % 1000)
}

fn naive(y: i32, mo: u32, d: u32, h: u32, mi: u32, s: u32, nano: u32) -> NaiveDateTime {
    NaiveDate::from_ymd_opt(y, mo, d)
        .unwrap()
        .and_hms_nano_opt(h, mi, s, nano)
        .unwrap()
}

/// The conversion against chrono's own reading of the same date-time.
fn check_against_chrono(dt: NaiveDateTime) {
    let t = UtcTime::try_from(dt).unwrap_or_else(|e| panic!("{dt}: {e}"));
    // chrono's Unix milliseconds (sub-millisecond part dropped toward the
    // past; a leap second counted into the next second).
    assert_eq!(unix_ms(&t), dt.and_utc().timestamp_millis(), "{dt}");
    // chrono's duration from its own epoch, the other arithmetic it has
    // (seconds and nanoseconds, both truncated toward zero), floored to the
    // millisecond.
    let since_epoch = dt.signed_duration_since(DateTime::UNIX_EPOCH.naive_utc());
    let since_epoch_ns = i128::from(since_epoch.num_seconds()) * 1_000_000_000
        + i128::from(since_epoch.subsec_nanos());
    assert_eq!(
        i128::from(unix_ms(&t)),
        since_epoch_ns.div_euclid(1_000_000),
        "{dt}"
    );
    if dt.nanosecond() < 1_000_000_000 {
        // No leap second: the same calendar fields, milliseconds truncated.
        assert_eq!(
            t.ymd(),
            (dt.year(), dt.month() as u8, dt.day() as u8),
            "{dt}"
        );
        assert_eq!(
            t.hms_milli(),
            (
                dt.hour() as u8,
                dt.minute() as u8,
                dt.second() as u8,
                (dt.nanosecond() / 1_000_000) as u16
            ),
            "{dt}"
        );
        // Back to chrono: the same instant without the sub-millisecond rest.
        let back = NaiveDateTime::from(t);
        assert_eq!(
            back,
            dt.with_nanosecond(dt.nanosecond() / 1_000_000 * 1_000_000)
                .unwrap()
        );
    }
}

/// A fixed linear congruential sequence (the same instants on every run).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 11
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

#[test]
fn many_instants_match_chronos_arithmetic() {
    let first = naive(MIN_YEAR, 1, 1, 0, 0, 0, 0).and_utc().timestamp();
    let last = naive(MAX_YEAR, 12, 31, 23, 59, 59, 0).and_utc().timestamp();
    let span = (last - first) as u64 + 1;
    let mut rng = Lcg(0x5EED_0FC0_FFEE);
    for i in 0..200_000 {
        let secs = first + rng.below(span) as i64;
        // Every fourth instant on a whole second, the others with any
        // nanosecond (sub-millisecond digits included).
        let nanos = if i % 4 == 0 {
            0
        } else {
            rng.below(1_000_000_000) as u32
        };
        let dt = DateTime::<Utc>::from_timestamp(secs, nanos).unwrap();
        check_against_chrono(dt.naive_utc());
        assert_eq!(
            UtcTime::try_from(dt),
            UtcTime::try_from(dt.naive_utc()),
            "{dt}"
        );
    }
}

#[test]
fn leap_days_and_year_boundaries() {
    for dt in [
        naive(2000, 2, 29, 12, 0, 0, 0),
        naive(2024, 2, 29, 23, 59, 59, 999_999_999),
        naive(2024, 3, 1, 0, 0, 0, 0),
        naive(1900, 2, 28, 23, 59, 59, 500_000_000),
        naive(1900, 3, 1, 0, 0, 0, 1),
        naive(2100, 2, 28, 23, 59, 59, 0),
        naive(1600, 2, 29, 6, 0, 0, 0),
        naive(-4, 2, 29, 6, 0, 0, 0),
        naive(0, 2, 29, 6, 0, 0, 0),
        naive(1999, 12, 31, 23, 59, 59, 999_000_000),
        naive(2000, 1, 1, 0, 0, 0, 0),
        naive(1969, 12, 31, 23, 59, 59, 999_999_999),
        naive(1970, 1, 1, 0, 0, 0, 0),
        naive(-1, 12, 31, 23, 59, 59, 0),
        naive(0, 1, 1, 0, 0, 0, 0),
        naive(MIN_YEAR, 1, 1, 0, 0, 0, 0),
        naive(MAX_YEAR, 12, 31, 23, 59, 59, 999_999_999),
    ] {
        check_against_chrono(dt);
    }
    // One millisecond before a new year is the last day of the old one.
    let t = UtcTime::try_from(naive(2024, 12, 31, 23, 59, 59, 999_999_999)).unwrap();
    assert_eq!(t.day_of_year(), 366);
    assert_eq!(t.add_millis(1).unwrap().ymd(), (2025, 1, 1));
}

#[test]
fn sub_millisecond_nanoseconds_are_dropped_toward_the_past() {
    for (nano, ms) in [
        (0, 0),
        (1, 0),
        (999_999, 0),
        (1_000_000, 1),
        (1_999_999, 1),
        (999_999_999, 999),
    ] {
        for y in [2024, 1969, -3000] {
            let dt = naive(y, 6, 15, 12, 0, 0, nano);
            let t = UtcTime::try_from(dt).unwrap();
            assert_eq!(t.hms_milli(), (12, 0, 0, ms), "{dt}");
            check_against_chrono(dt);
        }
    }
}

#[test]
fn leap_seconds_count_into_the_next_second() {
    // Real leap seconds (IERS: 2016-12-31, 2015-06-30) and a few that
    // chrono can represent anywhere a second 59 is.
    for (y, mo, d) in [(2016, 12, 31), (2015, 6, 30), (1972, 6, 30), (2024, 2, 29)] {
        for nano in [1_000_000_000, 1_000_999_999, 1_500_000_000, 1_999_999_999] {
            let dt = naive(y, mo, d, 23, 59, 59, nano);
            check_against_chrono(dt);
            let t = UtcTime::try_from(dt).unwrap();
            // The next day's first second.
            let next_day = NaiveDate::from_ymd_opt(y, mo, d)
                .unwrap()
                .succ_opt()
                .unwrap();
            assert_eq!(
                t.ymd(),
                (
                    next_day.year(),
                    next_day.month() as u8,
                    next_day.day() as u8
                )
            );
            assert_eq!(
                t.hms_milli(),
                (0, 0, 0, ((nano - 1_000_000_000) / 1_000_000) as u16)
            );
        }
    }
    // In the middle of a day: the next minute's second 0.
    let t = UtcTime::try_from(naive(2024, 5, 1, 10, 20, 59, 1_250_000_000)).unwrap();
    assert_eq!(t.hms_milli(), (10, 21, 0, 250));
    // At the very end of the range the next second is outside it.
    let dt = naive(MAX_YEAR, 12, 31, 23, 59, 59, 1_000_000_000);
    assert_eq!(UtcTime::try_from(dt), Err(Error::InvalidDate));
}

#[test]
fn out_of_range_years_are_errors_not_panics() {
    for dt in [
        naive(MAX_YEAR + 1, 1, 1, 0, 0, 0, 0),
        naive(MIN_YEAR - 1, 12, 31, 23, 59, 59, 999_999_999),
        naive(9999, 12, 31, 0, 0, 0, 0),
        naive(10_000, 1, 1, 0, 0, 0, 0),
        naive(-10_000, 1, 1, 0, 0, 0, 0),
        NaiveDateTime::MIN,
        NaiveDateTime::MAX,
    ] {
        assert_eq!(UtcTime::try_from(dt), Err(Error::InvalidDate), "{dt}");
        assert_eq!(
            UtcTime::try_from(dt.and_utc()),
            Err(Error::InvalidDate),
            "{dt}"
        );
    }
    assert_eq!(
        UtcTime::try_from(DateTime::<Utc>::MIN_UTC),
        Err(Error::InvalidDate)
    );
    assert_eq!(
        UtcTime::try_from(DateTime::<Utc>::MAX_UTC),
        Err(Error::InvalidDate)
    );
}

#[test]
fn time_zones_convert_at_their_utc_instant() {
    let mut rng = Lcg(42);
    for _ in 0..2_000 {
        let secs = 946_684_800 + rng.below(100 * 365 * 86_400) as i64;
        let offset_s = rng.below(2 * 86_399) as i32 - 86_399 + 1;
        let tz = FixedOffset::east_opt(offset_s).unwrap();
        let utc = DateTime::<Utc>::from_timestamp(secs, 0).unwrap();
        let local = utc.with_timezone(&tz);
        assert_eq!(UtcTime::try_from(local), UtcTime::try_from(utc), "{local}");
        assert_eq!(
            unix_ms(&UtcTime::try_from(local).unwrap()),
            local.timestamp_millis()
        );
    }
}

#[test]
fn every_utc_time_converts_to_chrono_and_back() {
    // The first and last days of the range, every day of 1999–2001, with
    // instants across the day.
    let first = UtcTime::from_ymd_hms(MIN_YEAR, 1, 1, 0, 0, 0).unwrap();
    let last = UtcTime::from_ymd_hms_milli(MAX_YEAR, 12, 31, 23, 59, 59, 999).unwrap();
    for t in [first, last] {
        let dt = DateTime::<Utc>::from(t);
        assert_eq!(dt.timestamp_millis(), unix_ms(&t));
        assert_eq!(UtcTime::try_from(dt), Ok(t));
    }
    let start = UtcTime::from_ymd_hms(1999, 1, 1, 0, 0, 0).unwrap();
    for day in 0..(3 * 366) {
        for ms in [0, 1, 999, 43_200_000, 86_399_999] {
            let t = UtcTime::from_days_ms(start.days_since_2000() + day, ms).unwrap();
            let n = NaiveDateTime::from(t);
            assert_eq!(n.and_utc().timestamp_millis(), unix_ms(&t));
            assert_eq!(UtcTime::try_from(n), Ok(t));
        }
    }
    // Whole-range spread, by chrono's arithmetic: the difference of two
    // converted instants is the difference of their Unix milliseconds.
    let mut rng = Lcg(7);
    let span = (last.unix_seconds() - first.unix_seconds()) as u64;
    for _ in 0..50_000 {
        let a = first.add_seconds(rng.below(span) as i64).unwrap();
        let b = first.add_millis(rng.below(span * 1000) as i64).unwrap();
        let d = NaiveDateTime::from(a).signed_duration_since(NaiveDateTime::from(b));
        assert_eq!(d, TimeDelta::milliseconds(unix_ms(&a) - unix_ms(&b)));
    }
}

#[test]
fn naive_time_of_day_spans_the_whole_day() {
    // Every second of one day, with a millisecond that walks through 0..1000.
    let date = NaiveDate::from_ymd_opt(2026, 6, 21).unwrap();
    for s in 0..86_400u32 {
        let nano = (s * 7919 % 1000) * 1_000_000 + s % 1_000_000;
        let dt = date.and_time(NaiveTime::from_num_seconds_from_midnight_opt(s, nano).unwrap());
        let t = UtcTime::try_from(dt).unwrap();
        assert_eq!(t.ms_of_day(), s * 1000 + nano / 1_000_000);
    }
}

#[test]
fn seconds_in_32_bits_match_chronos_arithmetic() {
    // Instants of 1900–2150 with any millisecond, moved by any i32 number
    // of seconds (every other one within ±100,000 s) and by any u32 number
    // of milliseconds, against chrono's
    // `TimeDelta` arithmetic; and the whole seconds between two of them
    // against the difference of chrono's (floored) Unix timestamps.
    let lo = naive(1900, 1, 1, 0, 0, 0, 0).and_utc().timestamp_millis();
    let hi = naive(2150, 12, 31, 23, 59, 59, 999_000_000)
        .and_utc()
        .timestamp_millis();
    let span = (hi - lo) as u64 + 1;
    let mut rng = Lcg(0x0032_B175);
    let instant = |rng: &mut Lcg| {
        let dt = DateTime::<Utc>::from_timestamp_millis(lo + rng.below(span) as i64).unwrap();
        (dt, UtcTime::try_from(dt).unwrap())
    };
    let (mut near, mut far) = (0, 0);
    for i in 0..100_000 {
        let (dt, t) = instant(&mut rng);
        let s = if i % 2 == 0 {
            rng.next() as u32 as i32
        } else {
            rng.below(200_001) as i32 - 100_000
        };
        // chrono's sum, or InvalidDate where it leaves the calendar.
        let want = |delta: TimeDelta| {
            dt.checked_add_signed(delta)
                .and_then(|w| UtcTime::try_from(w).ok())
                .ok_or(Error::InvalidDate)
        };
        assert_eq!(
            t.add_seconds_i32(s),
            want(TimeDelta::seconds(i64::from(s))),
            "{dt} + {s} s"
        );
        let ms = rng.next() as u32;
        assert_eq!(
            t.add_millis_u32(ms),
            want(TimeDelta::milliseconds(i64::from(ms))),
            "{dt} + {ms} ms"
        );
        let (dt2, t2) = instant(&mut rng);
        let apart_days = (t.days_since_2000() - t2.days_since_2000()).abs();
        if apart_days <= 24_854 {
            near += 1;
            let want_s = dt.timestamp() - dt2.timestamp();
            assert_eq!(
                t.seconds_since(&t2).map(i64::from),
                Some(want_s),
                "{dt} − {dt2}"
            );
        } else {
            far += 1;
            assert_eq!(t.seconds_since(&t2), None, "{dt} − {dt2}");
        }
    }
    // Both outcomes were exercised.
    assert!(near > 10_000 && far > 10_000, "{near} {far}");
}
