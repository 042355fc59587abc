//! Configuration: site, mechanics, limits, intervals and calibration.
//!
//! - this module: the schema, [`Config`] and its parts, with the defaults;
//! - [`ranges`]: the physical range of each field;
//! - `keys`: each field's dotted key ([`Field`]) and the text of each range
//!   or rule ([`Reason`]);
//! - [`range_text`]: the texts of the ranges, built when compiling from
//!   [`ranges`]' constants;
//! - `validate`: the checks ([`Config::validate`], [`ConfigError`]);
//! - `codec`: the binary payload ([`Config::encode`], [`Config::decode`],
//!   [`PAYLOAD_LEN`]);
//! - `record`: the [`Config`] as a record of the two-slot CRC-32 store
//!   ([`crate::persist::Record`]; [`LAYOUT_VERSION`], [`RECORD_LEN`] and
//!   [`crate::persist::ConfigStore::new`]).
//!
//! The store itself, its slot layout and its power-cut rules are
//! [`crate::persist`]'s ([`crate::persist::ConfigStore`]): a slot with a
//! bad CRC, a wrong magic or version, a payload of the wrong length or
//! values out of range is bad as a whole; with no good slot the defaults
//! are used. Nothing is ever applied in part.

use crate::plan::ScheduleConfig;
use crate::safety::OperatorHold;

pub(crate) mod codec;
mod keys;
pub mod range_text;
pub mod ranges;
mod record;
mod table;
mod validate;

pub use codec::PAYLOAD_LEN;
pub use keys::{Field, KeyName, Reason};
pub use record::{LAYOUT_VERSION, RECORD_LEN};
pub use table::{get, is_read_only, Value, KEYS};
pub(crate) use table::{slot, Slot, KEY_LIST};
pub(crate) use validate::check_f32;
pub use validate::ConfigError;

/// The tracker's site.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SiteConfig {
    /// Latitude, degrees north: −90…90 (`site.lat_deg`), the geographic
    /// range.
    pub latitude_deg: f32,
    /// Longitude, degrees east: −180…180 (`site.lon_deg`), the geographic
    /// range.
    pub longitude_deg: f32,
    /// Elevation, metres: −500…10,000 (`site.elevation_m`), from below the
    /// Dead Sea shore (−430 m) to above Everest (8,849 m).
    pub elevation_m: f32,
    /// Local time's offset from UTC, hours east: −12…14
    /// (`site.utc_offset_h`); the local date and time the Modbus map gives
    /// (SunSpec model 601's `DtLoc`, `TmLoc`, `Day`). Nothing else uses
    /// it: the sun and the schedule run on UTC.
    pub utc_offset_h: f32,
}

