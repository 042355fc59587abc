//! The key table: every configuration field by its key ([`Field`]), its
//! kind, where it lives in a [`Config`] and its range ([`super::ranges`]).
//! The console reads and writes fields through it (`get`, `set`), the
//! stored payload ([`super::codec`]) is its fields in its order, and
//! [`Config::validate`] checks its ranges in that order, so that one table
//! says all three.

#[cfg(feature = "linear")]
use super::LinearMount;
use super::{
    ranges as r, AxisConfig, Calibration, Config, Field, LogConfig, ModbusConfig, OvercastConfig,
    Reason, SafetyConfig, SiteConfig, StowConfig, SupplyConfig, WindConfig,
};
use crate::plan::ScheduleConfig;
use crate::safety::OperatorHold;

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

/// One field's value as the defaults table stores it: an `f32`'s bits
/// or the whole number; 0 for a derived key (not stored).
macro_rules! key_bits {
    (F32, $e:expr) => {
        $e.to_bits()
    };
    (Derived, $e:expr) => {
        0
    };
    // Widening casts (`u32::from` is not `const`).
    ($int:ident, $e:expr) => {
        $e as u32
    };
}

/// Where one key's range goes in the range table: the bounds in the
/// field's own kind, an `f32`'s bits or the whole number.
macro_rules! key_range {
    (F32, $range:expr, $why:ident) => {
        Range {
            lo: $range.0.to_bits(),
            hi: $range.1.to_bits(),
            reason: Reason::$why,
        }
    };
    (Derived, $range:expr, $why:ident) => {
        key_range!(F32, $range, $why)
    };
    // Widening casts (`u32::from` is not `const`).
    ($int:ident, $range:expr, $why:ident) => {
        Range {
            lo: $range.0 as u32,
            hi: $range.1 as u32,
            reason: Reason::$why,
        }
    };
}

