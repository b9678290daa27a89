//! `ladder.svg`, drawn with plotters: one panel per quantity of the join,
//! the error against ×native on log axes, one point per (scene, mode)
//! coloured by mode ([`kimpact_harness::color`], as every plot of this
//! package), the modes of a scene joined in ladder order by a grey line
//! (one dash style per scene) labelled with the scene, each noise floor a
//! dotted line. The legend is a strip under the title, outside the panels.
//! Every point is a `<circle>` of the SVG, and nothing else is.

use kimpact::Mode;
use kimpact_harness::{Method, color};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::LadderError;
use crate::join::{self, Join, Level, Point, QUANTITIES, SCENES, SceneRule};

/// One panel's size in pixels.
const PANEL: (u32, u32) = (560, 440);
/// The title and one row of legend above the panels.
const HEADER: u32 = 80;
/// A second row of legend.
const ROW: u32 = 22;
/// The scenes' lines and the noise floors.
const GREY: RGBColor = RGBColor(100, 100, 100);
const FLOOR: RGBColor = RGBColor(150, 150, 150);
const FLOOR_DASH: (i32, i32) = (2, 3);

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

fn plot_error<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> LadderError {
    LadderError::Plot(e.to_string())
}

/// The dashes of a scene's line (`None`: solid).
fn dash_of(scene: &SceneRule) -> Option<(i32, i32)> {
    (SCENES.iter().position(|s| s == scene) != Some(0)).then_some((7, 4))
}

/// The drawn value of a point's error whose axis starts at `bottom`.
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
    let (lo, hi) = if lo <= hi {
        (lo.floor(), hi.ceil().max(lo.floor() + 1.0))
    } else {
        (-3.0, 0.0)
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
    let steps = [1.0, 2.0, 5.0, 10.0].map(|m| m * magnitude);
    let step = steps
        .into_iter()
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * magnitude);
    let range = (lo / step).ceil() as i64..=(hi / step).floor() as i64;
    (range.map(|i| i as f64 * step).collect(), decimals(step))
}

