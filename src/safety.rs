//! Safety: typed faults with their recovery, wind stow, and the choice of
//! what the tracker does (track, stow, manual, stop).
//!
//! Fault handling follows what commercial tracker controllers do: retry a
//! transient failure a few times, then degrade (track open loop on counted
//! steps, or keep tracking on one axis), and stop safely only when neither
//! keeps the structure safe. Nothing here panics.
//!
//! Every duration here (wind hold and release, retry back-off, how long a
//! fault has been active) is measured on the board's monotonic millisecond
//! clock, never on UTC: a wall clock corrected by hours or days neither
//! delays nor hastens a stow or a retry.

use crate::config::{OvercastConfig, SafetyConfig, StowConfig, SupplyConfig, WindConfig};
use crate::text::FlashStr;
use crate::time::monotonic;
use drivers::counter::count_up;

/// The two axes: C (vertical at home, azimuth-like) and A (tilt).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum AxisId {
    /// C axis, rotation γ.
    C,
    /// A axis, rotation α.
    A,
}

impl AxisId {
    /// Index 0 for C, 1 for A.
    pub fn index(self) -> usize {
        match self {
            AxisId::C => 0,
            AxisId::A => 1,
        }
    }
}

/// A sensor of the tracker.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sensor {
    /// Two-axis inclinometer.
    Inclinometer,
    /// Magnetometer (compass).
    Compass,
    /// Encoder of an axis.
    Encoder(AxisId),
    /// Real-time clock.
    Rtc,
    /// GPS receiver.
    Gps,
}

/// A fault.
#[derive(Debug, Clone, Copy, PartialOrd, Ord)]
pub enum Fault {
    /// No reading from the sensor within the timeout.
    SensorTimeout(Sensor),
    /// The sensor's bus (I2C) returned an error.
    I2cError(Sensor),
    /// The GPS lost its fix.
    GpsLost,
    /// The RTC lost power or holds an impossible time.
    RtcInvalid,
    /// The axis was driven but its encoder showed no motion.
    MotorStalled(AxisId),
    /// Feedback and set-point differ by more than the maximum.
    SetPointDeviation(AxisId),
    /// A limit switch closed where none was expected, or homing could not
    /// find the switch (stuck closed or stuck open).
    LimitSwitchHit(AxisId),
    /// GPS reports a date outside the firmware's 1024-week window (the GPS
    /// week-rollover bug): its time is ignored and never written to the RTC.
    GpsTimeImplausible,
    /// GPS time disagrees with the monotonic clock between epochs (it
    /// jumps, runs backwards or alternates): it is not adopted.
    GpsTimeUnstable,
    /// The GPS position jumps between places: the site in use is kept.
    GpsPositionUnstable,
    /// The time lies outside the sun algorithm's validity range: no
    /// set-point can be computed for it.
    TimeOutOfRange,
    /// The day could not be planned for another reason (events, table
    /// capacity).
    ScheduleFailed,
    /// The axis's motor current stayed above its limit (a DC drive's
    /// current sense): the axis met an obstacle.
    Obstruction(AxisId),
    /// The axis moved while its motor rested (a DC drive's Hall counts):
    /// an external force back-drives it, or a gear is loose.
    UnexpectedMotion(AxisId),
    /// A move of the axis took longer than its distance at the drive's
    /// slowest expected speed, with a margin (a DC drive's move timeout).
    MoveTimeout(AxisId),
    /// The supply voltage input reads what no supply gives (its ADC at a
    /// rail: a divider disconnected or shorted): it causes no stow unless
    /// `stow.on_sensor_fault` asks for one.
    SupplyReading,
    /// The irradiance input reads what no sky gives (its ADC at a rail):
    /// the overcast mode is not entered on it.
    IrradianceReading,
}

/// Faults are equal when they are the same fault (`Fault::number` is
/// one to one): one comparison of two numbers, not a derived one of the
/// variant and then its sensor or axis.
impl PartialEq for Fault {
    fn eq(&self, other: &Self) -> bool {
        self.number() == other.number()
    }
}

impl Eq for Fault {}

/// Hashes the fault's number (equal faults, equal numbers).
impl core::hash::Hash for Fault {
    fn hash<H: core::hash::Hasher>(&self, state: &mut H) {
        self.number().hash(state);
    }
}

impl Fault {
    /// A short name for logs and traces (`motor_stalled_c`, `gps_lost`, …).
    pub fn name(self) -> FlashStr {
        // One table of the names, in the order of `number`.
        crate::flash_strs!(
            "timeout_inclinometer",
            "timeout_compass",
            "timeout_encoder_c",
            "timeout_encoder_a",
            "timeout_rtc",
            "timeout_gps",
            "bus_inclinometer",
            "bus_compass",
            "bus_encoder_c",
            "bus_encoder_a",
            "bus_rtc",
            "bus_gps",
            "gps_lost",
            "rtc_invalid",
            "motor_stalled_c",
            "motor_stalled_a",
            "deviation_c",
            "deviation_a",
            "limit_switch_c",
            "limit_switch_a",
            "gps_time_implausible",
            "gps_time_unstable",
            "gps_position_unstable",
            "time_out_of_range",
            "schedule_failed",
            "obstruction_c",
            "obstruction_a",
            "unexpected_motion_c",
            "unexpected_motion_a",
            "move_timeout_c",
            "move_timeout_a",
            "supply_reading",
            "irradiance_reading",
        )
        .get(self.number())
        .unwrap_or(crate::flash_str!(""))
    }

