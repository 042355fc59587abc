//! Reads an NMEA 0183 log (a file, or stdin) and prints one CSV line per new
//! fix, then the sentence counters:
//!
//! ```text
//! cargo run -p suntracker-drivers --example gps_log < drivers/tests/data/gps_golden_mixed.nmea
//! cargo run -p suntracker-drivers --example gps_log -- drivers/tests/data/gps_golden_mixed.nmea
//! ```
//!
//! Columns: `utc` (ISO 8601), `latitude` and `longitude` (degrees, north and
//! east positive), `altitude` (metres above mean sea level), `quality` (the
//! GGA digit), `satellites`. Unknown values are empty. An epoch with neither a
//! time nor a position is not printed.
//!
//! Arguments follow the host tools of the root package
//! (`examples/common/cli.rs`): `-h`/`--help` prints the usage on stdout and
//! exits 0; an unknown option or a second file is named on stderr with exit
//! code 2; `--` ends the options; `-` is stdin. This crate has no argument
//! parser among its dependencies and the example takes one optional path,
//! so the few lines below do the parsing.

use std::io::{Read as _, Write as _};
use std::process::ExitCode;

use drivers::gps::{GpsFix, GpsReader};

/// The help text of `--help`.
pub const HELP: &str = "\
usage: gps_log [FILE]

Reads an NMEA 0183 log and prints CSV: one line per new fix
(utc,latitude,longitude,altitude,quality,satellites; unknown values empty),
then the counters sentences=, accepted=, rejected_checksum=, rejected_other=.

arguments:
  FILE        the log to read; - for stdin [default: stdin]
  -h, --help  print this help on stdout and exit
";

/// What the command line asks for.
#[derive(Debug, PartialEq)]
pub enum Parsed {
    Help,
    /// Read this file, or stdin (`None`).
    Run(Option<String>),
}

/// Parses the arguments (without the program name).
pub fn parse(args: &[String]) -> Result<Parsed, String> {
    let mut file = None;
    let mut options = true;
    for a in args {
        match a.as_str() {
            "-h" | "--help" if options => return Ok(Parsed::Help),
            "--" if options => options = false,
            o if options && o.starts_with('-') && o != "-" => {
                let name = o.split('=').next().unwrap_or(o);
                return Err(format!("unknown option {name} (--help lists the options)"));
            }
            f => {
                if let Some(first) = &file {
                    return Err(format!("one FILE only (given {first:?} and {f:?})"));
                }
                file = Some(f.to_string());
            }
        }
    }
    Ok(Parsed::Run(file.filter(|f| f != "-")))
}

/// A `std::io::Read` (stdin or a file) as an `embedded_io::Read` (the `std`
/// feature of embedded-io 0.6 provides the error conversions but no adapter).
struct Input(Box<dyn std::io::Read>);

impl embedded_io::ErrorType for Input {
    type Error = std::io::Error;
}

impl embedded_io::Read for Input {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, std::io::Error> {
        self.0.read(buf)
    }
}

fn opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

fn csv(fix: &GpsFix) -> String {
    format!(
        "{},{},{},{},{},{}",
        opt(fix.utc),
        opt(fix.latitude_deg.map(|v| format!("{:.7}", v.deg::<f64>()))),
        opt(fix.longitude_deg.map(|v| format!("{:.7}", v.deg::<f64>()))),
        opt(fix.altitude_m.map(|v| format!("{v:.1}"))),
        fix.quality.code(),
        opt(fix.satellites),
    )
}

fn main() -> ExitCode {
    let args: Result<Vec<String>, String> = std::env::args_os()
        .skip(1)
        .map(|a| {
            a.into_string()
                .map_err(|a| format!("argument {a:?} is not UTF-8"))
        })
        .collect();
    let stdout = std::io::stdout();
    let stderr = std::io::stderr();
    let (mut out, mut err) = (stdout.lock(), stderr.lock());
    let code = match args {
        Ok(args) => cli(&args, &mut out, &mut err),
        Err(e) => {
            let _ = writeln!(err, "gps_log: {e}");
            2
        }
    };
    ExitCode::from(code)
}

/// Runs the tool with `args` (without the program name): the CSV or the
/// help to `out`, errors to `err`. Returns the exit code: 0; 2 for a usage
/// error; 1 when the log cannot be read or `out` written.
pub fn cli(args: &[String], out: &mut dyn std::io::Write, err: &mut dyn std::io::Write) -> u8 {
    let path = match parse(args) {
        Ok(Parsed::Help) => {
            // A closed stdout (`gps_log --help | head`) is not an error.
            let _ = out.write_all(HELP.as_bytes());
            return 0;
        }
        Ok(Parsed::Run(path)) => path,
        Err(e) => {
            let _ = writeln!(err, "gps_log: {e}");
            return 2;
        }
    };
    let input: Box<dyn std::io::Read> = match &path {
        Some(p) => match std::fs::File::open(p) {
            Ok(f) => Box::new(f),
            Err(e) => {
                let _ = writeln!(err, "gps_log: {p}: {e}");
                return 1;
            }
        },
        None => Box::new(std::io::stdin()),
    };
    match run(Input(input), out) {
        Ok(()) => 0,
        // A closed pipe (`gps_log < log | head`) is a normal way to stop.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => 0,
        Err(e) => {
            let _ = writeln!(err, "gps_log: {e}");
            1
        }
    }
}

fn run(input: Input, out: &mut dyn std::io::Write) -> std::io::Result<()> {
    // A log replay has no monotonic clock: time is held at 0 and staleness
    // (a matter for live receivers) is switched off.
    let mut reader = GpsReader::new(input, u32::MAX);
    let mut out = std::io::BufWriter::new(out);
    writeln!(out, "utc,latitude,longitude,altitude,quality,satellites")?;
    loop {
        match reader.poll(0) {
            Ok(Some(fix)) if fix.utc.is_some() || fix.has_position() => {
                writeln!(out, "{}", csv(&fix))?
            }
            Ok(_) => {}
            Err(drivers::gps::Error::EndOfStream) => break,
            Err(drivers::gps::Error::Comm(e)) => return Err(e),
        }
    }
    let s = reader.stats();
    writeln!(
        out,
        "sentences={} accepted={} rejected_checksum={} rejected_other={}",
        s.sentences, s.accepted, s.rejected_checksum, s.rejected_other
    )?;
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn arguments() {
        assert_eq!(parse(&[]), Ok(Parsed::Run(None)));
        assert_eq!(parse(&args("-")), Ok(Parsed::Run(None)));
        assert_eq!(
            parse(&args("a.nmea")),
            Ok(Parsed::Run(Some("a.nmea".into())))
        );
        assert_eq!(
            parse(&args("-- -x.nmea")),
            Ok(Parsed::Run(Some("-x.nmea".into())))
        );
        for help in ["-h", "--help", "a.nmea --help"] {
            assert_eq!(parse(&args(help)), Ok(Parsed::Help), "{help}");
        }
        let e = parse(&args("--bogus=1")).unwrap_err();
        assert!(e.contains("--bogus") && !e.contains('='), "{e}");
        assert!(parse(&args("a b")).unwrap_err().contains("one FILE"));
    }
}
