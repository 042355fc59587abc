//! The `daily_setpoints` job, shared by the example and its tests.
//!
//! Prints the day's table of tracker set-points (Jimoh & Aliyu 2019: optimum
//! slope and surface azimuth every 4 minutes from sunrise to sunset) for a
//! site given by latitude/longitude or by postal code (Dahli & Cheggaga 2023).

use std::io::Write;

use sun_algos::geometry::day_table::{capacity_for_interval, DayTable};
use sun_algos::geometry::events::{self, DayKind, Events};
use sun_algos::geometry::incidence::incidence_deg;
use sun_algos::geometry::optimum::Limits;
use sun_algos::{Algorithm, Atmosphere, Float, Options, Site, UtcTime};

#[path = "../common/cli.rs"]
pub mod cli;

use cli::Parsed;

/// Kano, Nigeria: the site of Jimoh & Aliyu 2019.
pub const KANO: (f64, f64) = (11.9683, 8.4261);

/// Exact CSV header.
pub const CSV_HEADER: &str =
    "time_utc,solar_time,sun_zenith,sun_azimuth,slope,surface_azimuth,incidence";

/// The program name in messages.
pub const TOOL: &str = "daily_setpoints";

/// The synopsis of `--help`.
pub const USAGE: &str = "[--lat DEG --lon DEG | --postal-code CC:CODE] [--date YYYY-MM-DD] \
[--interval-min N] [--algorithm NAME] [--float f32|f64] [--format table|csv] [--allow-out-of-range]";

/// The text of `--help`.
pub fn help() -> cli::Help {
    use cli::opt;
    cli::Help {
        tool: TOOL,
        synopsis: USAGE,
        about: "\
The tracker's set-points for one day: the slope and surface azimuth (east of north) that put the
panel normal to the sun every N minutes from sunrise to sunset, with the sun's zenith and azimuth
and the remaining incidence angle. Times in UTC and local apparent solar time. Positions are
apparent (standard atmosphere: 1013.25 hPa, 10 °C).",
        options: vec![
            opt(
                "--lat DEG",
                "site latitude, degrees north (south negative); with --lon",
                "11.9683 (Kano)",
            ),
            opt(
                "--lon DEG",
                "site longitude, degrees east (west negative); with --lat",
                "8.4261 (Kano)",
            ),
            opt(
                "--postal-code CC:CODE",
                "site of a postal code of data/postal_codes.csv (e.g. DZ:16000); not with --lat/--lon",
                "none",
            ),
            opt("--date YYYY-MM-DD", "the day (UTC)", "today"),
            opt(
                "--interval-min N",
                "minutes between set-points, 1 to 720 dividing 1440",
                "4",
            ),
            opt("--algorithm NAME", "solar position algorithm (list below)", "spa"),
            opt("--float f32|f64", "floating-point type of the computation", "f64"),
            opt("--format table|csv", "output: a table with the day's events, or CSV", "table"),
            opt(
                "--allow-out-of-range",
                "compute a date outside the algorithm's validity years, with a warning on stderr, \
                 instead of refusing it (exit 2)",
                "off",
            ),
        ],
        algorithms: true,
        notes: "",
    }
}

/// Parsed command line.
#[derive(Debug, Clone, PartialEq)]
pub struct Args {
    pub lat_deg: f64,
    pub lon_deg: f64,
    pub place: String,
    pub ymd: (i32, u8, u8),
    pub interval_min: u16,
    pub algorithm: Algorithm,
    pub f32: bool,
    pub csv: bool,
    /// Compute a date outside the algorithm's validity range (with a
    /// warning) instead of refusing it.
    pub allow_out_of_range: bool,
}

/// Parses the arguments (without the program name); `today` is the default
/// date. `--help` is [`Parsed::Help`].
pub fn parse_cli(args: &[String], today: (i32, u8, u8)) -> Result<Parsed<Args>, String> {
    use cli::{Long, Short};
    let mut a = Args {
        lat_deg: KANO.0,
        lon_deg: KANO.1,
        place: "Kano".into(),
        ymd: today,
        interval_min: 4,
        algorithm: Algorithm::Spa,
        f32: false,
        csv: false,
        allow_out_of_range: false,
    };
    let (mut lat, mut lon, mut postal_code) = (None, None, None);
    let mut p = cli::parser(args);
    while let Some(arg) = p.next().map_err(cli::error)? {
        match arg {
            Short('h') | Long("help") => return Ok(Parsed::Help),
            Long("lat") => lat = Some(cli::number(&mut p, "--lat")?),
            Long("lon") => lon = Some(cli::number(&mut p, "--lon")?),
            Long("postal-code") => postal_code = Some(cli::text(&mut p, "--postal-code")?),
            Long("date") => a.ymd = cli::date(&mut p, "--date")?,
            Long("interval-min") => {
                a.interval_min =
                    cli::value(&mut p, "--interval-min", "1..720 dividing 1440", |v| {
                        v.parse::<u16>()
                            .ok()
                            .filter(|n| (1..=720).contains(n) && 1440 % n == 0)
                    })?
            }
            Long("algorithm") => a.algorithm = cli::algorithm(&mut p, "--algorithm")?,
            Long("float") => {
                a.f32 = cli::choice(&mut p, "--float", &[("f32", true), ("f64", false)])?
            }
            Long("format") => {
                a.csv = cli::choice(&mut p, "--format", &[("table", false), ("csv", true)])?
            }
            Long("allow-out-of-range") => a.allow_out_of_range = true,
            other => return Err(cli::unexpected(other)),
        }
    }
    let kano = cli::NamedSite {
        lat_deg: KANO.0,
        lon_deg: KANO.1,
        place: "Kano".into(),
    };
    let site = cli::resolve_site(&cli::site_arg(lat, lon, postal_code)?, kano)?;
    a.lat_deg = site.lat_deg;
    a.lon_deg = site.lon_deg;
    a.place = site.place;
    if let Some(why) = outside_validity(&a) {
        if !a.allow_out_of_range {
            return Err(format!(
                "{why}; pick another --algorithm or pass --allow-out-of-range to compute anyway"
            ));
        }
    }
    Ok(Parsed::Run(a))
}

