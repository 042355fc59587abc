//! The parser: a command line into a typed [`Command`], or why it is not
//! one.

use super::keys::{key_in, Key, KeyList, KEYS, POSTAL_CODE_KEY};
use super::number::{Decimal, NumberError};
use super::words::{
    is_blank, is_blank_byte, same_word, split_at_byte, strip_prefix_ignore_case, trim_blank,
    trim_start_blank, word,
};
use crate::safety::AxisId;
use crate::text::FlashStr;
use sun_algos::UtcTime;

/// Several `KEY VALUE` (or `KEY=VALUE`) pairs of one `set`, checked by
/// [`parse`]: every key known, every value a number.
#[derive(Clone, Copy)]
pub struct Assignments<'a> {
    text: &'a str,
    /// The keys the line was parsed against.
    keys: KeyList,
}

impl core::fmt::Debug for Assignments<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Assignments")
            .field("text", &self.text)
            .finish_non_exhaustive()
    }
}

/// The same text parsed against the same key table.
impl PartialEq for Assignments<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.text == other.text && core::ptr::eq(self.keys, other.keys)
    }
}

impl Eq for Assignments<'_> {}

impl<'a> Assignments<'a> {
    /// The pairs, in the order typed.
    pub fn iter(&self) -> impl Iterator<Item = (Key, Decimal)> + 'a {
        let (mut rest, keys) = (self.text, self.keys);
        core::iter::from_fn(move || loop {
            let (key, value, tail) = next_pair(rest).ok()??;
            rest = tail;
            if let (Some(k), Ok(v)) = (key_in(keys, key), Decimal::parse(value)) {
                return Some((k, v));
            }
        })
    }
}

/// A command line, parsed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command<'a> {
    /// `help`.
    Help,
    /// `status`.
    Status,
    /// `get`: every key.
    GetAll,
    /// `get KEY`.
    Get(Key),
    /// `set KEY VALUE` (the value not yet checked against the range).
    Set(Key, Decimal),
    /// `set K1 V1 K2 V2 …`: all or nothing.
    SetMany(Assignments<'a>),
    /// `set site.postal_code CC:CODE`: the text after the key, trimmed.
    SetPostalCode(&'a str),
    /// `save`.
    Save,
    /// `load`.
    Load,
    /// `defaults`.
    Defaults,
    /// `time set YYYY-MM-DDTHH:MM:SSZ`.
    TimeSet(UtcTime),
    /// `stow`.
    Stow,
    /// `resume`.
    Resume,
    /// `home`.
    Home,
    /// `jog c|a DEG`: move an axis by DEG degrees (the firmware keeps it
    /// inside its limits).
    Jog(AxisId, f32),
    /// `manual off`.
    ManualOff,
    /// `service on` (true) or `service off` (false).
    Service(bool),
    /// `faults`.
    Faults,
    /// `clear`.
    Clear,
}

/// The words of the commands that [`execute`](super::execute) answers
/// `ok NAME` itself, each written once: [`Command::name`] gives them, and
/// `execute` names them in the arm of each command (looking them up by the
/// command again cost 268 B more on the ATmega2560).
pub(super) mod names {
    use crate::text::FlashStr;

    pub const DEFAULTS: FlashStr = crate::flash_str!("defaults");
    pub const STOW: FlashStr = crate::flash_str!("stow");
    pub const RESUME: FlashStr = crate::flash_str!("resume");
    pub const HOME: FlashStr = crate::flash_str!("home");
    pub const JOG: FlashStr = crate::flash_str!("jog");
    pub const MANUAL_OFF: FlashStr = crate::flash_str!("manual off");
    pub const SERVICE_ON: FlashStr = crate::flash_str!("service on");
    pub const SERVICE_OFF: FlashStr = crate::flash_str!("service off");
    pub const CLEAR: FlashStr = crate::flash_str!("clear");
}

impl Command<'_> {
    /// The command's words, for its `ok` reply (`stow`, `manual off`,
    /// `time set`, …).
    pub fn name(&self) -> FlashStr {
        match self {
            Command::Help => crate::flash_str!("help"),
            Command::Status => crate::flash_str!("status"),
            Command::GetAll | Command::Get(_) => crate::flash_str!("get"),
            Command::Set(..) | Command::SetMany(_) | Command::SetPostalCode(_) => {
                crate::flash_str!("set")
            }
            Command::Save => crate::flash_str!("save"),
            Command::Load => crate::flash_str!("load"),
            Command::Defaults => names::DEFAULTS,
            Command::TimeSet(_) => crate::flash_str!("time set"),
            Command::Stow => names::STOW,
            Command::Resume => names::RESUME,
            Command::Home => names::HOME,
            Command::Jog(..) => names::JOG,
            Command::ManualOff => names::MANUAL_OFF,
            Command::Service(true) => names::SERVICE_ON,
            Command::Service(false) => names::SERVICE_OFF,
            Command::Faults => crate::flash_str!("faults"),
            Command::Clear => names::CLEAR,
        }
    }
}

