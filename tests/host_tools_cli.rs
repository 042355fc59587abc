//! The command lines of the host tools (`examples/daily_setpoints.rs`,
//! `energy_gain.rs`, `simulate.rs`, `sun_path.rs` and the drivers crate's
//! `gps_log`), through the same `run` functions their `main`s call: help,
//! usage errors and exit codes, `energy_gain --format csv`, `simulate --svg`,
//! and the axis ranges of `sun_path`.

// Each tool includes the shared examples/common/ modules itself (they are
// separate programs); gathered here, those files are loaded once per tool.
#![allow(clippy::duplicate_mod)]

#[path = "../examples/daily_setpoints_support/run.rs"]
#[allow(dead_code)]
mod daily_setpoints;
#[path = "../examples/energy_gain.rs"]
#[allow(dead_code)]
mod energy_gain;
#[path = "../drivers/examples/gps_log.rs"]
#[allow(dead_code)]
mod gps_log;
#[path = "../examples/simulate_support/schedule.rs"]
#[allow(dead_code)]
mod schedule;
#[path = "../examples/simulate_support/run.rs"]
#[allow(dead_code)]
mod simulate;
#[path = "../examples/sun_path.rs"]
#[allow(dead_code)]
mod sun_path;

use sun_algos::geometry::events::DayKind;
use sun_algos::Algorithm;

/// Exit code, stdout and stderr of one run.
struct Outcome {
    code: u8,
    out: String,
    err: String,
}

type RunFn = fn(&[String], &mut dyn std::io::Write, &mut dyn std::io::Write) -> u8;

fn daily_setpoints_run(
    args: &[String],
    out: &mut dyn std::io::Write,
    err: &mut dyn std::io::Write,
) -> u8 {
    // As its main does: the tests' "today" is Jimoh & Aliyu's (2019) example day.
    match daily_setpoints::run(args, (2018, 10, 19), out, err) {
        Ok(()) => 0,
        Err(e) => daily_setpoints::cli::usage_error(daily_setpoints::TOOL, &e, err),
    }
}

/// Every tool: name and `run`.
const TOOLS: [(&str, RunFn); 5] = [
    ("daily_setpoints", daily_setpoints_run),
    ("energy_gain", energy_gain::run),
    ("simulate", simulate::run),
    ("sun_path", sun_path::run),
    ("gps_log", gps_log::cli),
];

fn run(f: RunFn, args: &[&str]) -> Outcome {
    let args: Vec<String> = args.iter().map(|s| s.to_string()).collect();
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let code = f(&args, &mut out, &mut err);
    Outcome {
        code,
        out: String::from_utf8(out).expect("utf8 stdout"),
        err: String::from_utf8(err).expect("utf8 stderr"),
    }
}

/// A unique temporary path.
fn temp(name: &str) -> std::path::PathBuf {
    let mut p = std::env::temp_dir();
    p.push(format!("host_tools_cli_{}_{name}", std::process::id()));
    p
}

#[test]
fn help_goes_to_stdout_with_exit_0_for_every_tool() {
    for (name, f) in TOOLS {
        // Anywhere on the line, after valid options too.
        for args in [&["--help"][..], &["-h"], &["--lat", "52", "--help"]] {
            if name == "gps_log" && args.len() > 1 {
                continue;
            }
            let o = run(f, args);
            assert_eq!(o.code, 0, "{name} {args:?}: {}", o.err);
            assert_eq!(o.err, "", "{name} {args:?}");
            assert!(
                o.out.starts_with(&format!("usage: {name}")),
                "{name}: {}",
                o.out
            );
            assert!(o.out.contains("-h, --help"), "{name}: {}", o.out);
        }
    }
}

/// The book's chapter on the host tools quotes each tool's `--help` as
/// the tool prints it (a new option shows there too).
#[test]
fn the_book_quotes_every_tool_help_as_printed() {
    let book = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/docs/src/host-tools.md"
    ))
    .expect("docs/src/host-tools.md");
    for (name, f) in TOOLS {
        let help = run(f, &["--help"]).out;
        assert!(
            book.contains(help.trim_end()),
            "docs/src/host-tools.md does not quote `{name} --help` as printed:\n{help}"
        );
    }
}

