//! SVG plots of the sun's path and the set-points.
//!
//! ```text
//! cargo run --example sun_path            # writes docs/src/figures/sun_path_kano.svg and docs/src/figures/psa_tianjin.svg
//! cargo run --example sun_path -- --lat 52.52 --lon 13.40 --date 2026-06-21 --out /tmp/berlin.svg
//! ```
//! 1. Like Jimoh & Aliyu 2019 Fig. 7: for a site and day (default Kano,
//!    2018-10-19), the sun's elevation and azimuth against local apparent
//!    solar time, the optimum slope β and the surface azimuth γ of the day
//!    table's set-points (4-minute entries; every fourth one marked).
//!    Azimuths are measured from the equator side, west positive: from
//!    south (Jimoh & Aliyu's convention) north of the equator, from north south
//!    of it, so that the curve rises through the day in both hemispheres; a
//!    curve is broken where it wraps through ±180° (a tropical sun passing
//!    the pole side of the zenith, the midnight sun). Both axes are scaled
//!    from the plotted points ([`axis_ranges`]), for any site: polar day
//!    (24 h of set-points), polar night (the sun below the horizon, no
//!    set-points) and both hemispheres.
//! 2. Like Li et al. 2022 Fig. 9: the zenith angle in Tianjin (39.13 N,
//!    117.20 E) from 9:00 to 17:00 Beijing time by the original PSA (2001)
//!    and the modified PSA of Li et al., with NREL SPA as the reference and
//!    the differences to SPA in a second panel. Li et al. name no date; their
//!    declination 0.07016 rad (4.02°) is the sun's on about 31 March, so
//!    2021-03-31 is used. Written only when `--out` is not given.
//!
//! Curves are drawn on a 4× canvas shown at the picture's size
//! (`examples/common/plot.rs`), so they are smooth, and the legend, below
//! the plot, names every series.

use std::error::Error;
use std::io::Write;
use std::process::ExitCode;

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use sun_algos::geometry::day_table::{capacity_for_interval, DayTable};
use sun_algos::geometry::events::{self, DayKind};
use sun_algos::geometry::optimum::Limits;
use sun_algos::{Algorithm, Atmosphere, Options, Site, UtcTime};

#[path = "common/cli.rs"]
mod cli;
#[path = "common/plot.rs"]
mod plot;

use cli::Parsed;
use plot::{font, px, stroke, Swatch};

/// The program name in messages.
pub const TOOL: &str = "sun_path";

/// Default site and day: Kano on Jimoh & Aliyu's (2019) example day.
const KANO: (f64, f64) = (11.9683, 8.4261);
const KANO_DATE: (i32, u8, u8) = (2018, 10, 19);
const DEFAULT_OUT: &str = "docs/src/figures/sun_path_kano.svg";
const DEFAULT_TIANJIN_OUT: &str = "docs/src/figures/psa_tianjin.svg";

/// Minutes between set-points of the plotted day table.
const TABLE_MIN: u16 = 4;
/// Every this many table entries is marked with a dot.
const MARK_EVERY: usize = 4;
/// Seconds between samples of the sun's curves.
const SAMPLE_S: i64 = 120;
/// The sun's curves are drawn while its elevation is above this (deg).
const ELEVATION_FLOOR_DEG: f64 = -5.0;
/// Space kept between the plotted points and the frame (deg).
const Y_PAD_DEG: f64 = 4.0;
/// The y axis ends on multiples of this (deg).
const Y_STEP_DEG: f64 = 10.0;

/// Parsed command line.
#[derive(Debug, Clone, PartialEq)]
pub struct Args {
    pub lat: f64,
    pub lon: f64,
    pub date: (i32, u8, u8),
    pub out: String,
    /// Where the Tianjin figure goes; `None` with `--out`.
    pub tianjin_out: Option<String>,
}

