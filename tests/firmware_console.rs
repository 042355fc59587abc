//! The configuration console of the firmware loop (`suntracker::firmware`) on a
//! host "board": the same parts as `firmware_app.rs` (simulated DS3231,
//! H-bridge steppers into the motor model, a millisecond clock the test
//! advances, no GPS unless a test sends it), plus console bytes the test
//! types and a configuration store in RAM with the two-slot layout.
//!
//! What is checked, each against something the firmware did not compute:
//! - `set site.lat_deg -33.8688` and `set site.lon_deg 151.2093` (Sydney)
//!   make the next `setpoint` lines Sydney's: their sun agrees with NREL
//!   SPA (Reda & Andreas 2004) for Sydney within 0.02°, and after `save`
//!   and a power cycle the stored site is used from boot;
//! - a value out of range (`set axis.c.gear_ratio 1e30`, `… 20000`) is
//!   refused naming the field, and `get` shows the old value;
//! - 10 KB of random bytes typed while tracking delay no set-point: every
//!   set-point of the undisturbed run is logged at the same monotonic
//!   second;
//! - `time set` is refused while GPS time is in force and sets an RTC that
//!   lost power otherwise (then tracking starts);
//! - `stow`, `resume`, `jog`, `manual off`, `status`, `faults`, `clear`,
//!   and the periodic `status` line every `log.status_min` minutes;
//! - on storage whose erase stalls the CPU (the Black Pill's flash, up to
//!   800 ms), a `save` typed while the axes home changes none of their
//!   steps: every step lands on the same millisecond as without the save.

mod common;

use std::cell::{Cell, RefCell};
use std::collections::VecDeque;
use std::rc::Rc;

use common::host_io::{Log, Uart};
use common::motor::{stepper_axis, Motor};
use sim::gps::GpsReceiverModel;
use sim::rtc::SimRtc;
use sim::sensors::MountSensors;
use sun_algos::{Algorithm, Options, Site, UtcTime};
use suntracker::config::Config;
use suntracker::controller::ControllerOptions;
use suntracker::firmware::{AppConfig, ConfigPersist, Firmware, Platform};
use suntracker::persist::{ConfigStore, MemStorage};
use suntracker::ports::Storage;

type Store = ConfigStore<TestFlash>;

/// RAM storage that may stand for a microcontroller's own flash: each
/// erase or write step then stalls the CPU for `stall_ms`, which the bench
/// adds to its clock with no loop pass and no motor step in between.
struct TestFlash {
    mem: MemStorage<1024>,
    stall_ms: u32,
    /// Stall time of the steps since the bench last looked, ms.
    stalled_ms: Cell<u64>,
}

impl TestFlash {
    fn new(stall_ms: u32) -> Self {
        TestFlash {
            mem: MemStorage::new(),
            stall_ms,
            stalled_ms: Cell::new(0),
        }
    }
    fn stall(&self) {
        self.stalled_ms
            .set(self.stalled_ms.get() + u64::from(self.stall_ms));
    }
}

impl Storage for TestFlash {
    type Error = <MemStorage<1024> as Storage>::Error;
    fn capacity(&self) -> usize {
        self.mem.capacity()
    }
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), Self::Error> {
        self.mem.read(offset, buf)
    }
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), Self::Error> {
        self.stall();
        self.mem.write(offset, data)
    }
    fn erase_step(&mut self, offset: usize, len: usize) -> Result<usize, Self::Error> {
        self.stall();
        self.mem.erase_step(offset, len)
    }
    fn write_step(&mut self, offset: usize, data: &[u8]) -> Result<usize, Self::Error> {
        self.stall();
        self.mem.write_step(offset, data)
    }
    fn stall_ms(&self) -> u32 {
        self.stall_ms
    }
}

/// `POSTAL`: whether the board has the postal-code table
/// ([`Platform::POSTAL_CODES`]).
struct HostPlatform<const POSTAL: bool = true> {
    now_ms: u64,
    /// Bytes "received" on the console, waiting for the firmware.
    console: VecDeque<u8>,
    /// A receive ring as small as a board's: what does not fit is dropped.
    ring_len: usize,
    dropped: usize,
    store: Store,
}

