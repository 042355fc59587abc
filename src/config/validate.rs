//! The checks of a configuration against its ranges ([`super::ranges`],
//! each key's in the key table, [`super::table`]) and the rules between
//! fields: [`Config::validate`], [`AxisConfig::validate`], and the error
//! naming the first field out of range ([`ConfigError`]).

use core::ops::Range;

use super::keys::AXIS_KEYS;
use super::table::{read, Value, BOUNDS, KEYS, KEY_LIST, REASONS};
#[cfg(feature = "linear")]
use super::DriveKind;
use super::{AxisConfig, Config, DriveSet, Field, Reason};

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

/// `Err` naming `field` unless `v` is finite and inside `lo..=hi`: the
/// check [`Config::validate`] makes of a real-valued key, for records that
/// hold a few of the configuration's fields (the Uno's settings). Out of
/// line: a call is smaller than the comparison it replaces.
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

/// The place of `key` in [`KEYS`] (its length when it is not there).
const fn key_index(key: Field) -> usize {
    let mut i = 0;
    while i < KEY_LIST.len() {
        if KEY_LIST[i] as usize == key as usize {
            return i;
        }
        i += 1;
    }
    KEY_LIST.len()
}

/// The places in [`KEYS`] of each axis's keys, `counts_per_motor_rev`
/// to `deadband_deg` (the table lists each axis's keys together).
const AXIS_SPANS: [(usize, usize); 2] = [
    (
        key_index(AXIS_KEYS[0].counts_per_motor_rev),
        key_index(AXIS_KEYS[0].deadband_deg) + 1,
    ),
    (
        key_index(AXIS_KEYS[1].counts_per_motor_rev),
        key_index(AXIS_KEYS[1].deadband_deg) + 1,
    ),
];
const _: () = assert!(AXIS_SPANS[0].1 - AXIS_SPANS[0].0 == 10);
const _: () = assert!(AXIS_SPANS[1].1 - AXIS_SPANS[1].0 == 10);

/// The places in [`KEYS`] of each axis's keys of layout version 7:
/// `drive`, `max_current_ma`, `overcurrent_ms` (listed together).
const AXIS_DRIVE_SPANS: [(usize, usize); 2] = [
    (
        key_index(AXIS_KEYS[0].drive),
        key_index(AXIS_KEYS[0].drive) + 3,
    ),
    (
        key_index(AXIS_KEYS[1].drive),
        key_index(AXIS_KEYS[1].drive) + 3,
    ),
];
const _: () = assert!(AXIS_DRIVE_SPANS[0].1 <= KEY_LIST.len());
const _: () = assert!(AXIS_DRIVE_SPANS[1].1 <= KEY_LIST.len());
// Each span holds the axis's own three keys, in that order.
const _: () =
    assert!(KEY_LIST[AXIS_DRIVE_SPANS[0].0 + 1] as usize == Field::AxisCMaxCurrentMa as usize);
const _: () =
    assert!(KEY_LIST[AXIS_DRIVE_SPANS[1].0 + 1] as usize == Field::AxisAMaxCurrentMa as usize);
const _: () =
    assert!(KEY_LIST[AXIS_DRIVE_SPANS[0].1 - 1] as usize == Field::AxisCOvercurrentMs as usize);
const _: () =
    assert!(KEY_LIST[AXIS_DRIVE_SPANS[1].1 - 1] as usize == Field::AxisAOvercurrentMs as usize);

/// The place in [`KEYS`] of each axis's key of layout version 8,
/// `back_speed_deg_s`.
const AXIS_BACK_SPEED: [usize; 2] = [
    key_index(AXIS_KEYS[0].back_speed_deg_s),
    key_index(AXIS_KEYS[1].back_speed_deg_s),
];
const _: () = assert!(AXIS_BACK_SPEED[0] < KEY_LIST.len() && AXIS_BACK_SPEED[1] < KEY_LIST.len());

#[cfg(feature = "linear")]
/// The places in [`KEYS`] of each axis's keys of layout version 10, its
/// linear actuator's (`pivot_a_mm` to `pot_extended_counts`, listed
/// together).
const AXIS_LINEAR_SPANS: [(usize, usize); 2] = [
    (
        key_index(AXIS_KEYS[0].linear.0),
        key_index(AXIS_KEYS[0].linear.1) + 1,
    ),
    (
        key_index(AXIS_KEYS[1].linear.0),
        key_index(AXIS_KEYS[1].linear.1) + 1,
    ),
];
#[cfg(feature = "linear")]
const _: () = assert!(AXIS_LINEAR_SPANS[0].1 - AXIS_LINEAR_SPANS[0].0 == 8);
#[cfg(feature = "linear")]
const _: () = assert!(AXIS_LINEAR_SPANS[1].1 - AXIS_LINEAR_SPANS[1].0 == 8);
#[cfg(feature = "linear")]
const _: () = assert!(AXIS_LINEAR_SPANS[1].1 <= KEY_LIST.len());