/// Mechanics and limits of one axis.
///
/// Besides each field's range, the counts per degree derived from the
/// first three ([`AxisConfig::counts_per_deg`], key `axis.c.counts_per_deg`)
/// lie in 1…1,000,000: at least a 1° resolution, and the largest move of
/// the axis (925°, [`ranges::MAX_MOVE_DEG`]) fits in under half of the
/// `i32` motor counts, so that no axis arithmetic can overflow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisConfig {
    /// Motor full steps per motor revolution (stepper) or encoder counts per
    /// motor revolution (servo): 1…16,777,216 (`axis.c.counts_per_motor_rev`);
    /// steppers have 200 or 400 full steps, absolute encoders up to 24 bits.
    pub counts_per_motor_rev: u32,
    /// Microsteps per full step (1 for a servo): 1…256 (`axis.c.microsteps`),
    /// what stepper drivers offer.
    pub microsteps: u16,
    /// Gear ratio, motor revolutions per axis revolution: 1…10,000
    /// (`axis.c.gear_ratio`), from direct drive to a worm gear plus a
    /// planetary stage.
    pub gear_ratio: f32,
    /// Soft limit, lowest angle, degrees: −360…360 and below `max_deg`
    /// (`axis.c.min_deg`); at most one turn either way.
    pub min_deg: f32,
    /// Soft limit, highest angle, degrees: −360…360 and above `min_deg`
    /// (`axis.c.max_deg`).
    pub max_deg: f32,
    /// Angle of the homing limit switch, degrees: `min_deg − 5`…`min_deg +
    /// 10` and at most `max_deg` (`axis.c.home_deg`). The switch is closed at and below this angle
    /// and homing drives negative onto it, so it sits at the low end of the
    /// travel; backing off a closed switch is limited to 15° in all, which
    /// must get an axis resting at its lowest limit off the switch.
    pub home_deg: f32,
    /// Backlash of the gear train, degrees: 0…5 (`axis.c.backlash_deg`);
    /// worm gears and slewing drives have 0.1–1°, beyond 5° counting the
    /// slack is meaningless.
    pub backlash_deg: f32,
    /// Highest axis speed, degrees per second: 0.01…30
    /// (`axis.c.max_speed_deg_s`), from a slow slewing drive to a sweep of
    /// 360° in 12 s; a panel's inertia allows no more.
    pub max_speed_deg_s: f32,
    /// Closed-loop deadband, degrees: 0…5 (`axis.c.deadband_deg`; cos 5° =
    /// 0.996, 0.4 % of the direct beam) and below
    /// `safety.max_deviation_deg`, or a deviation fault would be raised for
    /// an error the loop does not correct.
    pub deadband_deg: f32,
    /// The axis turns without end: 0…1 (`axis.c.continuous`), 1 on, 0 off
    /// (the C axis only; the A axis's is always 0): a slip ring or an
    /// unlimited drive. The soft limits then
    /// bound nothing but homing's seek; the axis takes the shorter way to
    /// each target and never unwinds, its count kept within one turn of
    /// the home switch by whole turns. On needs a whole number of motor
    /// counts per turn of the axis (an integer `gear_ratio`), or the count
    /// would drift by the fraction at each turn.
    pub continuous: u8,
    /// The axis's drive: 0…5 (`axis.c.drive`), a [`DriveKind`] code: 0
    /// stepper (an H-bridge or a STEP/DIR driver), 1 a continuous servo
    /// on an encoder, 2 a DC gear motor or slew drive counted by its Hall
    /// sensor (`counts_per_motor_rev` Hall counts a motor turn), 3 and 4 a
    /// linear actuator on Hall pulses or a potentiometer, 5 a DC motor
    /// timed, without feedback. A board builds its axes from it at
    /// power-on (`save` and reset after changing it) and refuses a kind
    /// its image has no driver for ([`Config::check_drives`]).
    pub drive: u8,
    /// A DC axis's motor current limit, milliamperes: 100…40,000
    /// (`axis.c.max_current_ma`), from a small gear motor to the BTS7960's
    /// 43 A; above it for `overcurrent_ms` is an obstruction
    /// (`obstruction_c`/`_a`). Not used by the other drives.
    pub max_current_ma: u16,
    /// Time above `max_current_ma` that is an obstruction, milliseconds:
    /// 10…5,000 (`axis.c.overcurrent_ms`); longer than a start's inrush,
    /// shorter than the time a stalled motor takes to overheat.
    pub overcurrent_ms: u16,
    /// A timed axis's speed driven backward (toward its home switch),
    /// degrees per second: 0.01…30 (`axis.c.back_speed_deg_s`), the range
    /// of `max_speed_deg_s`, which is its speed forward. Both are measured
    /// on the installed axis at full duty (a linear actuator retracts
    /// under the panel's weight faster or slower than it extends). Not
    /// used by the other drives.
    pub back_speed_deg_s: f32,
    /// A linear actuator's mounting and feedback (`linear_hall`,
    /// `linear_pot`; the keys of an image built with the `linear`
    /// feature). Not used by the other drives.
    #[cfg(feature = "linear")]
    pub linear: LinearMount,
}

