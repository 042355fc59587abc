//! The set-point scheduler of M. T. Jimoh and A. B. Aliyu (2019),
//! "Development of a Pseudo-Closed Loop Solar Collector Sun Tracking System
//! with Optimized Set-Point Paths for Flat Plate Payload" (its Figure 5
//! flowchart, 14 steps), as an explicit state machine driven by
//! [`Scheduler::tick`].
//!
//! | flowchart step | here |
//! |---|---|
//! | 1 read site, set-points zero | [`Phase::PowerOn`] → [`Action::SetPoints`] of zero |
//! | 2 read date, 3 sunrise/sunset | [`Phase::ReadDate`]: the solar day around `now` and its [`Daylight`] |
//! | 4–6 outside daylight: delay td_os | [`Phase::WaitSunrise`] until sunrise (or the next solar day) |
//! | 7 day table, 8 store | `sun_algos::geometry::day_table::DayTable` (default every 4 min) |
//! | 9 read time, 10 end of day? | [`Phase::Tracking`]; past sunset → [`Action::GoHome`], [`Phase::WaitNextDay`] (td_ed) |
//! | 11–12 match? else 30 s | a table entry whose time lies within `recheck_s` before `now` |
//! | 13 set set-points, 14 wait 2 min | [`Action::SetPoints`], next check after `hold_s` |
//!
//! In the paper's text the steps carry no numbers and fill fifteen
//! paragraphs. The numbers here follow its cross-references (sunrise and
//! sunset "calculated in step 3", the match "in step 11") and count the
//! end-of-day check and its td_ed delay as one step 10; the paper's 30-second
//! retry returns "to step 8 to read the current time", which is step 9 here.
//!
//! The home position at the end of the day is the day's starting position
//! (Li et al. 2022: "the control algorithm resets the panel to the previous
//! day initial position"): the first entry of the day table.
//!
//! **Real-time mode** (`N = 0`, no table; Chowdhury et al.'s (2019) way: their
//! ATmega328P computes the sun's position as it tracks, at an interval the
//! paper does not give): the same flowchart with the table replaced by one sun
//! position per slot, computed when the slot falls due. Step 3's daylight is
//! the sun's centre above the geometric horizon at the slot's time (Jimoh &
//! Aliyu 2019 eq. 9, the table's own criterion); steps 4–6 wait slot by
//! slot, and meanwhile the coming sunrise is found as the first slot with the
//! sun up, testing a plan budget of slots per tick (at most a day ahead of
//! `now`: [`Scheduler::next_sunrise`], where the tracker waits facing it);
//! step 10's end of day is the first slot after daylight (at most one slot
//! after sunset); steps 11–14 match and hold as with a table, and home is the
//! day's first daylight set-point. No event search and no table: no day
//! table in RAM (1.4 KB at 4 minutes), and none of the event search's or
//! table's code in flash.
//!
//! `tick` never blocks: every delay of the flowchart is a time stored in the
//! state and compared with the `now` of later ticks. A clock that jumps
//! backward, or forward by more than `max_tick_gap_s`, re-plans from step 2.
//!
//! Days are *solar* days, from one local mean solar midnight
//! (`00:00 UTC − longitude/15 h`) to the next, so that a day's daylight is
//! never split; in a polar day the whole solar day is daylight. Sunrise and
//! sunset are `sun_algos::geometry::events::find`, for the sun's centre on
//! the geometric horizon (Jimoh & Aliyu eq. 9), and the table is
//! `sun_algos::geometry::day_table::DayTable` (4-byte entries in 0.01°).

use crate::sun::PositionSource;
use sun_algos::geometry::day_table::DayTable;
use sun_algos::geometry::events::{self, DayKind, EventSearch, Events};
use sun_algos::geometry::GeometryError;
use sun_algos::refraction::SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG;
use sun_algos::{Error as SunError, Float, SunPosition, UtcTime};

/// Intervals of the scheduler (Jimoh & Aliyu 2019 defaults).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ScheduleConfig {
    /// Set-point table interval, seconds (flowchart step 7: 4 minutes);
    /// whole minutes dividing a day. Table times are whole multiples of it
    /// from UTC midnight, so an RTC matches them.
    pub table_step_s: u32,
    /// Wait after setting a set-point (flowchart step 14: 2 minutes).
    pub hold_s: u32,
    /// Re-check interval when no entry matches (flowchart step 12: 30 s); an
    /// entry matches while `now` lies within this long after its time.
    pub recheck_s: u32,
    /// A gap between two ticks longer than this counts as a forward clock
    /// jump and re-plans the day.
    pub max_tick_gap_s: u32,
    /// A backward step larger than this re-plans the day.
    pub max_backward_s: u32,
}

impl ScheduleConfig {
    /// The defaults ([`Default`]), as a constant (the configuration's
    /// defaults are built from it when compiling).
    pub const DEFAULT: ScheduleConfig = ScheduleConfig {
        table_step_s: 240,
        hold_s: 120,
        recheck_s: 30,
        max_tick_gap_s: 900,
        max_backward_s: 2,
    };
}

impl Default for ScheduleConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Why the scheduler cannot work.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScheduleError {
    /// An interval is zero, the table step is not whole minutes dividing a
    /// day, or the table capacity is too small for a polar day.
    InvalidConfig,
    /// The sun position could not be computed.
    Position(SunError),
    /// Events or table could not be computed.
    Geometry(GeometryError),
    /// Time arithmetic left the calendar range.
    TimeRange,
}

