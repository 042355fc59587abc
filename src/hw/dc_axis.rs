//! [`AxisDrive`] over a brushed DC gear motor on an H-bridge
//! ([`drivers::dc_motor::DcMotor`]: the Infineon BTS7960 pair of the IBT-2
//! module or the ST L298N) with a Hall encoder on the motor shaft, and an
//! optional current sense (the BTS7960's IS pin,
//! [`drivers::dc_motor::bts7960::CurrentSense`]).
//!
//! Counts are Hall counts (an [`EncoderCount`], usually kept by an interrupt: the
//! quadrature counter of the servo axis serves a two-channel Hall sensor). Like
//! the servo axis it never blocks: [`AxisDrive::move_counts`] moves the
//! target, and the main loop calls [`DcAxis::poll`] every pass (about every
//! millisecond), which runs the position loop:
//!
//! * farther than [`DcAxisConfig::slow_band_counts`] from the target, the
//!   motor is commanded [`DcAxisConfig::max_duty_permille`]; inside the band
//!   the duty falls linearly to [`DcAxisConfig::min_duty_permille`] at the
//!   target. The driver's duty ramp ([`drivers::dc_motor::DutyRamp`]) makes
//!   every change of duty a soft start or a soft stop.
//! * A gear motor runs on after its bridge brakes (the rotor's inertia
//!   against the short-circuit braking torque: a distance proportional to
//!   the speed). The loop brakes as soon as the remaining distance is at
//!   most `speed × lead`, where the lead (ms) starts at
//!   [`DcAxisConfig::brake_lead_ms`] and is re-measured after every stop
//!   (overrun counts / speed at the brake), so the axis comes to rest on the
//!   target instead of passing it and hunting back. The prediction is taken
//!   an eighth long: a stop errs short, and the rest of the way is a slow
//!   re-approach in the same direction, never a reversal.
//! * Once the counts have stood still for [`DcAxisConfig::settle_ms`], a
//!   stop farther than [`DcAxisConfig::deadband_counts`] from the target is
//!   re-approached slowly (at most [`DcAxisConfig::max_reapproaches`]
//!   times); then the axis rests, braked.
//!
//! The motor is watched with the drivers' [`drivers::hall::StallWatch`]:
//! driven with no count for [`DcAxisConfig::stall_ms`] is a
//! [`DcFault::Stall`]; more than [`DcAxisConfig::max_idle_counts`] counts
//! while resting is [`DcFault::UnexpectedMotion`] (a back-driven axis). With
//! a current sense, a current above [`DcAxisConfig::max_current_ma`] for
//! [`DcAxisConfig::overcurrent_ms`] while driven is [`DcFault::Overcurrent`]
//! (an obstruction: a blocked rotor draws its stall current, `V / R`). With
//! [`DcAxisConfig::min_speed_cps`] set, an approach that takes longer than
//! its distance at that speed plus [`DcAxisConfig::move_margin_ms`] is
//! [`DcFault::TooSlow`] (a load, a low supply or a dragging gear slows the
//! motor). A stall, an overcurrent or a slow move brakes the motor, is
//! returned once by `poll` as [`DcAxisError::Fault`] (and once by
//! [`AxisDrive::take_fault`]), and stays latched ([`DcAxis::fault`]; moves
//! are refused) until [`DcAxis::clear_fault`]. Unexpected motion is returned
//! once per rest and not latched; the target becomes the count where it
//! was seen (the axis does not fight the load on its own: correcting is the
//! controller's decision, from [`AxisDrive::encoder_deg`]).
//!
//! The home switch is read by [`AxisDrive::at_limit`] and at every poll
//! while the axis moves toward it (negative counts): driven, the loop
//! brakes when it closes; running on after a brake, the reading only
//! catches the closing edge. Unlike [`super::ServoAxis`], which takes the count of every
//! closed reading, the reference is the count where a reading first finds
//! it closed after an open one (the count at the first reading if it was
//! closed from the start): a DC motor runs on past the switch after the
//! brake, and the closing edge, not the rest after it, is the switch angle.
//! [`AxisDrive::encoder_deg`] is then `home_deg + (count − count_at_switch)
//! / counts_per_deg`.
//!
//! Times are the monotonic `u32` millisecond counter; differences wrap with
//! it (every 49.7 days).

use core::convert::Infallible;

use super::servo_axis::EncoderCount;
use drivers::adc::AdcChannel;
use drivers::dc_motor::bts7960::{CurrentSense, SenseError};
use drivers::dc_motor::{Bridge, DcMotor, Direction, Error as MotorError, Output};
use drivers::hall::{HallConfig, StallWatch, Watch};
use embedded_hal::digital::InputPin;
use sun_algos::time::{div_rem_u64, div_rem_u64_u16};

use crate::config::AxisConfig;
use crate::motion::{AxisDrive, DriveFault};

