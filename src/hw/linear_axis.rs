//! [`AxisDrive`] over a linear actuator (LINAK LA12 class) between two
//! pivots, driven by a DC H-bridge ([`drivers::dc_motor::DcMotor`]), its
//! position read from Hall pulses ([`HallFeedback`]) or a potentiometer on
//! an ADC ([`PotFeedback`]).
//!
//! The position loop, the duty ramps and every watch (stall, overcurrent,
//! unexpected motion, move timeout) are [`DcAxis`]'s: a `LinearAxis` owns
//! one whose counts are lengths (Hall pulses, or tenths of a millimetre of
//! the potentiometer), and converts between them and the controller's
//! counts, which are angles (`AxisConfig::counts_per_deg`):
//!
//! * a target angle becomes a length through
//!   [`ActuatorGeometry::length_mm`] (law of cosines), then an extension and
//!   a count of the inner axis;
//! * the measured count becomes an extension, a length, and an angle
//!   through [`ActuatorGeometry::axis_deg`] ([`AxisDrive::encoder_deg`]).
//!
//! The axis angle grows with the length (`L² = a² + b² − 2ab·cos γ` grows
//! with γ on 0..180°), so the controller's home (its lowest angle) is the
//! retracted end: `AxisConfig::home_deg` must be the angle at
//! [`LinearAxisConfig::switch_extension_mm`] (checked by
//! [`LinearAxis::new`]).
//!
//! # Stroke ends
//!
//! Targets are clamped to the stroke. The ends are end switches: whenever
//! the measured extension is at or beyond an end while the motor drives
//! that way, the axis stops (and a new target beyond it is clamped to it).
//! The Hall axis has its home switch at the retracted end instead, where
//! the pulse count is referenced (as [`DcAxis`] references its count, at
//! each closing edge): its retracted end is where that switch closes, not
//! where the count says, and a target below the stroke (only a homing run
//! asks for one) goes on at the stroke's mean mm per degree until the
//! switch stops it. So a switch that closed far from home (stuck, or a
//! bounce), which moved the reference there, cannot hold the next homing
//! run short of the real switch.
//!
//! # Feedback
//!
//! * Hall: pulses counted by the commanded direction (a single Hall
//!   output has no direction of its own: the board's interrupt adds or
//!   subtracts by the bridge's direction), [`PulseScale`] pulses per mm.
//!   The count is relative: until the home switch is found, moves are
//!   converted at the stroke's mean mm per degree and
//!   [`AxisDrive::encoder_deg`] is `None`.
//! * Potentiometer: absolute. Each poll reads
//!   [`PotConfig::samples`] conversions and averages them; a reading more
//!   than [`PotConfig::end_margin_counts`] outside the calibrated span
//!   ([`PotCalibration`]) is a fault (a broken wiper or lead reads at a
//!   rail), within it the end. The averaged position only moves when it
//!   changes by more than [`PotConfig::hysteresis_mm`], so ADC noise is
//!   neither motion at rest for the idle watch nor hunting at the target.
//!
//! A bad reading (ADC error, a reading outside the span) brakes the motor,
//! is returned by [`LinearAxis::poll`] as [`LinearAxisError::Feedback`],
//! is reported once by [`AxisDrive::take_fault`] as [`DriveFault::Stall`]
//! (no usable feedback: as a failed Hall sensor), and refuses moves until
//! [`AxisDrive::clear_fault`]. Nothing here panics on a reading.

use core::convert::Infallible;

use drivers::adc::AdcChannel;
use drivers::dc_motor::{Bridge, DcMotor, Output};
use drivers::linear::{ActuatorGeometry, LinearError, PotCalibration, PulseScale};
use embedded_hal::digital::{ErrorType, InputPin};
use sun_algos::Float;

use super::dc_axis::{DcAxis, DcAxisConfig, DcAxisConfigError, DcAxisError, DcState, MotorCurrent};
use super::servo_axis::EncoderCount;
use crate::config::AxisConfig;
use crate::motion::{AxisDrive, DriveFault};