impl From<GeometryError> for ScheduleError {
    fn from(e: GeometryError) -> Self {
        match e {
            GeometryError::Position(p) => ScheduleError::Position(p),
            other => ScheduleError::Geometry(other),
        }
    }
}

impl From<SunError> for ScheduleError {
    fn from(e: SunError) -> Self {
        ScheduleError::Position(e)
    }
}

/// A set-point: where the panel normal should point (Jimoh & Aliyu 2019: slope
/// β = solar zenith, surface azimuth γ = solar azimuth, eq. 14).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SetPoint<T> {
    /// Slope from horizontal = the sun's zenith angle, degrees.
    pub slope_deg: T,
    /// Azimuth east of north, degrees.
    pub azimuth_deg: T,
}

impl<T: Float> SetPoint<T> {
    /// The set-point that faces a sun position.
    pub fn facing(sun: &SunPosition<T>) -> Self {
        SetPoint {
            slope_deg: sun.zenith_deg,
            azimuth_deg: sun.azimuth_deg,
        }
    }
    /// Elevation of the normal, degrees.
    pub fn elevation_deg(&self) -> T {
        T::from_f64(90.0) - self.slope_deg
    }
}

/// Daylight of one solar day.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Daylight {
    /// The sun rises and sets within the day.
    Normal {
        /// Sunrise (sun centre crossing the horizon upward).
        rise: UtcTime,
        /// Sunset.
        set: UtcTime,
    },
    /// Above the horizon the whole solar day (polar day).
    PolarDay,
    /// Below the horizon the whole solar day (polar night).
    PolarNight,
}

/// One solar day: its window and daylight.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SolarDay {
    /// Local mean solar midnight starting the day.
    pub start: UtcTime,
    /// Daylight.
    pub daylight: Daylight,
}

/// `t` plus `s` seconds; past the calendar, [`ScheduleError::TimeRange`].
/// The one conversion of the calendar's error for the scheduler's steps
/// (out of line on the AVR, where each inlined one moved the instant
/// between two results).
#[cfg_attr(target_arch = "avr", inline(never))]
fn add_s(t: &UtcTime, s: i32) -> Result<UtcTime, ScheduleError> {
    t.add_seconds_i32(s).map_err(|_| ScheduleError::TimeRange)
}

impl SolarDay {
    /// The next solar midnight. Out of line on the AVR (two inlined copies
    /// of the calendar step there).
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn end(&self) -> Result<UtcTime, ScheduleError> {
        add_s(&self.start, 86_400)
    }

    /// Daylight span `[from, to)` (whole day for a polar day).
    pub fn span(&self) -> Result<Option<(UtcTime, UtcTime)>, ScheduleError> {
        Ok(match self.daylight {
            Daylight::Normal { rise, set } => Some((rise, set)),
            Daylight::PolarDay => Some((self.start, self.end()?)),
            Daylight::PolarNight => None,
        })
    }
}

/// Seconds of longitude time: 240 s per degree, truncated towards zero,
/// exactly (no `f64` on an 8-bit board, and no 64-bit shifts: the whole
/// number is converted in two halves of 16 bits, each exact in `f32`); 0
/// for a NaN or infinite longitude, `None` from ±2^31 s on (no site).
fn longitude_offset_s<T: Float>(longitude_deg: T) -> Option<i32> {
    let s = longitude_deg * T::from_f64(240.0);
    if !s.is_finite() {
        return Some(0);
    }
    let whole = s.abs().floor();
    if whole >= T::from_f64(2_147_483_648.0) {
        return None;
    }
    // Scaling by a power of two, its floor, product and difference are
    // exact for a whole number below 2^31: high < 2^15, low < 2^16.
    let high = (whole * T::from_f64(1.0 / 65_536.0)).floor();
    let low = whole - high * T::from_f64(65_536.0);
    let magnitude = ((high.to_f32() as i32) << 16) | low.to_f32() as i32;
    Some(if s < T::ZERO { -magnitude } else { magnitude })
}

/// The local mean solar midnight at or before `now` for `longitude_deg`.
// Out of line on AVR (as `solar_day_of`): inlined into the scheduler's
// plan they cost the Mega image 176 B.
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn solar_day_start<T: Float>(
    now: &UtcTime,
    longitude_deg: T,
) -> Result<UtcTime, ScheduleError> {
    // |off| ≤ 43 200 s for a longitude within ±180°; more is no site.
    let off = longitude_offset_s(longitude_deg).ok_or(ScheduleError::TimeRange)?;
    // The local midnight at or before `now + off`, back in UTC. Days
    // begin at whole seconds, so keeping `now`'s milliseconds changes no
    // day.
    let local = add_s(now, off)?;
    add_s(&local.start_of_day(), -off)
}

/// Sunrise and sunset (sun centre on the geometric horizon, Jimoh & Aliyu
/// (2019) eq. 9) of the solar day starting at `start`
/// (`sun_algos::geometry::events::find`: 10-minute samples, crossings
/// bisected to a second, any position source). The returned events are in
/// that sense too (their `transit_zenith_deg` is 0.833° high).
pub fn find_daylight<T: Float, P: PositionSource<T>>(
    start: UtcTime,
    sun: &mut P,
) -> Result<(SolarDay, Events<T>), ScheduleError> {
    // Jimoh & Aliyu 2019 eq. 9: sunrise is where the zenith angle is 90°
    // (the sun's centre on the geometric horizon; a set-point below it
    // could not be reached by an A axis limited to ±90°). `events::find`
    // looks for the standard 90.833°, so it is handed zenith + 0.833°.
    let shift = T::from_f64(SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG);
    let ev = events::find(start, |t| {
        sun.position(t).map(|p| SunPosition {
            zenith_deg: p.zenith_deg + shift,
            ..p
        })
    })?;
    Ok((solar_day_of(&ev)?, ev))
}

