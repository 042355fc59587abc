//! The board-independent firmware loop: what every image runs.
//!
//! A board (one crate per board under `boards/` in the repository) turns its chip's
//! peripherals into the parts this loop takes, and its image is a few
//! lines: build the parts, [`Firmware::new`], then [`Firmware::run`].
//!
//! | part | trait | on a board |
//! |---|---|---|
//! | UTC clock | [`drivers::rtc::Clock`] | DS3231 on I²C |
//! | GPS port | [`GpsInput`]: `embedded_io::{Read, ReadReady}`, or [`NoGps`](crate::hw::NoGps) | NMEA on a UART, interrupt-driven receive ring; none |
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

use drivers::counter::count_up;
use drivers::gps::GpsFix;
use drivers::rtc::Clock as RtcDriver;
use sun_algos::{Error as SunError, Float, Site, UtcTime};

use crate::attitude::Pose;
use crate::config::{Config, DriveSet};
use crate::console::{self, Executed, Jogged, LineBuffer, Operator, StatusView, TimeSetError};
use crate::controller::{Controller, ControllerError, ControllerOptions, TickInputs, TickReport};
use crate::hw::{GpsInput, GpsState};
use crate::log::{self, ChangeLog, Sink, SiteSource as LogSite};
use crate::motion::AxisDrive;
use crate::persist::{LoadReport, SaveError, SaveStatus};
use crate::ports::AttitudeSensor;
use crate::safety::{AxisId, Fault, Mode, OperatorHold, Weather, WeatherWatch};
use crate::site::filter::{SiteDecision, SiteFilterConfig};
use crate::site::{site_from_config, site_from_fix, site_moved, wmm_declination_deg};
use crate::sun::BoardSource;
use crate::time::TimeConfig;
use crate::time::{monotonic, TimeKeeper, TimeOrigin};

/// What a board gives the loop besides its devices.
pub trait Platform {
    /// Monotonic milliseconds since boot; never steps, never goes back. The
    /// loop keeps the low 32 bits ([`crate::time::monotonic`]); the drives'
    /// microseconds come from the whole count.
    fn now_ms(&mut self) -> u64;
    /// Anemometer pulses counted since the last call.
    fn take_wind_pulses(&mut self) -> u32;
    /// The snow, hail and plant-stow inputs as read now; a board without
    /// them keeps this default (none wired: they never stow).
    fn stow_inputs(&mut self) -> crate::safety::StowInputs {
        crate::safety::StowInputs::default()
    }
    /// Restarts the watchdog's timeout.
    fn feed_watchdog(&mut self);
    /// Sleeps until the next interrupt (a timer tick at the latest).
    fn wait_for_interrupt(&mut self);
    /// Moves bytes typed on the console (received since the last call)
    /// into `buf`; returns how many, 0 when none. Never waits. A board
    /// without a console keeps this default.
    fn console_read(&mut self, buf: &mut [u8]) -> usize {
        let _ = buf;
        0
    }
    /// Lines the console's receive ring lost whole since the last call
    /// (their line ends dropped where no marker stands for them:
    /// [`console::RxRing::take_lost_lines`]); each is answered `error input
    /// lost`. A board without a console, or whose ring marks every gap,
    /// keeps this default.
    fn console_lost_lines(&mut self) -> u8 {
        0
    }
    /// Whether `set site.postal_code` has the built-in postal-code table
    /// ([`crate::site::postal`]; with its search, 2.3 KB of the Uno's
    /// single image). A board short of flash says false: the command is
    /// then answered `error site.postal_code: not in this image`, and
    /// latitude and longitude are typed as keys.
    const POSTAL_CODES: bool = true;
    /// Where the configuration is stored (console `save` and `load`);
    /// `None` (the default): this board keeps it in RAM only.
    fn config_store(&mut self) -> Option<&mut dyn ConfigPersist> {
        None
    }
}

/// A board's configuration storage as the console uses it: load at once,
/// save stepwise (an EEPROM byte takes 3.4 ms, a flash sector erase
/// hundreds: the loop keeps running while a save goes on).
pub trait ConfigPersist {
    /// Reads the stored copies into `into`: the newest good one, or the
    /// defaults.
    fn load(&mut self, into: &mut Config) -> LoadReport;
    /// Starts storing `config`.
    fn begin_save(&mut self, config: &Config) -> Result<(), SaveError<()>>;
    /// Goes on with a save without waiting: `None` while it is not done,
    /// then its result once.
    fn poll_save(&mut self) -> Option<Result<(), SaveError<()>>>;
    /// The longest a save step stalls the CPU, ms
    /// ([`crate::ports::Storage::stall_ms`]): the loop then takes the steps
    /// only while no axis moves and no tick is due for that long, so that a
    /// save typed during a move changes none of its steps or their timing.
    fn stall_ms(&self) -> u32 {
        0
    }
}

/// The two-slot store over any storage, stepped from the loop.
impl<S: crate::ports::Storage> ConfigPersist for crate::persist::ConfigStore<S> {
    fn load(&mut self, into: &mut Config) -> LoadReport {
        self.load_into(into)
    }
    fn begin_save(&mut self, config: &Config) -> Result<(), SaveError<()>> {
        crate::persist::ConfigStore::begin_save(self, config).map_err(drop_storage_error)
    }
    fn stall_ms(&self) -> u32 {
        self.storage().stall_ms()
    }
    fn poll_save(&mut self) -> Option<Result<(), SaveError<()>>> {
        match self.poll() {
            SaveStatus::Busy => None,
            SaveStatus::Done(r) => Some(r.map_err(drop_storage_error)),
            // Nothing under way (never after a started save): reported as
            // a failed save, so that the console does not wait for it.
            SaveStatus::Idle => Some(Err(SaveError::Storage(()))),
        }
    }
}