impl<const POSTAL: bool> Platform for HostPlatform<POSTAL> {
    const POSTAL_CODES: bool = POSTAL;
    fn now_ms(&mut self) -> u64 {
        self.now_ms
    }
    fn take_wind_pulses(&mut self) -> u32 {
        0
    }
    fn feed_watchdog(&mut self) {}
    fn wait_for_interrupt(&mut self) {}
    fn console_read(&mut self, buf: &mut [u8]) -> usize {
        let n = buf.len().min(self.console.len());
        for b in buf.iter_mut().take(n) {
            *b = self.console.pop_front().unwrap_or(0);
        }
        n
    }
    fn config_store(&mut self) -> Option<&mut dyn ConfigPersist> {
        Some(&mut self.store)
    }
}

const KANO: (f64, f64) = (11.9683, 8.4261);
const SYDNEY: (f64, f64) = (-33.8688, 151.2093);

struct Bench<const POSTAL: bool = true> {
    fw: Firmware<f32, SimRtc, Uart, common::motor::Axis, MountSensors, Log, 0>,
    platform: HostPlatform<POSTAL>,
    c: Rc<RefCell<Motor>>,
    a: Rc<RefCell<Motor>>,
    log: Log,
    gps_uart: Uart,
    gps: Option<GpsReceiverModel>,
    start: UtcTime,
    /// Monotonic ms at which each log line was first seen.
    stamps: Vec<(u64, String)>,
    seen: usize,
    /// After each pass: its monotonic ms and both motors' half-steps.
    steps: Vec<(u64, i64, i64)>,
}

fn start_utc() -> UtcTime {
    // 2026-03-20 06:00 UTC: morning at Kano, afternoon in Sydney.
    UtcTime::from_ymd_hms(2026, 3, 20, 6, 0, 0).unwrap()
}

impl Bench {
    fn new(config: Config, store: Store, rtc_lost_power: bool) -> Bench {
        Bench::build(config, store, rtc_lost_power)
    }
}

impl<const POSTAL: bool> Bench<POSTAL> {
    fn build(config: Config, store: Store, rtc_lost_power: bool) -> Self {
        let options = ControllerOptions::<f32> {
            feedback: suntracker::motion::FeedbackMode::OpenLoop,
            homing_chunk_deg: 0.45,
            ..Default::default()
        };
        let c = Motor::new(30.0, config.axes[0].home_deg as f64);
        let a = Motor::new(20.0, config.axes[1].home_deg as f64);
        let start = start_utc();
        let mut rtc = SimRtc::new(start);
        if rtc_lost_power {
            rtc.power_loss();
        }
        let log = Log::default();
        let gps_uart = Uart::default();
        let fw = Firmware::new(
            AppConfig::new("host"),
            config,
            options,
            rtc,
            gps_uart.clone(),
            [stepper_axis(&c), stepper_axis(&a)],
            None,
            log.clone(),
        )
        .expect("valid configuration");
        Self {
            fw,
            platform: HostPlatform {
                now_ms: 0,
                console: VecDeque::new(),
                ring_len: 128,
                dropped: 0,
                store,
            },
            c,
            a,
            log,
            gps_uart,
            gps: None,
            start,
            stamps: Vec::new(),
            seen: 0,
            steps: Vec::new(),
        }
    }

    /// Types `bytes` as a UART would deliver them: into a ring of the
    /// board's size, dropping what does not fit.
    fn receive(&mut self, bytes: &[u8]) {
        for &b in bytes {
            if self.platform.console.len() < self.platform.ring_len {
                self.platform.console.push_back(b);
            } else {
                self.platform.dropped += 1;
            }
        }
    }

    fn type_line(&mut self, line: &str) {
        self.receive(line.as_bytes());
        self.receive(b"\r\n");
    }

    /// Runs the loop until monotonic `end_ms`; `feed` is called every
    /// millisecond (bytes arriving at line speed).
    fn run_until(&mut self, end_ms: u64, mut feed: impl FnMut(&mut Self)) {
        let mut buf = [0u8; 256];
        let mut next_epoch_ms = self.platform.now_ms - self.platform.now_ms % 1000;
        while self.platform.now_ms < end_ms {
            let now = self.start.add_millis(self.platform.now_ms as i64).unwrap();
            self.fw.time_keeper_mut().rtc_mut().advance(now);
            if self.platform.now_ms >= next_epoch_ms {
                if let Some(g) = &self.gps {
                    let n = g.epoch(now, &mut buf).unwrap();
                    self.gps_uart.0.borrow_mut().extend(&buf[..n]);
                }
                next_epoch_ms += 1000;
            }
            feed(self);
            self.fw.poll(&mut self.platform);
            for m in [&self.c, &self.a] {
                m.borrow_mut().settle();
            }
            self.steps.push((
                self.platform.now_ms,
                self.c.borrow().half_steps,
                self.a.borrow().half_steps,
            ));
            let text = String::from_utf8(self.log.0.borrow().clone()).unwrap();
            let lines: Vec<&str> = text.lines().collect();
            for line in lines.iter().skip(self.seen) {
                if std::env::var_os("FW_DEBUG").is_some() {
                    println!("{} ms: {line}", self.platform.now_ms);
                }
                self.stamps.push((self.platform.now_ms, line.to_string()));
            }
            self.seen = lines.len();
            // A stalled CPU: time passes, nothing runs.
            let stalled = self.platform.store.storage().stalled_ms.replace(0);
            self.platform.now_ms += 1 + stalled;
        }
    }

