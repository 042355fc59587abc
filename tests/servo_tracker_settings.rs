//! The Arduino Uno's settings console (`suntracker::servo_tracker::settings`,
//! the `avr_settings` image) on the host: over `MemStorage` or a byte
//! EEPROM model, with `SimRtc` as its clock and a sink collecting the
//! replies. The expected replies are the documented ones: the language of
//! `src/console/mod.rs` (module docs), the settings module's table (keys,
//! `error <command>: not on this image`) and the refusal texts of
//! `src/config/keys.rs` (`Reason`).

mod common;

use common::host_io::Buf;
use drivers::rtc::Clock;
use sim::rtc::SimRtc;
use sun_algos::UtcTime;
use suntracker::persist::{EepromCells, EepromStorage};
use suntracker::persist::{MemStorage, SlotState};
use suntracker::ports::Storage;
use suntracker::servo_tracker::settings::{self as settings, Settings, SettingsConsole};

/// The ATmega328P's EEPROM size.
const EEPROM_LEN: usize = 1024;

type Mem = MemStorage<EEPROM_LEN>;

/// Polls of the busy flag a byte write lasts in the EEPROM model.
const WRITE_POLLS: u32 = 3;

/// A byte EEPROM: each write busy for a few polls, writes counted.
#[derive(Debug, Clone)]
struct Cells {
    bytes: Vec<u8>,
    busy_for: u32,
    writes: usize,
}

impl Cells {
    fn erased() -> Self {
        Cells {
            bytes: vec![0xFF; EEPROM_LEN],
            busy_for: 0,
            writes: 0,
        }
    }
}

impl EepromCells for Cells {
    fn size_bytes(&self) -> usize {
        self.bytes.len()
    }
    fn busy(&mut self) -> bool {
        if self.busy_for > 0 {
            self.busy_for -= 1;
            true
        } else {
            false
        }
    }
    fn read_byte(&mut self, address: u16) -> u8 {
        assert_eq!(self.busy_for, 0, "EEPROM read while a write runs");
        self.bytes[usize::from(address)]
    }
    fn start_write(&mut self, address: u16, value: u8) {
        assert_eq!(self.busy_for, 0, "EEPROM write started while one runs");
        self.bytes[usize::from(address)] = value;
        self.writes += 1;
        self.busy_for = WRITE_POLLS;
    }
}

fn utc(s: &str) -> UtcTime {
    s.parse().expect("a valid instant")
}

/// The settings console on a storage, its clock and its output.
struct Rig<S> {
    console: SettingsConsole<S>,
    rtc: SimRtc,
    out: Buf,
}

impl<S: Storage> Rig<S> {
    /// Power-on on `storage`: the boot line is left in `out`.
    fn boot(storage: S) -> Self {
        let mut out = Buf::default();
        let console = SettingsConsole::boot(storage, &mut out);
        Rig {
            console,
            rtc: SimRtc::new(utc("2026-03-20T08:00:00Z")),
            out,
        }
    }

    /// The boot line (and anything else written since the last take).
    fn take(&mut self) -> String {
        self.out.take()
    }

    /// Feeds `bytes`, then polls until no save is under way: the reply.
    fn feed(&mut self, bytes: &[u8]) -> String {
        self.console.input(bytes, &mut self.rtc, &mut self.out);
        let mut polls = 0u32;
        while self.console.is_saving() {
            self.console.poll(&mut self.out);
            polls += 1;
            assert!(polls < 100_000, "the save does not end");
        }
        self.out.take()
    }

    /// Sends `line` with its end of line: the reply.
    fn send(&mut self, line: &str) -> String {
        self.feed(format!("{line}\r\n").as_bytes())
    }

    fn settings(&self) -> Settings {
        *self.console.settings()
    }
}

fn mem_rig() -> Rig<Mem> {
    let mut rig = Rig::boot(Mem::new());
    assert_eq!(rig.take(), "config source=defaults\n");
    rig
}

/// `ok KEY=VALUE` lines, each ended.
fn oks(pairs: &[(&str, &str)]) -> String {
    pairs.iter().map(|(k, v)| format!("ok {k}={v}\n")).collect()
}

const GEAR_REASON: &str = "1...10,000 motor revolutions per axis revolution";

fn sydney() -> Settings {
    Settings {
        lat_deg: -33.8688,
        lon_deg: 151.2093,
        ..settings::DEFAULTS
    }
}

