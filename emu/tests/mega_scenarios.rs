//! Scenario tests of the ATmega2560 tracker image (`avr_mega_tracker`, the
//! emulation build with time compression) under the harness, and (h) of
//! the board build, the ELF a user flashes, at real time.
//!
//! Gated: (a)–(g) (and the others but (h), (dc), (dc2)) run only when `SUNTRACKER_EMU_ELF_MEGA` names the
//! emulation build's ELF (`build_avr_mega_emu`), (h) only when
//! `SUNTRACKER_EMU_ELF_MEGA_RELEASE` names the board build's
//! (`build_avr_mega`, `$ELF_AVR_MEGA` in `.ci/firmware_env.sh`), (dc) and
//! (dc2) only when `SUNTRACKER_EMU_ELF_MEGA_DC` names the `dc` image's
//! emulation build (`build_avr_mega_dc_emu`, `$ELF_MEGA_DC_EMU`); otherwise
//! each prints "skipped: … not set" and passes. What the image must do for
//! them is listed in `emu/README.md` ("What the image must do").
//!
//! Conventions checked against (see `emu/src/models/mount.rs`): the panel
//! normal of a pose (γ = C, α = A) is `suntracker::attitude`'s forward
//! function `MountAttitude::normal_xyz`; the sun is SPA (sun_algos, f64,
//! geometric, Kano 11.9683 N 8.4261 E 480 m) at the set-point's UTC.

use std::path::{Path, PathBuf};

use sun_algos::{Algorithm, Options, Site, UtcTime};
use suntracker::attitude::{angle_between_deg, sun_vector_xyz, MountAttitude, Pose};
use suntracker_emu::log::{format_utc, parse_utc, Event};
use suntracker_emu::mega::SwitchEvent;
use suntracker_emu::models::linear::LinearFeedback;
use suntracker_emu::models::modbus_master;
use suntracker_emu::models::nmea::lying_epochs;
use suntracker_emu::script::xorshift32_noise;
use suntracker_emu::sim::{CpuState, ElfIdentity};
use suntracker_emu::{
    Contact, Field, GpsFeed, GpsSite, LogLine, MegaBench, Mount, Rtc, Run, WindProfile,
};

/// RAM that must stay free under the deepest stack a scenario reaches
/// (interrupts nesting on a path the scenarios did not take).
const STACK_HEADROOM_B: u16 = 512;
/// One motor step in axis degrees (10,000 full steps per turn).
const STEP_DEG: f64 = 0.036;
/// Slack for comparing decoded angles with commanded ones: one step, plus
/// the firmware's 2-decimal rounding of c and a.
const ANGLE_TOL_DEG: f64 = STEP_DEG + 0.005;
/// Config defaults (src/config/mod.rs `WindConfig`): hold before stowing and
/// calm before release, seconds.
const WIND_HOLD_S: f64 = 3.0;
const WIND_RELEASE_S: f64 = 600.0;
/// Assumed slowest axis speed for "travel time" bounds, degrees per
/// emulated second (override with SUNTRACKER_EMU_MIN_AXIS_DEG_S): the
/// bench runs motion at real time, where the drive's ramp (20 → 56 full
/// steps/s at 100 steps/s², 0.036° a step) reaches 2°/s within 0.4 s.
const MIN_AXIS_DEG_S: f64 = 1.8;

/// Sydney, the site typed on the console and saved in (f) and (h).
const SYDNEY: (f64, f64) = (-33.8688, 151.2093);

macro_rules! elf_or_skip {
    () => {
        elf_or_skip!("SUNTRACKER_EMU_ELF_MEGA")
    };
    ($var:literal) => {
        match std::env::var_os($var) {
            Some(p) => PathBuf::from(p),
            None => {
                println!(concat!("skipped: ", $var, " not set"));
                return;
            }
        }
    };
}

fn min_axis_deg_s() -> f64 {
    std::env::var("SUNTRACKER_EMU_MIN_AXIS_DEG_S")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(MIN_AXIS_DEG_S)
}

fn t(s: &str) -> i64 {
    parse_utc(s).unwrap()
}

fn kano_sun(unix_s: i64) -> [f64; 3] {
    sun_at(11.9683, 8.4261, unix_s)
}

/// The SPA sun (geometric) at a site of 480 m, as a unit vector.
fn sun_at(lat_deg: f64, lon_deg: f64, unix_s: i64) -> [f64; 3] {
    let site = Site::with_elevation(lat_deg, lon_deg, 480.0).unwrap();
    let p = Algorithm::Spa
        .position(
            &UtcTime::from_unix_seconds(unix_s).unwrap(),
            &site,
            &Options::default(),
        )
        .unwrap();
    sun_vector_xyz(90.0 - p.zenith_deg, p.azimuth_deg)
}

fn report(name: &str, run: &Run) {
    println!(
        "{name}: {} lines, {} cycles, timescale {}, wall {:.1} s, final C {:.3} A {:.3}, illegal C {} A {}",
        run.lines.len(),
        run.cycles,
        run.timescale,
        run.wall.as_secs_f64(),
        run.final_angles.0,
        run.final_angles.1,
        run.illegal_steps.0.len(),
        run.illegal_steps.1.len()
    );
    for l in run.events() {
        println!("  {} {}", format_utc(l.utc_s as i64), l.text);
    }
    println!("{name}: {}", run.ram.summary());
    if let Some((s, at)) = run.longest_awake {
        println!(
            "{name}: longest pass awake {:.1} ms of CPU time, ending at {}; {} passes over 10 ms",
            s * 1e3,
            format_utc(at as i64),
            run.long_passes.len()
        );
        let mut top = run.long_passes.clone();
        top.sort_by(|a, b| b.0.total_cmp(&a.0));
        let top: Vec<String> = top
            .iter()
            .take(5)
            .map(|(s, at)| format!("{:.1} ms at {}", s * 1e3, format_utc(*at as i64)))
            .collect();
        println!("{name}: longest passes: {}", top.join(", "));
    }
    run.ram.assert_headroom(name, STACK_HEADROOM_B);
}

fn assert_no_illegal_steps(run: &Run) {
    assert!(
        run.illegal_steps.0.is_empty() && run.illegal_steps.1.is_empty(),
        "illegal coil sequences: C {:?} A {:?}",
        run.illegal_steps.0.first(),
        run.illegal_steps.1.first()
    );
}

/// A `setpoint` line, its UTC (Unix s) and its pose (c, a), degrees.
type SetPoint<'a> = (&'a LogLine, i64, f64, f64);

fn set_points(run: &Run) -> Vec<SetPoint<'_>> {
    run.lines
        .iter()
        .filter_map(|l| match l.event {
            Event::SetPoint {
                unix_s,
                c_deg,
                a_deg,
                ..
            } => Some((l, unix_s, c_deg, a_deg)),
            _ => None,
        })
        .collect()
}

/// Both home switches closed at some time; the time both had closed.
fn homed_at(events: &[SwitchEvent], after_s: f64) -> Option<f64> {
    let first = |sw: usize| {
        events
            .iter()
            .find(|e| e.switch == sw && e.closed && e.utc_s >= after_s)
            .map(|e| e.utc_s)
    };
    Some(first(0)?.max(first(1)?))
}

fn has_line(run: &Run, pred: impl Fn(&Event) -> bool) -> bool {
    run.lines.iter().any(|l| pred(&l.event))
}

/// The scheduler's hold after a set-point, seconds (Jimoh & Aliyu 2019:
/// 2 minutes, `ScheduleConfig::hold_s`): a next set-point sooner than this
/// comes only after a set-point taken late in its slot.
const SCHEDULE_HOLD_S: f64 = 120.0;

/// For each set-point but the last: the decoded angles just before the
/// next set-point line started equal (c, a) within a step; the panel
/// normal of (c, a) through `mount` is within `pointing_tol_deg` of Kano's
/// sun. A set-point whose next line came within [`SCHEDULE_HOLD_S`] (the
/// tracker entered tracking late in a slot, took that slot's set-point, and
/// the next slot began before the axes could get there) had no time to be
/// reached: only its pointing is judged. In steady tracking set-points are
/// a slot (4 minutes) apart.
fn check_set_points(run: &Run, mount: &MountAttitude<f64>, pointing_tol_deg: f64) -> usize {
    check_set_points_of(&set_points(run), mount, kano_sun, pointing_tol_deg)
}

/// [`check_set_points`] on the set-points `sps` (in order), against `sun`.
fn check_set_points_of(
    sps: &[SetPoint],
    mount: &MountAttitude<f64>,
    sun: impl Fn(i64) -> [f64; 3],
    pointing_tol_deg: f64,
) -> usize {
    check_set_points_within(sps, mount, sun, ANGLE_TOL_DEG, pointing_tol_deg)
}

/// [`check_set_points_of`], each set-point reached within `angle_tol_deg`
/// on each axis (a drive without feedback errs by more than a step).
fn check_set_points_within(
    sps: &[SetPoint],
    mount: &MountAttitude<f64>,
    sun: impl Fn(i64) -> [f64; 3],
    angle_tol_deg: f64,
    pointing_tol_deg: f64,
) -> usize {
    assert!(!sps.is_empty(), "no setpoint line");
    let mut worst_angle: f64 = 0.0;
    let mut worst_pointing: f64 = 0.0;
    for w in sps.windows(2) {
        let (line, utc, c, a) = w[0];
        let (next, ..) = w[1];
        let dc = next.c_start_deg - c;
        let da = next.a_start_deg - a;
        let superseded = next.utc_s - line.utc_s < SCHEDULE_HOLD_S;
        if !superseded {
            worst_angle = worst_angle.max(dc.abs()).max(da.abs());
        }
        assert!(
            superseded || (dc.abs() <= angle_tol_deg && da.abs() <= angle_tol_deg),
            "set-point {} c={c} a={a}: axes at C {:.4} A {:.4} before the next one",
            format_utc(utc),
            next.c_start_deg,
            next.a_start_deg
        );
        let pose = Pose {
            gamma_deg: c,
            alpha_deg: a,
        };
        let err = angle_between_deg(&mount.normal_xyz(&pose), &sun(utc));
        worst_pointing = worst_pointing.max(err);
        assert!(
            err <= pointing_tol_deg,
            "set-point {} c={c} a={a}: normal {err:.4}° from the SPA sun",
            format_utc(utc)
        );
    }
    println!(
        "{} set-points: worst axis error {worst_angle:.4}°, worst pointing error {worst_pointing:.4}°",
        sps.len()
    );
    sps.len()
}

/// (a) Kano, 2026-06-21, power-on 05:00Z with GPS: homing, tracking all
/// day within a step of each set-point and 0.02° of the sun, home at the
/// end of the day, no illegal coil sequence. Until 19:00Z: sunset is at
/// 18:2x, the night after it only sleeps.
#[test]
fn a_kano_whole_day_with_gps() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T05:00:00Z");
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(GpsFeed::kano())
        .power_on_angles(30.0, 20.0)
        .run_minutes(14.0 * 60.0)
        .unwrap();
    report("a", &run);
    assert!(has_line(&run, |e| matches!(e, Event::Boot { .. })));
    assert!(has_line(
        &run,
        |e| matches!(e, Event::Time { source, .. } if source == "gps")
    ));
    assert!(has_line(
        &run,
        |e| matches!(e, Event::Site { source, .. } if source == "gps")
    ));
    let homed = homed_at(&run.switch_events, start as f64).expect("both axes reach home");
    let sps = set_points(&run);
    let first_sp = sps.first().expect("set-points").0.utc_s;
    assert!(homed <= first_sp, "homing before tracking");
    let n = check_set_points(&run, &MountAttitude::level(), 0.02);
    // 4-minute table from about sunrise to sunset: dozens at least.
    assert!(n >= 100, "{n} set-points");
    let last_sp = sps.last().unwrap().0.utc_s;
    assert!(
        homed_at(&run.switch_events, last_sp).is_some(),
        "home at the end of the day"
    );
    assert_no_illegal_steps(&run);
}

/// (b) GPS silent, DS3231 valid: time from the RTC, site from the
/// configuration, and it tracks.
#[test]
fn b_rtc_only_tracks() {
    let elf = elf_or_skip!();
    let run = MegaBench::mega(&elf)
        .start(t("2026-06-21T08:00:00Z"))
        .rtc(Rtc::Valid)
        .gps(GpsFeed::Silent)
        .run_minutes(60.0)
        .unwrap();
    report("b", &run);
    assert!(has_line(
        &run,
        |e| matches!(e, Event::Time { source, .. } if source == "rtc")
    ));
    assert!(has_line(
        &run,
        |e| matches!(e, Event::Site { source, .. } if source == "config")
    ));
    check_set_points(&run, &MountAttitude::level(), 0.02);
    assert_no_illegal_steps(&run);
}

/// (c) No valid time (DS3231 lost power, no GPS): after homing the axes
/// never move again, and `mode wait_for_time` is logged.
#[test]
fn c_no_time_waits_after_homing() {
    let elf = elf_or_skip!();
    let run = MegaBench::mega(&elf)
        .start(t("2026-06-21T08:00:00Z"))
        .rtc(Rtc::LostPower)
        .gps(GpsFeed::Silent)
        .run_minutes(60.0)
        .unwrap();
    report("c", &run);
    assert!(has_line(
        &run,
        |e| matches!(e, Event::Mode(m) if m == "wait_for_time")
    ));
    assert!(set_points(&run).is_empty(), "no set-point without time");
    let homed = homed_at(&run.switch_events, 0.0).expect("both axes reach home");
    // After homing (and any back-off from the switches, 60 s), no motion.
    let settle = homed + 60.0;
    let later: Vec<_> = run
        .angle_trace
        .iter()
        .filter(|s| s.utc_s >= settle)
        .collect();
    assert!(!later.is_empty());
    for s in &later {
        assert!(
            (s.c_deg - run.final_angles.0).abs() < 1e-9
                && (s.a_deg - run.final_angles.1).abs() < 1e-9,
            "moved after homing: {s:?}"
        );
    }
    assert_no_illegal_steps(&run);
}

/// (d) A gale (40 Hz for 10 minutes from 12:00Z): `mode wind_stow`, the A
/// axis at α = 0 within the hold time plus the travel time, and back to
/// tracking after 600 s of calm.
#[test]
fn d_gale_at_noon_stows_and_releases() {
    let elf = elf_or_skip!();
    let gale = t("2026-06-21T12:00:00Z");
    let run = MegaBench::mega(&elf)
        .start(t("2026-06-21T11:30:00Z"))
        .rtc(Rtc::Valid)
        .gps(GpsFeed::kano())
        .wind(WindProfile::gust(gale, 10, 40.0))
        .run_minutes(60.0)
        .unwrap();
    report("d", &run);
    println!("wind pulses {}", run.wind_pulses);
    let stow = run
        .lines
        .iter()
        .find(|l| matches!(&l.event, Event::Mode(m) if m == "wind_stow"))
        .expect("mode wind_stow");
    assert!(stow.utc_s >= gale as f64, "stowed before the gale");
    // α before the gale, from the last set-point before it.
    let alpha_before = set_points(&run)
        .iter()
        .rev()
        .find(|s| s.0.utc_s < gale as f64)
        .map_or(90.0, |s| s.3);
    let deadline = gale as f64 + WIND_HOLD_S + 5.0 + alpha_before.abs() / min_axis_deg_s();
    let stowed_at = run
        .angle_trace
        .iter()
        .find(|s| s.utc_s >= gale as f64 && s.a_deg.abs() <= ANGLE_TOL_DEG)
        .map(|s| s.utc_s)
        .or_else(|| {
            run.lines
                .iter()
                .find(|l| l.utc_s >= gale as f64 && l.a_deg.abs() <= ANGLE_TOL_DEG)
                .map(|l| l.utc_s)
        })
        .expect("A axis reaches α = 0");
    assert!(
        stowed_at <= deadline,
        "stowed at {} > deadline {}",
        format_utc(stowed_at as i64),
        format_utc(deadline as i64)
    );
    let calm = (gale + 600) as f64;
    let release = run
        .lines
        .iter()
        .find(|l| l.utc_s > stow.utc_s && matches!(&l.event, Event::Mode(m) if m != "wind_stow"))
        .expect("leaves wind_stow");
    println!(
        "gale from {}: mode wind_stow at +{:.1} s, A at 0 at +{:.1} s (deadline +{:.1} s); released {:.1} s after the calm began",
        format_utc(gale),
        stow.utc_s - gale as f64,
        stowed_at - gale as f64,
        deadline - gale as f64,
        release.utc_s - calm
    );
    assert!(
        release.utc_s >= calm + WIND_RELEASE_S - 5.0
            && release.utc_s <= calm + WIND_RELEASE_S + 60.0,
        "released at {} (calm from {})",
        format_utc(release.utc_s as i64),
        format_utc(calm as i64)
    );
    // Every set-point logged, the first after the release included, is
    // the one of the slot of the tick that logged it: never one from before
    // the slot's 4 minutes (the table step). The tick reads the time when it
    // starts and its line arrives when the pass has written it: at the
    // emulation's time scale the longest pass (CPU time) is some seconds of
    // emulated time, so the bound takes one such pass more.
    let pass_s = run
        .longest_awake
        .map_or(0.0, |(cpu_s, _)| cpu_s * run.timescale);
    assert!(pass_s < 10.0, "longest pass {pass_s:.1} emulated s");
    for (line, unix_s, _, _) in set_points(&run) {
        let age_s = line.utc_s - unix_s as f64;
        assert!(
            (-1.0..240.0 + pass_s).contains(&age_s),
            "set-point for {} logged at {}: {age_s:.0} s old",
            format_utc(unix_s),
            format_utc(line.utc_s as i64)
        );
    }
    assert_no_illegal_steps(&run);
}

/// (e) Mount tilted 7° facing 20° east of north: the attitude is applied
/// (the commanded pose differs from a level mount's), and the panel normal
/// through the tilted mount is within 0.05° of the sun. The frame
/// conventions are the firmware's (`src/attitude.rs`); the harness's
/// tilt/heading mapping is in `emu/src/models/mount.rs`.
#[test]
fn e_tilted_mount_is_compensated() {
    let elf = elf_or_skip!();
    let run = MegaBench::mega(&elf)
        .start(t("2026-06-21T08:00:00Z"))
        .rtc(Rtc::Valid)
        .gps(GpsFeed::kano())
        .mount(7.0, 20.0)
        .run_minutes(60.0)
        .unwrap();
    report("e", &run);
    let mount = Mount::tilted(7.0, 20.0).attitude;
    check_set_points(&run, &mount, 0.05);
    // A level mount would command something else.
    let level = MountAttitude::<f64>::level();
    let differs = set_points(&run).iter().any(|&(_, utc, c, a)| {
        let pose = Pose {
            gamma_deg: c,
            alpha_deg: a,
        };
        angle_between_deg(&level.normal_xyz(&pose), &kano_sun(utc)) > 1.0
    });
    assert!(differs, "the commanded poses ignore the tilt");
    assert_no_illegal_steps(&run);
}

