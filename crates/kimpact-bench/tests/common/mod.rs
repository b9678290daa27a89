//! Running the bench binary from its integration tests.

use std::ffi::OsStr;
use std::process::Command;

/// Run `kimpact-bench` with `args`; its standard output, after checking it
/// exited successfully (the failure shows its standard error).
pub fn run_bench<I, S>(args: I) -> String
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    let output = Command::new(env!("CARGO_BIN_EXE_kimpact-bench"))
        .args(args)
        .output()
        .expect("the bench binary starts");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "kimpact-bench failed: {}\n{stdout}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}
