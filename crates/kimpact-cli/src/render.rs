//! Pictures of the bodies, drawn with tiny-skia: 2D scenes as seen from
//! above, 3D scenes as an orthographic projection on the view's two axes
//! (far bodies drawn first).

use tiny_skia::{
    Color, FillRule, Paint, PathBuilder, Pixmap, PixmapPaint, Rect, Stroke, Transform,
};

use crate::scene::{JointEnd, Scene, Shape};
use crate::sim::{BodyState, Frame};

/// A rectangle of the view plane: lower and upper corners.
pub type Bounds = ([f64; 2], [f64; 2]);

/// Panel width in pixels.
pub const PANEL_WIDTH: u32 = 360;

/// The view plane's bounds: the scene's `view.min`/`view.max`, or a fit of
/// the scene at the start (when fixed bodies enclose it) or of every frame.
pub fn bounds(scene: &Scene, frames: &[&Frame]) -> Bounds {
    if let Some(b) = scene.view.bounds {
        return b;
    }
    let [a0, a1] = scene.view.axes;
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let mut grow = |p: &[f64], h: &[f64]| {
        for (k, a) in [a0, a1].into_iter().enumerate() {
            if p[a].is_finite() {
                lo[k] = lo[k].min(p[a] - h[a]);
                hi[k] = hi[k].max(p[a] + h[a]);
            }
        }
    };
    let half: Vec<Vec<f64>> = scene.bodies.iter().map(|b| b.half_box(scene.dim)).collect();
    for (b, h) in scene.bodies.iter().zip(&half) {
        grow(&b.position, h);
    }
    if !scene.bodies.iter().any(|b| b.fixed) {
        for f in frames {
            for (s, h) in f.bodies.iter().zip(&half) {
                grow(&s.position, h);
            }
        }
    }
    for k in 0..2 {
        if !(lo[k] < hi[k]) {
            lo[k] = if lo[k].is_finite() { lo[k] - 1.0 } else { -1.0 };
            hi[k] = lo[k] + 2.0;
        }
    }
    let pad = 0.04 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    ([lo[0] - pad, lo[1] - pad], [hi[0] + pad, hi[1] + pad])
}

/// Panel size for `bounds`: [`PANEL_WIDTH`] wide, height from the aspect
/// ratio (between a quarter and twice the width).
pub fn panel_size(b: &Bounds) -> (u32, u32) {
    panel_size_for(PANEL_WIDTH, b)
}

/// Panel size for `bounds` at a given width (the page's panels): height
/// from the aspect ratio, between a quarter and twice the width.
pub fn panel_size_for(width: u32, b: &Bounds) -> (u32, u32) {
    let w = f64::from(width);
    let aspect = (b.1[1] - b.0[1]) / (b.1[0] - b.0[0]);
    let h = (w * aspect).clamp(w / 4.0, w * 2.0);
    (width, h.round() as u32)
}

/// A colour per body: fixed grey, law bodies by index around the hue circle,
/// other moving bodies dark olive (the page, `compare.html`, takes the
/// same colours).
pub fn color(scene: &Scene, i: usize) -> (u8, u8, u8) {
    let b = &scene.bodies[i];
    if b.fixed {
        return (150, 150, 150);
    }
    if !b.law {
        return (110, 110, 40);
    }
    let h = (i as f64 * 0.618_033_988_75).fract() * 6.0;
    let (s, v) = (0.65, 0.85);
    let c = v * s;
    let x = c * (1.0 - ((h % 2.0) - 1.0).abs());
    let (r, g, bl) = match h as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    let to = |u: f64| ((u + m) * 255.0).round() as u8;
    (to(r), to(g), to(bl))
}

