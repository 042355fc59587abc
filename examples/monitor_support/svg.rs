//! `monitor --svg`: the log as a picture over the board's UTC time. Panels,
//! top down: the sun's elevation (90° − the logged zenith) and azimuth
//! with the commanded axis angles c and a of every set-point (from a
//! `--modbus` session: the target's elevation and azimuth, and where the
//! panel points, 601's `ElPos`/`AzPos`, at every poll); the panel
//! voltage when the set-points carry one; the mode in force (a band); one
//! row per fault (a bar while active, a dot where it was raised). Both axes
//! of the top panel are scaled from the data; the legend names every
//! series, every mode that occurs and the fault marks. A curve is broken
//! where set-points stop for longer than [`gap_s`] (night, a stow, a
//! reboot) or where the board's time goes back.

use std::error::Error;

use plotters::prelude::*;
use sun_algos::UtcTime;

use super::board_log::{Change, Monitor};

#[path = "../common/plot.rs"]
mod plot;
#[path = "../common/timeline.rs"]
mod timeline;

use plot::{font, px, stroke, Swatch};
use timeline::{FAULT, MODE_COLOURS};

/// A mode name the table does not know (a newer image).
const OTHER_MODE: RGBColor = RGBColor(0xbd, 0xbd, 0xbd);

const ELEVATION: RGBColor = RGBColor(0xd6, 0x27, 0x28);
const AZIMUTH: RGBColor = RGBColor(0x1f, 0x4e, 0xc8);
const AXIS_C: RGBColor = RGBColor(0x1a, 0x9a, 0x3a);
const AXIS_A: RGBColor = RGBColor(0x6a, 0x1b, 0x9a);
const PANEL: RGBColor = RGBColor(0xe6, 0x7e, 0x22);
const BOOT: RGBColor = RGBColor(0x75, 0x75, 0x75);

/// Space kept between the plotted points and the frame (deg).
const Y_PAD_DEG: f64 = 4.0;
/// The degree axis ends on multiples of this (deg).
const Y_STEP_DEG: f64 = 10.0;
/// Width of the plots, picture pixels (for the smallest bar width).
const PLOT_W: f64 = 780.0;

fn mode_colour(name: &str) -> RGBColor {
    MODE_COLOURS
        .iter()
        .find(|m| m.0 == name)
        .map_or(OTHER_MODE, |m| m.1)
}

/// Polylines.
type Curves = Vec<Vec<(f64, f64)>>;

/// One fault's row: name, active spans (hours), raise times (hours).
pub type FaultRow = (String, Vec<(f64, f64)>, Vec<f64>);

/// What the figure plots; x in hours since 00:00 UTC of the first day.
#[derive(Debug, Clone, Default)]
pub struct Day {
    /// Midnight UTC before the first time in the log (Unix seconds).
    pub day0_s: i64,
    /// First and last time in the log, hours.
    pub span_h: (f64, f64),
    pub elevation: Curves,
    pub azimuth: Curves,
    pub c: Curves,
    pub a: Curves,
    /// Where the panel points (a `--modbus` session's `ElPos`, `AzPos`).
    pub el: Curves,
    pub az: Curves,
    /// Panel voltage (V), when the set-points carry one.
    pub panel_v: Curves,
    /// Mode bands: from, to (hours), mode.
    pub modes: Vec<(f64, f64, String)>,
    /// Faults by first raise.
    pub faults: Vec<FaultRow>,
    /// Boots after the first line with a time (hours).
    pub boots: Vec<f64>,
    pub setpoints: usize,
}

impl Day {
    /// Every curve in degrees.
    fn degree_curves(&self) -> impl Iterator<Item = &Vec<(f64, f64)>> {
        self.elevation
            .iter()
            .chain(&self.azimuth)
            .chain(&self.c)
            .chain(&self.a)
            .chain(&self.el)
            .chain(&self.az)
    }
}

/// The longest pause between set-points that a curve bridges: three times
/// the usual spacing (the median), at least 10 minutes.
pub fn gap_s(times: &[i64]) -> i64 {
    let mut steps: Vec<i64> = times
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0)
        .collect();
    steps.sort_unstable();
    let median = steps.get(steps.len() / 2).copied().unwrap_or(0);
    (3 * median).max(600)
}

