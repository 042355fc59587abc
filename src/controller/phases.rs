//! The phases of [`Controller::tick`], in the order it runs them.
//!
//! On the 8-bit AVR core each phase is a function of its own (not inlined):
//! the AVR reaches a stack slot in one instruction only within 63 bytes of
//! the frame pointer, and every access to a slot farther out costs six more
//! (moving the frame pointer there and back, with the status register
//! saved): with the phases, `Controller::tick` and `Firmware::tick` in
//! frames of their own the ATmega2560 image is 5,472 B smaller than with
//! all of them in one (158,326 -> 152,854 B); the Cortex-M images keep the
//! compiler's choice. That holds for the three large phases (the set-point
//! kept current, the attitude, the mode and target); the others (time
//! health, the scheduler's action, the re-homing of a new day, homing, the
//! drive, the mode after it) are the compiler's to inline into the tick,
//! whose frame they keep within those 63 bytes: 336 B less on the
//! ATmega2560 (115,704 -> 115,368 B) than each in a frame of its own.

use sun_algos::geometry::GeometryError;
use sun_algos::{Error as SunError, Float, UtcTime};

use super::{Controller, TickInputs};
use crate::attitude::Pose;
use crate::motion::{AxisDrive, FeedbackMode, HomeState};
use crate::plan::{Action, Phase, ScheduleError};
use crate::ports::AttitudeSensor;
use crate::safety::{select_mode, Fault, Mode, ModeInputs, Weather};
use crate::sun::PositionSource;
use crate::time::monotonic;

use super::{look_ahead, AttitudeSource};

/// A swing ends when both axes are this close to its pose, degrees.
const UNWOUND_DEG: f32 = 1.0;