fn drop_storage_error<E>(e: SaveError<E>) -> SaveError<()> {
    match e {
        SaveError::Invalid => SaveError::Invalid,
        SaveError::TooSmall => SaveError::TooSmall,
        SaveError::Storage(_) => SaveError::Storage(()),
    }
}

/// Bytes taken from the console per pass: a flood of input is read at
/// this pace (the receive ring drops what does not fit) and never holds
/// the loop; typed lines come far slower.
pub const CONSOLE_BYTES_PER_PASS: usize = 16;

/// A drive whose motion is produced by the main loop (a stepper's steps).
pub trait Motion {
    /// Takes the step(s) due at `now_ms` of the loop's monotonic clock (the
    /// board's 64-bit millisecond count: it never wraps); false when the
    /// drive reported an error.
    fn service(&mut self, now_ms: u64) -> bool;

    /// Milliseconds from `now_ms` to the next instant this drive must be
    /// served at to stay on time (a timed run's end), if it has one; the
    /// pass puts a tick off while one is near ([`TICK_HOLD_MS`]).
    fn due_in_ms(&self, _now_ms: u64) -> Option<u32> {
        None
    }
}

impl<P, L, H, E> Motion for crate::hw::StepperAxis<P, L, H>
where
    P: embedded_hal::digital::OutputPin<Error = E>,
    L: embedded_hal::digital::InputPin<Error = E>,
    H: embedded_hal::digital::InputPin<Error = E>,
{
    // Out of line on the AVR: the main loop's pass held a copy for each
    // axis.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn service(&mut self, now_ms: u64) -> bool {
        self.poll(us_from_ms(now_ms)).is_ok()
    }
}

/// A servo axis closes its loop on the encoder once per pass (the
/// drivers' proportional controller; the servo takes the new pulse width
/// at its next 20 ms frame).
impl<P, E, H> Motion for crate::hw::ServoAxis<'_, P, E, H>
where
    P: embedded_hal::pwm::SetDutyCycle,
    E: crate::hw::EncoderCount,
    H: embedded_hal::digital::InputPin,
{
    fn service(&mut self, _now_ms: u64) -> bool {
        self.poll().is_ok()
    }
}

/// A DC axis closes its loop on the Hall count once per pass, at the
/// loop's millisecond count ([`crate::hw::DcAxis::poll`]). A motor fault
/// (an obstruction, a stall) is no drive error: the controller takes it
/// through [`AxisDrive::take_fault`].
impl<B, E, H, C> Motion for crate::hw::DcAxis<B, E, H, C>
where
    B: drivers::dc_motor::Bridge,
    E: crate::hw::EncoderCount,
    H: embedded_hal::digital::InputPin,
    C: crate::hw::MotorCurrent,
{
    fn service(&mut self, now_ms: u64) -> bool {
        // The axis's times wrap with the count's low 32 bits.
        match self.poll(now_ms as u32) {
            Ok(_) | Err(crate::hw::DcAxisError::Fault(_)) => true,
            Err(_) => false,
        }
    }
}

/// A timed axis ends a run whose time is up once per pass
/// ([`crate::hw::TimedAxis::poll`]); an obstruction is no drive error, as
/// for a DC axis.
impl<B, H, C> Motion for crate::hw::TimedAxis<B, H, C>
where
    B: drivers::dc_motor::Bridge,
    H: embedded_hal::digital::InputPin,
    C: crate::hw::MotorCurrent,
{
    fn service(&mut self, now_ms: u64) -> bool {
        // The axis's times wrap with the count's low 32 bits.
        match self.poll(now_ms as u32) {
            Ok(_) | Err(crate::hw::TimedAxisError::Obstruction) => true,
            Err(_) => false,
        }
    }

    /// The end of the run under way: a run ended late turns the axis on
    /// by the speed times the lateness until the next move.
    fn due_in_ms(&self, now_ms: u64) -> Option<u32> {
        self.run_left_ms(now_ms as u32)
    }
}

/// A linear actuator's axis closes its loop on its feedback once per
/// pass ([`crate::hw::LinearAxis::poll`]); a motor fault or a failed
/// reading is no drive error, as for a DC axis: the controller takes it
/// through [`AxisDrive::take_fault`].
impl<B, F, H, C> Motion for crate::hw::LinearAxis<B, F, H, C>
where
    B: drivers::dc_motor::Bridge,
    F: crate::hw::LinearFeedback,
    H: embedded_hal::digital::InputPin,
    C: crate::hw::MotorCurrent,
{
    fn service(&mut self, now_ms: u64) -> bool {
        use crate::hw::LinearAxisError as E;
        // The axis's times wrap with the count's low 32 bits.
        match self.poll(now_ms as u32) {
            Ok(_)
            | Err(E::Axis(crate::hw::DcAxisError::Fault(_)))
            | Err(E::Feedback(_) | E::FeedbackLost) => true,
            Err(_) => false,
        }
    }
}

/// How long a tick is put off while a drive is due within it, ms: a tick
/// on the ATmega2560 takes up to 70 ms (the longest pass of the emulator
/// scenarios, 138 ms, is the first after power-on), and a timed run that
/// ended after it would run on by that (0.5° at 7.6 °/s). A tick waits
/// for the drive's instant, at most this long past its own, unless a drive
/// stopped itself on a fault in the pass.
pub const TICK_HOLD_MS: u32 = 150;