/// The console over a power cut, as (f) and (h) run it: the tracker stands
/// in Sydney (its compass sees Sydney's field, WMM2025: declination about
/// 12.8° E) from 2026-03-20T04:00Z (15:00 there: the sun is up until about
/// 07:10Z), on the RTC (no GPS), configured for Kano until the operator
/// types Sydney's site (minutes 1 and 1.5), a gear ratio out of range (2),
/// reads the gear back (2.5) and saves (3); the power is cut at minute 6.
fn sydney_console_bench(elf: &Path) -> MegaBench {
    MegaBench::mega(elf)
        .field(Field::wmm2025(SYDNEY.0, SYDNEY.1, 0.48, (2026, 3, 20)))
        .start(t("2026-03-20T04:00:00Z"))
        .rtc(Rtc::Valid)
        .gps(GpsFeed::Silent)
        .type_at(1.0, "set site.lat_deg -33.8688")
        .type_at(1.5, "set site.lon_deg 151.2093")
        .type_at(2.0, "set axis.c.gear_ratio 20000")
        .type_at(2.5, "get axis.c.gear_ratio")
        .type_at(3.0, "save")
        .reset_at(6.0)
}

/// The texts of `run`'s lines and the place of the (first) power cut.
fn texts_and_cut(run: &Run) -> (Vec<&str>, usize) {
    let texts: Vec<&str> = run.lines.iter().map(|l| l.text.as_str()).collect();
    let cut = texts
        .iter()
        .position(|l| *l == "# power cut")
        .expect("power cut");
    (texts, cut)
}

/// What (f) and (h) assert of a [`sydney_console_bench`] run: each typed
/// line's reply before the power cut (the gear refused with its range's
/// text and unchanged), the stored configuration and Sydney's site at the
/// boot after it, and at least `min_after` set-points after it, each
/// reached (the axes within a step of it before the next one) and its
/// panel normal within 0.03° of SPA's sun at Sydney. Returns the lines'
/// texts after the cut and the set-points after it.
fn assert_site_saved_over_cut(run: &Run, min_after: usize) -> (Vec<&str>, Vec<SetPoint<'_>>) {
    let (texts, cut) = texts_and_cut(run);
    let (before, after) = texts.split_at(cut);
    for want in [
        "ok site.lat_deg=-33.8688",
        "ok site.lon_deg=151.2093",
        "error axis.c.gear_ratio: 1...10,000 motor revolutions per axis revolution",
        "ok save",
    ] {
        assert!(before.contains(&want), "{want}: {before:?}");
    }
    let gear = before
        .iter()
        .find(|l| l.starts_with("ok axis.c.gear_ratio="))
        .expect("get reply");
    assert_eq!(*gear, "ok axis.c.gear_ratio=50", "unchanged");
    for want in [
        "config source=stored",
        "site source=config lat=-33.8688 lon=151.2093",
    ] {
        assert!(after.contains(&want), "{want}: {after:?}");
    }
    let after_s = run.lines[cut].utc_s;
    let sps: Vec<_> = set_points(run)
        .into_iter()
        .filter(|(l, ..)| l.utc_s > after_s)
        .collect();
    assert!(
        sps.len() >= min_after,
        "{} set-points after the cut",
        sps.len()
    );
    // 0.03°, not Kano's 0.02°: the mount's heading comes from the compass,
    // and Sydney's horizontal field (about 24 µT against Kano's 33 µT,
    // WMM2025) gives the QMC5883L's counts a third less resolution in
    // heading.
    check_set_points_of(
        &sps,
        &MountAttitude::level(),
        |utc| sun_at(SYDNEY.0, SYDNEY.1, utc),
        0.03,
    );
    (after.to_vec(), sps)
}

/// (f) The console over a power cut ([`sydney_console_bench`]): the site
/// typed and saved is in force after the cut, every set-point after it is
/// Sydney's (see [`assert_site_saved_over_cut`]); 10 KB of random bytes
/// while tracking, after the cut, are answered with errors, a command after
/// them is answered, and the noise delays no set-point by more than a tick
/// beyond what the quiet ones (no input coming in) show.
#[test]
fn f_console_site_saved_across_a_power_cut() {
    let elf = elf_or_skip!();
    // Noise without line ends (a flood that never completes a line) and
    // with them (lines of garbage answered by errors).
    let noise = xorshift32_noise(0x2545_f491, 10_240);
    let run = sydney_console_bench(&elf)
        .bytes_at(20.0, noise)
        // An end of line closes the noise's last partial line (answered
        // with an error), then a command is read as usual.
        .type_at(29.5, "")
        .type_at(30.0, "get site.lat_deg")
        .run_minutes(45.0)
        .unwrap();
    let (after, sps) = assert_site_saved_over_cut(&run, 5);
    assert!(
        after.contains(&"ok site.lat_deg=-33.8688"),
        "no reply after the noise: {after:?}"
    );
    let start_s = t("2026-03-20T04:00:00Z") as f64;
    let mut worst_late: f64 = 0.0;
    let mut quiet_late: f64 = 0.0;
    for (line, utc, ..) in &sps {
        // How long after its slot each was logged: while the noise and
        // the lines after it come in (minute 20 to the last typed line at
        // minute 30, + 1 minute), and while nothing comes in (before and
        // after). (The first after the power cut waits for the day's plan,
        // spread over ticks after boot: not counted.) Quiet set-points
        // are late by 2 to 4 s depending on the emulator's phase (the
        // 04:36Z one by 3.8 s with homing one chunk a tick and at speed).
        let late = line.utc_s - *utc as f64;
        let noisy = (start_s + 20.0 * 60.0..start_s + 31.0 * 60.0).contains(&line.utc_s);
        if noisy {
            worst_late = worst_late.max(late);
        } else if !std::ptr::eq(*line, sps[0].0) {
            quiet_late = quiet_late.max(late);
        }
    }
    println!(
        "{} Sydney set-points after the cut; logged at most {quiet_late:.1} s after the slot \
         with no input, {worst_late:.1} s with the noise",
        sps.len()
    );
    // The noise delays no set-point by more than one tick (1 s) beyond
    // what the quiet ones show (the harness's clock runs at real time while
    // the axes move, and a tick is 1 s of the firmware's clock).
    assert!(
        worst_late <= quiet_late + 1.0,
        "the noise delayed a set-point: {worst_late:.1} s against {quiet_late:.1} s"
    );
    assert!(
        after.iter().any(|l| l.starts_with("error ")),
        "the noise's lines were answered"
    );
    report("f", &run);
}

/// (h) The board build, the ELF a user flashes (`build_avr_mega`, not the
/// emulation build `build_avr_mega_emu`, whose Timer0 clock runs 60× fast):
/// the very file, its SHA-256 printed (`.ci/run` compares it with the
/// release ELF's), no time scale in it or in its log: its clock runs 1 ms a
/// tick as on a board, and the harness's 1:1 with the CPU's (every emulated
/// second is a CPU second, the moves and the GPS included). (f)'s console
/// session over a power cut ([`sydney_console_bench`]), 30 emulated
/// minutes: `save` at minute 3, the cut at 6, the stored site in force
/// after it, every set-point after it reached and within 0.03° of SPA's
/// sun at Sydney; no illegal coil sequence; the RAM as the others.
#[test]
fn h_flashed_elf_saves_over_a_power_cut_at_real_time() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_MEGA_RELEASE");
    let id = ElfIdentity::of_board_build(&elf).unwrap();
    println!("h: {id}");
    let minutes = 30.0;
    let run = sydney_console_bench(&elf).run_minutes(minutes).unwrap();
    report("h", &run);
    assert_eq!(run.cpu, CpuState::Running, "the CPU stopped");
    assert!(run.emulated_s >= minutes * 60.0);
    assert!(
        !run.lines
            .iter()
            .any(|l| matches!(l.event, Event::Timescale(_))),
        "a timescale line from the board build"
    );
    // 1:1 all along: one segment, emulated seconds = CPU cycles / 16 MHz.
    assert_eq!(run.time_segments.len(), 1, "{:?}", run.time_segments);
    assert_eq!(run.time_segments[0].timescale, 1.0);
    let (_, sps) = assert_site_saved_over_cut(&run, 5);
    println!(
        "h: {} set-points after the cut, {:.0} emulated s in {} cycles, wall {:.1} s",
        sps.len(),
        run.emulated_s,
        run.cycles,
        run.wall.as_secs_f64()
    );
    assert_no_illegal_steps(&run);
    assert_eq!(
        ElfIdentity::of(&elf).unwrap(),
        id,
        "the ELF changed during the run"
    );
}

/// (g) Powered on in daylight (Kano, 10:00Z, GPS) with the axes far from
/// their switches: C at 170° (350° above its switch at −180°), A at 80°
/// (170° above −90°). Homing runs at the drive's speed (both axes at once),
/// not one chunk a tick: both switches have closed within the C axis's
/// travel / speed (at the slowest speed assumed, [`MIN_AXIS_DEG_S`]) + 5 s
/// (a 1 s tick to start, the ramp), and the first set-point line comes
/// within the C travel / speed + the A travel / speed + one table step
/// (240 s) of power-on. (At one 1° chunk a 1 s tick the C axis alone took
/// about 350 s.)
#[test]
fn g_daylight_power_on_homes_at_speed() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T10:00:00Z");
    let (c0_deg, a0_deg) = (170.0, 80.0);
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(GpsFeed::kano())
        .power_on_angles(c0_deg, a0_deg)
        .run_minutes(15.0)
        .unwrap();
    report("g", &run);
    let speed_deg_s = min_axis_deg_s();
    let (c_travel_s, a_travel_s) = (
        (c0_deg - -180.0) / speed_deg_s,
        (a0_deg - -90.0) / speed_deg_s,
    );
    let homed = homed_at(&run.switch_events, start as f64).expect("both axes reach home");
    let homed_s = homed - start as f64;
    assert!(
        homed_s <= c_travel_s + 5.0,
        "both switches closed {homed_s:.1} s after power-on; C travel / speed {c_travel_s:.1} s"
    );
    let sps = set_points(&run);
    let first_s = sps.first().expect("a set-point").0.utc_s - start as f64;
    let bound_s = c_travel_s + a_travel_s + 240.0;
    println!("g: switches closed after {homed_s:.1} s, first set-point after {first_s:.1} s (bound {bound_s:.1} s)");
    assert!(
        first_s <= bound_s,
        "first set-point {first_s:.1} s after power-on, bound {bound_s:.1} s"
    );
    check_set_points(&run, &MountAttitude::level(), 0.02);
    assert_no_illegal_steps(&run);
}

/// (g2) Powered on in daylight at Kano on 2026-03-20 at 09:00Z: the axes
/// home once. The first move of the day, from the pose the tracker waited
/// in for the first slot to the day's branch, is a swing, and a swing
/// re-homes open-loop axes unless they were homed since the last night, as
/// the power-on homing did (they homed a second time at 09:04, and the
/// first set-point came 50 s later).
#[test]
fn g2_daylight_power_on_homes_once() {
    let elf = elf_or_skip!();
    let start = t("2026-03-20T09:00:00Z");
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(GpsFeed::kano())
        .run_minutes(12.0)
        .unwrap();
    report("g2", &run);
    let modes = run.modes();
    let homings = modes.iter().filter(|(_, m)| m == "homing").count();
    assert_eq!(homings, 1, "{modes:?}");
    let sps = set_points(&run);
    let first_s = sps.first().expect("a set-point").0.utc_s - start as f64;
    println!("g2: modes {modes:?}; first set-point after {first_s:.1} s");
    check_set_points(&run, &MountAttitude::level(), 0.02);
    assert_no_illegal_steps(&run);
}

/// Emulated UTC of the first line after `after_s` whose text is `text`.
fn line_after(run: &Run, after_s: f64, text: &str) -> Option<f64> {
    run.lines
        .iter()
        .find(|l| l.utc_s >= after_s && l.text == text)
        .map(|l| l.utc_s)
}

/// Emulated UTC of each `# power cut` line, in order.
fn power_cuts(run: &Run) -> Vec<f64> {
    run.lines
        .iter()
        .filter(|l| l.text == "# power cut")
        .map(|l| l.utc_s)
        .collect()
}

/// Half-steps either axis took in `from_s..to_s` (emulated UTC).
fn steps_between(run: &Run, from_s: f64, to_s: f64) -> usize {
    let (c, a) = &run.step_times;
    c.iter()
        .chain(a.iter())
        .filter(|t| (from_s..to_s).contains(*t))
        .count()
}

/// The mode lines' names after `after_s`, in order.
fn modes_after(run: &Run, after_s: f64) -> Vec<&str> {
    run.lines
        .iter()
        .filter(|l| l.utc_s >= after_s)
        .filter_map(|l| match &l.event {
            Event::Mode(m) => Some(m.as_str()),
            _ => None,
        })
        .collect()
}

/// (i) The service lock over a power cut and a gale: Kano, 2026-06-21 from
/// 08:00Z, RTC and GPS. `service on` at minute 10 (tracking): `ok service
/// on` once it is saved, `mode service`, the axes stop (within the drive's
/// ramp, 2 s); the power is cut at minute 12; after it the stored record is
/// read (`config source=stored`), the first mode is `service`, and for the
/// 31 minutes to `service off` (minute 43) neither axis takes a single
/// step — no homing, and no stow for the 40 Hz gale of minutes 20–30,
/// which the anemometer counts all the same. `service off`: homing, then
/// tracking again, every set-point within a step and 0.02° of the sun.
#[test]
fn i_service_lock_holds_over_a_power_cut_and_a_gale() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T08:00:00Z");
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(GpsFeed::kano())
        .wind(WindProfile::gust(start + 20 * 60, 10, 40.0))
        .type_at(10.0, "service on")
        .reset_at(12.0)
        .type_at(43.0, "service off")
        .run_minutes(60.0)
        .unwrap();
    report("i", &run);
    let start_s = start as f64;
    let ok_on = line_after(&run, start_s, "ok service on").expect("ok service on");
    let cut = power_cuts(&run)[0];
    assert!(ok_on < cut, "the lock was not saved before the cut");
    assert!(line_after(&run, start_s, "mode service").is_some_and(|t| t < cut));
    let off_typed = line_after(&run, cut, "> service off").expect("typed");
    // Stopped within the ramp of the moment the line was answered.
    let held_from = line_after(&run, start_s, "> service on").expect("typed") + 2.0;
    let moved = steps_between(&run, held_from, off_typed);
    println!(
        "i: service on answered {:.3} s after typing; steps from then + 2 s to `service off` \
         ({:.0} s, power cut and gale included): {moved}",
        ok_on - (held_from - 2.0),
        off_typed - held_from
    );
    assert_eq!(moved, 0, "an axis moved under the service lock");
    assert!(off_typed - cut >= 30.0 * 60.0);
    assert!(line_after(&run, cut, "config source=stored").is_some());
    let after_cut = modes_after(&run, cut);
    assert_eq!(after_cut.first(), Some(&"service"), "{after_cut:?}");
    assert!(run.wind_pulses > 0, "no gale sent");
    let during: Vec<&str> = run
        .lines
        .iter()
        .filter(|l| (held_from..off_typed).contains(&l.utc_s))
        .filter_map(|l| match &l.event {
            Event::Mode(m) => Some(m.as_str()),
            _ => None,
        })
        .collect();
    assert!(
        during.iter().all(|m| *m == "service"),
        "another mode under the lock: {during:?}"
    );
    // After `service off`: homing (the cut took the reference), tracking.
    assert!(line_after(&run, off_typed, "ok service off").is_some());
    let after_off = modes_after(&run, off_typed);
    assert_eq!(after_off.first(), Some(&"homing"), "{after_off:?}");
    assert!(after_off.contains(&"tracking"), "{after_off:?}");
    assert!(
        homed_at(&run.switch_events, off_typed).is_some(),
        "no homing"
    );
    let sps: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|s| s.0.utc_s > off_typed)
        .collect();
    assert!(
        sps.len() >= 2,
        "{} set-points after `service off`",
        sps.len()
    );
    check_set_points_of(&sps, &MountAttitude::level(), kano_sun, 0.02);
    assert_no_illegal_steps(&run);
}

/// (j) A typed `stow` and a manual mode over power cuts: Kano, 2026-06-21
/// from 08:00Z, RTC. `stow` at minute 8, power cut at 10: after it `mode
/// command_stow`, the axes home and the panel is driven flat (α = 0)
/// again; `resume` at 20: tracking. `jog a 5` at 26 (manual, answered at
/// once), power cut at 28: after it `mode manual` and not one step until
/// `resume` at 40; then homing and tracking.
#[test]
fn j_stow_and_manual_are_kept_over_power_cuts() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T08:00:00Z");
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(GpsFeed::Silent)
        .type_at(8.0, "stow")
        .reset_at(10.0)
        .type_at(20.0, "resume")
        .type_at(26.0, "jog a 5")
        .reset_at(28.0)
        .type_at(40.0, "resume")
        .run_minutes(55.0)
        .unwrap();
    report("j", &run);
    let start_s = start as f64;
    let cuts = power_cuts(&run);
    assert_eq!(cuts.len(), 2);
    assert!(line_after(&run, start_s, "ok stow").is_some_and(|t| t < cuts[0]));
    let after_first = modes_after(&run, cuts[0]);
    assert_eq!(
        after_first.first(),
        Some(&"command_stow"),
        "{after_first:?}"
    );
    let resumed = line_after(&run, cuts[0], "> resume").expect("typed");
    // Homed, then flat, before `resume`.
    assert!(homed_at(&run.switch_events, cuts[0]).is_some_and(|t| t < resumed));
    let flat = run
        .angle_trace
        .iter()
        .rfind(|s| (cuts[0]..resumed).contains(&s.utc_s))
        .expect("trace");
    assert!(
        flat.a_deg.abs() <= ANGLE_TOL_DEG,
        "A at {} before resume",
        flat.a_deg
    );
    assert!(line_after(&run, resumed, "mode tracking").is_some_and(|t| t < cuts[1]));
    // Manual, then the second cut.
    let jog = run
        .lines
        .iter()
        .find(|l| l.utc_s > resumed && l.text.starts_with("ok jog c="))
        .expect("jog answered");
    assert!(jog.utc_s < cuts[1]);
    assert!(line_after(&run, jog.utc_s, "mode manual").is_some_and(|t| t < cuts[1]));
    let after_second = modes_after(&run, cuts[1]);
    assert_eq!(after_second.first(), Some(&"manual"), "{after_second:?}");
    let resumed2 = line_after(&run, cuts[1], "> resume").expect("typed");
    let moved = steps_between(&run, cuts[1], resumed2);
    println!(
        "j: steps from the second cut to `resume` ({:.0} s in manual): {moved}",
        resumed2 - cuts[1]
    );
    assert_eq!(moved, 0, "an axis moved in manual after the cut");
    let after_resume = modes_after(&run, resumed2);
    assert_eq!(after_resume.first(), Some(&"homing"), "{after_resume:?}");
    assert!(after_resume.contains(&"tracking"), "{after_resume:?}");
    let sps: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|s| s.0.utc_s > resumed2)
        .collect();
    assert!(!sps.is_empty(), "no set-point after the last `resume`");
    check_set_points_of(&sps, &MountAttitude::level(), kano_sun, 0.02);
    assert_no_illegal_steps(&run);
}

