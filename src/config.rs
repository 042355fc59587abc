//! Configuration: site, mechanics, limits, intervals and calibration, kept
//! in a versioned binary layout with a CRC-32 in two slots.
//!
//! # Layout (little-endian)
//! Each slot is [`SLOT_LEN`] bytes at offset `slot × SLOT_LEN`:
//!
//! | bytes | field |
//! |---|---|
//! | 0..4 | magic `b"STCF"` |
//! | 4..6 | layout version ([`LAYOUT_VERSION`]) |
//! | 6..8 | payload length `n` |
//! | 8..12 | sequence number (wrapping) |
//! | 12..12+n | payload ([`Config::encode`]) |
//! | 12+n..16+n | CRC-32 (IEEE 802.3, reflected, poly 0xEDB88320) of bytes 0..12+n |
//!
//! A save writes the slot that does *not* hold the newest good copy, with the
//! next sequence number; an interrupted write leaves at worst that slot
//! corrupt and the other one good. A load takes the good slot with the
//! newest sequence; a bad CRC, a wrong magic or version, a payload of the
//! wrong length or values out of range make a slot bad as a whole. With no
//! good slot the defaults are used. Nothing is ever applied in part.

use crate::plan::ScheduleConfig;
use crate::ports::Storage;
use crate::text::FlashStr;

/// Layout version written by this firmware: 2 added `log.status_min`; a
/// slot of version 1 is reported as [`SlotState::OldVersion`] and not used.
pub const LAYOUT_VERSION: u16 = 2;
/// Bytes per slot.
pub const SLOT_LEN: usize = 256;
/// Header bytes before the payload.
const HEADER_LEN: usize = 12;
const MAGIC: [u8; 4] = *b"STCF";

/// CRC-32 (IEEE 802.3: reflected, polynomial 0xEDB88320, initial and final
/// XOR 0xFFFFFFFF), bit by bit: small code, no table.
pub fn crc32(data: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &b in data {
        crc ^= u32::from(b);
        for _ in 0..8 {
            let mask = (crc & 1).wrapping_neg();
            crc = (crc >> 1) ^ (0xEDB8_8320 & mask);
        }
    }
    !crc
}

/// Which field of a [`Config`] is out of its range, and why.
///
/// `field` names the field by a dotted key with its unit
/// ([`Field::name`]): `site.lat_deg`, `schedule.table_step_s`,
/// `axis.c.gear_ratio` (the C axis is `Config::axes[0]`, the A axis
/// `Config::axes[1]`), `wind.stow_hz`, `safety.max_retries`,
/// `calibration.tilt_x_offset_deg`. `reason` is the range or rule that was
/// broken ([`Reason::text`]). Both are enums, not strings: an image links
/// the texts only where it prints them (an 8-bit AVR keeps every linked
/// string in its RAM). `Display` prints `key: reason`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConfigError {
    /// The field, by its dotted key.
    pub field: Field,
    /// The range or rule the value breaks.
    pub reason: Reason,
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{}: {}", self.field.name(), self.reason.text())
    }
}

/// An enum of names: each variant with its text, the text only through a
/// function (linked where called) and `Debug`/`Display`.
macro_rules! named {
    ($(#[$m:meta])* $vis:vis enum $name:ident fn $f:ident { $($v:ident => $s:literal,)* }) => {
        $(#[$m])*
        #[derive(Clone, Copy, PartialEq, Eq)]
        #[allow(missing_docs)]
        $vis enum $name { $($v,)* }
        impl $name {
            /// The text (in flash on AVR: [`FlashStr`]).
            pub fn $f(self) -> FlashStr {
                match self { $($name::$v => crate::flash_str!($s),)* }
            }
        }
        impl core::fmt::Debug for $name {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                core::fmt::Display::fmt(&self.$f(), f)
            }
        }
        impl core::fmt::Display for $name {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                core::fmt::Display::fmt(&self.$f(), f)
            }
        }
        impl PartialEq<str> for $name {
            fn eq(&self, other: &str) -> bool {
                self.$f() == *other
            }
        }
        impl PartialEq<&str> for $name {
            fn eq(&self, other: &&str) -> bool {
                self.$f() == *other
            }
        }
    };
}

named! {
    /// A field of [`Config`] by its dotted key with unit ([`Field::name`]).
    pub enum Field fn name {
        AxisCCountsPerMotorRev => "axis.c.counts_per_motor_rev",
        AxisCMicrosteps => "axis.c.microsteps",
        AxisCGearRatio => "axis.c.gear_ratio",
        AxisCCountsPerDeg => "axis.c.counts_per_deg",
        AxisCMinDeg => "axis.c.min_deg",
        AxisCMaxDeg => "axis.c.max_deg",
        AxisCHomeDeg => "axis.c.home_deg",
        AxisCBacklashDeg => "axis.c.backlash_deg",
        AxisCMaxSpeedDegS => "axis.c.max_speed_deg_s",
        AxisCDeadbandDeg => "axis.c.deadband_deg",
        AxisACountsPerMotorRev => "axis.a.counts_per_motor_rev",
        AxisAMicrosteps => "axis.a.microsteps",
        AxisAGearRatio => "axis.a.gear_ratio",
        AxisACountsPerDeg => "axis.a.counts_per_deg",
        AxisAMinDeg => "axis.a.min_deg",
        AxisAMaxDeg => "axis.a.max_deg",
        AxisAHomeDeg => "axis.a.home_deg",
        AxisABacklashDeg => "axis.a.backlash_deg",
        AxisAMaxSpeedDegS => "axis.a.max_speed_deg_s",
        AxisADeadbandDeg => "axis.a.deadband_deg",
        SiteLatDeg => "site.lat_deg",
        SiteLonDeg => "site.lon_deg",
        SiteElevationM => "site.elevation_m",
        ScheduleTableStepS => "schedule.table_step_s",
        ScheduleHoldS => "schedule.hold_s",
        ScheduleRecheckS => "schedule.recheck_s",
        ScheduleMaxTickGapS => "schedule.max_tick_gap_s",
        ScheduleMaxBackwardS => "schedule.max_backward_s",
        WindStowHz => "wind.stow_hz",
        WindHoldS => "wind.hold_s",
        WindReleaseS => "wind.release_s",
        SafetyMaxDeviationDeg => "safety.max_deviation_deg",
        SafetyStallTimeoutS => "safety.stall_timeout_s",
        SafetySensorTimeoutS => "safety.sensor_timeout_s",
        SafetyMaxRetries => "safety.max_retries",
        CalibrationDeclinationDeg => "calibration.declination_deg",
        CalibrationHeadingOffsetDeg => "calibration.heading_offset_deg",
        CalibrationTiltXOffsetDeg => "calibration.tilt_x_offset_deg",
        CalibrationTiltYOffsetDeg => "calibration.tilt_y_offset_deg",
        LogStatusMin => "log.status_min",
    }
}