// ---------------------------------------------------------------------------
// Keys, get and set

#[test]
fn get_lists_the_four_keys_in_order() {
    let mut rig = mem_rig();
    let names: Vec<String> = settings::KEYS
        .iter()
        .map(|k| k.name().to_string())
        .collect();
    assert_eq!(
        names,
        [
            "site.lat_deg",
            "site.lon_deg",
            "axis.c.gear_ratio",
            "axis.a.gear_ratio"
        ]
    );
    assert_eq!(
        rig.send("get"),
        oks(&[
            ("site.lat_deg", "11.9683"),
            ("site.lon_deg", "8.4261"),
            ("axis.c.gear_ratio", "1"),
            ("axis.a.gear_ratio", "1"),
        ])
    );
    assert_eq!(rig.settings(), settings::DEFAULTS);
}

#[test]
fn set_site_then_get_all() {
    let mut rig = mem_rig();
    assert_eq!(
        rig.send("set site.lat_deg -33.8688"),
        "ok site.lat_deg=-33.8688\n"
    );
    assert_eq!(
        rig.send("set site.lon_deg 151.2093"),
        "ok site.lon_deg=151.2093\n"
    );
    assert_eq!(
        rig.send("get"),
        oks(&[
            ("site.lat_deg", "-33.8688"),
            ("site.lon_deg", "151.2093"),
            ("axis.c.gear_ratio", "1"),
            ("axis.a.gear_ratio", "1"),
        ])
    );
    assert_eq!(rig.settings(), sydney());
    // `KEY=VALUE`, upper case, tabs: the library's parser.
    assert_eq!(rig.send("SET\tSite.Lat_Deg=12.5"), "ok site.lat_deg=12.5\n");
    assert_eq!(rig.send("get site.lat_deg"), "ok site.lat_deg=12.5\n");
}

#[test]
fn values_out_of_range_or_not_numbers_change_nothing() {
    let mut rig = mem_rig();
    assert_eq!(
        rig.send("set axis.c.gear_ratio 20000"),
        format!("error axis.c.gear_ratio: {GEAR_REASON}\n")
    );
    assert_eq!(
        rig.send("get axis.c.gear_ratio"),
        "ok axis.c.gear_ratio=1\n"
    );
    assert_eq!(
        rig.send("set axis.c.gear_ratio 1e30"),
        "error axis.c.gear_ratio: not a number\n"
    );
    assert_eq!(
        rig.send("set axis.a.gear_ratio 0.5"),
        format!("error axis.a.gear_ratio: {GEAR_REASON}\n")
    );
    assert_eq!(
        rig.send("set site.lat_deg 91"),
        "error site.lat_deg: -90...90 deg\n"
    );
    assert_eq!(
        rig.send("set site.lon_deg -180.5"),
        "error site.lon_deg: -180...180 deg\n"
    );
    assert_eq!(
        rig.send("set site.lat_deg nan"),
        "error site.lat_deg: not a number\n"
    );
    assert_eq!(
        rig.send("set site.lat_deg 99999999999"),
        "error site.lat_deg: number too large\n"
    );
    assert_eq!(rig.send("set site.lat_deg"), "error missing argument\n");
    assert_eq!(rig.settings(), settings::DEFAULTS);
    // The limits themselves are in range.
    assert_eq!(
        rig.send("set axis.c.gear_ratio 10000"),
        "ok axis.c.gear_ratio=10000\n"
    );
    assert_eq!(rig.send("set site.lat_deg -90"), "ok site.lat_deg=-90\n");
}

