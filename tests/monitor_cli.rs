//! The `monitor` tool (`examples/monitor.rs`), through the same `run` its
//! `main` calls: the CSV against the set-point lines of logs recorded from
//! the emulator harness (parsed here on their own), the mode and faults a
//! set-point belongs to, the pass-through of lines it does not know, the
//! figure's axes, help and usage errors, and `--send` and `--seconds` on a
//! pseudo-terminal where the test plays the board.
//!
//! Golden logs (tests/data/monitor/):
//! - `mega_day.log`: `suntracker-emu --image mega --minutes 1440 --start
//!   2026-03-20T00:00:00Z --gale-at 2026-03-20T12:00:00Z --log FILE` (the
//!   harness's Kano GPS fix; each line after the harness's `<utc> c= a= |`);
//! - `uno_day.log`: `suntracker-emu --image uno --minutes 1440 --start
//!   2026-03-20T00:00:00Z --log FILE` (the image's lines, each set-point
//!   followed by the harness's `axes` line);
//! - `mixed.log`: written by hand, every line shape of `src/log.rs`,
//!   `src/console/`, `src/panel.rs` and `src/firmware.rs` with lines of no
//!   known shape and one cut short.

#[path = "../examples/monitor_support/run.rs"]
#[allow(dead_code)]
mod monitor;

/// `--modbus` against the repository's own Modbus server.
#[path = "monitor/modbus.rs"]
mod modbus;

use std::io::{Read, Write};
use std::time::{Duration, Instant};

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/monitor");

/// Exit code, stdout and stderr of one run.
struct Outcome {
    code: u8,
    out: String,
    err: String,
}

fn run(args: &[&str]) -> Outcome {
    let args: Vec<String> = args.iter().map(|s| s.to_string()).collect();
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let code = monitor::run(&args, &mut out, &mut err);
    Outcome {
        code,
        out: String::from_utf8(out).expect("utf8 stdout"),
        err: String::from_utf8(err).expect("utf8 stderr"),
    }
}

/// A unique temporary path.
fn temp(name: &str) -> String {
    let mut p = std::env::temp_dir();
    p.push(format!("monitor_cli_{}_{name}", std::process::id()));
    p.to_string_lossy().into_owned()
}

fn data(name: &str) -> String {
    format!("{DATA}/{name}")
}

/// A set-point line of a log, read here on its own: the words after
/// `setpoint`, split at `=`.
#[derive(Debug, Clone, PartialEq)]
struct Expected {
    utc: String,
    zenith: f64,
    azimuth: f64,
    c: f64,
    a: f64,
    panel_mv: Option<u32>,
}

/// The board's line of a log line: the emulator harness writes the Mega's
/// after `... | `.
fn board_text(line: &str) -> &str {
    match line.find(" | ") {
        Some(i) if line.starts_with("20") => &line[i + 3..],
        _ => line,
    }
}

fn expected_setpoints(log: &str) -> Vec<Expected> {
    let mut v = Vec::new();
    for line in log.lines() {
        let Some(rest) = board_text(line).strip_prefix("setpoint ") else {
            continue;
        };
        let kv: Vec<(&str, &str)> = rest
            .split_whitespace()
            .map(|w| w.split_once('=').expect("key=value"))
            .collect();
        let get = |k: &str| kv.iter().find(|p| p.0 == k).map(|p| p.1);
        let num = |k: &str| get(k).and_then(|s| s.parse::<f64>().ok());
        // A line cut short is not a set-point.
        let (Some(utc), Some(zenith), Some(azimuth), Some(c), Some(a)) = (
            get("utc").filter(|u| u.len() == 20),
            num("zenith"),
            num("azimuth"),
            num("c"),
            num("a"),
        ) else {
            continue;
        };
        v.push(Expected {
            utc: utc.to_string(),
            zenith,
            azimuth,
            c,
            a,
            panel_mv: get("panel_mv").map(|p| p.parse().expect("panel_mv")),
        });
    }
    v
}

/// The rows of a CSV the monitor wrote: (header, records).
fn read_csv(path: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).expect("csv");
    let header = r
        .headers()
        .expect("header")
        .iter()
        .map(String::from)
        .collect();
    let rows = r
        .records()
        .map(|rec| rec.expect("record").iter().map(String::from).collect())
        .collect();
    (header, rows)
}