/// A motor-current reading, mA (magnitude).
pub trait MotorCurrent {
    /// Conversion error.
    type Error;
    /// One reading of the motor current, mA.
    fn current_ma(&mut self) -> Result<u32, Self::Error>;
}

impl<A: AdcChannel> MotorCurrent for CurrentSense<A> {
    type Error = SenseError<A::Error>;
    fn current_ma(&mut self) -> Result<u32, Self::Error> {
        CurrentSense::current_ma(self)
    }
}

/// The sensor type of an axis without current sense (pass `None`); it
/// reads 0 mA.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NoCurrentSense;

impl MotorCurrent for NoCurrentSense {
    type Error = Infallible;
    fn current_ma(&mut self) -> Result<u32, Infallible> {
        Ok(0)
    }
}

/// A motor fault seen by [`DcAxis::poll`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DcFault {
    /// Driven, but no Hall count for `stall_ms` (jammed axis, failed
    /// sensor, open motor lead).
    Stall,
    /// Current above `max_current_ma` for `overcurrent_ms` while driven (an
    /// obstruction).
    Overcurrent,
    /// More than `max_idle_counts` counts while resting (back-driven axis).
    UnexpectedMotion,
    /// An approach took longer than its distance at `min_speed_cps` plus
    /// `move_margin_ms` (a motor slowed by a load, a low supply, a
    /// dragging gear).
    TooSlow,
}

/// Errors of a DC axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DcAxisError<PE, NE, HE, CE> {
    /// The bridge refused a write.
    Motor(MotorError<PE, NE>),
    /// The home switch could not be read.
    Switch(HE),
    /// The current sense could not be read.
    Sense(CE),
    /// A motor fault (returned once by `poll`; stall and overcurrent also
    /// refuse moves until cleared).
    Fault(DcFault),
}

/// Which [`DcAxisConfig`] field is unusable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DcAxisConfigError {
    /// `max_duty_permille` is 0 or above 1000, or `min_duty_permille` above it.
    Duty,
    /// `deadband_counts` is 0 or above 1,000,000, or `slow_band_counts` is
    /// not above it or above 100,000,000.
    Band,
    /// `brake_lead_ms` above [`MAX_LEAD_MS`].
    BrakeLead,
    /// `settle_ms` is 0 or above [`MAX_SETTLE_MS`].
    Settle,
    /// `stall_ms` is 0 or above 600,000.
    Stall,
    /// `drive_threshold_permille` is not below `min_duty_permille`: a slow
    /// approach would never count as driven.
    DriveThreshold,
    /// `max_current_ma` is 0, or `overcurrent_ms` above 600,000.
    Current,
    /// `max_idle_counts` above [`MAX_IDLE_COUNTS`].
    IdleCounts,
    /// `move_margin_ms` above 600,000.
    MoveMargin,
}

/// Longest stopping lead, ms (a motor that runs on longer than two seconds
/// after a brake is not one this loop can place).
pub const MAX_LEAD_MS: u32 = 2_000;

/// A stop lasts at most `settle_ms` + this many stopping leads (the larger
/// of the measured one and `brake_lead_ms`): after eight time constants a
/// braked run-down is at 0.03 % of its speed. Counts still coming then (a
/// load back-driving the braked motor) end the stop without a
/// re-approach, and are the idle watch's to judge.
pub const STOP_LEADS: u32 = 8;

/// Longest `settle_ms`, ms.
pub const MAX_SETTLE_MS: u32 = 10_000;

/// Largest `max_idle_counts`: each count at rest is one pulse fed to the
/// watch, at most this many plus one per rest.
pub const MAX_IDLE_COUNTS: u32 = 10_000;

/// Interval of the speed estimate, ms: counts over at least this long.
pub const SPEED_WINDOW_MS: u32 = 8;

/// Slowest speed at a brake that re-measures the lead, counts/s: below it
/// the overrun is a count or two and says nothing about the lead.
pub const MIN_LEARN_SPEED_CPS: u32 = 200;

/// `n / d` with 32-bit divisions only (`sun_algos::time::div_rem_u64`: on
/// an AVR, `u64 / u64` links the compiler's 64-bit division routines);
/// `u64::MAX` for `d` = 0, which no caller passes.
fn div_u64(n: u64, d: u32) -> u64 {
    div_rem_u64(n, d).map_or(u64::MAX, |(q, _)| q)
}

