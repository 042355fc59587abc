//! Chowdhury et al.'s (2019) closed-loop tracker, board-independent: its
//! mechanics (two FEETECH FS5106R continuous-rotation servos, a YMT22
//! optical encoder on each shaft) and its loop, over any RTC and any pair of
//! closed-loop [`AxisDrive`]s. The Arduino Uno image (the `suntracker-uno` board crate) runs
//! it on the ATmega328P's peripherals; the host tests run it on models.
//!
//! The loop is the paper's (its §2 and Figure 1(b)), built from the library's
//! parts that fit the ATmega328P's 32 KB next to the sun algorithm: the
//! homing and the counted position of [`AxisController`], the stall watch
//! [`StallWatch`], the mode choice [`select_mode`], the sun source
//! [`BoardSource`], the time keeper [`TimeKeeper`]: the same code as every
//! other board's.
//!
//! | the paper | here |
//! |---|---|
//! | DS3231 / DS1302 clock | [`TimeKeeper`] and [`drivers::rtc`]: lost power, no answer or a date outside the window → no time: panel flat, `mode wait_for_time`, `fault rtc_invalid` (or `bus_rtc`) |
//! | the Astronomical Almanac's algorithm on the microcontroller, no table (the paper gives no interval) | one sun position at the start of each 4-minute slot ([`STEP_S`]) from [`SunSource`] (`michalsky`, or `psa-2020` with the `psa2020` feature), in `f32`; the sun below the horizon: night, panel flat |
//! | servos to the computed angles; encoders so that "if any deviation occurred, the controller would fix that" | per axis a closed-loop [`AxisDrive`] (on the Uno [`crate::hw::ServoAxis`]: the drivers' proportional controller on the encoder count, every loop pass), commanded in encoder counts from its home switch |
//! | panel voltage on the ADC, area under the curve (V·h) | [`crate::panel`]: `panel_mv=` on each `setpoint` line, `day_energy vh=` at sunset |
//!
//! The library's [`crate::controller::Controller`] (its scheduler, axis
//! controllers, fault manager and inverse kinematics) does not fit this
//! part: built for the ATmega328P with its GPS, console and `f64` paths
//! compiled out it links to 80–94 KB, by what is inlined.
//!
//! **Homing.** At power-on each axis homes with
//! [`AxisController::home_step`], once a tick: it seeks its home switch
//! (at its lowest angle) at the axis's speed plus a [`HOMING_CHUNK_DEG`]
//! lead (the drive stops as the switch closes), backs off and comes back
//! [`crate::motion::HOMING_FINE_DIVISOR`] times slower, so that the count
//! where the switch closes is taken at the slowest speed: that count is the
//! switch angle. A switch not found within the axis travel plus
//! [`crate::motion::HOMING_SEEK_EXTRA_DEG`] (stuck open, unplugged), or one
//! that does not open within [`crate::motion::HOMING_BACKOFF_MAX_DEG`]
//! backing off (stuck closed), raises `limit_switch_c|a` and the axis stays
//! stopped: a person checks it (a reset homes again).
//!
//! **Stall.** A drive with a move pending whose encoder shows no half count
//! of motion for [`STALL_TIMEOUT_MS`] ([`StallWatch`]) is stopped and
//! raises `motor_stalled_c|a`; it is commanded again every
//! [`STALL_RETRY_MS`], and the first count of motion clears the fault. The
//! durations run on the monotonic clock: an RTC step never delays them.
//!
//! **Pose.** The mount is level with its C axis vertical and its y axis
//! toward south, so the attitude module's inverse kinematics
//! ([`crate::attitude::MountAttitude::solutions`], Choi et al. (portable tracker)
//! eq. 18–21, with the identity attitude) reduce to two closed forms with
//! the same panel normal: `c = 180° − azimuth, a = −zenith` and `c =
//! −azimuth, a = +zenith`. Which one serves the whole day is chosen from
//! the side the sun transits on (its azimuth at local mean noon): south,
//! the first (the azimuth never crosses north, so `c` never wraps); north,
//! the second (it never crosses south). The C axis then turns continuously
//! all day within −180…+180°, at the cost of one sun position a day. At
//! night and while waiting for time the panel lies flat (`a = 0`), C where
//! it is.

