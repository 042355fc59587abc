//! Continuous-rotation servo (FEETECH FS5106R class, seed *chowdhury-2019*)
//! through `embedded_hal::pwm::SetDutyCycle`, and a closed-loop position
//! controller fed by a quadrature encoder ([`crate::encoder`]).
//!
//! Pulse width: 1.0–2.0 ms in a 20 ms (50 Hz) frame; the neutral (stop) pulse
//! is nominally 1.5 ms and is calibrated per servo ([`ContinuousServo::set_neutral_us`]).
//! Speed −1..+1 maps linearly on each side of neutral:
//! `pulse = neutral + s·(max − neutral)` for s ≥ 0, `neutral + s·(neutral − min)` for s < 0.
//! Duty = `round(pulse · max_duty / period)`, integer arithmetic.

use embedded_hal::pwm::SetDutyCycle;

/// Driver errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ServoConfig {
    /// PWM period, µs (20 000 at 50 Hz). The PWM channel must run at this period.
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
    }
}

/// A continuous-rotation servo on one PWM channel.
#[derive(Debug)]
pub struct ContinuousServo<P> {
    pwm: P,
    config: ServoConfig,
    max_duty: u16,
    pulse_us: u32,
}

impl<P: SetDutyCycle> ContinuousServo<P> {
    /// Reads the channel's max duty once and outputs the neutral pulse (stopped).
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
    pub fn destroy(self) -> P {
        self.pwm
    }

    /// The pulse width now output, µs.
    pub fn pulse_us(&self) -> u32 {
        self.pulse_us
    }

    /// The configuration (with the calibrated neutral).
    pub fn config(&self) -> ServoConfig {
        self.config
    }

    /// Outputs a raw pulse width, µs, within min..=max.
    pub fn set_pulse_us(&mut self, pulse_us: u32) -> Result<(), Error<P::Error>> {
        if pulse_us < self.config.min_pulse_us || pulse_us > self.config.max_pulse_us {
            return Err(Error::PulseOutOfRange);
        }
        let num =
            u64::from(pulse_us) * u64::from(self.max_duty) + u64::from(self.config.period_us / 2);
        let duty = num / u64::from(self.config.period_us.max(1));
        let duty = u16::try_from(duty)
            .unwrap_or(self.max_duty)
            .min(self.max_duty);
        self.pwm.set_duty_cycle(duty).map_err(Error::Comm)?;
        self.pulse_us = pulse_us;
        Ok(())
    }

    /// Speed command −1..+1 (clamped), 0 = neutral.
    pub fn set_speed(&mut self, speed: f32) -> Result<(), Error<P::Error>> {
        if !speed.is_finite() {
            return Err(Error::InvalidSpeed);
        }
        let s = speed.clamp(-1.0, 1.0);
        let c = self.config;
        let span = if s >= 0.0 {
            c.max_pulse_us - c.neutral_us
        } else {
            c.neutral_us - c.min_pulse_us
        };
        let offset = libm::roundf(s * span as f32) as i64;
        let pulse = (i64::from(c.neutral_us) + offset)
            .clamp(i64::from(c.min_pulse_us), i64::from(c.max_pulse_us));
        self.set_pulse_us(u32::try_from(pulse).unwrap_or(c.neutral_us))
    }

    /// Outputs the neutral pulse.
    pub fn stop(&mut self) -> Result<(), Error<P::Error>> {
        self.set_pulse_us(self.config.neutral_us)
    }

    /// Neutral calibration: the pulse at which this servo stands still (found by
    /// trimming until the encoder stops counting). Must lie strictly between
    /// min and max; the servo is stopped at the new neutral.
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
#[derive(Debug, Clone, Copy, PartialEq)]
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
    pub fn update(&self, target_counts: i32, measured_counts: i32) -> f32 {
        if !self.is_valid() {
            return 0.0;
        }
        let e = i64::from(target_counts) - i64::from(measured_counts);
        if e.unsigned_abs() <= u64::from(self.deadband_counts) {
            return 0.0;
        }
        let raw = (self.kp_per_count * e as f32).clamp(-self.max_speed, self.max_speed);
        if raw.abs() < self.min_speed {
            self.min_speed.copysign(raw)
        } else {
            raw
        }
    }
}
