//! SVG plots of the sun's path and the set-points.
//!
//! ```text
//! cargo run --example sun_path            # writes docs/sun_path_kano.svg and docs/psa_tianjin.svg
//! cargo run --example sun_path -- --lat 36.78 --lon 3.06 --date 2022-12-26 --out /tmp/alger.svg
//! ```
//! 1. Like seed jimoh-2019 Fig. 7: for Kano on 2018-10-19, the sun's
//!    elevation and azimuth (from south, west positive, the seed's
//!    convention) against local apparent solar time, the optimum slope β and
//!    the day table's set-points (every fourth 4-minute entry marked).
//! 2. Like seed li-2022 Fig. 9: the zenith angle in Tianjin (39.13 N,
//!    117.20 E) from 9:00 to 17:00 Beijing time by the original PSA (2001)
//!    and the modified PSA of li-2022, with NREL SPA as the reference and
//!    the differences to SPA in a second panel. The seed names no date; its
//!    declination 0.07016 rad (4.02°) is the sun's on about 31 March, so
//!    2021-03-31 is used.

use std::error::Error;

use plotters::prelude::*;
use sun_algos::geometry::day_table::{capacity_for_interval, DayTable};
use sun_algos::geometry::events;
use sun_algos::geometry::optimum::Limits;
use sun_algos::{Algorithm, Atmosphere, Options, Site, UtcTime};

struct Args {
    lat: f64,
    lon: f64,
    date: (i32, u8, u8),
    out: String,
    tianjin_out: Option<String>,
}

fn parse() -> Result<Args, String> {
    let mut a = Args {
        lat: 11.9683,
        lon: 8.4261,
        date: (2018, 10, 19),
        out: "docs/sun_path_kano.svg".into(),
        tianjin_out: Some("docs/psa_tianjin.svg".into()),
    };
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let mut it = argv.iter();
    while let Some(f) = it.next() {
        let v = it.next().ok_or_else(|| format!("{f} needs a value"))?;
        match f.as_str() {
            "--lat" => a.lat = v.parse().map_err(|_| "--lat: number")?,
            "--lon" => a.lon = v.parse().map_err(|_| "--lon: number")?,
            "--date" => {
                let t: UtcTime = format!("{v}T00:00:00Z")
                    .parse()
                    .map_err(|e| format!("--date: {e}"))?;
                a.date = t.ymd();
            }
            "--out" => {
                a.out = v.clone();
                a.tianjin_out = None;
            }
            _ => {
                return Err(
                    "usage: sun_path [--lat DEG --lon DEG] [--date YYYY-MM-DD] [--out FILE.svg]"
                        .into(),
                )
            }
        }
    }
    Ok(a)
}

/// Local apparent solar time in hours (SPA's equation of time).
fn solar_h(t: &UtcTime, lon: f64) -> f64 {
    let eot = sun_algos::spa::equation_of_time_min(t, &Options::<f64>::default()).unwrap_or(0.0);
    let h = f64::from(t.ms_of_day()) / 3.6e6 + lon / 15.0 + eot / 60.0;
    h.rem_euclid(24.0)
}

fn sun_path(a: &Args) -> Result<(), Box<dyn Error>> {
    let site = Site::new(a.lat, a.lon).map_err(|e| e.to_string())?;
    let apparent = Options {
        atmosphere: Some(Atmosphere::standard()),
        ..Options::default()
    };
    let ev = events::spa(a.date, &site, &Options::default()).map_err(|e| format!("{e}"))?;
    let table = DayTable::<{ capacity_for_interval(4) }>::compute(&ev, 4, &Limits::upward(), |t| {
        Algorithm::Spa.position(t, &site, &apparent)
    })
    .map_err(|e| format!("{e}"))?;
    // The sun every 2 minutes over the whole day (elevation may be < 0).
    let start =
        UtcTime::from_ymd_hms(a.date.0, a.date.1, a.date.2, 0, 0, 0).map_err(|e| e.to_string())?;
    let mut elev = Vec::new();
    let mut azim = Vec::new();
    for k in 0..720 {
        let t = start.add_seconds(k * 120).map_err(|e| e.to_string())?;
        let p = Algorithm::Spa
            .position(&t, &site, &apparent)
            .map_err(|e| e.to_string())?;
        let x = solar_h(&t, a.lon);
        if p.elevation_deg() > -5.0 {
            elev.push((x, p.elevation_deg()));
            azim.push((x, p.azimuth_from_south_deg()));
        }
    }
    elev.sort_by(|p, q| p.0.total_cmp(&q.0));
    azim.sort_by(|p, q| p.0.total_cmp(&q.0));
    let mut slope = Vec::new();
    let mut marks = Vec::new();
    for (i, (t, e)) in table.iter().enumerate() {
        let s = e.surface::<f64>();
        let x = solar_h(&t, a.lon);
        slope.push((x, s.slope_deg));
        if i % 4 == 0 {
            marks.push((x, s.slope_deg, s.azimuth_from_south_deg()));
        }
    }
    let (x0, x1) = match (elev.first(), elev.last()) {
        (Some(f), Some(l)) => (f.0.floor(), l.0.ceil()),
        _ => (0.0, 24.0),
    };

    let root = SVGBackend::new(&a.out, (960, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let (y, m, d) = a.date;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "Sun path and set-points, {:.4} N {:.4} E, {y:04}-{m:02}-{d:02} (NREL SPA, 4-min table)",
                a.lat, a.lon
            ),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(x0..x1, -100f64..125f64)?;
    chart
        .configure_mesh()
        .x_desc("local apparent solar time (h)")
        .y_desc("degrees")
        .draw()?;
    chart
        .draw_series(LineSeries::new(elev, RED.stroke_width(2)))?
        .label("sun elevation")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
    chart
        .draw_series(LineSeries::new(azim, BLUE.stroke_width(2)))?
        .label("sun azimuth from south (west +)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
    chart
        .draw_series(LineSeries::new(slope, GREEN.stroke_width(2)))?
        .label("set-point slope beta")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], GREEN));
    chart.draw_series(
        marks
            .iter()
            .map(|&(x, b, _)| Circle::new((x, b), 3, GREEN.filled())),
    )?;
    chart
        .draw_series(
            marks
                .iter()
                .map(|&(x, _, g)| Circle::new((x, g), 3, BLACK.filled())),
        )?
        .label("set-point surface azimuth gamma (every 16 min)")
        .legend(|(x, y)| Circle::new((x + 10, y), 3, BLACK.filled()));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

