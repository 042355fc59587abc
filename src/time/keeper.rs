//! The time keeper: which time is in force, GPS or the RTC.
//!
//! **Time**: a GPS fix first, then the RTC. GPS time disciplines the RTC: it
//! is written to the RTC when the RTC lost power, holds no valid date, or
//! has drifted more than [`TimeConfig::max_drift_s`] from GPS. An RTC that
//! lost power (DS3231 oscillator-stop flag, DS1302 clock halt) or reads a
//! date outside the firmware's 1024-week window ([`DateWindow`]) is *not*
//! trusted: until GPS sets it the time is unknown and the controller waits
//! ([`crate::safety::Mode::WaitForTime`]) instead of tracking with a wrong
//! time. GPS time is trusted only
//! - from a valid fix with a plausible position (RMC status `A` or GGA
//!   quality ≥ 1; a receiver without a fix may still be counting from a
//!   wrong almanac);
//! - while it is fresh: received at most [`TimeConfig::max_gps_age_ms`] ago
//!   on the monotonic clock, and advanced by that age;
//! - inside the firmware's [`DateWindow`]: a date outside it is the GPS
//!   week-rollover bug, reported as implausible, never written to the RTC,
//!   and the tracker carries on with the RTC;
//! - when it is consistent: two consecutive epochs whose times differ by
//!   the monotonic time between their arrivals, within
//!   [`TimeConfig::agree_ms`] (or one epoch that agrees with a running RTC
//!   within [`TimeConfig::max_drift_s`] and does not contradict the epoch
//!   before it). A receiver whose time jumps, runs
//!   backwards or alternates is never adopted; after
//!   [`UNSTABLE_DISAGREEMENTS`] disagreements it is reported unstable (fault
//!   `gps_time_unstable`) until it has agreed with itself for
//!   [`TimeConfig::fault_hold_ms`];
//! - and, when a running RTC reads more than [`TimeConfig::rtc_margin_s`]
//!   away from it, only after it has been consistent for
//!   [`TimeConfig::confirm_ms`]: a receiver with a wrong time cannot step a
//!   good clock by itself. The step, when it comes, is one write to the RTC
//!   and one `clock jump` line in the log.
//!
//! The implausible and unstable reports are held for
//! [`TimeConfig::fault_hold_ms`] after the last epoch that caused them, so
//! that a receiver that keeps sending them raises its fault once, not on
//! every epoch; [`TimeKeeper::rejected_epochs`] counts the epochs refused.
//!
//! Nothing here blocks or panics; every device error ends in a status flag.

use drivers::counter::count_up;
use drivers::gps::{FixQuality, GpsFix};
use drivers::rtc::Clock as RtcDriver;
use sun_algos::UtcTime;

use super::window::DateWindow;
use super::{datetime_from_utc, utc_from_datetime};
use crate::controller::TickInputs;

/// Where the time came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeOrigin {
    /// The GPS fix of this update.
    Gps,
    /// The RTC (running, not lost power).
    Rtc,
}

/// Settings of the time keeper.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimeConfig {
    /// The RTC is set from GPS when they differ by more than this, seconds.
    pub max_drift_s: u32,
    /// GPS time older than this (monotonic milliseconds since its sentence
    /// arrived) is not trusted.
    pub max_gps_age_ms: u32,
    /// The window a plausible date falls in.
    pub window: DateWindow,
    /// Two consecutive GPS epochs agree when their times differ from the
    /// monotonic time between them by at most this, ms.
    pub agree_ms: u32,
    /// GPS time farther than this from a running RTC is a step, seconds.
    pub rtc_margin_s: u32,
    /// A step is taken only after GPS has been consistent this long, ms.
    pub confirm_ms: u32,
    /// An implausible or unstable GPS time stays reported this long after
    /// the last epoch that showed it, ms.
    pub fault_hold_ms: u32,
}

/// Disagreeing GPS epochs (jumps) before the receiver's time counts as
/// unstable: a single wrong epoch is two (to it and back from it).
pub const UNSTABLE_DISAGREEMENTS: u8 = 3;