named! {
    /// The range or rule a field breaks ([`Reason::text`]).
    pub enum Reason fn text {
        CountsPerMotorRev => "1...16,777,216 full steps or encoder counts per motor revolution",
        Microsteps => "1...256 microsteps per full step",
        GearRatio => "1...10,000 motor revolutions per axis revolution",
        CountsPerDeg => "counts * microsteps * gear / 360 must be 1...1,000,000 counts per degree",
        LimitDeg => "-360...360 deg",
        AboveMinDeg => "must be above min_deg",
        HomeNearMinDeg => "min_deg - 5 deg ... min_deg + 10 deg and at most max_deg: the switch is at the low end of the travel",
        Deg0To5 => "0...5 deg",
        SpeedDegS => "0.01...30 deg/s",
        Latitude => "-90...90 deg",
        Deg180 => "-180...180 deg",
        ElevationM => "-500...10,000 m",
        TableStepS => "60...43,200 s",
        WholeMinutesOfDay => "whole minutes dividing a day (86,400 s)",
        S0To3600 => "0...3,600 s",
        S1To3600 => "1...3,600 s",
        S1To86400 => "1...86,400 s",
        S0To86400 => "0...86,400 s",
        StowHz => "0.1...1,000 Hz",
        S0To600 => "0...600 s",
        MaxDeviationDeg => "0.1...45 deg",
        S1To600 => "1...600 s",
        MaxRetries => "0...20",
        BelowMaxDeviation => "must be below safety.max_deviation_deg",
        TiltOffsetDeg => "-45...45 deg",
        StatusMin => "0...1,440 min (0: no periodic status line)",
    }
}

/// The physical ranges of the configuration, as checked by
/// [`Config::validate`]; each field's doc comment gives the reason.
pub mod ranges {
    /// Latitude, degrees: the geographic range.
    pub const LAT_DEG: (f32, f32) = (-90.0, 90.0);
    /// Longitude, degrees: the geographic range.
    pub const LON_DEG: (f32, f32) = (-180.0, 180.0);
    /// Elevation, metres: Dead Sea shore (−430 m) to above Everest.
    pub const ELEVATION_M: (f32, f32) = (-500.0, 10_000.0);
    /// Set-point table interval, seconds: one minute to half a day.
    pub const TABLE_STEP_S: (u32, u32) = (60, 43_200);
    /// Hold after a set-point, seconds: none to one hour.
    pub const HOLD_S: (u32, u32) = (0, 3_600);
    /// Re-check interval, seconds: one second to one hour.
    pub const RECHECK_S: (u32, u32) = (1, 3_600);
    /// Forward clock jump that re-plans, seconds: one second to one day.
    pub const MAX_TICK_GAP_S: (u32, u32) = (1, 86_400);
    /// Backward clock step that re-plans, seconds: none to one day.
    pub const MAX_BACKWARD_S: (u32, u32) = (0, 86_400);
    /// Full steps or encoder counts per motor revolution: 1 to 2^24 (a
    /// 24-bit absolute encoder).
    pub const COUNTS_PER_MOTOR_REV: (u32, u32) = (1, 16_777_216);
    /// Microsteps per full step, as stepper drivers offer: 1 to 256.
    pub const MICROSTEPS: (u16, u16) = (1, 256);
    /// Gear ratio, motor revolutions per axis revolution: direct drive to a
    /// worm plus planetary stack.
    pub const GEAR_RATIO: (f32, f32) = (1.0, 10_000.0);
    /// Motor counts per axis degree (derived: counts × microsteps × gear /
    /// 360): a 1° resolution at least; at most 10^6, so that the largest
    /// move of an axis ([`MAX_MOVE_DEG`] = 925°) is 9.25 × 10^8 counts,
    /// under half of `i32::MAX` (2.1 × 10^9).
    pub const COUNTS_PER_DEG: (f32, f32) = (1.0, 1_000_000.0);
    /// The largest move of an axis, degrees: the widest soft-limit span
    /// (720°), a home switch 5° below it, feedback believed up to
    /// `axis::FEEDBACK_MARGIN_DEG` (90°) beyond either limit, and the
    /// backlash take-up (5°), rounded up.
    pub const MAX_MOVE_DEG: f32 = 925.0;
    /// Soft limits, degrees: at most one turn either way (720° of cable
    /// wrap in all).
    pub const LIMIT_DEG: (f32, f32) = (-360.0, 360.0);
    /// Home switch angle relative to `min_deg`, degrees: from 5° below the
    /// lowest soft limit (a switch just outside the working range) to 10°
    /// above it (inside the range); homing drives negative onto it, and
    /// backs off a closed switch by at most `axis::HOMING_BACKOFF_MAX_DEG`
    /// (15°), which must get an axis resting at its lowest limit off it.
    /// Never above `max_deg` either: homed, the axis is at the switch.
    pub const HOME_ABOVE_MIN_DEG: (f32, f32) = (-5.0, 10.0);
    /// Backlash, degrees: worm gears and slewing drives have 0.1–1°;
    /// beyond 5° counting the slack is meaningless.
    pub const BACKLASH_DEG: (f32, f32) = (0.0, 5.0);
    /// Highest axis speed, degrees per second: a slow slewing drive to a
    /// 12-second sweep of a 360° span.
    pub const MAX_SPEED_DEG_S: (f32, f32) = (0.01, 30.0);
    /// Closed-loop deadband, degrees: none to 5° (cos 5° = 0.996, 0.4 %
    /// of the direct beam); also below `safety.max_deviation_deg`.
    pub const DEADBAND_DEG: (f32, f32) = (0.0, 5.0);
    /// Anemometer pulse rate that means "too windy", Hz: a cup anemometer
    /// gives 1–20 pulses per turn and turns at most ~30 times a second.
    pub const STOW_HZ: (f32, f32) = (0.1, 1_000.0);
    /// Seconds above the threshold before stowing: at once to 10 minutes.
    pub const WIND_HOLD_S: (u32, u32) = (0, 600);
    /// Seconds of calm before leaving stow: at once to one day.
    pub const WIND_RELEASE_S: (u32, u32) = (0, 86_400);
    /// Largest set-point deviation, degrees: above the attitude sensors'
    /// noise (0.1°), below the 45° that would let a reversed axis pass.
    pub const MAX_DEVIATION_DEG: (f32, f32) = (0.1, 45.0);
    /// Seconds without encoder motion before "stalled": 1 s to 10 minutes.
    pub const STALL_TIMEOUT_S: (u32, u32) = (1, 600);
    /// Seconds without a sensor reading before "timeout": 1 s to one hour.
    pub const SENSOR_TIMEOUT_S: (u32, u32) = (1, 3_600);
    /// Retries before degrading: none to 20.
    pub const MAX_RETRIES: (u8, u8) = (0, 20);
    /// Magnetic declination and compass mounting offset, degrees: any
    /// direction (declination reaches ±180° near the magnetic poles).
    pub const HEADING_DEG: (f32, f32) = (-180.0, 180.0);
    /// Inclinometer offsets, degrees: a sensor mounted more than 45° off
    /// has its x and y axes swapped, not offset.
    pub const TILT_OFFSET_DEG: (f32, f32) = (-45.0, 45.0);
    /// Minutes between periodic `status` log lines; 0 turns them off, a
    /// day is the longest period that still shows a logger the tracker
    /// is alive every day.
    pub const STATUS_MIN: (u16, u16) = (0, 1_440);
}

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
}

