//! 64-bit counts (seconds, milliseconds) divided by a 32-bit divisor with
//! 32-bit arithmetic only.
//!
//! On an 8-bit AVR, `u64 / u64` and `i64.div_euclid(…)` call the compiler's
//! 64-bit division routines (`__udivdi3`, `__divdi3` and compiler_builtins'
//! `u64_div_rem`, about 3 KB together), even for a constant divisor. The
//! quotients here are the same, found with one 32-bit division of the upper
//! half and a restoring (shift-and-subtract) division of the lower half,
//! one quotient bit per step (Knuth, *The Art of Computer Programming*
//! vol. 2, §4.3.1): the remainder always stays below the divisor, so it fits
//! 32 bits. A dividend that fits 32 bits takes a single 32-bit division.

/// `(n / d, n % d)`; `None` when `d` is 0.
///
/// ```
/// use suntracker_time::div_rem_u64;
///
/// // 2^40 ms are 12 725 days, 19 h, 53 min, 47.776 s:
/// // 1 099 511 627 776 = 12 725 · 86 400 000 + 71 627 776.
/// assert_eq!(div_rem_u64(1 << 40, 86_400_000), Some((12_725, 71_627_776)));
/// assert_eq!(div_rem_u64(u64::MAX, 1), Some((u64::MAX, 0)));
/// assert_eq!(div_rem_u64(7, 0), None);
/// ```
pub const fn div_rem_u64(n: u64, d: u32) -> Option<(u64, u32)> {
    if d == 0 {
        return None;
    }
    let (hi, lo) = ((n >> 32) as u32, n as u32);
    if hi == 0 {
        return Some(((lo / d) as u64, lo % d));
    }
    let q_hi = hi / d;
    let mut r = hi % d;
    let mut q_lo: u32 = 0;
    let mut rest = lo;
    let mut i = 0;
    while i < 32 {
        // r < d < 2^32: 2r + 1 may need a 33rd bit; when it does, it is
        // at least 2^32 > d, and the wrapped difference is the true one.
        let carry = r >> 31 != 0;
        r = (r << 1) | (rest >> 31);
        rest <<= 1;
        q_lo <<= 1;
        if carry || r >= d {
            r = r.wrapping_sub(d);
            q_lo |= 1;
        }
        i += 1;
    }
    Some((((q_hi as u64) << 32) | q_lo as u64, r))
}

/// `(n / d, n % d)` for a divisor below 2^16; `None` when `d` is 0.
///
/// Short division by 16-bit digits (Knuth, *The Art of Computer
/// Programming* vol. 2, §4.3.1, the single-precision divisor case): the
/// remainder stays below `d < 2^16`, so the remainder and the next digit
/// fit 32 bits, and four 32-bit divisions give the quotient. The shifts
/// are by whole bytes (register moves on an AVR), where [`div_rem_u64`]
/// takes 32 steps of one bit for any 32-bit divisor: this one is a
/// fraction of its code and time.
///
/// ```
/// use suntracker_time::div_rem_u64_u16;
///
/// // 2^40 = 1 099 511 627 776 = 1 099 511 627 · 1 000 + 776.
/// assert_eq!(div_rem_u64_u16(1 << 40, 1_000), Some((1_099_511_627, 776)));
/// assert_eq!(div_rem_u64_u16(u64::MAX, 1), Some((u64::MAX, 0)));
/// assert_eq!(div_rem_u64_u16(7, 0), None);
/// ```
pub const fn div_rem_u64_u16(n: u64, d: u16) -> Option<(u64, u16)> {
    if d == 0 {
        return None;
    }
    let d = d as u32;
    let digits = [
        (n >> 48) as u32 & 0xffff,
        (n >> 32) as u32 & 0xffff,
        (n >> 16) as u32 & 0xffff,
        n as u32 & 0xffff,
    ];
    let mut q: u64 = 0;
    let mut r: u32 = 0;
    let mut i = 0;
    while i < 4 {
        // r < d < 2^16: the value fits 32 bits.
        let cur = (r << 16) | digits[i];
        q = (q << 16) | (cur / d) as u64;
        r = cur % d;
        i += 1;
    }
    // r < d ≤ u16::MAX.
    Some((q, r as u16))
}

