//! Command-line handling shared by the host tools (`examples/*.rs`): one
//! argument parser, one help layout, one error convention.
//!
//! Each tool includes this file as a module (`#[path = "common/cli.rs"] mod
//! cli;` from `examples/`, `#[path = "../common/cli.rs"]` from a support
//! directory) and writes its own loop over [`Parser::next`]:
//!
//! ```text
//! let mut p = cli::parser(args);
//! while let Some(arg) = p.next().map_err(cli::error)? {
//!     match arg {
//!         Short('h') | Long("help") => return Ok(Parsed::Help),
//!         Long("lat") => lat = Some(cli::number(&mut p, "--lat")?),
//!         other => return Err(cli::unexpected(other)),
//!     }
//! }
//! ```
//!
//! and its help as a [`Help`] value: every option with its default, and the
//! algorithms (`Algorithm::ALL`, each with `validity_years`) when the tool
//! takes `--algorithm`.
//!
//! The conventions (POSIX utility syntax, getopt_long's `--name value` and
//! `--name=value`):
//! - `-h`/`--help` prints the help on stdout and exits 0; the arguments
//!   after it are not read (those before it are, so an unknown option before
//!   it is still reported);
//! - a usage error (an unknown option, a missing or bad value, a pair of
//!   options that exclude each other) prints `tool: message` on stderr,
//!   naming the option(s), and exits 2 ([`EXIT_USAGE`], as getopt-based
//!   tools, argparse and clap do);
//! - a value may start with `-` (`--lon -0.1278`), `--` ends the options.
//!
//! Why [lexopt](https://docs.rs/lexopt/0.3) rather than clap or argh: it is
//! one source file with no dependencies and no proc-macros (clap's derive
//! builds `syn` and `quote`, argh's too), so the examples build in the time
//! of that one file; it is already in the lock file at 0.3 for `emu/`; and
//! it does the lexing right (`--opt=value`, clustered short flags, `--`,
//! negative numbers as values, non-UTF-8 arguments as errors rather than
//! panics) while leaving help and messages to us, which is where the tools
//! have to agree.

// Each tool uses a part of this file.
#![allow(dead_code)]

use std::ffi::OsString;
use std::fmt::Write as _;
use std::io::Write;
use std::process::ExitCode;

pub use lexopt::prelude::*;
pub use lexopt::{Arg, Parser};
use sun_algos::{Algorithm, UtcTime};
use suntracker::site::postal;

/// Exit code of a usage error (bad option, value or combination).
pub const EXIT_USAGE: u8 = 2;

/// Width the help text is wrapped to.
const HELP_WIDTH: usize = 100;

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq)]
pub enum Parsed<T> {
    /// `-h`/`--help`: print the help, do nothing else.
    Help,
    /// Run with these arguments.
    Run(T),
}

/// A lexopt parser over `args` (without the program name).
pub fn parser(args: &[String]) -> Parser {
    Parser::from_args(args.iter())
}

/// The arguments of this process (without the program name), or the
/// message for one that is not UTF-8.
pub fn process_args() -> Result<Vec<String>, String> {
    std::env::args_os()
        .skip(1)
        .map(|a: OsString| {
            a.into_string()
                .map_err(|a| format!("argument {a:?} is not UTF-8"))
        })
        .collect()
}

/// `main` of a tool: runs `run` on this process's arguments, stdout and
/// stderr and exits with the code it returns.
pub fn main(
    tool: &str,
    run: impl FnOnce(&[String], &mut dyn Write, &mut dyn Write) -> u8,
) -> ExitCode {
    let stdout = std::io::stdout();
    let stderr = std::io::stderr();
    let (mut out, mut err) = (stdout.lock(), stderr.lock());
    let code = match process_args() {
        Ok(args) => run(&args, &mut out, &mut err),
        Err(e) => usage_error(tool, &e, &mut err),
    };
    ExitCode::from(code)
}

/// Writes `tool: message` to `err`; returns [`EXIT_USAGE`].
pub fn usage_error(tool: &str, message: &str, err: &mut dyn Write) -> u8 {
    // Best effort: nothing else can be done with a closed stderr.
    let _ = writeln!(err, "{tool}: {message}");
    EXIT_USAGE
}

/// Writes the help to `out`; returns the exit code 0 (a closed stdout, as
/// in `tool --help | head`, is not an error).
pub fn print_help(help: &Help, out: &mut dyn Write) -> u8 {
    let _ = out.write_all(help.render().as_bytes());
    let _ = out.flush();
    0
}