/// Position loop and watch settings of one DC axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DcAxisConfig {
    /// Duty far from the target, ‰ (1..=1000).
    pub max_duty_permille: u16,
    /// Duty at the target end of the slow band, ‰ (≤ `max_duty_permille`):
    /// enough to turn the loaded gear.
    pub min_duty_permille: u16,
    /// Distance over which the duty falls from max to min, counts.
    pub slow_band_counts: u32,
    /// A stop this close to the target is done, counts (≥ 1).
    pub deadband_counts: u32,
    /// First estimate of the run-on after a brake, ms of the present speed
    /// (re-measured at every stop; ≈ the mechanical time constant of the
    /// motor under short-circuit braking).
    pub brake_lead_ms: u32,
    /// Standstill time that ends a stop, ms.
    pub settle_ms: u32,
    /// Slow re-approaches after a stop outside the deadband.
    pub max_reapproaches: u8,
    /// Driven with no count this long is a stall, ms.
    pub stall_ms: u32,
    /// The motor counts as driven above this duty, ‰ (< `min_duty_permille`).
    pub drive_threshold_permille: u16,
    /// Counts tolerated while resting, beyond which the motion is
    /// unexpected.
    pub max_idle_counts: u32,
    /// Current limit while driven, mA (with a current sense).
    pub max_current_ma: u32,
    /// Time above `max_current_ma` that is an overcurrent, ms: longer than
    /// the inrush of a start (with a slow duty ramp a start draws little
    /// more than the running current; without one, up to the stall current
    /// `V / R` for about a mechanical time constant).
    pub overcurrent_ms: u32,
    /// The slowest the axis may turn at full duty, counts/s (0: no move
    /// timeout): a data-sheet speed under the heaviest expected load, with
    /// room for a low supply.
    pub min_speed_cps: u32,
    /// Time an approach may take beyond its distance at `min_speed_cps`,
    /// ms: the slow band's approach and the stop (the duty falls linearly
    /// to `min_duty_permille` over `slow_band_counts`, so the band takes
    /// about `slow_band / speed × ln(max/min duty) / (1 − min/max)`, 2.2
    /// times its distance at full speed for 1000 ‰ to 150 ‰).
    pub move_margin_ms: u32,
}

impl DcAxisConfig {
    /// Checks every field (see [`DcAxisConfigError`]).
    pub fn validate(&self) -> Result<(), DcAxisConfigError> {
        if self.max_duty_permille == 0
            || self.max_duty_permille > 1_000
            || self.min_duty_permille > self.max_duty_permille
        {
            return Err(DcAxisConfigError::Duty);
        }
        if self.deadband_counts == 0
            || self.deadband_counts > 1_000_000
            || self.slow_band_counts <= self.deadband_counts
            || self.slow_band_counts > 100_000_000
        {
            return Err(DcAxisConfigError::Band);
        }
        if self.brake_lead_ms > MAX_LEAD_MS {
            return Err(DcAxisConfigError::BrakeLead);
        }
        if self.settle_ms == 0 || self.settle_ms > MAX_SETTLE_MS {
            return Err(DcAxisConfigError::Settle);
        }
        if self.stall_ms == 0 || self.stall_ms > 600_000 {
            return Err(DcAxisConfigError::Stall);
        }
        if self.drive_threshold_permille >= self.min_duty_permille {
            return Err(DcAxisConfigError::DriveThreshold);
        }
        if self.max_current_ma == 0 || self.overcurrent_ms > 600_000 {
            return Err(DcAxisConfigError::Current);
        }
        if self.max_idle_counts > MAX_IDLE_COUNTS {
            return Err(DcAxisConfigError::IdleCounts);
        }
        if self.move_margin_ms > 600_000 {
            return Err(DcAxisConfigError::MoveMargin);
        }
        Ok(())
    }
}

/// What the position loop is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DcState {
    /// Resting, braked. `reported`: unexpected motion already returned.
    Idle {
        /// Unexpected motion was returned during this rest.
        reported: bool,
    },
    /// A new target: the next `poll` starts the approach.
    Starting,
    /// Driving toward the target.
    Driving {
        /// +1 forward, −1 backward.
        dir: i8,
    },
    /// Braked, waiting for the counts to stand still.
    Stopping {
        /// A stop outside the deadband may be re-approached.
        may_reapproach: bool,
    },
    /// Stopped by a fault; moves refused until [`DcAxis::clear_fault`].
    Faulted(DcFault),
}

/// One tracker axis on a DC gear motor with a Hall encoder; counts are Hall
/// counts (`AxisConfig::counts_per_motor_rev` = Hall counts per motor
/// revolution, `microsteps` = 1, `gear_ratio` = all stages).
///
/// The position loop and the watches are a private `DcLoop`, generic over
/// the bridge and the current sense only: it reads the count and the
/// switch through a trait object, so that one copy of it serves every
/// feedback and switch type of an image (on the ATmega2560: the DC gear
/// motor on its Hall encoder, and the linear actuator on Hall pulses or
/// on a potentiometer, [`super::LinearAxis`]). This type holds the count
/// and the switch and lends them to the loop.
pub struct DcAxis<B: Bridge, E, H, C> {
    core: DcLoop<B, C>,
    hall: E,
    home: H,
}

/// What [`DcLoop`] reads while it runs, at the moment it needs it: the
/// count (again at a switch's closing edge) and the home switch. A trait
/// object, so that the loop is not compiled once per feedback and switch
/// type.
trait Inputs<HE> {
    /// The Hall count now.
    fn count(&self) -> i32;
    /// The switch input's level now (true: high).
    fn switch_high(&mut self) -> Result<bool, HE>;
}

