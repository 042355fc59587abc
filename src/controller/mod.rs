//! The tracker's main loop: scheduler, attitude, axes and safety joined.
//!
//! [`Controller::tick`] is called periodically (once a minute in the
//! simulation, every few seconds on a board) and never blocks:
//!
//! 1. time and site health (RTC valid? GPS fix?) → faults;
//! 2. wind monitor → wind stow;
//! 3. the Jimoh & Aliyu 2019 scheduler → set-point, night, home;
//! 4. mount attitude: fixed (a level mount is the identity) or measured by
//!    the inclinometer and compass (Choi et al. (portable tracker));
//! 5. homing of axes that need it (boot, a fault, every night);
//! 6. the mode ([`crate::safety::select_mode`]) and its target pose;
//! 7. both axes driven, feedback checked for stall, deviation and
//!    unexpected limit switches.

mod look_ahead;
mod phases;

use crate::attitude::{sun_vector_xyz, MountAttitude, Pose, PoseLimits};
use crate::config::{Config, ConfigError};
use crate::motion::{
    AxisController, AxisDrive, AxisError, DriveFault, FeedbackMode, HomeState, StallVerdict,
    StallWatch,
};
use crate::plan::{ScheduleError, Scheduler, SetPoint};
use crate::ports::{AttitudeReading, AttitudeSensor};
use crate::safety::{
    AxisId, Fault, FaultManager, Mode, OperatorHold, Recovery, Sensor, StowInputs, Weather,
    WeatherConfig, WeatherWatch, WindMonitor,
};
use crate::sun::PositionSource;
use crate::time::monotonic;
use sun_algos::{Float, UtcTime};

/// Where the mount attitude comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AttitudeSource<T> {
    /// Known and fixed (a levelled, aligned mount is
    /// [`MountAttitude::level`]).
    Fixed(MountAttitude<T>),
    /// Measured every tick by the inclinometer and compass.
    Sensors,
}

/// Attitude readings in a row that may find no new compass sample before
/// the compass counts as stalled (`timeout_compass`): a part measuring at
/// 10 Hz has a sample for every reading one tick apart.
pub const ATTITUDE_NOT_READY_LIMIT: u8 = 5;

/// A command of at least this many degrees arms the axis's stall watch
/// ([`StallWatch`]); smaller ones may end inside the feedback's noise.
pub const STALL_MIN_COMMAND_DEG: f32 = 0.5;

/// Motion that proves a commanded axis is not stalled, degrees of
/// feedback, seen at the next tick.
pub const STALL_MIN_MOTION_DEG: f32 = 0.05;

/// The least monotonic time between a command that arms the stall watch
/// and a tick that judges it, ms: a tick that comes at once after a pass
/// longer than the tick interval (the firmware then runs the late tick
/// straight away) finds a drive that has not had a frame to start in (a
/// servo takes a new pulse every 20 ms); it leaves the watch armed for
/// the next tick. Half the boards' 1 s tick, so that ticks at their
/// interval judge as before.
pub const STALL_MIN_WAIT_MS: u32 = 500;

/// The C axis's limits for the choice of a pose when it turns without end
/// (`axis.c.continuous`), degrees: beyond any pose it is driven to (its
/// count is kept within a turn of the switch, its targets within half a
/// turn of that, a day's search a turn or two further).
const UNLIMITED_DEG: f32 = 10_000.0;

/// Choices of a tracker build.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControllerOptions<T> {
    /// How the axes use their encoders.
    pub feedback: FeedbackMode,
    /// Mount attitude source.
    pub attitude: AttitudeSource<T>,
    /// At night, stow flat instead of waiting at the day's start position.
    pub night_stow: bool,
    /// Re-home both axes at every end of day (open-loop drives lose steps).
    pub rehome_nightly: bool,
    /// Re-home both axes at the end of every stow (wind or command): a
    /// drive without feedback ([`crate::hw::TimedAxis`]) has only its
    /// switch to tell where it is after a long slew and a gale.
    pub rehome_after_stow: bool,
    /// Attitude readings averaged per tick.
    pub sensor_samples: u8,
    /// Weight of a new tick's attitude in the running average (1 = none);
    /// a change over 5° (the mount was moved) is taken at once.
    pub attitude_smoothing: f32,
    /// Least move of a homing step, degrees (`/ 50` on the final
    /// approach): the move a step takes when no time has passed since the
    /// previous one; otherwise homing moves at the axis's
    /// `max_speed_deg_s` for the time since (see
    /// [`AxisController::home_step`]).
    pub homing_chunk_deg: f32,
    /// Ticks between probes of an axis stopped by a stall.
    pub probe_every_ticks: u32,
    /// Sun positions computed per tick while the day is planned (0: the
    /// whole plan in one tick); see `Scheduler::set_plan_budget`.
    pub plan_positions_per_tick: u16,
    /// Read the attitude sensors at most this often, monotonic ms (0: every
    /// tick). A fixed mount does not move between reads; a slow 8-bit board
    /// saves the bus transfers and the trigonometry of every tick.
    pub attitude_every_ms: u32,
}

impl<T: Float> Default for ControllerOptions<T> {
    fn default() -> Self {
        ControllerOptions {
            feedback: FeedbackMode::ClosedLoop,
            attitude: AttitudeSource::Fixed(MountAttitude::level()),
            night_stow: false,
            rehome_nightly: true,
            rehome_after_stow: false,
            sensor_samples: 16,
            attitude_smoothing: 0.2,
            homing_chunk_deg: 1.0,
            probe_every_ticks: 10,
            plan_positions_per_tick: 0,
            attitude_every_ms: 0,
        }
    }
}

