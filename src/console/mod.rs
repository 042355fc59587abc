//! The configuration console every board image offers on its log serial
//! port: a line buffer, a parser of command lines into typed [`Command`]s,
//! the configuration commands themselves, and the reply lines.
//!
//! Everything here is `no_std`, allocation-free and free of `core::fmt`
//! (replies go through [`Sink`], numbers through [`Sink::fixed`] and
//! [`Sink::u32`]) and of core's float parsing (numbers are read by
//! [`Decimal::parse`]); nothing panics on any input.
//!
//! # The language
//!
//! One command a line; words are separated by spaces or tabs, command words
//! and keys are case-insensitive. Every reply line starts with `ok` or
//! `error`; a blank line gets no reply.
//!
//! | command | reply |
//! |---|---|
//! | `help` | one `ok …` line per line of [`help_lines`] |
//! | `status` | `ok mode=<mode> utc=<YYYY-MM-DDTHH:MM:SSZ>\|none time=gps\|rtc\|none lat=<deg> lon=<deg> site=gps\|config c=<deg>\|none a=<deg>\|none faults=<name>,…\|none wind_hz=<Hz>\|none` ([`write_status`]) |
//! | `get` | `ok KEY=VALUE` for every key of the table below |
//! | `get KEY` | `ok KEY=VALUE` |
//! | `set KEY VALUE` or `set KEY=VALUE` | `ok KEY=VALUE` (the value as stored), or `error FIELD: REASON` |
//! | `set K1 V1 K2 V2 …` | all or nothing: `ok K1=V1 K2=V2 …`, or `error FIELD: REASON` |
//! | `set site.postal_code CC:CODE` | `ok site.lat_deg=<deg> site.lon_deg=<deg>`, or `error site.postal_code: …` |
//! | `save`, `load`, `defaults` | `ok save`, `ok load`, `ok defaults`, or `error save: …`, `error load: …` |
//! | `time set YYYY-MM-DDTHH:MM:SSZ` | `ok utc=…`, or `error time set: GPS time is in force` |
//! | `stow`, `resume`, `home`, `manual off`, `clear` | `ok stow`, `ok resume`, … |
//! | `service on`, `service off` | `ok service on`, `ok service off` |
//! | `jog c\|a DEG` | `ok jog c=<deg> a=<deg>` (` limited` at a soft limit) |
//!
//! `stow`, `resume` (which ends a stow and a manual mode), `manual off`,
//! `service on|off` and a `jog` that starts a manual mode change the
//! operator's hold ([`crate::safety::OperatorHold`]): it is in force at
//! once and saved with the stored configuration, and the `ok` comes when
//! the save has ended (a `jog` is answered at once); a failed save is
//! answered `error <command>: in force but not saved`. While the service
//! lock is on (`mode service`) nothing moves, for wind or homing either,
//! except what `jog` moves; an axis with no reference (after a power cut)
//! is jogged from where it stands. `service off` homes both axes again.
//! | `faults` | `ok fault=<name> attempts=<n>` per active fault, or `ok faults=none` |
//!
//! Malformed lines get `error unknown command`, `error unknown key`,
//! `error missing argument`, `error unexpected argument`,
//! `error KEY: not a number`, `error KEY: number too large`,
//! `error axis must be c or a`, `error time must be YYYY-MM-DDTHH:MM:SSZ`;
//! from the [`LineBuffer`]: `error line too long`, `error non-ASCII input`,
//! `error control character`, `error input lost` (the board's receive ring
//! overflowed inside the line: [`LOST_INPUT`]); from the firmware loop,
//! for a line that comes while a save is under way: `error busy`.
//!
//! [`run_config`] carries out `help`, `get`, `set` and `defaults` on a
//! [`Config`] and answers them; the other commands act on the running
//! tracker, so the firmware carries them out and answers with the writers
//! of this module ([`write_status`], [`write_faults`], [`write_saved`],
//! [`write_loaded`], [`write_time_set`], [`write_time_refused`],
//! [`write_ok`] with [`Command::name`]). Refusing `time set` while GPS time
//! is trusted is the firmware's decision.
//!
//! # Keys
//!
//! Every field of [`Config`], named by [`Field::name`] (the dotted key with
//! its unit); [`KEYS`] lists them in `get`'s order. A `set` is applied to a
//! copy of the configuration, the copy is checked by [`Config::validate`],
//! and only a valid copy replaces the configuration: a value out of range
//! changes nothing and is answered with the field and the reason the
//! validation gives ([`ConfigError`]: `error FIELD: REASON`).
//!
//! Each key's unit and range are written once, in the configuration: the
//! bounds in [`crate::config::ranges`], the unit and range of each field in
//! its doc comment ([`Config`] and the structs of its parts, which name the
//! key of each field). Two kinds of key are not plain fields:
//! `site.postal_code` (`CC:CODE`, `set` only, not in [`KEYS`]: a code of
//! the built-in table, [`crate::site::postal`]) and
//! `axis.c.counts_per_deg`, `axis.a.counts_per_deg` (read only, derived:
//! [`crate::config::AxisConfig::counts_per_deg`], [`is_read_only`]).
//!
//! Rules between fields (home switch near `min_deg`, deadband below the
//! largest deviation, the derived counts per degree) can need two fields
//! changed at once: `set axis.c.min_deg -360 axis.c.home_deg -360` sets
//! both or neither.
//!
//! Integer keys take whole numbers (`5` or `5.0`; `5.5` is `error KEY:
//! whole number expected`). A number is an optional sign, digits and an
//! optional fraction (`-12.375`); no exponent, no `nan` or `inf`. Values
//! are printed with as many decimals as an `f32` holds reliably (at most
//! six, trailing zeros dropped), so that a printed value typed back in
//! prints the same.
//!
//! `set site.postal_code DZ:16000` looks the code up in the built-in table
//! and sets latitude and longitude; a numeric code typed without its
//! leading zeros (`DZ:9000` for `DZ:09000`) is found too. The table has no
//! elevation: `site.elevation_m` is left as it is. An image built without
//! the table (its board's [`crate::firmware::Platform::POSTAL_CODES`]; the
//! lookup is [`run_config_with`]'s and [`Operator::postal_lookup`]'s
//! [`PostalLookup`]) answers `error site.postal_code: not in this image`.
//!
//! # Use
//!
//! ```
//! use suntracker::config::{Config, DriveSet};
//! use suntracker::console::{self, LineBuffer, Outcome};
//! use suntracker::log::Sink;
//!
//! struct Out([u8; 64], usize);
//! impl Sink for Out {
//!     fn put(&mut self, bytes: &[u8]) {
//!         for &b in bytes {
//!             if let Some(slot) = self.0.get_mut(self.1) {
//!                 *slot = b;
//!                 self.1 += 1;
//!             }
//!         }
//!     }
//! }
//!
//! let mut config = Config::default();
//! let mut line = LineBuffer::<{ console::LINE_LEN }>::new();
//! let mut out = Out([0; 64], 0);
//! for &byte in b"set wind.stow_hz 30\r\n" {
//!     match line.push(byte) {
//!         None => {}
//!         Some(Err(e)) => console::write_line_error(&mut out, e),
//!         Some(Ok(text)) => match console::parse(text) {
//!             Err(e) => console::write_parse_error(&mut out, &e),
//!             Ok(cmd) => match console::run_config(&mut out, &mut config, DriveSet::STEPPER, cmd) {
//!                 Outcome::Answered | Outcome::Changed => {}
//!                 // status, save, stow, …: the firmware's part.
//!                 Outcome::Pass(cmd) => console::write_ok(&mut out, cmd.name()),
//!             },
//!         },
//!     }
//! }
//! assert_eq!(&out.0[..out.1], b"ok wind.stow_hz=30\n");
//! assert_eq!(config.wind.threshold_hz, 30.0);
//! ```
//!
//! # Size
//!
//! The texts are `&'static str`s: the key names are [`Field::name`]'s and
//! the reasons [`Reason::text`](crate::config::Reason::text)'s, shared with
//! the configuration's validation errors. An 8-bit AVR keeps every linked
//! string, and the postal-code table, in RAM: about 3.5 KB for the whole
//! console, more than the ATmega2560 image has to spare, so an AVR image
//! needs these in program memory before it links the console. Numbers are
//! read without division or 64-bit multiplication; [`parse`],
//! [`run_config`] and the word comparison are kept out of line (inlined,
//! they made the AVR code 2 KB larger).
//!
//! # Files
//!
//! One concern each, all re-exported here: `line` (the [`LineBuffer`]),
//! `number` ([`Decimal`], [`write_number`]), `words` (splitting and
//! comparing words), `keys` (the key table: [`KEYS`], [`get`]), `set`
//! ([`apply_set`], [`apply_assignments`]), `postal` (`set
//! site.postal_code`), `parse` ([`parse`], [`Command`]), `config_commands`
//! ([`run_config`]), `reply` (the `ok`/`error` lines), `status`
//! ([`StatusView`], [`write_status`]) and `operator` ([`Operator`],
//! [`execute`]).

