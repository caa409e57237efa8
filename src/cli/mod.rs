//! Argument parsing and dispatch to one folder per subcommand; what more
//! than one command uses is in `common/`, and each command's work that is
//! not about the command line is in the library.

mod bench;
mod check;
mod common;
mod compare;
mod diff;
mod golden;
mod info;
mod render;
mod warm;

use std::process::ExitCode;

use std::any::TypeId;

use clap::{ArgMatches, CommandFactory, FromArgMatches, Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "shadelab",
    version,
    about = "Headless renderer for flat, Gouraud and Phong shading (and ray tracing) on Vulkan",
    long_about = "Headless renderer for the classic shading models on Vulkan (Mesa lavapipe by default).\n\
                  A SCENE is a TOML scene file or a glTF (.gltf/.glb); leave it out for the built-in default scene."
)]
struct Cli {
    #[command(flatten)]
    machine: common::args::MachineArgs,

    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to a PNG (8-bit sRGB) or EXR (linear float) image.
    Render(common::batch::args::RenderArgs),
    /// Time each mode (medians, ratios to a baseline, rays per second).
    Bench(bench::BenchArgs),
    /// Render on the GPU and with the CPU reference, and compare.
    Check(check::CheckArgs),
    /// Render scenes and compare each with its stored reference image
    /// (image regression tests): --create makes missing references,
    /// --bless accepts changed ones.
    Golden(golden::GoldenArgs),
    /// One scene in many shader variants: speed against error.
    Compare(compare::CompareArgs),
    /// Compare two images (PNG or EXR): error figures, FLIP, an optional heat
    /// map; exit status 1 when a figure is over its threshold.
    Diff(diff::DiffArgs),
    /// List the Vulkan devices and show which one shadelab uses.
    Info(info::InfoArgs),
    /// Fill the caches (specialised modules, lavapipe's machine code) for
    /// scenes, so that later renders of them start warm.
    Warm(warm::WarmArgs),
}

/// The parser's error as every other error reads: one `shadelab: error:`
/// line (with clap's suggestion of a similar name, where it has one), then
/// the usage and where to read more. Clap's advice to pass a value after
/// `--` is dropped: after `--` it is a scene path.
fn parser_error_in_house_style(rendered: &str) -> String {
    let mut message = String::new();
    let mut tips = Vec::new();
    let mut usage = None;
    // Lines right after the error's, up to a blank one, belong to it (the
    // missing arguments clap lists under "were not provided:").
    let mut in_error = false;
    for line in rendered.lines().map(str::trim) {
        if line.is_empty() {
            in_error = false;
            continue;
        }
        if let Some(m) = line.strip_prefix("error: ") {
            message = m.to_string();
            in_error = true;
        } else if in_error && !line.starts_with("tip: ") && !line.starts_with("Usage: ") {
            let sep = if message.ends_with(':') { " " } else { ", " };
            message.push_str(sep);
            message.push_str(line);
        } else if let Some(tip) = line.strip_prefix("tip: ") {
            if !tip.contains("use '--") {
                tips.push(tip.to_string());
            }
        } else if let Some(u) = line.strip_prefix("Usage: ") {
            usage = Some(u.to_string());
        }
    }
    if message.is_empty() {
        message = rendered.lines().next().unwrap_or_default().to_string();
    }
    let mut text = format!("shadelab: error: {message}");
    for tip in tips {
        text.push_str(&format!(" ({tip})"));
    }
    if let Some(usage) = usage {
        let command: Vec<&str> = usage
            .split_whitespace()
            .take_while(|w| !w.starts_with(['[', '<', '-']))
            .collect();
        text.push_str(&format!(
            "\nusage: {usage}; see `{} --help`",
            command.join(" ")
        ));
    }
    text
}

/// The command line with every numeric flag taking a negative number as
/// its value (`--bounces -1`), so that it reaches the flag's range check and
/// its one line, as `--photons -5` does, rather than clap's "unexpected
/// argument" and the usage. Numeric flags are signed (`i64`, `f64`) for
/// the same reason. Here, for every command at once, so that no new flag
/// can miss it.
fn command() -> clap::Command {
    let numeric = [TypeId::of::<i64>(), TypeId::of::<f64>()];
    let negatives = |arg: clap::Arg| {
        let id = arg.get_value_parser().type_id();
        if numeric.iter().any(|t| id == *t) {
            arg.allow_negative_numbers(true)
        } else {
            arg
        }
    };
    Cli::command().mut_subcommands(move |sub| sub.mut_args(negatives))
}

