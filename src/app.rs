//! The board-independent firmware loop: what every image runs.
//!
//! A board (one module per board under [`crate::board`]) turns its chip's
//! peripherals into the parts this loop takes, and its image is a few
//! lines: build the parts, [`Firmware::new`], then [`Firmware::run`].
//!
//! | part | trait | on a board |
//! |---|---|---|
//! | UTC clock | [`drivers::rtc::Clock`] | DS3231 on I²C |
//! | GPS port | `embedded_io::{Read, ReadReady}` | NMEA on a UART, interrupt-driven receive ring |
//! | axis drives | [`AxisDrive`] + [`Motion`] | [`crate::hw::StepperAxis`]: H-bridge stepper + home switch |
//! | attitude | [`AttitudeSensor`] | [`crate::hw::MountSensorsHw`]: ADXL345 or WitMotion + QMC5883L |
//! | log | [`Sink`] | a UART, semihosting |
//! | monotonic ms, anemometer, watchdog, sleep | [`Platform`] | Timer0 / SysTick, INTn / EXTI, WDT / IWDG, `sleep` / `wfi` |
//!
//! Each pass of [`Firmware::poll`] never blocks: it drains the GPS port
//! (bounded), lets both drives take the steps now due, and once per
//! [`AppConfig::tick_ms`] of the monotonic clock runs one controller tick
//! (time keeping, site, wind, [`Controller::tick`]) and logs what changed
//! in the shapes of [`crate::log`]. [`Firmware::run`] sleeps until the next
//! interrupt between passes. The watchdog is fed only while ticks come on
//! time, so a loop that hangs (or a tick that never ends) resets the chip.
//!
//! There is no simulated clock: without a trusted time (RTC lost power or
//! outside the firmware's window, and no GPS) the controller waits stowed
//! and the log says so (`mode wait_for_time`, `fault rtc_invalid raised`).

use drivers::gps::GpsFix;
use drivers::rtc::Clock as RtcDriver;
use embedded_io::{Read, ReadReady};
use sun_algos::{Algorithm, Error as SunError, Float, Options, Site, SunPosition, UtcTime};

use crate::axis::AxisDrive;
use crate::config::Config;
use crate::controller::{Controller, ControllerError, ControllerOptions, TickReport};
use crate::hw::GpsPort;
use crate::log::{self, ChangeLog, Sink, SiteSource as LogSite, TimeSource};
use crate::safety::Mode;
use crate::sources::{site_from_config, site_from_fix, wmm_declination_deg, TimeConfig};
use crate::sources::{TimeKeeper, TimeOrigin};
use crate::traits::{AttitudeSensor, PositionSource};

/// What a board gives the loop besides its devices.
pub trait Platform {
    /// Monotonic milliseconds since boot; never steps, never goes back.
    fn now_ms(&mut self) -> u64;
    /// Anemometer pulses counted since the last call.
    fn take_wind_pulses(&mut self) -> u32;
    /// Restarts the watchdog's timeout.
    fn feed_watchdog(&mut self);
    /// Sleeps until the next interrupt (a timer tick at the latest).
    fn wait_for_interrupt(&mut self);
}

/// A drive whose motion is produced by the main loop (a stepper's steps).
pub trait Motion {
    /// Takes the step(s) due at `now_us` of the monotonic clock; false when
    /// the drive reported an error.
    fn service(&mut self, now_us: u64) -> bool;
}

impl<P, L, H, E> Motion for crate::hw::StepperAxis<P, L, H>
where
    P: embedded_hal::digital::OutputPin<Error = E>,
    L: embedded_hal::digital::InputPin<Error = E>,
    H: embedded_hal::digital::InputPin<Error = E>,
{
    fn service(&mut self, now_us: u64) -> bool {
        self.poll(now_us).is_ok()
    }
}

