//! Linear-actuator geometry: a tracker axis tilted by an actuator between
//! two pivots, and the actuator's position feedback (Hall pulses or a
//! potentiometer).
//!
//! The actuator's fixed pivot sits `a_mm` from the axis's hinge, its rod-end
//! pivot `b_mm` from it. With `L` the pivot-to-pivot length of the actuator
//! and γ the angle at the hinge between the two pivots, the law of cosines
//! gives
//!
//! `L² = a² + b² − 2ab·cos γ`, `γ = acos((a² + b² − L²) / (2ab))`,
//!
//! and the axis angle is `γ − offset_deg` (the offset is γ at the axis's
//! zero, fixed by how the actuator is mounted). A triangle exists only for
//! `|a − b| ≤ L ≤ a + b`; the actuator only reaches `retracted_mm ≤ L ≤
//! retracted_mm + stroke_mm`. Lengths and angles outside either are errors
//! ([`LinearError`]), never a panic or a NaN. `f32` throughout (libm or
//! avr-libc through the crate's math backend).
//!
//! Position feedback along the stroke (`extension = L − retracted`):
//! * Hall pulses, [`PulseScale`]: a fixed number of pulses per mm, from the
//!   actuator's data sheet (LINAK LA12 user manual, "I/O specifications":
//!   single Hall option L, 1 mm per pulse on the 12xLxx-1 spindle; LINAK
//!   LA35 user manual, "Relative positioning": 8 pulses per spindle turn,
//!   0.38 mm per pulse on the 3 mm pitch), counted by [`crate::hall`].
//! * A potentiometer read by an ADC ([`crate::adc`]), [`PotCalibration`]:
//!   the counts at both ends of the stroke are measured once and the
//!   extension is interpolated between them (the LA12's analogue option K
//!   spans 0.5 – 4.5 V over the stroke, the same manual page).

use crate::fmath;

/// Extension errors that are only `f32` rounding at the ends of the stroke
/// (a length computed from an end angle may come out a few µm beyond the
/// end): lengths this close outside the stroke are taken as the end.
const END_TOLERANCE_MM: f32 = 0.01;

/// Why a geometry or a conversion was refused.
///
/// ```
/// use drivers::linear::{ActuatorGeometry, LinearError};
///
/// let g = ActuatorGeometry { a_mm: 300.0, b_mm: 150.0, offset_deg: 75.0, retracted_mm: 245.0, stroke_mm: 100.0 };
/// assert_eq!(g.axis_deg(500.0), Err(LinearError::OutsideTriangle)); // longer than a + b = 450
/// assert_eq!(g.axis_deg(400.0), Err(LinearError::OutsideStroke)); // beyond 245 + 100
/// assert_eq!(LinearError::OutsideStroke.to_string(), "actuator length outside its stroke");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinearError {
    /// A configuration value is not finite or not positive, or the stroke
    /// does not lie strictly inside the triangle inequality `|a − b| < L <
    /// a + b`, or the potentiometer ends are equal.
    InvalidConfig,
    /// An input is NaN or infinite.
    NotFinite,
    /// No triangle has this length: `L < |a − b|` or `L > a + b`.
    OutsideTriangle,
    /// The length, extension or reading lies outside the stroke.
    OutsideStroke,
    /// The hinge angle `axis + offset` lies outside 0..=180°.
    AngleOutOfRange,
    /// A pulse count beyond the `i32` range.
    TooManyPulses,
}

impl core::fmt::Display for LinearError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            LinearError::InvalidConfig => "unusable actuator geometry or calibration",
            LinearError::NotFinite => "actuator input NaN or infinite",
            LinearError::OutsideTriangle => "actuator length outside the triangle inequality",
            LinearError::OutsideStroke => "actuator length outside its stroke",
            LinearError::AngleOutOfRange => "hinge angle outside 0..=180 degrees",
            LinearError::TooManyPulses => "pulse count beyond the i32 range",
        })
    }
}

impl core::error::Error for LinearError {}

/// Where the actuator is mounted, and its travel.
///
/// ```
/// use drivers::linear::ActuatorGeometry;
///
/// // a = 300 mm, b = 150 mm: at γ = 90° the actuator spans
/// // √(300² + 150²) = √112 500 = 335.41 mm; with the offset 75° that is
/// // the axis at +15°.
/// let g = ActuatorGeometry { a_mm: 300.0, b_mm: 150.0, offset_deg: 75.0, retracted_mm: 245.0, stroke_mm: 100.0 };
/// g.validate()?;
/// assert!((g.length_mm(15.0)? - 335.41).abs() < 0.01);
/// # Ok::<(), drivers::linear::LinearError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ActuatorGeometry {
    /// Hinge to the actuator's fixed pivot, mm.
    pub a_mm: f32,
    /// Hinge to the actuator's rod-end pivot, mm.
    pub b_mm: f32,
    /// Hinge angle γ at axis angle 0, degrees (axis = γ − offset).
    pub offset_deg: f32,
    /// Pivot-to-pivot length fully retracted, mm.
    pub retracted_mm: f32,
    /// Stroke, mm (fully extended = retracted + stroke).
    pub stroke_mm: f32,
}