/// Checks that the CSV of `log` has one row per set-point line, with the
/// line's values.
fn csv_matches_log(name: &str) -> Vec<Vec<String>> {
    let log = std::fs::read_to_string(data(name)).expect("golden log");
    let want = expected_setpoints(&log);
    let csv = temp(&format!("{name}.csv"));
    let o = run(&["--file", &data(name), "--csv", &csv, "--quiet"]);
    assert_eq!(o.code, 0, "{}", o.err);
    let (header, rows) = read_csv(&csv);
    assert_eq!(
        header,
        [
            "utc",
            "zenith_deg",
            "azimuth_deg",
            "c_deg",
            "a_deg",
            "panel_mv",
            "mode",
            "faults",
            "el_deg",
            "az_deg"
        ]
    );
    assert_eq!(rows.len(), want.len(), "{name}: one row per set-point line");
    for (row, w) in rows.iter().zip(&want) {
        let num = |i: usize| row[i].parse::<f64>().expect("number");
        assert_eq!(row[0], w.utc);
        assert_eq!(
            (num(1), num(2), num(3), num(4)),
            (w.zenith, w.azimuth, w.c, w.a),
            "{name} {}",
            w.utc
        );
        assert_eq!(
            row[5],
            w.panel_mv.map(|p| p.to_string()).unwrap_or_default()
        );
    }
    assert!(
        o.out
            .contains(&format!("wrote {csv} ({} rows)", want.len())),
        "{}",
        o.out
    );
    let _ = std::fs::remove_file(&csv);
    rows
}

#[test]
fn mega_day_csv_rows_are_the_setpoint_lines() {
    let rows = csv_matches_log("mega_day.log");
    // A day at Kano (11.97 N): set-points from about sunrise to sunset.
    assert!(rows.len() > 100, "{} rows", rows.len());
    // Every image logs set-points in tracking mode only (src/firmware.rs,
    // `log_setpoint`), so every row is in tracking mode, the first of each
    // morning too (its `mode tracking` line comes after it).
    for r in &rows {
        assert_eq!(r[6], "tracking", "{r:?}");
    }
}

#[test]
fn uno_day_csv_rows_are_the_setpoint_lines() {
    let rows = csv_matches_log("uno_day.log");
    assert!(rows.len() > 100, "{} rows", rows.len());
    for r in &rows {
        assert_eq!(r[6], "tracking", "{r:?}");
    }
}

/// The mode lines and the faults active at each set-point of the Mega day,
/// from the log on its own: the gale stows the tracker, and no set-point
/// is logged between `mode wind_stow` and the next `mode tracking`.
#[test]
fn mega_day_wind_stow_has_no_setpoints() {
    let log = std::fs::read_to_string(data("mega_day.log")).expect("golden log");
    let lines: Vec<&str> = log.lines().map(board_text).collect();
    let stow = lines
        .iter()
        .position(|l| *l == "mode wind_stow")
        .expect("the gale stows the tracker");
    let back = stow
        + lines[stow..]
            .iter()
            .position(|l| *l == "mode tracking")
            .expect("tracking again after the gale");
    // The set-point before the stow and the first after it.
    let before = lines[..stow]
        .iter()
        .rev()
        .find_map(|l| l.strip_prefix("setpoint utc="))
        .expect("set-point before the gale");
    let after = lines[stow..]
        .iter()
        .find_map(|l| l.strip_prefix("setpoint utc="))
        .expect("set-point after the gale");
    let before = &before[..20];
    let after = &after[..20];
    let csv = temp("stow.csv");
    let svg = temp("stow.svg");
    let o = run(&[
        "--file",
        &data("mega_day.log"),
        "--csv",
        &csv,
        "--svg",
        &svg,
        "--quiet",
    ]);
    assert_eq!(o.code, 0, "{}", o.err);
    let (_, rows) = read_csv(&csv);
    let i = rows
        .iter()
        .position(|r| r[0] == before)
        .expect("row before");
    assert_eq!(rows[i + 1][0], after, "no row between {before} and {after}");
    // The gale: 40 Hz for 10 minutes from 12:00 (the harness's --gale-at),
    // then the wind monitor's release time.
    assert!(before < "2026-03-20T12:01:00Z" && after > "2026-03-20T12:10:00Z");
    assert!(back > stow);
    let picture = std::fs::read_to_string(&svg).expect("svg");
    for label in [
        "mode wind_stow",
        "mode tracking",
        "mode night",
        "sun elevation",
        "mega2560",
    ] {
        assert!(picture.contains(label), "{label} missing from the figure");
    }
    let _ = std::fs::remove_file(&csv);
    let _ = std::fs::remove_file(&svg);
}