    fn lines_since(&self, from: usize) -> Vec<String> {
        self.stamps[from..].iter().map(|(_, l)| l.clone()).collect()
    }

    fn reply_to(&mut self, line: &str) -> Vec<String> {
        let from = self.stamps.len();
        self.type_line(line);
        let end = self.platform.now_ms + 200;
        self.run_until(end, |_| {});
        self.lines_since(from)
            .into_iter()
            .filter(|l| l.starts_with("ok") || l.starts_with("error"))
            .collect()
    }
}

fn store() -> Store {
    ConfigStore::new(TestFlash::new(0))
}

fn field(line: &str, key: &str) -> f64 {
    let k = format!("{key}=");
    let start = line.find(&k).unwrap_or_else(|| panic!("{key} in {line}")) + k.len();
    let rest = &line[start..];
    let end = rest.find(' ').unwrap_or(rest.len());
    rest[..end].parse().unwrap()
}

fn utc_field(line: &str) -> UtcTime {
    let start = line.find("utc=").unwrap() + 4;
    let t = &line[start..start + 20];
    let n = |a: usize, b: usize| t[a..b].parse::<u32>().unwrap();
    UtcTime::from_ymd_hms(
        n(0, 4) as i32,
        n(5, 7) as u8,
        n(8, 10) as u8,
        n(11, 13) as u8,
        n(14, 16) as u8,
        n(17, 19) as u8,
    )
    .unwrap()
}

/// Largest difference between a set-point line's sun and SPA for the site.
fn worst_vs_spa(lines: &[String], (lat, lon): (f64, f64)) -> (usize, f64) {
    let site = Site::<f64>::with_elevation(lat, lon, 0.0).unwrap();
    let opts = Options {
        delta_t_s: Some(69.0),
        ..Options::default()
    };
    let mut worst = 0.0f64;
    let mut n = 0;
    for l in lines.iter().filter(|l| l.starts_with("setpoint ")) {
        let t = utc_field(l);
        let spa = Algorithm::Spa.position(&t, &site, &opts).unwrap();
        let dz = (field(l, "zenith") - spa.zenith_deg).abs();
        let mut da = (field(l, "azimuth") - spa.azimuth_deg).abs() % 360.0;
        if da > 180.0 {
            da = 360.0 - da;
        }
        // The azimuth's weight on the sky is sin(zenith).
        let da = da * spa.zenith_deg.to_radians().sin();
        worst = worst.max(dz).max(da);
        n += 1;
    }
    (n, worst)
}

/// Kano's configuration with the elevation SPA is given (0 m).
fn kano_config() -> Config {
    let (mut config, _) = common::motor::tracker_config();
    config.site.latitude_deg = KANO.0 as f32;
    config.site.longitude_deg = KANO.1 as f32;
    config.site.elevation_m = 0.0;
    config
}

