//! How a command fails: an error that knows its exit status, made from
//! the library's errors (the statuses are in `docs/cli.md`).

/// An error that knows its exit status.
#[derive(Debug, Clone)]
pub struct Failure {
    pub code: u8,
    pub message: String,
}

impl Failure {
    /// Bad input or usage: exit status 2.
    pub fn usage(message: String) -> Self {
        Failure { code: 2, message }
    }
}

/// Ends the process at once with the watchdog's line and exit status 3.
/// A stuck device's submission is still running: waiting for it, tearing
/// it down or running the driver's exit handlers (`std::process::exit`)
/// would hang, and no other case can run on it, so nothing else the
/// command could do is worth doing.
pub fn end_stuck(message: &str) -> ! {
    eprintln!("shadelab: error: {message}");
    shadelab::output::remove_temporary_files();
    let _ = std::io::Write::flush(&mut std::io::stdout());
    // SAFETY: _exit(2) ends the process without running exit handlers or
    // destructors, which is the point; stdout is flushed above.
    unsafe { libc::_exit(3) }
}

impl From<shadelab::Error> for Failure {
    // Every error of the library reaches the CLI through here: the one
    // place a stuck device ends the command, wherever it happened (a
    // worker of golden or check included).
    fn from(e: shadelab::Error) -> Self {
        if e.leaves_device_stuck() {
            end_stuck(&e.to_string());
        }
        Failure {
            code: e.exit_code() as u8,
            message: e.to_string(),
        }
    }
}

impl From<shadelab::gpu::GpuError> for Failure {
    fn from(e: shadelab::gpu::GpuError) -> Self {
        shadelab::Error::from(e).into()
    }
}

impl From<shadelab::scene::SceneError> for Failure {
    fn from(e: shadelab::scene::SceneError) -> Self {
        shadelab::Error::from(e).into()
    }
}

impl From<shadelab::output::OutputError> for Failure {
    fn from(e: shadelab::output::OutputError) -> Self {
        shadelab::Error::from(e).into()
    }
}

// A golden case's error keeps the exit status it would give the command.
impl From<Failure> for shadelab::golden::CaseError {
    fn from(f: Failure) -> Self {
        shadelab::golden::CaseError {
            code: f.code,
            message: f.message,
        }
    }
}

impl From<shadelab::golden::CaseError> for Failure {
    fn from(e: shadelab::golden::CaseError) -> Self {
        Failure {
            code: e.code,
            message: e.message,
        }
    }
}