/// The solar day whose events (found with the zenith shifted as
/// [`find_daylight`] does) are `ev`.
#[cfg_attr(target_arch = "avr", inline(never))]
fn solar_day_of<T: Float>(ev: &Events<T>) -> Result<SolarDay, ScheduleError> {
    let span = ev.daylight().map_err(|_| ScheduleError::TimeRange)?;
    let daylight = match (ev.kind, span) {
        (DayKind::PolarDay, _) => Daylight::PolarDay,
        (_, Some((rise, set))) => Daylight::Normal { rise, set },
        (_, None) => Daylight::PolarNight,
    };
    Ok(SolarDay {
        start: ev.window_start,
        daylight,
    })
}

/// One row of the day table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableEntry<T> {
    /// When the set-point applies.
    pub time: UtcTime,
    /// The set-point.
    pub set_point: SetPoint<T>,
}

/// Row `i` of a day table with its set-point in degrees.
pub fn table_entry<T: Float, const N: usize>(
    table: &DayTable<N>,
    i: usize,
) -> Option<TableEntry<T>> {
    table.get(i).map(|(time, e)| {
        let s = e.surface::<T>();
        TableEntry {
            time,
            set_point: SetPoint {
                slope_deg: s.slope_deg,
                azimuth_deg: s.azimuth_deg,
            },
        }
    })
}

/// The entry whose time lies in `(now − window, now]` (flowchart step 11).
pub fn match_at<T: Float, const N: usize>(
    table: &DayTable<N>,
    now: &UtcTime,
    window_s: u32,
) -> Option<(usize, TableEntry<T>)> {
    entry_in_window(table, slot_of(table, now)?, window_s)
}

/// [`match_at`] for the slot `now` is in ([`slot_of`]).
fn entry_in_window<T: Float, const N: usize>(
    table: &DayTable<N>,
    slot: Slot,
    window_s: u32,
) -> Option<(usize, TableEntry<T>)> {
    let i = usize::try_from(slot.index).ok()?;
    let e = table_entry(table, i)?;
    (slot.late_s < window_s.max(1)).then_some((i, e))
}

/// The table slot an instant is in ([`slot_of`]).
#[derive(Debug, Clone, Copy)]
struct Slot {
    /// Its entry's index (possibly past the last entry).
    index: u32,
    /// Whole seconds the instant is past the slot's start (its entry's
    /// time, `index` steps after the first: whole seconds apart, so these
    /// are the seconds the instant is past that entry).
    late_s: u32,
    /// Seconds from the first entry to the next slot's start.
    next_s: u32,
}

/// The table slot `now` is in; `None` before the table or without one.
fn slot_of<const N: usize>(table: &DayTable<N>, now: &UtcTime) -> Option<Slot> {
    // Before the table, or 68 years after it: None.
    let since = u32::try_from(now.seconds_since(&table.first_time())?).ok()?;
    if table.is_empty() {
        return None;
    }
    // No step (an empty table's interval is 0): None.
    let step = u32::from(table.interval_min()) * 60;
    let late_s = since.checked_rem(step)?;
    Some(Slot {
        index: since.checked_div(step)?,
        late_s,
        // The slot's start (since − late_s, a whole number of steps) and
        // one step: from the remainder, not a product of the index (a
        // checked 32-bit product is three library calls on the AVR).
        next_s: (since - late_s).checked_add(step)?,
    })
}

/// The start of the table slot after `slot` (the one `now` is in,
/// [`slot_of`]): the instant the next entry becomes due.
fn slot_start_after<const N: usize>(table: &DayTable<N>, slot: &Slot) -> Option<UtcTime> {
    table
        .first_time()
        .add_seconds_i32(i32::try_from(slot.next_s).ok()?)
        .ok()
}

/// `now` plus `s` seconds of a configured interval (hold, recheck), in
/// 32-bit arithmetic; past the calendar, [`ScheduleError::TimeRange`].
fn seconds_after(now: &UtcTime, s: u32) -> Result<UtcTime, ScheduleError> {
    i32::try_from(s)
        .ok()
        .and_then(|s| now.add_seconds_i32(s).ok())
        .ok_or(ScheduleError::TimeRange)
}

/// The next check of a tracking day: `now` plus `wait_s` seconds
/// ([`seconds_after`]), but never after `next_slot`, the instant the next
/// entry falls due. One copy for the table's tracking and real-time mode's.
/// Inlined on the AVR, whose images all run in real-time mode (its one
/// caller): out of line there, LLVM passed the instants by value, beyond the
/// 18 bytes of r8-r25 (.ci/avr_codegen_check.py).
#[cfg_attr(target_arch = "avr", inline(always))]
fn next_check_at(
    now: &UtcTime,
    wait_s: u32,
    next_slot: Option<&UtcTime>,
) -> Result<UtcTime, ScheduleError> {
    let t = seconds_after(now, wait_s)?;
    Ok(match next_slot {
        Some(slot) if *slot < t => *slot,
        _ => t,
    })
}

