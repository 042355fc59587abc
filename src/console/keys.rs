//! The console's keys: a configuration field by its name (the table of
//! fields, their kinds and places is the configuration's own,
//! [`crate::config::KEYS`]), and the `site.postal_code` pseudo-key.

use crate::config::Field;
use crate::text::{FlashStr, ProgMem};

pub use crate::config::{get, is_read_only, Value, KEYS};
pub(super) use crate::config::{slot, Slot};

/// A configuration key: a field of [`Config`](crate::config::Config) by its dotted name with unit
/// ([`Field::name`]).
pub type Key = Field;

/// A table of keys a console accepts, in program memory on the AVR: the
/// configuration's [`KEYS`], or a smaller board's own.
pub type KeyList = &'static ProgMem<[Key]>;

/// The postal-code pseudo-key: `set` only, sets latitude and longitude.
pub const POSTAL_CODE_KEY: FlashStr = crate::flash_str!("site.postal_code");

/// The key named `name` (ASCII case-insensitive).
pub fn key_from_name(name: &str) -> Option<Key> {
    key_in(KEYS.as_slice(), name)
}

/// The key of `keys` named `name` (ASCII case-insensitive).
pub(super) fn key_in(keys: KeyList, name: &str) -> Option<Key> {
    keys.iter().find(|k| k.name().eq_ignore_ascii_case(name))
}