    /// The fault's place in [`Fault::name`]'s table: the sensor faults by
    /// sensor (inclinometer, compass, encoder C, encoder A, RTC, GPS), the
    /// axis faults C then A, as the names are listed there.
    fn number(self) -> usize {
        use AxisId::{A, C};
        let sensor = |s: Sensor| match s {
            Sensor::Inclinometer => 0,
            Sensor::Compass => 1,
            Sensor::Encoder(C) => 2,
            Sensor::Encoder(A) => 3,
            Sensor::Rtc => 4,
            Sensor::Gps => 5,
        };
        match self {
            Fault::SensorTimeout(s) => sensor(s),
            Fault::I2cError(s) => 6 + sensor(s),
            Fault::GpsLost => 12,
            Fault::RtcInvalid => 13,
            Fault::MotorStalled(a) => 14 + a.index(),
            Fault::SetPointDeviation(a) => 16 + a.index(),
            Fault::LimitSwitchHit(a) => 18 + a.index(),
            Fault::GpsTimeImplausible => 20,
            Fault::GpsTimeUnstable => 21,
            Fault::GpsPositionUnstable => 22,
            Fault::TimeOutOfRange => 23,
            Fault::ScheduleFailed => 24,
            Fault::Obstruction(a) => 25 + a.index(),
            Fault::UnexpectedMotion(a) => 27 + a.index(),
            Fault::MoveTimeout(a) => 29 + a.index(),
            Fault::SupplyReading => 31,
            Fault::IrradianceReading => 32,
        }
    }
}

/// What to do about a fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Recovery {
    /// Try the operation again next cycle.
    Retry,
    /// Stop using feedback: track open loop on counted steps.
    DegradeOpenLoop,
    /// Stop this axis where it is and track with the other.
    DegradeOneAxis(AxisId),
    /// Lost position reference: home the axis against its limit switch.
    Rehome(AxisId),
    /// Carry on with the RTC and the stored site until GPS returns.
    UseRtcAndStoredSite,
    /// Do not track (the time is unknown) until GPS sets the clock.
    WaitForGps,
    /// Do not track: no set-point can be computed for the time in force;
    /// stowed until a tick plans a day again.
    WaitForValidTime,
    /// Stop both axes; only a person clears it.
    StopSafely,
}

impl Fault {
    /// The recovery for the `attempt`-th occurrence (1 = first) while the
    /// fault is active, with at most `max_retries` retries.
    pub fn recovery(self, attempt: u16, max_retries: u8) -> Recovery {
        let retries = u16::from(max_retries);
        match self {
            Fault::SensorTimeout(Sensor::Gps)
            | Fault::I2cError(Sensor::Gps)
            | Fault::GpsLost
            | Fault::GpsTimeImplausible
            | Fault::GpsTimeUnstable
            | Fault::GpsPositionUnstable => Recovery::UseRtcAndStoredSite,
            Fault::TimeOutOfRange | Fault::ScheduleFailed => Recovery::WaitForValidTime,
            // Read again every tick; what it means for the stow is the
            // configuration's (`stow.on_sensor_fault`).
            Fault::SupplyReading | Fault::IrradianceReading => Recovery::Retry,
            Fault::SensorTimeout(Sensor::Rtc)
            | Fault::I2cError(Sensor::Rtc)
            | Fault::RtcInvalid => Recovery::WaitForGps,
            Fault::SensorTimeout(_) | Fault::I2cError(_) => {
                if attempt <= retries {
                    Recovery::Retry
                } else {
                    Recovery::DegradeOpenLoop
                }
            }
            Fault::MotorStalled(ax)
            | Fault::Obstruction(ax)
            | Fault::UnexpectedMotion(ax)
            | Fault::MoveTimeout(ax) => {
                if attempt <= retries {
                    Recovery::Retry
                } else {
                    Recovery::DegradeOneAxis(ax)
                }
            }
            Fault::SetPointDeviation(ax) => {
                if attempt <= retries {
                    Recovery::Rehome(ax)
                } else {
                    Recovery::DegradeOneAxis(ax)
                }
            }
            Fault::LimitSwitchHit(ax) => {
                if attempt <= retries {
                    Recovery::Rehome(ax)
                } else {
                    Recovery::StopSafely
                }
            }
        }
    }
}

/// Capacity of the active-fault list.
pub const MAX_ACTIVE: usize = 8;

/// First retry back-off, milliseconds; each further attempt waits twice as
/// long as the one before ([`retry_backoff_ms`]).
pub const RETRY_BACKOFF_BASE_MS: u32 = 10_000;
/// Longest retry back-off, milliseconds (10 minutes).
pub const RETRY_BACKOFF_MAX_MS: u32 = 600_000;
/// A fault raised again within this long after it cleared is the same
/// fault coming back: its attempts go on counting from where they were
/// (1 hour).
pub const RECURRENCE_WINDOW_MS: u32 = 3_600_000;