/// Counts of the inner axis per mm of a potentiometer's extension (a
/// tenth of a millimetre each: a 10-bit ADC over the LA12's 0.5–4.5 V and
/// 100 mm resolves 0.12 mm).
pub const POT_COUNTS_PER_MM: f32 = 10.0;

/// A linear actuator's position feedback, read as a count of the inner
/// [`DcAxis`] that grows with the extension.
pub trait LinearFeedback: EncoderCount {
    /// Why a reading was refused.
    type Error;
    /// True when the count is the extension from fully retracted
    /// ([`EncoderCount::count`] / [`LinearFeedback::counts_per_mm`]);
    /// false when it is relative and referenced at the home switch.
    const ABSOLUTE: bool;
    /// Takes a new reading (called before every poll of the axis).
    fn refresh(&mut self) -> Result<(), Self::Error>;
    /// Counts per mm of extension.
    fn counts_per_mm(&self) -> f32;
    /// The count to stop at for an extension (0..=stroke), from fully
    /// retracted: the nearest count the feedback can read there.
    fn counts_for(&self, extension_mm: f32) -> Result<i32, LinearError> {
        PulseScale::new(self.counts_per_mm())?.pulses(extension_mm)
    }
}

/// Hall pulses counted by the commanded direction (by the board's
/// interrupt), `scale` pulses per mm.
///
/// A pulse edge is a point of the stroke; between edges the rod is
/// somewhere in the pulse. The rod stops on the edge that ended a move
/// (the spindle is self-locking and the loop brakes on the count), so the
/// position is taken as the last edge crossed: the pulse's lower edge when
/// it was entered extending, its upper edge when entered retracting. The
/// count is in half pulses (`2 · pulses`, plus 2 after a retracting edge),
/// so that the inner loop's smallest deadband (1) stops on the target's
/// edge itself rather than one pulse short.
#[derive(Debug, Clone, Copy)]
pub struct HallFeedback<E> {
    counter: E,
    scale: PulseScale,
    /// The pulse count at the last refresh, and whether it last fell.
    last: i32,
    down: bool,
}

impl<E: EncoderCount> HallFeedback<E> {
    /// Pulses from `counter`, `scale` pulses per mm (LINAK LA12 option L:
    /// 1).
    pub fn new(counter: E, scale: PulseScale) -> Self {
        let last = counter.count();
        HallFeedback {
            counter,
            scale,
            last,
            down: false,
        }
    }
}

impl<E: EncoderCount> EncoderCount for HallFeedback<E> {
    fn count(&self) -> i32 {
        let edge = if self.down { 2 } else { 0 };
        self.last.saturating_mul(2).saturating_add(edge)
    }
}

impl<E: EncoderCount> LinearFeedback for HallFeedback<E> {
    type Error = Infallible;
    const ABSOLUTE: bool = false;
    fn refresh(&mut self) -> Result<(), Infallible> {
        let c = self.counter.count();
        if c != self.last {
            self.down = c < self.last;
            self.last = c;
        }
        Ok(())
    }
    fn counts_per_mm(&self) -> f32 {
        2.0 * self.scale.pulses_per_mm()
    }
    /// The nearest pulse edge (an even count of half pulses).
    fn counts_for(&self, extension_mm: f32) -> Result<i32, LinearError> {
        let pulses = self.scale.pulses(extension_mm)?;
        pulses.checked_mul(2).ok_or(LinearError::TooManyPulses)
    }
}

/// How a potentiometer is read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PotConfig {
    /// Conversions averaged per poll (1..=64).
    pub samples: u8,
    /// The position moves only by more than this, mm (≥ 0, finite): above
    /// the averaged noise.
    pub hysteresis_mm: f32,
    /// Readings this many counts outside the calibrated span are taken as
    /// the end (noise at the ends); farther out they are faults.
    pub end_margin_counts: u16,
}

