//! `ladder.svg`, drawn with plotters: one panel per quantity of the join,
//! the error against ×native on log axes, one point per (scene, mode)
//! coloured by mode ([`kimpact_harness::color`], as every plot of this
//! package), the modes of a scene joined in ladder order by a grey line
//! (one dash style per scene) labelled with the scene at its last mode,
//! each noise floor as a dotted line. The legend is a strip under the
//! title, outside the panels. Every point is a `<circle>` of the SVG, and
//! nothing else is.

use kimpact::Mode;
use kimpact_harness::{Method, color};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::LadderError;
use crate::join::{self, Join, Level, Point, QUANTITIES, SCENES, SceneRule};

/// One panel's size in pixels.
const PANEL: (u32, u32) = (560, 440);
/// The title and the legend above the panels (one row of legend; a second
/// row adds [`ROW`]).
const HEADER: u32 = 80;
/// A row of the legend.
const ROW: u32 = 22;
/// The lines' and the noise floors' greys.
const GREY: RGBColor = RGBColor(100, 100, 100);
const FLOOR: RGBColor = RGBColor(150, 150, 150);
/// The dashes of each scene's line (`None`: solid) and of a noise floor.
const DASHES: [Option<(i32, i32)>; 2] = [None, Some((7, 4))];
const FLOOR_DASH: (i32, i32) = (2, 3);

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

fn plot_error<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> LadderError {
    LadderError::Plot(e.to_string())
}

/// The dashes of a scene's line.
fn dash_of(scene: &SceneRule) -> Option<(i32, i32)> {
    let i = SCENES.iter().position(|s| s == scene).unwrap_or(0);
    DASHES[i % DASHES.len()]
}

/// The drawn value of an error whose axis starts at `bottom`.
fn drawn(p: &Point, bottom: f64) -> f64 {
    match p.level() {
        Level::Measured(v) | Level::AtFloor(v) => v,
        Level::Zero => bottom,
    }
}

/// The whole decades holding the positive `values` (one more below when
/// `zero` points go at the bottom; 10⁻³ to 1 when there is none), widened
/// by 4% at each end so that no point sits on the frame.
fn y_range(values: impl Iterator<Item = f64>, zero: bool) -> (f64, f64) {
    let (lo, hi) = values
        .map(f64::log10)
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = match lo <= hi {
        true => (lo.floor(), hi.ceil().max(lo.floor() + 1.0)),
        false => (-3.0, 0.0),
    };
    let lo = if zero { lo - 1.0 } else { lo };
    let pad = 0.04 * (hi - lo);
    (10f64.powf(lo - pad), 10f64.powf(hi + pad))
}

/// Round ticks in `lo..=hi` and their decimals: 1, 2 and 5 per decade over
/// a decade or more, else the multiples of a round step (0.05, 0.1, 0.2…)
/// that give at most 8 ticks.
fn ticks(lo: f64, hi: f64) -> (Vec<f64>, usize) {
    let decimals = |step: f64| (-(step.log10().floor())).max(0.0) as usize;
    if hi / lo >= 10.0 {
        let decades = (lo.log10().floor() as i32)..=(hi.log10().ceil() as i32);
        let all = decades.flat_map(|k| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k)));
        return (
            all.filter(|v| (lo..=hi).contains(v)).collect(),
            decimals(lo),
        );
    }
    let raw = (hi - lo) / 8.0;
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .map(|m| m * magnitude)
        .into_iter()
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * magnitude);
    let range = (lo / step).ceil() as i64..=(hi / step).floor() as i64;
    (range.map(|i| i as f64 * step).collect(), decimals(step))
}

/// A legend entry's marker.
enum Key {
    /// A square of the colour, filled or hollow.
    Square(RGBColor, bool),
    /// A line of the colour, solid or dashed.
    Line(RGBColor, Option<(i32, i32)>),
}

