//! `accuracy.svg`, drawn with plotters: one row of three panels per build
//! (the gas's energy error, one impact and the cradle against the CPU time
//! of the gas), then the cooling curves.

use std::collections::BTreeMap;

use kimpact_harness::{Method, Panel};
use plotters::chart::SeriesLabelPosition::{LowerLeft, UpperRight};

/// A series' points.
type Points = Vec<(f64, f64)>;

/// The panels of the points `(panel title, simulator, x, y)`: each build's
/// cost panels in a row, then the cooling curves (the cost runs' gas has
/// `gas_balls` balls).
pub fn panels(points: &[(String, Method, f64, f64)], gas_balls: usize) -> Vec<Panel> {
    let mut by_title: BTreeMap<&str, BTreeMap<Method, Points>> = BTreeMap::new();
    for (title, method, x, y) in points {
        let panel = by_title.entry(title).or_default();
        panel.entry(*method).or_default().push((*x, *y));
    }
    let panel = |(title, series): (&str, BTreeMap<_, _>)| {
        let cooling = title.starts_with("cooling");
        let (x_label, y_label, legend) = match cooling {
            true => ("time (s)".to_owned(), "kinetic energy / initial", LowerLeft),
            false => {
                let x = format!("CPU seconds per simulated second ({gas_balls}-ball gas)");
                (x, "error", UpperRight)
            }
        };
        Panel {
            title: title.to_owned(),
            x_label,
            y_label: y_label.to_owned(),
            series: series.into_iter().collect(),
            log_x: !cooling,
            dots: !cooling,
            legend,
        }
    };
    let mut list: Vec<Panel> = by_title.into_iter().map(panel).collect();
    // Every title ends with its build's label (`2D f32`…), which sorts as
    // the builds' rows.
    let kinds = ["gas energy", "one impact", "cradle", "cooling"];
    let rank = |t: &str| kinds.iter().position(|k| t.starts_with(k));
    list.sort_by_key(|p| {
        let (rank, build) = (rank(&p.title), p.title[p.title.len() - 6..].to_owned());
        (rank == Some(3), build, rank)
    });
    list
}
