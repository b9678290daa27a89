//! `ladder.svg`, drawn with plotters: one panel per quantity of the join,
//! the error against ×native on log axes, one point per (scene, mode)
//! coloured by mode (the colours of every plot of this package,
//! [`kimpact_harness::color`]), the modes of a scene joined in ladder order
//! by a grey line (solid, dashed…, one style per scene) labelled with the
//! scene at its last mode, each scene's noise floor as a dotted line. The
//! legend is a strip under the title, outside the panels, so that it
//! covers no point. Every point is a `<circle>` of the SVG, and nothing
//! else is.

use kimpact::Mode;
use kimpact_harness::{Method, color};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::LadderError;
use crate::join::{self, Join, Level, Point, QUANTITIES, SCENES, SceneRule};

/// One panel's size in pixels.
const PANEL: (u32, u32) = (560, 440);
/// The title's and the legend's first row above the panels.
const HEADER: u32 = 80;
/// The legend's second row (the hollow points' entries), when drawn.
const SECOND_ROW: u32 = 22;
/// The points' radius in pixels.
const RADIUS: i32 = 5;
/// The line joining a scene's modes, by scene: its grey and its dashes
/// (`None`: solid; else dash and gap in pixels).
const LINES: [(RGBColor, Option<(i32, i32)>); 2] = [
    (RGBColor(100, 100, 100), None),
    (RGBColor(100, 100, 100), Some((7, 4))),
];
/// The dashes of a noise floor's line.
const FLOOR_DASH: (i32, i32) = (2, 3);
/// The noise floors' grey.
const FLOOR: RGBColor = RGBColor(150, 150, 150);

/// plotters' error as the ladder's.
fn plot_error<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> LadderError {
    LadderError::Plot(e.to_string())
}

/// The line style of a scene.
fn line_of(scene: &SceneRule) -> (RGBColor, Option<(i32, i32)>) {
    let i = SCENES.iter().position(|s| s == scene).unwrap_or(0);
    LINES[i % LINES.len()]
}

/// The drawn value of an error whose axis starts at `bottom`.
fn drawn(p: &Point, bottom: f64) -> f64 {
    match p.level() {
        Level::Measured(v) | Level::AtFloor(v) => v,
        Level::Zero => bottom,
    }
}

/// The decades holding the positive `values` (one more below when `zero`
/// points go at the bottom; 10⁻³ to 1 when there is none), widened by 4%
/// at each end so that no point sits on the frame.
fn y_range(values: impl Iterator<Item = f64>, zero: bool) -> (f64, f64) {
    let (lo, hi) = values
        .map(f64::log10)
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = if lo <= hi {
        let lo = lo.floor();
        (lo, hi.ceil().max(lo + 1.0))
    } else {
        (-3.0, 0.0)
    };
    let lo = if zero { lo - 1.0 } else { lo };
    let pad = 0.04 * (hi - lo);
    (10f64.powf(lo - pad), 10f64.powf(hi + pad))
}

/// The x range around the ratios `lo..hi` (log scale): a little room on
/// the left, more on the right for the scenes' labels.
fn x_range(lo: f64, hi: f64) -> (f64, f64) {
    let (a, b) = (lo.log10(), hi.log10());
    let span = (b - a).max(0.05);
    (10f64.powf(a - 0.08 * span), 10f64.powf(b + 0.3 * span))
}

/// Round tick values in `lo..=hi` and their decimals: 1, 2 and 5 per decade
/// over a decade or more, else the multiples of a round step (0.05, 0.1,
/// 0.2…) that give at most 8 ticks.
fn ticks(lo: f64, hi: f64) -> (Vec<f64>, usize) {
    if hi / lo >= 10.0 {
        let mut out = Vec::new();
        for k in (lo.log10().floor() as i32)..=(hi.log10().ceil() as i32) {
            for m in [1.0, 2.0, 5.0] {
                let v = m * 10f64.powi(k);
                if (lo..=hi).contains(&v) {
                    out.push(v);
                }
            }
        }
        let decimals = (-(lo.log10().floor())).max(0.0) as usize;
        return (out, decimals);
    }
    let raw = (hi - lo) / 8.0;
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * magnitude)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * magnitude);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    let out = (first..=last).map(|i| i as f64 * step).collect();
    let decimals = (-(step.log10().floor())).max(0.0) as usize;
    (out, decimals)
}