/// Why a potentiometer reading was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PotError<AE> {
    /// The ADC failed.
    Adc(AE),
    /// A reading outside the calibrated span (beyond the margin).
    Reading(LinearError),
}

/// An actuator's potentiometer on an ADC channel: the count is the
/// extension in tenths of a mm ([`POT_COUNTS_PER_MM`]), averaged and with
/// hysteresis ([`PotConfig`]).
#[derive(Debug)]
pub struct PotFeedback<A> {
    adc: A,
    calibration: PotCalibration,
    config: PotConfig,
    /// Counts at the retracted and the extended end.
    ends: (u16, u16),
    stroke_mm: f32,
    /// The held extension, mm, and it as a count.
    held_mm: f32,
    count: i32,
}

impl<A: AdcChannel> PotFeedback<A> {
    /// A potentiometer calibrated by `calibration` over `stroke_mm` (the
    /// calibration's own stroke); reads once to start from where the rod is.
    pub fn new(
        adc: A,
        calibration: PotCalibration,
        stroke_mm: f32,
        config: PotConfig,
    ) -> Result<Self, PotError<A::Error>> {
        let config_ok = (1..=64).contains(&config.samples)
            && config.hysteresis_mm.is_finite()
            && config.hysteresis_mm >= 0.0;
        let ends = calibration
            .counts(0.0)
            .and_then(|r| Ok((r, calibration.counts(stroke_mm)?)))
            .map_err(PotError::Reading)?;
        if !config_ok {
            return Err(PotError::Reading(LinearError::InvalidConfig));
        }
        let mut pot = PotFeedback {
            adc,
            calibration,
            config,
            ends,
            stroke_mm,
            held_mm: 0.0,
            count: 0,
        };
        let mm = pot.read_mm()?;
        pot.hold(mm);
        Ok(pot)
    }

    /// One reading's extension, mm: within the margin outside the span it
    /// is the end.
    fn one_mm(&mut self) -> Result<f32, PotError<A::Error>> {
        let raw = self.adc.read_raw().map_err(PotError::Adc)?;
        let (lo, hi) = (self.ends.0.min(self.ends.1), self.ends.0.max(self.ends.1));
        let m = self.config.end_margin_counts;
        let raw = if raw < lo && lo - raw <= m {
            lo
        } else if raw > hi && raw - hi <= m {
            hi
        } else {
            raw
        };
        self.calibration
            .extension_mm(raw)
            .map_err(PotError::Reading)
    }

    /// The average of `samples` readings, mm.
    fn read_mm(&mut self) -> Result<f32, PotError<A::Error>> {
        let mut sum_mm = 0.0;
        for _ in 0..self.config.samples {
            sum_mm += self.one_mm()?;
        }
        Ok(sum_mm / f32::from(self.config.samples))
    }

    fn hold(&mut self, mm: f32) {
        // `Float::clamp`, not `f32::clamp`: no panic path for bounds that
        // are not ordered (none here: a calibrated stroke is positive).
        self.held_mm = Float::clamp(mm, 0.0, self.stroke_mm);
        // 0..=stroke · 10: a stroke of a valid calibration is finite.
        self.count = PulseScale::new(POT_COUNTS_PER_MM)
            .and_then(|s| s.pulses(self.held_mm))
            .unwrap_or(0);
    }

    /// The held extension, mm.
    pub fn extension_mm(&self) -> f32 {
        self.held_mm
    }

    /// Gives the ADC channel back.
    pub fn destroy(self) -> A {
        self.adc
    }
}

impl<A> EncoderCount for PotFeedback<A> {
    fn count(&self) -> i32 {
        self.count
    }
}

impl<A: AdcChannel> LinearFeedback for PotFeedback<A> {
    type Error = PotError<A::Error>;
    const ABSOLUTE: bool = true;
    fn refresh(&mut self) -> Result<(), Self::Error> {
        let mm = self.read_mm()?;
        if (mm - self.held_mm).abs() > self.config.hysteresis_mm {
            self.hold(mm);
        }
        Ok(())
    }
    fn counts_per_mm(&self) -> f32 {
        POT_COUNTS_PER_MM
    }
}

