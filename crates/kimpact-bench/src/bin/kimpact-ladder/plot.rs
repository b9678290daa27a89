//! `ladder.svg`: one panel per quantity, the error against ×native on log
//! axes, a point per (scene, mode) coloured by mode, a scene's modes joined
//! by a grey line, each noise floor dotted. Every point is a `<circle>` of
//! the SVG, and nothing else is (the legend's markers are squares).

use kimpact::Mode;
use kimpact_harness::{Method, color, decimal, legend};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::join::{BALLS, Join, Level, PRECISION, Point, QUANTITIES, SCENES};

/// The scenes' lines and the noise floors.
const GREY: RGBColor = RGBColor(100, 100, 100);
const FLOOR: RGBColor = RGBColor(150, 150, 150);

/// The drawn value of a point's error whose axis starts at `bottom`.
fn drawn(p: &Point, bottom: f64) -> f64 {
    match p.level() {
        Level::Measured(v) | Level::AtFloor(v) => v,
        Level::Zero => bottom,
    }
}

/// Round ticks in `lo..=hi` and their decimals: the multiples of a round
/// step (0.05, 0.1, 0.2…) that give at most 8 ticks, or 1, 2 and 5 per
/// decade over a decade or more.
fn ticks(lo: f64, hi: f64) -> (Vec<f64>, usize) {
    let decimals = |step: f64| (-(step.log10().floor())).max(0.0) as usize;
    if hi / lo >= 10.0 {
        let decades = (lo.log10().floor() as i32)..=(hi.log10().ceil() as i32);
        let all = decades.flat_map(|k| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k)));
        let ticks = all.filter(|v| (lo..=hi).contains(v)).collect();
        return (ticks, decimals(lo));
    }
    let raw = (hi - lo) / 8.0;
    let magnitude = 10f64.powf(raw.log10().floor());
    let steps = [1.0, 2.0, 5.0, 10.0].map(|m| m * magnitude);
    let step = steps.into_iter().find(|s| *s >= raw);
    let step = step.unwrap_or(10.0 * magnitude);
    let range = (lo / step).ceil() as i64..=(hi / step).floor() as i64;
    (range.map(|i| i as f64 * step).collect(), decimals(step))
}