/// Dotted keys of one axis's fields (`axis.c.*` or `axis.a.*`).
struct AxisKeys {
    counts_per_motor_rev: Field,
    microsteps: Field,
    gear_ratio: Field,
    counts_per_deg: Field,
    min_deg: Field,
    max_deg: Field,
    home_deg: Field,
    backlash_deg: Field,
    max_speed_deg_s: Field,
    deadband_deg: Field,
}

const AXIS_KEYS: [AxisKeys; 2] = [
    AxisKeys {
        counts_per_motor_rev: Field::AxisCCountsPerMotorRev,
        microsteps: Field::AxisCMicrosteps,
        gear_ratio: Field::AxisCGearRatio,
        counts_per_deg: Field::AxisCCountsPerDeg,
        min_deg: Field::AxisCMinDeg,
        max_deg: Field::AxisCMaxDeg,
        home_deg: Field::AxisCHomeDeg,
        backlash_deg: Field::AxisCBacklashDeg,
        max_speed_deg_s: Field::AxisCMaxSpeedDegS,
        deadband_deg: Field::AxisCDeadbandDeg,
    },
    AxisKeys {
        counts_per_motor_rev: Field::AxisACountsPerMotorRev,
        microsteps: Field::AxisAMicrosteps,
        gear_ratio: Field::AxisAGearRatio,
        counts_per_deg: Field::AxisACountsPerDeg,
        min_deg: Field::AxisAMinDeg,
        max_deg: Field::AxisAMaxDeg,
        home_deg: Field::AxisAHomeDeg,
        backlash_deg: Field::AxisABacklashDeg,
        max_speed_deg_s: Field::AxisAMaxSpeedDegS,
        deadband_deg: Field::AxisADeadbandDeg,
    },
];

/// `Err` naming `field` unless `v` is finite and inside `lo..=hi`.
pub(crate) fn check_f32(
    v: f32,
    (lo, hi): (f32, f32),
    field: Field,
    reason: Reason,
) -> Result<(), ConfigError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(ConfigError { field, reason })
    }
}

/// `Err` naming `field` unless `v` is inside `lo..=hi`.
fn check_int<T: PartialOrd>(
    v: T,
    (lo, hi): (T, T),
    field: Field,
    reason: Reason,
) -> Result<(), ConfigError> {
    if v >= lo && v <= hi {
        Ok(())
    } else {
        Err(ConfigError { field, reason })
    }
}

impl AxisConfig {
    /// Motor counts per axis degree: counts × microsteps × gear / 360.
    pub fn counts_per_deg(&self) -> f32 {
        self.counts_per_motor_rev as f32 * f32::from(self.microsteps) * self.gear_ratio / 360.0
    }

    /// Checks every field against its range; `axis` 0 is the C axis (keys
    /// `axis.c.*`), any other the A axis (`axis.a.*`). The deadband's
    /// relation to `safety.max_deviation_deg` is checked by
    /// [`Config::validate`].
    pub fn validate(&self, axis: usize) -> Result<(), ConfigError> {
        use ranges as r;
        let [keys_c, keys_a] = &AXIS_KEYS;
        let k = if axis == 0 { keys_c } else { keys_a };
        check_int(
            self.counts_per_motor_rev,
            r::COUNTS_PER_MOTOR_REV,
            k.counts_per_motor_rev,
            Reason::CountsPerMotorRev,
        )?;
        check_int(
            self.microsteps,
            r::MICROSTEPS,
            k.microsteps,
            Reason::Microsteps,
        )?;
        check_f32(
            self.gear_ratio,
            r::GEAR_RATIO,
            k.gear_ratio,
            Reason::GearRatio,
        )?;
        check_f32(
            self.counts_per_deg(),
            r::COUNTS_PER_DEG,
            k.counts_per_deg,
            Reason::CountsPerDeg,
        )?;
        check_f32(self.min_deg, r::LIMIT_DEG, k.min_deg, Reason::LimitDeg)?;
        check_f32(self.max_deg, r::LIMIT_DEG, k.max_deg, Reason::LimitDeg)?;
        if self.max_deg <= self.min_deg {
            return Err(ConfigError {
                field: k.max_deg,
                reason: Reason::AboveMinDeg,
            });
        }
        let (below, above) = r::HOME_ABOVE_MIN_DEG;
        check_f32(
            self.home_deg,
            (
                self.min_deg + below,
                (self.min_deg + above).min(self.max_deg),
            ),
            k.home_deg,
            Reason::HomeNearMinDeg,
        )?;
        check_f32(
            self.backlash_deg,
            r::BACKLASH_DEG,
            k.backlash_deg,
            Reason::Deg0To5,
        )?;
        check_f32(
            self.max_speed_deg_s,
            r::MAX_SPEED_DEG_S,
            k.max_speed_deg_s,
            Reason::SpeedDegS,
        )?;
        check_f32(
            self.deadband_deg,
            r::DEADBAND_DEG,
            k.deadband_deg,
            Reason::Deg0To5,
        )
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
}

impl Default for Config {
    /// Kano (seed jimoh-2019's site); 1.8° steppers with 16 microsteps and a
    /// 100:1 worm gear; the seed's 4-minute table, 2-minute hold, 30-second
    /// re-check.
    fn default() -> Self {
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
        };
        Config {
            site: SiteConfig {
                latitude_deg: 11.9683,
                longitude_deg: 8.4261,
                elevation_m: 480.0,
            },
            schedule: ScheduleConfig::default(),
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
        }
    }
}

