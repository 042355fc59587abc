//! The Modbus port (`suntracker::sunspec::ModbusPort`) on the firmware loop
//! of a host "board": simulated DS3231 at Kano from 06:00 UTC on
//! 2026-03-20, H-bridge steppers into the motor model, a millisecond clock
//! the test advances, and an RS-485 line the test writes request frames
//! into (each byte stamped with its µs) and reads the replies from.
//!
//! What is checked, each against something the port did not compute:
//! - model 601's `ElTrgt`/`AzTrgt` are the set-point the log printed
//!   (elevation = 90° − zenith) and `ElPos`/`AzPos` the motors' angles
//!   through Choi et al.'s eq. 15–17 (the test's own `normal_xyz`);
//! - with `modbus.write` 0 a write gets exception 01 and the hold is
//!   unchanged; with 1, a manual target and `GlblCtl` Manual move the
//!   motors until the panel normal points there (within one step), a target
//!   below the horizon gets exception 03 and moves nothing, Automatic
//!   tracks again, and the vendor `Stow` stows;
//! - `modbus.timeout_s` 60: a manual mode the bus set holds while the
//!   master reads, and ends 60 s after its last request;
//! - a request every 3 ms (each a read of 125 registers) delays no
//!   set-point: every set-point of the undisturbed run is logged at the same
//!   monotonic millisecond.

mod common;

use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;

use common::host_io::{Log, Uart};
use common::motor::{angle_deg, normal_xyz, stepper_axis, sun_xyz, Motor};
use sim::rtc::SimRtc;
use sim::sensors::MountSensors;
use sun_algos::UtcTime;
use suntracker::config::Config;
use suntracker::controller::ControllerOptions;
use suntracker::firmware::{AppConfig, Firmware, Platform};
use suntracker::sunspec::{ModbusLine, ModbusPort};
use suntracker_modbus::crc::crc16;
use suntracker_modbus::sunspec::Identity;

const KANO: (f32, f32) = (11.9683, 8.4261);

/// Register of model 601's ID (docs/src/modbus.md).
const M601: u16 = 40070;
/// Register of the vendor model's ID with model 305 in the map.
const M64201: u16 = 40158;
/// Register of the vendor model's ID without model 305 (the bench's map:
/// no GPS).
const VENDOR: u16 = M64201 - 38;

struct Clock {
    now_ms: u64,
    /// Anemometer pulses each tick takes.
    wind_pulses: u32,
}

impl Platform for Clock {
    fn now_ms(&mut self) -> u64 {
        self.now_ms
    }
    fn take_wind_pulses(&mut self) -> u32 {
        self.wind_pulses
    }
    fn feed_watchdog(&mut self) {}
    fn wait_for_interrupt(&mut self) {}
}

/// The RS-485 line: request bytes with their µs, replies kept.
#[derive(Default)]
struct Line {
    rx: VecDeque<(u8, u32)>,
    now_us: u32,
    sent: Vec<Vec<u8>>,
}

impl ModbusLine for Line {
    fn receive(&mut self) -> Option<(u8, u32)> {
        self.rx.pop_front()
    }
    fn now_us(&mut self) -> u32 {
        self.now_us
    }
    fn send(&mut self, frame: &[u8]) {
        self.sent.push(frame.to_vec());
    }
}

type Fw = Firmware<f32, SimRtc, Uart, common::motor::Axis, MountSensors, Log, 0>;

struct Bench {
    fw: Fw,
    port: ModbusPort,
    clock: Clock,
    line: Line,
    c: Rc<RefCell<Motor>>,
    a: Rc<RefCell<Motor>>,
    log: Log,
    start: UtcTime,
    /// (monotonic ms, line) of each log line.
    stamps: Vec<(u64, String)>,
    seen: usize,
}

const IDENTITY: Identity<'static> = Identity {
    manufacturer: "suntracker",
    model: "host",
    options: "",
    version: "0.1.0",
    serial: "1",
    controller_name: "host",
    tracker_name: "t1",
};

impl Bench {
    fn new(write: u8) -> Bench {
        Bench::with_timeout(write, 0)
    }

