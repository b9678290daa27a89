//! Writing outputs without ever leaving a partial file: each file is written
//! to a temporary file in the same directory and renamed into place.

use std::path::Path;

use crate::error::CliError;

/// Write `bytes` to `path` atomically (temporary file + rename).
///
/// # Errors
/// [`CliError::Internal`] if the file cannot be written.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), CliError> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("output");
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(CliError::Internal(format!(
            "cannot write {}: {e}",
            path.display()
        )));
    }
    Ok(())
}
