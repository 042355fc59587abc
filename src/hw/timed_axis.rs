//! [`AxisDrive`] over a DC motor with no position feedback: a move runs the
//! motor for the time the distance takes at a speed calibrated each way
//! (degrees per second forward and backward, measured on the installed
//! axis), as trackers on linear actuators without feedback do. The axis
//! knows where it is only from its home switch and the time it ran, so the
//! controller re-homes it every night and after every stow
//! (`ControllerOptions::rehome_nightly`, `rehome_after_stow`), and runs it
//! open loop ([`crate::motion::FeedbackMode::OpenLoop`]).
//!
//! Counts are the controller's (`AxisConfig::counts_per_deg`): a move of
//! `n` counts runs `|n| / counts_per_deg / speed` seconds at
//! [`TimedAxisConfig::duty_permille`], the speed of its direction.
//! [`AxisDrive::move_counts`] queues; [`TimedAxis::poll`], called every
//! main-loop pass with the monotonic millisecond counter, starts the
//! queued move, ends a run when its time is up (braking) and brakes at once
//! when the home switch closes on a run toward it. It never blocks.
//!
//! The run time assumes full duty from the first millisecond: give the
//! bridge no duty ramp (`drivers::dc_motor::Config::ramp_permille_per_ms`
//! = 0) and braking at rest. A DC motor's own start-up lag is then paid back
//! by its run-on after the brake: with the same mechanical time constant
//! driven and braked (the armature shorted either way), the angle a run of
//! `T` turns is the speed times `T` whatever the lag (the integral of a
//! first-order response), which the tests check on the motor model.

use drivers::dc_motor::{Bridge, DcMotor, Direction, Error as MotorError, Output};
use embedded_hal::digital::InputPin;

use crate::config::AxisConfig;
use crate::motion::AxisDrive;

/// Slowest and fastest calibrated speed, °/s.
pub const SPEED_RANGE_DEG_S: (f32, f32) = (0.001, 100.0);

/// Longest run of one move, ms (an hour: beyond any axis's travel).
pub const MAX_RUN_MS: u32 = 3_600_000;

/// Settings of a timed axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimedAxisConfig {
    /// Axis speed driven forward (positive counts), °/s.
    pub forward_deg_s: f32,
    /// Axis speed driven backward (toward home), °/s.
    pub backward_deg_s: f32,
    /// Duty of every run, ‰ (1..=1000): the duty the speeds were measured at.
    pub duty_permille: u16,
}

impl TimedAxisConfig {
    /// Checks both speeds (finite, within [`SPEED_RANGE_DEG_S`]) and the
    /// duty.
    pub fn validate(&self) -> Result<(), TimedAxisConfigError> {
        let (lo, hi) = SPEED_RANGE_DEG_S;
        // `!(x >= lo)` is true for NaN too.
        for v in [self.forward_deg_s, self.backward_deg_s] {
            if !(v >= lo && v <= hi) {
                return Err(TimedAxisConfigError::Speed);
            }
        }
        if self.duty_permille == 0 || self.duty_permille > 1_000 {
            return Err(TimedAxisConfigError::Duty);
        }
        Ok(())
    }
}

/// Which [`TimedAxisConfig`] field is unusable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimedAxisConfigError {
    /// A speed is not finite or outside [`SPEED_RANGE_DEG_S`].
    Speed,
    /// The duty is 0 or above 1000 ‰.
    Duty,
    /// The axis's counts per degree are not finite or not positive.
    Scale,
}

/// Errors of a timed axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimedAxisError<PE, NE, HE> {
    /// The bridge refused a write.
    Motor(MotorError<PE, NE>),
    /// The home switch could not be read.
    Switch(HE),
}

/// A run under way.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Run {
    /// Counts it moves (signed).
    counts: i32,
    /// Its start and length, ms.
    start_ms: u32,
    length_ms: u32,
}

/// One tracker axis on a DC motor without feedback.
pub struct TimedAxis<B: Bridge, H> {
    motor: DcMotor<B>,
    home: H,
    home_active_low: bool,
    config: TimedAxisConfig,
    counts_per_deg: f32,
    /// Counts commanded and not started yet.
    queued: i32,
    run: Option<Run>,
    /// The time of the last poll, ms.
    last_poll_ms: u32,
}

impl<B: Bridge, H> core::fmt::Debug for TimedAxis<B, H> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("TimedAxis")
            .field("queued", &self.queued)
            .field("run", &self.run)
            .field("output", &self.motor.output())
            .finish_non_exhaustive()
    }
}

type AxisErr<B, H> = TimedAxisError<
    <B as Bridge>::PwmError,
    <B as Bridge>::PinError,
    <H as embedded_hal::digital::ErrorType>::Error,
>;