/// (k) The board build (the ELF a user flashes, at real time): the power
/// is cut while `service on` is being saved. The configuration is saved
/// first (minute 1, slot 0), so the lock's record goes to the other, empty
/// slot: all of its 160 bytes are written, one EEPROM byte started per
/// pass of the loop (the run prints how long after the typed line `ok
/// service on` came: about 180 ms, since simavr stores a byte at once and
/// clears EEPE on the write (its `avr_eeprom.c`), where a real ATmega2560
/// takes 3.4 ms a byte, 0.54 s for the record; every byte of such a save is
/// cut on the host in `tests/persist_powercut.rs`). For cuts from 5 ms to
/// 1 s after the line is typed:
/// either the record was complete (`ok service on` came before the cut)
/// and the image boots in `mode service` with not one step after the cut,
/// or it was not, and the image boots on the configuration saved before
/// (no lock, never a lost configuration: `config source=stored`). Never
/// `ok service on` followed by motion.
#[test]
fn k_power_cut_while_the_service_lock_is_saved() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_MEGA_RELEASE");
    let start = t("2026-06-21T08:00:00Z");
    let typed_min = 2.0;
    let mut outcomes = Vec::new();
    let mut save_s: Option<f64> = None;
    for delay_s in [0.005, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 1.0] {
        let run = MegaBench::mega(&elf)
            .start(start)
            .rtc(Rtc::Valid)
            .gps(GpsFeed::Silent)
            .type_at(1.0, "save")
            .type_at(typed_min, "service on")
            .reset_at(typed_min + delay_s / 60.0)
            .run_minutes(4.0)
            .unwrap();
        let start_s = start as f64;
        assert!(line_after(&run, start_s, "ok save").is_some(), "save");
        let cut = power_cuts(&run)[0];
        let ok_at = line_after(&run, start_s, "ok service on").filter(|t| *t < cut);
        let saved = ok_at.is_some();
        if let (Some(ok), Some(typed)) = (ok_at, line_after(&run, start_s, "> service on")) {
            save_s = Some(save_s.map_or(ok - typed, |s: f64| s.max(ok - typed)));
        }
        assert!(
            line_after(&run, cut, "config source=stored").is_some(),
            "the configuration was lost (cut {delay_s} s after typing)"
        );
        let first = modes_after(&run, cut).first().map(|m| m.to_string());
        let moved = steps_between(&run, cut, f64::INFINITY);
        if saved {
            assert_eq!(first.as_deref(), Some("service"), "cut +{delay_s} s");
            assert_eq!(moved, 0, "moved after a saved lock (cut +{delay_s} s)");
        } else {
            assert!(
                matches!(first.as_deref(), Some("service" | "night" | "homing")),
                "cut +{delay_s} s: {first:?}"
            );
            if first.as_deref() == Some("service") {
                assert_eq!(moved, 0, "moved in service (cut +{delay_s} s)");
            }
        }
        outcomes.push(format!(
            "+{:.0} ms: {} -> {}",
            delay_s * 1000.0,
            if saved { "saved" } else { "not saved" },
            first.unwrap_or_default()
        ));
    }
    println!("k: {}", outcomes.join("; "));
    println!(
        "k: `ok service on` {:.0} ms after the typed line",
        save_s.unwrap_or(f64::NAN) * 1000.0
    );
    // Both outcomes were seen: the cuts straddle the save.
    assert!(outcomes.iter().any(|o| o.contains(": saved")));
    assert!(outcomes.iter().any(|o| o.contains("not saved")));
}

/// The replies (`ok …`, `error …`) logged in `from_s..to_s`.
fn replies_between(run: &Run, from_s: f64, to_s: f64) -> Vec<&str> {
    run.lines
        .iter()
        .filter(|l| (from_s..to_s).contains(&l.utc_s))
        .map(|l| l.text.as_str())
        .filter(|t| t.starts_with("ok") || t.starts_with("error"))
        .collect()
}

/// (l) Every typed line answered, by day (Kano 08:00Z, RTC, no GPS): 30
/// `save`s in a row (typed at line speed) get 30 replies, one save and
/// `error busy` for the lines that came during it; a
/// 100-character line is answered `error line too long` and the command
/// after it is answered; `time set` outside this firmware's dates (1969,
/// 2045) is refused with that reason and the RTC is not written.
#[test]
fn l_every_typed_line_is_answered() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T08:00:00Z");
    let long = "x".repeat(100);
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(GpsFeed::Silent)
        .bytes_at(2.0, b"save\n".repeat(30))
        .type_at(4.0, &long)
        .type_at(4.0, "get site.lat_deg")
        .type_at(5.0, "time set 1969-07-20T20:17:40Z")
        .type_at(5.5, "time set 2045-12-31T00:00:00Z")
        .run_minutes(7.0)
        .unwrap();
    report("l", &run);
    let s = start as f64;
    let saves = replies_between(&run, s + 120.0, s + 230.0);
    let ok = saves.iter().filter(|l| **l == "ok save").count();
    let busy = saves.iter().filter(|l| **l == "error busy").count();
    println!(
        "l: 30 saves typed in a row: {ok} ok save, {busy} busy, {} replies",
        saves.len()
    );
    assert_eq!(saves.len(), 30, "{saves:?}");
    assert!(ok >= 1 && ok + busy == 30, "{saves:?}");
    assert_eq!(
        replies_between(&run, s + 240.0, s + 290.0),
        ["error line too long", "ok site.lat_deg=11.9683"]
    );
    assert_eq!(
        replies_between(&run, s + 300.0, s + 400.0),
        [
            "error time set: outside this firmware's dates",
            "error time set: outside this firmware's dates"
        ]
    );
    assert_eq!(run.rtc_time_writes, 0, "the RTC was written");
}

/// (m) A flood the loop cannot keep up with (Kano 08:00Z, RTC): 40 pairs
/// of lines `help` and `set wind.stow_hz 25` pasted at once; each `help`
/// is answered with seven lines (about 280 bytes, 24 ms at 115200 baud,
/// for its 5), so input comes faster than the replies go out and the
/// 255-byte receive ring overflows. Every one of the 80 lines is answered
/// once: by its own reply, or `error input lost` (the line a gap falls in,
/// and each line the ring lost whole); no line runs with a piece missing
/// (`set wind.stow_hz 5` or `2` would be valid): every `set` answered sets
/// 25 Hz, the next line typed runs whole, and the threshold read back is
/// 25 Hz.
#[test]
fn m_lost_input_is_answered_never_run() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T08:00:00Z");
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(GpsFeed::Silent)
        .bytes_at(2.0, b"help\nset wind.stow_hz 25\n".repeat(40))
        .type_at(4.0, "get wind.stow_hz")
        .run_minutes(5.0)
        .unwrap();
    report("m", &run);
    let s = start as f64;
    let replies = replies_between(&run, s + 120.0, s + 230.0);
    let help = replies
        .iter()
        .filter(|l| **l == "ok status | faults | clear")
        .count();
    let set = replies
        .iter()
        .filter(|l| **l == "ok wind.stow_hz=25")
        .count();
    let lost = replies.iter().filter(|l| **l == "error input lost").count();
    println!(
        "m: 40 `help` and 40 `set` pasted: {help} help, {set} set, {lost} `error input lost`, {} reply lines",
        replies.len()
    );
    assert!(
        replies
            .iter()
            .filter(|l| l.starts_with("ok wind."))
            .all(|l| *l == "ok wind.stow_hz=25"),
        "{replies:?}"
    );
    assert!(lost >= 1, "the ring never overflowed: {replies:?}");
    assert_eq!(help + set + lost, 80, "{replies:?}");
    let closing = replies_between(&run, s + 230.0, s + 300.0);
    assert_eq!(closing, ["ok wind.stow_hz=25"]);
}

// ---------------------------------------------------------------------------
// (n), (o): receivers that lie about the place and the time. Each feed is a
// recorded one ([`lying_epochs`]): an epoch every 30 s of true time (as
// `GpsFeed::kano()`; every 10 s where the firmware's 60 s fault hold is
// tested), delivered when emulated UTC reaches it, whose text says another
// place or another time. The emulation build's monotonic clock runs with
// emulated time (60× CPU time), so the firmware's 10-minute rules are 10
// emulated minutes here.

/// Kano, the configuration's default site (`src/config/mod.rs`).
const KANO: (f64, f64) = (11.9683, 8.4261);
/// Seconds of true time between two epochs of a lying receiver.
const LIE_PERIOD_S: i64 = 30;
/// The same where a fault held 60 s after the last bad epoch is checked:
/// a receiver sends one epoch a second, and the image may miss an epoch
/// that arrives while a long pass (the day's plan) runs (under the 60×
/// compression such a pass outlasts the 1.5 s a fix stays fresh), which
/// at 30 s would leave 60 s without a bad epoch.
const LIE_FAST_PERIOD_S: i64 = 10;
/// Pointing tolerance of the lying-receiver scenarios: the sun for the true
/// site and time within 0.05°.
const LIE_POINTING_TOL_DEG: f64 = 0.05;

fn gps_site(lat_deg: f64, lon_deg: f64) -> GpsSite {
    GpsSite {
        lat_deg,
        lon_deg,
        elevation_m: 480.0,
    }
}

/// A feed from `start` + 10 s to the end of a run of `minutes`, an epoch
/// every `period_s`: epoch `k` due at true time `u` says `say(k, u)`
/// (position, time).
fn lying_feed(
    start: i64,
    minutes: f64,
    period_s: i64,
    say: impl FnMut(usize, i64) -> (GpsSite, i64),
) -> GpsFeed {
    let end = start + (minutes * 60.0) as i64;
    GpsFeed::Recorded(lying_epochs(start + 10, end, period_s, say))
}

/// Emulated UTC of each `fault <name> raised` line.
fn fault_raised(run: &Run, name: &str) -> Vec<f64> {
    run.lines
        .iter()
        .filter(|l| matches!(&l.event, Event::Fault { name: n, raised: true } if n == name))
        .map(|l| l.utc_s)
        .collect()
}

/// Every fault raised in the run, `name@+seconds` from `start`.
fn faults_summary(run: &Run, start: i64) -> String {
    let v: Vec<String> = run
        .lines
        .iter()
        .filter_map(|l| match &l.event {
            Event::Fault { name, raised } => Some(format!(
                "{name} {}@+{:.0}s",
                if *raised { "raised" } else { "cleared" },
                l.utc_s - start as f64
            )),
            _ => None,
        })
        .collect();
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}

/// The `site source=gps` lines: (emulated UTC, lat, lon).
fn gps_site_lines(run: &Run) -> Vec<(f64, f64, f64)> {
    run.lines
        .iter()
        .filter_map(|l| match &l.event {
            Event::Site {
                source,
                lat_deg,
                lon_deg,
            } if source == "gps" => Some((l.utc_s, *lat_deg, *lon_deg)),
            _ => None,
        })
        .collect()
}

/// The `clock jump from=… to=… source=…` lines.
fn clock_jumps(run: &Run) -> Vec<&LogLine> {
    run.lines
        .iter()
        .filter(|l| l.text.starts_with("clock jump "))
        .collect()
}

/// `from` and `to` of a `clock jump` line, Unix seconds.
fn clock_jump_from_to(line: &LogLine) -> Option<(i64, i64)> {
    let kv = |key: &str| {
        line.text
            .split_whitespace()
            .find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
            .and_then(parse_utc)
    };
    Some((kv("from")?, kv("to")?))
}

/// How many times the C and the A home switch closed (the image logs
/// `mode homing` at each homing, by night too).
fn home_closings(run: &Run) -> (usize, usize) {
    let n = |sw: usize| {
        run.switch_events
            .iter()
            .filter(|e| e.switch == sw && e.closed)
            .count()
    };
    (n(0), n(1))
}

/// No homing but the power-on one (which closes each home switch twice,
/// as with an honest receiver): no home switch closes after the first
/// set-point.
fn assert_homed_once(run: &Run) {
    let first_sp = set_points(run).first().expect("a set-point").0.utc_s;
    let later: Vec<_> = run
        .switch_events
        .iter()
        .filter(|e| e.switch <= 1 && e.closed && e.utc_s > first_sp)
        .collect();
    assert!(
        later.is_empty(),
        "homed again after tracking began: {later:?}; modes {:?}",
        run.modes()
    );
}

/// How late after its slot's start a set-point may be logged: after
/// power-on, a new site or a stow the real-time scheduler takes the present
/// slot's set-point whenever in the 4-minute slot that comes, and the day's
/// branch is then searched (two set-points a tick, the axes holding still,
/// up to some 100 ticks); far below the hour a lying clock is off by.
const SET_POINT_LATE_S: f64 = 360.0;

/// Each set-point's slot is the true time (the tracker runs on the true
/// clock): logged at most `late_s` after its slot and never before it by
/// more than a second.
fn assert_set_points_on_true_time(sps: &[SetPoint], late_s: f64) {
    for (l, utc, ..) in sps {
        let d = l.utc_s - *utc as f64;
        assert!(
            (-1.0..=late_s).contains(&d),
            "set-point for {} logged at {} ({d:+.0} s): not the true time",
            format_utc(*utc),
            format_utc(l.utc_s as i64)
        );
    }
}

/// Set-points keep coming: the longest gap between two (and from the last
/// to the end of the run) is at most `max_gap_s`.
fn assert_set_points_keep_coming(run: &Run, sps: &[SetPoint], max_gap_s: f64) -> f64 {
    let end = run.start_unix_s as f64 + run.emulated_s;
    let mut times: Vec<f64> = sps.iter().map(|s| s.0.utc_s).collect();
    times.push(end);
    let gap = times.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    assert!(gap <= max_gap_s, "{gap:.0} s without a set-point");
    gap
}

/// (n1) A receiver alternating between Kano and Sydney every 5 minutes
/// (epochs every 30 s, true time), Kano's stored site, RTC valid, from
/// 2026-06-21T08:00Z for 40 minutes: Sydney is never taken (every `site
/// source=gps` line is Kano's), `fault gps_position_unstable raised` once
/// (the third jump: away at 5 min, back at 10, away at 15; the jumps every 5
/// minutes after it keep it raised), set-points keep coming and are within
/// 0.05° of SPA's sun at Kano, and the axes home once (at power-on).
#[test]
fn n1_position_alternating_kano_sydney_is_not_followed() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T08:00:00Z");
    let minutes = 40.0;
    let feed = lying_feed(start, minutes, LIE_PERIOD_S, |_, u| {
        let (lat, lon) = if ((u - start) / 300) % 2 == 1 {
            SYDNEY
        } else {
            KANO
        };
        (gps_site(lat, lon), u)
    });
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(feed)
        .run_minutes(minutes)
        .unwrap();
    report("n1", &run);
    let sites = gps_site_lines(&run);
    let unstable = fault_raised(&run, "gps_position_unstable");
    let sps = set_points(&run);
    println!(
        "n1: {} GPS epochs, {} `site source=gps` lines {:?}, gps_position_unstable raised {} time(s) at {:?} s, home switch closings (C, A) {:?}, {} clock jumps; faults: {}",
        run.gps_epochs,
        sites.len(),
        sites.iter().map(|s| (s.1, s.2)).collect::<Vec<_>>(),
        unstable.len(),
        unstable.iter().map(|t| (t - start as f64).round()).collect::<Vec<_>>(),
        home_closings(&run),
        clock_jumps(&run).len(),
        faults_summary(&run, start)
    );
    assert!(!sites.is_empty(), "Kano's fix was never taken");
    for (at, lat, lon) in &sites {
        assert!(
            (lat - KANO.0).abs() <= 0.01 && (lon - KANO.1).abs() <= 0.01,
            "site lat={lat} lon={lon} taken at {}",
            format_utc(*at as i64)
        );
    }
    assert_eq!(
        unstable.len(),
        1,
        "gps_position_unstable raised {unstable:?}"
    );
    // The third jump comes at 15 min (the fourth epoch of Sydney's second
    // spell would be late): raised between then and a minute later.
    let third_jump = (start + 900) as f64;
    assert!(
        (third_jump - 1.0..=third_jump + 60.0).contains(&unstable[0]),
        "raised at {}",
        format_utc(unstable[0] as i64)
    );
    assert_homed_once(&run);
    assert!(clock_jumps(&run).is_empty());
    let n = check_set_points(&run, &MountAttitude::level(), LIE_POINTING_TOL_DEG);
    assert!(n >= 8, "{n} set-points");
    assert_set_points_on_true_time(&sps, SET_POINT_LATE_S);
    let gap = assert_set_points_keep_coming(&run, &sps, 300.0);
    println!("n1: {n} set-points, longest gap {gap:.0} s");
    assert_no_illegal_steps(&run);
}

/// A site on the date line (Fiji's latitude, 16.5 S), where a receiver's
/// longitude jitters between 179.99999 E and 179.99999 W (2 m apart).
const DATE_LINE: (f64, f64) = (-16.5, 179.99999);

/// (n2) The tracker stands on the date line (its compass sees the field
/// there, WMM2025), configured for Kano, RTC valid, from
/// 2026-06-21T21:00Z (09:00 local solar time; night at Kano) for 40
/// minutes; the receiver's longitude alternates 179.99999 E / W every
/// epoch. The fixes agree with each other (longitudes compared modulo
/// 360°): the place is taken once it has been consistent for 10 minutes,
/// in one `site source=gps` line (not one per epoch), with no
/// `gps_position_unstable`; every set-point after it within 0.05° of SPA's
/// sun there.
#[test]
fn n2_position_jittering_across_the_date_line_is_adopted_once() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T21:00:00Z");
    let minutes = 40.0;
    let (lat, lon) = DATE_LINE;
    let feed = lying_feed(start, minutes, LIE_PERIOD_S, |k, u| {
        (gps_site(lat, if k % 2 == 0 { lon } else { -lon }), u)
    });
    let run = MegaBench::mega(&elf)
        .field(Field::wmm2025(lat, lon, 0.48, (2026, 6, 21)))
        .start(start)
        .rtc(Rtc::Valid)
        .gps(feed)
        .run_minutes(minutes)
        .unwrap();
    report("n2", &run);
    let sites = gps_site_lines(&run);
    let unstable = fault_raised(&run, "gps_position_unstable");
    println!(
        "n2: {} GPS epochs, {} `site source=gps` lines {:?}, gps_position_unstable raised {} time(s), {} clock jumps; faults: {}",
        run.gps_epochs,
        sites.len(),
        sites
            .iter()
            .map(|s| format!("{} ({:+.0} s) {} {}", format_utc(s.0 as i64), s.0 - start as f64, s.1, s.2))
            .collect::<Vec<_>>(),
        unstable.len(),
        clock_jumps(&run).len(),
        faults_summary(&run, start)
    );
    assert_eq!(sites.len(), 1, "{sites:?}");
    let (taken, s_lat, s_lon) = sites[0];
    assert!(
        (s_lat - lat).abs() <= 0.001 && (s_lon.abs() - 180.0).abs() <= 0.001,
        "site lat={s_lat} lon={s_lon}"
    );
    // Consistent for 10 minutes from the first epoch (start + 10 s).
    let first_epoch = (start + 10) as f64;
    assert!(
        taken >= first_epoch + 600.0 - 1.0
            && taken <= first_epoch + 600.0 + 2.0 * LIE_PERIOD_S as f64,
        "taken at {} ({:+.0} s after the first epoch)",
        format_utc(taken as i64),
        taken - first_epoch
    );
    assert!(
        unstable.is_empty(),
        "gps_position_unstable raised {unstable:?}"
    );
    let sps: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|s| s.0.utc_s > taken)
        .collect();
    assert!(sps.len() >= 4, "{} set-points after the site", sps.len());
    check_set_points_of(
        &sps,
        &MountAttitude::level(),
        |u| sun_at(lat, lon, u),
        LIE_POINTING_TOL_DEG,
    );
    assert_set_points_on_true_time(&sps, SET_POINT_LATE_S);
    assert_no_illegal_steps(&run);
}