#[test]
fn sydney_typed_saved_and_kept_over_a_power_cycle() {
    let mut b = Bench::new(kano_config(), store(), false);
    b.run_until(20 * 60_000, |_| {});
    let (n, worst) = worst_vs_spa(&b.lines_since(0), KANO);
    assert!(n >= 3, "Kano set-points before the change: {n}");
    assert!(worst < 0.02, "Kano vs SPA {worst}°");

    assert_eq!(
        b.reply_to("set site.lat_deg -33.8688"),
        ["ok site.lat_deg=-33.8688"]
    );
    assert_eq!(
        b.reply_to("set site.lon_deg 151.2093"),
        ["ok site.lon_deg=151.2093"]
    );
    let from = b.stamps.len();
    b.run_until(45 * 60_000, |_| {});
    let after = b.lines_since(from);
    assert!(
        b.lines_since(0)
            .iter()
            .any(|l| l == "site source=config lat=-33.8688 lon=151.2093"),
        "{after:?}"
    );
    let (n, worst) = worst_vs_spa(&after, SYDNEY);
    assert!(n >= 3, "Sydney set-points after the change: {n}");
    assert!(worst < 0.02, "Sydney vs SPA {worst}°");

    assert_eq!(b.reply_to("save"), ["ok save"]);
    // Power cycle: the storage survives, nothing else.
    let kept = std::mem::replace(&mut b.platform.store, store()).release();
    let mut store2: Store = ConfigStore::new(kept);
    let loaded = store2.load();
    assert!(!loaded.defaults, "{:?}", loaded.slots);
    let mut b2 = Bench::new(loaded.config, store2, false);
    b2.run_until(20 * 60_000, |_| {});
    let lines = b2.lines_since(0);
    assert!(
        lines
            .iter()
            .any(|l| l == "site source=config lat=-33.8688 lon=151.2093"),
        "{lines:?}"
    );
    let (n, worst) = worst_vs_spa(&lines, SYDNEY);
    assert!(n >= 3 && worst < 0.02, "{n} set-points, {worst}°");
}

#[test]
fn values_out_of_range_are_refused_and_change_nothing() {
    let mut b = Bench::new(kano_config(), store(), false);
    b.run_until(2_000, |_| {});
    let before = b.reply_to("get axis.c.gear_ratio");
    assert_eq!(before.len(), 1);
    assert!(before[0].starts_with("ok axis.c.gear_ratio="), "{before:?}");
    // No exponents: not a number at all.
    assert_eq!(
        b.reply_to("set axis.c.gear_ratio 1e30"),
        ["error axis.c.gear_ratio: not a number"]
    );
    let r = b.reply_to("set axis.c.gear_ratio 20000");
    assert_eq!(r.len(), 1);
    assert!(r[0].starts_with("error axis.c.gear_ratio: "), "{r:?}");
    assert_eq!(b.reply_to("get axis.c.gear_ratio"), before);
    let r = b.reply_to("set site.lat_deg 91");
    assert!(r[0].starts_with("error site.lat_deg: "), "{r:?}");
    let r = b.reply_to("set log.status_min 1441");
    assert!(r[0].starts_with("error log.status_min: "), "{r:?}");
    assert_eq!(b.fw.controller().config(), &kano_config());
    assert_eq!(b.reply_to("frobnicate"), ["error unknown command"]);
    assert_eq!(b.reply_to("get no.such_key"), ["error unknown key"]);
}

#[test]
fn ten_kilobytes_of_noise_delay_no_setpoint() {
    fn setpoints(b: &Bench) -> Vec<(u64, String)> {
        b.stamps
            .iter()
            .filter(|(_, l)| l.starts_with("setpoint "))
            .cloned()
            .collect()
    }
    let end_ms = 40 * 60_000;
    let mut quiet = Bench::new(kano_config(), store(), false);
    quiet.run_until(end_ms, |_| {});
    let mut noisy = Bench::new(kano_config(), store(), false);
    // xorshift32: 10,240 bytes at 115,200 baud (11.5 bytes a ms) from the
    // 10th minute, while tracking.
    let mut x = 0x1234_5678u32;
    let mut sent = 0usize;
    noisy.run_until(end_ms, |b| {
        if b.platform.now_ms >= 10 * 60_000 && sent < 10_240 {
            let mut chunk = [0u8; 11];
            for byte in chunk.iter_mut() {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                *byte = x as u8;
            }
            b.receive(&chunk);
            sent += chunk.len();
        }
    });
    assert!(sent >= 10_240);
    let (q, n) = (setpoints(&quiet), setpoints(&noisy));
    assert!(q.len() >= 8, "{} set-points", q.len());
    assert_eq!(q, n, "the same set-points at the same monotonic ms");
    let errors = noisy
        .stamps
        .iter()
        .filter(|(_, l)| l.starts_with("error "))
        .count();
    assert!(errors > 0, "the noise was answered");
}