/// `points` (time, value) as polylines, broken at gaps and where time goes
/// back; NaN values are left out and break the curve too.
fn curves(points: &[(i64, f64)], gap: i64, x: impl Fn(i64) -> f64) -> Curves {
    let mut out: Curves = Vec::new();
    let mut last: Option<i64> = None;
    for &(t, v) in points {
        if !v.is_finite() {
            last = None;
            continue;
        }
        let joined = last.is_some_and(|l| t >= l && t - l <= gap);
        match out.last_mut() {
            Some(c) if joined => c.push((x(t), v)),
            _ => out.push(vec![(x(t), v)]),
        }
        last = Some(t);
    }
    out
}

/// The figure's data from a monitored log; `None` when no line of the log
/// carries a time.
pub fn day(m: &Monitor) -> Option<Day> {
    let first = m.first_time_s()?;
    let last = m
        .events
        .iter()
        .filter_map(|e| e.unix_s)
        .chain(m.rows.iter().map(|r| r.setpoint.utc.unix_s))
        .chain(m.now_s)
        .max()
        .unwrap_or(first);
    let day0_s = first.div_euclid(86_400) * 86_400;
    let x = |t: i64| (t - day0_s) as f64 / 3600.0;
    let times: Vec<i64> = m.rows.iter().map(|r| r.setpoint.utc.unix_s).collect();
    let gap = gap_s(&times);
    let series = |f: &dyn Fn(&super::board_log::Row) -> Option<f64>| -> Curves {
        let pts: Vec<(i64, f64)> = m
            .rows
            .iter()
            .filter_map(|r| f(r).map(|v| (r.setpoint.utc.unix_s, v)))
            .collect();
        curves(&pts, gap, x)
    };
    let mut d = Day {
        day0_s,
        span_h: (x(first), x(last)),
        elevation: series(&|r| Some(90.0 - r.setpoint.zenith_deg.value)),
        azimuth: series(&|r| Some(r.setpoint.azimuth_deg.value)),
        c: series(&|r| r.setpoint.c_deg.as_ref().map(|n| n.value)),
        a: series(&|r| r.setpoint.a_deg.as_ref().map(|n| n.value)),
        el: series(&|r| r.setpoint.position_deg.as_ref().map(|p| p.0.value)),
        az: series(&|r| r.setpoint.position_deg.as_ref().map(|p| p.1.value)),
        panel_v: series(&|r| r.setpoint.panel_mv.map(|mv| f64::from(mv) / 1000.0)),
        setpoints: m.rows.len(),
        ..Day::default()
    };
    // Events before the first time are placed at it.
    let at = |t: Option<i64>| x(t.unwrap_or(first));
    let mut mode: Option<(f64, String)> = None;
    let mut open: Vec<(String, f64)> = Vec::new();
    for e in &m.events {
        let t = at(e.unix_s);
        match &e.change {
            Change::Mode(new) => {
                if let Some((from, name)) = mode.take() {
                    d.modes.push((from, t, name));
                }
                mode = new.clone().map(|n| (t, n));
            }
            Change::Fault(name, raised) => {
                let i = match d.faults.iter().position(|f| &f.0 == name) {
                    Some(i) => i,
                    None => {
                        d.faults.push((name.clone(), Vec::new(), Vec::new()));
                        d.faults.len() - 1
                    }
                };
                if *raised {
                    d.faults[i].2.push(t);
                    open.push((name.clone(), t));
                } else if let Some(k) = open.iter().position(|o| &o.0 == name) {
                    let (_, from) = open.remove(k);
                    d.faults[i].1.push((from, t));
                }
            }
            Change::Boot => {
                if e.unix_s.is_some() {
                    d.boots.push(t);
                }
            }
        }
    }
    let end = x(last);
    if let Some((from, name)) = mode {
        d.modes.push((from, end, name));
    }
    for (name, from) in open {
        if let Some(f) = d.faults.iter_mut().find(|f| f.0 == name) {
            f.1.push((from, end));
        }
    }
    Some(d)
}

/// `hours` since the first day's midnight as `HH:MM`, `+Nd HH:MM` on the
/// days after it.
fn clock(hours: f64) -> String {
    let minutes = (hours * 60.0).round() as i64;
    let (day, m) = (minutes.div_euclid(1440), minutes.rem_euclid(1440));
    let hm = format!("{:02}:{:02}", m / 60, m % 60);
    if day == 0 {
        hm
    } else {
        format!("{day:+}d {hm}")
    }
}

/// Low and high of the values of `curves`.
fn extent<'a>(curves: impl Iterator<Item = &'a Vec<(f64, f64)>>) -> Option<(f64, f64)> {
    let (lo, hi) = curves
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    (lo <= hi).then_some((lo, hi))
}

