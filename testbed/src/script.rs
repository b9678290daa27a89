//! A scripted run (`--switch`, `--frames`) and what it leaves behind: the
//! record of each mode's stretch of the run, written as JSON, and the last
//! frame as a PNG. Both files are written whole or not at all.

use std::path::{Path, PathBuf};
use std::str::FromStr;

use kimpact2d::Mode;
use serde::Serialize;

/// `MODE@FRAME`: switch to `mode` before simulated frame `frame`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Switch {
    /// The mode switched to.
    pub mode: Mode,
    /// Simulated frames before the switch.
    pub frame: u64,
}

/// A `--switch` value that is not `MODE@FRAME`.
#[derive(Debug, thiserror::Error)]
pub enum ParseSwitchError {
    /// No `@`.
    #[error("`{0}`: expected MODE@FRAME, e.g. exact@60")]
    Form(String),
    /// The mode part.
    #[error("`{0}`: {1}")]
    Mode(String, kimpact2d::ParseModeError),
    /// The frame part.
    #[error("`{0}`: the frame is not a whole number ≥ 0")]
    Frame(String),
}

impl FromStr for Switch {
    type Err = ParseSwitchError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (mode, frame) = s
            .split_once('@')
            .ok_or_else(|| ParseSwitchError::Form(s.to_string()))?;
        Ok(Switch {
            mode: mode
                .trim()
                .parse()
                .map_err(|e| ParseSwitchError::Mode(s.to_string(), e))?,
            frame: frame
                .trim()
                .parse()
                .map_err(|_| ParseSwitchError::Frame(s.to_string()))?,
        })
    }
}

/// The switches in frame order and where the run stops.
#[derive(Clone, Debug, Default)]
pub struct Script {
    switches: Vec<Switch>,
    frames: Option<u64>,
}

impl Script {
    /// The script of `switches` (any order; the last one given wins at a
    /// frame) ending after `frames` simulated frames (`None`: never).
    pub fn new(mut switches: Vec<Switch>, frames: Option<u64>) -> Self {
        switches.sort_by_key(|s| s.frame);
        Script { switches, frames }
    }

    /// The mode to switch to before simulated frame `frame`, if any.
    pub fn switch_at(&self, frame: u64) -> Option<Mode> {
        self.switches
            .iter()
            .rev()
            .find(|s| s.frame == frame)
            .map(|s| s.mode)
    }

    /// Whether the run stops after `frame` simulated frames.
    pub fn done(&self, frame: u64) -> bool {
        self.frames.is_some_and(|n| frame >= n)
    }
}

/// One mode's stretch of a run.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Segment {
    /// The mode.
    pub mode: String,
    /// The first simulated frame of the stretch.
    pub from_frame: u64,
    /// Simulated frames in the stretch.
    pub frames: u64,
    /// Impacts kimpact resolved or reported in the stretch.
    pub impacts: u64,
    /// Kinetic energy at its start and at its end (J).
    pub kinetic_start: f64,
    /// See `kinetic_start`.
    pub kinetic_end: f64,
}

/// What a scripted run did, mode by mode.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Record {
    /// The scene's name.
    pub scene: String,
    /// Simulated frames in all.
    pub frames: u64,
    /// The stretches, in order.
    pub segments: Vec<Segment>,
}

impl Record {
    /// A run of `scene` starting in `mode` with kinetic energy `kinetic`.
    pub fn new(scene: &str, mode: Mode, kinetic: f64) -> Self {
        Record {
            scene: scene.to_string(),
            frames: 0,
            segments: vec![Segment::start(mode, 0, kinetic)],
        }
    }

    /// The mode changes to `mode` now (kinetic energy `kinetic`).
    pub fn switch(&mut self, mode: Mode, kinetic: f64) {
        self.close(kinetic);
        let segment = Segment::start(mode, self.frames, kinetic);
        match self.segments.last_mut() {
            // A switch before any frame of the stretch replaces it.
            Some(last) if last.frames == 0 => *last = segment,
            _ => self.segments.push(segment),
        }
    }

    /// One simulated frame with `impacts` impacts.
    pub fn step(&mut self, impacts: usize) {
        self.frames += 1;
        if let Some(last) = self.segments.last_mut() {
            last.frames += 1;
            last.impacts += impacts as u64;
        }
    }