/// A [`DcAxis`]'s count and switch, lent to its loop for one call.
struct Io<'a, E, H> {
    hall: &'a E,
    home: &'a mut H,
}

impl<E: EncoderCount, H: InputPin> Inputs<H::Error> for Io<'_, E, H> {
    fn count(&self) -> i32 {
        self.hall.count()
    }
    fn switch_high(&mut self) -> Result<bool, H::Error> {
        self.home.is_high()
    }
}

/// The position loop and the watches of a [`DcAxis`] (the module
/// documentation), without its count and switch: each call takes the
/// count read by the axis, and the loop reads the switch (and the count
/// at its closing edge) through [`Inputs`].
struct DcLoop<B: Bridge, C> {
    motor: DcMotor<B>,
    home_active_low: bool,
    sense: Option<C>,
    config: DcAxisConfig,
    /// The Hall watch (reset at every start and rest).
    watch: StallWatch,
    state: DcState,
    target: i32,
    approaches: u8,
    last_count: i32,
    /// Count and time the speed window started at.
    speed_ref: (i32, u32),
    speed_cps: i32,
    lead_ms: u32,
    /// Count and speed at the last brake of an approach.
    brake_at: Option<(i32, i32)>,
    /// Time the counts last changed (while stopping).
    still_since_ms: u32,
    /// Time the stop started (`None`: not known yet, set by the next poll).
    stop_since_ms: Option<u32>,
    over_since_ms: Option<u32>,
    /// Start and allowed length of the approach under way, ms.
    approach: (u32, u32),
    count_at_switch: Option<i32>,
    /// The switch at its last reading.
    switch_was_closed: bool,
    /// Motion toward the closed switch stops ([`AxisDrive::switch_stops`]).
    switch_stops: bool,
    home_deg: f32,
    counts_per_deg: f32,
    /// A fault not yet taken by [`AxisDrive::take_fault`].
    unseen: Option<DcFault>,
    /// The time of the last poll, ms (a fault cleared through the
    /// [`AxisDrive`] trait rests from then).
    last_poll_ms: u32,
}

impl<B: Bridge, E, H, C> core::fmt::Debug for DcAxis<B, E, H, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let l = &self.core;
        f.debug_struct("DcAxis")
            .field("state", &l.state)
            .field("target", &l.target)
            .field("last_count", &l.last_count)
            .field("speed_cps", &l.speed_cps)
            .field("lead_ms", &l.lead_ms)
            .field("output", &l.motor.output())
            .finish_non_exhaustive()
    }
}

type AxisErr<B, H, C> = LoopErr<B, <H as embedded_hal::digital::ErrorType>::Error, C>;

/// The loop's errors, `HE` the switch's.
type LoopErr<B, HE, C> =
    DcAxisError<<B as Bridge>::PwmError, <B as Bridge>::PinError, HE, <C as MotorCurrent>::Error>;

impl<B, E, H, C> DcAxis<B, E, H, C>
where
    B: Bridge,
    E: EncoderCount,
    H: InputPin,
    C: MotorCurrent,
{
    /// An axis resting at its present count. `axis` gives the switch angle
    /// and the counts per degree; `sense` is the current sense, if fitted.
    #[cfg_attr(target_arch = "avr", inline(always))]
    pub fn new(
        motor: DcMotor<B>,
        hall: E,
        home: H,
        home_active_low: bool,
        sense: Option<C>,
        config: DcAxisConfig,
        axis: &AxisConfig,
    ) -> Result<Self, DcAxisConfigError> {
        // Checked first, so that one out-of-line `DcLoop::new` builds the
        // loop with no `Result` around it. On the AVR this function is
        // built into its caller, whose frame holds the loop on its way
        // into the axis: in a frame of its own here it made the linear
        // actuator's start-up, the deepest stack of the Mega's runs,
        // 135 B deeper.
        let watch = watch_for(&config)?;
        let core = DcLoop::new(
            motor,
            hall.count(),
            home_active_low,
            sense,
            config,
            watch,
            axis,
        );
        Ok(DcAxis { core, hall, home })
    }

    /// Runs the position loop and the watch once; call every main-loop pass
    /// with the monotonic millisecond counter. Returns what the bridge now
    /// does. A stall, overcurrent or slow move brakes the motor and is returned here
    /// once (then [`DcAxis::fault`] keeps it); unexpected motion at rest is
    /// returned once per rest.
    pub fn poll(&mut self, now_ms: u32) -> Result<Output, AxisErr<B, H, C>> {
        let count = self.hall.count();
        let mut io = Io {
            hall: &self.hall,
            home: &mut self.home,
        };
        self.core.poll(now_ms, count, &mut io)
    }

    /// The latched fault (stall, overcurrent, slow move), if any.
    pub fn fault(&self) -> Option<DcFault> {
        self.core.fault()
    }

    /// Ends a latched fault: the axis rests where it is, braked.
    pub fn clear_fault(&mut self, now_ms: u32) {
        if self.core.fault().is_some() {
            self.core.clear_fault(self.hall.count(), now_ms);
        }
    }

    /// What the loop is doing.
    pub fn state(&self) -> DcState {
        self.core.state
    }

    /// The Hall count.
    pub fn count(&self) -> i32 {
        self.hall.count()
    }

    /// The count where the home switch was first found closed, if it was.
    pub fn count_at_switch(&self) -> Option<i32> {
        self.core.count_at_switch
    }

    /// The counter.
    pub fn encoder(&self) -> &E {
        &self.hall
    }

    /// The counter (a feedback that needs reading before each poll, as
    /// [`super::LinearAxis`]'s potentiometer does).
    pub fn encoder_mut(&mut self) -> &mut E {
        &mut self.hall
    }

    /// The target count.
    pub fn target(&self) -> i32 {
        self.core.target
    }

    /// The speed estimate, counts/s.
    pub fn speed_cps(&self) -> i32 {
        self.core.speed_cps
    }

    /// The present stopping lead, ms (see the module documentation).
    pub fn lead_ms(&self) -> u32 {
        self.core.lead_ms
    }

    /// What the bridge was last told to do.
    pub fn output(&self) -> Output {
        self.core.motor.output()
    }

    /// The duty output now, ‰ (signed).
    pub fn duty_permille(&self) -> i16 {
        self.core.motor.duty_permille()
    }

    /// Gives the motor, the switch and the current sense back.
    pub fn destroy(self) -> (DcMotor<B>, H, Option<C>) {
        (self.core.motor, self.home, self.core.sense)
    }
}

