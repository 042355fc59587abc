//! `monitor --modbus` (`examples/monitor_support/modbus_client.rs`,
//! `sunspec_client.rs`) against the repository's own Modbus RTU server:
//! the `suntracker-modbus` crate's receiver, server and SunSpec map over the
//! simulated tracker its tests use (`modbus/tests/common/mod.rs`), served on
//! the master side of a pseudo-terminal whose slave side the client opens by
//! its path. The server can answer from another address (a silent bus),
//! spoil the CRC of chosen replies, or leave model 305 out.

#[path = "../../modbus/tests/common/mod.rs"]
mod demo;

use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::monitor::{self, modbus_client, sunspec_client};
use super::{run, temp};
use modbus_client::{Client, Error};
use serialport::{SerialPort, TTYPort};
use sunspec_client::{Model, PollError};
use suntracker_modbus::crc::crc16;
use suntracker_modbus::rtu::{Push, RtuReceiver, RtuTiming};
use suntracker_modbus::sunspec::{m1, m305, m601, m64201, SunSpecMap, BASE_ADDR, SUNS_MARKER};
use suntracker_modbus::{Exception, Server};

const BAUD: u32 = 19_200;

/// How the test server behaves.
#[derive(Clone, Copy)]
struct Serve {
    /// The server's address.
    address: u8,
    /// Model 305 in the map.
    gps: bool,
    /// Spoil the CRC of every reply whose number (from 1) is a multiple
    /// of this (0: none).
    bad_crc_every: usize,
    /// Answer every request whose number (from 1) is a multiple of this
    /// with exception 06, server device busy (0: none).
    busy_every: usize,
}

impl Default for Serve {
    fn default() -> Self {
        Self {
            address: 1,
            gps: true,
            bad_crc_every: 0,
            busy_every: 0,
        }
    }
}

/// A running server: the path of the client's side; stops when dropped.
struct Running {
    path: String,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
    _slave: TTYPort,
}

