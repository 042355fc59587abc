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
//!   and the tracker carries on with the RTC.
//!
//! Nothing here blocks or panics; every device error ends in a status flag.

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
}

impl Default for TimeConfig {
    /// 2 s drift: a DS3231 (±2 ppm) drifts that much in about 12 days; at
    /// the equator the sun moves 0.0083° in 2 s, far inside any mechanism's
    /// resolution. 1.5 s age: receivers send one epoch a second (NMEA 0183
    /// at 1 Hz), so a fix older than that is a missed epoch. The window is
    /// the firmware's own.
    fn default() -> Self {
        TimeConfig {
            max_drift_s: 2,
            max_gps_age_ms: 1_500,
            window: DateWindow::firmware(),
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
/// documentation for the rules).
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
    /// week-rollover bug): ignored, not written to the RTC.
    pub gps_time_implausible: bool,
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
}

impl<C: RtcDriver> TimeKeeper<C> {
    /// A keeper over the RTC driver; no bus traffic.
    pub fn new(rtc: C, config: TimeConfig) -> Self {
        TimeKeeper {
            rtc,
            config,
            last_valid: None,
            rtc_sets: 0,
        }
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
    pub fn update(&mut self, gps: &GpsFix, now_ms: u32) -> TimeStatus {
        let gps_said = gps_time(gps, now_ms, &self.config);
        let gps_time = match gps_said {
            GpsTime::Trusted(t) => Some(t),
            _ => None,
        };
        let mut status = TimeStatus {
            now: None,
            origin: None,
            rtc_raw: None,
            gps_fix: gps_time.is_some(),
            gps_time_implausible: matches!(gps_said, GpsTime::Implausible(_)),
            rtc_implausible: false,
            rtc_lost_power: false,
            rtc_error: false,
            rtc_set: false,
        };
        // The RTC: a stopped oscillator makes its registers meaningless, so
        // they are not read.
        let mut rtc_time = None;
        let mut bus_ok = true;
        match self.rtc.lost_power() {
            Ok(true) => status.rtc_lost_power = true,
            Ok(false) => match self.rtc.datetime() {
                Ok(t) => match utc_from_datetime(&t) {
                    Ok(u) if self.config.window.contains(&u) => {
                        rtc_time = Some(u);
                        status.rtc_raw = Some(u);
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
                bus_ok = false;
            }
        }
        if let Some(g) = gps_time {
            let drifted = match rtc_time {
                // Beyond ±68 years apart: drifted.
                Some(r) => g
                    .seconds_since(&r)
                    .is_none_or(|d| d.unsigned_abs() > self.config.max_drift_s),
                None => true,
            };
            // A bus that failed to answer the status read is not written.
            if drifted && bus_ok {
                match datetime_from_utc(&g).map(|d| self.rtc.set_datetime(&d)) {
                    Ok(Ok(())) => {
                        status.rtc_set = true;
                        self.rtc_sets = self.rtc_sets.saturating_add(1);
                    }
                    _ => status.rtc_error = true,
                }
            }
            status.now = Some(g);
            status.origin = Some(TimeOrigin::Gps);
        } else if let Some(r) = rtc_time {
            status.now = Some(r);
            status.origin = Some(TimeOrigin::Rtc);
        }
        if status.now.is_some() {
            self.last_valid = status.now;
        }
        status
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
    /// the last `wind_interval_ms` of the monotonic clock.
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
            wind_pulses,
            wind_interval_ms,
        }
    }
}