impl ActuatorGeometry {
    /// The worked example of the tests and the book: a LINAK LA12 of
    /// 100 mm stroke (its manual's "I/O specifications": the longest stroke
    /// its potentiometer covers) between pivots 300 mm and 150 mm from the
    /// hinge, γ = 75° at the axis's zero. The 245 mm retracted length is an
    /// assumption (the manual's dimension drawing was not available), not a
    /// data-sheet figure. The stroke spans −20.666° (L = 245 mm) to
    /// +19.158° (L = 345 mm).
    ///
    /// ```
    /// use drivers::linear::ActuatorGeometry;
    ///
    /// assert_eq!(ActuatorGeometry::LA12_EXAMPLE.validate(), Ok(()));
    /// ```
    pub const LA12_EXAMPLE: ActuatorGeometry = ActuatorGeometry {
        a_mm: 300.0,
        b_mm: 150.0,
        offset_deg: 75.0,
        retracted_mm: 245.0,
        stroke_mm: 100.0,
    };

    /// Checks that every value is finite, the lengths positive, and that the
    /// whole stroke lies strictly inside the triangle inequality (so γ stays
    /// strictly between 0° and 180°, where `acos` is well conditioned).
    ///
    /// ```
    /// use drivers::linear::{ActuatorGeometry, LinearError};
    ///
    /// let g = ActuatorGeometry { a_mm: 300.0, b_mm: 150.0, offset_deg: 75.0, retracted_mm: 245.0, stroke_mm: 100.0 };
    /// assert_eq!(g.validate(), Ok(()));
    /// // Fully extended 245 + 210 = 455 mm > a + b = 450 mm: no triangle.
    /// assert_eq!(ActuatorGeometry { stroke_mm: 210.0, ..g }.validate(), Err(LinearError::InvalidConfig));
    /// assert_eq!(ActuatorGeometry { b_mm: f32::NAN, ..g }.validate(), Err(LinearError::InvalidConfig));
    /// ```
    pub fn validate(&self) -> Result<(), LinearError> {
        let values = [
            self.a_mm,
            self.b_mm,
            self.offset_deg,
            self.retracted_mm,
            self.stroke_mm,
        ];
        if values.iter().any(|v| !v.is_finite()) {
            return Err(LinearError::InvalidConfig);
        }
        let extended_mm = self.retracted_mm + self.stroke_mm;
        let ok = self.a_mm > 0.0
            && self.b_mm > 0.0
            && self.retracted_mm > 0.0
            && self.stroke_mm > 0.0
            && (self.a_mm - self.b_mm).abs() < self.retracted_mm
            && extended_mm < self.a_mm + self.b_mm;
        if ok {
            Ok(())
        } else {
            Err(LinearError::InvalidConfig)
        }
    }

    /// Pivot-to-pivot length for an axis angle, mm.
    ///
    /// ```
    /// use drivers::linear::{ActuatorGeometry, LinearError};
    ///
    /// let g = ActuatorGeometry { a_mm: 300.0, b_mm: 150.0, offset_deg: 75.0, retracted_mm: 245.0, stroke_mm: 100.0 };
    /// // Axis 0.52° → γ = 75.52°, cos γ ≈ 0.25: L² = 112 500 − 90 000 · 0.25 = 90 000, L = 300 mm.
    /// assert!((g.length_mm(0.5225)? - 300.0).abs() < 0.01);
    /// assert_eq!(g.length_mm(-60.0), Err(LinearError::OutsideStroke)); // γ = 15°: L = 159.9 mm, too short
    /// assert_eq!(g.length_mm(120.0), Err(LinearError::AngleOutOfRange)); // γ = 195°
    /// assert_eq!(g.length_mm(f32::NAN), Err(LinearError::NotFinite));
    /// # Ok::<(), LinearError>(())
    /// ```
    pub fn length_mm(&self, axis_deg: f32) -> Result<f32, LinearError> {
        self.validate()?;
        if !axis_deg.is_finite() {
            return Err(LinearError::NotFinite);
        }
        let gamma_deg = axis_deg + self.offset_deg;
        if !(0.0..=180.0).contains(&gamma_deg) {
            return Err(LinearError::AngleOutOfRange);
        }
        let (a, b) = (self.a_mm, self.b_mm);
        let l2 = a * a + b * b - 2.0 * a * b * fmath::cos(gamma_deg.to_radians());
        // l2 ≥ (a − b)² ≥ 0 up to rounding.
        let length_mm = fmath::sqrt(if l2 > 0.0 { l2 } else { 0.0 });
        self.in_stroke(length_mm)
    }