pub mod settings;

use drivers::rtc::Clock as RtcDriver;
use drivers::servo::{PositionController, ServoConfig};
use sun_algos::{Algorithm, Error as SunError, Site, UtcTime};

use crate::config::AxisConfig;
use crate::firmware::Motion;
use crate::log::{self, Sink};
use crate::motion::{AxisController, AxisDrive, AxisError, HomeState, StallVerdict, StallWatch};
use crate::panel::{self, DayEnergy};
use crate::safety::{select_mode, AxisId, Fault, Mode, ModeInputs, Sensor};
use crate::sun::{BoardSource, BuiltInAlgorithm, PositionSource};
use crate::text::FlashStr;
use crate::time::monotonic;
use crate::time::TimeOrigin;
use crate::time::{TimeConfig, TimeKeeper};

/// Encoder lines per revolution: the YMT22's "up to 300 ppr" (Chowdhury et al. 2019, Table
/// 1), read in quadrature: 4 counts a line.
pub const ENCODER_LINES: u32 = 300;
/// Encoder counts per shaft turn (4 × 300 = 1,200: 0.3° a count).
pub const COUNTS_PER_TURN: u32 = 4 * ENCODER_LINES;
/// The encoder sits on the servo's output shaft, which turns the axis
/// directly (Chowdhury et al. 2019, §2: "optical encoders were attached to the shaft of each
/// motor").
pub const GEAR_RATIO: f32 = 1.0;
/// Set-point interval: 4 minutes, the table step of Jimoh & Aliyu (2019);
/// Chowdhury et al. (2019) do not say how often they compute the sun.
pub const STEP_S: u32 = 240;
/// Monotonic milliseconds between two ticks (an RTC read each).
pub const TICK_MS: u32 = 1_000;
/// Homing's lead, degrees of servo shaft (divided by the gear for the
/// axis): each homing step keeps this much more than a tick's travel at
/// the homing speed queued (see [`AxisController::home_step`]).
pub const HOMING_CHUNK_DEG: f32 = 10.0;
/// Homing speed, degrees of servo shaft a second (divided by the gear for
/// the axis; the `max_speed_deg_s` of [`axis_configs_geared`]). The
/// FS5106R turns 570 °/s, far faster than this: homing here is paced by
/// the [`HOMING_CHUNK_DEG`] lead queued each 1 s tick (10.5° a tick
/// seeking: a whole turn in 35 ticks), and the speed term only matters on
/// the final approach, which moves a fiftieth of both a step:
/// (0.5 × dt + 10) / 50 degrees, one encoder count (0.3°) for any interval
/// dt up to 25 s between two steps. The position loop drives a one-count
/// error at its minimum speed (0.02 of full, some 8 °/s) and stops at the
/// switch within the 20 ms servo frame; a two-count step (a by-time term
/// of 7.5 °/s and a step 1.7 s after the last) ran the servo a count past
/// the switch in the emulator, and every set-point after it a count low.
pub const HOMING_SPEED_DEG_S: f32 = 0.5;
/// A pending move without a count of motion for this long is a stall
/// (monotonic ms): at the slowest approach speed the shaft passes a count
/// in well under a second.
pub const STALL_TIMEOUT_MS: u32 = 5_000;
/// A stalled axis is commanded again this often (monotonic ms).
pub const STALL_RETRY_MS: u32 = 60_000;
/// ΔT (TT − UT1) for the sun algorithm, seconds (2026, IERS Bulletin A
/// order of magnitude).
pub const DELTA_T_S: f32 = 69.0;
/// Milliseconds in a day.
const MS_PER_DAY: u32 = 86_400_000;