/// Why a line is not a command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParseError {
    /// Nothing but blanks: no reply.
    Empty,
    /// `error unknown command`.
    UnknownCommand,
    /// `error unknown key`.
    UnknownKey,
    /// `error missing argument`.
    MissingArgument,
    /// `error unexpected argument`.
    UnexpectedArgument,
    /// `error KEY: not a number` or `… number too large`.
    BadValue(Key, NumberError),
    /// `error not a number` or `error number too large` (`jog`).
    BadNumber(NumberError),
    /// `error axis must be c or a`.
    BadAxis,
    /// `error time must be YYYY-MM-DDTHH:MM:SSZ` (also for a date that
    /// does not exist).
    BadTime,
    /// `get site.postal_code`: `error site.postal_code: set only`.
    SetOnly,
}

fn no_more(rest: &str) -> Result<(), ParseError> {
    if is_blank(rest) {
        Ok(())
    } else {
        Err(ParseError::UnexpectedArgument)
    }
}

/// The next `KEY VALUE` or `KEY=VALUE` pair: (key, value, rest), `None` at
/// the end.
fn next_pair(s: &str) -> Result<Option<(&str, &str, &str)>, ParseError> {
    let (first, rest) = word(s);
    if first.is_empty() {
        return Ok(None);
    }
    let (key, value, rest) = match split_at_byte(first, b'=') {
        Some((k, v)) => (k, v, rest),
        None => {
            let (v, rest) = word(rest);
            (first, v, rest)
        }
    };
    if key.is_empty() || value.is_empty() {
        return Err(ParseError::MissingArgument);
    }
    Ok(Some((key, value, rest)))
}

/// Parses `set`'s arguments against `keys`.
fn parse_set(args: &str, keys: KeyList) -> Result<Command<'_>, ParseError> {
    let trimmed = trim_start_blank(args);
    if let Some(after) = strip_prefix_ignore_case(trimmed, POSTAL_CODE_KEY) {
        // The byte after the key: `=`, a blank or the end (a byte test, not
        // core's char pattern, 16 B more on the ATmega2560).
        let value = match after.bytes().next() {
            Some(b'=') => after.get(1..),
            next => next.is_none_or(is_blank_byte).then_some(after),
        };
        if let Some(value) = value {
            let value = trim_blank(value);
            if value.is_empty() {
                return Err(ParseError::MissingArgument);
            }
            return Ok(Command::SetPostalCode(value));
        }
    }
    let mut rest = args;
    let mut count = 0u8;
    let mut single = None;
    while let Some((key, value, tail)) = next_pair(rest)? {
        if same_word(key, POSTAL_CODE_KEY) {
            return Err(ParseError::UnexpectedArgument);
        }
        let k = key_in(keys, key).ok_or(ParseError::UnknownKey)?;
        let v = Decimal::parse(value).map_err(|e| ParseError::BadValue(k, e))?;
        single = Some((k, v));
        count = count.saturating_add(1);
        rest = tail;
    }
    match single {
        None => Err(ParseError::MissingArgument),
        Some((k, v)) if count == 1 => Ok(Command::Set(k, v)),
        Some(_) => Ok(Command::SetMany(Assignments { text: args, keys })),
    }
}

/// `YYYY-MM-DDTHH:MM:SSZ` exactly (`T` and `Z` in either case).
pub fn parse_utc(s: &str) -> Option<UtcTime> {
    // `0` stands for a digit; the other bytes end a field. In program
    // memory on the AVR (as a constant it took 20 B of RAM; the separators
    // tested one by one instead were 28 B more code there, 116 B more on
    // the Cortex-M4F).
    crate::progmem! {
        static TEMPLATE: [u8; 20] = *b"0000-00-00T00:00:00Z";
    }
    let b = s.as_bytes();
    if b.len() != TEMPLATE.len() {
        return None;
    }
    // Year, month, day, hour, minute, second: at most 9999.
    let mut fields = [0u16; 6];
    let mut field = 0usize;
    for (&c, t) in b.iter().zip(TEMPLATE.iter()) {
        if t == b'0' {
            if !c.is_ascii_digit() {
                return None;
            }
            let f = fields.get_mut(field)?;
            *f = f
                .wrapping_mul(10)
                .wrapping_add(u16::from(c.wrapping_sub(b'0')));
        } else if c.eq_ignore_ascii_case(&t) {
            field = field.saturating_add(1);
        } else {
            return None;
        }
    }
    let [year, month, day, hour, minute, second] = fields;
    let small = |v: u16| u8::try_from(v).ok();
    UtcTime::from_ymd_hms(
        i32::from(year),
        small(month)?,
        small(day)?,
        small(hour)?,
        small(minute)?,
        small(second)?,
    )
    .ok()
}