/// The texts of an SVG's `<text>` elements.
fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = t.split_once('>')?.1;
            Some(body.split_once("</text>")?.0.trim().to_string())
        })
        .collect()
}

/// The degree axis reaches from the lowest plotted value less 4° to the
/// highest plus 4°, rounded out to tens; the time axis from the first time
/// in the log to the last, rounded out to whole hours; both worked out here
/// from the log's lines.
#[test]
fn figure_axes_are_scaled_from_the_data() {
    let log = std::fs::read_to_string(data("mega_day.log")).expect("golden log");
    let sp = expected_setpoints(&log);
    let values = sp
        .iter()
        .flat_map(|s| [90.0 - s.zenith, s.azimuth, s.c, s.a]);
    let lo = values.clone().fold(f64::INFINITY, f64::min);
    let hi = values.fold(f64::NEG_INFINITY, f64::max);
    let y0 = ((lo - 4.0) / 10.0).floor() * 10.0;
    let y1 = ((hi + 4.0) / 10.0).ceil() * 10.0;
    // Times: `utc=` of the time and set-point lines (hours of the day).
    let hours: Vec<f64> = log
        .lines()
        .map(board_text)
        .filter_map(|l| {
            let t = l.split(' ').find_map(|w| w.strip_prefix("utc="))?;
            let h = |r: std::ops::Range<usize>| t[r].parse::<f64>().ok();
            Some(h(11..13)? + h(14..16)? / 60.0 + h(17..19)? / 3600.0)
        })
        .collect();
    let x0 = hours.iter().copied().fold(f64::INFINITY, f64::min).floor();
    let x1 = hours
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max)
        .ceil();

    let mut m = monitor::board_log::Monitor::new();
    for l in log.lines() {
        m.feed(l);
    }
    m.finish();
    let day = monitor::svg::day(&m).expect("the log has times");
    let r = monitor::svg::ranges(&day);
    assert_eq!(r.y_deg, (y0, y1));
    assert_eq!(r.x_h, (x0, x1));
    assert_eq!(r.panel_v, None);

    // The drawn figure labels nothing outside those ranges.
    let svg = temp("axes.svg");
    let o = run(&["--file", &data("mega_day.log"), "--svg", &svg, "--quiet"]);
    assert_eq!(o.code, 0, "{}", o.err);
    let texts = svg_texts(&std::fs::read_to_string(&svg).expect("svg"));
    assert!(texts.contains(&format!("{y0:.0}")), "{texts:?}");
    assert!(texts.contains(&format!("{:02}:00", x0 as u32)), "{texts:?}");
    assert!(texts.contains(&format!("{:02}:00", x1 as u32)), "{texts:?}");
    for t in &texts {
        if let Ok(v) = t.parse::<f64>() {
            assert!((y0..=y1).contains(&v), "label {v} outside {y0}..{y1}");
        }
        if let Some((h, mm)) = t.split_once(':').filter(|_| t.len() == 5) {
            let v = h.parse::<f64>().expect("hour") + mm.parse::<f64>().expect("min") / 60.0;
            assert!((x0..=x1).contains(&v), "label {t} outside {x0}..{x1} h");
        }
    }
    let _ = std::fs::remove_file(&svg);
}

/// The panel voltage gets its own axis, from 0 V to the next whole volt
/// above the highest `panel_mv`.
#[test]
fn panel_voltage_axis() {
    let log = std::fs::read_to_string(data("mixed.log")).expect("log");
    let mut m = monitor::board_log::Monitor::new();
    for l in log.lines() {
        m.feed(l);
    }
    m.finish();
    let day = monitor::svg::day(&m).expect("times");
    // panel_mv=1200 and 1450: 1.45 V.
    assert_eq!(monitor::svg::ranges(&day).panel_v, Some((0.0, 2.0)));
    // 06:00:05 to 07:04:00, about an hour: quarter hours.
    assert_eq!(monitor::svg::ranges(&day).x_h, (6.0, 7.25));
}