/// The message of a lexopt error, naming the option.
pub fn error(e: lexopt::Error) -> String {
    use lexopt::Error as E;
    match e {
        E::MissingValue { option: Some(o) } => format!("{o} needs a value"),
        E::MissingValue { option: None } => "a value is missing".into(),
        E::UnexpectedOption(o) => format!("unknown option {o} (--help lists the options)"),
        E::UnexpectedArgument(v) => {
            format!("unexpected argument {v:?} (--help lists the options)")
        }
        E::UnexpectedValue { option, value } => {
            format!("{option} takes no value (given {value:?})")
        }
        E::NonUnicodeValue(v) => format!("argument {v:?} is not UTF-8"),
        E::ParsingFailed { value, error } => format!("{value:?}: {error}"),
        E::Custom(e) => e.to_string(),
    }
}

/// The message for an argument the tool does not take.
pub fn unexpected(arg: Arg<'_>) -> String {
    error(arg.unexpected())
}

/// The value of option `opt`, as text.
pub fn text(p: &mut Parser, opt: &str) -> Result<String, String> {
    let v = p.value().map_err(error)?;
    v.into_string()
        .map_err(|v| format!("{opt} {v:?}: not UTF-8"))
}

/// The value of option `opt` as a finite number.
pub fn number(p: &mut Parser, opt: &str) -> Result<f64, String> {
    let v = text(p, opt)?;
    v.trim()
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("{opt} {v:?}: not a number"))
}

/// The value of option `opt` read by `read`, which returns `None` for a
/// value it refuses; `want` says what is accepted.
pub fn value<T>(
    p: &mut Parser,
    opt: &str,
    want: &str,
    read: impl FnOnce(&str) -> Option<T>,
) -> Result<T, String> {
    let v = text(p, opt)?;
    read(v.trim()).ok_or_else(|| format!("{opt} {v:?}: want {want}"))
}

/// The value of option `opt`, one of `choices` (name, value).
pub fn choice<T: Copy>(p: &mut Parser, opt: &str, choices: &[(&str, T)]) -> Result<T, String> {
    let names: Vec<&str> = choices.iter().map(|c| c.0).collect();
    value(p, opt, &names.join(" or "), |v| {
        choices.iter().find(|c| c.0 == v).map(|c| c.1)
    })
}

/// The value of option `opt` as a date `YYYY-MM-DD` (a real calendar day
/// in the range `UtcTime` covers).
pub fn date(p: &mut Parser, opt: &str) -> Result<(i32, u8, u8), String> {
    let v = text(p, opt)?;
    let t: UtcTime = format!("{}T00:00:00Z", v.trim())
        .parse()
        .map_err(|e| format!("{opt} {v:?}: {e} (want YYYY-MM-DD)"))?;
    Ok(t.ymd())
}

/// The value of option `opt` as an algorithm name.
pub fn algorithm(p: &mut Parser, opt: &str) -> Result<Algorithm, String> {
    let v = text(p, opt)?;
    Algorithm::from_name(v.trim()).ok_or_else(|| {
        let names: Vec<&str> = Algorithm::ALL.iter().map(|a| a.name()).collect();
        format!("{opt} {v:?}: one of {}", names.join(", "))
    })
}

/// A site given on the command line.
#[derive(Debug, Clone, PartialEq)]
pub enum SiteArg {
    /// Neither `--lat/--lon` nor `--postal-code`: the tool's default.
    Default,
    /// `--lat` and `--lon`, degrees.
    LatLon(f64, f64),
    /// `--postal-code CC:CODE`.
    Postal(String),
}

/// The site of `--lat`, `--lon` and `--postal-code`: both coordinates or
/// the code, not both, not one coordinate alone.
pub fn site_arg(
    lat: Option<f64>,
    lon: Option<f64>,
    postal: Option<String>,
) -> Result<SiteArg, String> {
    match (lat, lon, postal) {
        (None, None, None) => Ok(SiteArg::Default),
        (Some(la), Some(lo), None) => Ok(SiteArg::LatLon(la, lo)),
        (None, None, Some(code)) => Ok(SiteArg::Postal(code)),
        (la, lo, Some(_)) => {
            let given = match (la, lo) {
                (Some(_), Some(_)) => "--lat/--lon",
                (Some(_), None) => "--lat",
                _ => "--lon",
            };
            Err(format!(
                "--postal-code conflicts with {given}: give the site by one of them"
            ))
        }
        (Some(_), None, None) => Err("--lat needs --lon (they go together)".into()),
        (None, Some(_), None) => Err("--lon needs --lat (they go together)".into()),
    }
}

/// A resolved site: latitude and longitude (degrees) and its name.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedSite {
    pub lat_deg: f64,
    pub lon_deg: f64,
    pub place: String,
}

