//! The test suite's two tiers stay what docs/testing.md says they are.
//!
//! The default tier is `cargo test --locked`; the validation tier is every test marked
//! `#[ignore = "validation tier: …"]`, run by `cargo test --locked -- --ignored`. So every test
//! sits in exactly one tier, and this module checks that the mark is used for nothing else
//! and that docs/testing.md lists exactly the tests that carry it.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// The one `#[ignore]` attribute the project uses: it puts a test in the validation tier.
const TIER_MARK: &str = r#"#[ignore = "validation tier: cargo test -- --ignored"]"#;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
    paths.sort();
    for p in paths {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The test's module path inside its test binary: `tests/it/clip/agree.rs` → `clip::agree`.
fn module_of(file: &Path) -> String {
    let rel = file.strip_prefix(repo()).unwrap();
    let rel = rel
        .strip_prefix("tests/it")
        .or_else(|_| rel.strip_prefix("tests"))
        .unwrap_or(rel);
    let mut parts: Vec<String> = rel
        .with_extension("")
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.last().is_some_and(|l| l == "mod") {
        parts.pop();
    }
    parts.join("::")
}

/// The name an attribute at `line` applies to: the next `fn NAME(`, or the next `NAME =>` of a
/// table of generated tests (readme.rs's pages).
fn marked_name(lines: &[&str], line: usize) -> Option<String> {
    for l in &lines[line + 1..lines.len().min(line + 40)] {
        let t = l.trim();
        if t.starts_with("#[") || t.starts_with("///") || t.is_empty() {
            continue;
        }
        if let Some(rest) = t.strip_prefix("fn ") {
            return rest.split('(').next().map(str::to_string);
        }
        if let Some((name, _)) = t.split_once("=>") {
            return Some(name.trim().to_string());
        }
        return None;
    }
    None
}

/// (test path, problems) over the project's Rust sources.
fn marked_tests() -> (BTreeSet<String>, Vec<String>) {
    let mut files = Vec::new();
    for dir in ["tests", "src", "crates", "benches", "examples"] {
        rust_files(&repo().join(dir), &mut files);
    }
    let mut marked = BTreeSet::new();
    let mut problems = Vec::new();
    for file in files {
        if file.ends_with("tests/it/tiers.rs") {
            continue;
        }
        let text = fs::read_to_string(&file).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        for (i, l) in lines.iter().enumerate() {
            let t = l.trim();
            if !t.starts_with("#[ignore") {
                continue;
            }
            let at = format!("{}:{}", file.display(), i + 1);
            if t != TIER_MARK {
                problems.push(format!("{at}: `{t}`: the only ignore is `{TIER_MARK}`"));
                continue;
            }
            match marked_name(&lines, i) {
                Some(name) => {
                    marked.insert(format!("{}::{name}", module_of(&file)));
                }
                None => problems.push(format!("{at}: the mark is on no test")),
            }
        }
    }
    (marked, problems)
}

/// The tests docs/testing.md lists in its validation-tier table (first column, in backticks).
fn listed_tests() -> BTreeSet<String> {
    let page = fs::read_to_string(repo().join("docs/testing.md")).unwrap();
    let table = page
        .split("<!-- validation-tier -->")
        .nth(1)
        .expect("docs/testing.md marks its validation-tier table with <!-- validation-tier -->");
    table
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .filter_map(|l| {
            let cell = l.split('|').nth(1)?.trim();
            Some(cell.strip_prefix('`')?.strip_suffix('`')?.to_string())
        })
        .collect()
}

#[test]
fn every_ignored_test_is_in_the_validation_tier_and_listed() {
    let (marked, problems) = marked_tests();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(
        marked.len() >= 10,
        "the validation tier has only {} tests: is the mark still found? {marked:?}",
        marked.len()
    );
    let listed = listed_tests();
    let unlisted: Vec<&String> = marked.difference(&listed).collect();
    let stale: Vec<&String> = listed.difference(&marked).collect();
    assert!(
        unlisted.is_empty() && stale.is_empty(),
        "docs/testing.md's validation-tier table and the marked tests differ:\n  \
         marked but not listed: {unlisted:?}\n  listed but not marked: {stale:?}"
    );
}

#[test]
fn the_ci_script_runs_both_tiers() {
    let ci = fs::read_to_string(repo().join(".ci/run")).unwrap();
    let commands: Vec<&str> = ci.lines().map(str::trim).collect();
    assert!(commands.contains(&"cargo test --locked"), "{ci}");
    assert!(
        commands.contains(&"cargo test --locked -- --ignored"),
        "{ci}"
    );
}

#[test]
fn a_mark_elsewhere_or_misspelt_is_found() {
    let lines = [
        "#[test]",
        TIER_MARK,
        "/// doc",
        "fn slow_one() {",
        "page_tests! {",
        TIER_MARK,
        "    docs_x_commands => \"docs/x.md\";",
    ];
    assert_eq!(marked_name(&lines, 1).as_deref(), Some("slow_one"));
    assert_eq!(marked_name(&lines, 5).as_deref(), Some("docs_x_commands"));
    assert_eq!(
        module_of(&repo().join("tests/it/clip/agree.rs")),
        "clip::agree"
    );
    assert_eq!(
        module_of(&repo().join("tests/it/hardening/mod.rs")),
        "hardening"
    );
}
