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
//! when the home switch closes on a run toward it. It never blocks. A run
//! whose end is served late (a poll after a long pass) has turned the motor
//! on for the extra time: the next run is that much shorter (or longer),
//! so the lateness does not stay in the axis's position until its next
//! homing.
//!
//! On a supply that varies (a battery), the speeds are those at
//! [`TimedAxisConfig::calibration_supply_mv`], and a board that measures
//! its motor supply ([`TimedAxis::set_supply_mv`]) has each run's time
//! scaled by calibration / measured supply: a DC motor's no-load speed is
//! proportional to its voltage (`ω = V·k_t / (R·b + k_e·k_t)`; under load
//! it falls a further `I·R / k_e`, which the calibration on the installed
//! axis includes).
//!
//! With a current sense (the BTS7960's, [`super::MotorCurrent`]), a current
//! above [`TimedAxisConfig::max_current_ma`] for
//! [`TimedAxisConfig::overcurrent_ms`] during a run is an obstruction, as on
//! a [`super::DcAxis`]: the motor brakes, the fault is latched
//! ([`AxisDrive::take_fault`] gives [`DriveFault::Obstruction`] once) and
//! moves wait. The part of the run not done is kept, computed from the time
//! it ran until the current rose less the motor's start-up lag
//! ([`TimedAxisConfig::lag_ms`], which the cut run's run-on no longer pays
//! back), and runs first when the fault is cleared (the controller's
//! retry), so the controller's count of the axis stays what the motor
//! turns.
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
use sun_algos::time::div_rem_u64;

use super::dc_axis::{MotorCurrent, NoCurrentSense};
use crate::config::AxisConfig;
use crate::motion::{AxisDrive, DriveFault};

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
    /// Current limit during a run, mA (with a current sense).
    pub max_current_ma: u32,
    /// Time above `max_current_ma` that is an obstruction, ms (longer than
    /// the inrush of a start: up to the stall current `V / R` for about a
    /// mechanical time constant, as no duty ramp softens it).
    pub overcurrent_ms: u32,
    /// The motor's mechanical time constant, ms (J·R / (k_t·k_e), or
    /// measured: the time to 63 % of its speed): the start-up lag a run's
    /// run-on pays back, which a run stopped by an obstacle does not; the
    /// part of it kept for the retry adds it.
    pub lag_ms: u32,
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
        if self.max_current_ma == 0 || self.overcurrent_ms > 600_000 {
            return Err(TimedAxisConfigError::Current);
        }
        if self.lag_ms > 10_000 {
            return Err(TimedAxisConfigError::Lag);
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
    /// `max_current_ma` is 0, or `overcurrent_ms` above 600,000.
    Current,
    /// `lag_ms` above 10,000.
    Lag,
    /// The axis's counts per degree are not finite or not positive.
    Scale,
}

/// Errors of a timed axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimedAxisError<PE, NE, HE, CE> {
    /// The bridge refused a write.
    Motor(MotorError<PE, NE>),
    /// The home switch could not be read.
    Switch(HE),
    /// The current sense could not be read.
    Sense(CE),
    /// An obstruction stopped the motor (returned once by `poll`; moves
    /// are refused until [`AxisDrive::clear_fault`]).
    Obstruction,
}

/// A run under way.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Run {
    /// Counts it moves (signed).
    counts: i32,
    /// Its direction (with the carried rounding, a run of a count or two
    /// may go the other way).
    forward: bool,
    /// Its start and length, ms.
    start_ms: u32,
    length_ms: u32,
    /// Its speed, counts per ms.
    counts_per_ms: f32,
}

/// One tracker axis on a DC motor without feedback.
pub struct TimedAxis<B: Bridge, H, C = NoCurrentSense> {
    motor: DcMotor<B>,
    home: H,
    home_active_low: bool,
    sense: Option<C>,
    /// Since when the current is above the limit, ms.
    over_since_ms: Option<u32>,
    /// An obstruction stopped the axis; the counts of its run not done.
    held: Option<i32>,
    /// The obstruction not yet taken by [`AxisDrive::take_fault`].
    unseen: bool,
    config: TimedAxisConfig,
    counts_per_deg: f32,
    /// Counts commanded and not started yet.
    queued: i32,
    run: Option<Run>,
    /// Counts the next run adds: what the rounding of the last run's time
    /// left over (less than a millisecond's worth, either sign), less what
    /// it ran on past its time when its end was served late.
    carry_counts: f32,
    /// The time of the last poll, ms.
    last_poll_ms: u32,
    /// The motor supply measured last, mV (0: none).
    supply_mv: u32,
}

impl<B: Bridge, H, C> core::fmt::Debug for TimedAxis<B, H, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("TimedAxis")
            .field("queued", &self.queued)
            .field("run", &self.run)
            .field("held", &self.held)
            .field("output", &self.motor.output())
            .finish_non_exhaustive()
    }
}

