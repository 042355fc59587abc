//! What the Uno scenario tests share (`uno_scenarios.rs`, `uno_settings.rs`,
//! `uno_ds1302.rs`): the gate on an ELF's environment variable, the
//! tolerances, the references and the checks.
//!
//! References: the sun is SPA (sun_algos, `f64`, geometric; Kano 11.9683 N
//! 8.4261 E unless a test says otherwise) at the set-point's UTC; the panel
//! normal of a pose is `suntracker::attitude`'s forward function
//! `MountAttitude::normal_xyz` for the level mount (the firmware's own
//! geometry, `n = (sin c·sin a, −cos c·sin a, cos a)` in west/south/up); the
//! pose the axes reached is the one decoded from the encoder models' counts
//! (`home angle + (count − count at which the switch closes) × 0.3°`), never
//! the firmware's own idea of it.
// Each test file uses its own part of this module.
#![allow(dead_code)]

use std::collections::BTreeMap;

use suntracker::attitude::{angle_between_deg, sun_vector_xyz, MountAttitude, Pose};
use suntracker_emu::log::{format_utc, parse_utc, Event};
use suntracker_emu::sim::CpuState;
use suntracker_emu::uno::{kano_spa, UnoRun};

/// One encoder count of axis: 360° / (4 × 300 lines).
pub const COUNT_DEG: f64 = 0.3;
/// The log prints c and a to 2 decimals.
pub const PRINT_DEG: f64 = 0.005;
/// A set-point is reached when the decoded pose is within one encoder
/// count of the logged pose (plus its print rounding): the check of
/// `tests/expected/check_setpoints.py`.
pub const REACH_TOL_DEG: f64 = COUNT_DEG + PRINT_DEG;
/// The commanded panel normal against SPA: michalsky's stated 0.01° in
/// `f32`, plus the 0.005° print rounding of each of c and a.
pub const NORMAL_TOL_DEG: f64 = 0.03;
/// The tracker: the ATmega328P's 2,048 B of RAM less 256 B kept free.
pub const RAM_BUDGET_B: u16 = 1_792;
/// The settings image: static RAM and the deepest stack within the part's
/// RAM.
pub const SETTINGS_RAM_BUDGET_B: u16 = 2_048;
/// The set-point slot (4 minutes, the firmware's `servo_tracker::STEP_S`).
pub const STEP_S: i64 = 240;

/// The ELF named by an environment variable, or print `skipped: VAR not
/// set` and return from the test.
macro_rules! elf_or_skip {
    ($var:literal) => {
        match std::env::var_os($var) {
            Some(p) => std::path::PathBuf::from(p),
            None => {
                println!(concat!("skipped: ", $var, " not set"));
                return;
            }
        }
    };
}

pub fn t(s: &str) -> i64 {
    parse_utc(s).unwrap()
}

/// SPA at Kano: (zenith, azimuth), degrees.
pub fn kano(unix_s: i64) -> (f64, f64) {
    kano_spa(unix_s as f64).expect("SPA at Kano")
}

/// The log's lines other than set-points, the models' figures and the
/// RAM; asserts the CPU ran the whole span and the encoders' edges were
/// all legal.
pub fn report(name: &str, run: &UnoRun) {
    println!(
        "{name}: {} lines, {:.1} emulated min, {} cycles, timescale {}, wall {:.1} s",
        run.lines.len(),
        run.emulated_s / 60.0,
        run.cycles,
        run.timescale,
        run.wall.as_secs_f64()
    );
    for l in run
        .lines
        .iter()
        .filter(|l| !matches!(l.event, Event::SetPoint { .. }))
    {
        println!(
            "  {} c={:.2} a={:.2} | {}",
            format_utc(l.utc_s as i64),
            l.c_deg,
            l.a_deg,
            l.text
        );
    }
    for (axis, r) in ["C", "A"].iter().zip(&run.axes) {
        println!(
            "{name}: axis {axis}: shaft {:.3}°, decoded {:.2}° (count {}, switch count {}), {} edges, \
             {} illegal, {} decoder mismatches, {} hard-stop hits, {} switch changes, {} pulses",
            r.final_deg,
            r.decoded_deg,
            r.count,
            r.switch_count,
            r.edges,
            r.illegal_transitions,
            r.decoder_mismatches,
            r.hard_stop_hits,
            r.switch_changes.len(),
            r.pulses.len()
        );
        assert_eq!(
            (r.illegal_transitions, r.decoder_mismatches),
            (0, 0),
            "{name}: axis {axis}: encoder edges not one channel at a time"
        );
    }
    println!(
        "{name}: servo pulses on the pins C {} A {}, of which unlike the datasheet's (simavr's \
         unbuffered OCR1x) C {} A {}",
        run.pin_pulses.0,
        run.pin_pulses.1,
        run.pin_pulses_unlike_datasheet.0,
        run.pin_pulses_unlike_datasheet.1
    );
    println!("{name}: {}", run.ram.summary());
    assert_eq!(run.cpu, CpuState::Running, "{name}: the CPU stopped");
}