    fn with_timeout(write: u8, timeout_s: u32) -> Bench {
        Bench::with_config(|c| {
            c.modbus.write = write;
            c.modbus.timeout_s = timeout_s;
        })
    }

    /// Kano, writes off, no time-out, then `edit`.
    fn with_config(edit: impl FnOnce(&mut Config)) -> Bench {
        let (mut config, _): (Config, _) = common::motor::tracker_config();
        config.site.latitude_deg = KANO.0;
        config.site.longitude_deg = KANO.1;
        config.site.elevation_m = 0.0;
        edit(&mut config);
        let options = ControllerOptions::<f32> {
            feedback: suntracker::motion::FeedbackMode::OpenLoop,
            homing_chunk_deg: 0.45,
            ..Default::default()
        };
        let c = Motor::new(30.0, config.axes[0].home_deg as f64);
        let a = Motor::new(20.0, config.axes[1].home_deg as f64);
        let start = UtcTime::from_ymd_hms(2026, 3, 20, 6, 0, 0).unwrap();
        let log = Log::default();
        let fw = Firmware::new(
            AppConfig::new("host"),
            config,
            options,
            SimRtc::new(start),
            Uart::default(),
            [stepper_axis(&c), stepper_axis(&a)],
            None,
            log.clone(),
        )
        .expect("valid configuration");
        Bench {
            fw,
            port: ModbusPort::new(IDENTITY, false),
            clock: Clock {
                now_ms: 0,
                wind_pulses: 0,
            },
            line: Line::default(),
            c,
            a,
            log,
            start,
            stamps: Vec::new(),
            seen: 0,
        }
    }

    /// Runs the loop and the port until monotonic `end_ms`, one pass a
    /// millisecond; `feed` before each pass.
    fn run_until(&mut self, end_ms: u64, mut feed: impl FnMut(&mut Bench)) {
        while self.clock.now_ms < end_ms {
            let now = self.start.add_millis(self.clock.now_ms as i64).unwrap();
            self.fw.time_keeper_mut().rtc_mut().advance(now);
            self.line.now_us = (self.clock.now_ms * 1000) as u32;
            feed(self);
            self.fw.poll(&mut self.clock);
            self.port
                .poll(&mut self.fw, &mut self.line, self.clock.now_ms);
            for m in [&self.c, &self.a] {
                m.borrow_mut().settle();
            }
            let text = String::from_utf8(self.log.0.borrow().clone()).unwrap();
            let lines: Vec<&str> = text.lines().collect();
            for line in lines.iter().skip(self.seen) {
                self.stamps.push((self.clock.now_ms, line.to_string()));
            }
            self.seen = lines.len();
            self.clock.now_ms += 1;
        }
    }

    /// Queues `pdu` to address 1 with its CRC, all bytes at this µs.
    fn queue(&mut self, pdu: &[u8]) {
        let mut frame = vec![1u8];
        frame.extend_from_slice(pdu);
        let crc = crc16(&frame).to_le_bytes();
        frame.extend_from_slice(&crc);
        let t = self.line.now_us;
        self.line.rx.extend(frame.iter().map(|&b| (b, t)));
    }

    /// One request and its reply's PDU (no address, no CRC), served
    /// within 20 ms.
    fn request(&mut self, pdu: &[u8]) -> Vec<u8> {
        self.line.sent.clear();
        self.queue(pdu);
        let end = self.clock.now_ms + 20;
        self.run_until(end, |_| {});
        assert_eq!(self.line.sent.len(), 1, "one reply to {pdu:02x?}");
        let reply = self.line.sent[0].clone();
        assert_eq!(crc16(&reply), 0, "the reply's CRC");
        reply[1..reply.len() - 2].to_vec()
    }

    fn read(&mut self, start: u16, count: u16) -> Vec<u16> {
        let mut pdu = vec![3u8];
        pdu.extend_from_slice(&start.to_be_bytes());
        pdu.extend_from_slice(&count.to_be_bytes());
        let r = self.request(&pdu);
        assert_eq!(r[0], 3, "read refused: {r:02x?}");
        r[2..]
            .chunks(2)
            .map(|w| u16::from_be_bytes([w[0], w[1]]))
            .collect()
    }