#[test]
fn set_of_several_keys_is_all_or_nothing() {
    let mut rig = mem_rig();
    let reply = rig.send("set axis.c.gear_ratio 2 axis.a.gear_ratio 3");
    assert!(reply.starts_with("ok "), "{reply:?}");
    assert_eq!(rig.settings().gear_ratio, [2.0, 3.0]);
    assert_eq!(
        rig.send("get"),
        oks(&[
            ("site.lat_deg", "11.9683"),
            ("site.lon_deg", "8.4261"),
            ("axis.c.gear_ratio", "2"),
            ("axis.a.gear_ratio", "3"),
        ])
    );
    // The second out of range: neither changes.
    assert_eq!(
        rig.send("set axis.c.gear_ratio 4 axis.a.gear_ratio 20000"),
        format!("error axis.a.gear_ratio: {GEAR_REASON}\n")
    );
    // The first out of range: neither changes either.
    assert_eq!(
        rig.send("set site.lat_deg 95 site.lon_deg 10"),
        "error site.lat_deg: -90...90 deg\n"
    );
    // A key the settings do not hold among them: refused when parsed.
    assert_eq!(
        rig.send("set axis.c.gear_ratio 4 wind.stow_hz 30"),
        "error unknown key\n"
    );
    assert_eq!(
        rig.send("set axis.c.gear_ratio 4 axis.a.gear_ratio x"),
        "error axis.a.gear_ratio: not a number\n"
    );
    assert_eq!(
        rig.send("get axis.c.gear_ratio"),
        "ok axis.c.gear_ratio=2\n"
    );
    assert_eq!(
        rig.send("get axis.a.gear_ratio"),
        "ok axis.a.gear_ratio=3\n"
    );
    assert_eq!(rig.settings().gear_ratio, [2.0, 3.0]);
    assert_eq!(rig.settings().lat_deg, settings::DEFAULTS.lat_deg);
}

/// src/console/mod.rs documents `set K1 V1 K2 V2 …` as answered on one line,
/// `ok K1=V1 K2=V2 …`, and the settings module promises the library's
/// replies.
#[test]
fn set_of_several_keys_replies_on_one_line() {
    let mut rig = mem_rig();
    assert_eq!(
        rig.send("set axis.c.gear_ratio 2 axis.a.gear_ratio 3"),
        "ok axis.c.gear_ratio=2 axis.a.gear_ratio=3\n"
    );
    assert_eq!(
        rig.send("set site.lat_deg -33.8688 site.lon_deg 151.2093"),
        "ok site.lat_deg=-33.8688 site.lon_deg=151.2093\n"
    );
}

// ---------------------------------------------------------------------------
// save, load, defaults, and the tracker image's load

#[test]
fn save_then_boot_and_load_find_the_settings() {
    let mut rig = mem_rig();
    rig.send("set site.lat_deg -33.8688 site.lon_deg 151.2093");
    assert_eq!(rig.settings(), sydney());
    assert_eq!(rig.send("save"), "ok save\n");
    assert!(!rig.console.is_saving());
    let storage = rig.console.release();

    // The settings image, powered up again.
    let mut again = Rig::boot(storage.clone());
    assert_eq!(again.take(), "config source=stored\n");
    assert_eq!(again.settings(), sydney());
    assert_eq!(
        again.send("get"),
        oks(&[
            ("site.lat_deg", "-33.8688"),
            ("site.lon_deg", "151.2093"),
            ("axis.c.gear_ratio", "1"),
            ("axis.a.gear_ratio", "1"),
        ])
    );

    // The tracker image's power-on read.
    let mut out = Buf::default();
    assert_eq!(settings::load(storage, &mut out), sydney());
    assert_eq!(out.take(), "config source=stored\n");

    // Erased storage: the defaults, said so.
    let mut out = Buf::default();
    assert_eq!(settings::load(Mem::new(), &mut out), settings::DEFAULTS);
    assert_eq!(out.take(), "config source=defaults\n");
}

#[test]
fn save_on_the_eeprom_one_byte_write_a_poll_and_ok_at_the_end() {
    let mut rig = Rig::boot(EepromStorage::new(Cells::erased()));
    assert_eq!(rig.take(), "config source=defaults\n");
    rig.send("set site.lat_deg -33.8688 site.lon_deg 151.2093");

    // `save` only starts the save: no write, no reply yet.
    rig.console.input(b"save\n", &mut rig.rtc, &mut rig.out);
    assert!(rig.console.is_saving());
    assert_eq!(rig.out.take(), "");
    assert_eq!(rig.console.store().storage().cells().writes, 0);

    let mut polls = 0u32;
    while rig.console.is_saving() {
        let before = rig.console.store().storage().cells().writes;
        rig.console.poll(&mut rig.out);
        let after = rig.console.store().storage().cells().writes;
        assert!(
            after - before <= 1,
            "a poll started {} writes",
            after - before
        );
        polls += 1;
        assert!(polls < 100_000, "the save does not end");
        if rig.console.is_saving() {
            assert_eq!(rig.out.take(), "", "a reply before the save ended");
        }
    }
    assert_eq!(rig.out.take(), "ok save\n");
    let writes = rig.console.store().storage().cells().writes;
    // Header, payload and CRC-32 (12 + 16 + 4 bytes), erased bytes skipped.
    assert!(writes > 0 && writes <= settings::RECORD_LEN, "{writes}");
    assert!(polls > u32::try_from(writes).unwrap(), "{polls} polls");
    // Polled further: nothing more.
    rig.console.poll(&mut rig.out);
    assert_eq!(rig.out.take(), "");

    let cells = rig.console.release().release();
    let mut again = Rig::boot(EepromStorage::new(cells.clone()));
    assert_eq!(again.take(), "config source=stored\n");
    assert_eq!(again.settings(), sydney());
    assert_eq!(
        again.console.store().storage().cells().writes,
        cells.writes,
        "boot only reads"
    );
    let mut out = Buf::default();
    assert_eq!(
        settings::load(EepromStorage::new(cells), &mut out),
        sydney()
    );
    assert_eq!(out.take(), "config source=stored\n");
}