/// A linear actuator between two pivots on either side of an axis's hinge
/// (drive kinds `linear_hall` and `linear_pot`): the mounting
/// geometry of [`drivers::linear::ActuatorGeometry`] (the axis angle
/// follows from the actuator's pivot-to-pivot length by the law of
/// cosines, `L² = a² + b² − 2ab·cos γ`, axis = γ − offset) and its
/// feedback's scale. The defaults are the simulator's LA12 tilt mount
/// (`sim::linear_drive::LA12_TILT_MOUNT`: a LINAK LA12 of 100 mm stroke,
/// 245 mm retracted, pivots 237 mm and 110 mm from the hinge), a single
/// Hall pulse a mm (LINAK, *Actuator LA12 User manual*, "I/O
/// specifications", option L) and its potentiometer's 0.5 V and 4.5 V on
/// a 10-bit ADC at 5 V.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearMount {
    /// Hinge to the actuator's fixed pivot, mm: 10…5,000
    /// (`axis.c.pivot_a_mm`).
    pub pivot_a_mm: f32,
    /// Hinge to the actuator's rod-end pivot, mm: 10…5,000
    /// (`axis.c.pivot_b_mm`).
    pub pivot_b_mm: f32,
    /// The hinge angle γ at axis angle 0, degrees: −360…360
    /// (`axis.c.pivot_offset_deg`; axis = γ − offset).
    pub pivot_offset_deg: f32,
    /// Pivot-to-pivot length fully retracted, mm: 10…5,000
    /// (`axis.c.retracted_mm`).
    pub retracted_mm: f32,
    /// Stroke, mm: 10…5,000 (`axis.c.stroke_mm`). With the pivots the
    /// whole stroke must form a triangle (`a + b` above the extended
    /// length, `|a − b|` below the retracted one), and the axis's soft
    /// limits and home switch lie within the stroke's angles.
    pub stroke_mm: f32,
    /// Hall or reed pulses counted per mm of stroke (`linear_hall`):
    /// 0.01…1,000 (`axis.c.pulses_per_mm`); every edge counted, so a dual
    /// Hall (quadrature) output of 0.1875 mm a state shift is 5.333.
    pub pulses_per_mm: f32,
    /// The potentiometer's ADC reading fully retracted (`linear_pot`):
    /// 0…4,095 (`axis.c.pot_retracted_counts`), a 12-bit converter's span.
    pub pot_retracted_counts: u16,
    /// The potentiometer's ADC reading fully extended: 0…4,095
    /// (`axis.c.pot_extended_counts`), not the retracted reading (either
    /// may be the larger: a potentiometer wired the other way round).
    pub pot_extended_counts: u16,
}

impl LinearMount {
    /// The defaults ([`LinearMount`]).
    pub const DEFAULT: LinearMount = LinearMount {
        pivot_a_mm: 237.0,
        pivot_b_mm: 110.0,
        pivot_offset_deg: 172.9,
        retracted_mm: 245.0,
        stroke_mm: 100.0,
        pulses_per_mm: 1.0,
        pot_retracted_counts: 102,
        pot_extended_counts: 921,
    };

    /// The mounting geometry.
    pub const fn geometry(&self) -> drivers::linear::ActuatorGeometry {
        drivers::linear::ActuatorGeometry {
            a_mm: self.pivot_a_mm,
            b_mm: self.pivot_b_mm,
            offset_deg: self.pivot_offset_deg,
            retracted_mm: self.retracted_mm,
            stroke_mm: self.stroke_mm,
        }
    }
}

/// An axis's drive kind: the codes of `axis.c.drive` and `axis.a.drive`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum DriveKind {
    /// A stepper motor (H-bridge or STEP/DIR driver).
    Stepper = 0,
    /// A continuous-rotation servo closed on an encoder.
    ServoEncoder = 1,
    /// A DC gear motor or slew drive closed on its Hall count.
    DcHall = 2,
    /// A linear actuator counted by its Hall or reed pulses.
    LinearHall = 3,
    /// A linear actuator read by its potentiometer.
    LinearPot = 4,
    /// A DC motor without feedback, moved by time.
    Timed = 5,
}

