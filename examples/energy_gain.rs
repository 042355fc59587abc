//! Modelled clear-sky energy of a fixed panel, a single-axis and a
//! dual-axis tracker for a site over a day, a month or a year.
//!
//! ```text
//! cargo run --example energy_gain                                  # Doha, 2016-03-21
//! cargo run --example energy_gain -- --period year --date 2016-01-01
//! cargo run --example energy_gain -- --postal-code DZ:30000 --period month --date 2022-12-01
//! cargo run --example energy_gain -- --period year --date 2016-01-01 --format csv
//! ```
//! Model (sun_algos::geometry::irradiance): ASHRAE clear sky with Masters'
//! coefficient fits, isotropic sky, albedo 0.2 (`--albedo`), G_T = G_B +
//! G_D + G_R (Dahli & Cheggaga 2023), trapezoid rule every 5 min (Chowdhury
//! et al.'s (2019) area under the curve). Fixed: slope = |latitude|,
//! facing the equator. Single axis: horizontal north–south axis turned
//! east–west, unlimited. Dual axis: normal to the sun. Default site:
//! Chowdhury et al.'s (2019) Qatar University, Doha (25.37463 N, 51.49128 E).
//!
//! `--format table` (the default) prints a heading and a table in kWh/m²
//! with the dual-axis gains in percent; `--format csv` prints the same rows
//! as CSV ([`CSV_HEADER`]) with more digits and no heading. `--help` lists
//! every option with its default.

use std::io::Write;
use std::process::ExitCode;

use sun_algos::geometry::events::solar_day_start;
use sun_algos::geometry::irradiance::{clear_sky_day_energy_wh_m2, Mount};
use sun_algos::time::days_in_month;
use sun_algos::{Algorithm, Options, Site};

#[path = "common/cli.rs"]
mod cli;

use cli::Parsed;

/// The program name in messages.
pub const TOOL: &str = "energy_gain";

/// The header of `--format csv`: the period (`YYYY-MM-DD` for a day,
/// `YYYY-MM` for a month of a year run, `total`), the energies of the three
/// mounts in kWh/m², and the dual-axis gains over fixed and single axis in
/// percent (empty when the other mount collects nothing).
pub const CSV_HEADER: &str =
    "period,fixed_kwh_m2,single_kwh_m2,dual_kwh_m2,dual_vs_fixed_pct,dual_vs_single_pct";

/// The synopsis of `--help`.
const SYNOPSIS: &str = "[--lat DEG --lon DEG | --postal-code CC:CODE] [--date YYYY-MM-DD] \
[--period day|month|year] [--algorithm NAME] [--albedo A] [--step-min N] [--format table|csv]";

