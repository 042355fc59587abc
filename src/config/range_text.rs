//! The texts of the ranges, built when compiling from the constants of
//! [`super::ranges`], so that each range is written once: `lo...hi` with
//! thousands separators (`16,777,216`), a minus sign (`-90`) and decimals
//! without trailing zeros (`0.01`, `45`), as the console prints them in
//! `error <key>: <reason>` ([`super::Reason::text`]).
//!
//! A text is a list of [`Piece`]s; [`write()`] prints them into a buffer
//! and returns the length they need, so the same function sizes the array
//! ([`len`]) and fills it ([`to_array`]). Everything here is `const`: in an
//! image the texts are constants, and nothing of this module is linked.

/// A number as the texts print it: an optional `-`, the integer part with
/// a `,` every three digits, and the decimals it needs (none for a whole
/// number).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Num {
    neg: bool,
    int: u64,
    frac: u64,
    digits: u32,
}

/// Most decimals of a [`Num::f32`]: an `f32` has 6 to 9 significant
/// digits, and the ranges need two at most.
const MAX_DIGITS: u32 = 6;

impl Num {
    /// An integer.
    pub const fn int(v: i64) -> Num {
        Num {
            neg: v < 0,
            int: v.unsigned_abs(),
            frac: 0,
            digits: 0,
        }
    }

    /// `v` with the fewest decimals (at most 6) whose decimal number reads
    /// back as `v` (`0.01` for `0.01_f32`, which is 0.0099999998 exactly).
    /// Fails to compile for a `v` that is not finite, at least 10^12 in
    /// magnitude, or has no such decimal.
    pub const fn f32(v: f32) -> Num {
        assert!(v.is_finite(), "a range end is finite");
        let a = if v < 0.0 { -v } else { v };
        assert!(a < 1e12, "a range end is below 10^12");
        let mut digits = 0;
        let mut scale = 1u64;
        while digits <= MAX_DIGITS {
            // Rounded to `digits` decimals; `a * scale` is below 10^18.
            let scaled = (a as f64 * scale as f64 + 0.5) as u64;
            if (scaled as f64 / scale as f64) as f32 == a {
                return Num {
                    neg: v < 0.0,
                    int: scaled / scale,
                    frac: scaled % scale,
                    digits,
                };
            }
            digits += 1;
            scale *= 10;
        }
        panic!("a range end has at most 6 decimals")
    }

    /// The same number with the other sign.
    pub const fn neg(self) -> Num {
        Num {
            neg: !self.neg,
            ..self
        }
    }

    /// True below zero.
    pub const fn is_negative(self) -> bool {
        self.neg && (self.int != 0 || self.frac != 0)
    }
}

/// A piece of a text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Piece {
    /// Words, as they are.
    Str(&'static str),
    /// A number: `16,777,216`, `-90`, `0.01`.
    Num(Num),
    /// A range: `lo...hi`.
    Range(Num, Num),
    /// An offset added to a name: ` + 10`, ` - 5`.
    Offset(Num),
}

/// The range of `u8`s `(lo, hi)`.
pub const fn u8s((lo, hi): (u8, u8)) -> Piece {
    Piece::Range(Num::int(lo as i64), Num::int(hi as i64))
}

/// The range of `u16`s `(lo, hi)`.
pub const fn u16s((lo, hi): (u16, u16)) -> Piece {
    Piece::Range(Num::int(lo as i64), Num::int(hi as i64))
}

/// The range of `u32`s `(lo, hi)`.
pub const fn u32s((lo, hi): (u32, u32)) -> Piece {
    Piece::Range(Num::int(lo as i64), Num::int(hi as i64))
}

/// The range of `f32`s `(lo, hi)` ([`Num::f32`]).
pub const fn f32s((lo, hi): (f32, f32)) -> Piece {
    Piece::Range(Num::f32(lo), Num::f32(hi))
}

/// Puts `b` at `out[at]` if there is room; the next position.
const fn put(out: &mut [u8], at: usize, b: u8) -> usize {
    if at < out.len() {
        out[at] = b;
    }
    at + 1
}

/// Puts the bytes of `s` from `out[at]` on, as far as there is room; the
/// next position.
const fn put_str(out: &mut [u8], mut at: usize, s: &str) -> usize {
    let b = s.as_bytes();
    let mut i = 0;
    while i < b.len() {
        at = put(out, at, b[i]);
        i += 1;
    }
    at
}