impl DriveKind {
    /// The kind of a code of `axis.c.drive`, if it is one.
    pub const fn from_code(code: u8) -> Option<DriveKind> {
        Some(match code {
            0 => DriveKind::Stepper,
            1 => DriveKind::ServoEncoder,
            2 => DriveKind::DcHall,
            3 => DriveKind::LinearHall,
            4 => DriveKind::LinearPot,
            5 => DriveKind::Timed,
            _ => return None,
        })
    }
}

/// The drive kinds a board's image can build an axis of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DriveSet(u8);

impl DriveSet {
    /// No kind (a set to add kinds to: [`DriveSet::with`]).
    pub const NONE: DriveSet = DriveSet(0);
    /// Steppers only.
    pub const STEPPER: DriveSet = DriveSet(1);
    /// Every kind: the codes of [`ranges::DRIVE`].
    pub const ALL: DriveSet = DriveSet((1u8 << (ranges::DRIVE.1 + 1)) - 1);

    /// This set and `kind`.
    pub const fn with(self, kind: DriveKind) -> DriveSet {
        DriveSet(self.0 | 1 << kind as u8)
    }

    /// True when `code` is the code of a kind of this set.
    pub const fn has_code(self, code: u8) -> bool {
        code < 8 && self.0 & (1 << code) != 0
    }
}

impl AxisConfig {
    /// Motor counts per axis degree: counts × microsteps × gear / 360.
    pub fn counts_per_deg(&self) -> f32 {
        self.counts_per_motor_rev as f32 * f32::from(self.microsteps) * self.gear_ratio / 360.0
    }
}

/// Wind stow (anemometer pulse rate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindConfig {
    /// Pulse rate that means "too windy", Hz: 0.1…1,000 (`wind.stow_hz`); a
    /// cup anemometer gives 1–20 pulses per turn and turns at most ~30
    /// times a second.
    pub threshold_hz: f32,
    /// Seconds above the threshold before stowing: 0…600 (`wind.hold_s`);
    /// at once up to 10 minutes (a gust front arrives within minutes).
    pub hold_s: u32,
    /// Seconds of calm (below the threshold) before leaving stow: 0…86,400
    /// (`wind.release_s`), at once up to one day.
    pub release_s: u32,
    /// Wind speed per pulse rate, m/s per Hz: 0…10 (`wind.m_s_per_hz`);
    /// 0 when not known. Only reported (the Modbus map's wind speed): the
    /// stow works on the pulse rate.
    pub m_s_per_hz: f32,
}

/// Fault thresholds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SafetyConfig {
    /// Largest allowed difference between set-point and feedback, degrees:
    /// 0.1…45 (`safety.max_deviation_deg`); above the attitude sensors'
    /// noise, below the 45° that would let a reversed axis pass.
    pub max_deviation_deg: f32,
    /// Seconds a driven axis may show no encoder motion before "stalled":
    /// 1…600 (`safety.stall_timeout_s`); a slow slewing drive shows motion
    /// within a second, and 10 minutes of a stalled motor overheats it.
    pub stall_timeout_s: u32,
    /// Seconds without a sensor reading before "timeout": 1…3,600
    /// (`safety.sensor_timeout_s`); sensors answer within a second, and the
    /// sun moves 15° an hour.
    pub sensor_timeout_s: u32,
    /// Retries of a failed operation before degrading: 0…20
    /// (`safety.max_retries`); more keeps a failing part in use too long.
    pub max_retries: u8,
}

