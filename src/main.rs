//! The `wireflight` command; see `wireflight --help` and the README.

fn main() -> std::process::ExitCode {
    wireflight::app::main_with_args()
}
