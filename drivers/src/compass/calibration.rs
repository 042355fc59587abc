//! Hard- and soft-iron calibration from a rotation sweep.
//!
//! Method: per-axis min/max. While the tracker turns through a sweep, the
//! extremes of each axis are kept. Then, per axis i,
//! `offset_i = (max_i + min_i) / 2` (hard iron: a constant field added by magnetised
//! parts), `radius_i = (max_i − min_i) / 2` and `scale_i = mean(radius) / radius_i`
//! (soft iron, axis-aligned part: makes the distorted ellipsoid a sphere again).
//! A corrected sample is `(raw − offset) · scale`.
//!
//! Chosen over an ellipsoid fit because it needs six floats of state, no matrix
//! algebra and works sample by sample on an 8-bit MCU; it does not remove
//! cross-axis (rotated-ellipsoid) soft iron. A tracker that can only turn in
//! azimuth sees little z range: use [`CalibrationSweep::finish_xy`] there.

use super::Vector3;

/// Why a sweep did not give a calibration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CalibrationError {
    /// A sample was NaN or infinite (it was not used).
    NonFinite,
    /// Fewer samples than asked for.
    TooFewSamples,
    /// An axis span is below the minimum: the sweep did not turn far enough.
    SpanTooSmall,
}

impl core::fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CalibrationError::NonFinite => f.write_str("calibration sample NaN or infinite"),
            CalibrationError::TooFewSamples => {
                f.write_str("fewer calibration samples than asked for")
            }
            CalibrationError::SpanTooSmall => {
                f.write_str("axis span below the minimum: the sweep did not turn far enough")
            }
        }
    }
}

impl core::error::Error for CalibrationError {}

/// Hard-iron offsets and soft-iron scale factors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibration {
    /// Hard-iron offset, subtracted first (same unit as the samples).
    pub offset: Vector3,
    /// Soft-iron scale per axis, multiplied after the offset.
    pub scale: Vector3,
}

impl Calibration {
    /// No correction.
    pub const IDENTITY: Self = Self {
        offset: Vector3::new(0.0, 0.0, 0.0),
        scale: Vector3::new(1.0, 1.0, 1.0),
    };

    /// Applies the correction to one raw sample.
    pub fn apply(&self, raw: Vector3) -> Vector3 {
        Vector3 {
            x: (raw.x - self.offset.x) * self.scale.x,
            y: (raw.y - self.offset.y) * self.scale.y,
            z: (raw.z - self.offset.z) * self.scale.z,
        }
    }
}

/// Running min/max of a rotation sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrationSweep {
    min: Vector3,
    max: Vector3,
    samples: u32,
}

impl Default for CalibrationSweep {
    fn default() -> Self {
        Self::new()
    }
}

impl CalibrationSweep {
    /// An empty sweep.
    pub const fn new() -> Self {
        Self {
            min: Vector3::new(f32::INFINITY, f32::INFINITY, f32::INFINITY),
            max: Vector3::new(f32::NEG_INFINITY, f32::NEG_INFINITY, f32::NEG_INFINITY),
            samples: 0,
        }
    }

    /// Number of samples taken so far.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Adds one raw sample; non-finite samples are refused.
    pub fn add(&mut self, raw: Vector3) -> Result<(), CalibrationError> {
        if !raw.is_finite() {
            return Err(CalibrationError::NonFinite);
        }
        self.min.x = self.min.x.min(raw.x);
        self.min.y = self.min.y.min(raw.y);
        self.min.z = self.min.z.min(raw.z);
        self.max.x = self.max.x.max(raw.x);
        self.max.y = self.max.y.max(raw.y);
        self.max.z = self.max.z.max(raw.z);
        self.samples = self.samples.saturating_add(1);
        Ok(())
    }

    fn check(&self, min_samples: u32) -> Result<(), CalibrationError> {
        if self.samples < min_samples.max(2) {
            Err(CalibrationError::TooFewSamples)
        } else {
            Ok(())
        }
    }

    /// Three-axis calibration; every axis span must be at least `min_span`.
    pub fn finish(&self, min_samples: u32, min_span: f32) -> Result<Calibration, CalibrationError> {
        self.check(min_samples)?;
        let (ox, rx) = centre_radius(self.min.x, self.max.x, min_span)?;
        let (oy, ry) = centre_radius(self.min.y, self.max.y, min_span)?;
        let (oz, rz) = centre_radius(self.min.z, self.max.z, min_span)?;
        let mean = (rx + ry + rz) / 3.0;
        Ok(Calibration {
            offset: Vector3::new(ox, oy, oz),
            scale: Vector3::new(mean / rx, mean / ry, mean / rz),
        })
    }

    /// Calibration of x and y only (z left as measured): for a sweep in azimuth
    /// with the sensor roughly level.
    pub fn finish_xy(
        &self,
        min_samples: u32,
        min_span: f32,
    ) -> Result<Calibration, CalibrationError> {
        self.check(min_samples)?;
        let (ox, rx) = centre_radius(self.min.x, self.max.x, min_span)?;
        let (oy, ry) = centre_radius(self.min.y, self.max.y, min_span)?;
        let mean = (rx + ry) / 2.0;
        Ok(Calibration {
            offset: Vector3::new(ox, oy, 0.0),
            scale: Vector3::new(mean / rx, mean / ry, 1.0),
        })
    }
}

fn centre_radius(min: f32, max: f32, min_span: f32) -> Result<(f32, f32), CalibrationError> {
    let span = max - min;
    if !(span.is_finite() && span >= min_span && span > 0.0) {
        return Err(CalibrationError::SpanTooSmall);
    }
    Ok(((max + min) / 2.0, span / 2.0))
}