/// The text of `--help`.
pub fn help() -> cli::Help {
    use cli::opt;
    cli::Help {
        tool: TOOL,
        synopsis: "[--lat DEG --lon DEG] [--date YYYY-MM-DD] [--out FILE.svg]",
        about: "\
Draws the sun's elevation and azimuth over a day against local apparent solar time with the
set-points of the day's table (slope and surface azimuth every 4 min, NREL SPA, apparent
positions), after Jimoh & Aliyu 2019 Fig. 7; without --out also the PSA comparison in Tianjin
after Li et al. 2022 Fig. 9. Azimuths are from the equator side (south in the northern
hemisphere, north in the southern), west positive.",
        options: vec![
            opt(
                "--lat DEG",
                "site latitude, degrees north (south negative)",
                "11.9683 (Kano)",
            ),
            opt(
                "--lon DEG",
                "site longitude, degrees east (west negative)",
                "8.4261 (Kano)",
            ),
            opt(
                "--date YYYY-MM-DD",
                "the day (local solar day)",
                "2018-10-19",
            ),
            opt(
                "--out FILE.svg",
                "write the sun path there and skip the Tianjin figure",
                "docs/src/figures/sun_path_kano.svg, and docs/src/figures/psa_tianjin.svg",
            ),
        ],
        algorithms: false,
        notes: "Directories of the output files are created. Prints `wrote FILE` for each figure.",
    }
}

/// Parses the arguments (without the program name).
pub fn parse(argv: &[String]) -> Result<Parsed<Args>, String> {
    use cli::{Long, Short};
    let mut a = Args {
        lat: KANO.0,
        lon: KANO.1,
        date: KANO_DATE,
        out: DEFAULT_OUT.into(),
        tianjin_out: Some(DEFAULT_TIANJIN_OUT.into()),
    };
    let mut p = cli::parser(argv);
    while let Some(arg) = p.next().map_err(cli::error)? {
        match arg {
            Short('h') | Long("help") => return Ok(Parsed::Help),
            Long("lat") => a.lat = cli::number(&mut p, "--lat")?,
            Long("lon") => a.lon = cli::number(&mut p, "--lon")?,
            Long("date") => a.date = cli::date(&mut p, "--date")?,
            Long("out") => {
                a.out = cli::text(&mut p, "--out")?;
                a.tianjin_out = None;
            }
            other => return Err(cli::unexpected(other)),
        }
    }
    Site::new(a.lat, a.lon).map_err(|e| format!("site: {e}"))?;
    Ok(Parsed::Run(a))
}

/// Which way azimuths are measured from (west positive either way).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reference {
    /// From south: sites on or north of the equator.
    South,
    /// From north: sites south of the equator.
    North,
}

impl Reference {
    /// The equator side of latitude `lat_deg`.
    pub fn for_latitude(lat_deg: f64) -> Self {
        if lat_deg >= 0.0 {
            Reference::South
        } else {
            Reference::North
        }
    }

    /// `azimuth_deg` (east of north) measured from this reference, west
    /// positive, in (−180°, 180°].
    pub fn azimuth(self, azimuth_deg: f64) -> f64 {
        let from = match self {
            // South = 0, west = +90: az − 180.
            Reference::South => azimuth_deg - 180.0,
            // North = 0, west = +90: −az.
            Reference::North => -azimuth_deg,
        };
        let a = from.rem_euclid(360.0);
        if a > 180.0 {
            a - 360.0
        } else {
            a
        }
    }

    fn name(self) -> &'static str {
        match self {
            Reference::South => "south",
            Reference::North => "north",
        }
    }
}

/// Everything the sun-path figure plots; x is local apparent solar time in
/// hours, y degrees.
#[derive(Debug, Clone)]
pub struct SunPath {
    pub lat: f64,
    pub lon: f64,
    pub date: (i32, u8, u8),
    pub kind: DayKind,
    pub reference: Reference,
    /// The sun's elevation, every 2 minutes while above −5° (the whole day
    /// when it never gets there).
    pub elevation: Vec<(f64, f64)>,
    /// The sun's azimuth over the same instants, one polyline per stretch
    /// without a wrap through ±180°.
    pub azimuth: Vec<Vec<(f64, f64)>>,
    /// The set-point slope β of every table entry.
    pub slope: Vec<(f64, f64)>,
    /// Every fourth entry's slope, marked.
    pub slope_marks: Vec<(f64, f64)>,
    /// Every fourth entry's surface azimuth γ, marked.
    pub gamma_marks: Vec<(f64, f64)>,
}

