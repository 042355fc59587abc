//! The reply lines: `ok …` and `error …` for each command and each
//! refusal.

use super::keys::{get, Key, Value, POSTAL_CODE_KEY};
use super::line::LineError;
use super::number::write_number;
use super::operator::TimeSetError;
use super::parse::ParseError;
use super::set::SetError;
use crate::config::{Config, ConfigError, KeyName};
use crate::log::Sink;
use crate::persist::{LoadReport, SaveError};
use crate::safety::FaultManager;
use crate::site::PostalError;
use crate::text::{FlashStr, FlashStrs};
use sun_algos::UtcTime;

#[cfg(doc)]
use super::{line::LineBuffer, parse::parse};

/// The lines `help` prints, each after `ok ` (one table in program memory
/// on the AVR: a slice of texts was 4 B of RAM a line there, and a
/// constant of the table 8 B).
pub fn help_lines() -> FlashStrs {
    crate::flash_strs!(
        "status | faults | clear",
        "get [KEY] | set KEY VALUE [KEY VALUE ...]",
        "set site.postal_code CC:CODE",
        "save | load | defaults",
        "time set YYYY-MM-DDTHH:MM:SSZ",
        "stow | resume | home | jog c|a DEG | manual off",
        "service on | service off",
    )
}

/// `ok WHAT` (`ok` alone for an empty `what`).
pub fn write_ok(out: &mut dyn Sink, what: FlashStr) {
    out.flash(crate::flash_str!("ok"));
    if !what.is_empty() {
        out.flash(crate::flash_str!(" "));
        out.flash(what);
    }
    out.flash(crate::flash_str!("\n"));
}

/// The start of every `error` line (one copy of the text).
const ERROR: FlashStr = crate::flash_str!("error ");

/// `error WHAT`.
pub fn write_error(out: &mut dyn Sink, what: FlashStr) {
    out.flash(ERROR);
    out.flash(what);
    out.flash(crate::flash_str!("\n"));
}

/// `ok LINE` for every line of [`help_lines`].
pub fn write_help(out: &mut dyn Sink) {
    write_lines(out, help_lines());
}

/// `ok LINE` for every line of `lines`.
pub fn write_lines(out: &mut dyn Sink, lines: FlashStrs) {
    for i in 0..lines.len() {
        if let Some(line) = lines.get(i) {
            write_ok(out, line);
        }
    }
}

/// `KEY=VALUE`, without `ok` or end of line.
pub fn write_key_value(out: &mut dyn Sink, config: &Config, key: Key) {
    key.name().write(out);
    out.flash(crate::flash_str!("="));
    match get(config, key) {
        Value::F32(v) => write_number(out, v),
        Value::U32(v) => out.u32(v),
    }
}

/// `ok KEY=VALUE`: the reply to `get KEY` and to a successful `set`.
pub fn format_get(out: &mut dyn Sink, config: &Config, key: Key) {
    out.flash(crate::flash_str!("ok "));
    write_key_value(out, config, key);
    out.flash(crate::flash_str!("\n"));
}

/// The reply to a line the [`LineBuffer`] refused: `error line too long`, …
pub fn write_line_error(out: &mut dyn Sink, e: LineError) {
    write_error(out, e.text());
}

/// The reply to a line [`parse`] refused; nothing for a blank line.
pub fn write_parse_error(out: &mut dyn Sink, e: &ParseError) {
    let text = match e {
        ParseError::Empty => return,
        ParseError::UnknownCommand => crate::flash_str!("unknown command"),
        ParseError::UnknownKey => crate::flash_str!("unknown key"),
        ParseError::MissingArgument => crate::flash_str!("missing argument"),
        ParseError::UnexpectedArgument => crate::flash_str!("unexpected argument"),
        ParseError::BadValue(k, n) => return write_field_error(out, k.name(), n.text()),
        ParseError::BadNumber(n) => n.text(),
        ParseError::BadAxis => crate::flash_str!("axis must be c or a"),
        ParseError::BadTime => crate::flash_str!("time must be YYYY-MM-DDTHH:MM:SSZ"),
        ParseError::SetOnly => crate::flash_str!("site.postal_code: set only"),
    };
    write_error(out, text);
}

/// The reply text of a postal-code error (after `site.postal_code: `).
pub fn postal_error_text(e: PostalError) -> FlashStr {
    match e {
        PostalError::BadCountry => crate::flash_str!("country must be two letters"),
        PostalError::BadPostalCode => {
            crate::flash_str!("postal code must be 1-10 of 0-9, A-Z, space, -")
        }
        PostalError::BadFormat => crate::flash_str!("expected CC:CODE, e.g. DZ:16000"),
        PostalError::UnknownPostalCode => crate::flash_str!("not in the table"),
        PostalError::NoTable => crate::flash_str!("not in this image"),
    }
}