/// Rotate `v` by the body's orientation (2D `[angle]`, 3D `[x, y, z, w]`).
fn rotate(rotation: &[f64], v: &[f64]) -> Vec<f64> {
    match rotation.len() {
        1 => {
            let (s, c) = rotation[0].sin_cos();
            vec![c * v[0] - s * v[1], s * v[0] + c * v[1]]
        }
        4 => {
            let (qx, qy, qz, qw) = (rotation[0], rotation[1], rotation[2], rotation[3]);
            // v' = v + 2w (q × v) + 2 q × (q × v)
            let t = [
                2.0 * (qy * v[2] - qz * v[1]),
                2.0 * (qz * v[0] - qx * v[2]),
                2.0 * (qx * v[1] - qy * v[0]),
            ];
            vec![
                v[0] + qw * t[0] + (qy * t[2] - qz * t[1]),
                v[1] + qw * t[1] + (qz * t[0] - qx * t[2]),
                v[2] + qw * t[2] + (qx * t[1] - qy * t[0]),
            ]
        }
        _ => v.to_vec(),
    }
}

/// Convex hull (monotone chain) of a few points, counter-clockwise.
fn hull(mut pts: Vec<(f32, f32)>) -> Vec<(f32, f32)> {
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: (f32, f32), a: (f32, f32), b: (f32, f32)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut lower: Vec<(f32, f32)> = Vec::new();
    for &p in &pts {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<(f32, f32)> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// Draw one frame into a new panel.
pub fn frame(scene: &Scene, bodies: &[BodyState], b: &Bounds) -> Option<Pixmap> {
    let (w, h) = panel_size(b);
    let mut pixmap = Pixmap::new(w, h)?;
    pixmap.fill(Color::from_rgba8(250, 250, 247, 255));
    let scale = (w as f64 / (b.1[0] - b.0[0])).min(h as f64 / (b.1[1] - b.0[1]));
    let (ox, oy) = (
        (w as f64 - scale * (b.1[0] - b.0[0])) / 2.0,
        (h as f64 - scale * (b.1[1] - b.0[1])) / 2.0,
    );
    let [a0, a1] = scene.view.axes;
    let map = |p: &[f64]| -> (f32, f32) {
        let x = ox + (p[a0] - b.0[0]) * scale;
        let y = h as f64 - oy - (p[a1] - b.0[1]) * scale;
        (x as f32, y as f32)
    };
    // Fixed bodies first (a cutaway: walls never hide what is inside), then
    // in 3D far bodies first along the axis not drawn.
    let depth_axis = if scene.dim == 3 {
        Some(3 - a0 - a1)
    } else {
        None
    };
    let mut order: Vec<usize> = (0..bodies.len()).collect();
    order.sort_by(|&i, &j| {
        let fixed = scene.bodies[j].fixed.cmp(&scene.bodies[i].fixed);
        let depth = depth_axis.map_or(std::cmp::Ordering::Equal, |d| {
            bodies[i].position[d].total_cmp(&bodies[j].position[d])
        });
        fixed.then(depth).then(i.cmp(&j))
    });
    let outline = Stroke {
        width: 1.0,
        ..Stroke::default()
    };
    joints(scene, bodies, &map, &mut pixmap);
    for i in order {
        let s = &bodies[i];
        if !s.position.iter().all(|x| x.is_finite()) {
            continue;
        }
        let (r, g, bl) = color(scene, i);
        let mut paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        // 3D walls are translucent: walls in front of each other stay visible.
        let alpha = if scene.dim == 3 && scene.bodies[i].fixed {
            70
        } else {
            255
        };
        paint.set_color_rgba8(r, g, bl, alpha);
        let path = match &scene.bodies[i].shape {
            Shape::Ball { radius } => {
                let (x, y) = map(&s.position);
                let pr = (radius * scale).max(0.8) as f32;
                PathBuilder::from_circle(x, y, pr)
            }
            shape => {
                let pts: Vec<(f32, f32)> = shape
                    .outline(scene.dim)
                    .iter()
                    .map(|local| {
                        let off = rotate(&s.rotation, local);
                        let world: Vec<f64> =
                            s.position.iter().zip(&off).map(|(p, o)| p + o).collect();
                        map(&world)
                    })
                    .collect();
                let poly = hull(pts);
                let mut pb = PathBuilder::new();
                for (k, &(x, y)) in poly.iter().enumerate() {
                    if k == 0 {
                        pb.move_to(x, y);
                    } else {
                        pb.line_to(x, y);
                    }
                }
                pb.close();
                pb.finish()
            }
        };
        let Some(path) = path else { continue };
        pixmap.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
        if let Shape::Ball { radius } = scene.bodies[i].shape
            && radius * scale >= 4.0
        {
            let mut dark = Paint {
                anti_alias: true,
                ..Paint::default()
            };
            dark.set_color_rgba8(40, 40, 40, 255);
            pixmap.stroke_path(&path, &dark, &outline, Transform::identity(), None);
        }
    }
    Some(pixmap)
}

/// The joints, behind the bodies: a thin line from each jointed body's
/// centre to its anchor, and a small square at an anchor on the world.
fn joints(
    scene: &Scene,
    bodies: &[BodyState],
    map: &impl Fn(&[f64]) -> (f32, f32),
    pixmap: &mut Pixmap,
) {
    let mut paint = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    paint.set_color_rgba8(60, 60, 60, 255);
    let thin = Stroke {
        width: 1.0,
        ..Stroke::default()
    };
    for j in &scene.joints {
        for (end, anchor) in [(j.body1, &j.anchor1), (j.body2, &j.anchor2)] {
            match end {
                JointEnd::World => {
                    let (x, y) = map(anchor);
                    if let Some(r) = Rect::from_xywh(x - 2.0, y - 2.0, 4.0, 4.0) {
                        pixmap.fill_rect(r, &paint, Transform::identity(), None);
                    }
                }
                JointEnd::Body(i) => {
                    let s = &bodies[i];
                    let off = rotate(&s.rotation, anchor);
                    let at: Vec<f64> = s.position.iter().zip(&off).map(|(p, o)| p + o).collect();
                    if !at.iter().chain(&s.position).all(|x| x.is_finite()) {
                        continue;
                    }
                    let (x0, y0) = map(&s.position);
                    let (x1, y1) = map(&at);
                    let mut pb = PathBuilder::new();
                    pb.move_to(x0, y0);
                    pb.line_to(x1, y1);
                    if let Some(path) = pb.finish() {
                        pixmap.stroke_path(&path, &paint, &thin, Transform::identity(), None);
                    }
                }
            }
        }
    }
}

/// One row of the strip: its panels and its mode's colour.
pub type Row = (Vec<Pixmap>, (u8, u8, u8));

/// Lay out panels in a grid (one row per mode, one column per time), each
/// row marked on the left with its mode's colour.
pub fn strip(rows: &[Row]) -> Option<Pixmap> {
    const GAP: u32 = 6;
    const MARK: u32 = 14;
    let cols = rows.iter().map(|r| r.0.len()).max()?;
    let (pw, ph) = rows
        .first()
        .and_then(|r| r.0.first())
        .map(|p| (p.width(), p.height()))?;
    let w = MARK + GAP + cols as u32 * (pw + GAP);
    let h = GAP + rows.len() as u32 * (ph + GAP);
    let mut out = Pixmap::new(w, h)?;
    out.fill(Color::WHITE);
    for (r, (panels, rgb)) in rows.iter().enumerate() {
        let y = GAP + r as u32 * (ph + GAP);
        let mut paint = Paint::default();
        paint.set_color_rgba8(rgb.0, rgb.1, rgb.2, 255);
        if let Some(rect) = Rect::from_xywh(
            GAP as f32 / 2.0,
            y as f32,
            MARK as f32 - GAP as f32 / 2.0,
            ph as f32,
        ) {
            out.fill_rect(rect, &paint, Transform::identity(), None);
        }
        for (c, p) in panels.iter().enumerate() {
            let x = MARK + GAP + c as u32 * (pw + GAP);
            out.draw_pixmap(
                x as i32,
                y as i32,
                p.as_ref(),
                &PixmapPaint::default(),
                Transform::identity(),
                None,
            );
        }
    }
    Some(out)
}