/// The switch input of an axis without a home switch (a potentiometer's):
/// it reads low, so never closed as an active-high switch: build the axis
/// with `home_active_low = false` (with `true` it would read as closed for
/// ever, and motion toward it would stop).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NoEndSwitch;

impl ErrorType for NoEndSwitch {
    type Error = Infallible;
}

impl InputPin for NoEndSwitch {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(false)
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        Ok(true)
    }
}

/// `counts` rounded to the nearest whole count (beyond ±2³¹ the f32 → i32
/// cast saturates; NaN is 0).
fn round_counts(counts: f32) -> i32 {
    (if counts >= 0.0 {
        counts + 0.5
    } else {
        counts - 0.5
    }) as i32
}

/// The actuator's mounting and where its home switch closes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearAxisConfig {
    /// Pivots, offset and stroke.
    pub geometry: ActuatorGeometry,
    /// Hall: the extension of the last pulse edge the rod crosses before
    /// the home switch closes while retracting, mm (the first edge above
    /// the switch: [`HallFeedback`] places the rod on the last edge
    /// crossed). Unused with a potentiometer, whose home is the retracted
    /// end.
    pub switch_extension_mm: f32,
    /// A measured extension this close to an end is at it, mm (≥ 0): the
    /// potentiometer's resolution and hysteresis; 0 for Hall pulses.
    pub end_tolerance_mm: f32,
    /// The inner position loop and watches, in feedback counts.
    pub loop_config: DcAxisConfig,
}

/// Why a [`LinearAxisConfig`] is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearAxisConfigError {
    /// The position loop's settings.
    Loop(DcAxisConfigError),
    /// The geometry, the switch's extension outside the stroke, or the
    /// end tolerance negative or not finite.
    Geometry(LinearError),
    /// `AxisConfig::home_deg` is not the angle at the home switch (within
    /// a hundredth of a degree), or its counts per degree are not finite
    /// and positive.
    Home,
}

/// Errors of a linear axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearAxisError<PE, NE, HE, CE, FE> {
    /// The inner DC axis (bridge, switch, current sense, its faults).
    Axis(DcAxisError<PE, NE, HE, CE>),
    /// A refused reading (returned once by `poll`, then latched).
    Feedback(FE),
    /// Moves refused: the feedback failed and the fault is not cleared.
    FeedbackLost,
    /// A measured length with no angle (a count beyond the stroke).
    Geometry(LinearError),
}

type LinErr<B, F, H, C> = LinearAxisError<
    <B as Bridge>::PwmError,
    <B as Bridge>::PinError,
    <H as ErrorType>::Error,
    <C as MotorCurrent>::Error,
    <F as LinearFeedback>::Error,
>;

/// One tracker axis on a linear actuator: a [`DcAxis`] in feedback counts,
/// seen by the controller in angle counts.
pub struct LinearAxis<B: Bridge, F, H, C> {
    inner: DcAxis<B, F, H, C>,
    geometry: ActuatorGeometry,
    switch_extension_mm: f32,
    end_tolerance_mm: f32,
    /// Counts of the inner axis per mm.
    scale: PulseScale,
    /// The controller's counts per degree.
    counts_per_deg: f32,
    /// Mean mm per degree over the stroke (moves before the reference).
    mean_mm_per_deg: f32,
    /// Angles of the two stroke ends.
    range_deg: (f32, f32),
    /// The target is `base_deg + target_counts / counts_per_deg`.
    base_deg: f32,
    target_counts: i32,
    referenced: bool,
    feedback_lost: bool,
    unseen_lost: bool,
}

impl<B: Bridge, F, H, C> core::fmt::Debug for LinearAxis<B, F, H, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("LinearAxis")
            .field("inner", &self.inner)
            .field("base_deg", &self.base_deg)
            .field("target_counts", &self.target_counts)
            .field("referenced", &self.referenced)
            .field("feedback_lost", &self.feedback_lost)
            .finish_non_exhaustive()
    }
}

