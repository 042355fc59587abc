//! Trapezoidal speed profile with the step interval computed per step.
//!
//! Constant acceleration `a` (steps/s²) from a start speed `v₀` gives, after `k`
//! steps, `v_k² = v₀² + 2·a·k` (uniform acceleration, `v² = v₀² + 2as`). The
//! interval before the next step is `1e6 / v` µs, with `v` capped at `v_max`.
//! Deceleration is the mirror image counted from the end: for a move of `N`
//! steps, the interval after step `i` (1-based) uses level `k = min(i, N − i)`,
//! so the profile accelerates, cruises and decelerates symmetrically (a triangle
//! when `N` is too short to reach `v_max`). Integer arithmetic only (an integer
//! square root), so it costs the same on an 8-bit AVR as on a Cortex-M.
//!
//! The expected values in the examples are the formula above evaluated
//! independently (Python, `math.isqrt`).

use suntracker_time::div_rem_u64;

/// Why a ramp configuration was refused.
///
/// ```
/// use drivers::stepper::ramp::{Ramp, RampError};
///
/// let zero = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 0 };
/// assert_eq!(zero.validate(), Err(RampError::Zero));
/// assert_eq!(RampError::Zero.to_string(), "a speed or the acceleration is zero");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RampError {
    /// A speed or the acceleration is zero.
    Zero,
    /// Start speed above maximum speed.
    StartAboveMax,
    /// Maximum speed above 65 535 steps/s (interval below 16 µs): faster
    /// than a loop that polls the driver can step, and v² would exceed 32 bits.
    TooFast,
    /// The step pulse (high + low) does not fit in the shortest interval.
    PulseTooLong,
}

impl core::fmt::Display for RampError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RampError::Zero => f.write_str("a speed or the acceleration is zero"),
            RampError::StartAboveMax => f.write_str("start speed above maximum speed"),
            RampError::TooFast => f.write_str("maximum speed above 65 535 steps/s"),
            RampError::PulseTooLong => {
                f.write_str("step pulse does not fit in the shortest step interval")
            }
        }
    }
}

impl core::error::Error for RampError {}

/// The highest maximum speed [`Ramp::validate`] accepts, steps/s: its
/// square is the largest that fits in 32 bits.
pub const MAX_SPEED_SPS: u32 = 65_535;

/// Speed profile parameters.
///
/// ```
/// use drivers::stepper::ramp::Ramp;
///
/// // 100 steps/s at the ends, 1000 steps/s cruise, 10 000 steps/s².
/// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
/// // v_k = √(100² + 2·10 000·k): 100, 173, 223, … steps/s; cruise after 50 steps.
/// let intervals: Vec<u32> = (0..3).map(|k| ramp.interval_us(k)).collect();
/// assert_eq!(intervals, [10_000, 5_780, 4_484]);
/// assert_eq!(ramp.cruise_level(), 50);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ramp {
    /// Speed of the first and last step, steps/s (within the motor's pull-in rate).
    pub start_speed_sps: u32,
    /// Cruise speed, steps/s.
    pub max_speed_sps: u32,
    /// Acceleration and deceleration, steps/s².
    pub accel_sps2: u32,
}

impl Ramp {
    /// Checks the parameters.
    ///
    /// ```
    /// use drivers::stepper::ramp::{Ramp, RampError};
    ///
    /// // 100 steps/s at the ends, 1000 steps/s cruise, 10 000 steps/s².
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// assert_eq!(ramp.validate(), Ok(()));
    /// let slow_max = Ramp { max_speed_sps: 50, ..ramp };
    /// assert_eq!(slow_max.validate(), Err(RampError::StartAboveMax));
    /// let too_fast = Ramp { max_speed_sps: 65_536, ..ramp };
    /// assert_eq!(too_fast.validate(), Err(RampError::TooFast));
    /// ```
    pub fn validate(&self) -> Result<(), RampError> {
        if self.start_speed_sps == 0 || self.max_speed_sps == 0 || self.accel_sps2 == 0 {
            return Err(RampError::Zero);
        }
        if self.start_speed_sps > self.max_speed_sps {
            return Err(RampError::StartAboveMax);
        }
        if self.max_speed_sps > MAX_SPEED_SPS {
            return Err(RampError::TooFast);
        }
        Ok(())
    }

