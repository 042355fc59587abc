//! Continuous-rotation servo (FEETECH FS5106R class, Chowdhury et al. 2019)
//! through `embedded_hal::pwm::SetDutyCycle`, and a closed-loop position
//! controller fed by a quadrature encoder ([`crate::encoder`]).
//!
//! Pulse width: 1.0–2.0 ms in a 20 ms (50 Hz) frame; the neutral (stop) pulse
//! is nominally 1.5 ms and is calibrated per servo ([`ContinuousServo::set_neutral_us`]).
//! Speed −1..+1 maps linearly on each side of neutral:
//! `pulse = neutral + s·(max − neutral)` for s ≥ 0, `neutral + s·(neutral − min)` for s < 0.
//! Duty = `round(pulse · max_duty / period)`, integer arithmetic.
//!
//! The examples run against `embedded-hal-mock`'s PWM channel; the expected
//! duty values are that formula evaluated by hand.

use embedded_hal::pwm::SetDutyCycle;

/// Driver errors.
///
/// ```
/// use drivers::servo::{ContinuousServo, Error, ServoConfig};
/// use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};
///
/// // max duty 20 000 over 20 ms: one count per µs.
/// let mut pwm = Mock::new(&[T::max_duty_cycle(20_000), T::set_duty_cycle(1_500)]);
/// let mut servo = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ)?;
/// assert_eq!(servo.set_speed(f32::NAN), Err(Error::InvalidSpeed));
/// assert_eq!(servo.set_pulse_us(2_500), Err(Error::PulseOutOfRange));
/// assert_eq!(servo.set_neutral_us(2_000), Err(Error::InvalidConfig));
/// pwm.done(); // nothing written after the neutral pulse
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error<E> {
    /// The PWM channel refused the duty cycle.
    Comm(E),
    /// Speed command NaN or infinite.
    InvalidSpeed,
    /// Pulse width outside min..=max of the configuration.
    PulseOutOfRange,
    /// Configuration inconsistent (needs 0 < min < neutral < max ≤ period,
    /// and a PWM channel with a non-zero max duty).
    InvalidConfig,
}

impl<E: core::fmt::Debug> core::fmt::Display for Error<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Comm(e) => write!(f, "servo PWM error: {e:?}"),
            Error::InvalidSpeed => f.write_str("servo speed command NaN or infinite"),
            Error::PulseOutOfRange => f.write_str("servo pulse width outside the configured range"),
            Error::InvalidConfig => f.write_str("inconsistent servo configuration"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for Error<E> {}

/// Pulse timing of a servo.
///
/// ```
/// use drivers::servo::{ContinuousServo, Error, ServoConfig};
/// use embedded_hal_mock::eh1::pwm::Mock;
///
/// // Neutral must lie strictly between min and max: refused before the
/// // channel is asked anything.
/// let bad = ServoConfig { neutral_us: 1_000, ..ServoConfig::STANDARD_50HZ };
/// let mut pwm = Mock::new(&[]);
/// assert!(matches!(ContinuousServo::new(pwm.clone(), bad), Err(Error::InvalidConfig)));
/// // So is a period over MAX_PERIOD_US (65,535 µs).
/// let slow = ServoConfig { period_us: 70_000, ..ServoConfig::STANDARD_50HZ };
/// assert!(matches!(ContinuousServo::new(pwm.clone(), slow), Err(Error::InvalidConfig)));
/// pwm.done();
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ServoConfig {
    /// PWM period, µs (20 000 at 50 Hz), at most [`MAX_PERIOD_US`]. The PWM
    /// channel must run at this period.
    pub period_us: u32,
    /// Pulse for full speed backward, µs.
    pub min_pulse_us: u32,
    /// Pulse for stop, µs (calibrate per servo).
    pub neutral_us: u32,
    /// Pulse for full speed forward, µs.
    pub max_pulse_us: u32,
}

impl ServoConfig {
    /// 50 Hz, 1000 / 1500 / 2000 µs.
    ///
    /// ```
    /// use drivers::servo::ServoConfig;
    ///
    /// let c = ServoConfig::STANDARD_50HZ;
    /// assert_eq!((c.period_us, c.min_pulse_us, c.neutral_us, c.max_pulse_us), (20_000, 1_000, 1_500, 2_000));
    /// ```
    pub const STANDARD_50HZ: Self = Self {
        period_us: 20_000,
        min_pulse_us: 1_000,
        neutral_us: 1_500,
        max_pulse_us: 2_000,
    };

    fn is_valid(&self) -> bool {
        0 < self.min_pulse_us
            && self.min_pulse_us < self.neutral_us
            && self.neutral_us < self.max_pulse_us
            && self.max_pulse_us <= self.period_us
            && self.period_us <= MAX_PERIOD_US
    }
}

/// `x` limited to `lo..=hi` (`lo ≤ hi`, `x` finite) by two comparisons:
/// `f32::clamp` asserts its bounds (a panic path), and it, `max` and `min`
/// call NaN-aware library routines on a part without an FPU (280 B on an
/// AVR).
#[allow(clippy::manual_clamp)]
fn limit(x: f32, lo: f32, hi: f32) -> f32 {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}

/// `x` to the nearest integer, halves away from zero (as `roundf`, for the
/// |x| ≤ 65,535 of a pulse offset), without libm's `roundf` (about 1,000
/// cycles a call on an AVR).
fn round_half_away(x: f32) -> i32 {
    if x >= 0.0 {
        (x + 0.5) as i32
    } else {
        (x - 0.5) as i32
    }
}

/// Longest PWM period accepted, µs (65.5 ms; hobby servos take 20 ms
/// frames). It keeps the pulse-to-duty arithmetic in 32 bits: pulse ≤
/// period ≤ 65,535 and duty ≤ 65,535 give a product under 2³², and an
/// 8-bit MCU needs no 64-bit division routine for it.
pub const MAX_PERIOD_US: u32 = u16::MAX as u32;

/// A continuous-rotation servo on one PWM channel.
///
/// ```
/// use drivers::servo::{ContinuousServo, ServoConfig};
/// use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};
///
/// // A 12-bit channel (max duty 4095) at 50 Hz: duty = round(pulse · 4095 /
/// // 20 000): 1500 µs → 307.125 → 307, 1750 µs → 358.3 → 358.
/// let mut pwm = Mock::new(&[T::max_duty_cycle(4_095), T::set_duty_cycle(307), T::set_duty_cycle(358)]);
/// let mut servo = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ)?;
/// servo.set_speed(0.5)?; // half speed forward: 1500 + 0.5 · 500 µs
/// assert_eq!(servo.pulse_us(), 1_750);
/// servo.destroy();
/// pwm.done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct ContinuousServo<P> {
    pwm: P,
    config: ServoConfig,
    max_duty: u16,
    pulse_us: u32,
}