/// Sensor calibration offsets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibration {
    /// Magnetic declination, degrees east (true = magnetic + declination):
    /// −180…180 (`calibration.declination_deg`); any direction near the
    /// magnetic poles.
    pub declination_deg: f32,
    /// Compass mounting offset, degrees: −180…180
    /// (`calibration.heading_offset_deg`); the compass may be mounted in any
    /// direction.
    pub heading_offset_deg: f32,
    /// Inclinometer x offset, degrees: −45…45
    /// (`calibration.tilt_x_offset_deg`); a sensor more than 45° off has its
    /// axes swapped, not offset.
    pub tilt_x_offset_deg: f32,
    /// Inclinometer y offset, degrees: −45…45
    /// (`calibration.tilt_y_offset_deg`), as x.
    pub tilt_y_offset_deg: f32,
}

/// What the log reports unasked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogConfig {
    /// Minutes between periodic `status` lines on the monotonic clock:
    /// 0…1,440 (`log.status_min`); 0 turns them off.
    pub status_every_min: u16,
}

/// The Modbus RTU server on the RS-485 port (where a board has one):
/// what a plant's SCADA needs to reach this tracker on its bus.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModbusConfig {
    /// Device address: 1…247 (`modbus.address`); 0 is broadcast and
    /// 248–255 are reserved (Modbus over Serial Line V1.02 §2.2).
    pub address: u8,
    /// Serial rate, baud: 1,200…115,200 (`modbus.baud`), one of 1,200,
    /// 2,400, 4,800, 9,600, 19,200, 38,400, 57,600 and 115,200.
    pub baud: u32,
    /// Parity: 0…2 (`modbus.parity`), 0 none with two stop bits, 1 odd,
    /// 2 even (the serial line spec's default, §2.5.1).
    pub parity: u8,
    /// Writes from the bus (manual mode, manual targets, stow, clearing
    /// faults): 0…1 (`modbus.write`), 0 refused with an exception, 1
    /// carried out; off by default, so a bus reads but never moves a
    /// tracker until its installer allows it.
    pub write: u8,
    /// Seconds without a request to this tracker before the master counts
    /// as silent: 0…86,400 (`modbus.timeout_s`); 0 never.
    pub timeout_s: u32,
    /// A silent master stows the tracker: 0…1 (`modbus.timeout_stow`);
    /// 1: once a master has been heard, `timeout_s` without a request to
    /// this tracker commands a stow, which the master's next request
    /// releases; 0: the silence only ends a manual mode the bus set.
    pub timeout_stow: u8,
}

/// The weather stows' poses and release times ([`crate::safety::WeatherStow`]):
/// the panel's slope from horizontal in each (the C axis stays where it is;
/// the A axis's limits bound the slope), and how long an input must have
/// been clear before tracking resumes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StowConfig {
    /// Slope for snow, degrees: 0…90 (`stow.snow_slope_deg`); steep, so
    /// that snow slides off (default 90: the A axis's limit).
    pub snow_slope_deg: f32,
    /// Seconds the snow input must be clear before tracking resumes:
    /// 0…86,400 (`stow.snow_release_s`); default an hour, for the panel to
    /// shed what lies on it.
    pub snow_release_s: u32,
    /// Slope for a hail warning, degrees: 0…90 (`stow.hail_slope_deg`);
    /// steep, so that hail strikes the glass at a glancing angle (default
    /// 60).
    pub hail_slope_deg: f32,
    /// Seconds the hail warning must be clear before tracking resumes:
    /// 0…86,400 (`stow.hail_release_s`); default 30 minutes.
    pub hail_release_s: u32,
    /// Slope while the plant's stow contact is active, degrees: 0…90
    /// (`stow.external_slope_deg`); default 0, flat.
    pub external_slope_deg: f32,
    /// Active level of the plant's stow contact: 0…1
    /// (`stow.external_active`), 0 low (a contact closing to ground against
    /// the pin's pull-up, the default), 1 high.
    pub external_active: u8,
    /// A sensor that reads impossible values (an ADC at a rail: the supply
    /// input's divider off or shorted) stows by itself: 0…1
    /// (`stow.on_sensor_fault`), 0 no (the default: the fault is raised
    /// and the tracker goes on), 1 yes.
    pub on_sensor_fault: u8,
}

