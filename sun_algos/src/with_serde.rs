//! Serialized forms of the types with validated fields (feature `serde`).
//!
//! [`Site`], [`Atmosphere`], [`UtcTime`], [`Limits`], day-table [`Entry`]s
//! and [`DayTable`]s are written as their fields and read back through the
//! same checks as their constructors, so that an invalid value is an error
//! of the deserializer (with the crate's error message) and never an invalid
//! object. The plain-data types (public fields, any value valid) derive their
//! impls where they are defined.
//!
//! | type | form (JSON) |
//! |---|---|
//! | `Site` | `{"latitude_deg":11.97,"longitude_deg":8.43,"elevation_m":480.0}` (`elevation_m` may be left out: sea level) |
//! | `Atmosphere` | `{"pressure_hpa":1010.0,"temperature_c":25.0}` |
//! | `UtcTime` | `{"date":{"year":2026,"month":6,"day":21},"ms_of_day":43200000}` |
//! | `Limits` | `{"slope_min_deg":0.0,"slope_max_deg":90.0,"azimuth_min_deg":0.0,"azimuth_max_deg":360.0}` |
//! | `Entry` | `{"slope_cdeg":4512,"azimuth_cdeg":18000}` |
//! | `DayTable<N>` | `{"first":…,"interval_min":4,"needed":181,"entries":[…]}` |

use heapless::Vec;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::float::Float;
use crate::geometry::day_table::{interval_is_valid, DayTable, Entry};
use crate::geometry::{GeometryError, Limits};
use crate::site::{Atmosphere, Site};
use crate::time::{Date, UtcTime};

#[derive(Serialize, Deserialize)]
#[serde(rename = "Site")]
struct SiteFields<T> {
    latitude_deg: T,
    longitude_deg: T,
    #[serde(default)]
    elevation_m: T,
}

impl<T: Float + Serialize> Serialize for Site<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        SiteFields {
            latitude_deg: self.latitude_deg(),
            longitude_deg: self.longitude_deg(),
            elevation_m: self.elevation_m(),
        }
        .serialize(serializer)
    }
}

impl<'de, T: Float + Deserialize<'de>> Deserialize<'de> for Site<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let f = SiteFields::<T>::deserialize(deserializer)?;
        Site::with_elevation(f.latitude_deg, f.longitude_deg, f.elevation_m)
            .map_err(D::Error::custom)
    }
}

#[derive(Serialize, Deserialize)]
#[serde(rename = "Atmosphere")]
struct AtmosphereFields<T> {
    pressure_hpa: T,
    temperature_c: T,
}

impl<T: Float + Serialize> Serialize for Atmosphere<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        AtmosphereFields {
            pressure_hpa: self.pressure_hpa(),
            temperature_c: self.temperature_c(),
        }
        .serialize(serializer)
    }
}

impl<'de, T: Float + Deserialize<'de>> Deserialize<'de> for Atmosphere<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let f = AtmosphereFields::<T>::deserialize(deserializer)?;
        Atmosphere::new(f.pressure_hpa, f.temperature_c).map_err(D::Error::custom)
    }
}

#[derive(Serialize, Deserialize)]
#[serde(rename = "UtcTime")]
struct UtcTimeFields {
    /// Validated by `Date`'s own impl (any proleptic Gregorian date of
    /// years −9999…9999), then narrowed to −4000…8000 here.
    date: Date,
    ms_of_day: u32,
}

impl Serialize for UtcTime {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        UtcTimeFields {
            date: self.date(),
            ms_of_day: self.ms_of_day(),
        }
        .serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for UtcTime {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let f = UtcTimeFields::deserialize(deserializer)?;
        UtcTime::from_date_ms(f.date, f.ms_of_day).map_err(D::Error::custom)
    }
}

#[derive(Serialize, Deserialize)]
#[serde(rename = "Limits")]
struct LimitsFields<T> {
    slope_min_deg: T,
    slope_max_deg: T,
    azimuth_min_deg: T,
    azimuth_max_deg: T,
}

impl<T: Float + Serialize> Serialize for Limits<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        LimitsFields {
            slope_min_deg: self.slope_min_deg(),
            slope_max_deg: self.slope_max_deg(),
            azimuth_min_deg: self.azimuth_min_deg(),
            azimuth_max_deg: self.azimuth_max_deg(),
        }
        .serialize(serializer)
    }
}

impl<'de, T: Float + Deserialize<'de>> Deserialize<'de> for Limits<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let f = LimitsFields::<T>::deserialize(deserializer)?;
        Limits::new(
            f.slope_min_deg,
            f.slope_max_deg,
            f.azimuth_min_deg,
            f.azimuth_max_deg,
        )
        .map_err(D::Error::custom)
    }
}

#[derive(Serialize, Deserialize)]
#[serde(rename = "Entry")]
struct EntryFields {
    slope_cdeg: i16,
    azimuth_cdeg: u16,
}

impl Serialize for Entry {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        EntryFields {
            slope_cdeg: self.slope_cdeg(),
            azimuth_cdeg: self.azimuth_cdeg(),
        }
        .serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for Entry {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let f = EntryFields::deserialize(deserializer)?;
        Entry::from_cdeg(f.slope_cdeg, f.azimuth_cdeg).ok_or_else(|| {
            D::Error::custom(
                "day-table entry outside slope -18000..=18000 cdeg, azimuth 0..36000 cdeg",
            )
        })
    }
}

#[derive(Serialize)]
#[serde(rename = "DayTable")]
struct DayTableRef<'a, const N: usize> {
    first: UtcTime,
    interval_min: u16,
    needed: u16,
    entries: &'a Vec<Entry, N, u16>,
}

#[derive(Deserialize)]
#[serde(rename = "DayTable")]
struct DayTableFields<const N: usize> {
    first: UtcTime,
    interval_min: u16,
    needed: u16,
    entries: Vec<Entry, N, u16>,
}

impl<const N: usize> Serialize for DayTable<N> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let (first, interval_min, needed, entries) = self.parts();
        DayTableRef {
            first,
            interval_min,
            needed,
            entries,
        }
        .serialize(serializer)
    }
}

impl<'de, const N: usize> Deserialize<'de> for DayTable<N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        // More entries than N is already an error of heapless' Vec.
        let f = DayTableFields::<N>::deserialize(deserializer)?;
        if !interval_is_valid(f.interval_min) {
            return Err(D::Error::custom(GeometryError::InvalidInterval));
        }
        if usize::from(f.needed) > N {
            return Err(D::Error::custom(GeometryError::CapacityExceeded {
                needed: usize::from(f.needed),
                capacity: N,
            }));
        }
        if f.entries.len() > usize::from(f.needed) {
            return Err(D::Error::custom(
                "day table holds more entries than its day needs",
            ));
        }
        Ok(DayTable::from_parts(
            f.first,
            f.interval_min,
            f.needed,
            f.entries,
        ))
    }
}
