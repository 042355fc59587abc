//! Decimal numbers: read as typed ([`Decimal`]), without core's float
//! parsing, and written back ([`write_number`]) so that they read the same.

use crate::log::Sink;
use crate::text::FlashStr;

/// Why a word is not a number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NumberError {
    /// Not `[+-]digits[.digits]`: `not a number`.
    Invalid,
    /// The whole part exceeds 4,294,967,295: `number too large`.
    TooLarge,
}

impl NumberError {
    /// The reply text.
    pub fn text(self) -> FlashStr {
        match self {
            NumberError::Invalid => crate::flash_str!("not a number"),
            NumberError::TooLarge => crate::flash_str!("number too large"),
        }
    }
}

/// Fraction digits kept at most (further ones only count for
/// [`Decimal::has_fraction`]): an `f32` resolves nothing finer in the
/// configuration's ranges.
const MAX_SCALE: u8 = 12;

/// A decimal number as typed: `±digits / 10^scale`, read without core's
/// float parsing (whose tables cost kilobytes on an AVR) and without
/// division.
///
/// Whole numbers up to 4,294,967,295 are exact. Fraction digits are kept
/// while the digits fit in a `u32` (at least nine significant digits,
/// beyond an `f32`'s seven) and at most twelve places; further ones only
/// count for [`Decimal::has_fraction`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Decimal {
    negative: bool,
    /// The whole part.
    whole: u32,
    /// The digits kept, whole part and fraction.
    digits: u32,
    /// Fraction digits in `digits`.
    scale: u8,
    /// A fraction digit other than zero was typed.
    fraction: bool,
}

/// `v × 10 + d` unless it exceeds `u32::MAX` (compared, not multiplied
/// in 64 bits: an 8-bit core has no cheap wide multiply).
fn times_ten_plus(v: u32, d: u32) -> Option<u32> {
    const MAX_DIV_10: u32 = u32::MAX / 10;
    const MAX_REM_10: u32 = u32::MAX % 10;
    if v > MAX_DIV_10 || (v == MAX_DIV_10 && d > MAX_REM_10) {
        None
    } else {
        Some(v.wrapping_mul(10).wrapping_add(d))
    }
}

impl Decimal {
    /// Reads `[+-]digits[.digits]`: at least one digit before a point and
    /// one after it; nothing else (no exponent, no `nan`, no `inf`, no
    /// spaces).
    pub fn parse(s: &str) -> Result<Decimal, NumberError> {
        let bytes = s.as_bytes();
        let (negative, rest) = match bytes.split_first() {
            Some((b'-', r)) => (true, r),
            Some((b'+', r)) => (false, r),
            _ => (false, bytes),
        };
        let mut d = Decimal {
            negative,
            whole: 0,
            digits: 0,
            scale: 0,
            fraction: false,
        };
        let (mut whole_digits, mut point, mut fraction_digits) = (false, false, false);
        for &b in rest {
            if b == b'.' && whole_digits && !point {
                point = true;
                continue;
            }
            if !b.is_ascii_digit() {
                return Err(NumberError::Invalid);
            }
            let digit = u32::from(b.wrapping_sub(b'0'));
            // Before the point `digits` is the whole part: one step serves
            // both parts (one copy of it, 28 B less on the ATmega2560).
            let next = if point && d.scale >= MAX_SCALE {
                None
            } else {
                times_ten_plus(d.digits, digit)
            };
            if point {
                fraction_digits = true;
                d.fraction |= digit != 0;
                if let Some(v) = next {
                    d.digits = v;
                    d.scale = d.scale.saturating_add(1);
                }
            } else {
                whole_digits = true;
                d.whole = next.ok_or(NumberError::TooLarge)?;
                d.digits = d.whole;
            }
        }
        if !whole_digits || (point && !fraction_digits) {
            return Err(NumberError::Invalid);
        }
        if d.whole == 0 && !d.fraction {
            d.negative = false;
        }
        Ok(d)
    }

    /// A whole number.
    pub fn from_u32(value: u32) -> Decimal {
        Decimal {
            negative: false,
            whole: value,
            digits: value,
            scale: 0,
            fraction: false,
        }
    }

    /// The nearest `f32` (within one unit in the last place); always
    /// finite.
    pub fn to_f32(&self) -> f32 {
        let mut scale = 1.0f32;
        for _ in 0..self.scale {
            scale *= 10.0;
        }
        let v = self.digits as f32 / scale;
        if self.negative {
            -v
        } else {
            v
        }
    }

    /// True when the number has a fraction that is not zero.
    pub fn has_fraction(&self) -> bool {
        self.fraction
    }

    /// The number as a `u32`: `None` when it has a fraction or is negative.
    pub fn to_u32(&self) -> Option<u32> {
        let negative = self.negative && self.whole != 0;
        (!self.fraction && !negative).then_some(self.whole)
    }
}

/// Writes `value` with as many decimals as an `f32` holds reliably (at
/// most six, so that the scaled value stays below 2^21), trailing zeros
/// dropped: `25`, `0.05`, `11.9683`, `-179.1234`. A printed value read
/// back by [`Decimal::parse`] prints the same. `nan` for a value that is
/// not finite or above 4 × 10^9.
pub fn write_number(out: &mut dyn Sink, value: f32) {
    const LIMIT: f32 = 2_097_152.0;
    let magnitude = if value < 0.0 { -value } else { value };
    let mut decimals: u8 = 6;
    let mut scale = 1_000_000.0f32;
    while decimals > 0 && magnitude * scale >= LIMIT {
        decimals -= 1;
        scale /= 10.0;
    }
    // Below LIMIT (or zero decimals, where the count is not used): the
    // cast saturates and cannot fail.
    let mut units = (magnitude * scale + 0.5) as u32;
    while decimals > 0 && units.is_multiple_of(10) {
        units /= 10;
        decimals -= 1;
    }
    out.fixed(value, decimals);
}
