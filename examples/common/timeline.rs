//! The parts the two figures over time share, `simulate --svg`
//! (`examples/simulate_support/svg.rs`) and `monitor --svg`
//! (`examples/monitor_support/svg.rs`), so that both read alike: the mode
//! and fault colours, the title, the panels stacked over one time axis
//! (their frames, mesh and label styles), the mode band, the fault rows
//! named left of their axis, and the legend below. Sizes are in picture
//! pixels, as in `plot.rs`, which the including module declares as
//! `plot` next to this one.

// Each tool uses a part of this file.
#![allow(dead_code)]

use std::error::Error;

use plotters::chart::MeshStyle;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::plot::{self, font, px, stroke, Area, Swatch};

/// The controller's modes by name, in the order of the band (bottom up)
/// and of the legend, with their colours.
pub const MODE_COLOURS: [(&str, RGBColor); 15] = [
    ("tracking", RGBColor(0x4c, 0xaf, 0x50)),        // green
    ("unwind", RGBColor(0x00, 0x89, 0x7b)),          // teal
    ("overcast", RGBColor(0xbd, 0xbd, 0xbd)),        // grey
    ("homing", RGBColor(0x64, 0xb5, 0xf6)),          // light blue
    ("night", RGBColor(0x45, 0x4f, 0x6b)),           // slate
    ("wait_for_time", RGBColor(0xfb, 0xc0, 0x2d)),   // yellow
    ("wind_stow", RGBColor(0xff, 0x8f, 0x00)),       // orange
    ("hail_stow", RGBColor(0x00, 0x83, 0x8f)),       // dark cyan
    ("external_stow", RGBColor(0x5d, 0x40, 0x37)),   // dark brown
    ("snow_stow", RGBColor(0x90, 0xa4, 0xae)),       // blue grey
    ("low_supply_stow", RGBColor(0xc0, 0xca, 0x33)), // lime
    ("command_stow", RGBColor(0x8e, 0x44, 0xad)),    // purple
    ("manual", RGBColor(0x8d, 0x6e, 0x63)),          // brown
    ("safe_stop", RGBColor(0xef, 0x53, 0x50)),       // light red
    ("service", RGBColor(0x21, 0x21, 0x21)),         // near black
];

/// Active faults (bars) and where one was raised (dots).
pub const FAULT: RGBColor = RGBColor(0x8e, 0x00, 0x00);

/// Width of the area left of each panel for its labels and name.
const Y_LABEL_AREA: u32 = 130;

/// Boxes side by side (a mode band) get their edges snapped to pixels, or
/// the viewer's anti-aliasing lets the background through between them;
/// curves stay anti-aliased.
pub fn crisp_boxes(svg: String) -> String {
    svg.replace("<rect ", "<rect shape-rendering=\"crispEdges\" ")
}

/// The figure's area below its title.
pub fn titled<'a>(canvas: &Area<'a>, title: &str) -> Result<Area<'a>, Box<dyn Error>> {
    Ok(canvas.margin(px(6), 0, 0, 0).titled(title, font(15))?)
}

/// A panel of a figure: a chart over time (`X`) and a value (`Y`).
pub type Panel<'a, 'b, X, Y> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>;

/// A panel in `area` over `x` and `y`: `top` picture pixels above its
/// frame, `x_labels` below it (the time labels, or a small gap).
pub fn panel<'a, 'b, X: AsRangedCoord, Y: AsRangedCoord>(
    area: &'a Area<'b>,
    top: u32,
    x_labels: u32,
    x: X,
    y: Y,
) -> Result<Panel<'a, 'b, X::CoordDescType, Y::CoordDescType>, Box<dyn Error>> {
    Ok(ChartBuilder::on(area)
        .margin_left(px(12))
        .margin_right(px(20))
        .margin_top(px(top))
        .x_label_area_size(px(x_labels))
        .y_label_area_size(px(Y_LABEL_AREA))
        .build_cartesian_2d(x, y)?)
}

/// The grid, axes, labels and ticks of a panel with a mesh.
pub fn mesh<'m, 'a, 'b, X, Y, XT, YT, DB>(
    m: &'m mut MeshStyle<'a, 'b, X, Y, DB>,
) -> &'m mut MeshStyle<'a, 'b, X, Y, DB>
where
    X: Ranged<ValueType = XT> + ValueFormatter<XT>,
    Y: Ranged<ValueType = YT> + ValueFormatter<YT>,
    DB: DrawingBackend,
{
    let grid = |bold: f64| BLACK.mix(bold).stroke_width(px(1));
    m.label_style(font(12))
        .axis_desc_style(font(13))
        .axis_style(stroke(BLACK, 1))
        .bold_line_style(grid(0.18))
        .light_line_style(grid(0.05))
        .max_light_lines(1)
        .set_all_tick_mark_size(px(4))
}

/// The frame of the mode band: no grid, no labels, named "mode".
pub fn mode_band<X, DB>(
    c: &mut ChartContext<'_, DB, Cartesian2d<X, RangedCoordf64>>,
) -> Result<(), Box<dyn Error>>
where
    X: Ranged + ValueFormatter<X::ValueType>,
    DB: DrawingBackend,
    DB::ErrorType: 'static,
{
    c.configure_mesh()
        .disable_mesh()
        .y_desc("mode")
        .y_labels(0)
        .x_label_formatter(&|_| String::new())
        .axis_desc_style(font(13))
        .axis_style(stroke(BLACK, 1))
        .set_all_tick_mark_size(0)
        .draw()?;
    Ok(())
}

/// The fault rows' names: each fault's, or "(none)" for a single empty
/// row.
pub fn fault_rows<'a>(names: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    let rows: Vec<&str> = names.collect();
    if rows.is_empty() {
        vec!["(none)"]
    } else {
        rows
    }
}

/// Writes each row's name left of the fault panel's axis (`x0`, its left
/// end), on `canvas`, the whole figure.
pub fn fault_names<X, DB>(
    canvas: &Area,
    c: &ChartContext<'_, DB, Cartesian2d<X, RangedCoordf64>>,
    x0: X::ValueType,
    rows: &[&str],
) -> Result<(), Box<dyn Error>>
where
    X: Ranged,
    X::ValueType: Clone,
    DB: DrawingBackend,
{
    let label = font(12).pos(Pos::new(HPos::Right, VPos::Center));
    for (row, name) in rows.iter().enumerate() {
        let (x, y) = c.backend_coord(&(x0.clone(), row as f64 + 0.5));
        canvas.draw(&Text::new(
            name.to_string(),
            (x - px(6) as i32, y),
            label.clone(),
        ))?;
    }
    Ok(())
}

/// The legend in the area left below the panels.
pub fn legend(
    area: &DrawingArea<SVGBackend, Shift>,
    entries: &[(Swatch, String)],
    columns: usize,
) -> Result<(), Box<dyn Error>> {
    plot::legend(&area.margin(px(4), 0, px(60), px(12)), entries, columns)
}
