//! The operator: what a running tracker lets the console do
//! ([`Operator`]), and [`execute`], which answers every command through it.

use super::config_commands::{run_config_with, Outcome};
use super::parse::{names, parse, Command, ParseError};
use super::postal::{PostalLookup, POSTAL_TABLE};
use super::reply::{
    time_error_text, write_error, write_field_error, write_loaded, write_ok, write_parse_error,
    write_saved, write_time_set,
};
use super::status::{write_status, StatusView};
use crate::config::{Config, DriveSet, KeyName};
use crate::log::Sink;
use crate::persist::{LoadReport, SaveError};
use crate::safety::{AxisId, OperatorHold};
use crate::text::FlashStr;
use crate::time::{datetime_from_utc, DateWindow};
use drivers::rtc::Clock as RtcDriver;
use sun_algos::UtcTime;

#[cfg(doc)]
use super::reply::write_faults;

/// Sets `rtc` to `t` (the console's `time set` once the firmware has
/// allowed it): `OutsideWindow` for an instant outside this firmware's
/// date window (the tracker would not trust the RTC then:
/// [`DateWindow::firmware`]), `OutOfRange` for one the RTC's calendar
/// cannot hold, `RtcFailed` when the chip did not take it.
pub fn set_rtc_time<R: RtcDriver>(rtc: &mut R, t: &UtcTime) -> Result<(), TimeSetError> {
    if !DateWindow::firmware().contains(t) {
        return Err(TimeSetError::OutsideWindow);
    }
    let d = datetime_from_utc(t).map_err(|_| TimeSetError::OutOfRange)?;
    rtc.set_datetime(&d).map_err(|_| TimeSetError::RtcFailed)
}

/// Why `time set` was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeSetError {
    /// GPS time is trusted: `error time set: GPS time is in force`.
    GpsInForce,
    /// The RTC did not take it: `error time set: the RTC did not answer`.
    RtcFailed,
    /// Outside what the RTC holds: `error time set: outside the RTC's range`.
    OutOfRange,
    /// Outside this firmware's date window (1024 weeks from 2026-01-01),
    /// where it would not trust the RTC: `error time set: outside this
    /// firmware's dates`.
    OutsideWindow,
}

/// The result of a `jog`: the manual pose now commanded, and whether the
/// soft limits cut the move short.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jogged {
    /// C-axis angle commanded, degrees.
    pub c_deg: f32,
    /// A-axis angle commanded, degrees.
    pub a_deg: f32,
    /// The move was held at a soft limit.
    pub limited: bool,
}

/// What a board's tracker lets the console do besides editing the
/// configuration: [`execute`] answers every command through it, so every
/// board speaks the same language with the same replies.
pub trait Operator {
    /// Where replies go (the log port).
    fn out(&mut self) -> &mut dyn Sink;
    /// The configuration in force.
    fn config(&self) -> Config;
    /// The board's own configuration, which `defaults` restores (its
    /// mechanics, not [`Config::default`]'s generic ones).
    fn defaults(&self) -> Config;
    /// The drive kinds the board's image builds axes of (`set
    /// axis.c.drive` refuses the others).
    fn drives(&self) -> DriveSet;
    /// How `set site.postal_code` looks codes up: the built-in table (the
    /// default), or `None` in an image built without it.
    fn postal_lookup(&self) -> PostalLookup {
        POSTAL_TABLE
    }
    /// Puts a changed (valid) configuration into effect; false when the
    /// tracker refused it (then nothing changed).
    fn apply(&mut self, config: Config) -> bool;
    /// What `status` reports.
    fn status(&self) -> StatusView;
    /// Writes the `faults` reply ([`write_faults`] or the same shape).
    fn write_faults(&mut self);
    /// Starts storing `config`: `None` when the board has no storage; the
    /// reply to a started save comes when it ends (the caller polls it).
    fn begin_save(&mut self, config: &Config) -> Option<Result<(), SaveError<()>>>;
    /// Reads the stored configuration into `into` (the defaults when no
    /// stored copy is good): `None` when the board has no storage.
    fn load(&mut self, into: &mut Config) -> Option<LoadReport>;
    /// Sets the RTC.
    fn set_time(&mut self, t: &UtcTime) -> Result<(), TimeSetError>;
    /// An operator's stow (true) or its release (false).
    fn stow(&mut self, on: bool);
    /// The service lock on (true) or off (false).
    fn service(&mut self, on: bool);
    /// The operator's hold in force (changed by `stow`, `resume`, `jog`,
    /// `manual off` and `service`).
    fn hold(&self) -> OperatorHold;
    /// Homes both axes again; false on a board without home switches.
    fn home(&mut self) -> bool;
    /// Manual mode: moves `axis` by `deg`, within the soft limits.
    fn jog(&mut self, axis: AxisId, deg: f32) -> Jogged;
    /// Leaves manual mode.
    fn manual_off(&mut self);
    /// The operator's reset of a safe stop: faults cleared.
    fn clear(&mut self);
}