/// The axes (C then A): C turns −180…+180° from its home switch at −180°,
/// A tilts −90…+90° from its home at −90°; one encoder count is 0.3°.
///
/// A copy of a table in program memory: built in code, each field written
/// was its own instructions (830 B in the Uno's single image).
pub fn axis_configs() -> [AxisConfig; 2] {
    AXES.load()
}

crate::progmem! {
    /// [`axis_configs`].
    static AXES: [AxisConfig; 2] = axis_configs_geared([GEAR_RATIO; 2]);
}

/// The axes of [`axis_configs`] with a gear of `gear_ratio` (C, A) servo
/// turns per axis turn between each servo and its axis (the encoder on the
/// servo's shaft): a count is `0.3° / gear` of axis; homing runs at
/// [`HOMING_SPEED_DEG_S`]` / gear`.
pub const fn axis_configs_geared(gear_ratio: [f32; 2]) -> [AxisConfig; 2] {
    let [gear_c, gear_a] = gear_ratio;
    [
        servo_axis(gear_c, -180.0, 180.0),
        servo_axis(gear_a, -90.0, 90.0),
    ]
}

/// One servo axis of [`axis_configs_geared`]: the home switch at the
/// lowest angle; a ratio below 1, outside the configuration's range,
/// counts as 1.
const fn servo_axis(gear: f32, min_deg: f32, max_deg: f32) -> AxisConfig {
    AxisConfig {
        counts_per_motor_rev: COUNTS_PER_TURN,
        microsteps: 1,
        gear_ratio: gear,
        min_deg,
        max_deg,
        home_deg: min_deg,
        backlash_deg: 0.0,
        max_speed_deg_s: HOMING_SPEED_DEG_S / if gear >= 1.0 { gear } else { 1.0 },
        deadband_deg: 0.0,
        continuous: 0,
        drive: crate::config::DriveKind::ServoEncoder as u8,
        // The current watch's defaults (DC axes only).
        ..crate::config::Config::DEFAULT.axes[0]
    }
}

/// The FS5106R's pulses: 1,500 µs stop, 700 µs and 2,300 µs full speed
/// either way (FEETECH's control range), 50 Hz.
pub const SERVO: ServoConfig = ServoConfig {
    period_us: 20_000,
    min_pulse_us: 700,
    neutral_us: 1_500,
    max_pulse_us: 2_300,
};

/// The position loop on the encoder count. The servo takes a new pulse
/// every 20 ms frame, so the last counts are approached slowly enough to
/// stop within one: at the minimum speed (0.02 of full = 16 µs from
/// neutral, about 8 °/s past the FS5106R's ±4 µs dead band) the shaft turns
/// 0.16° a frame, half a count; full speed from 50 counts (15°) out.
pub const POSITION_LOOP: PositionController = PositionController {
    kp_per_count: 0.02,
    deadband_counts: 0,
    max_speed: 1.0,
    min_speed: 0.02,
};

/// The algorithm this build computes with: Chowdhury et al.'s (2019).
#[cfg(not(feature = "psa2020"))]
pub type BuildAlgorithm = crate::sun::Michalsky;
/// The algorithm this build computes with (feature `psa2020`).
#[cfg(feature = "psa2020")]
pub type BuildAlgorithm = crate::sun::Psa2020;
/// [`BuildAlgorithm`]'s algorithm.
pub const ALGORITHM: Algorithm = <BuildAlgorithm as BuiltInAlgorithm>::ALGORITHM;
/// [`ALGORITHM`]'s name (`Algorithm::name`), kept in flash on AVR.
#[cfg(not(feature = "psa2020"))]
pub const ALGORITHM_NAME: FlashStr = crate::flash_str!("michalsky");
/// [`ALGORITHM`]'s name (`Algorithm::name`), kept in flash on AVR.
#[cfg(feature = "psa2020")]
pub const ALGORITHM_NAME: FlashStr = crate::flash_str!("psa-2020");

/// The sun at one site in `f32` with [`ALGORITHM`] and ΔT [`DELTA_T_S`]:
/// the source every board's loop uses.
pub type SunSource = BoardSource<f32, BuildAlgorithm>;