/// Back-off after the `attempt`-th attempt (1 = first):
/// [`RETRY_BACKOFF_BASE_MS`] × 2^(attempt − 1), at most
/// [`RETRY_BACKOFF_MAX_MS`].
// Doubled once per attempt after the first until the cap (six doublings
// at most): no 32-bit multiply and no variable shift, each a loop on an
// 8-bit core. Out of line on the AVR: `FaultManager::raise` has two calls.
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn retry_backoff_ms(attempt: u16) -> u32 {
    let mut ms = RETRY_BACKOFF_BASE_MS;
    let mut doublings = attempt.saturating_sub(1);
    while doublings > 0 && ms < RETRY_BACKOFF_MAX_MS {
        ms = ms.saturating_mul(2);
        doublings -= 1;
    }
    ms.min(RETRY_BACKOFF_MAX_MS)
}

/// An active fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ActiveFault {
    /// The fault.
    pub fault: Fault,
    /// Attempts so far (1 = first occurrence); an attempt counts at most
    /// once per back-off interval, so the count stops at `u16::MAX` only
    /// after more than a year of ten-minute back-offs.
    pub attempts: u16,
    /// Monotonic time from which the next attempt counts, milliseconds; a
    /// passed one is kept at the present by [`FaultManager::catch_up`].
    pub next_attempt_ms: u32,
    /// The recovery chosen last.
    pub recovery: Recovery,
}

impl ActiveFault {
    /// True when a retry of the failed operation is due at `now_ms`.
    pub fn retry_due(&self, now_ms: u32) -> bool {
        monotonic::reached(now_ms, self.next_attempt_ms)
    }
}

/// A fault that cleared recently (for recurrence counting).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Cleared {
    fault: Fault,
    attempts: u16,
    at_ms: u32,
}

/// Keeps the active faults and counts raised and recovered ones.
#[derive(Debug, Clone)]
pub struct FaultManager {
    active: [Option<ActiveFault>; MAX_ACTIVE],
    recent: [Option<Cleared>; MAX_ACTIVE],
    config: SafetyConfig,
    /// Faults raised (first occurrences).
    pub raised: u32,
    /// Faults that cleared.
    pub recovered: u32,
    /// Faults that could not be recorded (list full); still acted upon.
    pub dropped: u32,
}

impl FaultManager {
    /// No active faults.
    pub fn new(config: SafetyConfig) -> Self {
        // On the AVR the empty lists as constants: the repeat expressions
        // were built aside on the stack and copied into the controller
        // there, the constants are one `memset` (64 B less on the
        // ATmega2560). The Cortex-M images copied the constants from a
        // 208-byte table in flash (about 200 B more): they keep the
        // repeat expressions.
        #[cfg(target_arch = "avr")]
        let (active, recent) = (const { [None; MAX_ACTIVE] }, const { [None; MAX_ACTIVE] });
        #[cfg(not(target_arch = "avr"))]
        let (active, recent) = ([None; MAX_ACTIVE], [None; MAX_ACTIVE]);
        FaultManager {
            active,
            recent,
            config,
            raised: 0,
            recovered: 0,
            dropped: 0,
        }
    }

    /// Takes new retry rules (an operator changed the configuration); the
    /// active faults keep their attempts and back-off.
    pub fn set_config(&mut self, config: SafetyConfig) {
        self.config = config;
    }

    /// Reports a fault (again) at monotonic time `now_ms`; returns the
    /// recovery to apply.
    ///
    /// While the fault is active, a report counts as a new attempt only
    /// once its back-off ([`retry_backoff_ms`]) has run out, so a fault
    /// seen on every tick escalates after the same time whatever the tick
    /// rate. A fault that comes back within [`RECURRENCE_WINDOW_MS`] of
    /// clearing goes on from its earlier attempts: a fault that keeps
    /// coming back escalates to its final recovery.
    pub fn raise(&mut self, fault: Fault, now_ms: u32) -> Recovery {
        let max_retries = self.config.max_retries;
        if let Some(a) = self.active.iter_mut().flatten().find(|a| a.fault == fault) {
            if a.retry_due(now_ms) {
                a.attempts = a.attempts.saturating_add(1);
                a.next_attempt_ms = now_ms.wrapping_add(retry_backoff_ms(a.attempts));
                a.recovery = fault.recovery(a.attempts, max_retries);
            }
            return a.recovery;
        }
        count_up(&mut self.raised);
        let mut attempts = 1;
        if let Some(slot) = self
            .recent
            .iter_mut()
            .find(|c| c.is_some_and(|c| c.fault == fault))
        {
            if let Some(c) = slot.take() {
                if monotonic::elapsed_ms(now_ms, c.at_ms) < RECURRENCE_WINDOW_MS {
                    attempts = c.attempts.saturating_add(1);
                }
            }
        }
        let recovery = fault.recovery(attempts, max_retries);
        match self.active.iter_mut().find(|s| s.is_none()) {
            Some(slot) => {
                *slot = Some(ActiveFault {
                    fault,
                    attempts,
                    next_attempt_ms: now_ms.wrapping_add(retry_backoff_ms(attempts)),
                    recovery,
                });
            }
            None => count_up(&mut self.dropped),
        }
        recovery
    }

    /// The fault's condition is gone at monotonic time `now_ms`; returns
    /// true when it was active.
    pub fn clear(&mut self, fault: Fault, now_ms: u32) -> bool {
        for slot in self.active.iter_mut() {
            if let Some(a) = slot.filter(|a| a.fault == fault) {
                *slot = None;
                count_up(&mut self.recovered);
                self.remember(a, now_ms);
                return true;
            }
        }
        false
    }