/// (n3) A fix at the North Pole (90 N) on 2026-06-21, configured for Kano,
/// RTC valid, from 12:00Z for 40 minutes: the pole is taken after 10
/// minutes; its day is polar (the sun up for all 24 hours, a table of 361
/// entries where the Mega's holds 240). The tracker must not be left in
/// `wait_for_time` with `schedule_failed`: after the site, set-points whose
/// zenith is within 0.05° of SPA's at the pole (the harness's compass field
/// is WMM2025's at 89.999 N, its model's range).
#[test]
fn n3_position_at_the_north_pole_in_june_tracks() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T12:00:00Z");
    let minutes = 40.0;
    let pole = (90.0, 0.0);
    let feed = lying_feed(start, minutes, LIE_PERIOD_S, |_, u| {
        (gps_site(pole.0, pole.1), u)
    });
    let run = MegaBench::mega(&elf)
        .field(Field::wmm2025(89.999, 0.0, 0.48, (2026, 6, 21)))
        .start(start)
        .rtc(Rtc::Valid)
        .gps(feed)
        .run_minutes(minutes)
        .unwrap();
    report("n3", &run);
    let sites = gps_site_lines(&run);
    let failed = fault_raised(&run, "schedule_failed");
    println!(
        "n3: {} `site source=gps` lines {:?}, schedule_failed raised {} time(s), modes {:?}; faults: {}",
        sites.len(),
        sites.iter().map(|s| (s.1, s.2)).collect::<Vec<_>>(),
        failed.len(),
        run.modes(),
        faults_summary(&run, start)
    );
    let taken = sites
        .iter()
        .find(|s| (s.1 - 90.0).abs() <= 0.001)
        .expect("the pole taken")
        .0;
    assert!(
        failed.iter().all(|t| *t < taken),
        "schedule_failed after the pole was taken: {failed:?}"
    );
    let modes_after_site = modes_after(&run, taken);
    assert_ne!(
        modes_after_site.last(),
        Some(&"wait_for_time"),
        "{modes_after_site:?}"
    );
    let sps: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|s| s.0.utc_s > taken)
        .collect();
    assert!(sps.len() >= 2, "{} set-points after the site", sps.len());
    let mut worst: f64 = 0.0;
    for (l, utc, ..) in &sps {
        let Event::SetPoint { zenith_deg, .. } = l.event else {
            unreachable!()
        };
        let spa = Site::with_elevation(pole.0, pole.1, 480.0).unwrap();
        let p = Algorithm::Spa
            .position(
                &UtcTime::from_unix_seconds(*utc).unwrap(),
                &spa,
                &Options::default(),
            )
            .unwrap();
        let err = (zenith_deg - p.zenith_deg).abs();
        worst = worst.max(err);
        assert!(
            err <= LIE_POINTING_TOL_DEG,
            "{}: zenith {zenith_deg} against SPA {}",
            l.text,
            p.zenith_deg
        );
    }
    println!(
        "n3: {} set-points after the site, worst zenith error {worst:.4}°",
        sps.len()
    );
    // The panel normal against SPA's sun there, printed, not asserted: the
    // heading comes from the compass, whose horizontal field and WMM
    // declination at the pole are those of a point where every direction
    // is south (the zenith above does not depend on it).
    let pointing: Vec<String> = sps
        .iter()
        .map(|&(_, utc, c, a)| {
            let pose = Pose {
                gamma_deg: c,
                alpha_deg: a,
            };
            let err = angle_between_deg(
                &MountAttitude::<f64>::level().normal_xyz(&pose),
                &sun_at(pole.0, pole.1, utc),
            );
            format!("{err:.3}")
        })
        .collect();
    println!("n3: panel normal from SPA's sun at the pole, degrees: {pointing:?}");
    assert_no_illegal_steps(&run);
}

/// (o1) Kano, RTC valid at the true time, from 2026-06-21T08:00Z for 20
/// minutes; the receiver is consistent but one hour behind. For the first
/// 10 minutes of consistent epochs (the monotonic clock's 10 minutes) the
/// time stays the RTC's: no `clock jump`, set-points on the true time and
/// within 0.05° of SPA's sun; then exactly one `clock jump … source=gps`
/// one hour back, and one write of the RTC.
#[test]
fn o1_time_an_hour_behind_is_adopted_after_ten_minutes() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T08:00:00Z");
    let minutes = 20.0;
    let kano = gps_site(KANO.0, KANO.1);
    let feed = lying_feed(start, minutes, LIE_PERIOD_S, |_, u| (kano, u - 3600));
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(feed)
        .run_minutes(minutes)
        .unwrap();
    report("o1", &run);
    let jumps = clock_jumps(&run);
    let first_epoch = (start + 10) as f64;
    println!(
        "o1: {} GPS epochs, {} clock jumps {:?}, RTC written {} time(s), {} `site source=gps` lines; faults: {}",
        run.gps_epochs,
        jumps.len(),
        jumps
            .iter()
            .map(|l| format!("+{:.0}s after the first epoch: {}", l.utc_s - first_epoch, l.text))
            .collect::<Vec<_>>(),
        run.rtc_time_writes,
        gps_site_lines(&run).len(),
        faults_summary(&run, start)
    );
    assert_eq!(jumps.len(), 1, "clock jumps: {jumps:?}");
    let jump = jumps[0];
    assert!(jump.text.contains("source=gps"), "{}", jump.text);
    // Ten minutes of consistent epochs from the first (a tick of slack
    // before, an epoch or two after).
    let since = jump.utc_s - first_epoch;
    assert!(
        (599.0..=600.0 + 2.0 * LIE_PERIOD_S as f64 + 2.0).contains(&since),
        "the jump came {since:.0} s after the first epoch"
    );
    let (from, to) = clock_jump_from_to(jump).expect("from= and to=");
    // `from` is the tick before the jump; the line ends after the pass
    // that re-plans the day (seconds of emulated time at 60×).
    assert!(
        (-1.0..=10.0).contains(&(jump.utc_s - from as f64)),
        "from={} is not the true time {}",
        format_utc(from),
        format_utc(jump.utc_s as i64)
    );
    assert!(
        ((to - from) + 3600).abs() <= 3,
        "the jump is {} s, not one hour back",
        to - from
    );
    assert_eq!(
        run.rtc_time_writes, 1,
        "the RTC was written {} times",
        run.rtc_time_writes
    );
    assert!(fault_raised(&run, "gps_time_unstable").is_empty());
    // Before the jump: the RTC's (true) time, the sun at Kano.
    let before: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|s| s.0.utc_s < jump.utc_s)
        .collect();
    assert!(
        before.len() >= 2,
        "{} set-points before the jump",
        before.len()
    );
    assert_set_points_on_true_time(&before, SET_POINT_LATE_S);
    check_set_points_of(
        &before,
        &MountAttitude::level(),
        kano_sun,
        LIE_POINTING_TOL_DEG,
    );
    // After it: the log's time is GPS's, an hour behind.
    let after: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|s| s.0.utc_s > jump.utc_s)
        .collect();
    for (l, utc, ..) in &after {
        let behind = l.utc_s - *utc as f64;
        assert!(
            // Within its slot (the table's 4 minutes): the first after the
            // jump is the present slot's, whose start the jump passed.
            (3600.0 - 1.0..3600.0 + 240.0).contains(&behind),
            "after the jump: set-point for {} logged at {}",
            format_utc(*utc),
            format_utc(l.utc_s as i64)
        );
    }
    println!(
        "o1: {} set-points before the jump, {} after (slots one hour behind)",
        before.len(),
        after.len()
    );
    assert_no_illegal_steps(&run);
}

/// What (o2)–(o4) assert: the tracker stays on the RTC (true time): no
/// `clock jump`, no RTC write, no `time source=gps`; `fault` raised exactly
/// once; at least `min_sps` set-points, all on the true time, within 0.05°
/// of SPA's sun at Kano, and coming at most 5 minutes apart.
fn assert_stays_on_the_rtc(name: &str, run: &Run, start: i64, fault: &str, min_sps: usize) {
    let jumps = clock_jumps(run);
    let raised = fault_raised(run, fault);
    let sps = set_points(run);
    println!(
        "{name}: {} GPS epochs, {} clock jumps, RTC written {} time(s), {fault} raised {} time(s) at {:?} s, {} set-points, {} `site source=gps` lines, home switch closings (C, A) {:?}; modes {:?}; faults: {}",
        run.gps_epochs,
        jumps.len(),
        run.rtc_time_writes,
        raised.len(),
        raised.iter().map(|t| (t - start as f64).round()).collect::<Vec<_>>(),
        sps.len(),
        gps_site_lines(run).len(),
        home_closings(run),
        run.modes().iter().map(|(_, m)| m.as_str()).collect::<Vec<_>>(),
        faults_summary(run, start)
    );
    assert!(jumps.is_empty(), "{jumps:?}");
    assert_eq!(run.rtc_time_writes, 0, "the RTC was written");
    assert_eq!(raised.len(), 1, "{fault} raised {raised:?}");
    assert!(sps.len() >= min_sps, "{} set-points", sps.len());
    assert_set_points_on_true_time(&sps, SET_POINT_LATE_S);
    check_set_points(run, &MountAttitude::level(), LIE_POINTING_TOL_DEG);
    assert_set_points_keep_coming(run, &sps, 300.0);
    assert_homed_once(run);
    assert_no_illegal_steps(run);
}

/// (o2) Kano, RTC valid, from 2026-06-21T08:00Z for 30 minutes; the
/// receiver's epochs (every 10 s) say one hour ahead and one hour behind in
/// turn: never
/// adopted (no `clock jump`, no RTC write), `fault gps_time_unstable
/// raised` once (from the third disagreement, held by the next ones), the
/// set-points on the true time within 0.05° of SPA's sun.
#[test]
fn o2_time_alternating_plus_minus_an_hour_is_never_adopted() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T08:00:00Z");
    let minutes = 30.0;
    let kano = gps_site(KANO.0, KANO.1);
    let feed = lying_feed(start, minutes, LIE_FAST_PERIOD_S, |k, u| {
        (kano, if k % 2 == 0 { u + 3600 } else { u - 3600 })
    });
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(feed)
        .run_minutes(minutes)
        .unwrap();
    report("o2", &run);
    assert_stays_on_the_rtc("o2", &run, start, "gps_time_unstable", 6);
    assert!(
        !has_line(
            &run,
            |e| matches!(e, Event::Time { source, .. } if source == "gps")
        ),
        "GPS time adopted"
    );
}

/// (o3) Kano, RTC valid, from 2026-06-21T08:00Z for 40 minutes; the
/// receiver's first epoch says the true time, each after it 100 s earlier
/// than the one before (10 s later in true time): by the end it says about
/// 01:25Z, before sunrise. `fault gps_time_unstable raised` once; once
/// tracking, the mode is never `night` (the image logs `mode night` at
/// power-on while it homes, with an honest receiver too: see (e)'s log);
/// the set-points on the true time within 0.05° of SPA's sun.
#[test]
fn o3_time_running_backwards_is_never_adopted() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T08:00:00Z");
    let minutes = 40.0;
    let kano = gps_site(KANO.0, KANO.1);
    let first = start + 10;
    let feed = lying_feed(start, minutes, LIE_FAST_PERIOD_S, |k, _| {
        (kano, first - 100 * k as i64)
    });
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(feed)
        .run_minutes(minutes)
        .unwrap();
    report("o3", &run);
    let modes = run.modes();
    let tracking = modes
        .iter()
        .find(|(_, m)| m == "tracking")
        .expect("mode tracking")
        .0;
    assert!(
        modes_after(&run, tracking).iter().all(|m| *m != "night"),
        "night in daylight: {modes:?}"
    );
    assert_stays_on_the_rtc("o3", &run, start, "gps_time_unstable", 8);
}

/// (o4) Kano, RTC valid, from 2026-06-21T08:00Z for 20 minutes; the
/// receiver (an epoch every 10 s) has the week-rollover bug: its dates are
/// 1024 weeks (7168 days) early, 2006-11-05. `fault gps_time_implausible raised` once over the 20
/// minutes (held while such epochs keep coming, not raised at each), the
/// tracker carries on with the RTC: set-points on the true time within
/// 0.05° of SPA's sun.
#[test]
fn o4_week_rollover_is_reported_once_and_tracking_goes_on() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T08:00:00Z");
    let minutes = 20.0;
    let kano = gps_site(KANO.0, KANO.1);
    let feed = lying_feed(start, minutes, LIE_FAST_PERIOD_S, |_, u| {
        (kano, u - 7168 * 86_400)
    });
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(feed)
        .run_minutes(minutes)
        .unwrap();
    report("o4", &run);
    assert!(has_line(
        &run,
        |e| matches!(e, Event::Time { source, .. } if source == "rtc")
    ));
    assert!(
        !has_line(
            &run,
            |e| matches!(e, Event::Time { source, .. } if source == "gps")
        ),
        "GPS time adopted"
    );
    assert_stays_on_the_rtc("o4", &run, start, "gps_time_implausible", 4);
}

/// The longest a loop pass may keep the CPU awake after the first, seconds:
/// a tick's work (the plan's four sun positions, a search's two set-points,
/// the drives, the log) stays far inside the 1 s tick and the 2 s watchdog;
/// the console and the steppers are served between passes.
const LONGEST_PASS_S: f64 = 0.060;
/// The power-on pass may take longer: it also synthesises the WMM2025
/// declination for the site (about 49 ms, once per site and day).
const LONGEST_FIRST_PASS_S: f64 = 0.110;

/// (p) The board build, the ELF a user flashes, at real time (1:1, as
/// (h)): powered on at Kano after sunset (2026-06-21T19:30Z, RTC valid,
/// GPS), 10 minutes: the axes home, the coming sunrise is found (the first
/// 4-minute slot with the sun up, one sun position a slot, four a tick),
/// the pose to wait for sunrise in is searched (48 sun positions and 288
/// inverse kinematics, spread over ticks) and driven to. Every pass after the
/// power-on one keeps the CPU awake at most [`LONGEST_PASS_S`] (the search
/// in one tick took some 135 ms of every second, and a day's branch search
/// about one second), the power-on pass at most [`LONGEST_FIRST_PASS_S`].
#[test]
fn p_a_night_at_real_time_keeps_every_pass_short() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_MEGA_RELEASE");
    let id = ElfIdentity::of_board_build(&elf).unwrap();
    println!("p: {id}");
    let minutes = 10.0;
    let start = t("2026-06-21T19:30:00Z");
    let run = MegaBench::mega(&elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(GpsFeed::kano())
        .run_minutes(minutes)
        .unwrap();
    report("p", &run);
    assert_eq!(run.cpu, CpuState::Running, "the CPU stopped");
    assert_eq!(run.time_segments.len(), 1, "{:?}", run.time_segments);
    assert!(has_line(
        &run,
        |e| matches!(e, Event::Mode(m) if m == "night")
    ));
    assert!(
        !has_line(&run, |e| matches!(e, Event::Mode(m) if m == "tracking")),
        "tracking at night"
    );
    assert!(homed_at(&run.switch_events, start as f64).is_some());
    let (first, rest) = run.long_passes.split_first().expect("no pass over 10 ms");
    let longest_rest = rest
        .iter()
        .copied()
        .fold((0.0, 0.0), |a, p| if p.0 > a.0 { p } else { a });
    println!(
        "p: power-on pass {:.1} ms (bound {:.0} ms); {} later passes over 10 ms, the longest {:.1} ms at {} (bound {:.0} ms)",
        first.0 * 1e3,
        LONGEST_FIRST_PASS_S * 1e3,
        rest.len(),
        longest_rest.0 * 1e3,
        format_utc(longest_rest.1 as i64),
        LONGEST_PASS_S * 1e3
    );
    assert!(
        first.1 < start as f64 + 2.0,
        "the first long pass is not the power-on one"
    );
    assert!(first.0 <= LONGEST_FIRST_PASS_S);
    assert!(
        longest_rest.0 <= LONGEST_PASS_S,
        "a pass of {:.1} ms at {}",
        longest_rest.0 * 1e3,
        format_utc(longest_rest.1 as i64)
    );
    let mut hist = std::collections::BTreeMap::new();
    for (len, _) in rest {
        *hist.entry((len * 200.0) as u32 * 5).or_insert(0u32) += 1;
    }
    println!("p: later passes over 10 ms by 5 ms bins (ms: count): {hist:?}");
    // The search ran: passes over 10 ms after the homing, at night.
    assert!(!rest.is_empty());
    // Waiting facing the coming sunrise: the first 4-minute slot of the
    // morning with SPA's sun (geometric centre) above the horizon.
    let first_slot = (start / 240 + 1) * 240;
    let rise = (0..360)
        .map(|k| first_slot + k * 240)
        .find(|&u| kano_sun(u)[2] > 0.0)
        .expect("a sunrise within a day");
    let (c, a) = run.final_angles;
    let normal = MountAttitude::level().normal_xyz(&Pose {
        gamma_deg: c,
        alpha_deg: a,
    });
    let off_deg = angle_between_deg(&normal, &kano_sun(rise));
    println!(
        "p: waiting facing the sunrise slot {} within {off_deg:.3}°",
        format_utc(rise)
    );
    assert!(off_deg < 0.2, "{off_deg}° from the sun at sunrise");
    assert_no_illegal_steps(&run);
    assert_eq!(
        ElfIdentity::of(&elf).unwrap(),
        id,
        "the ELF changed during the run"
    );
}

/// The sun's elevation at Tromsø (SPA, geometric, 480 m), degrees.
fn tromso_elevation_deg(unix_s: i64) -> f64 {
    let site = Site::with_elevation(TROMSO.0, TROMSO.1, 480.0).unwrap();
    let p = Algorithm::Spa
        .position(
            &UtcTime::from_unix_seconds(unix_s).unwrap(),
            &site,
            &Options::default(),
        )
        .unwrap();
    90.0 - p.zenith_deg
}

/// Tromsø, the site of the polar-day scenario (q).
const TROMSO: (f64, f64) = (69.65, 18.96);

/// Tromsø's midnight sun of (q) and (u): 2026-06-10 from 22:00Z for 100
/// minutes, the RTC valid and GPS, the Earth's field there; the start, the
/// minutes and the bench.
fn tromso_midnight(elf: &Path) -> (i64, f64, MegaBench) {
    let start = t("2026-06-10T22:00:00Z");
    let minutes = 100.0;
    let feed = lying_feed(start, minutes, LIE_PERIOD_S, |_, u| {
        (gps_site(TROMSO.0, TROMSO.1), u)
    });
    let bench = MegaBench::mega(elf)
        .field(Field::wmm2025(TROMSO.0, TROMSO.1, 0.48, (2026, 6, 10)))
        .start(start)
        .rtc(Rtc::Valid)
        .gps(feed);
    (start, minutes, bench)
}