/// The text of `--help`.
pub fn help() -> cli::Help {
    use cli::opt;
    cli::Help {
        tool: TOOL,
        synopsis: SYNOPSIS,
        about: "\
Modelled clear-sky energy (kWh/m2) of a fixed panel (slope = |latitude|, facing the equator), a
single-axis tracker (horizontal north-south axis) and a dual-axis tracker (normal to the sun),
per local solar day: ASHRAE clear sky, isotropic sky, ground albedo, trapezoid rule.",
        options: vec![
            opt(
                "--lat DEG",
                "site latitude, degrees north (south negative); with --lon",
                "25.37463 (Doha, Qatar University)",
            ),
            opt(
                "--lon DEG",
                "site longitude, degrees east (west negative); with --lat",
                "51.49128 (Doha, Qatar University)",
            ),
            opt(
                "--postal-code CC:CODE",
                "site of a postal code of data/postal_codes.csv (e.g. DZ:30000); not with --lat/--lon",
                "none",
            ),
            opt(
                "--date YYYY-MM-DD",
                "the day; for --period month or year its month or year",
                "2016-03-21",
            ),
            opt(
                "--period day|month|year",
                "one day, every day of the month (one row each), or the year (one row a month)",
                "day",
            ),
            opt("--algorithm NAME", "solar position algorithm (list below)", "spa"),
            opt("--albedo A", "ground reflectance, 0 to 1", "0.2"),
            opt("--step-min N", "integration step in minutes, 1 to 60 dividing 1440", "5"),
            opt(
                "--format table|csv",
                "output: heading and table, or CSV without heading",
                "table",
            ),
        ],
        algorithms: true,
        notes: "",
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Period {
    Day,
    Month,
    Year,
}

/// Parsed command line.
#[derive(Debug, Clone, PartialEq)]
pub struct Args {
    pub lat: f64,
    pub lon: f64,
    pub place: String,
    pub ymd: (i32, u8, u8),
    pub period: Period,
    pub algorithm: Algorithm,
    pub albedo: f64,
    pub step_min: u32,
    pub csv: bool,
}

/// Parses the arguments (without the program name).
pub fn parse(argv: &[String]) -> Result<Parsed<Args>, String> {
    use cli::{Long, Short};
    let mut a = Args {
        lat: 25.37463,
        lon: 51.49128,
        place: "Doha (Qatar University)".into(),
        ymd: (2016, 3, 21),
        period: Period::Day,
        algorithm: Algorithm::Spa,
        albedo: 0.2,
        step_min: 5,
        csv: false,
    };
    let (mut lat, mut lon, mut postal_code) = (None, None, None);
    let mut p = cli::parser(argv);
    while let Some(arg) = p.next().map_err(cli::error)? {
        match arg {
            Short('h') | Long("help") => return Ok(Parsed::Help),
            Long("lat") => lat = Some(cli::number(&mut p, "--lat")?),
            Long("lon") => lon = Some(cli::number(&mut p, "--lon")?),
            Long("postal-code") => postal_code = Some(cli::text(&mut p, "--postal-code")?),
            Long("albedo") => {
                a.albedo = cli::value(&mut p, "--albedo", "a number from 0 to 1", |v| {
                    v.parse::<f64>().ok().filter(|x| (0.0..=1.0).contains(x))
                })?
            }
            Long("step-min") => {
                a.step_min = cli::value(&mut p, "--step-min", "1..60 dividing 1440", |v| {
                    // Whole minutes, written `5` or `5.0`.
                    v.parse::<f64>()
                        .ok()
                        .filter(|x| (1.0..=60.0).contains(x) && x.fract() == 0.0)
                        .map(|x| x as u32)
                        .filter(|n| 1440 % n == 0)
                })?
            }
            Long("date") => a.ymd = cli::date(&mut p, "--date")?,
            Long("period") => {
                a.period = cli::choice(
                    &mut p,
                    "--period",
                    &[
                        ("day", Period::Day),
                        ("month", Period::Month),
                        ("year", Period::Year),
                    ],
                )?
            }
            Long("algorithm") => a.algorithm = cli::algorithm(&mut p, "--algorithm")?,
            Long("format") => {
                a.csv = cli::choice(&mut p, "--format", &[("table", false), ("csv", true)])?
            }
            other => return Err(cli::unexpected(other)),
        }
    }
    let doha = cli::NamedSite {
        lat_deg: a.lat,
        lon_deg: a.lon,
        place: a.place.clone(),
    };
    let site = cli::resolve_site(&cli::site_arg(lat, lon, postal_code)?, doha)?;
    a.lat = site.lat_deg;
    a.lon = site.lon_deg;
    a.place = site.place;
    Ok(Parsed::Run(a))
}

/// Energies [fixed, single, dual] of one local solar day, Wh/m².
fn day(a: &Args, y: i32, m: u8, d: u8) -> Result<[f64; 3], String> {
    let site = Site::new(a.lat, a.lon).map_err(|e| e.to_string())?;
    let opts = Options {
        allow_out_of_range: true,
        ..Options::default()
    };
    let mounts = [
        Mount::fixed_latitude_tilt(a.lat),
        Mount::HorizontalNorthSouthAxis {
            max_rotation_deg: 90.0,
        },
        Mount::DualAxis,
    ];
    let start = solar_day_start(y, m, d, a.lon).map_err(|e| e.to_string())?;
    clear_sky_day_energy_wh_m2(&start, a.step_min * 60, &mounts, a.albedo, |t| {
        a.algorithm.position(t, &site, &opts)
    })
    .map_err(|e| e.to_string())
}

/// The gain of `a` over `b` in percent, if `b` collects anything.
fn gain_pct(a: f64, b: f64) -> Option<f64> {
    (b > 0.0).then(|| (a / b - 1.0) * 100.0)
}

/// One output row: a table line or a CSV record.
fn row(out: &mut dyn Write, csv: bool, label: &str, e: [f64; 3]) -> std::io::Result<()> {
    let (g_fixed, g_single) = (gain_pct(e[2], e[0]), gain_pct(e[2], e[1]));
    if csv {
        let pct = |g: Option<f64>| g.map(|v| format!("{v:.3}")).unwrap_or_default();
        return writeln!(
            out,
            "{label},{:.5},{:.5},{:.5},{},{}",
            e[0] / 1000.0,
            e[1] / 1000.0,
            e[2] / 1000.0,
            pct(g_fixed),
            pct(g_single)
        );
    }
    let pct = |g: Option<f64>| {
        g.map(|v| format!("{v:+.1} %"))
            .unwrap_or_else(|| "-".into())
    };
    writeln!(
        out,
        "{label:<12} {:>9.2} {:>9.2} {:>9.2}   {:>9} {:>9}",
        e[0] / 1000.0,
        e[1] / 1000.0,
        e[2] / 1000.0,
        pct(g_fixed),
        pct(g_single)
    )
}

/// Runs the tool with `argv` (without the program name): the table, CSV
/// or help to `out`, errors to `err`. Returns the exit code: 0, 2 for a
/// usage error, 1 when a day cannot be computed or `out` fails.
pub fn run(argv: &[String], out: &mut dyn Write, err: &mut dyn Write) -> u8 {
    let a = match parse(argv) {
        Ok(Parsed::Run(a)) => a,
        Ok(Parsed::Help) => return cli::print_help(&help(), out),
        Err(e) => return cli::usage_error(TOOL, &e, err),
    };
    match energy(&a, out) {
        Ok(()) => 0,
        // A closed pipe (`| head`) is a normal way to stop.
        Err(Failure::Io(e)) if e.kind() == std::io::ErrorKind::BrokenPipe => 0,
        Err(Failure::Io(e)) => {
            let _ = writeln!(err, "{TOOL}: write: {e}");
            1
        }
        Err(Failure::Day(e)) => {
            let _ = writeln!(err, "{TOOL}: {e}");
            1
        }
    }
}

/// Why a run stopped.
enum Failure {
    Day(String),
    Io(std::io::Error),
}

impl From<std::io::Error> for Failure {
    fn from(e: std::io::Error) -> Self {
        Failure::Io(e)
    }
}

fn energy(a: &Args, out: &mut dyn Write) -> Result<(), Failure> {
    let (y, m, d) = a.ymd;
    if a.csv {
        writeln!(out, "{CSV_HEADER}")?;
    } else {
        writeln!(
            out,
            "Clear-sky energy, kWh/m2: {} ({:.4}, {:.4}), algorithm {}, albedo {}, step {} min",
            a.place,
            a.lat,
            a.lon,
            a.algorithm.name(),
            a.albedo,
            a.step_min
        )?;
        writeln!(out, "fixed: slope {:.1} deg facing the equator; single: horizontal N-S axis; dual: normal to the sun", a.lat.abs())?;
        writeln!(
            out,
            "{:<12} {:>9} {:>9} {:>9}   {:>9} {:>9}",
            "period", "fixed", "single", "dual", "dual/fix", "dual/sgl"
        )?;
    }
    let mut total = [0.0f64; 3];
    let months: Vec<u8> = match a.period {
        Period::Year => (1..=12).collect(),
        _ => vec![m],
    };
    for mo in months {
        let days: Vec<u8> = match a.period {
            Period::Day => vec![d],
            _ => (1..=days_in_month(y, mo)).collect(),
        };
        let mut month = [0.0f64; 3];
        for dd in days {
            let e = day(a, y, mo, dd)
                .map_err(|e| Failure::Day(format!("{y:04}-{mo:02}-{dd:02}: {e}")))?;
            if a.period != Period::Year {
                row(out, a.csv, &format!("{y:04}-{mo:02}-{dd:02}"), e)?;
            }
            for (t, v) in month.iter_mut().zip(e) {
                *t += v;
            }
        }
        if a.period == Period::Year {
            row(out, a.csv, &format!("{y:04}-{mo:02}"), month)?;
        }
        for (t, v) in total.iter_mut().zip(month) {
            *t += v;
        }
    }
    if a.period != Period::Day {
        row(out, a.csv, "total", total)?;
    }
    out.flush()?;
    Ok(())
}

#[allow(dead_code)] // a module of tests/host_tools_cli.rs too
fn main() -> ExitCode {
    cli::main(TOOL, run)
}
