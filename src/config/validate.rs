//! The checks of a configuration against its ranges ([`super::ranges`])
//! and the rules between fields: [`Config::validate`],
//! [`AxisConfig::validate`], and the error naming the first field out of
//! range ([`ConfigError`]).

use super::keys::AXIS_KEYS;
use super::{ranges, AxisConfig, Config, Field, Reason};

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

/// `Err` naming `field` unless `v` is finite and inside `lo..=hi`. Out of
/// line: a call is smaller than the comparison it replaces (a dozen callers).
#[inline(never)]
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

impl Config {
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