/// The options that `tests/` and `.ci/readme_figures.py` (and the README)
/// pass to the tools, each of which the help must list with its default.
const DOCUMENTED: [(&str, &[&str]); 4] = [
    (
        "daily_setpoints",
        &[
            "--lat",
            "--lon",
            "--postal-code",
            "--date",
            "--interval-min",
            "--algorithm",
            "--float",
            "--format",
            "--allow-out-of-range",
        ],
    ),
    (
        "energy_gain",
        &[
            "--lat",
            "--lon",
            "--postal-code",
            "--date",
            "--period",
            "--algorithm",
            "--albedo",
            "--step-min",
            "--format",
        ],
    ),
    (
        "simulate",
        &[
            "--lat",
            "--lon",
            "--start",
            "--days",
            "--drive",
            "--supply",
            "--feedback",
            "--mount",
            "--faults",
            "--seed",
            "--scenario",
            "--trace",
            "--svg",
        ],
    ),
    ("sun_path", &["--lat", "--lon", "--date", "--out"]),
];

#[test]
fn help_lists_every_option_with_its_default_and_every_algorithm() {
    for (name, options) in DOCUMENTED {
        let f = TOOLS.iter().find(|t| t.0 == name).expect("tool").1;
        let help = run(f, &["--help"]).out;
        // The option lines: from "options:" to the next blank line.
        let block: Vec<&str> = help
            .split("\noptions:\n")
            .nth(1)
            .expect("options block")
            .split("\n\n")
            .next()
            .expect("options")
            .lines()
            .collect();
        for opt in options {
            // An option's entry: its line ("  --opt ...") and the indented
            // continuation lines under it.
            let start = block
                .iter()
                .position(|l| {
                    l.starts_with("  -")
                        && (l[2..].starts_with(&format!("{opt} "))
                            || l[2..].starts_with(&format!("{opt}, ")))
                })
                .unwrap_or_else(|| panic!("{name}: {opt} not in the help:\n{help}"));
            let entry: String = block[start..]
                .iter()
                .enumerate()
                .take_while(|(i, l)| *i == 0 || l.starts_with("   "))
                .map(|(_, l)| l.trim())
                .collect::<Vec<_>>()
                .join(" ");
            assert!(entry.contains("[default: "), "{name}: {entry}");
        }
        // Every algorithm the tool accepts, with its years, from sun_algos.
        if options.contains(&"--algorithm") {
            for a in Algorithm::ALL {
                let (lo, hi) = a.validity_years();
                let line = help
                    .lines()
                    .find(|l| l.split_whitespace().next() == Some(a.name()))
                    .unwrap_or_else(|| panic!("{name}: no line for {}", a.name()));
                assert!(line.contains(&format!("{lo} to {hi}")), "{name}: {line}");
            }
        }
    }
}

#[test]
fn an_unknown_option_is_named_with_exit_2() {
    for (name, f) in TOOLS {
        for (args, named) in [
            (&["--bogus"][..], "--bogus"),
            (&["--bogus=3"], "--bogus"),
            (&["-q"], "-q"),
        ] {
            let o = run(f, args);
            assert_eq!(o.code, 2, "{name} {args:?}");
            assert_eq!(o.out, "", "{name} {args:?}");
            assert!(o.err.starts_with(&format!("{name}: ")), "{name}: {}", o.err);
            assert!(o.err.contains(named), "{name} {args:?}: {}", o.err);
        }
    }
}

#[test]
fn a_missing_or_bad_value_is_named_with_exit_2() {
    for (name, args, named) in [
        ("daily_setpoints", &["--lat"][..], "--lat"),
        ("daily_setpoints", &["--format", "xml"], "--format"),
        ("energy_gain", &["--period", "week"], "--period"),
        ("energy_gain", &["--albedo", "2"], "--albedo"),
        ("simulate", &["--days", "0"], "--days"),
        ("simulate", &["--drive", "diesel"], "--drive"),
        ("sun_path", &["--date", "2026-02-30"], "--date"),
        ("sun_path", &["--out"], "--out"),
    ] {
        let f = TOOLS.iter().find(|t| t.0 == name).expect("tool").1;
        let o = run(f, args);
        assert_eq!(o.code, 2, "{name} {args:?}");
        assert!(o.err.contains(named), "{name} {args:?}: {}", o.err);
    }
}

