//! Sensor models: the mount's inclinometer and compass with bias and noise
//! (Li et al. 2022: compass accurate to 1–2°, tilt sensor resolving under
//! 1°), an anemometer, and fault injection.

use crate::rng::SplitMix64;
use sun_algos::Float;
use suntracker::attitude::MountAttitude;
use suntracker::ports::{AttitudeReading, AttitudeSensor};

/// Errors of the simulated sensors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SensorError {
    /// The bus returned an error (NACK).
    Bus,
}

/// Accuracy of the attitude sensors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorAccuracy {
    /// Fixed compass bias, degrees.
    pub compass_bias_deg: f64,
    /// Compass noise, one sigma, degrees.
    pub compass_sigma_deg: f64,
    /// Fixed inclinometer biases (x, y), degrees.
    pub tilt_bias_deg: (f64, f64),
    /// Inclinometer noise, one sigma, degrees.
    pub tilt_sigma_deg: f64,
}

impl SensorAccuracy {
    /// Perfect sensors.
    pub fn exact() -> Self {
        SensorAccuracy {
            compass_bias_deg: 0.0,
            compass_sigma_deg: 0.0,
            tilt_bias_deg: (0.0, 0.0),
            tilt_sigma_deg: 0.0,
        }
    }

    /// Li et al.'s (2022) parts: a compass within 1–2° (bias 1.5°, noise 0.5°)
    /// and an inclinometer under 1° (bias up to 0.5°, noise 0.2°); bias signs
    /// drawn from `rng`.
    pub fn li_2022(rng: &mut SplitMix64) -> Self {
        let sign = |r: &mut SplitMix64| if r.next_u64() & 1 == 0 { 1.0 } else { -1.0 };
        SensorAccuracy {
            compass_bias_deg: 1.5 * sign(rng),
            compass_sigma_deg: 0.5,
            tilt_bias_deg: (0.5 * sign(rng), 0.4 * sign(rng)),
            tilt_sigma_deg: 0.2,
        }
    }
}

/// Inclinometer and compass fixed to the mount.
#[derive(Debug, Clone)]
pub struct MountSensors {
    /// The mount's true attitude.
    pub truth: MountAttitude<f64>,
    /// Accuracy.
    pub accuracy: SensorAccuracy,
    rng: SplitMix64,
    /// Injected: every read fails.
    pub failing: bool,
}

impl MountSensors {
    /// Sensors on a mount of attitude `truth`.
    pub fn new(truth: MountAttitude<f64>, accuracy: SensorAccuracy, seed: u64) -> Self {
        MountSensors {
            truth,
            accuracy,
            rng: SplitMix64::new(seed),
            failing: false,
        }
    }
}

impl AttitudeSensor<f64> for MountSensors {
    type Error = SensorError;
    fn read(&mut self) -> Result<AttitudeReading<f64>, SensorError> {
        if self.failing {
            return Err(SensorError::Bus);
        }
        let (tx, ty, h) = self.truth.to_sensors();
        let a = self.accuracy;
        let noise_t = a.tilt_sigma_deg;
        Ok(AttitudeReading {
            theta_x_deg: (tx + a.tilt_bias_deg.0 + self.rng.normal(noise_t)).clamp(0.0, 180.0),
            theta_y_deg: (ty + a.tilt_bias_deg.1 + self.rng.normal(noise_t)).clamp(0.0, 180.0),
            heading_deg: Float::rem_euclid(
                h + a.compass_bias_deg + self.rng.normal(a.compass_sigma_deg),
                360.0,
            ),
        })
    }
}

/// A cup anemometer: pulses per second proportional to wind speed.
#[derive(Debug, Clone, Copy)]
pub struct Anemometer {
    /// Pulses per second per m/s (e.g. 1 Hz = 0.7 m/s → 1.43).
    pub hz_per_m_s: f64,
}

impl Anemometer {
    /// Pulses counted in `interval_s` at `wind_m_s`.
    pub fn pulses(&self, wind_m_s: f64, interval_s: f64) -> u32 {
        let p = libm::round(wind_m_s.max(0.0) * self.hz_per_m_s * interval_s);
        if p.is_finite() && p < f64::from(u32::MAX) {
            p as u32
        } else {
            u32::MAX
        }
    }
}

/// The same readings in `f32` (a controller computing in `f32`, as on a
/// microcontroller).
impl AttitudeSensor<f32> for MountSensors {
    type Error = SensorError;
    fn read(&mut self) -> Result<AttitudeReading<f32>, SensorError> {
        let r: AttitudeReading<f64> = AttitudeSensor::<f64>::read(self)?;
        Ok(AttitudeReading {
            theta_x_deg: r.theta_x_deg as f32,
            theta_y_deg: r.theta_y_deg as f32,
            heading_deg: r.heading_deg as f32,
        })
    }
}