/// Why a controller could not be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ControllerError {
    /// A configuration value is out of its range (the field is named).
    Config(ConfigError),
    /// The scheduler refused its intervals or table capacity.
    Schedule(ScheduleError),
}

/// Inputs of one tick besides the devices the controller owns.
///
/// Two clocks: `now_ms` (the board's monotonic timer) measures every
/// duration — wind hold and release, fault back-off, homing retries —
/// and `now` (UTC) is used only for where the sun is and for the day's
/// schedule. A step of `now` changes neither when a stow happens nor when
/// a retry is due.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TickInputs {
    /// Monotonic time, milliseconds since an arbitrary start (boot), the
    /// low 32 bits ([`crate::time::monotonic`]); it never steps and never
    /// goes back (it wraps every 49.7 days).
    pub now_ms: u32,
    /// The wall clock's time (UTC).
    pub now: UtcTime,
    /// False when no trusted time is known (RTC lost power or holds a date
    /// outside the firmware's window, and GPS has not set it).
    pub time_valid: bool,
    /// True while GPS has a valid fix, and always on a board without a
    /// receiver (false raises `gps_lost`).
    pub gps_fix: bool,
    /// True while GPS reports a date outside the firmware's window (the
    /// week-rollover bug); its time is not used.
    pub gps_time_implausible: bool,
    /// True while GPS time disagrees with the monotonic clock between
    /// epochs (it jumps, runs backwards or alternates); not used.
    pub gps_time_unstable: bool,
    /// True while the GPS position jumps between places; the site in use
    /// is kept ([`crate::site::filter`]).
    pub gps_position_unstable: bool,
    /// Anemometer pulses since the last tick.
    pub wind_pulses: u32,
    /// Milliseconds of the monotonic clock those pulses were counted over.
    pub wind_interval_ms: u32,
    /// The snow, hail and plant-stow inputs (`None` where the board has
    /// none).
    pub stow_inputs: StowInputs,
}

/// What one tick did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TickReport<T> {
    /// The mode.
    pub mode: Mode,
    /// The pose commanded (after limits), if any.
    pub target: Option<Pose<T>>,
    /// The set-point in force.
    pub set_point: Option<SetPoint<T>>,
    /// An axis was homing.
    pub homing: bool,
    /// The scheduler saw a clock jump.
    pub clock_jump: bool,
    /// The scheduler reported an error.
    pub schedule_error: Option<ScheduleError>,
}

/// The tracker, computing in `T` (`f32` on microcontrollers, `f64` on
/// hosts), its sun from `P`, its axes driven by `D`, its attitude from `S`,
/// its day table `N` set-points long (0: real-time mode), its weather
/// stows from `W` ([`Weather`]: [`WeatherWatch`], or
/// [`crate::safety::NoWeather`] on a board without weather inputs).
///
/// Fields in this order (`repr(C)`): the small state read and written every
/// tick first, most used first, then the axes, configuration and fault
/// list, and the scheduler (its day table is most of the controller) last.
/// The AVR's `ldd`/`std` reach 63 bytes past a pointer: a field within them
/// is one instruction from `self`, one beyond needs its address computed
/// first (6 bytes). With the compiler's order the scheduler came before
/// the small state: this order is 348 B less on the ATmega2560
/// (117,116 -> 116,768 B).
#[repr(C)]
pub struct Controller<T, P, D, S, const N: usize, W = WeatherWatch> {
    attitude: MountAttitude<T>,
    set_point: Option<SetPoint<T>>,
    night: bool,
    /// A swing to another branch is under way (reported as
    /// [`Mode::Unwind`] until both axes reach its pose).
    unwinding: bool,
    /// The followed branch ran into a limit and the next 24 hours were
    /// searched for the branch to swing to (once per swing).
    swing_searched: bool,
    /// Monotonic time (ms) before which a failed homing is not retried,
    /// per axis; `None` once it has passed.
    home_retry_ms: [Option<u32>; 2],
    /// The pose an operator's `jog` asked for (manual mode, or inside the
    /// service lock); the hold flags themselves are `config.hold`.
    manual: Option<Pose<T>>,
    ticks: u32,
    pose: Pose<T>,
    /// The first tracking pose of the day (Li et al.'s (2022) home).
    day_start_pose: Option<Pose<T>>,
    /// Attitude readings in a row that found no new compass sample.
    attitude_not_ready: u8,
    /// Per axis: the stall watch, armed by a command of at least
    /// [`STALL_MIN_COMMAND_DEG`] and decided at the next tick at least
    /// [`STALL_MIN_WAIT_MS`] later.
    stall_watch: [StallWatch; 2],
    /// Re-homed at the last end of day.
    rehomed_tonight: bool,
    /// First entry time of the table seen by the re-homing check.
    rehome_day: Option<UtcTime>,
    /// Mode of the previous tick.
    last_mode: Option<Mode>,
    /// First entry time of the day table the branch was chosen for.
    branch_day: Option<UtcTime>,
    /// Starting pose of the branch chosen by look-ahead, used once.
    branch_anchor: Option<Pose<T>>,
    /// Smoothed attitude readings (θx, θy, heading sin, heading cos).
    smoothed: Option<[T; 4]>,
    /// Whether a target pose was ever driven (`pose` is then its last).
    pose_commanded: bool,
    /// When the attitude sensors were last read (monotonic ms).
    last_attitude_ms: Option<u32>,
    home_set_point: Option<SetPoint<T>>,
    axes: [AxisController<D>; 2],
    config: Config,
    faults: FaultManager,
    wind: WindMonitor,
    /// The weather watches, or none on a board without weather inputs.
    weather: W,
    options: ControllerOptions<T>,
    sensors: Option<S>,
    /// The search in progress (the module `look_ahead`): the day's branch
    /// search while tracking, or the night's for the pose facing sunrise
    /// (`night_pose` says which). One for both, as they never run at once.
    search: Option<look_ahead::PathSearch<T>>,
    /// Pose chosen to wait for a sunrise (before the first day), or none
    /// found, for that sunrise.
    night_pose: Option<look_ahead::NightPose<T>>,
    scheduler: Scheduler<T, P, N>,
}