impl<P: SetDutyCycle> ContinuousServo<P> {
    /// Reads the channel's max duty once and outputs the neutral pulse (stopped).
    ///
    /// ```
    /// use drivers::servo::{ContinuousServo, ServoConfig};
    /// use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};
    ///
    /// // A 16-bit channel: 1500 µs · 65 535 / 20 000 = 4915.1 → 4915.
    /// let mut pwm = Mock::new(&[T::max_duty_cycle(65_535), T::set_duty_cycle(4_915)]);
    /// let servo = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ)?;
    /// assert_eq!(servo.pulse_us(), 1_500);
    /// pwm.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn new(pwm: P, config: ServoConfig) -> Result<Self, Error<P::Error>> {
        if !config.is_valid() {
            return Err(Error::InvalidConfig);
        }
        let max_duty = pwm.max_duty_cycle();
        if max_duty == 0 {
            return Err(Error::InvalidConfig);
        }
        let mut s = Self {
            pwm,
            config,
            max_duty,
            pulse_us: config.neutral_us,
        };
        s.set_pulse_us(config.neutral_us)?;
        Ok(s)
    }

    /// Gives the PWM channel back.
    ///
    /// ```
    /// use drivers::servo::{ContinuousServo, ServoConfig};
    /// use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};
    ///
    /// let pwm = Mock::new(&[T::max_duty_cycle(20_000), T::set_duty_cycle(1_500)]);
    /// let servo = ContinuousServo::new(pwm, ServoConfig::STANDARD_50HZ)?;
    /// let mut pwm = servo.destroy();
    /// pwm.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn destroy(self) -> P {
        self.pwm
    }

    /// The pulse width now output, µs.
    ///
    /// ```
    /// use drivers::servo::{ContinuousServo, ServoConfig};
    /// use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};
    ///
    /// let mut pwm = Mock::new(&[T::max_duty_cycle(20_000), T::set_duty_cycle(1_500), T::set_duty_cycle(1_000)]);
    /// let mut servo = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ)?;
    /// servo.set_speed(-1.0)?;
    /// assert_eq!(servo.pulse_us(), 1_000);
    /// pwm.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn pulse_us(&self) -> u32 {
        self.pulse_us
    }

    /// The configuration (with the calibrated neutral).
    ///
    /// ```
    /// use drivers::servo::{ContinuousServo, ServoConfig};
    /// use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};
    ///
    /// let mut pwm = Mock::new(&[T::max_duty_cycle(20_000), T::set_duty_cycle(1_500), T::set_duty_cycle(1_520)]);
    /// let mut servo = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ)?;
    /// servo.set_neutral_us(1_520)?;
    /// assert_eq!(servo.config().neutral_us, 1_520);
    /// pwm.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn config(&self) -> ServoConfig {
        self.config
    }

    /// Outputs a raw pulse width, µs, within min..=max.
    ///
    /// ```
    /// use drivers::servo::{ContinuousServo, Error, ServoConfig};
    /// use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};
    ///
    /// // max duty 1000 over 20 ms: 1234 µs → 61.7 → 62.
    /// let mut pwm = Mock::new(&[T::max_duty_cycle(1_000), T::set_duty_cycle(75), T::set_duty_cycle(62)]);
    /// let mut servo = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ)?;
    /// servo.set_pulse_us(1_234)?;
    /// assert_eq!(servo.set_pulse_us(999), Err(Error::PulseOutOfRange));
    /// pwm.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn set_pulse_us(&mut self, pulse_us: u32) -> Result<(), Error<P::Error>> {
        if pulse_us < self.config.min_pulse_us || pulse_us > self.config.max_pulse_us {
            return Err(Error::PulseOutOfRange);
        }
        // pulse ≤ period ≤ MAX_PERIOD_US (checked by `new`) and max duty ≤
        // 65,535: the sum stays under 2³² (see MAX_PERIOD_US).
        let num = pulse_us
            .saturating_mul(u32::from(self.max_duty))
            .saturating_add(self.config.period_us / 2);
        let duty = num / self.config.period_us.max(1);
        let duty = u16::try_from(duty)
            .unwrap_or(self.max_duty)
            .min(self.max_duty);
        self.pwm.set_duty_cycle(duty).map_err(Error::Comm)?;
        self.pulse_us = pulse_us;
        Ok(())
    }

    /// Speed command −1..+1 (clamped), 0 = neutral.
    ///
    /// ```
    /// use drivers::servo::{ContinuousServo, ServoConfig};
    /// use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};
    ///
    /// // One count per µs; +1 → 2000 µs, −0.25 → 1375 µs, +3 clamps to 2000 µs.
    /// let mut pwm = Mock::new(&[
    ///     T::max_duty_cycle(20_000),
    ///     T::set_duty_cycle(1_500),
    ///     T::set_duty_cycle(2_000),
    ///     T::set_duty_cycle(1_375),
    ///     T::set_duty_cycle(2_000),
    /// ]);
    /// let mut servo = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ)?;
    /// for speed in [1.0, -0.25, 3.0] {
    ///     servo.set_speed(speed)?;
    /// }
    /// pwm.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn set_speed(&mut self, speed: f32) -> Result<(), Error<P::Error>> {
        if !speed.is_finite() {
            return Err(Error::InvalidSpeed);
        }
        let s = limit(speed, -1.0, 1.0);
        let c = self.config;
        // min < neutral < max ≤ period ≤ MAX_PERIOD_US (checked by `new`):
        // spans and pulses fit an i32.
        let span = if s >= 0.0 {
            c.max_pulse_us.saturating_sub(c.neutral_us)
        } else {
            c.neutral_us.saturating_sub(c.min_pulse_us)
        };
        let offset = round_half_away(s * span as f32);
        let neutral = i32::try_from(c.neutral_us).unwrap_or(i32::MAX);
        let pulse = u32::try_from(neutral.saturating_add(offset)).unwrap_or(c.neutral_us);
        self.set_pulse_us(pulse.max(c.min_pulse_us).min(c.max_pulse_us))
    }

    /// Outputs the neutral pulse.
    ///
    /// ```
    /// use drivers::servo::{ContinuousServo, ServoConfig};
    /// use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};
    ///
    /// let mut pwm = Mock::new(&[
    ///     T::max_duty_cycle(20_000),
    ///     T::set_duty_cycle(1_500),
    ///     T::set_duty_cycle(2_000),
    ///     T::set_duty_cycle(1_500),
    /// ]);
    /// let mut servo = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ)?;
    /// servo.set_speed(1.0)?;
    /// servo.stop()?;
    /// assert_eq!(servo.pulse_us(), 1_500);
    /// pwm.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn stop(&mut self) -> Result<(), Error<P::Error>> {
        self.set_pulse_us(self.config.neutral_us)
    }

    /// Neutral calibration: the pulse at which this servo stands still (found by
    /// trimming until the encoder stops counting). Must lie strictly between
    /// min and max; the servo is stopped at the new neutral.
    ///
    /// ```
    /// use drivers::servo::{ContinuousServo, ServoConfig};
    /// use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};
    ///
    /// // After trimming the neutral to 1520 µs, +1 still maps to 2000 µs and
    /// // −1 to 1000 µs, −0.5 to 1520 − 0.5 · 520 = 1260 µs.
    /// let mut pwm = Mock::new(&[
    ///     T::max_duty_cycle(20_000),
    ///     T::set_duty_cycle(1_500),
    ///     T::set_duty_cycle(1_520),
    ///     T::set_duty_cycle(1_260),
    /// ]);
    /// let mut servo = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ)?;
    /// servo.set_neutral_us(1_520)?;
    /// servo.set_speed(-0.5)?;
    /// pwm.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn set_neutral_us(&mut self, neutral_us: u32) -> Result<(), Error<P::Error>> {
        let mut c = self.config;
        c.neutral_us = neutral_us;
        if !c.is_valid() {
            return Err(Error::InvalidConfig);
        }
        self.config = c;
        self.stop()
    }
}

