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
//! On a supply that varies (a battery), the speeds are those at
//! [`TimedAxisConfig::calibration_supply_mv`], and a board that measures
//! its motor supply ([`TimedAxis::set_supply_mv`]) has each run's time
//! scaled by calibration / measured supply: a DC motor's no-load speed is
//! proportional to its voltage (`ω = V·k_t / (R·b + k_e·k_t)`; under load
//! it falls a further `I·R / k_e`, which the calibration on the installed
//! axis includes).
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

/// Highest supply a calibration or a measurement may name, mV.
pub const MAX_SUPPLY_MV: u32 = 100_000;

/// A measured supply below this share of the calibration's is taken as
/// this share: a failing supply must not stretch a run without bound
/// (the move timeout of a DC axis with feedback has no equal here).
pub const MIN_SUPPLY_SHARE: f32 = 0.5;

/// Settings of a timed axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimedAxisConfig {
    /// Axis speed driven forward (positive counts), °/s.
    pub forward_deg_s: f32,
    /// Axis speed driven backward (toward home), °/s.
    pub backward_deg_s: f32,
    /// Duty of every run, ‰ (1..=1000): the duty the speeds were measured at.
    pub duty_permille: u16,
    /// Motor supply the speeds were measured at, mV (0: runs are not
    /// scaled by the measured supply).
    pub calibration_supply_mv: u32,
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
        if self.calibration_supply_mv > MAX_SUPPLY_MV {
            return Err(TimedAxisConfigError::Supply);
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
    /// The calibration supply is above [`MAX_SUPPLY_MV`].
    Supply,
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
    /// Its direction (with the carried rounding, a run of a count or two
    /// may go the other way).
    forward: bool,
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
    /// Counts the rounding of the last run's time left over (less than a
    /// millisecond's worth, either sign).
    carry_counts: f32,
    /// The time of the last poll, ms.
    last_poll_ms: u32,
    /// The motor supply measured last, mV (0: none).
    supply_mv: u32,
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
            carry_counts: 0.0,
            last_poll_ms: 0,
            supply_mv: 0,
        })
    }

    fn switch_closed(&mut self) -> Result<bool, AxisErr<B, H>> {
        let high = self.home.is_high().map_err(TimedAxisError::Switch)?;
        Ok(high != self.home_active_low)
    }

    /// The run of `counts` plus the rounding carried from the runs
    /// before, at the speed of its direction: its time in whole ms (at most
    /// [`MAX_RUN_MS`]), the counts that rounding leaves over for the next
    /// run, and whether it runs forward. Tracker steps are alike (0.25° is 32.8 ms at 7.6 °/s): each
    /// rounded on its own, their roundings would add up in one direction
    /// all day.
    fn plan(&self, counts: i32) -> (u32, f32, bool) {
        let want = counts as f32 + self.carry_counts;
        let speed = if want > 0.0 {
            self.config.forward_deg_s
        } else {
            self.config.backward_deg_s
        };
        // Counts per ms; every factor is checked finite and positive at
        // construction, the supply factor is within 0.5..=2 or 1.
        let per_ms = self.counts_per_deg * speed / self.supply_factor() / 1_000.0;
        let ms = want.abs() / per_ms;
        let forward = want > 0.0;
        // Also for a NaN, which the checks at construction rule out.
        if ms.is_nan() || ms >= MAX_RUN_MS as f32 {
            return (MAX_RUN_MS, 0.0, forward);
        }
        // Rounded to the nearest millisecond; non-negative and finite.
        let whole = (ms + 0.5) as u32;
        let done = whole as f32 * per_ms;
        (whole, want - if forward { done } else { -done }, forward)
    }

    /// Calibration supply / measured supply (1 without either), at most
    /// 1 / [`MIN_SUPPLY_SHARE`].
    fn supply_factor(&self) -> f32 {
        let cal = self.config.calibration_supply_mv;
        if cal == 0 || self.supply_mv == 0 {
            return 1.0;
        }
        let share = self.supply_mv as f32 / cal as f32;
        if share < MIN_SUPPLY_SHARE {
            1.0 / MIN_SUPPLY_SHARE
        } else {
            1.0 / share
        }
    }

    /// The motor supply measured now, mV (0, or above [`MAX_SUPPLY_MV`]:
    /// unknown, runs not scaled); takes effect from the next run.
    pub fn set_supply_mv(&mut self, supply_mv: u32) {
        self.supply_mv = if supply_mv > MAX_SUPPLY_MV {
            0
        } else {
            supply_mv
        };
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
            if !run.forward && self.switch_closed()? {
                // At the switch: the rest of the run and of the queue are
                // dropped, as a stepper driver stops at its limit.
                self.queued = 0;
                self.carry_counts = 0.0;
                self.end_run()?;
            } else if now_ms.wrapping_sub(run.start_ms) >= run.length_ms {
                self.end_run()?;
            }
        }
        if self.run.is_none() && self.queued != 0 {
            let counts = core::mem::take(&mut self.queued);
            let (length_ms, carry, forward) = self.plan(counts);
            let at_home = !forward && self.switch_closed()?;
            self.carry_counts = if at_home { 0.0 } else { carry };
            if length_ms > 0 && !at_home {
                let direction = if forward {
                    Direction::Forward
                } else {
                    Direction::Backward
                };
                self.motor
                    .set_permille(direction, self.config.duty_permille)
                    .map_err(TimedAxisError::Motor)?;
                self.run = Some(Run {
                    counts,
                    forward,
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
        self.carry_counts = 0.0;
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