/// Payload length of layout version 2 (version 1 had no `log` fields).
pub const PAYLOAD_LEN: usize = 12 + 20 + 2 * 34 + 12 + 13 + 16 + 2;

struct Writer<'a> {
    buf: &'a mut [u8],
    pos: usize,
    overflow: bool,
}

impl Writer<'_> {
    fn bytes(&mut self, b: &[u8]) {
        match self.buf.get_mut(self.pos..self.pos + b.len()) {
            Some(dst) => dst.copy_from_slice(b),
            None => self.overflow = true,
        }
        self.pos += b.len();
    }
    fn u8(&mut self, v: u8) {
        self.bytes(&[v]);
    }
    fn u16(&mut self, v: u16) {
        self.bytes(&v.to_le_bytes());
    }
    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
    fn f32(&mut self, v: f32) {
        self.bytes(&v.to_le_bytes());
    }
}

struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn take<const K: usize>(&mut self) -> Option<[u8; K]> {
        let s = self.buf.get(self.pos..self.pos + K)?;
        self.pos += K;
        let mut a = [0u8; K];
        a.copy_from_slice(s);
        Some(a)
    }
    fn u8(&mut self) -> Option<u8> {
        self.take::<1>().map(|a| a[0])
    }
    fn u16(&mut self) -> Option<u16> {
        self.take().map(u16::from_le_bytes)
    }
    fn u32(&mut self) -> Option<u32> {
        self.take().map(u32::from_le_bytes)
    }
    fn f32(&mut self) -> Option<f32> {
        self.take().map(f32::from_le_bytes)
    }
}

impl Config {
    /// Serialises into `buf` (at least [`PAYLOAD_LEN`] bytes); returns the
    /// length written, or `None` when `buf` is too small.
    pub fn encode(&self, buf: &mut [u8]) -> Option<usize> {
        let mut w = Writer {
            buf,
            pos: 0,
            overflow: false,
        };
        w.f32(self.site.latitude_deg);
        w.f32(self.site.longitude_deg);
        w.f32(self.site.elevation_m);
        let s = &self.schedule;
        for v in [
            s.table_step_s,
            s.hold_s,
            s.recheck_s,
            s.max_tick_gap_s,
            s.max_backward_s,
        ] {
            w.u32(v);
        }
        for a in &self.axes {
            w.u32(a.counts_per_motor_rev);
            w.u16(a.microsteps);
            for v in [
                a.gear_ratio,
                a.min_deg,
                a.max_deg,
                a.home_deg,
                a.backlash_deg,
                a.max_speed_deg_s,
                a.deadband_deg,
            ] {
                w.f32(v);
            }
        }
        w.f32(self.wind.threshold_hz);
        w.u32(self.wind.hold_s);
        w.u32(self.wind.release_s);
        w.f32(self.safety.max_deviation_deg);
        w.u32(self.safety.stall_timeout_s);
        w.u32(self.safety.sensor_timeout_s);
        w.u8(self.safety.max_retries);
        let c = &self.calibration;
        for v in [
            c.declination_deg,
            c.heading_offset_deg,
            c.tilt_x_offset_deg,
            c.tilt_y_offset_deg,
        ] {
            w.f32(v);
        }
        w.u16(self.log.status_every_min);
        if w.overflow {
            None
        } else {
            Some(w.pos)
        }
    }

    /// Parses a payload of layout version 2 and checks every value; `None`
    /// for a short buffer or any value out of range.
    pub fn decode(buf: &[u8]) -> Option<Config> {
        let mut r = Reader { buf, pos: 0 };
        let site = SiteConfig {
            latitude_deg: r.f32()?,
            longitude_deg: r.f32()?,
            elevation_m: r.f32()?,
        };
        let schedule = ScheduleConfig {
            table_step_s: r.u32()?,
            hold_s: r.u32()?,
            recheck_s: r.u32()?,
            max_tick_gap_s: r.u32()?,
            max_backward_s: r.u32()?,
        };
        let mut axis = || -> Option<AxisConfig> {
            Some(AxisConfig {
                counts_per_motor_rev: r.u32()?,
                microsteps: r.u16()?,
                gear_ratio: r.f32()?,
                min_deg: r.f32()?,
                max_deg: r.f32()?,
                home_deg: r.f32()?,
                backlash_deg: r.f32()?,
                max_speed_deg_s: r.f32()?,
                deadband_deg: r.f32()?,
            })
        };
        let axes = [axis()?, axis()?];
        let wind = WindConfig {
            threshold_hz: r.f32()?,
            hold_s: r.u32()?,
            release_s: r.u32()?,
        };
        let safety = SafetyConfig {
            max_deviation_deg: r.f32()?,
            stall_timeout_s: r.u32()?,
            sensor_timeout_s: r.u32()?,
            max_retries: r.u8()?,
        };
        let calibration = Calibration {
            declination_deg: r.f32()?,
            heading_offset_deg: r.f32()?,
            tilt_x_offset_deg: r.f32()?,
            tilt_y_offset_deg: r.f32()?,
        };
        let log = LogConfig {
            status_every_min: r.u16()?,
        };
        if r.pos != buf.len() {
            return None;
        }
        let cfg = Config {
            site,
            schedule,
            axes,
            wind,
            safety,
            calibration,
            log,
        };
        cfg.is_valid().then_some(cfg)
    }

    /// Every value inside its range: `validate().is_ok()`.
    pub fn is_valid(&self) -> bool {
        self.validate().is_ok()
    }