/// Local mean time's offset from UTC at `site`, ms: 240 s per degree east.
fn offset_ms(site: &Site<f32>) -> i32 {
    // |longitude| ≤ 180° (Site::new): at most 43,200,000 ms.
    (site.longitude_deg() * 240_000.0) as i32
}

/// The local mean solar day at `site` that `time` falls in (days since
/// 2000).
pub fn solar_day(site: &Site<f32>, time: &UtcTime) -> i32 {
    let local_ms = i64::from(time.ms_of_day()) + i64::from(offset_ms(site));
    let shift = if local_ms < 0 {
        -1
    } else if local_ms >= i64::from(MS_PER_DAY) {
        1
    } else {
        0
    };
    time.days_since_2000().saturating_add(shift)
}

/// Local mean noon at `site` of solar day `day`, UTC.
pub fn noon(site: &Site<f32>, day: i32) -> Result<UtcTime, SunError> {
    let ms = 43_200_000 - offset_ms(site);
    // 43.2 M ± 43.2 M ms: within one day either side.
    let (day, ms) = if ms < 0 {
        (day.saturating_sub(1), ms + MS_PER_DAY as i32)
    } else if ms >= MS_PER_DAY as i32 {
        (day.saturating_add(1), ms - MS_PER_DAY as i32)
    } else {
        (day, ms)
    };
    UtcTime::from_days_ms(day, ms.unsigned_abs())
}

/// Which closed form of the level mount's pose serves the day (see the
/// module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Branch {
    /// The sun transits south: `c = 180° − azimuth`, `a = −zenith`.
    South,
    /// The sun transits north: `c = −azimuth`, `a = +zenith`.
    North,
}

impl Branch {
    /// The branch for a day whose noon sun is at `noon_azimuth_deg`.
    pub fn for_noon(noon_azimuth_deg: f32) -> Branch {
        // South of the east–west line: cos(azimuth) < 0.
        if (90.0..270.0).contains(&noon_azimuth_deg) {
            Branch::South
        } else {
            Branch::North
        }
    }

    /// The pose `(c, a)` in degrees facing the sun at `zenith_deg`,
    /// `azimuth_deg` (in [0°, 360°)); `c` in (−180°, 180°].
    pub fn pose_deg(self, zenith_deg: f32, azimuth_deg: f32) -> (f32, f32) {
        let (c, a) = match self {
            Branch::South => (180.0 - azimuth_deg, -zenith_deg),
            Branch::North => (-azimuth_deg, zenith_deg),
        };
        // c in (−360°, 180°]: one turn brings it in range.
        (if c <= -180.0 { c + 360.0 } else { c }, a)
    }
}

/// One axis: the library's [`AxisController`] (homing, soft limits, the
/// counted position) over a closed-loop drive, and the shared
/// [`StallWatch`].
#[derive(Debug)]
struct ServoLoopAxis<D> {
    axis: AxisController<D>,
    /// [`HOMING_CHUNK_DEG`] through the gear, degrees of axis.
    homing_chunk_deg: f32,
    /// Homing found no switch within the travel, or one that stayed
    /// closed (`limit_switch_*`): the axis stays stopped.
    lost: bool,
    /// Armed while a move is under way.
    stall: StallWatch,
    /// Stopped for a stall: the low 32 bits of the monotonic ms when it
    /// stopped (the retry's wait wraps correctly below 49.7 days).
    stalled_at: Option<u32>,
    /// `motor_stalled_*` is raised (until motion is seen).
    stall_raised: bool,
}

impl<D: AxisDrive> ServoLoopAxis<D> {
    fn new(drive: D, c: &AxisConfig) -> Self {
        ServoLoopAxis {
            axis: AxisController::new(drive, *c),
            homing_chunk_deg: HOMING_CHUNK_DEG
                / if c.gear_ratio >= 1.0 {
                    c.gear_ratio
                } else {
                    1.0
                },
            lost: false,
            stall: StallWatch::new(),
            stalled_at: None,
            stall_raised: false,
        }
    }