#[test]
fn postal_code_with_lat_lon_is_a_conflict_naming_both() {
    for name in ["energy_gain", "daily_setpoints"] {
        let f = TOOLS.iter().find(|t| t.0 == name).expect("tool").1;
        for args in [
            &["--postal-code", "DZ:30000", "--lat", "25", "--lon", "51"][..],
            &["--lat", "25", "--lon", "51", "--postal-code", "DZ:30000"],
            &["--lat", "25", "--postal-code", "DZ:30000"],
        ] {
            let o = run(f, args);
            assert_eq!(o.code, 2, "{name} {args:?}");
            assert_eq!(o.out, "", "{name} {args:?}");
            assert!(
                o.err.contains("--postal-code") && o.err.contains("--lat"),
                "{name} {args:?}: {}",
                o.err
            );
        }
        let o = run(f, &["--lon", "51"]);
        assert_eq!(o.code, 2);
        assert!(
            o.err.contains("--lon") && o.err.contains("--lat"),
            "{}",
            o.err
        );
    }
}

#[test]
fn negative_values_and_equals_signs_are_values() {
    // Sydney, through `--lat=-33.87` and `--lon 151.21`.
    let o = run(
        energy_gain::run,
        &["--lat=-33.87", "--lon", "151.21", "--date", "2016-06-21"],
    );
    assert_eq!(o.code, 0, "{}", o.err);
    assert!(o.out.contains("(-33.8700, 151.2100)"), "{}", o.out);
}

/// The numbers of a line after its first field.
fn numbers(fields: &[&str]) -> Vec<f64> {
    fields
        .iter()
        .map(|v| v.trim_end_matches(" %").parse().expect("number"))
        .collect()
}

#[test]
fn energy_gain_csv_has_the_table_rows_and_a_total_that_adds_up() {
    let csv = run(
        energy_gain::run,
        &[
            "--period",
            "month",
            "--date",
            "2016-02-01",
            "--format",
            "csv",
        ],
    );
    assert_eq!(csv.code, 0, "{}", csv.err);
    let mut lines = csv.out.lines();
    assert_eq!(lines.next(), Some(energy_gain::CSV_HEADER));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // 29 days of February 2016 and the total.
    assert_eq!(rows.len(), 30);
    assert_eq!(rows[0][0], "2016-02-01");
    assert_eq!(rows[28][0], "2016-02-29");
    assert_eq!(rows[29][0], "total");
    let mut sum = [0.0; 3];
    for r in &rows[..29] {
        assert_eq!(r.len(), 6, "{r:?}");
        let v = numbers(&r[1..]);
        for (s, x) in sum.iter_mut().zip(&v) {
            *s += x;
        }
        // The gains are those of the energies (to the printed digits).
        let gain = (v[2] / v[0] - 1.0) * 100.0;
        assert!((gain - v[3]).abs() < 0.002, "{r:?}");
    }
    let total = numbers(&rows[29][1..]);
    for (s, t) in sum.iter().zip(&total) {
        assert!((s - t).abs() < 29.0 * 0.000_005 + 1e-9, "{s} {t}");
    }
    // The same rows as the table, rounded as the table prints them.
    let table = run(
        energy_gain::run,
        &["--period", "month", "--date", "2016-02-01"],
    );
    assert_eq!(table.code, 0);
    let t: Vec<&str> = table
        .out
        .lines()
        .find(|l| l.starts_with("2016-02-10 "))
        .expect("table row")
        .split_whitespace()
        .collect();
    let c = &rows[9];
    assert_eq!(c[0], t[0]);
    for i in 1..4 {
        let x: f64 = c[i].parse().expect("csv");
        assert_eq!(format!("{x:.2}"), t[i], "{c:?} {t:?}");
    }
    let g: f64 = c[4].parse().expect("csv");
    assert_eq!(format!("{g:+.1}"), t[4], "{c:?} {t:?}");
}

#[test]
fn daily_setpoints_help_through_run() {
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let args = vec!["--help".to_string()];
    daily_setpoints::run(&args, (2018, 10, 19), &mut out, &mut err).expect("help");
    let out = String::from_utf8(out).expect("utf8");
    assert!(out.contains("--allow-out-of-range"));
    assert!(err.is_empty());
}