    /// Checks every field against its documented range (see [`ranges`] and
    /// the fields' doc comments) and the rules between fields; the first
    /// field out of range is named in the error. For every configuration
    /// that passes, the axis arithmetic cannot overflow (see
    /// [`ranges::COUNTS_PER_DEG`]).
    pub fn validate(&self) -> Result<(), ConfigError> {
        use ranges as r;
        let s = &self.site;
        check_f32(
            s.latitude_deg,
            r::LAT_DEG,
            Field::SiteLatDeg,
            Reason::Latitude,
        )?;
        check_f32(
            s.longitude_deg,
            r::LON_DEG,
            Field::SiteLonDeg,
            Reason::Deg180,
        )?;
        check_f32(
            s.elevation_m,
            r::ELEVATION_M,
            Field::SiteElevationM,
            Reason::ElevationM,
        )?;
        let sc = &self.schedule;
        check_int(
            sc.table_step_s,
            r::TABLE_STEP_S,
            Field::ScheduleTableStepS,
            Reason::TableStepS,
        )?;
        if !sc.table_step_s.is_multiple_of(60) || 86_400 % sc.table_step_s != 0 {
            return Err(ConfigError {
                field: Field::ScheduleTableStepS,
                reason: Reason::WholeMinutesOfDay,
            });
        }
        check_int(sc.hold_s, r::HOLD_S, Field::ScheduleHoldS, Reason::S0To3600)?;
        check_int(
            sc.recheck_s,
            r::RECHECK_S,
            Field::ScheduleRecheckS,
            Reason::S1To3600,
        )?;
        check_int(
            sc.max_tick_gap_s,
            r::MAX_TICK_GAP_S,
            Field::ScheduleMaxTickGapS,
            Reason::S1To86400,
        )?;
        check_int(
            sc.max_backward_s,
            r::MAX_BACKWARD_S,
            Field::ScheduleMaxBackwardS,
            Reason::S0To86400,
        )?;
        for (i, a) in self.axes.iter().enumerate() {
            a.validate(i)?;
        }
        let w = &self.wind;
        check_f32(
            w.threshold_hz,
            r::STOW_HZ,
            Field::WindStowHz,
            Reason::StowHz,
        )?;
        check_int(w.hold_s, r::WIND_HOLD_S, Field::WindHoldS, Reason::S0To600)?;
        check_int(
            w.release_s,
            r::WIND_RELEASE_S,
            Field::WindReleaseS,
            Reason::S0To86400,
        )?;
        let sf = &self.safety;
        check_f32(
            sf.max_deviation_deg,
            r::MAX_DEVIATION_DEG,
            Field::SafetyMaxDeviationDeg,
            Reason::MaxDeviationDeg,
        )?;
        check_int(
            sf.stall_timeout_s,
            r::STALL_TIMEOUT_S,
            Field::SafetyStallTimeoutS,
            Reason::S1To600,
        )?;
        check_int(
            sf.sensor_timeout_s,
            r::SENSOR_TIMEOUT_S,
            Field::SafetySensorTimeoutS,
            Reason::S1To3600,
        )?;
        check_int(
            sf.max_retries,
            r::MAX_RETRIES,
            Field::SafetyMaxRetries,
            Reason::MaxRetries,
        )?;
        for (a, k) in self.axes.iter().zip(AXIS_KEYS.iter()) {
            if a.deadband_deg >= sf.max_deviation_deg {
                return Err(ConfigError {
                    field: k.deadband_deg,
                    reason: Reason::BelowMaxDeviation,
                });
            }
        }
        let c = &self.calibration;
        check_f32(
            c.declination_deg,
            r::HEADING_DEG,
            Field::CalibrationDeclinationDeg,
            Reason::Deg180,
        )?;
        check_f32(
            c.heading_offset_deg,
            r::HEADING_DEG,
            Field::CalibrationHeadingOffsetDeg,
            Reason::Deg180,
        )?;
        check_f32(
            c.tilt_x_offset_deg,
            r::TILT_OFFSET_DEG,
            Field::CalibrationTiltXOffsetDeg,
            Reason::TiltOffsetDeg,
        )?;
        check_f32(
            c.tilt_y_offset_deg,
            r::TILT_OFFSET_DEG,
            Field::CalibrationTiltYOffsetDeg,
            Reason::TiltOffsetDeg,
        )?;
        check_int(
            self.log.status_every_min,
            r::STATUS_MIN,
            Field::LogStatusMin,
            Reason::StatusMin,
        )
    }
}

/// Why a slot was not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlotState {
    /// Good, with its sequence number.
    Good(u32),
    /// Never written (magic missing).
    Empty,
    /// Written by another layout version.
    OldVersion(u16),
    /// CRC, length or a value is wrong.
    Corrupt,
    /// The storage could not be read.
    Unreadable,
}

/// What a [`ConfigStore`] keeps in its two slots: the tracker's
/// [`Config`], or a board's smaller record (the Arduino Uno's settings),
/// each with its own magic and layout version so that one is never read
/// as the other.
pub trait Record: Copy {
    /// The slot's first four bytes.
    const MAGIC: [u8; 4];
    /// The layout version written; a slot of another version is reported
    /// as [`SlotState::OldVersion`] and not used.
    const VERSION: u16;
    /// Payload bytes of this version.
    const PAYLOAD_LEN: usize;
    /// Serialises into `buf` (at least [`Record::PAYLOAD_LEN`] bytes);
    /// the length written, or `None` when `buf` is too small.
    fn encode(&self, buf: &mut [u8]) -> Option<usize>;
    /// Parses a payload and checks every value; `None` for a wrong length
    /// or a value out of range.
    fn decode(buf: &[u8]) -> Option<Self>;
    /// Every value inside its range.
    fn is_valid(&self) -> bool;
    /// The record used when no slot is good.
    fn defaults() -> Self;
}

impl Record for Config {
    const MAGIC: [u8; 4] = MAGIC;
    const VERSION: u16 = LAYOUT_VERSION;
    const PAYLOAD_LEN: usize = PAYLOAD_LEN;
    fn encode(&self, buf: &mut [u8]) -> Option<usize> {
        Config::encode(self, buf)
    }
    fn decode(buf: &[u8]) -> Option<Self> {
        Config::decode(buf)
    }
    fn is_valid(&self) -> bool {
        Config::is_valid(self)
    }
    fn defaults() -> Self {
        Config::default()
    }
}

/// The result of [`ConfigStore::load`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Loaded<R = Config> {
    /// The configuration in force (defaults when no slot was good).
    pub config: R,
    /// True when `config` are the defaults because no slot was good.
    pub defaults: bool,
    /// What each slot held.
    pub slots: [SlotState; 2],
}

/// Errors of [`ConfigStore::save`] and [`ConfigStore::begin_save`], and
/// the failed end of a stepped save ([`SaveStatus::Done`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SaveError<E> {
    /// The configuration has a value out of range.
    Invalid,
    /// The storage is smaller than two slots.
    TooSmall,
    /// The storage failed.
    Storage(E),
}