/// [`parse_cli`] for a run: `--help` is an error holding the help text.
#[allow(dead_code)] // the tests' entry (tests/daily_setpoints_cli.rs)
pub fn parse(args: &[String], today: (i32, u8, u8)) -> Result<Args, String> {
    match parse_cli(args, today)? {
        Parsed::Run(a) => Ok(a),
        Parsed::Help => Err(help().render()),
    }
}

/// Why the date is outside the algorithm's validity range, if it is.
pub fn outside_validity(a: &Args) -> Option<String> {
    let (y, m, d) = a.ymd;
    let (lo, hi) = a.algorithm.validity_years();
    (!(lo..=hi).contains(&y)).then(|| {
        format!(
            "date {y:04}-{m:02}-{d:02} is outside the validity range of algorithm {} \
             (years {lo} to {hi})",
            a.algorithm.name()
        )
    })
}

/// One printed row, degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    pub time: UtcTime,
    /// Local apparent solar time, seconds after solar midnight of the date.
    pub solar_s: i64,
    pub sun_zenith_deg: f64,
    pub sun_azimuth_deg: f64,
    pub slope_deg: f64,
    pub surface_azimuth_deg: f64,
    pub incidence_deg: f64,
}

/// The day's events and rows.
#[derive(Debug, Clone)]
pub struct Day {
    pub events: Events<f64>,
    pub rows: Vec<Row>,
}

/// Local apparent solar time of `t` at `lon_deg`: UTC + λ/15 + EoT, with
/// the equation of time of NREL SPA (eq. A.1), seconds of the day.
fn solar_seconds<T: Float>(t: &UtcTime, site: &Site<T>) -> Result<i64, String> {
    let eot_min = sun_algos::spa::equation_of_time_min(t, &Options::<T>::default())
        .map_err(|e| e.to_string())?;
    let s = f64::from(t.ms_of_day()) / 1000.0
        + site.longitude_deg().to_f64() * 240.0
        + eot_min.to_f64() * 60.0;
    Ok(s.round() as i64)
}

fn compute_in<T: Float>(a: &Args) -> Result<Day, String> {
    let site =
        Site::new(T::from_f64(a.lat_deg), T::from_f64(a.lon_deg)).map_err(|e| e.to_string())?;
    // The date itself was checked against the validity range in `parse`;
    // the day's instants may still spill into the neighbouring year.
    let geo = Options::<T> {
        allow_out_of_range: true,
        ..Options::default()
    };
    let apparent = Options::<T> {
        atmosphere: Some(Atmosphere::standard()),
        ..geo
    };
    let ev = if a.algorithm == Algorithm::Spa {
        events::spa(a.ymd, &site, &geo)
    } else {
        events::for_algorithm(a.algorithm, a.ymd, &site, &geo)
    }
    .map_err(|e| e.to_string())?;
    let table = DayTable::<{ capacity_for_interval(1) }>::compute(
        &ev,
        a.interval_min,
        &Limits::upward(),
        |t| a.algorithm.position(t, &site, &apparent),
    )
    .map_err(|e| e.to_string())?;
    let mut rows = Vec::with_capacity(table.len());
    for (t, entry) in table.iter() {
        let sun = a
            .algorithm
            .position(&t, &site, &apparent)
            .map_err(|e| e.to_string())?;
        let surface = entry.surface::<T>();
        rows.push(Row {
            time: t,
            solar_s: solar_seconds(&t, &site)?,
            sun_zenith_deg: sun.zenith_deg.to_f64(),
            sun_azimuth_deg: sun.azimuth_deg.to_f64(),
            slope_deg: surface.slope_deg.to_f64(),
            surface_azimuth_deg: surface.azimuth_deg.to_f64(),
            incidence_deg: incidence_deg(&sun, &surface).to_f64(),
        });
    }
    let events = Events {
        kind: ev.kind,
        window_start: ev.window_start,
        sunrise: ev.sunrise,
        transit: ev.transit,
        transit_zenith_deg: ev.transit_zenith_deg.to_f64(),
        sunset: ev.sunset,
        daylight_s: ev.daylight_s,
    };
    Ok(Day { events, rows })
}

