//! The documentation runs: every command transcript in `README.md` and `docs/*.md` is run
//! against the built binary and must print what the page shows, so the pages cannot drift
//! from the program. (`docs/testing.md` describes the same rules for people writing pages.)
//!
//! # Transcripts
//!
//! A fenced block whose info string is `console` is a transcript:
//!
//! * a line starting with `$ ` is a command; a line ending in `\` continues it on the next;
//! * the lines up to the next command (or the end of the block) are what it prints, stdout
//!   and stderr together, in the order a terminal shows them;
//! * a line `...` in the expected output stands for any number of lines (zero included);
//! * trailing whitespace of each line and trailing empty lines are not compared.
//!
//! The commands of one page run through `sh -c`, in order, in a fresh temporary directory
//! (so a file one command writes is there for the next), with the repository's `assets/`,
//! `docs/` and `tests/` linked into it and `wireflight` on `PATH` being the binary under
//! test. Nothing is written into the repository. Each command must exit with status 0 (a
//! transcript of an error ends in `; echo "exit status $?"`, which also shows the status).
//!
//! What truly varies between runs is normalised before comparing, and nothing else: the time
//! per edge that `clip --stats` measures (`93.0 ns per edge`). Everything else — counts,
//! fitted values, errors — is deterministic for a given binary and must match exactly. (Thread
//! counts do not enter any output; the numbers can depend on the CPU only through the
//! AVX2 + FMA kernels, which CI's machines have, as the development machine does.)
//!
//! `wireflight view` commands run without a display (`DISPLAY` and `WAYLAND_DISPLAY`
//! removed): with no sample output they must get as far as opening the window — their
//! arguments parsed and their files read — and fail there; with a sample output (an error
//! transcript) they are compared like any other. A command run under `xvfb-run` runs for real
//! where `xvfb-run` is installed (CI installs it) and must exit with status 0; elsewhere its
//! `wireflight view …` part gets the no-display check.
//!
//! Lines `$ cargo …` are not run. The README's set-up block (its first fenced block, `sh`)
//! must hold exactly two commands: `cargo run --release -- ARGS`, whose ARGS are run against
//! the binary, and the test command that `.ci/run` runs. Its install command
//! (`cargo install … --path P`) must name the package that builds the `wireflight` binary.
//!
//! # Pictures
//!
//! An HTML comment `<!-- same-bytes: A B -->` (invisible on the rendered page) says that
//! after the page's commands have run, file A (in the temporary directory, written by a
//! command) has exactly the bytes of file B (usually a golden test image, reached through the
//! linked `tests/`): a picture the page shows is one its command writes.
//!
//! # Pages
//!
//! Every relative link and image of `README.md`, `CHANGELOG.md` and `docs/*.md` must resolve
//! to a file of the repository (and a `#fragment` to a heading there); the README stays
//! within 25 000 characters; no page points outside the repository or tells the history of
//! earlier measurements (that is `CHANGELOG.md`'s job).

#![cfg(target_os = "linux")]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The documentation pages whose transcripts run, each as its own test below. `docs/fuzzing.md`
/// is not run: its commands need a nightly toolchain and cargo-fuzz.
const PAGES: &[&str] = &[
    "README.md",
    "docs/benchmarks.md",
    "docs/clipping-lab.md",
    "docs/conventions.md",
    "docs/discover.md",
    "docs/euler-lab.md",
    "docs/expressions.md",
    "docs/filter-error.md",
    "docs/flight-data.md",
    "docs/flight-model.md",
    "docs/jsbsim.md",
    "docs/reliability.md",
    "docs/rendering.md",
    "docs/reference-flights.md",
    "docs/report.md",
    "docs/sensors.md",
    "docs/testing.md",
    "docs/validation.md",
    "docs/window.md",
    "docs/workbench.md",
    "docs/turbulence.md",
];

/// Pages in `docs/` that are checked for links and wording but whose commands are not run.
const NOT_RUN: &[&str] = &["docs/fuzzing.md"];

/// Longest a README may be, in characters.
const README_MAX_CHARS: usize = 25_000;

