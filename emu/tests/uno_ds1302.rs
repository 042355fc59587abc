//! The Uno's `ds1302` build (a DS1302 on A1–A3 instead of the DS3231:
//! `boards/uno/src/lib.rs`, `drivers/src/rtc/ds1302.rs`) on the harness's Uno
//! bench with the DS1302 model (`suntracker_emu::models::ds1302`, pin level:
//! CE, SCLK and the open-drain I/O line with its 10 kΩ pull-up), asserting on
//! what the pins did as well as on the log.
//!
//! Gated: the tracker's tests run only when `SUNTRACKER_EMU_ELF_UNO_DS1302`
//! names its ELF, the settings image's only when
//! `SUNTRACKER_EMU_ELF_UNO_SETTINGS_DS1302` does (both from
//! `build_avr_uno_ds1302_emu` in `.ci/firmware_env.sh`); otherwise each
//! prints "skipped: … not set" and passes.
//!
//! References as in `uno_scenarios.rs` (`uno_common`): SPA's sun at Kano, the
//! library's forward function for the panel normal, the pose decoded from
//! the encoder models. The clock the tracker must read is the model's,
//! which shows the bench's emulated UTC; the register bytes the settings
//! image must write are the datasheet's layout (Table 3) of the time typed.

use suntracker_emu::log::{format_utc, Event};
use suntracker_emu::models::ds1302::{Ds1302, Outcome, Rule, Supply};
use suntracker_emu::uno::{UnoBench, UnoRun};
use suntracker_emu::Rtc;

#[macro_use]
mod uno_common;
use uno_common::*;

/// The DS1302 model at the end of a run: no contention on I/O, no timing
/// rule of its AC table (5 V column, an Uno's) broken; the shortest times
/// printed, and held to the 2.0 V column too (what `drivers::rtc::Ds1302`
/// says it meets).
fn assert_clean_pins(name: &str, run: &UnoRun) -> Ds1302 {
    let ds = run.ds1302.clone().expect("a DS1302 model");
    println!(
        "{name}: DS1302: {} transfers, {} contentions, {} timing violations; shortest times \
         the image gave: {}",
        ds.transfers.len(),
        ds.contentions,
        ds.violation_count,
        ds.shortest_summary()
    );
    assert_eq!(
        ds.contentions, 0,
        "{name}: the MCU drove I/O while the DS1302 did, first at {:?} ns",
        ds.contention_at_ns
    );
    assert_eq!(ds.supply_column(), Supply::V5_0);
    assert_eq!(ds.violation_count, 0, "{name}: {:?}", ds.violations);
    for rule in Rule::ALL {
        if let Some(t) = ds.shortest(rule) {
            let min = Supply::V2_0.min_ns(rule);
            assert!(
                t >= min,
                "{name}: {} {t} ns, under the 2.0 V column's {min} ns",
                rule.symbol()
            );
        }
    }
    ds
}

