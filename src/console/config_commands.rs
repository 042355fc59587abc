//! Carrying out the configuration commands (`help`, `get`, `set`,
//! `defaults`) on a [`Config`] and answering them.

use super::keys::KEYS;
use super::parse::{names, Command};
use super::postal::{apply_postal, PostalLookup, POSTAL_TABLE};
use super::reply::{format_get, write_help, write_key_value, write_ok, write_set_error};
use super::set::{apply_assignments, apply_set};
use crate::config::{Config, DriveSet, Field};
use crate::log::Sink;

/// What [`run_config`] did with a command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome<'a> {
    /// Answered; the configuration is unchanged.
    Answered,
    /// Answered; the configuration changed (the firmware puts it into
    /// effect; `save` stores it).
    Changed,
    /// Not a configuration command: the firmware carries it out and
    /// answers.
    Pass(Command<'a>),
}

/// `config` back to its defaults. Not inlined on the AVR: the defaults
/// are built in this frame, on the stack only while it runs (inlined
/// elsewhere: 28 B less on the Cortex-M images).
#[cfg_attr(target_arch = "avr", inline(never))]
fn reset(config: &mut Config) {
    *config = Config::default();
}

/// Carries out and answers `help`, `get`, `set` and `defaults` on
/// `config`; passes every other command back. A `set` that gives an axis
/// a drive kind outside `drives` (the board's) is refused like a value
/// out of range. `set site.postal_code` looks in the built-in table.
pub fn run_config<'a>(
    out: &mut dyn Sink,
    config: &mut Config,
    drives: DriveSet,
    cmd: Command<'a>,
) -> Outcome<'a> {
    run_config_with(out, config, drives, POSTAL_TABLE, cmd)
}

/// [`run_config`] with the image's postal-code lookup, `postal` (`None`:
/// built without the table).
#[inline(never)]
pub fn run_config_with<'a>(
    out: &mut dyn Sink,
    config: &mut Config,
    drives: DriveSet,
    postal: PostalLookup,
    cmd: Command<'a>,
) -> Outcome<'a> {
    // The `set`s: their refusal answered by one call for all three kinds
    // (one in each arm cost more on the ATmega2560).
    let set = match cmd {
        Command::Help => {
            write_help(out);
            return Outcome::Answered;
        }
        Command::GetAll => {
            for k in KEYS.iter() {
                format_get(out, config, k);
            }
            return Outcome::Answered;
        }
        Command::Get(k) => {
            format_get(out, config, k);
            return Outcome::Answered;
        }
        Command::Set(k, v) => apply_set(config, k, v, drives),
        Command::SetMany(a) => apply_assignments(config, &a, drives),
        Command::SetPostalCode(text) => apply_postal(config, text, postal).map(|_| ()),
        Command::Defaults => {
            reset(config);
            write_ok(out, names::DEFAULTS);
            return Outcome::Changed;
        }
        other => return Outcome::Pass(other),
    };
    if let Err(e) = set {
        write_set_error(out, &e);
        return Outcome::Answered;
    }
    match cmd {
        Command::Set(k, _) => format_get(out, config, k),
        Command::SetMany(a) => {
            out.flash(crate::flash_str!("ok"));
            for (k, _) in a.iter() {
                out.flash(crate::flash_str!(" "));
                write_key_value(out, config, k);
            }
            out.flash(crate::flash_str!("\n"));
        }
        // `set site.postal_code`.
        _ => {
            out.flash(crate::flash_str!("ok "));
            write_key_value(out, config, Field::SiteLatDeg);
            out.flash(crate::flash_str!(" "));
            write_key_value(out, config, Field::SiteLonDeg);
            out.flash(crate::flash_str!("\n"));
        }
    }
    Outcome::Changed
}