    fn remember(&mut self, a: ActiveFault, now_ms: u32) {
        let entry = Cleared {
            fault: a.fault,
            attempts: a.attempts,
            at_ms: now_ms,
        };
        // The same fault's older entry, else the first free slot, else the
        // oldest (the last of equally old ones): one pass over the list
        // (three searches were 3 loops on the AVR).
        let (mut same, mut free, mut oldest) = (None, None, None::<(usize, u32)>);
        for (i, c) in self.recent.iter().enumerate() {
            match c {
                Some(c) if c.fault == a.fault => {
                    same = same.or(Some(i));
                }
                Some(c) => {
                    let age = monotonic::elapsed_ms(now_ms, c.at_ms);
                    if oldest.is_none_or(|(_, o)| age >= o) {
                        oldest = Some((i, age));
                    }
                }
                None => free = free.or(Some(i)),
            }
        }
        let idx = same.or(free).or(oldest.map(|(i, _)| i));
        if let Some(slot) = idx.and_then(|i| self.recent.get_mut(i)) {
            *slot = Some(entry);
        }
    }

    /// True when `fault` is active.
    pub fn is_active(&self, fault: Fault) -> bool {
        self.get(fault).is_some()
    }

    /// The active record of `fault`.
    pub fn get(&self, fault: Fault) -> Option<&ActiveFault> {
        self.active.iter().flatten().find(|a| a.fault == fault)
    }

    /// The active faults.
    pub fn active(&self) -> impl Iterator<Item = &ActiveFault> {
        self.active.iter().flatten()
    }

    /// Number of active faults.
    pub fn active_count(&self) -> usize {
        self.active().count()
    }

    /// True when any active fault asks to stop.
    pub fn must_stop(&self) -> bool {
        self.active().any(|a| a.recovery == Recovery::StopSafely)
    }

    /// True when tracking must run open loop.
    pub fn open_loop(&self) -> bool {
        self.active()
            .any(|a| a.recovery == Recovery::DegradeOpenLoop)
    }

    /// True when `axis` is stopped by a degradation.
    pub fn axis_disabled(&self, axis: AxisId) -> bool {
        self.active()
            .any(|a| a.recovery == Recovery::DegradeOneAxis(axis))
    }

    /// True when the time is not trusted or no set-point can be computed
    /// for it.
    pub fn time_unknown(&self) -> bool {
        self.active().any(|a| {
            matches!(
                a.recovery,
                Recovery::WaitForGps | Recovery::WaitForValidTime
            )
        })
    }

    /// Keeps the 32-bit monotonic stamps true at `now_ms` (call every tick;
    /// [`crate::time::monotonic`]): a retry that is due stays due however
    /// long no report of its fault comes, and a cleared fault is forgotten
    /// once [`RECURRENCE_WINDOW_MS`] have passed.
    pub fn catch_up(&mut self, now_ms: u32) {
        for a in self.active.iter_mut().flatten() {
            monotonic::catch_up(&mut a.next_attempt_ms, now_ms);
        }
        for slot in self.recent.iter_mut() {
            if slot.is_some_and(|c| monotonic::elapsed_ms(now_ms, c.at_ms) >= RECURRENCE_WINDOW_MS)
            {
                *slot = None;
            }
        }
    }

    /// Clears every fault and forgets their history (an operator's reset
    /// after a safe stop).
    pub fn reset(&mut self) {
        for slot in self.active.iter_mut() {
            if slot.take().is_some() {
                count_up(&mut self.recovered);
            }
        }
        self.recent = [None; MAX_ACTIVE];
    }
}

/// The stow inputs a board reads each tick besides the anemometer: each
/// `None` where the board has no such input (the default), else the
/// level read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StowInputs {
    /// A snow switch or sensor: true while it reports snow.
    pub snow: Option<bool>,
    /// A hail warning input: true while a warning is active.
    pub hail: Option<bool>,
    /// The plant's stow contact: true while its pin reads high (its
    /// active level is `stow.external_active`).
    pub external_high: Option<bool>,
    /// The supply voltage, millivolts, as its ADC channel reads it.
    pub supply_mv: Option<Reading>,
    /// The irradiance on a horizontal pyranometer or reference cell, W/m².
    pub irradiance_w_m2: Option<Reading>,
}

/// An analog input's reading.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reading {
    /// A value in the input's unit.
    Value(u16),
    /// What the input cannot read of a working sensor: its converter at a
    /// rail (0 or full scale), a wire off or shorted.
    Impossible,
}

/// Which weather stows are in force ([`WeatherStow::update`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct WeatherModes {
    /// Hail warning (or its release time still running).
    pub hail: bool,
    /// The plant's stow contact active.
    pub external: bool,
    /// Snow (or its release time still running).
    pub snow: bool,
    /// The supply is low (below `supply.stow_mv`, not yet back above
    /// `supply.resume_mv`).
    pub low_supply: bool,
    /// The supply input reads an impossible value.
    pub supply_fault: bool,
}

/// One latched stow input: on at once, off once the input has been clear
/// for its release time on the monotonic clock.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Latch {
    on: bool,
    clear_since_ms: Option<u32>,
}