/// Static RAM + the deepest stack, printed and held to `budget`.
pub fn assert_ram(name: &str, run: &UnoRun, budget: u16) {
    let used = run.ram.static_bytes + run.ram.stack_sp_bytes;
    println!(
        "{name}: static {} B + peak stack {} B (lowest SP; {} B painted) = {used} B of {} B",
        run.ram.static_bytes,
        run.ram.stack_sp_bytes,
        run.ram.stack_painted_bytes,
        run.ram.total_bytes
    );
    assert!(
        used <= budget,
        "{name}: static {} B + peak stack {} B = {used} B > {budget} B",
        run.ram.static_bytes,
        run.ram.stack_sp_bytes
    );
}

pub fn has(run: &UnoRun, text: &str) -> bool {
    run.lines.iter().any(|l| l.text == text)
}

/// The lines of the run as text.
pub fn texts(run: &UnoRun) -> Vec<&str> {
    run.lines.iter().map(|l| l.text.as_str()).collect()
}

/// The replies to the line typed as `> typed`: the `ok …` and `error …`
/// lines after it, up to the next typed line.
pub fn replies_to<'a>(run: &'a UnoRun, typed: &str) -> Vec<&'a str> {
    let shown = format!("> {typed}");
    let Some(at) = run.lines.iter().position(|l| l.text == shown) else {
        return Vec::new();
    };
    run.lines[at + 1..]
        .iter()
        .map(|l| l.text.as_str())
        .take_while(|l| !l.starts_with("> "))
        .filter(|l| l.starts_with("ok ") || l.starts_with("error "))
        .collect()
}

/// A set-point's fields and the decoded pose at the end of its slot.
pub struct Reached {
    pub unix_s: i64,
    pub text: String,
    pub c_deg: f64,
    pub a_deg: f64,
    pub decoded: Option<(f64, f64)>,
}

impl Reached {
    /// The larger axis error, in encoder counts.
    pub fn error_counts(&self) -> Option<f64> {
        self.decoded
            .map(|(c, a)| (c - self.c_deg).abs().max((a - self.a_deg).abs()) / COUNT_DEG)
    }
}

pub fn setpoints(run: &UnoRun) -> Vec<Reached> {
    run.lines
        .iter()
        .filter_map(|l| match l.event {
            Event::SetPoint {
                unix_s,
                c_deg,
                a_deg,
                ..
            } => Some(Reached {
                unix_s,
                text: l.text.clone(),
                c_deg,
                a_deg,
                decoded: run.pose_at_slot_end(unix_s),
            }),
            _ => None,
        })
        .collect()
}

/// The tracker image's boot at Kano with its stored defaults, a time from
/// the RTC, no time or switch fault (a good clock, working switches), and
/// tracking.
pub fn assert_tracks_at_kano_from_the_rtc(name: &str, run: &UnoRun) {
    for want in [
        "boot suntracker 0.1.0 board=uno",
        "site source=config lat=11.9683 lon=8.4261",
        "config step_s=240 tick_ms=1000 axis_step_deg=0.300 algorithm=michalsky",
        "mode tracking",
    ] {
        assert!(has(run, want), "{name}: no {want:?}");
    }
    assert!(
        run.lines
            .iter()
            .any(|l| matches!(l.event, Event::Time { ref source, .. } if source == "rtc")),
        "{name}: no time line"
    );
    assert!(
        !run.lines.iter().any(|l| l.text == "mode wait_for_time"
            || l.text.starts_with("fault rtc_")
            || l.text.starts_with("fault bus_rtc")
            || l.text.starts_with("fault limit_switch")),
        "{name}: a time or switch fault with a good RTC and working switches"
    );
}