#[test]
fn defaults_then_load_restores_the_saved_copy() {
    let mut rig = mem_rig();
    assert_eq!(rig.send("load"), "error load: no valid stored config\n");
    assert_eq!(rig.settings(), settings::DEFAULTS);

    rig.send("set site.lat_deg -33.8688 site.lon_deg 151.2093");
    assert_eq!(rig.send("save"), "ok save\n");
    assert_eq!(rig.send("defaults"), "ok defaults\n");
    assert_eq!(rig.settings(), settings::DEFAULTS);
    assert_eq!(rig.send("get site.lat_deg"), "ok site.lat_deg=11.9683\n");
    assert_eq!(rig.send("load"), "ok load\n");
    assert_eq!(rig.settings(), sydney());
    assert_eq!(rig.send("get site.lon_deg"), "ok site.lon_deg=151.2093\n");

    // A second save goes to the other slot; load gives the newest.
    rig.send("set axis.c.gear_ratio 2 axis.a.gear_ratio 3");
    assert_eq!(rig.send("save"), "ok save\n");
    assert_eq!(rig.send("defaults"), "ok defaults\n");
    assert_eq!(rig.send("load"), "ok load\n");
    assert_eq!(
        rig.settings(),
        Settings {
            gear_ratio: [2.0, 3.0],
            ..sydney()
        }
    );
    let mut store = settings::SettingsStore::for_record(rig.console.release());
    assert_eq!(store.load().slots, [SlotState::Good(1), SlotState::Good(2)]);
}

#[test]
fn load_on_erased_storage_keeps_the_settings_being_edited() {
    let mut rig = mem_rig();
    rig.send("set site.lat_deg -33.8688");
    assert_eq!(rig.send("load"), "error load: no valid stored config\n");
    assert_eq!(rig.settings().lat_deg, -33.8688);
}

// ---------------------------------------------------------------------------
// time set

#[test]
fn time_set_sets_the_rtc() {
    let mut rig = mem_rig();
    let t = utc("2026-06-21T12:00:00Z");
    assert_eq!(
        rig.send("time set 2026-06-21T12:00:00Z"),
        "ok utc=2026-06-21T12:00:00Z\n"
    );
    assert_eq!(rig.rtc.reading_unix_s(), Some(t.unix_seconds()));
    assert_eq!(rig.rtc.datetime().unwrap().unix_seconds(), t.unix_seconds());
    assert_eq!(rig.rtc.sets, 1);

    // After a power loss: the clock reads 2000-01-01 and says so; the set
    // clears the flag.
    rig.rtc.power_loss();
    assert!(rig.rtc.oscillator_stopped());
    assert_eq!(rig.rtc.lost_power(), Ok(true));
    assert_eq!(
        rig.send("time set 2026-06-21T12:00:00Z"),
        "ok utc=2026-06-21T12:00:00Z\n"
    );
    assert_eq!(rig.rtc.reading_unix_s(), Some(t.unix_seconds()));
    assert!(!rig.rtc.oscillator_stopped());
    assert_eq!(rig.rtc.lost_power(), Ok(false));
    assert_eq!(rig.rtc.sets, 2);

    // The clock runs on from there.
    rig.rtc.advance(utc("2026-03-20T08:01:00Z"));
    assert_eq!(rig.rtc.reading_unix_s(), Some(t.unix_seconds() + 60));

    // Lower-case `t` and `z` are accepted too.
    assert_eq!(
        rig.send("TIME SET 2026-06-21t12:30:00z"),
        "ok utc=2026-06-21T12:30:00Z\n"
    );
    assert_eq!(rig.rtc.sets, 3);
}