    /// Axis angle for a pivot-to-pivot length, degrees.
    ///
    /// ```
    /// use drivers::linear::ActuatorGeometry;
    ///
    /// let g = ActuatorGeometry { a_mm: 300.0, b_mm: 150.0, offset_deg: 75.0, retracted_mm: 245.0, stroke_mm: 100.0 };
    /// // L = 300: cos γ = (90 000 + 22 500 − 90 000) / 90 000 = 0.25, γ = 75.5225°, axis 0.5225°.
    /// assert!((g.axis_deg(300.0)? - 0.5225).abs() < 0.001);
    /// # Ok::<(), drivers::linear::LinearError>(())
    /// ```
    pub fn axis_deg(&self, length_mm: f32) -> Result<f32, LinearError> {
        self.validate()?;
        if !length_mm.is_finite() {
            return Err(LinearError::NotFinite);
        }
        let (a, b) = (self.a_mm, self.b_mm);
        if length_mm < (a - b).abs() || length_mm > a + b {
            return Err(LinearError::OutsideTriangle);
        }
        let length_mm = self.in_stroke(length_mm)?;
        let cos_gamma = (a * a + b * b - length_mm * length_mm) / (2.0 * a * b);
        Ok(fmath::acos_deg_clamped(cos_gamma) - self.offset_deg)
    }

    /// Extension beyond fully retracted for a pivot-to-pivot length, mm
    /// (0..=stroke).
    ///
    /// ```
    /// use drivers::linear::{ActuatorGeometry, LinearError};
    ///
    /// let g = ActuatorGeometry { a_mm: 300.0, b_mm: 150.0, offset_deg: 75.0, retracted_mm: 245.0, stroke_mm: 100.0 };
    /// assert_eq!(g.extension_mm(300.0), Ok(55.0));
    /// assert_eq!(g.extension_mm(244.0), Err(LinearError::OutsideStroke));
    /// ```
    pub fn extension_mm(&self, length_mm: f32) -> Result<f32, LinearError> {
        self.validate()?;
        if !length_mm.is_finite() {
            return Err(LinearError::NotFinite);
        }
        Ok(self.in_stroke(length_mm)? - self.retracted_mm)
    }

    /// Pivot-to-pivot length for an extension (0..=stroke), mm.
    ///
    /// ```
    /// use drivers::linear::{ActuatorGeometry, LinearError};
    ///
    /// let g = ActuatorGeometry { a_mm: 300.0, b_mm: 150.0, offset_deg: 75.0, retracted_mm: 245.0, stroke_mm: 100.0 };
    /// assert_eq!(g.length_from_extension_mm(100.0), Ok(345.0));
    /// assert_eq!(g.length_from_extension_mm(-1.0), Err(LinearError::OutsideStroke));
    /// ```
    pub fn length_from_extension_mm(&self, extension_mm: f32) -> Result<f32, LinearError> {
        self.validate()?;
        if !extension_mm.is_finite() {
            return Err(LinearError::NotFinite);
        }
        self.in_stroke(self.retracted_mm + extension_mm)
    }

    /// `length_mm` if within the stroke (within [`END_TOLERANCE_MM`] of an
    /// end counts as that end).
    fn in_stroke(&self, length_mm: f32) -> Result<f32, LinearError> {
        let lo = self.retracted_mm;
        let hi = self.retracted_mm + self.stroke_mm;
        if length_mm < lo - END_TOLERANCE_MM || length_mm > hi + END_TOLERANCE_MM {
            Err(LinearError::OutsideStroke)
        } else if length_mm < lo {
            Ok(lo)
        } else if length_mm > hi {
            Ok(hi)
        } else {
            Ok(length_mm)
        }
    }
}

/// `x` rounded to the nearest integer (halves away from zero) as an `i32`;
/// `None` when not finite or outside the `i32` range.
fn round_to_i32(x: f32) -> Option<i32> {
    if !x.is_finite() {
        return None;
    }
    let r = if x >= 0.0 { x + 0.5 } else { x - 0.5 };
    // 2³¹ is exact in f32; the range check makes the conversion exact
    // (the fraction is dropped, which is the rounding above).
    if (-2_147_483_648.0..2_147_483_648.0).contains(&r) {
        Some(r as i32)
    } else {
        None
    }
}