/// What [`execute`] left for the caller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Executed {
    /// Answered (or a blank line).
    Done,
    /// A save was started: poll it and answer with [`write_saved`] when it
    /// ends.
    SaveStarted,
    /// The command changed the operator's hold ([`Operator::hold`]): the
    /// caller stores it with the *stored* configuration (not the one in
    /// force, which may hold unsaved `set`s) and, when that save ends,
    /// answers with [`write_hold_saved`] (`ok NAME` only if
    /// `ok_when_saved`: a `jog` was answered at once). The save is the
    /// caller's, after this returns, so that its buffers are not on the
    /// stack under the command's.
    HoldChanged {
        /// The command's name ([`Command::name`]).
        name: FlashStr,
        /// Whether success is answered (`ok NAME`).
        ok_when_saved: bool,
    },
}

/// The end of a hold save: `ok NAME` (when asked for), or `error NAME: in
/// force but not saved` (the hold holds until a power cut, which would end
/// it: the operator is told).
pub fn write_hold_saved(
    out: &mut dyn Sink,
    name: FlashStr,
    ok_when_saved: bool,
    result: &Result<(), SaveError<()>>,
) {
    match result {
        Ok(()) if ok_when_saved => write_ok(out, name),
        Ok(()) => {}
        Err(_) => write_field_error(
            out,
            KeyName::plain(name),
            crate::flash_str!("in force but not saved"),
        ),
    }
}

/// After a command that may have changed the operator's hold (`before`):
/// [`Executed::HoldChanged`] when it did, else the answer at once.
fn save_hold(
    op: &mut dyn Operator,
    before: OperatorHold,
    name: FlashStr,
    ok_when_saved: bool,
) -> Executed {
    if op.hold() != before {
        return Executed::HoldChanged {
            name,
            ok_when_saved,
        };
    }
    if ok_when_saved {
        write_ok(op.out(), name);
    }
    Executed::Done
}

/// Puts `config` into effect ([`Operator::apply`]); when the tracker
/// refuses it, answers `error config refused by the tracker: not in
/// effect` and returns false. One copy of the reply for `defaults`, `set`
/// and `load` (three copies of its text and call cost 130 B more on the
/// ATmega2560).
#[inline(never)]
fn put_into_effect(op: &mut dyn Operator, config: Config) -> bool {
    let applied = op.apply(config);
    if !applied {
        write_error(
            op.out(),
            crate::flash_str!("config refused by the tracker: not in effect"),
        );
    }
    applied
}

/// `defaults`: the board's defaults put into effect, answered. Not
/// inlined on the AVR: the defaults are on the stack only while it runs.
#[cfg_attr(target_arch = "avr", inline(never))]
fn put_defaults_into_effect(op: &mut dyn Operator) {
    let defaults = op.defaults();
    if put_into_effect(op, defaults) {
        write_ok(op.out(), names::DEFAULTS);
    }
}

