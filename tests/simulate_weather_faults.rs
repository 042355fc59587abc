//! `simulate --faults` over a year at Kano: every weather spell of the
//! seeded schedule (`schedule::weather`, drawn here from the seed as the
//! tool draws it: `run::draws`) shows in the trace as its stow mode, or as
//! a mode of higher priority (`safety::select_mode`'s order), and the
//! tracker tracks again after each; the summary's minutes and entries per
//! mode agree with the trace, and the pointing error p95 while tracking
//! stays under 0.05° (`tests/controller.rs`'s bound for a day on a level
//! mount with encoders).
//!
//! The year with its trace takes 5.5 s in the release profile and 19 s
//! unoptimised (measured on the 2-core machine shared with other builds).

#[path = "../examples/simulate_support/run.rs"]
#[allow(dead_code)]
mod run;
#[path = "../examples/simulate_support/schedule.rs"]
#[allow(dead_code)]
mod schedule;

use schedule::{Kind, Window};

/// Kano (the tool's default site), a year of 2026.
const LON_DEG: f64 = 8.4261;
const DAYS: u32 = 365;
const SEED: u64 = 1;

/// The modes in `safety::select_mode`'s order: each outranks those after
/// it (`unwind` is tracking's move to another branch).
const PRIORITY: [&str; 15] = [
    "service",
    "safe_stop",
    "wind_stow",
    "hail_stow",
    "external_stow",
    "snow_stow",
    "low_supply_stow",
    "command_stow",
    "manual",
    "wait_for_time",
    "night",
    "homing",
    "overcast",
    "tracking",
    "unwind",
];

fn rank(mode: &str) -> usize {
    let i = PRIORITY
        .iter()
        .position(|m| *m == mode)
        .unwrap_or_else(|| panic!("unknown mode {mode}"));
    i.min(13)
}

/// The trace's columns these checks read.
struct Row {
    mode: &'static str,
    zenith_deg: f64,
    pointing_deg: Option<f64>,
    supply_mv: f64,
}

/// A weather spell's mode, and how long after its input clears the mode
/// may last (`stow.snow_release_s`, `stow.hail_release_s`,
/// `overcast.leave_s` at their defaults), minutes.
fn mode_of(kind: Kind) -> Option<(&'static str, u32)> {
    match kind {
        Kind::Snow => Some(("snow_stow", 60)),
        Kind::Hail => Some(("hail_stow", 30)),
        Kind::StowContact => Some(("external_stow", 0)),
        Kind::LowSupply(_) => Some(("low_supply_stow", 0)),
        Kind::Overcast(_) => Some(("overcast", 10)),
        _ => None,
    }
}

fn run_year() -> (String, Vec<Row>) {
    let mut trace = std::env::temp_dir();
    trace.push(format!(
        "simulate_weather_faults_{}.csv",
        std::process::id()
    ));
    let trace_s = trace.to_string_lossy().to_string();
    let days = DAYS.to_string();
    let args: Vec<String> = [
        "--start",
        "2026-01-01",
        "--days",
        &days,
        "--faults",
        "--trace",
        &trace_s,
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let code = run::run(&args, &mut out, &mut err);
    assert_eq!(code, 0, "{}", String::from_utf8_lossy(&err));
    let out = String::from_utf8(out).expect("utf8");
    let text = std::fs::read_to_string(&trace).expect("trace written");
    let _ = std::fs::remove_file(&trace);
    let rows = text
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 17, "{l}");
            let number = |s: &str| s.parse::<f64>().unwrap_or_else(|_| panic!("{l}"));
            Row {
                mode: PRIORITY[PRIORITY
                    .iter()
                    .position(|m| *m == f[2])
                    .unwrap_or_else(|| panic!("mode: {l}"))],
                zenith_deg: number(f[9]),
                pointing_deg: (!f[11].is_empty()).then(|| number(f[11])),
                supply_mv: number(f[16]),
            }
        })
        .collect();
    (out, rows)
}