/// The motor supply's watch (`low_supply_stow`), for a tracker on a
/// battery: below `stow_mv` it stows while the motors can still move, then
/// drives nothing until the supply is back at `resume_mv`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupplyConfig {
    /// Stow below this supply, millivolts: 0…60,000 (`supply.stow_mv`); 0
    /// (the default) turns the watch off. A 12 V lead-acid battery is
    /// nearly flat at 11,500 (20 % charge near 11.9 V at rest).
    pub stow_mv: u16,
    /// Track again from this supply, millivolts: 0…60,000
    /// (`supply.resume_mv`) and at least `supply.stow_mv`, so that the
    /// load taken off a sagging battery does not end the stow at once
    /// (12,200 for a 12 V lead-acid battery, 60 % charge at rest).
    pub resume_mv: u16,
    /// The motor supply the timed axes' speeds (`axis.X.max_speed_deg_s`
    /// forward, `axis.X.back_speed_deg_s` backward) were measured at,
    /// millivolts: 0…60,000 (`supply.calibration_mv`). A board that
    /// measures its motor supply then scales each timed run by this over
    /// the measured supply (a DC motor's speed is about proportional to
    /// its voltage: [`crate::hw::TimedAxis`]); 0 (the default) leaves the
    /// runs unscaled.
    pub calibration_mv: u16,
}

/// The overcast mode (`overcast`): under a sky whose measured irradiance
/// (a horizontal pyranometer or reference cell) stays below a fraction of
/// the clear sky's, the panel lies flat and collects the diffuse light of
/// the whole sky rather than pointing at a hidden sun.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OvercastConfig {
    /// The threshold as a fraction of the clear sky's global horizontal
    /// irradiance (B. Haurwitz (1945)): 0…1 (`overcast.ratio`); 0 (the
    /// default) turns the mode off, for a tracker without a pyranometer:
    /// an installer who wires one sets it, 0.3 for instance (under heavy
    /// cloud the global irradiance is a quarter to a third of the clear
    /// sky's, nearly all of it diffuse).
    pub ratio: f32,
    /// Seconds below the threshold before lying flat: 0…86,400
    /// (`overcast.enter_s`); default 10 minutes, longer than a passing
    /// cloud's shadow.
    pub enter_s: u32,
    /// Seconds at or above it before tracking again: 0…86,400
    /// (`overcast.leave_s`); default 10 minutes.
    pub leave_s: u32,
    /// Changes between tracking and flat an hour, at most: 1…8
    /// (`overcast.max_moves_per_hour`); default 4 (each change moves the
    /// panel: the motors cost energy).
    pub max_moves_per_hour: u8,
}

/// The whole configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    /// Site (used until GPS gives one).
    pub site: SiteConfig,
    /// Scheduler intervals, with these ranges (checked by
    /// [`Config::validate`]):
    ///
    /// | key | range | why |
    /// |---|---|---|
    /// | `schedule.table_step_s` | 60…43,200, whole minutes dividing 86,400 | the table is in whole minutes from UTC midnight; at least two entries a day |
    /// | `schedule.hold_s` | 0…3,600 | the sun moves 15° an hour |
    /// | `schedule.recheck_s` | 1…3,600 | zero would never advance; as hold |
    /// | `schedule.max_tick_gap_s` | 1…86,400 | a gap of a day or more is always a clock jump |
    /// | `schedule.max_backward_s` | 0…86,400 | as the gap |
    pub schedule: ScheduleConfig,
    /// C axis (vertical at home, keys `axis.c.*`), then A axis (`axis.a.*`).
    pub axes: [AxisConfig; 2],
    /// Wind stow.
    pub wind: WindConfig,
    /// Fault thresholds.
    pub safety: SafetyConfig,
    /// Calibration offsets.
    pub calibration: Calibration,
    /// Periodic log lines.
    pub log: LogConfig,
    /// The Modbus RTU server.
    pub modbus: ModbusConfig,
    /// The weather stows.
    pub stow: StowConfig,
    /// The motor supply's watch.
    pub supply: SupplyConfig,
    /// The overcast mode.
    pub overcast: OvercastConfig,
    /// Not a setting (no key; `set`, `load` and `defaults` leave the one in
    /// force): the operator's lasting commands, saved in the same record
    /// so that one power-cut-safe store keeps both ([`OperatorHold`]).
    pub hold: OperatorHold,
}

