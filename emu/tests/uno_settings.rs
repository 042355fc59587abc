//! The Arduino Uno's settings, on the harness's Uno bench
//! (`suntracker_emu::uno`): the settings image (`avr_settings`, the
//! configuration console on USART0) writes them into the ATmega328P's
//! EEPROM, and the tracker image (`avr_tracker`, no console) loads the
//! newest good copy of the two-slot store at power-on.
//!
//! Gated: the tracker's tests run only when `SUNTRACKER_EMU_ELF_UNO` names
//! its ELF, the settings image's only when `SUNTRACKER_EMU_ELF_UNO_SETTINGS`
//! names its ELF (both from `build_avr_uno_emu` in `.ci/firmware_env.sh`);
//! the test of the board builds, the ELFs a user flashes, only when
//! `SUNTRACKER_EMU_ELF_UNO_RELEASE` and `SUNTRACKER_EMU_ELF_UNO_SETTINGS_RELEASE`
//! name them (`build_avr_uno`: `$ELF_AVR_UNO`, `$ELF_AVR_SETTINGS`);
//! otherwise each prints "skipped: … not set" and passes.
//!
//! The settings image runs at 1:1 (it logs no timescale: emulated time is
//! CPU time), its typed lines at 115,200 baud. EEPROM contents the tests
//! make themselves come from the library's own store
//! (`suntracker::servo_tracker::settings::SettingsStore` over
//! `suntracker::persist::MemStorage`), as a host tool would make them.
//! References, as in `uno_scenarios.rs`: the sun is the harness's SPA
//! (`suntracker_emu::uno::spa`: sun_algos, `f64`, geometric) at the stored
//! site and the set-point's UTC; the panel normal of a pose is
//! `suntracker::attitude`'s `MountAttitude::normal_xyz` for the level mount
//! (either branch of the Uno's convention, `c = 180° − azimuth, a =
//! −zenith` or `c = −azimuth, a = +zenith`, faces the sun); the pose the
//! axes reached is the one decoded from the encoder models' counts at the
//! end of each set-point's slot.

use std::path::{Path, PathBuf};

use suntracker::attitude::{angle_between_deg, sun_vector_xyz, MountAttitude, Pose};
use suntracker::persist::{MemStorage, Record};
use suntracker::servo_tracker::settings::{Settings, SettingsStore, DEFAULTS, EEPROM_LEN};
use suntracker_emu::log::{format_utc, Event};
use suntracker_emu::script::xorshift32_noise;
use suntracker_emu::sim::ElfIdentity;
use suntracker_emu::uno::{spa, UnoBench, UnoRun};
use suntracker_emu::Rtc;

#[macro_use]
mod uno_common;
use uno_common::*;

/// Sydney, the site typed and stored.
const SYDNEY: (f64, f64) = (-33.8688, 151.2093);
/// A slot's header: magic, version, length, then the sequence number at
/// bytes 8..12 (`src/persist/store.rs`, "Slot layout").
const HEADER_LEN: usize = 12;
const SEQ_AT: usize = 8;

/// The board build of an image named by `var`, the ELF a user flashes, if
/// set: its identity printed (`.ci/run` compares the SHA-256 with the
/// release ELF's) and asserted to be no emulation build.
fn flashed_elf(var: &str) -> Option<(PathBuf, ElfIdentity)> {
    let elf = PathBuf::from(std::env::var_os(var)?);
    let id = ElfIdentity::of_board_build(&elf).unwrap();
    println!("{id}");
    Some((elf, id))
}

/// Emulated minutes of `s` seconds (the settings image's clock is 1:1).
fn min(s: f64) -> f64 {
    s / 60.0
}

/// The EEPROM after saving each of `saves` in turn through the library's
/// store, from erased.
fn eeprom_after(saves: &[Settings]) -> Vec<u8> {
    let mut store = SettingsStore::for_record(MemStorage::<EEPROM_LEN>::new());
    for s in saves {
        store.save(s).unwrap();
    }
    store.release().bytes.to_vec()
}

/// The settings the library's store loads from `eeprom`, and whether they
/// are the defaults (no good copy).
fn library_load(eeprom: &[u8]) -> (Settings, bool) {
    let mut storage = MemStorage::<EEPROM_LEN>::new();
    storage.bytes.copy_from_slice(eeprom);
    let loaded = SettingsStore::for_record(storage).load();
    (loaded.config, loaded.defaults)
}

