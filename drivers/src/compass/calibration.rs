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
///
/// ```
/// use drivers::compass::calibration::{CalibrationError, CalibrationSweep};
/// use drivers::compass::Vector3;
///
/// let mut sweep = CalibrationSweep::new();
/// assert_eq!(sweep.add(Vector3::new(f32::NAN, 0.0, 0.0)), Err(CalibrationError::NonFinite));
/// assert_eq!(sweep.finish(2, 0.1), Err(CalibrationError::TooFewSamples));
/// sweep.add(Vector3::new(0.1, 0.1, 0.1))?;
/// sweep.add(Vector3::new(0.1, 0.1, 0.1))?;
/// // The sensor never turned: every span is 0.
/// assert_eq!(sweep.finish(2, 0.1), Err(CalibrationError::SpanTooSmall));
/// # Ok::<(), CalibrationError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
///
/// With the `serde` feature it can be kept in a configuration store between
/// boots.
///
/// ```
/// use drivers::compass::calibration::Calibration;
/// use drivers::compass::Vector3;
///
/// let stored = Calibration {
///     offset: Vector3::new(0.05, -0.02, 0.1),
///     scale: Vector3::new(1.25, 1.0, 1.0),
/// };
/// let corrected = stored.apply(Vector3::new(0.25, -0.02, 0.1));
/// assert!((corrected.x - 0.25).abs() < 1e-6); // (0.25 − 0.05) × 1.25
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Calibration {
    /// Hard-iron offset, subtracted first (same unit as the samples).
    pub offset: Vector3,
    /// Soft-iron scale per axis, multiplied after the offset.
    pub scale: Vector3,
}

impl Calibration {
    /// No correction.
    ///
    /// ```
    /// use drivers::compass::calibration::Calibration;
    /// use drivers::compass::Vector3;
    ///
    /// let v = Vector3::new(0.1, -0.2, 0.3);
    /// assert_eq!(Calibration::IDENTITY.apply(v), v);
    /// ```
    pub const IDENTITY: Self = Self {
        offset: Vector3::new(0.0, 0.0, 0.0),
        scale: Vector3::new(1.0, 1.0, 1.0),
    };

    /// Applies the correction to one raw sample.
    ///
    /// ```
    /// use drivers::compass::calibration::Calibration;
    /// use drivers::compass::Vector3;
    ///
    /// let cal = Calibration {
    ///     offset: Vector3::new(0.05, -0.02, 0.1),
    ///     scale: Vector3::new(1.25, 1.0, 0.5),
    /// };
    /// // (raw − offset) · scale, per axis.
    /// let v = cal.apply(Vector3::new(0.05, 0.23, 0.5));
    /// assert!(v.x.abs() < 1e-7 && (v.y - 0.25).abs() < 1e-7 && (v.z - 0.2).abs() < 1e-7);
    /// ```
    pub fn apply(&self, raw: Vector3) -> Vector3 {
        Vector3 {
            x: (raw.x - self.offset.x) * self.scale.x,
            y: (raw.y - self.offset.y) * self.scale.y,
            z: (raw.z - self.offset.z) * self.scale.z,
        }
    }
}

