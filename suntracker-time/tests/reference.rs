//! The calendar checked against an independent implementation over its whole
//! range: chrono's `NaiveDate` (proleptic Gregorian, ISO 8601 year numbering
//! like ours), whose arithmetic works from per-year flags and a 400-year cycle
//! table rather than the era formula of this crate.

use chrono::{Datelike, NaiveDate};
use suntracker_time::{
    civil_from_days, days_from_civil, days_in_month, is_leap_year, Date, DateError, MAX_YEAR,
    MIN_YEAR,
};

/// chrono counts days from 0001-01-01 (day 1); 1970-01-01 is its day 719 163.
const CE_DAY_OF_UNIX_EPOCH: i32 = 719_163;

fn chrono_days_since_unix_epoch(d: NaiveDate) -> i32 {
    d.num_days_from_ce() - CE_DAY_OF_UNIX_EPOCH
}

fn chrono_date(days_since_unix_epoch: i32) -> NaiveDate {
    NaiveDate::from_num_days_from_ce_opt(days_since_unix_epoch + CE_DAY_OF_UNIX_EPOCH).unwrap()
}

fn fields(d: NaiveDate) -> (i32, u8, u8) {
    (d.year(), d.month() as u8, d.day() as u8)
}

#[test]
fn every_day_of_the_range_agrees_with_chrono() {
    let first = NaiveDate::from_ymd_opt(MIN_YEAR, 1, 1).unwrap();
    let last = NaiveDate::from_ymd_opt(MAX_YEAR, 12, 31).unwrap();
    let (first_days, last_days) = (
        chrono_days_since_unix_epoch(first),
        chrono_days_since_unix_epoch(last),
    );
    assert_eq!(Date::MIN.days_since_unix_epoch(), first_days);
    assert_eq!(Date::MAX.days_since_unix_epoch(), last_days);

    let mut reference = first;
    let mut previous: Option<Date> = None;
    for days in first_days..=last_days {
        let (y, m, d) = fields(reference);
        // Day count → date, both ways round.
        let date = Date::from_days_since_unix_epoch(days).unwrap();
        assert_eq!((date.year(), date.month(), date.day()), (y, m, d), "{days}");
        assert_eq!(civil_from_days(days), (y, m, d), "{days}");
        // Date → day count.
        assert_eq!(Date::new(y, m, d), Ok(date));
        assert_eq!(date.days_since_unix_epoch(), days, "{date}");
        assert_eq!(days_from_civil(y, m, d), i64::from(days), "{date}");
        // Day of year, weekday, month length.
        assert_eq!(u32::from(date.day_of_year()), reference.ordinal(), "{date}");
        assert_eq!(
            u32::from(date.iso_weekday()),
            reference.weekday().number_from_monday(),
            "{date}"
        );
        let next = reference.succ_opt().unwrap();
        if next.month() != reference.month() {
            assert_eq!(days_in_month(y, m), d, "{date}");
        }
        // Chronological order.
        if let Some(p) = previous {
            assert!(p < date, "{p} {date}");
        }
        previous = Some(date);
        reference = next;
    }
    assert_eq!(
        Date::from_days_since_unix_epoch(first_days - 1),
        Err(DateError::Year)
    );
    assert_eq!(
        Date::from_days_since_unix_epoch(last_days + 1),
        Err(DateError::Year)
    );
}

#[test]
fn valid_and_invalid_fields_agree_with_chrono() {
    for y in MIN_YEAR..=MAX_YEAR {
        assert_eq!(
            is_leap_year(y),
            NaiveDate::from_ymd_opt(y, 2, 29).is_some(),
            "{y}"
        );
        for m in 0..=13u8 {
            // Every month length is 28..=31: these days cover each boundary.
            for d in [0, 1, 27, 28, 29, 30, 31, 32, u8::MAX] {
                let ours = Date::new(y, m, d);
                let theirs = NaiveDate::from_ymd_opt(y, u32::from(m), u32::from(d));
                assert_eq!(ours.is_ok(), theirs.is_some(), "{y}-{m}-{d}");
                if ours.is_err() {
                    let expected = if (1..=12).contains(&m) {
                        DateError::Day
                    } else {
                        DateError::Month
                    };
                    assert_eq!(ours, Err(expected), "{y}-{m}-{d}");
                }
            }
        }
    }
    for y in [MIN_YEAR - 1, MAX_YEAR + 1, i32::MIN, i32::MAX] {
        assert_eq!(Date::new(y, 1, 1), Err(DateError::Year));
    }
}

