//! Whole-file writes for every tool of the package, and the machine a run
//! was on, for the reports' headers.

use std::io::Write as _;
use std::path::{Path, PathBuf};

/// A file that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {}: {source}", path.display())]
pub struct WriteError {
    /// The file.
    pub path: PathBuf,
    /// The file system's reason.
    pub source: std::io::Error,
}

/// Write every `(path, contents)` whole, all or none: each into a temporary
/// file beside it, renamed into place once every one is written (a rename
/// that fails after others succeeded leaves those). Missing folders are
/// created.
///
/// # Errors
/// [`WriteError`] naming the first file that could not be written.
pub fn write_files<P: AsRef<Path>, B: AsRef<[u8]>>(files: &[(P, B)]) -> Result<(), WriteError> {
    let mut temps = Vec::with_capacity(files.len());
    for (path, contents) in files {
        let path = path.as_ref();
        let error = |source| WriteError {
            path: path.to_owned(),
            source,
        };
        let folder = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        std::fs::create_dir_all(folder).map_err(error)?;
        let mut builder = tempfile::Builder::new();
        // A temporary file is private (0600); the results are not.
        #[cfg(unix)]
        builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
        let mut temp = builder.tempfile_in(folder).map_err(error)?;
        temp.write_all(contents.as_ref()).map_err(error)?;
        temps.push((path, temp));
    }
    for (path, temp) in temps {
        let error = |e: tempfile::PersistError| WriteError {
            path: path.to_owned(),
            source: e.error,
        };
        temp.persist(path).map_err(error)?;
    }
    Ok(())
}

/// The machine and the compiler, for the header.
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo").ok().and_then(|c| {
        let line = c.lines().find(|l| l.starts_with("model name"))?;
        Some(line.split(':').nth(1)?.trim().to_owned())
    });
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let out = |command: &str, arg: &str| {
        let o = std::process::Command::new(command).arg(arg).output();
        o.map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
            .unwrap_or_default()
    };
    // `rustc 1.95.0` without its commit and date: the docs name no commits.
    let (rustc, os) = (out("rustc", "-V"), out("uname", "-sr"));
    let rustc = rustc.split(' ').take(2).collect::<Vec<_>>().join(" ");
    let (cpu, os) = (cpu.as_deref().unwrap_or("unknown CPU"), os.trim());
    format!("{cpu}, {cores} cores available to the process, {os}; {rustc}")
}