impl Default for TimeConfig {
    /// 2 s drift: a DS3231 (±2 ppm) drifts that much in about 12 days; at
    /// the equator the sun moves 0.0083° in 2 s, far inside any mechanism's
    /// resolution. 1.5 s age: receivers send one epoch a second (NMEA 0183
    /// at 1 Hz), so a fix older than that is a missed epoch. The window is
    /// the firmware's own. Agreement within 1 s: an epoch's time is
    /// stamped when its last sentence ends, which moves by the length of a
    /// sentence at 9600 baud (under 0.1 s) and the loop's pass. A step
    /// beyond 60 s (a DS3231 drifts that much in a year, a DS1302 on a
    /// ±20 ppm crystal in five weeks) waits ten minutes of consistent
    /// epochs. Faults held for a minute.
    fn default() -> Self {
        TimeConfig {
            max_drift_s: 2,
            max_gps_age_ms: 1_500,
            window: DateWindow::firmware(),
            agree_ms: 1_000,
            rtc_margin_s: 60,
            confirm_ms: 600_000,
            fault_hold_ms: 60_000,
        }
    }
}

/// What a GPS fix says about the time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GpsTime {
    /// Trustworthy: the fix's UTC advanced by its age.
    Trusted(UtcTime),
    /// No valid fix with a plausible position, or no date-time.
    NoFix,
    /// The time was received too long ago.
    Stale,
    /// A valid fix whose date is outside the window (week rollover).
    Implausible(UtcTime),
}

/// What `fix` says about the time at monotonic `now_ms` (see the module
/// documentation for the rules). Out of line on the AVR: inlined into
/// [`TimeKeeper::update`], its values joined the update's (52 B more on
/// the ATmega2560).
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn gps_time(fix: &GpsFix, now_ms: u32, config: &TimeConfig) -> GpsTime {
    // A position a site can be made of (the exact coordinates' range,
    // checked without floats).
    let position = matches!(
        (fix.latitude_deg, fix.longitude_deg),
        (Some(lat), Some(lon)) if lat.within_deg(90) && lon.within_deg(180)
    );
    if fix.quality == FixQuality::Invalid || !position {
        return GpsTime::NoFix;
    }
    let (Some(dt), Some(age_ms)) = (fix.utc, fix.utc_age_ms(now_ms)) else {
        return GpsTime::NoFix;
    };
    if age_ms > config.max_gps_age_ms {
        return GpsTime::Stale;
    }
    let Ok(t) = utc_from_datetime(&dt) else {
        return GpsTime::NoFix;
    };
    if !config.window.contains(&t) {
        return GpsTime::Implausible(t);
    }
    match t.add_millis_u32(age_ms) {
        Ok(now) if config.window.contains(&now) => GpsTime::Trusted(now),
        Ok(now) => GpsTime::Implausible(now),
        Err(_) => GpsTime::NoFix,
    }
}

/// The outcome of one [`TimeKeeper::update`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimeStatus {
    /// The trusted time, when there is one.
    pub now: Option<UtcTime>,
    /// Where `now` came from.
    pub origin: Option<TimeOrigin>,
    /// The RTC's reading even when it is not trusted (for timers that need
    /// a monotonic-ish count, e.g. the wind hold), if it could be read.
    pub rtc_raw: Option<UtcTime>,
    /// True while GPS has a valid, fresh fix with a plausible date.
    pub gps_fix: bool,
    /// GPS reports a valid fix whose date is outside the window (the
    /// week-rollover bug): ignored, not written to the RTC. Held for
    /// [`TimeConfig::fault_hold_ms`] after the last such epoch.
    pub gps_time_implausible: bool,
    /// GPS time disagrees with the monotonic clock between epochs (it
    /// jumps, runs backwards or alternates): not adopted. Held for
    /// [`TimeConfig::fault_hold_ms`] after the last disagreement.
    pub gps_time_unstable: bool,
    /// The RTC reads a date outside the window (not trusted).
    pub rtc_implausible: bool,
    /// The RTC reported lost power (before any setting in this update).
    pub rtc_lost_power: bool,
    /// The RTC could not be read or written (bus error, invalid registers).
    pub rtc_error: bool,
    /// The RTC was set from GPS in this update.
    pub rtc_set: bool,
}

impl TimeStatus {
    /// No time, no GPS, no RTC flag.
    pub const NONE: TimeStatus = TimeStatus {
        now: None,
        origin: None,
        rtc_raw: None,
        gps_fix: false,
        gps_time_implausible: false,
        gps_time_unstable: false,
        rtc_implausible: false,
        rtc_lost_power: false,
        rtc_error: false,
        rtc_set: false,
    };