fn sydney() -> Settings {
    Settings {
        lat_deg: SYDNEY.0 as f32,
        lon_deg: SYDNEY.1 as f32,
        ..DEFAULTS
    }
}

/// Bytes of a slot of the settings record (its own length: the
/// configuration's may differ).
const SLOT_LEN: usize = <Settings as Record>::SLOT_LEN;

/// The sequence number in slot `slot`'s header.
fn seq_of(eeprom: &[u8], slot: usize) -> u32 {
    let at = slot * SLOT_LEN + SEQ_AT;
    u32::from_le_bytes(eeprom[at..at + 4].try_into().unwrap())
}

/// The settings image from an erased EEPROM: Sydney typed, two refusals,
/// the gear unchanged, saved; the RTC set. The EEPROM it leaves.
fn settings_run(elf: &Path) -> UnoRun {
    let run = UnoBench::settings(elf)
        .start(t("2026-03-20T03:00:00Z"))
        .rtc(Rtc::LostPower)
        .type_at(min(1.0), "set site.lat_deg -33.8688")
        .type_at(min(1.5), "set site.lon_deg 151.2093")
        .type_at(min(2.0), "set axis.c.gear_ratio 20000")
        .type_at(min(2.5), "set axis.c.gear_ratio 1e30")
        .type_at(min(3.0), "get axis.c.gear_ratio")
        .type_at(min(3.5), "save")
        .type_at(min(5.0), "time set 2026-03-20T04:00:00Z")
        .run_minutes(min(10.0))
        .unwrap();
    report("uno settings", &run);
    run
}

/// The settings image: exact replies, the EEPROM it writes (read back by
/// the library's own store as Sydney), the RTC it sets, its RAM.
#[test]
fn uno_settings_image_saves_the_site_typed() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO_SETTINGS");
    assert_settings_saved(&settings_run(&elf));
}

/// What the settings image did in [`settings_run`]: each reply exact, the
/// EEPROM it leaves loads as Sydney through the library's store and is the
/// library's own save of those settings, the DS3231 set, the RAM in budget.
fn assert_settings_saved(run: &UnoRun) {
    let texts = texts(run);
    assert!(texts.contains(&"config source=defaults"), "{texts:?}");
    for (typed, want) in [
        ("set site.lat_deg -33.8688", "ok site.lat_deg=-33.8688"),
        ("set site.lon_deg 151.2093", "ok site.lon_deg=151.2093"),
        (
            "set axis.c.gear_ratio 20000",
            "error axis.c.gear_ratio: 1...10,000 motor revolutions per axis revolution",
        ),
        ("get axis.c.gear_ratio", "ok axis.c.gear_ratio=1"),
        ("save", "ok save"),
        (
            "time set 2026-03-20T04:00:00Z",
            "ok utc=2026-03-20T04:00:00Z",
        ),
    ] {
        assert_eq!(replies_to(run, typed), [want], "replies to {typed:?}");
    }
    let huge = replies_to(run, "set axis.c.gear_ratio 1e30");
    assert!(
        huge.len() == 1 && huge[0].starts_with("error axis.c.gear_ratio: "),
        "replies to 1e30: {huge:?}"
    );
    assert_eq!(
        texts.iter().filter(|l| l.starts_with("boot ")).count(),
        1,
        "restarted"
    );

    // The EEPROM: the library's store loads Sydney from it, and it holds
    // what the library's own save of those settings writes.
    let (loaded, defaults) = library_load(&run.eeprom);
    assert!(!defaults, "no good copy in the EEPROM the image saved");
    assert_eq!(loaded, sydney(), "the settings the library loads");
    let same = run.eeprom == eeprom_after(&[sydney()]);
    println!("uno settings: EEPROM byte for byte the library's save of the same settings: {same}");
    assert!(same, "the image's save differs from the library's");

    // The RTC: set to 04:00:00 at 5 s (lost power before), 5 s before the
    // end.
    let rtc = run.rtc.as_ref().expect("a DS3231");
    println!(
        "uno settings: DS3231 at the end {} (OSF {}), {} time writes",
        format_utc(rtc.unix_s),
        rtc.osf,
        rtc.time_writes
    );
    assert!(!rtc.osf, "the oscillator-stop flag is still set");
    let end = t("2026-03-20T04:00:00Z") + 5;
    assert!(
        (rtc.unix_s - end).abs() <= 1,
        "the DS3231 shows {}",
        format_utc(rtc.unix_s)
    );
    assert_ram("uno settings", run, SETTINGS_RAM_BUDGET_B);
}

