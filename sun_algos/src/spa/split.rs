//! Time arguments that keep `f32` precise: whole days apart from the day's
//! fraction, and secular angles reduced in exact fixed-point turns.
//!
//! A secular angle `offset + rate · d` (d in days) is evaluated as
//! `offset + frac(rate · n) + rate · f` with `d = n + f`, `n` an integer. The
//! product `rate · n` is formed in 64-bit fixed point (units of 2⁻⁶⁴ turn),
//! where wrapping multiplication *is* the reduction modulo one turn, so no
//! large number ever reaches the float type. This is the split the crate's
//! time type ([`crate::UtcTime`]) is designed for.

use crate::float::Float;
use crate::time::{UtcTime, MS_PER_DAY};

/// 2⁻³²
const TWO_POW_M32: f64 = 1.0 / 4_294_967_296.0;
/// 2⁻⁶⁴
const TWO_POW_M64: f64 = TWO_POW_M32 * TWO_POW_M32;

/// An instant as days from J2000.0 (JD 2 451 545.0, 2000-01-01 12:00):
/// `days + frac_ut` on the UT1 scale and `days + frac_tt` on TT.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SplitDays<T> {
    /// Whole days: 2000-01-01 is 0.
    pub days: i32,
    /// Fraction on UT1, in `[-0.5, 0.5)`.
    pub frac_ut: T,
    /// Fraction on TT: `frac_ut + ΔT / 86 400`.
    pub frac_tt: T,
}

impl<T: Float> SplitDays<T> {
    /// Splits `time`, adding ΔT = TT − UT1 (seconds) for the TT fraction.
    pub fn new(time: &UtcTime, delta_t_s: T) -> Self {
        let frac_ut =
            T::from_u32(time.ms_of_day()) * T::from_f64(1.0 / MS_PER_DAY as f64) - T::from_f64(0.5);
        SplitDays {
            days: time.days_since_2000(),
            frac_ut,
            frac_tt: frac_ut + delta_t_s * T::from_f64(1.0 / 86_400.0),
        }
    }

    /// Time from J2000.0 on TT in units of `period_days` (Julian centuries,
    /// millennia): the whole days and the fraction are scaled apart, so `f32`
    /// rounds only once at the result's own magnitude.
    pub fn tt_in(&self, period_days: f64) -> T {
        let k = T::from_f64(1.0 / period_days);
        T::from_i32(self.days) * k + self.frac_tt * k
    }

    /// The same on UT1.
    pub fn ut_in(&self, period_days: f64) -> T {
        let k = T::from_f64(1.0 / period_days);
        T::from_i32(self.days) * k + self.frac_ut * k
    }
}

/// A secular angle `offset + rate · d`, in turns, d in days.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Secular {
    offset_turns: f64,
    rate_turns_per_day: f64,
    /// The same two rounded to `f32`, so an `f32` build never converts
    /// from `f64` at run time (soft-float on single-precision FPUs).
    offset_turns_f32: f32,
    rate_turns_per_day_f32: f32,
    /// `frac(rate)` in units of 2⁻⁶⁴ turn per day.
    rate_fx: u64,
}

impl Secular {
    /// From an offset and a rate, both in turns (per day).
    pub const fn turns(offset_turns: f64, rate_turns_per_day: f64) -> Self {
        let mut whole = rate_turns_per_day as i64;
        if (whole as f64) > rate_turns_per_day {
            whole -= 1;
        }
        let frac = rate_turns_per_day - whole as f64;
        // frac < 1, so the scaled value fits; `as` saturates at the top.
        let rate_fx = (frac * 18_446_744_073_709_551_616.0) as u64;
        Secular {
            offset_turns,
            rate_turns_per_day,
            offset_turns_f32: offset_turns as f32,
            rate_turns_per_day_f32: rate_turns_per_day as f32,
            rate_fx,
        }
    }

    /// From an offset in degrees and a rate in degrees per day.
    pub const fn degrees(offset_deg: f64, rate_deg_per_day: f64) -> Self {
        Self::turns(offset_deg / 360.0, rate_deg_per_day / 360.0)
    }

    /// The angle in turns at `days + frac` (not reduced: the result lies
    /// within a few turns of `[0, 1)`).
    #[inline]
    pub fn at<T: Float>(&self, days: i32, frac: T) -> T {
        // Two's complement: the wrapping product is `rate · days mod 1 turn`
        // for negative days too.
        let p = self.rate_fx.wrapping_mul(days as i64 as u64);
        let whole_days_turns = T::from_u32((p >> 32) as u32) * T::from_f64(TWO_POW_M32)
            + T::from_u32(p as u32) * T::from_f64(TWO_POW_M64);
        let (offset, rate) = if core::mem::size_of::<T>() == 4 {
            (
                T::from_f64(f64::from(self.offset_turns_f32)),
                T::from_f64(f64::from(self.rate_turns_per_day_f32)),
            )
        } else {
            (
                T::from_f64(self.offset_turns),
                T::from_f64(self.rate_turns_per_day),
            )
        };
        offset + whole_days_turns + rate * frac
    }
}

impl Secular {
    /// The angle in radians at `days + frac`: reduced to `[0, 2π)` for `f32`
    /// (whose precision needs a small argument); left within a few turns
    /// for `f64`, where trigonometry of ≤ 20 rad loses nothing.
    #[inline]
    pub fn rad<T: Float>(&self, days: i32, frac_days: T) -> T {
        let turns = self.at(days, frac_days);
        if core::mem::size_of::<T>() == 4 {
            frac(turns) * T::TAU
        } else {
            turns * T::TAU
        }
    }
}

/// `x` reduced to `[0, 1)`.
#[inline]
pub(crate) fn frac<T: Float>(x: T) -> T {
    let r = x - x.floor();
    if r >= T::ONE {
        T::ZERO
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn secular_matches_exact_rational_arithmetic() {
        // rate 1/7 turn per day: after 7·k + 3 days the angle is 3/7 turn.
        // (The rate itself is the f64 nearest 1/7, off by ~1e-17 turn/day,
        // so ~2e6 days drift by a few 1e-11 turn.)
        let s = Secular::turns(0.25, 1.0 / 7.0);
        for k in [-300_000, -1, 0, 5, 123_456] {
            let v: f64 = frac(s.at(7 * k + 3, 0.0));
            assert!((v - (0.25 + 3.0 / 7.0)).abs() < 1e-10, "{k}: {v}");
            let v32: f32 = frac(s.at(7 * k + 3, 0.5));
            let want = frac(0.25 + 3.0 / 7.0 + 0.5 / 7.0) as f32;
            assert!((v32 - want).abs() < 1e-6, "{k}: {v32}");
        }
    }

    #[test]
    fn negative_rates_wrap_correctly() {
        let s = Secular::degrees(0.0, -90.0); // −¼ turn per day
        let v: f64 = frac(s.at(5, 0.0));
        assert!((v - 0.75).abs() < 1e-12);
        let v: f64 = frac(s.at(-5, 0.0));
        assert!((v - 0.25).abs() < 1e-12);
    }
}