impl SunPath {
    /// Every plotted point.
    pub fn points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.elevation
            .iter()
            .chain(self.azimuth.iter().flatten())
            .chain(&self.slope)
            .chain(&self.slope_marks)
            .chain(&self.gamma_marks)
            .copied()
    }
}

/// Local apparent solar time of `t` at `lon` (hours, SPA's equation of
/// time), on the same clock as `near`: the value ± 24 h closest to it.
fn solar_h(t: &UtcTime, lon: f64, near: f64) -> f64 {
    let eot = sun_algos::spa::equation_of_time_min(t, &Options::<f64>::default()).unwrap_or(0.0);
    let h = f64::from(t.ms_of_day()) / 3.6e6 + lon / 15.0 + eot / 60.0;
    h + ((near - h) / 24.0).round() * 24.0
}

/// Splits a polyline where it jumps by more than 180° (a wrap of an angle).
fn split_at_wraps(points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut prev: Option<f64> = None;
    for &p in points {
        match (prev, out.last_mut()) {
            (Some(q), Some(seg)) if (p.1 - q).abs() <= 180.0 => seg.push(p),
            _ => out.push(vec![p]),
        }
        prev = Some(p.1);
    }
    out
}

/// Computes the sun-path figure's series for a site and local solar day.
pub fn sun_path_data(lat: f64, lon: f64, date: (i32, u8, u8)) -> Result<SunPath, String> {
    let site = Site::new(lat, lon).map_err(|e| format!("site: {e}"))?;
    let apparent = Options {
        atmosphere: Some(Atmosphere::standard()),
        ..Options::default()
    };
    // The local solar day (from mean solar midnight), the same window for
    // the curves and the table.
    let ev = events::for_algorithm(Algorithm::Spa, date, &site, &Options::default())
        .map_err(|e| e.to_string())?;
    let table = DayTable::<{ capacity_for_interval(TABLE_MIN) }>::compute(
        &ev,
        TABLE_MIN,
        &Limits::upward(),
        |t| Algorithm::Spa.position(t, &site, &apparent),
    )
    .map_err(|e| e.to_string())?;
    let start = ev.window_start;
    let reference = Reference::for_latitude(lat);
    // Solar time at the window start (near 0 h), then each instant on the
    // clock that follows from it.
    let x0 = solar_h(&start, lon, 0.0);
    let x_of = |t: &UtcTime| {
        solar_h(
            t,
            lon,
            x0 + (t.unix_seconds() - start.unix_seconds()) as f64 / 3600.0,
        )
    };
    let mut samples = Vec::new();
    for k in 0..=(86_400 / SAMPLE_S) {
        let t = start.add_seconds(k * SAMPLE_S).map_err(|e| e.to_string())?;
        let p = Algorithm::Spa
            .position(&t, &site, &apparent)
            .map_err(|e| e.to_string())?;
        samples.push((
            x_of(&t),
            p.elevation_deg(),
            reference.azimuth(p.azimuth_deg),
        ));
    }
    let up: Vec<_> = samples
        .iter()
        .filter(|s| s.1 > ELEVATION_FLOOR_DEG)
        .copied()
        .collect();
    // A sun that never gets to the floor: its whole day.
    let shown = if up.len() >= 2 { up } else { samples };
    let elevation = shown.iter().map(|s| (s.0, s.1)).collect();
    // One curve per stretch above the floor, broken at ±180°.
    let mut azimuth = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    for w in shown.windows(2) {
        run.push((w[0].0, w[0].2));
        if w[1].0 - w[0].0 > 1.5 * SAMPLE_S as f64 / 3600.0 {
            azimuth.extend(split_at_wraps(&run));
            run.clear();
        }
    }
    if let Some(last) = shown.last() {
        run.push((last.0, last.2));
    }
    azimuth.extend(split_at_wraps(&run));
    let mut slope = Vec::new();
    let mut slope_marks = Vec::new();
    let mut gamma_marks = Vec::new();
    for (i, (t, e)) in table.iter().enumerate() {
        let s = e.surface::<f64>();
        let x = x_of(&t);
        slope.push((x, s.slope_deg));
        if i % MARK_EVERY == 0 {
            slope_marks.push((x, s.slope_deg));
            gamma_marks.push((x, reference.azimuth(s.azimuth_deg)));
        }
    }
    Ok(SunPath {
        lat,
        lon,
        date,
        kind: ev.kind,
        reference,
        elevation,
        azimuth,
        slope,
        slope_marks,
        gamma_marks,
    })
}