impl<B, F, H, C> LinearAxis<B, F, H, C>
where
    B: Bridge,
    F: LinearFeedback,
    H: InputPin,
    C: MotorCurrent,
{
    /// An axis resting where it is. `axis` gives the controller's counts
    /// per degree and `home_deg`, the angle at the home switch (at the
    /// retracted end with a potentiometer).
    pub fn new(
        motor: DcMotor<B>,
        feedback: F,
        home: H,
        home_active_low: bool,
        sense: Option<C>,
        config: LinearAxisConfig,
        axis: &AxisConfig,
    ) -> Result<Self, LinearAxisConfigError> {
        let g = config.geometry;
        let geo = LinearAxisConfigError::Geometry;
        g.validate().map_err(geo)?;
        let tol = config.end_tolerance_mm;
        if !(tol.is_finite() && tol >= 0.0) {
            return Err(geo(LinearError::InvalidConfig));
        }
        let scale = PulseScale::new(feedback.counts_per_mm()).map_err(geo)?;
        let switch_mm = if F::ABSOLUTE {
            0.0
        } else {
            config.switch_extension_mm
        };
        let home_deg = g.axis_deg(g.length_from_extension_mm(switch_mm).map_err(geo)?);
        let home_deg = home_deg.map_err(geo)?;
        let lo = g.axis_deg(g.retracted_mm).map_err(geo)?;
        let hi = g.axis_deg(g.retracted_mm + g.stroke_mm).map_err(geo)?;
        let cpd = axis.counts_per_deg();
        if !(cpd.is_finite() && cpd > 0.0) || (axis.home_deg - home_deg).abs() > 0.01 {
            return Err(LinearAxisConfigError::Home);
        }
        // The inner axis's "degrees" are mm of extension from the switch
        // (counts per degree = counts per mm, home at 0).
        let inner_axis = AxisConfig {
            counts_per_motor_rev: 360,
            microsteps: 1,
            gear_ratio: scale.pulses_per_mm(),
            home_deg: 0.0,
            ..*axis
        };
        let inner = DcAxis::new(
            motor,
            feedback,
            home,
            home_active_low,
            sense,
            config.loop_config,
            &inner_axis,
        )
        .map_err(LinearAxisConfigError::Loop)?;
        let mut axis = LinearAxis {
            inner,
            geometry: g,
            switch_extension_mm: switch_mm,
            end_tolerance_mm: config.end_tolerance_mm,
            scale,
            counts_per_deg: cpd,
            // hi > lo: the angle grows with the length over a valid stroke.
            mean_mm_per_deg: g.stroke_mm / (hi - lo),
            range_deg: (lo, hi),
            base_deg: home_deg,
            target_counts: 0,
            referenced: false,
            feedback_lost: false,
            unseen_lost: false,
        };
        axis.sync_reference();
        Ok(axis)
    }

    /// The inner count where the extension is 0, once known.
    fn origin(&self) -> Option<i32> {
        if F::ABSOLUTE {
            return Some(0);
        }
        let switch = self.scale.pulses(self.switch_extension_mm).ok()?;
        self.inner
            .count_at_switch()
            .map(|c| c.saturating_sub(switch))
    }

    /// The measured extension, mm, once referenced (not clamped).
    pub fn extension_mm(&self) -> Option<f32> {
        self.origin().map(|o| {
            let counts = self.inner.count().saturating_sub(o);
            self.scale.extension_mm(counts)
        })
    }

    /// The measured axis angle, once referenced: an extension within a
    /// count of the stroke is its end, farther out an error.
    pub fn measured_deg(&self) -> Result<Option<f32>, LinearError> {
        let Some(ext) = self.extension_mm() else {
            return Ok(None);
        };
        let count_mm = 1.0 / self.scale.pulses_per_mm();
        let g = &self.geometry;
        let ext = if ext < 0.0 && ext >= -count_mm {
            0.0
        } else if ext > g.stroke_mm && ext <= g.stroke_mm + count_mm {
            g.stroke_mm
        } else {
            ext
        };
        g.axis_deg(g.length_from_extension_mm(ext)?).map(Some)
    }

    /// The reference was just found: the target is where the axis is.
    fn sync_reference(&mut self) {
        if self.referenced {
            return;
        }
        if let Ok(Some(deg)) = self.measured_deg() {
            self.referenced = true;
            self.base_deg = deg;
            self.target_counts = 0;
        }
    }

    /// The target becomes the measured angle, once referenced.
    fn target_at_measured(&mut self) {
        if let Ok(Some(deg)) = self.measured_deg() {
            self.base_deg = deg;
            self.target_counts = 0;
        }
    }

    fn target_deg(&self) -> f32 {
        self.base_deg + self.target_counts as f32 / self.counts_per_deg
    }

    /// Keeps the target within the stroke (on a relative feedback, down to
    /// a whole stroke below it: room for a homing run), so that moves asked
    /// beyond an end (a homing run backing off a switch stuck closed, a
    /// target the rod cannot reach) do not pile up there: a move back
    /// starts from the end, not from where the piled-up target was.
    fn bound_target(&mut self) {
        let (lo, hi) = self.range_deg;
        let floor = if F::ABSOLUTE { lo } else { lo - (hi - lo) };
        let deg = self.target_deg();
        if deg > hi || deg < floor {
            let to = Float::clamp(deg, floor, hi);
            // Within two strokes of the base angle: no saturation.
            self.target_counts = round_counts((to - self.base_deg) * self.counts_per_deg);
        }
    }

    /// The inner count for the target angle, clamped to the stroke; on a
    /// relative feedback a target below the retracted end (a homing run's)
    /// goes on at the stroke's mean mm per degree (module documentation).
    fn inner_target(&self) -> Option<i32> {
        let origin = self.origin()?;
        let (lo, hi) = self.range_deg;
        let g = &self.geometry;
        let deg = self.target_deg();
        let ext = if deg < lo && !F::ABSOLUTE {
            (deg - lo) * self.mean_mm_per_deg
        } else {
            g.extension_mm(g.length_mm(Float::clamp(deg, lo, hi)).ok()?)
                .ok()?
        };
        let counts = self.inner.encoder().counts_for(ext).ok()?;
        Some(origin.saturating_add(counts))
    }

    /// Stops the inner axis when it drives into a stroke end (on a
    /// relative feedback the retracted end is its home switch's).
    fn check_ends(&mut self) -> Result<(), LinErr<B, F, H, C>> {
        let (Some(ext), DcState::Driving { dir }) = (self.extension_mm(), self.inner.state())
        else {
            return Ok(());
        };
        let tol = self.end_tolerance_mm;
        let at_end = (dir > 0 && ext >= self.geometry.stroke_mm - tol)
            || (dir < 0 && F::ABSOLUTE && ext <= tol);
        if at_end {
            self.inner.stop().map_err(LinearAxisError::Axis)?;
        }
        Ok(())
    }

    /// Reads the feedback, stops at the stroke ends, and runs the inner
    /// position loop and watches ([`DcAxis::poll`]); call every main-loop
    /// pass. A refused reading brakes, is returned once here, and is kept
    /// until [`AxisDrive::clear_fault`].
    pub fn poll(&mut self, now_ms: u32) -> Result<Output, LinErr<B, F, H, C>> {
        if !self.feedback_lost {
            if let Err(e) = self.inner.encoder_mut().refresh() {
                self.feedback_lost = true;
                self.unseen_lost = true;
                self.inner.stop().map_err(LinearAxisError::Axis)?;
                return Err(LinearAxisError::Feedback(e));
            }
        }
        self.check_ends()?;
        let out = self.inner.poll(now_ms).map_err(LinearAxisError::Axis)?;
        self.sync_reference();
        Ok(out)
    }

    /// The inner DC axis (its state, counts and latched fault).
    pub fn inner(&self) -> &DcAxis<B, F, H, C> {
        &self.inner
    }

    /// True when the feedback failed and the fault is not cleared.
    pub fn feedback_lost(&self) -> bool {
        self.feedback_lost
    }
}