/// Running min/max of a rotation sweep.
///
/// ```
/// use drivers::compass::calibration::CalibrationSweep;
/// use drivers::compass::Vector3;
///
/// // A sweep of a sensor whose field circle (radius 0.2 G in x, 0.25 G in
/// // y, 0.3 G in z) is centred on a hard-iron offset (0.05, −0.02, 0.1).
/// let mut sweep = CalibrationSweep::new();
/// for raw in [
///     Vector3::new(0.25, -0.02, 0.1),
///     Vector3::new(-0.15, -0.02, 0.1),
///     Vector3::new(0.05, 0.23, 0.1),
///     Vector3::new(0.05, -0.27, 0.1),
///     Vector3::new(0.05, -0.02, 0.4),
///     Vector3::new(0.05, -0.02, -0.2),
/// ] {
///     sweep.add(raw)?;
/// }
/// let cal = sweep.finish(6, 0.1)?;
/// // offset = centre of each axis' range; scale = mean radius / axis radius,
/// // with radii 0.2, 0.25, 0.3 and mean 0.25.
/// assert!((cal.offset.x - 0.05).abs() < 1e-6 && (cal.offset.z - 0.1).abs() < 1e-6);
/// assert!((cal.scale.x - 1.25).abs() < 1e-5);
/// assert!((cal.scale.z - 0.25 / 0.3).abs() < 1e-5);
/// # Ok::<(), drivers::compass::calibration::CalibrationError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    ///
    /// ```
    /// use drivers::compass::calibration::CalibrationSweep;
    ///
    /// let sweep = CalibrationSweep::new();
    /// assert_eq!(sweep.samples(), 0);
    /// assert_eq!(sweep, CalibrationSweep::default());
    /// ```
    pub const fn new() -> Self {
        Self {
            min: Vector3::new(f32::INFINITY, f32::INFINITY, f32::INFINITY),
            max: Vector3::new(f32::NEG_INFINITY, f32::NEG_INFINITY, f32::NEG_INFINITY),
            samples: 0,
        }
    }

    /// Number of samples taken so far.
    ///
    /// ```
    /// use drivers::compass::calibration::CalibrationSweep;
    /// use drivers::compass::Vector3;
    ///
    /// let mut sweep = CalibrationSweep::new();
    /// sweep.add(Vector3::new(0.1, 0.2, 0.3))?;
    /// let _ = sweep.add(Vector3::new(f32::NAN, 0.0, 0.0)); // refused, not counted
    /// assert_eq!(sweep.samples(), 1);
    /// # Ok::<(), drivers::compass::calibration::CalibrationError>(())
    /// ```
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Adds one raw sample; non-finite samples are refused.
    ///
    /// ```
    /// use drivers::compass::calibration::{CalibrationError, CalibrationSweep};
    /// use drivers::compass::Vector3;
    ///
    /// let mut sweep = CalibrationSweep::new();
    /// assert_eq!(sweep.add(Vector3::new(0.1, 0.2, 0.3)), Ok(()));
    /// assert_eq!(
    ///     sweep.add(Vector3::new(0.1, f32::INFINITY, 0.3)),
    ///     Err(CalibrationError::NonFinite)
    /// );
    /// ```
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
    ///
    /// ```
    /// use drivers::compass::calibration::{CalibrationError, CalibrationSweep};
    /// use drivers::compass::Vector3;
    ///
    /// // A sweep of a sensor whose field circle (radius 0.2 G in x, 0.25 G in
    /// // y, 0.3 G in z) is centred on a hard-iron offset (0.05, −0.02, 0.1).
    /// let mut sweep = CalibrationSweep::new();
    /// for raw in [
    ///     Vector3::new(0.25, -0.02, 0.1),
    ///     Vector3::new(-0.15, -0.02, 0.1),
    ///     Vector3::new(0.05, 0.23, 0.1),
    ///     Vector3::new(0.05, -0.27, 0.1),
    ///     Vector3::new(0.05, -0.02, 0.4),
    ///     Vector3::new(0.05, -0.02, -0.2),
    /// ] {
    ///     sweep.add(raw)?;
    /// }
    /// let cal = sweep.finish(6, 0.1)?;
    /// // The six extremes map onto one sphere of radius 0.25 (the mean).
    /// let c = cal.apply(Vector3::new(-0.15, -0.02, 0.1));
    /// assert!((c.x + 0.25).abs() < 1e-5 && c.y.abs() < 1e-6 && c.z.abs() < 1e-6);
    /// // A span of 0.4 G in x is not enough when 0.5 G is asked for.
    /// assert_eq!(sweep.finish(6, 0.5), Err(CalibrationError::SpanTooSmall));
    /// assert_eq!(sweep.finish(100, 0.1), Err(CalibrationError::TooFewSamples));
    /// # Ok::<(), CalibrationError>(())
    /// ```
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
    ///
    /// ```
    /// use drivers::compass::calibration::CalibrationSweep;
    /// use drivers::compass::Vector3;
    ///
    /// // A turn in azimuth only: z stays near −0.4 G.
    /// let mut sweep = CalibrationSweep::new();
    /// for raw in [
    ///     Vector3::new(0.25, -0.02, -0.4),
    ///     Vector3::new(0.05, 0.23, -0.4),
    ///     Vector3::new(-0.15, -0.02, -0.41),
    ///     Vector3::new(0.05, -0.27, -0.4),
    /// ] {
    ///     sweep.add(raw)?;
    /// }
    /// let cal = sweep.finish_xy(4, 0.1)?;
    /// assert!((cal.offset.x - 0.05).abs() < 1e-6 && (cal.offset.y + 0.02).abs() < 1e-6);
    /// assert_eq!((cal.offset.z, cal.scale.z), (0.0, 1.0)); // z left as measured
    /// assert!((cal.scale.x - 1.125).abs() < 1e-5); // mean radius 0.225 / 0.2
    /// # Ok::<(), drivers::compass::calibration::CalibrationError>(())
    /// ```
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