/// Writes `svg` to `path`, creating its directory.
pub fn write(path: &str, svg: &str) -> Result<(), String> {
    plot::write(path, svg).map_err(|e| e.to_string())
}

/// The ranges of the axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ranges {
    /// Time, hours since the first day's midnight: whole hours around a
    /// log of 3 h or more, quarter hours around a shorter one.
    pub x_h: (f64, f64),
    /// Degrees: multiples of 10 at least 4° beyond the plotted values
    /// (0 to 90 without a set-point).
    pub y_deg: (f64, f64),
    /// Panel voltage: from 0 (or the lowest value below it) to the next
    /// whole volt above the highest; `None` without panel voltages.
    pub panel_v: Option<(f64, f64)>,
}

/// The axes of the figure of `d`, from its data.
pub fn ranges(d: &Day) -> Ranges {
    let x_step = if d.span_h.1 - d.span_h.0 >= 3.0 {
        1.0
    } else {
        0.25
    };
    let degrees = extent(d.degree_curves());
    Ranges {
        x_h: plot::padded_range(d.span_h.0, d.span_h.1, 0.0, x_step),
        y_deg: degrees.map_or((0.0, 90.0), |(lo, hi)| {
            plot::padded_range(lo, hi, Y_PAD_DEG, Y_STEP_DEG)
        }),
        panel_v: extent(d.panel_v.iter())
            .map(|(lo, hi)| plot::padded_range(lo.min(0.0), hi, 0.0, 1.0)),
    }
}

/// Draws the figure; `title` heads it. Returns the SVG.
pub fn draw(d: &Day, title: &str) -> Result<String, Box<dyn Error>> {
    Ok(timeline::crisp_boxes(draw_figure(d, title)?))
}