/// Longest pass after which a GPS fix decoded in the next pass keeps its
/// stamp (the moment it was decoded): 50 ms, a few ticks of a loop that
/// wakes every millisecond. After a longer pass (a day plan's step, the
/// axis branch look-ahead) the stamp is the previous pass's instant.
pub const GPS_STAMP_SLACK_MS: u32 = 50;

/// `error input lost` replies a pass writes for lines the console's ring
/// lost whole (17 bytes each: 1.5 ms at 115200 baud); the rest follow in
/// the next passes.
const LOST_REPLIES_PER_PASS: u8 = 4;

/// Settings of the loop itself (the tracker's are in [`Config`]).
#[derive(Debug, Clone, Copy)]
pub struct AppConfig {
    /// Board name for the boot line.
    pub board: &'static str,
    /// Monotonic milliseconds between controller ticks.
    pub tick_ms: u32,
    /// Trust rules for GPS time and the RTC.
    pub time: TimeConfig,
    /// A GPS position moving less than this (degrees of a great circle)
    /// from the site in use does not change it: fix noise of a
    /// few metres does not re-plan the day.
    pub site_min_move_deg: f32,
    /// When a GPS position far from the site in use becomes the site.
    pub site_filter: SiteFilterConfig,
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
    /// The board's own configuration: what the console's `defaults`
    /// restores (and what a board uses when nothing good is stored).
    pub defaults: fn() -> Config,
    /// The drive kinds the board builds its axes of (`axis.c.drive`,
    /// `axis.a.drive`): the console refuses the others.
    pub drives: DriveSet,
}

impl AppConfig {
    /// One tick a second, the default trust rules, declination from WMM.
    pub fn new(board: &'static str) -> Self {
        AppConfig {
            board,
            tick_ms: 1000,
            time: TimeConfig::default(),
            site_min_move_deg: 0.001,
            site_filter: SiteFilterConfig::default(),
            wmm_declination: true,
            delta_t_s: 69.0,
            gps_hold_ms: 60_000,
            defaults: Config::default,
            drives: DriveSet::STEPPER,
        }
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

/// The tracker firmware over one board's parts: `R` the RTC, `G` the GPS
/// input ([`GpsInput`]: a serial port or [`crate::hw::NoGps`]), `D` the axes'
/// drive, `S` the attitude sensors, `L` the log, `N` the day table's
/// capacity (0: real-time mode, [`crate::plan`]), `W` the weather inputs
/// ([`Weather`]: [`WeatherWatch`], or [`crate::safety::NoWeather`] on a board
/// that wires none).
// In this order on the AVR: the small fields every tick reads first,
// within the 63 bytes an `ldd` reaches from the struct's address (a field
// further on costs an address computation at each access), then the
// controller. Rust's own order put the controller (2.3 KB) first and
// these fields beyond it: 380 B more on the ATmega2560. Not on the
// Cortex-M images: there `repr(C)` made the Black Pill's image 356 B
// smaller, but `Firmware::new` on QEMU then built the firmware aside and
// copied it (a 6.5 KB frame; the day's peak stack 6,200 -> 12,376 B).
#[cfg_attr(target_arch = "avr", repr(C))]
pub struct Firmware<T, R, G: GpsInput<T>, D, S, L, const N: usize, W = WeatherWatch> {
    log: L,
    time_origin: Option<TimeOrigin>,
    site_origin: Option<LogSite>,
    /// Lines the console's ring lost whole, still to answer.
    lost_lines_due: u8,
    /// The axes whose drive held a latched fault at the last pass (a bit
    /// an axis, the last in bit 0).
    latched_axes: u8,
    stats: Stats,
    last_tick_ms: u32,
    /// Monotonic ms (the 32-bit clock of [`crate::time::monotonic`], as
    /// every stamp here) of the next controller tick.
    next_tick_ms: Option<u32>,
    /// Monotonic ms of the last pass.
    last_pass_ms: Option<u32>,
    /// GPS epochs refused before the GPS time faults were raised, while
    /// they are.
    rejected_at_fault: Option<u32>,
    /// Anemometer pulse rate over the last tick, Hz.
    last_wind_hz: Option<f32>,
    /// Monotonic ms of the next periodic `status` line.
    next_status_ms: Option<u32>,
    controller: Controller<T, BoardSource<T>, D, S, N, W>,
    /// UTC handed to the controller at the last tick.
    last_tick_utc: Option<UtcTime>,
    /// The trusted time at the last tick and where it came from.
    last_time: Option<(UtcTime, TimeOrigin)>,
    last_setpoint: Option<UtcTime>,
    /// A save in progress and the reply due when it ends.
    saving: Option<Executed>,
    boot_fallback: UtcTime,
    changes: ChangeLog,
    /// The site in use, in the controller's precision (`f32` on a board
    /// without an FPU: about a metre, and no software `f64`).
    site: Site<T>,
    /// The site and day (since 2000) the declination was computed for.
    declination_for: Option<(Site<T>, i32)>,
    /// The GPS receiver's part of the loop: its port, its fix, the filter
    /// of its positions; nothing on a board without one
    /// ([`NoGps`](crate::hw::NoGps)).
    gps: G::Part,
    app: AppConfig,
    console_line: LineBuffer<{ console::LINE_LEN }>,
    time: TimeKeeper<R>,
    last_report: Option<TickReport<T>>,
}

impl<T, R, G, D, S, L, const N: usize, W> Firmware<T, R, G, D, S, L, N, W>
where
    T: Float,
    R: RtcDriver,
    G: GpsInput<T>,
    D: AxisDrive + Motion,
    S: AttitudeSensor<T>,
    L: Sink,
    W: Weather,
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
        let site = site_from_config(&config.site).map_err(StartError::Site)?;
        let source = BoardSource::new(site, app.delta_t_s);
        Controller::<T, BoardSource<T>, D, S, N, W>::check(&config)
            .map_err(StartError::Controller)?;
        Ok(Firmware {
            // Built in place (no temporary copy of the controller).
            controller: Controller::new_checked(config, options, source, axes, sensors),
            time: TimeKeeper::new(rtc, app.time),
            gps: gps.into_part(app.time.max_gps_age_ms, app.site_filter),
            log,
            app,
            changes: ChangeLog::new(),
            stats: Stats::default(),
            next_tick_ms: None,
            last_tick_ms: 0,
            last_tick_utc: None,
            last_pass_ms: None,
            time_origin: None,
            site_origin: None,
            site,
            declination_for: None,
            last_setpoint: None,
            last_report: None,
            boot_fallback,
            console_line: LineBuffer::new(),
            saving: None,
            lost_lines_due: 0,
            latched_axes: 0,
            rejected_at_fault: None,
            last_time: None,
            last_wind_hz: None,
            next_status_ms: None,
        })
    }