impl<B: Bridge, H: InputPin> TimedAxis<B, H> {
    /// An axis at rest; `axis` gives the counts per degree.
    pub fn new(
        motor: DcMotor<B>,
        home: H,
        home_active_low: bool,
        config: TimedAxisConfig,
        axis: &AxisConfig,
    ) -> Result<Self, TimedAxisConfigError> {
        config.validate()?;
        let cpd = axis.counts_per_deg();
        if !(cpd.is_finite() && cpd > 0.0) {
            return Err(TimedAxisConfigError::Scale);
        }
        Ok(TimedAxis {
            motor,
            home,
            home_active_low,
            config,
            counts_per_deg: cpd,
            queued: 0,
            run: None,
            last_poll_ms: 0,
        })
    }

    fn switch_closed(&mut self) -> Result<bool, AxisErr<B, H>> {
        let high = self.home.is_high().map_err(TimedAxisError::Switch)?;
        Ok(high != self.home_active_low)
    }

    /// The run time of `counts`, ms, at the speed of their direction
    /// (at most [`MAX_RUN_MS`]).
    fn run_ms(&self, counts: i32) -> u32 {
        let speed = if counts > 0 {
            self.config.forward_deg_s
        } else {
            self.config.backward_deg_s
        };
        // Both factors are checked finite and positive at construction.
        let ms = counts.unsigned_abs() as f32 / self.counts_per_deg / speed * 1_000.0;
        if ms >= MAX_RUN_MS as f32 {
            MAX_RUN_MS
        } else {
            // Rounded to the nearest millisecond; non-negative and finite.
            (ms + 0.5) as u32
        }
    }

    fn end_run(&mut self) -> Result<(), AxisErr<B, H>> {
        self.run = None;
        self.motor.brake().map_err(TimedAxisError::Motor)
    }

    /// Ends a run whose time is up, brakes on the home switch, starts the
    /// queued move; call every main-loop pass with the monotonic
    /// millisecond counter. Returns what the bridge now does.
    pub fn poll(&mut self, now_ms: u32) -> Result<Output, AxisErr<B, H>> {
        self.last_poll_ms = now_ms;
        if let Some(run) = self.run {
            if run.counts < 0 && self.switch_closed()? {
                // At the switch: the rest of the run and of the queue are
                // dropped, as a stepper driver stops at its limit.
                self.queued = 0;
                self.end_run()?;
            } else if now_ms.wrapping_sub(run.start_ms) >= run.length_ms {
                self.end_run()?;
            }
        }
        if self.run.is_none() && self.queued != 0 {
            let counts = core::mem::take(&mut self.queued);
            let length_ms = self.run_ms(counts);
            let at_home = counts < 0 && self.switch_closed()?;
            if length_ms > 0 && !at_home {
                let direction = if counts > 0 {
                    Direction::Forward
                } else {
                    Direction::Backward
                };
                self.motor
                    .set_permille(direction, self.config.duty_permille)
                    .map_err(TimedAxisError::Motor)?;
                self.run = Some(Run {
                    counts,
                    start_ms: now_ms,
                    length_ms,
                });
            }
        }
        self.motor.poll(now_ms).map_err(TimedAxisError::Motor)
    }

    /// What the bridge was last told to do.
    pub fn output(&self) -> Output {
        self.motor.output()
    }

    /// Gives the motor and the switch back.
    pub fn destroy(self) -> (DcMotor<B>, H) {
        (self.motor, self.home)
    }
}

impl<B: Bridge, H: InputPin> AxisDrive for TimedAxis<B, H> {
    type Error = AxisErr<B, H>;

    /// Queues the move; the next poll starts it once the run under way
    /// ends.
    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error> {
        self.queued = self.queued.saturating_add(counts);
        Ok(())
    }

    /// The queued counts and the part of the run under way still to go at
    /// the last poll (never 0 while a run goes on).
    fn pending(&self) -> i32 {
        let running = self.run.map_or(0, |r| {
            let left = r
                .length_ms
                .saturating_sub(self.last_poll_ms.wrapping_sub(r.start_ms));
            // |counts| < 2³¹ and left ≤ length: the share fits in i32.
            let share = i64::from(r.counts) * i64::from(left) / i64::from(r.length_ms.max(1));
            let share = i32::try_from(share).unwrap_or(r.counts);
            if share == 0 {
                r.counts.signum()
            } else {
                share
            }
        });
        self.queued.saturating_add(running)
    }

    /// Brakes at once; the queue is dropped.
    fn stop(&mut self) -> Result<(), Self::Error> {
        self.queued = 0;
        self.end_run()
    }

    fn at_limit(&mut self) -> Result<bool, Self::Error> {
        self.switch_closed()
    }

    /// No feedback.
    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error> {
        Ok(None)
    }
}
