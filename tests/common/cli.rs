//! Running the `shadelab` binary the way scripts do.

use std::path::Path;
use std::process::Command;

pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// The suite's Mesa shader cache (`cache::use_for_mesa_shader_cache` makes
/// a folder per code generator configuration inside it).
pub fn mesa_cache() -> std::path::PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesa-shader-cache")
}

/// Runs `shadelab ARGS` in `dir` with the validation layer on, and the
/// lighting hooks' and specialised modules' cache in `dir/cache` (not the
/// user's).
pub fn shadelab(dir: &Path, args: &[&str]) -> Run {
    shadelab_with(dir, args, &[])
}

/// The command [`shadelab_with`] runs.
fn command(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_shadelab"));
    command
        .args(args)
        .current_dir(dir)
        .env("SHADELAB_VALIDATION", "1")
        .env("SHADELAB_CACHE_DIR", dir.join("cache"))
        // One Mesa shader cache for the whole suite, as a user's runs share
        // one: a fresh one per test would compile every shader again.
        .env("MESA_SHADER_CACHE_DIR", mesa_cache())
        .envs(env.iter().copied());
    command
}

/// As [`shadelab`], killed past `limit` (a run that may hang must fail its
/// test, not stop the suite): `None` where it was.
#[allow(dead_code)]
pub fn shadelab_within(dir: &Path, args: &[&str], limit: std::time::Duration) -> Option<Run> {
    let mut child = command(dir, args, &[])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let read = |mut pipe: Box<dyn std::io::Read + Send>| {
        std::thread::spawn(move || {
            let mut text = String::new();
            let _ = pipe.read_to_string(&mut text);
            text
        })
    };
    let stdout = read(Box::new(child.stdout.take().unwrap()));
    let stderr = read(Box::new(child.stderr.take().unwrap()));
    let started = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break Some(status);
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    let (stdout, stderr) = (stdout.join().unwrap(), stderr.join().unwrap());
    status.map(|status| Run {
        code: status.code().unwrap_or(-1),
        stdout,
        stderr,
    })
}

/// As [`shadelab`], with the variables `env` set too.
pub fn shadelab_with(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Run {
    let out = command(dir, args, env).output().expect("the binary runs");
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Asserts that `run` (of `args`) was refused with exit status 2 and one
/// line on stderr, `shadelab: error: ...` holding `expect`.
pub fn assert_one_line_refusal(run: &Run, args: &[&str], expect: &str) {
    assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
    let lines: Vec<&str> = run
        .stderr
        .lines()
        .filter(|l| !l.trim().is_empty())
        .collect();
    assert_eq!(lines.len(), 1, "{args:?}: {}", run.stderr);
    assert!(
        lines[0].starts_with("shadelab: error: ") && lines[0].contains(expect),
        "{args:?}: {}",
        run.stderr
    );
}

/// Runs `shadelab` with `args` in `dir` (a render that writes `out`),
/// asserting it succeeds; the mean of every channel of `out`, and the
/// run's stderr.
pub fn render_mean(dir: &Path, args: &[&str], out: &str) -> (f64, String) {
    let run = shadelab(dir, args);
    assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
    let image = shadelab::output::read_image(&dir.join(out)).unwrap();
    let sum: f64 = image.pixels.iter().flatten().map(|&v| f64::from(v)).sum();
    (sum / (3 * image.pixels.len()) as f64, run.stderr)
}
