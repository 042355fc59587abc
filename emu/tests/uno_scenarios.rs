//! Scenario tests of the ATmega328P (Arduino Uno) tracker image
//! (`avr_tracker`, Chowdhury et al.'s (2019) closed-loop tracker, the emulation
//! build with time compression) on the harness's Uno bench
//! (`suntracker_emu::uno`): a DS3231 on the TWI, two FS5106R servo models
//! driven by the Timer1 pulses, turning YMT22 encoder models whose edges
//! the bench puts on PD4–PD7, home switches and hard stops, and the panel
//! voltage on ADC0.
//!
//! Gated: they run only when `SUNTRACKER_EMU_ELF_UNO` names the ELF
//! (`build_avr_uno_emu` in `.ci/firmware_env.sh`); otherwise each prints
//! "skipped: SUNTRACKER_EMU_ELF_UNO not set" and passes.
//!
//! References (`uno_common`): the sun is SPA (sun_algos, `f64`, geometric,
//! Kano 11.9683 N 8.4261 E) at the set-point's UTC; the panel normal of a
//! pose is `suntracker::attitude`'s `MountAttitude::normal_xyz` for the
//! level mount; the pose the axes reached is the one decoded from the
//! encoder models' counts, never the firmware's own idea of it; the day's
//! energy is the trapezoid rule over the bench's panel model sampled every
//! emulated second (`models::panel`).

use std::path::PathBuf;

use suntracker_emu::log::{format_utc, Event};
use suntracker_emu::uno::{Axis, UnoBench};
use suntracker_emu::Rtc;

#[macro_use]
mod uno_common;
use uno_common::*;

/// `day_energy` against the bench's trapezoid of the panel model.
const ENERGY_TOL: f64 = 0.01;

#[test]
fn uno_tracks_a_day_at_kano_from_the_rtc() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO");
    let day = t("2026-03-20T00:00:00Z");
    // CI checks this day's set-points against pvlib from the log written
    // here (`.ci/run`, step uno_day), rather than emulating the day twice.
    let log = std::env::var_os("SUNTRACKER_EMU_UNO_DAY_LOG").map(PathBuf::from);
    let run = UnoBench::new(&elf)
        .start(day)
        .log_to(log)
        .run_minutes(1_440.0)
        .unwrap();
    report("uno day", &run);
    assert_tracks_at_kano_from_the_rtc("uno day", &run);

    // Every set-point: on the grid, served within the tick, its commanded
    // normal on SPA's sun, reached by the end of its slot.
    let check = check_setpoints(&run);
    assert_eq!(check.reached, check.n, "the run ends after the last slot");
    // The expected count: every slot start of the day with the sun up by
    // SPA (the firmware decides with michalsky at the same instants).
    let up = (0..86_400 / STEP_S)
        .filter(|k| kano(day + k * STEP_S).0 < 90.0)
        .count() as i64;
    let n = check.n as i64;
    let energy = run.energy_check().expect("a day_energy line after sunset");
    let stalls = fault_times(&run, "motor_stalled_c", true).len()
        + fault_times(&run, "motor_stalled_a", true).len();
    let off = &check.off;
    println!(
        "uno day: {n} set-points (SPA has the sun up at {up} slot starts), commanded normal \
         within {:.4}° of SPA, reach: worst {:.2} counts from the logged pose, (decoded − \
         logged) in counts per axis {:?}; {} set-points off by more than one count",
        check.worst_normal_deg,
        check.worst_reach_counts,
        check.histogram,
        off.len()
    );
    println!(
        "uno day: day_energy {:.3} V·h logged, {:.3} V·h by the trapezoid of the panel model \
         every emulated second from {} to {} ({} samples): {:+.3} %",
        energy.logged_vh,
        energy.model_vh,
        format_utc(energy.from_utc_s),
        format_utc(energy.to_utc_s),
        energy.samples,
        100.0 * energy.relative_error()
    );
    println!(
        "uno day: motor_stalled raised {stalls} times with free shafts; peak stack {} B, \
         wall {:.1} s",
        run.ram.stack_sp_bytes,
        run.wall.as_secs_f64()
    );
    for o in off.iter().take(20) {
        println!("  off: {o}");
    }
    assert!((n - up).abs() <= 1, "{n} set-points, SPA says {up}");
    assert!(
        off.is_empty(),
        "{} of {n} set-points not reached within one count by the end of their slot, e.g. {}",
        off.len(),
        off[0]
    );
    assert!(
        energy.relative_error().abs() <= ENERGY_TOL,
        "day_energy {:.3} V·h vs the model's {:.3} V·h",
        energy.logged_vh,
        energy.model_vh
    );
    // The day ends at night, panel flat (A within a count of 0°).
    let last_mode = run
        .lines
        .iter()
        .rev()
        .find(|l| matches!(l.event, Event::Mode(_)))
        .expect("a mode line");
    assert_eq!(last_mode.text, "mode night");
    let last_sp = setpoints(&run).last().map_or(0, |s| s.unix_s);
    assert!(last_mode.utc_s > last_sp as f64);
    let a_end = run.axes[1].decoded_deg;
    assert!(a_end.abs() <= COUNT_DEG, "not flat at night: A {a_end:.2}°");
    assert_ram("uno day", &run, RAM_BUDGET_B);
}