/// How far a soft limit or home switch angle may lie outside a linear
/// actuator's stroke, degrees: the rounding of a typed angle.
#[cfg(feature = "linear")]
const STROKE_TOLERANCE_DEG: f32 = 0.01;

impl AxisConfig {
    /// Checks every field against its range; `axis` 0 is the C axis (keys
    /// `axis.c.*`), any other the A axis (`axis.a.*`). The deadband's
    /// relation to `safety.max_deviation_deg` is checked by
    /// [`Config::validate`].
    pub fn validate(&self, axis: usize) -> Result<(), ConfigError> {
        let i = usize::from(axis != 0);
        let mut config = Config::default();
        let (Some(slot), Some(&(from, to)), Some(&(drive_from, drive_to))) = (
            config.axes.get_mut(i),
            AXIS_SPANS.get(i),
            AXIS_DRIVE_SPANS.get(i),
        ) else {
            return Ok(());
        };
        *slot = *self;
        config.check_keys(from..to)?;
        config.check_keys(drive_from..drive_to)?;
        let back = AXIS_BACK_SPEED[i];
        config.check_keys(back..back + 1)?;
        #[cfg(feature = "linear")]
        {
            let (lin_from, lin_to) = AXIS_LINEAR_SPANS[i];
            config.check_keys(lin_from..lin_to)?;
        }
        Ok(())
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
    ///
    /// [`ranges`]: super::ranges
    /// [`ranges::COUNTS_PER_DEG`]: super::ranges::COUNTS_PER_DEG
    pub fn validate(&self) -> Result<(), ConfigError> {
        // Read through the table's slots, which borrow for writing: a
        // copy, made here so that the checks' frame does not hold it.
        let mut copy = *self;
        copy.check_in_place()
    }

    /// [`Config::validate`] of a configuration the caller owns and lets
    /// it borrow mutably (nothing is written): no copy of it. A copy is
    /// a [`Config`]'s size on the stack (on an 8-bit board, a few percent
    /// of its RAM) in the frame of whoever reads a stored copy or commits
    /// a typed one.
    pub(crate) fn check_in_place(&mut self) -> Result<(), ConfigError> {
        self.check_keys(0..KEYS.len())
    }

    /// `Err` naming the first axis whose `drive` is not a kind of
    /// `drives` (the kinds a board's image can build: a configuration
    /// saved by another image, or typed for another board).
    pub fn check_drives(&self, drives: DriveSet) -> Result<(), ConfigError> {
        for (a, k) in self.axes.iter().zip(AXIS_KEYS.iter()) {
            if !drives.has_code(a.drive) {
                return Err(ConfigError {
                    field: k.drive,
                    reason: Reason::DriveNotOnBoard,
                });
            }
        }
        Ok(())
    }

    /// The keys at `places` of [`KEYS`] in order: each against its range
    /// ([`BOUNDS`], [`REASONS`]), then the rules between fields that end at it. Takes
    /// the configuration mutably (the table's slots borrow for writing;
    /// nothing is written). Out of line on the AVR: with the copy of the
    /// configuration in its frame, the checks' slots lay beyond
    /// `ldd`/`std` reach.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn check_keys(&mut self, places: Range<usize>) -> Result<(), ConfigError> {
        for i in places {
            let (Some(key), Some([lo_bits, hi_bits]), Some(reason)) =
                (KEYS.get(i), BOUNDS.get(i), REASONS.get(i))
            else {
                break;
            };
            let ok = match read(self, key) {
                Value::F32(v) => {
                    let (mut lo, mut hi) = (f32::from_bits(lo_bits), f32::from_bits(hi_bits));
                    // A home switch angle: from its offsets below and above
                    // `min_deg`, and never above `max_deg`.
                    let home = match key {
                        Field::AxisCHomeDeg => self.axes.first(),
                        Field::AxisAHomeDeg => self.axes.last(),
                        _ => None,
                    };
                    if let Some(a) = home {
                        // The upper bound by a comparison: what `f32::min`
                        // gives (`max_deg` when the sum is not a number;
                        // `max_deg` is checked before this key), without
                        // the library function it links on the AVR.
                        let top = a.min_deg + hi;
                        (lo, hi) = (
                            a.min_deg + lo,
                            if top < a.max_deg { top } else { a.max_deg },
                        );
                    }
                    v.is_finite() && v >= lo && v <= hi
                }
                Value::U32(v) => v >= lo_bits && v <= hi_bits,
            };
            if !ok {
                return Err(ConfigError { field: key, reason });
            }
            self.rules_at(key)?;
        }
        Ok(())
    }