/// `(n.div_euclid(d), n.rem_euclid(d))`: the quotient rounded towards
/// −∞ and a remainder in `0..d`; `None` when `d` is 0.
///
/// ```
/// use suntracker_time::div_rem_euclid_i64;
///
/// // One second before 1970-01-01T00:00:00Z is day −1, second 86 399.
/// assert_eq!(div_rem_euclid_i64(-1, 86_400), Some((-1, 86_399)));
/// assert_eq!(div_rem_euclid_i64(1_700_000_000, 86_400), Some((19_675, 80_000)));
/// assert_eq!(div_rem_euclid_i64(i64::MIN, 1), Some((i64::MIN, 0)));
/// assert_eq!(div_rem_euclid_i64(1, 0), None);
/// ```
pub const fn div_rem_euclid_i64(n: i64, d: u32) -> Option<(i64, u32)> {
    let Some((q, r)) = div_rem_u64(n.unsigned_abs(), d) else {
        return None;
    };
    // q ≤ |n| ≤ 2^63. For n ≥ 0, q ≤ 2^63 − 1 fits an i64. For n < 0,
    // −q ≥ −2^63 (wrapping_neg maps 2^63 onto i64::MIN, which is −2^63);
    // with a remainder, d ≥ 2 and q < 2^62, so −q − 1 cannot overflow.
    Some(if n >= 0 {
        (q as i64, r)
    } else if r == 0 {
        ((q as i64).wrapping_neg(), 0)
    } else {
        (-(q as i64) - 1, d - r)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xorshift64 (Marsaglia 2003): test dividends over every magnitude.
    fn xorshift(state: &mut u64) -> u64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        *state
    }

    fn check(n: u64, d: u32) {
        let want = (n / u64::from(d), (n % u64::from(d)) as u32);
        assert_eq!(div_rem_u64(n, d), Some(want), "{n} / {d}");
        let s = n as i64;
        let want = (
            s.div_euclid(i64::from(d)),
            s.rem_euclid(i64::from(d)) as u32,
        );
        assert_eq!(div_rem_euclid_i64(s, d), Some(want), "{s} div_euclid {d}");
        if let Ok(d16) = u16::try_from(d) {
            let want = (n / u64::from(d), (n % u64::from(d)) as u16);
            assert_eq!(div_rem_u64_u16(n, d16), Some(want), "{n} / {d16} (u16)");
        }
    }

    #[test]
    fn zero_divisor_is_none() {
        assert_eq!(div_rem_u64(1, 0), None);
        assert_eq!(div_rem_u64_u16(1, 0), None);
        assert_eq!(div_rem_euclid_i64(-1, 0), None);
    }

    #[test]
    fn agrees_with_native_division() {
        let divisors = [
            1,
            2,
            3,
            7,
            60,
            675,
            1_000,
            28_125,
            u16::MAX as u32 - 1,
            u16::MAX as u32,
            1 << 16,
            86_400,
            86_400_000,
            u32::MAX - 1,
            u32::MAX,
        ];
        let edges = [
            0,
            1,
            u64::from(u32::MAX),
            1 << 32,
            (1 << 32) + 1,
            u64::MAX,
            1 << 63,
        ];
        for &d in &divisors {
            for &n in &edges {
                for n in [n, n.wrapping_sub(1), n.wrapping_add(1), n.wrapping_neg()] {
                    check(n, d);
                }
            }
        }
        let mut state = 0x2545_f491_4f6c_dd1d;
        for _ in 0..200_000 {
            let n = xorshift(&mut state) >> (xorshift(&mut state) % 64);
            let d = (xorshift(&mut state) >> (32 + xorshift(&mut state) % 32)) as u32;
            if d != 0 {
                check(n, d);
                // The 16-bit divisors too, every magnitude of them.
                check(n, d >> 16 | 1);
            }
        }
    }
}