/// Longest one documented command may take (a hung window must not hang the tests).
const COMMAND_TIMEOUT: Duration = Duration::from_secs(300);

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(rel: &str) -> String {
    fs::read_to_string(repo().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

// ---------------------------------------------------------------------------------------------
// Markdown: fenced blocks, transcripts, directives, links
// ---------------------------------------------------------------------------------------------

/// A fenced code block: its info string, its lines (the fence's indentation removed) and the
/// 1-based line of the page its first line is on.
#[derive(Debug)]
struct Fence {
    info: String,
    lines: Vec<String>,
    first_line: usize,
}

/// The fenced blocks of a Markdown page (``` fences, possibly indented inside a list).
fn fences(text: &str) -> Vec<Fence> {
    let mut out = Vec::new();
    let mut lines = text.lines().enumerate();
    while let Some((i, line)) = lines.next() {
        let trimmed = line.trim_start();
        let Some(info) = trimmed.strip_prefix("```") else {
            continue;
        };
        let indent = line.len() - trimmed.len();
        let mut body = Vec::new();
        for (_, l) in lines.by_ref() {
            if l.trim() == "```" {
                break;
            }
            let cut = l.len() - l.trim_start().len();
            body.push(l[cut.min(indent)..].to_string());
        }
        out.push(Fence {
            info: info.trim().to_string(),
            lines: body,
            first_line: i + 2,
        });
    }
    out
}

/// One command of a transcript and the output the page shows for it.
#[derive(Debug, Clone)]
struct Step {
    command: String,
    expected: Vec<String>,
    line: usize,
}

/// The commands of a `console` block, each with the lines that follow it.
fn transcript(fence: &Fence, page: &str) -> Vec<Step> {
    let mut steps: Vec<Step> = Vec::new();
    let mut continuing = false;
    for (k, line) in fence.lines.iter().enumerate() {
        let at = fence.first_line + k;
        if continuing {
            let step = steps.last_mut().unwrap();
            step.command.push('\n');
            step.command.push_str(line);
            continuing = line.ends_with('\\');
        } else if let Some(cmd) = line.strip_prefix("$ ") {
            steps.push(Step {
                command: cmd.to_string(),
                expected: Vec::new(),
                line: at,
            });
            continuing = cmd.ends_with('\\');
        } else {
            match steps.last_mut() {
                Some(step) => step.expected.push(line.clone()),
                None => panic!("{page}:{at}: a console block must start with a `$ ` command"),
            }
        }
    }
    steps
}

/// The `<!-- same-bytes: A B -->` directives of a page.
fn same_bytes(text: &str) -> Vec<(String, String, usize)> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let Some(rest) = line.trim().strip_prefix("<!-- same-bytes:") else {
            continue;
        };
        let words: Vec<&str> = rest.trim_end_matches("-->").split_whitespace().collect();
        assert_eq!(words.len(), 2, "line {}: same-bytes takes two paths", i + 1);
        out.push((words[0].to_string(), words[1].to_string(), i + 1));
    }
    out
}

/// Relative link targets of a page (`[text](target)` and `![alt](target)`), with their lines;
/// URLs and code spans are left out.
fn links(text: &str) -> Vec<(String, usize)> {
    let mut out = Vec::new();
    let mut in_fence = false;
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
            continue;
        }
        if in_fence {
            continue;
        }
        // Drop code spans, so `a](b)` inside backticks is not a link.
        let mut plain = String::new();
        let mut in_code = false;
        for c in line.chars() {
            if c == '`' {
                in_code = !in_code;
            } else if !in_code {
                plain.push(c);
            }
        }
        let mut rest = plain.as_str();
        while let Some(p) = rest.find("](") {
            let after = &rest[p + 2..];
            let Some(end) = after.find(')') else { break };
            let target = after[..end].trim();
            let external = target.contains("://") || target.starts_with("mailto:");
            if !external && !target.is_empty() {
                out.push((target.to_string(), i + 1));
            }
            rest = &after[end..];
        }
    }
    out
}