/// (q) Tromsø in the midnight sun, 2026-06-10 from 22:00Z for 100 minutes,
/// RTC and GPS. The C axis turns one whole turn (−180…180°) and the sun
/// circles the sky: once a day the axis must turn back, and the image
/// must do it at the sun's lowest (about 22:43Z, 2.7° up), logging
/// `mode unwind` from the swing's start until both axes are on the new
/// pose, then `mode tracking`; the open-loop axes take the day's
/// re-homing just before it (`mode homing`). Exactly one unwind; it begins
/// with the sun within 1° of its lowest over the run (SPA sampled every
/// minute); every set-point after it is within a step of the axes and
/// 0.05° of SPA's sun.
#[test]
fn q_polar_day_unwinds_once_at_the_sun_lowest() {
    let elf = elf_or_skip!();
    let (start, minutes, bench) = tromso_midnight(&elf);
    let run = bench.run_minutes(minutes).unwrap();
    report("q", &run);
    let modes = run.modes();
    println!(
        "q: modes {modes:?}; faults: {}",
        faults_summary(&run, start)
    );
    let unwinds: Vec<f64> = modes
        .iter()
        .filter(|(_, m)| m == "unwind")
        .map(|(t, _)| *t)
        .collect();
    assert_eq!(unwinds.len(), 1, "{modes:?}");
    let unwind_s = unwinds[0];
    let lowest_deg = (0..=minutes as i64)
        .map(|m| tromso_elevation_deg(start + 60 * m))
        .fold(f64::INFINITY, f64::min);
    let at_deg = tromso_elevation_deg(unwind_s as i64);
    println!(
        "q: unwind at {} with the sun at {at_deg:.2}° (lowest {lowest_deg:.2}°)",
        format_utc(unwind_s as i64)
    );
    assert!(at_deg < lowest_deg + 1.0, "{at_deg} against {lowest_deg}");
    // Homing (the day's, for open-loop axes) just before it, none after;
    // the power-on homing (before the first tracking) aside.
    let first_tracking_s = modes
        .iter()
        .find(|(_, m)| m == "tracking")
        .map_or(0.0, |(t, _)| *t);
    let homings: Vec<f64> = modes
        .iter()
        .filter(|(t, m)| m == "homing" && *t > first_tracking_s)
        .map(|(t, _)| *t)
        .collect();
    assert!(
        homings
            .iter()
            .all(|t| *t < unwind_s && *t > unwind_s - 120.0),
        "{modes:?}"
    );
    // Tracking again after it, and then only tracking.
    let after: Vec<&str> = modes_after(&run, unwind_s + 1.0);
    assert_eq!(after.first(), Some(&"tracking"), "{modes:?}");
    assert!(after.iter().all(|m| *m == "tracking"), "{modes:?}");
    let back_s = modes
        .iter()
        .find(|(t, m)| *t > unwind_s && m == "tracking")
        .map(|(t, _)| *t)
        .unwrap();
    // The turn back ends: a whole turn at the axis's speed, and the
    // controller's ticks to see it done and take the next set-point
    // (minutes in this time-compressed build).
    println!("q: unwind for {:.0} s", back_s - unwind_s);
    assert!(back_s - unwind_s <= 360.0 / min_axis_deg_s() + 600.0);
    let sps: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|s| s.0.utc_s > back_s)
        .collect();
    assert!(sps.len() >= 10, "{} set-points after the unwind", sps.len());
    // Within 0.05° (as the other sites' scenarios): the heading comes from
    // the compass, and Tromsø's horizontal field is a third of Kano's
    // (0.02°–0.03° off before the unwind as after it; the sun itself is
    // within 0.001° in zenith and 0.006° in azimuth of SPA).
    check_set_points_of(
        &sps,
        &MountAttitude::level(),
        |u| sun_at(TROMSO.0, TROMSO.1, u),
        LIE_POINTING_TOL_DEG,
    );
    assert_no_illegal_steps(&run);
}

/// (u) The midnight sun of (q) on a C axis that turns without end: a slip
/// ring, the bench's C axis with an index cam once a turn at −180° (≡
/// 180°) and no end switch, `set axis.c.continuous 1` typed into the
/// running image. No unwind, no fault, no homing after the first
/// set-point but at most the open-loop axes' day re-homing (which seeks the
/// index and returns to the branch followed): the axis follows the sun round
/// past its index (the switch closes as it passes, and the drive does not
/// stop there), ends beyond ±180°, and every
/// set-point is reached (the decoded angle within a step of it, modulo a
/// turn) with its panel normal within 0.05° of SPA's sun, as in (q).
#[test]
fn u_continuous_c_axis_passes_its_index_and_never_unwinds() {
    let elf = elf_or_skip!();
    let (start, minutes, bench) = tromso_midnight(&elf);
    let run = bench
        .continuous_c()
        .type_at(0.5, "set axis.c.continuous 1")
        .run_minutes(minutes)
        .unwrap();
    report("u", &run);
    let modes = run.modes();
    println!(
        "u: modes {modes:?}; faults: {}",
        faults_summary(&run, start)
    );
    assert!(
        run.lines.iter().any(|l| l.text == "ok axis.c.continuous=1"),
        "the key was not taken"
    );
    assert!(modes.iter().all(|(_, m)| m != "unwind"), "{modes:?}");
    let first_tracking_s = modes
        .iter()
        .find(|(_, m)| m == "tracking")
        .map(|(t, _)| *t)
        .expect("tracking");
    // Tracking throughout but for at most the open-loop axes' one
    // re-homing of the new day (22:44Z, the scheduler's day boundary near
    // the sun's lowest; none here: the power-on homing, 44 minutes before,
    // counts as the day's).
    let after = modes_after(&run, first_tracking_s + 1.0);
    assert!(
        after.iter().all(|m| *m == "tracking" || *m == "homing")
            && after.iter().filter(|m| **m == "homing").count() <= 1
            && after.last().is_none_or(|m| *m == "tracking"),
        "{modes:?}"
    );
    assert!(
        !run.lines
            .iter()
            .any(|l| l.utc_s > first_tracking_s
                && matches!(l.event, Event::Fault { raised: true, .. })),
        "faults: {}",
        faults_summary(&run, start)
    );
    // The index passed while tracking, and the axis on beyond it.
    let passes = run
        .switch_events
        .iter()
        .filter(|e| e.switch == 0 && e.closed && e.utc_s > first_tracking_s)
        .count();
    println!(
        "u: index passed {passes} times; final C {:.3}",
        run.final_angles.0
    );
    assert!(passes >= 1);
    assert!(run.final_angles.0.abs() > 180.0);
    // Every set-point reached and on the sun; the decoded angle counts
    // turns, the set-points do not.
    let sps: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|s| s.0.utc_s > first_tracking_s)
        .collect();
    // The 4-minute table over some 90 minutes of tracking.
    assert!(sps.len() >= 20, "{} set-points", sps.len());
    let homings: Vec<f64> = modes
        .iter()
        .filter(|(t, m)| m == "homing" && *t > first_tracking_s)
        .map(|(t, _)| *t)
        .collect();
    // The C angles taken to the turn the decoder counts (the image's count
    // is kept within a turn of its switch), each against the next
    // set-point's decoded angle; checked as every scenario's, in the runs
    // between the day's re-homing (the axes leave a set-point for it).
    let in_turn: Vec<SetPoint> = sps
        .iter()
        .zip(sps.iter().skip(1).map(Some).chain([None]))
        .map(|(&(line, utc, c, a), next)| {
            let turns = next.map_or(0.0, |n| ((n.0.c_start_deg - c) / 360.0).round());
            (line, utc, c + 360.0 * turns, a)
        })
        .collect();
    let mut checked = 0;
    let mut from = 0;
    for k in 0..in_turn.len() {
        let end = k + 1 == in_turn.len();
        let spans_homing = !end
            && homings
                .iter()
                .any(|h| *h > in_turn[k].0.utc_s && *h < in_turn[k + 1].0.utc_s);
        if spans_homing || end {
            if k > from {
                checked += check_set_points_of(
                    &in_turn[from..=k],
                    &MountAttitude::level(),
                    |u| sun_at(TROMSO.0, TROMSO.1, u),
                    LIE_POINTING_TOL_DEG,
                );
            }
            from = k + 1;
        }
    }
    assert!(checked >= 20, "{checked} set-points checked");
    assert_no_illegal_steps(&run);
}

/// The mode logged last at or before emulated UTC `at_s` (the power-on
/// mode before the first).
fn mode_at(modes: &[(f64, String)], at_s: f64) -> &str {
    modes
        .iter()
        .rev()
        .find(|(t, _)| *t <= at_s)
        .map_or("", |(_, m)| m.as_str())
}

/// Kano from 2026-06-21T08:00Z, RTC valid and GPS (the weather and supply
/// scenarios' morning).
fn kano_morning(elf: &Path) -> (i64, MegaBench) {
    let start = t("2026-06-21T08:00:00Z");
    let bench = MegaBench::mega(elf)
        .start(start)
        .rtc(Rtc::Valid)
        .gps(GpsFeed::kano());
    (start, bench)
}

/// Prints the run's modes and faults, and checks the mode in force at
/// each (minute, mode) of `want`; returns the modes.
fn modes_at_minutes(name: &str, run: &Run, start: i64, want: &[(f64, &str)]) -> Vec<(f64, String)> {
    let modes = run.modes();
    println!(
        "{name}: modes {modes:?}; faults: {}",
        faults_summary(run, start)
    );
    for &(m, mode) in want {
        let at = start as f64 + m * 60.0;
        assert_eq!(mode_at(&modes, at), mode, "{name}: minute {m}: {modes:?}");
    }
    modes
}

/// Tracking again from `minute`: at least five set-points, each within a
/// step of the axes and 0.02° of SPA's sun at Kano; no illegal step.
fn tracks_after(run: &Run, start: i64, minute: f64) {
    let sps: Vec<_> = set_points(run)
        .into_iter()
        .filter(|s| s.0.utc_s > start as f64 + minute * 60.0)
        .collect();
    assert!(
        sps.len() >= 5,
        "{} set-points after minute {minute}",
        sps.len()
    );
    check_set_points_of(&sps, &MountAttitude::level(), kano_sun, 0.02);
    assert_no_illegal_steps(run);
}

/// (r) The weather contacts at Kano, 2026-06-21 from 08:00Z for 105
/// minutes, RTC and GPS, both release times typed down to 300 s at
/// minute 1: the snow switch closed over minutes 20–30 (`snow_stow`, the
/// panel upright at the A axis's limit, until 5 minutes after it opens),
/// the hail contact over 45–75 with a 40 Hz gust over 45–55 (`hail_stow`,
/// then `wind_stow` within seconds: flat for the gust and its 10-minute
/// release; the hail slope of 60° again; tracking 5 minutes after the
/// contact opens), the
/// plant's stow contact (active low, the default) over 85–95
/// (`external_stow`, flat, while it is closed). Each mode is logged when
/// its contact changes (within a minute: the image ticks the controller
/// once a minute of emulated time in this build), the A axis reaches its
/// stow slope within two minutes, the C axis stays, and every set-point
/// after the last contact opens is within a step and 0.02° of the sun.
#[test]
fn r_weather_contacts_stow_and_release() {
    let elf = elf_or_skip!();
    let (start, bench) = kano_morning(&elf);
    let run = bench
        .type_at(1.0, "set stow.snow_release_s 300")
        .type_at(1.5, "set stow.hail_release_s 300")
        .contact_at(20.0, Contact::Snow, true)
        .contact_at(30.0, Contact::Snow, false)
        .contact_at(45.0, Contact::Hail, true)
        // The gust as the axes start for the hail slope: the harness runs
        // at real time while coils are driven, so the anemometer's pulses
        // come at their rate (in compressed time it pulses slower).
        .wind(WindProfile::gust(start + 45 * 60, 10, 40.0))
        .contact_at(75.0, Contact::Hail, false)
        .contact_at(85.0, Contact::PlantStow, true)
        .contact_at(95.0, Contact::PlantStow, false)
        .run_minutes(105.0)
        .unwrap();
    report("r", &run);
    println!("r: wind pulses {}", run.wind_pulses);
    let modes = modes_at_minutes(
        "r",
        &run,
        start,
        &[
            (18.0, "tracking"),
            (21.5, "snow_stow"),
            (33.0, "snow_stow"),
            (36.5, "tracking"),
            (46.5, "wind_stow"),
            (66.0, "hail_stow"),
            (81.5, "tracking"),
            (86.5, "external_stow"),
            (96.5, "tracking"),
        ],
    );
    // Hail first (its contact and the gust's first pulses come together;
    // the wind stow waits for its 3 s hold).
    let hail = modes.iter().position(|(_, m)| m == "hail_stow").unwrap();
    assert_eq!(modes[hail + 1].1, "wind_stow", "{modes:?}");
    let at = |m: f64| start as f64 + m * 60.0;
    // The A axis at each stow's slope once there, the C axis still over
    // each stow.
    for (from, to, slope_deg) in [
        (22.0, 30.0, 90.0),
        (47.0, 64.5, 0.0),
        (67.0, 75.0, 60.0),
        (87.0, 95.0, 0.0),
    ] {
        let samples: Vec<_> = run
            .angle_trace
            .iter()
            .filter(|s| s.utc_s >= at(from) && s.utc_s < at(to))
            .collect();
        let Some(c_first) = samples.first().map(|s| s.c_deg) else {
            panic!("no samples over minutes {from}–{to}");
        };
        for s in samples {
            assert!(
                (s.a_deg.abs() - slope_deg).abs() <= STEP_DEG + 0.01,
                "A at {:.3} at {} (want ±{slope_deg})",
                s.a_deg,
                format_utc(s.utc_s as i64)
            );
            assert!(
                (s.c_deg - c_first).abs() <= STEP_DEG,
                "C moved to {}",
                s.c_deg
            );
        }
    }
    let sps: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|s| s.0.utc_s > at(97.0))
        .collect();
    assert!(!sps.is_empty(), "set-points after the last contact");
    check_set_points_of(&sps, &MountAttitude::level(), kano_sun, 0.02);
    assert_no_illegal_steps(&run);
}

/// (s) The motor supply at Kano, 2026-06-21 from 08:00Z for 80 minutes,
/// RTC and GPS, `supply.resume_mv 12200` and `supply.stow_mv 11500` typed
/// at minute 1 (ADC0 behind the board's 100 kΩ / 10 kΩ divider; 12 V
/// before and after): 11.4 V from minute 20 (`low_supply_stow`: flat
/// within two minutes, then not a half-step until the supply is back),
/// 11.9 V from minute 30 (below the resume level: still stowed), 12.3 V
/// from minute 40 (`tracking` within a minute), 0 V over minutes 55–65 (the
/// divider come loose: fault `supply_reading` raised and cleared, tracking
/// goes on).
#[test]
fn s_low_supply_stows_then_drives_nothing() {
    let elf = elf_or_skip!();
    let (start, bench) = kano_morning(&elf);
    let run = bench
        .type_at(1.0, "set supply.resume_mv 12200")
        .type_at(1.5, "set supply.stow_mv 11500")
        .supply_at(20.0, 11_400)
        .supply_at(30.0, 11_900)
        .supply_at(40.0, 12_300)
        .supply_at(55.0, 0)
        .supply_at(65.0, 12_000)
        .run_minutes(80.0)
        .unwrap();
    report("s", &run);
    let modes = modes_at_minutes(
        "s",
        &run,
        start,
        &[
            (18.0, "tracking"),
            (21.0, "low_supply_stow"),
            (39.5, "low_supply_stow"),
            (41.0, "tracking"),
            (70.0, "tracking"),
        ],
    );
    let at = |m: f64| start as f64 + m * 60.0;
    // Flat within two minutes, then no step at all until minute 40.
    let flat = run
        .angle_trace
        .iter()
        .filter(|s| s.utc_s >= at(22.0) && s.utc_s < at(40.0))
        .all(|s| s.a_deg.abs() <= STEP_DEG);
    assert!(flat, "A not flat in the stow");
    let steps = steps_between(&run, at(22.0), at(40.0));
    assert_eq!(steps, 0, "{steps} half-steps while the supply was low");
    // The loose divider: a fault raised and cleared, no stow.
    let raised = fault_raised(&run, "supply_reading");
    assert_eq!(raised.len(), 1, "{}", faults_summary(&run, start));
    assert!(raised[0] >= at(55.0) && raised[0] < at(56.5));
    assert!(modes
        .iter()
        .filter(|(t, _)| *t > at(41.0))
        .all(|(_, m)| m == "tracking"));
    tracks_after(&run, start, 42.0);
}

/// (t) The pyranometer at Kano, 2026-06-21 from 08:00Z for 90 minutes, RTC
/// and GPS, `overcast.ratio 0.3`, `enter_s 300` and `leave_s 300` typed at
/// minutes 1–2 (ADC1, 2 mV per W/m²): 800 W/m² (clear), 150 from minute
/// 20 (`overcast` 5 minutes later: flat within two more, the C axis
/// unmoved), 800 from minute 50 (`tracking` 5 minutes later), 0 over
/// minutes 70–75 with the sun well up (a sensor come loose: fault
/// `irradiance_reading` once, tracking goes on).
#[test]
fn t_overcast_lies_flat_and_returns() {
    let elf = elf_or_skip!();
    let (start, bench) = kano_morning(&elf);
    let run = bench
        .type_at(1.0, "set overcast.ratio 0.3")
        .type_at(1.5, "set overcast.enter_s 300")
        .type_at(2.0, "set overcast.leave_s 300")
        .irradiance_at(0.0, 800)
        .irradiance_at(20.0, 150)
        .irradiance_at(50.0, 800)
        .irradiance_at(70.0, 0)
        .irradiance_at(75.0, 800)
        .run_minutes(90.0)
        .unwrap();
    report("t", &run);
    modes_at_minutes(
        "t",
        &run,
        start,
        &[
            (19.0, "tracking"),
            (24.0, "tracking"),
            (26.5, "overcast"),
            (54.0, "overcast"),
            (56.5, "tracking"),
            (85.0, "tracking"),
        ],
    );
    let at = |m: f64| start as f64 + m * 60.0;
    let c_before = run
        .angle_trace
        .iter()
        .rfind(|s| s.utc_s <= at(25.0))
        .map(|s| s.c_deg)
        .unwrap();
    for s in run
        .angle_trace
        .iter()
        .filter(|s| s.utc_s >= at(28.0) && s.utc_s < at(54.0))
    {
        assert!(s.a_deg.abs() <= STEP_DEG, "A at {} while overcast", s.a_deg);
        assert!(
            (s.c_deg - c_before).abs() <= STEP_DEG,
            "C moved to {}",
            s.c_deg
        );
    }
    let raised = fault_raised(&run, "irradiance_reading");
    assert_eq!(raised.len(), 1, "{}", faults_summary(&run, start));
    assert!(raised[0] >= at(70.0) && raised[0] < at(71.5));
    tracks_after(&run, start, 57.0);
}

/// SunSpec register of a point: 40000 + `offset` (the map's base, `SunS`).
const SUNS: u16 = 40_000;
/// Model 601's ID register, and its length with the ID and L (2 + 48).
const M601: u16 = 40_070;
const M601_REGS: u16 = 50;
/// Model 64201's ID register, and its length with the ID and L (2 + 12).
const M64201: u16 = 40_158;
const M64201_REGS: u16 = 14;
/// The tolerance of model 601's angles against the set-point and SPA: the
/// map's 0.01° steps and the firmware's f32 table.
const MODBUS_ANGLE_TOL_DEG: f64 = 0.05;
/// The emulated minute (v) starts its 10 KB of noise at.
const NOISE_MIN: f64 = 9.0;

/// A reply's registers, or a panic naming the transaction.
fn registers(t: &modbus_master::Transaction) -> Vec<u16> {
    match t.parsed() {
        Some(modbus_master::Reply::Registers(r)) => r,
        other => panic!("{}: {other:?}", t.summary()),
    }
}

