//! Setting keys: a `set` applied to a copy of the configuration, validated,
//! and kept only when valid.

use super::keys::{slot, Key, Slot};
use super::number::Decimal;
use super::parse::Assignments;
use crate::config::{Config, ConfigError, DriveSet};
use crate::site::PostalError;

/// Why a `set` changed nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SetError {
    /// The new configuration breaks a range or rule: the field and reason
    /// from [`Config::validate`] (usually the key that was set; for a rule
    /// between fields, the field the rule names):
    /// `error FIELD: REASON`.
    Invalid(ConfigError),
    /// A fraction for a whole-number key: `error KEY: whole number expected`.
    NotWhole(Key),
    /// A derived value (`axis.*.counts_per_deg`): `error KEY: read only`.
    ReadOnly(Key),
    /// A value the field cannot hold that the validation did not refuse
    /// either (no range allows it today): `error KEY: out of range`.
    OutOfRange(Key),
    /// The postal code gave no site: `error site.postal_code: …`.
    Postal(PostalError),
}

/// A whole number for a field of at most `max`, and whether it had to be
/// clipped: `NotWhole` for a fraction; `(max, true)` for a negative number
/// or one above `max`. No range of [`Config::validate`] includes its
/// type's maximum, so the validation then refuses the field with its own
/// reason.
fn whole(v: &Decimal, key: Key, max: u32) -> Result<(u32, bool), SetError> {
    if v.has_fraction() {
        return Err(SetError::NotWhole(key));
    }
    Ok(match v.to_u32() {
        Some(w) if w <= max => (w, false),
        _ => (max, true),
    })
}

/// Stores `v` in `key` of `c`, unchecked; `Ok(true)` when it had to be
/// clipped to the field's type.
fn store(c: &mut Config, key: Key, v: &Decimal) -> Result<bool, SetError> {
    // The whole-number kinds share one check against their type's maximum
    // (checked at each kind, 168 B more on the ATmega2560).
    let max = match slot(c, key) {
        Slot::F32(f) => {
            *f = v.to_f32();
            return Ok(false);
        }
        Slot::U32(_) => u32::MAX,
        Slot::U16(_) => u32::from(u16::MAX),
        Slot::U8(_) => u32::from(u8::MAX),
        Slot::Derived => return Err(SetError::ReadOnly(key)),
    };
    let (w, clipped) = whole(v, key, max)?;
    match slot(c, key) {
        Slot::U32(f) => *f = w,
        Slot::U16(f) => *f = u16::try_from(w).unwrap_or(u16::MAX),
        Slot::U8(f) => *f = u8::try_from(w).unwrap_or(u8::MAX),
        Slot::F32(_) | Slot::Derived => {}
    }
    Ok(clipped)
}

/// Sets `key` to `value` in a copy of `config`, validates the copy with
/// [`Config::validate`] and against the board's drive kinds `drives`
/// ([`Config::check_drives`]) and only then stores it; on error `config`
/// is unchanged. Not inlined on the AVR, as the other `apply_*`: each
/// holds a copy of the configuration, on the stack only while it runs
/// (inlined elsewhere: the Black Pill image was 188 B larger with them
/// out of line, over its 64 KiB).
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn apply_set(
    config: &mut Config,
    key: Key,
    value: Decimal,
    drives: DriveSet,
) -> Result<(), SetError> {
    let mut copy = *config;
    let clipped = store(&mut copy, key, &value)?;
    commit(config, &mut copy, clipped.then_some(key), drives)
}

/// Sets every pair of `set` in a copy of `config`, validates the copy once
/// (as [`apply_set`]) and only then stores it: all or nothing.
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn apply_assignments(
    config: &mut Config,
    set: &Assignments<'_>,
    drives: DriveSet,
) -> Result<(), SetError> {
    let mut copy = *config;
    let mut clipped = None;
    for (key, value) in set.iter() {
        if store(&mut copy, key, &value)? {
            clipped = Some(key);
        }
    }
    commit(config, &mut copy, clipped, drives)
}

/// Stores `copy` if it is valid, its axes' drive kinds are of `drives` and
/// no value had to be clipped to its field's type (`clipped` names such a
/// key). `copy` is checked where it lies ([`Config::check_in_place`]: it
/// is borrowed mutably and nothing is written), not copied once more.
pub(super) fn commit(
    config: &mut Config,
    copy: &mut Config,
    clipped: Option<Key>,
    drives: DriveSet,
) -> Result<(), SetError> {
    // A kind the board has no driver for is named before the rules of that
    // kind (a linear actuator's mounting means nothing on a board without
    // one); a code out of the range of kinds is that range's error.
    let valid = copy.check_in_place();
    if let Err(e) = copy.check_drives(drives) {
        if !matches!(valid, Err(v) if v.field == e.field) {
            return Err(SetError::Invalid(e));
        }
    }
    valid.map_err(SetError::Invalid)?;
    if let Some(key) = clipped {
        return Err(SetError::OutOfRange(key));
    }
    *config = *copy;
    Ok(())
}