/// A read-only view of the scheduler's day table in degrees.
#[derive(Debug, Clone, Copy)]
pub struct TableView<'a, T, const N: usize> {
    table: Option<&'a DayTable<N>>,
    _float: core::marker::PhantomData<T>,
}

impl<T: Float, const N: usize> TableView<'_, T, N> {
    /// Number of entries (0 before the first day and in a polar night).
    pub fn len(&self) -> usize {
        self.table.map_or(0, |t| t.len())
    }
    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Entry `i`.
    pub fn get(&self, i: usize) -> Option<TableEntry<T>> {
        self.table.and_then(|t| table_entry(t, i))
    }
    /// The compact table itself (4-byte entries), once computed.
    pub fn raw(&self) -> Option<&DayTable<N>> {
        self.table
    }
}

/// Where the state machine is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Not started (flowchart step 1 pending).
    PowerOn,
    /// About to read the date and plan the day (flowchart steps 2–3).
    ReadDate,
    /// Outside daylight, waiting td_os until `until` (flowchart step 6).
    WaitSunrise {
        /// End of the delay.
        until: UtcTime,
    },
    /// Following the day table (flowchart steps 9–14).
    Tracking {
        /// Next time the table is searched.
        next_check: UtcTime,
    },
    /// After sunset, waiting td_ed until the next solar day (flowchart step 10).
    WaitNextDay {
        /// End of the delay.
        until: UtcTime,
    },
    /// Planning the day a few positions per tick (flowchart steps 2–8 spread
    /// over ticks: see [`Scheduler::set_plan_budget`]).
    Planning,
    /// Planning failed; retried at `retry_at`.
    Failed {
        /// Next attempt.
        retry_at: UtcTime,
    },
}

/// What the tracker should do after a tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action<T> {
    /// Nothing new.
    Idle,
    /// Drive to this set-point (zero at power-on, flowchart step 1; a table
    /// entry, step 13).
    SetPoints(SetPoint<T>),
    /// End of day: return to the day's starting position (Li et al. 2022).
    GoHome(SetPoint<T>),
    /// The day was planned: outside daylight, nothing moves until sunrise.
    Sleep {
        /// When the scheduler wakes.
        until: UtcTime,
    },
    /// Planning failed (sun position, time range); retried later.
    Error(ScheduleError),
}

/// What a tick reports besides its action.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Output<T> {
    /// The action.
    pub action: Action<T>,
    /// A clock jump was seen and the day re-planned.
    pub clock_jump: bool,
}

/// The scheduler; `N` is the day-table capacity (at least one entry per
/// `table_step_s` of a whole day, for polar days).
#[derive(Debug, Clone)]
pub struct Scheduler<T, P, const N: usize> {
    config: ScheduleConfig,
    source: P,
    phase: Phase,
    day: Option<SolarDay>,
    /// The day table's storage, reused in place every day; valid only
    /// while `has_table` (an 8-bit board cannot hold a second copy).
    table: DayTable<N>,
    has_table: bool,
    _float: core::marker::PhantomData<T>,
    last_now: Option<UtcTime>,
    last_applied: Option<usize>,
    /// Real-time mode: the entry applied last (its slot and set-point).
    last_entry: Option<TableEntry<T>>,
    /// Real-time mode: the solar day being tracked (its start) and its
    /// first daylight slot.
    rt_day: Option<(UtcTime, UtcTime)>,
    /// This solar day's daylight does not fit the table (a day longer
    /// than `N` entries: a polar day on a board with a short table): it is
    /// tracked slot by slot as in real-time mode until the sun sets.
    overflow: bool,
    home: SetPoint<T>,
    /// Positions computed per tick while planning; 0: all in one tick.
    plan_budget: u16,
    /// The plan in progress.
    planner: Option<Planner<T>>,
}

/// Real-time mode's daylight at a slot: the sun's centre above the
/// geometric horizon (Jimoh & Aliyu 2019 eq. 9, the table's own criterion);
/// a NaN zenith is not daylight.
fn sun_up<T: Float>(sun: &SunPosition<T>) -> bool {
    sun.zenith_deg < T::from_f64(90.0)
}

/// A day being planned over several ticks.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Planner<T> {
    /// Finding sunrise and sunset (flowchart steps 2–4).
    Daylight(EventSearch<T>),
    /// Filling the table of the solar day starting then (flowchart steps
    /// 7–8).
    Table(UtcTime),
    /// Real-time mode, waiting for sunrise: searching for the coming
    /// sunrise, the first slot at which the sun is up (`rt_check`'s test,
    /// so tracking begins there), slots tested in order from the first slot
    /// of the wait; this is the next slot to test. (In the planner's place:
    /// real-time mode plans no day, and a table board's layout stays as it
    /// was.)
    RiseSearch(UtcTime),
    /// Real-time mode: the coming sunrise, found.
    Sunrise(UtcTime),
}

impl<T: Float, P: PositionSource<T>, const N: usize> Scheduler<T, P, N> {
    /// True for a scheduler without a table (`N = 0`): real-time mode, see
    /// the module documentation.
    pub const REAL_TIME: bool = N == 0;

    /// True while set-points are computed slot by slot: real-time mode, or
    /// a day too long for the table.
    pub fn real_time(&self) -> bool {
        Self::REAL_TIME || self.overflow
    }

