//! The `serde` feature: `Date` round trips through JSON as its fields and is
//! validated again when read, so an invalid date is an error.
#![cfg(feature = "serde")]

use suntracker_time::{Date, DateError};

#[test]
fn dates_round_trip_as_their_fields() {
    let d = Date::new(2024, 2, 29).unwrap();
    let text = serde_json::to_string(&d).unwrap();
    assert_eq!(text, r#"{"year":2024,"month":2,"day":29}"#);
    assert_eq!(serde_json::from_str::<Date>(&text).unwrap(), d);
    for d in [
        Date::MIN,
        Date::MAX,
        Date::UNIX_EPOCH,
        Date::new(-44, 3, 15).unwrap(),
    ] {
        let text = serde_json::to_string(&d).unwrap();
        assert_eq!(serde_json::from_str::<Date>(&text).unwrap(), d, "{text}");
    }
}

#[test]
fn invalid_dates_are_deserialization_errors() {
    for (text, why) in [
        (r#"{"year":2023,"month":2,"day":29}"#, DateError::Day),
        (r#"{"year":1900,"month":2,"day":29}"#, DateError::Day),
        (r#"{"year":2024,"month":4,"day":31}"#, DateError::Day),
        (r#"{"year":2024,"month":1,"day":0}"#, DateError::Day),
        (r#"{"year":2024,"month":13,"day":1}"#, DateError::Month),
        (r#"{"year":2024,"month":0,"day":1}"#, DateError::Month),
        (r#"{"year":10000,"month":1,"day":1}"#, DateError::Year),
        (r#"{"year":-10000,"month":1,"day":1}"#, DateError::Year),
    ] {
        let err = serde_json::from_str::<Date>(text).unwrap_err();
        // The message is the DateError's own.
        assert!(
            err.to_string().starts_with(&why.to_string()),
            "{text}: {err}"
        );
    }
    // Not a date at all: wrong types, missing fields, out of the field types.
    for text in [
        r#"{"year":2024,"month":2}"#,
        r#"{"year":2024,"month":256,"day":1}"#,
        r#"{"year":"2024","month":2,"day":1}"#,
        r#""2024-02-29""#,
    ] {
        assert!(serde_json::from_str::<Date>(text).is_err(), "{text}");
    }
}

#[test]
fn date_errors_round_trip() {
    for e in [DateError::Year, DateError::Month, DateError::Day] {
        let text = serde_json::to_string(&e).unwrap();
        assert_eq!(serde_json::from_str::<DateError>(&text).unwrap(), e);
    }
    assert_eq!(
        serde_json::to_string(&DateError::Year).unwrap(),
        r#""Year""#
    );
}
