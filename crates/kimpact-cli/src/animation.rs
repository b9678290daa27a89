//! `compare.gif` (`kimpact compare --gif`): modes side by side (native
//! beside exact), animated in real time, each panel drawn by the pictures'
//! renderer ([`crate::render::frame`]) under a caption in the mode's plot
//! colour.
//!
//! After the first, each GIF frame holds only the rectangle that changed
//! (with a palette of its own), so still walls and resting balls cost
//! nothing.

use tiny_skia::{Color, Paint, Pixmap, PixmapPaint, Rect, Transform};

use kimpact::Mode;

use crate::palette::mode_color;
use crate::render::{self, Bounds};
use crate::scene::Scene;
use crate::sim::Frame;

/// At most this many frames per simulated second.
const MAX_RATE: f64 = 25.0;

/// At most this many frames in all (longer runs show fewer per second).
const MAX_FRAMES: u64 = 300;

/// How long the last frame stays, in hundredths of a second.
const HOLD_CS: u16 = 100;

/// Caption height, gap between panels, caption text size (pixels).
const CAPTION: u32 = 24;
const GAP: u32 = 6;
const TEXT: u32 = 14;

/// The steps the animation shows: every `g`-th step and the last, with `g`
/// the smallest stride that keeps within [`MAX_RATE`] and [`MAX_FRAMES`].
pub fn steps(dt: f64, steps: u64) -> Vec<u64> {
    let by_rate = (1.0 / (MAX_RATE * dt)).ceil();
    let by_rate = if by_rate.is_finite() && by_rate >= 1.0 {
        by_rate as u64
    } else {
        1
    };
    let g = by_rate.max(steps.div_ceil(MAX_FRAMES)).max(1);
    crate::shown::shown_steps(steps, g)
}

/// Hundredths of a second between frames at `times` (seconds), rounded so
/// that the rounding does not add up; at least 2 (viewers slow shorter
/// delays down), the last frame [`HOLD_CS`].
fn delays(times: &[f64]) -> Vec<u16> {
    let cs = |t: f64| (t * 100.0).round();
    let mut out: Vec<u16> = times
        .windows(2)
        .map(|w| (cs(w[1]) - cs(w[0])).clamp(2.0, f64::from(u16::MAX)) as u16)
        .collect();
    out.push(HOLD_CS);
    out
}

/// Draw one animation frame: a caption and a panel per mode, the time in
/// the last caption.
fn compose(
    scene: &Scene,
    panes: &[(Mode, &Frame)],
    bounds: &Bounds,
    time: f64,
) -> Result<Pixmap, String> {
    let (pw, ph) = render::panel_size(bounds);
    let n = panes.len() as u32;
    let w = GAP + n * (pw + GAP);
    let h = CAPTION + ph + GAP;
    let mut out = Pixmap::new(w, h).ok_or("cannot allocate a frame")?;
    out.fill(Color::WHITE);
    for (k, (mode, frame)) in panes.iter().enumerate() {
        let x = GAP + k as u32 * (pw + GAP);
        let (r, g, b) = mode_color(*mode);
        let mut paint = Paint::default();
        paint.set_color_rgba8(r, g, b, 255);
        if let Some(rect) = Rect::from_xywh(x as f32, 6.0, 14.0, 14.0) {
            out.fill_rect(rect, &paint, Transform::identity(), None);
        }
        crate::plot::label(
            &mut out,
            mode.name(),
            (x as i32 + 20, 4),
            TEXT,
            (20, 20, 20),
        );
        let panel = render::frame(scene, &frame.bodies, bounds).ok_or("cannot draw a panel")?;
        out.draw_pixmap(
            x as i32,
            CAPTION as i32,
            panel.as_ref(),
            &PixmapPaint::default(),
            Transform::identity(),
            None,
        );
    }
    let clock = format!("t = {time:.2} s");
    crate::plot::label(
        &mut out,
        &clock,
        (w as i32 - GAP as i32 - 8 * clock.len() as i32, 4),
        TEXT,
        (20, 20, 20),
    );
    Ok(out)
}

/// A rectangle of pixels: `(x, y, w, h)`.
type Area = (u32, u32, u32, u32);

/// A GIF frame waiting to be written: the area that changed, the picture,
/// and the delay, which grows while the following frames change nothing.
struct Pending {
    area: Area,
    pixmap: Pixmap,
    delay: u16,
}

/// The smallest rectangle where `a` and `b` differ, if any.
fn changed(a: &Pixmap, b: &Pixmap) -> Option<Area> {
    let w = a.width();
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for (i, (p, q)) in a.pixels().iter().zip(b.pixels()).enumerate() {
        if p != q {
            let (x, y) = (i as u32 % w, i as u32 / w);
            x0 = x0.min(x);
            y0 = y0.min(y);
            x1 = x1.max(x);
            y1 = y1.max(y);
        }
    }
    (x0 <= x1).then(|| (x0, y0, x1 - x0 + 1, y1 - y0 + 1))
}