/// Checks `config` and builds the Hall watch of a loop on it.
fn watch_for(config: &DcAxisConfig) -> Result<StallWatch, DcAxisConfigError> {
    config.validate()?;
    StallWatch::new(HallConfig {
        stall_ms: config.stall_ms,
        drive_threshold_permille: config.drive_threshold_permille,
        max_idle_pulses: config.max_idle_counts,
    })
    .map_err(|_| DcAxisConfigError::Stall)
}

impl<B, C> DcLoop<B, C>
where
    B: Bridge,
    C: MotorCurrent,
{
    /// A loop resting at `count` ([`DcAxis::new`]), `watch` from
    /// [`watch_for`] on `config`. Out of line on the AVR: one copy for
    /// every axis type.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn new(
        motor: DcMotor<B>,
        count: i32,
        home_active_low: bool,
        sense: Option<C>,
        config: DcAxisConfig,
        watch: StallWatch,
        axis: &AxisConfig,
    ) -> Self {
        let cpd = axis.counts_per_deg();
        DcLoop {
            motor,
            home_active_low,
            sense,
            config,
            watch,
            state: DcState::Idle { reported: false },
            target: count,
            approaches: 0,
            last_count: count,
            speed_ref: (count, 0),
            speed_cps: 0,
            lead_ms: config.brake_lead_ms,
            brake_at: None,
            still_since_ms: 0,
            stop_since_ms: None,
            over_since_ms: None,
            approach: (0, u32::MAX),
            count_at_switch: None,
            switch_was_closed: false,
            switch_stops: true,
            home_deg: axis.home_deg,
            unseen: None,
            last_poll_ms: 0,
            counts_per_deg: if cpd.is_finite() && cpd > 0.0 {
                cpd
            } else {
                1.0
            },
        }
    }

    fn switch_closed<HE>(&mut self, io: &mut dyn Inputs<HE>) -> Result<bool, LoopErr<B, HE, C>> {
        let high = io.switch_high().map_err(DcAxisError::Switch)?;
        let closed = high != self.home_active_low;
        if closed && !self.switch_was_closed {
            self.count_at_switch = Some(io.count());
        }
        self.switch_was_closed = closed;
        Ok(closed)
    }

    /// Brakes and waits for standstill; `may_reapproach` lets a stop outside
    /// the deadband be corrected.
    fn brake<HE>(&mut self, now_ms: u32, may_reapproach: bool) -> Result<(), LoopErr<B, HE, C>> {
        self.motor.brake().map_err(DcAxisError::Motor)?;
        self.watch.set_drive(0, now_ms);
        self.still_since_ms = now_ms;
        self.stop_since_ms = Some(now_ms);
        self.state = DcState::Stopping { may_reapproach };
        Ok(())
    }

    /// Brakes, latches `fault` and returns it.
    fn trip<HE>(&mut self, fault: DcFault, count: i32) -> Result<Output, LoopErr<B, HE, C>> {
        self.target = count;
        self.brake_at = None;
        self.state = DcState::Faulted(fault);
        self.unseen = Some(fault);
        self.motor.brake().map_err(DcAxisError::Motor)?;
        Err(DcAxisError::Fault(fault))
    }

    fn rest(&mut self, now_ms: u32) {
        self.watch.reset();
        self.watch.set_drive(0, now_ms);
        self.state = DcState::Idle { reported: false };
    }

    /// Counts/s over the last window of at least [`SPEED_WINDOW_MS`].
    fn update_speed(&mut self, count: i32, now_ms: u32) {
        let (c0, t0) = self.speed_ref;
        let dt = now_ms.wrapping_sub(t0);
        if dt >= SPEED_WINDOW_MS {
            let dc = i64::from(count) - i64::from(c0);
            // |dc| < 2³³, · 1000 < 2⁴³: no overflow; dt ≥ 8.
            let v = i64::try_from(div_u64(dc.unsigned_abs() * 1_000, dt)).unwrap_or(i64::MAX);
            let v = if dc < 0 { -v } else { v };
            self.speed_cps = i32::try_from(v).unwrap_or(if v < 0 { i32::MIN } else { i32::MAX });
            self.speed_ref = (count, now_ms);
        }
    }

    /// Duty for `remaining` counts to go, ‰.
    fn duty_for(&self, remaining: u64) -> u16 {
        let c = &self.config;
        let band = u64::from(c.slow_band_counts);
        if remaining >= band {
            return c.max_duty_permille;
        }
        let span = u64::from(c.max_duty_permille - c.min_duty_permille);
        // span ≤ 1000, remaining < band ≤ 10⁸: the product is under 2⁴⁰.
        let extra = div_u64(span * remaining, c.slow_band_counts);
        c.min_duty_permille
            .saturating_add(u16::try_from(extra).unwrap_or(u16::MAX))
            .min(c.max_duty_permille)
    }

    /// Counts the motor still runs after a brake at the present speed.
    fn predicted_overrun(&self) -> u64 {
        // |speed| ≤ 2³¹, lead ≤ 2000, · 9: under 2⁴⁷.
        let n = u64::from(self.speed_cps.unsigned_abs()) * u64::from(self.lead_ms) * 9;
        div_rem_u64_u16(n, 8_000).map_or(u64::MAX, |(q, _)| q)
    }

    /// [`DcAxis::poll`] with the count it read first.
    fn poll<HE>(
        &mut self,
        now_ms: u32,
        count: i32,
        io: &mut dyn Inputs<HE>,
    ) -> Result<Output, LoopErr<B, HE, C>> {
        let moved = count.saturating_sub(self.last_count);
        self.last_count = count;
        self.last_poll_ms = now_ms;
        self.update_speed(count, now_ms);
        // One call of `drive` (for a new approach and one under way), so
        // that it is built into this function, in its stack frame.
        let driving = match self.state {
            DcState::Faulted(_) | DcState::Idle { reported: true } => false,
            DcState::Idle { reported: false } => {
                // Each count is a pulse; beyond the limit more make no
                // difference (so at most MAX_IDLE_COUNTS + 1 in all).
                let n = moved
                    .unsigned_abs()
                    .min(self.config.max_idle_counts.saturating_add(1));
                for _ in 0..n {
                    self.watch.pulse(now_ms);
                }
                if self.watch.check(now_ms) == Watch::UnexpectedMotion {
                    self.state = DcState::Idle { reported: true };
                    self.unseen = Some(DcFault::UnexpectedMotion);
                    self.target = count;
                    self.motor.brake().map_err(DcAxisError::Motor)?;
                    return Err(DcAxisError::Fault(DcFault::UnexpectedMotion));
                }
                false
            }
            DcState::Starting => {
                // A stop cut short by a new target measured no run-on.
                self.brake_at = None;
                self.watch.reset();
                self.speed_ref = (count, now_ms);
                self.over_since_ms = None;
                let e = i64::from(self.target) - i64::from(count);
                if e.unsigned_abs() <= u64::from(self.config.deadband_counts) {
                    self.rest(now_ms);
                    false
                } else {
                    self.state = DcState::Driving {
                        dir: if e > 0 { 1 } else { -1 },
                    };
                    self.approach = (now_ms, self.approach_ms(e.unsigned_abs()));
                    true
                }
            }
            DcState::Driving { .. } => true,
            DcState::Stopping { may_reapproach } => {
                if moved != 0 {
                    self.still_since_ms = now_ms;
                    if moved < 0 {
                        // Running on toward the switch: its closing edge
                        // is the reference.
                        self.switch_closed(io)?;
                    }
                }
                let since = *self.stop_since_ms.get_or_insert(now_ms);
                if now_ms.wrapping_sub(self.still_since_ms) >= self.config.settle_ms {
                    self.settled(count, now_ms, may_reapproach);
                } else if now_ms.wrapping_sub(since) >= self.max_stop_ms() {
                    // A load keeps turning the braked motor: rest, and let
                    // the idle watch judge the motion.
                    self.brake_at = None;
                    self.rest(now_ms);
                }
                false
            }
        };
        if driving {
            return self.drive(count, now_ms, moved, io);
        }
        self.motor.poll(now_ms).map_err(DcAxisError::Motor)
    }

    /// The time allowed for an approach of `distance` counts, ms: its
    /// travel at `min_speed_cps` and the margin.
    fn approach_ms(&self, distance: u64) -> u32 {
        self.travel_ms(distance)
            .saturating_add(self.config.move_margin_ms)
    }

    /// `distance` counts at `min_speed_cps`, ms (`u32::MAX` without a
    /// speed: no time-out).
    fn travel_ms(&self, distance: u64) -> u32 {
        let speed = self.config.min_speed_cps;
        if speed == 0 {
            return u32::MAX;
        }
        // distance < 2³³, · 1000 < 2⁴³.
        u32::try_from(div_u64(distance * 1_000, speed)).unwrap_or(u32::MAX)
    }

    /// Longest stop, ms ([`STOP_LEADS`]); at most 10,000 + 8 · 2,000.
    fn max_stop_ms(&self) -> u32 {
        let lead = self.lead_ms.max(self.config.brake_lead_ms);
        self.config
            .settle_ms
            .saturating_add(STOP_LEADS.saturating_mul(lead))
    }

    /// The stop is over: learn the lead, then rest or re-approach.
    fn settled(&mut self, count: i32, now_ms: u32, may_reapproach: bool) {
        if let Some((c0, v0)) = self.brake_at.take() {
            let speed = v0.unsigned_abs();
            if speed >= MIN_LEARN_SPEED_CPS {
                let overrun = (i64::from(count) - i64::from(c0)).unsigned_abs();
                // overrun < 2³³: · 1000 under 2⁴³.
                let lead = div_u64(overrun * 1_000, speed).min(u64::from(MAX_LEAD_MS));
                let lead = u32::try_from(lead).unwrap_or(MAX_LEAD_MS);
                // Half the old estimate, half the new one (both ≤ 2000).
                self.lead_ms = (self.lead_ms + lead).div_ceil(2);
            }
        }
        let e = i64::from(self.target) - i64::from(count);
        let outside = e.unsigned_abs() > u64::from(self.config.deadband_counts);
        if outside && may_reapproach && self.approaches < self.config.max_reapproaches {
            self.approaches = self.approaches.saturating_add(1);
            self.state = DcState::Starting;
        } else {
            self.rest(now_ms);
        }
    }

    fn drive<HE>(
        &mut self,
        count: i32,
        now_ms: u32,
        moved: i32,
        io: &mut dyn Inputs<HE>,
    ) -> Result<Output, LoopErr<B, HE, C>> {
        let DcState::Driving { dir } = self.state else {
            return self.motor.poll(now_ms).map_err(DcAxisError::Motor);
        };
        if moved != 0 {
            self.watch.pulse(now_ms);
        }
        if self.watch.check(now_ms) == Watch::Stall {
            return self.trip(DcFault::Stall, count);
        }
        let (since, allowed) = self.approach;
        if now_ms.wrapping_sub(since) > allowed {
            return self.trip(DcFault::TooSlow, count);
        }
        if let Some(sense) = self.sense.as_mut() {
            let ma = sense.current_ma().map_err(DcAxisError::Sense)?;
            if ma > self.config.max_current_ma {
                let since = *self.over_since_ms.get_or_insert(now_ms);
                if now_ms.wrapping_sub(since) >= self.config.overcurrent_ms {
                    return self.trip(DcFault::Overcurrent, count);
                }
            } else {
                self.over_since_ms = None;
            }
        }
        if dir < 0 && self.switch_closed(io)? && self.switch_stops {
            // At the switch: stop here, no re-approach past it.
            self.target = count;
            self.brake_at = None;
            self.brake(now_ms, false)?;
            return self.motor.poll(now_ms).map_err(DcAxisError::Motor);
        }
        let e = i64::from(self.target) - i64::from(count);
        // Remaining distance in the driven direction (negative: passed).
        let ahead = if dir > 0 { e } else { -e };
        let toward = i64::from(self.speed_cps) * i64::from(dir) > 0;
        let overrun = if toward { self.predicted_overrun() } else { 0 };
        let db = u64::from(self.config.deadband_counts);
        if ahead <= 0 || ahead.unsigned_abs() <= db || ahead.unsigned_abs() <= overrun {
            self.brake_at = Some((count, self.speed_cps));
            self.brake(now_ms, true)?;
            return self.motor.poll(now_ms).map_err(DcAxisError::Motor);
        }
        let duty = self.duty_for(ahead.unsigned_abs());
        let direction = if dir > 0 {
            Direction::Forward
        } else {
            Direction::Backward
        };
        self.motor
            .set_permille(direction, duty)
            .map_err(DcAxisError::Motor)?;
        let out = self.motor.poll(now_ms).map_err(DcAxisError::Motor)?;
        self.watch.set_drive(self.motor.duty_permille(), now_ms);
        Ok(out)
    }

    /// [`DcAxis::fault`].
    fn fault(&self) -> Option<DcFault> {
        match self.state {
            DcState::Faulted(f) => Some(f),
            _ => None,
        }
    }

    /// [`DcAxis::clear_fault`] of a latched fault, at `count`.
    fn clear_fault(&mut self, count: i32, now_ms: u32) {
        self.target = count;
        self.unseen = None;
        self.rest(now_ms);
    }

    /// [`AxisDrive::move_counts`].
    fn move_counts<HE>(&mut self, counts: i32) -> Result<(), LoopErr<B, HE, C>> {
        if let DcState::Faulted(f) = self.state {
            return Err(DcAxisError::Fault(f));
        }
        if counts != 0 {
            self.target = self.target.saturating_add(counts);
            self.approaches = 0;
            if matches!(self.state, DcState::Driving { .. }) {
                // A target moved during the approach (homing tops its
                // target up while it drives) gets the time of the counts
                // added: the approach is timed from its first distance.
                let (since, allowed) = self.approach;
                let more = self.travel_ms(u64::from(counts.unsigned_abs()));
                self.approach = (since, allowed.saturating_add(more));
            } else {
                self.state = DcState::Starting;
            }
        }
        Ok(())
    }

    /// [`AxisDrive::pending`] at `count`.
    fn pending(&self, count: i32) -> i32 {
        let e = self.target.saturating_sub(count);
        match self.state {
            DcState::Starting | DcState::Driving { .. } => {
                if e != 0 {
                    e
                } else {
                    1
                }
            }
            DcState::Stopping {
                may_reapproach: true,
            } if e.unsigned_abs() > self.config.deadband_counts
                && self.approaches < self.config.max_reapproaches =>
            {
                e
            }
            _ => 0,
        }
    }

    /// [`AxisDrive::stop`] at `count`.
    fn stop<HE>(&mut self, count: i32) -> Result<(), LoopErr<B, HE, C>> {
        self.target = count;
        self.brake_at = None;
        self.stop_since_ms = None;
        self.motor.brake().map_err(DcAxisError::Motor)?;
        if !matches!(self.state, DcState::Faulted(_)) {
            self.state = DcState::Stopping {
                may_reapproach: false,
            };
        }
        Ok(())
    }

    /// [`AxisDrive::take_fault`].
    fn take_fault(&mut self) -> Option<DriveFault> {
        self.unseen.take().map(|f| match f {
            DcFault::Stall => DriveFault::Stall,
            DcFault::Overcurrent => DriveFault::Obstruction,
            DcFault::UnexpectedMotion => DriveFault::UnexpectedMotion,
            DcFault::TooSlow => DriveFault::TooSlow,
        })
    }
}

