//! Plots of kinetic energy and momentum over time, laid out once by
//! plotters and drawn twice: SVG (the text left to the viewer's fonts) and
//! PNG (tiny-skia, the text drawn with the bundled DejaVu Sans through
//! ab_glyph: no system font library, no font on the machine needed).

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
};
use tiny_skia::{
    FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, PremultipliedColorU8, Rect, Stroke,
    Transform,
};

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

/// Title font size (pixels per em).
const TITLE_SIZE: u32 = 22;

/// plotters' default inner margin of the legend box.
const LEGEND_MARGIN: u32 = 10;

/// plotters' default legend font size.
const LEGEND_FONT_SIZE: u32 = 12;

/// The chart, on any plotters backend; `legend_margin` pads the legend box.
fn chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    legend_margin: u32,
) -> Result<(), String> {
    let (x0, x1, y0, y1) = bounds(series);
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", TITLE_SIZE))
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
                Color::stroke_width(&color, 2),
            ))
            .map_err(|e| e.to_string())?
            .label(s.label.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], Color::stroke_width(&color, 2))
            });
    }
    chart
        .configure_series_labels()
        .margin(legend_margin)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())?;
    Ok(())
}

/// An SVG line plot with title, axis labels and legend.
///
/// # Errors
/// plotters' drawing error, as text.
pub fn svg(title: &str, x_label: &str, y_label: &str, series: &[Series]) -> Result<String, String> {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, SIZE).into_drawing_area();
        chart(&root, title, x_label, y_label, series, LEGEND_MARGIN)?;
    }
    Ok(out)
}

/// The same plot as a PNG, with the same text.
///
/// # Errors
/// plotters' drawing error or tiny-skia's encoding error, as text.
pub fn png(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<Vec<u8>, String> {
    let (w, h) = SIZE;
    let mut pixmap = Pixmap::new(w, h).ok_or("cannot allocate the plot")?;
    // plotters sizes the legend box with its own estimate of the text (a
    // font-less guess without a font feature): widen the box's margin by
    // what the bundled font needs beyond that guess.
    let guess = ("sans-serif", LEGEND_FONT_SIZE).into_font();
    let extra = series
        .iter()
        .map(|s| {
            let (gw, gh) = guess.box_size(&s.label).unwrap_or((0, 0));
            let (tw, th) = text_size(&s.label, f64::from(LEGEND_FONT_SIZE));
            (tw.ceil() as i64 - i64::from(gw)).max(th.ceil() as i64 - i64::from(gh))
        })
        .fold(0, i64::max);
    let legend_margin = LEGEND_MARGIN + u32::try_from(extra).unwrap_or(0);
    {
        let root = PngBackend {
            pixmap: &mut pixmap,
        }
        .into_drawing_area();
        chart(&root, title, x_label, y_label, series, legend_margin)?;
    }
    pixmap.encode_png().map_err(|e| e.to_string())
}

/// Write `text` on `pixmap` with the bundled font, `size` pixels per em,
/// its top-left corner at `pos` (the animation's captions).
pub fn label(pixmap: &mut Pixmap, text: &str, pos: (i32, i32), size: u32, rgb: (u8, u8, u8)) {
    let color = RGBColor(rgb.0, rgb.1, rgb.2);
    let style = TextStyle::from(("sans-serif", size).into_font()).color(&color);
    let mut backend = PngBackend { pixmap };
    // Drawing text on a pixmap has no failure of its own.
    let _ = backend.draw_text(text, &style, pos);
}

/// The bundled font (DejaVu Sans; license in `assets/fonts/`).
fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| {
        FontRef::try_from_slice(include_bytes!("../../../assets/fonts/DejaVuSans.ttf"))
            .expect("the bundled font is a valid TrueType font")
    })
}

/// The font scale for a plotters font size: `size` pixels per em, as an
/// SVG `font-size`.
fn scale(size: f64) -> PxScale {
    let f = font();
    let per_em = f.height_unscaled() / f.units_per_em().unwrap_or(2048.0);
    PxScale::from(size as f32 * per_em)
}

/// Width (advances and kerning) and height (ascent to descent) of a line
/// of text, in pixels.
fn text_size(text: &str, size: f64) -> (f32, f32) {
    let font = font().as_scaled(scale(size));
    let mut width = 0.0;
    let mut prev = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = prev {
            width += font.kern(p, id);
        }
        width += font.h_advance(id);
        prev = Some(id);
    }
    (width, font.height())
}

/// A plotters backend drawing on a tiny-skia pixmap (anti-aliased), with
/// text from the bundled font.
struct PngBackend<'a> {
    pixmap: &'a mut Pixmap,
}

/// tiny-skia's paint for a plotters colour.
fn paint(c: BackendColor) -> Paint<'static> {
    let mut p = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    p.set_color_rgba8(c.rgb.0, c.rgb.1, c.rgb.2, alpha(c.alpha));
    p
}