#[test]
fn time_set_refused_under_gps_and_sets_an_rtc_that_lost_power() {
    // RTC lost power, no GPS: waits; `time set` starts tracking.
    let mut b = Bench::new(kano_config(), store(), true);
    b.run_until(5_000, |_| {});
    assert!(b.lines_since(0).iter().any(|l| l == "mode wait_for_time"));
    let r = b.reply_to("time set 2026-03-20T06:00:05Z");
    assert_eq!(r, ["ok utc=2026-03-20T06:00:05Z"]);
    b.run_until(15 * 60_000, |_| {});
    let (n, worst) = worst_vs_spa(&b.lines_since(0), KANO);
    assert!(n >= 2 && worst < 0.02, "{n} set-points, {worst}°");

    // GPS in force: refused.
    let mut g = Bench::new(kano_config(), store(), false);
    g.gps = Some(GpsReceiverModel::new(KANO.0, KANO.1, 0.0));
    g.run_until(5_000, |_| {});
    assert!(g
        .lines_since(0)
        .iter()
        .any(|l| l.starts_with("time source=gps")));
    assert_eq!(
        g.reply_to("time set 2027-01-01T00:00:00Z"),
        ["error time set: GPS time is in force"]
    );
}

#[test]
fn operator_commands_and_the_periodic_status_line() {
    let mut config = kano_config();
    config.log.status_every_min = 2;
    let mut b = Bench::new(config, store(), false);
    b.run_until(10 * 60_000, |_| {});
    let status: Vec<(u64, String)> = b
        .stamps
        .iter()
        .filter(|(_, l)| l.starts_with("status "))
        .cloned()
        .collect();
    assert_eq!(status.len(), 4, "{status:?}");
    for (i, (ms, l)) in status.iter().enumerate() {
        // Every 2 minutes of the monotonic clock, within one tick.
        let due = (i as u64 + 1) * 120_000;
        assert!(*ms >= due && *ms < due + 1_000, "{ms} {l}");
        assert!(l.contains(" lat=11.9683 lon=8.4261 site=config "), "{l}");
    }
    let r = b.reply_to("status");
    assert_eq!(r.len(), 1);
    // The last tick's time: 10 minutes after the start, within a tick.
    let t = utc_field(&r[0]).unix_seconds() - start_utc().unix_seconds();
    assert!((599..=601).contains(&t), "{r:?}");
    assert!(r[0].starts_with("ok mode=tracking utc="), "{r:?}");
    assert!(r[0].contains(" time=rtc "), "{r:?}");
    // No GPS on this bench: its loss is the one fault.
    assert!(r[0].ends_with(" faults=gps_lost wind_hz=0.00"), "{r:?}");

    assert_eq!(b.reply_to("stow"), ["ok stow"]);
    b.run_until(b.platform.now_ms + 3_000, |_| {});
    assert!(b.stamps.iter().any(|(_, l)| l == "mode command_stow"));
    assert_eq!(b.reply_to("resume"), ["ok resume"]);
    let r = b.reply_to("jog a 5");
    assert_eq!(r.len(), 1);
    assert!(r[0].starts_with("ok jog c="), "{r:?}");
    let a_jog = field(&r[0], "a");
    b.run_until(b.platform.now_ms + 60_000, |_| {});
    assert!(b.stamps.iter().any(|(_, l)| l == "mode manual"));
    // The motor went there (open loop: one half-step).
    let a_motor = b.a.borrow().angle_deg();
    assert!((a_motor - a_jog).abs() < 0.02, "{a_motor} vs {a_jog}");
    // Beyond the soft limit: held at it.
    let r = b.reply_to("jog a 500");
    assert!(r[0].ends_with(" a=90.00 limited"), "{r:?}");
    assert_eq!(b.reply_to("manual off"), ["ok manual off"]);
    let r = b.reply_to("faults");
    assert_eq!(r.len(), 1);
    assert!(r[0].starts_with("ok fault=gps_lost attempts="), "{r:?}");
    assert_eq!(b.reply_to("clear"), ["ok clear"]);
    assert_eq!(b.reply_to("faults"), ["ok faults=none"]);
    b.run_until(b.platform.now_ms + 5 * 60_000, |_| {});
    assert_eq!(
        b.stamps
            .iter()
            .rev()
            .find(|(_, l)| l.starts_with("mode "))
            .map(|(_, l)| l.as_str()),
        Some("mode tracking")
    );
}