/// The first word of a command line.
#[derive(Clone, Copy)]
enum Verb {
    Help,
    Status,
    Get,
    Set,
    Save,
    Load,
    Defaults,
    Time,
    Stow,
    Resume,
    Home,
    Jog,
    Manual,
    Service,
    Faults,
    Clear,
}

/// The command words and their verbs, each pair written once: the words as
/// one [`FlashStrs`](crate::text::FlashStrs) table, the verbs in a table of
/// the same order (both in program memory on AVR; read one at a time).
macro_rules! verbs {
    ($($word:literal => $verb:ident,)*) => {
        fn verb_words() -> crate::text::FlashStrs {
            crate::flash_strs!($($word),*)
        }

        crate::progmem! {
            /// The verb of each of [`verb_words`].
            static VERB_OF: [Verb; [$(Verb::$verb),*].len()] = [$(Verb::$verb),*];
        }
    };
}

verbs! {
    "help" => Help,
    "status" => Status,
    "get" => Get,
    "set" => Set,
    "save" => Save,
    "load" => Load,
    "defaults" => Defaults,
    "time" => Time,
    "stow" => Stow,
    "resume" => Resume,
    "home" => Home,
    "jog" => Jog,
    "manual" => Manual,
    "service" => Service,
    "faults" => Faults,
    "clear" => Clear,
}

/// The second word of `manual off` and `service off` (one copy of the
/// text).
const OFF: FlashStr = crate::flash_str!("off");

/// Parses one command line (see the module docs for the language).
pub fn parse(line: &str) -> Result<Command<'_>, ParseError> {
    parse_in(line, KEYS.as_slice())
}

/// Parses one command line whose keys are those of `keys`: the language of
/// [`parse`] on a board that offers a part of the configuration (the
/// Arduino Uno's settings); any other key is `error unknown key`.
#[inline(never)]
pub fn parse_in(line: &str, keys: KeyList) -> Result<Command<'_>, ParseError> {
    let (cmd, rest) = word(line);
    if cmd.is_empty() {
        return Err(ParseError::Empty);
    }
    let words = verb_words();
    let Some(verb) = (0..words.len())
        .find(|&i| words.get(i).is_some_and(|w| same_word(cmd, w)))
        .and_then(|i| VERB_OF.get(i))
    else {
        return Err(ParseError::UnknownCommand);
    };
    let (arg, after) = word(rest);
    // The commands of one word: one check that nothing follows for all
    // (one per command, 88 B more on the ATmega2560).
    let alone = match verb {
        Verb::Help => Command::Help,
        Verb::Status => Command::Status,
        Verb::Save => Command::Save,
        Verb::Load => Command::Load,
        Verb::Defaults => Command::Defaults,
        Verb::Stow => Command::Stow,
        Verb::Resume => Command::Resume,
        Verb::Home => Command::Home,
        Verb::Faults => Command::Faults,
        Verb::Clear => Command::Clear,
        Verb::Get => {
            if arg.is_empty() {
                return Ok(Command::GetAll);
            }
            no_more(after)?;
            if same_word(arg, POSTAL_CODE_KEY) {
                return Err(ParseError::SetOnly);
            }
            return key_in(keys, arg)
                .map(Command::Get)
                .ok_or(ParseError::UnknownKey);
        }
        Verb::Set => return parse_set(rest, keys),
        Verb::Time => {
            if !same_word(arg, crate::flash_str!("set")) {
                return Err(ParseError::UnknownCommand);
            }
            let (t, after) = word(after);
            if t.is_empty() {
                return Err(ParseError::MissingArgument);
            }
            no_more(after)?;
            return parse_utc(t)
                .map(Command::TimeSet)
                .ok_or(ParseError::BadTime);
        }
        Verb::Manual => {
            if !same_word(arg, OFF) {
                return Err(ParseError::UnknownCommand);
            }
            return no_more(after).map(|()| Command::ManualOff);
        }
        Verb::Service => {
            let on = if same_word(arg, crate::flash_str!("on")) {
                true
            } else if same_word(arg, OFF) {
                false
            } else if arg.is_empty() {
                return Err(ParseError::MissingArgument);
            } else {
                return Err(ParseError::UnknownCommand);
            };
            return no_more(after).map(|()| Command::Service(on));
        }
        Verb::Jog => {
            let (deg, after) = word(after);
            if deg.is_empty() {
                return Err(ParseError::MissingArgument);
            }
            no_more(after)?;
            let axis = if same_word(arg, crate::flash_str!("c")) {
                AxisId::C
            } else if same_word(arg, crate::flash_str!("a")) {
                AxisId::A
            } else {
                return Err(ParseError::BadAxis);
            };
            let deg = Decimal::parse(deg).map_err(ParseError::BadNumber)?;
            return Ok(Command::Jog(axis, deg.to_f32()));
        }
    };
    if arg.is_empty() {
        Ok(alone)
    } else {
        Err(ParseError::UnexpectedArgument)
    }
}