/// The hand-written log: the mode and faults of each set-point follow the
/// tick order of src/firmware.rs (a set-point, then the tick's fault lines, then
/// its mode line), worked out here line by line.
#[test]
fn mode_and_faults_of_each_setpoint() {
    csv_matches_log("mixed.log");
    let csv = temp("mixed.csv");
    let o = run(&["--file", &data("mixed.log"), "--csv", &csv, "--quiet"]);
    assert_eq!(o.code, 0, "{}", o.err);
    let (_, rows) = read_csv(&csv);
    let got: Vec<(&str, &str, &str)> = rows
        .iter()
        .map(|r| (r[0].as_str(), r[6].as_str(), r[7].as_str()))
        .collect();
    assert_eq!(
        got,
        [
            // After `mode night`, followed by `mode tracking`: the same tick.
            ("2026-03-20T06:04:00Z", "tracking", ""),
            // Followed by a fault line and then a set-point: a later tick's.
            ("2026-03-20T06:08:00Z", "tracking", ""),
            // Raised before it; cleared after it, with `mode safe_stop`,
            // which cannot be its own tick's (set-points are logged in
            // tracking mode only).
            ("2026-03-20T06:12:00Z", "tracking", "deviation_c"),
            // The `ok mode=tracking ... faults=none` status reply before it.
            ("2026-03-20T06:20:00Z", "tracking", ""),
            // After a clock jump; `mode wind_stow` after it is later.
            ("2026-03-20T06:52:00Z", "tracking", ""),
            // After a reboot (no mode, faults cleared) and a raised fault,
            // followed by `mode tracking`.
            ("2026-03-20T07:04:00Z", "tracking", "gps_lost"),
        ]
    );
    // The summary counts the lines by kind and ends in the last state.
    assert!(
        o.out.contains(
            "29 lines: 6 set-points, 5 mode, 4 fault, 2 time, 1 site, 2 boot, 1 day_energy, \
1 clock jump, 1 status, 2 ok and 1 error replies, 3 other (1 malformed)"
        ),
        "{}",
        o.out
    );
    assert!(
        o.out.contains("mode tracking, active faults gps_lost"),
        "{}",
        o.out
    );
    assert!(
        o.out.contains("site 33.9249 S 18.4241 E (config)"),
        "{}",
        o.out
    );
    let _ = std::fs::remove_file(&csv);
}

/// Every line is echoed as read, the unknown and the cut-short ones too,
/// in order, before the summary.
#[test]
fn unknown_lines_are_passed_through() {
    let log = std::fs::read_to_string(data("mixed.log")).expect("log");
    let o = run(&["--file", &data("mixed.log")]);
    assert_eq!(o.code, 0, "{}", o.err);
    assert!(o.err.is_empty(), "{}", o.err);
    let echoed: Vec<&str> = o.out.lines().take(log.lines().count()).collect();
    assert_eq!(echoed, log.lines().collect::<Vec<_>>());
    for l in [
        "this line is not part of the log format",
        "axes utc=2026-03-20T06:04:00Z c=-4.7000 a=85.1200",
        "setpoint utc=2026-03-20T06:1",
    ] {
        assert!(o.out.lines().any(|x| x == l), "{l}");
    }
    // The rest is the summary.
    assert!(o
        .out
        .lines()
        .skip(log.lines().count())
        .all(|l| l.starts_with("monitor: ")));
}

/// CRLF line ends (a terminal program's capture) read like LF.
#[test]
fn crlf_lines_read_like_lf() {
    let log = std::fs::read_to_string(data("mixed.log")).expect("log");
    let crlf = temp("crlf.log");
    std::fs::write(&crlf, log.replace('\n', "\r\n")).expect("write");
    let (a, b) = (temp("lf.csv"), temp("crlf.csv"));
    assert_eq!(
        run(&["--file", &data("mixed.log"), "--csv", &a, "--quiet"]).code,
        0
    );
    assert_eq!(run(&["--file", &crlf, "--csv", &b, "--quiet"]).code, 0);
    assert_eq!(read_csv(&a), read_csv(&b));
    for f in [crlf, a, b] {
        let _ = std::fs::remove_file(f);
    }
}