    /// The controller (tests and host tools look inside).
    pub fn controller(&self) -> &Controller<T, BoardSource<T>, D, S, N, W> {
        &self.controller
    }
    /// The controller, mutable (an operator's console).
    pub fn controller_mut(&mut self) -> &mut Controller<T, BoardSource<T>, D, S, N, W> {
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
    /// The trusted time at the last tick, where it came from, and the
    /// tick's monotonic ms ([`crate::time::monotonic`]); `None` while no
    /// time is trusted.
    pub fn last_time(&self) -> Option<(UtcTime, TimeOrigin, u32)> {
        self.last_time.map(|(t, o)| (t, o, self.last_tick_ms))
    }
    /// The GPS receiver's latest fix (`GpsFix::NONE` before any); `None`
    /// on a board without a receiver.
    pub fn gps_fix(&self) -> Option<&GpsFix> {
        self.gps.track().map(|g| &g.fix)
    }
    /// The anemometer's pulse rate over the last tick, Hz.
    pub fn wind_hz(&self) -> Option<f32> {
        self.last_wind_hz
    }
    /// The loop's own settings (board name, tick).
    pub fn app(&self) -> &AppConfig {
        &self.app
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
    /// controller tick ran in it. Not inlined on the AVR: a board's loop
    /// that calls it sits in the frame that holds the firmware, where its
    /// spills would lie beyond the 63 bytes `ldd`/`std` reach.
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn poll<P: Platform>(&mut self, platform: &mut P) -> bool {
        let board_ms = platform.now_ms();
        let now_ms = monotonic::from_board_ms(board_ms);
        // The drives first, at the pass's instant: a DC axis's count is
        // read when it is served, and stamped with it.
        // A bit an axis, the last axis in bit 0.
        let mut latched = 0u8;
        for ax in self.controller.axes_mut().iter_mut() {
            if !ax.drive_mut().service(board_ms) {
                count_up(&mut self.stats.drive_errors);
            }
            latched = (latched << 1) | u8::from(ax.drive().fault_latched());
        }
        // The reader stamps what it decodes with the instant it is given;
        // the bytes drained now came at any time since the previous pass.
        // After a pass longer than GPS_STAMP_SLACK_MS they are stamped at
        // the previous pass: a fix's age is then never under-counted, and
        // a fix found late is not taken as fresh time (it would set the
        // clock back by the pass's length). The time keeper ages the fix
        // against `now_ms`.
        let stamp_ms = match self.last_pass_ms.replace(now_ms) {
            Some(prev) if monotonic::elapsed_ms(now_ms, prev) > GPS_STAMP_SLACK_MS => prev,
            _ => now_ms,
        };
        if !self.gps.service(stamp_ms) {
            count_up(&mut self.stats.gps_errors);
        }
        // A drive that stopped itself on a fault in this pass (a DC
        // motor's obstruction or stall) brings the tick forward: the fault
        // is raised and logged now, not up to a tick later.
        let tripped = latched & !self.latched_axes != 0;
        self.latched_axes = latched;
        self.service_console(platform, now_ms);
        let tick_ms = self.app.tick_ms.max(1);
        let reached = self
            .next_tick_ms
            .is_none_or(|t| monotonic::reached(now_ms, t));
        // A drive due soon holds a tick that is not late by TICK_HOLD_MS
        // yet: the drive is then served on time in a short pass, and the
        // tick follows. A tripped drive ticks at once all the same.
        let held = reached
            && self
                .next_tick_ms
                .is_some_and(|t| monotonic::elapsed_ms(now_ms, t) < TICK_HOLD_MS)
            && self.drive_due_within(board_ms, TICK_HOLD_MS);
        let due = (reached && !held) || tripped;
        if due {
            if let (true, Some(t)) = (reached, self.next_tick_ms) {
                if monotonic::elapsed_ms(now_ms, t) > tick_ms {
                    count_up(&mut self.stats.late_ticks);
                }
            }
            let pulses = platform.take_wind_pulses();
            let stow_inputs = platform.stow_inputs();
            // The motor supply to the drives (a timed axis scales its runs
            // by it); an impossible reading or none is no supply.
            let supply_mv = match stow_inputs.supply_mv {
                Some(crate::safety::Reading::Value(mv)) => u32::from(mv),
                _ => 0,
            };
            for ax in self.controller.axes_mut().iter_mut() {
                ax.drive_mut().set_supply_mv(supply_mv);
            }
            self.tick(now_ms, pulses, stow_inputs);
            self.next_tick_ms = Some(now_ms.wrapping_add(tick_ms));
            self.periodic_status(now_ms);
        }
        // Fed only while ticks come on time: a pass that hangs, or ticks
        // that stop, let the watchdog reset the chip.
        // Three tick periods, saturating: one 32-bit product after a
        // comparison (`saturating_mul` made a 64-bit product of two library
        // calls on the AVR).
        let watchdog_ms = if tick_ms > u32::MAX / 3 {
            u32::MAX
        } else {
            tick_ms.wrapping_mul(3)
        };
        if monotonic::elapsed_ms(now_ms, self.last_tick_ms) <= watchdog_ms {
            platform.feed_watchdog();
        }
        due
    }

    /// True when a drive must be served within `within_ms` of `board_ms`.
    fn drive_due_within(&self, board_ms: u64, within_ms: u32) -> bool {
        self.controller.axes().iter().any(|ax| {
            ax.drive()
                .due_in_ms(board_ms)
                .is_some_and(|ms| ms < within_ms)
        })
    }

    // Its own frame on the AVR, apart from the pass's (a stack slot more
    // than 63 bytes from the frame pointer costs six more instructions at
    // each access there).
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn tick(&mut self, now_ms: u32, wind_pulses: u32, stow_inputs: crate::safety::StowInputs) {
        let interval_ms = monotonic::elapsed_ms(now_ms, self.last_tick_ms);
        self.last_tick_ms = now_ms;
        self.last_wind_hz = (interval_ms > 0 && self.stats.ticks > 0)
            .then(|| wind_pulses as f32 * 1000.0 / interval_ms as f32);
        count_up(&mut self.stats.ticks);
        let rejected_before = self.time.rejected_epochs();
        let hold_ms = self.app.gps_hold_ms;
        // A constant `Some` or `None` of each image: a board without a
        // receiver has the RTC alone and none of the GPS rules' code.
        let mut status = match self.gps.track() {
            Some(gps) => self.time.update(&gps.fix, now_ms),
            None => self.time.update_without_gps(),
        };
        let gps_recent = self.gps.track_mut().is_some_and(|gps| {
            if status.origin == Some(TimeOrigin::Gps) {
                gps.last_time_ms = Some(now_ms);
            }
            gps.last_time_ms
                .as_mut()
                .is_some_and(|t| monotonic::age_ms(t, now_ms) <= hold_ms)
        });
        // Between two epochs the RTC that GPS set carries the time: still
        // GPS time as far as the log and the GPS fault are concerned. A
        // board without a receiver has no fix to lose: no `gps_lost`.
        status.gps_fix = gps_recent || self.gps.track().is_none();
        let origin = match status.origin {
            Some(TimeOrigin::Rtc) if gps_recent => Some(TimeOrigin::Gps),
            o => o,
        };
        // Time: logged when first trusted and when its source changes.
        if origin != self.time_origin {
            if let (Some(origin), Some(now)) = (origin, status.now) {
                log::time(&mut self.log, origin, &now);
            }
            self.time_origin = origin;
        }
        self.last_time = match (origin, status.now) {
            (Some(origin), Some(t)) => Some((t, origin)),
            _ => None,
        };
        // Site: the GPS position when a fix gives one (and it is consistent),
        // else the stored one.
        self.update_site(now_ms, status.now);
        let fallback = self.time.last_valid().unwrap_or(self.boot_fallback);
        let mut inputs = status.tick_inputs(now_ms, fallback, wind_pulses, interval_ms);
        inputs.gps_position_unstable = self.gps.track().is_some_and(|g| g.site_filter.unstable());
        inputs.stow_inputs = stow_inputs;
        self.run_controller(&inputs, status.origin, rejected_before);
    }

    /// The controller's tick over `inputs`, and what it changed in the
    /// log (`origin`: where the time came from; `rejected_before`: the GPS
    /// epochs refused before the keeper's update). Its own frame on the
    /// AVR: the report and the set-point's entry then stay within the 63
    /// bytes `ldd` reaches, apart from the time status and the inputs.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn run_controller(
        &mut self,
        inputs: &TickInputs,
        origin: Option<TimeOrigin>,
        rejected_before: u32,
    ) {
        let report = self.controller.tick(inputs);
        if report.clock_jump {
            // The schedule starts over: say why tracking pauses.
            self.log.flash(crate::flash_str!("clock jump from="));
            if let Some(t) = self.last_tick_utc {
                self.log.utc(&t);
            }
            self.log.flash(crate::flash_str!(" to="));
            self.log.utc(&inputs.now);
            self.log.flash(match origin {
                Some(TimeOrigin::Gps) => crate::flash_str!(" source=gps"),
                Some(TimeOrigin::Rtc) => crate::flash_str!(" source=rtc"),
                None => crate::flash_str!(" source=none"),
            });
            self.log
                .flash(crate::flash_str!(": the day is planned again\n"));
        }
        self.last_tick_utc = Some(inputs.now);
        self.log_setpoint(&inputs.now, &report);
        self.changes
            .update(&mut self.log, self.controller.faults(), report.mode);
        // A bad GPS time stream: its fault is logged once, raised and
        // cleared, and the epochs refused meanwhile summed when it clears.
        let faults = self.controller.faults();
        let bad_gps_time =
            faults.is_active(Fault::GpsTimeImplausible) || faults.is_active(Fault::GpsTimeUnstable);
        let rejected = self.time.rejected_epochs();
        match (self.rejected_at_fault, bad_gps_time) {
            // Counted from the epoch that raised it.
            (None, true) => self.rejected_at_fault = Some(rejected_before),
            (Some(before), false) => {
                log::gps_rejected(&mut self.log, rejected.saturating_sub(before));
                self.rejected_at_fault = None;
            }
            _ => {}
        }
        self.last_report = Some(report);
    }

    // Not inlined: the WMM synthesis's rows (four of 13 floats) are then on
    // the stack only during this call, not under the controller's tick.
    #[inline(never)]
    fn update_site(&mut self, now_ms: u32, now: Option<UtcTime>) {
        // A position far from the site in use is taken only once it has
        // been consistent for a while (a fixed tracker does not travel).
        let site = self.site;
        let taken = self.gps.track_mut().and_then(|gps| {
            gps.site_filter.expire(now_ms);
            site_from_fix::<T>(&gps.fix).and_then(|s| {
                match gps.site_filter.update(s, &site, now_ms) {
                    SiteDecision::Take(s) => Some(s),
                    SiteDecision::Keep => None,
                }
            })
        });
        match taken {
            Some(s) => {
                let min_move_deg = T::from_f32(self.app.site_min_move_deg);
                let moved = site_moved(&s, &self.site, min_move_deg);
                if self.site_origin != Some(LogSite::Gps) || moved {
                    self.use_site(s, LogSite::Gps);
                }
            }
            None => {
                if self.site_origin.is_none() {
                    self.site_origin = Some(LogSite::Config);
                    log::site(
                        &mut self.log,
                        LogSite::Config,
                        self.site.latitude_deg().to_f32(),
                        self.site.longitude_deg().to_f32(),
                    );
                }
            }
        }
        if self.app.wmm_declination {
            if let Some(now) = now {
                self.update_declination(&now);
            }
        }
    }

    /// Declination from WMM2025 for the site in use, once per site and day
    /// (it changes by about 0.1° a year). Its own frame on the AVR: the
    /// model's sums are the bulk of the site update's temporaries.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn update_declination(&mut self, now: &UtcTime) {
        // Only for a compass that applies it.
        if self.controller.sensors_mut().is_none() {
            return;
        }
        let key = (self.site, now.days_since_2000());
        if self.declination_for != Some(key) {
            self.declination_for = Some(key);
            // In the controller's precision: f32 on a board without an
            // FPU (software f64 takes ten times longer).
            if let Ok(d) = wmm_declination_deg(&self.site, now) {
                if let Some(s) = self.controller.sensors_mut() {
                    s.set_declination_deg(d);
                }
            }
        }
    }