fn draw_figure(d: &Day, title: &str) -> Result<String, Box<dyn Error>> {
    let r = ranges(d);
    let ((x0, x1), (y0, y1), panel) = (r.x_h, r.y_deg, r.panel_v);
    // plotters picks round steps for at most this many labels.
    let x_labels = 13;
    let degrees = extent(d.degree_curves());
    let fault_rows = timeline::fault_rows(d.faults.iter().map(|f| f.0.as_str()));

    let mut entries: Vec<(Swatch, String)> = vec![
        (
            Swatch::Line(ELEVATION, 2),
            "sun elevation (90\u{b0} \u{2212} zenith)".into(),
        ),
        (
            Swatch::Line(AZIMUTH, 2),
            "sun azimuth (east of north)".into(),
        ),
    ];
    // The axis angles of the log; a `--modbus` session has the panel's
    // elevation and azimuth instead.
    let modbus = d.c.is_empty() && d.a.is_empty() && !(d.el.is_empty() && d.az.is_empty());
    let (c_label, a_label) = if modbus {
        (
            "panel elevation (ElPos; dot: poll)",
            "panel azimuth (AzPos; dot: poll)",
        )
    } else {
        (
            "commanded c (dot: set-point)",
            "commanded a (dot: set-point)",
        )
    };
    entries.push((Swatch::LineDots(AXIS_C, 2, 2), c_label.into()));
    entries.push((Swatch::LineDots(AXIS_A, 2, 2), a_label.into()));
    if panel.is_some() {
        entries.push((Swatch::Line(PANEL, 2), "panel voltage".into()));
    }
    let mut seen: Vec<&str> = Vec::new();
    for (_, _, m) in &d.modes {
        if !seen.contains(&m.as_str()) {
            seen.push(m);
        }
    }
    // In the table's order, names it does not know last.
    seen.sort_by_key(|m| {
        MODE_COLOURS
            .iter()
            .position(|c| c.0 == *m)
            .unwrap_or(MODE_COLOURS.len())
    });
    for m in &seen {
        entries.push((Swatch::Box(mode_colour(m)), format!("mode {m}")));
    }
    entries.push((Swatch::Box(FAULT), "fault active".into()));
    entries.push((Swatch::Dot(FAULT, 4), "fault raised".into()));
    if !d.boots.is_empty() {
        entries.push((Swatch::Line(BOOT, 1), "board boot".into()));
    }
    let columns = 3;
    let legend_h = plot::legend_height(entries.len(), columns);
    let top_h = 400;
    let panel_h = if panel.is_some() { 130 } else { 0 };
    let mode_h = 46;
    let fault_h = 50 + 18 * fault_rows.len() as u32;
    let (w, h) = (960, 30 + top_h + panel_h + mode_h + fault_h + legend_h + 10);
    let day0 = UtcTime::from_unix_seconds(d.day0_s).map_err(|e| e.to_string())?;
    let (yy, mo, dd) = day0.ymd();
    let x_desc = format!("UTC (the board's time) from {yy:04}-{mo:02}-{dd:02} 00:00");
    let x_fmt = |v: &f64| clock(*v);
    plot::render((w, h), |canvas| {
        let root = timeline::titled(canvas, title)?;
        let (top, rest) = root.split_vertically(px(top_h));
        let (mid, rest) = rest.split_vertically(px(panel_h));
        let (band, rest) = rest.split_vertically(px(mode_h));
        let (bottom, legend) = rest.split_vertically(px(fault_h));

        // Sun and commanded pose.
        let mut c = timeline::panel(&top, 8, 8, x0..x1, y0..y1)?;
        timeline::mesh(
            c.configure_mesh()
                .y_desc("degrees")
                .x_labels(x_labels)
                .y_labels((((y1 - y0) / Y_STEP_DEG) as usize + 1).min(13))
                .x_label_formatter(&|_| String::new())
                .y_label_formatter(&|v| format!("{v:.0}")),
        )
        .draw()?;
        if degrees.is_none() {
            c.draw_series(std::iter::once(Text::new(
                "no set-point in the log",
                (x0 + (x1 - x0) * 0.4, 45.0),
                font(14),
            )))?;
        }
        for b in &d.boots {
            c.draw_series(LineSeries::new(vec![(*b, y0), (*b, y1)], stroke(BOOT, 1)))?;
        }
        for (set, colour) in [(&d.elevation, ELEVATION), (&d.azimuth, AZIMUTH)] {
            for l in set {
                c.draw_series(LineSeries::new(l.clone(), stroke(colour, 2)))?;
            }
        }
        for (set, colour) in [
            (&d.c, AXIS_C),
            (&d.a, AXIS_A),
            (&d.el, AXIS_C),
            (&d.az, AXIS_A),
        ] {
            for l in set {
                c.draw_series(LineSeries::new(l.clone(), stroke(colour, 2)))?;
                c.draw_series(l.iter().map(|&p| Circle::new(p, px(2), colour.filled())))?;
            }
        }

        // Panel voltage.
        if let Some((v0, v1)) = panel {
            let mut c = timeline::panel(&mid, 6, 6, x0..x1, v0..v1)?;
            timeline::mesh(
                c.configure_mesh()
                    .y_desc("panel (V)")
                    .x_labels(x_labels)
                    .y_labels(5)
                    .x_label_formatter(&|_| String::new())
                    .y_label_formatter(&|v| format!("{v:.1}")),
            )
            .draw()?;
            for l in &d.panel_v {
                c.draw_series(LineSeries::new(l.clone(), stroke(PANEL, 2)))?;
            }
        }

        // Mode band.
        let mut c = timeline::panel(&band, 6, 6, x0..x1, 0f64..1f64)?;
        timeline::mode_band(&mut c)?;
        // At least 2 pixels wide, so that every mode that occurs shows.
        let min_w = (x1 - x0) * 2.0 / PLOT_W;
        c.draw_series(d.modes.iter().map(|(a, b, m)| {
            Rectangle::new(
                [(*a, 0.0), (b.max(a + min_w), 1.0)],
                mode_colour(m).filled(),
            )
        }))?;

        // Faults: a row each, named left of the axis.
        let rows = fault_rows.len() as f64;
        let mut c = timeline::panel(&bottom, 6, 40, x0..x1, 0f64..rows)?;
        timeline::mesh(
            c.configure_mesh()
                .disable_y_mesh()
                .x_desc(x_desc.as_str())
                .x_labels(x_labels)
                .y_labels(0)
                .x_label_formatter(&x_fmt),
        )
        .draw()?;
        timeline::fault_names(canvas, &c, x0, &fault_rows)?;
        // At least 2 pixels wide, so that a fault of seconds shows.
        let min_w = (x1 - x0) * 2.0 / PLOT_W;
        for (row, (_, spans, raised)) in d.faults.iter().enumerate() {
            let row = row as f64;
            c.draw_series(spans.iter().map(|&(a, b)| {
                Rectangle::new(
                    [(a, row + 0.3), (b.max(a + min_w), row + 0.7)],
                    FAULT.filled(),
                )
            }))?;
            c.draw_series(
                raised
                    .iter()
                    .map(|&t| Circle::new((t, row + 0.5), px(4), FAULT.filled())),
            )?;
        }
        timeline::legend(&legend, &entries, columns)?;
        Ok(())
    })
}