    /// A write of `regs` from `start` (function 16): the exception code, or
    /// 0 when done.
    fn write(&mut self, start: u16, regs: &[u16]) -> u8 {
        let mut pdu = vec![16u8];
        pdu.extend_from_slice(&start.to_be_bytes());
        pdu.extend_from_slice(&(regs.len() as u16).to_be_bytes());
        pdu.push((regs.len() * 2) as u8);
        for r in regs {
            pdu.extend_from_slice(&r.to_be_bytes());
        }
        let r = self.request(&pdu);
        if r[0] & 0x80 != 0 {
            r[1]
        } else {
            0
        }
    }

    fn lines(&self) -> Vec<&str> {
        self.stamps.iter().map(|(_, l)| l.as_str()).collect()
    }

    fn motor_normal(&self) -> [f64; 3] {
        normal_xyz(self.c.borrow().angle_deg(), self.a.borrow().angle_deg())
    }
}

fn int32(regs: &[u16], at: usize) -> i32 {
    ((u32::from(regs[at]) << 16) | u32::from(regs[at + 1])) as i32
}

fn field(line: &str, key: &str) -> f64 {
    let k = format!("{key}=");
    let start = line.find(&k).unwrap() + k.len();
    line[start..].split(' ').next().unwrap().parse().unwrap()
}

/// 0.01° pairs of an int32 elevation, azimuth.
fn angles(regs: &[u16], at: usize) -> (f64, f64) {
    (
        f64::from(int32(regs, at)) / 100.0,
        f64::from(int32(regs, at + 2)) / 100.0,
    )
}

#[test]
fn the_map_reads_what_the_tracker_does() {
    let mut b = Bench::new(0);
    b.run_until(30 * 60_000, |_| {});
    let regs = b.read(M601, 50);
    assert_eq!(regs[0], 601);
    let sp = *b
        .lines()
        .iter()
        .rev()
        .find(|l| l.starts_with("setpoint "))
        .expect("tracking after half an hour");
    let (el, az) = angles(&regs, 36);
    assert!(
        (el - (90.0 - field(sp, "zenith"))).abs() <= 0.006,
        "{el} {sp}"
    );
    assert!((az - field(sp, "azimuth")).abs() <= 0.006, "{az} {sp}");
    // The position: the motors' normal, within the 0.01° rounding.
    let (pel, paz) = angles(&regs, 40);
    let n = b.motor_normal();
    assert!(angle_deg(sun_xyz(pel, paz), n) <= 0.02, "{pel} {paz}");
    // Local date and time: 06:30 UTC less a pass or two.
    let text: String = regs[11..19]
        .iter()
        .flat_map(|r| r.to_be_bytes())
        .map(char::from)
        .collect();
    assert!(text.starts_with("20260320\0\x00063"), "{text:?}");
    assert_eq!(regs[19], 79, "day of the year");
    assert_eq!(regs[24], 0, "GlblCtl Automatic");
    let vendor = b.read(M64201 - 38, 14);
    // Without a GPS the vendor model follows model 601.
    assert_eq!(vendor[0], 64201);
    assert_eq!(vendor[2], 8, "mode tracking");
}

