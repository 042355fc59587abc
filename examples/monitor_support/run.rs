//! The `monitor` tool: arguments, the source of the lines (a file, standard
//! input, the serial port, or the polls of a Modbus session), the
//! pass-through, the CSV, the figure and the summary. `examples/monitor.rs` calls [`run`]; so does
//! `tests/monitor_cli.rs`.

use std::fs::File;
use std::io::{BufRead, BufReader, Write};

#[path = "board_log.rs"]
pub mod board_log;
#[path = "../common/cli.rs"]
pub mod cli;
#[path = "modbus_client.rs"]
pub mod modbus_client;
#[path = "port.rs"]
pub mod port;
#[path = "sunspec_client.rs"]
pub mod sunspec_client;
#[path = "svg.rs"]
pub mod svg;

use board_log::{Line, Monitor, Row};
use cli::Parsed;

/// The program name in messages.
pub const TOOL: &str = "monitor";

/// Baud rate of every image's log and console UART.
pub const DEFAULT_BAUD: u32 = 115_200;
/// Default of `--settle`, seconds: longer than the bootloader waits after
/// the auto-reset (see `port.rs`).
pub const DEFAULT_SETTLE_S: f64 = 2.0;
/// Default of `--reply-timeout`, seconds.
pub const DEFAULT_REPLY_TIMEOUT_S: f64 = 2.0;
/// Default of `--reply-timeout` with `--modbus`, seconds.
pub const DEFAULT_MODBUS_REPLY_TIMEOUT_S: f64 = 1.0;
/// Default of `--baud` with `--modbus` (the firmware's `modbus.baud`).
pub const DEFAULT_MODBUS_BAUD: u32 = 19_200;
/// Default of `--every-s`, seconds.
pub const DEFAULT_EVERY_S: f64 = 10.0;

/// The CSV header of `--csv`.
pub const CSV_HEADER: [&str; 10] = [
    "utc",
    "zenith_deg",
    "azimuth_deg",
    "c_deg",
    "a_deg",
    "panel_mv",
    "mode",
    "faults",
    "el_deg",
    "az_deg",
];

/// Where the lines come from.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// A log file; `-` is standard input.
    File(String),
    /// The board's serial port.
    Port(port::Session),
    /// The tracker's Modbus RTU server.
    Modbus(sunspec_client::Session),
}

/// Parsed command line.
#[derive(Debug, Clone, PartialEq)]
pub struct Args {
    pub source: Source,
    pub csv: Option<String>,
    pub svg: Option<String>,
    /// Do not echo the board's lines (replies to `--send` still show).
    pub quiet: bool,
}