/// Puts `n` ([`Num`]) from `out[at]` on; the next position.
const fn put_num(out: &mut [u8], mut at: usize, n: Num) -> usize {
    if n.is_negative() {
        at = put(out, at, b'-');
    }
    // The integer part, highest digit first, a `,` before each group of
    // three.
    let mut p = 1u64;
    let mut left = 1;
    while n.int / p >= 10 {
        p *= 10;
        left += 1;
    }
    while left > 0 {
        at = put(out, at, b'0' + (n.int / p % 10) as u8);
        left -= 1;
        if left > 0 && left % 3 == 0 {
            at = put(out, at, b',');
        }
        p /= 10;
    }
    if n.digits > 0 {
        at = put(out, at, b'.');
        let mut p = 10u64.pow(n.digits - 1);
        while p > 0 {
            at = put(out, at, b'0' + (n.frac / p % 10) as u8);
            p /= 10;
        }
    }
    at
}

/// Prints `pieces` into `out` as far as there is room; the length of the
/// whole text (more than `out.len()` if it did not fit).
pub const fn write(pieces: &[Piece], out: &mut [u8]) -> usize {
    let mut at = 0;
    let mut i = 0;
    while i < pieces.len() {
        at = match pieces[i] {
            Piece::Str(s) => put_str(out, at, s),
            Piece::Num(n) => put_num(out, at, n),
            Piece::Range(lo, hi) => {
                let at = put_num(out, at, lo);
                let at = put_str(out, at, "...");
                put_num(out, at, hi)
            }
            Piece::Offset(n) => {
                let at = put_str(out, at, if n.is_negative() { " - " } else { " + " });
                let n = if n.is_negative() { n.neg() } else { n };
                put_num(out, at, n)
            }
        };
        i += 1;
    }
    at
}

/// The length of the text of `pieces`.
pub const fn len(pieces: &[Piece]) -> usize {
    write(pieces, &mut [])
}

/// The text of `pieces` as an array of its length ([`len`]); fails to
/// compile for another `N`.
pub const fn to_array<const N: usize>(pieces: &[Piece]) -> [u8; N] {
    let mut a = [0u8; N];
    assert!(write(pieces, &mut a) == N, "N is the text's length");
    a
}

/// Whether two `f32` ranges are the same (for the compile-time checks of
/// ranges that share one text).
pub(super) const fn same_f32(a: (f32, f32), b: (f32, f32)) -> bool {
    a.0 == b.0 && a.1 == b.1
}

/// Whether two `u32` ranges are the same.
pub(super) const fn same_u32(a: (u32, u32), b: (u32, u32)) -> bool {
    a.0 == b.0 && a.1 == b.1
}

/// The `&'static str` of a list of [`Piece`]s, built when compiling.
macro_rules! range_text {
    ($($piece:expr),+ $(,)?) => {{
        const PIECES: &[$crate::config::range_text::Piece] = &[$($piece),+];
        const BYTES: [u8; $crate::config::range_text::len(PIECES)] =
            $crate::config::range_text::to_array(PIECES);
        match core::str::from_utf8(&BYTES) {
            Ok(s) => s,
            Err(_) => panic!("range texts are ASCII"),
        }
    }};
}
pub(super) use range_text;

#[cfg(test)]
mod tests {
    use super::*;
    use Piece::{Offset, Str};

    /// Asserts that `pieces` print `expected`.
    fn check(pieces: &[Piece], expected: &str) {
        let n = len(pieces);
        let mut buf = [0u8; 64];
        assert_eq!(write(pieces, &mut buf), n);
        assert_eq!(core::str::from_utf8(&buf[..n]), Ok(expected));
    }

    #[test]
    fn numbers() {
        for (v, s) in [
            (0.0, "0"),
            (-0.0, "0"),
            (5.0, "5"),
            (-90.0, "-90"),
            (0.01, "0.01"),
            (0.1, "0.1"),
            (-0.5, "-0.5"),
            (1_000.0, "1,000"),
            (16_777_216.0, "16,777,216"),
            (1_234.25, "1,234.25"),
            (123_456.78, "123,456.78"),
        ] {
            check(&[Piece::Num(Num::f32(v))], s);
        }
        for (v, s) in [
            (0, "0"),
            (999, "999"),
            (100_000, "100,000"),
            (-1_234, "-1,234"),
        ] {
            check(&[Piece::Num(Num::int(v))], s);
        }
        check(
            &[Piece::Num(Num::int(i64::MIN))],
            "-9,223,372,036,854,775,808",
        );
    }

    #[test]
    fn pieces() {
        check(
            &[
                Str("x"),
                Offset(Num::int(-5)),
                Str(" y"),
                Offset(Num::f32(0.0)),
            ],
            "x - 5 y + 0",
        );
        check(&[u32s((1, 86_400)), Str(" s")], "1...86,400 s");
        check(&[f32s((-0.25, 0.5))], "-0.25...0.5");
        // A buffer too short gets what fits, and the whole length.
        let mut short = [0u8; 3];
        assert_eq!(write(&[u16s((0, 1_440))], &mut short), 9);
        assert_eq!(&short, b"0..");
    }
}