    /// Speed at ramp level `k` (steps from the nearer end of the move),
    /// steps/s, for a ramp [`validate`](Self::validate) accepts (one above
    /// 65,535 steps/s reads `max_speed_sps` wherever v² exceeds 32 bits).
    ///
    /// ```
    /// use drivers::stepper::ramp::Ramp;
    ///
    /// // 100 steps/s at the ends, 1000 steps/s cruise, 10 000 steps/s².
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// // ⌊√(100² + 2·10 000·k)⌋, capped at 1000.
    /// assert_eq!(ramp.speed_sps(0), 100);
    /// assert_eq!(ramp.speed_sps(10), 458);
    /// assert_eq!(ramp.speed_sps(49), 994);
    /// assert_eq!(ramp.speed_sps(50), 1_000);
    /// assert_eq!(ramp.speed_sps(u32::MAX), 1_000);
    /// ```
    pub fn speed_sps(&self, level: u32) -> u32 {
        // v² = v0² + 2·a·k in 32 bits: a v² that does not fit is above
        // 65,535², so above every maximum `validate` accepts. (On an 8-bit
        // CPU the 64-bit products and root cost several times more, once
        // per step.)
        let v0 = self.start_speed_sps;
        let max = self.max_speed_sps;
        let v2 = square_u32(v0).and_then(|sq| {
            self.accel_sps2
                .checked_mul(2)?
                .checked_mul(level)?
                .checked_add(sq)
        });
        match v2 {
            Some(v2) if square_u32(max).is_none_or(|m2| v2 < m2) => isqrt32(v2).min(max).max(1),
            _ => max.max(1),
        }
    }

    /// Interval in whole µs (rounded to nearest) at ramp level `k`.
    ///
    /// ```
    /// use drivers::stepper::ramp::Ramp;
    ///
    /// // 100 steps/s at the ends, 1000 steps/s cruise, 10 000 steps/s².
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// // 10⁶ / v rounded: 10⁶ / 458 = 2183.4, 10⁶ / 994 = 1006.04.
    /// assert_eq!(ramp.interval_us(10), 2_183);
    /// assert_eq!(ramp.interval_us(49), 1_006);
    /// assert_eq!(ramp.interval_us(50), 1_000);
    /// ```
    pub fn interval_us(&self, level: u32) -> u32 {
        let v = self.speed_sps(level).max(1);
        (1_000_000 + v / 2) / v
    }

    /// Level at which the cruise speed is reached (`v_k ≥ v_max`): also the
    /// number of steps needed to stop from cruise.
    ///
    /// ```
    /// use drivers::stepper::ramp::Ramp;
    ///
    /// // 100 steps/s at the ends, 1000 steps/s cruise, 10 000 steps/s².
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// // ⌈(1000² − 100²) / (2·10 000)⌉ = ⌈49.5⌉.
    /// assert_eq!(ramp.cruise_level(), 50);
    /// assert!(ramp.speed_sps(ramp.cruise_level()) >= ramp.max_speed_sps);
    /// ```
    pub fn cruise_level(&self) -> u32 {
        if self.validate().is_ok() {
            return self.cruise_level_valid();
        }
        let vmax = u64::from(self.max_speed_sps);
        let v0 = u64::from(self.start_speed_sps);
        // ⌈n / 2a⌉ = ⌈⌈n / 2⌉ / a⌉, the division by a 32-bit a in 32-bit
        // steps (no 64-bit division routine on an 8-bit board).
        let half = (vmax * vmax).saturating_sub(v0 * v0).div_ceil(2);
        let (q, r) = div_rem_u64(half, self.accel_sps2.max(1)).unwrap_or((u64::MAX, 0));
        let k = q.saturating_add(u64::from(r != 0));
        u32::try_from(k).unwrap_or(u32::MAX)
    }
}

impl Ramp {
    /// [`Ramp::cruise_level`] of a ramp [`Ramp::validate`] accepts: both
    /// speeds within 16 bits, so their squares fit 32 bits and so does the
    /// rest (⌈⌈n / 2⌉ / a⌉ = ⌈n / 2a⌉), without the 64-bit products and
    /// long division an 8-bit board would link for the general case.
    pub(crate) fn cruise_level_valid(&self) -> u32 {
        // Beyond 16 bits (not a valid ramp) the square saturates.
        let square = |v: u32| square_u32(v).unwrap_or(u32::MAX);
        let half = square(self.max_speed_sps)
            .saturating_sub(square(self.start_speed_sps))
            .div_ceil(2);
        // ⌈h / a⌉ = ⌊(h − 1) / a⌋ + 1 for h ≥ 1: one division, where
        // `div_ceil` also multiplies back for the remainder on the AVR.
        match half.checked_sub(1) {
            Some(h) => h / self.accel_sps2.max(1) + 1,
            None => 0,
        }
    }
}

/// The bit-by-bit integer square root ⌊√n⌋ for one unsigned width.
/// `v²` when it fits in 32 bits (`v.checked_mul(v)`): exactly when `v`
/// fits in 16 (65,535² < 2³² ≤ 65,536²). A compare and a 16 × 16-bit
/// product rather than a 32 × 32-bit one with its high half checked (two
/// multiplication calls more per step on an 8-bit CPU).
fn square_u32(v: u32) -> Option<u32> {
    u16::try_from(v).ok().map(|v| u32::from(v) * u32::from(v))
}

