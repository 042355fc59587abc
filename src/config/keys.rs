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
/// `ALL` lists the variants. The `@table` form makes the enum, `ALL` and the
/// table (read by `text_at`) only, for an enum whose names are more than its
/// table's texts ([`Field`]).
macro_rules! named {
    ($(#[$m:meta])* $vis:vis enum $name:ident fn $f:ident { $($(#[$vm:meta])* $v:ident => $s:expr,)* }) => {
        named! { @table $(#[$m])* $vis enum $name { $($(#[$vm])* $v => $s,)* } }
        impl $name {
            /// The text (in flash on AVR: [`FlashStr`]).
            pub fn $f(self) -> FlashStr {
                Self::text_at(self as usize)
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
    (@table $(#[$m:meta])* $vis:vis enum $name:ident { $($(#[$vm:meta])* $v:ident => $s:expr,)* }) => {
        $(#[$m])*
        #[derive(Clone, Copy, PartialEq, Eq)]
        #[allow(missing_docs)]
        $vis enum $name { $($(#[$vm])* $v,)* }
        impl $name {
            /// Every variant, in declaration order.
            pub const ALL: &'static [$name] = &[$($(#[$vm])* $name::$v,)*];

            /// The text of the variant numbered `i` (empty past the last).
            fn text_at(i: usize) -> FlashStr {
                // One table of the texts, by the variant's number (they
                // are declared in the same order; `ALL` lists them so).
                crate::flash_strs!(@texts &[$($(#[$vm])* $s),*])
                    .get(i)
                    .unwrap_or(crate::flash_str!(""))
            }
        }
    };
}

named! {
    @table
    /// A field of [`Config`](super::Config) by its dotted key with unit ([`Field::name`]).
    ///
    /// (Its table holds an axis key's name without `axis.c.` or `axis.a.`,
    /// and an A-axis key's not at all: see [`Field::name`].)
    pub enum Field {
        AxisCCountsPerMotorRev => "counts_per_motor_rev",
        AxisCMicrosteps => "microsteps",
        AxisCGearRatio => "gear_ratio",
        AxisCCountsPerDeg => "counts_per_deg",
        AxisCMinDeg => "min_deg",
        AxisCMaxDeg => "max_deg",
        AxisCHomeDeg => "home_deg",
        AxisCBacklashDeg => "backlash_deg",
        AxisCMaxSpeedDegS => "max_speed_deg_s",
        AxisCDeadbandDeg => "deadband_deg",
        // The A axis's keys: each named by its C-axis twin's text (after
        // `axis.a.`, `Field::name`), not kept in the table twice.
        AxisACountsPerMotorRev => "",
        AxisAMicrosteps => "",
        AxisAGearRatio => "",
        AxisACountsPerDeg => "",
        AxisAMinDeg => "",
        AxisAMaxDeg => "",
        AxisAHomeDeg => "",
        AxisABacklashDeg => "",
        AxisAMaxSpeedDegS => "",
        AxisADeadbandDeg => "",
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
        AxisCContinuous => "continuous",
        SiteUtcOffsetH => "site.utc_offset_h",
        WindMSPerHz => "wind.m_s_per_hz",
        ModbusTimeoutStow => "modbus.timeout_stow",
        AxisCDrive => "drive",
        AxisCMaxCurrentMa => "max_current_ma",
        AxisCOvercurrentMs => "overcurrent_ms",
        // (The C-axis twin's name, as above.)
        AxisADrive => "",
        AxisAMaxCurrentMa => "",
        AxisAOvercurrentMs => "",
        AxisCBackSpeedDegS => "back_speed_deg_s",
        // (The C-axis twin's name, as above.)
        AxisABackSpeedDegS => "",
        SupplyCalibrationMv => "supply.calibration_mv",
        #[cfg(feature = "linear")]
        AxisCPivotAMm => "pivot_a_mm",
        #[cfg(feature = "linear")]
        AxisCPivotBMm => "pivot_b_mm",
        #[cfg(feature = "linear")]
        AxisCPivotOffsetDeg => "pivot_offset_deg",
        #[cfg(feature = "linear")]
        AxisCRetractedMm => "retracted_mm",
        #[cfg(feature = "linear")]
        AxisCStrokeMm => "stroke_mm",
        #[cfg(feature = "linear")]
        AxisCPulsesPerMm => "pulses_per_mm",
        #[cfg(feature = "linear")]
        AxisCPotRetractedCounts => "pot_retracted_counts",
        #[cfg(feature = "linear")]
        AxisCPotExtendedCounts => "pot_extended_counts",
        // (The C-axis twin's name, as above.)
        #[cfg(feature = "linear")]
        AxisAPivotAMm => "",
        #[cfg(feature = "linear")]
        AxisAPivotBMm => "",
        #[cfg(feature = "linear")]
        AxisAPivotOffsetDeg => "",
        #[cfg(feature = "linear")]
        AxisARetractedMm => "",
        #[cfg(feature = "linear")]
        AxisAStrokeMm => "",
        #[cfg(feature = "linear")]
        AxisAPulsesPerMm => "",
        #[cfg(feature = "linear")]
        AxisAPotRetractedCounts => "",
        #[cfg(feature = "linear")]
        AxisAPotExtendedCounts => "",
    }
}

/// The prefixes of the axes' keys.
const C_AXIS: FlashStr = crate::flash_str!("axis.c.");
const A_AXIS: FlashStr = crate::flash_str!("axis.a.");

/// A configuration key's dotted name ([`Field::name`]): a prefix and a
/// text. An axis key's text is kept once for both axes, after `axis.c.` or
/// `axis.a.` (the axes have the same keys), which keeps some 330 bytes of
/// names out of every image.
#[derive(Clone, Copy)]
pub struct KeyName {
    /// `axis.c.`, `axis.a.` or empty.
    prefix: FlashStr,
    /// The rest.
    text: FlashStr,
}

impl KeyName {
    /// A name that is one text (the console's `site.postal_code`, a
    /// command's word).
    pub const fn plain(text: FlashStr) -> KeyName {
        KeyName {
            prefix: crate::flash_str!(""),
            text,
        }
    }

    /// Writes the name to `out`.
    pub fn write(self, out: &mut dyn crate::log::Sink) {
        out.flash(self.prefix);
        out.flash(self.text);
    }

    /// Whether `name` is this name, ASCII case ignored (the console's
    /// reading of a key).
    pub fn eq_ignore_ascii_case(self, name: &str) -> bool {
        match name.as_bytes().split_at_checked(self.prefix.len()) {
            Some((head, rest)) => {
                self.prefix.eq_ignore_ascii_case_bytes(head)
                    && self.text.eq_ignore_ascii_case_bytes(rest)
            }
            None => false,
        }
    }
}

impl core::fmt::Display for KeyName {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(&self.prefix, f)?;
        core::fmt::Display::fmt(&self.text, f)
    }
}

impl core::fmt::Debug for KeyName {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(self, f)
    }
}

impl PartialEq<str> for KeyName {
    fn eq(&self, other: &str) -> bool {
        match other.split_at_checked(self.prefix.len()) {
            Some((head, rest)) => self.prefix == *head && self.text == *rest,
            None => false,
        }
    }
}

impl PartialEq<&str> for KeyName {
    fn eq(&self, other: &&str) -> bool {
        *self == **other
    }
}

impl Field {
    /// The dotted key with unit (`axis.c.gear_ratio`, `site.lat_deg`).
    pub fn name(self) -> KeyName {
        // The axes' keys come in runs: the A axis's two each in the order
        // of a C-axis run (declared above), a run's distance after it.
        const C_RUN_1: (u8, u8) = (
            Field::AxisCCountsPerMotorRev as u8,
            Field::AxisCDeadbandDeg as u8,
        );
        const A_RUN_1: (u8, u8) = (
            Field::AxisACountsPerMotorRev as u8,
            Field::AxisADeadbandDeg as u8,
        );
        const C_RUN_2: (u8, u8) = (Field::AxisCDrive as u8, Field::AxisCOvercurrentMs as u8);
        const A_RUN_2: (u8, u8) = (Field::AxisADrive as u8, Field::AxisAOvercurrentMs as u8);
        // The linear actuators' keys (an image without them: two empty
        // runs, which no key is in).
        #[cfg(feature = "linear")]
        const C_RUN_3: (u8, u8) = (
            Field::AxisCPivotAMm as u8,
            Field::AxisCPotExtendedCounts as u8,
        );
        #[cfg(feature = "linear")]
        const A_RUN_3: (u8, u8) = (
            Field::AxisAPivotAMm as u8,
            Field::AxisAPotExtendedCounts as u8,
        );
        #[cfg(not(feature = "linear"))]
        const C_RUN_3: (u8, u8) = (u8::MAX, 0);
        #[cfg(not(feature = "linear"))]
        const A_RUN_3: (u8, u8) = (u8::MAX, 0);
        const C_ALONE: u8 = Field::AxisCContinuous as u8;
        // A run of one key: the C axis's, then the A axis's.
        const C_BACK: u8 = Field::AxisCBackSpeedDegS as u8;
        const _: () = assert!(Field::AxisABackSpeedDegS as u8 == C_BACK + 1);
        // The first run begins the table, and each A run is as long as its
        // C run.
        const _: () = assert!(C_RUN_1.0 == 0);
        const _: () = assert!(A_RUN_1.1 - A_RUN_1.0 == C_RUN_1.1 - C_RUN_1.0);
        const _: () = assert!(A_RUN_2.1 - A_RUN_2.0 == C_RUN_2.1 - C_RUN_2.0);
        #[cfg(feature = "linear")]
        const _: () = assert!(A_RUN_3.1 - A_RUN_3.0 == C_RUN_3.1 - C_RUN_3.0);
        let i = self as u8;
        let (prefix, text) = if i >= A_RUN_1.0 && i <= A_RUN_1.1 {
            (A_AXIS, i - (A_RUN_1.0 - C_RUN_1.0))
        } else if i >= A_RUN_2.0 && i <= A_RUN_2.1 {
            (A_AXIS, i - (A_RUN_2.0 - C_RUN_2.0))
        } else if i >= A_RUN_3.0 && i <= A_RUN_3.1 {
            (A_AXIS, i - (A_RUN_3.0 - C_RUN_3.0))
        } else if i == C_BACK + 1 {
            (A_AXIS, C_BACK)
        } else if i <= C_RUN_1.1
            || i == C_ALONE
            || i == C_BACK
            || (i >= C_RUN_2.0 && i <= C_RUN_2.1)
            || (i >= C_RUN_3.0 && i <= C_RUN_3.1)
        {
            (C_AXIS, i)
        } else {
            (crate::flash_str!(""), i)
        };
        KeyName {
            prefix,
            text: Field::text_at(usize::from(text)),
        }
    }
}

impl core::fmt::Debug for Field {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(&self.name(), f)
    }
}

impl core::fmt::Display for Field {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(&self.name(), f)
    }
}

impl PartialEq<str> for Field {
    fn eq(&self, other: &str) -> bool {
        self.name() == *other
    }
}

impl PartialEq<&str> for Field {
    fn eq(&self, other: &&str) -> bool {
        self.name() == **other
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
        #[cfg(feature = "linear")]
        LengthMm => range_text!(f32s(r::LENGTH_MM), Str(" mm")),
        #[cfg(feature = "linear")]
        PulsesPerMm => range_text!(f32s(r::PULSES_PER_MM), Str(" pulses per mm")),
        #[cfg(feature = "linear")]
        AdcCounts => range_text!(u16s(r::ADC_COUNTS), Str(" ADC counts")),
        #[cfg(feature = "linear")]
        LinearGeometry => "no triangle: |a - b| < retracted length, extended length < a + b",
        #[cfg(feature = "linear")]
        WithinStroke => "must lie within the actuator's stroke",
        #[cfg(feature = "linear")]
        HomeAtRetracted => "must be the angle fully retracted (linear_pot), within 0.01 deg",
        #[cfg(feature = "linear")]
        PotSpan => "must differ from pot_retracted_counts",
    }
}

/// Dotted keys of one axis's fields (`axis.c.*` or `axis.a.*`) that the
/// validation names or bounds its span by: the first and last of the
/// axis's keys in the key table (the deadband also the rule between it and
/// `safety.max_deviation_deg` names).
pub(super) struct AxisKeys {
    pub(super) counts_per_motor_rev: Field,
    #[cfg(feature = "linear")]
    pub(super) min_deg: Field,
    #[cfg(feature = "linear")]
    pub(super) max_deg: Field,
    #[cfg(feature = "linear")]
    pub(super) home_deg: Field,
    pub(super) deadband_deg: Field,
    /// The first of the axis's keys added in layout version 7 (its drive,
    /// current limit and overcurrent time, in that order).
    pub(super) drive: Field,
    /// The axis's key added in layout version 8.
    pub(super) back_speed_deg_s: Field,
    /// The first and the last of the axis's keys added in layout version
    /// 10 (its linear actuator's, `pivot_a_mm` to `pot_extended_counts`).
    #[cfg(feature = "linear")]
    pub(super) linear: (Field, Field),
    /// The stroke (the linear geometry's rule names it).
    #[cfg(feature = "linear")]
    pub(super) stroke_mm: Field,
}

/// The keys of the C axis (`Config::axes[0]`), then the A axis.
pub(super) const AXIS_KEYS: [AxisKeys; 2] = [
    AxisKeys {
        counts_per_motor_rev: Field::AxisCCountsPerMotorRev,
        #[cfg(feature = "linear")]
        min_deg: Field::AxisCMinDeg,
        #[cfg(feature = "linear")]
        max_deg: Field::AxisCMaxDeg,
        #[cfg(feature = "linear")]
        home_deg: Field::AxisCHomeDeg,
        deadband_deg: Field::AxisCDeadbandDeg,
        drive: Field::AxisCDrive,
        back_speed_deg_s: Field::AxisCBackSpeedDegS,
        #[cfg(feature = "linear")]
        linear: (Field::AxisCPivotAMm, Field::AxisCPotExtendedCounts),
        #[cfg(feature = "linear")]
        stroke_mm: Field::AxisCStrokeMm,
    },
    AxisKeys {
        counts_per_motor_rev: Field::AxisACountsPerMotorRev,
        #[cfg(feature = "linear")]
        min_deg: Field::AxisAMinDeg,
        #[cfg(feature = "linear")]
        max_deg: Field::AxisAMaxDeg,
        #[cfg(feature = "linear")]
        home_deg: Field::AxisAHomeDeg,
        deadband_deg: Field::AxisADeadbandDeg,
        drive: Field::AxisADrive,
        back_speed_deg_s: Field::AxisABackSpeedDegS,
        #[cfg(feature = "linear")]
        linear: (Field::AxisAPivotAMm, Field::AxisAPotExtendedCounts),
        #[cfg(feature = "linear")]
        stroke_mm: Field::AxisAStrokeMm,
    },
];

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::{String, ToString};

    /// The A axis's keys as the console and the book name them, written
    /// out here rather than derived from the C axis's.
    const A_AXIS_NAMES: &[(Field, &str)] = &[
        (Field::AxisACountsPerMotorRev, "axis.a.counts_per_motor_rev"),
        (Field::AxisAMicrosteps, "axis.a.microsteps"),
        (Field::AxisAGearRatio, "axis.a.gear_ratio"),
        (Field::AxisACountsPerDeg, "axis.a.counts_per_deg"),
        (Field::AxisAMinDeg, "axis.a.min_deg"),
        (Field::AxisAMaxDeg, "axis.a.max_deg"),
        (Field::AxisAHomeDeg, "axis.a.home_deg"),
        (Field::AxisABacklashDeg, "axis.a.backlash_deg"),
        (Field::AxisAMaxSpeedDegS, "axis.a.max_speed_deg_s"),
        (Field::AxisADeadbandDeg, "axis.a.deadband_deg"),
        (Field::AxisADrive, "axis.a.drive"),
        (Field::AxisAMaxCurrentMa, "axis.a.max_current_ma"),
        (Field::AxisAOvercurrentMs, "axis.a.overcurrent_ms"),
        (Field::AxisABackSpeedDegS, "axis.a.back_speed_deg_s"),
        #[cfg(feature = "linear")]
        (Field::AxisAPivotAMm, "axis.a.pivot_a_mm"),
        #[cfg(feature = "linear")]
        (Field::AxisAPivotBMm, "axis.a.pivot_b_mm"),
        #[cfg(feature = "linear")]
        (Field::AxisAPivotOffsetDeg, "axis.a.pivot_offset_deg"),
        #[cfg(feature = "linear")]
        (Field::AxisARetractedMm, "axis.a.retracted_mm"),
        #[cfg(feature = "linear")]
        (Field::AxisAStrokeMm, "axis.a.stroke_mm"),
        #[cfg(feature = "linear")]
        (Field::AxisAPulsesPerMm, "axis.a.pulses_per_mm"),
        #[cfg(feature = "linear")]
        (
            Field::AxisAPotRetractedCounts,
            "axis.a.pot_retracted_counts",
        ),
        #[cfg(feature = "linear")]
        (Field::AxisAPotExtendedCounts, "axis.a.pot_extended_counts"),
    ];

    /// For a key of the A axis, the same key of the C axis (by the text
    /// both names end in); else `None`.
    fn c_axis_twin(field: Field) -> Option<Field> {
        let name = field.name();
        if name.prefix != A_AXIS {
            return None;
        }
        Field::ALL
            .iter()
            .copied()
            .find(|c| c.name().prefix == C_AXIS && Field::text_at(*c as usize) == name.text)
    }

    #[test]
    fn axis_keys_are_named_from_one_text_for_both_axes() {
        for &(field, name) in A_AXIS_NAMES {
            assert_eq!(field.name().to_string(), name);
            assert!(field.name() == name);
            assert!(field.name().eq_ignore_ascii_case(&name.to_uppercase()));
            let twin = c_axis_twin(field).map(|c| c.name().to_string());
            assert_eq!(twin, Some(name.replace("axis.a.", "axis.c.")));
            assert!(
                Field::text_at(field as usize).is_empty(),
                "{name} kept in the table"
            );
        }
        let a_axis: usize = Field::ALL
            .iter()
            .filter(|f| c_axis_twin(**f).is_some())
            .count();
        assert_eq!(a_axis, A_AXIS_NAMES.len());
        // Every other key is its table's text, after `axis.c.` for the C
        // axis's twins and `continuous`.
        let mut c_axis = 0;
        for f in Field::ALL.iter().filter(|f| c_axis_twin(**f).is_none()) {
            let text = Field::text_at(*f as usize).as_str();
            assert!(!text.is_empty());
            let name = f.name().to_string();
            if name.starts_with("axis.") {
                assert_eq!(name, std::format!("axis.c.{text}"));
                c_axis += 1;
            } else {
                assert_eq!(name, text);
            }
        }
        assert_eq!(c_axis, A_AXIS_NAMES.len() + 1);
    }

    #[test]
    fn a_name_matches_only_whole() {
        let gear = Field::AxisAGearRatio.name();
        let not_it: [String; 8] = [
            "axis.a.gear_ratio2".into(),
            "axis.a.gear_rati".into(),
            "axis.c.gear_ratio".into(),
            "axis.a.".into(),
            "axis.a".into(),
            String::new(),
            // A character of two bytes across the prefix's end.
            "axis.a\u{e9}gear_ratio".into(),
            "axis.a.gear_rati\u{f3}".into(),
        ];
        for other in &not_it {
            assert!(!gear.eq_ignore_ascii_case(other), "{other:?}");
            assert!(gear != **other, "{other:?}");
        }
        let lat = Field::SiteLatDeg.name();
        assert!(lat == "site.lat_deg");
        assert!(lat != "SITE.LAT_DEG");
        assert!(lat.eq_ignore_ascii_case("SITE.LAT_DEG"));
    }
}
