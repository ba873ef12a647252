//! The command line: parse (clap) → validate → run. `main` only calls [`main_with_args`].
//!
//! Errors travel up as `anyhow::Error` chains and are printed once, prefixed with the program
//! name; the process then exits with status 2.

pub mod cli;
pub mod compare;
pub mod data;
pub mod diagnose;
pub mod import;
pub mod render;
pub mod simulate;
pub mod view;

use std::ffi::OsString;
use std::process::ExitCode;

use clap::Parser;

use cli::{Cli, Command};

/// Run the program on the given arguments (the first is the program name).
///
/// # Errors
/// Any failure of the chosen command, with context naming files and options.
pub fn run<I, T>(args: I) -> anyhow::Result<()>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = Cli::parse_from(args);
    crate::progress::set_quiet(cli.quiet);
    quiet_mesa_device_select();
    match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Diagnose(args) => diagnose::run(&args),
        Command::View(args) => view::run(&args),
        Command::Import(args) => import::run(&args),
    }
}

/// Mesa's Vulkan device-selection layer connects to Wayland to rank the GPUs and, where
/// `XDG_RUNTIME_DIR` is unset or not a directory (containers, CI, ssh), prints `error:
/// XDG_RUNTIME_DIR is invalid or not set in the environment.` twice per instance. Without a
/// runtime directory there is no Wayland session for it to ask, so the layer is turned off
/// then (`NODEVICE_SELECT=1`, its own switch) unless the user set that variable; the Vulkan
/// loader's own order is used. Called once, before any thread is started.
fn quiet_mesa_device_select() {
    let runtime_dir_ok = std::env::var_os("XDG_RUNTIME_DIR")
        .map(std::path::PathBuf::from)
        .is_some_and(|d| d.is_absolute() && d.is_dir());
    if !runtime_dir_ok && std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

/// `main` for the `wireflight` binary: run, print the error chain once, exit 2 on failure.
pub fn main_with_args() -> ExitCode {
    match run(std::env::args_os()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("wireflight: {err:#}");
            ExitCode::from(2)
        }
    }
}