/// Longest pass after which a GPS fix decoded in the next pass keeps its
/// stamp (the moment it was decoded): 50 ms, a few ticks of a loop that
/// wakes every millisecond. After a longer pass (a day plan's step, the
/// axis branch look-ahead) the stamp is the previous pass's instant.
pub const GPS_STAMP_SLACK_MS: u64 = 50;

/// Settings of the loop itself (the tracker's are in [`Config`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AppConfig {
    /// Board name for the boot line.
    pub board: &'static str,
    /// Monotonic milliseconds between controller ticks.
    pub tick_ms: u32,
    /// Trust rules for GPS time and the RTC.
    pub time: TimeConfig,
    /// A GPS position moving less than this (degrees of latitude or
    /// longitude) from the site in use does not change it: fix noise of a
    /// few metres does not re-plan the day.
    pub site_min_move_deg: f64,
    /// Take the magnetic declination from WMM2025 for the site in use
    /// (instead of the configuration's `calibration.declination_deg`).
    pub wmm_declination: bool,
    /// ΔT (TT − UT1) in seconds for the sun algorithm.
    pub delta_t_s: f32,
    /// GPS counts as lost (fault `gps_lost`) only after this long without
    /// trusted GPS time on the monotonic clock: a receiver that misses
    /// epochs for up to a minute (an obstructed antenna, a receiver set to
    /// a slow output rate) neither raises it nor switches the time source
    /// in the log (the RTC it set carries the time meanwhile; at ±2 ppm a
    /// DS3231 drifts 0.12 ms in a minute).
    pub gps_hold_ms: u32,
}

impl AppConfig {
    /// One tick a second, the default trust rules, declination from WMM.
    pub fn new(board: &'static str) -> Self {
        AppConfig {
            board,
            tick_ms: 1000,
            time: TimeConfig::default(),
            site_min_move_deg: 0.001,
            wmm_declination: true,
            delta_t_s: 69.0,
            gps_hold_ms: 60_000,
        }
    }
}

/// The position source of the images: `psa-2020` (seed blanco-2020, valid
/// 2020–2050) for a site the loop may replace.
#[derive(Debug, Clone, Copy)]
pub struct SiteSource<T> {
    site: Site<T>,
    options: Options<T>,
}

impl<T: Float> SiteSource<T> {
    /// The source for `site` with ΔT `delta_t_s`.
    pub fn new(site: Site<T>, delta_t_s: f32) -> Self {
        SiteSource {
            site,
            options: Options {
                delta_t_s: Some(T::from_f32(delta_t_s)),
                ..Options::default()
            },
        }
    }
    /// Replaces the site.
    pub fn set_site(&mut self, site: Site<T>) {
        self.site = site;
    }
}

impl<T: Float> PositionSource<T> for SiteSource<T> {
    fn site(&self) -> Site<T> {
        self.site
    }
    #[inline(never)]
    fn position(&mut self, time: &UtcTime) -> Result<SunPosition<T>, SunError> {
        Algorithm::Psa2020.position(time, &self.site, &self.options)
    }
}

/// Why the firmware could not start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartError {
    /// The configuration's site is impossible.
    Site(SunError),
    /// The controller refused the configuration.
    Controller(ControllerError),
}

/// Counters of one run, for the log and the tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Stats {
    /// Controller ticks run.
    pub ticks: u32,
    /// Set-point lines written.
    pub setpoints: u32,
    /// GPS port read errors (overruns, framing).
    pub gps_errors: u32,
    /// Drive service calls that failed.
    pub drive_errors: u32,
    /// Ticks that started more than one tick period late.
    pub late_ticks: u32,
}

