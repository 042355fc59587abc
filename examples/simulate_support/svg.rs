//! `simulate --svg`: the run as a figure. Three panels over the run's time:
//! the pointing error while tracking with the sun up (log scale; every
//! minute, or the maximum and mean of each bin of whole days when the run
//! is longer than 3 days), the controller's mode (the share of each mode in
//! each bin, stacked) and one row per fault that was active (a bar while
//! active). The legend names every series.

use std::error::Error;

use plotters::prelude::*;
use sun_algos::UtcTime;
use suntracker::safety::Mode;

#[path = "../common/plot.rs"]
mod plot;
#[path = "../common/timeline.rs"]
mod timeline;

use plot::{font, px, stroke, Swatch};
use timeline::{FAULT, MODE_COLOURS};

/// Every mode, in the order of the band (bottom up) and the legend (that
/// of [`MODE_COLOURS`]).
pub const MODES: [Mode; 15] = [
    Mode::Tracking,
    Mode::Unwind,
    Mode::Overcast,
    Mode::Homing,
    Mode::Night,
    Mode::WaitForTime,
    Mode::WindStow,
    Mode::HailStow,
    Mode::ExternalStow,
    Mode::SnowStow,
    Mode::LowSupplyStow,
    Mode::CommandStow,
    Mode::Manual,
    Mode::SafeStop,
    Mode::Service,
];

/// The position of `mode` in [`MODES`] and [`MODE_COLOURS`] (exhaustive: a
/// new mode must be given a place and a colour).
pub fn mode_index(mode: Mode) -> usize {
    match mode {
        Mode::Tracking => 0,
        Mode::Unwind => 1,
        Mode::Overcast => 2,
        Mode::Homing => 3,
        Mode::Night => 4,
        Mode::WaitForTime => 5,
        Mode::WindStow => 6,
        Mode::HailStow => 7,
        Mode::ExternalStow => 8,
        Mode::SnowStow => 9,
        Mode::LowSupplyStow => 10,
        Mode::CommandStow => 11,
        Mode::Manual => 12,
        Mode::SafeStop => 13,
        Mode::Service => 14,
    }
}

const ERROR_MAX: RGBColor = RGBColor(0x1f, 0x4e, 0xc8);
const ERROR_MEAN: RGBColor = RGBColor(0x0b, 0x1f, 0x4f);

/// Pixel columns of the plots (picture pixels): the bins of a long run.
const PLOT_COLUMNS: u32 = 800;
/// Runs up to this many minutes plot the pointing error of every minute.
const PER_MINUTE_MAX: u32 = 3 * 1440;
/// Smallest pointing error shown on the log axis, degrees.
const ERROR_FLOOR_DEG: f64 = 1e-4;

/// What the figure needs of each minute of the run.
#[derive(Debug, Clone)]
pub struct Recorder {
    minutes: u32,
    modes: Vec<u8>,
    /// Pointing error while tracking with the sun up, else NaN.
    error_deg: Vec<f32>,
    /// Fault names by first appearance, with their active intervals.
    faults: Vec<(&'static str, Vec<(u32, u32)>)>,
    /// Faults active at the last recorded minute: (index, since).
    open: Vec<(usize, u32)>,
}

/// A finished run's record.
#[derive(Debug, Clone)]
pub struct Run {
    pub minutes: u32,
    pub modes: Vec<u8>,
    pub error_deg: Vec<f32>,
    /// Each fault that was active and its minutes `[from, until)`.
    pub faults: Vec<(&'static str, Vec<(u32, u32)>)>,
}

impl Recorder {
    /// A record of a run of `minutes` minutes.
    pub fn new(minutes: u32) -> Self {
        Recorder {
            minutes,
            modes: Vec::with_capacity(minutes as usize),
            error_deg: Vec::with_capacity(minutes as usize),
            faults: Vec::new(),
            open: Vec::new(),
        }
    }