/// Computes the day in the requested float type.
pub fn compute(a: &Args) -> Result<Day, String> {
    if a.f32 {
        compute_in::<f32>(a)
    } else {
        compute_in::<f64>(a)
    }
}

fn hms(s: i64) -> String {
    let s = s.rem_euclid(86_400);
    format!("{:02}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

fn utc_hms(t: &UtcTime) -> String {
    let (h, m, s, _) = t.hms_milli();
    format!("{h:02}:{m:02}:{s:02}")
}

/// Writes the day in the requested format.
pub fn write(a: &Args, day: &Day, out: &mut dyn Write) -> std::io::Result<()> {
    if a.csv {
        writeln!(out, "{CSV_HEADER}")?;
        for r in &day.rows {
            writeln!(
                out,
                "{},{},{:.4},{:.4},{:.2},{:.2},{:.4}",
                r.time,
                hms(r.solar_s),
                r.sun_zenith_deg,
                r.sun_azimuth_deg,
                r.slope_deg,
                r.surface_azimuth_deg,
                r.incidence_deg
            )?;
        }
        return Ok(());
    }
    let (y, m, d) = a.ymd;
    let ns = if a.lat_deg >= 0.0 { 'N' } else { 'S' };
    let ew = if a.lon_deg >= 0.0 { 'E' } else { 'W' };
    writeln!(
        out,
        "Set-points for {} ({:.4} {ns}, {:.4} {ew}) on {y:04}-{m:02}-{d:02}, algorithm {} ({}), every {} min",
        a.place,
        a.lat_deg.abs(),
        a.lon_deg.abs(),
        a.algorithm.name(),
        if a.f32 { "f32" } else { "f64" },
        a.interval_min
    )?;
    let ev = &day.events;
    let solar = |t: &UtcTime| {
        // Solar time of an event, for the header line.
        let site = Site::new(a.lat_deg, a.lon_deg).ok();
        site.and_then(|s| solar_seconds(t, &s).ok())
            .map(hms)
            .unwrap_or_default()
    };
    match ev.kind {
        DayKind::PolarNight => writeln!(out, "Polar night: the sun does not rise.")?,
        DayKind::PolarDay => writeln!(out, "Polar day: the sun does not set.")?,
        DayKind::Normal => {
            if let Some(r) = &ev.sunrise {
                writeln!(out, "Sunrise  {} UTC   {} solar", utc_hms(r), solar(r))?;
            }
            writeln!(
                out,
                "Transit  {} UTC   {} solar   zenith {:.2} deg",
                utc_hms(&ev.transit),
                solar(&ev.transit),
                ev.transit_zenith_deg
            )?;
            if let Some(s) = &ev.sunset {
                writeln!(out, "Sunset   {} UTC   {} solar", utc_hms(s), solar(s))?;
            }
        }
    }
    writeln!(
        out,
        "Daylight {} h {:02} min; {} set-points. Angles in degrees, azimuths east of north.",
        ev.daylight_s / 3600,
        ev.daylight_s / 60 % 60,
        day.rows.len()
    )?;
    if day.rows.is_empty() {
        return Ok(());
    }
    writeln!(out)?;
    writeln!(
        out,
        "{:>8}  {:>8}  {:>8}  {:>8}  {:>6}  {:>7}  {:>9}",
        "UTC", "solar", "zenith", "azimuth", "slope", "surf_az", "incidence"
    )?;
    for r in &day.rows {
        writeln!(
            out,
            "{:>8}  {:>8}  {:>8.3}  {:>8.3}  {:>6.2}  {:>7.2}  {:>9.3}",
            utc_hms(&r.time),
            hms(r.solar_s),
            r.sun_zenith_deg,
            r.sun_azimuth_deg,
            r.slope_deg,
            r.surface_azimuth_deg,
            r.incidence_deg
        )?;
    }
    Ok(())
}

/// Parse, compute and write the table (or the help) to `out` and warnings
/// to `warn`; the error is the message to print (exit 2).
pub fn run(
    args: &[String],
    today: (i32, u8, u8),
    out: &mut dyn Write,
    warn: &mut dyn Write,
) -> Result<(), String> {
    let a = match parse_cli(args, today)? {
        Parsed::Run(a) => a,
        Parsed::Help => {
            cli::print_help(&help(), out);
            return Ok(());
        }
    };
    if let Some(why) = outside_validity(&a) {
        // Best effort: a closed stderr must not stop the table.
        let _ = writeln!(
            warn,
            "warning: {why}; computed anyway (--allow-out-of-range), expect larger errors"
        );
    }
    let day = compute(&a)?;
    match write(&a, &day, out) {
        // A closed pipe (`| head`) is not an error of ours.
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.to_string()),
        _ => Ok(()),
    }
}