/// The legend: the modes, the scenes' lines and the noise floors (first
/// row), the hollow points (second row).
fn legend(join: &Join) -> [Vec<(Key, &'static str)>; 2] {
    let modes = Mode::ALL.into_iter();
    let mut first: Vec<_> = modes
        .filter(|m| join.points.iter().any(|p| p.mode == *m))
        .map(|m| (Key::Square(color(Method::Rapier(m)), true), m.name()))
        .collect();
    for s in SCENES
        .iter()
        .filter(|s| join.points.iter().any(|p| p.scene == *s))
    {
        first.push((Key::Line(GREY, dash_of(s)), s.label));
    }
    let levels: Vec<Level> = join.points.iter().map(Point::level).collect();
    if join
        .points
        .iter()
        .any(|p| p.noise_floor.is_some_and(|f| f > 0.0))
    {
        first.push((Key::Line(FLOOR, Some(FLOOR_DASH)), "noise floor"));
    }
    let mut second = Vec::new();
    let grey = Key::Square(RGBColor(80, 80, 80), false);
    if levels.iter().any(|l| matches!(l, Level::AtFloor(_))) {
        second.push((
            grey,
            "hollow: at or below the noise floor, drawn at the floor",
        ));
    }
    if levels.contains(&Level::Zero) {
        let grey = Key::Square(RGBColor(80, 80, 80), false);
        second.push((grey, "hollow at the bottom: an error of 0, no noise floor"));
    }
    [first, second]
}

/// A line from `(x0, y)` to `(x1, y)`, solid or dashed.
fn hline(area: &Area<'_>, (x0, x1, y): (i32, i32, i32), key: &Key) -> Result<(), LadderError> {
    let Key::Line(c, dash) = key else {
        return Ok(());
    };
    let (on, off) = dash.unwrap_or((x1 - x0, 0));
    let mut x = x0;
    while x < x1 {
        let end = (x + on).min(x1);
        let segment = PathElement::new(vec![(x, y), (end, y)], c.stroke_width(2));
        area.draw(&segment).map_err(plot_error)?;
        x = end + off;
    }
    Ok(())
}

/// The title, the line under it and the legend into `area`.
fn header(area: &Area<'_>, join: &Join) -> Result<(), LadderError> {
    let scenes: Vec<&str> = SCENES
        .iter()
        .filter(|s| join.points.iter().any(|p| p.scene == *s))
        .map(|s| s.label)
        .collect();
    let lines = [
        (
            "What accuracy costs: error against × native rapier".to_owned(),
            20.0,
        ),
        (
            format!(
                "{}, {}. × native: kimpact-bench, {} balls, CPU time per step. Error: kimpact-accuracy, against the exact reference at rapier's time step.",
                scenes.join(" and "),
                join::PRECISION,
                join::BALLS,
            ),
            13.0,
        ),
    ];
    let (w, _) = area.dim_in_pixel();
    // sans-serif is about half as wide as it is tall
    let centre =
        |text: &str, size: f64| (w as f64 - text.chars().count() as f64 * size * 0.5) / 2.0;
    for ((text, size), y) in lines.iter().zip([8, 34]) {
        let font = ("sans-serif", *size).into_font();
        let font = if y == 8 {
            font.style(FontStyle::Bold)
        } else {
            font
        };
        let at = (centre(text, *size).max(4.0) as i32, y);
        area.draw(&Text::new(text.clone(), at, font))
            .map_err(plot_error)?;
    }
    for (row, y) in legend(join).iter().zip([58, 58 + ROW as i32]) {
        // sans-serif at 14 px: about 6.4 px per character
        let width = |key: &Key, t: &str| {
            let marker = if matches!(key, Key::Line(..)) { 24 } else { 12 };
            (
                marker,
                marker + 6 + (t.chars().count() as f64 * 6.4) as i32 + 18,
            )
        };
        let total: i32 = row.iter().map(|(k, t)| width(k, t).1).sum();
        let mut x = ((w as i32 - total) / 2).max(4);
        for (key, text) in row {
            match key {
                Key::Square(c, filled) => {
                    let style = if *filled {
                        c.filled()
                    } else {
                        c.stroke_width(2)
                    };
                    let square = Rectangle::new([(x, y), (x + 12, y + 12)], style);
                    area.draw(&square).map_err(plot_error)?;
                }
                Key::Line(..) => hline(area, (x, x + 24, y + 6), key)?,
            }
            let (marker, step) = width(key, text);
            let label = Text::new(*text, (x + marker + 6, y - 1), ("sans-serif", 14));
            area.draw(&label).map_err(plot_error)?;
            x += step;
        }
    }
    Ok(())
}

/// One quantity's panel into `area`, its x axis `x0..x1`.
fn panel(
    area: &Area<'_>,
    label: &str,
    points: &[&Point],
    (x0, x1): (f64, f64),
) -> Result<(), LadderError> {
    let zero = points.iter().any(|p| p.level() == Level::Zero);
    let values = points.iter().filter_map(|p| match p.level() {
        Level::Measured(v) | Level::AtFloor(v) => Some(v),
        Level::Zero => None,
    });
    let floors = points
        .iter()
        .filter_map(|p| p.noise_floor.filter(|f| *f > 0.0));
    let (y0, y1) = y_range(values.chain(floors), zero);
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
        .x_label_formatter(&|x| {
            let s = format!("{x:.decimals$}");
            match s.contains('.') {
                true => s.trim_end_matches('0').trim_end_matches('.').to_owned(),
                false => s,
            }
        })
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
        let mut floors: Vec<f64> = series
            .iter()
            .filter_map(|p| p.noise_floor.filter(|f| *f > 0.0))
            .collect();
        floors.sort_by(f64::total_cmp);
        floors.dedup();
        for f in floors {
            let (on, off) = FLOOR_DASH;
            let line = DashedLineSeries::new([(x0, f), (x1, f)], on, off, FLOOR.stroke_width(1));
            chart.draw_series(line).map_err(plot_error)?;
        }
        let line: Vec<(f64, f64)> = series.iter().map(|p| (p.ratio, drawn(p, y0))).collect();
        let style = GREY.stroke_width(1);
        match dash_of(scene) {
            None => chart.draw_series(LineSeries::new(line, style)),
            Some((on, off)) => chart.draw_series(DashedLineSeries::new(line, on, off, style)),
        }
        .map_err(plot_error)?;
        let font = ("sans-serif", 13).into_font().color(&GREY);
        let name =
            EmptyElement::at((last.ratio, drawn(last, y0))) + Text::new(scene.label, (9, -6), font);
        chart.draw_series([name]).map_err(plot_error)?;
    }
    chart
        .draw_series(points.iter().map(|p| {
            let c = color(Method::Rapier(p.mode));
            let style = match p.level() {
                Level::Measured(_) => c.filled(),
                Level::AtFloor(_) | Level::Zero => c.stroke_width(2),
            };
            Circle::new((p.ratio, drawn(p, y0)), 5, style)
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
    // A little room on the left, more on the right for the scenes' labels.
    let (a, b) = (lo.log10(), hi.log10());
    let span = (b - a).max(0.05);
    let x = (10f64.powf(a - 0.08 * span), 10f64.powf(b + 0.3 * span));
    let two_rows = !legend(join)[1].is_empty();
    let top = HEADER + if two_rows { ROW } else { 0 };
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (PANEL.0 * n, top + PANEL.1));
        let root = root.into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let (head, body) = root.split_vertically(top);
        header(&head, join)?;
        for (area, q) in body.split_evenly((1, n as usize)).iter().zip(&quantities) {
            let points: Vec<&Point> = join.points.iter().filter(|p| p.quantity == *q).collect();
            panel(area, q.label, &points, x)?;
        }
        root.present().map_err(plot_error)?;
    }
    Ok(out)
}