/// The stall watch must not fire on shafts that turn freely: a move takes
/// its first encoder count well inside the 5 s the firmware allows.
#[test]
fn uno_free_shafts_raise_no_stall_fault() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO");
    let run = UnoBench::new(&elf)
        .start(t("2026-03-20T05:30:00Z"))
        .run_minutes(40.0)
        .unwrap();
    report("uno free shafts", &run);
    assert!(has(&run, "mode tracking"));
    let stalls: Vec<&str> = run
        .lines
        .iter()
        .filter(|l| l.text.starts_with("fault motor_stalled"))
        .map(|l| l.text.as_str())
        .collect();
    assert!(
        stalls.is_empty(),
        "{} motor_stalled lines with free shafts (no stall injected), first {:?}",
        stalls.len(),
        stalls.first()
    );
}

#[test]
fn uno_recovers_from_a_ten_minute_stall() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO");
    let stall_from = t("2026-03-20T10:00:00Z");
    let stall_s = 600.0;
    let run = UnoBench::new(&elf)
        .start(t("2026-03-20T09:40:00Z"))
        .stall(Axis::C, stall_from as f64, stall_s)
        .run_minutes(50.0)
        .unwrap();
    report("uno stall", &run);
    let free_at = stall_from as f64 + stall_s;
    let raised = fault_times(&run, "motor_stalled_c", true);
    let cleared = fault_times(&run, "motor_stalled_c", false);
    // The fault in force when the shaft is let go, raised after the stall
    // began (the 10:00 set-point moves C: no count then), cleared only
    // after the release.
    let held = raised
        .iter()
        .copied()
        .rfind(|&r| r <= free_at)
        .expect("motor_stalled_c raised");
    let clear = cleared
        .iter()
        .copied()
        .find(|&c| c > held)
        .expect("motor_stalled_c cleared after it was raised");
    println!(
        "uno stall: C held {} to {}: raised at {}, cleared at {}",
        format_utc(stall_from),
        format_utc(free_at as i64),
        format_utc(held as i64),
        format_utc(clear as i64)
    );
    assert!(
        held >= stall_from as f64,
        "the fault in force at the release was raised at {}, before the stall",
        format_utc(held as i64)
    );
    assert!(
        clear >= free_at,
        "cleared at {} while the shaft was still held",
        format_utc(clear as i64)
    );
    // Retried every 60 s after the watch stops it, each retry failing
    // after the watch's 5 s while the shaft is held: moving again at
    // most one retry (60 s + 5 s) and two ticks after the release.
    assert!(
        clear <= free_at + 67.0,
        "cleared only at {}",
        format_utc(clear as i64)
    );
    // After the recovery every set-point is reached again.
    let after: Vec<Reached> = setpoints(&run)
        .into_iter()
        .filter(|s| s.unix_s as f64 >= clear && s.decoded.is_some())
        .collect();
    assert!(
        after.len() >= 3,
        "{} set-points after the recovery",
        after.len()
    );
    for s in &after {
        let (dc, da) = s.decoded.unwrap();
        println!(
            "uno stall: {} -> decoded c {dc:.2} a {da:.2} ({:.2} counts)",
            s.text,
            s.error_counts().unwrap()
        );
        assert!(
            (dc - s.c_deg).abs() <= REACH_TOL_DEG && (da - s.a_deg).abs() <= REACH_TOL_DEG,
            "{} not reached: decoded c {dc:.2} a {da:.2}",
            s.text
        );
    }
}

#[test]
fn uno_with_an_rtc_that_lost_power_waits_flat() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO");
    let run = UnoBench::new(&elf)
        .start(t("2026-03-20T10:00:00Z"))
        .rtc(Rtc::LostPower)
        .run_minutes(20.0)
        .unwrap();
    assert_waits_flat("uno lost power", &run, "rtc_invalid");
}

#[test]
fn uno_without_an_rtc_waits_flat() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_UNO");
    let run = UnoBench::new(&elf)
        .start(t("2026-03-20T10:00:00Z"))
        .rtc(Rtc::Absent)
        .run_minutes(20.0)
        .unwrap();
    assert_waits_flat("uno no rtc", &run, "bus_rtc");
}