/// What [`check_setpoints`] found.
pub struct SetpointCheck {
    /// Set-points logged.
    pub n: usize,
    /// Of them checked at the end of their slot.
    pub reached: usize,
    /// The largest angle between a commanded normal and SPA's sun, degrees.
    pub worst_normal_deg: f64,
    /// The largest axis error at the end of a slot, counts.
    pub worst_reach_counts: f64,
    /// (decoded − logged) in counts, per axis, over all set-points.
    pub histogram: BTreeMap<i64, usize>,
    /// Set-points not reached within one count by the end of their slot.
    pub off: Vec<String>,
}

/// Every set-point of the run: on the 4-minute grid, served within the
/// tick (less than 3 s after its slot starts, or after `mode tracking`
/// when homing ends within the slot), its commanded normal within
/// [`NORMAL_TOL_DEG`] of SPA's sun at Kano (asserted); its slot's decoded
/// pose against it (collected). Only the last set-point may have no
/// decoded pose (the run ended in its slot).
pub fn check_setpoints(run: &UnoRun) -> SetpointCheck {
    let sps = setpoints(run);
    let mut check = SetpointCheck {
        n: sps.len(),
        reached: 0,
        worst_normal_deg: 0.0,
        worst_reach_counts: 0.0,
        histogram: BTreeMap::new(),
        off: Vec::new(),
    };
    // A run that starts in daylight serves its first slot when homing ends.
    let tracking_s = run
        .lines
        .iter()
        .find(|l| l.text == "mode tracking")
        .map_or(f64::NEG_INFINITY, |l| l.utc_s);
    let lines = run
        .lines
        .iter()
        .filter(|l| matches!(l.event, Event::SetPoint { .. }));
    for (i, (sp, line)) in sps.iter().zip(lines).enumerate() {
        assert_eq!(sp.unix_s % STEP_S, 0, "off the 4-minute grid: {}", sp.text);
        assert!(
            line.utc_s - (sp.unix_s as f64).max(tracking_s) < 3.0,
            "late set-point: {}",
            sp.text
        );
        let (z, az) = kano(sp.unix_s);
        let normal = MountAttitude::<f64>::level().normal_xyz(&Pose {
            gamma_deg: sp.c_deg,
            alpha_deg: sp.a_deg,
        });
        let err = angle_between_deg(&normal, &sun_vector_xyz(90.0 - z, az));
        check.worst_normal_deg = check.worst_normal_deg.max(err);
        assert!(
            err <= NORMAL_TOL_DEG,
            "{}: panel normal {err:.4}° from SPA",
            sp.text
        );
        let Some((dc, da)) = sp.decoded else {
            assert_eq!(i + 1, sps.len(), "{}: its slot's end not seen", sp.text);
            continue;
        };
        check.reached += 1;
        for (d, cmd) in [(dc, sp.c_deg), (da, sp.a_deg)] {
            *check
                .histogram
                .entry(((d - cmd) / COUNT_DEG).round() as i64)
                .or_default() += 1;
        }
        let e = sp.error_counts().unwrap_or(f64::INFINITY);
        check.worst_reach_counts = check.worst_reach_counts.max(e);
        if (dc - sp.c_deg).abs() > REACH_TOL_DEG || (da - sp.a_deg).abs() > REACH_TOL_DEG {
            check
                .off
                .push(format!("{} -> decoded c {dc:.2} a {da:.2}", sp.text));
        }
    }
    check
}

/// The UTC of the fault lines `name raised|cleared`.
pub fn fault_times(run: &UnoRun, name: &str, raised: bool) -> Vec<f64> {
    run.lines
        .iter()
        .filter(|l| matches!(&l.event, Event::Fault { name: n, raised: r } if n == name && *r == raised))
        .map(|l| l.utc_s)
        .collect()
}

/// Waiting for time: the fault, `mode wait_for_time`, no set-point, no
/// time, and the panel flat.
pub fn assert_waits_flat(name: &str, run: &UnoRun, fault: &str) {
    report(name, run);
    assert!(
        has(run, &format!("fault {fault} raised")),
        "{name}: no {fault}"
    );
    assert!(has(run, "mode wait_for_time"));
    assert!(
        !run.lines
            .iter()
            .any(|l| matches!(l.event, Event::SetPoint { .. } | Event::Time { .. })),
        "{name}: a set-point or a time without a valid RTC"
    );
    let a = run.axes[1].decoded_deg;
    println!(
        "{name}: flat: A decoded {a:.2}° (C {:.2}°)",
        run.axes[0].decoded_deg
    );
    assert!(a.abs() <= COUNT_DEG, "{name}: A at {a:.2}°, not flat");
}