/// The ranges of the axes of a figure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ranges {
    /// Solar time, whole hours around the plotted points.
    pub x: (f64, f64),
    /// Degrees, multiples of 10 at least 4° beyond the plotted points.
    pub y: (f64, f64),
}

/// The axes of the sun-path figure: every plotted point inside, with some
/// room in y.
pub fn axis_ranges(data: &SunPath) -> Ranges {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (x, y) in data.points() {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    Ranges {
        x: plot::padded_range(x0, x1, 0.0, 1.0),
        y: plot::padded_range(y0, y1, Y_PAD_DEG, Y_STEP_DEG),
    }
}

const ELEVATION: RGBColor = RGBColor(0xd6, 0x27, 0x28);
const AZIMUTH: RGBColor = RGBColor(0x1f, 0x4e, 0xc8);
const SLOPE: RGBColor = RGBColor(0x1a, 0x9a, 0x3a);
const GAMMA: RGBColor = BLACK;

/// The legend entries of the sun-path figure: one for every drawn series.
fn sun_path_legend(d: &SunPath) -> Vec<(Swatch, String)> {
    let r = d.reference.name();
    let mut v = vec![
        (Swatch::Line(ELEVATION, 2), "sun elevation".to_string()),
        (
            Swatch::Line(AZIMUTH, 2),
            format!("sun azimuth from {r} (west +)"),
        ),
    ];
    if !d.slope.is_empty() {
        v.push((
            Swatch::LineDots(SLOPE, 2, 3),
            format!(
                "set-point slope \u{3b2} (every {TABLE_MIN} min, dots every {} min)",
                usize::from(TABLE_MIN) * MARK_EVERY
            ),
        ));
        v.push((
            Swatch::Dot(GAMMA, 3),
            format!(
                "set-point surface azimuth \u{3b3} from {r} (every {} min)",
                usize::from(TABLE_MIN) * MARK_EVERY
            ),
        ));
    }
    v
}

/// Draws the axes, grid and labels of a chart: `x_labels` and `y_labels`
/// labels (whole numbers) along each axis.
fn mesh(
    c: &mut ChartContext<'_, SVGBackend<'_>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    x_desc: &str,
    y_desc: &str,
    x_labels: usize,
    y_labels: usize,
) -> Result<(), Box<dyn Error>> {
    c.configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(x_labels)
        .y_labels(y_labels)
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0}"))
        .label_style(font(12))
        .axis_desc_style(font(13))
        .axis_style(stroke(BLACK, 1))
        .bold_line_style(BLACK.mix(0.18).stroke_width(px(1)))
        .light_line_style(BLACK.mix(0.06).stroke_width(px(1)))
        .max_light_lines(1)
        .set_all_tick_mark_size(px(4))
        .draw()?;
    Ok(())
}