/// 10 KB of noise into the settings image: the lines it ends are answered
/// with errors, nothing is saved, no watchdog reset, and a command after
/// it is answered.
#[test]
fn uno_settings_image_survives_noise() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO_SETTINGS");
    // The Mega scenario's noise: lines of garbage, some ended by the 0x0A
    // bytes among them, and a last partial one.
    let noise = xorshift32_noise(0x2545_f491, 10_240);
    let eeprom = eeprom_after(&[sydney()]);
    let run = UnoBench::settings(&elf)
        .start(t("2026-03-20T03:00:00Z"))
        .eeprom(eeprom.clone())
        // 10,240 bytes take 0.87–0.92 s at 115,200 baud.
        .bytes_at(min(1.0), noise)
        // An end of line closes the noise's last partial line, then a
        // command is read as usual.
        .type_at(min(3.0), "")
        .type_at(min(3.5), "get site.lat_deg")
        .run_minutes(min(5.0))
        .unwrap();
    report("uno settings noise", &run);
    let texts = texts(&run);
    assert!(texts.contains(&"config source=stored"), "{texts:?}");
    assert_eq!(
        texts.iter().filter(|l| l.starts_with("boot ")).count(),
        1,
        "the watchdog reset the image"
    );
    let noise_at = texts
        .iter()
        .position(|l| l.starts_with("> (") && l.ends_with(" bytes)"))
        .expect("noise sent");
    let errors = texts[noise_at..]
        .iter()
        .filter(|l| l.starts_with("error "))
        .count();
    println!("uno settings noise: {errors} error replies after the noise");
    assert!(errors > 0, "the noise's lines were not answered");
    assert_eq!(
        replies_to(&run, "get site.lat_deg"),
        ["ok site.lat_deg=-33.8688"],
        "the console after the noise"
    );
    assert_eq!(run.eeprom, eeprom, "the noise changed the EEPROM");
    assert_ram("uno settings noise", &run, SETTINGS_RAM_BUDGET_B);
}

/// 80 `get site.lat_deg` pasted at once into the settings image: each
/// reply (25 bytes) takes longer to send than its line (17 bytes) to
/// arrive, so the 64-byte receive ring overflows; every line is answered
/// once all the same, by its reply or `error input lost` (the line a gap
/// falls in, and each line the ring lost whole), and the next line typed
/// runs whole.
#[test]
fn uno_settings_image_answers_every_pasted_line() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO_SETTINGS");
    let eeprom = eeprom_after(&[sydney()]);
    let run = UnoBench::settings(&elf)
        .start(t("2026-03-20T03:00:00Z"))
        .eeprom(eeprom.clone())
        .bytes_at(min(1.0), b"get site.lat_deg\n".repeat(80))
        .type_at(min(3.5), "get site.lon_deg")
        .run_minutes(min(5.0))
        .unwrap();
    report("uno settings paste", &run);
    let texts = texts(&run);
    let pasted_at = texts
        .iter()
        .position(|l| l.starts_with("> (") && l.ends_with(" bytes)"))
        .expect("lines pasted");
    let typed_at = texts
        .iter()
        .position(|l| *l == "> get site.lon_deg")
        .expect("line typed");
    let answers = &texts[pasted_at..typed_at];
    let ok = answers
        .iter()
        .filter(|l| **l == "ok site.lat_deg=-33.8688")
        .count();
    let lost = answers.iter().filter(|l| **l == "error input lost").count();
    println!("uno settings paste: 80 lines, {ok} answered, {lost} `error input lost`");
    assert!(lost > 0, "the ring never overflowed: {answers:?}");
    assert_eq!(ok + lost, 80, "{answers:?}");
    assert_eq!(
        answers
            .iter()
            .filter(|l| l.starts_with("ok ") || l.starts_with("error "))
            .count(),
        80,
        "{answers:?}"
    );
    assert_eq!(
        replies_to(&run, "get site.lon_deg"),
        ["ok site.lon_deg=151.2093"]
    );
    assert_eq!(run.eeprom, eeprom, "the paste changed the EEPROM");
    assert_ram("uno settings paste", &run, SETTINGS_RAM_BUDGET_B);
}