    /// `setpoint …` at each new table entry the controller tracks.
    fn log_setpoint(&mut self, now: &UtcTime, report: &TickReport<T>) {
        if !matches!(report.mode, Mode::Tracking | Mode::Unwind) {
            return;
        }
        // The present slot's entry when the day's table has one (what the
        // controller tracks: the scheduler's check for a new slot can come
        // a tick after a stow ends), else the one applied last.
        let scheduler = self.controller.scheduler();
        let entry = scheduler.current(now).or_else(|| scheduler.applied());
        let (Some(entry), Some(target)) = (entry, report.target) else {
            return;
        };
        if self.last_setpoint == Some(entry.time) {
            return;
        }
        self.last_setpoint = Some(entry.time);
        count_up(&mut self.stats.setpoints);
        log::setpoint(
            &mut self.log,
            &entry.time,
            entry.set_point.slope_deg.to_f32(),
            entry.set_point.azimuth_deg.to_f32(),
            target.gamma_deg.to_f32(),
            target.alpha_deg.to_f32(),
        );
    }

    // The console and the configuration.

    /// The console: goes on with a save in progress (on storage whose steps
    /// stall the CPU, only while no axis moves and no tick is due within
    /// the stall: [`ConfigPersist::stall_ms`]), takes at most
    /// [`CONSOLE_BYTES_PER_PASS`] bytes and runs each complete line (while
    /// a save is under way it answers `error busy` instead). Not inlined:
    /// its buffers are then not in the frame of every pass.
    #[inline(never)]
    fn service_console<P: Platform>(&mut self, platform: &mut P, now_ms: u32) {
        if let Some(pending) = self.saving {
            let busy_within = |stall_ms: u32| {
                self.controller.axes().iter().any(|a| a.drive().pending() != 0)
                    // A stall as long as a tick delays one whatever the wait.
                    || (stall_ms < self.app.tick_ms
                        && self.next_tick_ms.is_some_and(|t| {
                            monotonic::reached(now_ms.wrapping_add(stall_ms), t)
                        }))
            };
            if let Some(store) = platform.config_store() {
                let stall_ms = store.stall_ms();
                if stall_ms > 0 && busy_within(stall_ms) {
                    // Waits for the axes to rest between ticks.
                } else if let Some(result) = store.poll_save() {
                    self.saving = None;
                    match pending {
                        Executed::HoldChanged {
                            name,
                            ok_when_saved,
                        } => console::write_hold_saved(&mut self.log, name, ok_when_saved, &result),
                        _ => console::write_saved(&mut self.log, &result),
                    }
                }
            } else {
                self.saving = None;
            }
        }
        let mut bytes = [0u8; CONSOLE_BYTES_PER_PASS];
        let n = platform.console_read(&mut bytes).min(bytes.len());
        for &b in bytes.iter().take(n) {
            let mut line = [0u8; console::LINE_LEN];
            let len = match self.console_line.push(b) {
                None => continue,
                Some(Err(e)) => {
                    console::write_line_error(&mut self.log, e);
                    continue;
                }
                Some(Ok(text)) => crate::bytes::copy_prefix(&mut line, text.as_bytes()),
            };
            if self.saving.is_some() {
                // No command while a save is under way (it takes under a
                // second; a NOR flash sector erase stalls the CPU anyway):
                // the line is answered, not run. The console is read all
                // the same, so that its receive ring does not overflow
                // behind the save.
                console::write_error(&mut self.log, crate::flash_str!("busy"));
                continue;
            }
            // The line buffer passes printable ASCII only.
            if let Some(text) = crate::text::ascii_str(line.get(..len).unwrap_or(&[])) {
                self.run_command(text, platform);
            }
        }
        // Lines lost whole in the ring: one reply each, a few a pass (each
        // reply takes the log's time).
        self.lost_lines_due = self
            .lost_lines_due
            .saturating_add(platform.console_lost_lines());
        let now = self.lost_lines_due.min(LOST_REPLIES_PER_PASS);
        for _ in 0..now {
            console::write_line_error(&mut self.log, console::LineError::Lost);
        }
        self.lost_lines_due -= now;
    }