    /// Records minute `m` (called for 0, 1, 2, … in order).
    pub fn minute(
        &mut self,
        m: u32,
        mode: Mode,
        pointing_deg: Option<f64>,
        active: impl Iterator<Item = &'static str>,
    ) {
        self.modes.push(mode_index(mode) as u8);
        self.error_deg
            .push(pointing_deg.map_or(f32::NAN, |e| e as f32));
        let mut now: Vec<usize> = Vec::new();
        for name in active {
            let i = match self.faults.iter().position(|f| f.0 == name) {
                Some(i) => i,
                None => {
                    self.faults.push((name, Vec::new()));
                    self.faults.len() - 1
                }
            };
            if !now.contains(&i) {
                now.push(i);
            }
        }
        // Close what ended, open what started.
        let faults = &mut self.faults;
        self.open.retain(|&(i, since)| {
            let still = now.contains(&i);
            if !still {
                faults[i].1.push((since, m));
            }
            still
        });
        for i in now {
            if !self.open.iter().any(|o| o.0 == i) {
                self.open.push((i, m));
            }
        }
    }

    /// The record, faults still active ending with the run.
    pub fn finish(mut self) -> Run {
        let end = self.modes.len() as u32;
        for (i, since) in self.open.drain(..) {
            self.faults[i].1.push((since, end));
        }
        Run {
            minutes: self.minutes.min(end),
            modes: self.modes,
            error_deg: self.error_deg,
            faults: self.faults,
        }
    }
}

/// The time axis: minutes to plotted units.
#[derive(Debug, Clone, Copy)]
struct TimeAxis {
    minutes_per_unit: f64,
    unit: &'static str,
}

impl TimeAxis {
    fn for_run(minutes: u32) -> Self {
        if minutes <= 3 * 1440 {
            TimeAxis {
                minutes_per_unit: 60.0,
                unit: "hours",
            }
        } else {
            TimeAxis {
                minutes_per_unit: 1440.0,
                unit: "days",
            }
        }
    }

