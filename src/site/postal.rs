//! Postal code → latitude/longitude, a compact sorted table in flash.
//!
//! Dahli & Cheggaga 2023 replaces the GPS receiver by the postal (ZIP) code of the
//! installation: the code names a place whose coordinates are in a table.
//! `build.rs` reads `data/postal_codes.csv` (columns
//! `country,postal_code,place,latitude,longitude`), packs each row and
//! sorts it; lookup is a binary search.
//!
//! Format per entry, 14 bytes of flash: an 8-byte key (country and code,
//! [`super::key`]) and latitude and longitude as 24-bit integers in units
//! of 1e-4° (±0.00005° rounding, ≤ 5.6 m on the ground — far finer than
//! the place a postal code stands for). 1000 entries cost 14 000 bytes;
//! place names are a separate array the linker keeps only when
//! [`PostalEntry::place`] is used.

use sun_algos::{Float, Site};

use super::key::{self, KeyError};

mod table {
    include!(concat!(env!("OUT_DIR"), "/postal_table.rs"));
}

/// Flash bytes of the keys and coordinates (place names excluded), as the
/// compiler lays the two arrays out: 14 per entry.
pub const TABLE_BYTES: usize =
    core::mem::size_of::<[u64; table::LEN]>() + core::mem::size_of::<[[u8; 6]; table::LEN]>();

/// Number of postal codes in the table.
pub const LEN: usize = table::LEN;

/// Why a postal code gave no site.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PostalError {
    /// Country is not two letters.
    BadCountry,
    /// Not a well-formed postal code (empty, too long, bad characters).
    BadPostalCode,
    /// `COUNTRY:CODE` expected (e.g. `DZ:16000`).
    BadFormat,
    /// Well-formed but not in the table.
    UnknownPostalCode,
    /// This image was built without the table: its board left it out for
    /// flash (`Platform::POSTAL_CODES` in the firmware loop).
    NoTable,
}

impl From<KeyError> for PostalError {
    fn from(e: KeyError) -> Self {
        match e {
            KeyError::BadCountry => PostalError::BadCountry,
            KeyError::BadPostalCode => PostalError::BadPostalCode,
        }
    }
}

impl core::fmt::Display for PostalError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            PostalError::BadCountry => "country must be two letters (ISO 3166-1 alpha-2)",
            PostalError::BadPostalCode => "postal code must be 1-10 of 0-9, A-Z, space, '-'",
            PostalError::BadFormat => "expected COUNTRY:CODE, e.g. DZ:16000",
            PostalError::UnknownPostalCode => "postal code not in the table",
            PostalError::NoTable => "no postal-code table in this image",
        })
    }
}

/// One row of the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PostalEntry {
    index: usize,
    lat_e4: i32,
    lon_e4: i32,
}

impl PostalEntry {
    /// Latitude in units of 1e-4 degree.
    pub fn latitude_e4(&self) -> i32 {
        self.lat_e4
    }
    /// Longitude in units of 1e-4 degree.
    pub fn longitude_e4(&self) -> i32 {
        self.lon_e4
    }
    /// Latitude in degrees, north positive.
    pub fn latitude_deg<T: Float>(&self) -> T {
        T::from_i32(self.lat_e4) / T::from_f64(1e4)
    }
    /// Longitude in degrees, east positive.
    pub fn longitude_deg<T: Float>(&self) -> T {
        T::from_i32(self.lon_e4) / T::from_f64(1e4)
    }
    /// The place's name from the CSV.
    pub fn place(&self) -> &'static str {
        table::PLACES.get(self.index).copied().unwrap_or("")
    }
    /// The site at sea level (the table has no elevation).
    pub fn site<T: Float>(&self) -> Result<Site<T>, sun_algos::Error> {
        Site::new(self.latitude_deg(), self.longitude_deg())
    }
}

fn i24(b: &[u8]) -> i32 {
    match b {
        [a, b, c] => {
            let v = i32::from(*a) | i32::from(*b) << 8 | i32::from(*c) << 16;
            // Sign-extend from 24 bits.
            (v << 8) >> 8
        }
        _ => 0,
    }
}

/// The entry of `country` (alpha-2) and `code`.
pub fn lookup(country: &str, code: &str) -> Result<PostalEntry, PostalError> {
    let k = key::pack(country.as_bytes(), code.trim_ascii().as_bytes())?;
    // Binary search over the keys in flash (read one at a time on AVR).
    let (mut lo, mut hi) = (0usize, table::LEN);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        let Some(key) = table::KEYS.get(mid) else {
            break;
        };
        match key.cmp(&k) {
            core::cmp::Ordering::Less => lo = mid + 1,
            core::cmp::Ordering::Greater => hi = mid,
            core::cmp::Ordering::Equal => return Ok(entry(mid)),
        }
    }
    Err(PostalError::UnknownPostalCode)
}

/// Row `index` (coordinates read from flash on AVR).
fn entry(index: usize) -> PostalEntry {
    let c = table::COORDS.get(index).unwrap_or([0; 6]);
    PostalEntry {
        index,
        lat_e4: i24(c.get(0..3).unwrap_or(&[])),
        lon_e4: i24(c.get(3..6).unwrap_or(&[])),
    }
}

/// The entry of `COUNTRY:CODE`, e.g. `DZ:16000`.
pub fn lookup_str(s: &str) -> Result<PostalEntry, PostalError> {
    let (country, code) = s
        .trim_ascii()
        .split_once(':')
        .ok_or(PostalError::BadFormat)?;
    lookup(country.trim_ascii(), code)
}

/// Every entry, in key order (country, then code).
pub fn entries() -> impl Iterator<Item = PostalEntry> {
    (0..table::LEN).map(entry)
}