    fn run_command<P: Platform>(&mut self, line: &str, platform: &mut P) {
        let mut op = FirmwareConsole {
            fw: self,
            platform: &mut *platform,
        };
        let done = console::execute(&mut op, line);
        match done {
            Executed::Done => {}
            Executed::SaveStarted => self.saving = Some(done),
            Executed::HoldChanged {
                name,
                ok_when_saved,
            } => match self.begin_hold_save(platform) {
                Some(Ok(())) => self.saving = Some(done),
                // A save that failed to start, or no storage (then the
                // reply of a save that succeeded: `ok NAME` or nothing).
                r => console::write_hold_saved(
                    &mut self.log,
                    name,
                    ok_when_saved,
                    &r.unwrap_or(Ok(())),
                ),
            },
        }
    }

    /// Starts storing the operator's hold in force with the *stored*
    /// configuration (the board's own when none is good): unsaved `set`s
    /// stay unsaved. `None` when the board has no storage. Not inlined: the
    /// copy read is on the stack only here.
    #[inline(never)]
    fn begin_hold_save<P: Platform>(
        &mut self,
        platform: &mut P,
    ) -> Option<Result<(), SaveError<()>>> {
        let store = platform.config_store()?;
        let mut config = (self.app.defaults)();
        if store.load(&mut config).defaults {
            config = (self.app.defaults)();
        }
        config.hold = self.controller.hold();
        Some(store.begin_save(&config))
    }

