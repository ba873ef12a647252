//! The `wireflight` binary under test, run as a user runs it: with arguments, optionally in a
//! directory or under a time limit, its stdout and stderr captured and stdin closed.
//!
//! `wireflight` and `wireflight_in` return the run whatever it did; `ok` and `refused` also
//! check how it ended (exit status 0, or 2: the status of every error the program reports) and
//! on failure print the command line, the status, stdout and stderr.

use std::ffi::OsStr;
use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::thread;
use std::time::{Duration, Instant};

/// The binary under test, not yet started: for runs the launchers below do not cover (a
/// closed pipe, a signal).
pub fn command() -> Command {
    Command::new(env!("CARGO_BIN_EXE_wireflight"))
}

/// `wireflight ARGS`, run to the end in the tests' directory (the repository's root).
pub fn wireflight<S: AsRef<OsStr>>(args: &[S]) -> Output {
    command()
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("`{}` did not start: {e}", command_line(args)))
}

/// `wireflight ARGS`, run to the end in `dir`.
pub fn wireflight_in<S: AsRef<OsStr>>(dir: &Path, args: &[S]) -> Output {
    command()
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| panic!("`{}` did not start: {e}", command_line(args)))
}

/// `wireflight ARGS`; fails the test if it runs longer than `limit` (a hang).
pub fn wireflight_timed<S: AsRef<OsStr>>(args: &[S], limit: Duration) -> Output {
    spawn_timed(command().args(args), args, limit)
}

/// `wireflight ARGS` in `dir`; fails the test if it runs longer than `limit` (a hang).
pub fn wireflight_in_timed<S: AsRef<OsStr>>(dir: &Path, args: &[S], limit: Duration) -> Output {
    spawn_timed(command().args(args).current_dir(dir), args, limit)
}

fn spawn_timed<S: AsRef<OsStr>>(cmd: &mut Command, args: &[S], limit: Duration) -> Output {
    let child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("`{}` did not start: {e}", command_line(args)));
    wait_timed(child, args, limit)
}

/// The output of a started `wireflight ARGS` (its pipes read as it runs, those it was given);
/// fails the test, killing it, if it runs longer than `limit`.
pub fn wait_timed<S: AsRef<OsStr>>(mut child: Child, args: &[S], limit: Duration) -> Output {
    fn drain(pipe: Option<impl Read + Send + 'static>) -> thread::JoinHandle<Vec<u8>> {
        thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut pipe) = pipe {
                pipe.read_to_end(&mut bytes)
                    .expect("read a pipe of the child");
            }
            bytes
        })
    }
    let (out, err) = (drain(child.stdout.take()), drain(child.stderr.take()));
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for wireflight") {
            break Some(status);
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        thread::sleep(Duration::from_millis(20));
    };
    let stdout = out.join().expect("the stdout reader");
    let stderr = err.join().expect("the stderr reader");
    let Some(status) = status else {
        panic!(
            "`{}` ran longer than {limit:?}\n--- stdout\n{}\n--- stderr\n{}",
            command_line(args),
            String::from_utf8_lossy(&stdout),
            String::from_utf8_lossy(&stderr)
        );
    };
    Output {
        status,
        stdout,
        stderr,
    }
}

/// `wireflight ARGS`, which must exit with status 0: its stdout (which must be UTF-8).
#[track_caller]
pub fn ok<S: AsRef<OsStr>>(args: &[S]) -> String {
    succeeded(wireflight(args), args).0
}

/// `wireflight ARGS` in `dir`, which must exit with status 0: its stdout (UTF-8).
#[track_caller]
pub fn ok_in<S: AsRef<OsStr>>(dir: &Path, args: &[S]) -> String {
    succeeded(wireflight_in(dir, args), args).0
}

/// `wireflight ARGS`, which must exit with status 0: its stdout (UTF-8) and stderr (where the
/// commands report what they read).
#[track_caller]
pub fn ok_with_stderr<S: AsRef<OsStr>>(args: &[S]) -> (String, String) {
    succeeded(wireflight(args), args)
}

/// `wireflight ARGS`, which must be refused (exit status 2): its stderr.
#[track_caller]
pub fn refused<S: AsRef<OsStr>>(args: &[S]) -> String {
    refusal(wireflight(args), args)
}

/// `wireflight ARGS` in `dir`, which must be refused (exit status 2): its stderr.
#[track_caller]
pub fn refused_in<S: AsRef<OsStr>>(dir: &Path, args: &[S]) -> String {
    refusal(wireflight_in(dir, args), args)
}

#[track_caller]
fn succeeded<S: AsRef<OsStr>>(o: Output, args: &[S]) -> (String, String) {
    assert!(o.status.success(), "{}", report(&o, args));
    let err = stderr(&o);
    let out = String::from_utf8(o.stdout)
        .unwrap_or_else(|e| panic!("`{}`: stdout is not UTF-8: {e}", command_line(args)));
    (out, err)
}

#[track_caller]
fn refusal<S: AsRef<OsStr>>(o: Output, args: &[S]) -> String {
    assert_eq!(o.status.code(), Some(2), "{}", report(&o, args));
    stderr(&o)
}

/// The command line, how it ended, stdout and stderr: the message of a failed check.
fn report<S: AsRef<OsStr>>(o: &Output, args: &[S]) -> String {
    format!(
        "`{}` exited with {}\n--- stdout\n{}\n--- stderr\n{}",
        command_line(args),
        o.status,
        stdout(o),
        stderr(o)
    )
}

/// `wireflight ARGS` as a shell would take it: arguments with spaces or quotes in quotes.
fn command_line<S: AsRef<OsStr>>(args: &[S]) -> String {
    let mut line = String::from("wireflight");
    for a in args {
        let a = a.as_ref().to_string_lossy();
        let plain = !a.is_empty()
            && a.chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_=+./:,@%^".contains(c));
        line.push(' ');
        if plain {
            line.push_str(&a);
        } else {
            line.push('\'');
            line.push_str(&a.replace('\'', r"'\''"));
            line.push('\'');
        }
    }
    line
}

/// A run's stdout as text (invalid UTF-8 replaced).
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A run's stderr as text (invalid UTF-8 replaced).
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}
