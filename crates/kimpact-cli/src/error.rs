//! The two kinds of failure the command reports, and their exit codes.

use std::fmt;

/// Why a command failed.
#[derive(Debug)]
pub enum CliError {
    /// Bad input: an unreadable or invalid scene, a bad flag. Exit code 2.
    Input(String),
    /// Something went wrong on our side (an output that could not be
    /// written, a panic). Exit code 1.
    Internal(String),
}

impl CliError {
    /// The process exit code for this error.
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::Input(_) => 2,
            CliError::Internal(_) => 1,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) => write!(f, "error: {m}"),
            CliError::Internal(m) => write!(f, "internal error: {m}"),
        }
    }
}

impl std::error::Error for CliError {}

impl From<crate::scene::SceneError> for CliError {
    fn from(e: crate::scene::SceneError) -> Self {
        CliError::Input(e.to_string())
    }
}