    /// One step of the library's homing ([`AxisController::home_step`]:
    /// seek at the axis's speed, back off and come back
    /// [`crate::motion::HOMING_FINE_DIVISOR`] times slower; the drive
    /// stops as the switch closes); true while homing goes on. A switch
    /// not found within the travel, or one that does not open backing off,
    /// leaves the axis stopped and `lost`.
    #[inline(never)]
    fn home_step(&mut self, now_ms: u32) -> bool {
        if self.lost || self.axis.home_state() == HomeState::Done {
            return false;
        }
        match self.axis.home_step(self.homing_chunk_deg, now_ms) {
            Ok(HomeState::Done) => {
                // Counted from the switch as the encoder counts: the
                // count where it last read closed.
                if let Ok(Some(e)) = self.axis.drive_mut().encoder_deg() {
                    self.axis.reanchor(e);
                }
                false
            }
            Ok(_) => true,
            Err(AxisError::HomeNotFound) => {
                let _ = self.axis.stop();
                self.lost = true;
                false
            }
            // The drive did not answer: the next tick tries again.
            Err(_) => true,
        }
    }

    /// Commands `deg`, watching for a stall; returns the stall flag's
    /// change (`Some(true)` raised, `Some(false)` cleared). A drive with a
    /// move pending whose encoder shows no half count of motion for
    /// [`STALL_TIMEOUT_MS`] is stopped and commanded again after
    /// [`STALL_RETRY_MS`].
    #[inline(never)]
    fn drive_to(&mut self, deg: f32, now_ms: u32) -> Option<bool> {
        if self.axis.home_state() != HomeState::Done {
            return None;
        }
        if let Some(at) = self.stalled_at {
            if monotonic::elapsed_ms(now_ms, at) < STALL_RETRY_MS {
                return None;
            }
            self.stalled_at = None;
        }
        let mut change = None;
        match self.axis.drive_mut().encoder_deg().ok().flatten() {
            Some(e) => {
                let moving = self.axis.drive().pending() != 0;
                let half_count_deg = 0.5 / self.axis.counts_per_deg();
                match self
                    .stall
                    .check(e, now_ms, half_count_deg, STALL_TIMEOUT_MS)
                {
                    // Motion clears the fault, even a move that ended
                    // within the tick.
                    Some(StallVerdict::Moving) if self.stall_raised => {
                        self.stall_raised = false;
                        change = Some(false);
                    }
                    Some(StallVerdict::Stalled) if moving => {
                        // The drive now holds where it is: count from the
                        // encoder, as after homing.
                        let _ = self.axis.stop();
                        self.axis.reanchor(e);
                        self.stall.disarm();
                        self.stalled_at = Some(now_ms);
                        if self.stall_raised {
                            return None;
                        }
                        self.stall_raised = true;
                        return Some(true);
                    }
                    _ => {}
                }
                // At rest (or not watched yet): the next move is timed
                // from here and now.
                if !moving || !self.stall.is_armed() {
                    self.stall.arm(e, now_ms);
                }
            }
            None => self.stall.disarm(),
        }
        // Within the soft limits, counted from the switch; the encoder
        // closes the loop inside the drive, so the count is open loop here.
        // A drive that fails keeps its count and is commanded again next
        // pass.
        let _ = self.axis.move_to(deg);
        change
    }

    /// The commanded angle, degrees.
    fn commanded_deg(&self) -> f32 {
        self.axis.counted_deg()
    }
}

/// The tracker: Chowdhury et al.'s (2019) loop over RTC `R` and drives `D`.
pub struct ServoTracker<R, D> {
    time: TimeKeeper<R>,
    source: SunSource,
    axes: [ServoLoopAxis<D>; 2],
    energy: DayEnergy,
    mode: Option<Mode>,
    /// The time fault in force (`rtc_invalid`, `bus_rtc`,
    /// `time_out_of_range`).
    time_fault: Option<Fault>,
    limit_logged: [bool; 2],
    time_logged: bool,
    /// The slot served last (days since 2000, slot of the day).
    last_slot: Option<(i32, u32)>,
    /// The slot's sun: zenith, azimuth, and its time.
    sun: Option<(UtcTime, f32, f32)>,
    /// The day's branch and its solar day.
    branch: Option<(i32, Branch)>,
    /// The slot of the last `setpoint` line.
    last_logged: Option<UtcTime>,
}

