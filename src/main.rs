//! The `wireflight` command; see `wireflight --help` and the README.

#![warn(clippy::too_many_lines)]

fn main() -> std::process::ExitCode {
    wireflight::app::main_with_args()
}