#[test]
fn time_set_refuses_what_is_not_an_instant() {
    let mut rig = mem_rig();
    let before = rig.rtc.reading_unix_s();
    for bad in [
        "time set 2026-02-30T00:00:00Z",
        "time set 2026-06-21T12:00:00",
        "time set 2026-06-21_12:00:00Z",
        "time set 2026-06-21T24:00:00Z",
        "time set 2026-13-01T00:00:00Z",
        "time set 26-06-21T12:00:00Z",
    ] {
        assert_eq!(
            rig.send(bad),
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
            "{bad}"
        );
    }
    assert_eq!(rig.send("time set"), "error missing argument\n");
    assert_eq!(
        rig.send("time set 2026-06-21T12:00:00Z now"),
        "error unexpected argument\n"
    );
    assert_eq!(rig.send("time"), "error unknown command\n");
    assert_eq!(rig.rtc.reading_unix_s(), before);
    assert_eq!(rig.rtc.sets, 0);

    // Valid instants outside this firmware's dates (1024 weeks from
    // 2026-01-01, src/time/window.rs), where the tracker would not trust
    // the RTC: refused before the RTC is touched (year 0 is also outside
    // the RTC's calendar, which starts in year 1).
    for t in [
        "0000-06-21T12:00:00Z",
        "2025-12-31T23:59:59Z",
        "2046-01-01T00:00:00Z",
    ] {
        assert_eq!(
            rig.send(&format!("time set {t}")),
            "error time set: outside this firmware's dates\n",
            "{t}"
        );
    }
    assert_eq!(rig.rtc.sets, 0);

    // A clock that does not answer.
    rig.rtc.bus_error = true;
    assert_eq!(
        rig.send("time set 2026-06-21T12:00:00Z"),
        "error time set: the RTC did not answer\n"
    );
    rig.rtc.bus_error = false;
    assert_eq!(rig.rtc.sets, 0);
}

// ---------------------------------------------------------------------------
// What the image does not offer

#[test]
fn tracker_commands_are_not_on_this_image() {
    let mut rig = mem_rig();
    for (line, name) in [
        ("status", "status"),
        ("stow", "stow"),
        ("resume", "resume"),
        ("home", "home"),
        ("jog c 5", "jog"),
        ("jog a -2.5", "jog"),
        ("manual off", "manual off"),
        ("faults", "faults"),
        ("clear", "clear"),
    ] {
        assert_eq!(
            rig.send(line),
            format!("error {name}: not on this image\n"),
            "{line}"
        );
    }
    assert_eq!(rig.send("set wind.stow_hz 30"), "error unknown key\n");
    assert_eq!(rig.send("get wind.stow_hz"), "error unknown key\n");
    assert_eq!(rig.send("get site.elevation_m"), "error unknown key\n");
    assert_eq!(
        rig.send("get site.postal_code"),
        "error site.postal_code: set only\n"
    );
    assert_eq!(rig.send("frobnicate"), "error unknown command\n");
    assert_eq!(rig.send("jog x 5"), "error axis must be c or a\n");
    assert_eq!(rig.send("save now"), "error unexpected argument\n");
    assert_eq!(rig.settings(), settings::DEFAULTS);
    assert_eq!(rig.rtc.sets, 0);
}

/// The postal-code table (`data/postal_codes.csv`, stored at 1e-4°):
/// `DZ,16000,Alger Gare,36.779443,3.061738`, `DZ,09000,Blida,36.473571,
/// 2.832315` typed without its leading zero (the paper prints "9000").
#[test]
fn postal_code_sets_the_site_with_or_without_leading_zero() {
    let mut rig = mem_rig();
    assert_eq!(
        rig.send("set site.postal_code DZ:16000"),
        "ok site.lat_deg=36.7794 site.lon_deg=3.0617\n"
    );
    assert_eq!(
        rig.send("set site.postal_code DZ:9000"),
        "ok site.lat_deg=36.4736 site.lon_deg=2.8323\n"
    );
    let s = rig.settings();
    assert!((s.lat_deg - 36.4736).abs() < 1e-5 && (s.lon_deg - 2.8323).abs() < 1e-5);
    assert_eq!(s.gear_ratio, settings::DEFAULTS.gear_ratio);
    // Not in the table, or not a code: refused, the site unchanged.
    assert_eq!(
        rig.send("set site.postal_code DZ:99999"),
        "error site.postal_code: not in the table\n"
    );
    assert_eq!(
        rig.send("set site.postal_code 16000"),
        "error site.postal_code: expected CC:CODE, e.g. DZ:16000\n"
    );
    assert_eq!(rig.settings(), s);
}