    /// Puts a changed configuration into effect: the controller's, and the
    /// site when GPS does not give it.
    fn apply_config(&mut self, config: Config) -> bool {
        // A drive kind the board has no driver for (a `load` of a record
        // another image saved): the axes in force are of other kinds.
        if config.check_drives(self.app.drives).is_err()
            || self.controller.reconfigure(config).is_err()
        {
            return false;
        }
        if self.site_origin == Some(LogSite::Gps) {
            return true;
        }
        let Ok(site) = site_from_config(&config.site) else {
            return true;
        };
        if site == self.site {
            return true;
        }
        self.use_site(site, LogSite::Config);
        true
    }

    /// Tracks for `site` from now on (the day is planned again) and logs
    /// where it came from.
    fn use_site(&mut self, site: Site<T>, origin: LogSite) {
        self.site = site;
        self.controller.position_source_mut().set_site(site);
        self.controller.replan();
        self.site_origin = Some(origin);
        log::site(
            &mut self.log,
            origin,
            site.latitude_deg().to_f32(),
            site.longitude_deg().to_f32(),
        );
    }

    fn status_view(&self) -> StatusView {
        let axes = self.controller.axes();
        let angle = |i: usize| {
            axes.get(i)
                .filter(|a| a.has_had_reference())
                .map(|a| a.counted_deg())
        };
        StatusView {
            mode: self.last_report.map_or(Mode::WaitForTime, |r| r.mode),
            time: self.last_time,
            lat_deg: self.site.latitude_deg().to_f32(),
            lon_deg: self.site.longitude_deg().to_f32(),
            site_source: match self.site_origin {
                Some(LogSite::Gps) => LogSite::Gps,
                _ => LogSite::Config,
            },
            c_deg: angle(0),
            a_deg: angle(1),
            faults: StatusView::faults_of(self.controller.faults()),
            wind_hz: self.last_wind_hz,
        }
    }

    /// The periodic `status …` line, every `log.status_min` minutes of the
    /// monotonic clock (none when 0).
    #[inline(never)]
    fn periodic_status(&mut self, now_ms: u32) {
        // At most 1,440 minutes (the configuration's range): 86,400,000 ms.
        let every_ms =
            u32::from(self.controller.config().log.status_every_min).saturating_mul(60_000);
        if every_ms == 0 {
            self.next_status_ms = None;
            return;
        }
        let due = *self
            .next_status_ms
            .get_or_insert(now_ms.wrapping_add(every_ms));
        if monotonic::reached(now_ms, due) {
            self.next_status_ms = Some(now_ms.wrapping_add(every_ms));
            let view = self.status_view();
            self.log.flash(crate::flash_str!("status "));
            console::write_status_fields(&mut self.log, &view);
        }
    }
}

/// The firmware and its board as the console's [`Operator`].
struct FirmwareConsole<'a, T, R, G: GpsInput<T>, D, S, L, P, const N: usize, W> {
    fw: &'a mut Firmware<T, R, G, D, S, L, N, W>,
    platform: &'a mut P,
}

