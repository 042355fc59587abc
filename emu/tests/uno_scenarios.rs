//! Scenario tests of the ATmega328P (Arduino Uno) tracker image
//! (`avr_tracker`, the emulation build with time compression) under the
//! harness: a DS3231 on the TWI and both servo signals decoded from their
//! pins (`suntracker_emu::uno`).
//!
//! Gated: they run only when `SUNTRACKER_EMU_ELF_UNO` names the ELF;
//! otherwise each prints "skipped: SUNTRACKER_EMU_ELF_UNO not set" and
//! passes.
//!
//! References: the sun is SPA (sun_algos, f64, geometric, Kano 11.9683 N
//! 8.4261 E) at the set-point's UTC; the panel normal of a pose is
//! `suntracker::attitude`'s forward function `MountAttitude::normal_xyz`
//! for a level mount facing north; the servo signal's convention (500 µs
//! at 0°, 2,500 µs at 180°, 50 Hz) is the board module's.

use std::path::PathBuf;

use sun_algos::{Algorithm, Options, Site, UtcTime};
use suntracker::attitude::{angle_between_deg, sun_vector_xyz, MountAttitude, Pose};
use suntracker_emu::log::{format_utc, parse_utc, Event};
use suntracker_emu::uno::{pose_deg, UnoBench, UnoRun, PULSE_PER_DEG_US, PULSE_STEP_US};
use suntracker_emu::Rtc;

/// RAM that must stay free under the deepest stack a scenario reaches.
const STACK_HEADROOM_B: u16 = 512;
/// One Timer1 count of a servo pulse in servo degrees (0.045°), plus the
/// log's 2-decimal rounding of c and a.
const POSE_TOL_DEG: f64 = PULSE_STEP_US / PULSE_PER_DEG_US + 0.005;
/// The logged sun against SPA: psa-2020's f32 bound (0.011°) and the
/// 3-decimal print rounding, within 0.02°.
const SUN_TOL_DEG: f64 = 0.02;
/// The commanded panel normal against SPA: the sun's 0.02° and the
/// 0.005° rounding of each of c and a.
const NORMAL_TOL_DEG: f64 = 0.03;

fn elf() -> Option<PathBuf> {
    std::env::var_os("SUNTRACKER_EMU_ELF_UNO").map(PathBuf::from)
}

macro_rules! elf_or_skip {
    () => {
        match elf() {
            Some(p) => p,
            None => {
                println!("skipped: SUNTRACKER_EMU_ELF_UNO not set");
                return;
            }
        }
    };
}

fn t(s: &str) -> i64 {
    parse_utc(s).unwrap()
}

fn kano_spa(unix_s: i64) -> (f64, f64) {
    let site = Site::new(11.9683, 8.4261).unwrap();
    let p = Algorithm::Spa
        .position(
            &UtcTime::from_unix_seconds(unix_s).unwrap(),
            &site,
            &Options::default(),
        )
        .unwrap();
    (p.zenith_deg, p.azimuth_deg)
}

fn report(name: &str, run: &UnoRun) {
    println!(
        "{name}: {} lines, {} cycles, timescale {}, wall {:.1} s, pulses C {} A {}",
        run.lines.len(),
        run.cycles,
        run.timescale,
        run.wall.as_secs_f64(),
        run.pulses_c.len(),
        run.pulses_a.len()
    );
    for l in run.lines.iter().filter(|l| l.event != Event::Other) {
        println!("  {} {}", format_utc(l.utc_s as i64), l.text);
    }
    println!("{name}: {}", run.ram.summary());
    run.ram.assert_headroom(name, STACK_HEADROOM_B);
    assert_eq!(
        run.cpu,
        suntracker_emu::sim::CpuState::Running,
        "{name}: the CPU stopped"
    );
}

fn has(run: &UnoRun, text: &str) -> bool {
    run.lines.iter().any(|l| l.text == text)
}

/// Every pulse from `from_utc_s` on commands the stow pose (c = 0, a = 0).
fn assert_stowed_from(run: &UnoRun, from_utc_s: f64) {
    let frame = |p: &&suntracker_emu::uno::Pulse| p.utc_s >= from_utc_s;
    let n = run.pulses_c.iter().filter(frame).count();
    assert!(n > 10, "too few pulses after {from_utc_s}: {n}");
    for (c, a) in run
        .pulses_c
        .iter()
        .filter(frame)
        .zip(run.pulses_a.iter().filter(frame))
    {
        let (pc, pa) = pose_deg(c.width_us, a.width_us);
        assert!(
            pc.abs() <= POSE_TOL_DEG && pa.abs() <= POSE_TOL_DEG,
            "not stowed at {}: c {pc:.3} a {pa:.3}",
            format_utc(c.utc_s as i64)
        );
    }
}