/// (a) A DS1302 that kept time: the tracker reads it at every tick, logs
/// the time it holds and tracks as with the DS3231: every set-point on the
/// grid, its commanded normal within 0.03° of SPA's sun at Kano, reached
/// within one encoder count by the end of its slot.
#[test]
fn uno_ds1302_tracks_from_the_clock_it_reads() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO_DS1302");
    let start = t("2026-03-20T09:00:00Z");
    let run = UnoBench::new(&elf)
        .ds1302()
        .start(start)
        .run_minutes(60.0)
        .unwrap();
    report("uno ds1302", &run);
    assert_tracks_at_kano_from_the_rtc("uno ds1302", &run);
    // The time logged is the model's: the bench's emulated UTC when read
    // (the line completes within the tick that read it).
    let (line, read) = run
        .lines
        .iter()
        .find_map(|l| match &l.event {
            Event::Time { source, unix_s } if source == "rtc" => Some((l, *unix_s)),
            _ => None,
        })
        .expect("a time line");
    let lag_s = line.utc_s - read as f64;
    println!(
        "uno ds1302: time logged {} at bench time {:.3} s after it",
        format_utc(read),
        lag_s
    );
    assert!((0.0..2.0).contains(&lag_s), "{}", line.text);

    let check = check_setpoints(&run);
    println!(
        "uno ds1302: {} set-points ({} checked at the end of their slot), commanded normal \
         within {:.4}° of SPA, reach: worst {:.2} counts, (decoded − logged) in counts per axis \
         {:?}",
        check.n, check.reached, check.worst_normal_deg, check.worst_reach_counts, check.histogram
    );
    assert!(check.reached >= 14, "{} set-points reached", check.reached);
    assert!(check.off.is_empty(), "not reached: {:?}", check.off);
    assert_ram("uno ds1302", &run, RAM_BUDGET_B);

    // On the pins: only reads (the tracker never writes a running clock),
    // the seconds (81h, CH clear) and a clock burst (BFh) at every tick.
    let ds = assert_clean_pins("uno ds1302", &run);
    let count = |c: u8| ds.transfers.iter().filter(|t| t.command == c).count();
    let (seconds, bursts) = (count(0x81), count(0xBF));
    println!("uno ds1302: {seconds} seconds reads (81h), {bursts} clock bursts (BFh)");
    for t in &ds.transfers {
        assert!(
            t.outcome == Outcome::Read && matches!(t.command, 0x81 | 0xBF),
            "{t:?}"
        );
        let want = if t.command == 0x81 { 1 } else { 7 };
        assert_eq!(t.bytes.len(), want, "{t:?}");
        assert_eq!(t.bytes[0] & 0x80, 0, "CH read set: {t:?}");
    }
    // One of each a tick, about a second apart: a tick comes 1,000 ms of
    // the image's clock after the last one's pass began, and at 60× that
    // clock steps 60 ms a Timer0 tick and a pass's CPU milliseconds (the
    // sun's position at a slot's start) are 60 emulated ones each.
    let starts: Vec<f64> = ds
        .transfers
        .iter()
        .filter(|t| t.command == 0xBF)
        .map(|t| t.at_emu_s)
        .collect();
    let gaps = starts.windows(2).map(|w| w[1] - w[0]);
    let (shortest, longest) = gaps.fold((f64::INFINITY, 0.0f64), |(a, b), g| (a.min(g), b.max(g)));
    println!(
        "uno ds1302: clock bursts {shortest:.3} to {longest:.3} emulated s apart, the first at {:.3} s",
        starts.first().copied().unwrap_or(f64::NAN)
    );
    assert_eq!(seconds, bursts);
    assert!(starts.first().is_some_and(|&s| s < 3.0), "no read at boot");
    assert!(
        shortest >= 0.5 && longest <= 1.5,
        "clock bursts {shortest:.3} to {longest:.3} s apart"
    );
    assert_eq!(ds.time_writes, 0);
}

/// (b) A DS1302 that lost power (CH set: its oscillator stopped) is reported
/// as the DS3231 that lost power is (`uno_scenarios.rs`): `fault rtc_invalid`,
/// `mode wait_for_time`, no set-point, the panel flat; the image reads the
/// seconds register only and writes nothing. With the DS3231 build too
/// (`SUNTRACKER_EMU_ELF_UNO`), the two images' mode and fault lines are the
/// same.
#[test]
fn uno_ds1302_with_the_clock_halted_waits_flat() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO_DS1302");
    let bench = |elf: &std::path::Path| {
        UnoBench::new(elf)
            .start(t("2026-03-20T10:00:00Z"))
            .rtc(Rtc::LostPower)
    };
    let run = bench(&elf).ds1302().run_minutes(20.0).unwrap();
    assert_waits_flat("uno ds1302 halted", &run, "rtc_invalid");
    let ds = assert_clean_pins("uno ds1302 halted", &run);
    assert!(ds.halted(), "the image started the clock");
    assert!(!ds.transfers.is_empty());
    for t in &ds.transfers {
        assert!(
            t.outcome == Outcome::Read && t.command == 0x81 && t.bytes == [0x80],
            "{t:?}"
        );
    }
    let events = |run: &UnoRun| -> Vec<String> {
        run.lines
            .iter()
            .filter(|l| matches!(l.event, Event::Mode(_) | Event::Fault { .. }))
            .map(|l| l.text.clone())
            .collect()
    };
    if let Some(ds3231) = std::env::var_os("SUNTRACKER_EMU_ELF_UNO") {
        let other = bench(std::path::Path::new(&ds3231))
            .run_minutes(20.0)
            .unwrap();
        println!("uno ds1302 halted: mode and fault lines {:?}", events(&run));
        assert_eq!(events(&run), events(&other), "against the DS3231 build");
    }
}

