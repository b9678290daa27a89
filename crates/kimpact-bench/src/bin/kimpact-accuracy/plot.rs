//! `accuracy.svg`, drawn with plotters: one row of three panels per build
//! (the gas's energy error, one impact and the cradle against the CPU time
//! of the gas), then the cooling curves.

use std::collections::BTreeMap;

use kimpact_harness::{Method, color};
use plotters::coord::CoordTranslate;
use plotters::prelude::*;

/// A series' points.
type Points = Vec<(f64, f64)>;

/// One panel: a title, its axes and a series per simulator.
pub struct Panel {
    /// The panel's title (also its sort key).
    pub title: String,
    xlabel: String,
    ylabel: &'static str,
    logx: bool,
    series: Vec<(Method, Vec<(f64, f64)>)>,
}

/// The panels of the plot points `(panel title, simulator, x, y)`: the cost
/// panels of each build in a row (2D f32, 2D f64, 3D f32, 3D f64; the
/// gas's energy error, one impact, the cradle), then the cooling curves;
/// in each the simulators in their order. The cost runs' gas has
/// `gas_balls` balls.
pub fn panels(points: &[(String, Method, f64, f64)], gas_balls: usize) -> Vec<Panel> {
    let mut by_title: BTreeMap<&str, BTreeMap<Method, Points>> = BTreeMap::new();
    for (title, method, x, y) in points {
        by_title
            .entry(title)
            .or_default()
            .entry(*method)
            .or_default()
            .push((*x, *y));
    }
    let mut list: Vec<Panel> = by_title
        .into_iter()
        .map(|(title, series)| {
            let cooling = title.starts_with("cooling");
            Panel {
                title: title.to_owned(),
                xlabel: if cooling {
                    "time (s)".to_owned()
                } else {
                    format!("CPU seconds per simulated second ({gas_balls}-ball gas)")
                },
                ylabel: if cooling {
                    "kinetic energy / initial"
                } else {
                    "error"
                },
                logx: !cooling,
                series: series.into_iter().collect(),
            }
        })
        .collect();
    let rank = |t: &str| {
        ["gas energy", "one impact", "cradle", "cooling"]
            .iter()
            .position(|k| t.starts_with(k))
            .unwrap_or(9)
    };
    list.sort_by_key(|p| {
        let cooling = p.title.starts_with("cooling");
        let build = if cooling {
            (false, false)
        } else {
            (p.title.contains("3D"), p.title.contains("f64"))
        };
        (cooling, build, rank(&p.title), p.title.clone())
    });
    list
}

/// The decades that hold `values` (at least one).
fn decades(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values.fold((f64::MAX, f64::MIN), |(a, b), v| {
        (a.min(v.log10()), b.max(v.log10()))
    });
    (lo <= hi).then(|| {
        let lo = lo.floor();
        (10f64.powf(lo), 10f64.powf(hi.ceil().max(lo + 1.0)))
    })
}

/// The legend of a panel's series at `position`.
fn legend<'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, CT>,
    position: SeriesLabelPosition,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())
}

/// One panel into `area`.
fn draw(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    p: &Panel,
) -> Result<(), String> {
    let ok =
        |(x, y): &(f64, f64)| x.is_finite() && y.is_finite() && *y > 0.0 && (!p.logx || *x > 0.0);
    let pts: Vec<(f64, f64)> = p
        .series
        .iter()
        .flat_map(|s| s.1.iter().copied())
        .filter(ok)
        .collect();
    let Some((y0, y1)) = decades(pts.iter().map(|q| q.1)) else {
        return Ok(());
    };
    let err = |e: DrawingAreaErrorKind<_>| e.to_string();
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(&p.title, ("sans-serif", 15))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(52);
    let y_fmt = |y: &f64| format!("{y:.0e}");
    if p.logx {
        let Some((x0, x1)) = decades(pts.iter().map(|q| q.0)) else {
            return Ok(());
        };
        let mut chart = builder
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(err)?;
        chart
            .configure_mesh()
            .light_line_style(WHITE.mix(0.0))
            .x_label_formatter(&|x| format!("{x:.0e}"))
            .y_label_formatter(&y_fmt)
            .x_desc(&p.xlabel)
            .y_desc(p.ylabel)
            .draw()
            .map_err(err)?;
        for (method, series) in &p.series {
            let c = color(*method);
            let pts: Vec<(f64, f64)> = series.iter().copied().filter(ok).collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                .map_err(err)?
                .label(method.name())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                });
            chart
                .draw_series(pts.into_iter().map(|q| Circle::new(q, 3, c.filled())))
                .map_err(err)?;
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    } else {
        let x1 = pts.iter().map(|q| q.0).fold(0.0, f64::max);
        // f32 times end a hair past the whole second (30.0000016).
        let x1 = (x1 - 1e-6 * x1.abs()).ceil().max(1.0);
        let mut chart = builder
            .build_cartesian_2d(0.0..x1, (y0..y1).log_scale())
            .map_err(err)?;
        chart
            .configure_mesh()
            .light_line_style(WHITE.mix(0.0))
            .y_label_formatter(&y_fmt)
            .x_desc(&p.xlabel)
            .y_desc(p.ylabel)
            .draw()
            .map_err(err)?;
        for (method, series) in &p.series {
            let c = color(*method);
            let pts: Vec<(f64, f64)> = series.iter().copied().filter(ok).collect();
            chart
                .draw_series(LineSeries::new(pts, c.stroke_width(2)))
                .map_err(err)?
                .label(method.name())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                });
        }
        legend(&mut chart, SeriesLabelPosition::LowerLeft)?;
    }
    Ok(())
}

/// The panels in a grid of `cols` columns, as an SVG document.
///
/// # Errors
/// plotters', as text.
pub fn svg(panels: &[Panel], cols: usize) -> Result<String, String> {
    let (pw, ph) = (460u32, 320u32);
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (pw * cols as u32, ph * rows as u32))
            .into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let areas = root.split_evenly((rows, cols));
        for (area, p) in areas.iter().zip(panels) {
            draw(area, p)?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}