/// Where a stepped save stands: the answer of [`ConfigStore::poll`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SaveStatus<E> {
    /// No save is staged.
    Idle,
    /// A save goes on: poll again (at the next pass of the loop).
    Busy,
    /// The save has just ended, with its result; reported once, then
    /// [`SaveStatus::Idle`]. On `Ok` the new copy is in the storage and is
    /// what [`ConfigStore::load`] returns; on `Err` the storage holds what it
    /// held before (the slot written was not the newest good one).
    Done(Result<(), SaveError<E>>),
}

/// Bytes of the CRC-32 after the payload.
const CRC_LEN: usize = 4;

/// Bytes one stored copy takes at the start of its slot: header, payload
/// and CRC-32 (12 + [`PAYLOAD_LEN`] + 4). The rest of the slot is never
/// written; [`ConfigStore`] keeps this many bytes in RAM for a save.
pub const RECORD_LEN: usize = record_len(PAYLOAD_LEN);

// The record fits in its slot (checked when compiling).
const _: () = assert!(RECORD_LEN <= SLOT_LEN);

/// The CRC-32 of [`crc32`] over pieces: the register after `data`, without
/// the initial and final inversion, so that
/// `!crc32_update(crc32_update(!0, a), b) == crc32(a ‖ b)`. Not inlined:
/// one copy of the bit loop for the header, payload and staging.
#[inline(never)]
fn crc32_update(mut crc: u32, data: &[u8]) -> u32 {
    for &b in data {
        crc ^= u32::from(b);
        for _ in 0..8 {
            let mask = (crc & 1).wrapping_neg();
            crc = (crc >> 1) ^ (0xEDB8_8320 & mask);
        }
    }
    crc
}

/// Which slot holds the newest good copy, as far as the store knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Newest {
    /// Not read yet, or a slot could not be read.
    Unknown,
    /// Both slots were read and neither is good.
    NoGoodSlot,
    /// This slot, with this sequence number.
    Slot { slot: usize, seq: u32 },
}

/// The step a save is at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Preparing the slot (erasing it on NOR flash); `done` bytes are ready.
    Erase { done: usize },
    /// Writing the record; `pos` bytes are taken.
    Write { pos: usize },
    /// Waiting until the last bytes are in the storage.
    Flush,
}

/// A save under way: the staged record goes to `slot` with `seq`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Job {
    slot: usize,
    seq: u32,
    /// Bytes of the staged record.
    len: usize,
    phase: Phase,
}

/// The result of reading both slots.
struct Scan<E, R> {
    slots: [SlotState; 2],
    /// The newest good slot: its index, sequence number and configuration.
    best: Option<(usize, u32, R)>,
    /// The first read error, if a slot could not be read.
    error: Option<E>,
}

/// Two-slot configuration store over a [`Storage`], with a save that runs
/// in steps beside a main loop.
///
/// A save writes the slot that does not hold the newest good copy, with the
/// next sequence number (wrapping, compared RFC 1982 style); the other slot
/// is never touched, so a power cut at any point of a save leaves either
/// the old copy or the new one in force, never the defaults while a good
/// copy existed and never a mix (a part-written slot fails its CRC-32).
/// `tests/config_powercut.rs` cuts the power at every byte, word and erase
/// of a save on fault-injecting EEPROM and NOR flash models to show it.
///
/// # In a main loop
///
/// ```
/// use suntracker::config::{Config, ConfigStore, MemStorage, SaveStatus};
///
/// let mut store = ConfigStore::new(MemStorage::<512>::new());
/// let config = store.load().config; // at boot: reads only
/// store.begin_save(&config).unwrap(); // console `save`: stages, writes nothing
/// loop {
///     // ... step the motors, serve the console ...
///     match store.poll() {
///         SaveStatus::Busy => continue,           // at most one storage step per pass
///         SaveStatus::Done(result) => { result.unwrap(); break }
///         SaveStatus::Idle => break,
///     }
/// }
/// ```
///
/// Each [`ConfigStore::poll`] makes at most one call into the storage: one
/// [`Storage::erase_step`], [`Storage::write_step`] or
/// [`Storage::flush_step`], none of which waits (an AVR EEPROM byte is
/// started and left to the hardware; a NOR flash write step programs a few
/// words). What the hardware itself stalls is the storage's to document: a
/// sector erase of the STM32F411's flash stalls every flash read, and so
/// the CPU, for the whole erase ([`crate::persist`]).
///
/// RAM: the store keeps the staged record (`N` bytes: [`RECORD_LEN`] for
/// the [`Config`]) and a few words; [`ConfigStore::load`] uses a buffer of
/// `N` bytes on the stack.
///
/// The store keeps any [`Record`] `R` in records of `N` bytes (header,
/// payload, CRC-32: [`record_len`]); [`ConfigStore::new`] makes the
/// [`Config`]'s, [`ConfigStore::for_record`] another record's.
#[derive(Debug)]
pub struct ConfigStore<S, R = Config, const N: usize = RECORD_LEN> {
    storage: S,
    newest: Newest,
    job: Option<Job>,
    staged: [u8; N],
    record: core::marker::PhantomData<R>,
}

/// Bytes one stored copy of a record with `payload_len` bytes of payload
/// takes: header, payload and CRC-32 (the `N` of a [`ConfigStore`]).
pub const fn record_len(payload_len: usize) -> usize {
    HEADER_LEN + payload_len + CRC_LEN
}

fn seq_newer(a: u32, b: u32) -> bool {
    // Serial-number arithmetic (RFC 1982 style): a is newer than b.
    a != b && a.wrapping_sub(b) < 0x8000_0000
}

/// Offset of byte `at` of slot `slot`, checked.
fn slot_offset(slot: usize, at: usize) -> Option<usize> {
    slot.checked_mul(SLOT_LEN)?.checked_add(at)
}

impl<S: Storage> ConfigStore<S> {
    /// A store of the tracker's [`Config`] over `storage`; nothing is read
    /// until [`ConfigStore::load`] or a save.
    pub fn new(storage: S) -> Self {
        Self::for_record(storage)
    }
}

impl<S: Storage, R: Record, const N: usize> ConfigStore<S, R, N> {
    /// `N` holds a record of `R` and a slot holds `N` (checked when
    /// compiling each store type).
    const FITS: () = assert!(N == record_len(R::PAYLOAD_LEN) && N <= SLOT_LEN);