/// A key's range and the reason its error names. The bounds are in the
/// field's own kind: an `f32`'s bits ([`f32::to_bits`]) for a real number,
/// else the whole number. For the home switch angles they are offsets
/// from the axis's `min_deg` ([`r::HOME_ABOVE_MIN_DEG`]).
#[derive(Clone, Copy)]
pub(crate) struct Range {
    pub(crate) lo: u32,
    pub(crate) hi: u32,
    pub(crate) reason: Reason,
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
    ($c:ident; $( $(#[$m:meta])* $field:ident $kind:ident $place:expr, $range:ident $why:ident; )*) => {
        /// [`KEYS`] when compiling (the tables built from it, the layout's
        /// places); at run time [`KEYS`] is read, from program memory on
        /// the AVR.
        pub(crate) const KEY_LIST: &[Field] = &[$($(#[$m])* Field::$field,)*];

        crate::progmem! {
            /// Every key, in the order of the configuration's layout (`get`
            /// lists them in this order). `site.postal_code` is not a field
            /// and not in the table. In program memory on the AVR: as a
            /// constant slice it took a byte of RAM a key.
            pub static KEYS: [Field; KEY_LIST.len()] = [$($(#[$m])* Field::$field,)*];
        }

        /// The range of each key of [`KEYS`], at the same place; when
        /// compiling only ([`BOUNDS`] and [`REASONS`] hold it).
        const RANGES: [Range; KEY_LIST.len()] = [$($(#[$m])* key_range!($kind, r::$range, $why),)*];

        /// The value of `key` in `$c` in the defaults table's bits
        /// ([`key_bits`]); when compiling.
        const fn key_bits($c: &Config, key: Field) -> u32 {
            match key {
                $($(#[$m])* Field::$field => key_bits!($kind, $place),)*
            }
        }

        /// The field of `key`, to write.
        pub(crate) fn slot($c: &mut Config, key: Field) -> Slot<'_> {
            match key {
                $($(#[$m])* Field::$field => key_slot!($kind, $place),)*
            }
        }
    };
}

key_table! { c;
    SiteLatDeg F32 c.site.latitude_deg, LAT_DEG Latitude;
    SiteLonDeg F32 c.site.longitude_deg, LON_DEG Deg180;
    SiteElevationM F32 c.site.elevation_m, ELEVATION_M ElevationM;
    ScheduleTableStepS U32 c.schedule.table_step_s, TABLE_STEP_S TableStepS;
    ScheduleHoldS U32 c.schedule.hold_s, HOLD_S S0To3600;
    ScheduleRecheckS U32 c.schedule.recheck_s, RECHECK_S S1To3600;
    ScheduleMaxTickGapS U32 c.schedule.max_tick_gap_s, MAX_TICK_GAP_S S1To86400;
    ScheduleMaxBackwardS U32 c.schedule.max_backward_s, MAX_BACKWARD_S S0To86400;
    AxisCCountsPerMotorRev U32 c.axes[0].counts_per_motor_rev, COUNTS_PER_MOTOR_REV CountsPerMotorRev;
    AxisCMicrosteps U16 c.axes[0].microsteps, MICROSTEPS Microsteps;
    AxisCGearRatio F32 c.axes[0].gear_ratio, GEAR_RATIO GearRatio;
    AxisCCountsPerDeg Derived c.axes[0].counts_per_deg(), COUNTS_PER_DEG CountsPerDeg;
    AxisCMinDeg F32 c.axes[0].min_deg, LIMIT_DEG LimitDeg;
    AxisCMaxDeg F32 c.axes[0].max_deg, LIMIT_DEG LimitDeg;
    AxisCHomeDeg F32 c.axes[0].home_deg, HOME_ABOVE_MIN_DEG HomeNearMinDeg;
    AxisCBacklashDeg F32 c.axes[0].backlash_deg, BACKLASH_DEG Deg0To5;
    AxisCMaxSpeedDegS F32 c.axes[0].max_speed_deg_s, MAX_SPEED_DEG_S SpeedDegS;
    AxisCDeadbandDeg F32 c.axes[0].deadband_deg, DEADBAND_DEG Deg0To5;
    AxisACountsPerMotorRev U32 c.axes[1].counts_per_motor_rev, COUNTS_PER_MOTOR_REV CountsPerMotorRev;
    AxisAMicrosteps U16 c.axes[1].microsteps, MICROSTEPS Microsteps;
    AxisAGearRatio F32 c.axes[1].gear_ratio, GEAR_RATIO GearRatio;
    AxisACountsPerDeg Derived c.axes[1].counts_per_deg(), COUNTS_PER_DEG CountsPerDeg;
    AxisAMinDeg F32 c.axes[1].min_deg, LIMIT_DEG LimitDeg;
    AxisAMaxDeg F32 c.axes[1].max_deg, LIMIT_DEG LimitDeg;
    AxisAHomeDeg F32 c.axes[1].home_deg, HOME_ABOVE_MIN_DEG HomeNearMinDeg;
    AxisABacklashDeg F32 c.axes[1].backlash_deg, BACKLASH_DEG Deg0To5;
    AxisAMaxSpeedDegS F32 c.axes[1].max_speed_deg_s, MAX_SPEED_DEG_S SpeedDegS;
    AxisADeadbandDeg F32 c.axes[1].deadband_deg, DEADBAND_DEG Deg0To5;
    WindStowHz F32 c.wind.threshold_hz, STOW_HZ StowHz;
    WindHoldS U32 c.wind.hold_s, WIND_HOLD_S S0To600;
    WindReleaseS U32 c.wind.release_s, WIND_RELEASE_S S0To86400;
    SafetyMaxDeviationDeg F32 c.safety.max_deviation_deg, MAX_DEVIATION_DEG MaxDeviationDeg;
    SafetyStallTimeoutS U32 c.safety.stall_timeout_s, STALL_TIMEOUT_S S1To600;
    SafetySensorTimeoutS U32 c.safety.sensor_timeout_s, SENSOR_TIMEOUT_S S1To3600;
    SafetyMaxRetries U8 c.safety.max_retries, MAX_RETRIES MaxRetries;
    CalibrationDeclinationDeg F32 c.calibration.declination_deg, HEADING_DEG Deg180;
    CalibrationHeadingOffsetDeg F32 c.calibration.heading_offset_deg, HEADING_DEG Deg180;
    CalibrationTiltXOffsetDeg F32 c.calibration.tilt_x_offset_deg, TILT_OFFSET_DEG TiltOffsetDeg;
    CalibrationTiltYOffsetDeg F32 c.calibration.tilt_y_offset_deg, TILT_OFFSET_DEG TiltOffsetDeg;
    LogStatusMin U16 c.log.status_every_min, STATUS_MIN StatusMin;
    ModbusAddress U8 c.modbus.address, MODBUS_ADDRESS ModbusAddress;
    ModbusBaud U32 c.modbus.baud, MODBUS_BAUD ModbusBaud;
    ModbusParity U8 c.modbus.parity, MODBUS_PARITY ModbusParity;
    ModbusWrite U8 c.modbus.write, SWITCH Switch;
    ModbusTimeoutS U32 c.modbus.timeout_s, WIND_RELEASE_S S0To86400;
    StowSnowSlopeDeg F32 c.stow.snow_slope_deg, STOW_SLOPE_DEG SlopeDeg;
    StowSnowReleaseS U32 c.stow.snow_release_s, WIND_RELEASE_S S0To86400;
    StowHailSlopeDeg F32 c.stow.hail_slope_deg, STOW_SLOPE_DEG SlopeDeg;
    StowHailReleaseS U32 c.stow.hail_release_s, WIND_RELEASE_S S0To86400;
    StowExternalSlopeDeg F32 c.stow.external_slope_deg, STOW_SLOPE_DEG SlopeDeg;
    StowExternalActive U8 c.stow.external_active, ACTIVE_LEVEL ActiveLevel;
    StowOnSensorFault U8 c.stow.on_sensor_fault, SWITCH Switch;
    SupplyStowMv U16 c.supply.stow_mv, SUPPLY_MV SupplyMv;
    SupplyResumeMv U16 c.supply.resume_mv, SUPPLY_MV SupplyMv;
    OvercastRatio F32 c.overcast.ratio, OVERCAST_RATIO OvercastRatio;
    OvercastEnterS U32 c.overcast.enter_s, WIND_RELEASE_S S0To86400;
    OvercastLeaveS U32 c.overcast.leave_s, WIND_RELEASE_S S0To86400;
    OvercastMaxMovesPerHour U8 c.overcast.max_moves_per_hour, OVERCAST_MOVES OvercastMoves;
    AxisCContinuous U8 c.axes[0].continuous, SWITCH Switch;
    SiteUtcOffsetH F32 c.site.utc_offset_h, UTC_OFFSET_H UtcOffsetH;
    WindMSPerHz F32 c.wind.m_s_per_hz, WIND_M_S_PER_HZ WindMSPerHz;
    ModbusTimeoutStow U8 c.modbus.timeout_stow, SWITCH Switch;
    AxisCDrive U8 c.axes[0].drive, DRIVE DriveKind;
    AxisCMaxCurrentMa U16 c.axes[0].max_current_ma, MAX_CURRENT_MA MaxCurrentMa;
    AxisCOvercurrentMs U16 c.axes[0].overcurrent_ms, OVERCURRENT_MS OvercurrentMs;
    AxisADrive U8 c.axes[1].drive, DRIVE DriveKind;
    AxisAMaxCurrentMa U16 c.axes[1].max_current_ma, MAX_CURRENT_MA MaxCurrentMa;
    AxisAOvercurrentMs U16 c.axes[1].overcurrent_ms, OVERCURRENT_MS OvercurrentMs;
    AxisCBackSpeedDegS F32 c.axes[0].back_speed_deg_s, MAX_SPEED_DEG_S SpeedDegS;
    AxisABackSpeedDegS F32 c.axes[1].back_speed_deg_s, MAX_SPEED_DEG_S SpeedDegS;
    SupplyCalibrationMv U16 c.supply.calibration_mv, SUPPLY_MV SupplyMv;
    #[cfg(feature = "linear")]
    AxisCPivotAMm F32 c.axes[0].linear.pivot_a_mm, LENGTH_MM LengthMm;
    #[cfg(feature = "linear")]
    AxisCPivotBMm F32 c.axes[0].linear.pivot_b_mm, LENGTH_MM LengthMm;
    #[cfg(feature = "linear")]
    AxisCPivotOffsetDeg F32 c.axes[0].linear.pivot_offset_deg, LIMIT_DEG LimitDeg;
    #[cfg(feature = "linear")]
    AxisCRetractedMm F32 c.axes[0].linear.retracted_mm, LENGTH_MM LengthMm;
    #[cfg(feature = "linear")]
    AxisCStrokeMm F32 c.axes[0].linear.stroke_mm, LENGTH_MM LengthMm;
    #[cfg(feature = "linear")]
    AxisCPulsesPerMm F32 c.axes[0].linear.pulses_per_mm, PULSES_PER_MM PulsesPerMm;
    #[cfg(feature = "linear")]
    AxisCPotRetractedCounts U16 c.axes[0].linear.pot_retracted_counts, ADC_COUNTS AdcCounts;
    #[cfg(feature = "linear")]
    AxisCPotExtendedCounts U16 c.axes[0].linear.pot_extended_counts, ADC_COUNTS AdcCounts;
    #[cfg(feature = "linear")]
    AxisAPivotAMm F32 c.axes[1].linear.pivot_a_mm, LENGTH_MM LengthMm;
    #[cfg(feature = "linear")]
    AxisAPivotBMm F32 c.axes[1].linear.pivot_b_mm, LENGTH_MM LengthMm;
    #[cfg(feature = "linear")]
    AxisAPivotOffsetDeg F32 c.axes[1].linear.pivot_offset_deg, LIMIT_DEG LimitDeg;
    #[cfg(feature = "linear")]
    AxisARetractedMm F32 c.axes[1].linear.retracted_mm, LENGTH_MM LengthMm;
    #[cfg(feature = "linear")]
    AxisAStrokeMm F32 c.axes[1].linear.stroke_mm, LENGTH_MM LengthMm;
    #[cfg(feature = "linear")]
    AxisAPulsesPerMm F32 c.axes[1].linear.pulses_per_mm, PULSES_PER_MM PulsesPerMm;
    #[cfg(feature = "linear")]
    AxisAPotRetractedCounts U16 c.axes[1].linear.pot_retracted_counts, ADC_COUNTS AdcCounts;
    #[cfg(feature = "linear")]
    AxisAPotExtendedCounts U16 c.axes[1].linear.pot_extended_counts, ADC_COUNTS AdcCounts;
}

crate::progmem! {
    /// The bounds of each key's range ([`Range`]'s `lo` and `hi`) at its
    /// place in [`KEYS`]. Apart from the reasons: a [`Range`] a row took
    /// 12 bytes on a 32-bit target (its one-byte reason padded), the two
    /// tables 9.
    pub(crate) static BOUNDS: [[u32; 2]; KEY_LIST.len()] = {
        let mut b = [[0u32; 2]; KEY_LIST.len()];
        let mut i = 0;
        while i < KEY_LIST.len() {
            b[i] = [RANGES[i].lo, RANGES[i].hi];
            i += 1;
        }
        b
    };
}

crate::progmem! {
    /// The reason of each key's range ([`Range`]'s `reason`) at its place
    /// in [`KEYS`].
    pub(crate) static REASONS: [Reason; KEY_LIST.len()] = {
        let mut r = [Reason::Switch; KEY_LIST.len()];
        let mut i = 0;
        while i < KEY_LIST.len() {
            r[i] = RANGES[i].reason;
            i += 1;
        }
        r
    };
}

crate::progmem! {
    /// Each key's default ([`Config::DEFAULT`]) at its place in [`KEYS`],
    /// in the bits of [`key_bits`]; built when compiling.
    pub(crate) static DEFAULTS: [u32; KEY_LIST.len()] = {
        let mut bits = [0u32; KEY_LIST.len()];
        let mut i = 0;
        while i < KEY_LIST.len() {
            bits[i] = key_bits(&Config::DEFAULT, KEY_LIST[i]);
            i += 1;
        }
        bits
    };
}

/// [`Config::DEFAULT`], written key by key from [`DEFAULTS`] into a
/// configuration of zeros ([`write_defaults`]).
pub(crate) fn defaults() -> Config {
    let mut config = ZEROS;
    write_defaults(&mut config);
    config
}

/// Writes [`Config::DEFAULT`] over `config` in place, key by key from
/// [`DEFAULTS`] (the operator's hold, not a key, to none): every field.
/// Through the table: on the AVR the fields written one by one were
/// several times the code of this loop and the table's 4 bytes a key.
/// In place: a configuration built and returned was a second copy on an
/// 8-bit board's stack under whoever reads a stored one.
pub(crate) fn write_defaults(config: &mut Config) {
    config.hold = OperatorHold::NONE;
    // By place (here and in the codec): an `enumerate` over the table's
    // reads from program memory was 230 B more on the AVR.
    for i in 0..KEYS.len() {
        let Some(key) = KEYS.get(i) else { break };
        let field = slot(config, key);
        let bits = DEFAULTS.get(i).unwrap_or(0);
        // Each value came from its own field (`key_bits`): the narrowing
        // casts give it back.
        match field {
            Slot::F32(v) => *v = f32::from_bits(bits),
            Slot::U32(v) => *v = bits,
            Slot::U16(v) => *v = bits as u16,
            Slot::U8(v) => *v = bits as u8,
            Slot::Derived => {}
        }
    }
}

/// A configuration of zeros (every field's bits 0), which [`defaults`]
/// fills in.
const ZEROS: Config = {
    let axis = AxisConfig {
        counts_per_motor_rev: 0,
        microsteps: 0,
        gear_ratio: 0.0,
        min_deg: 0.0,
        max_deg: 0.0,
        home_deg: 0.0,
        backlash_deg: 0.0,
        max_speed_deg_s: 0.0,
        deadband_deg: 0.0,
        continuous: 0,
        drive: 0,
        max_current_ma: 0,
        overcurrent_ms: 0,
        back_speed_deg_s: 0.0,
        #[cfg(feature = "linear")]
        linear: LinearMount {
            pivot_a_mm: 0.0,
            pivot_b_mm: 0.0,
            pivot_offset_deg: 0.0,
            retracted_mm: 0.0,
            stroke_mm: 0.0,
            pulses_per_mm: 0.0,
            pot_retracted_counts: 0,
            pot_extended_counts: 0,
        },
    };
    Config {
        site: SiteConfig {
            latitude_deg: 0.0,
            longitude_deg: 0.0,
            elevation_m: 0.0,
            utc_offset_h: 0.0,
        },
        schedule: ScheduleConfig {
            table_step_s: 0,
            hold_s: 0,
            recheck_s: 0,
            max_tick_gap_s: 0,
            max_backward_s: 0,
        },
        axes: [axis, axis],
        wind: WindConfig {
            threshold_hz: 0.0,
            hold_s: 0,
            release_s: 0,
            m_s_per_hz: 0.0,
        },
        safety: SafetyConfig {
            max_deviation_deg: 0.0,
            stall_timeout_s: 0,
            sensor_timeout_s: 0,
            max_retries: 0,
        },
        calibration: Calibration {
            declination_deg: 0.0,
            heading_offset_deg: 0.0,
            tilt_x_offset_deg: 0.0,
            tilt_y_offset_deg: 0.0,
        },
        log: LogConfig {
            status_every_min: 0,
        },
        modbus: ModbusConfig {
            address: 0,
            baud: 0,
            parity: 0,
            write: 0,
            timeout_s: 0,
            timeout_stow: 0,
        },
        stow: StowConfig {
            snow_slope_deg: 0.0,
            snow_release_s: 0,
            hail_slope_deg: 0.0,
            hail_release_s: 0,
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
            enter_s: 0,
            leave_s: 0,
            max_moves_per_hour: 0,
        },
        hold: OperatorHold::NONE,
    }
};

/// The value of `key` in `config`: read through its slot in a copy
/// (one table of places, not a second `match` over the keys); the derived
/// counts per degree computed for the axis of `key`.
pub fn get(config: &Config, key: Field) -> Value {
    let mut copy = *config;
    read(&mut copy, key)
}

/// [`get`] from a configuration the caller lets it borrow mutably (its
/// slots are references for writing): no copy of it.
pub(crate) fn read(config: &mut Config, key: Field) -> Value {
    match slot(config, key) {
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