impl Latch {
    /// Feeds the input (`None`: not wired, never on); true while latched.
    fn update(&mut self, input: Option<bool>, now_ms: u32, release_s: u32) -> bool {
        if input == Some(true) {
            self.on = true;
            self.clear_since_ms = None;
        } else if self.on {
            let since = self.clear_since_ms.get_or_insert(now_ms);
            if monotonic::age_ms(since, now_ms) >= release_s.saturating_mul(1000) {
                self.on = false;
                self.clear_since_ms = None;
            }
        }
        self.on
    }
}

/// The weather stows from their inputs: snow and hail latched until clear
/// for their release times, the plant's contact while active. Durations on
/// the monotonic clock: a wall-clock step never shortens or lengthens one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct WeatherStow {
    snow: Latch,
    hail: Latch,
    modes: WeatherModes,
}

impl WeatherStow {
    /// Feeds this tick's inputs at monotonic `now_ms`; returns the stows in
    /// force. The supply: low below `supply.stow_mv`, until back at
    /// `supply.resume_mv` or above (hysteresis); never with
    /// `supply.stow_mv` 0 or no input; an impossible reading keeps the
    /// state, or stows when `stow.on_sensor_fault` is 1.
    pub fn update(
        &mut self,
        inputs: &StowInputs,
        now_ms: u32,
        config: &StowConfig,
        supply: &SupplyConfig,
    ) -> WeatherModes {
        let active_high = config.external_active != 0;
        let was_low = self.modes.low_supply;
        let low_supply = match (inputs.supply_mv, supply.stow_mv) {
            (None, _) | (_, 0) => false,
            (Some(Reading::Value(mv)), stow) if mv < stow => true,
            (Some(Reading::Value(mv)), _) if mv >= supply.resume_mv => false,
            (Some(Reading::Value(_)), _) => was_low,
            (Some(Reading::Impossible), _) => was_low || config.on_sensor_fault != 0,
        };
        self.modes = WeatherModes {
            hail: self.hail.update(inputs.hail, now_ms, config.hail_release_s),
            external: inputs.external_high == Some(active_high),
            snow: self.snow.update(inputs.snow, now_ms, config.snow_release_s),
            low_supply,
            // A fault only where the watch is on: an input nobody wired
            // reads anything.
            supply_fault: supply.stow_mv != 0 && inputs.supply_mv == Some(Reading::Impossible),
        };
        self.modes
    }

    /// The stows in force since the last update.
    pub fn modes(&self) -> WeatherModes {
        self.modes
    }
}

/// The clear sky's global horizontal irradiance, W/m², for the sun's
/// zenith angle: B. Haurwitz (1945), "Insolation in relation to cloudiness
/// and cloud density", J. Meteorology 2: `1098 · cos z · exp(−0.059 / cos
/// z)` (the coefficients as pvlib's `clearsky.haurwitz` uses them); 0 with
/// the sun at or below the horizon. The cosine is the board's
/// ([`sun_algos::Float`]: avr-libc on the AVR), the exponential
/// `exp_neg`'s: no library exponential, whose f32 version computes in
/// software `f64` on an 8-bit part.
pub fn clear_sky_ghi_w_m2(zenith_deg: f32) -> f32 {
    let cos_z = sun_algos::Float::cos(zenith_deg.to_radians());
    // Also a zenith that is not a number: no sun.
    if cos_z.is_nan() || cos_z <= 0.0 {
        return 0.0;
    }
    1098.0 * cos_z * exp_neg(0.059 / cos_z)
}

/// `e^(−x)` for `x ≥ 0` in `f32` arithmetic alone: `x` halved until at
/// most 1/4, its Taylor series to the sixth power there (remainder under
/// 2e-7), squared back; within 1e-6 of `e^(−x)` relatively for `x` up to
/// 20 (below that `e^(−x)` is under 2e-9, and 0 is returned from 88 on).
fn exp_neg(x: f32) -> f32 {
    if x.is_nan() || x >= 88.0 {
        return 0.0;
    }
    let mut x = x.max(0.0);
    let mut halvings = 0u8;
    while x > 0.25 {
        x *= 0.5;
        halvings += 1;
    }
    // 1 − x + x²/2 − x³/6 + x⁴/24 − x⁵/120 + x⁶/720, by Horner.
    let mut e = 1.0
        - x * (1.0
            - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0 - x * (1.0 / 120.0 - x / 720.0)))));
    for _ in 0..halvings {
        e *= e;
    }
    e
}

/// Below this a sky is not, with the sun up ([`SUN_UP_W_M2`] of clear
/// sky): the diffuse light under the heaviest overcast is tens of W/m².
const DARKEST_SKY_W_M2: u16 = 5;
/// The clear sky's irradiance above which [`DARKEST_SKY_W_M2`] is judged,
/// and the sky at all (Haurwitz (1945): the sun 13.4° up).
const SUN_UP_W_M2: f32 = 200.0;

/// The overcast mode from measured irradiance: in after the measured
/// irradiance stayed below `overcast.ratio` of the clear sky's
/// ([`clear_sky_ghi_w_m2`]) for `overcast.enter_s`, out after it stayed at
/// or above for `overcast.leave_s`, and never more than
/// `overcast.max_moves_per_hour` changes in an hour (each is a move of the
/// panel). Durations on the monotonic clock.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct OvercastMonitor {
    on: bool,
    /// Since when the sky has read the other way (monotonic ms).
    other_since_ms: Option<u32>,
    /// When the last changes were made (monotonic ms), a ring of
    /// `overcast.max_moves_per_hour`'s largest value: `changes` of them
    /// kept, the next written at `next`.
    changes_ms: [u32; 8],
    changes: u8,
    next: u8,
    /// True while the input reads impossible values.
    fault: bool,
}

