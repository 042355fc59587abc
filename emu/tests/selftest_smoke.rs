//! Smoke test of the harness against the ATmega2560 board self-test
//! (`boards/avr/src/bin/avr_board_selftest.rs`, built by `.ci/firmware_env.sh`'s
//! `build_avr_mega`). Without a TWI device the self-test expects a NACK
//! from the DS3231 address (tests/expected/avr_board_selftest.txt); with the
//! DS3231 model attached the read is answered, so that line changes from
//! `I2C error NoAcknowledge(Address) … ok` to `answered … FAIL` (the
//! self-test's own verdict, written for plain simavr) while every other
//! line stays as expected.
//!
//! The ELF: `$SUNTRACKER_EMU_ELF_SELFTEST`, else
//! `$CARGO_TARGET_DIR/mega/avr-none/release/avr_board_selftest.elf` (or
//! `target/…` at the repository root). Skipped when absent.

use std::path::PathBuf;

use suntracker_emu::{MegaBench, Rtc};

fn selftest_elf() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("SUNTRACKER_EMU_ELF_SELFTEST") {
        return Some(PathBuf::from(p));
    }
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../target")));
    let p = target.join("mega/avr-none/release/avr_board_selftest.elf");
    p.is_file().then_some(p)
}

fn expected() -> Vec<String> {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/expected/avr_board_selftest.txt"
    ))
    .unwrap()
    .lines()
    .map(str::to_string)
    .collect()
}

#[test]
fn selftest_with_ds3231_model() {
    let Some(elf) = selftest_elf() else {
        println!("skipped: avr_board_selftest.elf not built (SUNTRACKER_EMU_ELF_SELFTEST not set)");
        return;
    };
    // The self-test has no time compression: 1 emulated s = 1 CPU s.
    let run = MegaBench::mega(&elf)
        .timescale(1.0)
        .rtc(Rtc::Valid)
        .run_minutes(5.0 / 60.0)
        .unwrap();
    let got: Vec<&str> = run.lines.iter().map(|l| l.text.as_str()).collect();
    println!(
        "selftest: {} lines, {} cycles, wall {:?}, cpu {:?}",
        got.len(),
        run.cycles,
        run.wall,
        run.cpu
    );
    for l in &got {
        println!("  {l}");
    }
    let want = expected();
    assert_eq!(got.len(), want.len(), "{got:#?}");
    for (g, w) in got.iter().zip(&want) {
        if w.starts_with("twi:") {
            assert!(
                g.starts_with("twi: drivers Ds3231::datetime -> answered in "),
                "{g}"
            );
        } else if w.starts_with("watchdog:") {
            assert!(
                g.starts_with("watchdog: fed for 25") && g.ends_with(" ok"),
                "{g}"
            );
        } else {
            assert_eq!(g, w);
        }
    }
    // The program ended (interrupts off, sleep) rather than running out.
    assert_ne!(run.cpu, suntracker_emu::sim::CpuState::Running);
    // One transaction set at 0x68 at least (the read answered).
    assert!(run.twi_starts.iter().any(|&(a, n)| a == 0x68 && n >= 1));
}

#[test]
fn selftest_without_rtc_still_nacks() {
    let Some(elf) = selftest_elf() else {
        println!("skipped: avr_board_selftest.elf not built");
        return;
    };
    let run = MegaBench::mega(&elf)
        .timescale(1.0)
        .rtc(Rtc::Absent)
        .run_minutes(5.0 / 60.0)
        .unwrap();
    let got: Vec<&str> = run.lines.iter().map(|l| l.text.as_str()).collect();
    let twi = got.iter().find(|l| l.starts_with("twi:")).unwrap();
    assert!(
        twi.starts_with("twi: drivers Ds3231::datetime -> I2C error NoAcknowledge(Address)")
            && twi.ends_with(" ok"),
        "{twi}"
    );
}