type AxisErr<B, H, C> = TimedAxisError<
    <B as Bridge>::PwmError,
    <B as Bridge>::PinError,
    <H as embedded_hal::digital::ErrorType>::Error,
    <C as MotorCurrent>::Error,
>;

impl<B: Bridge, H: InputPin, C: MotorCurrent> TimedAxis<B, H, C> {
    /// An axis at rest; `axis` gives the counts per degree; `sense` is the
    /// current sense, if fitted.
    pub fn new(
        motor: DcMotor<B>,
        home: H,
        home_active_low: bool,
        sense: Option<C>,
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
            sense,
            over_since_ms: None,
            held: None,
            unseen: false,
            config,
            counts_per_deg: cpd,
            queued: 0,
            run: None,
            carry_counts: 0.0,
            last_poll_ms: 0,
            supply_mv: 0,
        })
    }

    fn switch_closed(&mut self) -> Result<bool, AxisErr<B, H, C>> {
        let high = self.home.is_high().map_err(TimedAxisError::Switch)?;
        Ok(high != self.home_active_low)
    }

    /// The run of `counts` plus the rounding carried from the runs
    /// before, at the speed of its direction: its time in whole ms (at most
    /// [`MAX_RUN_MS`]), the counts that rounding leaves over for the next
    /// run, whether it runs forward, and its speed in counts per ms.
    /// Tracker steps are alike (0.25° is 32.8 ms at 7.6 °/s): each rounded
    /// on its own, their roundings would add up in one direction all day.
    fn plan(&self, counts: i32) -> (u32, f32, bool, f32) {
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
            return (MAX_RUN_MS, 0.0, forward, per_ms);
        }
        // Rounded to the nearest millisecond; non-negative and finite.
        let whole = (ms + 0.5) as u32;
        let done = whole as f32 * per_ms;
        let left = want - if forward { done } else { -done };
        (whole, left, forward, per_ms)
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

    fn end_run(&mut self) -> Result<(), AxisErr<B, H, C>> {
        self.run = None;
        // The next run's current is watched from its own start.
        self.over_since_ms = None;
        self.motor.brake().map_err(TimedAxisError::Motor)
    }

    /// Ends a run whose time is up, brakes on the home switch, starts the
    /// queued move; call every main-loop pass with the monotonic
    /// millisecond counter. Returns what the bridge now does.
    pub fn poll(&mut self, now_ms: u32) -> Result<Output, AxisErr<B, H, C>> {
        self.last_poll_ms = now_ms;
        if let (Some(run), Some(sense)) = (self.run, self.sense.as_mut()) {
            let ma = sense.current_ma().map_err(TimedAxisError::Sense)?;
            if ma <= self.config.max_current_ma {
                self.over_since_ms = None;
            } else if now_ms.wrapping_sub(*self.over_since_ms.get_or_insert(now_ms))
                >= self.config.overcurrent_ms
            {
                // What the run did not do, by its time up to the current's
                // rise (the motor has stood since, held by the obstacle).
                let since = self.over_since_ms.unwrap_or(now_ms);
                let ran_ms = since.wrapping_sub(run.start_ms);
                let left = run_share_after(run, ran_ms.saturating_sub(self.config.lag_ms));
                self.held = Some(self.queued.saturating_add(left));
                self.queued = 0;
                self.carry_counts = 0.0;
                self.unseen = true;
                self.end_run()?;
                return Err(TimedAxisError::Obstruction);
            }
        }
        if let Some(run) = self.run {
            if !run.forward && self.switch_closed()? {
                // At the switch: the rest of the run and of the queue are
                // dropped, as a stepper driver stops at its limit.
                self.queued = 0;
                self.carry_counts = 0.0;
                self.end_run()?;
            } else if let Some(over_ms) =
                now_ms.wrapping_sub(run.start_ms).checked_sub(run.length_ms)
            {
                // Ended `over_ms` late (the poll came after a long pass):
                // the motor ran that much further, which the next run
                // takes off, as it takes a rounding. Without it the
                // overrun stayed until the next homing.
                let overrun = over_ms.min(MAX_RUN_MS) as f32 * run.counts_per_ms;
                self.carry_counts -= if run.forward { overrun } else { -overrun };
                self.end_run()?;
            }
        }
        if self.run.is_none() && self.queued != 0 && self.held.is_none() {
            let counts = core::mem::take(&mut self.queued);
            let (length_ms, carry, forward, counts_per_ms) = self.plan(counts);
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
                    counts_per_ms,
                });
            }
        }
        self.motor.poll(now_ms).map_err(TimedAxisError::Motor)
    }

    /// Milliseconds from `now_ms` to the end of the run under way (0 when
    /// it is due), `None` without one.
    pub fn run_left_ms(&self, now_ms: u32) -> Option<u32> {
        self.run
            .map(|r| r.length_ms.saturating_sub(now_ms.wrapping_sub(r.start_ms)))
    }

    /// What the bridge was last told to do.
    pub fn output(&self) -> Output {
        self.motor.output()
    }

    /// Gives the motor, the switch and the current sense back.
    pub fn destroy(self) -> (DcMotor<B>, H, Option<C>) {
        (self.motor, self.home, self.sense)
    }
}

