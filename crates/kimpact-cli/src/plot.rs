//! Plots of kinetic energy and momentum over time: SVG (plotters, with
//! text) and PNG (tiny-skia, lines only: same colours, no text).

use plotters::prelude::*;
use tiny_skia::{Paint, PathBuilder, Pixmap, Stroke, Transform};

/// One line of a plot.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Colour (RGB).
    pub color: (u8, u8, u8),
    /// `(x, y)` points.
    pub points: Vec<(f64, f64)>,
}

/// Plot size in pixels.
const SIZE: (u32, u32) = (900, 500);

/// At most this many points per line (evenly thinned, last point kept).
const MAX_POINTS: usize = 2000;

/// Thin a line to at most [`MAX_POINTS`] points.
pub fn thin(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    if points.len() <= MAX_POINTS {
        return points.to_vec();
    }
    let stride = points.len().div_ceil(MAX_POINTS);
    let mut out: Vec<(f64, f64)> = points.iter().step_by(stride).copied().collect();
    if let Some(last) = points.last()
        && out.last() != Some(last)
    {
        out.push(*last);
    }
    out
}

/// The data range of every series, padded, never empty.
fn bounds(series: &[Series]) -> (f64, f64, f64, f64) {
    let finite = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in finite {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !(x0 <= x1) {
        (x0, x1) = (0.0, 1.0);
    }
    if !(y0 <= y1) {
        (y0, y1) = (0.0, 1.0);
    }
    // Energies and momentum magnitudes: show the zero.
    y0 = y0.min(0.0);
    y1 = y1.max(0.0);
    if x1 - x0 <= 0.0 {
        x1 = x0 + 1.0;
    }
    let span = y1 - y0;
    let pad = if span > 1e-12 * y1.abs().max(y0.abs()) {
        0.05 * span
    } else {
        0.05 * y1.abs().max(1e-9)
    };
    (x0, x1, y0 - pad, y1 + pad)
}

/// An SVG line plot with title, axis labels and legend.
///
/// # Errors
/// plotters' drawing error, as text.
pub fn svg(title: &str, x_label: &str, y_label: &str, series: &[Series]) -> Result<String, String> {
    let (x0, x1, y0, y1) = bounds(series);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(90)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .draw()
            .map_err(|e| e.to_string())?;
        for s in series {
            let color = RGBColor(s.color.0, s.color.1, s.color.2);
            chart
                .draw_series(LineSeries::new(
                    s.points
                        .iter()
                        .copied()
                        .filter(|(x, y)| x.is_finite() && y.is_finite()),
                    color.stroke_width(2),
                ))
                .map_err(|e| e.to_string())?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// The same plot as a PNG, drawn with tiny-skia: frame, grid, zero line and
/// the lines in the same colours (no text: the SVG carries the labels).
///
/// # Errors
/// tiny-skia's encoding error, as text.
pub fn png(series: &[Series]) -> Result<Vec<u8>, String> {
    let (w, h) = SIZE;
    let mut pixmap = Pixmap::new(w, h).ok_or("cannot allocate the plot")?;
    pixmap.fill(tiny_skia::Color::WHITE);
    let (x0, x1, y0, y1) = bounds(series);
    let (left, right, top, bottom) = (60.0f32, w as f32 - 20.0, 20.0f32, h as f32 - 40.0);
    let map = |x: f64, y: f64| -> (f32, f32) {
        let px = left + ((x - x0) / (x1 - x0)) as f32 * (right - left);
        let py = bottom - ((y - y0) / (y1 - y0)) as f32 * (bottom - top);
        (px, py)
    };
    let line = |pixmap: &mut Pixmap, pts: &[(f32, f32)], rgb: (u8, u8, u8), width: f32| {
        let mut pb = PathBuilder::new();
        for (i, &(x, y)) in pts.iter().enumerate() {
            if i == 0 {
                pb.move_to(x, y);
            } else {
                pb.line_to(x, y);
            }
        }
        if let Some(path) = pb.finish() {
            let mut p = Paint {
                anti_alias: true,
                ..Paint::default()
            };
            p.set_color_rgba8(rgb.0, rgb.1, rgb.2, 255);
            let stroke = Stroke {
                width,
                ..Stroke::default()
            };
            pixmap.stroke_path(&path, &p, &stroke, Transform::identity(), None);
        }
    };
    for i in 0..=10 {
        let f = i as f32 / 10.0;
        let x = left + f * (right - left);
        let y = top + f * (bottom - top);
        line(&mut pixmap, &[(x, top), (x, bottom)], (225, 225, 225), 1.0);
        line(&mut pixmap, &[(left, y), (right, y)], (225, 225, 225), 1.0);
    }
    if y0 < 0.0 && y1 > 0.0 {
        let (_, zy) = map(x0, 0.0);
        line(
            &mut pixmap,
            &[(left, zy), (right, zy)],
            (120, 120, 120),
            1.0,
        );
    }
    line(
        &mut pixmap,
        &[
            (left, top),
            (right, top),
            (right, bottom),
            (left, bottom),
            (left, top),
        ],
        (0, 0, 0),
        1.5,
    );
    for s in series {
        let pts: Vec<(f32, f32)> = s
            .points
            .iter()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|&(x, y)| map(x, y))
            .collect();
        line(&mut pixmap, &pts, s.color, 2.0);
    }
    pixmap.encode_png().map_err(|e| e.to_string())
}