impl<T, P, D, S, const N: usize, W> Controller<T, P, D, S, N, W>
where
    T: Float,
    P: PositionSource<T>,
    D: AxisDrive,
    S: AttitudeSensor<T>,
    W: Weather,
{
    /// A controller at power-on. `axes` are the C axis then the A axis.
    /// A configuration with a value outside its range is refused, naming
    /// the field: the axis arithmetic is proven only over the valid ranges.
    pub fn new(
        config: Config,
        options: ControllerOptions<T>,
        source: P,
        axes: [D; 2],
        sensors: Option<S>,
    ) -> Result<Self, ControllerError> {
        Self::check(&config)?;
        Ok(Self::new_checked(config, options, source, axes, sensors))
    }

    /// Whether [`Controller::new`] accepts `config`.
    pub fn check(config: &Config) -> Result<(), ControllerError> {
        config.validate().map_err(ControllerError::Config)?;
        Scheduler::<T, P, N>::check(&config.schedule).map_err(ControllerError::Schedule)
    }

    /// [`Controller::new`] for a configuration [`Controller::check`]
    /// accepted. Infallible and not inlined, so that the controller (its day
    /// table is most of an 8-bit board's RAM) is built once, in the place
    /// the caller gives it, not in a temporary first.
    #[inline(never)]
    pub fn new_checked(
        config: Config,
        options: ControllerOptions<T>,
        source: P,
        axes: [D; 2],
        sensors: Option<S>,
    ) -> Self {
        let mut scheduler = Scheduler::new_checked(config.schedule, source);
        scheduler.set_plan_budget(options.plan_positions_per_tick);
        let [dc, da] = axes;
        let attitude = match options.attitude {
            AttitudeSource::Fixed(m) => m,
            AttitudeSource::Sensors => MountAttitude::level(),
        };
        Controller {
            config,
            options,
            scheduler,
            axes: [
                AxisController::new(dc, config.axes[0]),
                AxisController::new(da, config.axes[1]),
            ],
            sensors,
            faults: FaultManager::new(config.safety),
            wind: WindMonitor::new(config.wind),
            weather: W::default(),
            attitude,
            set_point: None,
            home_set_point: None,
            night: true,
            unwinding: false,
            swing_searched: false,
            pose: Pose::default(),
            pose_commanded: false,
            manual: None,
            ticks: 0,
            home_retry_ms: [None; 2],
            last_mode: None,
            branch_day: None,
            branch_anchor: None,
            search: None,
            day_start_pose: None,
            smoothed: None,
            stall_watch: [StallWatch::new(); 2],
            last_attitude_ms: None,
            attitude_not_ready: 0,
            night_pose: None,
            rehome_day: None,
            rehomed_tonight: false,
        }
    }

    /// The configuration in force.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Puts `config` into effect while running (an operator's `set`,
    /// `load` or `defaults`): checked as [`Controller::new`] checks it, and
    /// a refused configuration changes nothing. The day is planned again
    /// when the scheduler's intervals changed; an axis whose count-to-degree scale changed homes again
    /// ([`AxisController::set_config`]); active faults keep their attempts
    /// under the new retry rules; the wind thresholds apply from the next
    /// reading. The site is the position source's (the firmware sets it).
    /// The operator's hold in force stays (it is not a setting).
    pub fn reconfigure(&mut self, mut config: Config) -> Result<(), ControllerError> {
        config.hold = self.config.hold;
        // Checked where it lies (it is this call's own): `check` would
        // copy it once more (a configuration's size on an 8-bit board's
        // stack, under the console's command).
        config.check_in_place().map_err(ControllerError::Config)?;
        Scheduler::<T, P, N>::check(&config.schedule).map_err(ControllerError::Schedule)?;
        if config.schedule != self.config.schedule {
            self.scheduler
                .set_config(config.schedule)
                .map_err(ControllerError::Schedule)?;
        }
        for (ax, c) in self.axes.iter_mut().zip(config.axes.iter()) {
            ax.set_config(*c);
        }
        self.faults.set_config(config.safety);
        self.wind.set_config(config.wind);
        self.config = config;
        Ok(())
    }

    /// The faults.
    pub fn faults(&self) -> &FaultManager {
        &self.faults
    }
    /// The wind monitor.
    pub fn wind(&self) -> &WindMonitor {
        &self.wind
    }
    /// The axis controllers (C, A).
    pub fn axes(&self) -> &[AxisController<D>; 2] {
        &self.axes
    }
    /// The axis controllers, mutable (tests and simulation drive the plants).
    pub fn axes_mut(&mut self) -> &mut [AxisController<D>; 2] {
        &mut self.axes
    }
    /// The attitude sensors.
    pub fn sensors_mut(&mut self) -> Option<&mut S> {
        self.sensors.as_mut()
    }
    /// The attitude in use.
    pub fn attitude(&self) -> MountAttitude<T> {
        self.attitude
    }
    /// The scheduler.
    pub fn scheduler(&self) -> &Scheduler<T, P, N> {
        &self.scheduler
    }
    /// The scheduler's position source (to change the site).
    pub fn position_source_mut(&mut self) -> &mut P {
        self.scheduler.source_mut()
    }
    /// Plans the day again at the next tick, after the site changed.
    pub fn replan(&mut self) {
        self.scheduler.replan();
    }
    /// Stow on an operator's command (true) or release it.
    pub fn command_stow(&mut self, on: bool) {
        self.config.hold.stow = on;
    }
    /// The operator's hold in force (what `config().hold` says).
    pub fn hold(&self) -> OperatorHold {
        self.config.hold
    }
    /// The pose jogged to in manual mode or in service, if any.
    pub fn manual_pose(&self) -> Option<Pose<T>> {
        self.manual
    }
    /// Manual override to a pose, or back to automatic with `None`. Inside
    /// the service lock a pose is what the operator jogged to, and the lock
    /// stays.
    pub fn manual(&mut self, pose: Option<Pose<T>>) {
        self.manual = pose;
        if !self.config.hold.service || pose.is_none() {
            self.config.hold.manual = pose.is_some();
        }
    }
    /// The service lock on (nothing moves but what is jogged, the axes
    /// held where they are; a manual mode ends) or off (the axes home
    /// again: hands may have moved them, and tracking follows).
    pub fn service(&mut self, on: bool) {
        if self.config.hold.service == on {
            return;
        }
        self.config.hold.service = on;
        // The lock ends a manual mode: after it the axes home and track.
        self.config.hold.manual = false;
        self.manual = None;
        if on {
            // A homing chunk or a move under way ends now.
            for ax in self.axes.iter_mut() {
                let _ = ax.stop();
            }
        } else {
            self.rehome();
        }
    }
    /// An operator's jog of an axis that has no position reference (after
    /// a power cut in service or manual mode, where homing waits): `deg`
    /// from where it stands, at most one span of its soft limits either way,
    /// counted on from there; the drive's limit switches still stop it.
    /// False when the axis has its reference (jog to a pose then) or the
    /// drive refused the move.
    pub fn nudge(&mut self, axis: AxisId, deg: f32) -> bool {
        let Some(ax) = self.axes.get_mut(axis.index()) else {
            return false;
        };
        if ax.home_state() == HomeState::Done {
            return false;
        }
        ax.nudge(deg).is_ok()
    }
    /// Whether homing may move the axes: not inside the service lock, and
    /// not in a manual mode with no pose jogged yet (restored after a power
    /// cut: the axes stay where they are). While it may not, an axis with
    /// no reference is jogged from where it stands ([`Controller::nudge`]).
    pub fn homing_allowed(&self) -> bool {
        let h = self.config.hold;
        !(h.service || (h.manual && self.manual.is_none()))
    }
    /// Operator reset after a safe stop: faults and their history are
    /// cleared and failed homing is tried again at once.
    pub fn reset_faults(&mut self) {
        self.faults.reset();
        self.home_retry_ms = [None; 2];
    }

    /// Operator command: forget both axes' references and home them again.
    pub fn rehome(&mut self) {
        for ax in self.axes.iter_mut() {
            ax.unhome();
        }
        self.home_retry_ms = [None; 2];
    }

    /// The soft limits as a pose range. Out of line on the AVR, where six
    /// callers each copied the four limits.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn limits(&self) -> PoseLimits<T> {
        let c = &self.config.axes;
        // A C axis that turns without end has no limit to meet: of the
        // poses for a sun, the one of least travel (never an unwind).
        let (gamma_min_deg, gamma_max_deg) = if self.c_is_continuous() {
            (-UNLIMITED_DEG, UNLIMITED_DEG)
        } else {
            (c[0].min_deg, c[0].max_deg)
        };
        PoseLimits {
            gamma_min_deg: T::from_f32(gamma_min_deg),
            gamma_max_deg: T::from_f32(gamma_max_deg),
            alpha_min_deg: T::from_f32(c[1].min_deg),
            alpha_max_deg: T::from_f32(c[1].max_deg),
        }
    }

    /// True when the C axis turns without end (its controller's geometry,
    /// the one place that says so).
    fn c_is_continuous(&self) -> bool {
        self.axes.first().is_some_and(|c| c.is_continuous())
    }

    /// A C axis that turns without end ([`AxisController::rebase`]): its
    /// count taken back within the turn above its switch, and every pose
    /// kept in degrees by as many turns, so that counts and poses stay in
    /// one frame (and small) however many turns the axis makes. Not while
    /// a search holds poses of its own (a few ticks). Out of line on the
    /// AVR: once a tick, not in `tick`'s frame.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn keep_c_within_a_turn(&mut self) {
        if self.search.is_some() {
            return;
        }
        let Some(c) = self.axes.first_mut() else {
            return;
        };
        let turns = c.rebase();
        if turns == 0 {
            return;
        }
        let off = T::from_i32(turns) * T::from_f32(360.0);
        let shift = |p: &mut Pose<T>| p.gamma_deg -= off;
        shift(&mut self.pose);
        for p in [
            &mut self.day_start_pose,
            &mut self.branch_anchor,
            &mut self.manual,
        ] {
            if let Some(p) = p.as_mut() {
                shift(p);
            }
        }
        if let Some(look_ahead::NightPose::Found(_, Some(p))) = self.night_pose.as_mut() {
            shift(p);
        }
        // The watch's origin was measured in the old frame.
        if let Some(w) = self.stall_watch.first_mut() {
            w.disarm();
        }
    }

    /// One pass of the main loop, phase by phase (the module docs list
    /// them); never blocks.
    // Its own frame on the AVR (see the phases module).
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn tick(&mut self, inp: &TickInputs) -> TickReport<T> {
        self.ticks = self.ticks.wrapping_add(1);
        // Self-test of .ci/panic_check.sh only (built with `--cfg
        // suntracker_panic_canary`): an index the optimiser cannot prove in
        // range puts a panic call site in this file, which the check must name.
        #[cfg(suntracker_panic_canary)]
        let _ = core::hint::black_box(self.home_retry_ms[self.ticks as usize]);
        // The monotonic clock's stamps stay true across its 32-bit wrap:
        // passed deadlines are pulled up to now.
        self.faults.catch_up(inp.now_ms);
        for t in self.home_retry_ms.iter_mut() {
            if t.is_some_and(|t| monotonic::reached(inp.now_ms, t)) {
                *t = None;
            }
        }
        // 1. Time and site health.
        self.time_health(inp);
        // 2. Wind (monotonic clock only).
        let wind_stow = self
            .wind
            .update_pulses(inp.now_ms, inp.wind_pulses, inp.wind_interval_ms);
        // Snow, hail, the plant's stow contact, the supply and the sky
        // (monotonic clock only; the sky with the sun of the set-point in
        // force by day); an impossible supply or irradiance reading is a
        // fault. Nothing of it on a board without weather inputs.
        if W::WIRED {
            let zenith_deg = self
                .set_point
                .filter(|_| !self.night)
                .map(|sp| sp.slope_deg.to_f32());
            let config = WeatherConfig {
                stow: &self.config.stow,
                supply: &self.config.supply,
                overcast: &self.config.overcast,
            };
            let (supply_fault, irradiance_fault) =
                self.weather
                    .update(&inp.stow_inputs, zenith_deg, inp.now_ms, &config);
            for (on, fault) in [
                (supply_fault, Fault::SupplyReading),
                (irradiance_fault, Fault::IrradianceReading),
            ] {
                if on {
                    self.faults.raise(fault, inp.now_ms);
                } else {
                    self.faults.clear(fault, inp.now_ms);
                }
            }
        }
        // 3. Scheduler (only with a trusted clock), daylight only with a
        // set-point for the present slot, the re-homing of a new day.
        let (clock_jump, schedule_error) = self.schedule(inp);
        self.keep_set_point_current(inp);
        self.rehome_on_new_day();
        // 4. Attitude (at the configured cadence; the first tick always).
        self.attitude_if_due(inp.now_ms);
        // 5. Homing (never during a safe stop nor in service: nothing
        // moves then).
        let homing = self.homing_allowed() && self.homing(inp.now_ms);
        // 6. Mode and target.
        let (mode, target) = self.mode_and_target(wind_stow, inp.now);
        // 7. Drive.
        self.drive(target, mode, inp.now_ms);
        self.keep_c_within_a_turn();
        let mode = self.mode_after_drive(mode);
        TickReport {
            mode,
            target,
            set_point: self.set_point,
            homing,
            clock_jump,
            schedule_error,
        }
    }

    /// The pose for a set-point with the current attitude (Choi et al.,
    /// portable tracker, eq. 13–21), least motion from the current pose.
    fn pose_for(&mut self, sp: &SetPoint<T>) -> Option<Pose<T>> {
        let sun = sun_vector_xyz(sp.elevation_deg(), sp.azimuth_deg);
        let current = match self.branch_anchor.take() {
            Some(anchor) => anchor,
            None => self.counted_pose(),
        };
        self.attitude
            .choose(&sun, &current, &self.limits())
            .ok()
            .map(|c| c.pose())
    }

    /// The pose the axes' counts say. Out of line on the AVR: three
    /// callers.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn counted_pose(&self) -> Pose<T> {
        Pose {
            gamma_deg: T::from_f32(self.axes[0].counted_deg()),
            alpha_deg: T::from_f32(self.axes[1].counted_deg()),
        }
    }

    fn update_attitude(&mut self, now_ms: u32) {
        let Some(sensors) = self.sensors.as_mut() else {
            // Measured attitude asked for but no sensor answered at power-on:
            // the last attitude (level at first) is used, and it is a fault.
            self.faults
                .raise(Fault::SensorTimeout(Sensor::Inclinometer), now_ms);
            return;
        };
        let n = self.options.sensor_samples.max(1);
        let (mut sx, mut sy, mut hs, mut hc) = (T::ZERO, T::ZERO, T::ZERO, T::ZERO);
        // At most `n` (a `u8`): one byte (40 B less on the ATmega2560 than
        // a `u32`).
        let mut ok = 0u8;
        let mut failed = false;
        for _ in 0..n {
            match sensors.read() {
                // No new sample yet (the compass measures at its data
                // rate; the next ones will not be ready either): average
                // what came.
                Err(e) if S::is_not_ready(&e) => break,
                Ok(AttitudeReading {
                    theta_x_deg,
                    theta_y_deg,
                    heading_deg,
                }) => {
                    sx += theta_x_deg;
                    sy += theta_y_deg;
                    // Headings averaged as unit vectors (359° and 1° → 0°).
                    let (s, c) = heading_deg.to_radians().sin_cos();
                    hs += s;
                    hc += c;
                    ok += 1;
                }
                Err(_) => failed = true,
            }
        }
        let fault = Fault::I2cError(Sensor::Compass);
        if failed {
            // Retry next tick; after the retries, go on with the last
            // attitude (open loop on attitude).
            self.faults.raise(fault, now_ms);
            return;
        }
        let stalled = Fault::SensorTimeout(Sensor::Compass);
        if ok == 0 {
            // Not one new sample: read again at the next tick, keeping the
            // last attitude. A compass that has stopped measuring (never
            // ready ATTITUDE_NOT_READY_LIMIT times in a row) is a fault.
            self.attitude_not_ready = self.attitude_not_ready.saturating_add(1);
            if self.attitude_not_ready >= ATTITUDE_NOT_READY_LIMIT {
                self.faults.raise(stalled, now_ms);
            }
            self.last_attitude_ms = None;
            return;
        }
        self.attitude_not_ready = 0;
        self.faults.clear(stalled, now_ms);
        let k = T::from_u32(u32::from(ok));
        // The averages, smoothed in place: one array in the frame rather
        // than copies of the old and new ones (the frame stays nearer the
        // 63 bytes `ldd`/`std` reach on the AVR).
        let mut avg = [sx, sy, hs, hc];
        // One division in a loop rather than four written out.
        for a in avg.iter_mut() {
            *a /= k;
        }
        let w = T::from_f32(self.options.attitude_smoothing.clamp(0.0, 1.0));
        // A change over 5° (or ~5° of heading: 0.09 of a unit vector) is a
        // moved mount, taken at once.
        let (tilt_jump, heading_jump) = (T::from_f64(5.0), T::from_f64(0.09));
        // Loops over the four averages rather than four written-out copies
        // of the f32 calls (32 B less on the ATmega2560); every comparison
        // is evaluated, as none has a side effect.
        if let Some(old) = &self.smoothed {
            let mut steady = true;
            for (i, (&m, &o)) in avg.iter().zip(old).enumerate() {
                // The first two are tilts, the last two the heading's vector.
                let jump = if i < 2 { tilt_jump } else { heading_jump };
                steady &= (m - o).abs() < jump;
            }
            if steady {
                for (a, &o) in avg.iter_mut().zip(old) {
                    *a = o + w * (*a - o);
                }
            }
        }
        self.smoothed = Some(avg);
        let [sx, sy, hs, hc] = avg;
        let cal = &self.config.calibration;
        let heading = Float::atan2(hs, hc).to_degrees()
            + T::from_f32(cal.declination_deg)
            + T::from_f32(cal.heading_offset_deg);
        match MountAttitude::from_sensors(
            sx - T::from_f32(cal.tilt_x_offset_deg),
            sy - T::from_f32(cal.tilt_y_offset_deg),
            Float::rem_euclid(heading, T::from_f64(360.0)),
        ) {
            Ok(m) => {
                self.attitude = m;
                self.faults.clear(fault, now_ms);
            }
            Err(_) => {
                self.faults.raise(fault, now_ms);
            }
        }
    }

    fn axis_id(i: usize) -> AxisId {
        if i == 0 {
            AxisId::C
        } else {
            AxisId::A
        }
    }

    /// Runs homing steps of axis `i` at `now_ms`: the first moves for the
    /// time since the previous tick at the axis's speed, and more follow
    /// (one chunk each) while the drive finishes them at once. Returns true
    /// while homing.
    ///
    /// A homing run that cannot find its switch (stuck closed: the axis
    /// cannot back away from it within the bounded back-off; stuck open:
    /// a whole travel without it) raises [`Fault::LimitSwitchHit`] once per
    /// failed attempt; the next attempt waits for the fault's back-off on
    /// the monotonic clock, and after the configured retries the fault's
    /// final recovery (a safe stop) ends the attempts.
    fn home_axis(&mut self, i: usize, now_ms: u32) -> bool {
        let id = Self::axis_id(i);
        let chunk = self.options.homing_chunk_deg;
        let wait_until = self.home_retry_ms.get(i).copied().flatten();
        // On the AVR the axis is chosen of the two, not addressed by `i`
        // times its size: LLVM's AVR backend was seen to let the
        // status-register save of a far stack access overwrite that product
        // in r0 before it was read here (.ci/avr_codegen_check.py). The
        // Cortex-M images keep the index (488 B smaller there).
        #[cfg(target_arch = "avr")]
        let axis = match i {
            0 => self.axes.first_mut(),
            1 => self.axes.last_mut(),
            _ => None,
        };
        #[cfg(not(target_arch = "avr"))]
        let axis = self.axes.get_mut(i);
        let Some(ax) = axis else {
            return false;
        };
        if ax.home_state() == HomeState::Done {
            return false;
        }
        // Homing moves the axis on its own: the last tracking command says
        // nothing about a stall any more.
        if let Some(w) = self.stall_watch.get_mut(i) {
            w.disarm();
        }
        if wait_until.is_some_and(|t| !monotonic::reached(now_ms, t)) {
            return true; // waiting before another attempt
        }
        if ax.drive().self_watched() && drive_watch(&mut self.faults, ax.drive_mut(), id, now_ms) {
            return true; // a latched motor fault waits for its retry
        }
        // Bounded: a whole travel at the fine step is ≤ 50 × 370 chunks.
        // Counted in 16 bits, not the default `i32` (36 B less on the
        // ATmega2560).
        for _ in 0..20_000u16 {
            // Inline: with the axis's state first in `AxisController` its
            // temporaries stay within the 63 bytes `ldd`/`std` reach on the
            // AVR (out of line it was 128 B more on the ATmega2560).
            match ax.home_step(chunk, now_ms) {
                Ok(HomeState::Done) => {
                    // A reference regained ends the faults that asked for it.
                    self.faults.clear(Fault::LimitSwitchHit(id), now_ms);
                    self.faults.clear(Fault::SetPointDeviation(id), now_ms);
                    return false;
                }
                Ok(_) => {
                    if ax.drive().pending() != 0 {
                        return true; // out of motion time this tick
                    }
                }
                Err(AxisError::HomeNotFound) => {
                    // Stuck switch or blocked axis: one more failed
                    // attempt; the next one waits for the back-off.
                    self.faults.raise(Fault::LimitSwitchHit(id), now_ms);
                    let next = self
                        .faults
                        .get(Fault::LimitSwitchHit(id))
                        .map_or(now_ms, |a| a.next_attempt_ms);
                    if let Some(t) = self.home_retry_ms.get_mut(i) {
                        *t = Some(next);
                    }
                    return true;
                }
                Err(_) if ax.drive().self_watched() && ax.drive().fault_latched() => {
                    drive_watch(&mut self.faults, ax.drive_mut(), id, now_ms);
                    return true;
                }
                Err(_) => {
                    self.faults
                        .raise(Fault::I2cError(Sensor::Encoder(id)), now_ms);
                    return true;
                }
            }
        }
        true
    }

    fn drive_axis(&mut self, i: usize, target_deg: T, now_ms: u32) {
        let id = Self::axis_id(i);
        let max_dev = self.config.safety.max_deviation_deg;
        let enc_fault = Fault::SensorTimeout(Sensor::Encoder(id));
        let stall = Fault::MotorStalled(id);
        let probe_every = self.options.probe_every_ticks.max(1);
        let ticks = self.ticks;
        let disabled = self.faults.axis_disabled(id);
        // A fault has one record at most (`FaultManager::raise` updates
        // the one it finds): its own is the one to look at.
        let enc_degraded = self
            .faults
            .get(enc_fault)
            .is_some_and(|a| a.recovery == Recovery::DegradeOpenLoop);
        let Some(ax) = self.axes.get_mut(i) else {
            return;
        };
        if ax.home_state() != HomeState::Done {
            return;
        }
        // A stalled axis is left alone, but probed now and then.
        if disabled && !ticks.is_multiple_of(probe_every) {
            return;
        }
        if ax.drive().self_watched() && drive_watch(&mut self.faults, ax.drive_mut(), id, now_ms) {
            return; // a latched motor fault waits for its retry
        }
        // Unexpected limit switch: closed far from the home angle (within
        // the turn on an axis that turns without end: it passes its
        // switch once a turn).
        let above_home_deg = ax.above_home_deg();
        match ax.drive_mut().at_limit() {
            Ok(true) if above_home_deg > 2.0 => {
                let _ = ax.stop();
                if let Recovery::Rehome(_) = self.faults.raise(Fault::LimitSwitchHit(id), now_ms) {
                    ax.unhome();
                }
                return;
            }
            _ => {}
        }
        // The encoder is read whenever one is configured, so that its
        // return is noticed; while degraded its value is not used.
        let has_feedback = self.options.feedback != FeedbackMode::OpenLoop;
        let mode = if has_feedback && !enc_degraded {
            self.options.feedback
        } else {
            FeedbackMode::OpenLoop
        };
        let read = |ax: &mut AxisController<D>, faults: &mut FaultManager| -> Option<f32> {
            if !has_feedback {
                return None;
            }
            match ax.drive_mut().encoder_deg() {
                Ok(v) => {
                    faults.clear(enc_fault, now_ms);
                    if enc_degraded {
                        None
                    } else {
                        // In the turn the count is in (an axis that turns
                        // without end).
                        v.map(|d| ax.near_count(d))
                    }
                }
                Err(_) => {
                    faults.raise(enc_fault, now_ms);
                    None
                }
            }
        };
        // Closed loop: a few corrections per tick, each checked for motion.
        // A byte, not the default `i32` (84 B less on the ATmega2560).
        let passes: u8 = if mode == FeedbackMode::ClosedLoop {
            3
        } else {
            1
        };
        let target = target_deg.to_f32();
        let mut last_dev = None;
        // Stall: the previous command was long enough to be seen, but the
        // encoder has not moved since (one tick later, whatever the speed,
        // and at least STALL_MIN_WAIT_MS later: until then the watch
        // stays armed as it was).
        let first = read(ax, &mut self.faults);
        let watch = match self.stall_watch.get_mut(i) {
            Some(w) => w,
            None => return,
        };
        match first.and_then(|d| watch.check(d, now_ms, STALL_MIN_MOTION_DEG, STALL_MIN_WAIT_MS)) {
            // Retry is simply commanding again below.
            Some(StallVerdict::Stalled) => {
                self.faults.raise(stall, now_ms);
                watch.disarm();
            }
            // Moved: the watch restarted where it was seen.
            Some(StallVerdict::Moving) => {
                self.faults.clear(stall, now_ms);
                watch.disarm();
            }
            Some(StallVerdict::Waiting) => {}
            None => watch.disarm(),
        }
        for pass in 0..passes {
            let before = if pass == 0 {
                first
            } else {
                read(ax, &mut self.faults)
            };
            let report = match ax.update(target, mode, before) {
                Ok(r) => r,
                Err(AxisError::NotHomed) => return,
                // Refused: the motor's watch tripped during this tick's
                // moves (raised below).
                Err(_) if ax.drive().self_watched() && ax.drive().fault_latched() => break,
                Err(_) => {
                    self.faults
                        .raise(Fault::I2cError(Sensor::Encoder(id)), now_ms);
                    return;
                }
            };
            last_dev = report.deviation_deg;
            if report.commanded_counts == 0 {
                break;
            }
            if pass == 0 {
                // Counts are at most 10^9 (configuration ranges): f32
                // keeps them to 7 digits, plenty for "was it ≥ 0.5°".
                let cmd_deg = report.commanded_counts as f32 / ax.counts_per_deg();
                // A drive that watches its own motor (a DC axis: no pulse
                // while driven) is not judged a tick later: it may still be
                // settling from its last stop or ramping up, and its own
                // watch raises the stall (`drive_watch` below).
                let watched = ax.drive().self_watched();
                // A watch still waiting for its verdict keeps the first
                // command's angle and time: commanded again at every tick
                // that comes sooner, it would never be judged.
                if let (Some(b), Some(w)) = (
                    before.filter(|_| !watched && cmd_deg.abs() >= STALL_MIN_COMMAND_DEG),
                    self.stall_watch.get_mut(i),
                ) {
                    if !w.is_armed() {
                        w.arm(b, now_ms);
                    }
                }
            }
            if let Some(a) = read(ax, &mut self.faults) {
                last_dev = Some(a - report.target_deg);
            }
        }
        if ax.drive().self_watched() {
            // What the motor's watch saw during this tick's moves; a move
            // done without one ends a stall, an obstruction, unexpected
            // motion or a slow move.
            // A latched fault explains the deviation: it is not a lost
            // reference.
            let drive = ax.drive_mut();
            raise_drive_fault(&mut self.faults, drive, id, now_ms);
            if drive.fault_latched() {
                return;
            }
            if drive.pending() == 0 {
                self.faults.clear(Fault::MotorStalled(id), now_ms);
                self.faults.clear(Fault::Obstruction(id), now_ms);
                self.faults.clear(Fault::UnexpectedMotion(id), now_ms);
                self.faults.clear(Fault::MoveTimeout(id), now_ms);
            }
        }
        if let Some(dev) = last_dev {
            if dev.abs() > max_dev && ax.drive().pending() == 0 {
                if let Recovery::Rehome(_) = self.faults.raise(Fault::SetPointDeviation(id), now_ms)
                {
                    ax.unhome();
                }
            } else if dev.abs() <= max_dev {
                self.faults.clear(Fault::SetPointDeviation(id), now_ms);
            }
        }
    }
}