/// The reply to a refused `set`: `error FIELD: REASON`, `error KEY: whole
/// number expected`, `error KEY: read only`, `error KEY: out of range`,
/// `error site.postal_code: …`.
pub fn write_set_error(out: &mut dyn Sink, e: &SetError) {
    // The key's name looked up once (at each arm, 24 B more on the
    // ATmega2560); `None` for the postal-code pseudo-key.
    let (key, reason) = match *e {
        SetError::Invalid(ConfigError { field, reason }) => (Some(field), reason.text()),
        SetError::NotWhole(k) => (Some(k), crate::flash_str!("whole number expected")),
        SetError::ReadOnly(k) => (Some(k), crate::flash_str!("read only")),
        SetError::OutOfRange(k) => (Some(k), crate::flash_str!("out of range")),
        SetError::Postal(p) => (None, postal_error_text(p)),
    };
    write_field_error(
        out,
        key.map_or(KeyName::plain(POSTAL_CODE_KEY), Key::name),
        reason,
    );
}

/// `error NAME: REASON`: a refused value (a key's, a command's). One copy
/// for the parser's, `set`'s and the hold's refusals (written out at each,
/// 44 B more on the ATmega2560).
#[inline(never)]
pub(super) fn write_field_error(out: &mut dyn Sink, name: KeyName, reason: FlashStr) {
    out.flash(ERROR);
    name.write(out);
    out.flash(crate::flash_str!(": "));
    out.flash(reason);
    out.flash(crate::flash_str!("\n"));
}

/// The reply to `faults`: `ok fault=<name> attempts=<n>` per active fault,
/// or `ok faults=none`.
pub fn write_faults(out: &mut dyn Sink, m: &FaultManager) {
    let mut any = false;
    for a in m.active() {
        out.flash(crate::flash_str!("ok fault="));
        out.flash(a.fault.name());
        out.flash(crate::flash_str!(" attempts="));
        out.u32(u32::from(a.attempts));
        out.flash(crate::flash_str!("\n"));
        any = true;
    }
    if !any {
        write_ok(out, crate::flash_str!("faults=none"));
    }
}

/// The reply to `time set` once the clock is set: `ok utc=…`.
pub fn write_time_set(out: &mut dyn Sink, t: &UtcTime) {
    out.flash(crate::flash_str!("ok utc="));
    out.utc(t);
    out.flash(crate::flash_str!("\n"));
}

/// The reply to `time set` while GPS time is trusted:
/// `error time set: GPS time is in force`.
pub fn write_time_refused(out: &mut dyn Sink) {
    write_error(out, GPS_IN_FORCE);
}

/// The text of [`write_time_refused`] (one copy).
const GPS_IN_FORCE: FlashStr = crate::flash_str!("time set: GPS time is in force");

/// The reply to a refused `time set`: `error time set: GPS time is in
/// force`, `… the RTC did not answer`, `… outside the RTC's range`, `…
/// outside this firmware's dates`.
pub fn write_time_error(out: &mut dyn Sink, e: TimeSetError) {
    write_error(out, time_error_text(e));
}

/// The text of [`write_time_error`]'s line, after `error `.
pub(super) fn time_error_text(e: TimeSetError) -> FlashStr {
    match e {
        TimeSetError::GpsInForce => GPS_IN_FORCE,
        TimeSetError::RtcFailed => crate::flash_str!("time set: the RTC did not answer"),
        TimeSetError::OutOfRange => crate::flash_str!("time set: outside the RTC's range"),
        TimeSetError::OutsideWindow => {
            crate::flash_str!("time set: outside this firmware's dates")
        }
    }
}

/// The reply to `save`: `ok save`, or `error save: config invalid`,
/// `… storage too small`, `… storage failed`.
pub fn write_saved<E>(out: &mut dyn Sink, r: &Result<(), SaveError<E>>) {
    match r {
        Ok(()) => write_ok(out, crate::flash_str!("save")),
        Err(SaveError::Invalid) => write_error(out, crate::flash_str!("save: config invalid")),
        Err(SaveError::TooSmall) => write_error(out, crate::flash_str!("save: storage too small")),
        Err(SaveError::Storage(_)) => write_error(out, crate::flash_str!("save: storage failed")),
    }
}

/// The reply to `load`: `ok load` when a stored copy was good, else
/// `error load: no valid stored config` (the firmware then keeps the
/// configuration in force; `defaults` gives the defaults).
pub fn write_loaded(out: &mut dyn Sink, l: &LoadReport) {
    if l.defaults {
        write_error(out, crate::flash_str!("load: no valid stored config"));
    } else {
        write_ok(out, crate::flash_str!("load"));
    }
}