/// The text of `--help`.
pub fn help() -> cli::Help {
    use cli::opt;
    cli::Help {
        tool: TOOL,
        synopsis:
            "(--file LOG | --port DEVICE [--baud N] [--send LINE]... [--seconds S] [--settle S] \
[--reply-timeout S] | --modbus DEVICE --address N [--baud N] [--parity P] [--every-s S] \
[--utc-offset-h H] [--seconds S] [--reply-timeout S]) [--csv OUT.csv] [--svg OUT.svg] [--quiet]",
        about: "\
Reads the tracker's serial log (the line format of src/log.rs that every image writes: boot, time,
site, setpoint, mode, fault, day_energy, clock jump, status and the console's ok/error replies)
from the board's serial port or from a file, echoes every line to stdout (lines it does not know
are passed through), follows the mode and the active faults, and writes the set-points as CSV and
the day as an SVG figure. With --send it types lines into the board's console and shows the
replies. With --modbus it reads the tracker's Modbus RTU server instead, as a SunSpec client does
(the SunS marker, the model chain; models 601, 305 and the vendor model 64201 polled), and prints
each poll as a status line: mode, time, site, faults, target and position.",
        options: vec![
            opt(
                "--file LOG",
                "read a recorded log (- for standard input)",
                "",
            ),
            opt(
                "--port DEVICE",
                "read the board's serial port (/dev/ttyUSB0, /dev/ttyACM0)",
                "",
            ),
            opt(
                "--modbus DEVICE",
                "read the tracker's Modbus RTU server on this serial port (an RS-485 adapter)",
                "",
            ),
            opt(
                "--address N",
                "with --modbus: the tracker's Modbus address, 1 to 247",
                "",
            ),
            opt(
                "--baud N",
                "baud rate of --port (8N1) or --modbus",
                "115200 with --port, 19200 with --modbus",
            ),
            opt(
                "--parity P",
                "with --modbus: even, odd or none (two stop bits)",
                "even",
            ),
            opt("--every-s S", "with --modbus: seconds between polls", "10"),
            opt(
                "--utc-offset-h H",
                "with --modbus: the tracker's site.utc_offset_h (-12 to 14): model 601 gives \
local time, the status line UTC",
                "0",
            ),
            opt(
                "--send LINE",
                "with --port: write LINE and a newline to the board's console and wait for its \
replies (lines starting with ok or error); repeat for several lines, sent in order",
                "",
            ),
            opt(
                "--seconds S",
                "with --port or --modbus: stop S seconds after opening the port (a --modbus run \
without it polls until Ctrl-C)",
                "after the replies with --send, else when the port closes",
            ),
            opt(
                "--settle S",
                "with --send: wait up to S seconds for the board's boot line before the first \
line (opening the port resets an Arduino)",
                "2",
            ),
            opt(
                "--reply-timeout S",
                "with --send: how long to wait for the first reply to each line; with --modbus: \
for each reply",
                "2 with --send, 1 with --modbus",
            ),
            opt(
                "--csv OUT.csv",
                "write one row per set-point: utc, zenith_deg, azimuth_deg, c_deg, a_deg, \
panel_mv (empty when not logged), the mode in force, the active faults (;-separated), el_deg, \
az_deg (where the panel points: --modbus only); rows are written as they arrive; with --modbus a \
row per poll in tracking mode (zenith and azimuth of 601's target, no c and a)",
                "",
            ),
            opt(
                "--svg OUT.svg",
                "draw the log over UTC time: sun elevation and azimuth, commanded c and a (with \
--modbus: the panel's elevation and azimuth), mode band, fault rows, legend; written at the end \
(with --port, give --seconds or --send; with --modbus, --seconds)",
                "",
            ),
            opt(
                "--quiet",
                "do not echo the board's lines; sent lines, replies and the summary still show",
                "off",
            ),
        ],
        algorithms: false,
        notes: "\
stdout: every line read, as read; `> LINE` for each line sent; with --modbus `monitor: modbus: ...`
where the map was found and a status line per poll; at the end `monitor: ...` summary lines and
`monitor: wrote FILE` for each output. stderr: `monitor: ...` for an error, for each --send line
that got no reply or an error reply, and for each missed poll (a time-out, a CRC error, an exception
by its code and name). Exit status: 0 done; 1 a --send line got no reply or an error reply, or no
poll was answered; 2 a usage error, an input that cannot be opened or read, an output that cannot
be written. Ctrl-C ends a --port or --modbus run at once: the CSV has every row up to then, no
figure is drawn.",
    }
}

/// A positive number of seconds.
fn secs(p: &mut cli::Parser, opt: &str) -> Result<f64, String> {
    let v = cli::number(p, opt)?;
    if (0.0..=1e6).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{opt} {v}: want 0 to 1000000 seconds"))
    }
}