#[test]
fn simulate_svg_draws_the_run_with_its_fault() {
    let svg = temp("stall.svg");
    let scenario = format!(
        "{}/tests/scenarios/motor_stall.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let o = run(
        simulate::run,
        &[
            "--start",
            "2026-06-01",
            "--scenario",
            &scenario,
            "--svg",
            &svg.to_string_lossy(),
        ],
    );
    assert_eq!(o.code, 0, "{}", o.err);
    let text = std::fs::read_to_string(&svg).expect("svg written");
    let _ = std::fs::remove_file(&svg);
    assert!(text.starts_with("<svg width=\"960\""), "{}", &text[..80]);
    assert!(text.trim_end().ends_with("</svg>"));
    // The fault the scenario causes has its row, the modes their legend.
    let trace_fault = "motor_stalled_a";
    assert!(text.contains(trace_fault));
    for label in [
        "mode tracking",
        "mode night",
        "fault active",
        "pointing error",
    ] {
        assert!(text.contains(label), "{label}");
    }
    // A path that cannot be written fails before the run.
    let o = run(simulate::run, &["--svg", "/nonexistent/dir/run.svg"]);
    assert_eq!(o.code, 2);
    assert_eq!(o.out, "");
    assert!(o.err.contains("/nonexistent/dir/run.svg"), "{}", o.err);
}

#[test]
fn gps_log_reads_a_file_argument() {
    let path = format!(
        "{}/drivers/tests/data/gps_golden_mixed.nmea",
        env!("CARGO_MANIFEST_DIR")
    );
    let o = run(gps_log::cli, &[&path]);
    assert_eq!(o.code, 0, "{}", o.err);
    assert!(o
        .out
        .starts_with("utc,latitude,longitude,altitude,quality,satellites\n"));
    assert!(o.out.contains("\nsentences="), "{}", o.out);
    let o = run(gps_log::cli, &["/nonexistent.nmea"]);
    assert_eq!(o.code, 1);
    assert!(o.err.contains("/nonexistent.nmea"));
}

// ---------------------------------------------------------------- sun_path

/// Obliquity of the ecliptic, the sun's declination at the June solstice
/// (its negative in December), degrees (Astronomical Almanac 2026: 23.436°).
const SOLSTICE_DECL_DEG: f64 = 23.44;

/// Azimuth of sunrise from the equator side (degrees, east negative) at a
/// latitude with the sun at declination `decl`, from the spherical triangle
/// pole–zenith–sun at the geometric horizon: cos A_N = sin δ / cos φ (A_N
/// east of north; Duffie & Beckman, Solar Engineering of Thermal
/// Processes, sec. 1.6, with θz = 90°). An independent computation.
fn sunrise_azimuth_from_equator_deg(lat: f64, decl: f64) -> f64 {
    let a_north = (decl.to_radians().sin() / lat.to_radians().cos())
        .acos()
        .to_degrees();
    if lat >= 0.0 {
        -(180.0 - a_north)
    } else {
        -a_north
    }
}

/// Noon elevation, 90° − |φ − δ| (geometric).
fn noon_elevation_deg(lat: f64, decl: f64) -> f64 {
    90.0 - (lat - decl).abs()
}