impl<R: RtcDriver, D: AxisDrive + Motion> ServoTracker<R, D> {
    /// The tracker at power-on: nothing homed, no time yet. `axes` are C
    /// then A, built with `configs` ([`axis_configs`] or
    /// [`axis_configs_geared`]).
    // Not inlined: built in place once, not copied field by field into the
    // caller's frame (1.4 KB of loads and stores on an AVR).
    #[inline(never)]
    pub fn new(rtc: R, site: Site<f32>, axes: [D; 2], configs: &[AxisConfig; 2]) -> Self {
        let [c, a] = axes;
        let [cc, ac] = configs;
        ServoTracker {
            time: TimeKeeper::new(rtc, TimeConfig::default()),
            source: SunSource::new(site, DELTA_T_S),
            axes: [ServoLoopAxis::new(c, cc), ServoLoopAxis::new(a, ac)],
            energy: DayEnergy::new(),
            mode: None,
            time_fault: None,
            limit_logged: [false; 2],
            time_logged: false,
            last_slot: None,
            sun: None,
            branch: None,
            last_logged: None,
        }
    }

    /// The mode after the last tick.
    pub fn mode(&self) -> Option<Mode> {
        self.mode
    }

    /// The RTC (tests move a simulated one on).
    pub fn rtc_mut(&mut self) -> &mut R {
        self.time.rtc_mut()
    }

    /// Every pass of the main loop (about every millisecond): each drive
    /// closes its loop once.
    #[inline(never)]
    pub fn service(&mut self, now_ms: u64) {
        // A failed PWM write is retried at the next pass: the servo axis
        // only records a pass that reached the servo.
        for ax in self.axes.iter_mut() {
            let _ = ax.axis.drive_mut().service(now_ms);
        }
    }

    /// One tick at monotonic `now_ms`, with the latest panel voltage
    /// (`None`: no reading). Never blocks: an RTC read, at most two sun
    /// positions (a new slot's and, once a day, the noon one), the drive
    /// commands.
    #[inline(never)]
    pub fn tick(&mut self, out: &mut dyn Sink, now_ms: u32, panel_mv: Option<u32>) {
        let status = self.time.update_without_gps();
        let time_fault = match status.now {
            Some(now) => {
                if !self.time_logged {
                    log::time(out, TimeOrigin::Rtc, &now);
                    self.time_logged = true;
                }
                self.schedule(out, &now)
            }
            None => {
                self.time_logged = false;
                self.sun = None;
                self.last_slot = None;
                Some(if status.rtc_error {
                    Fault::I2cError(Sensor::Rtc)
                } else {
                    Fault::RtcInvalid
                })
            }
        };
        if time_fault != self.time_fault {
            if let Some(old) = self.time_fault {
                fault_line(out, old, false);
            }
            if let Some(new) = time_fault {
                fault_line(out, new, true);
            }
            self.time_fault = time_fault;
        }
        let mut homing = false;
        for ((i, ax), logged) in self.axes.iter_mut().enumerate().zip(&mut self.limit_logged) {
            homing |= ax.home_step(now_ms);
            if ax.lost && !*logged {
                *logged = true;
                fault_line(out, Fault::LimitSwitchHit(axis_id(i)), true);
            }
        }
        let daylight = self.sun.filter(|_| time_fault.is_none());
        // The mode choice every board makes; this loop has no fault stop,
        // wind, operator or manual inputs.
        let mode = select_mode(&ModeInputs {
            weather: Default::default(),
            overcast: false,
            must_stop: false,
            wind_stow: false,
            service: false,
            command_stow: false,
            manual: false,
            time_unknown: time_fault.is_some(),
            night: daylight.is_none(),
            unhomed: homing,
        });
        if self.mode != Some(mode) {
            mode_line(out, mode);
            self.mode = Some(mode);
        }
        let pose = match daylight {
            Some((_, zenith, azimuth)) if !homing => {
                let branch = self.branch.map_or(Branch::South, |(_, b)| b);
                Some(branch.pose_deg(zenith, azimuth))
            }
            // Flat, C where it was commanded.
            _ if !homing => {
                let [c, _] = &self.axes;
                Some((c.commanded_deg(), 0.0))
            }
            _ => None,
        };
        if let Some((c, a)) = pose {
            for ((i, ax), deg) in self.axes.iter_mut().enumerate().zip([c, a]) {
                if let Some(raised) = ax.drive_to(deg, now_ms) {
                    fault_line(out, Fault::MotorStalled(axis_id(i)), raised);
                }
            }
        }
        if let (Some(mv), Some(_)) = (panel_mv, daylight) {
            self.energy.add(now_ms, mv);
        }
        if let (Some((time, zenith, azimuth)), Some((c, a)), Mode::Tracking) =
            (daylight, pose, mode)
        {
            self.log_setpoint(out, &time, zenith, azimuth, c, a, panel_mv);
        }
    }