/// Proportional position controller with deadband and speed limit.
///
/// `speed = clamp(kp · e, ±max_speed)` with `e = target − measured` in encoder
/// counts; `0` when `|e| ≤ deadband`; commands smaller than `min_speed` are raised
/// to it so the servo's own neutral deadband cannot stall the approach.
///
/// ```
/// use drivers::servo::PositionController;
///
/// let ctl = PositionController { kp_per_count: 0.01, deadband_counts: 2, max_speed: 0.8, min_speed: 0.1 };
/// assert_eq!(ctl.update(1_000, 900), 0.8); // 0.01 · 100 = 1, limited to 0.8
/// assert_eq!(ctl.update(1_000, 1_050), -0.5);
/// assert_eq!(ctl.update(1_000, 995), 0.1); // 0.05 raised to the minimum
/// assert_eq!(ctl.update(1_000, 998), 0.0); // within the deadband
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PositionController {
    /// Speed per count of error.
    pub kp_per_count: f32,
    /// Error (counts) treated as on target.
    pub deadband_counts: u32,
    /// Largest speed command, 0..=1.
    pub max_speed: f32,
    /// Smallest non-zero speed command, 0..=max_speed.
    pub min_speed: f32,
}

impl PositionController {
    /// True when the gains are finite and 0 ≤ min_speed ≤ max_speed ≤ 1, kp > 0.
    ///
    /// ```
    /// use drivers::servo::PositionController;
    ///
    /// let ctl = PositionController { kp_per_count: 0.01, deadband_counts: 2, max_speed: 0.8, min_speed: 0.1 };
    /// assert!(ctl.is_valid());
    /// assert!(!PositionController { max_speed: 1.5, ..ctl }.is_valid());
    /// assert!(!PositionController { kp_per_count: f32::NAN, ..ctl }.is_valid());
    /// assert!(!PositionController { min_speed: 0.9, ..ctl }.is_valid());
    /// ```
    pub fn is_valid(&self) -> bool {
        self.kp_per_count.is_finite()
            && self.kp_per_count > 0.0
            && self.max_speed.is_finite()
            && self.min_speed.is_finite()
            && 0.0 <= self.min_speed
            && self.min_speed <= self.max_speed
            && self.max_speed <= 1.0
    }

