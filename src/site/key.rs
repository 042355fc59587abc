//! Packing of a (country, postal code) pair into one sortable `u64`.
//!
//! Shared by the build script (which sorts the table by it) and the
//! firmware (which binary-searches it), so both agree by construction.
//!
//! - Country: ISO 3166-1 alpha-2, two letters A–Z, 5 bits each (10 bits).
//! - Postal code: up to [`MAX_CODE_LEN`] characters, each a base-38 digit
//!   (0 = padding, `0`–`9` → 1–10, `A`–`Z` → 11–36, space or `-` → 37),
//!   left-aligned so numeric order equals the codes' lexicographic order;
//!   38¹⁰ < 2⁵³, so key = country << 53 | code.
//!
//! Lower-case letters are accepted and folded to upper case.

/// Longest postal code the table stores (the UK's "SW1A 1AA" is 8, the
/// longest in use worldwide are 10 with separators).
pub const MAX_CODE_LEN: usize = 10;

/// Why a country or postal code cannot be packed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyError {
    /// Country is not two letters A–Z.
    BadCountry,
    /// Postal code empty, longer than [`MAX_CODE_LEN`], or with a character
    /// other than 0–9, A–Z, space and `-`.
    BadPostalCode,
}

fn letter(b: u8) -> Option<u64> {
    match b {
        b'A'..=b'Z' => Some(u64::from(b - b'A')),
        b'a'..=b'z' => Some(u64::from(b - b'a')),
        _ => None,
    }
}

fn code_digit(b: u8) -> Option<u64> {
    match b {
        b'0'..=b'9' => Some(u64::from(b - b'0') + 1),
        b'A'..=b'Z' => Some(u64::from(b - b'A') + 11),
        b'a'..=b'z' => Some(u64::from(b - b'a') + 11),
        b' ' | b'-' => Some(37),
        _ => None,
    }
}

/// The 10-bit country number of an alpha-2 code.
pub fn pack_country(country: &[u8]) -> Result<u64, KeyError> {
    match country {
        [a, b] => match (letter(*a), letter(*b)) {
            (Some(a), Some(b)) => Ok(a << 5 | b),
            _ => Err(KeyError::BadCountry),
        },
        _ => Err(KeyError::BadCountry),
    }
}

/// The key of a (country, postal code) pair.
pub fn pack(country: &[u8], code: &[u8]) -> Result<u64, KeyError> {
    let c = pack_country(country)?;
    if code.is_empty() || code.len() > MAX_CODE_LEN {
        return Err(KeyError::BadPostalCode);
    }
    let mut v: u64 = 0;
    for i in 0..MAX_CODE_LEN {
        let d = match code.get(i) {
            Some(&b) => code_digit(b).ok_or(KeyError::BadPostalCode)?,
            None => 0,
        };
        v = v * 38 + d;
    }
    Ok(c << 53 | v)
}