    /// The run ends (or a stretch) with kinetic energy `kinetic`.
    pub fn close(&mut self, kinetic: f64) {
        if let Some(last) = self.segments.last_mut() {
            last.kinetic_end = kinetic;
        }
    }
}

impl Segment {
    fn start(mode: Mode, from_frame: u64, kinetic: f64) -> Self {
        Segment {
            mode: mode.to_string(),
            from_frame,
            frames: 0,
            impacts: 0,
            kinetic_start: kinetic,
            kinetic_end: kinetic,
        }
    }
}

/// A file that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct WriteError {
    /// The file.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

/// Write `bytes` to `path` whole: into a temporary file beside it
/// (`tempfile`), then renamed over it (`NamedTempFile::persist`); on an
/// error the temporary file is removed and `path` is left as it was.
fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    use std::io::Write as _;
    let error = |message: String| WriteError {
        path: path.to_path_buf(),
        message,
    };
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut temp = tempfile::NamedTempFile::new_in(folder).map_err(|e| error(e.to_string()))?;
    temp.write_all(bytes).map_err(|e| error(e.to_string()))?;
    temp.persist(path).map_err(|e| error(e.error.to_string()))?;
    Ok(())
}

/// Save `record` as JSON at `path`.
///
/// # Errors
/// [`WriteError`] when the file cannot be written (nothing is left then).
pub fn save_report(record: &Record, path: &Path) -> Result<(), WriteError> {
    let text = serde_json::to_string_pretty(record).expect("a record serializes");
    write_whole(path, text.as_bytes())
}

/// Save `image` as a PNG at `path`.
///
/// # Errors
/// [`WriteError`] when the image cannot be encoded or written.
pub fn save_png(image: &image::RgbImage, path: &Path) -> Result<(), WriteError> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| WriteError {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
    write_whole(path, bytes.get_ref())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn switches_parse_and_name_what_is_wrong() {
        let s: Switch = "exact@60".parse().unwrap();
        assert_eq!(
            s,
            Switch {
                mode: Mode::Exact,
                frame: 60
            }
        );
        assert!(matches!(
            "exact".parse::<Switch>(),
            Err(ParseSwitchError::Form(_))
        ));
        assert!(matches!(
            "fast@3".parse::<Switch>(),
            Err(ParseSwitchError::Mode(..))
        ));
        assert!(matches!(
            "exact@-1".parse::<Switch>(),
            Err(ParseSwitchError::Frame(_))
        ));
    }

    #[test]
    fn a_script_switches_at_its_frames_and_ends() {
        let script = Script::new(
            vec![
                Switch {
                    mode: Mode::Exact,
                    frame: 30,
                },
                Switch {
                    mode: Mode::Native,
                    frame: 10,
                },
            ],
            Some(40),
        );
        assert_eq!(script.switch_at(10), Some(Mode::Native));
        assert_eq!(script.switch_at(30), Some(Mode::Exact));
        assert_eq!(script.switch_at(20), None);
        assert!(!script.done(39));
        assert!(script.done(40));
        assert!(!Script::new(vec![], None).done(u64::MAX));
    }

    #[test]
    fn a_record_keeps_one_stretch_per_mode_run() {
        let mut r = Record::new("cradle2d", Mode::Native, 1.0);
        r.switch(Mode::Exact, 1.0); // before any frame: replaces
        r.step(0);
        r.step(2);
        r.switch(Mode::Native, 0.5);
        r.step(0);
        r.close(0.25);
        assert_eq!(r.frames, 3);
        assert_eq!(r.segments.len(), 2);
        assert_eq!(r.segments[0].mode, "exact");
        assert_eq!((r.segments[0].frames, r.segments[0].impacts), (2, 2));
        assert_eq!(r.segments[0].kinetic_end, 0.5);
        assert_eq!((r.segments[1].from_frame, r.segments[1].frames), (2, 1));
        assert_eq!(r.segments[1].kinetic_end, 0.25);
    }

    #[test]
    fn a_report_is_written_whole_or_not_at_all() {
        let dir = std::env::temp_dir().join(format!("kimpact-testbed-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let record = Record::new("s", Mode::Exact, 0.0);
        let path = dir.join("r.json");
        save_report(&record, &path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("\"scene\": \"s\""));
        let missing = dir.join("no-such-folder").join("r.json");
        let e = save_report(&record, &missing).unwrap_err();
        assert!(e.to_string().contains("no-such-folder"), "{e}");
        assert!(!missing.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
