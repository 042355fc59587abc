//! Fixed-point decimal text of an `f64`: the same bytes as the standard
//! library's `format!("{v:.9}")`, without its generic machinery.
//!
//! `{:.9}` prints the exact binary value rounded to 9 decimals, ties to
//! even (the flt2dec "exact" mode: Grisu with a Dragon4 fallback). For
//! `|v| < 2^53` the same result follows from integer arithmetic: the
//! integer part is exact in a `u64`, and the fraction is `m · 2^-s` with
//! `m < 2^53`, so `m · 10^9` fits a `u128` and the shift by `s` gives the
//! quotient and the exact remainder to round with. Other values (huge,
//! infinite, NaN) go to the standard formatter.

/// 10^9: the scale of 9 decimals.
const SCALE: u64 = 1_000_000_000;

/// Two-digit ASCII pairs "00".."99".
const PAIRS: &[u8; 200] = b"\
0001020304050607080910111213141516171819\
2021222324252627282930313233343536373839\
4041424344454647484950515253545556575859\
6061626364656667686970717273747576777879\
8081828384858687888990919293949596979899";

/// Appends `v` with exactly 9 decimals: byte for byte `format!("{v:.9}")`.
pub fn push_fixed9(out: &mut Vec<u8>, v: f64) {
    // 2^53: below it the integer part of |v| is exact in a u64 and the
    // fraction has at most 52 significant bits.
    const FAST_LIMIT: f64 = 9_007_199_254_740_992.0;
    let a = v.abs();
    if !a.is_finite() || a >= FAST_LIMIT {
        // NaN, infinities and huge values: rare, the standard formatter.
        use std::io::Write;
        // Writing to a Vec cannot fail.
        let _ = write!(out, "{v:.9}");
        return;
    }
    let int = a.trunc();
    // Exact: a and its integer part share the exponent range.
    let frac = a - int;
    let mut int_part = int as u64;
    let mut frac_part = round_fraction_to_nanos(frac);
    if frac_part == SCALE {
        int_part += 1;
        frac_part = 0;
    }
    // The sign of v as `{:.9}` prints it: "-0.000000000" for -0.0 and for
    // negative values that round to zero.
    if v.is_sign_negative() {
        out.push(b'-');
    }
    push_u64(out, int_part);
    out.push(b'.');
    push_nine_digits(out, frac_part);
}

/// `frac · 10^9` (for `0 <= frac < 1`) rounded to the nearest integer,
/// ties to even; `SCALE` when it rounds up to 1.
fn round_fraction_to_nanos(frac: f64) -> u64 {
    if frac == 0.0 {
        return 0;
    }
    let bits = frac.to_bits();
    let biased_exp = ((bits >> 52) & 0x7ff) as u32;
    let fraction_bits = bits & ((1u64 << 52) - 1);
    // frac = mantissa · 2^-shift exactly; shift >= 53 because frac < 1.
    let (mantissa, shift) = if biased_exp == 0 {
        (fraction_bits, 1074u32)
    } else {
        (fraction_bits | (1u64 << 52), 1075 - biased_exp)
    };
    let product = u128::from(mantissa) * u128::from(SCALE);
    // product < 2^83: from shift 84 on it is below half a unit.
    if shift >= 84 {
        return 0;
    }
    let quotient = (product >> shift) as u64;
    let remainder = product & ((1u128 << shift) - 1);
    let half = 1u128 << (shift - 1);
    if remainder > half || (remainder == half && quotient & 1 == 1) {
        quotient + 1
    } else {
        quotient
    }
}

/// Appends `n` in decimal, no padding.
fn push_u64(out: &mut Vec<u8>, mut n: u64) {
    let mut buf = [0u8; 20];
    let mut i = buf.len();
    while n >= 100 {
        let pair = (n % 100) as usize * 2;
        n /= 100;
        i -= 2;
        buf[i..i + 2].copy_from_slice(&PAIRS[pair..pair + 2]);
    }
    if n >= 10 {
        let pair = n as usize * 2;
        i -= 2;
        buf[i..i + 2].copy_from_slice(&PAIRS[pair..pair + 2]);
    } else {
        i -= 1;
        buf[i] = b'0' + n as u8;
    }
    out.extend_from_slice(&buf[i..]);
}