/// GitHub's anchor for a heading: lower case, spaces to hyphens, other punctuation dropped.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// The anchors of a Markdown file's headings (outside fences).
fn anchors(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_fence = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
        } else if !in_fence && line.starts_with('#') {
            out.push(anchor(line.trim_start_matches('#')));
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Comparing output
// ---------------------------------------------------------------------------------------------

/// What varies between runs, replaced by a fixed token: the measured time per edge of
/// `clip --stats` (`58.8 ns per edge` → `N ns per edge`).
fn normalise(line: &str) -> String {
    const UNIT: &str = " ns per edge";
    let mut line = line.trim_end().to_string();
    let mut from = 0;
    while let Some(p) = line[from..].find(UNIT).map(|p| p + from) {
        let start = line[..p]
            .rfind(|c: char| !(c.is_ascii_digit() || c == '.'))
            .map_or(0, |q| q + 1);
        line.replace_range(start..p, "N");
        from = start + 1 + UNIT.len();
    }
    line
}

/// Whether `actual` is what `expected` shows: line for line after [`normalise`], a `...` line
/// standing for any number of lines, trailing empty lines ignored on both sides.
fn matches(expected: &[String], actual: &[String]) -> bool {
    fn trim(lines: &[String]) -> Vec<String> {
        let mut v: Vec<String> = lines.iter().map(|l| normalise(l)).collect();
        while v.last().is_some_and(|l| l.is_empty()) {
            v.pop();
        }
        v
    }
    let (e, a) = (trim(expected), trim(actual));
    // m[i][j]: expected[i..] matches actual[j..].
    let mut m = vec![vec![false; a.len() + 1]; e.len() + 1];
    m[e.len()][a.len()] = true;
    for i in (0..e.len()).rev() {
        for j in (0..=a.len()).rev() {
            m[i][j] = if e[i] == "..." {
                m[i + 1][j] || (j < a.len() && m[i][j + 1])
            } else {
                j < a.len() && e[i] == a[j] && m[i + 1][j + 1]
            };
        }
    }
    m[0][0]
}

// ---------------------------------------------------------------------------------------------
// Running a page
// ---------------------------------------------------------------------------------------------

/// A temporary directory laid out like the repository root for the documented commands, and
/// a `bin/` directory (outside it) whose `wireflight` is the binary under test.
struct Workspace {
    root: tempfile::TempDir,
    bin: tempfile::TempDir,
}

impl Workspace {
    fn new() -> Self {
        let root = tempfile::tempdir().unwrap();
        for dir in ["assets", "docs", "tests"] {
            std::os::unix::fs::symlink(repo().join(dir), root.path().join(dir)).unwrap();
        }
        let bin = tempfile::tempdir().unwrap();
        std::os::unix::fs::symlink(
            env!("CARGO_BIN_EXE_wireflight"),
            bin.path().join("wireflight"),
        )
        .unwrap();
        Self { root, bin }
    }

    fn path_var(&self) -> String {
        let old = std::env::var("PATH").unwrap_or_default();
        format!("{}:{old}", self.bin.path().display())
    }
}

/// Whether a program is on `PATH`.
fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join(program).is_file()))
}

