//! The package's plots: the colour of each simulator, the same in every
//! plot, and panels of one series per simulator (the accuracy study's
//! `accuracy.svg`, the bench's scaling plots).

use kimpact::Mode;
use plotters::coord::Shift;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::Method;

/// The colour of a simulator's points and lines: black for the reference,
/// then red, orange, green and blue up the ladder (native, restitution,
/// impulse, exact).
pub fn color(method: Method) -> RGBColor {
    match method {
        Method::Reference => RGBColor(0, 0, 0),
        Method::Rapier(Mode::Native) => RGBColor(214, 39, 40),
        Method::Rapier(Mode::Restitution) => RGBColor(255, 127, 14),
        Method::Rapier(Mode::Impulse) => RGBColor(44, 160, 44),
        Method::Rapier(Mode::Exact) => RGBColor(31, 119, 180),
    }
}

/// A panel: a title, its axes' labels, and a line (with dots when `dots`)
/// through the points of each simulator; y logarithmic, x logarithmic when
/// `log_x`, else linear from 0; the legend at `legend`.
#[allow(missing_docs)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub log_x: bool,
    pub dots: bool,
    pub legend: SeriesLabelPosition,
    pub series: Vec<(Method, Vec<(f64, f64)>)>,
}

impl Panel {
    /// Whether a point can be drawn on the panel's axes.
    fn drawable(&self, &(x, y): &(f64, f64)) -> bool {
        x.is_finite() && y.is_finite() && y > 0.0 && (!self.log_x || x > 0.0)
    }
}

/// The whole decades that hold the positive `values` (at least one).
fn decades(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values.fold((f64::MAX, f64::MIN), |(a, b), v| {
        (a.min(v.log10()), b.max(v.log10()))
    });
    let lo = lo.floor();
    (lo <= hi).then(|| (10f64.powf(lo), 10f64.powf(hi.ceil().max(lo + 1.0))))
}

/// The series of `p` (drawable points only) into its chart.
fn draw_series<'a, X>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, Cartesian2d<X, LogCoord<f64>>>,
    p: &Panel,
) -> Result<(), String>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    let x_fmt = |x: &f64| match p.log_x {
        true => format!("{x:.0e}"),
        false => decimal(*x, 2),
    };
    chart
        .configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .x_desc(&p.x_label)
        .y_desc(&p.y_label)
        .draw()
        .map_err(e)?;
    for (method, series) in &p.series {
        let c = color(*method);
        let pts: Vec<(f64, f64)> = series.iter().filter(|q| p.drawable(q)).copied().collect();
        let line = chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
            .map_err(e)?;
        line.label(method.name())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], c.stroke_width(2)));
        if p.dots {
            chart
                .draw_series(pts.into_iter().map(|q| Circle::new(q, 3, c.filled())))
                .map_err(e)?;
        }
    }
    legend(chart, p.legend.clone())
}

/// `x` with at most `decimals` decimals (trailing zeros dropped).
pub fn decimal(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    match s.contains('.') {
        true => s.trim_end_matches('0').trim_end_matches('.').to_owned(),
        false => s,
    }
}

/// The legend of `chart`'s labelled series at `position`.
///
/// # Errors
/// plotters', as text.
pub fn legend<'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, CT>,
    position: SeriesLabelPosition,
) -> Result<(), String> {
    let mut labels = chart.configure_series_labels();
    labels.position(position).border_style(BLACK);
    labels.background_style(WHITE.mix(0.85));
    labels.draw().map_err(|e| e.to_string())
}

/// One panel into `area` (nothing when it has no drawable point).
fn draw(area: &DrawingArea<SVGBackend<'_>, Shift>, p: &Panel) -> Result<(), String> {
    let pts = || p.series.iter().flat_map(|s| &s.1).filter(|q| p.drawable(q));
    let (Some((y0, y1)), Some((x0, x1))) =
        (decades(pts().map(|q| q.1)), decades(pts().map(|q| q.0)))
    else {
        return Ok(());
    };
    let mut chart = ChartBuilder::on(area);
    chart
        .caption(&p.title, ("sans-serif", 15))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(52);
    let y = (y0..y1).log_scale();
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    if p.log_x {
        let chart = chart.build_cartesian_2d((x0..x1).log_scale(), y);
        draw_series(&mut chart.map_err(e)?, p)
    } else {
        // f32 times end a hair past the whole second (30.0000016).
        let x1 = pts().map(|q| q.0).fold(0.0, f64::max);
        let x1 = (x1 - 1e-6 * x1.abs()).ceil().max(1.0);
        let x: RangedCoordf64 = (0.0..x1).into();
        draw_series(&mut chart.build_cartesian_2d(x, y).map_err(e)?, p)
    }
}

/// The panels in a grid of `cols` columns, each `size` pixels, as an SVG
/// document.
///
/// # Errors
/// plotters', as text.
pub fn svg(panels: &[Panel], cols: usize, size: (u32, u32)) -> Result<String, String> {
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (size.0 * cols as u32, size.1 * rows as u32));
        let root = root.into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        for (area, p) in root.split_evenly((rows, cols)).iter().zip(panels) {
            draw(area, p)?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}