/// Appends `n < 10^9` as exactly nine digits (leading zeros kept).
fn push_nine_digits(out: &mut Vec<u8>, n: u64) {
    let mut buf = [0u8; 9];
    let mut n = n as u32;
    for i in (0..4).rev() {
        let pair = (n % 100) as usize * 2;
        n /= 100;
        buf[1 + 2 * i..3 + 2 * i].copy_from_slice(&PAIRS[pair..pair + 2]);
    }
    buf[0] = b'0' + n as u8;
    out.extend_from_slice(&buf);
}

#[cfg(test)]
mod tests {
    //! The reference is the standard library's own `{:.9}` (core's flt2dec,
    //! an independent implementation: Grisu exact mode with Dragon4).

    use super::push_fixed9;

    fn ours(v: f64) -> String {
        let mut out = Vec::new();
        push_fixed9(&mut out, v);
        String::from_utf8(out).expect("ASCII")
    }

    fn check(v: f64) {
        assert_eq!(ours(v), format!("{v:.9}"), "bits {:#018x}", v.to_bits());
    }

    /// xorshift64*: a fixed pseudo-random sequence.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
    }

    #[test]
    fn special_values_and_limits() {
        for v in [
            0.0,
            -0.0,
            f64::NAN,
            -f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            5e-324,
            -5e-324,
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            1.0,
            -1.0,
            9_007_199_254_740_991.0,
            9_007_199_254_740_992.0,
            -9_007_199_254_740_991.5 + 0.5,
            4_503_599_627_370_495.5,
            1e15 + 0.3,
            123_456_789.0 + 0.987_654_321,
            0.5e-9,
            1.5e-9,
            2.5e-9,
            0.999_999_999_5,
            -0.999_999_999_5,
            0.999_999_999_499_999_9,
            359.999_999_999_9,
            179.999_999_999_5,
            -1e-10,
            -4.9e-10,
            -5.1e-10,
            1e-300,
        ] {
            check(v);
        }
    }

    /// Exact ties at the tenth decimal: every odd multiple of 2^-10 ends in
    /// ...5 there (n · 0.0009765625), in the angle ranges and beyond.
    #[test]
    fn exact_ties_round_to_even() {
        for n in (0..(400 * 1024)).step_by(7) {
            let v = f64::from(n) / 1024.0;
            check(v);
            check(-v);
        }
        // Finer dyadic steps also hit ties after more digits.
        for n in 0..20_000u32 {
            let v = f64::from(n) / 65536.0 + 1000.0;
            check(v);
        }
    }

    /// Every f32 value in a few binades (the `--float f32` outputs are f32
    /// widened to f64): ties occur often there.
    #[test]
    fn widened_f32_values() {
        for start in [1.0f32, 64.0, 128.0, 256.0] {
            let mut x = start;
            for _ in 0..10_000 {
                check(f64::from(x));
                check(-f64::from(x));
                x = f32::from_bits(x.to_bits() + 37);
            }
        }
    }

    #[test]
    fn random_bit_patterns_and_angles() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for _ in 0..30_000 {
            check(f64::from_bits(rng.next()));
            // Uniform angles in -360..360 with full random mantissas.
            let u = (rng.next() >> 11) as f64 / (1u64 << 53) as f64;
            check(720.0 * u - 360.0);
            // Values a few ulps from a 9-decimal rounding boundary.
            let k = (rng.next() % 360_000_000_000) as f64;
            let edge = (k + 0.5) / 1e9;
            let ulps = (rng.next() % 9) as i64 - 4;
            check(f64::from_bits((edge.to_bits() as i64 + ulps) as u64));
        }
    }
}
