//! The words of a command line: splitting at blanks and comparing
//! without case, in byte loops.

use crate::text::FlashStr;

pub(super) fn is_blank_byte(b: u8) -> bool {
    b == b' ' || b == b'\t'
}

/// `s` without leading spaces and tabs.
pub(super) fn trim_start_blank(s: &str) -> &str {
    let start = s.bytes().position(|c| !is_blank_byte(c)).unwrap_or(s.len());
    s.get(start..).unwrap_or("")
}

/// `s` without leading and trailing spaces and tabs (byte loops: `trim`
/// links a Unicode table).
pub(super) fn trim_blank(s: &str) -> &str {
    let s = trim_start_blank(s);
    let end = s
        .bytes()
        .rposition(|c| !is_blank_byte(c))
        .map_or(0, |i| i.saturating_add(1));
    s.get(..end).unwrap_or("")
}

/// Splits off the first word: (word, rest); the word is empty when `s` is
/// blank.
pub(super) fn word(s: &str) -> (&str, &str) {
    let s = trim_start_blank(s);
    let end = s.bytes().position(is_blank_byte).unwrap_or(s.len());
    // One boundary check for both halves (two `get`s, 56 B more on the
    // ATmega2560).
    s.split_at_checked(end).unwrap_or((s, ""))
}

/// Splits `s` at the first `sep` (an ASCII byte).
pub(super) fn split_at_byte(s: &str, sep: u8) -> Option<(&str, &str)> {
    let i = s.bytes().position(|c| c == sep)?;
    Some((s.get(..i)?, s.get(i.saturating_add(1)..)?))
}

pub(super) fn is_blank(s: &str) -> bool {
    s.bytes().all(is_blank_byte)
}

/// `s` without a leading `prefix` (ASCII case-insensitive).
pub(super) fn strip_prefix_ignore_case(s: &str, prefix: FlashStr) -> Option<&str> {
    s.get(..prefix.len())
        .filter(|p| same_word(p, prefix))
        .and_then(|_| s.get(prefix.len()..))
}

/// ASCII case-insensitive equality (one copy, not inlined at every use).
#[inline(never)]
pub(super) fn same_word(a: &str, b: FlashStr) -> bool {
    b.eq_ignore_ascii_case(a)
}
