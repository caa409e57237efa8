//! The `shadelab` command line: a thin layer over the library that parses
//! arguments, prints results, and maps errors to exit statuses
//! (0 success, 1 failed comparison, 2 bad input or usage, 3 Vulkan/internal).

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    cli::run()
}