/// Parses the arguments (without the program name).
pub fn parse(argv: &[String]) -> Result<Parsed<Args>, String> {
    use cli::Long;
    let (mut file, mut path, mut modbus) = (None, None, None);
    let (mut baud, mut seconds, mut settle, mut reply) = (None, None, None, None);
    let (mut address, mut parity, mut every, mut offset_h) = (None, None, None, None);
    let mut send: Vec<String> = Vec::new();
    let (mut csv, mut svg, mut quiet) = (None, None, false);
    let mut p = cli::parser(argv);
    while let Some(arg) = p.next().map_err(cli::error)? {
        match arg {
            cli::Short('h') | Long("help") => return Ok(Parsed::Help),
            Long("file") => file = Some(cli::text(&mut p, "--file")?),
            Long("port") => path = Some(cli::text(&mut p, "--port")?),
            Long("modbus") => modbus = Some(cli::text(&mut p, "--modbus")?),
            Long("baud") => {
                baud = Some(cli::value(
                    &mut p,
                    "--baud",
                    "a rate of 50 to 4000000",
                    |v| {
                        v.parse::<u32>()
                            .ok()
                            .filter(|b| (50..=4_000_000).contains(b))
                    },
                )?)
            }
            Long("address") => {
                address = Some(cli::value(
                    &mut p,
                    "--address",
                    "an address of 1 to 247",
                    |v| v.parse::<u8>().ok().filter(|a| (1..=247).contains(a)),
                )?)
            }
            Long("parity") => {
                use serialport::Parity;
                parity = Some(cli::choice(
                    &mut p,
                    "--parity",
                    &[
                        ("even", Parity::Even),
                        ("odd", Parity::Odd),
                        ("none", Parity::None),
                    ],
                )?)
            }
            Long("every-s") => {
                let v = secs(&mut p, "--every-s")?;
                if v < 0.05 {
                    return Err(format!("--every-s {v}: want at least 0.05 seconds"));
                }
                every = Some(v);
            }
            Long("utc-offset-h") => {
                offset_h = Some(cli::value(
                    &mut p,
                    "--utc-offset-h",
                    "hours east of UTC, -12 to 14",
                    |v| v.parse::<f32>().ok().filter(|h| (-12.0..=14.0).contains(h)),
                )?)
            }
            Long("send") => {
                let line = cli::text(&mut p, "--send")?;
                if line.contains(['\n', '\r']) {
                    return Err(format!(
                        "--send {line:?}: one line each (repeat --send for more)"
                    ));
                }
                send.push(line);
            }
            Long("seconds") => seconds = Some(secs(&mut p, "--seconds")?),
            Long("settle") => settle = Some(secs(&mut p, "--settle")?),
            Long("reply-timeout") => reply = Some(secs(&mut p, "--reply-timeout")?),
            Long("csv") => csv = Some(cli::text(&mut p, "--csv")?),
            Long("svg") => svg = Some(cli::text(&mut p, "--svg")?),
            Long("quiet") => quiet = true,
            other => return Err(cli::unexpected(other)),
        }
    }
    let given = |o: &Option<String>, name: &'static str| o.as_ref().map(|_| name);
    let sources: Vec<&str> = [
        given(&file, "--file"),
        given(&path, "--port"),
        given(&modbus, "--modbus"),
    ]
    .into_iter()
    .flatten()
    .collect();
    if let [a, b, ..] = sources[..] {
        return Err(format!("{a} conflicts with {b}: read one of them"));
    }
    let first_given = |opts: &[(&'static str, bool)]| opts.iter().find(|o| o.1).map(|o| o.0);
    let modbus_only = [
        ("--address", address.is_some()),
        ("--parity", parity.is_some()),
        ("--every-s", every.is_some()),
        ("--utc-offset-h", offset_h.is_some()),
    ];
    if modbus.is_none() {
        if let Some(name) = first_given(&modbus_only) {
            return Err(format!("{name} needs --modbus"));
        }
    }
    let source = match (file, path, modbus) {
        (Some(f), _, _) => {
            let port_only = [
                ("--baud", baud.is_some()),
                ("--send", !send.is_empty()),
                ("--seconds", seconds.is_some()),
                ("--settle", settle.is_some()),
                ("--reply-timeout", reply.is_some()),
            ];
            if let Some(name) = first_given(&port_only) {
                return Err(format!("{name} needs --port (it does not apply to --file)"));
            }
            Source::File(f)
        }
        (None, Some(path), _) => {
            if send.is_empty() && (settle.is_some() || reply.is_some()) {
                let name = if settle.is_some() {
                    "--settle"
                } else {
                    "--reply-timeout"
                };
                return Err(format!("{name} needs --send"));
            }
            if svg.is_some() && send.is_empty() && seconds.is_none() {
                return Err(
                    "--svg with --port needs --seconds or --send (the figure is drawn when the run ends)"
                        .into(),
                );
            }
            Source::Port(port::Session {
                path,
                baud: baud.unwrap_or(DEFAULT_BAUD),
                send,
                seconds,
                settle_s: settle.unwrap_or(DEFAULT_SETTLE_S),
                reply_timeout_s: reply.unwrap_or(DEFAULT_REPLY_TIMEOUT_S),
            })
        }
        (None, None, Some(path)) => {
            let console_only = [("--send", !send.is_empty()), ("--settle", settle.is_some())];
            if let Some(name) = first_given(&console_only) {
                return Err(format!(
                    "{name} needs --port (it does not apply to --modbus)"
                ));
            }
            let address = address.ok_or("--modbus needs --address N (the tracker's, 1 to 247)")?;
            if svg.is_some() && seconds.is_none() {
                return Err(
                    "--svg with --modbus needs --seconds (the figure is drawn when the run ends)"
                        .into(),
                );
            }
            Source::Modbus(sunspec_client::Session {
                path,
                baud: baud.unwrap_or(DEFAULT_MODBUS_BAUD),
                parity: parity.unwrap_or(serialport::Parity::Even),
                address,
                every_s: every.unwrap_or(DEFAULT_EVERY_S),
                seconds,
                reply_timeout_s: reply.unwrap_or(DEFAULT_MODBUS_REPLY_TIMEOUT_S),
                utc_offset_s: suntracker::sunspec::utc_offset_s(offset_h.unwrap_or(0.0)),
            })
        }
        (None, None, None) => {
            return Err(
                "give --file LOG, --port DEVICE or --modbus DEVICE (--help lists the options)"
                    .into(),
            )
        }
    };
    Ok(Parsed::Run(Args {
        source,
        csv,
        svg,
        quiet,
    }))
}

/// The CSV record of a row.
pub fn csv_record(r: &Row) -> [String; 10] {
    let s = &r.setpoint;
    let text = |n: Option<&board_log::Number>| n.map(|n| n.text.clone()).unwrap_or_default();
    let position = s.position_deg.as_ref();
    [
        s.utc.text.clone(),
        s.zenith_deg.text.clone(),
        s.azimuth_deg.text.clone(),
        text(s.c_deg.as_ref()),
        text(s.a_deg.as_ref()),
        s.panel_mv.map(|v| v.to_string()).unwrap_or_default(),
        r.mode.clone().unwrap_or_default(),
        r.faults.join(";"),
        text(position.map(|p| &p.0)),
        text(position.map(|p| &p.1)),
    ]
}

/// Where the lines go: the echo, the monitor, the CSV.
struct Handler<'a> {
    out: &'a mut dyn Write,
    err: &'a mut dyn Write,
    quiet: bool,
    monitor: Monitor,
    csv: Option<(String, csv::Writer<File>)>,
    /// Rows written to the CSV so far.
    written: usize,
}

impl Handler<'_> {
    fn out_err(e: std::io::Error) -> String {
        format!("stdout: {e}")
    }

    /// Writes the settled rows not yet written.
    fn write_rows(&mut self) -> Result<(), String> {
        if let Some((path, w)) = &mut self.csv {
            let rows = self.monitor.rows.get(self.written..).unwrap_or(&[]);
            for r in rows {
                w.write_record(csv_record(r))
                    .map_err(|e| format!("--csv {path}: {e}"))?;
            }
            if !rows.is_empty() {
                // Flushed per row: a run stopped with Ctrl-C keeps them.
                w.flush().map_err(|e| format!("--csv {path}: {e}"))?;
            }
        }
        self.written = self.monitor.rows.len();
        Ok(())
    }

    fn finish(&mut self) -> Result<(), String> {
        self.monitor.finish();
        self.write_rows()
    }
}