#[test]
fn help_on_stdout_exit_0() {
    for flag in ["--help", "-h"] {
        let o = run(&[flag]);
        assert_eq!(o.code, 0);
        assert!(o.out.starts_with("usage: monitor "), "{}", o.out);
        for opt in [
            "--file",
            "--port",
            "--baud",
            "--send",
            "--csv",
            "--svg",
            "--seconds",
        ] {
            assert!(o.out.contains(opt), "{opt} missing from the help");
        }
        assert!(o.err.is_empty());
    }
}

#[test]
fn usage_errors_are_named_with_exit_2() {
    let file = data("mixed.log");
    let cases: [(&[&str], &str); 10] = [
        (&["--bogus"], "--bogus"),
        (&[], "--file"),
        (&["--file", &file, "--port", "/dev/null"], "--port"),
        (
            &["--file", &file, "--send", "status"],
            "--send needs --port",
        ),
        (&["--file", &file, "--baud", "9600"], "--baud needs --port"),
        (&["--port", "/dev/ttyUSB0", "--baud", "0"], "--baud"),
        (&["--port", "/dev/ttyUSB0", "--baud", "fast"], "--baud"),
        (&["--port", "/dev/ttyUSB0", "--svg", "x.svg"], "--svg"),
        (&["--port", "/dev/ttyUSB0", "--seconds", "-1"], "--seconds"),
        (&["--file"], "--file"),
    ];
    for (args, named) in cases {
        let o = run(args);
        assert_eq!(o.code, 2, "{args:?}");
        assert!(o.err.starts_with("monitor: "), "{args:?}: {}", o.err);
        assert!(o.err.contains(named), "{args:?}: {}", o.err);
        assert!(o.out.is_empty(), "{args:?}");
    }
}

#[test]
fn a_missing_file_is_an_error_and_writes_nothing() {
    let missing = temp("no_such.log");
    let csv = temp("missing.csv");
    let o = run(&["--file", &missing, "--csv", &csv]);
    assert_eq!(o.code, 2);
    assert!(
        o.err.starts_with(&format!("monitor: --file {missing}: ")),
        "{}",
        o.err
    );
    assert!(o.out.is_empty());
    assert!(!std::path::Path::new(&csv).exists());
    // A port that does not exist, likewise.
    let o = run(&["--port", &missing]);
    assert_eq!(o.code, 2);
    assert!(
        o.err.starts_with(&format!("monitor: --port {missing}: ")),
        "{}",
        o.err
    );
}

#[test]
fn a_log_without_time_cannot_be_drawn() {
    let log = temp("notime.log");
    std::fs::write(
        &log,
        "boot suntracker 0.1.0 board=uno\nmode wait_for_time\n",
    )
    .expect("write");
    let svg = temp("notime.svg");
    let o = run(&["--file", &log, "--svg", &svg]);
    assert_eq!(o.code, 2);
    assert!(
        o.err.contains("--svg") && o.err.contains("no line with a board time"),
        "{}",
        o.err
    );
    let _ = std::fs::remove_file(&log);
}

// ---------------------------------------------------------------------------
// The serial port, on a pseudo-terminal: the test holds the master side and
// plays the board, the monitor opens the slave side by its path.

use serialport::{SerialPort, TTYPort};

/// A pseudo-terminal pair: (board side, the path the monitor opens). The
/// slave handle is kept open so that the master never reads EIO.
fn pty() -> (TTYPort, TTYPort, String) {
    let (mut master, slave) = TTYPort::pair().expect("a pseudo-terminal pair (openpty)");
    master
        .set_timeout(Duration::from_millis(50))
        .expect("timeout");
    let path = slave.name().expect("slave path");
    (master, slave, path)
}

/// Reads one line from the board side, waiting up to 10 s.
fn board_reads_line(master: &mut TTYPort) -> String {
    let end = Instant::now() + Duration::from_secs(10);
    let mut line = Vec::new();
    let mut b = [0u8; 1];
    while Instant::now() < end {
        match master.read(&mut b) {
            Ok(1) if b[0] == b'\n' => return String::from_utf8(line).expect("utf8"),
            Ok(1) => line.push(b[0]),
            _ => {}
        }
    }
    panic!("the monitor sent no line (got {line:?})");
}

/// Runs the monitor on `args` in a thread.
fn spawn(args: Vec<String>) -> std::thread::JoinHandle<Outcome> {
    std::thread::spawn(move || {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        run(&a)
    })
}