impl<T, R, G, D, S, L, P, const N: usize, W> Operator
    for FirmwareConsole<'_, T, R, G, D, S, L, P, N, W>
where
    T: Float,
    R: RtcDriver,
    G: GpsInput<T>,
    D: AxisDrive + Motion,
    S: AttitudeSensor<T>,
    L: Sink,
    P: Platform,
    W: Weather,
{
    fn out(&mut self) -> &mut dyn Sink {
        &mut self.fw.log
    }
    fn config(&self) -> Config {
        *self.fw.controller.config()
    }
    fn defaults(&self) -> Config {
        (self.fw.app.defaults)()
    }
    fn drives(&self) -> DriveSet {
        self.fw.app.drives
    }
    fn postal_lookup(&self) -> console::PostalLookup {
        if P::POSTAL_CODES {
            console::POSTAL_TABLE
        } else {
            None
        }
    }
    fn apply(&mut self, config: Config) -> bool {
        self.fw.apply_config(config)
    }
    fn status(&self) -> StatusView {
        self.fw.status_view()
    }
    fn write_faults(&mut self) {
        console::write_faults(&mut self.fw.log, self.fw.controller.faults());
    }
    fn begin_save(&mut self, config: &Config) -> Option<Result<(), SaveError<()>>> {
        self.platform.config_store().map(|s| s.begin_save(config))
    }
    fn load(&mut self, into: &mut Config) -> Option<LoadReport> {
        self.platform.config_store().map(|s| s.load(into))
    }
    fn set_time(&mut self, t: &UtcTime) -> Result<(), TimeSetError> {
        if self.fw.time_origin == Some(TimeOrigin::Gps) {
            return Err(TimeSetError::GpsInForce);
        }
        console::set_rtc_time(self.fw.time.rtc_mut(), t)
    }
    fn stow(&mut self, on: bool) {
        self.fw.controller.command_stow(on);
    }
    fn service(&mut self, on: bool) {
        self.fw.controller.service(on);
    }
    fn hold(&self) -> OperatorHold {
        self.fw.controller.hold()
    }
    fn home(&mut self) -> bool {
        self.fw.controller.rehome();
        true
    }
    fn jog(&mut self, axis: AxisId, deg: f32) -> Jogged {
        let c = &mut self.fw.controller;
        // In service, or in a manual mode restored after a power cut,
        // homing waits: an axis with no reference is jogged from where it
        // stands (`nudge` refuses an axis that has its reference).
        let nudged = !c.homing_allowed() && c.nudge(axis, deg);
        // Each axis's count read once for both answers.
        let [c_axis, a_axis] = c.axes();
        let (c_deg, a_deg) = (c_axis.counted_deg(), a_axis.counted_deg());
        if nudged {
            return Jogged {
                c_deg,
                a_deg,
                limited: false,
            };
        }
        let counted = Pose {
            gamma_deg: T::from_f32(c_deg),
            alpha_deg: T::from_f32(a_deg),
        };
        let mut pose = c.manual_pose().unwrap_or(counted);
        let limits = &c.config().axes;
        let (slot, lim) = match axis {
            AxisId::C => (&mut pose.gamma_deg, &limits[0]),
            AxisId::A => (&mut pose.alpha_deg, &limits[1]),
        };
        let moved = slot.to_f32() + deg;
        // Within [min_deg, max_deg] (min_deg < max_deg: the configuration
        // is validated): both bounds by comparisons, which give what
        // `moved.max(min_deg).min(max_deg)` gives, a value that is not a
        // number included (then min_deg). `f32::max` and `f32::min` link
        // library functions (138 and 130 B on the ATmega2560).
        let clamped = if moved >= lim.min_deg {
            if moved < lim.max_deg {
                moved
            } else {
                lim.max_deg
            }
        } else {
            lim.min_deg
        };
        *slot = T::from_f32(clamped);
        c.manual(Some(pose));
        Jogged {
            c_deg: pose.gamma_deg.to_f32(),
            a_deg: pose.alpha_deg.to_f32(),
            limited: clamped != moved,
        }
    }
    fn manual_off(&mut self) {
        self.fw.controller.manual(None);
    }
    fn clear(&mut self) {
        self.fw.controller.reset_faults();
    }
}

/// `ms × 1000`, saturating at `u64::MAX`: the range test, then one
/// product that cannot overflow (a `u64::saturating_mul` would check a
/// 128-bit product).
fn us_from_ms(ms: u64) -> u64 {
    if ms > u64::MAX / 1000 {
        return u64::MAX;
    }
    // ms ≤ ⌊(2^64 − 1) / 1000⌋, so ms·1000 ≤ 2^64 − 1.
    ms * 1000
}

#[cfg(test)]
mod tests {
    use super::us_from_ms;

    #[test]
    fn microseconds_are_the_product_saturated() {
        let limit = u64::MAX / 1000;
        for ms in [0, 1, 999, 1_000, 86_400_000, 1 << 32, limit - 1, limit] {
            assert_eq!(us_from_ms(ms), ms * 1000, "{ms}");
        }
        for ms in [limit + 1, 1 << 60, u64::MAX] {
            assert_eq!(us_from_ms(ms), u64::MAX, "{ms}");
        }
        // xorshift64 (Marsaglia 2003) over every magnitude.
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let ms = x >> (x % 64);
            assert_eq!(us_from_ms(ms), ms.saturating_mul(1000), "{ms}");
        }
    }
}