impl port::Lines for Handler<'_> {
    fn line(&mut self, text: &str) -> Result<Line, String> {
        let line = self.monitor.feed(text);
        if !self.quiet || board_log::is_reply(&line) {
            writeln!(self.out, "{text}")
                .and_then(|()| self.out.flush())
                .map_err(Self::out_err)?;
        }
        self.write_rows()?;
        Ok(line)
    }

    fn sent(&mut self, text: &str) -> Result<(), String> {
        writeln!(self.out, "> {text}")
            .and_then(|()| self.out.flush())
            .map_err(Self::out_err)
    }
}

impl sunspec_client::Polls for Handler<'_> {
    fn line(&mut self, text: &str) -> Result<(), String> {
        port::Lines::line(self, text).map(|_| ())
    }

    fn found(
        &mut self,
        map: &sunspec_client::Map,
        identity: Option<(String, String)>,
    ) -> Result<(), String> {
        if let Some((model, version)) = identity {
            self.monitor.board = Some((model, version));
        }
        writeln!(self.out, "{TOOL}: modbus: {map}")
            .and_then(|()| self.out.flush())
            .map_err(Self::out_err)
    }

    fn missed(&mut self, at_s: f64, error: &sunspec_client::PollError) {
        // Best effort: nothing else can be done with a closed stderr.
        let _ = writeln!(self.err, "{TOOL}: modbus: poll at {at_s:.1} s: {error}");
    }
}