    /// The rules between fields checked once `key`, the last field they
    /// read in the table's order, is in range.
    fn rules_at(&self, key: Field) -> Result<(), ConfigError> {
        let fail = |field, reason| Err(ConfigError { field, reason });
        if key == Field::ScheduleTableStepS {
            let step = self.schedule.table_step_s;
            // (At least 60 s, its range, checked: never a zero divisor.)
            if !step.is_multiple_of(60) || 86_400u32.checked_rem(step) != Some(0) {
                return fail(key, Reason::WholeMinutesOfDay);
            }
        }
        let max = match key {
            Field::AxisCMaxDeg => self.axes.first(),
            Field::AxisAMaxDeg => self.axes.last(),
            _ => None,
        };
        if let Some(a) = max {
            if a.max_deg <= a.min_deg {
                return fail(key, Reason::AboveMinDeg);
            }
        }
        if key == Field::AxisCContinuous {
            if let Some(c) = self.axes.first() {
                // The count is kept within a turn by whole turns: exact
                // only for a whole number of counts per turn (motor counts
                // and microsteps are integers; the gear ratio, 1…10,000,
                // converts to `i32` exactly when whole).
                if c.continuous != 0 && c.gear_ratio != (c.gear_ratio as i32) as f32 {
                    return fail(key, Reason::WholeCountsPerTurn);
                }
            }
        }
        if key == Field::SupplyResumeMv && self.supply.resume_mv < self.supply.stow_mv {
            return fail(key, Reason::AtLeastStowMv);
        }
        if key == Field::ModbusBaud
            && !super::ranges::MODBUS_BAUDS
                .iter()
                .any(|b| b == self.modbus.baud)
        {
            return fail(key, Reason::ModbusBaud);
        }
        #[cfg(feature = "linear")]
        {
            let linear = match key {
                Field::AxisCPotExtendedCounts => Some(0),
                Field::AxisAPotExtendedCounts => Some(1),
                _ => None,
            };
            if let Some(i) = linear {
                self.check_linear(i)?;
            }
        }
        if key == Field::SafetyMaxRetries {
            for (a, k) in self.axes.iter().zip(AXIS_KEYS.iter()) {
                if a.deadband_deg >= self.safety.max_deviation_deg {
                    return fail(k.deadband_deg, Reason::BelowMaxDeviation);
                }
            }
        }
        Ok(())
    }

    /// The rules of axis `i`'s linear actuator, when its drive is one
    /// (`linear_hall`, `linear_pot`): the mounting forms a triangle over
    /// the whole stroke ([`drivers::linear::ActuatorGeometry::validate`]),
    /// the soft limits and the home switch lie within the stroke's angles
    /// (a potentiometer's home is the retracted end itself: the axis is
    /// homed there), and the potentiometer's two readings differ.
    /// Not inlined: one copy for both axes.
    #[cfg(feature = "linear")]
    #[inline(never)]
    fn check_linear(&self, i: usize) -> Result<(), ConfigError> {
        let (Some(a), Some(k)) = (self.axes.get(i), AXIS_KEYS.get(i)) else {
            return Ok(());
        };
        let pot = a.drive == DriveKind::LinearPot as u8;
        if !pot && a.drive != DriveKind::LinearHall as u8 {
            return Ok(());
        }
        let fail = |field, reason| Err(ConfigError { field, reason });
        let m = &a.linear;
        if pot && m.pot_retracted_counts == m.pot_extended_counts {
            return fail(k.linear.1, Reason::PotSpan);
        }
        let g = m.geometry();
        let ends = g.validate().and_then(|()| {
            Ok((
                g.axis_deg(g.retracted_mm)?,
                g.axis_deg(g.retracted_mm + g.stroke_mm)?,
            ))
        });
        let Ok((retracted_deg, extended_deg)) = ends else {
            return fail(k.stroke_mm, Reason::LinearGeometry);
        };
        let within = |deg: f32| {
            deg >= retracted_deg - STROKE_TOLERANCE_DEG
                && deg <= extended_deg + STROKE_TOLERANCE_DEG
        };
        if !within(a.min_deg) {
            return fail(k.min_deg, Reason::WithinStroke);
        }
        if !within(a.max_deg) {
            return fail(k.max_deg, Reason::WithinStroke);
        }
        if pot && (a.home_deg - retracted_deg).abs() > STROKE_TOLERANCE_DEG {
            return fail(k.home_deg, Reason::HomeAtRetracted);
        }
        if !within(a.home_deg) {
            return fail(k.home_deg, Reason::WithinStroke);
        }
        Ok(())
    }
}
