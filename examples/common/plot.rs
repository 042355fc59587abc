//! SVG figures of the host tools (`sun_path`, `simulate --svg`), drawn with
//! plotters' SVG backend.
//!
//! plotters hands its backends integer pixel coordinates, so a curve drawn
//! at the picture's own size is a staircase of whole pixels. Figures are
//! therefore drawn on a canvas [`K`] times larger in each direction and
//! the `<svg>` element is given the picture's size with the large canvas as
//! its `viewBox`: the viewer scales by 1/K and every coordinate keeps K
//! sub-pixel steps. Sizes in this module (fonts, strokes, margins) are in
//! picture pixels; [`px`] converts them to canvas pixels.

// Each tool uses a part of this file.
#![allow(dead_code)]

use std::error::Error;

use plotters::coord::Shift;
use plotters::prelude::*;

/// Canvas pixels per picture pixel.
pub const K: u32 = 4;

/// `n` picture pixels in canvas pixels.
pub const fn px(n: u32) -> u32 {
    n * K
}

/// `n` picture pixels in canvas pixels, signed (element coordinates).
pub const fn pxi(n: i32) -> i32 {
    n * K as i32
}

/// A sans-serif font of `size` picture pixels.
pub fn font(size: u32) -> TextStyle<'static> {
    ("sans-serif", px(size)).into_font().into()
}

/// A line style of `width` picture pixels.
pub fn stroke(colour: RGBColor, width: u32) -> ShapeStyle {
    colour.stroke_width(px(width))
}

/// The drawing area of a figure of `size` picture pixels.
pub type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Draws a figure of `size` (picture pixels) with `draw` and returns the
/// SVG text.
pub fn render(
    size: (u32, u32),
    draw: impl FnOnce(&Area) -> Result<(), Box<dyn Error>>,
) -> Result<String, Box<dyn Error>> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (px(size.0), px(size.1))).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root)?;
        root.present()?;
    }
    // The backend writes `<svg width="W·K" height="H·K" viewBox="0 0 W·K
    // H·K"`: keep the viewBox, show it at W×H.
    let big = format!("<svg width=\"{}\" height=\"{}\"", px(size.0), px(size.1));
    let small = format!("<svg width=\"{}\" height=\"{}\"", size.0, size.1);
    if !svg.starts_with(&big) {
        return Err(format!("unexpected SVG header: {:?}", svg.get(..80)).into());
    }
    Ok(svg.replacen(&big, &small, 1))
}

/// Writes `svg` to `path`, creating its directory.
pub fn write(path: &str, svg: &str) -> Result<(), Box<dyn Error>> {
    if let Some(dir) = std::path::Path::new(path).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
    }
    std::fs::write(path, svg).map_err(|e| format!("{path}: {e}"))?;
    Ok(())
}

/// How a legend entry is drawn.
#[derive(Debug, Clone, Copy)]
pub enum Swatch {
    /// A line of the colour and width (picture pixels).
    Line(RGBColor, u32),
    /// A filled dot of the colour and radius (picture pixels).
    Dot(RGBColor, u32),
    /// A line with dots on it: a curve with marked samples.
    LineDots(RGBColor, u32, u32),
    /// A filled box: a band or bar.
    Box(RGBColor),
}

/// Draws a legend in `area`: the entries in rows of `columns`, each a
/// swatch and its label, inside a thin frame.
pub fn legend(
    area: &Area,
    entries: &[(Swatch, String)],
    columns: usize,
) -> Result<(), Box<dyn Error>> {
    let (w, _) = area.dim_in_pixel();
    let columns = columns.max(1);
    let row_h = pxi(20);
    let col_w = (w as i32 - pxi(20)) / columns as i32;
    let rows = entries.len().div_ceil(columns) as i32;
    // A closed path, not a Rectangle: plotters writes no stroke width for
    // rectangles (one canvas pixel, a quarter of a picture pixel).
    let (x0, y0, x1, y1) = (pxi(4), pxi(2), w as i32 - pxi(4), pxi(10) + rows * row_h);
    area.draw(&PathElement::new(
        vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)],
        stroke(RGBColor(0x66, 0x66, 0x66), 1),
    ))?;
    for (i, (swatch, label)) in entries.iter().enumerate() {
        let x = pxi(14) + (i % columns) as i32 * col_w;
        let y = pxi(16) + (i / columns) as i32 * row_h;
        match *swatch {
            Swatch::Line(c, width) => area.draw(&PathElement::new(
                vec![(x, y), (x + pxi(28), y)],
                stroke(c, width),
            ))?,
            Swatch::Dot(c, r) => area.draw(&Circle::new((x + pxi(14), y), px(r), c.filled()))?,
            Swatch::LineDots(c, width, r) => {
                area.draw(&PathElement::new(
                    vec![(x, y), (x + pxi(28), y)],
                    stroke(c, width),
                ))?;
                area.draw(&Circle::new((x + pxi(6), y), px(r), c.filled()))?;
                area.draw(&Circle::new((x + pxi(22), y), px(r), c.filled()))?;
            }
            Swatch::Box(c) => area.draw(&Rectangle::new(
                [(x, y - pxi(6)), (x + pxi(28), y + pxi(6))],
                c.filled(),
            ))?,
        }
        area.draw(&Text::new(
            label.clone(),
            (x + pxi(36), y - pxi(7)),
            font(13),
        ))?;
    }
    Ok(())
}

/// The height in picture pixels of a legend of `n` entries in `columns`.
pub fn legend_height(n: usize, columns: usize) -> u32 {
    14 + 20 * n.div_ceil(columns.max(1)) as u32
}

/// `lo..hi` widened to whole multiples of `step`, with at least `pad`
/// (same unit) beyond the data on each side; a degenerate or empty range
/// becomes one step around its value.
pub fn padded_range(lo: f64, hi: f64, pad: f64, step: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return (0.0, step);
    }
    let a = ((lo - pad) / step).floor() * step;
    let mut b = ((hi + pad) / step).ceil() * step;
    if b <= a {
        b = a + step;
    }
    (a, b)
}