/// Hall pulses per millimetre of stroke.
///
/// ```
/// use drivers::linear::PulseScale;
///
/// // LINAK LA35, 3 mm pitch: 8 pulses per spindle turn, 3 mm / 8 = 0.375 mm
/// // per pulse (the manual rounds it to 0.38), 8 / 3 = 2.667 pulses per mm;
/// // 100 mm of stroke are 266.7 pulses (the manual: 266).
/// let s = PulseScale::new(8.0 / 3.0)?;
/// assert_eq!(s.pulses(100.0)?, 267);
/// assert_eq!(s.extension_mm(8), 3.0);
/// # Ok::<(), drivers::linear::LinearError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "f32", into = "f32")
)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PulseScale {
    pulses_per_mm: f32,
}

impl PulseScale {
    /// A scale of `pulses_per_mm` (finite, > 0).
    ///
    /// ```
    /// use drivers::linear::{LinearError, PulseScale};
    ///
    /// assert_eq!(PulseScale::new(0.0), Err(LinearError::InvalidConfig));
    /// assert_eq!(PulseScale::new(f32::INFINITY), Err(LinearError::InvalidConfig));
    /// ```
    pub fn new(pulses_per_mm: f32) -> Result<Self, LinearError> {
        if pulses_per_mm.is_finite() && pulses_per_mm > 0.0 {
            Ok(Self { pulses_per_mm })
        } else {
            Err(LinearError::InvalidConfig)
        }
    }

    /// Pulses per mm.
    ///
    /// ```
    /// use drivers::linear::PulseScale;
    ///
    /// assert_eq!(PulseScale::new(1.0)?.pulses_per_mm(), 1.0);
    /// # Ok::<(), drivers::linear::LinearError>(())
    /// ```
    pub fn pulses_per_mm(&self) -> f32 {
        self.pulses_per_mm
    }

    /// Pulses from fully retracted for an extension, rounded to the nearest.
    ///
    /// ```
    /// use drivers::linear::{LinearError, PulseScale};
    ///
    /// let s = PulseScale::new(1.0)?;
    /// assert_eq!(s.pulses(55.4)?, 55);
    /// assert_eq!(s.pulses(f32::NAN), Err(LinearError::NotFinite));
    /// assert_eq!(s.pulses(3e9), Err(LinearError::TooManyPulses));
    /// # Ok::<(), LinearError>(())
    /// ```
    pub fn pulses(&self, extension_mm: f32) -> Result<i32, LinearError> {
        if !extension_mm.is_finite() {
            return Err(LinearError::NotFinite);
        }
        round_to_i32(extension_mm * self.pulses_per_mm).ok_or(LinearError::TooManyPulses)
    }

    /// Extension for a pulse count, mm.
    ///
    /// ```
    /// use drivers::linear::PulseScale;
    ///
    /// // LINAK LA12 single Hall option N on the 12xNxx-1: 0.5 mm per pulse.
    /// let s = PulseScale::new(2.0)?;
    /// assert_eq!(s.extension_mm(111), 55.5);
    /// # Ok::<(), drivers::linear::LinearError>(())
    /// ```
    pub fn extension_mm(&self, pulses: i32) -> f32 {
        pulses as f32 / self.pulses_per_mm
    }
}

/// A feedback potentiometer's ADC counts at both ends of the stroke.
///
/// ```
/// use drivers::linear::PotCalibration;
///
/// // Counts 100 retracted and 900 extended over 100 mm: 8 counts per mm.
/// let pot = PotCalibration::new(100, 900, 100.0)?;
/// assert_eq!(pot.extension_mm(500)?, 50.0);
/// assert_eq!(pot.counts(25.0)?, 300);
/// # Ok::<(), drivers::linear::LinearError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "PotFields", into = "PotFields")
)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PotCalibration {
    retracted_counts: u16,
    extended_counts: u16,
    stroke_mm: f32,
}

impl PotCalibration {
    /// Counts read fully retracted and fully extended (either may be the
    /// larger: a potentiometer wired the other way round), and the stroke.
    ///
    /// ```
    /// use drivers::linear::{LinearError, PotCalibration};
    ///
    /// assert_eq!(PotCalibration::new(512, 512, 100.0), Err(LinearError::InvalidConfig));
    /// assert_eq!(PotCalibration::new(0, 1_023, -5.0), Err(LinearError::InvalidConfig));
    /// ```
    pub fn new(
        retracted_counts: u16,
        extended_counts: u16,
        stroke_mm: f32,
    ) -> Result<Self, LinearError> {
        if retracted_counts == extended_counts || !stroke_mm.is_finite() || stroke_mm <= 0.0 {
            return Err(LinearError::InvalidConfig);
        }
        Ok(Self {
            retracted_counts,
            extended_counts,
            stroke_mm,
        })
    }