/// A tick's label: `decimals` places, without trailing zeros.
fn tick_label(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

/// The figure's title and the line under it, from the join's rules.
fn titles(join: &Join) -> (String, String) {
    let scenes: Vec<&str> = SCENES
        .iter()
        .filter(|s| join.points.iter().any(|p| p.scene == *s))
        .map(|s| s.label)
        .collect();
    let step = if join::DT_DIV == 1 {
        "rapier's time step".to_owned()
    } else {
        format!("rapier's time step / {}", join::DT_DIV)
    };
    (
        "What accuracy costs: error against × native rapier".to_owned(),
        format!(
            "{}, {}. × native: kimpact-bench, {} balls, CPU time per step. Error: kimpact-accuracy, against the exact reference at {step}.",
            scenes.join(" and "),
            join::PRECISION,
            join::BALLS,
        ),
    )
}

/// The legend's entries, each a marker and its text.
type Entries = Vec<(Key, String)>;

/// One legend entry's marker.
enum Key {
    /// A filled square of the colour.
    Filled(RGBColor),
    /// A hollow square of the colour.
    Hollow(RGBColor),
    /// A line of the colour, solid or dashed.
    Line(RGBColor, Option<(i32, i32)>),
}

/// A horizontal line from `x0` to `x1` at `y` into `area`, solid or dashed.
fn hline(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    (x0, x1, y): (i32, i32, i32),
    dash: Option<(i32, i32)>,
    style: ShapeStyle,
) -> Result<(), LadderError> {
    let (on, off) = dash.unwrap_or((x1 - x0, 0));
    let mut x = x0;
    while x < x1 {
        let end = (x + on).min(x1);
        area.draw(&PathElement::new(vec![(x, y), (end, y)], style))
            .map_err(plot_error)?;
        x = end + off;
    }
    Ok(())
}

/// One row of legend entries, centred, at `y` in `area`.
fn legend_row(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    entries: &[(Key, String)],
    y: i32,
) -> Result<(), LadderError> {
    const GAP: i32 = 18;
    let marker = |k: &Key| if matches!(k, Key::Line(..)) { 24 } else { 12 };
    // sans-serif at 14 px: about 6.4 px per character
    let text_width = |t: &str| (t.chars().count() as f64 * 6.4) as i32;
    let width: i32 = entries
        .iter()
        .map(|(k, t)| marker(k) + 6 + text_width(t) + GAP)
        .sum();
    let (w, _) = area.dim_in_pixel();
    let mut x = ((w as i32 - width) / 2).max(4);
    for (key, text) in entries {
        match key {
            Key::Filled(c) => area
                .draw(&Rectangle::new([(x, y), (x + 12, y + 12)], c.filled()))
                .map_err(plot_error)?,
            Key::Hollow(c) => area
                .draw(&Rectangle::new(
                    [(x, y), (x + 12, y + 12)],
                    c.stroke_width(2),
                ))
                .map_err(plot_error)?,
            Key::Line(c, dash) => hline(area, (x, x + 24, y + 6), *dash, c.stroke_width(2))?,
        }
        let tx = x + marker(key) + 6;
        area.draw(&Text::new(text.clone(), (tx, y - 1), ("sans-serif", 14)))
            .map_err(plot_error)?;
        x = tx + text_width(text) + GAP;
    }
    Ok(())
}

/// The legend's entries: the modes, the scenes' lines and the noise
/// floors' (first row); the hollow points' (second row).
fn legend(join: &Join) -> (Entries, Entries) {
    let mut first: Entries = Mode::ALL
        .into_iter()
        .filter(|m| join.points.iter().any(|p| p.mode == *m))
        .map(|m| (Key::Filled(color(Method::Rapier(m))), m.name().to_owned()))
        .collect();
    for scene in SCENES
        .iter()
        .filter(|s| join.points.iter().any(|p| p.scene == *s))
    {
        let (c, dash) = line_of(scene);
        first.push((Key::Line(c, dash), scene.label.to_owned()));
    }
    if join
        .points
        .iter()
        .any(|p| p.noise_floor.is_some_and(|f| f > 0.0))
    {
        first.push((Key::Line(FLOOR, Some(FLOOR_DASH)), "noise floor".to_owned()));
    }
    let mut second = Vec::new();
    let grey = RGBColor(80, 80, 80);
    let levels: Vec<Level> = join.points.iter().map(Point::level).collect();
    if levels.iter().any(|l| matches!(l, Level::AtFloor(_))) {
        second.push((
            Key::Hollow(grey),
            "hollow: at or below the noise floor, drawn at the floor".to_owned(),
        ));
    }
    if levels.contains(&Level::Zero) {
        second.push((
            Key::Hollow(grey),
            "hollow at the bottom: an error of 0, no noise floor".to_owned(),
        ));
    }
    (first, second)
}

/// The title, the subtitle and the legend into `area`.
fn header(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    join: &Join,
    legend: &(Entries, Entries),
) -> Result<(), LadderError> {
    let (title, subtitle) = titles(join);
    let (w, _) = area.dim_in_pixel();
    let centre = |text: &str, size: f64| {
        // sans-serif is about half as wide as it is tall
        (w as i32 - (text.chars().count() as f64 * size * 0.5) as i32) / 2
    };
    area.draw(&Text::new(
        title.clone(),
        (centre(&title, 20.0), 8),
        ("sans-serif", 20).into_font().style(FontStyle::Bold),
    ))
    .map_err(plot_error)?;
    area.draw(&Text::new(
        subtitle.clone(),
        (centre(&subtitle, 13.0).max(4), 34),
        ("sans-serif", 13),
    ))
    .map_err(plot_error)?;
    legend_row(area, &legend.0, 58)?;
    legend_row(area, &legend.1, 58 + SECOND_ROW as i32)
}

/// One quantity's panel into `area`, its x axis `x0..x1`.
fn panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    label: &str,
    points: &[&Point],
    (x0, x1): (f64, f64),
) -> Result<(), LadderError> {
    let zero = points.iter().any(|p| p.level() == Level::Zero);
    let floors = points
        .iter()
        .filter_map(|p| p.noise_floor.filter(|f| *f > 0.0));
    let (y0, y1) = y_range(
        points
            .iter()
            .filter_map(|p| match p.level() {
                Level::Measured(v) | Level::AtFloor(v) => Some(v),
                Level::Zero => None,
            })
            .chain(floors),
        zero,
    );
    let (xticks, decimals) = ticks(x0, x1);
    let mut chart = ChartBuilder::on(area)
        .caption(label, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(44)
        .y_label_area_size(58)
        .build_cartesian_2d(
            (x0..x1).log_scale().with_key_points(xticks),
            (y0..y1).log_scale(),
        )
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .x_label_formatter(&|x| tick_label(*x, decimals))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .x_desc("× native rapier (time per step)")
        .y_desc("error")
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(plot_error)?;
    for scene in &SCENES {
        let mut series: Vec<&Point> = points
            .iter()
            .copied()
            .filter(|p| p.scene == scene)
            .collect();
        series.sort_by_key(|p| p.mode);
        let Some(last) = series.last() else {
            continue;
        };
        let (grey, dash) = line_of(scene);
        let mut floors: Vec<f64> = series
            .iter()
            .filter_map(|p| p.noise_floor.filter(|f| *f > 0.0))
            .collect();
        floors.sort_by(f64::total_cmp);
        floors.dedup();
        for f in floors {
            chart
                .draw_series(DashedLineSeries::new(
                    [(x0, f), (x1, f)],
                    FLOOR_DASH.0,
                    FLOOR_DASH.1,
                    FLOOR.stroke_width(1),
                ))
                .map_err(plot_error)?;
        }
        let line: Vec<(f64, f64)> = series.iter().map(|p| (p.ratio, drawn(p, y0))).collect();
        let style = grey.stroke_width(1);
        match dash {
            None => chart.draw_series(LineSeries::new(line, style)),
            Some((on, off)) => chart.draw_series(DashedLineSeries::new(line, on, off, style)),
        }
        .map_err(plot_error)?;
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((last.ratio, drawn(last, y0)))
                    + Text::new(
                        scene.label,
                        (9, -6),
                        ("sans-serif", 13).into_font().color(&grey),
                    ),
            ))
            .map_err(plot_error)?;
    }
    chart
        .draw_series(points.iter().map(|p| {
            let c = color(Method::Rapier(p.mode));
            let style = match p.level() {
                Level::Measured(_) => c.filled(),
                Level::AtFloor(_) | Level::Zero => c.stroke_width(2),
            };
            Circle::new((p.ratio, drawn(p, y0)), RADIUS, style)
        }))
        .map_err(plot_error)?;
    Ok(())
}