/// The counts of `run` still to go at `now_ms`, by its time (never 0 while
/// it has time left).
fn run_share(run: Run, now_ms: u32) -> i32 {
    run_share_after(run, now_ms.wrapping_sub(run.start_ms))
}

/// The counts of `run` still to go after it ran `elapsed_ms`.
fn run_share_after(run: Run, elapsed_ms: u32) -> i32 {
    let left = run.length_ms.saturating_sub(elapsed_ms);
    if left == 0 {
        return 0;
    }
    // |counts| ≤ 2³¹ and left ≤ length: the share is at most |counts|.
    // Divided with 32-bit divisions only (`div_rem_u64`: on an AVR,
    // `u64 / u64` links the compiler's 64-bit division routines), the
    // magnitude rounded toward zero as `i64` division rounds.
    let product = u64::from(run.counts.unsigned_abs()) * u64::from(left);
    let share = div_rem_u64(product, run.length_ms.max(1)).map_or(0, |(q, _)| q);
    match i32::try_from(share) {
        Ok(0) => run.counts.signum(),
        Ok(s) if run.counts < 0 => -s,
        Ok(s) => s,
        Err(_) => run.counts,
    }
}

impl<B: Bridge, H: InputPin, C: MotorCurrent> AxisDrive for TimedAxis<B, H, C> {
    type Error = AxisErr<B, H, C>;
    const SELF_WATCHED: bool = true;

    /// Queues the move; the next poll starts it once the run under way
    /// ends. Refused while an obstruction is latched.
    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error> {
        if self.held.is_some() {
            return Err(TimedAxisError::Obstruction);
        }
        self.queued = self.queued.saturating_add(counts);
        Ok(())
    }

    /// The queued counts and the part of the run under way still to go at
    /// the last poll (never 0 while a run goes on); 0 while an obstruction
    /// is latched.
    fn pending(&self) -> i32 {
        let running = self
            .run
            .map_or(0, |r| match run_share(r, self.last_poll_ms) {
                0 => r.counts.signum(),
                s => s,
            });
        self.queued.saturating_add(running)
    }

    /// Brakes at once; the queue is dropped. A run held by an obstruction
    /// is kept for the retry: [`AxisDrive::pending`] does not count it (0
    /// while latched), so the controller, which takes a stop's dropped
    /// counts off its position by `pending`, still counts it as done, and
    /// the axis gets there once the fault clears. (Dropped, the held part
    /// was lost for good: a controller with no target stops its axes at
    /// every tick, and an obstruction met on the way to the day's first
    /// set-point left the axis 40° short until the night's homing.)
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

    /// An obstruction, once.
    fn take_fault(&mut self) -> Option<DriveFault> {
        core::mem::take(&mut self.unseen).then_some(DriveFault::Obstruction)
    }

    fn fault_latched(&self) -> bool {
        self.held.is_some()
    }

    /// Ends a latched obstruction: the part of the run it stopped is
    /// queued again (the retry).
    fn clear_fault(&mut self) {
        if let Some(left) = self.held.take() {
            self.queued = self.queued.saturating_add(left);
            self.unseen = false;
        }
    }
    fn set_supply_mv(&mut self, supply_mv: u32) {
        TimedAxis::set_supply_mv(self, supply_mv);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The share of a run left after `elapsed_ms`, in 32-bit divisions,
    /// is what `i64` arithmetic gives (rounded toward zero, at least one
    /// count while time is left), at the ends of both ranges.
    #[test]
    fn run_share_is_the_i64_quotient() {
        for counts in [
            1,
            -1,
            7,
            -7,
            1_400,
            -56_000,
            i32::MAX,
            i32::MIN + 1,
            i32::MIN,
        ] {
            for length_ms in [1, 3, 1_000, 33, MAX_RUN_MS] {
                for elapsed_ms in [0, 1, length_ms / 3, length_ms - 1, length_ms, u32::MAX] {
                    let run = Run {
                        counts,
                        forward: counts > 0,
                        start_ms: 0,
                        length_ms,
                        counts_per_ms: 1.0,
                    };
                    let left = length_ms.saturating_sub(elapsed_ms);
                    let want = if left == 0 {
                        0
                    } else {
                        let q = i64::from(counts) * i64::from(left) / i64::from(length_ms);
                        match i32::try_from(q) {
                            Ok(0) => counts.signum(),
                            Ok(s) => s,
                            Err(_) => counts,
                        }
                    };
                    assert_eq!(
                        run_share_after(run, elapsed_ms),
                        want,
                        "{counts} counts, {elapsed_ms} of {length_ms} ms"
                    );
                }
            }
        }
    }
}
