//! The dotted keys of the configuration's fields ([`Field`], as the
//! console and the log name them) and the texts of their ranges and rules
//! ([`Reason`]): enums, each text linked only where it is printed.

use crate::text::FlashStr;

/// An enum of names: each variant with its text (a constant `&str`
/// expression), the text only through a function (linked where called) and
/// `Debug`/`Display`; `ALL` lists the variants.
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

/// Dotted keys of one axis's fields (`axis.c.*` or `axis.a.*`).
pub(super) struct AxisKeys {
    pub(super) counts_per_motor_rev: Field,
    pub(super) microsteps: Field,
    pub(super) gear_ratio: Field,
    pub(super) counts_per_deg: Field,
    pub(super) min_deg: Field,
    pub(super) max_deg: Field,
    pub(super) home_deg: Field,
    pub(super) backlash_deg: Field,
    pub(super) max_speed_deg_s: Field,
    pub(super) deadband_deg: Field,
}

/// The keys of the C axis (`Config::axes[0]`), then the A axis.
pub(super) const AXIS_KEYS: [AxisKeys; 2] = [
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
