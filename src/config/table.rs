//! The key table: every configuration field by its key ([`Field`]), its
//! kind, and where it lives in a [`Config`]. The console reads and writes
//! fields through it (`get`, `set`), and the stored payload
//! ([`super::codec`]) is its fields in its order, so that one table says
//! both.

use super::{Config, Field};

/// A key's value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A real number.
    F32(f32),
    /// A whole number (the `u8`, `u16` and `u32` fields).
    U32(u32),
}

/// Where one field of the table lives, for writing.
macro_rules! key_slot {
    (F32, $e:expr) => {
        Slot::F32(&mut $e)
    };
    // The expression says what the key shows; `get` computes it.
    (Derived, $e:expr) => {
        Slot::Derived
    };
    (U32, $e:expr) => {
        Slot::U32(&mut $e)
    };
    (U16, $e:expr) => {
        Slot::U16(&mut $e)
    };
    (U8, $e:expr) => {
        Slot::U8(&mut $e)
    };
}

/// A field to write, or to read through a copy.
pub(crate) enum Slot<'a> {
    F32(&'a mut f32),
    U32(&'a mut u32),
    U16(&'a mut u16),
    U8(&'a mut u8),
    /// Computed from other fields (read only).
    Derived,
}

/// The key table: each key once, with its kind and where it lives in the
/// configuration. The matches are exhaustive over [`Field`]: a field added
/// to the configuration's keys must be added here.
macro_rules! key_table {
    ($c:ident; $( $field:ident $kind:ident $place:expr; )*) => {
        /// Every key, in the order of the configuration's layout (`get`
        /// lists them in this order). `site.postal_code` is not a field and
        /// not in the table.
        pub const KEYS: &[Field] = &[$(Field::$field,)*];

        /// The field of `key`, to write.
        pub(crate) fn slot($c: &mut Config, key: Field) -> Slot<'_> {
            match key {
                $(Field::$field => key_slot!($kind, $place),)*
            }
        }
    };
}

key_table! { c;
    SiteLatDeg F32 c.site.latitude_deg;
    SiteLonDeg F32 c.site.longitude_deg;
    SiteElevationM F32 c.site.elevation_m;
    ScheduleTableStepS U32 c.schedule.table_step_s;
    ScheduleHoldS U32 c.schedule.hold_s;
    ScheduleRecheckS U32 c.schedule.recheck_s;
    ScheduleMaxTickGapS U32 c.schedule.max_tick_gap_s;
    ScheduleMaxBackwardS U32 c.schedule.max_backward_s;
    AxisCCountsPerMotorRev U32 c.axes[0].counts_per_motor_rev;
    AxisCMicrosteps U16 c.axes[0].microsteps;
    AxisCGearRatio F32 c.axes[0].gear_ratio;
    AxisCCountsPerDeg Derived c.axes[0].counts_per_deg();
    AxisCMinDeg F32 c.axes[0].min_deg;
    AxisCMaxDeg F32 c.axes[0].max_deg;
    AxisCHomeDeg F32 c.axes[0].home_deg;
    AxisCBacklashDeg F32 c.axes[0].backlash_deg;
    AxisCMaxSpeedDegS F32 c.axes[0].max_speed_deg_s;
    AxisCDeadbandDeg F32 c.axes[0].deadband_deg;
    AxisACountsPerMotorRev U32 c.axes[1].counts_per_motor_rev;
    AxisAMicrosteps U16 c.axes[1].microsteps;
    AxisAGearRatio F32 c.axes[1].gear_ratio;
    AxisACountsPerDeg Derived c.axes[1].counts_per_deg();
    AxisAMinDeg F32 c.axes[1].min_deg;
    AxisAMaxDeg F32 c.axes[1].max_deg;
    AxisAHomeDeg F32 c.axes[1].home_deg;
    AxisABacklashDeg F32 c.axes[1].backlash_deg;
    AxisAMaxSpeedDegS F32 c.axes[1].max_speed_deg_s;
    AxisADeadbandDeg F32 c.axes[1].deadband_deg;
    WindStowHz F32 c.wind.threshold_hz;
    WindHoldS U32 c.wind.hold_s;
    WindReleaseS U32 c.wind.release_s;
    SafetyMaxDeviationDeg F32 c.safety.max_deviation_deg;
    SafetyStallTimeoutS U32 c.safety.stall_timeout_s;
    SafetySensorTimeoutS U32 c.safety.sensor_timeout_s;
    SafetyMaxRetries U8 c.safety.max_retries;
    CalibrationDeclinationDeg F32 c.calibration.declination_deg;
    CalibrationHeadingOffsetDeg F32 c.calibration.heading_offset_deg;
    CalibrationTiltXOffsetDeg F32 c.calibration.tilt_x_offset_deg;
    CalibrationTiltYOffsetDeg F32 c.calibration.tilt_y_offset_deg;
    LogStatusMin U16 c.log.status_every_min;
}

/// The value of `key` in `config`: read through its slot in a copy
/// (one table of places, not a second `match` over the keys); the derived
/// counts per degree computed for the axis of `key`.
pub fn get(config: &Config, key: Field) -> Value {
    let mut copy = *config;
    match slot(&mut copy, key) {
        Slot::F32(v) => Value::F32(*v),
        Slot::U32(v) => Value::U32(*v),
        Slot::U16(v) => Value::U32(u32::from(*v)),
        Slot::U8(v) => Value::U32(u32::from(*v)),
        Slot::Derived => {
            let axis = if key == Field::AxisCCountsPerDeg {
                0
            } else {
                1
            };
            Value::F32(config.axes.get(axis).map_or(0.0, |a| a.counts_per_deg()))
        }
    }
}

/// True for a key `set` refuses (`axis.*.counts_per_deg`, derived).
pub fn is_read_only(key: Field) -> bool {
    matches!(key, Field::AxisCCountsPerDeg | Field::AxisACountsPerDeg)
}
