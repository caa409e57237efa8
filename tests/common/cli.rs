//! Running the `shadelab` binary the way scripts do.

use std::path::Path;
use std::process::Command;

pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// Runs `shadelab ARGS` in `dir` with the validation layer on, and the
/// lighting hooks' cache in `dir/cache` (not the user's).
pub fn shadelab(dir: &Path, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_shadelab"))
        .args(args)
        .current_dir(dir)
        .env("SHADELAB_VALIDATION", "1")
        .env("SHADELAB_CACHE_DIR", dir.join("cache"))
        .output()
        .expect("the binary runs");
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}