/// An int32 point (high word first) scaled by 10^sf.
fn i32_point(r: &[u16], at: usize, sf: i16) -> f64 {
    let v = ((u32::from(r[at]) << 16) | u32::from(r[at + 1])) as i32;
    f64::from(v) * 10f64.powi(i32::from(sf))
}

/// Model 601 read whole (from its ID): the instant its DtLoc/TmLoc say
/// (Unix s), and ElTrgt, AzTrgt, ElPos, AzPos, GlblElCtl, GlblAzCtl
/// (degrees, Dgr_SF applied) and GlblCtl.
struct Tracker601 {
    unix_s: i64,
    el_trgt: f64,
    az_trgt: f64,
    el_pos: f64,
    az_pos: f64,
    glbl_el: f64,
    glbl_az: f64,
    glbl_ctl: u16,
}

fn tracker_601(t: &modbus_master::Transaction) -> Tracker601 {
    let r = registers(t);
    assert_eq!((r[0], r[1], r.len()), (601, 48, 50), "{}", t.summary());
    let text = |from: usize, n: usize| -> String {
        r[from..from + n]
            .iter()
            .flat_map(|w| w.to_be_bytes())
            .take_while(|b| *b != 0)
            .map(char::from)
            .collect()
    };
    let (d, tm) = (text(11, 5), text(16, 3));
    let unix_s = t_compact(&d, &tm).unwrap_or_else(|| panic!("DtLoc {d:?} TmLoc {tm:?}"));
    let sf = r[26] as i16;
    assert_eq!(sf, -2, "Dgr_SF");
    Tracker601 {
        unix_s,
        glbl_el: i32_point(&r, 20, sf),
        glbl_az: i32_point(&r, 22, sf),
        glbl_ctl: r[24],
        el_trgt: i32_point(&r, 36, sf),
        az_trgt: i32_point(&r, 38, sf),
        el_pos: i32_point(&r, 40, sf),
        az_pos: i32_point(&r, 42, sf),
    }
}

/// `YYYYMMDD` and `hhmmss` → Unix seconds.
fn t_compact(d: &str, tm: &str) -> Option<i64> {
    if d.len() != 8 || tm.len() != 6 {
        return None;
    }
    parse_utc(&format!(
        "{}-{}-{}T{}:{}:{}Z",
        &d[0..4],
        &d[4..6],
        &d[6..8],
        &tm[0..2],
        &tm[2..4],
        &tm[4..6]
    ))
}

/// Elevation and azimuth (degrees) of a unit vector in the horizontal
/// frame (X west, Y south, Z up: `suntracker::attitude`).
fn el_az(v: &[f64; 3]) -> (f64, f64) {
    let el = v[2].atan2(v[0].hypot(v[1])).to_degrees();
    let az = (-v[0]).atan2(-v[1]).to_degrees().rem_euclid(360.0);
    (el, az)
}

fn az_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// (v) A Modbus RTU master on the RS-485 port (USART2, DE on PH3) at Kano,
/// 2026-06-21 from 08:00Z, RTC and GPS, 32 minutes. At minute 3 it reads
/// `SunS` and walks the model chain from 40002 as a SunSpec client does
/// (1, 601, 305, 64201, the end marker 0xFFFF); at 6 it reads model 601:
/// its ElTrgt/AzTrgt (Dgr_SF −2) within 0.05° of the set-point in force at
/// the instant its DtLoc/TmLoc say (the last `setpoint` line at or before
/// it: the normal of its pose and its sun) and of SPA's sun at that
/// set-point's time, computed here; GlblCtl = Manual (06) with
/// `modbus.write` 0 gets exception 01 and nothing changes; a frame with a
/// bad CRC and one to address 7 get no reply; 10 KB of noise at the line's
/// rate over minutes 9–15 delay no set-point by more than a tick (1 s),
/// and model 601 reads right again after it; `set modbus.write 1` typed at
/// 18: manual targets and GlblCtl = Manual in one write (16) → `mode
/// manual`, the axes there (the normal of the decoded pose, and ElPos/AzPos,
/// within 0.05° + a step); a target below the horizon: exception 03,
/// nothing moves; the vendor model's Stow broadcast (address 0): no reply,
/// `mode command_stow`. Every transaction's pins: DE high over every reply
/// byte, low before and after, the reply ≥ 3.5 characters after the
/// request, its bytes back to back ([`modbus_master::Transaction`]).
#[test]
fn v_modbus_master_reads_and_commands() {
    use modbus_master::{read_holding, write_multiple, write_single, Reply, Step};
    let elf = elf_or_skip!();
    let (start, bench) = kano_morning(&elf);
    let frame = |bytes: Vec<u8>| Step::Frame {
        bytes,
        expect_reply: true,
    };
    let silent = |bytes: Vec<u8>| Step::Frame {
        bytes,
        expect_reply: false,
    };
    let mut bad_crc = read_holding(1, SUNS, 2);
    *bad_crc.last_mut().unwrap() ^= 0x5A;
    let (el_manual, az_manual) = (55.0, 85.0);
    let [eh, el] = modbus_master::i32_registers((el_manual * 100.0) as i32);
    let [ah, al] = modbus_master::i32_registers((az_manual * 100.0) as i32);
    let [bh, bl] = modbus_master::i32_registers(-8_000);
    let read_601 = || frame(read_holding(1, M601, M601_REGS));
    let read_vendor = || frame(read_holding(1, M64201, M64201_REGS));
    let steps = vec![
        (3.0, frame(read_holding(1, SUNS, 2)), "SunS"),
        (
            3.1,
            Step::Walk {
                unit: 1,
                from: SUNS + 2,
            },
            "walk",
        ),
        (6.0, read_601(), "601 tracking"),
        (6.5, read_vendor(), "64201 tracking"),
        (
            7.0,
            frame(write_single(1, M601 + 24, 1)),
            "GlblCtl manual, writes off",
        ),
        (8.0, silent(bad_crc), "bad CRC"),
        (8.5, silent(read_holding(7, SUNS, 2)), "address 7"),
        (
            NOISE_MIN,
            Step::Noise(xorshift32_noise(0x2545_f491, 10_240)),
            "noise",
        ),
        (17.0, read_601(), "601 after the noise"),
        (
            19.0,
            frame(write_multiple(1, M601 + 20, &[eh, el, ah, al, 1])),
            "manual targets",
        ),
        (22.0, read_601(), "601 manual"),
        (
            23.0,
            frame(write_multiple(1, M601 + 20, &[bh, bl])),
            "below the horizon",
        ),
        (24.5, read_601(), "601 after 03"),
        (
            25.0,
            silent(write_single(0, M64201 + 11, 1)),
            "broadcast stow",
        ),
        (28.0, read_vendor(), "64201 stowed"),
    ];
    // The same bench without the noise, to minute 17: the set-points'
    // lateness without it.
    let quiet = steps
        .iter()
        .filter(|s| s.0 < NOISE_MIN)
        .fold(bench.clone(), |b, (m, step, label)| {
            b.modbus_at(*m, step.clone(), label)
        })
        .run_minutes(17.0)
        .unwrap();
    let run = steps
        .into_iter()
        .fold(bench, |b, (m, step, label)| b.modbus_at(m, step, label))
        .type_at(18.0, "set modbus.write 1")
        .run_minutes(32.0)
        .unwrap();
    report("v", &run);
    let m = &run.modbus;
    for t in &m.transactions {
        println!("v: {:.1} min {}", t.sent_emu_s / 60.0, t.summary());
    }
    let at = |min: f64| start as f64 + min * 60.0;
    let one = |label: &str| {
        let ts = m.labelled(label);
        assert_eq!(ts.len(), 1, "transactions {label}");
        ts[0]
    };
    // The pins, on every transaction.
    let bad: Vec<String> = m
        .transactions
        .iter()
        .filter(|t| !t.violations.is_empty())
        .map(|t| format!("{}: {:?}", t.summary(), t.violations))
        .collect();
    assert!(bad.is_empty(), "{bad:#?}");
    assert!(
        m.unsolicited.is_empty() && m.unsolicited_de.is_empty(),
        "bytes {:?} / DE {:?} outside any transaction",
        m.unsolicited,
        m.unsolicited_de
    );
    let turnaround: Vec<f64> = m
        .transactions
        .iter()
        .filter_map(|t| t.turnaround_chars())
        .collect();
    println!(
        "v: {} transactions, replies {:.2} to {:.2} characters after the request",
        m.transactions.len(),
        turnaround.iter().copied().fold(f64::INFINITY, f64::min),
        turnaround.iter().copied().fold(0.0, f64::max)
    );
    // SunS and the model chain.
    assert_eq!(registers(one("SunS")), [0x5375, 0x6E53]);
    let chain: Vec<(u16, u16, u16)> = m
        .labelled("walk ")
        .into_iter()
        .map(|t| {
            let r = registers(t);
            (t.label[5..].parse().unwrap(), r[0], r[1])
        })
        .collect();
    assert_eq!(
        chain,
        [
            (40_002, 1, 66),
            (40_070, 601, 48),
            (40_120, 305, 36),
            (40_158, 64201, 12),
            (40_172, 0xFFFF, 0)
        ]
    );
    // Model 601 against the set-point in force and SPA.
    let sps = set_points(&run);
    let check_601 = |label: &str| -> (f64, f64) {
        let p = tracker_601(one(label));
        let (line, sp_utc, c, a) = *sps
            .iter()
            .rfind(|s| s.1 <= p.unix_s)
            .unwrap_or_else(|| panic!("{label}: no set-point before {}", format_utc(p.unix_s)));
        let Event::SetPoint {
            zenith_deg,
            azimuth_deg,
            ..
        } = line.event
        else {
            unreachable!()
        };
        let pose = Pose {
            gamma_deg: c,
            alpha_deg: a,
        };
        let (nel, naz) = el_az(&MountAttitude::level().normal_xyz(&pose));
        let (sel, saz) = el_az(&kano_sun(sp_utc));
        let dev_log = (p.el_trgt - (90.0 - zenith_deg))
            .abs()
            .max(az_diff(p.az_trgt, azimuth_deg));
        let dev_pose = (p.el_trgt - nel).abs().max(az_diff(p.az_trgt, naz));
        let dev_spa = ((p.el_trgt - sel).abs(), az_diff(p.az_trgt, saz));
        println!(
            "v: {label}: read at {} (DtLoc/TmLoc), set-point {}: ElTrgt {:.2} AzTrgt {:.2}; \
             log's sun {:.4} {:.4} (off {dev_log:.4}), pose's normal {nel:.4} {naz:.4} (off \
             {dev_pose:.4}), SPA {sel:.4} {saz:.4} (off {:.4} / {:.4})",
            format_utc(p.unix_s),
            format_utc(sp_utc),
            p.el_trgt,
            p.az_trgt,
            90.0 - zenith_deg,
            azimuth_deg,
            dev_spa.0,
            dev_spa.1
        );
        assert!(
            dev_log <= MODBUS_ANGLE_TOL_DEG && dev_pose <= MODBUS_ANGLE_TOL_DEG,
            "{label}"
        );
        assert!(
            dev_spa.0.max(dev_spa.1) <= MODBUS_ANGLE_TOL_DEG,
            "{label}: SPA"
        );
        assert_eq!(p.glbl_ctl, 0, "{label}: GlblCtl Automatic");
        dev_spa
    };
    check_601("601 tracking");
    check_601("601 after the noise");
    let vendor = registers(one("64201 tracking"));
    assert_eq!(
        (vendor[0], vendor[2], vendor[3]),
        (64201, 8, 0),
        "tracking, no stow"
    );
    // Writes off: 01, nothing changes.
    assert_eq!(
        one("GlblCtl manual, writes off").parsed(),
        Some(Reply::Exception(1))
    );
    assert!(
        line_after(&run, at(7.0), "mode manual") >= Some(at(19.0)),
        "manual before the writes were on"
    );
    // No reply to a bad CRC, nor to another address (checked as no reply
    // and DE low above).
    assert!(one("bad CRC").reply.is_empty() && one("address 7").reply.is_empty());
    // The noise: each set-point whose slot came while it was on the line
    // logged at most a controller tick (1 s) later than in the run without
    // it.
    let (noise_s, noise_len) = m.noise_sent[0];
    assert_eq!(noise_len, 10_240);
    let noise_end_s = run.emu_s_at(m.noise_fed_cycles[0]);
    println!(
        "v: noise from {} to {}",
        format_utc((start as f64 + noise_s) as i64),
        format_utc((start as f64 + noise_end_s) as i64)
    );
    let quiet_sps = set_points(&quiet);
    let mut over_noise = 0;
    for (l, utc, ..) in sps
        .iter()
        .filter(|s| (s.1 as f64) >= at(NOISE_MIN) && (s.1 as f64) < at(17.0))
    {
        let (q, ..) = quiet_sps
            .iter()
            .find(|q| q.1 == *utc)
            .unwrap_or_else(|| panic!("no set-point {} without the noise", format_utc(*utc)));
        let (d, dq) = (l.utc_s - *utc as f64, q.utc_s - *utc as f64);
        println!(
            "v: set-point {} logged {d:.3} s after its slot with the noise, {dq:.3} s without",
            format_utc(*utc)
        );
        assert!(
            d - dq <= 1.0,
            "set-point {} delayed {:.3} s by the noise",
            format_utc(*utc),
            d - dq
        );
        if (*utc as f64) < start as f64 + noise_end_s {
            over_noise += 1;
        }
    }
    assert!(
        over_noise >= 1,
        "no set-point while the noise was on the line"
    );
    // Writes on: manual.
    assert!(line_after(&run, at(18.0), "ok modbus.write=1").is_some());
    assert_eq!(one("manual targets").parsed(), Some(Reply::Written));
    let manual_at = line_after(&run, at(19.0), "mode manual").expect("mode manual");
    assert!(
        manual_at < at(19.5),
        "mode manual at {}",
        format_utc(manual_at as i64)
    );
    let p = tracker_601(one("601 manual"));
    let pos_tol = MODBUS_ANGLE_TOL_DEG + STEP_DEG;
    assert_eq!(p.glbl_ctl, 1);
    assert!((p.glbl_el - el_manual).abs() < 0.005 && (p.glbl_az - az_manual).abs() < 0.005);
    assert!(
        (p.el_pos - el_manual).abs() <= pos_tol && az_diff(p.az_pos, az_manual) <= pos_tol,
        "ElPos/AzPos {} {}",
        p.el_pos,
        p.az_pos
    );
    let l = run
        .lines
        .iter()
        .find(|l| l.text.starts_with("# modbus 601 manual"))
        .unwrap();
    let pose = Pose {
        gamma_deg: l.c_deg,
        alpha_deg: l.a_deg,
    };
    let (nel, naz) = el_az(&MountAttitude::level().normal_xyz(&pose));
    println!("v: manual {el_manual} {az_manual}: ElPos {:.2} AzPos {:.2}, decoded pose's normal {nel:.3} {naz:.3}", p.el_pos, p.az_pos);
    assert!((nel - el_manual).abs() <= pos_tol && az_diff(naz, az_manual) <= pos_tol);
    // Below the horizon: 03, nothing moves, the target kept.
    assert_eq!(one("below the horizon").parsed(), Some(Reply::Exception(3)));
    assert_eq!(steps_between(&run, at(23.0), at(25.0)), 0, "moved after 03");
    let p = tracker_601(one("601 after 03"));
    assert!(
        (p.glbl_el - el_manual).abs() < 0.005,
        "GlblElCtl {}",
        p.glbl_el
    );
    // The broadcast stow: no reply, command_stow.
    let stow_at = line_after(&run, at(25.0), "mode command_stow").expect("mode command_stow");
    assert!(stow_at < at(25.5));
    let vendor = registers(one("64201 stowed"));
    assert_eq!(
        (vendor[2], vendor[3]),
        (3, 2),
        "command_stow, reason command"
    );
    assert_no_illegal_steps(&run);
}

// ---------------------------------------------------------------------------
// (dc), (dc2): the `dc` image (feature `dc`, `build_avr_mega_dc_emu`), and
// (dc3): the default image configured so by its console: DC
// gear motors on IBT-2 (BTS7960) bridges with Hall encoders, the
// harness's models of `suntracker_emu::models::ibt2` (the motor physics of
// `sim::dc_motor`, `sim::dc_drive::worm_slew_motor`: 1,400 Hall counts an
// axis degree, at most 7.62 °/s). (dc) and (dc2) gated on
// SUNTRACKER_EMU_ELF_MEGA_DC, (dc3) on SUNTRACKER_EMU_ELF_MEGA.

/// A DC-driven set-point is reached within this of the commanded angle,
/// degrees (the brief's 0.2° bound on the panel normal; the image's
/// deadband is 14 counts, 0.01°).
const DC_POINTING_TOL_DEG: f64 = 0.2;

/// The DC axes' bench of (dc), (dc2), (dc3): Kano with GPS and a valid
/// RTC, power-on at `start` with the shafts at `c_deg`, `a_deg`.
fn kano_dc_bench(elf: &Path, start: i64, c_deg: f64, a_deg: f64) -> MegaBench {
    MegaBench::mega(elf)
        .dc_drives()
        .start(start)
        .rtc(Rtc::Valid)
        .gps(GpsFeed::kano())
        .power_on_angles(c_deg, a_deg)
        .echo(std::env::var_os("SUNTRACKER_EMU_ECHO").is_some())
}

/// The DC axes after `from_s` (Unix seconds): homed before the first
/// set-point, set-points for 30 minutes and more, each reached by the
/// models' shafts within `tol_deg` before the next (and within
/// `angle_tol_deg`), the panel normal within `tol_deg` of Kano's SPA sun.
/// The number of set-points and the worst shaft error, degrees.
fn assert_dc_morning(run: &Run, from_s: f64, tol_deg: f64, angle_tol_deg: f64) -> (usize, f64) {
    let homed = homed_at(&run.switch_events, from_s).expect("both axes reach home");
    assert_tracked_after(run, from_s, homed, tol_deg, angle_tol_deg)
}

/// [`assert_dc_morning`] for axes homed at `homed` (Unix seconds).
fn assert_tracked_after(
    run: &Run,
    from_s: f64,
    homed: f64,
    tol_deg: f64,
    angle_tol_deg: f64,
) -> (usize, f64) {
    let sps: Vec<_> = set_points(run)
        .into_iter()
        .filter(|(l, ..)| l.utc_s > from_s)
        .collect();
    let first_sp = sps.first().expect("set-points").0.utc_s;
    let last_sp = sps.last().unwrap().0.utc_s;
    assert!(homed <= first_sp, "homing before tracking");
    assert!(
        last_sp - first_sp >= 30.0 * 60.0,
        "set-points from {} to {}: under 30 minutes",
        format_utc(first_sp as i64),
        format_utc(last_sp as i64)
    );
    let mut worst: f64 = 0.0;
    for w in sps.windows(2) {
        let (_, utc, c, a) = w[0];
        let (next, ..) = w[1];
        let err = (next.c_start_deg - c)
            .abs()
            .max((next.a_start_deg - a).abs());
        worst = worst.max(err);
        assert!(
            err <= tol_deg,
            "set-point {} c={c} a={a}: shafts at C {:.4} A {:.4} before the next one",
            format_utc(utc),
            next.c_start_deg,
            next.a_start_deg
        );
    }
    let n = check_set_points_within(
        &sps,
        &MountAttitude::level(),
        kano_sun,
        angle_tol_deg,
        tol_deg,
    );
    (n, worst)
}