fn alpha(a: f64) -> u8 {
    (a.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// The centre of plotters' pixel `(x, y)`.
fn centre((x, y): BackendCoord) -> (f32, f32) {
    (x as f32 + 0.5, y as f32 + 0.5)
}

impl PngBackend<'_> {
    /// Blend `c` with coverage `coverage` over the pixel at `(x, y)`.
    fn blend(&mut self, (x, y): BackendCoord, c: BackendColor, coverage: f32) {
        let (w, h) = (self.pixmap.width(), self.pixmap.height());
        let (Ok(ux), Ok(uy)) = (u32::try_from(x), u32::try_from(y)) else {
            return;
        };
        if ux >= w || uy >= h {
            return;
        }
        let a = (c.alpha as f32 * coverage).clamp(0.0, 1.0);
        if a <= 0.0 {
            return;
        }
        let i = (uy * w + ux) as usize;
        let d = self.pixmap.pixels()[i];
        let mix = |s: u8, d: u8| (f32::from(s) * a + f32::from(d) * (1.0 - a)).round() as u8;
        let out_a = (255.0 * a + f32::from(d.alpha()) * (1.0 - a)).round() as u8;
        // Premultiplied: the source's channels times its alpha.
        let ch = |s: u8, d: u8| mix(s, d).min(out_a);
        let (r, g, b) = if d.alpha() == 255 {
            (
                ch(c.rgb.0, d.red()),
                ch(c.rgb.1, d.green()),
                ch(c.rgb.2, d.blue()),
            )
        } else {
            let pm = |s: u8, d: u8| {
                ((f32::from(s) * a + f32::from(d) * (1.0 - a)).round() as u8).min(out_a)
            };
            (
                pm(c.rgb.0, d.red()),
                pm(c.rgb.1, d.green()),
                pm(c.rgb.2, d.blue()),
            )
        };
        if let Some(p) = PremultipliedColorU8::from_rgba(r, g, b, out_a) {
            self.pixmap.pixels_mut()[i] = p;
        }
    }

    /// Stroke a polyline through pixel centres.
    fn stroke<S: BackendStyle>(&mut self, points: &[(f32, f32)], style: &S, close: bool) {
        let c = style.color();
        if c.alpha <= 0.0 || points.is_empty() {
            return;
        }
        let mut pb = PathBuilder::new();
        pb.move_to(points[0].0, points[0].1);
        for &(x, y) in &points[1..] {
            pb.line_to(x, y);
        }
        if close {
            pb.close();
        }
        let Some(path) = pb.finish() else { return };
        let stroke = Stroke {
            width: style.stroke_width().max(1) as f32,
            line_cap: LineCap::Round,
            line_join: LineJoin::Round,
            ..Stroke::default()
        };
        self.pixmap
            .stroke_path(&path, &paint(c), &stroke, Transform::identity(), None);
    }

    /// Fill a path.
    fn fill(&mut self, path: Option<tiny_skia::Path>, c: BackendColor) {
        if c.alpha <= 0.0 {
            return;
        }
        if let Some(path) = path {
            self.pixmap.fill_path(
                &path,
                &paint(c),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
    }
}

impl DrawingBackend for PngBackend<'_> {
    type ErrorType = std::convert::Infallible;

    fn get_size(&self) -> (u32, u32) {
        (self.pixmap.width(), self.pixmap.height())
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        Ok(())
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        Ok(())
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.blend(point, color, 1.0);
        Ok(())
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.stroke(&[centre(from), centre(to)], style, false);
        Ok(())
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let (x0, y0) = (
            upper_left.0.min(bottom_right.0),
            upper_left.1.min(bottom_right.1),
        );
        let (x1, y1) = (
            upper_left.0.max(bottom_right.0),
            upper_left.1.max(bottom_right.1),
        );
        if fill {
            // plotters' rectangles include both corners.
            let rect = Rect::from_ltrb(x0 as f32, y0 as f32, x1 as f32 + 1.0, y1 as f32 + 1.0);
            self.fill(rect.map(PathBuilder::from_rect), style.color());
        } else {
            let (a, b) = (centre((x0, y0)), centre((x1, y1)));
            self.stroke(&[a, (b.0, a.1), b, (a.0, b.1)], style, true);
        }
        Ok(())
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let points: Vec<(f32, f32)> = path.into_iter().map(centre).collect();
        self.stroke(&points, style, false);
        Ok(())
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let (x, y) = centre(center);
        let circle = PathBuilder::from_circle(x, y, radius as f32);
        if fill {
            self.fill(circle, style.color());
        } else if let Some(circle) = circle {
            let stroke = Stroke {
                width: style.stroke_width().max(1) as f32,
                ..Stroke::default()
            };
            let c = style.color();
            if c.alpha > 0.0 {
                self.pixmap
                    .stroke_path(&circle, &paint(c), &stroke, Transform::identity(), None);
            }
        }
        Ok(())
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let mut pb = PathBuilder::new();
        for (i, p) in vert.into_iter().enumerate() {
            let (x, y) = centre(p);
            if i == 0 {
                pb.move_to(x, y);
            } else {
                pb.line_to(x, y);
            }
        }
        pb.close();
        self.fill(pb.finish(), style.color());
        Ok(())
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha <= 0.0 {
            return Ok(());
        }
        let size = style.size();
        let (w, h) = text_size(text, size);
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -w / 2.0,
            HPos::Right => -w,
        };
        let dy = match anchor.v_pos {
            VPos::Top => 0.0,
            VPos::Center => -h / 2.0,
            VPos::Bottom => -h,
        };
        // Laid out horizontally from the anchor, then turned about it.
        let transform = style.transform();
        let font = font().as_scaled(scale(size));
        let mut caret = dx;
        let mut prev = None;
        for c in text.chars() {
            let id = font.glyph_id(c);
            if let Some(p) = prev {
                caret += font.kern(p, id);
            }
            let glyph = id.with_scale_and_position(font.scale(), point(caret, dy + font.ascent()));
            caret += font.h_advance(id);
            prev = Some(id);
            let Some(outline) = font.outline_glyph(glyph) else {
                continue;
            };
            let bounds = outline.px_bounds();
            outline.draw(|gx, gy, coverage| {
                let (x, y) = transform.transform(
                    bounds.min.x as i32 + gx as i32,
                    bounds.min.y as i32 + gy as i32,
                );
                self.blend((pos.0 + x, pos.1 + y), color, coverage);
            });
        }
        Ok(())
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        let (w, h) = text_size(text, style.size());
        Ok((w.ceil() as u32, h.ceil() as u32))
    }
}