impl Config {
    /// The defaults: Kano (Jimoh & Aliyu's (2019) site); 1.8° steppers with
    /// 16 microsteps and a 100:1 worm gear; Jimoh & Aliyu's 4-minute table,
    /// 2-minute hold and 30-second re-check (their flowchart's steps 7, 14
    /// and 12). A constant for the key table's defaults, built from it when
    /// compiling; [`Config::default`] returns these values.
    pub const DEFAULT: Config = {
        let axis = AxisConfig {
            counts_per_motor_rev: 200,
            microsteps: 16,
            gear_ratio: 100.0,
            min_deg: -180.0,
            max_deg: 180.0,
            home_deg: -180.0,
            backlash_deg: 0.2,
            max_speed_deg_s: 2.0,
            deadband_deg: 0.05,
            continuous: 0,
            drive: DriveKind::Stepper as u8,
            max_current_ma: 3_000,
            overcurrent_ms: 100,
            back_speed_deg_s: 2.0,
            #[cfg(feature = "linear")]
            linear: LinearMount::DEFAULT,
        };
        Config {
            site: SiteConfig {
                latitude_deg: 11.9683,
                longitude_deg: 8.4261,
                elevation_m: 480.0,
                utc_offset_h: 0.0,
            },
            schedule: ScheduleConfig::DEFAULT,
            axes: [
                axis,
                AxisConfig {
                    min_deg: -90.0,
                    max_deg: 90.0,
                    home_deg: -90.0,
                    ..axis
                },
            ],
            wind: WindConfig {
                threshold_hz: 25.0,
                hold_s: 3,
                release_s: 600,
                m_s_per_hz: 0.0,
            },
            safety: SafetyConfig {
                max_deviation_deg: 5.0,
                stall_timeout_s: 5,
                sensor_timeout_s: 10,
                max_retries: 3,
            },
            calibration: Calibration {
                declination_deg: 0.0,
                heading_offset_deg: 0.0,
                tilt_x_offset_deg: 0.0,
                tilt_y_offset_deg: 0.0,
            },
            log: LogConfig {
                status_every_min: 10,
            },
            modbus: ModbusConfig {
                address: 1,
                baud: 19_200,
                parity: 2,
                write: 0,
                timeout_s: 0,
                timeout_stow: 0,
            },
            stow: StowConfig {
                snow_slope_deg: 90.0,
                snow_release_s: 3_600,
                hail_slope_deg: 60.0,
                hail_release_s: 1_800,
                external_slope_deg: 0.0,
                external_active: 0,
                on_sensor_fault: 0,
            },
            supply: SupplyConfig {
                stow_mv: 0,
                resume_mv: 0,
                calibration_mv: 0,
            },
            overcast: OvercastConfig {
                ratio: 0.0,
                enter_s: 600,
                leave_s: 600,
                max_moves_per_hour: 4,
            },
            hold: OperatorHold::NONE,
        }
    };
}

impl Default for Config {
    /// [`Config::DEFAULT`], written key by key from the key table's
    /// defaults (a table built from it when compiling, in flash on the
    /// AVR).
    // Not inlined: a board's own defaults start from these. From the
    // table: the fields written one by one were 584 B of code on the
    // ATmega2560.
    #[inline(never)]
    fn default() -> Self {
        table::defaults()
    }
}