/// The ladder plot of `join` as an SVG document: one panel per quantity
/// with points, side by side, the x axis the same in all.
///
/// # Errors
/// plotters', as [`LadderError::Plot`].
pub fn svg(join: &Join) -> Result<String, LadderError> {
    let quantities: Vec<_> = QUANTITIES
        .iter()
        .filter(|q| join.points.iter().any(|p| p.quantity == *q))
        .collect();
    let n = quantities.len().max(1) as u32;
    let (lo, hi) = join.points.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
        (a.min(p.ratio), b.max(p.ratio))
    });
    let x = x_range(lo, hi);
    let legend = legend(join);
    let top = HEADER + if legend.1.is_empty() { 0 } else { SECOND_ROW };
    let mut out = String::new();
    {
        let root =
            SVGBackend::with_string(&mut out, (PANEL.0 * n, top + PANEL.1)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let (head, body) = root.split_vertically(top);
        header(&head, join, &legend)?;
        let areas = body.split_evenly((1, n as usize));
        for (area, q) in areas.iter().zip(&quantities) {
            let points: Vec<&Point> = join.points.iter().filter(|p| p.quantity == *q).collect();
            panel(area, q.label, &points, x)?;
        }
        root.present().map_err(plot_error)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_inside_the_range() {
        let (t, d) = ticks(0.93, 1.9);
        assert_eq!(d, 1);
        assert_eq!(t.first().copied(), Some(1.0));
        assert!(t.iter().all(|v| (0.93..=1.9).contains(v)));
        assert!(t.len() >= 4 && t.len() <= 9, "{t:?}");
        let (t, d) = ticks(0.5, 30.0);
        assert_eq!(t, vec![0.5, 1.0, 2.0, 5.0, 10.0, 20.0]);
        assert_eq!(d, 1);
        assert_eq!(tick_label(20.0, 1), "20");
        assert_eq!(tick_label(1.2000000001, 1), "1.2");
        assert_eq!(tick_label(0.5, 1), "0.5");
    }

    #[test]
    fn the_y_range_holds_every_value_in_whole_decades() {
        let decades = |(lo, hi): (f64, f64)| (lo.log10(), hi.log10());
        let close =
            |(a, b): (f64, f64), (c, d): (f64, f64)| (a - c).abs() < 1e-9 && (b - d).abs() < 1e-9;
        // six decades, 4% of them (0.24) beyond each end
        assert!(close(
            decades(y_range([3e-6, 0.9].into_iter(), false)),
            (-6.24, 0.24)
        ));
        // a decade more below for the zeros
        assert!(close(
            decades(y_range([0.004].into_iter(), true)),
            (-4.08, -1.92)
        ));
        assert!(close(
            decades(y_range(std::iter::empty(), false)),
            (-3.12, 0.12)
        ));
    }
}