    /// A store of record `R` over `storage`; nothing is read until
    /// [`ConfigStore::load`] or a save.
    pub fn for_record(storage: S) -> Self {
        let () = Self::FITS;
        ConfigStore {
            storage,
            newest: Newest::Unknown,
            job: None,
            staged: [0; N],
            record: core::marker::PhantomData,
        }
    }

    /// Gives the storage back; a save under way is abandoned (the storage
    /// then holds the old copy, and the slot being written is not good).
    pub fn release(self) -> S {
        self.storage
    }

    /// The storage, to look at (a board's status, tests).
    pub fn storage(&self) -> &S {
        &self.storage
    }

    /// True while a save is staged and not yet done.
    pub fn is_saving(&self) -> bool {
        self.job.is_some()
    }

    /// Reads and checks slot `slot`: its state and, when good, its
    /// configuration; `Err` when the storage could not be read.
    // The good copy goes into `out` (the slot state alone is returned: a
    // returned `(SlotState, Option<Config>)` made the compiler keep a
    // 149-byte constant of it in an AVR's RAM).
    // Not inlined: one copy for both slots.
    #[inline(never)]
    fn read_slot(&mut self, slot: usize, out: &mut Option<R>) -> Result<SlotState, S::Error> {
        const CORRUPT: SlotState = SlotState::Corrupt;
        let Some(base) = slot_offset(slot, 0) else {
            return Ok(CORRUPT);
        };
        let mut header = [0u8; HEADER_LEN];
        self.storage.read(base, &mut header)?;
        let [m0, m1, m2, m3, v0, v1, l0, l1, s0, s1, s2, s3] = header;
        if [m0, m1, m2, m3] != R::MAGIC {
            return Ok(SlotState::Empty);
        }
        let version = u16::from_le_bytes([v0, v1]);
        let len = usize::from(u16::from_le_bytes([l0, l1]));
        let seq = u32::from_le_bytes([s0, s1, s2, s3]);
        // The CRC must lie inside the slot.
        let crc_at = match HEADER_LEN.checked_add(len) {
            Some(at) if at.checked_add(CRC_LEN).is_some_and(|end| end <= SLOT_LEN) => at,
            _ => return Ok(CORRUPT),
        };
        let mut crc = crc32_update(!0, &header);
        // The payload, in small pieces into the CRC; kept when it has this
        // layout's version and length (another one only decides between
        // `OldVersion` and `Corrupt`).
        let current = version == R::VERSION && len == R::PAYLOAD_LEN;
        let mut payload = [0u8; N];
        let mut chunk = [0u8; 16];
        let mut at = HEADER_LEN;
        while at < crc_at {
            let n = (crc_at - at).min(chunk.len());
            let (Some(part), Some(from)) = (chunk.get_mut(..n), slot_offset(slot, at)) else {
                return Ok(CORRUPT);
            };
            self.storage.read(from, part)?;
            crc = crc32_update(crc, part);
            let into = at - HEADER_LEN;
            if let (true, Some(keep)) = (current, payload.get_mut(into..into + n)) {
                keep.copy_from_slice(part);
            }
            at += n;
        }
        let mut stored = [0u8; CRC_LEN];
        let Some(at) = slot_offset(slot, crc_at) else {
            return Ok(CORRUPT);
        };
        self.storage.read(at, &mut stored)?;
        if !crc != u32::from_le_bytes(stored) {
            return Ok(CORRUPT);
        }
        if version != R::VERSION {
            return Ok(SlotState::OldVersion(version));
        }
        if !current {
            return Ok(CORRUPT);
        }
        match payload.get(..R::PAYLOAD_LEN).and_then(R::decode) {
            Some(cfg) => {
                *out = Some(cfg);
                Ok(SlotState::Good(seq))
            }
            None => Ok(CORRUPT),
        }
    }

    /// Reads both slots; remembers which holds the newest good copy.
    fn scan(&mut self) -> Scan<S::Error, R> {
        let mut scan = Scan {
            slots: [SlotState::Unreadable; 2],
            best: None,
            error: None,
        };
        for slot in 0..2 {
            let mut cfg = None;
            let state = match self.read_slot(slot, &mut cfg) {
                Ok(state) => {
                    if let (SlotState::Good(seq), Some(cfg)) = (state, cfg) {
                        let newer = match scan.best {
                            Some((_, best_seq, _)) => seq_newer(seq, best_seq),
                            None => true,
                        };
                        if newer {
                            scan.best = Some((slot, seq, cfg));
                        }
                    }
                    state
                }
                Err(e) => {
                    if scan.error.is_none() {
                        scan.error = Some(e);
                    }
                    SlotState::Unreadable
                }
            };
            if let Some(s) = scan.slots.get_mut(slot) {
                *s = state;
            }
        }
        self.newest = match (&scan.best, &scan.error) {
            (Some((slot, seq, _)), _) => Newest::Slot {
                slot: *slot,
                seq: *seq,
            },
            (None, Some(_)) => Newest::Unknown,
            (None, None) => Newest::NoGoodSlot,
        };
        scan
    }

    /// Reads both slots and returns the newest good configuration, or the
    /// defaults when neither is good. Only reads (two slots, a CRC each);
    /// a save under way goes on.
    pub fn load(&mut self) -> Loaded<R> {
        let scan = self.scan();
        match scan.best {
            Some((_, _, config)) => Loaded {
                config,
                defaults: false,
                slots: scan.slots,
            },
            None => Loaded {
                config: R::defaults(),
                defaults: true,
                slots: scan.slots,
            },
        }
    }

    /// The slot and sequence number the next save writes: the slot not
    /// holding the newest good copy. Reads the slots when that is not known;
    /// refuses to write when a slot cannot be read (it might be the only
    /// good copy).
    fn target(&mut self) -> Result<(usize, u32), SaveError<S::Error>> {
        if self.newest == Newest::Unknown {
            if let Some(e) = self.scan().error {
                return Err(SaveError::Storage(e));
            }
        }
        Ok(match self.newest {
            Newest::Slot { slot, seq } => (if slot == 0 { 1 } else { 0 }, seq.wrapping_add(1)),
            Newest::NoGoodSlot | Newest::Unknown => (0, 1),
        })
    }