#[test]
fn writes_refused_when_off_and_carried_out_when_on() {
    let mut b = Bench::new(0);
    b.run_until(30 * 60_000, |_| {});
    assert_eq!(b.write(M601 + 24, &[1]), 1, "writes off: exception 01");
    b.run_until(b.clock.now_ms + 10_000, |_| {});
    assert!(!b.lines().contains(&"mode manual"));

    let mut b = Bench::new(1);
    b.run_until(30 * 60_000, |_| {});
    let (el, az) = (40.0_f64, 120.0_f64);
    let t = |v: f64| ((v * 100.0).round() as i32 as u32).to_be_bytes();
    let [e0, e1, e2, e3] = t(el);
    let [a0, a1, a2, a3] = t(az);
    let regs = [
        u16::from_be_bytes([e0, e1]),
        u16::from_be_bytes([e2, e3]),
        u16::from_be_bytes([a0, a1]),
        u16::from_be_bytes([a2, a3]),
        1,
    ];
    assert_eq!(b.write(M601 + 20, &regs), 0, "manual targets and mode");
    b.run_until(b.clock.now_ms + 60_000, |_| {});
    assert!(b.lines().contains(&"mode manual"));
    let miss = angle_deg(sun_xyz(el, az), b.motor_normal());
    assert!(miss <= 0.05, "the panel points {miss} deg off the target");
    let before = b.motor_normal();
    // Below the horizon: the A axis cannot reach it.
    assert_eq!(
        b.write(M601 + 20, &[0xFFFF, 0xE0C0]),
        3,
        "-80 deg: exception 03"
    );
    b.run_until(b.clock.now_ms + 10_000, |_| {});
    assert_eq!(angle_deg(before, b.motor_normal()), 0.0, "nothing moved");
    let regs = b.read(M601, 50);
    assert_eq!(angles(&regs, 20).0, 40.0, "the target kept");
    // Automatic: tracking again.
    let from = b.stamps.len();
    assert_eq!(b.write(M601 + 24, &[0]), 0);
    b.run_until(b.clock.now_ms + 60_000, |_| {});
    assert!(b.lines()[from..].contains(&"mode tracking"));
    // The vendor stow.
    assert_eq!(b.write(M64201 - 38 + 11, &[1]), 0);
    b.run_until(b.clock.now_ms + 20_000, |_| {});
    assert!(b.lines()[from..].contains(&"mode command_stow"));
}

#[test]
fn a_silent_master_ends_the_manual_mode_it_set() {
    let mut b = Bench::with_timeout(1, 60);
    b.run_until(30 * 60_000, |_| {});
    assert_eq!(b.write(M601 + 24, &[1]), 0, "Manual, where the axes stand");
    let from = b.stamps.len();
    // Reads keep the master present.
    for _ in 0..10 {
        b.read(M601, 2);
        b.run_until(b.clock.now_ms + 10_000, |_| {});
    }
    assert!(b.lines()[from..].contains(&"mode manual"));
    assert!(!b.lines()[from..].contains(&"mode tracking"));
    // Silent for 70 s: automatic again.
    b.run_until(b.clock.now_ms + 70_000, |_| {});
    assert!(b.lines()[from..].contains(&"mode tracking"));
    assert_eq!(b.read(M601 + 24, 1), [0], "GlblCtl Automatic");
}

#[test]
fn a_request_every_three_milliseconds_delays_no_setpoint() {
    fn setpoints(b: &Bench) -> Vec<(u64, String)> {
        b.stamps
            .iter()
            .filter(|(_, l)| l.starts_with("setpoint "))
            .cloned()
            .collect()
    }
    let end_ms = 40 * 60_000;
    let mut quiet = Bench::new(0);
    quiet.run_until(end_ms, |_| {});
    let mut flooded = Bench::new(0);
    let mut replies = 0usize;
    flooded.run_until(end_ms, |b| {
        // A read of 125 registers every 3 ms from minute 20 (the frames
        // more than 3.5 characters apart: each one served), about what the
        // line carries at 115,200 baud; the replies counted and dropped.
        replies += b.line.sent.len();
        b.line.sent.clear();
        if b.clock.now_ms >= 20 * 60_000 && b.clock.now_ms % 3 == 0 {
            b.queue(&[3, 0x9C, 0x40, 0, 125]);
        }
    });
    let want = setpoints(&quiet);
    assert!(want.len() >= 4, "{want:?}");
    assert_eq!(setpoints(&flooded), want);
    // Every request of the 20 minutes answered.
    assert_eq!(replies, 20 * 60_000 / 3 - 1);
}

/// Model 601's `DtLoc` (YYYYMMDD) and `TmLoc` (hhmmss) as text.
fn local_date_time(b: &mut Bench) -> (String, String) {
    let regs = b.read(M601 + 11, 8);
    let text = |r: &[u16]| -> String {
        r.iter()
            .flat_map(|w| w.to_be_bytes())
            .filter(|&c| c != 0)
            .map(char::from)
            .collect()
    };
    (text(&regs[..5]), text(&regs[5..]))
}