impl<T, P, D, S, const N: usize, W> Controller<T, P, D, S, N, W>
where
    T: Float,
    P: PositionSource<T>,
    D: AxisDrive,
    S: AttitudeSensor<T>,
    W: Weather,
{
    /// Phase 1: Time and site health: the faults of an untrusted RTC, a lost GPS
    /// fix, an implausible or unstable GPS time and an unstable GPS position.
    pub(super) fn time_health(&mut self, inp: &TickInputs) {
        let now_ms = inp.now_ms;
        // All five in one loop, in this order, rather than the first two
        // written out (32 B less on the ATmega2560).
        for (on, fault) in [
            (!inp.time_valid, Fault::RtcInvalid),
            (!inp.gps_fix, Fault::GpsLost),
            (inp.gps_time_implausible, Fault::GpsTimeImplausible),
            (inp.gps_time_unstable, Fault::GpsTimeUnstable),
            (inp.gps_position_unstable, Fault::GpsPositionUnstable),
        ] {
            if on {
                self.faults.raise(fault, now_ms);
            } else {
                self.faults.clear(fault, now_ms);
            }
        }
    }

    /// Phase 3: The scheduler's action for this tick (only with a trusted
    /// clock): a set-point, the night's home, sleep, or an error, which
    /// raises its fault. Returns whether the clock jumped and the error.
    pub(super) fn schedule(&mut self, inp: &TickInputs) -> (bool, Option<ScheduleError>) {
        let now_ms = inp.now_ms;
        let mut clock_jump = false;
        let mut schedule_error = None;
        if inp.time_valid {
            let out = self.scheduler.tick(inp.now);
            clock_jump = out.clock_jump;
            match out.action {
                Action::SetPoints(sp) => {
                    self.set_point = Some(sp);
                    // The power-on zero set-point (Jimoh & Aliyu 2019,
                    // flowchart step 1) is not daylight yet: only table
                    // set-points are.
                    self.night = !matches!(self.scheduler.phase(), Phase::Tracking { .. });
                }
                Action::GoHome(sp) => {
                    self.home_set_point = Some(sp);
                    self.night = true;
                    if self.options.rehome_nightly {
                        for ax in self.axes.iter_mut() {
                            ax.unhome();
                        }
                        self.rehomed_tonight = true;
                    }
                }
                Action::Sleep { .. } => self.night = true,
                Action::Error(e) => {
                    // No set-point for this time: the last one is not used
                    // again, and the tracker waits stowed while the
                    // scheduler retries.
                    schedule_error = Some(e);
                    self.set_point = None;
                    self.night = true;
                    let fault = match e {
                        ScheduleError::TimeRange
                        | ScheduleError::Position(SunError::OutOfValidityRange { .. })
                        | ScheduleError::Position(SunError::InvalidDate)
                        | ScheduleError::Geometry(GeometryError::Position(
                            SunError::OutOfValidityRange { .. },
                        )) => Fault::TimeOutOfRange,
                        _ => Fault::ScheduleFailed,
                    };
                    self.faults.raise(fault, now_ms);
                }
                Action::Idle => {}
            }
            if !matches!(out.action, Action::Error(_) | Action::Idle) {
                self.faults.clear(Fault::TimeOutOfRange, now_ms);
                self.faults.clear(Fault::ScheduleFailed, now_ms);
            }
        }
        (clock_jump, schedule_error)
    }

    /// Phase 3: Daylight only with a set-point computed for the present minute:
    /// the table entry applied last must be the one for now (a frozen
    /// set-point from an earlier time is never tracked).
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub(super) fn keep_set_point_current(&mut self, inp: &TickInputs) {
        let now = inp.now;
        if !self.night {
            let config = self.scheduler.config();
            let step_s = i32::try_from(config.table_step_s).unwrap_or(i32::MAX);
            let recheck_s = i32::try_from(config.recheck_s).unwrap_or(i32::MAX);
            let age_s = self
                .scheduler
                .applied()
                .and_then(|e| now.seconds_since(&e.time));
            let within = |until_s: i32| age_s.is_some_and(|a| (-60..until_s).contains(&a));
            if !within(step_s) {
                // The entry applied last is of an earlier slot (ticks were
                // missed: time unknown for a while, a slow loop, or the
                // scheduler's check for this slot is still to come): the
                // entry of the present slot when the day's table has one;
                // else the one applied last while the scheduler's next
                // check can still come (real-time mode); else nothing is
                // tracked.
                match self.scheduler.current(&now) {
                    Some(e) if inp.time_valid => self.set_point = Some(e.set_point),
                    _ if within(step_s.saturating_add(recheck_s)) => {}
                    _ => self.night = true,
                }
            }
        }
    }

    /// Phase 3: A new day without a night before it (polar day): open-loop axes
    /// are re-homed all the same, or lost steps would stay for weeks.
    pub(super) fn rehome_on_new_day(&mut self) {
        let table_day = self.scheduler.day_key();
        if table_day != self.rehome_day {
            if self.rehome_day.is_some()
                && !self.rehomed_tonight
                && self.options.rehome_nightly
                && self.options.feedback == FeedbackMode::OpenLoop
            {
                for ax in self.axes.iter_mut() {
                    ax.unhome();
                }
            }
            // The first day after power-on: the axes homed at power-on, and
            // that homing counts as tonight's (a swing on this day would
            // otherwise home them again minutes later).
            self.rehomed_tonight = self.rehome_day.is_none();
            self.rehome_day = table_day;
        }
    }

    /// Phase 4: The mount's attitude from its sensors, at the configured cadence
    /// (the first tick always).
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub(super) fn attitude_if_due(&mut self, now_ms: u32) {
        let every_ms = self.options.attitude_every_ms;
        let attitude_due = self
            .last_attitude_ms
            .as_mut()
            .is_none_or(|t| monotonic::age_ms(t, now_ms) >= every_ms);
        if self.options.attitude == AttitudeSource::Sensors && attitude_due {
            self.last_attitude_ms = Some(now_ms);
            self.update_attitude(now_ms);
        }
    }

    /// Phase 5: One homing step of each axis that needs it (none during a safe
    /// stop: nothing moves then). Returns whether an axis is homing.
    pub(super) fn homing(&mut self, now_ms: u32) -> bool {
        let mut homing = false;
        if !self.faults.must_stop() {
            for i in 0..2 {
                homing |= self.home_axis(i, now_ms);
            }
        }
        homing
    }

    /// Phase 6: The mode ([`select_mode`]) and the pose it asks for, inside the
    /// soft limits.
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub(super) fn mode_and_target(
        &mut self,
        wind_stow: bool,
        now: UtcTime,
    ) -> (Mode, Option<Pose<T>>) {
        let unhomed = self.axes.iter().any(|a| a.home_state() != HomeState::Done);
        let hold = self.config.hold;
        let mode = select_mode(&ModeInputs {
            service: hold.service,
            must_stop: self.faults.must_stop(),
            wind_stow,
            weather: self.weather.modes(),
            command_stow: hold.stow,
            manual: hold.manual,
            time_unknown: self.faults.time_unknown(),
            night: self.night,
            unhomed,
            // An unwind under way ends first: the C axis then does not
            // turn through its range again when the sky clears.
            overcast: self.weather.overcast() && !self.unwinding,
        });
        // Stow: the panel flat (α = 0), the C axis at the last commanded
        // azimuth; before any pose was commanded (just homed, no trusted
        // time yet), where the C axis is: no 180° swing from the home
        // switch to an azimuth nobody asked for.
        let gamma_now = match self.axes.first() {
            Some(c) if !self.pose_commanded && c.home_state() == HomeState::Done => {
                T::from_f32(c.counted_deg())
            }
            _ => self.pose.gamma_deg,
        };
        let stow = Pose {
            gamma_deg: gamma_now,
            alpha_deg: T::ZERO,
        };
        // A weather stow's slope, on the side of the A axis's present tilt
        // (the shorter move; the limits clamp it).
        let stow_cfg = &self.config.stow;
        let slope_deg = match mode {
            Mode::HailStow => Some(stow_cfg.hail_slope_deg),
            Mode::ExternalStow => Some(stow_cfg.external_slope_deg),
            Mode::SnowStow => Some(stow_cfg.snow_slope_deg),
            _ => None,
        };
        let weather_stow = slope_deg.map(|s| {
            let s = T::from_f32(s);
            Pose {
                gamma_deg: gamma_now,
                alpha_deg: if self.pose.alpha_deg < T::ZERO { -s } else { s },
            }
        });
        // Entering tracking, or a new day table: pick the branch of the
        // two solutions that serves the rest of the day with least travel.
        let table_day = self.scheduler.day_key();
        // The day's comparison once (`UtcTime`s compared field by field):
        // 158 B less on the ATmega2560 than written in both places.
        let new_day = table_day != self.branch_day;
        if mode == Mode::Tracking
            && (self.last_mode != Some(Mode::Tracking) || new_day)
            && self.begin_look_ahead(now)
        {
            self.branch_day = table_day;
            if new_day {
                self.day_start_pose = None;
            }
        }
        // While the day's branch is searched (a few ticks on a slow
        // board), the axes hold still.
        let choosing_branch = mode == Mode::Tracking && self.look_ahead_pending();
        let stowed = |m: Option<Mode>| {
            matches!(
                m,
                Some(
                    Mode::WindStow
                        | Mode::HailStow
                        | Mode::ExternalStow
                        | Mode::SnowStow
                        | Mode::LowSupplyStow
                        | Mode::CommandStow
                )
            )
        };
        if self.options.rehome_after_stow && stowed(self.last_mode) && !stowed(Some(mode)) {
            for ax in self.axes.iter_mut() {
                ax.unhome();
            }
        }
        // Following the sun since the last tick: a new pose far from the
        // last one is a swing (the move from a stow or the night's pose is
        // not).
        let was_tracking = self.last_mode == Some(Mode::Tracking);
        self.last_mode = Some(mode);
        // The pose for the set-point is asked for in one place (its copy
        // and call once in the code): `from_set_point` says the target is
        // that pose.
        let (target, from_set_point) = match mode {
            Mode::SafeStop | Mode::Homing => (None, false),
            Mode::WindStow | Mode::CommandStow | Mode::WaitForTime => (Some(stow), false),
            Mode::HailStow | Mode::ExternalStow | Mode::SnowStow => (weather_stow, false),
            // Flat under an overcast sky, facing all of it.
            Mode::Overcast => (Some(stow), false),
            // Flat while the motors can still move, then nothing driven.
            Mode::LowSupplyStow if self.axes_at(&stow) => (None, false),
            Mode::LowSupplyStow => (Some(stow), false),
            Mode::Manual | Mode::Service => (self.manual, false),
            Mode::Night if self.options.night_stow => (Some(stow), false),
            Mode::Night => {
                // The day's starting pose, on the branch the day used
                // (Li et al. 2022). Before any day: facing the coming
                // sunrise; failing that the power-on zero set-point
                // (Jimoh & Aliyu 2019 step 1).
                // While that search runs (a few ticks), the axes
                // wait where they are.
                let next_rise = self.scheduler.next_sunrise();
                match (self.day_start_pose, next_rise) {
                    (Some(p), _) => (Some(p), false),
                    (None, Some(rise)) => match self.pre_position(rise) {
                        None => (None, false),
                        Some(p) => (p, p.is_none()),
                    },
                    (None, None) => (None, true),
                }
            }
            // (`select_mode` never gives `Unwind`: `unwind_mode` makes it
            // of tracking.)
            Mode::Tracking | Mode::Unwind => (None, !choosing_branch),
        };
        // Whether this tick's pose is a swing from the last one, judged
        // once (the pose for a set-point lies inside the limits already).
        let mut swing = false;
        let target = if from_set_point {
            let anchored = self.branch_anchor.is_some();
            let mut p = self.set_point.and_then(|sp| self.pose_for(&sp));
            if let (Mode::Tracking, Some(q), Some(sp)) = (mode, p, self.set_point) {
                // A C axis that turns without end meets no limit: a large
                // move (from a night pose faced for another site, say) is
                // never an unwind there.
                swing = was_tracking && !self.c_is_continuous() && self.swing_from_last(&q);
                if anchored {
                    // The pose of a branch chosen on purpose.
                } else if swing {
                    // The branch followed runs into a limit here: swing
                    // once, to the branch the next 24 hours need.
                    // The axes hold still this tick; the search goes on
                    // (or ends) in the next ones, as a day's search does.
                    if !self.swing_searched {
                        self.swing_searched = true;
                        self.begin_swing_search(now, &sp);
                        p = None;
                        swing = false;
                    }
                } else {
                    self.swing_searched = false;
                }
            }
            if mode == Mode::Tracking && self.day_start_pose.is_none() {
                self.day_start_pose = p;
            }
            p
        } else {
            target
        };
        let target = target.map(|p| self.limits().clamp(&p));
        let mode = self.unwind_mode(mode, swing);
        (mode, target)
    }

    /// True when both axes have run their counts and are within
    /// [`UNWOUND_DEG`] of `pose`.
    fn axes_at(&self, pose: &Pose<T>) -> bool {
        let near = |i: usize, deg: T| {
            self.axes.get(i).is_some_and(|a| {
                a.drive().pending() == 0
                    && (T::from_f32(a.counted_deg()) - deg).abs() <= T::from_f32(UNWOUND_DEG)
            })
        };
        near(0, pose.gamma_deg) && near(1, pose.alpha_deg)
    }

    /// True when the move from the last commanded pose to `p` is a swing
    /// ([`Pose::swings_from`], [`look_ahead::SWING_DEG`]).
    fn swing_from_last(&self, p: &Pose<T>) -> bool {
        self.pose_commanded && p.swings_from(&self.pose, T::from_f32(look_ahead::SWING_DEG))
    }

    /// [`Mode::Unwind`] instead of tracking from a swing's first tick
    /// until both axes have run their counts and are within
    /// [`UNWOUND_DEG`] of the pose commanded last, before this tick's
    /// target is driven: where the C axis turns a few degrees a minute
    /// under a high sun, the next target is always further than that.
    ///
    /// Open-loop axes re-homed every day take the day's re-homing at the
    /// swing's start (the sun is as low as it gets, and on a polar day the
    /// C axis swings from its home end): homing first, then the swing from
    /// the switches, still reported as the unwind; the new day's re-homing
    /// minutes later is then not done twice.
    fn unwind_mode(&mut self, mode: Mode, swing: bool) -> Mode {
        if mode == Mode::Homing {
            return mode;
        }
        if mode != Mode::Tracking {
            self.unwinding = false;
            return mode;
        }
        if self.axes_at(&self.pose) {
            self.unwinding = false;
        }
        if swing {
            self.unwinding = true;
            if self.options.rehome_nightly
                && self.options.feedback == FeedbackMode::OpenLoop
                && !self.rehomed_tonight
            {
                for ax in self.axes.iter_mut() {
                    ax.unhome();
                }
                self.rehomed_tonight = true;
            }
        }
        if self.unwinding {
            Mode::Unwind
        } else {
            mode
        }
    }

    /// Phase 7: The axes driven to the target, or held (stopped in a safe stop).
    pub(super) fn drive(&mut self, target: Option<Pose<T>>, mode: Mode, now_ms: u32) {
        match target {
            Some(p) => {
                self.pose = p;
                // Counts once the axes can follow it (they ignore targets
                // while homing).
                self.pose_commanded |= self.axes.iter().all(|a| a.home_state() == HomeState::Done);
                self.drive_axis(0, p.gamma_deg, now_ms);
                self.drive_axis(1, p.alpha_deg, now_ms);
            }
            None => {
                // With no target the axes hold still; an axis still homing
                // goes on homing (non-blocking drives would otherwise never
                // finish it before sunrise), unless a fault asks to stop.
                let stop_all = mode == Mode::SafeStop;
                for ax in self.axes.iter_mut() {
                    if stop_all || ax.home_state() == HomeState::Done {
                        // A stop that fails leaves nothing better to do.
                        // Through the axis: the counts the drive drops are
                        // taken off its position.
                        let _ = ax.stop();
                    }
                }
            }
        }
    }

    /// A fault found while driving (a deviation, a limit switch) may have
    /// taken an axis's reference: that tick is no longer tracking.
    pub(super) fn mode_after_drive(&mut self, mode: Mode) -> Mode {
        let following = matches!(mode, Mode::Tracking | Mode::Unwind);
        if following && self.axes.iter().any(|a| a.home_state() != HomeState::Done) {
            self.last_mode = Some(Mode::Homing);
            Mode::Homing
        } else {
            mode
        }
    }
}
