//! The `chrono` feature: `Date` ↔ `chrono::NaiveDate`, checked against
//! chrono's own calendar arithmetic (its day counts and date differences),
//! over the whole range, at leap days and year boundaries, and outside the
//! range.
#![cfg(feature = "chrono")]

use chrono::{Datelike, Days, NaiveDate};
use suntracker_time::{Date, DateError, MAX_YEAR, MIN_YEAR};

/// chrono counts days from 0001-01-01 (day 1); 1970-01-01 is its day 719 163.
const CE_DAY_OF_UNIX_EPOCH: i32 = 719_163;

fn ymd(y: i32, m: u32, d: u32) -> NaiveDate {
    NaiveDate::from_ymd_opt(y, m, d).unwrap()
}

#[test]
fn every_date_converts_both_ways_with_chronos_day_count() {
    let mut reference = ymd(MIN_YEAR, 1, 1);
    let mut days = Date::MIN.days_since_unix_epoch();
    loop {
        // chrono's day number of the same day, from its own arithmetic.
        assert_eq!(reference.num_days_from_ce() - CE_DAY_OF_UNIX_EPOCH, days);
        let date = Date::from_days_since_unix_epoch(days).unwrap();
        assert_eq!(NaiveDate::from(date), reference, "{date}");
        assert_eq!(Date::try_from(reference), Ok(date), "{reference}");
        if date == Date::MAX {
            break;
        }
        reference = reference.succ_opt().unwrap();
        days += 1;
    }
    assert_eq!(reference, ymd(MAX_YEAR, 12, 31));
}

#[test]
fn leap_days_and_year_boundaries_follow_chrono() {
    for (y, m, d) in [
        (2000, 2, 29),
        (2024, 2, 29),
        (1600, 2, 29),
        (-4, 2, 29),
        (0, 2, 29),
        (-400, 2, 29),
        (1900, 2, 28),
        (2100, 2, 28),
        (1999, 12, 31),
        (2000, 1, 1),
        (-1, 12, 31),
        (0, 1, 1),
        (9999, 12, 31),
        (-9999, 1, 1),
    ] {
        let nd = ymd(y, m, d);
        let date = Date::try_from(nd).unwrap();
        assert_eq!(
            (date.year(), u32::from(date.month()), u32::from(date.day())),
            (y, m, d)
        );
        // The next day by chrono's arithmetic is the next day count here
        // (none after 9999-12-31 in this crate).
        let next = nd + Days::new(1);
        assert_eq!(
            Date::try_from(next).ok(),
            Date::from_days_since_unix_epoch(date.days_since_unix_epoch() + 1).ok(),
            "{nd}"
        );
        // Day of year and weekday as chrono computes them.
        assert_eq!(u32::from(date.day_of_year()), nd.ordinal());
        assert_eq!(
            u32::from(date.iso_weekday()),
            nd.weekday().number_from_monday()
        );
    }
    // Not leap years: chrono has no such dates, and neither has Date.
    for y in [1900, 2100, 2023, -100] {
        assert!(NaiveDate::from_ymd_opt(y, 2, 29).is_none());
        assert_eq!(Date::new(y, 2, 29), Err(DateError::Day));
    }
}

#[test]
fn differences_of_dates_match_chrono_durations() {
    // A spread of dates over the range (a fixed linear congruential
    // sequence, so the test is the same on every run).
    let span = i64::from(Date::MAX.days_since_unix_epoch() - Date::MIN.days_since_unix_epoch());
    let mut x: u64 = 0x2545_f491_4f6c_dd1d;
    let mut pick = || {
        x = x
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let off = ((x >> 33) % (span as u64 + 1)) as i32;
        Date::from_days_since_unix_epoch(Date::MIN.days_since_unix_epoch() + off).unwrap()
    };
    for _ in 0..20_000 {
        let (a, b) = (pick(), pick());
        let chrono_days = NaiveDate::from(a)
            .signed_duration_since(NaiveDate::from(b))
            .num_days();
        assert_eq!(
            chrono_days,
            i64::from(a.days_since_unix_epoch() - b.days_since_unix_epoch()),
            "{a} - {b}"
        );
        assert_eq!(NaiveDate::from(a).cmp(&NaiveDate::from(b)), a.cmp(&b));
    }
}

#[test]
fn chrono_dates_outside_the_range_are_year_errors() {
    for nd in [
        ymd(MAX_YEAR + 1, 1, 1),
        ymd(MIN_YEAR - 1, 12, 31),
        ymd(100_000, 6, 15),
        ymd(-100_000, 6, 15),
        NaiveDate::MIN,
        NaiveDate::MAX,
    ] {
        assert_eq!(Date::try_from(nd), Err(DateError::Year), "{nd}");
    }
    // The last and first days inside.
    assert_eq!(Date::try_from(ymd(MAX_YEAR, 12, 31)), Ok(Date::MAX));
    assert_eq!(Date::try_from(ymd(MIN_YEAR, 1, 1)), Ok(Date::MIN));
}