/// No fault raised in `log` but the GPS's (lost for its first seconds at
/// power-on): none from the motors or their watches.
fn assert_no_motor_fault(log: &[&str], when: &str) {
    let faults: Vec<&str> = log
        .iter()
        .copied()
        .filter(|t| t.starts_with("fault ") && !t.starts_with("fault gps_lost"))
        .collect();
    assert!(faults.is_empty(), "faults {when}: {faults:?}");
}

/// (dc) Kano, 2026-06-21, power-on 05:00Z with GPS, the `dc` image: homing,
/// then set-points for at least 30 emulated minutes, each reached by the
/// models' shafts (the angles just before the next set-point line) within
/// 0.2° of the commanded pose, whose panel normal is within 0.2° of the
/// SPA sun.
#[test]
fn dc_morning_at_kano() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_MEGA_DC");
    let start = t("2026-06-21T05:00:00Z");
    let run = kano_dc_bench(&elf, start, 30.0, 20.0)
        .run_minutes(75.0)
        .unwrap();
    report("dc", &run);
    let (n, worst) = assert_dc_morning(&run, start as f64, DC_POINTING_TOL_DEG, ANGLE_TOL_DEG);
    // No motor fault on an unobstructed morning: no stall while an axis
    // settles from its last stop, no slow move while homing tops its
    // target up, no limit switch (the GPS is lost for its first seconds).
    let texts: Vec<&str> = run.lines.iter().map(|l| l.text.as_str()).collect();
    assert_no_motor_fault(&texts, "on an unobstructed morning");
    println!(
        "dc: {n} set-points, worst shaft error {worst:.4}°, run {:.1} s",
        run.wall.as_secs_f64()
    );
}

/// The A axis's obstacle in (dc2): it holds the axis at this angle, degrees,
/// on its way up from home (−90°) to the first set-point of the day.
const DC2_OBSTACLE_DEG: f64 = -40.0;
/// The emulated minute the obstacle goes.
const DC2_CLEAR_MIN: f64 = 8.0;

/// (dc2) Kano, 2026-06-21, power-on 10:00Z, the `dc` image, an obstacle in
/// the A axis's way at −40° until minute 8: the first move after homing
/// runs into it at full duty; the held motor's current (V·d/R, 5.5 A at
/// full duty) passes the image's 3 A limit and `obstruction_a` is logged
/// within a second of it (the limit's 100 ms and a tick); the motor is
/// stopped (the axis stays at the obstacle, braked), retried (the current
/// rises again), and once the obstacle is gone the retry carries the axis
/// to its set-point and the fault is cleared.
#[test]
fn dc2_obstruction_on_the_a_axis() {
    let elf = elf_or_skip!("SUNTRACKER_EMU_ELF_MEGA_DC");
    let start = t("2026-06-21T10:00:00Z");
    let run = kano_dc_bench(&elf, start, 30.0, -60.0)
        .obstacle_at(0.0, 1, Some(DC2_OBSTACLE_DEG))
        .obstacle_at(DC2_CLEAR_MIN, 1, None)
        .run_minutes(24.0)
        .unwrap();
    report("dc2", &run);
    let clear_s = start as f64 + DC2_CLEAR_MIN * 60.0;
    let ob = assert_obstruction_a(
        &run,
        start,
        clear_s,
        DC2_OBSTACLE_DEG,
        (ANGLE_TOL_DEG, DC_POINTING_TOL_DEG),
    );
    // The swing to the obstacle is one move: its current passes 3 A at
    // the obstacle, and before that at most once, as the motor starts from
    // rest (its stall current at full duty until it turns), the 50° from
    // home to the obstacle earlier (some 7 s at the axis's speed). A move
    // braked and started again at every tick, as the closed loop once did,
    // passed it at each restart, a second apart.
    let rises = &run.current_rises.1;
    let before: Vec<f64> = rises.iter().copied().filter(|&r| r <= ob.fault_s).collect();
    assert!(
        before.len() == 1 || (before.len() == 2 && before[1] - before[0] > 5.0),
        "A current rises before the fault: {rises:?}"
    );
    println!(
        "dc2: fault {} cleared {} ({} retries), run {:.1} s",
        format_utc(ob.fault_s as i64),
        format_utc(ob.cleared_s as i64),
        ob.retries,
        run.wall.as_secs_f64()
    );
}

/// What [`assert_obstruction_a`] found.
struct Obstruction {
    /// `obstruction_a` first raised, emulated UTC s.
    fault_s: f64,
    /// Cleared, emulated UTC s.
    cleared_s: f64,
    /// Rises of the A motor's current over its mark (the bench's current
    /// limit: 3 A a DC motor, 6 A the linear actuator) between the fault and the
    /// obstacle's going: the retries.
    retries: usize,
}

/// An obstacle held the A axis at `obstacle_deg` until `clear_s`:
/// `obstruction_a` raised within a second of the last rise of the A
/// motor's current above its mark (3 A a DC motor, 6 A the linear
/// actuator) before it, the axis not past the obstacle at
/// the fault, retried (the current rises again) before the obstacle goes,
/// the fault cleared only after it went, and at least two set-points after
/// that reached within `angle_tol_deg` on each axis, their panel normals
/// within `tol_deg` of SPA.
fn assert_obstruction_a(
    run: &Run,
    start: i64,
    clear_s: f64,
    obstacle_deg: f64,
    (angle_tol_deg, tol_deg): (f64, f64),
) -> Obstruction {
    let rises = &run.current_rises.1;
    println!(
        "A current rises above its mark at {:?}",
        rises.iter().map(|r| r - start as f64).collect::<Vec<_>>()
    );
    let raised = fault_raised(run, "obstruction_a");
    let fault_s = *raised.first().expect("obstruction_a raised");
    // The rise the fault answers: the last before it (the earlier ones
    // are starts, each under the limit again within its 100 ms).
    let rise = *rises
        .iter()
        .rfind(|&&r| r <= fault_s)
        .expect("the A motor's current passes its mark before the fault");
    let delay_s = fault_s - rise;
    println!("obstruction_a {delay_s:.3} s after the current passed its mark");
    assert!(
        (0.0..=1.0).contains(&delay_s),
        "obstruction_a {delay_s:.3} s after the current limit"
    );
    // Stopped: from the fault until the obstacle goes, the A axis never
    // passed it, and the motor was not left driven against it (every rise
    // of the current is a new attempt, at least one more: the retry).
    // Within 1e-4° of the obstacle: a linear axis's model holds the rod at
    // the obstacle's extension, and its angle comes back through f32
    // (−77.9999924° for −78°).
    let at_fault = run.lines.iter().find(|l| l.utc_s >= fault_s).unwrap();
    assert!(
        at_fault.a_deg <= obstacle_deg + 1e-4,
        "A at {}",
        at_fault.a_deg
    );
    let retries = rises
        .iter()
        .filter(|&&r| r > fault_s && r < clear_s)
        .count();
    assert!(
        retries >= 1,
        "no retry against the obstacle: rises {rises:?}"
    );
    let cleared_s = run
        .lines
        .iter()
        .find(
            |l| matches!(&l.event, Event::Fault { name, raised: false } if name == "obstruction_a"),
        )
        .map(|l| l.utc_s)
        .expect("obstruction_a cleared");
    assert!(
        cleared_s >= clear_s,
        "cleared at {} before the obstacle went",
        format_utc(cleared_s as i64)
    );
    // After it: the set-points are reached again.
    let sps: Vec<_> = set_points(run)
        .into_iter()
        .filter(|sp| sp.0.utc_s > cleared_s)
        .collect();
    assert!(
        sps.len() >= 2,
        "{} set-points after the obstacle went",
        sps.len()
    );
    check_set_points_within(
        &sps,
        &MountAttitude::level(),
        kano_sun,
        angle_tol_deg,
        tol_deg,
    );
    Obstruction {
        fault_s,
        cleared_s,
        retries,
    }
}

/// Each typed `set KEY VALUE` of `typed` answered `ok KEY=VALUE` in `log`
/// (a number as the console writes it back: `-92.00` typed is `-92`).
fn assert_set_lines_taken(log: &[&str], typed: &[impl AsRef<str>]) {
    for line in typed {
        let mut words = line.as_ref().split(' ').skip(1);
        let (key, value) = (words.next().unwrap(), words.next().unwrap());
        let want = format!("ok {key}={value}");
        let prefix = format!("ok {key}=");
        let same_number = |l: &&str| {
            l.strip_prefix(prefix.as_str())
                .and_then(|v| Some((v.parse::<f64>().ok()?, value.parse::<f64>().ok()?)))
                .is_some_and(|(got, typed)| got == typed)
        };
        assert!(
            log.contains(&want.as_str()) || log.iter().any(same_number),
            "{want}: {log:?}"
        );
    }
}

/// `bench` with `lines` typed from minute 1 (a tenth of a minute apart,
/// closer when there are more than 14, so that all come before the save),
/// `save` at minute 2.5 and a power cut at minute 4.
fn typed_saved_and_cut(mut bench: MegaBench, lines: &[impl AsRef<str>]) -> MegaBench {
    let apart_min = (1.4 / lines.len() as f64).min(0.1);
    for (i, line) in lines.iter().enumerate() {
        bench = bench.type_at(1.0 + apart_min * i as f64, line.as_ref());
    }
    bench.type_at(2.5, "save").reset_at(4.0)
}

/// The slew drive's speed as an installer calibrates a timed axis, °/s
/// as typed: its no-load speed through the gears at 12 V, from the motor's
/// constants (`sim::dc_motor::MotorSpec::no_load_motor_rad_s`), what timing
/// a sweep each way measures.
fn timed_speed() -> String {
    let motor = sim::dc_drive::worm_slew_motor();
    let deg_s = (motor.no_load_motor_rad_s() / motor.gear_ratio).to_degrees();
    format!("{deg_s:.3}")
}

/// The lines (dc3) types on the default image's console: both axes to the
/// slew drives of the `dc` image (`dc::dc_config`: Hall counts, gears, top
/// speed, deadband), one key a line (a line holds 64 characters).
const DC3_TYPED: [&str; 10] = [
    "set axis.c.drive 2",
    "set axis.c.counts_per_motor_rev 64",
    "set axis.c.gear_ratio 7875",
    "set axis.c.max_speed_deg_s 7",
    "set axis.c.deadband_deg 0.05",
    "set axis.a.drive 2",
    "set axis.a.counts_per_motor_rev 64",
    "set axis.a.gear_ratio 7875",
    "set axis.a.max_speed_deg_s 7",
    "set axis.a.deadband_deg 0.05",
];

/// (dc3) The drive kind by configuration, on the default image (the one
/// built without the `dc` feature, whose own axes are steppers), with the
/// DC gear motors and IBT-2 models of (dc) wired: Kano, 2026-06-21,
/// power-on 05:00Z. An installer types `set axis.a.drive 6` (no such
/// kind: refused with the kinds' list; the board builds every kind), then
/// [`DC3_TYPED`], `save`, and cuts the power at minute 4;
/// after it the image reads the stored configuration, builds both axes as
/// DC axes, homes them on the motors and tracks: set-points for 30 minutes
/// and more, each reached by the models' shafts within 0.2°, the panel
/// normal within 0.2° of SPA, and no motor fault after the cut.
#[test]
fn dc3_drive_kinds_typed_saved_and_built_at_power_on() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T05:00:00Z");
    let bench = kano_dc_bench(&elf, start, 30.0, 20.0).type_at(0.5, "set axis.a.drive 6");
    let run = typed_saved_and_cut(bench, &DC3_TYPED)
        .run_minutes(80.0)
        .unwrap();
    report("dc3", &run);
    let (texts, cut) = texts_and_cut(&run);
    let (before, after) = texts.split_at(cut);
    assert!(
        before.contains(&"config source=defaults"),
        "the default image starts on its own (stepper) axes: {before:?}"
    );
    assert!(
        before.contains(
            &"error axis.a.drive: 0 stepper, 1 servo_encoder, 2 dc_hall, 3 linear_hall, \
              4 linear_pot, 5 timed"
        ),
        "{before:?}"
    );
    assert_set_lines_taken(before, &DC3_TYPED);
    assert!(before.contains(&"ok save"), "{before:?}");
    assert!(after.contains(&"config source=stored"), "{after:?}");
    let cut_s = run.lines[cut].utc_s;
    let (n, worst) = assert_dc_morning(&run, cut_s, DC_POINTING_TOL_DEG, ANGLE_TOL_DEG);
    assert_no_motor_fault(after, "after the cut");
    println!(
        "dc3: {n} set-points after the cut on DC axes built from the stored configuration, \
         worst shaft error {worst:.4}°, run {:.1} s",
        run.wall.as_secs_f64()
    );
}

/// The lines (dc4) types on the default image's console: both axes timed
/// (`drive` 5) on the slew drives of (dc), their Hall encoders unused:
/// 1,400 counts a degree (64 × 7,875 / 360, the count's resolution only),
/// forward and backward at the speed `speed` (°/s, as typed).
fn dc4_typed(speed: &str) -> Vec<String> {
    let mut lines = Vec::new();
    for axis in ["c", "a"] {
        lines.push(format!("set axis.{axis}.drive 5"));
        lines.push(format!("set axis.{axis}.counts_per_motor_rev 64"));
        lines.push(format!("set axis.{axis}.gear_ratio 7875"));
        lines.push(format!("set axis.{axis}.max_speed_deg_s {speed}"));
        lines.push(format!("set axis.{axis}.back_speed_deg_s {speed}"));
    }
    lines
}

/// A timed axis's set-point is reached within this of the commanded angle,
/// degrees: the same bound as the Hall-closed axes' (the drive's target
/// for a timed axis is 2° at the 95th percentile; on this drive it does
/// far better, as the simulator's timed years show).
const TIMED_POINTING_TOL_DEG: f64 = DC_POINTING_TOL_DEG;

/// (dc4) Timed axes (no feedback) by configuration, on the default image
/// with the DC gear motors and IBT-2 models of (dc): Kano, 2026-06-21,
/// power-on 05:00Z. An installer types both axes as timed at the slew
/// drive's calibrated speed (its no-load speed through the gears at 12 V,
/// from the motor's constants: what timing a sweep each way measures),
/// `save`, and cuts the power at minute 4; after it both axes are timed
/// axes, homed against their switches, and track: set-points for 30
/// minutes and more, each reached by the models' shafts within 0.2°, the
/// panel normal within 0.2° of SPA. A `stow` typed at minute 50 and
/// `resume` at 55: both axes are homed again before the next set-point
/// (a timed axis knows where it is only from its switch). No motor fault
/// after the cut.
#[test]
fn dc4_timed_axes_typed_saved_and_homed_after_a_stow() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T05:00:00Z");
    let speed = timed_speed();
    let typed = dc4_typed(&speed);
    let (stow_min, resume_min) = (50.0, 55.0);
    let run = typed_saved_and_cut(kano_dc_bench(&elf, start, 30.0, 20.0), &typed)
        .type_at(stow_min, "stow")
        .type_at(resume_min, "resume")
        .run_minutes(80.0)
        .unwrap();
    report("dc4", &run);
    let (texts, cut) = texts_and_cut(&run);
    let (before, after) = texts.split_at(cut);
    assert_set_lines_taken(before, &typed);
    assert!(before.contains(&"ok save"), "{before:?}");
    assert!(after.contains(&"config source=stored"), "{after:?}");
    let cut_s = run.lines[cut].utc_s;
    let resume_s = start as f64 + resume_min * 60.0;
    // The morning up to the stow.
    let stow_s = start as f64 + stow_min * 60.0;
    let morning = Run {
        lines: run
            .lines
            .iter()
            .filter(|l| l.utc_s < stow_s)
            .cloned()
            .collect(),
        ..run.clone()
    };
    let (n, worst) = assert_dc_morning(
        &morning,
        cut_s,
        TIMED_POINTING_TOL_DEG,
        TIMED_POINTING_TOL_DEG,
    );
    // After the resume: homed again, then set-points reached as before.
    let homed = homed_at(&run.switch_events, resume_s).expect("homed after the stow");
    let sps: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|sp| sp.0.utc_s > resume_s)
        .collect();
    let first = sps.first().expect("set-points after the resume").0.utc_s;
    assert!(
        homed <= first,
        "homed at {} after the first set-point {}",
        format_utc(homed as i64),
        format_utc(first as i64)
    );
    let m = check_set_points_within(
        &sps,
        &MountAttitude::level(),
        kano_sun,
        TIMED_POINTING_TOL_DEG,
        TIMED_POINTING_TOL_DEG,
    );
    assert_no_motor_fault(after, "after the cut");
    println!(
        "dc4: timed axes at {speed} deg/s: {n} set-points before the stow (worst shaft error \
         {worst:.4}°), homed {:.0} s after the resume, {m} set-points after it, run {:.1} s",
        homed - resume_s,
        run.wall.as_secs_f64()
    );
}

/// The emulated minute (dc5)'s obstacle goes.
const DC5_CLEAR_MIN: f64 = 14.0;

/// (dc5) Timed axes meet an obstacle: Kano, 2026-06-21, power-on 10:00Z on
/// the default image, both axes typed as timed axes as in (dc4), `save`, a
/// power cut at minute 4, an obstacle holding the A axis at −40° until
/// minute 14. After the cut the axes home, and the first swing up runs
/// into the obstacle at full duty: `obstruction_a` within a second of the
/// held motor's current passing 3 A, the motor braked (the axis stays at
/// the obstacle), retried on the fault's back-off, and once the obstacle
/// is gone the retry runs the part of the swing not done (its time up to
/// the current's rise, less the motor's lag) and the fault clears; the
/// next set-points are reached within 0.2° (a timed axis has no count to
/// correct it: what the retry leaves stays until the next homing).
#[test]
fn dc5_obstruction_on_a_timed_a_axis() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T10:00:00Z");
    let bench = kano_dc_bench(&elf, start, 30.0, -60.0)
        .obstacle_at(0.0, 1, Some(DC2_OBSTACLE_DEG))
        .obstacle_at(DC5_CLEAR_MIN, 1, None);
    let run = typed_saved_and_cut(bench, &dc4_typed(&timed_speed()))
        .run_minutes(30.0)
        .unwrap();
    report("dc5", &run);
    let (texts, cut) = texts_and_cut(&run);
    assert!(texts[cut..].contains(&"config source=stored"));
    let clear_s = start as f64 + DC5_CLEAR_MIN * 60.0;
    let ob = assert_obstruction_a(
        &run,
        start,
        clear_s,
        DC2_OBSTACLE_DEG,
        (TIMED_POINTING_TOL_DEG, TIMED_POINTING_TOL_DEG),
    );
    assert!(ob.fault_s > run.lines[cut].utc_s, "the fault after the cut");
    println!(
        "dc5: fault {} cleared {} ({} retries), run {:.1} s",
        format_utc(ob.fault_s as i64),
        format_utc(ob.cleared_s as i64),
        ob.retries,
        run.wall.as_secs_f64()
    );
}

/// (dc6)'s motor supply, mV: a 12 V battery run down to 10.8 V, the
/// motors 10 % slower than at the 12 V their speeds were timed at.
const DC6_SUPPLY_MV: u32 = 10_800;

/// (dc6)'s bound on a set-point's error, degrees: the timed drive's target
/// (a pointing error of 2° at the 95th percentile). A run is scaled by the
/// supply ratio, but a loaded motor's speed is not quite proportional to
/// its voltage (the I·R drop does not scale), and the long first swings
/// from home carry that small share as degrees.
const DC6_TOL_DEG: f64 = 2.0;

