//! What the command's integration tests share: running the `kimpact`
//! binary, the bundled scenes, temporary files and folders, and reading the
//! JSON report.
// Each test file uses some of these.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

/// Every mode, cheapest first.
pub const MODES: [&str; 4] = ["native", "restitution", "impulse", "exact"];

/// The `kimpact` binary, for its arguments.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kimpact"))
}

/// `kimpact` with `args`, run to its end.
pub fn kimpact(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

/// What `o` printed on its standard error.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `kimpact` with `args`, which must succeed.
pub fn kimpact_ok(args: &[&str]) -> Output {
    let o = kimpact(args);
    assert!(
        o.status.success(),
        "kimpact {args:?} failed: {}",
        stderr(&o)
    );
    o
}

/// The report `kimpact` with `args` prints (it must succeed).
pub fn report(args: &[&str]) -> Value {
    serde_json::from_slice(&kimpact_ok(args).stdout).expect("the report is JSON")
}

/// `kimpact run SCENE --mode MODE` (it must succeed): the report and the
/// standard error.
pub fn run_scene(path: &Path, mode: &str) -> (Value, String) {
    let o = kimpact(&["run", path.to_str().unwrap(), "--mode", mode]);
    let err = stderr(&o);
    assert!(o.status.success(), "{} {mode}: {err}", path.display());
    (serde_json::from_slice(&o.stdout).expect("JSON"), err)
}

/// The folder of the bundled scenes.
pub fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// A bundled scene.
pub fn scene(name: &str) -> PathBuf {
    scenes_dir().join(name)
}

/// A fresh, empty temporary folder for one test of this file.
pub fn temp_dir(name: &str) -> PathBuf {
    let (file, id) = (env!("CARGO_CRATE_NAME"), std::process::id());
    let dir = std::env::temp_dir().join(format!("kimpact-{file}-{name}-{id}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// `contents` written to `name` in this test file's temporary folder.
pub fn write(name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
    let (file, id) = (env!("CARGO_CRATE_NAME"), std::process::id());
    let dir = std::env::temp_dir().join(format!("kimpact-{file}-{id}"));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("write");
    path
}

/// A number of the report.
pub fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// An array of numbers of the report.
pub fn vecf(v: &Value) -> Vec<f64> {
    v.as_array().expect("an array").iter().map(f).collect()
}