#[test]
fn uno_tracks_a_day_at_kano_from_the_rtc() {
    let elf = elf_or_skip!();
    // The March equinox: the sun's azimuth stays within the positional
    // servos' 90°–270°, so no pose is clamped.
    let start = t("2026-03-20T05:00:00Z");
    let run = UnoBench::new(&elf)
        .start(start)
        .run_minutes(13.0 * 60.0)
        .unwrap();
    report("uno day", &run);
    assert!(has(&run, "boot suntracker 0.1.0 board=uno"));
    assert!(has(&run, "site source=config lat=11.9683 lon=8.4261"));
    assert!(
        run.lines
            .iter()
            .any(|l| matches!(l.event, Event::Time { ref source, .. } if source == "rtc")),
        "no time line"
    );
    assert!(
        !run.lines
            .iter()
            .any(|l| matches!(l.event, Event::Fault { .. }) || l.text == "mode wait_for_time"),
        "a fault or a wait with a good RTC"
    );
    let mut n = 0;
    let mut last_sp = 0.0;
    for l in &run.lines {
        let Event::SetPoint {
            unix_s,
            zenith_deg,
            azimuth_deg,
            c_deg,
            a_deg,
        } = l.event
        else {
            continue;
        };
        n += 1;
        last_sp = l.utc_s;
        // On the seed's 4-minute grid, served within the 1 s tick.
        assert_eq!(
            unix_s % 240,
            0,
            "set-point off the 4-minute grid: {}",
            l.text
        );
        assert!(
            l.utc_s - (unix_s as f64) < 3.0,
            "late set-point: {}",
            l.text
        );
        let (z, az) = kano_spa(unix_s);
        let spa = sun_vector_xyz(90.0 - z, az);
        let logged = sun_vector_xyz(90.0 - zenith_deg, azimuth_deg);
        let sun_err = angle_between_deg(&logged, &spa);
        assert!(
            sun_err <= SUN_TOL_DEG,
            "{}: sun {sun_err:.4}° from SPA",
            l.text
        );
        let normal = MountAttitude::<f64>::level().normal_xyz(&Pose {
            gamma_deg: c_deg,
            alpha_deg: a_deg,
        });
        let pose_err = angle_between_deg(&normal, &spa);
        assert!(
            pose_err <= NORMAL_TOL_DEG,
            "{}: panel normal {pose_err:.4}° from SPA",
            l.text
        );
        let (dc, da) = run.pose_after(l.utc_s).expect("pulses after the set-point");
        assert!(
            (dc - c_deg).abs() <= POSE_TOL_DEG && (da - a_deg).abs() <= POSE_TOL_DEG,
            "{}: servos decoded at c {dc:.3} a {da:.3}",
            l.text
        );
    }
    // Kano at the equinox: sunrise 05:3x, sunset 17:4x UTC, about 181
    // four-minute slots of daylight.
    assert!((175..=185).contains(&n), "{n} set-points");
    assert!(has(&run, "mode tracking"));
    let night = run
        .lines
        .iter()
        .rev()
        .find(|l| matches!(l.event, Event::Mode(_)))
        .expect("a mode line");
    assert_eq!(night.text, "mode night", "the day does not end at night");
    assert!(night.utc_s > last_sp);
    // After sunset: flat (stowed) until the end.
    assert_stowed_from(&run, night.utc_s + 2.0);
    println!("uno day: {n} set-points, servo poses within {POSE_TOL_DEG:.3}° of the log");
}

#[test]
fn uno_with_an_rtc_that_lost_power_waits_stowed() {
    let elf = elf_or_skip!();
    let run = UnoBench::new(&elf)
        .start(t("2026-03-20T10:00:00Z"))
        .rtc(Rtc::LostPower)
        .run_minutes(30.0)
        .unwrap();
    report("uno lost power", &run);
    assert!(has(&run, "fault rtc_invalid raised"));
    assert!(has(&run, "mode wait_for_time"));
    assert!(
        !run.lines
            .iter()
            .any(|l| matches!(l.event, Event::SetPoint { .. } | Event::Time { .. })),
        "a set-point or a time from an RTC that lost power"
    );
    assert_stowed_from(&run, run.start_unix_s as f64);
}

#[test]
fn uno_without_an_rtc_waits_stowed() {
    let elf = elf_or_skip!();
    let run = UnoBench::new(&elf)
        .start(t("2026-03-20T10:00:00Z"))
        .rtc(Rtc::Absent)
        .run_minutes(30.0)
        .unwrap();
    report("uno no rtc", &run);
    assert!(has(&run, "fault bus_rtc raised"));
    assert!(has(&run, "mode wait_for_time"));
    assert!(!run
        .lines
        .iter()
        .any(|l| matches!(l.event, Event::SetPoint { .. } | Event::Time { .. })));
    assert_stowed_from(&run, run.start_unix_s as f64);
}