impl OvercastMonitor {
    /// Feeds the irradiance read at monotonic `now_ms` with the sun at
    /// `zenith_deg` (none: no set-point, night); returns true while
    /// overcast. Off (`overcast.ratio` 0), without an input or without a
    /// sun, never overcast; an impossible reading keeps the state.
    pub fn update(
        &mut self,
        reading: Option<Reading>,
        zenith_deg: Option<f32>,
        now_ms: u32,
        config: &OvercastConfig,
    ) -> bool {
        self.fault = config.ratio > 0.0 && reading == Some(Reading::Impossible);
        let (Some(Reading::Value(w_m2)), Some(z), true) = (reading, zenith_deg, config.ratio > 0.0)
        else {
            if reading.is_none() || zenith_deg.is_none() || config.ratio <= 0.0 {
                self.on = false;
                self.other_since_ms = None;
            }
            return self.on;
        };
        let clear_w_m2 = clear_sky_ghi_w_m2(z);
        // No sky gives less than the diffuse light of the heaviest cloud
        // with the sun well up: a reading of (nearly) nothing then is a
        // sensor disconnected, not darkness.
        if w_m2 < DARKEST_SKY_W_M2 && clear_w_m2 > SUN_UP_W_M2 {
            self.fault = true;
            return self.on;
        }
        // A low sun's sky is not judged (its few W/m² against a clear
        // sky of a few W/m², the sensor's cosine error, the horizon's
        // obstructions would call it dark many times a day where the sun
        // skims the horizon): the state is kept until the sun is 13.4° up.
        if clear_w_m2 <= SUN_UP_W_M2 {
            self.other_since_ms = None;
            return self.on;
        }
        let dark = f32::from(w_m2) < config.ratio * clear_w_m2;
        if dark == self.on {
            self.other_since_ms = None;
            return self.on;
        }
        let since = self.other_since_ms.get_or_insert(now_ms);
        let need_s = if dark { config.enter_s } else { config.leave_s };
        let kept = self
            .changes_ms
            .get(..usize::from(self.changes))
            .unwrap_or(&[]);
        let recent = kept
            .iter()
            .filter(|t| monotonic::elapsed_ms(now_ms, **t) < 3_600_000)
            .count();
        if monotonic::age_ms(since, now_ms) >= need_s.saturating_mul(1000)
            && recent < usize::from(config.max_moves_per_hour)
        {
            self.on = dark;
            self.other_since_ms = None;
            if let Some(slot) = self.changes_ms.get_mut(usize::from(self.next)) {
                *slot = now_ms;
            }
            self.next = (self.next + 1) % 8;
            self.changes = (self.changes + 1).min(8);
        }
        self.on
    }

    /// True while the irradiance input reads impossible values (its ADC
    /// at a rail, or nothing at all with the sun well up) and the mode is
    /// on.
    pub fn fault(&self) -> bool {
        self.fault
    }

    /// True while overcast (since the last update).
    pub fn is_on(&self) -> bool {
        self.on
    }
}

/// The weather inputs a board wires, as the controller's part chosen by
/// type (the last parameter of [`crate::controller::Controller`] and
/// [`crate::firmware::Firmware`]): [`WeatherWatch`] on a board with any of
/// the snow, hail and stow contacts, the motor supply or a pyranometer
/// ([`StowInputs`]); [`NoWeather`] on one that wires none of them (the
/// Arduino Uno), which takes no RAM, links none of the watches' code and
/// never stows for weather. The anemometer's wind stow is the controller's
/// own ([`WindMonitor`]) either way.
pub trait Weather: Default {
    /// False for [`NoWeather`]: a constant of each image, so that the
    /// controller's weather phase folds away on a board without inputs.
    const WIRED: bool;
    /// Feeds one tick's inputs at monotonic `now_ms`, the sun at
    /// `zenith_deg` (none at night: [`OvercastMonitor::update`]); returns
    /// whether the supply reading and the irradiance reading are
    /// impossible (each a fault).
    fn update(
        &mut self,
        inputs: &StowInputs,
        zenith_deg: Option<f32>,
        now_ms: u32,
        config: &WeatherConfig<'_>,
    ) -> (bool, bool);
    /// The weather stows in force since the last update.
    fn modes(&self) -> WeatherModes;
    /// True while overcast (since the last update).
    fn overcast(&self) -> bool;
}

/// The parts of the configuration the weather watches read.
#[derive(Debug, Clone, Copy)]
pub struct WeatherConfig<'a> {
    /// Snow, hail and the stow contact.
    pub stow: &'a StowConfig,
    /// The motor supply's low-supply stow.
    pub supply: &'a SupplyConfig,
    /// The overcast mode.
    pub overcast: &'a OvercastConfig,
}

/// The weather watches of a board with weather inputs: [`WeatherStow`] and
/// [`OvercastMonitor`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct WeatherWatch {
    stows: WeatherStow,
    overcast: OvercastMonitor,
}

impl Weather for WeatherWatch {
    const WIRED: bool = true;