macro_rules! bitwise_isqrt {
    ($(#[$doc:meta])* $name:ident, $t:ty) => {
        $(#[$doc])*
        pub fn $name(n: $t) -> $t {
            let mut rem = n;
            let mut root: $t = 0;
            // The highest power of four the type holds.
            let mut bit: $t = 1 << (<$t>::BITS - 2);
            while bit > n {
                bit >>= 2;
            }
            while bit != 0 {
                if rem >= root + bit {
                    rem -= root + bit;
                    root = (root >> 1) + bit;
                } else {
                    root >>= 1;
                }
                bit >>= 2;
            }
            root
        }
    };
}

bitwise_isqrt!(
    /// [`isqrt`] of a 32-bit value (the same method, half the iterations,
    /// 32-bit arithmetic).
    ///
    /// ```
    /// use drivers::stepper::ramp::isqrt32;
    ///
    /// assert_eq!(isqrt32(0), 0);
    /// assert_eq!(isqrt32(99), 9);
    /// assert_eq!(isqrt32(u32::MAX), 65_535);
    /// ```
    isqrt32,
    u32
);
bitwise_isqrt!(
    /// Integer square root, ⌊√n⌋ (bit-by-bit method).
    ///
    /// ```
    /// use drivers::stepper::ramp::isqrt;
    ///
    /// assert_eq!(isqrt(1_000_000_000_000), 1_000_000);
    /// assert_eq!(isqrt(1_000_000_000_000 - 1), 999_999);
    /// assert_eq!(isqrt(u64::MAX), 4_294_967_295);
    /// ```
    isqrt,
    u64
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_u32_is_the_square_when_it_fits_in_32_bits() {
        // 65,535² = 4,294,836,225 < 2³² = 4,294,967,296 = 65,536².
        assert_eq!(square_u32(0), Some(0));
        assert_eq!(square_u32(3), Some(9));
        assert_eq!(square_u32(65_535), Some(4_294_836_225));
        assert_eq!(square_u32(65_536), None);
        assert_eq!(square_u32(u32::MAX), None);
    }

    #[test]
    fn speed_is_the_capped_root_of_the_exact_square() {
        // ⌊√(v₀² + 2·a·k)⌋ capped at v_max (and at least 1) in 128-bit
        // arithmetic; where v², or a term of it (v₀², 2·a, 2·a·k), leaves
        // 32 bits the driver reads v_max, and so where v_max² does not fit
        // the root is not capped by the compare but by v_max itself.
        let speeds = [1, 2, 99, 100, 1_000, 65_535, 65_536, 999_999];
        let accels = [1, 3, 10_000, u32::MAX / 2, u32::MAX / 2 + 1, u32::MAX];
        let levels = [0, 1, 2, 49, 50, 65_536, u32::MAX];
        for ramp in ramps(&speeds, &accels) {
            let (v0, vmax) = (
                u128::from(ramp.start_speed_sps),
                u128::from(ramp.max_speed_sps),
            );
            for &level in &levels {
                let a2 = 2 * u128::from(ramp.accel_sps2);
                let v2 = v0.pow(2) + a2 * u128::from(level);
                let fits = |x: u128| x <= u128::from(u32::MAX);
                let terms_fit = fits(v0.pow(2)) && fits(a2) && fits(a2 * u128::from(level));
                let want = if terms_fit && fits(v2) && (!fits(vmax.pow(2)) || v2 < vmax.pow(2)) {
                    let root = (v2 as f64).sqrt() as u128;
                    // The float root corrected to the integer one.
                    let root = (root.saturating_sub(2)..=root + 2)
                        .filter(|r| r * r <= v2)
                        .max()
                        .unwrap();
                    root.min(vmax).max(1)
                } else {
                    vmax.max(1)
                };
                assert_eq!(
                    u128::from(ramp.speed_sps(level)),
                    want,
                    "{ramp:?} k={level}"
                );
            }
        }
    }

    /// Every ramp of these speeds (the start at most the maximum) and
    /// accelerations.
    fn ramps<'a>(speeds: &'a [u32], accels: &'a [u32]) -> impl Iterator<Item = Ramp> + 'a {
        speeds.iter().flat_map(move |&max_speed_sps| {
            speeds
                .iter()
                .filter(move |&&v| v <= max_speed_sps)
                .flat_map(move |&start_speed_sps| {
                    accels.iter().map(move |&accel_sps2| Ramp {
                        start_speed_sps,
                        max_speed_sps,
                        accel_sps2,
                    })
                })
        })
    }

    #[test]
    fn cruise_level_is_the_ceiling_of_the_exact_quotient() {
        // ⌈(v_max² − v₀²) / 2a⌉ in 128-bit arithmetic, over the extremes
        // of every field (v_max beyond the 65,535 steps/s `validate` allows).
        let speeds = [1, 2, 99, 100, 1_000, 65_535, 65_536, 999_999, 1_000_000];
        let accels = [
            1,
            2,
            3,
            7,
            10_000,
            65_537,
            u32::MAX / 3,
            u32::MAX - 1,
            u32::MAX,
        ];
        for ramp in ramps(&speeds, &accels) {
            let n = u128::from(ramp.max_speed_sps).pow(2) - u128::from(ramp.start_speed_sps).pow(2);
            // Saturated to a u32.
            let want = n
                .div_ceil(2 * u128::from(ramp.accel_sps2))
                .min(u32::MAX.into());
            assert_eq!(u128::from(ramp.cruise_level()), want, "{ramp:?}");
        }
    }
}