    /// Encodes `cfg` with sequence `seq` into the staged record; its
    /// length, or `None` when it does not fit.
    fn stage(&mut self, cfg: &R, seq: u32) -> Option<usize> {
        let buf: &mut [u8] = &mut self.staged;
        let n = cfg.encode(buf.get_mut(HEADER_LEN..)?)?;
        let crc_at = HEADER_LEN.checked_add(n)?;
        let mut w = Writer {
            buf: &mut *buf,
            pos: 0,
            overflow: false,
        };
        w.bytes(&R::MAGIC);
        w.u16(R::VERSION);
        w.u16(u16::try_from(n).ok()?);
        w.u32(seq);
        if w.overflow {
            return None;
        }
        let crc = !crc32_update(!0, buf.get(..crc_at)?);
        let mut w = Writer {
            buf,
            pos: crc_at,
            overflow: false,
        };
        w.u32(crc);
        if w.overflow {
            return None;
        }
        crc_at.checked_add(CRC_LEN)
    }

    /// Starts saving `cfg`: checks it, picks the slot (reading the slots
    /// first if the store has not), encodes the record into RAM. Writes
    /// nothing: [`ConfigStore::poll`] does, step by step. A save already
    /// under way is replaced by this one (its slot is written again from
    /// the start). A refused request (an error) leaves a save under way
    /// going on.
    pub fn begin_save(&mut self, cfg: &R) -> Result<(), SaveError<S::Error>> {
        if !cfg.is_valid() {
            return Err(SaveError::Invalid);
        }
        if self.storage.capacity() < 2 * SLOT_LEN {
            return Err(SaveError::TooSmall);
        }
        let (slot, seq) = self.target()?;
        // The staged record is overwritten now: drop the old job first (an
        // encoding failure, which the fixed layout rules out, leaves none).
        self.job = None;
        let len = self.stage(cfg, seq).ok_or(SaveError::TooSmall)?;
        self.job = Some(Job {
            slot,
            seq,
            len,
            phase: Phase::Erase { done: 0 },
        });
        Ok(())
    }

    /// Advances a staged save by one storage step, without waiting:
    /// [`SaveStatus::Busy`] while it goes on, [`SaveStatus::Done`] once at
    /// its end, [`SaveStatus::Idle`] when no save is staged.
    pub fn poll(&mut self) -> SaveStatus<S::Error> {
        let Some(job) = self.job else {
            return SaveStatus::Idle;
        };
        match self.step(job) {
            Ok(Some(phase)) => {
                self.job = Some(Job { phase, ..job });
                SaveStatus::Busy
            }
            Ok(None) => {
                self.job = None;
                self.newest = Newest::Slot {
                    slot: job.slot,
                    seq: job.seq,
                };
                SaveStatus::Done(Ok(()))
            }
            Err(e) => {
                self.job = None;
                SaveStatus::Done(Err(e))
            }
        }
    }

    /// One storage step of `job`: the next phase, or `None` when done.
    fn step(&mut self, job: Job) -> Result<Option<Phase>, SaveError<S::Error>> {
        let offset = |at: usize| slot_offset(job.slot, at).ok_or(SaveError::TooSmall);
        match job.phase {
            Phase::Erase { done } => {
                let left = SLOT_LEN.saturating_sub(done);
                let n = self
                    .storage
                    .erase_step(offset(done)?, left)
                    .map_err(SaveError::Storage)?;
                let done = done.saturating_add(n.min(left));
                Ok(Some(if done >= SLOT_LEN {
                    Phase::Write { pos: 0 }
                } else {
                    Phase::Erase { done }
                }))
            }
            Phase::Write { pos } => {
                let data = self.staged.get(pos..job.len).ok_or(SaveError::TooSmall)?;
                let n = self
                    .storage
                    .write_step(offset(pos)?, data)
                    .map_err(SaveError::Storage)?;
                let pos = pos.saturating_add(n.min(data.len()));
                Ok(Some(if pos >= job.len {
                    Phase::Flush
                } else {
                    Phase::Write { pos }
                }))
            }
            Phase::Flush => {
                if self.storage.flush_step().map_err(SaveError::Storage)? {
                    Ok(None)
                } else {
                    Ok(Some(Phase::Flush))
                }
            }
        }
    }

    /// Writes `cfg` into the slot not holding the newest good copy and
    /// returns when it is done: [`ConfigStore::begin_save`], then
    /// [`ConfigStore::poll`] until done (a storage that stays busy keeps it
    /// waiting). For hosts and tests; a firmware loop polls instead.
    pub fn save(&mut self, cfg: &R) -> Result<(), SaveError<S::Error>> {
        self.begin_save(cfg)?;
        loop {
            match self.poll() {
                SaveStatus::Busy => {}
                SaveStatus::Done(result) => return result,
                // Not reached: `begin_save` staged a job, and only `Done`
                // ends it.
                SaveStatus::Idle => return Ok(()),
            }
        }
    }
}

/// Storage in RAM (tests, simulation): `N` bytes, erased to 0xFF.
#[derive(Debug, Clone)]
pub struct MemStorage<const N: usize> {
    /// The bytes.
    pub bytes: [u8; N],
    /// When `Some(k)`, the next write stops after `k` bytes and fails, as a
    /// power cut would (then the budget is cleared).
    pub tear_after: Option<usize>,
}

/// Errors of [`MemStorage`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MemError {
    /// Access beyond the end.
    OutOfRange,
    /// The write was cut short.
    Torn,
}

impl<const N: usize> MemStorage<N> {
    /// Erased storage.
    pub fn new() -> Self {
        MemStorage {
            bytes: [0xFF; N],
            tear_after: None,
        }
    }
}

impl<const N: usize> Default for MemStorage<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Storage for MemStorage<N> {
    type Error = MemError;
    fn capacity(&self) -> usize {
        N
    }
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), MemError> {
        let end = offset.checked_add(buf.len()).ok_or(MemError::OutOfRange)?;
        let src = self.bytes.get(offset..end).ok_or(MemError::OutOfRange)?;
        buf.copy_from_slice(src);
        Ok(())
    }
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), MemError> {
        let end = offset.checked_add(data.len()).ok_or(MemError::OutOfRange)?;
        let dst = self
            .bytes
            .get_mut(offset..end)
            .ok_or(MemError::OutOfRange)?;
        match self.tear_after.take() {
            Some(k) if k < data.len() => {
                if let (Some(d), Some(s)) = (dst.get_mut(..k), data.get(..k)) {
                    d.copy_from_slice(s);
                }
                Err(MemError::Torn)
            }
            _ => {
                dst.copy_from_slice(data);
                Ok(())
            }
        }
    }
}