    /// True when the time can be used for tracking.
    pub fn time_valid(&self) -> bool {
        self.now.is_some()
    }
}

/// Keeps UTC from GPS and an RTC driver.
#[derive(Debug)]
pub struct TimeKeeper<C> {
    rtc: C,
    config: TimeConfig,
    last_valid: Option<UtcTime>,
    rtc_sets: u32,
    gps: GpsConsistency,
}

/// What the keeper remembers of the GPS epochs (monotonic milliseconds).
#[derive(Debug, Clone, Copy, Default)]
struct GpsConsistency {
    /// The last plausible epoch's UTC, advanced to the call that took it,
    /// and that call's instant.
    last: Option<(UtcTime, u32)>,
    /// Arrival of the last epoch taken (plausible or not): an epoch is
    /// looked at once, however many calls see it.
    last_arrival_ms: Option<u32>,
    /// Arrival of the first epoch of the current run of agreeing ones.
    agree_since_ms: Option<u32>,
    /// Disagreements since GPS last agreed for the hold time.
    disagreements: u8,
    /// The last epoch disagreed with the one before it.
    last_disagreed: bool,
    /// When the last disagreement and the last implausible epoch came.
    last_disagreement_ms: Option<u32>,
    last_implausible_ms: Option<u32>,
    /// Epochs not adopted (implausible, inconsistent, or an unconfirmed
    /// step).
    rejected: u32,
}

impl GpsConsistency {
    /// Forgets what is too old to count, every update: a stamp on the
    /// 32-bit monotonic clock must not live to its wrap (49.7 days), where
    /// it would look recent again.
    fn expire(&mut self, now_ms: u32, hold_ms: u32) {
        if !within(self.last_disagreement_ms, now_ms, hold_ms) {
            self.last_disagreement_ms = None;
            self.disagreements = 0;
        }
        if !within(self.last_implausible_ms, now_ms, hold_ms) {
            self.last_implausible_ms = None;
        }
        // An hour without a plausible epoch: the next starts a new run.
        if self
            .last
            .is_some_and(|(_, t)| !within(Some(t), now_ms, GPS_RUN_GAP_MS))
        {
            self.last = None;
            self.agree_since_ms = None;
            self.last_disagreed = false;
        }
    }
}

/// Longest gap between two plausible epochs of one run of agreeing ones.
const GPS_RUN_GAP_MS: u32 = 3_600_000;

/// `later − earlier` in milliseconds when they are at most 20 days apart
/// (32-bit arithmetic), else `None`.
fn ms_between(later: &UtcTime, earlier: &UtcTime) -> Option<i32> {
    let days = later
        .days_since_2000()
        .checked_sub(earlier.days_since_2000())?;
    if !(-20..=20).contains(&days) {
        return None;
    }
    // |days| ≤ 20: 20 × 86 400 000 + 86 399 999 < 2³¹.
    Some(days * 86_400_000 + later.ms_of_day() as i32 - earlier.ms_of_day() as i32)
}

/// True when `t` (monotonic ms) is set and at most `hold_ms` before `now_ms`.
// Out of line on the AVR: `GpsState::expire` has three calls.
#[cfg_attr(target_arch = "avr", inline(never))]
fn within(t: Option<u32>, now_ms: u32, hold_ms: u32) -> bool {
    t.is_some_and(|t| super::monotonic::elapsed_ms(now_ms, t) <= hold_ms)
}

impl<C: RtcDriver> TimeKeeper<C> {
    /// A keeper over the RTC driver; no bus traffic.
    pub fn new(rtc: C, config: TimeConfig) -> Self {
        TimeKeeper {
            rtc,
            config,
            last_valid: None,
            rtc_sets: 0,
            gps: GpsConsistency::default(),
        }
    }

    /// GPS epochs refused so far: implausible dates, times that disagree
    /// with the monotonic clock, and steps not yet confirmed.
    pub fn rejected_epochs(&self) -> u32 {
        self.gps.rejected
    }

    /// The RTC driver.
    pub fn rtc_mut(&mut self) -> &mut C {
        &mut self.rtc
    }

    /// Gives the RTC driver back.
    pub fn destroy(self) -> C {
        self.rtc
    }