    /// Extension for a reading, mm; a reading outside the calibrated span
    /// is [`LinearError::OutsideStroke`].
    ///
    /// ```
    /// use drivers::linear::{LinearError, PotCalibration};
    ///
    /// // Wired the other way round: 900 retracted, 100 extended.
    /// let pot = PotCalibration::new(900, 100, 100.0)?;
    /// assert_eq!(pot.extension_mm(700)?, 25.0);
    /// assert_eq!(pot.extension_mm(950), Err(LinearError::OutsideStroke));
    /// # Ok::<(), LinearError>(())
    /// ```
    pub fn extension_mm(&self, counts: u16) -> Result<f32, LinearError> {
        let (r, e, c) = (
            i32::from(self.retracted_counts),
            i32::from(self.extended_counts),
            i32::from(counts),
        );
        if c < r.min(e) || c > r.max(e) {
            return Err(LinearError::OutsideStroke);
        }
        // Differences of 16-bit counts: exact in f32.
        Ok((c - r) as f32 / (e - r) as f32 * self.stroke_mm)
    }

    /// The reading expected at an extension (0..=stroke), rounded to the
    /// nearest count.
    ///
    /// ```
    /// use drivers::linear::{LinearError, PotCalibration};
    ///
    /// let pot = PotCalibration::new(100, 900, 100.0)?;
    /// assert_eq!(pot.counts(100.0)?, 900);
    /// assert_eq!(pot.counts(100.5), Err(LinearError::OutsideStroke));
    /// assert_eq!(pot.counts(f32::NAN), Err(LinearError::NotFinite));
    /// # Ok::<(), LinearError>(())
    /// ```
    pub fn counts(&self, extension_mm: f32) -> Result<u16, LinearError> {
        if !extension_mm.is_finite() {
            return Err(LinearError::NotFinite);
        }
        if !(0.0..=self.stroke_mm).contains(&extension_mm) {
            return Err(LinearError::OutsideStroke);
        }
        let r = f32::from(self.retracted_counts);
        let e = f32::from(self.extended_counts);
        let c = round_to_i32(r + (e - r) * extension_mm / self.stroke_mm)
            .ok_or(LinearError::OutsideStroke)?;
        // Between the two calibrated counts, so within u16.
        u16::try_from(c).map_err(|_| LinearError::OutsideStroke)
    }
}

/// Pulses per mm, checked as by [`PulseScale::new`] (the form the `serde`
/// feature reads and writes: a bare number).
///
/// ```
/// use drivers::linear::{LinearError, PulseScale};
///
/// assert_eq!(PulseScale::try_from(2.0), PulseScale::new(2.0));
/// assert_eq!(PulseScale::try_from(-1.0), Err(LinearError::InvalidConfig));
/// assert_eq!(f32::from(PulseScale::new(2.0)?), 2.0);
/// # Ok::<(), LinearError>(())
/// ```
impl TryFrom<f32> for PulseScale {
    type Error = LinearError;

    fn try_from(pulses_per_mm: f32) -> Result<Self, LinearError> {
        Self::new(pulses_per_mm)
    }
}

impl From<PulseScale> for f32 {
    fn from(scale: PulseScale) -> f32 {
        scale.pulses_per_mm
    }
}

/// The serialized form of [`PotCalibration`], checked by
/// [`PotCalibration::new`] on the way in.
#[cfg(feature = "serde")]
#[derive(Clone, Copy, serde::Serialize, serde::Deserialize)]
struct PotFields {
    retracted_counts: u16,
    extended_counts: u16,
    stroke_mm: f32,
}

#[cfg(feature = "serde")]
impl TryFrom<PotFields> for PotCalibration {
    type Error = LinearError;

    fn try_from(f: PotFields) -> Result<Self, LinearError> {
        Self::new(f.retracted_counts, f.extended_counts, f.stroke_mm)
    }
}

#[cfg(feature = "serde")]
impl From<PotCalibration> for PotFields {
    fn from(c: PotCalibration) -> Self {
        Self {
            retracted_counts: c.retracted_counts,
            extended_counts: c.extended_counts,
            stroke_mm: c.stroke_mm,
        }
    }
}