/// Reads `input` line by line into `h`.
fn read_all(input: &mut dyn BufRead, name: &str, h: &mut Handler) -> Result<(), String> {
    use port::Lines;
    let mut buf = Vec::new();
    loop {
        buf.clear();
        let n = input
            .read_until(b'\n', &mut buf)
            .map_err(|e| format!("--file {name}: {e}"))?;
        if n == 0 {
            return Ok(());
        }
        if buf.last() == Some(&b'\n') {
            buf.pop();
        }
        if buf.last() == Some(&b'\r') {
            buf.pop();
        }
        h.line(&String::from_utf8_lossy(&buf))?;
    }
}

/// `deg` as `11.9683 N` / `8.4261 W` from the board's text.
fn hemisphere(n: &board_log::Number, pos: char, neg: char) -> String {
    let t = n.text.strip_prefix('-').unwrap_or(&n.text);
    format!("{t} {}", if n.value < 0.0 { neg } else { pos })
}

/// The summary lines.
fn summary(m: &Monitor) -> Vec<String> {
    let c = &m.counts;
    let mut v = vec![format!(
        "{} lines: {} set-points, {} mode, {} fault, {} time, {} site, {} boot, {} day_energy, \
{} clock jump, {} status, {} ok and {} error replies, {} other ({} malformed)",
        c.lines,
        c.setpoints,
        c.modes,
        c.faults,
        c.times,
        c.sites,
        c.boots,
        c.day_energy,
        c.clock_jumps,
        c.status,
        c.replies_ok,
        c.replies_error,
        c.other,
        c.malformed
    )];
    let mut state = Vec::new();
    if let Some((board, version)) = &m.board {
        state.push(format!("board {board} ({version})"));
    }
    if let Some(s) = &m.site {
        state.push(format!(
            "site {} {} ({})",
            hemisphere(&s.lat_deg, 'N', 'S'),
            hemisphere(&s.lon_deg, 'E', 'W'),
            s.source
        ));
    }
    state.push(format!("mode {}", m.mode.as_deref().unwrap_or("unknown")));
    state.push(if m.faults.is_empty() {
        "no active fault".into()
    } else {
        format!("active faults {}", m.faults.join(","))
    });
    v.push(format!("at the end: {}", state.join(", ")));
    if let (Some(a), Some(b)) = (m.rows.first(), m.rows.last()) {
        let what = if m.rows_are_polls() {
            "polls in tracking mode"
        } else {
            "set-points"
        };
        v.push(format!(
            "{what} from {} to {}",
            a.setpoint.utc.text, b.setpoint.utc.text
        ));
    }
    for (_, vh) in &m.day_energy {
        v.push(format!("day_energy {} V\u{b7}h", vh.text));
    }
    v
}

/// The figure's title.
fn title(m: &Monitor, d: &svg::Day) -> String {
    let mut t = String::from("Tracker log");
    if let Some((board, _)) = &m.board {
        t.push_str(&format!(", board {board}"));
    }
    if let Some(s) = &m.site {
        t.push_str(&format!(
            ", site {} {}",
            hemisphere(&s.lat_deg, 'N', 'S'),
            hemisphere(&s.lon_deg, 'E', 'W')
        ));
    }
    if let Ok(day) = sun_algos::UtcTime::from_unix_seconds(d.day0_s) {
        let (y, mo, dd) = day.ymd();
        t.push_str(&format!(", {y:04}-{mo:02}-{dd:02}"));
    }
    let what = if m.rows_are_polls() {
        "polls in tracking mode"
    } else {
        "set-points"
    };
    t.push_str(&format!(", {} {what}", d.setpoints));
    t
}