#[test]
fn help_lists_the_commands_and_keys() {
    let mut rig = mem_rig();
    let reply = rig.send("help");
    assert!(!reply.is_empty());
    for l in reply.lines() {
        assert!(l.starts_with("ok "), "{l:?}");
    }
    for word in [
        "get",
        "set",
        "save",
        "load",
        "defaults",
        "set site.postal_code CC:CODE",
        "time set YYYY-MM-DDTHH:MM:SSZ",
    ] {
        assert!(reply.contains(word), "{word} in {reply:?}");
    }
    for k in settings::KEYS.iter() {
        assert!(
            reply.contains(&k.name().to_string()),
            "{} in {reply:?}",
            k.name()
        );
    }
    assert_eq!(rig.send("help me"), "error unexpected argument\n");
}

// ---------------------------------------------------------------------------
// The line buffer and noise

#[test]
fn a_line_too_long_is_refused_and_the_next_one_works() {
    let mut rig = mem_rig();
    // 64 bytes is the longest line: answered.
    let longest = format!("{:<64}", "get site.lat_deg");
    assert_eq!(longest.len(), 64);
    assert_eq!(rig.send(&longest), "ok site.lat_deg=11.9683\n");
    // 65 bytes: refused once, at its end.
    let too_long = format!("{:<65}", "set site.lat_deg 45");
    assert_eq!(rig.send(&too_long), "error line too long\n");
    assert_eq!(rig.settings(), settings::DEFAULTS);
    // Much longer, in pieces: refused once.
    rig.console.input(&[b'x'; 500], &mut rig.rtc, &mut rig.out);
    assert_eq!(rig.out.take(), "");
    assert_eq!(rig.feed(b"\n"), "error line too long\n");
    assert_eq!(rig.send("set site.lat_deg 45"), "ok site.lat_deg=45\n");
    // Other refused lines, each answered once.
    assert_eq!(
        rig.feed(b"get \x01site.lat_deg\n"),
        "error control character\n"
    );
    assert_eq!(
        rig.feed(b"get site.lat_deg\xC3\xA9\n"),
        "error non-ASCII input\n"
    );
    // Blank lines get no reply; backspace edits.
    assert_eq!(rig.feed(b"\r\n\n   \n"), "");
    assert_eq!(
        rig.feed(b"get site.lon_degX\x08\n"),
        "ok site.lon_deg=8.4261\n"
    );
}

/// A small deterministic generator (xorshift64).
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

#[test]
fn noise_never_panics_and_the_console_answers_after_it() {
    for seed in [0x9E37_79B9_7F4A_7C15u64, 0xD1B5_4A32_D192_ED03, 1] {
        let mut rig = mem_rig();
        rig.send("set site.lat_deg -33.8688 site.lon_deg 151.2093");
        let mut rng = XorShift(seed);
        let noise: Vec<u8> = (0..10 * 1024).map(|_| (rng.next() >> 32) as u8).collect();
        // In pieces of 1..=64 bytes, polled in between as the loop does.
        let mut replies = String::new();
        let mut rest = &noise[..];
        while !rest.is_empty() {
            let n = (1 + (rng.next() % 64) as usize).min(rest.len());
            let (piece, tail) = rest.split_at(n);
            replies.push_str(&rig.feed(piece));
            rest = tail;
        }
        for l in replies.lines() {
            assert!(
                l.starts_with("ok ") || l.starts_with("error "),
                "seed {seed:#x}: {l:?}"
            );
        }
        assert!(!replies.is_empty(), "seed {seed:#x}: noise has line ends");
        // End the noise's partial line (its reply, if any, is dropped).
        rig.feed(b"\n");
        assert_eq!(rig.settings(), sydney(), "seed {seed:#x}");
        assert_eq!(
            rig.send("get site.lat_deg"),
            "ok site.lat_deg=-33.8688\n",
            "seed {seed:#x}"
        );
    }
}