    fn update(
        &mut self,
        inputs: &StowInputs,
        zenith_deg: Option<f32>,
        now_ms: u32,
        config: &WeatherConfig<'_>,
    ) -> (bool, bool) {
        let modes = self
            .stows
            .update(inputs, now_ms, config.stow, config.supply);
        self.overcast
            .update(inputs.irradiance_w_m2, zenith_deg, now_ms, config.overcast);
        (modes.supply_fault, self.overcast.fault())
    }

    fn modes(&self) -> WeatherModes {
        self.stows.modes()
    }

    fn overcast(&self) -> bool {
        self.overcast.is_on()
    }
}

/// No weather input on the board: never a weather stow, never overcast.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NoWeather;

impl Weather for NoWeather {
    const WIRED: bool = false;

    fn update(
        &mut self,
        _inputs: &StowInputs,
        _zenith_deg: Option<f32>,
        _now_ms: u32,
        _config: &WeatherConfig<'_>,
    ) -> (bool, bool) {
        (false, false)
    }

    fn modes(&self) -> WeatherModes {
        WeatherModes::default()
    }

    fn overcast(&self) -> bool {
        false
    }
}

/// Wind stow from an anemometer's pulse rate: stow after the rate stayed
/// above the threshold for `hold_s`; leave stow after it stayed below for
/// `release_s`.
#[derive(Debug, Clone, Copy)]
pub struct WindMonitor {
    config: WindConfig,
    above_since_ms: Option<u32>,
    calm_since_ms: Option<u32>,
    stowed: bool,
    /// Number of stows so far.
    pub stow_count: u32,
}

impl WindMonitor {
    /// Calm, not stowed.
    pub fn new(config: WindConfig) -> Self {
        WindMonitor {
            config,
            above_since_ms: None,
            calm_since_ms: None,
            stowed: false,
            stow_count: 0,
        }
    }

    /// Takes new thresholds (an operator changed the configuration); the
    /// hold and release timers go on, judged by the new values from the
    /// next reading.
    pub fn set_config(&mut self, config: WindConfig) {
        self.config = config;
    }

    /// Feeds `pulses` counted over the `interval_ms` milliseconds (of the
    /// monotonic clock) that end at monotonic time `now_ms`; returns true
    /// while stowed. A zero interval keeps the state.
    ///
    /// The rate was above the threshold over the whole interval, so the
    /// hold counts from the interval's start: a gale seen over one interval
    /// at least as long as the hold stows at once.
    pub fn update_pulses(&mut self, now_ms: u32, pulses: u32, interval_ms: u32) -> bool {
        if interval_ms == 0 {
            return self.stowed;
        }
        let rate_hz = pulses as f32 * 1000.0 / interval_ms as f32;
        self.update_rate(now_ms, interval_ms, rate_hz)
    }

    /// Feeds a pulse rate in Hz measured over the `interval_ms` ending at
    /// monotonic `now_ms`; returns true while stowed. A rate that is not a
    /// number counts as windy (fail safe).
    pub fn update_rate(&mut self, now_ms: u32, interval_ms: u32, rate_hz: f32) -> bool {
        let windy = rate_hz.is_nan() || rate_hz > self.config.threshold_hz;
        // An interval longer than the clock's longest age counts as that.
        let began = now_ms.wrapping_sub(interval_ms.min(monotonic::MAX_AGE_MS));
        // One path for both states, the windy one timing the hold and the
        // calm one the release, rather than two written-out copies (216 B
        // less on the ATmega2560, where this is inlined into the tick).
        let (since, other, after_s) = if windy {
            (
                &mut self.above_since_ms,
                &mut self.calm_since_ms,
                self.config.hold_s,
            )
        } else {
            (
                &mut self.calm_since_ms,
                &mut self.above_since_ms,
                self.config.release_s,
            )
        };
        *other = None;
        let age_ms = monotonic::age_ms(since.get_or_insert(began), now_ms);
        if self.stowed != windy && age_ms >= after_s.saturating_mul(1000) {
            self.stowed = windy;
            if windy {
                count_up(&mut self.stow_count);
            }
        }
        self.stowed
    }

    /// True while stowed.
    pub fn is_stowed(&self) -> bool {
        self.stowed
    }
}

/// What the tracker is doing, highest priority first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// An operator locked the tracker for work on it (console `service
    /// on`): nothing moves, not for wind nor for homing, except what the
    /// operator jogs; kept across power cuts until `service off`.
    Service,
    /// A fault asked to stop: nothing moves.
    SafeStop,
    /// Stowed for wind.
    WindStow,
    /// Stowed steep for a hail warning (`stow.hail_slope_deg`), until the
    /// warning has been clear for `stow.hail_release_s`.
    HailStow,
    /// Stowed on a plant's stow contact (`stow.external_slope_deg`) while
    /// it is active.
    ExternalStow,
    /// Stowed steep to shed snow (`stow.snow_slope_deg`), until the snow
    /// input has been clear for `stow.snow_release_s`.
    SnowStow,
    /// The supply fell below `supply.stow_mv`: stowed flat while the
    /// motors can still move, then nothing is driven until it is back
    /// above `supply.resume_mv`.
    LowSupplyStow,
    /// Stowed on an operator's command.
    CommandStow,
    /// An operator drives the axes.
    Manual,
    /// The time is unknown (RTC invalid, no GPS): stowed, waiting.
    WaitForTime,
    /// An axis has no position reference yet (at power-on, after a fault,
    /// the nightly re-homing of open-loop axes): it is seeking its home
    /// switch and nothing tracks until it has one.
    Homing,
    /// Outside daylight: stowed or parked at home.
    Night,
    /// Following the sun, but the axes are turning to another branch of
    /// the mount's two solutions (or another turn of the C axis) because
    /// the one followed runs into a limit: a long move during which the
    /// panel does not face the sun. Planned at the sun's lowest (see
    /// the controller's look-ahead); the controller reports it from the
    /// move's start until both axes reach the new pose.
    Unwind,
    /// Daylight under an overcast sky (measured irradiance below
    /// `overcast.ratio` of the clear sky's for `overcast.enter_s`): the
    /// panel lies flat, facing the whole sky, until the sky has been bright
    /// again for `overcast.leave_s`.
    Overcast,
    /// Following the sun.
    Tracking,
}