/// `time set` outside this firmware's dates (1024 weeks from 2026-01-01)
/// is refused with that reason, not sent to the RTC; 30 `save`s typed in a
/// row at line speed get 30 replies (one save, the others `busy`).
#[test]
fn time_set_outside_the_window_and_saves_in_a_row() {
    let mut b = Bench::new(kano_config(), store(), true);
    b.run_until(2_000, |_| {});
    for t in [
        "1969-07-20T20:17:40Z",
        "2045-12-31T00:00:00Z",
        "2025-12-31T23:59:59Z",
    ] {
        assert_eq!(
            b.reply_to(&format!("time set {t}")),
            ["error time set: outside this firmware's dates"],
            "{t}"
        );
    }
    assert_eq!(
        b.reply_to("time set 2026-03-20T06:00:00Z"),
        ["ok utc=2026-03-20T06:00:00Z"]
    );
    // Typed at 115200 baud: 11 bytes a millisecond.
    let mut typed: VecDeque<u8> = b"save\n".repeat(30).into();
    let from = b.stamps.len();
    let end = b.platform.now_ms + 500;
    b.run_until(end, |b| {
        let n = typed.len().min(11);
        let chunk: Vec<u8> = typed.drain(..n).collect();
        b.receive(&chunk);
    });
    assert_eq!(b.platform.dropped, 0, "the ring overflowed");
    let replies: Vec<String> = b
        .lines_since(from)
        .into_iter()
        .filter(|l| l.starts_with("ok") || l.starts_with("error"))
        .collect();
    assert_eq!(replies.len(), 30, "{replies:?}");
    let saved = replies.iter().filter(|l| *l == "ok save").count();
    let busy = replies.iter().filter(|l| *l == "error busy").count();
    assert!(saved >= 1 && saved + busy == 30, "{replies:?}");
}

#[test]
fn load_and_defaults() {
    let mut b = Bench::new(kano_config(), store(), false);
    b.run_until(2_000, |_| {});
    assert_eq!(b.reply_to("load"), ["error load: no valid stored config"]);
    assert_eq!(b.reply_to("set wind.stow_hz 30"), ["ok wind.stow_hz=30"]);
    assert_eq!(b.reply_to("save"), ["ok save"]);
    assert_eq!(b.reply_to("defaults"), ["ok defaults"]);
    assert_eq!(b.fw.controller().config(), &Config::default());
    assert_eq!(b.reply_to("load"), ["ok load"]);
    let mut expected = kano_config();
    expected.wind.threshold_hz = 30.0;
    assert_eq!(b.fw.controller().config(), &expected);
}

/// A board that leaves the postal-code table out (`Platform::POSTAL_CODES`
/// false, as the Uno's single image does for flash) refuses `set
/// site.postal_code` and changes nothing; the keys set the site as ever.
/// With the table, the same line sets data/postal_codes.csv's place
/// (`DZ,16000,Alger Gare,36.779443,3.061738`, stored at 1e-4°).
#[test]
fn postal_codes_only_where_the_board_has_the_table() {
    let mut b = Bench::<false>::build(kano_config(), store(), false);
    b.run_until(2_000, |_| {});
    assert_eq!(
        b.reply_to("set site.postal_code DZ:16000"),
        ["error site.postal_code: not in this image"]
    );
    assert_eq!(b.fw.controller().config(), &kano_config());
    assert_eq!(
        b.reply_to("set site.lat_deg 36.7794 site.lon_deg 3.0617"),
        ["ok site.lat_deg=36.7794 site.lon_deg=3.0617"]
    );

    let mut b = Bench::new(kano_config(), store(), false);
    b.run_until(2_000, |_| {});
    assert_eq!(
        b.reply_to("set site.postal_code DZ:16000"),
        ["ok site.lat_deg=36.7794 site.lon_deg=3.0617"]
    );
}

/// A power cycle of the bench: the storage survives (the store is read
/// as a board's start-up reads it), the motors stay where they are, RAM
/// and the log start over.
fn power_cycle(b: Bench) -> Bench {
    let angles = (b.c.borrow().angle_deg(), b.a.borrow().angle_deg());
    let kept = b.platform.store.release();
    let mut store2: Store = ConfigStore::new(kept);
    let loaded = store2.load();
    assert!(!loaded.defaults, "{:?}", loaded.slots);
    let b2 = Bench::new(loaded.config, store2, false);
    b2.c.borrow_mut().start_deg = angles.0;
    b2.a.borrow_mut().start_deg = angles.1;
    b2
}

fn motor_angles(b: &Bench) -> (f64, f64) {
    (b.c.borrow().angle_deg(), b.a.borrow().angle_deg())
}

fn modes(b: &Bench) -> Vec<&str> {
    b.stamps
        .iter()
        .filter(|(_, l)| l.starts_with("mode "))
        .map(|(_, l)| l.as_str())
        .collect()
}

