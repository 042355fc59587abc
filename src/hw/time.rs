//! Conversions between the drivers' [`DateTime`] and `sun_algos`' [`UtcTime`].

use drivers::time::DateTime;
use sun_algos::UtcTime;

/// A date-time that one side cannot represent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeConversionError {
    /// Outside the other type's calendar range (e.g. a year past 65535 for
    /// [`DateTime`]).
    OutOfRange,
}

/// The same instant as a [`UtcTime`] (milliseconds kept).
pub fn utc_from_datetime(t: &DateTime) -> Result<UtcTime, TimeConversionError> {
    UtcTime::from_ymd_hms_milli(
        i32::from(t.year()),
        t.month(),
        t.day(),
        t.hour(),
        t.minute(),
        t.second(),
        t.millis(),
    )
    .map_err(|_| TimeConversionError::OutOfRange)
}

/// The same instant as a [`DateTime`] (milliseconds kept).
pub fn datetime_from_utc(t: &UtcTime) -> Result<DateTime, TimeConversionError> {
    let (y, mo, d) = t.ymd();
    let (h, mi, s, ms) = t.hms_milli();
    let year = u16::try_from(y).map_err(|_| TimeConversionError::OutOfRange)?;
    DateTime::new(year, mo, d, h, mi, s)
        .and_then(|dt| dt.with_millis(ms))
        .map_err(|_| TimeConversionError::OutOfRange)
}