/// Parses `line`, carries it out through `op` and answers on
/// [`Operator::out`]. Not inlined: a command's temporaries (a copy of the
/// configuration, the status view) are on the stack only while it runs.
#[inline(never)]
pub fn execute(op: &mut dyn Operator, line: &str) -> Executed {
    let cmd = match parse(line) {
        Ok(c) => c,
        Err(ParseError::Empty) => return Executed::Done,
        Err(e) => {
            write_parse_error(op.out(), &e);
            return Executed::Done;
        }
    };
    if cmd == Command::Defaults {
        put_defaults_into_effect(op);
        return Executed::Done;
    }
    let mut config = op.config();
    let drives = op.drives();
    let postal = op.postal_lookup();
    let cmd = match run_config_with(op.out(), &mut config, drives, postal, cmd) {
        Outcome::Answered => return Executed::Done,
        Outcome::Changed => {
            put_into_effect(op, config);
            return Executed::Done;
        }
        Outcome::Pass(cmd) => cmd,
    };
    // The commands answered `ok NAME` or `error TEXT` at the end, by one
    // call of each writer (a pair of calls in each arm cost more on the
    // ATmega2560).
    let reply = match cmd {
        Command::Status => {
            let view = op.status();
            write_status(op.out(), &view);
            return Executed::Done;
        }
        Command::Faults => {
            op.write_faults();
            return Executed::Done;
        }
        Command::Save => match op.begin_save(&config) {
            Some(Ok(())) => return Executed::SaveStarted,
            Some(Err(e)) => {
                write_saved(op.out(), &Err(e));
                return Executed::Done;
            }
            None => Err(crate::flash_str!("save: no storage on this board")),
        },
        // Read into this command's copy: no second configuration on the
        // stack (an 8-bit board runs this on top of its loop's).
        Command::Load => match op.load(&mut config) {
            Some(report) => {
                write_loaded(op.out(), &report);
                if !report.defaults {
                    put_into_effect(op, config);
                }
                return Executed::Done;
            }
            None => Err(crate::flash_str!("load: no storage on this board")),
        },
        Command::TimeSet(t) => match op.set_time(&t) {
            Ok(()) => {
                write_time_set(op.out(), &t);
                return Executed::Done;
            }
            Err(e) => Err(time_error_text(e)),
        },
        Command::Stow | Command::Resume | Command::ManualOff | Command::Service(_) => {
            let before = op.hold();
            let name = match cmd {
                Command::Stow => {
                    op.stow(true);
                    names::STOW
                }
                Command::Service(on) => {
                    op.service(on);
                    if on {
                        names::SERVICE_ON
                    } else {
                        names::SERVICE_OFF
                    }
                }
                // `resume` ends a stow and a manual mode.
                Command::Resume => {
                    op.stow(false);
                    op.manual_off();
                    names::RESUME
                }
                _ => {
                    op.manual_off();
                    names::MANUAL_OFF
                }
            };
            return save_hold(op, before, name, true);
        }
        Command::Home => {
            if op.home() {
                Ok(names::HOME)
            } else {
                Err(crate::flash_str!("home: no home switches on this board"))
            }
        }
        Command::Clear => {
            op.clear();
            Ok(names::CLEAR)
        }
        Command::Jog(axis, deg) => {
            let before = op.hold();
            let j = op.jog(axis, deg);
            let out = op.out();
            out.flash(crate::flash_str!("ok jog c="));
            out.fixed(j.c_deg, 2);
            out.flash(crate::flash_str!(" a="));
            out.fixed(j.a_deg, 2);
            out.flash(if j.limited {
                crate::flash_str!(" limited\n")
            } else {
                crate::flash_str!("\n")
            });
            return save_hold(op, before, names::JOG, false);
        }
        // Carried out by `run_config`.
        Command::Help
        | Command::GetAll
        | Command::Get(_)
        | Command::Set(..)
        | Command::SetMany(_)
        | Command::SetPostalCode(_)
        | Command::Defaults => return Executed::Done,
    };
    match reply {
        Ok(name) => write_ok(op.out(), name),
        Err(text) => write_error(op.out(), text),
    }
    Executed::Done
}
