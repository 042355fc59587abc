//! `set site.postal_code CC:CODE`: the site from the built-in postal-code
//! table.

use super::set::{commit, SetError};
use super::words::{split_at_byte, trim_blank};
use crate::config::{Config, DriveSet};
use crate::site::key::MAX_CODE_LEN;
use crate::site::{lookup, PostalEntry, PostalError};

#[cfg(doc)]
use super::set::apply_set;

/// How an image looks a postal code up: [`POSTAL_TABLE`], or `None` in an
/// image built without the table (`set site.postal_code` is then answered
/// `error site.postal_code: not in this image`). The table and its search
/// take 2.3 KB of the Uno's single image.
pub type PostalLookup = Option<fn(&str) -> Result<PostalEntry, PostalError>>;

/// The built-in table ([`find_postal`]).
pub const POSTAL_TABLE: PostalLookup = Some(find_postal);

/// Looks `text` (`CC:CODE`, e.g. `DZ:16000`) up in the postal-code table
/// and sets the site's latitude and longitude from it (the elevation stays:
/// the table has none), validated as [`apply_set`] does.
///
/// A numeric code not in the table is tried again with leading zeros, up
/// to the longest code the table stores, so that `DZ:9000` finds
/// `DZ:09000`.
pub fn apply_postal_code(config: &mut Config, text: &str) -> Result<PostalEntry, SetError> {
    apply_postal(config, text, POSTAL_TABLE)
}

/// [`apply_postal_code`] with `lookup`, the image's table or none. Not
/// inlined on the AVR, as [`apply_set`].
#[cfg_attr(target_arch = "avr", inline(never))]
pub(super) fn apply_postal(
    config: &mut Config,
    text: &str,
    lookup: PostalLookup,
) -> Result<PostalEntry, SetError> {
    let find = lookup.ok_or(SetError::Postal(PostalError::NoTable))?;
    let entry = find(text).map_err(SetError::Postal)?;
    let mut copy = *config;
    copy.site.latitude_deg = entry.latitude_deg::<f32>();
    copy.site.longitude_deg = entry.longitude_deg::<f32>();
    // Validated and kept as a `set` is (one copy of that step); a postal
    // code changes no drive, so any kind passes.
    commit(config, &mut copy, None, DriveSet::ALL)?;
    Ok(entry)
}

/// The table entry of `CC:CODE`, with leading zeros added to a numeric
/// code that is not found as typed.
pub fn find_postal(text: &str) -> Result<PostalEntry, PostalError> {
    let (country, code) = split_at_byte(text, b':').ok_or(PostalError::BadFormat)?;
    let (country, code) = (trim_blank(country), trim_blank(code));
    let first = lookup(country, code);
    if first != Err(PostalError::UnknownPostalCode) || !code.bytes().all(|b| b.is_ascii_digit()) {
        return first;
    }
    let mut buf = [b'0'; MAX_CODE_LEN];
    let mut total = code.len();
    // One more leading zero each time, up to the longest code stored.
    while total < MAX_CODE_LEN {
        total = total.saturating_add(1);
        buf.fill(b'0');
        let zeros = total.saturating_sub(code.len());
        for (d, s) in buf.iter_mut().skip(zeros).zip(code.bytes()) {
            *d = s;
        }
        if let Some(padded) = buf.get(..total).and_then(crate::text::ascii_str) {
            if let found @ Ok(_) = lookup(country, padded) {
                return found;
            }
        }
    }
    first
}