    /// Times the RTC was set from GPS.
    pub fn rtc_sets(&self) -> u32 {
        self.rtc_sets
    }

    /// The last trusted time.
    pub fn last_valid(&self) -> Option<UtcTime> {
        self.last_valid
    }

    /// Reads the RTC (lost-power flag, then the time unless it lost power),
    /// disciplines it from `gps` when that gives trusted time
    /// ([`gps_time`]) at monotonic `now_ms`, and decides the time. Bus
    /// traffic per call: one status read and one time read; plus one time
    /// write (and the flag clear) when the RTC is set.
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn update(&mut self, gps: &GpsFix, now_ms: u32) -> TimeStatus {
        let gps_said = gps_time(gps, now_ms, &self.config);
        // A new epoch: its arrival differs from the last one seen.
        let new_epoch = gps
            .utc_received_ms
            .filter(|&r| self.gps.last_arrival_ms != Some(r));
        let mut gps_time = None;
        match gps_said {
            GpsTime::Trusted(t) => {
                if let Some(r) = new_epoch {
                    self.gps.last_arrival_ms = Some(r);
                    self.gps_epoch(t, now_ms);
                }
                gps_time = Some(t);
            }
            GpsTime::Implausible(_) => {
                if let Some(r) = new_epoch {
                    self.gps.last_arrival_ms = Some(r);
                    self.gps.last_implausible_ms = Some(now_ms);
                    count_up(&mut self.gps.rejected);
                }
            }
            GpsTime::NoFix | GpsTime::Stale => {}
        }
        self.gps.expire(now_ms, self.config.fault_hold_ms);
        // Field by field, not `..TimeStatus::NONE`: the constant's two
        // `None` times were copied whole from RAM.
        let mut status = TimeStatus {
            now: None,
            origin: None,
            rtc_raw: None,
            gps_fix: gps_time.is_some(),
            // `expire` dropped a stamp older than the hold.
            gps_time_implausible: self.gps.last_implausible_ms.is_some(),
            gps_time_unstable: self.gps.disagreements >= UNSTABLE_DISAGREEMENTS,
            rtc_implausible: false,
            rtc_lost_power: false,
            rtc_error: false,
            rtc_set: false,
        };
        let (rtc_time, bus_ok) = self.read_rtc_apart(&mut status);
        if let Some(g) = gps_time {
            // Beyond ±68 years apart (or no running RTC): drifted.
            let from_rtc_s = rtc_time.and_then(|r| g.seconds_since(&r));
            let within_drift =
                from_rtc_s.is_some_and(|d| d.unsigned_abs() <= self.config.max_drift_s);
            // GPS time is adopted when it agrees with a running RTC (one
            // epoch, unless it contradicts the epoch before it) or with
            // itself (two epochs); a step beyond the margin from a running
            // RTC waits until GPS has agreed with itself for the confirm
            // time.
            let adopt = if within_drift {
                !self.gps.last_disagreed
            } else {
                match (from_rtc_s, self.gps.agree_since_ms) {
                    (_, None) => false,
                    (Some(d), Some(t)) if d.unsigned_abs() > self.config.rtc_margin_s => {
                        super::monotonic::elapsed_ms(now_ms, t) >= self.config.confirm_ms
                    }
                    // No running RTC (or one beyond ±68 years: lost), or
                    // within the margin: two agreeing epochs.
                    (_, Some(_)) => rtc_time.is_none() || from_rtc_s.is_some(),
                }
            };
            if adopt {
                // A bus that failed to answer the status read is not
                // written.
                if !within_drift && bus_ok {
                    match datetime_from_utc(&g).map(|d| self.rtc.set_datetime(&d)) {
                        Ok(Ok(())) => {
                            status.rtc_set = true;
                            count_up(&mut self.rtc_sets);
                        }
                        _ => status.rtc_error = true,
                    }
                }
                status.now = Some(g);
                status.origin = Some(TimeOrigin::Gps);
            } else if new_epoch.is_some() {
                count_up(&mut self.gps.rejected);
            }
        }
        if status.now.is_none() {
            if let Some(r) = rtc_time {
                status.now = Some(r);
                status.origin = Some(TimeOrigin::Rtc);
            }
        }
        if status.now.is_some() {
            self.last_valid = status.now;
        }
        status
    }