impl Mode {
    /// The name used in logs and traces (`safe_stop`, `wind_stow`, …).
    pub fn name(self) -> FlashStr {
        // One table of the names, in the order the variants are declared.
        crate::flash_strs!(
            "service",
            "safe_stop",
            "wind_stow",
            "hail_stow",
            "external_stow",
            "snow_stow",
            "low_supply_stow",
            "command_stow",
            "manual",
            "wait_for_time",
            "homing",
            "night",
            "unwind",
            "overcast",
            "tracking",
        )
        .get(self as usize)
        .unwrap_or(crate::flash_str!(""))
    }
}

/// Inputs of [`select_mode`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ModeInputs {
    /// An operator's service lock is on.
    pub service: bool,
    /// A fault requires a safe stop.
    pub must_stop: bool,
    /// The wind monitor is stowed.
    pub wind_stow: bool,
    /// Stowed for hail, for the plant's stow contact, for snow
    /// ([`WeatherStow`]).
    pub weather: WeatherModes,
    /// An operator commanded stow.
    pub command_stow: bool,
    /// An operator took manual control.
    pub manual: bool,
    /// The time is not trusted.
    pub time_unknown: bool,
    /// The scheduler is outside daylight (or has no set-point for the
    /// present minute).
    pub night: bool,
    /// An axis has no position reference.
    pub unhomed: bool,
    /// The sky is overcast ([`OvercastMonitor`]).
    pub overcast: bool,
}

/// The mode for the inputs. The service lock first (a person may be at the
/// tracker: it does not move even for wind), then protection of the
/// structure (fault stop, wind), then the operator, then the clock, then
/// the sun.
pub fn select_mode(i: &ModeInputs) -> Mode {
    if i.service {
        Mode::Service
    } else if i.must_stop {
        Mode::SafeStop
    } else if i.wind_stow {
        Mode::WindStow
    } else if i.weather.hail {
        Mode::HailStow
    } else if i.weather.external {
        Mode::ExternalStow
    } else if i.weather.snow {
        Mode::SnowStow
    } else if i.weather.low_supply {
        Mode::LowSupplyStow
    } else if i.command_stow {
        Mode::CommandStow
    } else if i.manual {
        Mode::Manual
    } else if i.time_unknown {
        Mode::WaitForTime
    } else if i.unhomed {
        Mode::Homing
    } else if i.night {
        Mode::Night
    } else if i.overcast {
        Mode::Overcast
    } else {
        Mode::Tracking
    }
}

/// The operator's lasting commands: what the console's `service on`,
/// `stow` and `jog` (manual) set and `service off`, `resume` and `manual
/// off` end. Saved with the configuration in the same power-cut-safe
/// record (one byte of flags, [`OperatorHold::to_bits`]) and restored at
/// power-on before the first tick, so a tracker an operator stopped stays
/// stopped through a brown-out, a breaker test or a watchdog reset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct OperatorHold {
    /// Stowed on the operator's command ([`Mode::CommandStow`]).
    pub stow: bool,
    /// Manual mode ([`Mode::Manual`]): after a power cut the axes stay
    /// where they are until the operator jogs.
    pub manual: bool,
    /// The service lock ([`Mode::Service`]).
    pub service: bool,
}

impl OperatorHold {
    const STOW: u8 = 1;
    const MANUAL: u8 = 2;
    const SERVICE: u8 = 4;

    /// No hold in force (the default).
    pub const NONE: OperatorHold = OperatorHold {
        stow: false,
        manual: false,
        service: false,
    };

    /// The stored byte: bit 0 stow, bit 1 manual, bit 2 service.
    pub fn to_bits(self) -> u8 {
        let bit = |on: bool, b: u8| if on { b } else { 0 };
        bit(self.stow, Self::STOW)
            | bit(self.manual, Self::MANUAL)
            | bit(self.service, Self::SERVICE)
    }

    /// The hold of a stored byte; `None` when a bit outside the three is
    /// set (not written by this firmware: the record is not used).
    pub fn from_bits(b: u8) -> Option<Self> {
        if b & !(Self::STOW | Self::MANUAL | Self::SERVICE) != 0 {
            return None;
        }
        Some(OperatorHold {
            stow: b & Self::STOW != 0,
            manual: b & Self::MANUAL != 0,
            service: b & Self::SERVICE != 0,
        })
    }
}