/// The tracker firmware over one board's parts.
pub struct Firmware<T, R, G, D, S, L, const N: usize> {
    controller: Controller<T, SiteSource<T>, D, S, N>,
    time: TimeKeeper<R>,
    gps: GpsPort<G>,
    log: L,
    app: AppConfig,
    changes: ChangeLog,
    stats: Stats,
    fix: GpsFix,
    next_tick_ms: Option<u64>,
    last_tick_ms: u64,
    /// UTC handed to the controller at the last tick.
    last_tick_utc: Option<UtcTime>,
    /// Monotonic ms of the last pass.
    last_pass_ms: Option<u64>,
    time_origin: Option<TimeOrigin>,
    site_origin: Option<LogSite>,
    site_f64: Site<f64>,
    declination_for: Option<(Site<f64>, i32)>,
    last_setpoint: Option<UtcTime>,
    last_report: Option<TickReport<T>>,
    last_gps_ms: Option<u64>,
    boot_fallback: UtcTime,
}

impl<T, R, G, D, S, L, const N: usize> Firmware<T, R, G, D, S, L, N>
where
    T: Float,
    R: RtcDriver,
    G: Read + ReadReady,
    D: AxisDrive + Motion,
    S: AttitudeSensor<T>,
    L: Sink,
{
    /// The firmware at power-on: writes the boot line and the stored site.
    /// `axes` are the C (azimuth rotation) then the A (tilt) axis.
    #[allow(clippy::too_many_arguments)]
    // Not inlined: its temporaries (the controller under construction) then
    // leave the stack before the loop starts (an 8-bit board has 8 KB).
    #[inline(never)]
    pub fn new(
        app: AppConfig,
        config: Config,
        options: ControllerOptions<T>,
        rtc: R,
        gps: G,
        axes: [D; 2],
        sensors: Option<S>,
        mut log: L,
    ) -> Result<Self, StartError> {
        log::boot(&mut log, app.board);
        // The instant handed to the controller's timers before any time is
        // known (it neither tracks nor plans then).
        let boot_fallback = UtcTime::from_days_ms(0, 0).map_err(StartError::Site)?;
        let site_f64 = site_from_config(&config.site).map_err(StartError::Site)?;
        let site = convert_site::<T>(&site_f64).map_err(StartError::Site)?;
        let source = SiteSource::new(site, app.delta_t_s);
        Controller::<T, SiteSource<T>, D, S, N>::check(&config).map_err(StartError::Controller)?;
        Ok(Firmware {
            // Built in place (no temporary copy of the controller).
            controller: Controller::new_checked(config, options, source, axes, sensors),
            time: TimeKeeper::new(rtc, app.time),
            gps: GpsPort::new(gps, u64::from(app.time.max_gps_age_ms)),
            log,
            app,
            changes: ChangeLog::new(),
            stats: Stats::default(),
            fix: GpsFix::NONE,
            next_tick_ms: None,
            last_tick_ms: 0,
            last_tick_utc: None,
            last_pass_ms: None,
            time_origin: None,
            site_origin: None,
            site_f64,
            declination_for: None,
            last_setpoint: None,
            last_report: None,
            last_gps_ms: None,
            boot_fallback,
        })
    }

    /// The controller (tests and host tools look inside).
    pub fn controller(&self) -> &Controller<T, SiteSource<T>, D, S, N> {
        &self.controller
    }
    /// The controller, mutable (an operator's console).
    pub fn controller_mut(&mut self) -> &mut Controller<T, SiteSource<T>, D, S, N> {
        &mut self.controller
    }
    /// The log sink.
    pub fn log_mut(&mut self) -> &mut L {
        &mut self.log
    }
    /// The time keeper (and through it the RTC).
    pub fn time_keeper_mut(&mut self) -> &mut TimeKeeper<R> {
        &mut self.time
    }
    /// Counters.
    pub fn stats(&self) -> Stats {
        self.stats
    }
    /// The last tick's report.
    pub fn last_report(&self) -> Option<TickReport<T>> {
        self.last_report
    }

    /// Runs forever, sleeping between passes. Takes `&mut self`: moving
    /// the firmware (kilobytes) into the call would copy it on the stack.
    pub fn run<P: Platform>(&mut self, platform: &mut P) -> ! {
        loop {
            self.poll(platform);
            platform.wait_for_interrupt();
        }
    }

    /// One pass of the main loop; never blocks. Returns true when a
    /// controller tick ran in it.
    pub fn poll<P: Platform>(&mut self, platform: &mut P) -> bool {
        let now_ms = platform.now_ms();
        // The reader stamps what it decodes with the instant it is given;
        // the bytes drained now came at any time since the previous pass.
        // After a pass longer than GPS_STAMP_SLACK_MS they are stamped at
        // the previous pass: a fix's age is then never under-counted, and
        // a fix found late is not taken as fresh time (it would set the
        // clock back by the pass's length). The time keeper ages the fix
        // against `now_ms`.
        let stamp_ms = match self.last_pass_ms.replace(now_ms) {
            Some(prev) if now_ms.saturating_sub(prev) > GPS_STAMP_SLACK_MS => prev,
            _ => now_ms,
        };
        match self.gps.service(stamp_ms) {
            Ok(fix) => self.fix = fix,
            Err(_) => self.stats.gps_errors = self.stats.gps_errors.saturating_add(1),
        }
        let now_us = now_ms.saturating_mul(1000);
        for ax in self.controller.axes_mut().iter_mut() {
            if !ax.drive_mut().service(now_us) {
                self.stats.drive_errors = self.stats.drive_errors.saturating_add(1);
            }
        }
        let tick_ms = u64::from(self.app.tick_ms.max(1));
        let due = self.next_tick_ms.is_none_or(|t| now_ms >= t);
        if due {
            if let Some(t) = self.next_tick_ms {
                if now_ms.saturating_sub(t) > tick_ms {
                    self.stats.late_ticks = self.stats.late_ticks.saturating_add(1);
                }
            }
            let pulses = platform.take_wind_pulses();
            self.tick(now_ms, pulses);
            self.next_tick_ms = Some(now_ms.saturating_add(tick_ms));
        }
        // Fed only while ticks come on time: a pass that hangs, or ticks
        // that stop, let the watchdog reset the chip.
        if now_ms.saturating_sub(self.last_tick_ms) <= tick_ms.saturating_mul(3) {
            platform.feed_watchdog();
        }
        due
    }

    fn tick(&mut self, now_ms: u64, wind_pulses: u32) {
        let interval_ms = now_ms.saturating_sub(self.last_tick_ms);
        let interval_ms = u32::try_from(interval_ms).unwrap_or(u32::MAX);
        self.last_tick_ms = now_ms;
        self.stats.ticks = self.stats.ticks.saturating_add(1);
        let mut status = self.time.update(&self.fix, now_ms);
        if status.origin == Some(TimeOrigin::Gps) {
            self.last_gps_ms = Some(now_ms);
        }
        let gps_recent = self
            .last_gps_ms
            .is_some_and(|t| now_ms.saturating_sub(t) <= u64::from(self.app.gps_hold_ms));
        // Between two epochs the RTC that GPS set carries the time: still
        // GPS time as far as the log and the GPS fault are concerned.
        status.gps_fix = gps_recent;
        let origin = match status.origin {
            Some(TimeOrigin::Rtc) if gps_recent => Some(TimeOrigin::Gps),
            o => o,
        };
        // Time: logged when first trusted and when its source changes.
        if origin != self.time_origin {
            if let (Some(origin), Some(now)) = (origin, status.now) {
                let source = match origin {
                    TimeOrigin::Gps => TimeSource::Gps,
                    TimeOrigin::Rtc => TimeSource::Rtc,
                };
                log::time(&mut self.log, source, &now);
            }
            self.time_origin = origin;
        }
        // Site: the GPS position when a fix gives one, else the stored one.
        self.update_site(status.now);
        let fallback = self.time.last_valid().unwrap_or(self.boot_fallback);
        let inputs = status.tick_inputs(now_ms, fallback, wind_pulses, interval_ms);
        let report = self.controller.tick(&inputs);
        if report.clock_jump {
            // The schedule starts over: say why tracking pauses.
            self.log.text("clock jump from=");
            if let Some(t) = self.last_tick_utc {
                self.log.utc(&t);
            }
            self.log.text(" to=");
            self.log.utc(&inputs.now);
            self.log.text(match status.origin {
                Some(TimeOrigin::Gps) => " source=gps",
                Some(TimeOrigin::Rtc) => " source=rtc",
                None => " source=none",
            });
            self.log.text(": the day is planned again\n");
        }
        self.last_tick_utc = Some(inputs.now);
        self.log_setpoint(&report);
        self.changes
            .update(&mut self.log, self.controller.faults(), report.mode);
        self.last_report = Some(report);
    }

    // Not inlined: the WMM synthesis's rows (about 1 KB of f64) are then on
    // the stack only during this call, not under the controller's tick.
    #[inline(never)]
    fn update_site(&mut self, now: Option<UtcTime>) {
        match site_from_fix(&self.fix) {
            Some(s) => {
                let moved = (s.latitude_deg() - self.site_f64.latitude_deg()).abs()
                    > self.app.site_min_move_deg
                    || (s.longitude_deg() - self.site_f64.longitude_deg()).abs()
                        > self.app.site_min_move_deg;
                if self.site_origin != Some(LogSite::Gps) || moved {
                    if let Ok(site) = convert_site::<T>(&s) {
                        self.site_f64 = s;
                        self.controller.position_source_mut().set_site(site);
                        self.controller.replan();
                        self.site_origin = Some(LogSite::Gps);
                        log::site(
                            &mut self.log,
                            LogSite::Gps,
                            s.latitude_deg() as f32,
                            s.longitude_deg() as f32,
                        );
                    }
                }
            }
            None => {
                if self.site_origin.is_none() {
                    self.site_origin = Some(LogSite::Config);
                    log::site(
                        &mut self.log,
                        LogSite::Config,
                        self.site_f64.latitude_deg() as f32,
                        self.site_f64.longitude_deg() as f32,
                    );
                }
            }
        }
        // Declination from WMM2025 for the site in use, once per site and
        // day (it changes by about 0.1° a year).
        if self.app.wmm_declination {
            if let Some(now) = now {
                let day = now.unix_seconds().div_euclid(86_400);
                let day = i32::try_from(day).unwrap_or(i32::MAX);
                let key = (self.site_f64, day);
                if self.declination_for != Some(key) {
                    self.declination_for = Some(key);
                    // In the controller's precision: f32 on a board
                    // without an FPU (software f64 takes ten times longer).
                    if let Ok(d) = wmm_declination_deg::<T>(&self.site_f64, &now) {
                        if let Some(s) = self.controller.sensors_mut() {
                            s.set_declination_deg(d);
                        }
                    }
                }
            }
        }
    }

    /// `setpoint …` at each new table entry the controller tracks.
    fn log_setpoint(&mut self, report: &TickReport<T>) {
        if report.mode != Mode::Tracking {
            return;
        }
        let (Some(entry), Some(target)) = (self.controller.scheduler().applied(), report.target)
        else {
            return;
        };
        if self.last_setpoint == Some(entry.time) {
            return;
        }
        self.last_setpoint = Some(entry.time);
        self.stats.setpoints = self.stats.setpoints.saturating_add(1);
        log::setpoint(
            &mut self.log,
            &entry.time,
            entry.set_point.slope_deg.to_f32(),
            entry.set_point.azimuth_deg.to_f32(),
            target.gamma_deg.to_f32(),
            target.alpha_deg.to_f32(),
        );
    }
}

fn convert_site<T: Float>(s: &Site<f64>) -> Result<Site<T>, SunError> {
    Site::with_elevation(
        T::from_f64(s.latitude_deg()),
        T::from_f64(s.longitude_deg()),
        T::from_f64(s.elevation_m()),
    )
}