impl<B, E, H, C> AxisDrive for DcAxis<B, E, H, C>
where
    B: Bridge,
    E: EncoderCount,
    H: InputPin,
    C: MotorCurrent,
{
    type Error = AxisErr<B, H, C>;
    const SELF_WATCHED: bool = true;

    /// Moves the target; refused while a stall, overcurrent or slow move is latched.
    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error> {
        self.core.move_counts(counts)
    }

    /// Counts to go while a move runs (never 0 while driving); 0 at rest,
    /// faulted, or in the last stop of a move.
    fn pending(&self) -> i32 {
        self.core.pending(self.hall.count())
    }

    /// Brakes at once; the target becomes the present count.
    fn stop(&mut self) -> Result<(), Self::Error> {
        self.core.stop(self.hall.count())
    }

    fn at_limit(&mut self) -> Result<bool, Self::Error> {
        let mut io = Io {
            hall: &self.hall,
            home: &mut self.home,
        };
        self.core.switch_closed(&mut io)
    }

    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error> {
        let l = &self.core;
        Ok(l.count_at_switch.map(|c0| {
            // Wraps with the Hall count: an axis that turns without end is
            // kept within a turn of its switch (`rebase_counts`).
            let d = self.hall.count().wrapping_sub(c0);
            l.home_deg + d as f32 / l.counts_per_deg
        }))
    }

    fn rebase_counts(&mut self, counts: i32) {
        let l = &mut self.core;
        l.count_at_switch = l.count_at_switch.map(|c0| c0.wrapping_add(counts));
    }

    fn switch_stops(&mut self, on: bool) {
        self.core.switch_stops = on;
    }

    /// A stall, overcurrent or unexpected motion seen by `poll` since the
    /// last call.
    fn take_fault(&mut self) -> Option<DriveFault> {
        self.core.take_fault()
    }

    fn fault_latched(&self) -> bool {
        self.fault().is_some()
    }

    /// [`DcAxis::clear_fault`] at the time of the last poll.
    fn clear_fault(&mut self) {
        DcAxis::clear_fault(self, self.core.last_poll_ms);
    }
}