    /// [`TimeKeeper::update`] for a board without a GPS receiver: the RTC
    /// alone (the same bus traffic, none of the GPS rules' code).
    pub fn update_without_gps(&mut self) -> TimeStatus {
        let mut status = TimeStatus::NONE;
        let (rtc_time, _) = self.read_rtc(&mut status);
        if let Some(r) = rtc_time {
            status.now = Some(r);
            status.origin = Some(TimeOrigin::Rtc);
            self.last_valid = Some(r);
        }
        status
    }

    /// [`TimeKeeper::read_rtc`] for [`TimeKeeper::update`], out of line on
    /// the AVR: inlined there its temporaries joined the GPS rules' frame
    /// (206 B more on the ATmega2560). The Uno's `update_without_gps`
    /// keeps its own call inline (294 B less there).
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn read_rtc_apart(&mut self, status: &mut TimeStatus) -> (Option<UtcTime>, bool) {
        self.read_rtc(status)
    }

    /// Reads the RTC into `status`: its time when it can be trusted, and
    /// whether the bus answered. A stopped oscillator makes its registers
    /// meaningless, so they are not read.
    fn read_rtc(&mut self, status: &mut TimeStatus) -> (Option<UtcTime>, bool) {
        match self.rtc.lost_power() {
            Ok(true) => status.rtc_lost_power = true,
            Ok(false) => match self.rtc.datetime() {
                Ok(t) => match utc_from_datetime(&t) {
                    Ok(u) if self.config.window.contains(&u) => {
                        status.rtc_raw = Some(u);
                        return (Some(u), true);
                    }
                    Ok(u) => {
                        status.rtc_implausible = true;
                        status.rtc_raw = Some(u);
                    }
                    Err(_) => status.rtc_error = true,
                },
                Err(_) => status.rtc_error = true,
            },
            Err(_) => {
                status.rtc_error = true;
                return (None, false);
            }
        }
        (None, true)
    }

    /// A new plausible epoch saying `t` (advanced to monotonic `now_ms`):
    /// does it agree with the last one?
    fn gps_epoch(&mut self, t: UtcTime, now_ms: u32) {
        let g = &mut self.gps;
        if let Some((last_t, last_ms)) = g.last {
            // Both instants are advanced to the keeper's calls: their UTC
            // difference should be the monotonic time between the calls.
            let mono_ms = i32::try_from(super::monotonic::elapsed_ms(now_ms, last_ms)).ok();
            let agrees = ms_between(&t, &last_t)
                .zip(mono_ms)
                .and_then(|(d, m)| d.checked_sub(m))
                .is_some_and(|e| e.unsigned_abs() <= self.config.agree_ms);
            g.last_disagreed = !agrees;
            if agrees {
                g.agree_since_ms.get_or_insert(last_ms);
            } else {
                g.agree_since_ms = None;
                g.disagreements = g.disagreements.saturating_add(1);
                g.last_disagreement_ms = Some(now_ms);
            }
        }
        // Remembered at the call's instant (the time is advanced to it).
        g.last = Some((t, now_ms));
    }
}

impl TimeStatus {
    /// The instant to hand the controller: the trusted time, else the RTC's
    /// raw reading, else `fallback` (the controller does not track while the
    /// time is not valid; the instant only drives its timers).
    pub fn tick_time(&self, fallback: UtcTime) -> UtcTime {
        self.now.or(self.rtc_raw).unwrap_or(fallback)
    }

    /// The controller's inputs for this tick: the monotonic time, UTC and
    /// its validity, the GPS state, and the anemometer pulses counted over
    /// the last `wind_interval_ms` of the monotonic clock; no stow inputs
    /// (the caller sets those its board has).
    pub fn tick_inputs(
        &self,
        now_ms: u32,
        fallback: UtcTime,
        wind_pulses: u32,
        wind_interval_ms: u32,
    ) -> TickInputs {
        TickInputs {
            now_ms,
            now: self.tick_time(fallback),
            time_valid: self.time_valid(),
            gps_fix: self.gps_fix,
            gps_time_implausible: self.gps_time_implausible,
            gps_time_unstable: self.gps_time_unstable,
            gps_position_unstable: false,
            wind_pulses,
            wind_interval_ms,
            stow_inputs: crate::safety::StowInputs::default(),
        }
    }
}
