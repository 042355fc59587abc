//! Conversions between the drivers' [`DateTime`] and `sun_algos`' [`UtcTime`].
//!
//! Both types keep their calendar in the same `suntracker-time` [`Date`]
//! (one day-count arithmetic in the workspace), so a conversion hands the
//! date across as it is and only re-expresses the time of day; what is left
//! to check is each type's own year range.

use drivers::time::DateTime;
#[cfg(doc)]
use sun_algos::time::Date;
use sun_algos::UtcTime;

/// A date-time that one side cannot represent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeConversionError {
    /// Outside the other type's calendar range ([`UtcTime`]: years
    /// −4000…8000; [`DateTime`]: years 1…9999).
    OutOfRange,
}

/// The same instant as a [`UtcTime`] (milliseconds kept).
pub fn utc_from_datetime(t: &DateTime) -> Result<UtcTime, TimeConversionError> {
    UtcTime::from_date_ms(t.date(), t.ms_of_day()).map_err(|_| TimeConversionError::OutOfRange)
}

/// The same instant as a [`DateTime`] (milliseconds kept).
pub fn datetime_from_utc(t: &UtcTime) -> Result<DateTime, TimeConversionError> {
    DateTime::from_date_ms(t.date(), t.ms_of_day()).map_err(|_| TimeConversionError::OutOfRange)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_day_both_types_hold_converts_both_ways() {
        // Years 1..=8000: the overlap of DateTime (1..=9999) and UtcTime
        // (-4000..=8000).
        let first = UtcTime::from_ymd_hms(1, 1, 1, 0, 0, 0).unwrap();
        let last = UtcTime::from_ymd_hms(8000, 12, 31, 0, 0, 0).unwrap();
        for days in first.days_since_2000()..=last.days_since_2000() {
            let u = UtcTime::from_days_ms(days, 86_399_999).unwrap();
            let d = datetime_from_utc(&u).unwrap();
            assert_eq!(
                d.days_since_unix_epoch() * 86_400,
                u.unix_seconds() - 86_399
            );
            assert_eq!(utc_from_datetime(&d), Ok(u));
        }
    }

    #[test]
    fn known_instant_and_the_ends_of_each_range() {
        // 2009-02-13T23:31:30Z is Unix time 1 234 567 890.
        let d = DateTime::new(2009, 2, 13, 23, 31, 30)
            .unwrap()
            .with_millis(250)
            .unwrap();
        let u = utc_from_datetime(&d).unwrap();
        assert_eq!(u.unix_seconds(), 1_234_567_890);
        assert_eq!(u.hms_milli(), (23, 31, 30, 250));
        assert_eq!(datetime_from_utc(&u), Ok(d));
        // A DateTime after UtcTime's last year, a UtcTime before DateTime's
        // first.
        let late = DateTime::new(8001, 1, 1, 0, 0, 0).unwrap();
        assert_eq!(
            utc_from_datetime(&late),
            Err(TimeConversionError::OutOfRange)
        );
        let early = UtcTime::from_ymd_hms(0, 12, 31, 23, 59, 59).unwrap();
        assert_eq!(
            datetime_from_utc(&early),
            Err(TimeConversionError::OutOfRange)
        );
    }
}