#[test]
fn send_writes_the_line_and_prints_the_reply() {
    let (mut master, _slave, path) = pty();
    let h = spawn(
        [
            "--port",
            &path,
            "--send",
            "status",
            "--send",
            "set wind.stow_hz 30",
            "--settle",
            "0",
            "--reply-timeout",
            "10",
        ]
        .map(String::from)
        .to_vec(),
    );
    assert_eq!(board_reads_line(&mut master), "status");
    let status = "ok mode=tracking utc=2026-03-20T12:00:00Z time=gps lat=11.9683 lon=8.4261 \
site=gps c=12.50 a=-3.25 faults=none wind_hz=0.00";
    master
        .write_all(format!("setpoint utc=2026-03-20T12:00:00Z zenith=10.000 azimuth=180.000 c=12.50 a=-3.25\r\n{status}\r\n").as_bytes())
        .expect("write");
    assert_eq!(board_reads_line(&mut master), "set wind.stow_hz 30");
    master.write_all(b"ok wind.stow_hz=30\n").expect("write");
    let o = h.join().expect("monitor thread");
    assert_eq!(o.code, 0, "{}\n{}", o.out, o.err);
    assert!(o.err.is_empty(), "{}", o.err);
    let lines: Vec<&str> = o.out.lines().collect();
    let at = |l: &str| {
        lines
            .iter()
            .position(|x| *x == l)
            .unwrap_or_else(|| panic!("{l} missing: {lines:?}"))
    };
    // In order: the sent line, the board's lines, the next sent line, its reply.
    assert!(at("> status") < at(status));
    assert!(at(status) < at("> set wind.stow_hz 30"));
    assert!(at("> set wind.stow_hz 30") < at("ok wind.stow_hz=30"));
    assert!(lines
        .iter()
        .any(|l| l.starts_with("setpoint utc=2026-03-20T12:00:00Z")));
    // The status reply set the state.
    assert!(
        o.out.contains("mode tracking, no active fault"),
        "{}",
        o.out
    );
}

#[test]
fn an_error_reply_or_no_reply_exits_1() {
    let (mut master, _slave, path) = pty();
    let h = spawn(
        [
            "--port",
            &path,
            "--send",
            "set bogus 1",
            "--send",
            "status",
            "--settle",
            "0",
            "--reply-timeout",
            "2",
        ]
        .map(String::from)
        .to_vec(),
    );
    assert_eq!(board_reads_line(&mut master), "set bogus 1");
    master.write_all(b"error unknown key\n").expect("write");
    assert_eq!(board_reads_line(&mut master), "status");
    // The board stays silent.
    let o = h.join().expect("monitor thread");
    assert_eq!(o.code, 1, "{}\n{}", o.out, o.err);
    assert!(o.out.lines().any(|l| l == "error unknown key"), "{}", o.out);
    // Named on stderr.
    assert_eq!(
        o.err.lines().collect::<Vec<_>>(),
        [
            "monitor: \"set bogus 1\" was refused: error unknown key",
            "monitor: no reply to \"status\" within 2 s"
        ]
    );
}

/// `--seconds`: the monitor follows the port and writes the CSV rows of
/// what the board logged.
#[test]
fn seconds_follows_the_port_into_the_csv() {
    let (mut master, _slave, path) = pty();
    let csv = temp("port.csv");
    let h = spawn(
        ["--port", &path, "--seconds", "2", "--csv", &csv, "--quiet"]
            .map(String::from)
            .to_vec(),
    );
    // Give the monitor time to open the port; bytes written before that
    // wait in the pseudo-terminal's buffer anyway.
    std::thread::sleep(Duration::from_millis(200));
    let log = std::fs::read_to_string(data("mixed.log")).expect("log");
    master.write_all(log.as_bytes()).expect("write");
    let o = h.join().expect("monitor thread");
    assert_eq!(o.code, 0, "{}", o.err);
    let (_, rows) = read_csv(&csv);
    assert_eq!(rows.len(), expected_setpoints(&log).len());
    // --quiet: the replies still show, the log lines do not.
    assert!(o.out.lines().any(|l| l == "error unknown key"));
    assert!(!o.out.lines().any(|l| l == "mode night"));
    let _ = std::fs::remove_file(&csv);
}