    fn x(&self, minute: f64) -> f64 {
        minute / self.minutes_per_unit
    }
}

/// Bins of a run: `(first minute, end minute)` of each. A run of up to 3
/// days has one per plot column; a longer one whole days each (so that the
/// bins do not beat against the day), as few days as fill the columns.
fn bins(minutes: u32) -> Vec<(u32, u32)> {
    if minutes > PER_MINUTE_MAX {
        let days = minutes.div_ceil(1440);
        let per_bin = days.div_ceil(PLOT_COLUMNS) * 1440;
        return (0..minutes.div_ceil(per_bin))
            .map(|i| (i * per_bin, ((i + 1) * per_bin).min(minutes)))
            .collect();
    }
    let n = minutes.clamp(1, PLOT_COLUMNS);
    (0..n)
        .map(|i| {
            let a = (u64::from(i) * u64::from(minutes) / u64::from(n)) as u32;
            let b = (u64::from(i + 1) * u64::from(minutes) / u64::from(n)) as u32;
            (a, b)
        })
        .filter(|(a, b)| b > a)
        .collect()
}

/// Curves, each broken into polylines.
type Polylines = Vec<Vec<(f64, f64)>>;

/// The pointing-error series: per minute, or (max, mean) per bin; each a
/// list of polylines broken where nothing was tracked.
fn error_series(run: &Run, axis: TimeAxis) -> (Polylines, Polylines, bool) {
    let per_minute = run.minutes <= PER_MINUTE_MAX;
    let spans = if per_minute {
        (0..run.minutes).map(|m| (m, m + 1)).collect()
    } else {
        bins(run.minutes)
    };
    let (mut max, mut mean) = (vec![Vec::new()], vec![Vec::new()]);
    for (a, b) in spans {
        let vals: Vec<f64> = run.error_deg[a as usize..b as usize]
            .iter()
            .filter(|e| e.is_finite())
            .map(|&e| f64::from(e).max(ERROR_FLOOR_DEG))
            .collect();
        if vals.is_empty() {
            for s in [&mut max, &mut mean] {
                if s.last().is_some_and(|l| !l.is_empty()) {
                    s.push(Vec::new());
                }
            }
            continue;
        }
        let x = axis.x(f64::from(a) + f64::from(b - a) / 2.0);
        let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let avg = vals.iter().sum::<f64>() / vals.len() as f64;
        if let Some(l) = max.last_mut() {
            l.push((x, hi));
        }
        if let Some(l) = mean.last_mut() {
            l.push((x, avg));
        }
    }
    max.retain(|l| !l.is_empty());
    mean.retain(|l| !l.is_empty());
    (max, mean, per_minute)
}

/// Draws the run; returns the SVG. `start` is the run's first minute.
pub fn draw(run: &Run, start: &UtcTime, title: &str) -> Result<String, Box<dyn Error>> {
    Ok(timeline::crisp_boxes(draw_figure(run, start, title)?))
}

fn draw_figure(run: &Run, start: &UtcTime, title: &str) -> Result<String, Box<dyn Error>> {
    let axis = TimeAxis::for_run(run.minutes);
    let x_end = axis.x(f64::from(run.minutes.max(1)));
    let (max, mean, per_minute) = error_series(run, axis);
    let (lo, hi) = max
        .iter()
        .chain(&mean)
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    // Whole decades around the points; a decade below the floor when a
    // point sits on it (an error below the floor, drawn at the floor).
    let (e0, e1) = if lo.is_finite() && hi.is_finite() {
        let e0 = 10f64.powf(lo.log10().floor());
        let e0 = if e0 >= lo { e0 / 10.0 } else { e0 };
        (e0, 10f64.powf(hi.log10().ceil()))
    } else {
        (1e-3, 1.0)
    };
    let floored = max.iter().flatten().any(|p| p.1 <= ERROR_FLOOR_DEG);
    let e1 = if e1 <= e0 { e0 * 10.0 } else { e1 };
    // Which modes occurred, and their share in each bin.
    let mut seen = [false; MODES.len()];
    for &m in &run.modes {
        seen[usize::from(m)] = true;
    }
    let fault_rows = timeline::fault_rows(run.faults.iter().map(|f| f.0));

    let mut entries: Vec<(Swatch, String)> = Vec::new();
    let below = if floored {
        format!(" (floor {ERROR_FLOOR_DEG}\u{b0})")
    } else {
        String::new()
    };
    if per_minute {
        entries.push((
            Swatch::Line(ERROR_MAX, 2),
            format!("pointing error, each minute tracking{below}"),
        ));
    } else {
        let days = bins(run.minutes)
            .first()
            .map_or(1, |b| (b.1 - b.0).div_ceil(1440));
        let per = if days == 1 {
            "day".to_string()
        } else {
            format!("{days} days")
        };
        entries.push((
            Swatch::Line(ERROR_MAX, 1),
            format!("pointing error tracking, max per {per}{below}"),
        ));
        entries.push((
            Swatch::Line(ERROR_MEAN, 2),
            format!("pointing error tracking, mean per {per}"),
        ));
    }
    for (i, m) in MODES.iter().enumerate() {
        if seen[i] {
            entries.push((Swatch::Box(MODE_COLOURS[i].1), format!("mode {}", m.name())));
        }
    }
    entries.push((Swatch::Box(FAULT), "fault active".into()));
    // Three columns of labels up to ~40 characters fit the width.
    let longest = entries
        .iter()
        .map(|e| e.1.chars().count())
        .max()
        .unwrap_or(0);
    let columns = if longest > 40 { 2 } else { 3 };
    let legend_h = plot::legend_height(entries.len(), columns);
    let error_h = 300;
    let mode_h = 64;
    let fault_h = 50 + 18 * fault_rows.len() as u32;
    let (w, h) = (960, 30 + error_h + mode_h + fault_h + legend_h + 10);
    let (y0, mo, d) = start.ymd();
    let x_desc = format!("{} since {y0:04}-{mo:02}-{d:02} 00:00 UTC", axis.unit);

    plot::render((w, h), |canvas| {
        let root = timeline::titled(canvas, title)?;
        let (top, rest) = root.split_vertically(px(error_h));
        let (mid, rest) = rest.split_vertically(px(mode_h));
        let (bottom, legend) = rest.split_vertically(px(fault_h));

        // Pointing error.
        let mut c = timeline::panel(&top, 8, 8, 0f64..x_end, (e0..e1).log_scale())?;
        timeline::mesh(
            c.configure_mesh()
                .y_desc("pointing error (deg)")
                .x_label_formatter(&|_| String::new())
                .y_label_formatter(&|v| format!("{v}")),
        )
        .draw()?;
        if max.is_empty() {
            c.draw_series(std::iter::once(Text::new(
                "no minute tracking with the sun up",
                (x_end * 0.35, (e0 * e1).sqrt()),
                font(14),
            )))?;
        }
        let width = if per_minute { 2 } else { 1 };
        for l in &max {
            c.draw_series(LineSeries::new(l.clone(), stroke(ERROR_MAX, width)))?;
        }
        if !per_minute {
            for l in &mean {
                c.draw_series(LineSeries::new(l.clone(), stroke(ERROR_MEAN, 2)))?;
            }
        }

        // Modes: the share of each in each bin, stacked.
        let mut c = timeline::panel(&mid, 6, 6, 0f64..x_end, 0f64..1f64)?;
        timeline::mode_band(&mut c)?;
        // Runs of bins with the same single mode are one rectangle.
        let mut rects: Vec<(f64, f64, f64, f64, usize)> = Vec::new();
        for (a, b) in bins(run.minutes) {
            let mut count = [0u32; MODES.len()];
            for &m in &run.modes[a as usize..b as usize] {
                count[usize::from(m)] += 1;
            }
            let (x0, x1) = (axis.x(f64::from(a)), axis.x(f64::from(b)));
            let n = f64::from(b - a);
            let mut y = 0.0;
            for (i, &k) in count.iter().enumerate().filter(|(_, k)| **k > 0) {
                let top = y + f64::from(k) / n;
                match rects.last_mut() {
                    Some(r) if k == b - a && r.4 == i && r.2 == 0.0 && r.3 == 1.0 && r.1 == x0 => {
                        r.1 = x1
                    }
                    _ => rects.push((x0, x1, y, top, i)),
                }
                y = top;
            }
        }
        // Each box reaches 2 canvas pixels (half a picture pixel) into the
        // next, which is drawn over it, so that no anti-aliased seam shows
        // between neighbours.
        let seam = x_end * 2.0 / f64::from(px(PLOT_COLUMNS));
        c.draw_series(rects.iter().map(|&(x0, x1, y0, y1, i)| {
            Rectangle::new(
                [(x0, y0), ((x1 + seam).min(x_end), y1)],
                MODE_COLOURS[i].1.filled(),
            )
        }))?;

        // Faults: a row each, named left of the axis.
        let rows = fault_rows.len() as f64;
        let mut c = timeline::panel(&bottom, 6, 40, 0f64..x_end, 0f64..rows)?;
        timeline::mesh(
            c.configure_mesh()
                .disable_y_mesh()
                .x_desc(x_desc.as_str())
                .y_labels(0)
                .x_label_formatter(&|v| format!("{v}")),
        )
        .draw()?;
        timeline::fault_names(canvas, &c, 0.0, &fault_rows)?;
        // At least 2 pixels wide, so that a one-minute fault shows.
        let min_w = x_end * 2.0 / f64::from(PLOT_COLUMNS);
        for (row, (_, spans)) in run.faults.iter().enumerate() {
            let row = row as f64;
            c.draw_series(spans.iter().map(|&(a, b)| {
                let x0 = axis.x(f64::from(a));
                let x1 = axis.x(f64::from(b)).max(x0 + min_w);
                Rectangle::new([(x0, row + 0.2), (x1, row + 0.8)], FAULT.filled())
            }))?;
        }
        timeline::legend(&legend, &entries, columns)?;
        Ok(())
    })
}