/// Runs the tool with `argv` (without the program name); see the help for
/// the exit codes.
pub fn run(argv: &[String], out: &mut dyn Write, err: &mut dyn Write) -> u8 {
    let a = match parse(argv) {
        Ok(Parsed::Run(a)) => a,
        Ok(Parsed::Help) => return cli::print_help(&help(), out),
        Err(e) => return cli::usage_error(TOOL, &e, err),
    };
    match monitor(&a, out, err) {
        Ok(code) => code,
        Err((code, e)) => {
            let _ = writeln!(err, "{TOOL}: {e}");
            code
        }
    }
}

/// The run; `Err` with the exit code and the message.
fn monitor(a: &Args, out: &mut dyn Write, err: &mut dyn Write) -> Result<u8, (u8, String)> {
    let fail = |e: String| (cli::EXIT_USAGE, e);
    // The input first: nothing is written for an input that cannot be read.
    enum Input<'s> {
        File(Box<dyn BufRead>, &'s str),
        Port(&'s port::Session),
        Modbus(&'s sunspec_client::Session),
    }
    let input = match &a.source {
        Source::File(f) if f == "-" => Input::File(Box::new(BufReader::new(std::io::stdin())), f),
        Source::File(f) => Input::File(
            Box::new(BufReader::new(
                File::open(f).map_err(|e| fail(format!("--file {f}: {e}")))?,
            )),
            f,
        ),
        Source::Port(s) => Input::Port(s),
        Source::Modbus(s) => Input::Modbus(s),
    };
    let csv = match &a.csv {
        Some(path) => {
            let mut w =
                csv::Writer::from_path(path).map_err(|e| fail(format!("--csv {path}: {e}")))?;
            w.write_record(CSV_HEADER)
                .and_then(|()| w.flush().map_err(csv::Error::from))
                .map_err(|e| fail(format!("--csv {path}: {e}")))?;
            Some((path.clone(), w))
        }
        None => None,
    };
    let mut h = Handler {
        out,
        err,
        quiet: a.quiet,
        monitor: Monitor::new(),
        csv,
        written: 0,
    };
    // An error while reading ends the input; what was read is still
    // summarised and drawn, then the error is reported.
    let mut code = 0;
    let mut polled = None;
    let failed = match input {
        Input::File(mut reader, name) => read_all(reader.as_mut(), name, &mut h).err(),
        Input::Port(session) => {
            let ended = port::run(session, &mut h).map_err(fail)?;
            for (line, answer) in session.send.iter().zip(&ended.answers) {
                let note = match answer {
                    port::Answer::Ok => continue,
                    port::Answer::Refused(reply) => format!("{line:?} was refused: {reply}"),
                    port::Answer::NoReply => {
                        format!("no reply to {line:?} within {} s", session.reply_timeout_s)
                    }
                };
                // Best effort: nothing else can be done with a closed stderr.
                let _ = writeln!(h.err, "{TOOL}: {note}");
                code = 1;
            }
            ended.error
        }
        Input::Modbus(session) => {
            let (counts, error) = sunspec_client::run(session, &mut h).map_err(fail)?;
            if counts.answered == 0 {
                code = 1;
            }
            polled = Some(counts);
            error
        }
    };
    h.finish().map_err(fail)?;
    let mut report = summary(&h.monitor);
    if let Some(counts) = polled {
        report.insert(0, format!("modbus: {counts}"));
    }
    if let Some((path, _)) = &h.csv {
        report.push(format!("wrote {path} ({} rows)", h.written));
    }
    if let Some(path) = &a.svg {
        let day = svg::day(&h.monitor).ok_or_else(|| {
            fail(format!(
                "--svg {path}: the log has no line with a board time (time, setpoint, clock jump, status)"
            ))
        })?;
        let picture = svg::draw(&day, &title(&h.monitor, &day))
            .map_err(|e| fail(format!("--svg {path}: {e}")))?;
        svg::write(path, &picture).map_err(|e| fail(format!("--svg {e}")))?;
        report.push(format!("wrote {path}"));
    }
    for r in report {
        writeln!(h.out, "{TOOL}: {r}").map_err(|e| fail(Handler::out_err(e)))?;
    }
    match failed {
        Some(e) => Err(fail(e)),
        None => Ok(code),
    }
}