/// A legend entry: a square (filled or hollow) or a line (solid or dashed)
/// of a colour, and its text.
type Entry = (RGBColor, Result<bool, Option<(i32, i32)>>, &'static str);

/// The legend: the modes, the scenes' lines and the noise floors (first
/// row), the hollow points (second row).
fn legend(join: &Join) -> [Vec<Entry>; 2] {
    let has = |f: &dyn Fn(&Point) -> bool| join.points.iter().any(f);
    let mut first: Vec<Entry> = Mode::ALL
        .into_iter()
        .filter(|m| has(&|p| p.mode == *m))
        .map(|m| (color(Method::Rapier(m)), Ok(true), m.name()))
        .collect();
    for s in SCENES.iter().filter(|s| has(&|p| p.scene == *s)) {
        first.push((GREY, Err(dash_of(s)), s.label));
    }
    if has(&|p| p.noise_floor.is_some_and(|f| f > 0.0)) {
        first.push((FLOOR, Err(Some(FLOOR_DASH)), "noise floor"));
    }
    let grey = RGBColor(80, 80, 80);
    let mut second = Vec::new();
    if has(&|p| matches!(p.level(), Level::AtFloor(_))) {
        second.push((
            grey,
            Ok(false),
            "hollow: at or below the noise floor, drawn at the floor",
        ));
    }
    if has(&|p| p.level() == Level::Zero) {
        second.push((
            grey,
            Ok(false),
            "hollow at the bottom: an error of 0, no noise floor",
        ));
    }
    [first, second]
}

/// A line from `(x0, y)` to `(x1, y)`, solid or dashed.
fn hline(
    area: &Area<'_>,
    (x0, x1, y): (i32, i32, i32),
    c: RGBColor,
    dash: Option<(i32, i32)>,
) -> Result<(), LadderError> {
    let (on, off) = dash.unwrap_or((x1 - x0, 0));
    let mut x = x0;
    while x < x1 {
        let end = (x + on).min(x1);
        area.draw(&PathElement::new(vec![(x, y), (end, y)], c.stroke_width(2)))
            .map_err(plot_error)?;
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
    let subtitle = format!(
        "{}, {}. × native: kimpact-bench, {} balls, CPU time per step. Error: kimpact-accuracy, against the exact reference at rapier's time step.",
        scenes.join(" and "),
        join::PRECISION,
        join::BALLS,
    );
    let title = "What accuracy costs: error against × native rapier";
    let w = area.dim_in_pixel().0 as i32;
    // sans-serif is about half as wide as it is tall
    let centre =
        |text: &str, size: f64| (w - (text.chars().count() as f64 * size * 0.5) as i32) / 2;
    let bold = ("sans-serif", 20).into_font().style(FontStyle::Bold);
    area.draw(&Text::new(title, (centre(title, 20.0), 8), bold))
        .map_err(plot_error)?;
    let at = (centre(&subtitle, 13.0).max(4), 34);
    area.draw(&Text::new(subtitle, at, ("sans-serif", 13)))
        .map_err(plot_error)?;
    for (row, y) in legend(join).iter().zip([58, 58 + ROW as i32]) {
        // sans-serif at 14 px: about 6.4 px per character
        let width = |(_, key, text): &Entry| {
            let marker = if key.is_ok() { 12 } else { 24 };
            (
                marker,
                marker + 24 + (text.chars().count() as f64 * 6.4) as i32,
            )
        };
        let mut x = ((w - row.iter().map(|e| width(e).1).sum::<i32>()) / 2).max(4);
        for entry in row {
            let (c, key, text) = *entry;
            match key {
                Ok(filled) => {
                    let style = if filled {
                        c.filled()
                    } else {
                        c.stroke_width(2)
                    };
                    area.draw(&Rectangle::new([(x, y), (x + 12, y + 12)], style))
                        .map_err(plot_error)?;
                }
                Err(dash) => hline(area, (x, x + 24, y + 6), c, dash)?,
            }
            let (marker, step) = width(entry);
            area.draw(&Text::new(
                text,
                (x + marker + 6, y - 1),
                ("sans-serif", 14),
            ))
            .map_err(plot_error)?;
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
    let x = (x0..x1).log_scale().with_key_points(xticks);
    let mut chart = ChartBuilder::on(area)
        .caption(label, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(44)
        .y_label_area_size(58)
        .build_cartesian_2d(x, (y0..y1).log_scale())
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .x_label_formatter(&|x| {
            let s = format!("{x:.decimals$}");
            if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.').to_owned()
            } else {
                s
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
    let circles = points.iter().map(|p| {
        let c = color(Method::Rapier(p.mode));
        let style = if matches!(p.level(), Level::Measured(_)) {
            c.filled()
        } else {
            c.stroke_width(2)
        };
        Circle::new((p.ratio, drawn(p, y0)), 5, style)
    });
    chart.draw_series(circles).map_err(plot_error)?;
    Ok(())
}

/// The ladder plot of `join` as an SVG document: one panel per quantity
/// with points, side by side, the x axis the same in all.
///
/// # Errors
/// plotters', as [`LadderError::Plot`].
pub fn svg(join: &Join) -> Result<String, LadderError> {
    let quantities: Vec<&str> = QUANTITIES
        .iter()
        .map(|q| q.1)
        .filter(|q| join.points.iter().any(|p| p.quantity == *q))
        .collect();
    let n = quantities.len().max(1) as u32;
    let ratios = join.points.iter().map(|p| p.ratio.log10());
    let (a, b) = ratios.fold((f64::MAX, f64::MIN), |(a, b), r| (a.min(r), b.max(r)));
    // A little room on the left, more on the right for the scenes' labels.
    let span = (b - a).max(0.05);
    let x = (10f64.powf(a - 0.08 * span), 10f64.powf(b + 0.3 * span));
    let top = HEADER + if legend(join)[1].is_empty() { 0 } else { ROW };
    let mut out = String::new();
    {
        let root =
            SVGBackend::with_string(&mut out, (PANEL.0 * n, top + PANEL.1)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let (head, body) = root.split_vertically(top);
        header(&head, join)?;
        for (area, q) in body.split_evenly((1, n as usize)).iter().zip(&quantities) {
            let points: Vec<&Point> = join.points.iter().filter(|p| p.quantity == *q).collect();
            panel(area, q, &points, x)?;
        }
        root.present().map_err(plot_error)?;
    }
    Ok(out)
}
