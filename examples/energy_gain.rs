//! Modelled clear-sky energy of a fixed panel, a single-axis and a
//! dual-axis tracker for a site over a day, a month or a year.
//!
//! ```text
//! cargo run --example energy_gain                                  # Doha, 2016-03-21
//! cargo run --example energy_gain -- --period year --date 2016-01-01
//! cargo run --example energy_gain -- --postal-code DZ:30000 --period month --date 2022-12-01
//! ```
//! Model (sun_algos::geometry::irradiance): ASHRAE clear sky with Masters'
//! coefficient fits, isotropic sky, albedo 0.2 (`--albedo`), G_T = G_B +
//! G_D + G_R (seed dahli-2023), trapezoid rule every 5 min (seed
//! chowdhury-2019's area under the curve). Fixed: slope = |latitude|,
//! facing the equator. Single axis: horizontal north–south axis turned
//! east–west, unlimited. Dual axis: normal to the sun. Default site: seed
//! chowdhury-2019's Qatar University, Doha (25.37463 N, 51.49128 E).

use std::process::ExitCode;

use sun_algos::geometry::events::solar_day_start;
use sun_algos::geometry::irradiance::{clear_sky_day_energy_wh_m2, Mount};
use sun_algos::time::days_in_month;
use sun_algos::{Algorithm, Options, Site, UtcTime};
use suntracker::site::postal;

const USAGE: &str =
    "usage: energy_gain [--lat DEG --lon DEG | --postal-code CC:CODE] [--date YYYY-MM-DD]
                   [--period day|month|year] [--algorithm NAME] [--albedo A] [--step-min N]";

#[derive(Clone, Copy, PartialEq)]
enum Period {
    Day,
    Month,
    Year,
}

struct Args {
    lat: f64,
    lon: f64,
    place: String,
    ymd: (i32, u8, u8),
    period: Period,
    algorithm: Algorithm,
    albedo: f64,
    step_min: u32,
}

fn parse(argv: &[String]) -> Result<Args, String> {
    let mut a = Args {
        lat: 25.37463,
        lon: 51.49128,
        place: "Doha (Qatar University)".into(),
        ymd: (2016, 3, 21),
        period: Period::Day,
        algorithm: Algorithm::Spa,
        albedo: 0.2,
        step_min: 5,
    };
    let mut it = argv.iter();
    let (mut lat, mut lon) = (None, None);
    let num = |s: Option<&String>, f: &str| -> Result<f64, String> {
        s.and_then(|v| v.parse::<f64>().ok())
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{f} needs a number"))
    };
    while let Some(f) = it.next() {
        match f.as_str() {
            "--lat" => lat = Some(num(it.next(), f)?),
            "--lon" => lon = Some(num(it.next(), f)?),
            "--albedo" => {
                a.albedo = num(it.next(), f)?;
                if !(0.0..=1.0).contains(&a.albedo) {
                    return Err("--albedo: 0..1".into());
                }
            }
            "--step-min" => {
                let v = num(it.next(), f)?;
                if !(1.0..=60.0).contains(&v) || 1440 % (v as u32) != 0 || v.fract() != 0.0 {
                    return Err("--step-min: 1..60 dividing 1440".into());
                }
                a.step_min = v as u32;
            }
            "--postal-code" => {
                let c = it.next().ok_or("--postal-code needs CC:CODE")?;
                let e = postal::lookup_str(c).map_err(|e| format!("--postal-code {c:?}: {e}"))?;
                a.lat = e.latitude_deg();
                a.lon = e.longitude_deg();
                a.place = format!("{} ({c})", e.place());
            }
            "--date" => {
                let d = it.next().ok_or("--date needs YYYY-MM-DD")?;
                let t: UtcTime = format!("{d}T00:00:00Z")
                    .parse()
                    .map_err(|e| format!("--date {d:?}: {e}"))?;
                a.ymd = t.ymd();
            }
            "--period" => {
                a.period = match it.next().map(String::as_str) {
                    Some("day") => Period::Day,
                    Some("month") => Period::Month,
                    Some("year") => Period::Year,
                    _ => return Err("--period day|month|year".into()),
                }
            }
            "--algorithm" => {
                let n = it.next().ok_or("--algorithm needs a name")?;
                a.algorithm =
                    Algorithm::from_name(n).ok_or_else(|| format!("unknown algorithm {n:?}"))?;
            }
            _ => return Err(USAGE.into()),
        }
    }
    match (lat, lon) {
        (Some(la), Some(lo)) => {
            a.lat = la;
            a.lon = lo;
            a.place = "site".into();
        }
        (None, None) => {}
        _ => return Err("--lat and --lon go together".into()),
    }
    Site::new(a.lat, a.lon).map_err(|e| e.to_string())?;
    Ok(a)
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

fn pct(a: f64, b: f64) -> String {
    if b > 0.0 {
        format!("{:+.1} %", (a / b - 1.0) * 100.0)
    } else {
        "-".into()
    }
}

fn row(label: &str, e: [f64; 3]) {
    println!(
        "{label:<12} {:>9.2} {:>9.2} {:>9.2}   {:>9} {:>9}",
        e[0] / 1000.0,
        e[1] / 1000.0,
        e[2] / 1000.0,
        pct(e[2], e[0]),
        pct(e[2], e[1])
    );
}

fn main() -> ExitCode {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let a = match parse(&argv) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let (y, m, d) = a.ymd;
    println!(
        "Clear-sky energy, kWh/m2: {} ({:.4}, {:.4}), algorithm {}, albedo {}, step {} min",
        a.place,
        a.lat,
        a.lon,
        a.algorithm.name(),
        a.albedo,
        a.step_min
    );
    println!("fixed: slope {:.1} deg facing the equator; single: horizontal N-S axis; dual: normal to the sun", a.lat.abs());
    println!(
        "{:<12} {:>9} {:>9} {:>9}   {:>9} {:>9}",
        "period", "fixed", "single", "dual", "dual/fix", "dual/sgl"
    );
    let mut total = [0.0f64; 3];
    let mut add = |e: [f64; 3]| {
        for (t, v) in total.iter_mut().zip(e) {
            *t += v;
        }
    };
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
            match day(&a, y, mo, dd) {
                Ok(e) => {
                    if a.period != Period::Year {
                        row(&format!("{y:04}-{mo:02}-{dd:02}"), e);
                    }
                    for (t, v) in month.iter_mut().zip(e) {
                        *t += v;
                    }
                }
                Err(e) => {
                    eprintln!("{y:04}-{mo:02}-{dd:02}: {e}");
                    return ExitCode::from(1);
                }
            }
        }
        if a.period == Period::Year {
            row(&format!("{y:04}-{mo:02}"), month);
        }
        add(month);
    }
    if a.period != Period::Day {
        row("total", total);
    }
    ExitCode::SUCCESS
}
