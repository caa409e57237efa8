//! The `shadelab` command line: a thin layer over the library that parses
//! arguments, prints results, and maps errors to exit statuses
//! (0 success, 1 failed comparison, 2 bad input or usage, 3 Vulkan/internal).

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    // A reader that closes the pipe early (`shadelab info | head -1`) ends
    // the process quietly, as for any Unix tool; Rust's default (SIGPIPE
    // ignored) made `println!` panic with a backtrace.
    // SAFETY: signal(2) with SIG_DFL, before any other thread exists.
    unsafe { libc::signal(libc::SIGPIPE, libc::SIG_DFL) };
    // First, while no other thread runs: it sets an environment variable
    // that the driver reads when it loads.
    if let Err(warning) = shadelab::cache::use_for_mesa_shader_cache() {
        eprintln!("shadelab: warning: {warning}");
    }
    // Stopped by Ctrl-C or SIGTERM: no half-written temporary file stays.
    // 130 is the shell's status for an interrupted command.
    let _ = ctrlc::set_handler(|| {
        shadelab::output::remove_temporary_files();
        std::process::exit(130);
    });
    let status = cli::run();
    // A stuck device whose error a report took as text (a case that could
    // not run) still must not be waited for at exit.
    if shadelab::gpu::any_device_stuck() {
        let _ = std::io::Write::flush(&mut std::io::stdout());
        // SAFETY: _exit(2) skips the driver's exit handlers, which would
        // wait for the stuck shader's threads.
        unsafe { libc::_exit(3) };
    }
    status
}
