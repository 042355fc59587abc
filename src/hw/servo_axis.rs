//! [`AxisDrive`] over a continuous-rotation servo and a quadrature encoder
//! (Chowdhury et al. 2019: FS5106R servo, YMT22 optical encoder), with the
//! drivers' proportional position controller closing the loop on the
//! encoder count.
//!
//! Like the stepper axis it never blocks: [`AxisDrive::move_counts`] moves
//! the target, and the main loop calls [`ServoAxis::poll`] often (every
//! millisecond or so) to update the servo's speed from the encoder.
//!
//! The encoder is incremental. Its count becomes an axis angle once the
//! homing switch has been seen closed: every [`AxisDrive::at_limit`] that
//! finds it closed takes the count there as the switch angle (the homing's
//! last, slow approach is the last such reading), so
//! [`AxisDrive::encoder_deg`] is `home_deg + (count − count_at_switch) /
//! counts_per_deg`, the same reference [`crate::motion::AxisController`]
//! takes when homing ends.

use drivers::encoder::SharedEncoder;
use drivers::servo::{ContinuousServo, Error as ServoError, PositionController};
use embedded_hal::digital::InputPin;
use embedded_hal::pwm::SetDutyCycle;

use crate::config::AxisConfig;
use crate::motion::AxisDrive;

/// Something that counts encoder edges (usually updated by an interrupt).
pub trait EncoderCount {
    /// Counts so far.
    fn count(&self) -> i32;
}

/// A shared reference counts as its encoder does (an encoder kept by an
/// interrupt is shared between the interrupt and the axis).
impl<T: EncoderCount + ?Sized> EncoderCount for &T {
    fn count(&self) -> i32 {
        T::count(self)
    }
}

impl EncoderCount for SharedEncoder {
    fn count(&self) -> i32 {
        SharedEncoder::count(self)
    }
}

#[cfg(target_has_atomic = "32")]
#[cfg(target_has_atomic = "32")]
impl EncoderCount for drivers::encoder::AtomicEncoder {
    fn count(&self) -> i32 {
        drivers::encoder::AtomicEncoder::count(self)
    }
}

/// Errors of a servo axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ServoAxisError<EP, EH> {
    /// The servo's PWM channel failed.
    Servo(ServoError<EP>),
    /// The home switch could not be read.
    Switch(EH),
}

/// One tracker axis on a continuous-rotation servo with a quadrature
/// encoder; counts are encoder counts (`AxisConfig::counts_per_motor_rev`
/// = encoder counts per motor revolution, `microsteps` = 1).
#[derive(Debug)]
pub struct ServoAxis<'a, P, E, H> {
    servo: ContinuousServo<P>,
    encoder: &'a E,
    home: H,
    home_active_low: bool,
    control: PositionController,
    /// Target encoder count (saturating at the `i32` range, as the count).
    target: i32,
    /// Target and count of the last pass that left the servo stopped.
    resting: Option<(i32, i32)>,
    count_at_switch: Option<i32>,
    home_deg: f32,
    counts_per_deg: f32,
    /// Motion toward the closed switch stops ([`AxisDrive::switch_stops`]).
    switch_stops: bool,
}

impl<'a, P, E, H> ServoAxis<'a, P, E, H>
where
    P: SetDutyCycle,
    E: EncoderCount,
    H: InputPin,
{
    /// An axis holding its present position. `axis` gives the switch angle
    /// and the counts per degree.
    pub fn new(
        servo: ContinuousServo<P>,
        encoder: &'a E,
        home: H,
        home_active_low: bool,
        control: PositionController,
        axis: &AxisConfig,
    ) -> Self {
        let cpd = axis.counts_per_deg();
        ServoAxis {
            servo,
            encoder,
            home,
            home_active_low,
            control,
            target: encoder.count(),
            resting: None,
            count_at_switch: None,
            switch_stops: true,
            home_deg: axis.home_deg,
            counts_per_deg: if cpd.is_finite() && cpd > 0.0 {
                cpd
            } else {
                1.0
            },
        }
    }

    fn switch_closed(&mut self) -> Result<bool, ServoAxisError<P::Error, H::Error>> {
        let high = self.home.is_high().map_err(ServoAxisError::Switch)?;
        let closed = high != self.home_active_low;
        if closed {
            self.count_at_switch = Some(self.encoder.count());
        }
        Ok(closed)
    }

    /// Closes the loop once: speed from the position error. Motion toward
    /// the switch stops when it is closed (as the stepper driver's limit
    /// input does). Returns the speed commanded, −1..1.
    ///
    /// At rest (stopped on the target, and neither the target nor the count
    /// changed since) nothing is computed or written: the servo already
    /// has its neutral pulse. An 8-bit part then spends its loop passes
    /// asleep, not in soft-float arithmetic.
    pub fn poll(&mut self) -> Result<f32, ServoAxisError<P::Error, H::Error>> {
        let count = self.encoder.count();
        if self.resting == Some((self.target, count)) {
            return Ok(0.0);
        }
        let mut speed = self.control.update(self.target, count);
        if speed < 0.0 && self.switch_stops && self.switch_closed()? {
            self.target = count;
            speed = 0.0;
        }
        self.resting = None;
        self.servo.set_speed(speed).map_err(ServoAxisError::Servo)?;
        if speed == 0.0 {
            self.resting = Some((self.target, count));
        }
        Ok(speed)
    }

    /// The encoder count.
    pub fn count(&self) -> i32 {
        self.encoder.count()
    }

    /// The target count.
    pub fn target(&self) -> i32 {
        self.target
    }

    /// The pulse width now output, µs.
    pub fn pulse_us(&self) -> u32 {
        self.servo.pulse_us()
    }

    /// Gives the servo and the switch back.
    pub fn destroy(self) -> (ContinuousServo<P>, H) {
        (self.servo, self.home)
    }
}

impl<P, E, H> AxisDrive for ServoAxis<'_, P, E, H>
where
    P: SetDutyCycle,
    E: EncoderCount,
    H: InputPin,
{
    type Error = ServoAxisError<P::Error, H::Error>;

    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error> {
        self.target = self.target.saturating_add(counts);
        Ok(())
    }

    /// Counts to go, 0 once inside the controller's deadband.
    #[inline(never)]
    fn pending(&self) -> i32 {
        // Saturating: both ends of the i32 range give the largest move.
        let e = self.target.saturating_sub(self.encoder.count());
        if e.unsigned_abs() <= self.control.deadband_counts {
            0
        } else {
            e
        }
    }

    #[inline(never)]
    fn stop(&mut self) -> Result<(), Self::Error> {
        self.target = self.encoder.count();
        self.servo.stop().map_err(ServoAxisError::Servo)
    }

    #[inline(never)]
    fn at_limit(&mut self) -> Result<bool, Self::Error> {
        self.switch_closed()
    }

    #[inline(never)]
    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error> {
        Ok(self.count_at_switch.map(|c0| {
            // 32 bits: an axis between limits turns a few times 1,200
            // counts from its switch, one that turns without end is kept
            // within a turn of it (`rebase_counts`); the difference wraps
            // with the encoder's count.
            let d = self.encoder.count().wrapping_sub(c0);
            self.home_deg + d as f32 / self.counts_per_deg
        }))
    }

    fn rebase_counts(&mut self, counts: i32) {
        self.count_at_switch = self.count_at_switch.map(|c0| c0.wrapping_add(counts));
    }

    fn switch_stops(&mut self, on: bool) {
        self.switch_stops = on;
    }
}