/// Status and output (stdout and stderr together, in order) of `sh -c command` in `ws`.
fn run_shell(ws: &Workspace, command: &str, display: bool) -> (Option<i32>, String) {
    let log_dir = tempfile::tempdir().unwrap();
    let log_path = log_dir.path().join("output");
    let log = fs::File::create(&log_path).unwrap();
    let mut cmd = Command::new("sh");
    cmd.arg("-c")
        .arg(command)
        .current_dir(ws.root.path())
        .env("PATH", ws.path_var())
        .stdin(Stdio::null())
        .stdout(log.try_clone().unwrap())
        .stderr(log);
    if !display {
        for var in ["DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"] {
            cmd.env_remove(var);
        }
    }
    std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
    let mut child = cmd.spawn().expect("start sh");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > COMMAND_TIMEOUT {
            // The whole process group: sh and what it started.
            let _ = Command::new("kill")
                .args(["-s", "KILL", "--", &format!("-{}", child.id())])
                .status();
            let _ = child.wait();
            return (None, format!("(killed after {COMMAND_TIMEOUT:?})"));
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let output = String::from_utf8_lossy(&fs::read(&log_path).unwrap()).into_owned();
    (status.code(), output)
}

/// How a documented command is run.
#[derive(Debug, PartialEq)]
enum Kind {
    /// Not run (`cargo …`).
    Skip,
    /// Run; status 0 and the page's output.
    Plain,
    /// `wireflight view …`: run without a display.
    Window,
    /// Under `xvfb-run`, run for real.
    Xvfb,
}

fn kind(command: &str) -> Kind {
    let words: Vec<&str> = command.split_whitespace().collect();
    match words.as_slice() {
        ["cargo", ..] => Kind::Skip,
        ["xvfb-run", ..] => Kind::Xvfb,
        ["wireflight", "view", ..] => Kind::Window,
        _ => Kind::Plain,
    }
}

fn show(lines: &[String]) -> String {
    lines
        .iter()
        .map(|l| format!("    | {l}\n"))
        .collect::<String>()
}

/// Run one step; `Err` says what is wrong.
fn check_step(ws: &Workspace, step: &Step) -> Result<(), String> {
    let mut kind = kind(&step.command);
    let mut command = step.command.clone();
    if kind == Kind::Xvfb && !on_path("xvfb-run") {
        // No Xvfb here: check what can be checked without a display.
        let at = command
            .find("wireflight ")
            .ok_or("an xvfb-run command must run wireflight")?;
        command = command[at..].to_string();
        kind = Kind::Window;
    }
    let (status, output) = match kind {
        Kind::Skip => return Ok(()),
        Kind::Plain | Kind::Window => run_shell(ws, &command, false),
        Kind::Xvfb => run_shell(ws, &command, true),
    };
    let actual: Vec<String> = output.lines().map(str::to_string).collect();
    if kind == Kind::Window && step.expected.is_empty() {
        // Arguments parsed and files read; the window is where it stops.
        return if output.contains("cannot open a window") && !output.contains("Usage:") {
            Ok(())
        } else {
            Err(format!(
                "without a display it should fail only at opening the window; it printed\n{}",
                show(&actual)
            ))
        };
    }
    if status != Some(0) {
        return Err(format!(
            "exit status {status:?} (a transcript of an error ends in `; echo \"exit status $?\"`); it printed\n{}",
            show(&actual)
        ));
    }
    if kind == Kind::Xvfb && step.expected.is_empty() {
        return Ok(()); // frame rates and the adapter vary: nothing to compare
    }
    if matches(&step.expected, &actual) {
        Ok(())
    } else {
        Err(format!(
            "the page shows\n{}but the command printed\n{}",
            show(&step.expected),
            show(&actual)
        ))
    }
}

/// Run every transcript of a page and its `same-bytes` checks; panic with every failure.
fn check_page(page: &str) {
    let text = read(page);
    let ws = Workspace::new();
    let mut failures = Vec::new();
    let mut commands = 0;
    for fence in fences(&text).iter().filter(|f| f.info == "console") {
        for step in transcript(fence, page) {
            commands += 1;
            if let Err(why) = check_step(&ws, &step) {
                failures.push(format!("{page}:{}: $ {}\n  {why}", step.line, step.command));
            }
        }
    }
    for (made, reference, line) in same_bytes(&text) {
        let a = fs::read(ws.root.path().join(&made));
        let b = fs::read(ws.root.path().join(&reference));
        match (a, b) {
            (Ok(a), Ok(b)) if a == b => {}
            (Ok(_), Ok(_)) => failures.push(format!(
                "{page}:{line}: {made} (written by the page's command) differs from {reference}"
            )),
            (a, b) => failures.push(format!(
                "{page}:{line}: same-bytes {made} {reference}: {:?} / {:?}",
                a.err(),
                b.err()
            )),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {commands} documented commands of {page} do not do what the page shows \
         (rules: tests/it/readme.rs):\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

macro_rules! page_tests {
    ($($(#[$tier:meta])* $name:ident => $page:expr;)*) => {$(
        #[test]
        $(#[$tier])*
        fn $name() {
            check_page($page);
        }
    )*};
}

page_tests! {
    readme_commands_print_what_the_readme_shows => "README.md";
    docs_benchmarks_commands => "docs/benchmarks.md";
    docs_clipping_lab_commands => "docs/clipping-lab.md";
    docs_conventions_commands => "docs/conventions.md";
    #[ignore = "validation tier: cargo test -- --ignored"]
    docs_discover_commands => "docs/discover.md";
    docs_euler_lab_commands => "docs/euler-lab.md";
    docs_expressions_commands => "docs/expressions.md";
    docs_filter_error_commands => "docs/filter-error.md";
    docs_flight_data_commands => "docs/flight-data.md";
    docs_flight_model_commands => "docs/flight-model.md";
    docs_jsbsim_commands => "docs/jsbsim.md";
    docs_reliability_commands => "docs/reliability.md";
    docs_rendering_commands => "docs/rendering.md";
    #[ignore = "validation tier: cargo test -- --ignored"]
    docs_reference_flights_commands => "docs/reference-flights.md";
    docs_report_commands => "docs/report.md";
    #[ignore = "validation tier: cargo test -- --ignored"]
    docs_sensors_commands => "docs/sensors.md";
    docs_testing_commands => "docs/testing.md";
    #[ignore = "validation tier: cargo test -- --ignored"]
    docs_validation_commands => "docs/validation.md";
    docs_window_commands => "docs/window.md";
    #[ignore = "validation tier: cargo test -- --ignored"]
    docs_workbench_commands => "docs/workbench.md";
    #[ignore = "validation tier: cargo test -- --ignored"]
    docs_turbulence_commands => "docs/turbulence.md";
}

// ---------------------------------------------------------------------------------------------
// The pages themselves
// ---------------------------------------------------------------------------------------------

/// `docs/*.md`, as repository-relative paths.
fn docs_pages() -> Vec<String> {
    let mut pages: Vec<String> = fs::read_dir(repo().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    pages.sort();
    pages
}

#[test]
fn every_page_with_commands_is_run() {
    for page in docs_pages() {
        assert!(
            PAGES.contains(&page.as_str()) || NOT_RUN.contains(&page.as_str()),
            "{page} is not in readme.rs's PAGES: add it there and a test to page_tests!"
        );
    }
    for page in PAGES {
        assert!(repo().join(page).is_file(), "{page} is listed but missing");
    }
}

#[test]
fn readme_setup_and_install_commands_are_what_ci_runs_and_builds() {
    let readme = read("README.md");
    let blocks = fences(&readme);
    let setup = blocks
        .first()
        .expect("the README opens with its set-up block");
    assert_eq!(setup.info, "sh", "the set-up block is a plain `sh` block");
    let commands: Vec<String> = setup
        .lines
        .iter()
        .map(|l| l.split('#').next().unwrap().trim().to_string())
        .filter(|l| !l.is_empty())
        .collect();
    assert_eq!(
        commands.len(),
        2,
        "exactly two set-up commands: {commands:?}"
    );

    // The first runs the program on built-in defaults: run its arguments.
    let args = commands[0]
        .strip_prefix("cargo run --release -- ")
        .unwrap_or_else(|| panic!("`{}` is not `cargo run --release -- ARGS`", commands[0]));
    let ws = Workspace::new();
    let (status, output) = run_shell(&ws, &format!("wireflight {args}"), false);
    assert_eq!(status, Some(0), "wireflight {args}:\n{output}");

    // The second is the test command CI runs.
    let ci = read(".ci/run");
    assert!(
        ci.lines().any(|l| l.trim() == commands[1]),
        "`{}` is not a command of .ci/run",
        commands[1]
    );

    // `cargo install … --path P`: P is the package of the wireflight binary.
    let install: Vec<&String> = blocks
        .iter()
        .flat_map(|b| &b.lines)
        .filter(|l| l.trim_start().starts_with("cargo install"))
        .collect();
    assert!(
        !install.is_empty(),
        "the README shows how to install the binary"
    );
    for line in install {
        let words: Vec<&str> = line.split_whitespace().collect();
        let at = words
            .iter()
            .position(|w| *w == "--path")
            .unwrap_or_else(|| panic!("`{line}`: install from the repository with --path"));
        let manifest = read(&format!("{}/Cargo.toml", words[at + 1]));
        assert!(
            manifest.contains("[package]\nname = \"wireflight\"")
                && manifest.contains("name = \"wireflight\"\npath = \"src/main.rs\""),
            "`{line}`: that path's Cargo.toml is not the package of the wireflight binary"
        );
    }
}

/// `docs/notes/*.md`, the dated notebooks (measurement history, what was tried), as
/// repository-relative paths.
fn notes_pages() -> Vec<String> {
    let mut pages: Vec<String> = fs::read_dir(repo().join("docs/notes"))
        .map(|dir| {
            dir.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(".md"))
                .map(|n| format!("docs/notes/{n}"))
                .collect()
        })
        .unwrap_or_default();
    pages.sort();
    pages
}

/// The pages checked for links and wording.
fn all_pages() -> Vec<String> {
    let mut pages = vec!["README.md".to_string(), "CHANGELOG.md".to_string()];
    pages.extend(docs_pages());
    pages.extend(notes_pages());
    pages
}

/// The notebooks are history: no transcript there (none would be run), and the user pages
/// do not send a reader to them before their second screen.
#[test]
fn notebooks_hold_no_transcripts_and_user_pages_open_without_them() {
    let mut found = Vec::new();
    for page in notes_pages() {
        for fence in fences(&read(&page)) {
            if fence.info == "console" {
                found.push(format!("{page}: a `console` block, which no test runs"));
            }
        }
    }
    let mut user_pages = vec!["README.md".to_string()];
    user_pages.extend(docs_pages());
    for page in user_pages {
        for (i, line) in read(&page).lines().take(40).enumerate() {
            if line.contains("notes/") {
                found.push(format!("{page}:{}: a notebook in the first screen", i + 1));
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

#[test]
fn links_and_images_resolve_inside_the_repository() {
    let mut broken = Vec::new();
    for page in all_pages() {
        let text = read(&page);
        let dir = Path::new(&page).parent().unwrap().to_path_buf();
        for (target, line) in links(&text) {
            let (file, fragment) = match target.split_once('#') {
                Some((f, frag)) => (f, Some(frag)),
                None => (target.as_str(), None),
            };
            let resolved = if file.is_empty() {
                PathBuf::from(&page)
            } else {
                dir.join(file)
            };
            let full = repo().join(&resolved);
            // Inside the repository: no `..` climbing out of it.
            let inside = full
                .canonicalize()
                .is_ok_and(|p| p.starts_with(repo().canonicalize().unwrap()));
            if !full.exists() || !inside {
                broken.push(format!(
                    "{page}:{line}: {target} (no file {})",
                    resolved.display()
                ));
                continue;
            }
            if let Some(fragment) = fragment {
                let heads = anchors(&fs::read_to_string(&full).unwrap_or_default());
                if !heads.iter().any(|h| h == fragment) {
                    broken.push(format!("{page}:{line}: {target} (no heading #{fragment})"));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn pages_describe_the_software_as_it_is() {
    let readme = read("README.md");
    let chars = readme.chars().count();
    assert!(
        chars <= README_MAX_CHARS,
        "README.md is {chars} characters, more than {README_MAX_CHARS}: move text into docs/"
    );
    let mut found = Vec::new();
    for page in all_pages() {
        if page == "CHANGELOG.md" {
            continue; // history belongs there
        }
        let text = read(&page);
        for (i, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            let history = [
                "session before",
                "earlier session",
                "first round",
                "shared/specs",
            ]
            .iter()
            .find(|p| lower.contains(*p));
            let issue_number = lower.match_indices("issue ").any(|(p, m)| {
                lower[p + m.len()..]
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_ascii_digit())
            });
            if let Some(p) = history {
                found.push(format!("{page}:{}: `{p}`: {line}", i + 1));
            }
            if issue_number || lower.contains("../shared") {
                found.push(format!("{page}:{}: {line}", i + 1));
            }
        }
    }
    assert!(
        found.is_empty(),
        "pages point outside the repository or tell history (CHANGELOG.md is for that):\n{}",
        found.join("\n")
    );
}

// ---------------------------------------------------------------------------------------------
// The harness itself
// ---------------------------------------------------------------------------------------------

fn lines(s: &str) -> Vec<String> {
    s.lines().map(str::to_string).collect()
}

#[test]
fn a_sample_that_drifted_from_the_output_fails() {
    let printed = lines("wrote a.png (480x360, cpu (Bresenham)); 102 segments drawn\nclip: 4");
    assert!(matches(&printed, &printed));
    // One number different, a line missing, a line more: all fail.
    let drifted = lines("wrote a.png (480x360, cpu (Bresenham)); 101 segments drawn\nclip: 4");
    assert!(!matches(&drifted, &printed));
    assert!(!matches(&printed[..1], &printed));
    assert!(!matches(&printed, &printed[..1]));
    // `...` stands for any number of lines, and only where it is.
    assert!(matches(
        &lines("wrote a.png (480x360, cpu (Bresenham)); 102 segments drawn\n..."),
        &printed
    ));
    assert!(matches(&lines("...\nclip: 4"), &printed));
    assert!(matches(
        &lines(
            "...\nwrote a.png (480x360, cpu (Bresenham)); 102 segments drawn\n...\nclip: 4\n..."
        ),
        &printed
    ));
    assert!(!matches(&lines("...\nclip: 5"), &printed));
    // Trailing whitespace and trailing empty lines are not compared; inner empty lines are.
    assert!(matches(&lines("a  \nb\n\n"), &lines("a\nb")));
    assert!(!matches(&lines("a\n\nb"), &lines("a\nb")));
    // Only the measured time per edge is normalised.
    let stats =
        "accepted 1, rejected 1, clipped 2 (0 of them to nothing), non-finite 0; 58.8 ns per edge";
    assert_eq!(
        normalise(stats),
        "accepted 1, rejected 1, clipped 2 (0 of them to nothing), non-finite 0; N ns per edge"
    );
    assert!(matches(
        &lines(stats),
        &lines(&stats.replace("58.8", "1234.5"))
    ));
    assert!(!matches(
        &lines(stats),
        &lines(&stats.replace("clipped 2", "clipped 3"))
    ));
}

#[test]
fn transcripts_parse_commands_continuations_and_outputs() {
    let page = "text\n\n```console\n$ wireflight a \\\n    --b c\nout 1\n\nout 2\n$ cat x\n```\n\n  ```console\n  $ echo hi\n  hi\n  ```\n";
    let blocks = fences(page);
    assert_eq!(blocks.len(), 2);
    let steps = transcript(&blocks[0], "page");
    assert_eq!(steps.len(), 2);
    assert_eq!(steps[0].command, "wireflight a \\\n    --b c");
    assert_eq!(steps[0].expected, ["out 1", "", "out 2"]);
    assert_eq!(steps[0].line, 4);
    assert_eq!(steps[1].command, "cat x");
    assert!(steps[1].expected.is_empty());
    let indented = transcript(&blocks[1], "page");
    assert_eq!(indented[0].command, "echo hi");
    assert_eq!(indented[0].expected, ["hi"]);
    assert_eq!(kind("cargo test --locked"), Kind::Skip);
    assert_eq!(kind("wireflight view --mesh x"), Kind::Window);
    assert_eq!(kind("xvfb-run -a wireflight view"), Kind::Xvfb);
    assert_eq!(kind("wireflight render --out a.png"), Kind::Plain);
    assert_eq!(anchor("JSBSim's Cessna 172P"), "jsbsims-cessna-172p");
    assert_eq!(
        anchor(" Replays: frames and GIFs"),
        "replays-frames-and-gifs"
    );
    assert_eq!(anchor(" `wireflight clip`"), "wireflight-clip");
    assert_eq!(
        links("see [a](docs/a.md#x) and ![b](../b.png), `[c](d)`, [e](https://f)"),
        [("docs/a.md#x".to_string(), 1), ("../b.png".to_string(), 1)]
    );
}