#[test]
fn sun_path_axes_hold_every_plotted_point_for_any_site() {
    let sites = [
        ("Berlin", 52.52, 13.40),
        ("Sydney", -33.87, 151.21),
        ("Tromso", 69.65, 18.96),
    ];
    for (name, lat, lon) in sites {
        for (month, decl) in [(6u8, SOLSTICE_DECL_DEG), (12, -SOLSTICE_DECL_DEG)] {
            let d = sun_path::sun_path_data(lat, lon, (2026, month, 21)).expect("data");
            let r = sun_path::axis_ranges(&d);
            let what = format!("{name} 2026-{month:02}-21 {r:?}");
            let mut n = 0;
            let (mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for (x, y) in d.points() {
                assert!(r.x.0 <= x && x <= r.x.1, "{what}: x {x}");
                assert!(r.y.0 <= y && y <= r.y.1, "{what}: y {y}");
                y_lo = y_lo.min(y);
                y_hi = y_hi.max(y);
                n += 1;
            }
            assert!(n > 100, "{what}: {n} points");
            // Room for the curves, not a fixed frame: within 14° (4° pad,
            // rounded to 10°) of the points, within an hour in x.
            assert!(y_lo - r.y.0 <= 14.0 && r.y.1 - y_hi <= 14.0, "{what}");
            let (x_lo, x_hi) = d
                .points()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p.0), b.max(p.0))
                });
            assert!(x_lo - r.x.0 <= 1.0 && r.x.1 - x_hi <= 1.0, "{what}");

            // The sky of that day, from the independent formulas (1° for
            // refraction, the -5° tail and the day's exact declination).
            let noon = noon_elevation_deg(lat, decl);
            if noon > 0.0 {
                assert!(r.y.1 >= noon - 1.0, "{what}: noon elevation {noon}");
            }
            let polar_day = lat.abs() + decl.abs() > 90.0 && lat.signum() == decl.signum();
            let polar_night = lat.abs() + decl.abs() > 90.0 && lat.signum() != decl.signum();
            if polar_day {
                assert_eq!(d.kind, DayKind::PolarDay, "{what}");
                // The sun all round the sky, the set-points all day.
                assert!(r.y.0 <= -179.0 && r.y.1 >= 179.0, "{what}");
                assert!(r.x.1 - r.x.0 >= 24.0, "{what}");
                assert_eq!(d.slope.len(), 24 * 60 / 4, "{what}");
            } else if polar_night {
                assert_eq!(d.kind, DayKind::PolarNight, "{what}");
                assert!(d.slope.is_empty(), "{what}");
                // Noon at -3.1°: the sun never up.
                assert!(y_hi > noon - 1.0, "{what}");
                assert!(d.elevation.iter().all(|p| p.1 < 0.0), "{what}");
            } else {
                let rise = sunrise_azimuth_from_equator_deg(lat, decl);
                // East at sunrise, west (mirror) at sunset, both inside.
                assert!(
                    r.y.0 <= rise + 1.0 && r.y.1 >= -rise - 1.0,
                    "{what}: sunrise {rise}"
                );
                assert!(
                    y_lo <= rise + 1.0 && y_hi >= -rise - 1.0,
                    "{what}: sunrise {rise}"
                );
            }
        }
    }
}

#[test]
fn sun_path_measures_azimuths_from_the_equator_side() {
    use sun_path::Reference;
    // East of north → from the equator, west positive.
    for (az, south, north) in [
        (90.0, -90.0, -90.0),
        (270.0, 90.0, 90.0),
        (180.0, 0.0, 180.0),
        (0.0, 180.0, 0.0),
        (135.0, -45.0, -135.0),
    ] {
        assert_eq!(Reference::South.azimuth(az), south, "{az}");
        assert_eq!(Reference::North.azimuth(az), north, "{az}");
    }
    assert_eq!(Reference::for_latitude(52.0), Reference::South);
    assert_eq!(Reference::for_latitude(-33.0), Reference::North);
}

#[test]
fn sun_path_breaks_the_azimuth_curve_where_it_wraps() {
    // Kano in June: the noon sun passes north of the zenith, the azimuth
    // from south jumps from -180° to +180°: two polylines, none with a
    // step larger than the sun moves in two minutes.
    let d = sun_path::sun_path_data(11.9683, 8.4261, (2026, 6, 21)).expect("data");
    assert_eq!(
        d.azimuth.len(),
        2,
        "{:?}",
        d.azimuth.iter().map(Vec::len).collect::<Vec<_>>()
    );
    for seg in &d.azimuth {
        for w in seg.windows(2) {
            assert!((w[1].1 - w[0].1).abs() < 20.0, "{w:?}");
        }
    }
    // Berlin in June: one curve, past the old fixed frame's -100°/+125°.
    let d = sun_path::sun_path_data(52.52, 13.40, (2026, 6, 21)).expect("data");
    assert_eq!(d.azimuth.len(), 1);
    let r = sun_path::axis_ranges(&d);
    assert!(r.y.0 < -100.0 && r.y.1 > 125.0, "{r:?}");
}

#[test]
fn sun_path_svg_has_a_legend_entry_for_every_series() {
    let d = sun_path::sun_path_data(11.9683, 8.4261, (2018, 10, 19)).expect("data");
    let svg = sun_path::sun_path_svg(&d).expect("svg");
    for label in [
        "sun elevation",
        "sun azimuth from south",
        "set-point slope",
        "set-point surface azimuth",
    ] {
        assert!(svg.contains(label), "{label}");
    }
    // Drawn on the 4x canvas, shown at 960 x 620.
    assert!(svg.starts_with("<svg width=\"960\" height=\"620\" viewBox=\"0 0 3840 2480\""));
}
