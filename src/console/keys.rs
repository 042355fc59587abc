//! The console's keys: a configuration field by its name (the table of
//! fields, their kinds and places is the configuration's own,
//! [`crate::config::KEYS`]), and the `site.postal_code` pseudo-key.

use crate::config::Field;
use crate::text::FlashStr;

pub use crate::config::{get, is_read_only, Value, KEYS};
pub(super) use crate::config::{slot, Slot};

/// A configuration key: a field of [`Config`](crate::config::Config) by its dotted name with unit
/// ([`Field::name`]).
pub type Key = Field;

/// The postal-code pseudo-key: `set` only, sets latitude and longitude.
pub const POSTAL_CODE_KEY: FlashStr = crate::flash_str!("site.postal_code");

/// The key named `name` (ASCII case-insensitive).
pub fn key_from_name(name: &str) -> Option<Key> {
    key_in(KEYS, name)
}

/// The key of `keys` named `name` (ASCII case-insensitive).
pub(super) fn key_in(keys: &[Key], name: &str) -> Option<Key> {
    keys.iter()
        .copied()
        .find(|k| k.name().eq_ignore_ascii_case(name))
}