/// (dc6) Timed axes on a sagging supply: Kano, 2026-06-21, power-on
/// 05:00Z on the default image, the DC models' motors and the board's
/// supply divider at 10.8 V throughout. Both axes typed as in (dc4), their
/// speeds those timed at 12 V, and `set supply.calibration_mv 12000`,
/// `save`, a power cut at minute 4. After it each run is lengthened by
/// 12 V over the measured supply: the set-points are reached within 2°.
/// The control: the same without the calibration supply (runs not scaled),
/// whose first swings fall short by a tenth, and every set-point after
/// them with them, until the night's homing.
#[test]
fn dc6_timed_runs_scaled_by_the_measured_supply() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T05:00:00Z");
    let speed = timed_speed();
    let worst_of = |calibrated: bool| {
        let mut typed = dc4_typed(&speed);
        if calibrated {
            typed.push("set supply.calibration_mv 12000".into());
        }
        let bench = kano_dc_bench(&elf, start, 30.0, 20.0).supply_at(0.0, DC6_SUPPLY_MV);
        let run = typed_saved_and_cut(bench, &typed)
            .run_minutes(50.0)
            .unwrap();
        report(if calibrated { "dc6" } else { "dc6 control" }, &run);
        let (texts, cut) = texts_and_cut(&run);
        let (before, after) = texts.split_at(cut);
        assert_set_lines_taken(before, &typed);
        assert!(after.contains(&"config source=stored"), "{after:?}");
        assert_no_motor_fault(after, "after the cut");
        let cut_s = run.lines[cut].utc_s;
        let sps: Vec<_> = set_points(&run)
            .into_iter()
            .filter(|(l, ..)| l.utc_s > cut_s)
            .collect();
        assert!(sps.len() >= 10, "{} set-points", sps.len());
        // The shafts just before the next set-point against this one's.
        let worst = sps
            .windows(2)
            .map(|w| {
                let (_, _, c, a) = w[0];
                let (next, ..) = w[1];
                (next.c_start_deg - c)
                    .abs()
                    .max((next.a_start_deg - a).abs())
            })
            .fold(0.0f64, f64::max);
        (run, cut_s, worst)
    };
    let (run, cut_s, _) = worst_of(true);
    let (n, worst) = assert_dc_morning(&run, cut_s, DC6_TOL_DEG, DC6_TOL_DEG);
    let (_, _, unscaled) = worst_of(false);
    assert!(
        unscaled > DC6_TOL_DEG,
        "the unscaled runs at {DC6_SUPPLY_MV} mV reached within {unscaled:.3}°"
    );
    println!(
        "dc6: timed axes at {DC6_SUPPLY_MV} mV, speeds timed at 12 V: {n} set-points within \
         {worst:.4}° with the runs scaled, {unscaled:.2}° without, run {:.1} s",
        run.wall.as_secs_f64()
    );
}

/// The mounting of the emulator's linear actuator (`sim::linear_drive::
/// LA12_TILT_MOUNT`): pivots 237 mm and 110 mm from the hinge, the hinge
/// angle 172.9° at the axis's zero, 245 mm pivot to pivot retracted, a
/// stroke of 100 mm.
const LA12_PIVOTS_MM: (f64, f64) = (237.0, 110.0);
const LA12_OFFSET_DEG: f64 = 172.9;
const LA12_RETRACTED_MM: f64 = 245.0;
const LA12_STROKE_MM: f64 = 100.0;
/// The LA12's dual Hall outputs: a state shift every 0.1875 mm (LINAK,
/// *Actuator system* user manual, "Dual Hall, digital (F2)": 16 shifts a
/// turn of a 3 mm spindle).
const LA12_MM_PER_SHIFT: f64 = 0.1875;
/// The issue's pointing targets for the linear axes, degrees: on the
/// potentiometer and on Hall pulses.
const LINEAR_POT_TOL_DEG: f64 = 0.5;
const LINEAR_HALL_TOL_DEG: f64 = 0.2;

/// The axis angle at pivot-to-pivot length `l_mm` of the LA12 mount, by
/// the law of cosines (`L² = a² + b² − 2ab·cos γ`, axis = γ − offset),
/// computed here in `f64`, apart from the firmware's `f32` geometry.
fn la12_axis_deg(l_mm: f64) -> f64 {
    let (a, b) = LA12_PIVOTS_MM;
    ((a * a + b * b - l_mm * l_mm) / (2.0 * a * b))
        .acos()
        .to_degrees()
        - LA12_OFFSET_DEG
}

/// What an installer types for the linear scenarios on the default
/// image: the C axis the slew drive of (dc) ([`DC3_TYPED`]'s C lines), the
/// A axis the LA12 on its mount, 100 counts a degree (as the simulator's
/// `la12_tilt_axis_config`), its soft limits the stroke's ends (rounded
/// inward to the hundredth), home at the retracted end (potentiometer) or
/// at the first state shift above the switch (Hall), 10 °/s, the LA12's
/// 6 A limit for 200 ms (the simulator's `LA12_HALL_LOOP`), and the
/// feedback: the potentiometer's readings at the ends as the ATmega's
/// ADC gives them (0.5 V and 4.5 V of its 5 V reference: ⌊V / 5 · 1,023⌋,
/// datasheet §26.7, ADC = V_IN · 1024 / V_REF, truncated) or the Hall
/// pair's state shifts a mm; the drive kind last (its rules read the rest).
fn linear_typed(pot: bool) -> Vec<String> {
    let lo = la12_axis_deg(LA12_RETRACTED_MM);
    let hi = la12_axis_deg(LA12_RETRACTED_MM + LA12_STROKE_MM);
    let home = if pot {
        lo
    } else {
        la12_axis_deg(LA12_RETRACTED_MM + LA12_MM_PER_SHIFT)
    };
    let adc = |volts: f64| (volts / 5.0 * 1_023.0).floor();
    let mut lines: Vec<String> = DC3_TYPED[..5].iter().map(|l| l.to_string()).collect();
    lines.extend([
        "set axis.a.counts_per_motor_rev 36000".into(),
        "set axis.a.microsteps 1".into(),
        "set axis.a.gear_ratio 1".into(),
        format!("set axis.a.pivot_a_mm {}", LA12_PIVOTS_MM.0),
        format!("set axis.a.pivot_b_mm {}", LA12_PIVOTS_MM.1),
        format!("set axis.a.pivot_offset_deg {LA12_OFFSET_DEG}"),
        format!("set axis.a.retracted_mm {LA12_RETRACTED_MM}"),
        format!("set axis.a.stroke_mm {LA12_STROKE_MM}"),
        format!("set axis.a.min_deg {:.2}", (lo * 100.0).ceil() / 100.0),
        format!("set axis.a.max_deg {:.2}", (hi * 100.0).floor() / 100.0),
        format!("set axis.a.home_deg {:.2}", home),
        "set axis.a.max_speed_deg_s 10".into(),
        "set axis.a.deadband_deg 0.05".into(),
        "set axis.a.max_current_ma 6000".into(),
        "set axis.a.overcurrent_ms 200".into(),
    ]);
    if pot {
        lines.push(format!("set axis.a.pot_retracted_counts {}", adc(0.5)));
        lines.push(format!("set axis.a.pot_extended_counts {}", adc(4.5)));
        lines.push("set axis.a.drive 4".into());
    } else {
        // To the five decimals the console keeps and writes back
        // (5.33333: 0.00006 mm short over the stroke).
        lines.push(format!(
            "set axis.a.pulses_per_mm {:.5}",
            1.0 / LA12_MM_PER_SHIFT
        ));
        lines.push("set axis.a.drive 3".into());
    }
    lines
}

/// How long the linear scenarios run, emulated minutes: tracking starts
/// at 05:12Z, and set-points to 05:48Z make the 30 minutes asked.
const LINEAR_RUN_MIN: f64 = 50.0;

/// The linear scenarios: Kano, 2026-06-21, power-on 05:00Z on the default
/// image, the C axis the slew drive of (dc), the A axis the LA12 on the
/// mount of [`linear_typed`] read by `feedback`, its rod 30 mm out. An
/// installer types [`linear_typed`], `save`, and cuts the power at minute
/// 4; after it the image builds the C axis as a DC axis and the A axis as
/// a linear actuator from the stored configuration and tracks: set-points
/// for 30 minutes and more, each reached by the shafts within `tol_deg`
/// before the next, the panel normal within `tol_deg` of SPA, and no motor
/// fault after the cut. The number of set-points and the worst error.
fn linear_morning(
    elf: &Path,
    feedback: LinearFeedback,
    tol_deg: f64,
    name: &str,
) -> (usize, f64, f64) {
    let start = t("2026-06-21T05:00:00Z");
    let pot = feedback == LinearFeedback::Pot;
    let typed = linear_typed(pot);
    let bench = kano_dc_bench(elf, start, 30.0, 20.0).linear_a(feedback, 30.0);
    let (run, cut_s) = typed_morning(bench, &typed, name);
    let homed = if pot {
        pot_homed_at(&run, cut_s)
    } else {
        homed_at(&run.switch_events, cut_s).expect("both axes reach home")
    };
    let (n, worst) = assert_tracked_after(&run, cut_s, homed, tol_deg, tol_deg);
    (n, worst, run.wall.as_secs_f64())
}

/// [`linear_morning`]'s and (sv1)'s run: `typed` on `bench`, `save`, a
/// power cut at minute 4, [`LINEAR_RUN_MIN`] minutes in all; every line
/// taken, saved, the stored configuration used after the cut, no motor
/// fault after it. The run and the cut's time.
fn typed_morning(bench: MegaBench, typed: &[String], name: &str) -> (Run, f64) {
    let run = typed_saved_and_cut(bench, typed)
        .run_minutes(LINEAR_RUN_MIN)
        .unwrap();
    report(name, &run);
    let (texts, cut) = texts_and_cut(&run);
    let (before, after) = texts.split_at(cut);
    assert_set_lines_taken(before, typed);
    assert!(before.contains(&"ok save"), "{before:?}");
    assert!(after.contains(&"config source=stored"), "{after:?}");
    assert_no_motor_fault(after, "after the cut");
    let cut_s = run.lines[cut].utc_s;
    (run, cut_s)
}

/// How far from the retracted end a rod homed on its potentiometer may
/// stop, mm: the reading's hysteresis (0.1 mm) and two of its ADC counts
/// (100 mm over 818 counts: 0.24 mm), rounded up to allow the brake's
/// coast.
const LA12_POT_HOME_TOL_MM: f64 = 0.5;

/// On the potentiometer there is no switch (the model's at the retracted
/// end may stay open a fraction of a mm short of it): the time homing
/// ended after `from_s` (the first mode line after `mode homing`), with
/// the C axis's switch closed before it and the A shaft then within
/// [`LA12_POT_HOME_TOL_MM`] of the retracted end.
fn pot_homed_at(run: &Run, from_s: f64) -> f64 {
    let after: Vec<_> = run.lines.iter().filter(|l| l.utc_s >= from_s).collect();
    let homing = after
        .iter()
        .position(|l| matches!(&l.event, Event::Mode(m) if m == "homing"))
        .expect("homing after the cut");
    let done = after[homing + 1..]
        .iter()
        .find(|l| matches!(&l.event, Event::Mode(m) if m != "homing"))
        .expect("homing ends");
    let c_home = run
        .switch_events
        .iter()
        .find(|e| e.switch == 0 && e.closed && e.utc_s >= from_s)
        .expect("the C axis reaches its switch");
    assert!(c_home.utc_s <= done.utc_s, "C homed before homing ended");
    let end_deg = la12_axis_deg(LA12_RETRACTED_MM);
    let tol_deg = la12_axis_deg(LA12_RETRACTED_MM + LA12_POT_HOME_TOL_MM) - end_deg;
    assert!(
        (done.a_start_deg - end_deg).abs() <= tol_deg,
        "A at {:.3}° when homing ended, the retracted end {end_deg:.3}° (±{tol_deg:.3}°)",
        done.a_start_deg
    );
    done.utc_s
}

/// (dc7) [`linear_morning`] on the LA12's potentiometer (`linear_pot`,
/// the wiper on A5): within the issue's 0.5°.
#[test]
fn dc7_linear_actuator_on_its_potentiometer_typed_saved_and_tracking() {
    let elf = elf_or_skip!();
    let (n, worst, wall_s) = linear_morning(&elf, LinearFeedback::Pot, LINEAR_POT_TOL_DEG, "dc7");
    println!(
        "dc7: {n} set-points after the cut, the A axis a linear actuator on its \
         potentiometer, worst shaft error {worst:.4}°, run {wall_s:.1} s"
    );
}

/// (dc8) [`linear_morning`] on the LA12's dual Hall pair (`linear_hall`,
/// on the A axis's encoder inputs), homed on its retracted-end switch:
/// within the issue's 0.2°.
#[test]
fn dc8_linear_actuator_on_hall_pulses_typed_saved_and_tracking() {
    let elf = elf_or_skip!();
    let (n, worst, wall_s) = linear_morning(&elf, LinearFeedback::Hall, LINEAR_HALL_TOL_DEG, "dc8");
    println!(
        "dc8: {n} set-points after the cut, the A axis a linear actuator on Hall pulses, \
         worst shaft error {worst:.4}°, run {wall_s:.1} s"
    );
}

/// The linear A axis's obstacle in (dc9): it holds the rod at the
/// extension of this angle, degrees, on its first way up from the
/// retracted end (−92°).
const DC9_OBSTACLE_DEG: f64 = -78.0;
/// The emulated minute the obstacle goes.
const DC9_CLEAR_MIN: f64 = 16.0;

/// (dc9) Obstruction on a linear actuator: Kano, 2026-06-21, power-on
/// 06:30Z on the default image (before the C axis's unwind of the day, at
/// about 08:05Z), the A axis the LA12 on Hall pulses typed as in (dc8),
/// `save`, a power cut at minute 4, and an obstacle in the rod's way at
/// the extension of −78° until minute 16. After the cut the rod retracts
/// to home through the obstacle's place (it holds only a rod coming from
/// below); its first swing up runs into it, and the held actuator's current
/// (9.67 A stalled at full duty in the model) passes the typed 6 A limit:
/// `obstruction_a` within a second of it (the limit's 200 ms and a tick),
/// the rod not past the obstacle, retried on the fault's back-off, and
/// once the obstacle is gone the retry carries the axis to its set-point
/// and the fault is cleared; the set-points after it within the issue's
/// 0.2° for Hall pulses.
#[test]
fn dc9_obstruction_on_a_linear_a_axis() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T06:30:00Z");
    let typed = linear_typed(false);
    let bench = kano_dc_bench(&elf, start, 30.0, 20.0)
        .linear_a(LinearFeedback::Hall, 30.0)
        .obstacle_at(0.0, 1, Some(DC9_OBSTACLE_DEG))
        .obstacle_at(DC9_CLEAR_MIN, 1, None);
    let run = typed_saved_and_cut(bench, &typed)
        .run_minutes(30.0)
        .unwrap();
    report("dc9", &run);
    let (texts, cut) = texts_and_cut(&run);
    let (before, after) = texts.split_at(cut);
    assert_set_lines_taken(before, &typed);
    assert!(after.contains(&"config source=stored"), "{after:?}");
    let clear_s = start as f64 + DC9_CLEAR_MIN * 60.0;
    let ob = assert_obstruction_a(
        &run,
        start,
        clear_s,
        DC9_OBSTACLE_DEG,
        (LINEAR_HALL_TOL_DEG, LINEAR_HALL_TOL_DEG),
    );
    assert!(ob.fault_s > run.lines[cut].utc_s, "the fault after the cut");
    // No other: the C slew drive leaves its switch for the first
    // set-point without a limit fault.
    let others: Vec<&str> = after
        .iter()
        .copied()
        .filter(|l| {
            l.starts_with("fault ") && !l.contains("gps_lost") && !l.contains("obstruction_a")
        })
        .collect();
    assert!(others.is_empty(), "other faults after the cut: {others:?}");
    println!(
        "dc9: fault {} cleared {} ({} retries), run {:.1} s",
        format_utc(ob.fault_s as i64),
        format_utc(ob.cleared_s as i64),
        ob.retries,
        run.wall.as_secs_f64()
    );
}

/// The servo A axis's gear in (sv1), servo turns per axis turn: 0.003° of
/// axis a count of the YMT22's 1,200, 5.7 °/s at the FS5106R's 95 rpm.
const SV1_GEAR: u32 = 100;
/// How close (sv1)'s servo axis reaches each set-point, degrees: the
/// Mega's pointing bound (0.03°), ten counts of its encoder.
const SERVO_TOL_DEG: f64 = 0.03;

/// (sv1) A continuous servo on its encoder: Kano, 2026-06-21, power-on
/// 05:00Z on the default image, the C axis the slew drive of (dc) typed
/// as in (dc7), the A axis an FS5106R through a 100:1 gear on a YMT22
/// (`servo_encoder`: the servo on OC3C, D3; the encoder on PK6/PK7) typed
/// with it, `save`, a power cut at minute 4. After it the image builds the
/// A axis as a servo from the stored configuration, homes it on its switch
/// (PC1) and tracks: set-points for 30 minutes and more, the C shaft
/// within the DC axes' 0.2° and the A shaft within 0.03° of each before
/// the next, the panel normal within 0.2° of SPA, no motor fault after the
/// cut.
#[test]
fn sv1_servo_a_axis_on_its_encoder_typed_saved_and_tracking() {
    let elf = elf_or_skip!();
    let start = t("2026-06-21T05:00:00Z");
    let mut typed: Vec<String> = DC3_TYPED[..5].iter().map(|l| l.to_string()).collect();
    typed.extend([
        "set axis.a.drive 1".into(),
        "set axis.a.counts_per_motor_rev 1200".into(),
        "set axis.a.microsteps 1".into(),
        format!("set axis.a.gear_ratio {SV1_GEAR}"),
        "set axis.a.max_speed_deg_s 4".into(),
        "set axis.a.deadband_deg 0.01".into(),
    ]);
    let bench = kano_dc_bench(&elf, start, 30.0, 20.0).servo_a(f64::from(SV1_GEAR));
    let (run, cut_s) = typed_morning(bench, &typed, "sv1");
    let homed = homed_at(&run.switch_events, cut_s).expect("both axes reach home");
    let (n, worst) =
        assert_tracked_after(&run, cut_s, homed, DC_POINTING_TOL_DEG, DC_POINTING_TOL_DEG);
    // The servo's own bound, tighter than the slew drive's.
    let sps: Vec<_> = set_points(&run)
        .into_iter()
        .filter(|(l, ..)| l.utc_s > cut_s)
        .collect();
    let mut worst_a: f64 = 0.0;
    for w in sps.windows(2) {
        let (_, utc, _, a) = w[0];
        let err = (w[1].0.a_start_deg - a).abs();
        worst_a = worst_a.max(err);
        assert!(
            err <= SERVO_TOL_DEG,
            "set-point {} a={a}: the servo axis at {:.4} before the next one",
            format_utc(utc),
            w[1].0.a_start_deg
        );
    }
    println!(
        "sv1: {n} set-points after the cut, the A axis a servo on its encoder, worst A \
         error {worst_a:.4}° (both shafts {worst:.4}°), run {:.1} s",
        run.wall.as_secs_f64()
    );
}