/// Draws the sun-path figure; returns the SVG.
pub fn sun_path_svg(d: &SunPath) -> Result<String, Box<dyn Error>> {
    let r = axis_ranges(d);
    let entries = sun_path_legend(d);
    let (w, h) = (960, 620);
    plot::render((w, h), |root| {
        let (y, m, dd) = d.date;
        let ns = if d.lat >= 0.0 { 'N' } else { 'S' };
        let ew = if d.lon >= 0.0 { 'E' } else { 'W' };
        let (what, kind) = match d.kind {
            DayKind::Normal => ("Sun path and set-points", String::new()),
            DayKind::PolarDay => ("Sun path and set-points", ", polar day".into()),
            DayKind::PolarNight => ("Sun path", ": polar night, no set-points".into()),
        };
        let table = if d.slope.is_empty() {
            String::new()
        } else {
            format!(", {TABLE_MIN}-min table")
        };
        let title = format!(
            "{what}, {:.4} {ns} {:.4} {ew}, {y:04}-{m:02}-{dd:02}{kind} (NREL SPA{table})",
            d.lat.abs(),
            d.lon.abs()
        );
        let legend_h = plot::legend_height(entries.len(), 2);
        let (upper, lower) = root.split_vertically(px(h - legend_h - 8));
        let mut chart = ChartBuilder::on(&upper)
            .caption(title, font(19))
            .margin(px(12))
            .x_label_area_size(px(40))
            .y_label_area_size(px(52))
            .build_cartesian_2d(r.x.0..r.x.1, r.y.0..r.y.1)?;
        mesh(
            &mut chart,
            "local apparent solar time (h)",
            "degrees",
            ((r.x.1 - r.x.0) as usize).min(24) + 1,
            // Every 10° up to 12 labels, then plotters' next round step.
            (((r.y.1 - r.y.0) / Y_STEP_DEG) as usize + 1).min(13),
        )?;
        chart.draw_series(LineSeries::new(d.elevation.clone(), stroke(ELEVATION, 2)))?;
        for seg in &d.azimuth {
            chart.draw_series(LineSeries::new(seg.clone(), stroke(AZIMUTH, 2)))?;
        }
        chart.draw_series(LineSeries::new(d.slope.clone(), stroke(SLOPE, 2)))?;
        chart.draw_series(
            d.slope_marks
                .iter()
                .map(|&p| Circle::new(p, px(3), SLOPE.filled())),
        )?;
        chart.draw_series(
            d.gamma_marks
                .iter()
                .map(|&p| Circle::new(p, px(3), GAMMA.filled())),
        )?;
        plot::legend(&lower.margin(0, px(4), px(60), px(12)), &entries, 2)?;
        Ok(())
    })
}