/// Raises the fault the drive saw itself since it was last asked, if any.
fn raise_drive_fault<D: AxisDrive>(
    faults: &mut FaultManager,
    drive: &mut D,
    id: AxisId,
    now_ms: u32,
) {
    let fault = match drive.take_fault() {
        None => return,
        Some(DriveFault::Stall) => Fault::MotorStalled(id),
        Some(DriveFault::Obstruction) => Fault::Obstruction(id),
        Some(DriveFault::UnexpectedMotion) => Fault::UnexpectedMotion(id),
        Some(DriveFault::TooSlow) => Fault::MoveTimeout(id),
    };
    faults.raise(fault, now_ms);
}

/// For a drive that watches its own motor ([`AxisDrive::self_watched`]):
/// raises what the watch saw, and returns true while a latched fault
/// (stall, obstruction, move timeout) waits for its retry, leaving the
/// axis alone. When the fault manager's back-off for it has passed (or the
/// fault was cleared by the operator), the drive's fault is cleared and the
/// axis is commanded again: the retry, counted as one more attempt if it
/// trips again.
fn drive_watch<D: AxisDrive>(
    faults: &mut FaultManager,
    drive: &mut D,
    id: AxisId,
    now_ms: u32,
) -> bool {
    raise_drive_fault(faults, drive, id, now_ms);
    if !drive.fault_latched() {
        return false;
    }
    let due = [
        Fault::Obstruction(id),
        Fault::MotorStalled(id),
        Fault::MoveTimeout(id),
    ]
    .into_iter()
    .filter_map(|f| faults.get(f))
    .all(|a| a.retry_due(now_ms));
    if due {
        drive.clear_fault();
    }
    !due
}