/// The tracker from the EEPROM the settings image saved: Sydney at boot
/// and again after a power cut (the EEPROM kept), every set-point on
/// Sydney's sun and reached.
#[test]
fn uno_tracks_sydney_from_the_saved_eeprom_over_a_power_cut() {
    let settings = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO_SETTINGS");
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO");
    let eeprom = settings_run(&settings).eeprom;
    tracks_sydney_over_a_cut("uno sydney", &elf, &eeprom, 20.0, 45.0);
}

/// The board builds, the ELFs a user flashes (`build_avr_uno`, not the
/// emulation builds of `build_avr_uno_emu`, whose Timer0 clocks run 60×
/// fast): the very files, their SHA-256 printed (`.ci/run` compares them
/// with the release ELFs'), no time scale in them or in their logs. The
/// settings image saves Sydney as in [`settings_run`] (`save` on its
/// console: the tracker image has none); the tracker reads those settings
/// from the EEPROM at power-on and again after a power cut at minute 14,
/// 30 emulated minutes at real time (its clock 1 ms a tick as on a board,
/// the harness's 1:1 with the CPU's: the servos, the stall watch and the
/// set-point slots on one clock), every set-point on Sydney's sun within
/// 0.03° and reached within a count by the end of its slot.
#[test]
fn uno_flashed_elfs_save_then_track_sydney_over_a_power_cut() {
    let Some((settings, settings_id)) = flashed_elf("SUNTRACKER_EMU_ELF_UNO_SETTINGS_RELEASE")
    else {
        println!("skipped: SUNTRACKER_EMU_ELF_UNO_SETTINGS_RELEASE not set");
        return;
    };
    let Some((elf, id)) = flashed_elf("SUNTRACKER_EMU_ELF_UNO_RELEASE") else {
        println!("skipped: SUNTRACKER_EMU_ELF_UNO_RELEASE not set");
        return;
    };
    let saved = settings_run(&settings);
    assert_settings_saved(&saved);
    let run = tracks_sydney_over_a_cut("uno flashed", &elf, &saved.eeprom, 14.0, 30.0);
    for r in [&saved, &run] {
        assert!(
            !r.lines
                .iter()
                .any(|l| matches!(l.event, Event::Timescale(_))),
            "a timescale line from a board build"
        );
        assert_eq!(r.timescale, 1.0);
    }
    assert_eq!(
        ElfIdentity::of(&settings).unwrap(),
        settings_id,
        "the ELF changed"
    );
    assert_eq!(ElfIdentity::of(&elf).unwrap(), id, "the ELF changed");
}

