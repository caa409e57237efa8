//! The `shadelab` command line: a thin layer over the library that parses
//! arguments, prints results, and maps errors to exit statuses
//! (0 success, 1 failed comparison, 2 bad input or usage, 3 Vulkan/internal).

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    // First, while no other thread runs: it sets an environment variable
    // that the driver reads when it loads.
    shadelab::cache::use_for_mesa_shader_cache();
    cli::run()
}