/// The site of `arg`: `default` when none is given, `"site"` for bare
/// coordinates, the postal place name followed by the code otherwise.
/// Coordinates out of range are an error.
pub fn resolve_site(arg: &SiteArg, default: NamedSite) -> Result<NamedSite, String> {
    let s = match arg {
        SiteArg::Default => default,
        SiteArg::LatLon(la, lo) => NamedSite {
            lat_deg: *la,
            lon_deg: *lo,
            place: "site".into(),
        },
        SiteArg::Postal(code) => {
            let e = postal::lookup_str(code).map_err(|e| format!("--postal-code {code:?}: {e}"))?;
            NamedSite {
                lat_deg: e.latitude_deg(),
                lon_deg: e.longitude_deg(),
                place: format!("{} ({code})", e.place()),
            }
        }
    };
    sun_algos::Site::new(s.lat_deg, s.lon_deg).map_err(|e| format!("site: {e}"))?;
    Ok(s)
}

/// One option in the help.
#[derive(Debug, Clone)]
pub struct Opt {
    /// As the user types it: `--lat DEG`, `--faults`.
    pub flag: &'static str,
    /// What it does.
    pub help: String,
    /// Its value when not given (`off` for a flag).
    pub default: String,
}

/// An option for the help: `flag`, what it does, its default.
pub fn opt(flag: &'static str, help: impl Into<String>, default: impl Into<String>) -> Opt {
    Opt {
        flag,
        help: help.into(),
        default: default.into(),
    }
}

/// A tool's help text.
#[derive(Debug, Clone)]
pub struct Help {
    /// The program name.
    pub tool: &'static str,
    /// The synopsis after the name (`[--lat DEG --lon DEG] …`).
    pub synopsis: &'static str,
    /// What the tool does (wrapped as written).
    pub about: &'static str,
    /// Every option but `-h/--help`, which is added.
    pub options: Vec<Opt>,
    /// List the algorithms of `--algorithm` with their validity years.
    pub algorithms: bool,
    /// A closing paragraph (wrapped as written), may be empty.
    pub notes: &'static str,
}

/// The words of `text`, a bracketed group (`[--lat DEG --lon DEG]`,
/// `[default: 11.9683 (Kano)]`) counting as one word.
fn words(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut depth = 0usize;
    for c in text.chars() {
        match c {
            '[' => depth += 1,
            ']' => depth = depth.saturating_sub(1),
            _ => {}
        }
        if c.is_whitespace() && depth == 0 {
            if !word.is_empty() {
                out.push(std::mem::take(&mut word));
            }
        } else if c.is_whitespace() {
            // Inside brackets: one space for any run of blanks.
            if !word.ends_with(' ') {
                word.push(' ');
            }
        } else {
            word.push(c);
        }
    }
    if !word.is_empty() {
        out.push(word);
    }
    out
}

/// Appends `text` to `s` wrapped at [`HELP_WIDTH`] (between [`words`]): the
/// first line goes on from column `col`, the others start with `indent`
/// spaces.
fn wrap_into(s: &mut String, text: &str, mut col: usize, indent: usize) {
    let mut first = true;
    for word in words(text) {
        let n = word.chars().count();
        if !first && col + 1 + n > HELP_WIDTH {
            s.push('\n');
            s.push_str(&" ".repeat(indent));
            col = indent;
        } else if !first {
            s.push(' ');
            col += 1;
        }
        s.push_str(&word);
        col += n;
        first = false;
    }
    s.push('\n');
}

impl Help {
    /// The help as printed by `--help`.
    pub fn render(&self) -> String {
        let mut s = String::new();
        let head = format!("usage: {} ", self.tool);
        s.push_str(&head);
        wrap_into(&mut s, self.synopsis, head.len(), head.len());
        if !self.about.is_empty() {
            s.push('\n');
            s.push_str(self.about.trim_end());
            s.push('\n');
        }
        s.push_str("\noptions:\n");
        let help = opt("-h, --help", "print this help on stdout and exit", "");
        let width = self
            .options
            .iter()
            .chain(std::iter::once(&help))
            .map(|o| o.flag.len())
            .max()
            .unwrap_or(0)
            + 4;
        for o in self.options.iter().chain(std::iter::once(&help)) {
            let _ = write!(s, "  {:<w$}", o.flag, w = width - 2);
            let text = if o.default.is_empty() {
                o.help.clone()
            } else {
                format!("{} [default: {}]", o.help, o.default)
            };
            wrap_into(&mut s, &text, width, width);
        }
        if self.algorithms {
            s.push_str("\nalgorithms (--algorithm NAME) and the years each is valid for:\n");
            s.push_str(&algorithm_table());
        }
        if !self.notes.is_empty() {
            s.push('\n');
            s.push_str(self.notes.trim_end());
            s.push('\n');
        }
        s
    }
}

/// Every algorithm of `Algorithm::ALL` with its validity years, one a line.
pub fn algorithm_table() -> String {
    let width = Algorithm::ALL
        .iter()
        .map(|a| a.name().len())
        .max()
        .unwrap_or(0);
    let mut s = String::new();
    for a in Algorithm::ALL {
        let (lo, hi) = a.validity_years();
        let _ = writeln!(s, "  {:<width$}  {lo} to {hi}", a.name());
    }
    s
}