/// Parses the command line; a bad value of a flag (not a number, or not
/// one of its names) is one line, as every other bad value: its usage
/// would say nothing about the value.
fn parse() -> Result<Cli, ExitCode> {
    let parsed = command()
        .try_get_matches()
        .and_then(|matches: ArgMatches| Cli::from_arg_matches(&matches));
    parsed.map_err(|e| {
        // --help and --version are not errors.
        if !e.use_stderr() {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        let text = parser_error_in_house_style(&e.render().to_string());
        let bad_value = matches!(
            e.kind(),
            clap::error::ErrorKind::ValueValidation | clap::error::ErrorKind::InvalidValue
        );
        match text.lines().next() {
            Some(first) if bad_value => eprintln!("{first}"),
            _ => eprintln!("{text}"),
        }
        ExitCode::from(2)
    })
}

pub fn run() -> ExitCode {
    let cli = match parse() {
        Ok(cli) => cli,
        Err(code) => return code,
    };
    let own = match &cli.command {
        Command::Render(a) => a.machine.clone(),
        Command::Bench(a) => a.machine.clone(),
        Command::Check(a) => a.machine.clone(),
        Command::Compare(a) => a.machine.clone(),
        Command::Golden(a) => a.machine.clone(),
        Command::Info(a) => a.machine.clone(),
        Command::Warm(a) => a.machine.clone(),
        Command::Diff(_) => common::args::MachineArgs::default(),
    };
    let machine = own.or(&cli.machine);
    common::progress::set_quiet(machine.quiet);
    let mut gpu_options = shadelab::gpu::GpuOptions::from_env();
    if machine.device.is_some() {
        gpu_options.device = machine.device;
    }
    let memory = match shadelab::memory::MemoryLimit::resolve(machine.max_memory.as_deref()) {
        Ok(limit) => limit,
        Err(e) => {
            eprintln!("shadelab: error: {e}");
            return ExitCode::from(e.exit_code() as u8);
        }
    };
    let result = match cli.command {
        Command::Render(args) => render::run(args, &gpu_options, &memory),
        Command::Bench(args) => bench::run(args, &gpu_options, &memory),
        Command::Check(args) => check::run(args, &gpu_options, &memory),
        Command::Compare(args) => compare::run_command(args, &gpu_options, &memory),
        Command::Diff(args) => diff::run(args),
        Command::Golden(args) => golden::run(args, &gpu_options, &memory),
        Command::Info(args) => info::run(args, &gpu_options),
        Command::Warm(args) => warm::run(args, &gpu_options, &memory),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("shadelab: error: {}", failure.message);
            ExitCode::from(failure.code)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every numeric flag of every command is signed and takes `-1` as its
    /// value, for its own range check (issue 55: `--bounces -1` was clap's
    /// two lines): no unsigned flag, whose `-1` clap refuses by itself.
    #[test]
    fn every_numeric_flag_takes_a_negative_value_to_range_check() {
        let unsigned = [
            TypeId::of::<u8>(),
            TypeId::of::<u16>(),
            TypeId::of::<u32>(),
            TypeId::of::<u64>(),
            TypeId::of::<usize>(),
        ];
        let mut checked = 0;
        for sub in command().get_subcommands() {
            for arg in sub.get_arguments() {
                let id = arg.get_value_parser().type_id();
                let name = format!("{} --{}", sub.get_name(), arg.get_id());
                assert!(!unsigned.iter().any(|t| id == *t), "{name} is unsigned");
                if id == TypeId::of::<i64>() || id == TypeId::of::<f64>() {
                    assert!(arg.is_allow_negative_numbers_set(), "{name}");
                    let flag = format!("--{}", arg.get_long().unwrap());
                    let parsed =
                        command().try_get_matches_from(["shadelab", sub.get_name(), &flag, "-1"]);
                    if let Err(e) = parsed {
                        assert_eq!(
                            e.kind(),
                            clap::error::ErrorKind::MissingRequiredArgument,
                            "{name}: {e}"
                        );
                    }
                    checked += 1;
                }
            }
        }
        assert!(checked >= 20, "{checked} numeric flags");
    }

    #[test]
    fn parser_errors_read_as_one_line_then_the_usage() {
        let clap_text = "error: unexpected argument '--shadin' found\n\n  tip: a similar argument exists: '--shading'\n\nUsage: shadelab render --shading <SHADING> [SCENE]\n\nFor more information, try '--help'.\n";
        let text = parser_error_in_house_style(clap_text);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 2, "{text}");
        assert_eq!(
            lines[0],
            "shadelab: error: unexpected argument '--shadin' found (a similar argument exists: '--shading')"
        );
        assert_eq!(
            lines[1],
            "usage: shadelab render --shading <SHADING> [SCENE]; see `shadelab render --help`"
        );
        let missing = "error: the following required arguments were not provided:\n  --references <DIR>\n  --out <DIR>\n\nUsage: shadelab golden --references <DIR> [SCENES]...\n\nFor more information, try '--help'.\n";
        let text = parser_error_in_house_style(missing);
        assert_eq!(
            text.lines().next(),
            Some("shadelab: error: the following required arguments were not provided: --references <DIR>, --out <DIR>")
        );
        let dash = "error: unexpected argument '-x' found\n\n  tip: to pass '-x' as a value, use '-- -x'\n";
        assert_eq!(
            parser_error_in_house_style(dash),
            "shadelab: error: unexpected argument '-x' found"
        );
    }
}