/// Straight RGBA bytes of a rectangle of an opaque pixmap.
fn rgba(p: &Pixmap, (x, y, w, h): Area) -> Vec<u8> {
    let mut out = Vec::with_capacity((w * h * 4) as usize);
    for row in y..y + h {
        let start = (row * p.width() + x) as usize;
        for px in &p.pixels()[start..start + w as usize] {
            let c = px.demultiply();
            out.extend_from_slice(&[c.red(), c.green(), c.blue(), 255]);
        }
    }
    out
}

/// The animation: `panes` holds each mode's frames at the same steps
/// ([`steps`]), drawn side by side in the order given.
///
/// # Errors
/// Nothing to draw, a frame too large for a GIF, or the encoder's error.
pub fn animation(
    scene: &Scene,
    panes: &[(Mode, Vec<&Frame>)],
    bounds: &Bounds,
) -> Result<Vec<u8>, String> {
    let count = panes.iter().map(|p| p.1.len()).min().unwrap_or(0);
    let first = panes.first().ok_or("no modes to animate")?;
    if count == 0 {
        return Err("no frames to animate".into());
    }
    let times: Vec<f64> = first.1.iter().take(count).map(|f| f.time).collect();
    let delays = delays(&times);
    let at = |k: usize| -> Result<Pixmap, String> {
        let row: Vec<(Mode, &Frame)> = panes.iter().map(|(m, fs)| (*m, fs[k])).collect();
        compose(scene, &row, bounds, times[k])
    };
    let mut prev = at(0)?;
    let too_big = |_| "the animation is too large for a GIF".to_owned();
    let (w, h) = (
        u16::try_from(prev.width()).map_err(too_big)?,
        u16::try_from(prev.height()).map_err(too_big)?,
    );
    let mut bytes = Vec::new();
    {
        let mut enc = gif::Encoder::new(&mut bytes, w, h, &[]).map_err(|e| e.to_string())?;
        enc.set_repeat(gif::Repeat::Infinite)
            .map_err(|e| e.to_string())?;
        let mut pending = Some(Pending {
            area: (0, 0, u32::from(w), u32::from(h)),
            pixmap: prev.clone(),
            delay: delays[0],
        });
        let mut write = |p: Pending| {
            let mut data = rgba(&p.pixmap, p.area);
            // In range: the area lies inside a frame of u16 size.
            let (x, y, aw, ah) = p.area;
            let mut frame = gif::Frame::from_rgba_speed(aw as u16, ah as u16, &mut data, 10);
            frame.left = x as u16;
            frame.top = y as u16;
            frame.delay = p.delay;
            frame.dispose = gif::DisposalMethod::Keep;
            enc.write_frame(&frame).map_err(|e| e.to_string())
        };
        for (k, delay) in delays.iter().enumerate().skip(1) {
            let next = at(k)?;
            match changed(&prev, &next) {
                None => {
                    if let Some(p) = pending.as_mut() {
                        p.delay = p.delay.saturating_add(*delay);
                    }
                }
                Some(area) => {
                    if let Some(p) = pending.take() {
                        write(p)?;
                    }
                    pending = Some(Pending {
                        area,
                        pixmap: next.clone(),
                        delay: *delay,
                    });
                }
            }
            prev = next;
        }
        if let Some(p) = pending.take() {
            write(p)?;
        }
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_keep_to_the_rate_and_the_frame_cap() {
        // 60 Hz: every third step (20 frames per second).
        assert_eq!(steps(1.0 / 60.0, 9), [0, 3, 6, 9]);
        // A long run: at most MAX_FRAMES frames (and the last step).
        let long = steps(1.0 / 60.0, 100_000);
        assert!(long.len() as u64 <= MAX_FRAMES + 1, "{}", long.len());
        assert_eq!(long.last(), Some(&100_000));
        // A coarse step: every step.
        assert_eq!(steps(0.1, 3), [0, 1, 2, 3]);
    }

    #[test]
    fn delays_follow_the_times_without_adding_up_rounding() {
        let times: Vec<f64> = (0..7).map(|k| k as f64 * 3.0 / 60.0).collect();
        let d = delays(&times);
        assert_eq!(d, [5, 5, 5, 5, 5, 5, HOLD_CS]);
        let times: Vec<f64> = (0..4).map(|k| k as f64 / 30.0).collect();
        let d = delays(&times);
        // 3.33 cs each: 3 + 4 + 3 = 10 cs for 0.1 s.
        assert_eq!(d[..3].iter().map(|&x| u32::from(x)).sum::<u32>(), 10);
    }

    #[test]
    fn changed_finds_the_rectangle() {
        let a = Pixmap::new(10, 8).unwrap();
        let mut b = a.clone();
        assert_eq!(changed(&a, &b), None);
        let mut paint = Paint::default();
        paint.set_color_rgba8(255, 0, 0, 255);
        b.fill_rect(
            Rect::from_xywh(2.0, 3.0, 4.0, 2.0).unwrap(),
            &paint,
            Transform::identity(),
            None,
        );
        assert_eq!(changed(&a, &b), Some((2, 3, 4, 2)));
    }
}
