//! `compare --gif` and `compare.html` without a browser: the animation's
//! frames put together are the pictures the CLI draws, in real time; the
//! page is self-contained and small.

mod common;

use std::path::Path;
use std::process::Command;

use common::{scene, temp_dir};

fn compare(scene_file: &str, extra: &[&str], out: &Path) {
    let o = Command::new(env!("CARGO_BIN_EXE_kimpact"))
        .args(["compare", scene(scene_file).to_str().unwrap(), "--out"])
        .arg(out)
        .args(extra)
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Every frame of a GIF put together on one canvas (each frame's
/// rectangle drawn over the last), with its delay in hundredths.
fn gif_frames(bytes: &[u8]) -> (u32, u32, Vec<(Vec<u8>, u16)>) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(bytes).expect("a GIF");
    let (w, h) = (u32::from(dec.width()), u32::from(dec.height()));
    let mut canvas = vec![0u8; (w * h * 4) as usize];
    let mut out = Vec::new();
    while let Some(f) = dec.read_next_frame().expect("a frame") {
        assert_eq!(f.dispose, gif::DisposalMethod::Keep);
        for y in 0..u32::from(f.height) {
            for x in 0..u32::from(f.width) {
                let s = ((y * u32::from(f.width) + x) * 4) as usize;
                let d = (((y + u32::from(f.top)) * w + x + u32::from(f.left)) * 4) as usize;
                canvas[d..d + 4].copy_from_slice(&f.buffer[s..s + 4]);
            }
        }
        out.push((canvas.clone(), f.delay));
    }
    (w, h, out)
}

/// The cradle's animation: native beside exact, the last frame put together
/// from the changed rectangles is the exact mode's last picture
/// (`frames/exact-K.png`, drawn by the same renderer) up to the GIF's
/// palette, and the delays add up to the simulated time.
#[test]
fn the_gif_is_the_pictures_in_real_time() {
    let dir = temp_dir("gif");
    compare("cradle2d.ron", &["--steps", "30", "--gif"], &dir);
    let bytes = std::fs::read(dir.join("compare.gif")).unwrap();
    assert_eq!(&bytes[..6], b"GIF89a");
    let (w, _h, frames) = gif_frames(&bytes);
    // 30 steps at 60 Hz shown every 3rd step: 11 frames (fewer when a
    // frame changes nothing and its delay goes to the one before).
    assert!((2..=11).contains(&frames.len()), "{} frames", frames.len());
    let total: u32 = frames.iter().map(|f| u32::from(f.1)).sum();
    // 0.5 s of simulation and the last frame held for a second.
    assert_eq!(
        total,
        50 + 100,
        "delays {:?}",
        frames.iter().map(|f| f.1).collect::<Vec<_>>()
    );
    // The last picture: the one at the end (0.5 s), frames/exact-2.png.
    let picture = tiny_skia::Pixmap::load_png(dir.join("frames/exact-2.png")).unwrap();
    let (pw, ph) = (picture.width(), picture.height());
    // Second pane: after a 6 px gap, one panel and another gap; below the
    // 24 px caption.
    let (x0, y0) = (6 + pw + 6, 24);
    assert_eq!(w, 6 + 2 * (pw + 6));
    let last = &frames.last().unwrap().0;
    let mut worst = 0u8;
    let mut total_error = 0u64;
    for y in 0..ph {
        for x in 0..pw {
            let want = picture.pixel(x, y).unwrap().demultiply();
            let k = (((y + y0) * w + x + x0) * 4) as usize;
            for (c, wc) in [want.red(), want.green(), want.blue()]
                .into_iter()
                .enumerate()
            {
                let e = last[k + c].abs_diff(wc);
                worst = worst.max(e);
                total_error += u64::from(e);
            }
        }
    }
    let mean = total_error as f64 / f64::from(pw * ph * 3);
    // The palette of 256 colours per frame: a few levels off on average,
    // and never a whole colour (a missing or misplaced ball is 100+).
    assert!(mean < 2.0, "mean error {mean}");
    assert!(worst < 64, "worst error {worst}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `compare` writes the page without being asked, self-contained (the
/// security policy, no address of any server, no external element) and
/// well under 5 MB for the bundled break; without `--gif`, no GIF.
#[test]
fn the_page_is_self_contained_and_small() {
    let dir = temp_dir("page");
    compare("billiards2d.ron", &[], &dir);
    let page = std::fs::read_to_string(dir.join("compare.html")).unwrap();
    assert!(page.len() < 5_000_000, "{} bytes", page.len());
    assert!(page.contains(
        "content=\"default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data:\""
    ));
    for banned in ["http://", "https://", "<link", "src=\"", "@import", "url("] {
        assert!(!page.contains(banned), "the page holds {banned:?}");
    }
    assert!(!page.contains("/*KIMPACT_DATA*/"), "the data went in");
    assert!(page.contains("billiards2d — kimpact compare"));
    assert!(!dir.join("compare.gif").exists());
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| !n.ends_with(".tmp")),
        "a temporary file left: {names:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