    /// Speed command for the servo; 0 when on target or when the gains are invalid.
    ///
    /// ```
    /// use drivers::servo::PositionController;
    ///
    /// let ctl = PositionController { kp_per_count: 0.002, deadband_counts: 1, max_speed: 1.0, min_speed: 0.05 };
    /// assert_eq!(ctl.update(0, -250), 0.5); // 0.002 · 250
    /// assert_eq!(ctl.update(i32::MAX, i32::MIN), 1.0); // no overflow
    /// let invalid = PositionController { kp_per_count: -1.0, ..ctl };
    /// assert_eq!(invalid.update(0, -250), 0.0);
    /// ```
    pub fn update(&self, target_counts: i32, measured_counts: i32) -> f32 {
        if !self.is_valid() {
            return 0.0;
        }
        // Saturating: an error beyond the i32 range commands full speed all
        // the same.
        let e = target_counts.saturating_sub(measured_counts);
        if e.unsigned_abs() <= self.deadband_counts {
            return 0.0;
        }
        // Valid gains: max_speed ≥ 0.
        let raw = limit(
            self.kp_per_count * e as f32,
            -self.max_speed,
            self.max_speed,
        );
        if raw.abs() < self.min_speed {
            self.min_speed.copysign(raw)
        } else {
            raw
        }
    }
}
