//! The serialized form of [`DateTime`] (feature `serde`): its seven fields,
//! `{"year":2024,"month":2,"day":29,"hour":12,"minute":0,"second":0,"millis":0}`
//! in JSON, validated again by [`DateTime::new`] and [`DateTime::with_millis`]
//! when deserialized (serde's `try_from`), so that an invalid date-time is an
//! error of the deserializer and never an invalid [`DateTime`].
//!
//! ```
//! use drivers::time::DateTime;
//!
//! let t = DateTime::new(2024, 2, 29, 12, 0, 0)?;
//! let json = serde_json::to_string(&t)?;
//! assert_eq!(json, r#"{"year":2024,"month":2,"day":29,"hour":12,"minute":0,"second":0,"millis":0}"#);
//! assert_eq!(serde_json::from_str::<DateTime>(&json)?, t);
//! // 2023 is not a leap year: refused, with the reason.
//! let bad = r#"{"year":2023,"month":2,"day":29,"hour":12,"minute":0,"second":0,"millis":0}"#;
//! let e = serde_json::from_str::<DateTime>(bad).unwrap_err();
//! assert!(e.to_string().contains("day is 0 or past the end of the month"));
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```

use serde::{Deserialize, Serialize};

use super::{DateTime, DateTimeError};

/// A date-time's fields as serialized; not validated until converted.
#[derive(Serialize, Deserialize)]
#[serde(rename = "DateTime")]
pub(crate) struct DateTimeFields {
    year: u16,
    month: u8,
    day: u8,
    hour: u8,
    minute: u8,
    second: u8,
    millis: u16,
}

impl From<DateTime> for DateTimeFields {
    fn from(t: DateTime) -> Self {
        DateTimeFields {
            year: t.year(),
            month: t.month(),
            day: t.day(),
            hour: t.hour(),
            minute: t.minute(),
            second: t.second(),
            millis: t.millis(),
        }
    }
}

impl TryFrom<DateTimeFields> for DateTime {
    type Error = DateTimeError;

    fn try_from(f: DateTimeFields) -> Result<DateTime, DateTimeError> {
        DateTime::new(f.year, f.month, f.day, f.hour, f.minute, f.second)?.with_millis(f.millis)
    }
}
