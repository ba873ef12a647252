//! The command line: parse (clap) → validate → run. `main` only calls [`main_with_args`].
//!
//! Errors travel up as `anyhow::Error` chains and are printed once, prefixed with the program
//! name; the process then exits with status 2.

pub mod cli;
pub mod clip;
pub mod commands;
pub mod compare;
pub mod data;
pub mod diagnose;
pub mod discover;
pub mod euler;
pub mod identify;
pub mod import;
pub(crate) mod outputs;
pub mod render;
pub mod simulate;
pub mod view;
pub mod workbench;

use std::ffi::OsString;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

use clap::{CommandFactory, FromArgMatches};

use cli::{Cli, Command};

/// A path as printed for people: its control characters escaped
/// ([`crate::fsio::printable`]), so that no file name sets the terminal's title or clears the
/// screen.
pub(crate) fn shown(path: &std::path::Path) -> String {
    crate::fsio::printable(&path.display().to_string()).into_owned()
}

/// Exit status of a run that hit a bug (a panic, on any thread): distinct from 2 (bad input or
/// a failed command) and from Rust's 101.
pub const EXIT_BUG: u8 = 3;

/// The command line: [`Cli`], with every option that takes a value accepting negative
/// numbers (`--fov -10` reaches the option's own check instead of reading as an option).
pub fn command() -> clap::Command {
    let cmd = Cli::command();
    let subcommands: Vec<String> = cmd
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .collect();
    subcommands.iter().fold(cmd, |cmd, name| {
        cmd.mut_subcommand(name, |sub| {
            let ids: Vec<String> = sub
                .get_arguments()
                .filter(|a| a.get_action().takes_values() && !a.is_positional())
                .map(|a| a.get_id().to_string())
                .collect();
            ids.iter().fold(sub, |sub, id| {
                sub.mut_arg(id, |a| a.allow_negative_numbers(true))
            })
        })
    })
}

/// Run the program on the given arguments (the first is the program name).
///
/// # Errors
/// Any failure of the chosen command, with context naming files and options.
pub fn run<I, T>(args: I) -> anyhow::Result<()>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let args: Vec<OsString> = args.into_iter().map(Into::into).collect();
    let matches = command().get_matches_from(&args);
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let Some(name) = matches.subcommand_name() {
        note_old_spellings(name, &args);
    }
    crate::fsio::set_input_limits(crate::fsio::InputLimits {
        max_file_bytes: cli.max_input_mb.saturating_mul(1 << 20),
        max_config_bytes: cli.max_config_mb.saturating_mul(1 << 20),
        allow_external_uris: cli.allow_external_uris,
    });
    crate::draw::progress::set_quiet(cli.quiet);
    quiet_mesa_device_select();
    match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Diagnose(args) => diagnose::run(&args),
        Command::Discover(args) => discover::run(&args),
        Command::Identify(args) => identify::run(&args),
        Command::View(args) => view::run(&args),
        Command::Euler(args) => euler::run(&args),
        Command::Clip(args) => clip::run(&args),
        Command::Import(args) => import::run(&args),
        Command::Keys(args) => commands::keys::run(&args),
        Command::Effects(args) => commands::effects::run(&args),
    }
}

/// Old spellings of options that still work, per command: `(command, old, new)`. One flag,
/// one meaning: `--mesh` is a wireframe, `--model` a flight model, `--flight` flight data.
/// (`render --model`, which is a mesh there, is handled by `render` itself: a TOML file there is
/// refused instead.)
pub const OLD_SPELLINGS: &[(&str, &str, &str)] = &[
    ("compare", "--data", "--flight"),
    ("diagnose", "--data", "--flight"),
    ("identify", "--data", "--flight"),
    ("view", "--flight-model", "--model"),
    ("clip", "--output", "--out"),
    ("clip", "--window", "--rect"),
];

/// Say on stderr that `old` is an old spelling of `new`; it still works.
pub(crate) fn deprecated(old: &str, new: &str) {
    eprintln!("wireflight: note: {old} is an old spelling of {new}; it still works, but use {new}");
}

/// A note for each old spelling used on the command line of `command` (after the command's
/// name, before any `--`).
fn note_old_spellings(command: &str, args: &[OsString]) {
    let Some(start) = args.iter().skip(1).position(|a| a == command) else {
        return;
    };
    let given: Vec<&str> = args[start + 2..]
        .iter()
        .filter_map(|a| a.to_str())
        .take_while(|a| *a != "--")
        .collect();
    for (_, old, new) in OLD_SPELLINGS.iter().filter(|(c, ..)| *c == command) {
        let used = given.iter().any(|a| {
            a.strip_prefix(old)
                .is_some_and(|rest| rest.is_empty() || rest.starts_with('='))
        });
        if used {
            deprecated(old, new);
        }
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

/// Set when any thread panics (see [`main_with_args`]).
static PANICKED: AtomicBool = AtomicBool::new(false);

/// `main` for the `wireflight` binary: run, print the error chain once, exit 2 on failure.
///
/// Around the run: a closed stdout (`wireflight diagnose … | head -1`) ends the program
/// quietly, as for any Unix filter (SIGPIPE's default action); SIGINT, SIGTERM and SIGHUP
/// remove the temporary files before exiting; and a panic on any thread — a worker's too,
/// which would otherwise only end that thread — is reported as a bug and makes the exit status
/// [`EXIT_BUG`].
pub fn main_with_args() -> ExitCode {
    // SAFETY: restoring the default action of SIGPIPE before any thread is started; no Rust
    // code relies on SIGPIPE being ignored.
    #[cfg(unix)]
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    if let Err(e) = crate::fsio::install_signal_cleanup() {
        eprintln!(
            "wireflight: warning: {}",
            crate::fsio::printable(&format!("{e:#}"))
        );
    }
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        PANICKED.store(true, Ordering::SeqCst);
        default_hook(info);
        eprintln!("wireflight: internal error (a bug): please report it with the command line");
    }));
    let result = std::panic::catch_unwind(|| run(std::env::args_os()));
    if crate::fsio::signalled() {
        // The signal thread exits with the signal's status once the temporaries are gone.
        loop {
            std::thread::park();
        }
    }
    crate::fsio::remove_temporaries();
    let code = match result {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(err)) => {
            // File names and fields quoted from input may hold control characters: escaped,
            // so that no input sets the terminal's title or clears the screen.
            eprintln!(
                "wireflight: {}",
                crate::fsio::printable(&format!("{err:#}"))
            );
            ExitCode::from(2)
        }
        Err(_) => ExitCode::from(EXIT_BUG),
    };
    if PANICKED.load(Ordering::SeqCst) {
        ExitCode::from(EXIT_BUG)
    } else {
        code
    }
}