    /// A scheduler at power-on. Errors for zero intervals or a step that is
    /// not whole minutes dividing a day.
    ///
    /// `N` below the polar-day size (`capacity_for_interval` of
    /// `sun_algos::geometry::day_table`, 361 at 4 minutes) is allowed for sites whose
    /// longest day fits (an 8-bit board at low latitude); a day that does not
    /// fit gives [`Action::Error`] with `CapacityExceeded`, never a truncated
    /// table.
    pub fn new(config: ScheduleConfig, source: P) -> Result<Self, ScheduleError> {
        Self::check(&config)?;
        Ok(Self::new_checked(config, source))
    }

    /// Whether [`Scheduler::new`] accepts `config` for this capacity.
    pub fn check(config: &ScheduleConfig) -> Result<(), ScheduleError> {
        let c = config;
        if c.table_step_s == 0
            || c.recheck_s == 0
            || !c.table_step_s.is_multiple_of(60)
            || c.table_step_s > 720 * 60
            || 86_400 % c.table_step_s != 0
        {
            return Err(ScheduleError::InvalidConfig);
        }
        Ok(())
    }

    /// [`Scheduler::new`] for a configuration [`Scheduler::check`] accepted.
    /// Infallible, so that a caller can build it straight into its place
    /// (an 8-bit board cannot hold a second copy of the day table).
    pub(crate) fn new_checked(config: ScheduleConfig, source: P) -> Self {
        Scheduler {
            config,
            source,
            phase: Phase::PowerOn,
            day: None,
            table: DayTable::empty(UtcTime::MIDNIGHT_2000),
            has_table: false,
            _float: core::marker::PhantomData,
            last_now: None,
            last_applied: None,
            last_entry: None,
            rt_day: None,
            overflow: false,
            home: SetPoint::default(),
            plan_budget: 0,
            planner: None,
        }
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }
    /// The day being followed, once planned.
    pub fn day(&self) -> Option<SolarDay> {
        self.day
    }
    /// The stored day table (flowchart step 8); empty before the first day.
    pub fn table(&self) -> TableView<'_, T, N> {
        TableView {
            table: self.has_table.then_some(&self.table),
            _float: core::marker::PhantomData,
        }
    }
    /// Entry `i` of the stored table, in degrees.
    pub fn entry(&self, i: usize) -> Option<TableEntry<T>> {
        self.table().get(i)
    }
    /// The intervals.
    pub fn config(&self) -> &ScheduleConfig {
        &self.config
    }
    /// Takes new intervals (checked by [`Scheduler::check`]) and plans the
    /// day again.
    pub fn set_config(&mut self, config: ScheduleConfig) -> Result<(), ScheduleError> {
        Self::check(&config)?;
        self.config = config;
        self.replan();
        Ok(())
    }
    /// The position source.
    pub fn source_mut(&mut self) -> &mut P {
        &mut self.source
    }
    /// Plans the day again at the next tick (the site changed: a GPS fix
    /// moved it). Before the first tick nothing changes: the power-on
    /// step plans with the new site anyway.
    pub fn replan(&mut self) {
        self.planner = None;
        self.overflow = false;
        // The table was for the site before: none of its entries is the
        // present slot's any more.
        self.has_table = false;
        if self.phase != Phase::PowerOn {
            self.phase = Phase::ReadDate;
        }
    }
    /// Spreads planning over ticks: at most `positions` sun positions per
    /// tick (0, the default: the whole plan in one tick). A plan takes
    /// about 190 positions for sunrise and sunset and one per table entry
    /// (some 180 at 4 minutes); at 45,000 cycles a position (psa-2020 in f32
    /// on a 16 MHz ATmega) it would hold one tick for about a second, during
    /// which the loop serves neither motors nor serial ports. While
    /// planning, nothing is tracked ([`Phase::Planning`]).
    pub fn set_plan_budget(&mut self, positions: u16) {
        self.plan_budget = positions;
    }
    /// Sun positions a tick may compute while planning (0: no limit).
    pub fn plan_budget(&self) -> u16 {
        self.plan_budget
    }
    /// The table entry applied last in this day's tracking, if any.
    pub fn applied(&self) -> Option<TableEntry<T>> {
        match self.phase {
            Phase::Tracking { .. } if self.real_time() => self.last_entry,
            Phase::Tracking { .. } => self.last_applied.and_then(|i| self.entry(i)),
            _ => None,
        }
    }
    /// The entry for the slot `now` is in, when the day has one: from the
    /// table, or in real-time mode the entry applied last if it is that
    /// slot's (ticks were missed: nothing else is known without computing).
    pub fn current(&self, now: &UtcTime) -> Option<TableEntry<T>> {
        let step_s = i32::try_from(self.config.table_step_s).unwrap_or(i32::MAX);
        let in_slot = |e: &TableEntry<T>| {
            now.seconds_since(&e.time)
                .is_some_and(|late| (0..step_s).contains(&late))
        };
        if let Some(e) = self.applied().filter(in_slot) {
            return Some(e);
        }
        if self.real_time() {
            return None;
        }
        // Ticks were missed (or the scheduler's check for this slot is
        // still to come): the table's entry, one scan of it. Usually the
        // entry applied last is the slot's, and a tick costs no scan.
        let table = self.table();
        (0..table.len())
            .filter_map(|i| table.get(i))
            .find(|e| in_slot(e))
    }
    /// The day being tracked, as the time of its first set-point (the
    /// table's first entry; real-time mode: the first daylight slot); it
    /// changes when a new day starts.
    pub fn day_key(&self) -> Option<UtcTime> {
        if self.real_time() {
            self.rt_day.map(|(_, first)| first)
        } else {
            self.table().get(0).map(|e| e.time)
        }
    }
    /// The computed sunrise the scheduler waits for, if any: the table's
    /// (the daylight search's), or in real-time mode the first slot with
    /// the sun up once the search has found it (`None` while it searches,
    /// and in a polar night, as long as no slot within a day of `now` has
    /// the sun up).
    pub fn next_sunrise(&self) -> Option<UtcTime> {
        match self.phase {
            Phase::WaitSunrise { .. } if Self::REAL_TIME => match self.planner {
                Some(Planner::Sunrise(t)) => Some(t),
                _ => None,
            },
            Phase::WaitSunrise { until } if !self.real_time() => Some(until),
            _ => None,
        }
    }
    /// The home set-point (the day's first table entry; zero before).
    pub fn home(&self) -> SetPoint<T> {
        self.home
    }

    /// Advances the state machine to `now`. Never blocks.
    // Out of line on the AVR: inlined into the controller's tick it shared
    // that frame (measured in docs/src/sizes.md).
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn tick(&mut self, now: UtcTime) -> Output<T> {
        let mut clock_jump = false;
        if let Some(last) = self.last_now {
            // Beyond ±68 years (no difference in 32 bits) is a jump too.
            let jumped = now.seconds_since(&last).is_none_or(|dt| {
                let limit = if dt < 0 {
                    self.config.max_backward_s
                } else {
                    self.config.max_tick_gap_s
                };
                dt.unsigned_abs() > limit
            });
            if jumped && self.phase != Phase::PowerOn {
                clock_jump = true;
                self.phase = Phase::ReadDate;
            }
        }
        self.last_now = Some(now);
        let action = self.step(now).unwrap_or_else(|e| {
            let retry_at = now.add_seconds_i32(60).unwrap_or(now);
            self.phase = Phase::Failed { retry_at };
            Action::Error(e)
        });
        Output { action, clock_jump }
    }

    /// One step of the flowchart, for the table and for real-time mode:
    /// power-on and the waits are the same in both (one comparison of the
    /// wait's end for all four phases that wait), then the table's plan
    /// and tracking, or real-time mode's check of the present slot.
    fn step(&mut self, now: UtcTime) -> Result<Action<T>, ScheduleError> {
        let real_time = self.real_time();
        if Self::REAL_TIME && matches!(self.phase, Phase::WaitSunrise { .. }) {
            self.seek_sunrise(&now);
        }
        match self.phase {
            Phase::PowerOn => {
                // Step 1: the site is in the source; set-points zero.
                self.phase = Phase::ReadDate;
                Ok(Action::SetPoints(SetPoint::default()))
            }
            Phase::Tracking { next_check: t }
            | Phase::WaitSunrise { until: t }
            | Phase::WaitNextDay { until: t }
            | Phase::Failed { retry_at: t }
                if now < t =>
            {
                // Sunset still ends the table's day even inside a hold.
                if !real_time
                    && matches!(self.phase, Phase::Tracking { .. })
                    && self.past_daylight(&now)?
                {
                    return self.end_of_day(now);
                }
                Ok(Action::Idle)
            }
            _ if real_time => self.rt_check(now),
            Phase::Tracking { .. } => self.track(now),
            _ => self.plan(now),
        }
    }

    /// Steps 2–8: read the date, find daylight, wait or build the table;
    /// in steps of the plan budget, resumed at the next tick. The plan in
    /// progress is advanced where it is stored (an 8-bit board copies
    /// its event search in and out byte by byte otherwise); an error drops
    /// it.
    fn plan(&mut self, now: UtcTime) -> Result<Action<T>, ScheduleError> {
        let result = self.plan_in_place(now);
        if result.is_err() {
            self.planner = None;
        }
        result
    }

    fn plan_in_place(&mut self, now: UtcTime) -> Result<Action<T>, ScheduleError> {
        let lon = self.source.site().longitude_deg();
        let start = solar_day_start(&now, lon)?;
        // A plan for another solar day (midnight passed while planning) is
        // dropped.
        let current = match &self.planner {
            Some(Planner::Daylight(s)) => s.window_start() == start,
            Some(Planner::Table(day_start)) => *day_start == start,
            _ => false,
        };
        if !current {
            self.planner = Some(Planner::Daylight(EventSearch::new(start)));
        }
        let mut budget = match self.plan_budget {
            0 => u32::MAX,
            b => u32::from(b),
        };
        if let Some(action) = self.plan_daylight(now, &mut budget)? {
            return Ok(action);
        }
        // The table of the day (its planner is `Table`: the search above
        // either returned or set it).
        let src = &mut self.source;
        let mut sun = |t: &UtcTime| src.position(t);
        let done = budget > 0
            && self
                .table
                .fill_facing(&mut sun, usize::try_from(budget).unwrap_or(usize::MAX))?;
        if !done {
            self.phase = Phase::Planning;
            return Ok(Action::Idle);
        }
        self.planner = None;
        self.has_table = true;
        if let Some(first) = self.entry(0) {
            self.home = first.set_point;
        }
        // (Daylight may have ended while the table was filled: tracking
        // begins with that check.)
        self.phase = Phase::Tracking { next_check: now };
        self.track(now)
    }

    /// Steps 2–6 of [`Scheduler::plan_in_place`]: the daylight search of
    /// the solar day the planner's `Daylight` search covers (its window
    /// start is the day's start), taking its positions from `budget`; then
    /// the table begun, or the wait. `Some` is the tick's action when the
    /// plan stops here.
    // Out of line on the AVR: its events and solar day in the planner's
    // frame put that frame's slots out of `ldd`/`std` reach. The day's
    // start is read from the search, not passed: with it, the arguments
    // exceed the 18 bytes of r8-r25, and on the ATmega2560 LLVM reads
    // stack-passed arguments one byte low (.ci/avr_codegen_check.py).
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn plan_daylight(
        &mut self,
        now: UtcTime,
        budget: &mut u32,
    ) -> Result<Option<Action<T>>, ScheduleError> {
        let Some(Planner::Daylight(search)) = &mut self.planner else {
            return Ok(None);
        };
        // Jimoh & Aliyu 2019 eq. 9: sunrise is where the zenith
        // angle is 90° (see find_daylight).
        let shift = T::from_f64(SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG);
        let src = &mut self.source;
        let mut used = 0u32;
        let mut sun = |t: &UtcTime| {
            used = used.saturating_add(1);
            src.position(t).map(|p| SunPosition {
                zenith_deg: p.zenith_deg + shift,
                ..p
            })
        };
        let found = search.step(&mut sun, *budget);
        *budget = budget.saturating_sub(used);
        // The events read where the search returned them (no copy).
        match &found {
            Ok(Some(ev)) => self.plan_found_daylight(now, ev),
            Ok(None) => {
                self.phase = Phase::Planning;
                Ok(Some(Action::Idle))
            }
            Err(e) => Err((*e).into()),
        }
    }

    /// Steps 4–7 of [`Scheduler::plan_in_place`] once the events `ev` of
    /// a solar day are found: the table begun, or the wait.
    // Out of line on the AVR: in `plan_daylight` its solar day and action
    // share a frame with the events, beyond `ldd`/`std` reach. The day's
    // start is the events' window start, not an argument: the arguments
    // (sret, &mut self, `now`, &ev) are 14 bytes, within r8-r25 (see
    // `plan_daylight`).
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn plan_found_daylight(
        &mut self,
        now: UtcTime,
        ev: &Events<T>,
    ) -> Result<Option<Action<T>>, ScheduleError> {
        let start = ev.window_start;
        self.planner = None;
        let day = solar_day_of(ev)?;
        self.day = Some(day);
        self.last_applied = None;
        match day.span()? {
            Some((from, to)) if now >= from && now < to => {
                // Steps 7–8: the table for the whole daylight
                // (set-points facing the sun: no slope or azimuth
                // limits, the axes' own limits are applied by the
                // attitude step).
                let interval_min = (self.config.table_step_s / 60) as u16;
                self.has_table = false;
                // The day's span is its events' daylight (`solar_day_of`).
                let daylight = Ok(Some((from, to)));
                match self.table.begin_daylight(start, &daylight, interval_min) {
                    Ok(()) => self.planner = Some(Planner::Table(start)),
                    Err(GeometryError::CapacityExceeded { .. }) if N > 0 => {
                        // Longer than the table (a polar day on a board
                        // with a short one): slot by slot until sunset.
                        self.overflow = true;
                        self.phase = Phase::ReadDate;
                        return self.rt_check(now).map(Some);
                    }
                    Err(e) => return Err(e.into()),
                }
            }
            waiting => {
                let until = match waiting {
                    // Steps 5–6: td_os = sunrise − now.
                    Some((from, _)) if now < from => from,
                    // After sunset, or polar night: wait for the next
                    // solar day.
                    _ => day.end()?,
                };
                self.phase = Phase::WaitSunrise { until };
                return Ok(Some(Action::Sleep { until }));
            }
        }
        Ok(None)
    }

    fn past_daylight(&self, now: &UtcTime) -> Result<bool, ScheduleError> {
        // Read in place (a copy of the day is 26 bytes moved on the AVR).
        match &self.day {
            // The end of the daylight span (`SolarDay::span`).
            Some(d) => Ok(match d.daylight {
                Daylight::Normal { set, .. } => *now >= set,
                Daylight::PolarDay => *now >= d.end()?,
                Daylight::PolarNight => true,
            }),
            None => Ok(true),
        }
    }

    /// Step 10 (yes branch): td_ed until the next solar day, go home. When
    /// the sun is still up as the solar day ends (a polar day, or its edge),
    /// td_ed is zero and there is no night to go home for: the next day is
    /// planned at once.
    fn end_of_day(&mut self, now: UtcTime) -> Result<Action<T>, ScheduleError> {
        let (until, up_at_end) = match &self.day {
            Some(d) => {
                let end = d.end()?;
                // The daylight span's end (`SolarDay::span`) at or after
                // the day's end; a polar day's span ends there.
                let up = match d.daylight {
                    Daylight::Normal { set, .. } => set >= end,
                    Daylight::PolarDay => true,
                    Daylight::PolarNight => false,
                };
                (end, up)
            }
            None => return Err(ScheduleError::TimeRange),
        };
        if up_at_end && now >= until {
            return self.plan(now);
        }
        self.phase = Phase::WaitNextDay { until };
        Ok(Action::GoHome(self.home))
    }

    /// Steps 9–14.
    fn track(&mut self, now: UtcTime) -> Result<Action<T>, ScheduleError> {
        if self.past_daylight(&now)? {
            return self.end_of_day(now);
        }
        // The slot `now` is in, found once for the match and the next
        // slot (None without a table).
        let slot = self.has_table.then(|| slot_of(&self.table, &now)).flatten();
        let found = slot.and_then(|s| entry_in_window(&self.table, s, self.config.recheck_s));
        // The next check comes after the hold (or the recheck interval),
        // but never after the next entry falls due: checks every recheck_s
        // against a window of recheck_s would otherwise drift to its edge,
        // and a tick a second late would skip an entry.
        let next_slot = slot.and_then(|s| slot_start_after(&self.table, &s));
        let (wait_s, action) = match found {
            Some((i, e)) if self.last_applied != Some(i) => {
                self.last_applied = Some(i);
                (self.config.hold_s, Action::SetPoints(e.set_point))
            }
            _ => (self.config.recheck_s, Action::Idle),
        };
        let next_check = next_check_at(&now, wait_s, next_slot.as_ref())?;
        self.phase = Phase::Tracking { next_check };
        Ok(action)
    }

    /// Real-time mode's slot, seconds: the step, which divides a day
    /// (`Scheduler::check`; at most 12 h); slots are whole steps from UTC
    /// midnight.
    fn slot_s(&self) -> u32 {
        self.config.table_step_s.clamp(60, 43_200)
    }

    /// Real-time mode, while waiting for sunrise: tests up to the plan
    /// budget of slots (all when it is 0) for the sun up, in order, no
    /// further than a day after `now` (a polar night is searched as the
    /// days pass). A failed position drops the search; the next slot's
    /// check begins it again.
    fn seek_sunrise(&mut self, now: &UtcTime) {
        let Some(Planner::RiseSearch(mut slot)) = self.planner else {
            return;
        };
        let step_s = self.slot_s() as i32;
        let mut budget = self.plan_budget;
        self.planner = loop {
            if now.seconds_since(&slot).is_none_or(|ahead| ahead < -86_400) {
                break Some(Planner::RiseSearch(slot));
            }
            let Ok(sun) = self.source.position(&slot) else {
                break None;
            };
            if sun_up(&sun) {
                break Some(Planner::Sunrise(slot));
            }
            let Ok(next) = add_s(&slot, step_s) else {
                break None;
            };
            slot = next;
            // 0: no limit (`set_plan_budget`).
            budget = budget.wrapping_sub(1);
            if budget == 0 {
                break Some(Planner::RiseSearch(slot));
            }
        };
    }

    /// Real-time mode, steps 2–14 at one instant: the slot `now` is in
    /// (whole multiples of the step from UTC midnight, as the table's),
    /// the sun at the slot's time, and what follows from it.
    fn rt_check(&mut self, now: UtcTime) -> Result<Action<T>, ScheduleError> {
        let step_s = self.slot_s();
        let of_day_s = now.ms_of_day() / 1000;
        // Below 86 400: fits an i32.
        let slot_s = (of_day_s - of_day_s % step_s) as i32;
        let slot = add_s(&now.start_of_day(), slot_s)?;
        let next_slot = add_s(&slot, step_s as i32)?;
        let tracking = matches!(self.phase, Phase::Tracking { .. });
        // The wait (one computation of the next check, for both kinds of
        // check) and the action of a check that keeps tracking.
        let (wait_s, action) = 'check: {
            // This slot's set-point was applied: nothing to compute (step 12).
            if tracking && self.last_entry.as_ref().is_some_and(|e| e.time == slot) {
                break 'check (self.config.recheck_s, Action::Idle);
            }
            let sun = self.source.position(&slot)?;
            if !sun_up(&sun) {
                // Outside daylight (Jimoh & Aliyu eq. 9). After tracking: the day has
                // ended (step 10), go home; else wait for the next slot (steps
                // 4–6), with a Sleep the first time (power-on, clock jump).
                let first = matches!(self.phase, Phase::ReadDate | Phase::Planning);
                // A day too long for the table has ended: the next is planned
                // with the table again.
                self.overflow = false;
                // The search for the coming sunrise begins with the wait
                // (again after a clock jump, a new site or a failed
                // position).
                if Self::REAL_TIME && (first || self.planner.is_none()) {
                    self.planner = Some(Planner::RiseSearch(next_slot));
                }
                let (phase, action) = if tracking {
                    (
                        Phase::WaitNextDay { until: next_slot },
                        Action::GoHome(self.home),
                    )
                } else if first {
                    (
                        Phase::WaitSunrise { until: next_slot },
                        Action::Sleep { until: next_slot },
                    )
                } else {
                    (Phase::WaitSunrise { until: next_slot }, Action::Idle)
                };
                self.phase = phase;
                return Ok(action);
            }
            let set_point = SetPoint::facing(&sun);
            // Daylight: the next night searches its own sunrise.
            if Self::REAL_TIME {
                self.planner = None;
            }
            // A new solar day: its first daylight slot is home (Li et al. 2022).
            let day_start = solar_day_start(&slot, self.source.site().longitude_deg())?;
            if self.rt_day.as_ref().is_none_or(|(d, _)| *d != day_start) {
                self.rt_day = Some((day_start, slot));
                self.home = set_point;
                self.last_entry = None;
            }
            // Steps 11–14: the slot's set-point, then the hold. A check that
            // comes late in the slot (ticks were missed) still takes it, as the
            // table's present entry would be taken (it is the slot's time the
            // set-point faces, at most one step old).
            self.last_entry = Some(TableEntry {
                time: slot,
                set_point,
            });
            (self.config.hold_s, Action::SetPoints(set_point))
        };
        // Never after the next slot falls due.
        self.phase = Phase::Tracking {
            next_check: next_check_at(&now, wait_s, Some(&next_slot))?,
        };
        Ok(action)
    }
}