#[test]
fn a_faults_year_enters_every_weather_stow_and_tracks_again_after_each() {
    let draws = run::draws(SEED, DAYS, LON_DEG, true);
    let spells: Vec<(Window, &str, u32)> = draws
        .weather
        .iter()
        .filter_map(|w| mode_of(w.kind).map(|(mode, release)| (*w, mode, release)))
        .collect();
    assert_eq!(spells.len(), draws.weather.len());
    // A handful of each a year, and some of them meet a fault.
    for mode in [
        "snow_stow",
        "hail_stow",
        "external_stow",
        "low_supply_stow",
        "overcast",
    ] {
        let n = spells.iter().filter(|s| s.1 == mode).count();
        assert!((3..=10).contains(&n), "{n} spells of {mode}");
    }
    assert!(
        spells.iter().any(|(w, _, _)| draws
            .windows
            .iter()
            .any(|f| f.from < w.until && w.from < f.until)),
        "no weather spell meets a fault window"
    );

    let t0 = std::time::Instant::now();
    let (out, rows) = run_year();
    eprintln!(
        "a year with --faults and a trace: {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    assert_eq!(rows.len(), (DAYS * 1440) as usize);
    let daylight = |m: u32| rows[m as usize].zenith_deg < 90.0;

    let mut entered = std::collections::BTreeMap::<&str, u32>::new();
    for (w, mode, release) in &spells {
        let (from, until) = (w.from, w.until);
        let outranked = |m: u32| rank(rows[m as usize].mode) < rank(mode);
        let spell = |m: u32| rows[m as usize].mode == *mode;
        if *mode == "overcast" {
            // The pyranometer reads a tenth to a quarter of the clear sky:
            // under overcast.ratio 0.3, flat after overcast.enter_s (10
            // minutes) of daylight, never tracking once in. Within a few
            // degrees of the horizon its whole W/m² (0 to 5 there) read
            // now dark, now bright, each restarting the 10 minutes: the
            // first half hour of daylight may track.
            let mut daylight_min = 0;
            let mut since_in: Option<u32> = None;
            for m in from..until {
                daylight_min = if daylight(m) { daylight_min + 1 } else { 0 };
                since_in = if spell(m) {
                    Some(m)
                } else {
                    since_in.filter(|_| daylight(m))
                };
                let r = &rows[m as usize];
                if matches!(r.mode, "tracking" | "unwind") {
                    assert!(
                        since_in.is_none() && daylight_min <= 30,
                        "overcast spell {from}..{until}: tracking at minute {m}"
                    );
                }
            }
        } else {
            // The input is read at its first minute: the stow, or a mode
            // above it, from then to its end.
            for m in from..until {
                assert!(
                    spell(m) || outranked(m),
                    "{mode} spell {from}..{until}: {} at minute {m}",
                    rows[m as usize].mode
                );
            }
        }
        let was_entered = (from..until + release).any(spell);
        if was_entered {
            *entered.entry(mode).or_default() += 1;
        } else {
            assert!(
                (from..until).all(outranked),
                "{mode} spell {from}..{until} never entered"
            );
        }
        if let Kind::LowSupply(sag_mv) = w.kind {
            let overlapped = spells.iter().any(|(o, ..)| {
                matches!(o.kind, Kind::LowSupply(_))
                    && o.from != w.from
                    && o.from < until + 60
                    && w.from < o.until + 60
            });
            if !overlapped {
                // Below the stow level, then between the levels (held by
                // hysteresis), then charged above the resume level; then
                // the regulated 12 V again.
                assert_eq!(rows[from as usize].supply_mv, f64::from(sag_mv));
                assert!(f64::from(sag_mv) < 11_500.0);
                assert_eq!(rows[until as usize - 1].supply_mv, 11_900.0);
                assert_eq!(rows[until as usize].supply_mv, 12_600.0);
                assert_eq!(rows[until as usize + 60].supply_mv, 12_000.0);
                assert_ne!(rows[until as usize].mode, "low_supply_stow");
            }
        }
        // Tracking again within two days of the release (a night, a safe
        // stop until the technician's visit the next morning).
        let after = until + release;
        let back = (after..after + 2 * 1440).find(|m| rows[*m as usize].mode == "tracking");
        assert!(
            back.is_some(),
            "{mode} spell {from}..{until}: no tracking in the two days after"
        );
    }
    for mode in [
        "snow_stow",
        "hail_stow",
        "external_stow",
        "low_supply_stow",
        "overcast",
    ] {
        assert!(
            entered.get(mode).copied().unwrap_or(0) >= 1,
            "{mode}: {entered:?}"
        );
    }

    // The summary's minutes and entries per mode are the trace's.
    let line = out
        .lines()
        .find_map(|l| l.strip_prefix("modes (minutes / entries): "))
        .unwrap_or_else(|| panic!("no modes line: {out}"));
    for item in line.split(", ") {
        let (name, figures) = item.split_once(' ').expect("mode figures");
        let (minutes, entries) = figures.split_once(" / ").expect("minutes / entries");
        let in_mode = rows.iter().filter(|r| r.mode == name).count();
        let entries_in_trace = (0..rows.len())
            .filter(|&m| rows[m].mode == name && (m == 0 || rows[m - 1].mode != name))
            .count();
        assert_eq!(minutes.parse::<usize>().ok(), Some(in_mode), "{item}");
        assert_eq!(
            entries.parse::<usize>().ok(),
            Some(entries_in_trace),
            "{item}"
        );
    }
    assert_eq!(line.split(", ").count(), PRIORITY.len(), "{line}");

    // Pointing while tracking, from the trace.
    let mut errors: Vec<f64> = rows
        .iter()
        .filter(|r| r.mode == "tracking")
        .filter_map(|r| r.pointing_deg)
        .collect();
    errors.sort_by(f64::total_cmp);
    let p95 = errors[((errors.len() - 1) as f64 * 0.95).round() as usize];
    assert!(p95 < 0.05, "p95 {p95}");
    let last = out.lines().last().unwrap_or("");
    let tool_p95: f64 = last
        .split_whitespace()
        .find_map(|kv| kv.strip_prefix("pointing_p95_deg="))
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{last}"));
    assert!((tool_p95 - p95).abs() <= 0.0001, "{tool_p95} against {p95}");
    assert!(last.ends_with("faults_unrecovered=0 panics=0"), "{last}");
}