impl Drop for Running {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// Serves the SunSpec map of the demo tracker on a new pseudo-terminal.
fn serve(how: Serve) -> Running {
    let (mut master, slave) = TTYPort::pair().expect("a pseudo-terminal pair (openpty)");
    master
        .set_timeout(Duration::from_millis(1))
        .expect("timeout");
    let path = slave.name().expect("slave path");
    let stop = Arc::new(AtomicBool::new(false));
    let halt = stop.clone();
    let thread = std::thread::spawn(move || {
        let start = Instant::now();
        let micros = || start.elapsed().as_micros() as u32;
        let mut receiver = RtuReceiver::new(RtuTiming::from_baud_us(BAUD));
        let server = Server {
            address: how.address,
            writes_enabled: false,
        };
        let mut map = SunSpecMap::new(demo::Demo::new(how.address, how.gps), how.gps);
        let (mut buf, mut out) = ([0_u8; 256], [0_u8; 256]);
        let mut replies = 0;
        let mut reply = |frame: &[u8], master: &mut TTYPort| {
            if let Some(mut len) = server.handle(frame, &mut map, &mut out) {
                replies += 1;
                if how.busy_every != 0 && replies % how.busy_every == 0 {
                    out[1] |= 0x80;
                    out[2] = Exception::ServerDeviceBusy as u8;
                    let crc = crc16(&out[..3]).to_le_bytes();
                    out[3..5].copy_from_slice(&crc);
                    len = 5;
                }
                if how.bad_crc_every != 0 && replies % how.bad_crc_every == 0 {
                    out[len - 1] ^= 0x5A;
                }
                let _ = master.write_all(&out[..len]);
            }
        };
        while !halt.load(Ordering::Relaxed) {
            if let Ok(n @ 1..) = master.read(&mut buf) {
                let t = micros();
                for &b in &buf[..n] {
                    if receiver.push(b, t) == Push::FrameWaiting {
                        if let Some(frame) = receiver.poll(t) {
                            reply(frame, &mut master);
                        }
                        receiver.push(b, t);
                    }
                }
            }
            if let Some(frame) = receiver.poll(micros()) {
                reply(frame, &mut master);
            }
        }
    });
    Running {
        path,
        stop,
        thread: Some(thread),
        _slave: slave,
    }
}

fn client(path: &str, address: u8) -> Client {
    let port = modbus_client::open(path, BAUD, serialport::Parity::Even).expect("open");
    Client::new(port, address, BAUD, Duration::from_millis(300))
}

/// A server with or without model 305, a client of it and the map found.
fn found(gps: bool) -> (Running, Client, sunspec_client::Map) {
    let s = serve(Serve {
        gps,
        ..Serve::default()
    });
    let mut c = client(&s.path, 1);
    let map = sunspec_client::discover(&mut c).expect("discover");
    (s, c, map)
}

/// The map's own addresses, from the server's crate.
fn expected_models(gps: bool) -> (Vec<Model>, u16) {
    let map = SunSpecMap::new(demo::Demo::new(1, gps), gps);
    let mut v = vec![
        Model {
            id: m1::ID,
            addr: map.common_addr(),
            len: m1::LEN,
        },
        Model {
            id: m601::ID,
            addr: map.tracker_addr(),
            len: m601::LEN,
        },
    ];
    if let Some(addr) = map.gps_addr() {
        v.push(Model {
            id: m305::ID,
            addr,
            len: m305::LEN,
        });
    }
    v.push(Model {
        id: m64201::ID,
        addr: map.vendor_addr(),
        len: m64201::LEN,
    });
    (v, map.end_addr())
}

/// The request frame of the application protocol's read (V1.1b3 §6.3)
/// with the serial line spec's CRC (V1.02 §6.2.2): ten registers from 0 at
/// server 1 is `01 03 00 00 00 0A C5 CD`; the spec's own CRC example, the
/// frame `02 07`, carries `41 12`.
#[test]
fn the_request_frame_carries_the_specified_crc() {
    assert_eq!(
        modbus_client::read_request(1, 0, 10),
        [0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD]
    );
    let reply = [0x02, 0x07, 0x41, 0x12];
    // A frame that ends in its right CRC is not a CRC error.
    assert!(!matches!(
        modbus_client::parse_read_reply(&reply, 2, 1),
        Err(Error::Crc { .. })
    ));
}

#[test]
fn the_chain_is_walked_with_and_without_the_gps_model() {
    for gps in [true, false] {
        let (_server, mut c, map) = found(gps);
        let (models, end) = expected_models(gps);
        assert_eq!(map.base, BASE_ADDR);
        assert_eq!(map.models, models, "gps {gps}");
        assert_eq!(map.end, end);
        assert_eq!(map.find(m305::ID).is_some(), gps);
        // Model 1's identity.
        let id = sunspec_client::identity(&mut c, &map).expect("model 1");
        assert_eq!(
            id,
            Some(("dual-axis ATmega2560".to_string(), "0.1.0".to_string()))
        );
    }
}

#[test]
fn model_601_and_the_vendor_model_are_decoded() {
    for gps in [true, false] {
        let (_server, mut c, map) = found(gps);
        let r = sunspec_client::poll(&mut c, &map, 0).expect("poll");
        // modbus/tests/common: 2026-03-20 12:34:56, target 77.34 / 180.50,
        // position 77.30 / 180.41, tracking (8), faults 0x8000_0005 and Flt2 0x0001, the fix
        // at 12.0022 N 8.5919 E.
        assert_eq!(r.utc.as_deref(), Some("2026-03-20T12:34:56Z"));
        assert_eq!(r.target_deg, Some(("77.34".into(), "180.50".into())));
        assert_eq!(r.position_deg, Some(("77.30".into(), "180.41".into())));
        assert_eq!(r.mode, "tracking");
        assert_eq!(
            r.faults,
            [
                "timeout_inclinometer",
                "timeout_encoder_c",
                "supply_reading",
                "irradiance_reading"
            ]
        );
        let site = gps.then(|| ("12.0022".to_string(), "8.5919".to_string()));
        assert_eq!(r.site_deg, site);
        let line = r.line();
        let want_site = if gps {
            " lat=12.0022 lon=8.5919 site=gps"
        } else {
            ""
        };
        assert_eq!(
            line,
            format!(
                "status mode=tracking utc=2026-03-20T12:34:56Z{want_site} \
faults=timeout_inclinometer,timeout_encoder_c,supply_reading,irradiance_reading target_el=77.34 target_az=180.50 \
el=77.30 az=180.41"
            )
        );
    }
}

/// 601's local date and time back to UTC with the tracker's offset,
/// `site.utc_offset_h` (worked by hand: 12:34:56 local at UTC+5:45 is
/// 06:49:56 UTC; 21:30 on 19 March at UTC−9:30 is 07:00 on 20 March UTC,
/// and 00:10 on 1 January 2027 at UTC+14 is 10:10 on 31 December 2026).
#[test]
fn the_local_time_is_turned_back_to_utc_by_the_offset() {
    let (_server, mut c, map) = found(false);
    let nepal_s = suntracker::sunspec::utc_offset_s(5.75);
    assert_eq!(nepal_s, 20_700);
    let r = sunspec_client::poll(&mut c, &map, nepal_s).expect("poll");
    assert_eq!(r.utc.as_deref(), Some("2026-03-20T06:49:56Z"));
    let regs = |s: &str| -> Vec<u16> {
        let b = s.as_bytes();
        b.chunks(2)
            .map(|p| u16::from(p[0]) << 8 | u16::from(*p.get(1).unwrap_or(&0)))
            .collect()
    };
    let marquesas_s = suntracker::sunspec::utc_offset_s(-9.5);
    assert_eq!(
        sunspec_client::utc_of_local(&regs("20260319\0\0"), &regs("213000"), marquesas_s)
            .as_deref(),
        Some("2026-03-20T07:00:00Z")
    );
    assert_eq!(
        sunspec_client::utc_of_local(&regs("20270101\0\0"), &regs("001000"), 14 * 3600).as_deref(),
        Some("2026-12-31T10:10:00Z")
    );
    // Not set (NUL), or not a date: none.
    assert_eq!(sunspec_client::utc_of_local(&[0; 5], &[0; 3], 0), None);
    assert_eq!(
        sunspec_client::utc_of_local(&regs("20260230\0\0"), &regs("120000"), 0),
        None
    );
}

/// The names come from the core crate: every mode code and fault bit.
#[test]
fn modes_and_faults_are_named_by_the_core_crate() {
    assert_eq!(sunspec_client::mode_name(2), "wind_stow");
    assert_eq!(sunspec_client::mode_name(13), "overcast");
    assert_eq!(sunspec_client::mode_name(99), "code_99");
    assert_eq!(
        sunspec_client::fault_names(1 << 12 | 1 << 30 | 1 << 32),
        ["gps_lost", "move_timeout_a", "irradiance_reading"]
    );
    // Every fault number (0 to 32) named, a bit no fault has by number.
    let names = sunspec_client::fault_names((1 << 33) - 1);
    assert_eq!(names.len(), 33);
    assert!(names
        .iter()
        .all(|n| !n.is_empty() && !n.starts_with("bit_")));
    assert_eq!(sunspec_client::fault_names(1 << 40), ["bit_40"]);
}

#[test]
fn an_exception_is_typed_and_named() {
    let s = serve(Serve::default());
    let mut c = client(&s.path, 1);
    let e = c
        .read_holding(BASE_ADDR + 500, 2)
        .expect_err("outside the map");
    assert_eq!(
        e,
        Error::Exception {
            function: 0x03,
            code: Exception::IllegalDataAddress as u8
        }
    );
    assert_eq!(
        e.to_string(),
        "exception 02 (illegal data address) to function 03"
    );
    // The next request is answered.
    assert_eq!(c.read_holding(BASE_ADDR, 2), Ok(SUNS_MARKER.to_vec()));
}

#[test]
fn a_silent_server_is_a_time_out() {
    let s = serve(Serve {
        address: 7,
        ..Serve::default()
    });
    let mut c = client(&s.path, 1);
    let t = Instant::now();
    assert_eq!(c.read_holding(BASE_ADDR, 2), Err(Error::Timeout { got: 0 }));
    assert!(t.elapsed() >= Duration::from_millis(300));
    assert!(matches!(
        sunspec_client::discover(&mut c),
        Err(PollError::Modbus(Error::Timeout { .. }))
    ));
}

#[test]
fn a_reply_with_a_bad_crc_is_rejected() {
    // Every other reply spoilt: the second.
    let s = serve(Serve {
        bad_crc_every: 2,
        ..Serve::default()
    });
    let mut c = client(&s.path, 1);
    assert_eq!(c.read_holding(BASE_ADDR, 2), Ok(SUNS_MARKER.to_vec()));
    let e = c.read_holding(BASE_ADDR, 2).expect_err("spoilt");
    assert!(matches!(e, Error::Crc { .. }), "{e:?}");
    assert!(e.to_string().starts_with("CRC error"), "{e}");
    assert_eq!(c.read_holding(BASE_ADDR, 2), Ok(SUNS_MARKER.to_vec()));
}

/// A `--modbus` session of the tool with address 1 on `s`: `--every-s`,
/// `--seconds` and `--reply-timeout` as given, then `more` arguments.
fn session(
    s: &Running,
    (every, seconds, timeout): (&str, &str, &str),
    more: &[&str],
) -> super::Outcome {
    let mut args = vec![
        "--modbus",
        &s.path,
        "--address",
        "1",
        "--every-s",
        every,
        "--seconds",
        seconds,
        "--reply-timeout",
        timeout,
    ];
    args.extend_from_slice(more);
    run(&args)
}

/// A session: a status line per answered poll, the spoilt replies counted
/// and the polls going on after them, a CSV row per poll in tracking mode
/// (zenith 90° − the target's elevation, the position), a figure; the
/// session's stdout read back as a log file gives the same rows.
#[test]
fn a_session_polls_on_after_missed_replies_into_csv_and_svg() {
    // The map found in 7 requests, a poll takes 3: the 11th reply, 21st,
    // ... spoilt.
    let s = serve(Serve {
        bad_crc_every: 11,
        ..Serve::default()
    });
    let (csv, svg) = (temp("session.csv"), temp("session.svg"));
    let o = session(&s, ("0.2", "2", "0.3"), &["--csv", &csv, "--svg", &svg]);
    assert_eq!(o.code, 0, "{}\n{}", o.out, o.err);
    let polls: Vec<&str> = o
        .out
        .lines()
        .filter(|l| l.starts_with("status mode=tracking"))
        .collect();
    assert!(polls.len() >= 4, "{}", o.out);
    assert!(
        o.out
            .lines()
            .any(|l| l.starts_with("monitor: modbus: SunS at 40000, model 1 at 40002")),
        "{}",
        o.out
    );
    // Missed polls named on stderr, counted in the summary.
    assert!(o.err.contains("CRC error"), "{}", o.err);
    let summary = o
        .out
        .lines()
        .find(|l| l.starts_with("monitor: modbus: ") && l.contains(" polls: "))
        .expect("poll summary");
    assert!(
        summary.contains(&format!("{} answered", polls.len())),
        "{summary}"
    );
    assert!(!summary.contains(", 0 CRC errors"), "{summary}");
    assert!(
        o.out.contains("board dual-axis ATmega2560 (0.1.0)"),
        "{}",
        o.out
    );
    assert!(
        o.out
            .contains("active faults timeout_inclinometer,timeout_encoder_c,supply_reading,irradiance_reading"),
        "{}",
        o.out
    );
    let mut r = csv::Reader::from_path(&csv).expect("csv");
    assert_eq!(
        r.headers().expect("header").iter().collect::<Vec<_>>(),
        monitor::CSV_HEADER
    );
    let rows: Vec<csv::StringRecord> = r.records().map(|x| x.expect("row")).collect();
    assert_eq!(rows.len(), polls.len());
    for row in &rows {
        assert_eq!(
            row.iter().collect::<Vec<_>>(),
            [
                "2026-03-20T12:34:56Z",
                "12.66",
                "180.50",
                "",
                "",
                "",
                "tracking",
                "timeout_inclinometer;timeout_encoder_c;supply_reading;irradiance_reading",
                "77.30",
                "180.41"
            ]
        );
    }
    let picture = std::fs::read_to_string(&svg).expect("svg");
    assert!(picture.contains("panel elevation (ElPos"), "legend");
    assert!(
        picture.contains(&format!("{} polls in tracking mode", rows.len())),
        "title"
    );
    // The session's output is a log the monitor reads back.
    let log = temp("session.log");
    std::fs::write(&log, &o.out).expect("log");
    let again = temp("again.csv");
    let o2 = run(&["--file", &log, "--csv", &again, "--quiet"]);
    assert_eq!(o2.code, 0, "{}", o2.err);
    assert_eq!(
        std::fs::read_to_string(&again).expect("csv"),
        std::fs::read_to_string(&csv).expect("csv")
    );
    for f in [csv, svg, log, again] {
        let _ = std::fs::remove_file(f);
    }
}

/// An exception in a session is named and counted, and the map is looked
/// for again at the next poll.
#[test]
fn a_session_finds_the_map_again_after_an_exception() {
    // The map found in 7 requests, a poll takes 3: the 12th reply (the
    // second poll's vendor model) is an exception, and so on.
    let s = serve(Serve {
        busy_every: 12,
        ..Serve::default()
    });
    let o = session(&s, ("0.2", "1.5", "0.3"), &[]);
    assert_eq!(o.code, 0, "{}\n{}", o.out, o.err);
    assert!(
        o.err
            .contains("exception 06 (server device busy) to function 03"),
        "{}",
        o.err
    );
    let found = o
        .out
        .lines()
        .filter(|l| l.starts_with("monitor: modbus: SunS at 40000"))
        .count();
    assert!(found >= 2, "{}", o.out);
    let polls = o.out.lines().filter(|l| l.starts_with("status ")).count();
    assert!(polls >= 3, "{}", o.out);
    assert!(!o.out.contains(" 0 exceptions"), "{}", o.out);
}

#[test]
fn a_session_without_any_reply_exits_1() {
    let s = serve(Serve {
        address: 9,
        ..Serve::default()
    });
    let o = session(&s, ("0.3", "1", "0.2"), &[]);
    assert_eq!(o.code, 1, "{}\n{}", o.out, o.err);
    assert!(o.err.contains("time-out: no reply"), "{}", o.err);
    assert!(o.out.contains(" polls: 0 answered, "), "{}", o.out);
}

#[test]
fn modbus_usage_errors_are_named_with_exit_2() {
    let cases: [(&[&str], &str); 7] = [
        (&["--modbus", "/dev/ttyUSB0"], "--address"),
        (
            &["--file", "x.log", "--address", "1"],
            "--address needs --modbus",
        ),
        (
            &["--port", "/dev/ttyUSB0", "--every-s", "5"],
            "--every-s needs --modbus",
        ),
        (
            &[
                "--modbus",
                "/dev/ttyUSB0",
                "--address",
                "1",
                "--parity",
                "mark",
            ],
            "--parity",
        ),
        (&["--modbus", "/dev/ttyUSB0", "--address", "0"], "--address"),
        (
            &[
                "--modbus",
                "/dev/ttyUSB0",
                "--address",
                "1",
                "--svg",
                "x.svg",
            ],
            "--svg with --modbus needs --seconds",
        ),
        (
            &["--modbus", "/dev/ttyUSB0", "--port", "/dev/ttyUSB1"],
            "conflicts",
        ),
    ];
    for (args, named) in cases {
        let o = run(args);
        assert_eq!(o.code, 2, "{args:?}");
        assert!(o.err.contains(named), "{args:?}: {}", o.err);
        assert!(o.out.is_empty(), "{args:?}");
    }
}

/// The book quotes `monitor --help` as printed (docs/src/monitor.md).
#[test]
fn the_book_quotes_the_help_as_printed() {
    let book = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/src/monitor.md"))
        .expect("docs/src/monitor.md");
    let help = run(&["--help"]).out;
    assert!(
        book.contains(help.trim_end()),
        "docs/src/monitor.md does not quote `monitor --help` as printed:\n{help}"
    );
}