/// The y axis of `points`: the whole decades of the errors and floors (one
/// more below for the zeros), 4% wider at each end.
fn y_axis(points: &[&Point]) -> (f64, f64) {
    let floors = points.iter().filter_map(|p| p.noise_floor);
    let values = points.iter().map(|p| drawn(p, f64::NAN)).chain(floors);
    let logs = values.filter(|v| *v > 0.0).map(f64::log10);
    let (lo, hi) = logs.fold((0.0f64, -3.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let zeros = points.iter().any(|p| p.level() == Level::Zero);
    let (lo, hi) = (lo.floor() - f64::from(zeros), hi.ceil());
    let margin = 0.04 * (hi - lo);
    (10f64.powf(lo - margin), 10f64.powf(hi + margin))
}

/// One quantity's panel into `area`, its x axis `x0..x1`; the legend in
/// its upper right corner (no mode is both costly and inaccurate).
fn panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    label: &str,
    points: &[&Point],
    (x0, x1): (f64, f64),
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    let (y0, y1) = y_axis(points);
    let (xticks, decimals) = ticks(x0, x1);
    let x = (x0..x1).log_scale().with_key_points(xticks);
    let mut chart = ChartBuilder::on(area)
        .caption(label, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(44)
        .y_label_area_size(58)
        .build_cartesian_2d(x, (y0..y1).log_scale())
        .map_err(e)?;
    chart
        .configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08))
        .x_label_formatter(&|x| decimal(*x, decimals))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .x_desc("× native rapier (time per step)")
        .y_desc("error")
        .draw()
        .map_err(e)?;
    let floors = points.iter().filter_map(|p| p.noise_floor);
    let mut floors: Vec<f64> = floors.filter(|f| *f > 0.0).collect();
    floors.sort_by(f64::total_cmp);
    floors.dedup();
    for (i, f) in floors.into_iter().enumerate() {
        let line = DashedLineSeries::new([(x0, f), (x1, f)], 2, 3, FLOOR.stroke_width(1));
        let drawn = chart.draw_series(line).map_err(e)?;
        if i == 0 {
            drawn
                .label("noise floor")
                .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], FLOOR));
        }
    }
    for (i, scene) in SCENES.iter().enumerate() {
        let mut line: Vec<&&Point> = points.iter().filter(|p| p.scene == scene).collect();
        line.sort_by_key(|p| p.mode);
        let Some(last) = line.last() else {
            continue;
        };
        let at = (last.ratio, drawn(last, y0));
        let line: Vec<(f64, f64)> = line.iter().map(|p| (p.ratio, drawn(p, y0))).collect();
        let style = GREY.stroke_width(1);
        match i {
            0 => chart.draw_series(LineSeries::new(line, style)),
            _ => chart.draw_series(DashedLineSeries::new(line, 7, 4, style)),
        }
        .map_err(e)?;
        let font = ("sans-serif", 13).into_font().color(&GREY);
        chart
            .draw_series([EmptyElement::at(at) + Text::new(scene.2, (9, -6), font)])
            .map_err(e)?;
    }
    for mode in Mode::ALL {
        let c = color(Method::Rapier(mode));
        let mine = points.iter().filter(|p| p.mode == mode);
        let dots = mine.map(|p| {
            let style = if matches!(p.level(), Level::Measured(_)) {
                c.filled()
            } else {
                c.stroke_width(2)
            };
            Circle::new((p.ratio, drawn(p, y0)), 5, style)
        });
        let drawn = chart.draw_series(dots).map_err(e)?;
        drawn
            .label(mode.name())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], c.filled()));
    }
    legend(&mut chart, SeriesLabelPosition::UpperRight)
}

/// The ladder plot of `join` as an SVG document: a title, then one panel
/// per quantity with points, side by side, the x axis the same in all.
///
/// # Errors
/// plotters', as text.
pub fn svg(join: &Join) -> Result<String, String> {
    let quantities: Vec<&str> = QUANTITIES
        .iter()
        .map(|q| q.1)
        .filter(|q| join.points.iter().any(|p| p.quantity == *q))
        .collect();
    let ratios = join.points.iter().map(|p| p.ratio.log10());
    let (a, b) = ratios.fold((f64::MAX, f64::MIN), |(a, b), r| (a.min(r), b.max(r)));
    // A little room on the left, more on the right for the scenes' labels.
    let span = (b - a).max(0.05);
    let x = (10f64.powf(a - 0.08 * span), 10f64.powf(b + 0.3 * span));
    let mut out = String::new();
    {
        let n = quantities.len().max(1);
        let root = SVGBackend::with_string(&mut out, (560 * n as u32, 520)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let title = "What accuracy costs: error against × native rapier";
        let root = root.titled(title, ("sans-serif", 20));
        let root = root.map_err(|e| e.to_string())?;
        let (head, body) = root.split_vertically(40);
        let subtitle = format!(
            "{PRECISION}. × native: kimpact-bench, {BALLS} balls, CPU time per step. Error: kimpact-accuracy, against the exact reference at rapier's time step. Hollow: at or below the noise floor (drawn at it), or 0 (at the bottom)."
        );
        let style = ("sans-serif", 13).into_text_style(&head);
        let style = style.pos(Pos::new(HPos::Center, VPos::Top));
        let at = ((head.dim_in_pixel().0 / 2) as i32, 4);
        head.draw(&Text::new(subtitle, at, style))
            .map_err(|e| e.to_string())?;
        for (area, q) in body.split_evenly((1, n)).iter().zip(&quantities) {
            let points: Vec<&Point> = join.points.iter().filter(|p| p.quantity == *q).collect();
            panel(area, q, &points, x)?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}