fn tianjin(out: &str) -> Result<(), Box<dyn Error>> {
    let site = Site::new(39.13f64, 117.20).map_err(|e| e.to_string())?;
    let opts = Options::default();
    let mut series: Vec<(Algorithm, Vec<(f64, f64)>)> = vec![
        (Algorithm::Psa2001, Vec::new()),
        (Algorithm::PsaModified, Vec::new()),
        (Algorithm::Spa, Vec::new()),
    ];
    // 9:00–17:00 Beijing time (UTC+8) = 01:00–09:00 UTC.
    let start = UtcTime::from_ymd_hms(2021, 3, 31, 1, 0, 0).map_err(|e| e.to_string())?;
    for k in 0..=96 {
        let t = start.add_seconds(k * 300).map_err(|e| e.to_string())?;
        let x = 9.0 + f64::from(k as u32) * 300.0 / 3600.0;
        for (alg, pts) in series.iter_mut() {
            pts.push((
                x,
                alg.position(&t, &site, &opts)
                    .map_err(|e| e.to_string())?
                    .zenith_deg,
            ));
        }
    }
    let spa: Vec<(f64, f64)> = series.get(2).map(|s| s.1.clone()).unwrap_or_default();
    let diff = |pts: &[(f64, f64)]| -> Vec<(f64, f64)> {
        pts.iter()
            .zip(&spa)
            .map(|(p, s)| (p.0, (p.1 - s.1) * 3600.0))
            .collect()
    };
    let root = SVGBackend::new(out, (960, 720)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, bottom) = root.split_vertically(440);
    let mut c = ChartBuilder::on(&top)
        .caption(
            "Zenith angle, Tianjin (39.13 N, 117.20 E), 2021-03-31, Beijing time",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(50)
        .build_cartesian_2d(9f64..17f64, 35f64..90f64)?;
    c.configure_mesh()
        .x_desc("hour (UTC+8)")
        .y_desc("zenith (deg)")
        .draw()?;
    let colours = [BLUE, RED, BLACK];
    let names = [
        "PSA original (2001)",
        "PSA modified (li-2022)",
        "NREL SPA (reference)",
    ];
    for ((_, pts), (col, name)) in series.iter().zip(colours.iter().zip(names)) {
        let col = *col;
        c.draw_series(LineSeries::new(pts.clone(), col.stroke_width(2)))?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col));
    }
    c.configure_series_labels()
        .position(SeriesLabelPosition::UpperMiddle)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    let d0 = series.first().map(|s| diff(&s.1)).unwrap_or_default();
    let d1 = series.get(1).map(|s| diff(&s.1)).unwrap_or_default();
    let lim = d0.iter().chain(&d1).fold(10.0f64, |m, p| m.max(p.1.abs())) * 1.2;
    let mut c2 = ChartBuilder::on(&bottom)
        .caption("difference to SPA (arcseconds)", ("sans-serif", 16))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(50)
        .build_cartesian_2d(9f64..17f64, -lim..lim)?;
    c2.configure_mesh()
        .x_desc("hour (UTC+8)")
        .y_desc("arcsec")
        .draw()?;
    c2.draw_series(LineSeries::new(d0, BLUE.stroke_width(2)))?
        .label("PSA 2001 - SPA")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
    c2.draw_series(LineSeries::new(d1, RED.stroke_width(2)))?
        .label("PSA modified - SPA")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
    c2.configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

fn main() -> Result<(), Box<dyn Error>> {
    let a = parse()?;
    if let Some(dir) = std::path::Path::new(&a.out).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)?;
        }
    }
    sun_path(&a)?;
    println!("wrote {}", a.out);
    if let Some(t) = &a.tianjin_out {
        tianjin(t)?;
        println!("wrote {t}");
    }
    Ok(())
}