    /// A new slot's sun; returns the time fault (`time_out_of_range` when
    /// the algorithm does not cover the time).
    #[inline(never)]
    fn schedule(&mut self, out: &mut dyn Sink, now: &UtcTime) -> Option<Fault> {
        let slot = (now.days_since_2000(), now.ms_of_day() / (STEP_S * 1000));
        if self.last_slot == Some(slot) {
            return None;
        }
        self.last_slot = Some(slot);
        let Ok(start) = UtcTime::from_days_ms(slot.0, slot.1 * STEP_S * 1000) else {
            return Some(Fault::TimeOutOfRange);
        };
        let site = self.source.site();
        let day = solar_day(&site, &start);
        if self.branch.map(|(d, _)| d) != Some(day) {
            if let Ok(sun) = noon(&site, day).and_then(|t| self.source.at(&t)) {
                self.branch = Some((day, Branch::for_noon(sun.azimuth_deg)));
            }
        }
        let was_day = self.sun.is_some();
        match self.source.at(&start) {
            Ok(sun) if sun.zenith_deg < 90.0 => {
                if !was_day {
                    // Sunrise: a new day's area.
                    self.energy.reset();
                }
                self.sun = Some((start, sun.zenith_deg, sun.azimuth_deg));
                None
            }
            Ok(_) => {
                if was_day {
                    panel::log_day_energy(out, &self.energy);
                }
                self.sun = None;
                None
            }
            Err(_) => {
                self.sun = None;
                Some(Fault::TimeOutOfRange)
            }
        }
    }

    /// `setpoint … panel_mv=…` once per slot tracked.
    #[allow(clippy::too_many_arguments)]
    fn log_setpoint(
        &mut self,
        out: &mut dyn Sink,
        time: &UtcTime,
        zenith_deg: f32,
        azimuth_deg: f32,
        c_deg: f32,
        a_deg: f32,
        panel_mv: Option<u32>,
    ) {
        if self.last_logged == Some(*time) {
            return;
        }
        self.last_logged = Some(*time);
        log::setpoint_with_panel(
            out,
            time,
            zenith_deg,
            azimuth_deg,
            c_deg,
            a_deg,
            panel_mv.unwrap_or(0),
        );
    }
}

/// `fault … raised|cleared`, from one place (inlined at each site it
/// would take some 200 B of flash each).
#[inline(never)]
fn fault_line(out: &mut dyn Sink, fault: Fault, raised: bool) {
    log::fault(out, fault, raised);
}

/// `mode …`, from one place.
#[inline(never)]
fn mode_line(out: &mut dyn Sink, mode: Mode) {
    log::mode(out, mode);
}

fn axis_id(i: usize) -> AxisId {
    if i == 0 {
        AxisId::C
    } else {
        AxisId::A
    }
}