/// `service on` is saved with the stored configuration (not with an
/// unsaved `set`) and survives a power cut: after it no motor moves for
/// 30 minutes, homing included, the log says `mode service`; a `jog` moves
/// an axis with no reference from where it stands; `service off` homes and
/// tracks again.
#[test]
fn service_lock_survives_a_power_cycle() {
    let mut b = Bench::new(kano_config(), store(), false);
    b.run_until(20 * 60_000, |_| {});
    assert_eq!(modes(&b).last(), Some(&"mode tracking"));
    assert_eq!(b.reply_to("save"), ["ok save"]);
    // Not saved: the service lock must not store it.
    assert_eq!(b.reply_to("set site.lat_deg 45"), ["ok site.lat_deg=45"]);
    assert_eq!(b.reply_to("service on"), ["ok service on"]);
    b.run_until(b.platform.now_ms + 2_000, |_| {});
    assert_eq!(modes(&b).last(), Some(&"mode service"));
    let held = motor_angles(&b);
    b.run_until(b.platform.now_ms + 10 * 60_000, |_| {});
    assert_eq!(motor_angles(&b), held, "moved in service");
    let r = b.reply_to("status");
    assert!(r[0].starts_with("ok mode=service "), "{r:?}");
    // A jog moves a homed axis to the pose it names; the lock stays.
    let r = b.reply_to("jog a 3");
    assert!(r[0].starts_with("ok jog c="), "{r:?}");
    let a_jog = field(&r[0], "a");
    b.run_until(b.platform.now_ms + 30_000, |_| {});
    assert!((b.a.borrow().angle_deg() - a_jog).abs() < 0.02);
    assert!(
        (a_jog - held.1 - 3.0).abs() < 0.02,
        "{a_jog} from {}",
        held.1
    );
    assert_eq!(b.c.borrow().angle_deg(), held.0);
    assert_eq!(modes(&b).last(), Some(&"mode service"));
    assert!(b.fw.controller().config().hold.service);

    let mut b = power_cycle(b);
    assert!(b.fw.controller().config().hold.service);
    // The stored site, not the unsaved one.
    assert_eq!(b.fw.controller().config().site.latitude_deg, KANO.0 as f32);
    let start = motor_angles(&b);
    b.run_until(30 * 60_000, |_| {});
    assert_eq!(motor_angles(&b), start, "a motor moved after the cut");
    assert_eq!(modes(&b), ["mode service"]);
    assert!(!b.stamps.iter().any(|(_, l)| l.starts_with("setpoint ")));
    // A jog of an axis with no reference: 2° from where it stands.
    let r = b.reply_to("jog c 2");
    assert_eq!(r.len(), 1, "{r:?}");
    b.run_until(b.platform.now_ms + 5_000, |_| {});
    let (c, a) = motor_angles(&b);
    assert!((c - start.0 - 2.0).abs() < 0.02, "{c} from {}", start.0);
    assert_eq!(a, start.1);
    assert_eq!(modes(&b), ["mode service"]);

    assert_eq!(b.reply_to("service off"), ["ok service off"]);
    b.run_until(b.platform.now_ms + 15 * 60_000, |_| {});
    let m = modes(&b);
    assert_eq!(m[1..], ["mode homing", "mode tracking"], "{m:?}");
    let (n, worst) = worst_vs_spa(&b.lines_since(0), KANO);
    assert!(n >= 2 && worst < 0.02, "{n} set-points, {worst}°");
    // Two lines in one read: the second comes while the first one's save
    // goes on, and is answered, not dropped.
    let from = b.stamps.len();
    b.receive(b"stow\nresume\n");
    b.run_until(b.platform.now_ms + 200, |_| {});
    let r: Vec<String> = b
        .lines_since(from)
        .into_iter()
        .filter(|l| l.starts_with("ok") || l.starts_with("error"))
        .collect();
    assert_eq!(r, ["error busy", "ok stow"], "{r:?}");
    assert_eq!(b.reply_to("resume"), ["ok resume"]);
    // Off is saved too: the next power-on tracks.
    let mut b = power_cycle(b);
    assert_eq!(b.fw.controller().config().hold, Default::default());
    b.run_until(10 * 60_000, |_| {});
    assert_eq!(modes(&b).last(), Some(&"mode tracking"));
}