/// Seconds of the day of `hhmmss`.
fn seconds_of_day(hhmmss: &str) -> i64 {
    let n: i64 = hhmmss.parse().unwrap();
    n / 10_000 * 3_600 + n / 100 % 100 * 60 + n % 100
}

#[test]
fn local_time_is_utc_moved_by_the_configured_offset() {
    // At 06:30 UTC on 2026-03-20 (the bench's start plus 30 minutes): UTC
    // by default, 12:15 in Nepal (UTC+5:45), 21:00 the day before at
    // UTC−9:30 (the Marquesas).
    for (offset_h, date, time) in [
        (0.0, "20260320", "063000"),
        (5.75, "20260320", "121500"),
        (-9.5, "20260319", "210000"),
    ] {
        let mut b = Bench::with_config(|c| c.site.utc_offset_h = offset_h);
        b.run_until(30 * 60_000, |_| {});
        let (d, t) = local_date_time(&mut b);
        assert_eq!(d, date, "offset {offset_h}");
        // The read is served a few ms after 06:30:00.
        let late_s = seconds_of_day(&t) - seconds_of_day(time);
        assert!((0..=1).contains(&late_s), "offset {offset_h}: {t}");
    }
}

#[test]
fn wind_speed_from_the_pulse_rate_and_the_factor() {
    // 9 pulses a 1-second tick: 9 Hz. Without a factor "not implemented";
    // with the common cup anemometer's 2.4 km/h per Hz (0.667 m/s per
    // Hz), 6.0 m/s (9 × 0.667 = 6.003).
    for (factor, expected) in [(0.0, 0xFFFF), (0.667, 60)] {
        let mut b = Bench::with_config(|c| c.wind.m_s_per_hz = factor);
        b.clock.wind_pulses = 9;
        b.run_until(60_000, |_| {});
        let regs = b.read(VENDOR + 4, 2);
        assert_eq!(regs[0], expected, "factor {factor}");
        assert_eq!(regs[1] as i16, -1, "WndSpd_SF");
    }
}

#[test]
fn a_silent_master_stows_when_configured_and_its_return_releases() {
    let mut b = Bench::with_config(|c| {
        c.modbus.timeout_s = 60;
        c.modbus.timeout_stow = 1;
    });
    // No master heard yet: no stow, however long.
    b.run_until(30 * 60_000, |_| {});
    assert!(!b.lines().contains(&"mode command_stow"));
    // Heard, then silent for 70 s: stowed.
    b.read(M601, 2);
    let heard = b.stamps.len();
    b.run_until(b.clock.now_ms + 50_000, |_| {});
    assert!(!b.lines()[heard..].contains(&"mode command_stow"));
    b.run_until(b.clock.now_ms + 20_000, |_| {});
    assert!(b.lines()[heard..].contains(&"mode command_stow"));
    assert_eq!(b.read(VENDOR + 3, 1), [2], "StowRsn command");
    // Its next request releases the stow (writes are off: a read will do).
    let back = b.stamps.len();
    b.run_until(b.clock.now_ms + 10_000, |_| {});
    assert!(b.lines()[back..].contains(&"mode tracking"));
}

#[test]
fn clearing_the_faults_from_the_bus() {
    let mut b = Bench::with_config(|c| c.modbus.write = 1);
    b.run_until(30 * 60_000, |_| {});
    // The bench has no GPS: `gps_lost` (fault number 12) is active.
    let gps_lost = 1 << 12;
    let flt = b.read(VENDOR + 6, 2);
    assert_eq!(int32(&flt, 0), gps_lost, "{flt:?}");
    // Cleared (the reads come before the next tick, every 1,000 ms from
    // the start) ...
    assert_eq!(b.write(VENDOR + 13, &[1]), 0, "ClrFlt = 1");
    assert_eq!(b.read(VENDOR + 6, 2), [0, 0], "no fault left");
    assert_eq!(b.read(VENDOR + 13, 1), [0], "ClrFlt reads 0");
    // ... and raised again while its cause is there.
    b.run_until(b.clock.now_ms + 60_000, |_| {});
    assert_eq!(int32(&b.read(VENDOR + 6, 2), 0), gps_lost);
}
