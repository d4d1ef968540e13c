//! Helpers shared by the command-line test files.

use std::path::Path;
use std::process::Command;

/// Runs the `lorentz` binary with `args` in `dir`: (exit status, stdout, stderr).
pub fn lorentz_in(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lorentz"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run lorentz");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}