/// The tracker at `elf` from `eeprom` (Sydney saved), from
/// 2026-03-20T04:00Z (15:00 in Sydney: the sun is up until about 07:10Z)
/// with the bench standing in Sydney (its panel sees Sydney's sun), the
/// power cut at emulated minute `cut_min`, for `minutes`: the stored
/// configuration and Sydney's site at both boots, the EEPROM unchanged,
/// every set-point's commanded normal on Sydney's sun and each reached by
/// the end of its slot (but the slot the cut interrupts and the last), at
/// least 3 set-points on each side of the cut, the RAM in budget.
fn tracks_sydney_over_a_cut(
    name: &str,
    elf: &Path,
    eeprom: &[u8],
    cut_min: f64,
    minutes: f64,
) -> UnoRun {
    assert_eq!(eeprom.len(), EEPROM_LEN);
    let run = UnoBench::new(elf)
        .start(t("2026-03-20T04:00:00Z"))
        .rtc(Rtc::Valid)
        .site(SYDNEY.0, SYDNEY.1)
        .eeprom(eeprom.to_vec())
        .reset_at(cut_min)
        .run_minutes(minutes)
        .unwrap();
    report(name, &run);
    let texts = texts(&run);
    let cut = texts
        .iter()
        .position(|l| *l == "# power cut")
        .expect("power cut");
    let (before, after) = texts.split_at(cut);
    for (part, lines) in [("at power-on", before), ("after the cut", after)] {
        for want in [
            "config source=stored",
            "site source=config lat=-33.8688 lon=151.2093",
        ] {
            assert!(lines.contains(&want), "{part}: no {want:?}: {lines:?}");
        }
    }
    assert_eq!(run.eeprom, eeprom, "the tracker changed the EEPROM");

    // Every set-point, before and after the cut: its commanded normal on
    // Sydney's sun, reached by the end of its slot.
    let cut_s = run.lines[cut].utc_s;
    let mut worst_normal: f64 = 0.0;
    let mut worst_reach: f64 = 0.0;
    let (mut n_before, mut n_after, mut reached) = (0, 0, 0);
    let mut unchecked = Vec::new();
    let mut last_slot_s = i64::MIN;
    for l in &run.lines {
        let Event::SetPoint {
            unix_s,
            c_deg,
            a_deg,
            ..
        } = l.event
        else {
            continue;
        };
        last_slot_s = last_slot_s.max(unix_s);
        if l.utc_s < cut_s {
            n_before += 1;
        } else {
            n_after += 1;
        }
        let (z, az) = spa(SYDNEY.0, SYDNEY.1, unix_s as f64).expect("SPA");
        let normal = MountAttitude::<f64>::level().normal_xyz(&Pose {
            gamma_deg: c_deg,
            alpha_deg: a_deg,
        });
        let err = angle_between_deg(&normal, &sun_vector_xyz(90.0 - z, az));
        worst_normal = worst_normal.max(err);
        assert!(
            err <= NORMAL_TOL_DEG,
            "{}: panel normal {err:.4}° from Sydney's sun (SPA zenith {z:.3} azimuth {az:.3})",
            l.text
        );
        // The slot the power cut interrupts cannot be finished.
        let cut_in_slot = (unix_s as f64) < cut_s && cut_s < (unix_s + run.step_s) as f64;
        if let (Some((dc, da)), false) = (run.pose_at_slot_end(unix_s), cut_in_slot) {
            let e = (dc - c_deg).abs().max((da - a_deg).abs());
            worst_reach = worst_reach.max(e / COUNT_DEG);
            assert!(
                e <= REACH_TOL_DEG,
                "{} not reached by the end of its slot: decoded c {dc:.2} a {da:.2}",
                l.text
            );
            reached += 1;
        } else {
            unchecked.push((unix_s, cut_in_slot, l.text.as_str()));
        }
    }
    println!(
        "{name}: {n_before} set-points before the cut, {n_after} after ({reached} checked \
         at the end of their slot): commanded normal within {worst_normal:.4}° of SPA's sun \
         at Sydney, reached within {worst_reach:.2} counts"
    );
    assert!(
        n_before >= 3 && n_after >= 3,
        "{n_before} set-points before the cut, {n_after} after"
    );
    // All but the slot the cut interrupted (logged before the cut and
    // again after the boot when the boot comes within it) and the last,
    // unfinished one.
    assert!(
        unchecked
            .iter()
            .all(|&(slot_s, in_cut, _)| in_cut || slot_s == last_slot_s),
        "set-points not checked at the end of their slot: {unchecked:?}"
    );
    assert_ram(name, &run, RAM_BUDGET_B);
    run
}

/// An erased EEPROM (no good copy): the defaults, Kano.
#[test]
fn uno_with_an_erased_eeprom_takes_the_defaults() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO");
    let run = UnoBench::new(&elf)
        .start(t("2026-03-20T10:00:00Z"))
        .run_minutes(3.0)
        .unwrap();
    report("uno erased", &run);
    let texts = texts(&run);
    for want in [
        "config source=defaults",
        "site source=config lat=11.9683 lon=8.4261",
    ] {
        assert!(texts.contains(&want), "no {want:?}: {texts:?}");
    }
    assert!(run.eeprom.iter().all(|&b| b == 0xFF), "the image wrote");
}

/// A save torn by a power cut (Kano saved, then Sydney, then a byte of the
/// newest copy's payload changed): the older good copy, Kano, stored.
#[test]
fn uno_with_a_torn_save_keeps_the_older_copy() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO");
    let mut eeprom = eeprom_after(&[DEFAULTS, sydney()]);
    let newest = (0..2)
        .find(|&s| seq_of(&eeprom, s) == 2)
        .expect("a slot holding seq 2");
    assert_eq!(seq_of(&eeprom, 1 - newest), 1, "the older copy");
    // A byte of the payload: the latitude's low byte.
    eeprom[newest * SLOT_LEN + HEADER_LEN] ^= 0x5A;
    assert_eq!(
        library_load(&eeprom),
        (DEFAULTS, false),
        "the test's EEPROM"
    );
    let run = UnoBench::new(&elf)
        .start(t("2026-03-20T10:00:00Z"))
        .eeprom(eeprom)
        .run_minutes(3.0)
        .unwrap();
    report("uno torn", &run);
    let texts = texts(&run);
    for want in [
        "config source=stored",
        "site source=config lat=11.9683 lon=8.4261",
    ] {
        assert!(texts.contains(&want), "no {want:?}: {texts:?}");
    }
}
