//! The dotted keys of the configuration's fields ([`Field`], as the
//! console and the log name them) and the texts of their ranges and rules
//! ([`Reason`]): enums, each text linked only where it is printed.

use super::range_text::{f32s, range_text, same_f32, same_u32, u16s, u32s, u8s, Num, Piece};
use super::ranges as r;
use crate::text::FlashStr;
use Piece::{Offset, Str};

/// An enum of names: each variant with its text (a constant `&str`
/// expression), the texts in one [`FlashStrs`](crate::text::FlashStrs) table
/// read through a function (linked where called), and `Debug`/`Display`;
/// `ALL` lists the variants.
macro_rules! named {
    ($(#[$m:meta])* $vis:vis enum $name:ident fn $f:ident { $($v:ident => $s:expr,)* }) => {
        $(#[$m])*
        #[derive(Clone, Copy, PartialEq, Eq)]
        #[allow(missing_docs)]
        $vis enum $name { $($v,)* }
        impl $name {
            /// Every variant, in declaration order.
            pub const ALL: &'static [$name] = &[$($name::$v,)*];

            /// The text (in flash on AVR: [`FlashStr`]).
            pub fn $f(self) -> FlashStr {
                // One table of the texts, by the variant's number (they
                // are declared in the same order; `ALL` lists them so).
                crate::flash_strs!($($s),*)
                    .get(self as usize)
                    .unwrap_or(crate::flash_str!(""))
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
    /// A field of [`Config`](super::Config) by its dotted key with unit ([`Field::name`]).
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
        ModbusAddress => "modbus.address",
        ModbusBaud => "modbus.baud",
        ModbusParity => "modbus.parity",
        ModbusWrite => "modbus.write",
        ModbusTimeoutS => "modbus.timeout_s",
        StowSnowSlopeDeg => "stow.snow_slope_deg",
        StowSnowReleaseS => "stow.snow_release_s",
        StowHailSlopeDeg => "stow.hail_slope_deg",
        StowHailReleaseS => "stow.hail_release_s",
        StowExternalSlopeDeg => "stow.external_slope_deg",
        StowExternalActive => "stow.external_active",
        StowOnSensorFault => "stow.on_sensor_fault",
        SupplyStowMv => "supply.stow_mv",
        SupplyResumeMv => "supply.resume_mv",
        OvercastRatio => "overcast.ratio",
        OvercastEnterS => "overcast.enter_s",
        OvercastLeaveS => "overcast.leave_s",
        OvercastMaxMovesPerHour => "overcast.max_moves_per_hour",
        AxisCContinuous => "axis.c.continuous",
        SiteUtcOffsetH => "site.utc_offset_h",
        WindMSPerHz => "wind.m_s_per_hz",
        ModbusTimeoutStow => "modbus.timeout_stow",
        AxisCDrive => "axis.c.drive",
        AxisCMaxCurrentMa => "axis.c.max_current_ma",
        AxisCOvercurrentMs => "axis.c.overcurrent_ms",
        AxisADrive => "axis.a.drive",
        AxisAMaxCurrentMa => "axis.a.max_current_ma",
        AxisAOvercurrentMs => "axis.a.overcurrent_ms",
    }
}

// The texts of the ranges are built from `ranges`' constants; a text shared
// by several ranges is built from the first, and the others must equal it.
const _: () = assert!(same_f32(r::DEADBAND_DEG, r::BACKLASH_DEG));
const _: () = assert!(same_f32(r::HEADING_DEG, r::LON_DEG));
const _: () = assert!(same_u32(r::SENSOR_TIMEOUT_S, r::RECHECK_S));
const _: () = assert!(same_u32(r::WIND_RELEASE_S, r::MAX_BACKWARD_S));

named! {
    /// The range or rule a field breaks ([`Reason::text`]). A range's text
    /// is built from its constant in [`ranges`](super::ranges).
    pub enum Reason fn text {
        CountsPerMotorRev => range_text!(
            u32s(r::COUNTS_PER_MOTOR_REV),
            Str(" full steps or encoder counts per motor revolution"),
        ),
        Microsteps => range_text!(u16s(r::MICROSTEPS), Str(" microsteps per full step")),
        GearRatio => range_text!(
            f32s(r::GEAR_RATIO),
            Str(" motor revolutions per axis revolution"),
        ),
        CountsPerDeg => range_text!(
            Str("counts * microsteps * gear / 360 must be "),
            f32s(r::COUNTS_PER_DEG),
            Str(" counts per degree"),
        ),
        LimitDeg => range_text!(f32s(r::LIMIT_DEG), Str(" deg")),
        AboveMinDeg => "must be above min_deg",
        HomeNearMinDeg => range_text!(
            Str("min_deg"),
            Offset(Num::f32(r::HOME_ABOVE_MIN_DEG.0)),
            Str(" deg ... min_deg"),
            Offset(Num::f32(r::HOME_ABOVE_MIN_DEG.1)),
            Str(" deg and at most max_deg: the switch is at the low end of the travel"),
        ),
        // Also `DEADBAND_DEG`.
        Deg0To5 => range_text!(f32s(r::BACKLASH_DEG), Str(" deg")),
        SpeedDegS => range_text!(f32s(r::MAX_SPEED_DEG_S), Str(" deg/s")),
        Latitude => range_text!(f32s(r::LAT_DEG), Str(" deg")),
        // Also `HEADING_DEG`.
        Deg180 => range_text!(f32s(r::LON_DEG), Str(" deg")),
        ElevationM => range_text!(f32s(r::ELEVATION_M), Str(" m")),
        TableStepS => range_text!(u32s(r::TABLE_STEP_S), Str(" s")),
        WholeMinutesOfDay => "whole minutes dividing a day (86,400 s)",
        S0To3600 => range_text!(u32s(r::HOLD_S), Str(" s")),
        // Also `SENSOR_TIMEOUT_S`.
        S1To3600 => range_text!(u32s(r::RECHECK_S), Str(" s")),
        S1To86400 => range_text!(u32s(r::MAX_TICK_GAP_S), Str(" s")),
        // Also `WIND_RELEASE_S`.
        S0To86400 => range_text!(u32s(r::MAX_BACKWARD_S), Str(" s")),
        StowHz => range_text!(f32s(r::STOW_HZ), Str(" Hz")),
        S0To600 => range_text!(u32s(r::WIND_HOLD_S), Str(" s")),
        MaxDeviationDeg => range_text!(f32s(r::MAX_DEVIATION_DEG), Str(" deg")),
        S1To600 => range_text!(u32s(r::STALL_TIMEOUT_S), Str(" s")),
        MaxRetries => range_text!(u8s(r::MAX_RETRIES)),
        BelowMaxDeviation => "must be below safety.max_deviation_deg",
        TiltOffsetDeg => range_text!(f32s(r::TILT_OFFSET_DEG), Str(" deg")),
        StatusMin => range_text!(
            u16s(r::STATUS_MIN),
            Str(" min (0: no periodic status line)"),
        ),
        ModbusAddress => range_text!(u8s(r::MODBUS_ADDRESS)),
        ModbusBaud => "1200, 2400, 4800, 9600, 19200, 38400, 57600 or 115200 baud",
        ModbusParity => "0 none (2 stop bits), 1 odd, 2 even",
        Switch => "0 off, 1 on",
        SlopeDeg => range_text!(f32s(r::STOW_SLOPE_DEG), Str(" deg")),
        ActiveLevel => "0 low, 1 high",
        SupplyMv => range_text!(u16s(r::SUPPLY_MV), Str(" mV (0: off)")),
        AtLeastStowMv => "must be at least supply.stow_mv",
        OvercastRatio => range_text!(f32s(r::OVERCAST_RATIO), Str(" of the clear sky (0: off)")),
        OvercastMoves => range_text!(u8s(r::OVERCAST_MOVES), Str(" changes an hour")),
        WholeCountsPerTurn => "needs a whole axis.c.gear_ratio (whole motor counts per turn)",
        UtcOffsetH => range_text!(f32s(r::UTC_OFFSET_H), Str(" h east of UTC")),
        WindMSPerHz => range_text!(f32s(r::WIND_M_S_PER_HZ), Str(" m/s per Hz (0: not known)")),
        DriveKind => "0 stepper, 1 servo_encoder, 2 dc_hall, 3 linear_hall, 4 linear_pot, 5 timed",
        DriveNotOnBoard => "no driver for it on this board",
        MaxCurrentMa => range_text!(u16s(r::MAX_CURRENT_MA), Str(" mA")),
        OvercurrentMs => range_text!(u16s(r::OVERCURRENT_MS), Str(" ms")),
    }
}

/// Dotted keys of one axis's fields (`axis.c.*` or `axis.a.*`) that the
/// validation names or bounds its span by: the first and last of the
/// axis's keys in the key table (the deadband also the rule between it and
/// `safety.max_deviation_deg` names).
pub(super) struct AxisKeys {
    pub(super) counts_per_motor_rev: Field,
    pub(super) deadband_deg: Field,
    /// The first of the axis's keys added in layout version 7 (its drive,
    /// current limit and overcurrent time, in that order).
    pub(super) drive: Field,
}

/// The keys of the C axis (`Config::axes[0]`), then the A axis.
pub(super) const AXIS_KEYS: [AxisKeys; 2] = [
    AxisKeys {
        counts_per_motor_rev: Field::AxisCCountsPerMotorRev,
        deadband_deg: Field::AxisCDeadbandDeg,
        drive: Field::AxisCDrive,
    },
    AxisKeys {
        counts_per_motor_rev: Field::AxisACountsPerMotorRev,
        deadband_deg: Field::AxisADeadbandDeg,
        drive: Field::AxisADrive,
    },
];