/// The Tianjin comparison figure; returns the SVG.
pub fn tianjin_svg() -> Result<String, Box<dyn Error>> {
    let site = Site::new(39.13f64, 117.20).map_err(|e| e.to_string())?;
    let opts = Options::default();
    let algorithms = [Algorithm::Psa2001, Algorithm::PsaModified, Algorithm::Spa];
    let mut series: Vec<Vec<(f64, f64)>> = vec![Vec::new(); 3];
    // 9:00–17:00 Beijing time (UTC+8) = 01:00–09:00 UTC.
    let start = UtcTime::from_ymd_hms(2021, 3, 31, 1, 0, 0).map_err(|e| e.to_string())?;
    for k in 0..=96 {
        let t = start.add_seconds(k * 300).map_err(|e| e.to_string())?;
        let x = 9.0 + f64::from(k as u32) * 300.0 / 3600.0;
        for (alg, pts) in algorithms.iter().zip(series.iter_mut()) {
            pts.push((
                x,
                alg.position(&t, &site, &opts)
                    .map_err(|e| e.to_string())?
                    .zenith_deg,
            ));
        }
    }
    let diff = |pts: &[(f64, f64)]| -> Vec<(f64, f64)> {
        pts.iter()
            .zip(&series[2])
            .map(|(p, s)| (p.0, (p.1 - s.1) * 3600.0))
            .collect()
    };
    let diffs = [diff(&series[0]), diff(&series[1])];
    let colours = [AZIMUTH, ELEVATION, BLACK];
    let names = [
        "PSA original (2001)",
        "PSA modified (li-2022)",
        "NREL SPA (reference; curves overlap)",
    ];
    let diff_names = ["PSA 2001 \u{2212} SPA", "PSA modified \u{2212} SPA"];
    let (z0, z1) = series
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    let zr = plot::padded_range(z0, z1, 2.0, 5.0);
    let (d0, d1) = diffs
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    // Zero inside, room around the curves.
    let dr = plot::padded_range(d0.min(0.0), d1.max(0.0), 1.0, 2.0);
    plot::render((960, 760), |root| {
        let (top, bottom) = root.split_vertically(px(470));
        let (top, top_legend) = top.split_vertically(px(470 - plot::legend_height(3, 3) - 6));
        let (bottom, bottom_legend) =
            bottom.split_vertically(px(290 - plot::legend_height(2, 3) - 6));
        let mut c = ChartBuilder::on(&top)
            .caption(
                "Zenith angle, Tianjin (39.13 N, 117.20 E), 2021-03-31, Beijing time",
                font(19),
            )
            .margin(px(12))
            .x_label_area_size(px(35))
            .y_label_area_size(px(52))
            .build_cartesian_2d(9f64..17f64, zr.0..zr.1)?;
        mesh(
            &mut c,
            "hour (UTC+8)",
            "zenith (deg)",
            9,
            ((zr.1 - zr.0) / 5.0) as usize + 1,
        )?;
        for (pts, col) in series.iter().zip(colours) {
            c.draw_series(LineSeries::new(pts.clone(), stroke(col, 2)))?;
        }
        let entries: Vec<(Swatch, String)> = colours
            .iter()
            .zip(names)
            .map(|(c, n)| (Swatch::Line(*c, 2), n.to_string()))
            .collect();
        plot::legend(&top_legend.margin(0, 0, px(64), px(12)), &entries, 3)?;
        let mut c2 = ChartBuilder::on(&bottom)
            .caption("difference to SPA (arcseconds)", font(16))
            .margin(px(12))
            .x_label_area_size(px(35))
            .y_label_area_size(px(52))
            .build_cartesian_2d(9f64..17f64, dr.0..dr.1)?;
        mesh(
            &mut c2,
            "hour (UTC+8)",
            "arcsec",
            9,
            ((dr.1 - dr.0) / 2.0) as usize + 1,
        )?;
        for (pts, col) in diffs.iter().zip(colours) {
            c2.draw_series(LineSeries::new(pts.clone(), stroke(col, 2)))?;
        }
        let entries: Vec<(Swatch, String)> = colours
            .iter()
            .zip(diff_names)
            .map(|(c, n)| (Swatch::Line(*c, 2), n.to_string()))
            .collect();
        plot::legend(&bottom_legend.margin(0, 0, px(64), px(12)), &entries, 3)?;
        Ok(())
    })
}

/// Runs the tool with `argv` (without the program name). Returns the exit
/// code: 0, 2 for a usage error, 1 when a figure cannot be made or written.
pub fn run(argv: &[String], out: &mut dyn Write, err: &mut dyn Write) -> u8 {
    let a = match parse(argv) {
        Ok(Parsed::Run(a)) => a,
        Ok(Parsed::Help) => return cli::print_help(&help(), out),
        Err(e) => return cli::usage_error(TOOL, &e, err),
    };
    let mut figures = || -> Result<(), Box<dyn Error>> {
        let d = sun_path_data(a.lat, a.lon, a.date)?;
        plot::write(&a.out, &sun_path_svg(&d)?)?;
        writeln!(out, "wrote {}", a.out)?;
        if let Some(t) = &a.tianjin_out {
            plot::write(t, &tianjin_svg()?)?;
            writeln!(out, "wrote {t}")?;
        }
        Ok(())
    };
    match figures() {
        Ok(()) => 0,
        Err(e) => {
            let _ = writeln!(err, "{TOOL}: {e}");
            1
        }
    }
}

#[allow(dead_code)] // a module of tests/host_tools_cli.rs too
fn main() -> ExitCode {
    cli::main(TOOL, run)
}