/// (c) The settings image sets the DS1302 from its console: `time set`
/// answered, and on the pins WP cleared (8Eh ← 00h) then a clock burst
/// (BEh) of the typed time with WP set again: 00 s, 00 min, 04 h (24-hour
/// mode), date 20, month 03, day 6 (2026-03-20 is a Friday; 1 = Sunday, the
/// driver's convention), year 26, control 80h. The chip lost power (CH and
/// WP set) before: the registers then hold the typed time, running.
#[test]
fn uno_ds1302_settings_image_sets_the_clock() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO_SETTINGS_DS1302");
    let typed = "time set 2026-03-20T04:00:00Z";
    let run = UnoBench::settings(&elf)
        .ds1302()
        .start(t("2026-03-20T03:00:00Z"))
        .rtc(Rtc::LostPower)
        .type_at(1.0 / 60.0, typed)
        .run_minutes(6.0 / 60.0)
        .unwrap();
    for l in &run.lines {
        println!("  {} | {}", format_utc(l.utc_s as i64), l.text);
    }
    assert_eq!(run.cpu, suntracker_emu::sim::CpuState::Running);
    assert_eq!(replies_to(&run, typed), ["ok utc=2026-03-20T04:00:00Z"]);
    let ds = assert_clean_pins("uno ds1302 settings", &run);
    let writes: Vec<_> = ds.transfers.iter().filter(|t| t.command & 1 == 0).collect();
    println!("uno ds1302 settings: writes {writes:?}");
    assert_eq!(writes.len(), 2, "{writes:?}");
    assert!(writes[0].is_write(0x8E, &[0x00]), "{:?}", writes[0]);
    let burst = [0x00, 0x00, 0x04, 0x20, 0x03, 0x06, 0x26, 0x80];
    assert!(writes[1].is_write(0xBE, &burst), "{:?}", writes[1]);
    // Set at the typed line (1 s), 5 s before the end: 04:00:05, give or
    // take the second the set came in.
    let end = t("2026-03-20T04:00:00Z") + 5;
    let shown = ds.unix_at(run.emulated_s);
    let regs = ds.clock_burst(run.emulated_s);
    println!(
        "uno ds1302 settings: at the end {} registers {regs:02x?}",
        format_utc(shown)
    );
    assert!((shown - end).abs() <= 1, "shows {}", format_utc(shown));
    assert_eq!(regs[1..], burst[1..], "minutes … control");
    assert!(!ds.halted() && ds.write_protected());
    assert_eq!(ds.time_writes, 1);
    assert_ram("uno ds1302 settings", &run, SETTINGS_RAM_BUDGET_B);
}

/// No DS1302 fitted: nothing drives I/O, the pull-up holds it high, and the
/// seconds register reads FFh, CH set: the three-wire bus has no
/// acknowledge, so the image reports the clock as one that lost power
/// (`fault rtc_invalid`; the DS3231 build's missing acknowledge is
/// `bus_rtc`), waits and lays the panel flat.
#[test]
fn uno_ds1302_absent_reads_as_halted_and_waits_flat() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO_DS1302");
    let run = UnoBench::new(&elf)
        .ds1302()
        .start(t("2026-03-20T10:00:00Z"))
        .rtc(Rtc::Absent)
        .run_minutes(20.0)
        .unwrap();
    assert!(run.ds1302.is_none() && run.rtc.is_none());
    assert_waits_flat("uno ds1302 absent", &run, "rtc_invalid");
}