/// A typed `stow` survives a power cut (the axes home and the stow pose is
/// driven to again), and so does manual mode (the axes stay still until a
/// jog); `resume` ends both.
#[test]
fn stow_and_manual_survive_a_power_cycle() {
    let mut b = Bench::new(kano_config(), store(), false);
    b.run_until(20 * 60_000, |_| {});
    // The installer saved the bench's mechanics (a hold is saved with the
    // stored configuration, else with the board's own, `Config::default`).
    assert_eq!(b.reply_to("save"), ["ok save"]);
    assert_eq!(b.reply_to("stow"), ["ok stow"]);
    let mut b = power_cycle(b);
    assert!(b.fw.controller().config().hold.stow);
    b.run_until(10 * 60_000, |_| {});
    let m = modes(&b);
    assert_eq!(m.last(), Some(&"mode command_stow"), "{m:?}");
    // The stow pose: the panel flat.
    assert!(
        b.a.borrow().angle_deg().abs() < 0.05,
        "{:?}",
        motor_angles(&b)
    );
    assert_eq!(b.reply_to("resume"), ["ok resume"]);
    b.run_until(b.platform.now_ms + 5 * 60_000, |_| {});
    assert_eq!(modes(&b).last(), Some(&"mode tracking"));

    // Manual: a jog starts it (answered at once, saved behind).
    let r = b.reply_to("jog a 5");
    assert!(r[0].starts_with("ok jog c="), "{r:?}");
    b.run_until(b.platform.now_ms + 60_000, |_| {});
    assert_eq!(modes(&b).last(), Some(&"mode manual"));
    let mut b = power_cycle(b);
    assert!(b.fw.controller().config().hold.manual);
    let start = motor_angles(&b);
    b.run_until(10 * 60_000, |_| {});
    assert_eq!(modes(&b), ["mode manual"]);
    assert_eq!(motor_angles(&b), start, "moved in manual after the cut");
    assert_eq!(b.reply_to("resume"), ["ok resume"]);
    b.run_until(b.platform.now_ms + 10 * 60_000, |_| {});
    let m = modes(&b);
    assert_eq!(m[1..], ["mode homing", "mode tracking"], "{m:?}");
}

/// The Black Pill's flash stalls the CPU for up to 800 ms a sector erase
/// (`suntracker::persist`): no step can be taken meanwhile. A `save` typed
/// while both axes home (a long move) waits until they rest with no tick
/// due within the stall; every step of the homing and of the tracking
/// after it lands on the same millisecond as on a bench whose storage
/// never stalls, and the save is answered after homing.
#[test]
fn save_on_a_stalling_flash_changes_no_step() {
    let run = |stall_ms: u32| {
        let mut b = Bench::new(
            kano_config(),
            ConfigStore::new(TestFlash::new(stall_ms)),
            false,
        );
        b.run_until(3_000, |_| {});
        let from = b.stamps.len();
        b.type_line("save");
        b.run_until(10 * 60_000, |_| {});
        let saved_ms = b.stamps[from..]
            .iter()
            .find(|(_, l)| l == "ok save")
            .map(|(t, _)| *t)
            .unwrap_or_else(|| panic!("no `ok save`: {:?}", &b.stamps[from..]));
        let tracking_ms = b
            .stamps
            .iter()
            .find(|(_, l)| l == "mode tracking")
            .map(|(t, _)| *t)
            .expect("tracking after homing");
        (b.steps, saved_ms, tracking_ms)
    };
    let (free, free_saved, free_tracking) = run(0);
    let (stalled, stalled_saved, stalled_tracking) = run(800);
    // Without a stall the save is done within the passes after the line.
    assert!(free_saved < 3_100, "{free_saved}");
    // With it, after homing (mode tracking), and the steps are the same.
    assert_eq!(stalled_tracking, free_tracking);
    assert!(
        stalled_saved > stalled_tracking,
        "{stalled_saved} {stalled_tracking}"
    );
    let moved = free
        .windows(2)
        .filter(|w| (w[0].1, w[0].2) != (w[1].1, w[1].2))
        .count();
    assert!(moved > 10_000, "homing moved the axes in {moved} passes");
    let at = |steps: &[(u64, i64, i64)], ms: u64| {
        // The motors' state at `ms`: after the last pass at or before it.
        let i = steps.partition_point(|s| s.0 <= ms);
        steps[i - 1]
    };
    let mut compared = 0;
    for s in &stalled {
        let f = at(&free, s.0);
        assert_eq!((s.1, s.2), (f.1, f.2), "steps differ at {} ms", s.0);
        compared += 1;
    }
    // The stalls: time without passes on the stalling bench.
    let gaps: u64 = stalled.windows(2).map(|w| w[1].0 - w[0].0 - 1).sum();
    assert!(gaps >= 800, "no erase stalled the CPU ({gaps} ms)");
    assert!(compared > 500_000, "{compared}");
}