mod config_commands;
mod keys;
mod line;
mod number;
mod operator;
mod parse;
mod postal;
mod reply;
mod ring;
mod set;
mod status;
mod words;

pub use config_commands::{run_config, run_config_with, Outcome};
pub use keys::{get, is_read_only, key_from_name, Key, KeyList, Value, KEYS, POSTAL_CODE_KEY};
pub use line::{LineBuffer, LineError, LINE_LEN, LOST_INPUT, LOST_LINE_END};
pub use number::{write_number, Decimal, NumberError};
pub use operator::{
    execute, set_rtc_time, write_hold_saved, Executed, Jogged, Operator, TimeSetError,
};
pub use parse::{parse, parse_in, parse_utc, Assignments, Command, ParseError};
pub use postal::{apply_postal_code, find_postal, PostalLookup, POSTAL_TABLE};
pub use reply::{
    format_get, help_lines, postal_error_text, write_error, write_faults, write_help,
    write_key_value, write_line_error, write_lines, write_loaded, write_ok, write_parse_error,
    write_saved, write_set_error, write_time_error, write_time_refused, write_time_set,
};
pub use ring::RxRing;
pub use set::{apply_assignments, apply_set, SetError};
pub use status::{write_status, write_status_fields, StatusView};

#[cfg(doc)]
use crate::config::{Config, ConfigError, Field};
#[cfg(doc)]
use crate::log::Sink;
