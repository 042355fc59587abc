//! Carrying out the configuration commands (`help`, `get`, `set`,
//! `defaults`) on a [`Config`] and answering them.

use super::keys::KEYS;
use super::parse::{names, Command};
use super::postal::apply_postal_code;
use super::reply::{format_get, write_help, write_key_value, write_ok, write_set_error};
use super::set::{apply_assignments, apply_set};
use crate::config::{Config, Field};
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

/// Carries out and answers `help`, `get`, `set` and `defaults` on
/// `config`; passes every other command back.
#[inline(never)]
pub fn run_config<'a>(out: &mut dyn Sink, config: &mut Config, cmd: Command<'a>) -> Outcome<'a> {
    let changed = |ok: bool| {
        if ok {
            Outcome::Changed
        } else {
            Outcome::Answered
        }
    };
    match cmd {
        Command::Help => {
            write_help(out);
            Outcome::Answered
        }
        Command::GetAll => {
            for k in KEYS {
                format_get(out, config, *k);
            }
            Outcome::Answered
        }
        Command::Get(k) => {
            format_get(out, config, k);
            Outcome::Answered
        }
        Command::Set(k, v) => {
            let r = apply_set(config, k, v);
            match r {
                Ok(()) => format_get(out, config, k),
                Err(e) => write_set_error(out, &e),
            }
            changed(r.is_ok())
        }
        Command::SetMany(a) => {
            let r = apply_assignments(config, &a);
            match r {
                Ok(()) => {
                    out.flash(crate::flash_str!("ok"));
                    for (k, _) in a.iter() {
                        out.flash(crate::flash_str!(" "));
                        write_key_value(out, config, k);
                    }
                    out.flash(crate::flash_str!("\n"));
                }
                Err(e) => write_set_error(out, &e),
            }
            changed(r.is_ok())
        }
        Command::SetPostalCode(text) => {
            let r = apply_postal_code(config, text);
            match r {
                Ok(_) => {
                    out.flash(crate::flash_str!("ok "));
                    write_key_value(out, config, Field::SiteLatDeg);
                    out.flash(crate::flash_str!(" "));
                    write_key_value(out, config, Field::SiteLonDeg);
                    out.flash(crate::flash_str!("\n"));
                }
                Err(e) => write_set_error(out, &e),
            }
            changed(r.is_ok())
        }
        Command::Defaults => {
            *config = Config::default();
            write_ok(out, names::DEFAULTS);
            Outcome::Changed
        }
        other => Outcome::Pass(other),
    }
}
