//! The serialized form of [`Date`] (feature `serde`): its three fields,
//! `{"year":2024,"month":2,"day":29}` in JSON, validated again by
//! [`Date::new`] when deserialized, so that an invalid date is an error of
//! the deserializer and never an invalid `Date`.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::Date;

/// A date's fields as serialized; not validated until converted.
#[derive(Serialize, Deserialize)]
#[serde(rename = "Date")]
struct DateFields {
    year: i32,
    month: u8,
    day: u8,
}

impl Serialize for Date {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        DateFields {
            year: self.year(),
            month: self.month(),
            day: self.day(),
        }
        .serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for Date {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let f = DateFields::deserialize(deserializer)?;
        Date::new(f.year, f.month, f.day).map_err(serde::de::Error::custom)
    }
}