impl<B, F, H, C> AxisDrive for LinearAxis<B, F, H, C>
where
    B: Bridge,
    F: LinearFeedback,
    H: InputPin,
    C: MotorCurrent,
{
    type Error = LinErr<B, F, H, C>;
    const SELF_WATCHED: bool = true;

    /// Moves the target angle by `counts` / counts per degree; before the
    /// reference, moves the rod at the stroke's mean mm per degree.
    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error> {
        if self.feedback_lost {
            return Err(LinearAxisError::FeedbackLost);
        }
        self.sync_reference();
        self.target_counts = self.target_counts.saturating_add(counts);
        self.bound_target();
        let inner_counts = if let Some(target) = self.inner_target() {
            target.saturating_sub(self.inner.target())
        } else {
            let mm = counts as f32 / self.counts_per_deg * self.mean_mm_per_deg;
            self.scale
                .pulses(mm)
                .unwrap_or(if counts < 0 { i32::MIN } else { i32::MAX })
        };
        self.inner
            .move_counts(inner_counts)
            .map_err(LinearAxisError::Axis)
    }

    /// Angle counts to go while the inner axis moves (never 0 then).
    fn pending(&self) -> i32 {
        let inner = self.inner.pending();
        if inner == 0 {
            return 0;
        }
        let left = match self.measured_deg() {
            Ok(Some(now)) => round_counts((self.target_deg() - now) * self.counts_per_deg),
            _ => inner,
        };
        if left != 0 {
            left
        } else {
            inner.signum()
        }
    }

    /// Brakes at once; the target becomes the measured angle.
    fn stop(&mut self) -> Result<(), Self::Error> {
        self.inner.stop().map_err(LinearAxisError::Axis)?;
        self.target_at_measured();
        Ok(())
    }

    /// The home switch (Hall), or the rod at the retracted end
    /// (potentiometer).
    fn at_limit(&mut self) -> Result<bool, Self::Error> {
        if F::ABSOLUTE {
            return Ok(self
                .extension_mm()
                .is_some_and(|e| e <= self.end_tolerance_mm));
        }
        let closed = self.inner.at_limit().map_err(LinearAxisError::Axis)?;
        self.sync_reference();
        Ok(closed)
    }

    /// The angle from the measured length, once referenced.
    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error> {
        self.measured_deg().map_err(LinearAxisError::Geometry)
    }

    fn switch_stops(&mut self, on: bool) {
        self.inner.switch_stops(on);
    }

    /// On Hall pulses, at rest: the target becomes the measured edge (the
    /// potentiometer's axis keeps its target: its held reading moves only
    /// by more than its hysteresis).
    fn rebase_at_rest(&mut self) {
        if F::ABSOLUTE || !matches!(self.inner.state(), DcState::Idle { .. }) {
            return;
        }
        self.target_at_measured();
    }

    /// The inner axis's faults, and a lost feedback as
    /// [`DriveFault::Stall`].
    fn take_fault(&mut self) -> Option<DriveFault> {
        if self.unseen_lost {
            self.unseen_lost = false;
            return Some(DriveFault::Stall);
        }
        self.inner.take_fault()
    }

    fn fault_latched(&self) -> bool {
        self.feedback_lost || self.inner.fault_latched()
    }

    /// Ends a lost feedback and the inner axis's latched fault: rests
    /// where it is.
    fn clear_fault(&mut self) {
        self.feedback_lost = false;
        self.unseen_lost = false;
        AxisDrive::clear_fault(&mut self.inner);
        self.target_at_measured();
    }
}