/// The unvalidated arithmetic beyond a `Date`'s years, sampled with a stride
/// that walks through every day of the 400-year cycle and every month, over
/// chrono's own range (years ±262 143).
#[test]
fn raw_arithmetic_agrees_with_chrono_beyond_the_date_range() {
    let lo = chrono_days_since_unix_epoch(NaiveDate::MIN);
    let hi = chrono_days_since_unix_epoch(NaiveDate::MAX);
    let mut samples = 0;
    for days in (lo..=hi).step_by(9_973).chain([lo, hi]) {
        let reference = chrono_date(days);
        let (y, m, d) = fields(reference);
        assert_eq!(civil_from_days(days), (y, m, d), "{days}");
        assert_eq!(days_from_civil(y, m, d), i64::from(days), "{y}-{m}-{d}");
        samples += 1;
    }
    assert!(samples > 19_000, "{samples}");
}

/// Named dates: leap days and month ends around the century rules, the ends of
/// the range, the Unix epoch (expected values from Python's `datetime`:
/// `(date(y, m, d) - date(1970, 1, 1)).days`; for years before 1, which
/// Python lacks, from chrono).
#[test]
fn leap_days_and_month_ends() {
    let python: [((i32, u8, u8), i32); 12] = [
        ((1900, 2, 28), -25_509),
        ((1900, 3, 1), -25_508),
        ((2000, 2, 29), 11_016),
        ((2000, 3, 1), 11_017),
        ((2100, 2, 28), 47_540),
        ((2100, 3, 1), 47_541),
        ((2024, 2, 29), 19_782),
        ((2024, 4, 30), 19_843),
        ((2024, 12, 31), 20_088),
        ((1970, 1, 1), 0),
        ((1, 1, 1), -719_162),
        ((9999, 12, 31), 2_932_896),
    ];
    for ((y, m, d), days) in python {
        let date = Date::new(y, m, d).unwrap();
        assert_eq!(date.days_since_unix_epoch(), days, "{date}");
        assert_eq!(Date::from_days_since_unix_epoch(days), Ok(date));
    }
    for (y, m, d) in [(1900, 2, 29), (2100, 2, 29), (2023, 2, 29), (2024, 4, 31)] {
        assert_eq!(Date::new(y, m, d), Err(DateError::Day), "{y}-{m}-{d}");
    }
    for (y, m, d) in [(0, 2, 29), (-1, 2, 28), (-100, 3, 1), (-400, 2, 29)] {
        let reference = NaiveDate::from_ymd_opt(y, u32::from(m), u32::from(d)).unwrap();
        let date = Date::new(y, m, d).unwrap();
        assert_eq!(
            date.days_since_unix_epoch(),
            chrono_days_since_unix_epoch(reference)
        );
    }
    assert_eq!(Date::new(-100, 2, 29), Err(DateError::Day));
}

/// The unvalidated count rolls over like the calendar for month 0 and 13 and
/// for day numbers past either end of a month (what device models that
/// accept any register value rely on).
#[test]
fn raw_count_rolls_over_months_and_days() {
    let days = |y: i32, m: u32, d: u32| {
        i64::from(chrono_days_since_unix_epoch(
            NaiveDate::from_ymd_opt(y, m, d).unwrap(),
        ))
    };
    for y in MIN_YEAR + 1..MAX_YEAR {
        // Month 0 is December of the year before, month 13 January of the next.
        assert_eq!(days_from_civil(y, 0, 15), days(y - 1, 12, 15), "{y}");
        assert_eq!(days_from_civil(y, 13, 1), days(y + 1, 1, 1), "{y}");
        for m in 1..=12u8 {
            let first = days(y, u32::from(m), 1);
            // Day 0 is the day before the first, and a day past the end
            // continues into the next month.
            assert_eq!(days_from_civil(y, m, 0), first - 1, "{y}-{m}");
            let len = i64::from(days_in_month(y, m));
            assert_eq!(days_from_civil(y, m, 40), first + 39, "{y}-{m}");
            assert_eq!(
                days_from_civil(y, m, days_in_month(y, m) + 1),
                first + len,
                "{y}-{m}"
            );
        }
    }
}
