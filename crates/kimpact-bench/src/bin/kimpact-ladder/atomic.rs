//! Writing files whole or not at all: each is written to a temporary file
//! in its own folder, and only when every one is written are they renamed
//! into place (a rename within a folder replaces the old file at once).
//! On an error the temporary files are removed and the old files stay as
//! they were.

use std::path::{Path, PathBuf};

use crate::error::LadderError;

/// The temporary file beside `path`.
fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

/// The folder of `path` (`.` for a bare file name).
fn folder(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Write every `(path, contents)`, all or none (as far as the file system
/// allows: a rename that fails after others succeeded leaves those).
///
/// # Errors
/// [`LadderError::Write`] naming the file that could not be written.
pub fn write_all(files: &[(&Path, &[u8])]) -> Result<(), LadderError> {
    let mut written: Vec<PathBuf> = Vec::new();
    let clean = |written: &[PathBuf]| {
        for t in written {
            let _ = std::fs::remove_file(t);
        }
    };
    for (path, contents) in files {
        let tmp = temporary(path);
        let result =
            std::fs::create_dir_all(folder(path)).and_then(|()| std::fs::write(&tmp, contents));
        if let Err(source) = result {
            let _ = std::fs::remove_file(&tmp);
            clean(&written);
            return Err(LadderError::Write {
                path: path.to_path_buf(),
                source,
            });
        }
        written.push(tmp);
    }
    for (i, ((path, _), tmp)) in files.iter().zip(&written).enumerate() {
        if let Err(source) = std::fs::rename(tmp, path) {
            clean(&written[i..]);
            return Err(LadderError::Write {
                path: path.to_path_buf(),
                source,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!(
            "kimpact-ladder-atomic-{name}-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn writes_every_file_and_leaves_no_temporary() {
        let d = dir("ok");
        let (a, b) = (d.join("a.svg"), d.join("sub/b.md"));
        std::fs::write(&a, "old").unwrap();
        write_all(&[(&a, b"new a"), (&b, b"new b")]).unwrap();
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "new a");
        assert_eq!(std::fs::read_to_string(&b).unwrap(), "new b");
        let names: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn an_error_on_the_second_file_leaves_the_first_as_it_was() {
        let d = dir("err");
        let a = d.join("a.svg");
        std::fs::write(&a, "old").unwrap();
        std::fs::write(d.join("file"), "").unwrap();
        // a folder that is a file: the second write fails
        let b = d.join("file/b.md");
        let e = write_all(&[(&a, b"new a"), (&b, b"new b")]).unwrap_err();
        assert!(
            matches!(&e, LadderError::Write { path, .. } if *path == b),
            "{e}"
        );
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "old");
        let names: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        let _ = std::fs::remove_dir_all(&d);
    }
}
