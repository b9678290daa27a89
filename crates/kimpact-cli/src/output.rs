//! Writing outputs whole: each file into a temporary file beside it
//! (`tempfile`), renamed into place (`NamedTempFile::persist`); on an error
//! the temporary file is removed and an existing file stays as it was.

use std::io::Write as _;
use std::path::Path;

use crate::error::CliError;

/// Write `bytes` to `path` whole, or not at all.
///
/// # Errors
/// [`CliError::Internal`] if the file cannot be written.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), CliError> {
    let folder = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    // A temporary file is private (0600); the outputs are not.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
    let written = builder.tempfile_in(folder).and_then(|mut temp| {
        temp.write_all(bytes)?;
        temp.persist(path).map(drop).map_err(|e| e.error)
    });
    written.map_err(|e| CliError::Internal(format!("cannot write {}: {e}", path.display())))
}
